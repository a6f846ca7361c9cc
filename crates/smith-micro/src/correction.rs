//! A per-material correction of Smith's Λ, kept beside eq. 17: `Λ' = c(u) Λ` with
//! `u = Λ/(1 + Λ)` and `c` piecewise linear over eight knots, and the corrected mean
//! visible attribute `ā(v, l) = ā + a_s Λ'/(Λ' + 2)`.
//!
//! Eq. 17 (Heitz & Neyret 2012, §5.5) is exact for Smith's masking `g(h)^Λ`; on real
//! Gaussian height fields the ray-traced mean attribute differs from it by a factor on Λ
//! that depends on the spectrum and on Λ (measured by `cargo xtask fig9 --spectra`:
//! 0.86 … 1.6), not on Λ alone. A pre-computation that has a material's detailed height
//! field can fit that factor to ray-traced ground truth (`microsurface-truth`'s
//! `fit_lambda_correction`) and store it per material as a [`LambdaCorrection`]: eight
//! factors, two `vec4`s on the GPU. [`LambdaCorrection::IDENTITY`] gives eq. 17 exactly,
//! bit for bit.
//!
//! On the GPU the correction costs 22 operations more than eq. 17
//! (`smith_corrected_visible_mean_attribute`: the `Λ/(1 + Λ)` division, the lookup, one
//! product and a flush; counted on naga's IR by the test `smith_micro_cost` in
//! `shader-registry`, eq. 17 being 61). Its cubic form, [`crate::cubic_correction`],
//! costs 16 and is as accurate on the ray-traced sweeps.
//!
//! A [`LambdaCorrection`] is valid by construction: its knots are private and
//! [`LambdaCorrection::from_knots`] (or [`LambdaCorrection::IDENTITY`]) checks them once
//! per material, naming the knot it rejects ([`LambdaCorrectionError`]); no evaluation
//! re-checks them. The GPU reads its [`GpuLambdaCorrection`] ([`LambdaCorrection::to_gpu`]),
//! and the WGSL twins assume it came from there.
//!
//! The correction applies to the **sum** `Λ = Λ(v) + Λ(l)`
//! ([`corrected_visible_mean_attribute`]): eq. 17 only sees the sum, and a factor fitted
//! on view-only sweeps (`Λ(l) = 0`) describes the visible attribute as a function of
//! it. Correcting each direction instead is
//! `visible_mean_attribute(a, corrected_lambda(Λ(v))?, corrected_lambda(Λ(l))?)`; both
//! agree when either Λ is zero.
//!
//! | input | [`corrected_lambda`] | [`corrected_visible_mean_attribute`] |
//! |---|---|---|
//! | `Λ = 0` (normal incidence, flat) | `0` | `ā` |
//! | `Λ = +∞`, or above [`MAX_CORRECTED_LAMBDA`] | `+∞` | `ā + a_s` |
//! | `Λ` subnormal, or `c Λ` subnormal | `0` (flushed, as the GPU does) | `ā` |
//! | a Λ negative or NaN | `None` | `None` |
//! | [`LambdaCorrection::IDENTITY`] | `Λ` (flushed) | eq. 17, same bits |
//!
//! | knots given to [`LambdaCorrection::from_knots`] | result |
//! |---|---|
//! | all in `[MIN_CORRECTION_FACTOR, MAX_CORRECTION_FACTOR]` | the correction |
//! | knot `i` NaN | [`LambdaCorrectionError::KnotNotANumber`] |
//! | knot `i` below `MIN_CORRECTION_FACTOR` (`−∞` included) | [`LambdaCorrectionError::KnotBelowMinimum`] |
//! | knot `i` above `MAX_CORRECTION_FACTOR` (`+∞` included) | [`LambdaCorrectionError::KnotAboveMaximum`] |

use core::fmt;

use glam::Vec4;
use gpu_layout::gpu_struct;

use crate::attribute::{HeightCorrelatedAttribute, is_valid_lambda, visible_fraction_of_finite};
use crate::erf::{flush_subnormal, is_infinite_bits, is_nan_bits};

/// Number of knots of a [`LambdaCorrection`], at `u = i/7`, `i = 0 … 7`.
pub const CORRECTION_KNOTS: usize = 8;

