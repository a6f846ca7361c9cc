//! The convolved BRDF lobe (§5.5) and the shading of eq. 13.
//!
//! §5.5 represents both the NDF of the filtered surface (slope variance `σ_n²`) and the
//! microfacet BRDF (`σ_np²`) as Gaussian slope distributions, so their convolution is
//! the Gaussian of variance `σ_n² + σ_np²` ([`convolved_slope_deviation`]). The lobe is
//! the Gaussian-slope (Beckmann) NDF
//!
//! `D(m) = exp(−(s_x²/2σ_x² + s_y²/2σ_y²)) / (2π σ_x σ_y m_z⁴)`, `s = −(m_x, m_y)/m_z`.
//!
//! [`shade`] evaluates eq. 13, `L = Ē ā(v, l) ρ̄(v, l) ⟨n̄·l⟩ V̄(l)`, with
//! `ρ̄ = D(h) V̄(v) / (4 ⟨n̄·v⟩ ⟨n̄·l⟩)` the microfacet specular lobe of the convolved
//! slopes at the half vector `h` (no Fresnel factor: under eq. 1 the colour is the
//! attribute), `V̄(d) = 1/(1 + Λ(d))` Smith's mean visibility and `ā(v, l)` eq. 17. Hence
//! `L = Ē ā(v, l) D(h) V̄(v) V̄(l) / (4 ⟨n̄·v⟩)`. Masking (Λ) uses the surface slopes
//! `σ_n` stored in the voxel, as eq. 6 does; the lobe uses the convolved ones.
//!
//! | input | result |
//! |---|---|
//! | light below the horizon or grazing (`l_z ≤ 0`) | `Some(0)`: unlit |
//! | view below the horizon or grazing (`v_z ≤ 0`) | `None`: no projected area is seen |
//! | zero or non-finite direction | `None` |
//! | convolved `σ_x` or `σ_y` = 0 | `None`: the lobe is a Dirac |
//! | `2π σ_x σ_y m_z⁴` below `2⁻¹²⁶` | `None` (numerically a Dirac) |
//! | the radiance overflows f32 | `None` |
//! | `Ē` negative, NaN or above `2⁶⁴` | `None` |
//!
//! The slopes and the attribute are valid by construction ([`SlopeDeviation::new`],
//! [`HeightCorrelatedAttribute::new`]); the WGSL twin takes them raw and returns `None`
//! where those constructors return an error.

use glam::Vec3;

use crate::attribute::{HeightCorrelatedAttribute, visible_mean_attribute};
use crate::erf::{EXP_ZERO_FROM, flush_subnormal, is_nan_bits};

/// Largest accepted light radiance `Ē`, `2⁶⁴`.
pub const MAX_LIGHT_RADIANCE: f32 = 18_446_744_073_709_551_616.0;
use crate::masking::{SlopeDeviation, canonical_direction, mean_visibility, smith_lambda_direction};

/// The slopes of the surface's NDF convolved with the BRDF's microfacet slopes (§5.5):
/// `√(σ_n² + σ_np²)` per axis: at most `√2` [`MAX_SLOPE_DEVIATION`](crate::masking::MAX_SLOPE_DEVIATION),
/// which [`SlopeDeviation`]'s invariant allows.
///
/// WGSL twin: `smith_convolved_slope_deviation`.
pub fn convolved_slope_deviation(surface: SlopeDeviation, brdf: SlopeDeviation) -> SlopeDeviation {
    SlopeDeviation::convolved(scaled_hypot(surface.x(), brdf.x()), scaled_hypot(surface.y(), brdf.y()))
}

/// `√(a² + b²)` for `a, b ≥ 0`, as `m √(1 + (n/m)²)` with `m = max`, `n = min` (the
/// WGSL twin has no `hypot`).
fn scaled_hypot(a: f32, b: f32) -> f32 {
    let (larger, smaller) = (a.max(b), a.min(b));
    if larger == 0.0 {
        return 0.0;
    }
    let ratio = smaller / larger;
    larger * libm::sqrtf(1.0 + ratio * ratio)
}

/// `a·b`, or `None` when it overflows f32, decided without forming an infinity.
fn checked_mul(a: f32, b: f32) -> Option<f32> {
    let overflows = b.abs() > 1.0 && a.abs() > f32::MAX / b.abs();
    (!overflows).then(|| flush_subnormal(a * b))
}

