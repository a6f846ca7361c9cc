//! Structs and constants shared with the WGSL twin, `shaders/smith_micro.wgsl`, and the
//! CPU reference of its differential kernel.
//!
//! Their WGSL declarations are generated into `shaders/generated/smith_micro.wgsl` by
//! `cargo xtask codegen`; a test checks that the WGSL layout equals this one. The
//! approximation coefficients and thresholds are generated from the Rust constants, so
//! the CPU and the GPU evaluate the same formulas with the same numbers.
//!
//! WGSL has no `Option` and WGSL implementations may assume that no NaN or infinity
//! reaches float operations, so results cross the boundary as bits: [`encode`] maps
//! `None` to [`NONE_BITS`] (a NaN, which no function of this crate returns) and every
//! other value, ±∞ included, to its own bits.

use glam::{UVec4, Vec3, Vec4};
use gpu_layout::{GpuConst, gpu_const, gpu_struct};

use crate::attribute::{
    HeightCorrelatedAttribute, MAX_ATTRIBUTE_MAGNITUDE, visible_mean_attribute, visible_mean_attribute_for_directions,
};
use crate::correction::{
    CORRECTION_KNOTS, LambdaCorrection, MAX_CORRECTED_LAMBDA, MAX_CORRECTION_FACTOR, MIN_CORRECTION_FACTOR,
    corrected_lambda, corrected_visible_mean_attribute,
};
use crate::correlated::{
    MAX_CORRELATION, MAX_CORRELATION_COEFFICIENT, MIN_CORRELATION, VisibilityCorrection, correlated_lambda,
    correlated_visible_mean_attribute, correlated_visible_mean_attribute_for_directions, cos_azimuth_difference,
};
use crate::cubic_correction::{CubicLambdaCorrection, cubic_corrected_visible_mean_attribute};
use crate::erf::{ERF_SERIES_LIMIT, ERFC_COEFFICIENTS, ERFC_ZERO_FROM, erf, erfc, erfcx};
use crate::height::{
    LOG_ONE_MINUS_SERIES_LIMIT, MAX_HEIGHT_DEVIATION, STANDARDIZED_HEIGHT_LIMIT, attribute_at_height, height_cdf,
    height_visibility, log_height_cdf,
};
use crate::masking::{
    CONTINUED_FRACTION_FROM_NU, CONTINUED_FRACTION_TERMS, FRAC_1_SQRT_PI, LAMBDA_ZERO_FROM_NU, MAX_SLOPE_DEVIATION,
    MIN_SLOPE_DEVIATION, SlopeDeviation, mean_visibility, nu_of_direction, smith_lambda, smith_lambda_direction,
    smith_lambda_from_nu,
};
use crate::shading::{FilteredSurface, MAX_LIGHT_RADIANCE, convolved_slope_deviation, gaussian_slope_ndf, shade};

/// The bits that stand for `None` in GPU results: the canonical quiet NaN.
pub const NONE_BITS: u32 = 0x7fc0_0000;

/// `value`'s bits, or [`NONE_BITS`] for `None`.
pub fn encode(value: Option<f32>) -> u32 {
    value.map_or(NONE_BITS, f32::to_bits)
}

gpu_struct! {
    /// The inputs of one case of the differential kernel `smith_values`: every function
    /// of the crate reads the fields it needs (see [`reference_results`]).
    pub struct SmithCase {
        /// `xyz`: the view direction in the mean-normal frame; `w`: a `ν` for
        /// `smith_lambda_from_nu`.
        pub view: Vec4,
        /// `xyz`: the light direction; `w`: an `x` for `erf`, `erfc`, `erfcx`.
        pub light: Vec4,
        /// `(σ_nx, σ_ny, σ_npx, σ_npy)`: surface and BRDF slope deviations.
        pub slopes: Vec4,
        /// `(μ, σ, h, σ_h)`: the isotropic Λ's inputs, a height and the height deviation.
        pub scalars: Vec4,
        /// `(ā, a_s, Ē, Λ)`: the attribute, the light radiance, and a Λ for `g^Λ` and
        /// `1/(1+Λ)`.
        pub material: Vec4,
    }
}

