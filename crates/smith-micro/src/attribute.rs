//! The view- and light-dependent mean visible attribute `ā(v, l)` (eqs. 14–17).
//!
//! Under hypotheses H5 and H5bis an attribute depends on height only,
//! `a(h) = ā + a_s s(h)` with `s(h) = 2g(h) − 1`, and Smith's visibility from the eye
//! and from the light is `g(h)^Λ(v)` and `g(h)^Λ(l)`. Eq. 15 then integrates to eq. 17:
//!
//! `ā(v, l) = ā + a_s (2 (Λ + 1)/(Λ + 2) − 1) = ā + a_s Λ / (Λ + 2)`,
//! `Λ = Λ(v) + Λ(l)`,
//!
//! since with `u = g(h)`, `∫ g′ g^(Λ+1) dh / ∫ g′ g^Λ dh = (Λ+1)/(Λ+2)`. (We re-derived it;
//! the extraction of eq. 17 matches.) Notably `σ_h` cancels: `ā(v, l)` depends on the
//! heights only through `a_s`, and on the slopes through Λ. It is evaluated as
//! `ā + a_s / (1 + 2/Λ)`, which has no cancellation for small Λ and tends to `ā + a_s`
//! as Λ → ∞.
//!
//! | input | `ā(v, l)` |
//! |---|---|
//! | `Λ(v) = Λ(l) = 0` (normal incidence or flat) | `ā` |
//! | either Λ `= +∞` (grazing) | `ā + a_s`: only the highest points are seen |
//! | a Λ negative or NaN, `|ā|` or `|a_s|` above `2⁶⁴` or NaN | `None` |
//! | view or light below the horizon ([`visible_mean_attribute_for_directions`]) | `None` |

use glam::Vec3;

use crate::erf::{flush_subnormal, is_infinite_bits, is_nan_bits};
use crate::masking::{SlopeDeviation, smith_lambda_direction};

/// An attribute correlated with height (hypothesis H5bis): `a(h) = ā + a_s (2g(h) − 1)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeightCorrelatedAttribute {
    /// `ā`, the attribute's mean over the surface.
    pub mean: f32,
    /// `a_s`, the projection of the attribute on `s(h)` (§5.2): positive when higher
    /// points have larger values.
    pub height_correlation: f32,
}

/// Largest accepted `|ā|` and `|a_s|`, `2⁶⁴`, so that `ā + a_s x` never overflows f32
/// (which the WGSL twin could not represent).
pub const MAX_ATTRIBUTE_MAGNITUDE: f32 = 18_446_744_073_709_551_616.0;

impl HeightCorrelatedAttribute {
    /// Whether `|ā|` and `|a_s|` are both at most [`MAX_ATTRIBUTE_MAGNITUDE`] (false
    /// for NaN).
    pub fn is_valid(&self) -> bool {
        let valid = |x: f32| !is_nan_bits(x) && x.abs() <= MAX_ATTRIBUTE_MAGNITUDE;
        valid(self.mean) && valid(self.height_correlation)
    }
}

/// Eq. 17 from the two masking values `Λ(v)` and `Λ(l)` (see the module's table).
///
/// WGSL twin: `smith_visible_mean_attribute`.
pub fn visible_mean_attribute(
    attribute: HeightCorrelatedAttribute,
    lambda_view: f32,
    lambda_light: f32,
) -> Option<f32> {
    if !(is_valid_lambda(lambda_view) && is_valid_lambda(lambda_light) && attribute.is_valid()) {
        return None;
    }
    // Λ = +∞ (or a sum beyond f32) gives 1; Λ = 0 gives 0; a normal Λ ≥ 1.2·10⁻³⁸ keeps
    // 2/Λ finite.
    let infinite =
        is_infinite_bits(lambda_view) || is_infinite_bits(lambda_light) || lambda_view > f32::MAX - lambda_light;
    let lambda = flush_subnormal(lambda_view + lambda_light);
    let visible_fraction = if infinite { 1.0 } else { visible_fraction_of_finite(lambda) };
    Some(attribute.mean + attribute.height_correlation * visible_fraction)
}

/// Whether `lambda` is a Smith Λ (eq. 6): `+∞` or a value `≥ 0` (false for NaN). WGSL
/// twin: `smith_lambda_is_valid`.
pub(crate) fn is_valid_lambda(lambda: f32) -> bool {
    !is_nan_bits(lambda) && lambda >= 0.0
}