/// `a/b` for `b > 0`, or `None` when it overflows f32.
fn checked_div(a: f32, b: f32) -> Option<f32> {
    let overflows = b < 1.0 && a.abs() > f32::MAX * b;
    (!overflows).then(|| flush_subnormal(a / b))
}

/// The Gaussian-slope NDF `D(m)` of a microfacet normal `m` (need not be normalized) in
/// the mean-normal frame: `Some(0)` for `m_z ≤ 0`, `None` for a zero or non-finite `m`
/// and for the Dirac cases of the module's table.
///
/// WGSL twin: `smith_gaussian_slope_ndf`.
pub fn gaussian_slope_ndf(normal: Vec3, slopes: SlopeDeviation) -> Option<f32> {
    let m = canonical_direction(normal)?;
    let (sigma_x, sigma_y) = (slopes.x(), slopes.y());
    if sigma_x == 0.0 || sigma_y == 0.0 {
        return None;
    }
    if m.z <= 0.0 {
        return Some(0.0);
    }
    let m = (m / m.length()).map(flush_subnormal);
    // q / m_z² is the exponent s_x²/2σ_x² + s_y²/2σ_y²; |m_x/σ_x| ≤ 2³² so q is finite,
    // and comparing q with 104 m_z² avoids dividing by a tiny m_z².
    let (x, y) = (m.x / sigma_x, m.y / sigma_y);
    let q = 0.5 * (x * x + y * y);
    let z_squared = flush_subnormal(m.z * m.z);
    if q >= EXP_ZERO_FROM * z_squared {
        return Some(0.0);
    }
    let gaussian = flush_subnormal(libm::expf(-(q / z_squared)));
    let denominator =
        flush_subnormal(core::f32::consts::TAU * sigma_x * sigma_y * flush_subnormal(z_squared * z_squared));
    if denominator == 0.0 {
        return None;
    }
    // gaussian ≤ 1 and denominator ≥ 2⁻¹²⁶: the quotient is below 8.5·10³⁷.
    Some(flush_subnormal(gaussian / denominator))
}

/// The statistics of a pre-filtered surface element that eq. 13 needs. Its fields are
/// public: it has no invariant of its own, each field's type guarantees its validity
/// ([`SlopeDeviation`], [`HeightCorrelatedAttribute`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilteredSurface {
    /// `σ_nx, σ_ny`: the slopes of the filtered surface (masking, eq. 6, and the NDF).
    pub slopes: SlopeDeviation,
    /// `σ_npx, σ_npy`: the microfacet slopes of the BRDF (§5.5).
    pub brdf_slopes: SlopeDeviation,
    /// `ā, a_s` of the attribute (H5bis).
    pub attribute: HeightCorrelatedAttribute,
}