gpu_struct! {
    /// The encoded results of one [`SmithCase`], in the order of [`reference_results`].
    pub struct SmithResults {
        /// Four groups of four results.
        pub values: [UVec4; 4],
    }
}

/// The CPU reference of the kernel `smith_values`: 16 encoded results,
///
/// `erf(x), erfc(x), erfcx(x), Λ(ν)`,
/// `Λ(μ, σ), Λ(view), Λ(light), 1/(1+Λ)`,
/// `g(h), ln g(h), g(h)^Λ, a(h)`,
/// `ā(view, light), D(view) with the convolved slopes, eq. 13, ν(view)`.
pub fn reference_results(case: &SmithCase) -> SmithResults {
    let (view, light) = (case.view.truncate(), case.light.truncate());
    let [mu, sigma, height, height_deviation] = case.scalars.to_array();
    let [mean, correlation, radiance, lambda] = case.material.to_array();
    let slopes = SlopeDeviation::new(case.slopes.x, case.slopes.y);
    let brdf_slopes = SlopeDeviation::new(case.slopes.z, case.slopes.w);
    let attribute = HeightCorrelatedAttribute { mean, height_correlation: correlation };
    let x = case.light.w;
    let lambda_of = |d: Vec3| slopes.and_then(|s| smith_lambda_direction(d, s));
    let convolved = slopes.zip(brdf_slopes).map(|(s, b)| convolved_slope_deviation(s, b));
    let surface =
        slopes.zip(brdf_slopes).map(|(slopes, brdf_slopes)| FilteredSurface { slopes, brdf_slopes, attribute });
    let values = [
        erf(x),
        erfc(x),
        erfcx(x),
        smith_lambda_from_nu(case.view.w),
        smith_lambda(mu, sigma),
        lambda_of(view),
        lambda_of(light),
        mean_visibility(lambda),
        height_cdf(height, height_deviation),
        log_height_cdf(height, height_deviation),
        height_visibility(lambda, height, height_deviation),
        attribute_at_height(attribute, height, height_deviation),
        slopes.and_then(|s| visible_mean_attribute_for_directions(attribute, view, light, s)),
        convolved.and_then(|c| gaussian_slope_ndf(view, c)),
        surface.and_then(|s| shade(view, light, s, radiance)),
        slopes.and_then(|s| nu_of_direction(view, s)),
    ]
    .map(encode);
    let group = |i: usize| UVec4::from_slice(values.get(i..i + 4).unwrap_or(&[NONE_BITS; 4]));
    SmithResults { values: [group(0), group(4), group(8), group(12)] }
}

gpu_struct! {
    /// The inputs of one case of the differential kernel `smith_corrected_values`.
    pub struct CorrectionCase {
        /// [`LambdaCorrection::low`]: the factors at knots 0 … 3.
        pub knots_low: Vec4,
        /// [`LambdaCorrection::high`]: the factors at knots 4 … 7.
        pub knots_high: Vec4,
        /// `(ā, a_s, Λ(v), Λ(l))`.
        pub inputs: Vec4,
    }
}

gpu_struct! {
    /// The encoded results of one [`CorrectionCase`], in the order of
    /// [`reference_correction_results`].
    pub struct CorrectionResults {
        /// Four results.
        pub values: UVec4,
    }
}

