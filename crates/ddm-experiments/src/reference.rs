//! A fair yardstick: each tile's own surface, not its facets, and the accuracy of a method
//! measured against it.
//!
//! The tiles of [`mesostructure`] are built from analytic shapes — beads and the ball are
//! spheres on a floor ([`mesostructure::SpheresOnFloor`]), chain mail is tori
//! ([`mesostructure::Ring`]) — and tessellated into meshes whose facets lie up to a tenth
//! of a voxel inside them (16-segment beads at 12 × 12 × 6: a sagitta of 0.07–0.13 voxel).
//! Measured against the mesh, a smooth quadric that follows the sphere is 25–130× outside a
//! 10⁻³-voxel window by construction. [`ReferenceSurface`] is the analytic surface where
//! the tile is analytic, and the height field's own triangles where the tile is a height
//! field (maze, bricks: there the facets are the surface).
//!
//! [`ReferenceAccuracy`] then measures, per method and separately:
//!
//! - the **geometric error** `|SDF(hit)|` of each hit (p50, p99, max, in voxels);
//! - the **normal error**, the angle between the method's normal and the surface's at the
//!   hit (p50, p99, degrees);
//! - **leaks**: rays that, before the method's hit (or, for a miss, before leaving the
//!   slab), run deeper than `τ` into the solid, with `τ` twice the method's own p99
//!   geometric error (at least [`LEAK_FLOOR`]).

use ddm_tracer::TraceOutcome;
use glam::{DVec2, DVec3, UVec3, Vec3};
use grain_mesh::bounds::closest_point_on_triangle;
use mesostructure::{HeightField, Mesostructure, Ring, SpheresOnFloor};

/// The least leak depth (voxels): the `f32` rounding of a hit point far outside this.
pub const LEAK_FLOOR: f64 = 1e-3;

/// Steps of the leak search along one ray before it gives up (counted in
/// [`ReferenceAccuracy::unfinished`]).
const LEAK_STEPS: usize = 4096;

/// The analytic or faceted surface of a tile, periodic in x and y, as a signed distance
/// (negative inside the solid).
#[derive(Clone, Debug)]
pub enum ReferenceSurface {
    /// Spheres on a floor (beads, ball).
    Spheres(SpheresOnFloor, DVec2),
    /// Tori (chain mail).
    Rings(Vec<Ring>, DVec2),
    /// A height field: its triangles are the surface (maze, bricks).
    HeightField(HeightField),
}

impl ReferenceSurface {
    /// The surface of `which` on a tile of `size` voxels.
    pub fn of(which: Mesostructure, size: UVec3) -> Self {
        let period = DVec2::new(f64::from(size.x), f64::from(size.y));
        match which {
            Mesostructure::Maze(seed) => Self::HeightField(mesostructure::maze_height_field(size, seed)),
            Mesostructure::Bricks => Self::HeightField(mesostructure::bricks_height_field(size)),
            Mesostructure::Beads => Self::Spheres(mesostructure::bead_spheres(size), period),
            Mesostructure::Ball => Self::Spheres(mesostructure::ball_sphere(size), period),
            Mesostructure::ChainMail => Self::Rings(mesostructure::chain_mail_rings(size), period),
        }
    }

    /// The signed distance at `p` (voxels; negative inside): exact outside the solid, and
    /// inside for the height field; inside a union of overlapping shapes the distance to
    /// the nearest shape's surface (a lower bound of the depth).
    pub fn signed_distance(&self, p: DVec3) -> f64 {
        match self {
            Self::Spheres(s, period) => {
                let mut d = p.z - f64::from(s.floor);
                for &(centre, radius) in &s.spheres {
                    d = d.min(periodic_min(p, *period, |q| (q - centre.as_dvec3()).length() - f64::from(radius)));
                }
                d
            }
            Self::Rings(rings, period) => rings
                .iter()
                .map(|ring| periodic_min(p, *period, |q| torus_distance(ring, q)))
                .fold(f64::INFINITY, f64::min),
            Self::HeightField(field) => height_field_distance(field, p),
        }
    }

    /// The unit normal at `p` (out of the solid): the signed distance's gradient by central
    /// differences of 10⁻⁵ voxel.
    pub fn normal(&self, p: DVec3) -> DVec3 {
        let h = 1e-5;
        let axis = |a: DVec3| self.signed_distance(p + a * h) - self.signed_distance(p - a * h);
        DVec3::new(axis(DVec3::X), axis(DVec3::Y), axis(DVec3::Z)).normalize_or_zero()
    }
}

/// The smallest of `f` over `p` brought into the tile and its copies shifted by one period
/// in x and y (the shapes reach at most one period past the tile).
fn periodic_min(p: DVec3, period: DVec2, f: impl Fn(DVec3) -> f64) -> f64 {
    let p = DVec3::new(p.x.rem_euclid(period.x), p.y.rem_euclid(period.y), p.z);
    let mut best = f64::INFINITY;
    for dy in [-1.0, 0.0, 1.0] {
        for dx in [-1.0, 0.0, 1.0] {
            best = best.min(f(p + DVec3::new(dx * period.x, dy * period.y, 0.0)));
        }
    }
    best
}

