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

use crate::direction::{canonical_direction, is_plain_direction};

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
/// - the input goes through [`canonical_direction`] first, unless it is *plain* (not zero,
///   every component `±0` or of magnitude in `[2⁻⁶³, 2⁶⁴)`, which one bit test decides),
///   since then the canonical form would change no bit of the result;
/// - `u` and `v` are clamped to `[0, n-1]`;
/// - `fract(x)` is written `x - floor(x)`, its WGSL definition.
pub fn view_sample_from_direction(direction: Vec3, subdivisions: u32) -> ViewSample {
    let n = subdivisions.clamp(1, MAX_SUBDIVISIONS);
    let d = if is_plain_direction(direction) { direction } else { canonical_special_direction(direction) };
    view_sample_of_plain(d, n)
}

/// [`canonical_direction`] of a direction that is not plain: out of the common path.
#[cold]
#[inline(never)]
fn canonical_special_direction(direction: Vec3) -> Vec3 {
    canonical_direction(direction)
}

/// Listing 1 (cancellation-free, clamped) of `d`, a plain direction or the canonical form
/// of one, for `n` in `1..=MAX_SUBDIVISIONS`.
///
/// The same bits as the formulas of [`view_sample_from_direction`], in fewer operations:
/// - `2(x⁺ + x⁻ + y⁺ + y⁻ + |z|)` as `2(|x| + |y| + |z|)`, since one of `x⁺`, `x⁻` (and
///   of `y⁺`, `y⁻`) is zero, and `y⁻` as `|y| - y⁺`, exact;
/// - `u` is finite and in `[0, n-1]`, so `⌊u⌋ = u as u32` and `⌈u⌉ = ⌊u⌋ + (u > ⌊u⌋)`,
///   exactly (`n - 1 < 2²⁴`), without `libm`'s branches;
/// - the hemisphere's `n²` is added to the two rows `⌊u⌋ n` and `⌈u⌉ n` (integer sums,
///   the same in any order).
fn view_sample_of_plain(d: Vec3, n: u32) -> ViewSample {
    let z_abs = d.z.abs();
    let twice_l1 = 2.0 * (d.x.abs() + d.y.abs() + z_abs);
    let (x_pos, y_pos) = (d.x.max(0.0), d.y.max(0.0));
    let y_neg = d.y.abs() - y_pos;
    let edge = (n - 1) as f32;
    let u = ((2.0 * (x_pos + y_pos) + z_abs) / twice_l1 * edge).clamp(0.0, edge);
    let v = ((2.0 * (x_pos + y_neg) + z_abs) / twice_l1 * edge).clamp(0.0, edge);
    let (u0, v0) = (u as u32, v as u32);
    let (u_floor, v_floor) = (u0 as f32, v0 as f32);
    let (u1, v1) = (u0 + u32::from(u > u_floor), v0 + u32::from(v > v_floor));
    let hemisphere = if d.z > 0.0 { n * n } else { 0 };
    let (row0, row1) = (u0 * n + hemisphere, u1 * n + hemisphere);
    ViewSample {
        indices: UVec4::new(row0 + v0, row1 + v0, row0 + v1, row1 + v1),
        alpha: Vec2::new(u - u_floor, v - v_floor),
        padding: Vec2::ZERO,
    }
}

#[cfg(test)]
mod tests {
    extern crate std;

    use super::*;
    use gpu_layout::f32_bits::SIGN_MASK;

    use crate::direction::{PLAIN_END_BITS, PLAIN_MIN_BITS};

