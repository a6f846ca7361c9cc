//! The exact answer, in double precision: is a ball hidden behind another one?
//!
//! A point `x` is hidden from the eye `O` by the (solid) ball `B₀ = B(g₀, r)` when the
//! segment `[O, x]` meets `B₀`. With `C` the cone of the rays that meet `B₀` (axis
//! `u = g₀/|g₀|`, half-angle `α`, `sin α = r/|g₀|`), the set of hidden points is the
//! Minkowski sum `S = B₀ + C` (every point behind a point of `B₀` along its ray; the crate
//! documentation proves the converse). `S` is convex, so a ball `B(g₁, R)` is hidden iff
//! its support function is below `S`'s in every direction `n`. `C`'s support function is
//! `0` on its polar cone `{n : n·u ≤ −sin α}` and `+∞` elsewhere, hence
//!
//! `B(g₁, R) hidden  ⇔  max { w·n : |n| = 1, n·u ≤ −sin α } ≤ r − R`, `w = g₁ − g₀`.
//!
//! The directions form a spherical cap around `−u` of angular radius `π/2 − α`, so with
//! `θ` the angle between `w` and `u` the maximum is `|w|` when `θ ≥ π/2 + α` and
//! `|w| sin(θ − α)` otherwise. For `R ≥ r` this says: `g₁` lies in the cone of apex `g₀`
//! eroded by `R − r`, i.e. in the cone of apex `g₀ R/r` — Listing 2's test, which is thus
//! exact, not only sufficient.
//!
//! [`hidden_exact`] evaluates this with `atan2` angles in `f64`, a formulation independent
//! of the cross products of [`crate::is_occluded_by`], and reports values within `f64`
//! rounding of the boundary as [`Exact::Boundary`].

use glam::DVec3;

/// The exact answer for one configuration.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Exact {
    /// Every point of the grain's ball is hidden (by at least the boundary band).
    Hidden,
    /// Some point of the grain's ball is visible (by at least the boundary band).
    Visible,
    /// Within `f64` rounding of the boundary (the value of the criterion is within
    /// [`BOUNDARY_BAND`] of the configuration's scale).
    Boundary,
    /// The eye is inside or on the occluder ball, a radius is not positive, or a value is
    /// not finite: hiding is not defined.
    Undefined,
}

/// Half-width of the band around the boundary, relative to the scale `|g₀| + |g₁| + r + R`
/// (some hundred `f64` ulps: the criterion is a handful of rounded operations on values of
/// that size, `atan2` and `asin` within a few ulps each).
pub const BOUNDARY_BAND: f64 = 1e-12;

/// Whether the ball `B(grain, grain_radius)` is hidden from the eye at the origin by the
/// ball `B(occluder, occluder_radius)` (module documentation).
pub fn hidden_exact(occluder: DVec3, occluder_radius: f64, grain: DVec3, grain_radius: f64) -> Exact {
    let (r, big_r) = (occluder_radius, grain_radius);
    let finite = occluder.is_finite() && grain.is_finite() && r.is_finite() && big_r.is_finite();
    let distance = occluder.length();
    if !(finite && r > 0.0 && big_r > 0.0 && distance > r) {
        return Exact::Undefined;
    }
    let alpha = libm::asin(r / distance);
    let u = occluder / distance;
    let w = grain - occluder;
    let theta = libm::atan2(u.cross(w).length(), u.dot(w));
    let w_length = w.length();
    let reach =
        if theta >= core::f64::consts::FRAC_PI_2 + alpha { w_length } else { w_length * libm::sin(theta - alpha) };
    let value = (r - big_r) - reach;
    let band = BOUNDARY_BAND * (distance + grain.length() + r + big_r);
    if value > band {
        Exact::Hidden
    } else if value < -band {
        Exact::Visible
    } else {
        Exact::Boundary
    }
}