/// Eq. 13: the radiance reflected towards `view` from `light` (both in the mean-normal
/// frame, need not be normalized) by `surface`, lit with radiance `light_radiance`
/// (`Ē`). See the module's table for every special case.
///
/// WGSL twin: `smith_shade`.
pub fn shade(view: Vec3, light: Vec3, surface: FilteredSurface, light_radiance: f32) -> Option<f32> {
    if is_nan_bits(light_radiance) || !(0.0..=MAX_LIGHT_RADIANCE).contains(&light_radiance) {
        return None;
    }
    let v = canonical_direction(view)?;
    let l = canonical_direction(light)?;
    let (v, l) = ((v / v.length()).map(flush_subnormal), (l / l.length()).map(flush_subnormal));
    if v.z <= 0.0 {
        return None;
    }
    if l.z <= 0.0 {
        return Some(0.0);
    }
    let lambda_view = smith_lambda_direction(v, surface.slopes)?;
    let lambda_light = smith_lambda_direction(l, surface.slopes)?;
    let attribute = visible_mean_attribute(surface.attribute, lambda_view, lambda_light)?;
    let lobe = gaussian_slope_ndf(v + l, convolved_slope_deviation(surface.slopes, surface.brdf_slopes))?;
    let visibility = flush_subnormal(mean_visibility(lambda_view)? * mean_visibility(lambda_light)?);
    let reflected = checked_div(flush_subnormal(lobe * visibility), 4.0 * v.z)?;
    checked_mul(light_radiance, checked_mul(attribute, reflected)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ndf_integrates_to_one_over_projected_area() {
        // ∫ D(m) m_z dω = 1 for a normalized NDF (midpoint rule in θ, φ).
        for slopes in [SlopeDeviation::new(0.3, 0.3).unwrap(), SlopeDeviation::new(0.1, 0.5).unwrap()] {
            let (steps_theta, steps_phi) = (2000, 400);
            let mut total = 0.0_f64;
            for i in 0..steps_theta {
                let theta = (f64::from(i) + 0.5) / f64::from(steps_theta) * core::f64::consts::FRAC_PI_2;
                for j in 0..steps_phi {
                    let phi = (f64::from(j) + 0.5) / f64::from(steps_phi) * core::f64::consts::TAU;
                    let m = Vec3::new(
                        (libm::sin(theta) * libm::cos(phi)) as f32,
                        (libm::sin(theta) * libm::sin(phi)) as f32,
                        libm::cos(theta) as f32,
                    );
                    let d = f64::from(gaussian_slope_ndf(m, slopes).unwrap());
                    total += d * libm::cos(theta) * libm::sin(theta);
                }
            }
            total *=
                core::f64::consts::FRAC_PI_2 / f64::from(steps_theta) * core::f64::consts::TAU / f64::from(steps_phi);
            assert!((total - 1.0).abs() < 1e-3, "{slopes:?}: {total}");
        }
    }

    #[test]
    fn convolution_adds_variances() {
        let c =
            convolved_slope_deviation(SlopeDeviation::new(0.3, 0.0).unwrap(), SlopeDeviation::new(0.4, 0.2).unwrap());
        assert!((c.x() - 0.5).abs() < 1e-7 && (c.y() - 0.2).abs() < 1e-7);
        // The largest accepted deviations convolve to √2 times the bound, finite, and the
        // NDF and Λ stay finite on them.
        let steep = SlopeDeviation::isotropic(crate::masking::MAX_SLOPE_DEVIATION).unwrap();
        let widest = convolved_slope_deviation(steep, steep);
        assert!((widest.x() / crate::masking::MAX_SLOPE_DEVIATION - core::f32::consts::SQRT_2).abs() < 1e-6);
        assert!(gaussian_slope_ndf(Vec3::new(0.3, 0.2, 1.0), widest).is_some_and(|d| d.is_finite() && d > 0.0));
        assert!(smith_lambda_direction(Vec3::new(1.0, 0.0, 1.0), widest).is_some_and(f32::is_finite));
    }

    #[test]
    fn special_inputs_have_defined_results() {
        let surface = FilteredSurface {
            slopes: SlopeDeviation::new(0.2, 0.4).unwrap(),
            brdf_slopes: SlopeDeviation::isotropic(0.1).unwrap(),
            attribute: HeightCorrelatedAttribute::new(0.6, 0.2).unwrap(),
        };
        let normal_incidence = shade(Vec3::Z, Vec3::Z, surface, 1.0).unwrap();
        // At v = l = n: D(n) / 4 · ā with Λ = 0.
        let expected = 0.6 / (core::f32::consts::TAU * 0.2_f32.hypot(0.1) * 0.4_f32.hypot(0.1)) / 4.0;
        assert!((normal_incidence - expected).abs() < 1e-6 * expected);
        assert_eq!(shade(Vec3::Z, Vec3::new(1.0, 0.0, -0.1), surface, 1.0), Some(0.0));
        assert_eq!(shade(Vec3::Z, Vec3::X, surface, 1.0), Some(0.0));
        assert_eq!(shade(Vec3::new(1.0, 0.0, -0.1), Vec3::Z, surface, 1.0), None);
        assert_eq!(shade(Vec3::X, Vec3::Z, surface, 1.0), None);
        assert_eq!(shade(Vec3::Z, Vec3::Z, surface, -1.0), None);
        assert_eq!(shade(Vec3::Z, Vec3::Z, surface, f32::NAN), None);
        assert_eq!(shade(Vec3::ZERO, Vec3::Z, surface, 1.0), None);
        let mirror = FilteredSurface {
            slopes: SlopeDeviation::isotropic(0.0).unwrap(),
            brdf_slopes: SlopeDeviation::isotropic(0.0).unwrap(),
            ..surface
        };
        assert_eq!(shade(Vec3::Z, Vec3::Z, mirror, 1.0), None);
        assert_eq!(gaussian_slope_ndf(Vec3::new(1.0, 0.0, -1.0), surface.slopes), Some(0.0));
        assert_eq!(gaussian_slope_ndf(Vec3::Z, SlopeDeviation::isotropic(1e-25).unwrap()), None);
    }
}
