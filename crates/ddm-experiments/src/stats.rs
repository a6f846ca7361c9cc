//! Statistics of a method's outcomes: against the exact mesh's first hits (Tables 1/2:
//! steps, hit error, holes, false hits) and against another tracing of the same rays
//! (Table 3: raw against compressed maps).

use ddm_tracer::TraceOutcome;
use glam::DVec3;

/// A hit within this distance of the truth (voxels) counts as exact: the goal.
pub const WITHIN: f64 = 1e-3;
/// A hit further than this from the truth (voxels) is gross: a ray through a hole of the
/// surface that hits something behind it.
pub const GROSS: f64 = 0.5;
/// Two hit points further apart than this (voxels) count as moved in [`hit_differences`].
pub const MOVED: f32 = 1e-5;

/// Accuracy and cost of one method against the truth.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TraceStats {
    /// Mean map reads per ray.
    pub mean_steps: f64,
    /// Most map reads of a ray.
    pub max_steps: u32,
    /// Rays that hit both in the method and in the truth.
    pub both_hit: usize,
    /// Rays that hit the mesh.
    pub truth_hits: usize,
    /// Mean distance from the truth of the hits where both hit (0 when none).
    pub mean_error: f64,
    /// Largest distance from the truth where both hit.
    pub max_error: f64,
    /// Hits within [`WITHIN`] of the truth.
    pub within: usize,
    /// The mesh hit, the method missed.
    pub holes: usize,
    /// The method hit, the mesh did not.
    pub false_hits: usize,
    /// Hits more than [`GROSS`] from the truth.
    pub gross: usize,
    /// Rays that ran out of steps.
    pub exhausted: usize,
}

impl TraceStats {
    /// Percent of the rays where both hit whose hit is within [`WITHIN`] (0 when none).
    pub fn within_of_both_percent(&self) -> f64 {
        100.0 * self.within as f64 / self.both_hit.max(1) as f64
    }

    /// Percent of the rays that hit the mesh whose hit is within [`WITHIN`] (0 when none).
    pub fn within_of_truth_percent(&self) -> f64 {
        100.0 * self.within as f64 / self.truth_hits.max(1) as f64
    }
}

/// The statistics of `outcomes` against `truth` (the mesh's first hit point of each ray,
/// in the same order); rays beyond the shorter of the two are ignored.
pub fn trace_stats(outcomes: &[TraceOutcome], truth: &[Option<DVec3>]) -> TraceStats {
    let mut s = TraceStats::default();
    let mut error_sum = 0.0;
    let mut rays = 0_usize;
    for (outcome, truth) in outcomes.iter().zip(truth) {
        rays += 1;
        s.mean_steps += f64::from(outcome.steps);
        s.max_steps = s.max_steps.max(outcome.steps);
        s.exhausted += usize::from(outcome.exhausted);
        s.truth_hits += usize::from(truth.is_some());
        match (outcome.hit, truth) {
            (Some(hit), Some(point)) => {
                let error = (hit.point.as_dvec3() - *point).length();
                s.both_hit += 1;
                error_sum += error;
                s.max_error = s.max_error.max(error);
                s.within += usize::from(error <= WITHIN);
                s.gross += usize::from(error > GROSS);
            }
            (None, Some(_)) => s.holes += 1,
            (Some(_), None) => s.false_hits += 1,
            (None, None) => {}
        }
    }
    s.mean_steps /= rays.max(1) as f64;
    s.mean_error = error_sum / s.both_hit.max(1) as f64;
    s
}

/// How two tracings of the same rays differ.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HitDifferences {
    /// Rays that hit in one and miss in the other.
    pub hit_miss: usize,
    /// Rays that hit in both at points more than [`MOVED`] apart.
    pub moved: usize,
    /// The largest distance between the two hit points of a ray (0 when none).
    pub max_distance: f32,
}

/// The differences between `a` and `b`, ray by ray.
pub fn hit_differences(a: &[TraceOutcome], b: &[TraceOutcome]) -> HitDifferences {
    let mut d = HitDifferences::default();
    for (a, b) in a.iter().zip(b) {
        match (a.hit, b.hit) {
            (Some(a), Some(b)) => {
                let distance = (a.point - b.point).length();
                d.max_distance = d.max_distance.max(distance);
                d.moved += usize::from(distance > MOVED);
            }
            (None, None) => {}
            _ => d.hit_miss += 1,
        }
    }
    d
}

/// Mean map reads per ray of `outcomes` (NaN for none, as 0/0).
pub fn mean_steps(outcomes: &[TraceOutcome]) -> f64 {
    outcomes.iter().map(|o| f64::from(o.steps)).sum::<f64>() / outcomes.len() as f64
}

#[cfg(test)]
mod tests {
    use ddm_compress::DistanceMapSettings;
    use ddm_tracer::{MeshRaycaster, Method, PatchSettings, Stepping, TraceHit, TraceSettings, VoxelPatches, trace};
    use glam::{UVec3, Vec2, Vec3};

    use super::*;
    use crate::maps::{TableMap, compute_named};

    fn outcome(point: Option<Vec3>, steps: u32) -> TraceOutcome {
        let hit = point.map(|point| TraceHit { t: 1.0, point, normal: Vec3::Z, voxel: UVec3::ZERO });
        TraceOutcome { hit, steps, exhausted: false, cone: 0 }
    }