/// The CPU reference of the kernel `smith_corrected_values`: 4 encoded results,
/// `Λ'(v)`, `Λ'(l)`, `ā(v, l)` corrected on the sum
/// ([`corrected_visible_mean_attribute`]) and corrected per direction
/// (`visible_mean_attribute(a, Λ'(v), Λ'(l))`).
pub fn reference_correction_results(case: &CorrectionCase) -> CorrectionResults {
    let correction = LambdaCorrection { low: case.knots_low, high: case.knots_high };
    let [mean, correlation, lambda_view, lambda_light] = case.inputs.to_array();
    let attribute = HeightCorrelatedAttribute { mean, height_correlation: correlation };
    let corrected_view = corrected_lambda(lambda_view, &correction);
    let corrected_light = corrected_lambda(lambda_light, &correction);
    let per_direction = corrected_view.zip(corrected_light).and_then(|(v, l)| visible_mean_attribute(attribute, v, l));
    let values = [
        corrected_view,
        corrected_light,
        corrected_visible_mean_attribute(attribute, lambda_view, lambda_light, &correction),
        per_direction,
    ]
    .map(encode);
    CorrectionResults { values: UVec4::from_array(values) }
}

gpu_struct! {
    /// The inputs of one case of the differential kernel `smith_cubic_corrected_values`.
    pub struct CubicCase {
        /// [`CubicLambdaCorrection::coefficients`] (a valid correction: the WGSL twin
        /// takes one checked once per material).
        pub coefficients: Vec4,
        /// `(ā, a_s, Λ(v), Λ(l))`.
        pub inputs: Vec4,
    }
}

gpu_struct! {
    /// The encoded results of one [`CubicCase`], in the order of
    /// [`reference_cubic_results`].
    pub struct CubicResults {
        /// Four results.
        pub values: UVec4,
    }
}

/// The CPU reference of the kernel `smith_cubic_corrected_values`: 4 encoded results,
/// `c(u)` at `u = Λ(v)/(1 + Λ(v))` (`None` unless `Λ(v)` is finite, non-negative and at
/// most [`MAX_CORRECTED_LAMBDA`]), and `ā(v, l)` corrected on the sum
/// ([`cubic_corrected_visible_mean_attribute`]) for `(Λ(v), Λ(l))`, `(Λ(l), Λ(v))` and
/// `(Λ(v), 0)`.
pub fn reference_cubic_results(case: &CubicCase) -> CubicResults {
    let correction = CubicLambdaCorrection { coefficients: case.coefficients };
    let [mean, correlation, lambda_view, lambda_light] = case.inputs.to_array();
    let attribute = HeightCorrelatedAttribute { mean, height_correlation: correlation };
    let factor = (0.0..=MAX_CORRECTED_LAMBDA)
        .contains(&lambda_view)
        .then(|| correction.factor(lambda_view / (1.0 + lambda_view)));
    let values = [
        factor,
        cubic_corrected_visible_mean_attribute(attribute, lambda_view, lambda_light, &correction),
        cubic_corrected_visible_mean_attribute(attribute, lambda_light, lambda_view, &correction),
        cubic_corrected_visible_mean_attribute(attribute, lambda_view, 0.0, &correction),
    ]
    .map(encode);
    CubicResults { values: UVec4::from_array(values) }
}

gpu_struct! {
    /// The inputs of one case of the differential kernel `smith_correlated_values`.
    pub struct CorrelatedCase {
        /// [`VisibilityCorrection::view_low`] of the model under test.
        pub view_low: Vec4,
        /// [`VisibilityCorrection::view_high`].
        pub view_high: Vec4,
        /// [`VisibilityCorrection::light_low`].
        pub light_low: Vec4,
        /// [`VisibilityCorrection::light_high`].
        pub light_high: Vec4,
        /// [`VisibilityCorrection::correlation`].
        pub correlation: Vec4,
        /// `(ā, a_s, Λ(v), Λ(l))`.
        pub inputs: Vec4,
        /// The view direction in `xyz`, `cos Δφ` for the Λ-based functions in `w`.
        pub view: Vec4,
        /// The light direction in `xyz`, the isotropic slope deviation `σ_n` in `w`.
        pub light: Vec4,
    }
}

gpu_struct! {
    /// The encoded results of one [`CorrelatedCase`], in the order of
    /// [`reference_correlated_results`].
    pub struct CorrelatedResults {
        /// Four results.
        pub values: UVec4,
    }
}

