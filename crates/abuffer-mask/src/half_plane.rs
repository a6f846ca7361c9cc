//! The half-plane of the pixel footprint occluded by a cone element (§5.4), and its exact
//! area.
//!
//! # Re-derivation of §5.4
//!
//! The cone element `d` is a cylinder of radius `r_d` around the cone axis `z`, from
//! `z_d − l_d` to `z_d + l_d`. The local geometry is the half-space below the plane
//! `n_x x + n_y y + (z − z_d) n_z + h̄ = 0`. A ray through the footprint point
//! `ω = (ω_x, ω_y)` runs along `(r_d ω_x, r_d ω_y, z)`. The plane function is linear along
//! the ray, so the ray meets the half-space inside the element iff the smaller of its two
//! end values is `≤ 0`:
//!
//! ```text
//! r_d (ω_x n_x + ω_y n_y) − l_d |n_z| + h̄ ≤ 0
//! ⇔  ω · (cos θ, sin θ) ≤ v,   v = (l_d |n_z| − h̄) / (r_d sqrt(n_x² + n_y²)),
//!    (n_x, n_y) = sqrt(n_x² + n_y²) (cos θ, sin θ).
//! ```
//!
//! The extracted paper text writes `−l_d n_z` and `v = (n_z l_d − h̄) / (r_d ‖n_xy‖)`: this is
//! the same only for `n_z ≥ 0`. For `n_z < 0` the lower end `z_d − l_d` is not the extremity
//! "below the plane"; taking the minimum over both ends gives `|n_z|`, used here.
//!
//! When `n_x = n_y = 0` (plane parallel to the footprint) the test no longer depends on
//! `ω`: every ray is inside iff `l_d |n_z| − h̄ ≥ 0`. This and every other case where `|v|`
//! would exceed [`V_SATURATION`] (including `r_d ‖n_xy‖` tiny) returns `θ = 0` and
//! `v = ±V_SATURATION`, which the mask table maps to its full / empty end cells.
//!
//! The footprint is `ω ∈ [−1, 1]²`, the square circumscribing the cylinder's disc of radius
//! `r_d` (the pixel's square footprint at the element); [`SamplePattern`](crate::SamplePattern)
//! positions `p ∈ [0, 1]²` map to `ω = 2p − 1`.

use glam::{DVec2, Vec2, Vec3};
use gpu_layout::f32_bits::{ABS_MASK, INFINITY_BITS};

/// `|v|` at and above which a half-plane covers all of the footprint (`v ≥ √2`) or none of
/// it (`v ≤ −√2`); [`HalfPlane::from_cone_element`] returns `±V_SATURATION` there.
pub const V_SATURATION: f32 = 2.0;

/// Replaces a subnormal value by `+0.0`, as GPUs may.
fn flush_subnormal(x: f32) -> f32 {
    if x.to_bits() & INFINITY_BITS == 0 { 0.0 } else { x }
}

fn is_finite_bits(x: f32) -> bool {
    x.to_bits() & ABS_MASK < INFINITY_BITS
}

/// The half-plane `ω · (cos θ, sin θ) ≤ v` of the footprint `[−1, 1]²` (§5.4).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HalfPlane {
    /// `θ`, the angle of the outward normal `(cos θ, sin θ)`, in radians.
    pub theta: f32,
    /// `v`, the signed offset of the boundary line along the normal.
    pub v: f32,
}

impl HalfPlane {
    /// The half-plane that covers nothing: `θ = 0`, `v = −V_SATURATION`.
    pub const EMPTY: Self = Self { theta: 0.0, v: -V_SATURATION };
    /// The half-plane that covers everything: `θ = 0`, `v = V_SATURATION`.
    pub const FULL: Self = Self { theta: 0.0, v: V_SATURATION };