/// The exact signed distance to a torus.
fn torus_distance(ring: &Ring, p: DVec3) -> f64 {
    let axis = ring.axis.as_dvec3().normalize();
    let q = p - ring.center.as_dvec3();
    let along = q.dot(axis);
    let radial = (q - axis * along).length();
    DVec2::new(radial - f64::from(ring.major_radius), along).length() - f64::from(ring.minor_radius)
}

/// The signed distance to a periodic height field's triangles (negative below them): the
/// nearest triangle found by rings of cells around `p`'s cell, stopped when no farther ring
/// can hold a nearer point.
fn height_field_distance(field: &HeightField, p: DVec3) -> f64 {
    let (w, h) = (i64::from(field.width.max(1)), i64::from(field.height.max(1)));
    let (cx, cy) = (p.x.floor() as i64, p.y.floor() as i64);
    let mut best = f64::INFINITY;
    let mut below = false;
    let reach = w.max(h);
    for ring in 0..=reach {
        for y in cy - ring..=cy + ring {
            for x in cx - ring..=cx + ring {
                if (x - cx).abs() != ring && (y - cy).abs() != ring {
                    continue;
                }
                let (tx, ty) = (x.rem_euclid(w), y.rem_euclid(h));
                let shift = DVec3::new((x - tx) as f64, (y - ty) as f64, 0.0);
                for triangle in field.cell_triangles(tx as u32, ty as u32) {
                    let [a, b, c] = triangle.0.map(|v| v.as_dvec3() + shift);
                    let q = closest_point_on_triangle(p, a, b, c);
                    let d = (p - q).length();
                    if d < best {
                        best = d;
                        // The side: below the triangle's plane at the nearest point (the
                        // normal faces up).
                        below = (p - q).dot((b - a).cross(c - a)) < 0.0;
                    }
                }
            }
        }
        // Cells of the next ring are at least `ring` away in x or y.
        if best <= ring as f64 {
            break;
        }
    }
    if below { -best } else { best }
}

/// One method's accuracy against a [`ReferenceSurface`] (see the module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ReferenceAccuracy {
    /// Hits measured.
    pub hits: usize,
    /// Median `|SDF(hit)|`, voxels.
    pub p50: f64,
    /// 99th percentile of `|SDF(hit)|`, voxels.
    pub p99: f64,
    /// Largest `|SDF(hit)|`, voxels.
    pub max: f64,
    /// Median angle between the method's and the surface's normal, degrees.
    pub normal_p50: f64,
    /// 99th percentile of that angle, degrees.
    pub normal_p99: f64,
    /// The leak depth `τ` used (voxels).
    pub tau: f64,
    /// Rays that ran deeper than `τ` into the solid before the method's hit or exit.
    pub leaks: usize,
    /// Rays whose leak search ran out of steps (not counted as leaks).
    pub unfinished: usize,
}

/// The quantile `q` of sorted `values` (nearest rank; 0 when empty).
fn quantile(values: &[f64], q: f64) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    let rank = ((q * values.len() as f64).ceil() as usize).clamp(1, values.len());
    values[rank - 1]
}

/// The accuracy of `outcomes` of `rays` (origin, direction) against `surface`; a ray's
/// leak search runs from its origin into the slab of depth `size_z`.
pub fn reference_accuracy(
    surface: &ReferenceSurface,
    rays: &[(Vec3, Vec3)],
    outcomes: &[TraceOutcome],
    size_z: f32,
) -> ReferenceAccuracy {
    let mut errors = Vec::new();
    let mut angles = Vec::new();
    for outcome in outcomes {
        if let Some(hit) = outcome.hit {
            let p = hit.point.as_dvec3();
            errors.push(surface.signed_distance(p).abs());
            let n = surface.normal(p);
            // The method's normal faces the ray; the surface's points out of the solid.
            let cos = hit.normal.as_dvec3().normalize_or_zero().dot(n).abs().min(1.0);
            angles.push(cos.acos().to_degrees());
        }
    }
    errors.sort_by(f64::total_cmp);
    angles.sort_by(f64::total_cmp);
    let p99 = quantile(&errors, 0.99);
    let tau = (2.0 * p99).max(LEAK_FLOOR);
    let (mut leaks, mut unfinished) = (0, 0);
    for (&(origin, direction), outcome) in rays.iter().zip(outcomes) {
        let d = direction.as_dvec3().normalize();
        let o = origin.as_dvec3();
        // Where the ray stops: the method's hit, or the slab's floor for a miss.
        let end = match outcome.hit {
            Some(hit) => f64::from(hit.t),
            None if d.z < 0.0 => (o.z / -d.z).max(0.0),
            None => continue,
        };
        let start = if o.z > f64::from(size_z) && d.z < 0.0 { (o.z - f64::from(size_z)) / -d.z } else { 0.0 };
        match deepest_before(surface, o, d, start, end, tau) {
            Some(true) => leaks += 1,
            Some(false) => {}
            None => unfinished += 1,
        }
    }
    ReferenceAccuracy {
        hits: errors.len(),
        p50: quantile(&errors, 0.5),
        p99,
        max: errors.last().copied().unwrap_or(0.0),
        normal_p50: quantile(&angles, 0.5),
        normal_p99: quantile(&angles, 0.99),
        tau,
        leaks,
        unfinished,
    }
}

