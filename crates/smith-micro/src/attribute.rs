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
//! | a Λ negative or NaN | `None` |
//! | view or light below the horizon ([`visible_mean_attribute_for_directions`]) | `None` |
//!
//! The attribute is valid by construction: [`HeightCorrelatedAttribute::new`] rejects
//! `|ā|` or `|a_s|` above [`MAX_ATTRIBUTE_MAGNITUDE`] or NaN ([`AttributeError`]), so no
//! function re-checks it. The WGSL twins read `(ā, a_s)` from voxel data as a `vec2<f32>`
//! and check it on every call (`smith_attribute_is_valid`): for such an attribute they
//! return `None` where the Rust constructor returns an error.

use core::fmt;

use glam::Vec3;

use crate::erf::{flush_subnormal, is_infinite_bits, is_nan_bits};
use crate::masking::{SlopeDeviation, smith_lambda_direction};

/// An attribute correlated with height (hypothesis H5bis): `a(h) = ā + a_s (2g(h) − 1)`,
/// with `|ā|` and `|a_s|` at most [`MAX_ATTRIBUTE_MAGNITUDE`] (so that `ā + a_s x` never
/// overflows f32, which the WGSL twin could not represent). Built only by
/// [`HeightCorrelatedAttribute::new`], which checks the bound.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeightCorrelatedAttribute {
    mean: f32,
    height_correlation: f32,
}

/// Largest accepted `|ā|` and `|a_s|`, `2⁶⁴`, so that `ā + a_s x` never overflows f32
/// (which the WGSL twin could not represent).
pub const MAX_ATTRIBUTE_MAGNITUDE: f32 = 18_446_744_073_709_551_616.0;

/// Which value of a [`HeightCorrelatedAttribute`] an [`AttributeError`] is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AttributeComponent {
    /// `ā`, the mean.
    Mean,
    /// `a_s`, the height correlation.
    HeightCorrelation,
}

/// Why [`HeightCorrelatedAttribute::new`] rejected its input.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AttributeError {
    /// The value is NaN.
    NotANumber {
        /// `ā` or `a_s`.
        component: AttributeComponent,
    },
    /// `|value|` is above [`MAX_ATTRIBUTE_MAGNITUDE`] (±∞ included).
    TooLarge {
        /// `ā` or `a_s`.
        component: AttributeComponent,
        /// The value given.
        value: f32,
    },
}

impl fmt::Display for AttributeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let name = |component: &AttributeComponent| match component {
            AttributeComponent::Mean => "mean ā",
            AttributeComponent::HeightCorrelation => "height correlation a_s",
        };
        match self {
            AttributeError::NotANumber { component } => write!(f, "the attribute's {} is NaN", name(component)),
            AttributeError::TooLarge { component, value } => write!(
                f,
                "the attribute's {} is {value}, above {MAX_ATTRIBUTE_MAGNITUDE} in magnitude",
                name(component)
            ),
        }
    }
}

impl core::error::Error for AttributeError {}

impl HeightCorrelatedAttribute {
    /// The attribute `a(h) = ā + a_s (2g(h) − 1)` of H5bis with `ā = mean` and
    /// `a_s = height_correlation` (the projection of the attribute on `s(h)`, §5.2:
    /// positive when higher points have larger values), or why not: a value NaN or above
    /// [`MAX_ATTRIBUTE_MAGNITUDE`] in magnitude (the mean is checked first).
    ///
    /// WGSL twin of the check: `smith_attribute_is_valid`.
    pub fn new(mean: f32, height_correlation: f32) -> Result<Self, AttributeError> {
        let check = |component: AttributeComponent, value: f32| {
            if is_nan_bits(value) {
                Err(AttributeError::NotANumber { component })
            } else if value.abs() > MAX_ATTRIBUTE_MAGNITUDE {
                Err(AttributeError::TooLarge { component, value })
            } else {
                Ok(value)
            }
        };
        Ok(Self {
            mean: check(AttributeComponent::Mean, mean)?,
            height_correlation: check(AttributeComponent::HeightCorrelation, height_correlation)?,
        })
    }