/// The CPU reference of the kernel `smith_correlated_values`: 4 encoded results,
/// [`correlated_lambda`], [`correlated_visible_mean_attribute`],
/// [`cos_azimuth_difference`] of the two directions, and
/// [`correlated_visible_mean_attribute_for_directions`] over isotropic slopes `σ_n`.
pub fn reference_correlated_results(case: &CorrelatedCase) -> CorrelatedResults {
    let model = VisibilityCorrection {
        view_low: case.view_low,
        view_high: case.view_high,
        light_low: case.light_low,
        light_high: case.light_high,
        correlation: case.correlation,
    };
    let [mean, correlation, lambda_view, lambda_light] = case.inputs.to_array();
    let attribute = HeightCorrelatedAttribute { mean, height_correlation: correlation };
    let cos = case.view.w;
    let (view, light) = (case.view.truncate(), case.light.truncate());
    let slopes = SlopeDeviation::new(case.light.w, case.light.w);
    let values = [
        correlated_lambda(lambda_view, lambda_light, cos, &model),
        correlated_visible_mean_attribute(attribute, lambda_view, lambda_light, cos, &model),
        Some(cos_azimuth_difference(view, light)),
        slopes.and_then(|s| correlated_visible_mean_attribute_for_directions(attribute, view, light, s, &model)),
    ]
    .map(encode);
    CorrelatedResults { values: UVec4::from_array(values) }
}

// Evaluated at compile time: an index out of bounds would not compile.
const ERFC_C0: f32 = ERFC_COEFFICIENTS[0];
const ERFC_C1: f32 = ERFC_COEFFICIENTS[1];
const ERFC_C2: f32 = ERFC_COEFFICIENTS[2];
const ERFC_C3: f32 = ERFC_COEFFICIENTS[3];
const ERFC_C4: f32 = ERFC_COEFFICIENTS[4];
const ERFC_C5: f32 = ERFC_COEFFICIENTS[5];
const ERFC_C6: f32 = ERFC_COEFFICIENTS[6];
const ERFC_C7: f32 = ERFC_COEFFICIENTS[7];
const ERFC_C8: f32 = ERFC_COEFFICIENTS[8];
const ERFC_C9: f32 = ERFC_COEFFICIENTS[9];