/// Smallest accepted correction factor: a knot below it is rejected.
pub const MIN_CORRECTION_FACTOR: f32 = 0.25;

/// Largest accepted correction factor, so that `c Λ` never overflows f32.
pub const MAX_CORRECTION_FACTOR: f32 = 4.0;

/// `2⁶⁴`: Λ above it is corrected to `+∞`. Eq. 17 gives `ā + a_s` to the last bit for any
/// Λ' above `2⁶³`, so the visible attribute does not change; bounding Λ keeps `c Λ` and
/// `1 + Λ` far from overflow in WGSL, which cannot represent it.
pub const MAX_CORRECTED_LAMBDA: f32 = 18_446_744_073_709_551_616.0;

/// A per-material factor `c(u)` on Smith's Λ (eq. 6), piecewise linear in
/// `u = Λ/(1 + Λ) ∈ [0, 1]` through eight knots at `u = i/7` (`u = 1` is `Λ = ∞`), each
/// in `[MIN_CORRECTION_FACTOR, MAX_CORRECTION_FACTOR]`: built only by
/// [`LambdaCorrection::from_knots`] (or a fit through it) and
/// [`LambdaCorrection::IDENTITY`]. See the module's table for what each input gives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LambdaCorrection {
    knots: [f32; CORRECTION_KNOTS],
}

/// Why [`LambdaCorrection::from_knots`] rejected a table: the first knot outside
/// `[MIN_CORRECTION_FACTOR, MAX_CORRECTION_FACTOR]`, by index (`0 … 7`, at `u = i/7`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LambdaCorrectionError {
    /// Knot `index` is NaN.
    KnotNotANumber {
        /// The knot's index.
        index: usize,
    },
    /// Knot `index` is below [`MIN_CORRECTION_FACTOR`] (`−∞` included).
    KnotBelowMinimum {
        /// The knot's index.
        index: usize,
        /// Its value.
        value: f32,
    },
    /// Knot `index` is above [`MAX_CORRECTION_FACTOR`] (`+∞` included).
    KnotAboveMaximum {
        /// The knot's index.
        index: usize,
        /// Its value.
        value: f32,
    },
}

impl fmt::Display for LambdaCorrectionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LambdaCorrectionError::KnotNotANumber { index } => write!(f, "correction knot {index} is NaN"),
            LambdaCorrectionError::KnotBelowMinimum { index, value } => {
                write!(f, "correction knot {index} is {value}, below {MIN_CORRECTION_FACTOR}")
            }
            LambdaCorrectionError::KnotAboveMaximum { index, value } => {
                write!(f, "correction knot {index} is {value}, above {MAX_CORRECTION_FACTOR}")
            }
        }
    }
}

impl core::error::Error for LambdaCorrectionError {}

gpu_struct! {
    /// A [`LambdaCorrection`] as the GPU reads it ([`LambdaCorrection::to_gpu`]), the
    /// correction argument of the WGSL twins, which assume it came from a validated
    /// correction and do not re-check it. Its fields are private to this crate: safe Rust gets one only
    /// from [`LambdaCorrection::to_gpu`] (reinterpreting other bytes with `bytemuck` voids
    /// that guarantee).
    pub struct GpuLambdaCorrection {
        /// Factors at `u = 0, 1/7, 2/7, 3/7` (`Λ = 0, 1/6, 2/5, 3/4`).
        pub(crate) low: Vec4,
        /// Factors at `u = 4/7, 5/7, 6/7, 1` (`Λ = 4/3, 5/2, 6, ∞`).
        pub(crate) high: Vec4,
    }
}

impl LambdaCorrection {
    /// No correction: every factor is 1, and the corrected functions equal eq. 17.
    pub const IDENTITY: Self = Self { knots: [1.0; CORRECTION_KNOTS] };

    /// The correction through `knots` (factors at `u = i/7`), or the first knot that is
    /// NaN or outside `[MIN_CORRECTION_FACTOR, MAX_CORRECTION_FACTOR]`, and why.
    pub fn from_knots(knots: [f32; CORRECTION_KNOTS]) -> Result<Self, LambdaCorrectionError> {
        for (index, &value) in knots.iter().enumerate() {
            if is_nan_bits(value) {
                return Err(LambdaCorrectionError::KnotNotANumber { index });
            }
            if value < MIN_CORRECTION_FACTOR {
                return Err(LambdaCorrectionError::KnotBelowMinimum { index, value });
            }
            if value > MAX_CORRECTION_FACTOR {
                return Err(LambdaCorrectionError::KnotAboveMaximum { index, value });
            }
        }
        Ok(Self { knots })
    }

