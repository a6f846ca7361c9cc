//! The ground-truth experiment of Fig. 9: the mean attribute over what an orthographic
//! camera sees (and, with a light, over what is also lit).

use glam::DVec3;
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

use crate::heightfield::HeightField;
use crate::raycast::{first_hit, is_lit};

/// Independent ray batches, each with its own seeded generator, so results do not
/// depend on how many threads run them.
const BATCHES: usize = 16;

/// Monte-Carlo estimator of visible (and lit) attribute averages over a height field.
#[derive(Clone, Debug)]
pub struct VisibleAverage<'a> {
    field: &'a HeightField,
    rays: usize,
    seed: u64,
}

/// The estimate of [`VisibleAverage::mean_attribute`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AttributeEstimate {
    /// The mean attribute over the counted hits.
    pub mean: f64,
    /// Its Monte-Carlo standard error.
    pub standard_error: f64,
    /// Hits counted (all visible hits, or the lit ones when a light is given).
    pub samples: usize,
}

impl<'a> VisibleAverage<'a> {
    /// An estimator casting `rays` rays per query, deterministic for a `seed`.
    pub fn new(field: &'a HeightField, rays: usize, seed: u64) -> Self {
        Self { field, rays, seed }
    }

    /// The mean of `attribute(height)` over the surface points seen from direction `view`
    /// (unit, pointing from the surface to the viewer, `view.z > 0`), counting only points
    /// that also see the light direction `light` when one is given (eq. 15's weighting).
    ///
    /// Returns `None` when no ray counts (for example a light below the horizon).
    pub fn mean_attribute(
        &self,
        view: DVec3,
        light: Option<DVec3>,
        attribute: impl Fn(f64) -> f64 + Sync,
    ) -> Option<AttributeEstimate> {
        if view.z.is_nan() || view.z <= 0.0 {
            return None;
        }
        let direction = -view.normalize();
        let n = self.field.size() as f64;
        let per_batch = self.rays.div_ceil(BATCHES);
        let batch = |b: usize| {
            let mut rng = SmallRng::seed_from_u64(self.seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) ^ b as u64);
            let (mut sum, mut sum_sq, mut count) = (0.0, 0.0, 0_usize);
            for _ in 0..per_batch {
                let (x, y) = (rng.random_range(0.0..n), rng.random_range(0.0..n));
                let Some(hit) = first_hit(self.field, x, y, direction) else { continue };
                if light.is_some_and(|l| !is_lit(self.field, hit, l.normalize())) {
                    continue;
                }
                let a = attribute(hit.z);
                (sum, sum_sq, count) = (sum + a, sum_sq + a * a, count + 1);
            }
            (sum, sum_sq, count)
        };
        let threads = std::thread::available_parallelism().map_or(1, |p| p.get()).min(BATCHES);
        let results: Vec<(f64, f64, usize)> = std::thread::scope(|scope| {
            let handles: Vec<_> = (0..threads)
                .map(|t| {
                    let batch = &batch;
                    scope.spawn(move || (t..BATCHES).step_by(threads).map(|b| (b, batch(b))).collect::<Vec<_>>())
                })
                .collect();
            let mut all: Vec<(usize, (f64, f64, usize))> =
                handles.into_iter().flat_map(|h| h.join().unwrap_or_default()).collect();
            all.sort_by_key(|(b, _)| *b);
            all.into_iter().map(|(_, r)| r).collect()
        });
        let (sum, sum_sq, count) =
            results.iter().fold((0.0, 0.0, 0), |(s, q, c), &(s2, q2, c2)| (s + s2, q + q2, c + c2));
        if count == 0 {
            return None;
        }
        let mean = sum / count as f64;
        let variance = (sum_sq / count as f64 - mean * mean).max(0.0);
        Some(AttributeEstimate { mean, standard_error: (variance / count as f64).sqrt(), samples: count })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::{Spectrum, generate_gaussian};

    #[test]
    fn at_normal_view_every_point_is_visible() {
        let field = generate_gaussian(64, Spectrum::Gaussian { wavelength: 10.0 }, 0.5, 2).unwrap();
        let truth = VisibleAverage::new(&field, 40_000, 5);
        // Seen from straight above, the visible heights are the area-weighted heights.
        let seen = truth.mean_attribute(DVec3::Z, None, |h| h).unwrap();
        let area_mean = field.heights().iter().sum::<f64>() / field.heights().len() as f64;
        assert!((seen.mean - area_mean).abs() < 4.0 * seen.standard_error + 1e-3, "{seen:?} vs {area_mean}");
        // Seen at grazing angles, the visible points are higher than average.
        let view = DVec3::new(80_f64.to_radians().sin(), 0.0, 80_f64.to_radians().cos());
        let grazing = truth.mean_attribute(view, None, |h| h).unwrap();
        assert!(grazing.mean > area_mean + 10.0 * grazing.standard_error, "{grazing:?} vs {area_mean}");
        assert!(truth.mean_attribute(-DVec3::Z, None, |h| h).is_none());
    }
}