/// Constants of this crate that the WGSL twin uses, for `cargo xtask codegen`.
pub const WGSL_CONSTANTS: &[GpuConst] = &[
    gpu_const!(NONE_BITS: u32 as "SMITH_NONE_BITS"),
    gpu_const!(ERFC_C0: f32 as "SMITH_ERFC_C0"),
    gpu_const!(ERFC_C1: f32 as "SMITH_ERFC_C1"),
    gpu_const!(ERFC_C2: f32 as "SMITH_ERFC_C2"),
    gpu_const!(ERFC_C3: f32 as "SMITH_ERFC_C3"),
    gpu_const!(ERFC_C4: f32 as "SMITH_ERFC_C4"),
    gpu_const!(ERFC_C5: f32 as "SMITH_ERFC_C5"),
    gpu_const!(ERFC_C6: f32 as "SMITH_ERFC_C6"),
    gpu_const!(ERFC_C7: f32 as "SMITH_ERFC_C7"),
    gpu_const!(ERFC_C8: f32 as "SMITH_ERFC_C8"),
    gpu_const!(ERFC_C9: f32 as "SMITH_ERFC_C9"),
    gpu_const!(ERF_SERIES_LIMIT: f32 as "SMITH_ERF_SERIES_LIMIT"),
    gpu_const!(ERFC_ZERO_FROM: f32 as "SMITH_ERFC_ZERO_FROM"),
    gpu_const!(FRAC_1_SQRT_PI: f32 as "SMITH_FRAC_1_SQRT_PI"),
    gpu_const!(CONTINUED_FRACTION_FROM_NU: f32 as "SMITH_CONTINUED_FRACTION_FROM_NU"),
    gpu_const!(CONTINUED_FRACTION_TERMS: u32 as "SMITH_CONTINUED_FRACTION_TERMS"),
    gpu_const!(LAMBDA_ZERO_FROM_NU: f32 as "SMITH_LAMBDA_ZERO_FROM_NU"),
    gpu_const!(MAX_SLOPE_DEVIATION: f32 as "SMITH_MAX_SLOPE_DEVIATION"),
    gpu_const!(MIN_SLOPE_DEVIATION: f32 as "SMITH_MIN_SLOPE_DEVIATION"),
    gpu_const!(LOG_ONE_MINUS_SERIES_LIMIT: f32 as "SMITH_LOG_ONE_MINUS_SERIES_LIMIT"),
    gpu_const!(MAX_HEIGHT_DEVIATION: f32 as "SMITH_MAX_HEIGHT_DEVIATION"),
    gpu_const!(STANDARDIZED_HEIGHT_LIMIT: f32 as "SMITH_STANDARDIZED_HEIGHT_LIMIT"),
    gpu_const!(MAX_ATTRIBUTE_MAGNITUDE: f32 as "SMITH_MAX_ATTRIBUTE_MAGNITUDE"),
    gpu_const!(MAX_LIGHT_RADIANCE: f32 as "SMITH_MAX_LIGHT_RADIANCE"),
    gpu_const!(CORRECTION_SEGMENTS: u32 as "SMITH_CORRECTION_SEGMENTS"),
    gpu_const!(MIN_CORRECTION_FACTOR: f32 as "SMITH_MIN_CORRECTION_FACTOR"),
    gpu_const!(MAX_CORRECTION_FACTOR: f32 as "SMITH_MAX_CORRECTION_FACTOR"),
    gpu_const!(MAX_CORRECTED_LAMBDA: f32 as "SMITH_MAX_CORRECTED_LAMBDA"),
    gpu_const!(MIN_CORRELATION: f32 as "SMITH_MIN_CORRELATION"),
    gpu_const!(MAX_CORRELATION: f32 as "SMITH_MAX_CORRELATION"),
    gpu_const!(MAX_CORRELATION_COEFFICIENT: f32 as "SMITH_MAX_CORRELATION_COEFFICIENT"),
];

/// Segments of the piecewise linear [`LambdaCorrection`]: knots − 1.
const CORRECTION_SEGMENTS: u32 = CORRECTION_KNOTS as u32 - 1;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn structs_have_the_expected_sizes() {
        assert_eq!(size_of::<SmithCase>(), 80);
        assert_eq!(size_of::<SmithResults>(), 64);
        assert_eq!(size_of::<LambdaCorrection>(), 32);
        assert_eq!(size_of::<CorrectionCase>(), 48);
        assert_eq!(size_of::<CorrectionResults>(), 16);
        assert_eq!(size_of::<VisibilityCorrection>(), 80);
        assert_eq!(size_of::<CorrelatedCase>(), 128);
        assert_eq!(size_of::<CorrelatedResults>(), 16);
    }

    #[test]
    fn encoding_keeps_every_value_and_marks_none() {
        assert_eq!(encode(None), NONE_BITS);
        assert_eq!(encode(Some(f32::INFINITY)), f32::INFINITY.to_bits());
        assert_eq!(encode(Some(-0.0)), (-0.0_f32).to_bits());
        let case = SmithCase {
            view: Vec4::new(0.0, 0.0, 1.0, 0.5),
            light: Vec4::new(0.0, 0.0, 1.0, 0.5),
            slopes: Vec4::new(0.3, 0.3, 0.1, 0.1),
            scalars: Vec4::new(1.0, 0.3, 0.0, 1.0),
            material: Vec4::new(0.5, 0.1, 1.0, 0.0),
        };
        let results = reference_results(&case);
        assert_eq!(results.values[0].x, erf(0.5).map_or(0, f32::to_bits));
        assert_eq!(results.values[1].y, 0.0_f32.to_bits(), "Λ at normal incidence");
        assert_eq!(results.values[3].w, f32::INFINITY.to_bits(), "ν at normal incidence");
    }
}