    #[test]
    fn outcomes_at_the_truth_have_no_error() {
        let points = [Some(Vec3::new(1.0, 2.0, 0.5)), None, Some(Vec3::new(3.0, 1.0, 0.25))];
        let outcomes: Vec<_> = points.iter().map(|&p| outcome(p, 4)).collect();
        let truth: Vec<_> = points.iter().map(|p| p.map(Vec3::as_dvec3)).collect();
        let s = trace_stats(&outcomes, &truth);
        assert_eq!((s.both_hit, s.truth_hits, s.within, s.holes, s.false_hits, s.gross), (2, 2, 2, 0, 0, 0));
        assert_eq!((s.mean_error, s.max_error, s.mean_steps, s.max_steps), (0.0, 0.0, 4.0, 4));
        assert_eq!((s.within_of_both_percent(), s.within_of_truth_percent()), (100.0, 100.0));
    }

    #[test]
    fn holes_false_hits_and_gross_errors_are_counted_apart() {
        let p = Vec3::new(1.0, 1.0, 1.0);
        let outcomes = [
            outcome(None, 2),                                     // hole
            outcome(Some(p), 3),                                  // false hit
            outcome(Some(p + Vec3::X * 0.25), 5),                 // error 0.25
            outcome(Some(p + Vec3::Z * 0.75), 6),                 // gross error 0.75
            TraceOutcome { exhausted: true, ..outcome(None, 9) }, // exhausted, no truth
        ];
        let truth = [Some(p.as_dvec3()), None, Some(p.as_dvec3()), Some(p.as_dvec3()), None];
        let s = trace_stats(&outcomes, &truth);
        assert_eq!(
            (s.holes, s.false_hits, s.both_hit, s.truth_hits, s.gross, s.within, s.exhausted),
            (1, 1, 2, 3, 1, 0, 1)
        );
        assert!((s.mean_error - 0.5).abs() < 1e-7 && (s.max_error - 0.75).abs() < 1e-7);
        assert_eq!((s.mean_steps, s.max_steps), (5.0, 9));
        assert_eq!(s.within_of_truth_percent(), 0.0);
    }

    #[test]
    fn no_rays_give_zero_statistics() {
        assert_eq!(trace_stats(&[], &[]), TraceStats::default());
    }

    #[test]
    fn a_tracing_against_itself_has_no_differences() {
        let outcomes = [outcome(Some(Vec3::ONE), 1), outcome(None, 2)];
        assert_eq!(hit_differences(&outcomes, &outcomes), HitDifferences::default());
    }

    #[test]
    fn hit_differences_count_misses_and_moved_points() {
        let a =
            [outcome(Some(Vec3::ONE), 1), outcome(None, 1), outcome(Some(Vec3::ONE), 1), outcome(Some(Vec3::ONE), 1)];
        let b = [
            outcome(None, 1),
            outcome(Some(Vec3::ONE), 1),
            outcome(Some(Vec3::ONE + Vec3::X * 0.5), 1),
            outcome(Some(Vec3::ONE + Vec3::Y * 1e-6), 1),
        ];
        let d = hit_differences(&a, &b);
        assert_eq!((d.hit_miss, d.moved), (2, 1));
        assert!((d.max_distance - 0.5).abs() < 1e-6);
    }

    #[test]
    fn mean_steps_is_the_mean() {
        assert_eq!(mean_steps(&[outcome(None, 1), outcome(None, 2), outcome(None, 6)]), 3.0);
    }

    /// A flat floor at a known height: the quadric patches represent it exactly, so the
    /// tracer's hits lie on the ray at the analytic distance, as the mesh's do.
    #[test]
    fn a_plane_is_hit_at_its_analytic_distance() {
        let dims = UVec3::new(8, 8, 4);
        let z = 1.25;
        let floor = mesostructure::plane(dims, z);
        let settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: true };
        let ddm = compute_named("floor", dims, &floor, TableMap::ddm("DDM 4x1", 4, 1), settings).unwrap().maps;
        let patches = VoxelPatches::build(dims, &floor, &ddm.surface, PatchSettings::default()).unwrap();
        let mesh = MeshRaycaster::new(&floor, Vec2::new(8.0, 8.0));
        let quadric = TraceSettings { method: Method::Quadric, max_steps: 256, stepping: Stepping::Distance };
        let rays: Vec<(Vec3, Vec3)> = (0..16)
            .map(|i| {
                let a = i as f32 * 0.4;
                (Vec3::new(1.3 + 0.3 * i as f32, 2.1, 5.0), Vec3::new(a.cos(), a.sin(), -1.5).normalize())
            })
            .collect();
        let outcomes: Vec<_> = rays.iter().map(|&(o, d)| trace(&ddm, Some(&patches), o, d, quadric)).collect();
        let truth: Vec<_> =
            rays.iter().map(|&(o, d)| mesh.first_hit(o.as_dvec3(), d.as_dvec3(), 1e4).map(|h| h.point)).collect();
        for (&(o, d), t) in rays.iter().zip(&truth) {
            let analytic = o.as_dvec3() + d.as_dvec3() * f64::from((o.z - z) / -d.z);
            assert!((t.unwrap() - analytic).length() < 1e-4, "mesh {t:?} vs plane {analytic}");
        }
        let s = trace_stats(&outcomes, &truth);
        assert_eq!((s.both_hit, s.holes, s.false_hits, s.gross), (16, 0, 0, 0));
        assert!(s.max_error < WITHIN, "max error {}", s.max_error);
    }
}