    /// The half-plane of the footprint occluded by the plane `(h̄, n̄)` inside a cone
    /// element of radius `r_d` and half-length `l_d` (§5.4, Algorithm 1 line 8; see the
    /// module docs for the derivation and the `|n_z|` correction).
    ///
    /// Every input has a defined result: any NaN or infinite input, `r_d ≤ 0` or
    /// `l_d < 0` gives [`HalfPlane::EMPTY`]; `n_x = n_y = 0` and `|v| ≥ V_SATURATION` give
    /// `θ = 0`, `v = ±V_SATURATION`. Subnormal inputs are flushed to zero first, as GPUs may.
    pub fn from_cone_element(distance: f32, normal: Vec3, radius: f32, half_length: f32) -> Self {
        let inputs = [distance, normal.x, normal.y, normal.z, radius, half_length];
        if !inputs.iter().all(|&x| is_finite_bits(x)) {
            return Self::EMPTY;
        }
        let [h, nx, ny, nz, r, l] = inputs.map(flush_subnormal);
        if !(r > 0.0 && l >= 0.0) {
            return Self::EMPTY;
        }
        let offset = l * nz.abs() - h;
        let rho = libm::sqrtf(nx * nx + ny * ny);
        let limit = r * rho;
        // `limit` is 0 for n_x = n_y = 0, possibly +∞ for huge inputs; never NaN (r > 0).
        if offset.abs() >= V_SATURATION * limit {
            return if offset >= 0.0 { Self::FULL } else { Self::EMPTY };
        }
        Self { theta: libm::atan2f(ny, nx), v: offset / limit }
    }

    /// Whether the footprint point `ω` is inside: `ω · (cos θ, sin θ) ≤ v`, in `f64`.
    pub fn contains(&self, omega: Vec2) -> bool {
        let theta = f64::from(self.theta);
        omega.as_dvec2().dot(DVec2::new(libm::cos(theta), libm::sin(theta))) <= f64::from(self.v)
    }

    /// The exact fraction of the footprint `[−1, 1]²` inside the half-plane, in `f64`: the
    /// square clipped by the line (Sutherland–Hodgman), its area by the shoelace formula,
    /// divided by 4.
    pub fn exact_coverage(&self) -> f64 {
        exact_coverage(f64::from(self.theta), f64::from(self.v))
    }
}