    /// The eight factors, at `u = 0, 1/7, …, 1`.
    pub fn knots(&self) -> [f32; CORRECTION_KNOTS] {
        self.knots
    }

    /// The correction as the GPU reads it: knots 0 … 3 in `low`, 4 … 7 in `high`.
    pub fn to_gpu(&self) -> GpuLambdaCorrection {
        let [a, b, c, d, e, f, g, h] = self.knots;
        GpuLambdaCorrection { low: Vec4::new(a, b, c, d), high: Vec4::new(e, f, g, h) }
    }

    /// The factor `c(u)` for `u ∈ [0, 1]`, interpolated linearly between the knots
    /// (`u` is clamped to `[0, 1]`; NaN gives the first knot).
    ///
    /// WGSL twin: `smith_correction_factor`.
    pub fn factor(&self, u: f32) -> f32 {
        let t = u.clamp(0.0, 1.0) * (CORRECTION_KNOTS - 1) as f32;
        // `t as usize` saturates (NaN gives 0), and `min` keeps `index + 1` in range.
        let index = (t as usize).min(CORRECTION_KNOTS - 2);
        let fraction = if is_nan_bits(t) { 0.0 } else { t - index as f32 };
        let knot = |i: usize| self.knots.get(i).copied().unwrap_or(1.0);
        let (k0, k1) = (knot(index), knot(index + 1));
        k0 + fraction * (k1 - k0)
    }
}

impl Default for LambdaCorrection {
    fn default() -> Self {
        Self::IDENTITY
    }
}

/// The corrected `Λ' = c(Λ/(1 + Λ)) Λ` of a Smith Λ (eq. 6); see the module's table.
///
/// WGSL twin: `smith_corrected_lambda`.
pub fn corrected_lambda(lambda: f32, correction: &LambdaCorrection) -> Option<f32> {
    if !is_valid_lambda(lambda) {
        return None;
    }
    if is_infinite_bits(lambda) || lambda > MAX_CORRECTED_LAMBDA {
        return Some(f32::INFINITY);
    }
    let lambda = flush_subnormal(lambda);
    let u = lambda / (1.0 + lambda);
    Some(flush_subnormal(correction.factor(u) * lambda))
}

/// Eq. 17 with the corrected sum: `ā + a_s Λ'/(Λ' + 2)`, `Λ' = c(u) Λ`,
/// `Λ = Λ(v) + Λ(l)` (see the module's table). With [`LambdaCorrection::IDENTITY`] this
/// is [`crate::visible_mean_attribute`], bit for bit.
///
/// WGSL twin: `smith_corrected_visible_mean_attribute`.
pub fn corrected_visible_mean_attribute(
    attribute: HeightCorrelatedAttribute,
    lambda_view: f32,
    lambda_light: f32,
    correction: &LambdaCorrection,
) -> Option<f32> {
    visible_mean_attribute_of_corrected_sum(attribute, lambda_view, lambda_light, |u| correction.factor(u))
}

