//! The view layout: `N = 2n²` directions on the octahedron, and the four views nearest to
//! a direction (Listing 1 of the paper).
//!
//! # Layout
//!
//! A direction `d` is first scaled to the L1 sphere, `p = d / (|dx| + |dy| + |dz|)`, whose
//! upper and lower halves both project onto the diamond `|px| + |py| ≤ 1`. The diamond is
//! rotated by 45° into the square `[0, n-1]²`:
//!
//! ```text
//! u = (px + py + 1) (n - 1) / 2        v = (px - py + 1) (n - 1) / 2
//! ```
//!
//! View `(u, v)` of a hemisphere, `u, v ∈ 0..n`, has index `h n² + u n + v` with `h = 0`
//! for the lower hemisphere (`z ≤ 0`) and `h = 1` for the upper one (`z > 0`). The views on
//! the boundary of the square lie on the equator (`z = 0`) and are stored once per
//! hemisphere, as in the paper. For even `n` no view lies on the poles.
//!
//! Interpolation happens in the `(u, v)` square of the direction's hemisphere: the four
//! returned views are the corners of the grid cell containing `(u, v)`.

use glam::{DVec3, IVec3, UVec4, Vec2, Vec3};

use gpu_layout::gpu_struct;

use crate::direction::canonical_direction;

/// The largest supported subdivision count: `2n²` must fit in a `u32`.
pub const MAX_SUBDIVISIONS: u32 = 46_340;

gpu_struct! {
    /// The four views nearest to a direction and their interpolation coefficients
    /// (Listing 1 of the paper).
    pub struct ViewSample {
        /// `(i0, i1, i2, i3)`: the views at `(⌊u⌋,⌊v⌋)`, `(⌈u⌉,⌊v⌋)`, `(⌊u⌋,⌈v⌉)`,
        /// `(⌈u⌉,⌈v⌉)` of the direction's hemisphere.
        pub indices: UVec4,
        /// `α = fract(u, v)`: `α.x` interpolates `(i0, i2) → (i1, i3)`, `α.y`
        /// interpolates `(i0, i1) → (i2, i3)`.
        pub alpha: Vec2,
        /// Explicit padding to WGSL's 16-byte struct alignment; always zero.
        pub padding: Vec2,
    }
}

impl ViewSample {
    /// The bilinear weights of `indices`, summing to 1:
    /// `((1-αx)(1-αy), αx(1-αy), (1-αx)αy, αx αy)`.
    pub fn weights(&self) -> [f32; 4] {
        let Vec2 { x, y } = self.alpha;
        [(1.0 - x) * (1.0 - y), x * (1.0 - y), (1.0 - x) * y, x * y]
    }
}

/// The `N = 2n²` view directions of an octahedral impostor with `n` views per edge.
///
/// Construct it with [`OctahedralViews::new`], which rejects `n = 0` and `n` above
/// [`MAX_SUBDIVISIONS`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct OctahedralViews {
    subdivisions: u32,
}

impl OctahedralViews {
    /// The layout with `subdivisions` views along each edge of the `(u, v)` square, or
    /// `None` when `subdivisions` is 0 or larger than [`MAX_SUBDIVISIONS`].
    ///
    /// `n = 1` is valid and holds the two poles.
    pub const fn new(subdivisions: u32) -> Option<Self> {
        if subdivisions == 0 || subdivisions > MAX_SUBDIVISIONS { None } else { Some(Self { subdivisions }) }
    }

    /// The layout with `subdivisions` clamped to `1..=MAX_SUBDIVISIONS`.
    pub(crate) const fn clamped(subdivisions: u32) -> Self {
        Self {
            subdivisions: if subdivisions == 0 {
                1
            } else if subdivisions > MAX_SUBDIVISIONS {
                MAX_SUBDIVISIONS
            } else {
                subdivisions
            },
        }
    }

    /// `n`, the number of views along an edge of one hemisphere's square.
    pub const fn subdivisions(self) -> u32 {
        self.subdivisions
    }

    /// `N = 2n²`, the number of stored views (equator views counted twice).
    pub const fn view_count(self) -> u32 {
        2 * self.subdivisions * self.subdivisions
    }

    /// The four views nearest to `direction` and their interpolation weights (Listing 1).
    ///
    /// `direction` need not be normalized; every input has a defined result (see
    /// [`canonical_direction`]). Directions with `z ≤ 0` (including `-0.0`) use the lower
    /// hemisphere.
    pub fn sample(self, direction: Vec3) -> ViewSample {
        view_sample_from_direction(direction, self.subdivisions)
    }