    /// `ā`, the attribute's mean over the surface.
    pub fn mean(&self) -> f32 {
        self.mean
    }

    /// `a_s`, the projection of the attribute on `s(h) = 2g(h) − 1` (§5.2).
    pub fn height_correlation(&self) -> f32 {
        self.height_correlation
    }

    /// `ā + a_s x`, the attribute at visible fraction (or `s(h)`) `x ∈ [−1, 1]`: finite,
    /// since both magnitudes are at most `2⁶⁴`.
    pub(crate) fn at(&self, x: f32) -> f32 {
        self.mean + self.height_correlation * x
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
    if !(is_valid_lambda(lambda_view) && is_valid_lambda(lambda_light)) {
        return None;
    }
    // Λ = +∞ (or a sum beyond f32) gives 1; Λ = 0 gives 0; a normal Λ ≥ 1.2·10⁻³⁸ keeps
    // 2/Λ finite.
    let infinite =
        is_infinite_bits(lambda_view) || is_infinite_bits(lambda_light) || lambda_view > f32::MAX - lambda_light;
    let lambda = flush_subnormal(lambda_view + lambda_light);
    let visible_fraction = if infinite { 1.0 } else { visible_fraction_of_finite(lambda) };
    Some(attribute.at(visible_fraction))
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
        let attribute = HeightCorrelatedAttribute::new(0.4, 0.3).unwrap();
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
        let attribute = HeightCorrelatedAttribute::new(0.5, -0.2).unwrap();
        assert_eq!(visible_mean_attribute(attribute, 0.0, 0.0), Some(0.5));
        assert_eq!(visible_mean_attribute(attribute, f32::INFINITY, 0.0), Some(0.3));
        assert_eq!(visible_mean_attribute(attribute, f32::INFINITY, f32::INFINITY), Some(0.3));
        assert_eq!(visible_mean_attribute(attribute, -1.0, 0.0), None);
        assert_eq!(visible_mean_attribute(attribute, 0.0, f32::NAN), None);
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

    #[test]
    fn the_constructor_rejects_what_would_overflow_and_says_why() {
        use AttributeComponent::{HeightCorrelation, Mean};
        let attribute = HeightCorrelatedAttribute::new(-MAX_ATTRIBUTE_MAGNITUDE, MAX_ATTRIBUTE_MAGNITUDE).unwrap();
        assert_eq!(
            (attribute.mean(), attribute.height_correlation()),
            (-MAX_ATTRIBUTE_MAGNITUDE, MAX_ATTRIBUTE_MAGNITUDE)
        );
        // The bounds themselves keep ā + a_s x finite.
        assert_eq!(visible_mean_attribute(attribute, f32::INFINITY, 0.0), Some(0.0));
        let above = f32::from_bits(MAX_ATTRIBUTE_MAGNITUDE.to_bits() + 1);
        assert_eq!(HeightCorrelatedAttribute::new(f32::NAN, 0.0), Err(AttributeError::NotANumber { component: Mean }));
        assert_eq!(
            HeightCorrelatedAttribute::new(0.0, -f32::NAN),
            Err(AttributeError::NotANumber { component: HeightCorrelation })
        );
        assert_eq!(
            HeightCorrelatedAttribute::new(above, 0.0),
            Err(AttributeError::TooLarge { component: Mean, value: above })
        );
        assert_eq!(
            HeightCorrelatedAttribute::new(0.5, f32::NEG_INFINITY),
            Err(AttributeError::TooLarge { component: HeightCorrelation, value: f32::NEG_INFINITY })
        );
        // The mean is checked first.
        assert_eq!(
            HeightCorrelatedAttribute::new(f32::INFINITY, f32::NAN),
            Err(AttributeError::TooLarge { component: Mean, value: f32::INFINITY })
        );
    }
}