/// The exact fraction of `[−1, 1]²` where `ω · (cos θ, sin θ) ≤ v` (see
/// [`HalfPlane::exact_coverage`]), for `f64` parameters.
pub fn exact_coverage(theta: f64, v: f64) -> f64 {
    let normal = DVec2::new(libm::cos(theta), libm::sin(theta));
    let square = [DVec2::new(-1.0, -1.0), DVec2::new(1.0, -1.0), DVec2::new(1.0, 1.0), DVec2::new(-1.0, 1.0)];
    // Clipping a convex quadrilateral by one line leaves at most 5 vertices.
    let mut clipped = [DVec2::ZERO; 5];
    let mut count = 0;
    for (i, &a) in square.iter().enumerate() {
        let b = square[(i + 1) % 4];
        let (fa, fb) = (a.dot(normal) - v, b.dot(normal) - v);
        if fa <= 0.0 {
            clipped[count] = a;
            count += 1;
        }
        if (fa < 0.0 && fb > 0.0) || (fa > 0.0 && fb < 0.0) {
            clipped[count] = a + (b - a) * (fa / (fa - fb));
            count += 1;
        }
    }
    let polygon = &clipped[..count];
    let twice_area: f64 = (0..count).map(|i| polygon[i].perp_dot(polygon[(i + 1) % count])).sum();
    (twice_area.abs() / 8.0).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f64::consts::{FRAC_PI_4, PI, SQRT_2};

    #[test]
    fn exact_coverage_of_known_half_planes() {
        assert!((exact_coverage(0.0, 0.0) - 0.5).abs() < 1e-15);
        assert!((exact_coverage(0.0, 0.5) - 0.75).abs() < 1e-15);
        assert!((exact_coverage(PI, 0.5) - 0.75).abs() < 1e-15);
        assert!((exact_coverage(FRAC_PI_4, 0.0) - 0.5).abs() < 1e-15);
        // Diagonal line cutting the corner triangle with legs 1: area 1/2 of 4.
        assert!((exact_coverage(FRAC_PI_4, -SQRT_2 / 2.0) - 0.125).abs() < 1e-12);
        assert_eq!(exact_coverage(1.0, 2.0), 1.0);
        assert_eq!(exact_coverage(1.0, -2.0), 0.0);
    }

    #[test]
    fn derivation_matches_a_direct_ray_test() {
        // Brute-force the definition: the ray through ω meets the half-space below the
        // plane between z_d − l_d and z_d + l_d (z_d = 0).
        let cases = [
            (0.1_f32, Vec3::new(0.6, 0.0, 0.8), 0.5_f32, 0.2_f32),
            (-0.05, Vec3::new(0.3, -0.4, -0.866), 0.3, 0.1),
            (0.2, Vec3::new(-0.7, 0.7, 0.1), 1.0, 0.05),
        ];
        let (mut compared, mut total) = (0, 0);
        for (h, n, r, l) in cases {
            let plane = HalfPlane::from_cone_element(h, n, r, l);
            for i in 0..21 {
                for j in 0..21 {
                    let omega = Vec2::new(i as f32 / 10.0 - 1.0, j as f32 / 10.0 - 1.0);
                    let f = |z: f32| n.x * r * omega.x + n.y * r * omega.y + z * n.z + h;
                    let direct = f(-l).min(f(l)) <= 0.0;
                    // Points where `f` is within its own rounding (a few `f32`
                    // operations on values below 2: ~1e-6) of zero lie on the line;
                    // either answer is right there. 1e-5 leaves a factor 10.
                    let margin = (f(-l).min(f(l))).abs();
                    total += 1;
                    if margin > 1e-5 {
                        compared += 1;
                        assert_eq!(plane.contains(omega), direct, "h={h} n={n} ω={omega}");
                    }
                }
            }
        }
        // The line passes exactly through grid points in a column or two per case (the
        // first case's at ω_x = 0.2): at least 90 % of the 3 × 21² points are compared.
        assert!(compared * 10 >= total * 9, "only {compared} of {total} points compared");
    }

    #[test]
    fn degenerate_inputs_have_defined_results() {
        let up = Vec3::Z;
        assert_eq!(HalfPlane::from_cone_element(-0.1, up, 1.0, 0.5), HalfPlane::FULL);
        assert_eq!(HalfPlane::from_cone_element(0.6, up, 1.0, 0.5), HalfPlane::EMPTY);
        assert_eq!(HalfPlane::from_cone_element(0.5, up, 1.0, 0.5), HalfPlane::FULL);
        assert_eq!(HalfPlane::from_cone_element(0.0, Vec3::ZERO, 1.0, 0.5), HalfPlane::FULL);
        assert_eq!(HalfPlane::from_cone_element(f32::NAN, up, 1.0, 0.5), HalfPlane::EMPTY);
        assert_eq!(HalfPlane::from_cone_element(0.0, Vec3::X, 0.0, 0.5), HalfPlane::EMPTY);
        assert_eq!(HalfPlane::from_cone_element(0.0, Vec3::X, 1.0, -1.0), HalfPlane::EMPTY);
        assert_eq!(HalfPlane::from_cone_element(0.0, Vec3::new(f32::INFINITY, 0.0, 0.0), 1.0, 1.0), HalfPlane::EMPTY);
        let subnormal = f32::from_bits(3);
        assert_eq!(HalfPlane::from_cone_element(-1.0, Vec3::new(subnormal, 0.0, 1.0), 1.0, 1.0), HalfPlane::FULL);
        let huge = HalfPlane::from_cone_element(1.0, Vec3::new(3e38, 3e38, 0.0), 3e38, 1e30);
        assert!(huge.v.is_finite() && huge.theta.is_finite());
    }
}