    /// The unit direction of view `index`, or `None` when `index ≥ 2n²`.
    pub fn view_direction(self, index: u32) -> Option<Vec3> {
        self.view_lattice_point(index).map(|p| p.as_vec3().normalize())
    }

    /// [`view_direction`](Self::view_direction) in double precision, for analysis.
    pub fn view_direction_f64(self, index: u32) -> Option<DVec3> {
        self.view_lattice_point(index).map(|p| p.as_dvec3().normalize())
    }

    /// The view whose direction is nearest (largest dot product) to `direction`, chosen
    /// among the four views of [`sample`](Self::sample).
    ///
    /// The property tests check that no other view is nearer.
    pub fn nearest_view(self, direction: Vec3) -> u32 {
        let d = canonical_direction(direction).as_dvec3().normalize();
        let mut best = (f64::NEG_INFINITY, 0);
        for index in self.sample(direction).indices.to_array() {
            let dot = self.view_direction_f64(index).map_or(f64::NEG_INFINITY, |v| v.dot(d));
            if dot > best.0 {
                best = (dot, index);
            }
        }
        best.1
    }

    /// View `index` as an integer point on the octahedron scaled by `n - 1`:
    /// `|x| + |y| + |z| = n - 1` (or the unit poles when `n = 1`).
    pub fn view_lattice_point(self, index: u32) -> Option<IVec3> {
        let n = self.subdivisions;
        if index >= self.view_count() {
            return None;
        }
        let per_hemisphere = n * n;
        let upper = index >= per_hemisphere;
        let local = index % per_hemisphere;
        if n == 1 {
            return Some(IVec3::new(0, 0, if upper { 1 } else { -1 }));
        }
        // n ≤ MAX_SUBDIVISIONS, so every value below fits in an i32.
        let edge = n as i32 - 1;
        let u = (local / n) as i32;
        let v = (local % n) as i32;
        let x = u + v - edge;
        let y = u - v;
        let z = edge - x.abs() - y.abs();
        Some(IVec3::new(x, y, if upper { z } else { -z }))
    }
}