/// Whether the ray `o + t d`, `t ∈ [start, end]`, runs deeper than `tau` into the solid:
/// outside it steps by the distance (sphere tracing cannot step over solid), inside by
/// `tau / 2` (so a path deeper than `1.5 τ` is always seen). `None` when the steps run out.
fn deepest_before(surface: &ReferenceSurface, o: DVec3, d: DVec3, start: f64, end: f64, tau: f64) -> Option<bool> {
    let mut t = start;
    for _ in 0..LEAK_STEPS {
        if t >= end {
            return Some(false);
        }
        let distance = surface.signed_distance(o + d * t);
        if distance < -tau {
            return Some(true);
        }
        t += distance.max(0.5 * tau);
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_references_are_the_tiles_shapes() {
        let size = UVec3::new(12, 12, 6);
        let beads = ReferenceSurface::of(Mesostructure::Beads, size);
        let spheres = mesostructure::bead_spheres(size);
        let (centre, radius) = spheres.spheres[0];
        let top = centre.as_dvec3() + DVec3::Z * f64::from(radius);
        assert!(beads.signed_distance(top).abs() < 1e-9);
        assert!((beads.normal(top) - DVec3::Z).length() < 1e-6);
        assert!(beads.signed_distance(DVec3::new(6.0, 6.0, 1.0)) < 0.0, "under the floor");
        // Across the tile border: the copies of the first bead one and three tiles away.
        assert!((beads.signed_distance(top + DVec3::X * 12.0)).abs() < 1e-9);
        assert!((beads.signed_distance(top - DVec3::new(36.0, 24.0, 0.0))).abs() < 1e-9);
        let mail = ReferenceSurface::of(Mesostructure::ChainMail, size);
        let ring = mesostructure::chain_mail_rings(size)[0];
        let on_tube = ring.centerline(0.3).as_dvec3() + ring.axis.as_dvec3() * f64::from(ring.minor_radius);
        assert!(mail.signed_distance(on_tube).abs() < 1e-5, "{}", mail.signed_distance(on_tube));
        // A height field: its corner heights are on the surface, and the distance from
        // above a flat floor is the height above it.
        let field = mesostructure::maze_height_field(size, 1);
        let maze = ReferenceSurface::of(Mesostructure::Maze(1), size);
        let corner = DVec3::new(3.0, 5.0, f64::from(field.corner(3, 5)));
        assert!(maze.signed_distance(corner).abs() < 1e-6);
        assert!(maze.signed_distance(corner - DVec3::Z * 0.01) < 0.0);
    }

    /// Straight-down rays over the ball's tile: missing all of them leaks every ray (the
    /// floor's solid is under all), and stopping each exactly on the surface leaks none and
    /// measures no error.
    #[test]
    fn misses_leak_and_exact_hits_do_not() {
        use ddm_tracer::{TraceHit, TraceOutcome};
        let size = UVec3::new(12, 12, 6);
        let ball = ReferenceSurface::of(Mesostructure::Ball, size);
        let rays: Vec<(Vec3, Vec3)> = (0..64)
            .map(|i| (Vec3::new(0.37 + (i % 8) as f32 * 1.5, 0.61 + (i / 8) as f32 * 1.5, 7.0), Vec3::NEG_Z))
            .collect();
        let misses = vec![TraceOutcome { hit: None, steps: 1, exhausted: false, cone: 0 }; rays.len()];
        let missed = reference_accuracy(&ball, &rays, &misses, 6.0);
        assert_eq!((missed.hits, missed.leaks, missed.tau), (0, rays.len(), LEAK_FLOOR));
        // The exact first hits, by bisection on the signed distance.
        let exact: Vec<TraceOutcome> = rays
            .iter()
            .map(|&(o, d)| {
                let (mut lo, mut hi) = (0.0_f64, 7.0_f64);
                for _ in 0..60 {
                    let mid = 0.5 * (lo + hi);
                    // The first sign change from above: the column is outside down to it.
                    let clear = (0..=64)
                        .all(|k| ball.signed_distance(o.as_dvec3() + d.as_dvec3() * (mid * f64::from(k) / 64.0)) > 0.0);
                    if clear { lo = mid } else { hi = mid }
                }
                let point = o + d * hi as f32;
                let normal = ball.normal(point.as_dvec3()).as_vec3();
                let hit = TraceHit { t: hi as f32, point, normal, voxel: point.floor().as_uvec3() };
                TraceOutcome { hit: Some(hit), steps: 1, exhausted: false, cone: 0 }
            })
            .collect();
        let measured = reference_accuracy(&ball, &rays, &exact, 6.0);
        assert_eq!((measured.hits, measured.leaks, measured.unfinished), (rays.len(), 0, 0));
        // The f32 hit points: within the rounding of coordinates below 8.
        assert!(measured.max < 1e-5, "{measured:?}");
        assert!(measured.normal_p99 < 0.1, "{measured:?}");
    }
}