/// `ā + a_s Λ'/(Λ' + 2)` for the sum `Λ = Λ(v) + Λ(l)` corrected to `Λ' = c(u) Λ`,
/// `u = Λ/(1 + Λ)`, `c` given by `factor` (of a validated correction), with the special
/// inputs of the module's table: shared by the table and its cubic form
/// ([`crate::cubic_correction`]).
pub(crate) fn visible_mean_attribute_of_corrected_sum(
    attribute: HeightCorrelatedAttribute,
    lambda_view: f32,
    lambda_light: f32,
    factor: impl Fn(f32) -> f32,
) -> Option<f32> {
    if !(is_valid_lambda(lambda_view) && is_valid_lambda(lambda_light)) {
        return None;
    }
    let infinite =
        is_infinite_bits(lambda_view) || is_infinite_bits(lambda_light) || lambda_view > f32::MAX - lambda_light;
    // As eq. 17: 0 gives 0, ∞ gives 1, a normal Λ' keeps 2/Λ' finite; above
    // MAX_CORRECTED_LAMBDA the corrected Λ is +∞.
    let mut visible_fraction = 1.0;
    if !infinite {
        let lambda = flush_subnormal(lambda_view + lambda_light);
        if lambda <= MAX_CORRECTED_LAMBDA {
            let u = lambda / (1.0 + lambda);
            visible_fraction = visible_fraction_of_finite(flush_subnormal(factor(u) * lambda));
        }
    }
    Some(attribute.at(visible_fraction))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::attribute::{MAX_ATTRIBUTE_MAGNITUDE, visible_mean_attribute};

    /// Λs that stress the corrections: zero, subnormal, the bounds, ∞, negative, NaN.
    pub(crate) const SPECIAL: [f32; 16] = [
        0.0,
        -0.0,
        1e-40,
        f32::MIN_POSITIVE,
        1e-3,
        0.2,
        1.0,
        5.0,
        30.0,
        1e19,
        MAX_CORRECTED_LAMBDA,
        3e30,
        f32::MAX,
        f32::INFINITY,
        -1.0,
        f32::NAN,
    ];

    /// Asserts that `corrected(attribute, Λ(v), Λ(l))` has the bits of eq. 17 over special
    /// and ordinary inputs.
    pub(crate) fn assert_eq17_bit_for_bit(corrected: impl Fn(HeightCorrelatedAttribute, f32, f32) -> Option<f32>) {
        let attributes = [
            HeightCorrelatedAttribute::new(0.4, 0.3).unwrap(),
            HeightCorrelatedAttribute::new(-1.5, -2.0).unwrap(),
            HeightCorrelatedAttribute::new(-MAX_ATTRIBUTE_MAGNITUDE, MAX_ATTRIBUTE_MAGNITUDE).unwrap(),
        ];
        let mut lambdas = SPECIAL.to_vec();
        lambdas.extend((0..400).map(|i| 1e-4 * 1.05_f32.powi(i)));
        for attribute in attributes {
            for &view in &lambdas {
                for &light in &SPECIAL {
                    let eq17 = visible_mean_attribute(attribute, view, light).map(f32::to_bits);
                    let corrected = corrected(attribute, view, light);
                    assert_eq!(corrected.map(f32::to_bits), eq17, "Λ = {view} + {light}");
                }
            }
        }
    }

    #[test]
    fn identity_is_eq17_bit_for_bit() {
        assert_eq17_bit_for_bit(|attribute, view, light| {
            corrected_visible_mean_attribute(attribute, view, light, &LambdaCorrection::IDENTITY)
        });
    }

    #[test]
    fn factor_interpolates_the_knots() {
        let knots = [0.5, 0.75, 1.0, 1.5, 2.0, 1.25, 1.0, 3.0];
        let correction = LambdaCorrection::from_knots(knots).unwrap();
        assert_eq!(correction.knots(), knots);
        for (i, &k) in knots.iter().enumerate() {
            assert_eq!(correction.factor(i as f32 / 7.0), k, "knot {i}");
        }
        assert!((correction.factor(0.5 / 7.0) - 0.625).abs() < 1e-6);
        assert!((correction.factor(6.5 / 7.0) - 2.0).abs() < 1e-6);
        assert_eq!(correction.factor(-1.0), 0.5);
        assert_eq!(correction.factor(2.0), 3.0);
        assert_eq!(correction.factor(f32::NAN), 0.5);
        // Λ = 1 is u = 1/2, between knots 3 (1.5) and 4 (2.0).
        let expected = 1.5 + 0.5 * (2.0 - 1.5);
        assert!((corrected_lambda(1.0, &correction).unwrap() - expected).abs() < 1e-6);
    }

    #[test]
    fn special_inputs_have_defined_results() {
        let correction = LambdaCorrection::from_knots([1.2, 1.2, 1.1, 0.9, 0.8, 0.7, 0.6, 0.5]).unwrap();
        let attribute = HeightCorrelatedAttribute::new(0.5, -0.2).unwrap();
        assert_eq!(corrected_lambda(0.0, &correction), Some(0.0));
        assert_eq!(corrected_lambda(1e-40, &correction), Some(0.0));
        assert_eq!(corrected_lambda(f32::INFINITY, &correction), Some(f32::INFINITY));
        assert_eq!(corrected_lambda(f32::MAX, &correction), Some(f32::INFINITY));
        assert_eq!(corrected_lambda(-1.0, &correction), None);
        assert_eq!(corrected_lambda(f32::NAN, &correction), None);
        let grazing = corrected_visible_mean_attribute(attribute, f32::MAX, f32::MAX, &correction);
        assert_eq!(grazing, Some(0.3));
        assert_eq!(corrected_visible_mean_attribute(attribute, 0.0, 0.0, &correction), Some(0.5));
        assert_eq!(corrected_visible_mean_attribute(attribute, 0.0, f32::NAN, &correction), None);
        // Every accepted input gives a finite result, whatever the knots.
        let extreme = LambdaCorrection::from_knots([0.25, 4.0, 0.25, 4.0, 0.25, 4.0, 0.25, 4.0]).unwrap();
        for &view in &SPECIAL[..14] {
            for &light in &SPECIAL[..14] {
                let value = corrected_visible_mean_attribute(attribute, view, light, &extreme).unwrap();
                assert!(value.is_finite() && (0.3..=0.5).contains(&value), "Λ = {view} + {light}: {value}");
            }
        }
    }

    #[test]
    fn a_larger_factor_sees_higher_points() {
        let attribute = HeightCorrelatedAttribute::new(0.0, 1.0).unwrap();
        let up = LambdaCorrection::from_knots([1.3; CORRECTION_KNOTS]).unwrap();
        let down = LambdaCorrection::from_knots([0.7; CORRECTION_KNOTS]).unwrap();
        for lambda in [0.05_f32, 0.5, 2.0, 10.0] {
            let eq17 = visible_mean_attribute(attribute, lambda, 0.0).unwrap();
            assert!(corrected_visible_mean_attribute(attribute, lambda, 0.0, &up).unwrap() > eq17);
            assert!(corrected_visible_mean_attribute(attribute, lambda, 0.0, &down).unwrap() < eq17);
        }
    }

    #[test]
    fn invalid_knots_are_rejected_by_index_value_and_reason() {
        use LambdaCorrectionError::{KnotAboveMaximum, KnotBelowMinimum, KnotNotANumber};
        let with = |index: usize, value: f32| {
            let mut knots = [1.0; CORRECTION_KNOTS];
            knots[index] = value;
            LambdaCorrection::from_knots(knots)
        };
        for index in 0..CORRECTION_KNOTS {
            assert_eq!(with(index, f32::NAN), Err(KnotNotANumber { index }));
            assert_eq!(with(index, -f32::NAN), Err(KnotNotANumber { index }));
            for value in [f32::NEG_INFINITY, -1.0, -0.0, 0.0, 1e-40, 0.2, 0.249_999_98] {
                assert_eq!(with(index, value), Err(KnotBelowMinimum { index, value }), "{value}");
            }
            for value in [4.000_000_5, 4.5, f32::MAX, f32::INFINITY] {
                assert_eq!(with(index, value), Err(KnotAboveMaximum { index, value }), "{value}");
            }
            // The range's ends are accepted.
            for value in [MIN_CORRECTION_FACTOR, MAX_CORRECTION_FACTOR] {
                assert_eq!(with(index, value).map(|c| c.knots()[index]), Ok(value));
            }
        }
        // The first invalid knot is reported.
        let knots = [1.0, 1.0, 9.0, f32::NAN, 0.0, 1.0, 1.0, 1.0];
        assert_eq!(LambdaCorrection::from_knots(knots), Err(KnotAboveMaximum { index: 2, value: 9.0 }));
        assert_eq!(LambdaCorrection::default(), LambdaCorrection::IDENTITY);
    }

    #[test]
    fn the_gpu_form_holds_the_knots_in_order() {
        let knots = [0.5, 0.75, 1.0, 1.5, 2.0, 1.25, 1.0, 3.0];
        let gpu = LambdaCorrection::from_knots(knots).unwrap().to_gpu();
        let floats: [f32; CORRECTION_KNOTS] = bytemuck::cast(gpu);
        assert_eq!(floats, knots);
    }
}