/// Eq. 17's visible fraction `Λ/(Λ + 2)`, written `1/(1 + 2/Λ)`, for a finite, flushed
/// `Λ ≥ 0`: 0 for `Λ = 0`, and a normal `Λ ≥ 1.2·10⁻³⁸` keeps `2/Λ` finite (callers give
/// 1 for `Λ = +∞`). Shared by eq. 17 and the corrected models. WGSL twin:
/// `smith_visible_fraction_of_finite`.
pub(crate) fn visible_fraction_of_finite(lambda: f32) -> f32 {
    if lambda == 0.0 { 0.0 } else { 1.0 / (1.0 + 2.0 / lambda) }
}

/// Eq. 17 for a view and a light direction in the mean-normal frame (z along the mean
/// normal, need not be normalized) over slopes `slopes` (`σ_nx`, `σ_ny`, e.g. measured
/// on a surface): `None` when either direction is below the horizon, zero or not finite.
pub fn visible_mean_attribute_for_directions(
    attribute: HeightCorrelatedAttribute,
    view: Vec3,
    light: Vec3,
    slopes: SlopeDeviation,
) -> Option<f32> {
    let lambda_view = smith_lambda_direction(view, slopes)?;
    let lambda_light = smith_lambda_direction(light, slopes)?;
    visible_mean_attribute(attribute, lambda_view, lambda_light)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::height::{attribute_at_height, height_visibility};

    /// Eq. 15 by numerical integration over `h` (trapezoids on `±12σ_h`).
    fn eq15_by_integration(attribute: HeightCorrelatedAttribute, lambda: f64, sigma_h: f32) -> f64 {
        let (mut numerator, mut denominator) = (0.0_f64, 0.0_f64);
        let steps = 48_000;
        for i in 0..=steps {
            let h = (-12.0 + 24.0 * f64::from(i) / f64::from(steps)) * f64::from(sigma_h);
            let density = libm::exp(-h * h / (2.0 * f64::from(sigma_h).powi(2)));
            let visibility = f64::from(height_visibility(lambda as f32, h as f32, sigma_h).unwrap());
            let a = f64::from(attribute_at_height(attribute, h as f32, sigma_h).unwrap());
            numerator += a * visibility * density;
            denominator += visibility * density;
        }
        numerator / denominator
    }

    #[test]
    fn eq17_matches_eq15_integrated() {
        let attribute = HeightCorrelatedAttribute { mean: 0.4, height_correlation: 0.3 };
        for (lambda_view, lambda_light) in [(0.0_f32, 0.0_f32), (0.2, 0.0), (1.0, 0.5), (4.0, 7.0), (30.0, 0.1)] {
            let closed = visible_mean_attribute(attribute, lambda_view, lambda_light).unwrap();
            let integrated = eq15_by_integration(attribute, f64::from(lambda_view + lambda_light), 0.8);
            assert!(
                (f64::from(closed) - integrated).abs() < 2e-5,
                "Λ={lambda_view}+{lambda_light}: {closed} vs {integrated}"
            );
        }
    }

    #[test]
    fn special_inputs_have_defined_results() {
        let attribute = HeightCorrelatedAttribute { mean: 0.5, height_correlation: -0.2 };
        assert_eq!(visible_mean_attribute(attribute, 0.0, 0.0), Some(0.5));
        assert_eq!(visible_mean_attribute(attribute, f32::INFINITY, 0.0), Some(0.3));
        assert_eq!(visible_mean_attribute(attribute, f32::INFINITY, f32::INFINITY), Some(0.3));
        assert_eq!(visible_mean_attribute(attribute, -1.0, 0.0), None);
        assert_eq!(visible_mean_attribute(attribute, 0.0, f32::NAN), None);
        let broken = HeightCorrelatedAttribute { mean: f32::INFINITY, height_correlation: 0.0 };
        assert_eq!(visible_mean_attribute(broken, 0.0, 0.0), None);
        let slopes = SlopeDeviation::new(0.1, 0.6).unwrap();
        let below = Vec3::new(0.0, 1.0, -0.2);
        assert_eq!(visible_mean_attribute_for_directions(attribute, Vec3::Z, below, slopes), None);
        // Fig. 5 (b–d): grazing along the flat axis changes nothing, along the rough axis
        // only the high points remain.
        let grooves = SlopeDeviation::new(0.0, 0.6).unwrap();
        let along_flat = visible_mean_attribute_for_directions(attribute, Vec3::Z, Vec3::new(1.0, 0.0, 0.01), grooves);
        let along_rough = visible_mean_attribute_for_directions(attribute, Vec3::Z, Vec3::new(0.0, 1.0, 0.01), grooves);
        assert_eq!(along_flat, Some(0.5));
        assert!((along_rough.unwrap() - 0.3).abs() < 0.02);
    }
}