/// A brute-force check of [`hidden_exact`]'s `Hidden`, independent of its derivation: for
/// `samples²` points on the grain's sphere, whether the segment from the eye meets the
/// occluder ball. `true` when every sampled point is hidden.
pub fn sampled_points_hidden(
    occluder: DVec3,
    occluder_radius: f64,
    grain: DVec3,
    grain_radius: f64,
    samples: u32,
) -> bool {
    let samples = samples.max(2);
    (0..samples).all(|i| {
        (0..samples).all(|j| {
            // Fibonacci-like lattice over the sphere: cos θ uniform, φ uniform.
            let z = 1.0 - 2.0 * (f64::from(i) + 0.5) / f64::from(samples);
            let phi = core::f64::consts::TAU * (f64::from(j) + 0.5 * f64::from(i % 2)) / f64::from(samples);
            let s = libm::sqrt((1.0 - z * z).max(0.0));
            let x = grain + grain_radius * DVec3::new(s * libm::cos(phi), s * libm::sin(phi), z);
            segment_meets_ball(x, occluder, occluder_radius)
        })
    })
}

/// Whether the segment `[0, x]` meets the ball `B(centre, radius)`.
fn segment_meets_ball(x: DVec3, centre: DVec3, radius: f64) -> bool {
    let length2 = x.length_squared();
    let t = if length2 > 0.0 { (centre.dot(x) / length2).clamp(0.0, 1.0) } else { 0.0 };
    (x * t - centre).length_squared() <= radius * radius
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axis_cases_have_known_answers() {
        let occluder = DVec3::new(0.0, 0.0, -10.0);
        // R = r on the axis: hidden anywhere behind g0 (the eroded cone's apex is g0).
        assert_eq!(hidden_exact(occluder, 1.0, DVec3::new(0.0, 0.0, -11.0), 1.0), Exact::Hidden);
        // R = 2 r: hidden from the apex 2 g0 on; between g0 and the apex not.
        assert_eq!(hidden_exact(occluder, 1.0, DVec3::new(0.0, 0.0, -25.0), 2.0), Exact::Hidden);
        assert_eq!(hidden_exact(occluder, 1.0, DVec3::new(0.0, 0.0, -15.0), 2.0), Exact::Visible);
        assert_eq!(hidden_exact(occluder, 1.0, DVec3::new(0.0, 0.0, -20.0), 2.0), Exact::Boundary);
        // A small ball inside the occluder ball is hidden; one in front is not.
        assert_eq!(hidden_exact(occluder, 1.0, DVec3::new(0.0, 0.3, -10.0), 0.2), Exact::Hidden);
        assert_eq!(hidden_exact(occluder, 1.0, DVec3::new(0.0, 0.0, -8.5), 0.2), Exact::Visible);
        assert_eq!(hidden_exact(DVec3::new(0.0, 0.0, -0.5), 1.0, DVec3::Z, 1.0), Exact::Undefined);
        assert_eq!(hidden_exact(occluder, f64::NAN, DVec3::Z, 1.0), Exact::Undefined);
    }

    #[test]
    fn brute_force_agrees_where_the_answer_is_clear() {
        let occluder = DVec3::new(0.5, -0.3, -10.0);
        let (mut hidden, mut visible) = (0, 0);
        for k in 0..400_u32 {
            let f = |m: u32| f64::from(k.wrapping_mul(m) % 997) / 997.0;
            let grain = DVec3::new(4.0 * f(7) - 2.0, 4.0 * f(13) - 2.0, -8.0 - 30.0 * f(31));
            let radius = 0.3 + 2.0 * f(53);
            let sampled = sampled_points_hidden(occluder, 1.0, grain, radius, 24);
            match hidden_exact(occluder, 1.0, grain, radius) {
                // Every point of a hidden ball is hidden, so every sample is.
                Exact::Hidden => {
                    assert!(sampled, "{grain} {radius}");
                    hidden += 1;
                }
                Exact::Visible => visible += 1,
                Exact::Boundary => {}
                Exact::Undefined => panic!("defined configuration"),
            }
        }
        // The set exercises both answers.
        assert!(hidden >= 20 && visible >= 20, "{hidden} hidden, {visible} visible");
    }
}