    /// The lookup before the plain fast path, verbatim: every input through
    /// [`canonical_direction`], the five-term L1 sum, `libm`'s floor and ceil. The
    /// reference that [`the_fast_path_changes_no_bit`] compares with.
    fn reference_view_sample(direction: Vec3, subdivisions: u32) -> ViewSample {
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

    /// `SplitMix64`: a fixed stream of test inputs without a dependency.
    struct SplitMix(u64);

    impl SplitMix {
        fn next(&mut self) -> u32 {
            self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            ((z ^ (z >> 31)) >> 32) as u32
        }

        /// Uniform in `[-1, 1)`.
        fn unit(&mut self) -> f32 {
            (self.next() >> 8) as f32 * 2.0_f32.powi(-23) - 1.0
        }

        /// A random sign and mantissa with a biased exponent in `60..=195` (both ends of
        /// the plain range and beyond), or `±0` one time in eight.
        fn around_the_plain_range(&mut self) -> f32 {
            let bits = self.next();
            let exponent = if bits.is_multiple_of(8) { 0 } else { 60 + (bits >> 3) % 136 };
            let mantissa = if exponent == 0 { 0 } else { self.next() & 0x007f_ffff };
            f32::from_bits((bits & SIGN_MASK) | exponent << 23 | mantissa)
        }
    }

    /// Compares [`view_sample_from_direction`] with [`reference_view_sample`] bit for bit
    /// (indices and both alphas) at `d` for every `n` of `SUBDIVISIONS`; counts `d` and
    /// whether it was plain.
    #[derive(Default)]
    struct Comparison {
        directions: usize,
        plain: usize,
    }

    const SUBDIVISIONS: [u32; 8] = [1, 2, 3, 8, 12, 64, 256, MAX_SUBDIVISIONS];

    impl Comparison {
        fn check(&mut self, d: Vec3) {
            let bits = |s: ViewSample| (s.indices, s.alpha.to_array().map(f32::to_bits));
            for n in SUBDIVISIONS {
                assert_eq!(bits(view_sample_from_direction(d, n)), bits(reference_view_sample(d, n)), "n={n} d={d:?}");
            }
            self.directions += 1;
            self.plain += usize::from(is_plain_direction(d));
        }
    }

    /// Every input class, compared bit for bit with the lookup before the fast path: 10⁶
    /// random directions in the cube (the common path), 10⁶ with exponents around both
    /// ends of the plain range, 10⁶ random bit patterns (NaN, ±∞, subnormal, huge), the
    /// products of special scalars, and every view direction and cell-edge midpoint of
    /// n ≤ 12 (exact ties).
    #[test]
    fn the_fast_path_changes_no_bit() {
        const RANDOM: usize = 1_000_000;
        let mut rng = SplitMix(0x0c7a_fa57);
        let mut cube = Comparison::default();
        for _ in 0..RANDOM {
            cube.check(Vec3::new(rng.unit(), rng.unit(), rng.unit()));
        }
        assert_eq!((cube.directions, cube.plain), (RANDOM, RANDOM), "the cube is the common path");
        let mut others = Comparison::default();
        for _ in 0..RANDOM {
            others.check(Vec3::new(
                rng.around_the_plain_range(),
                rng.around_the_plain_range(),
                rng.around_the_plain_range(),
            ));
            others.check(Vec3::new(f32::from_bits(rng.next()), f32::from_bits(rng.next()), f32::from_bits(rng.next())));
        }
        let (min, end) = (f32::from_bits(PLAIN_MIN_BITS), f32::from_bits(PLAIN_END_BITS));
        let special = [
            0.0,
            -0.0,
            f32::NAN,
            -f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::MIN_POSITIVE,
            f32::from_bits(1),
            -f32::from_bits(0x0040_0000),
            f32::MAX,
            -f32::MAX,
            min,
            -min.next_down(),
            end,
            end.next_down(),
            1.0,
            -1.0,
            0.5,
            -1e-30,
            3e30,
        ];
        for x in special {
            for y in special {
                for z in special {
                    others.check(Vec3::new(x, y, z));
                }
            }
        }
        let mut ties = 0;
        for n in 1..=12 {
            let views = OctahedralViews::new(n).unwrap();
            for index in 0..views.view_count() {
                let d = views.view_direction(index).unwrap();
                let next = views.view_direction((index + 1) % views.view_count()).unwrap();
                others.check(d);
                others.check((d + next) * 0.5);
                ties += 2;
            }
        }
        assert_eq!(others.directions, 2 * RANDOM + special.len().pow(3) + ties);
        // Both paths are taken many times: most random bit patterns are not plain.
        let special_inputs = others.directions - others.plain;
        assert!(others.plain > RANDOM / 2 && special_inputs > RANDOM / 2, "{} plain", others.plain);
        let compared = SUBDIVISIONS.len() * (cube.directions + others.directions);
        std::println!(
            "{compared} samples compared bit for bit: {} directions, {special_inputs} not plain",
            cube.directions + others.directions
        );
    }

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