/// Listing 1 for `n = subdivisions` (clamped to `1..=MAX_SUBDIVISIONS`); the free-function
/// form of [`OctahedralViews::sample`] mirrored by the WGSL `octahedral_view_sample`.
///
/// Listing 1 computes `u = (px + py + 1)(n-1)/2` with `p = d / L1(d)`. Here the same value
/// is computed without cancellation: with `s = |x| + |y| + |z|`, `x⁺ = max(x, 0)` and
/// `y⁻ = max(-y, 0)`,
///
/// ```text
/// px + py + 1 = (x + y + s) / s = (2x⁺ + 2y⁺ + |z|) / s
/// px - py + 1 = (x - y + s) / s = (2x⁺ + 2y⁻ + |z|) / s
/// ```
///
/// Every sum has non-negative terms, so axis-aligned, polar and equatorial inputs land
/// exactly on grid lines, and GPU compilers that reassociate additions (Mesa folds the
/// listing's `+ 1` into other terms) no longer flip `floor` at them. Other differences from
/// the listing, all robustness fixes:
/// - the input goes through [`canonical_direction`] first;
/// - `u` and `v` are clamped to `[0, n-1]`;
/// - `fract(x)` is written `x - floor(x)`, its WGSL definition.
pub fn view_sample_from_direction(direction: Vec3, subdivisions: u32) -> ViewSample {
    let n = subdivisions.clamp(1, MAX_SUBDIVISIONS);
    let d = canonical_direction(direction);
    let (x_pos, x_neg) = (d.x.max(0.0), (-d.x).max(0.0));
    let (y_pos, y_neg) = (d.y.max(0.0), (-d.y).max(0.0));
    let z_abs = d.z.abs();
    let twice_l1 = 2.0 * (x_pos + x_neg + y_pos + y_neg + z_abs);
    let edge = (n - 1) as f32;
    let u = ((2.0 * (x_pos + y_pos) + z_abs) / twice_l1 * edge).clamp(0.0, edge);
    let v = ((2.0 * (x_pos + y_neg) + z_abs) / twice_l1 * edge).clamp(0.0, edge);
    let (u_floor, v_floor) = (libm::floorf(u), libm::floorf(v));
    let (u0, v0) = (u_floor as u32, v_floor as u32);
    let (u1, v1) = (libm::ceilf(u) as u32, libm::ceilf(v) as u32);
    let hemisphere = if d.z > 0.0 { n * n } else { 0 };
    ViewSample {
        indices: UVec4::new(u0 * n + v0, u1 * n + v0, u0 * n + v1, u1 * n + v1) + hemisphere,
        alpha: Vec2::new(u - u_floor, v - v_floor),
        padding: Vec2::ZERO,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_invalid_subdivisions() {
        assert!(OctahedralViews::new(0).is_none());
        assert!(OctahedralViews::new(MAX_SUBDIVISIONS + 1).is_none());
        let largest = OctahedralViews::new(MAX_SUBDIVISIONS).unwrap();
        assert!(largest.view_count() > 4_000_000_000);
        assert_eq!(largest.view_direction(largest.view_count()), None);
    }

    #[test]
    fn every_view_maps_back_to_itself() {
        for n in 1..=12 {
            let views = OctahedralViews::new(n).unwrap();
            for index in 0..views.view_count() {
                let direction = views.view_direction(index).unwrap();
                let sample = views.sample(direction);
                // The view's own weight is 1 (within rounding), possibly under the index
                // of its equator twin in the other hemisphere.
                let (best, weight) = sample
                    .indices
                    .to_array()
                    .into_iter()
                    .zip(sample.weights())
                    .max_by(|a, b| a.1.total_cmp(&b.1))
                    .unwrap();
                assert!(weight > 1.0 - 1e-5, "n={n} view {index}: weight {weight}");
                let back = views.view_direction(best).unwrap();
                assert!(back.dot(direction) > 1.0 - 1e-6, "n={n} view {index} -> {best}");
                assert_eq!(views.nearest_view(direction) % (n * n), best % (n * n));
            }
        }
    }

    #[test]
    fn inputs_without_a_direction_use_the_fallback() {
        let views = OctahedralViews::new(8).unwrap();
        let fallback = views.sample(crate::FALLBACK_DIRECTION);
        for d in [Vec3::ZERO, Vec3::NAN, Vec3::new(1.0, f32::NAN, 0.0), Vec3::splat(f32::from_bits(3))] {
            assert_eq!(views.sample(d), fallback, "{d}");
        }
        // Infinite components keep their direction.
        assert_eq!(views.sample(Vec3::new(f32::INFINITY, 1.0, 0.0)), views.sample(Vec3::X));
        assert_eq!(
            views.sample(Vec3::new(0.0, f32::NEG_INFINITY, f32::INFINITY)),
            views.sample(Vec3::new(0.0, -1.0, 1.0))
        );
        // Huge and tiny finite inputs keep theirs too (exact power-of-two scaling gives
        // bit-identical samples; other factors round the input itself).
        let d = Vec3::new(0.3, -0.7, 0.2);
        assert_eq!(views.sample(d * 2.0_f32.powi(120)), views.sample(d));
        assert_eq!(views.sample(d * 2.0_f32.powi(-120)), views.sample(d));
        let scaled = views.sample(d * 1e37);
        assert_eq!(scaled.indices, views.sample(d).indices);
        assert!((scaled.alpha - views.sample(d).alpha).abs().max_element() < 1e-5);
    }

    #[test]
    fn axes_poles_and_equator() {
        let views = OctahedralViews::new(8).unwrap();
        // +x is the corner (n-1, n-1) of the lower square.
        let s = views.sample(Vec3::X);
        assert_eq!(s.indices, UVec4::splat(63));
        assert_eq!(s.alpha, Vec2::ZERO);
        // -x is the corner (0, 0); -0.0 in z stays in the lower hemisphere.
        assert_eq!(views.sample(Vec3::new(-1.0, 0.0, -0.0)).indices, UVec4::splat(0));
        // The north pole of n = 8 falls in the middle of the upper square's central cell.
        let s = views.sample(Vec3::Z);
        assert_eq!(s.indices, UVec4::new(64 + 27, 64 + 35, 64 + 28, 64 + 36));
        assert_eq!(s.alpha, Vec2::splat(0.5));
        // The equator view on +y is stored at (n-1, 0) in both hemispheres.
        assert_eq!(views.view_direction(56), views.view_direction(64 + 56));
        assert_eq!(views.view_direction(56).unwrap(), Vec3::Y);
        // n = 1: the two poles.
        let poles = OctahedralViews::new(1).unwrap();
        assert_eq!(poles.sample(Vec3::new(0.3, 0.4, 0.1)).indices, UVec4::splat(1));
        assert_eq!(poles.view_direction(0), Some(Vec3::NEG_Z));
    }
}
