//! The CPU references of the `smith_micro_*_differential` kernels: for one case, what the
//! kernel must write, computed with `smith-micro`'s Rust functions and encoded as the
//! kernels encode (`smith_micro::encode`).

use glam::{UVec4, Vec3, Vec4};
use shader_registry::kernel_io::smith_micro::{
    CorrectionCase, CorrectionResults, CorrelatedCase, CorrelatedResults, CubicCase, CubicResults, SmithCase,
    SmithResults,
};
use smith_micro::correction::MAX_CORRECTED_LAMBDA;
use smith_micro::{
    CubicLambdaCorrection, FilteredSurface, GpuLambdaCorrection, HeightCorrelatedAttribute, LambdaCorrection,
    NONE_BITS, SlopeDeviation, VisibilityCorrection, attribute_at_height, convolved_slope_deviation, corrected_lambda,
    corrected_visible_mean_attribute, correlated_lambda, correlated_visible_mean_attribute,
    correlated_visible_mean_attribute_for_directions, cos_azimuth_difference, cubic_corrected_visible_mean_attribute,
    encode, erf, erfc, erfcx, gaussian_slope_ndf, height_cdf, height_visibility, log_height_cdf, mean_visibility,
    nu_of_direction, shade, smith_lambda, smith_lambda_direction, smith_lambda_from_nu, visible_mean_attribute,
    visible_mean_attribute_for_directions,
};

/// The CPU reference of the kernel `smith_values`: 16 encoded results,
///
/// `erf(x), erfc(x), erfcx(x), Λ(ν)`,
/// `Λ(μ, σ), Λ(view), Λ(light), 1/(1+Λ)`,
/// `g(h), ln g(h), g(h)^Λ, a(h)`,
/// `ā(view, light), D(view) with the convolved slopes, eq. 13, ν(view)`.
pub(crate) fn reference_results(case: &SmithCase) -> SmithResults {
    let (view, light) = (case.view.truncate(), case.light.truncate());
    let [mu, sigma, height, height_deviation] = case.scalars.to_array();
    let [mean, correlation, radiance, lambda] = case.material.to_array();
    // The raw slopes and attribute as the constructors take them: `None` where they reject
    // them (the WGSL twin checks the raw values on every call).
    let slopes = SlopeDeviation::new(case.slopes.x, case.slopes.y).ok();
    let brdf_slopes = SlopeDeviation::new(case.slopes.z, case.slopes.w).ok();
    let attribute = HeightCorrelatedAttribute::new(mean, correlation).ok();
    let x = case.light.w;
    let lambda_of = |d: Vec3| slopes.and_then(|s| smith_lambda_direction(d, s));
    let convolved = slopes.zip(brdf_slopes).map(|(s, b)| convolved_slope_deviation(s, b));
    let surface = slopes.zip(brdf_slopes).zip(attribute).map(|((slopes, brdf_slopes), attribute)| FilteredSurface {
        slopes,
        brdf_slopes,
        attribute,
    });
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
        attribute.and_then(|a| attribute_at_height(a, height, height_deviation)),
        slopes.zip(attribute).and_then(|(s, a)| visible_mean_attribute_for_directions(a, view, light, s)),
        convolved.and_then(|c| gaussian_slope_ndf(view, c)),
        surface.and_then(|s| shade(view, light, s, radiance)),
        slopes.and_then(|s| nu_of_direction(view, s)),
    ]
    .map(encode);
    let group = |i: usize| UVec4::from_slice(values.get(i..i + 4).unwrap_or(&[NONE_BITS; 4]));
    SmithResults { values: [group(0), group(4), group(8), group(12)] }
}

/// A case of a correction kernel with the validated correction its correction fields were
/// produced from (by `to_gpu`): the GPU reads `case`, the CPU reference evaluates
/// `correction`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Validated<T, C> {
    /// The validated correction the CPU reference evaluates.
    pub(crate) correction: T,
    /// The kernel case the GPU reads, made from it.
    pub(crate) case: C,
}

/// The case of `smith_corrected_values` for `correction` (its [`GpuLambdaCorrection`]) and
/// `(ā, a_s, Λ(v), Λ(l))`.
pub(crate) fn correction_case(
    correction: LambdaCorrection,
    inputs: Vec4,
) -> Validated<LambdaCorrection, CorrectionCase> {
    let [knots_low, knots_high]: [Vec4; 2] = bytemuck::cast::<GpuLambdaCorrection, _>(correction.to_gpu());
    Validated { correction, case: CorrectionCase { knots_low, knots_high, inputs } }
}

/// The CPU reference of the kernel `smith_corrected_values`: 4 encoded results,
/// `Λ'(v)`, `Λ'(l)`, `ā(v, l)` corrected on the sum
/// ([`corrected_visible_mean_attribute`]) and corrected per direction
/// (`visible_mean_attribute(a, Λ'(v), Λ'(l))`); `None` for the attributes where
/// [`HeightCorrelatedAttribute::new`] rejects `(ā, a_s)`.
pub(crate) fn reference_correction_results(
    validated: &Validated<LambdaCorrection, CorrectionCase>,
) -> CorrectionResults {
    let Validated { correction, case } = validated;
    let [mean, correlation, lambda_view, lambda_light] = case.inputs.to_array();
    let attribute = HeightCorrelatedAttribute::new(mean, correlation).ok();
    let corrected_view = corrected_lambda(lambda_view, correction);
    let corrected_light = corrected_lambda(lambda_light, correction);
    let per_direction =
        corrected_view.zip(corrected_light).zip(attribute).and_then(|((v, l), a)| visible_mean_attribute(a, v, l));
    let values = [
        corrected_view,
        corrected_light,
        attribute.and_then(|a| corrected_visible_mean_attribute(a, lambda_view, lambda_light, correction)),
        per_direction,
    ]
    .map(encode);
    CorrectionResults { values: UVec4::from_array(values) }
}

/// The CPU reference of the kernel `smith_cubic_corrected_values`: 4 encoded results,
/// `c(u)` at `u = Λ(v)/(1 + Λ(v))` (`None` unless `Λ(v)` is finite, non-negative and at
/// most [`MAX_CORRECTED_LAMBDA`]), and `ā(v, l)` corrected on the sum
/// ([`cubic_corrected_visible_mean_attribute`]) for `(Λ(v), Λ(l))`, `(Λ(l), Λ(v))` and
/// `(Λ(v), 0)` (`None` where [`HeightCorrelatedAttribute::new`] rejects `(ā, a_s)`).
pub(crate) fn reference_cubic_results(validated: &Validated<CubicLambdaCorrection, CubicCase>) -> CubicResults {
    let Validated { correction, case } = validated;
    let [mean, correlation, lambda_view, lambda_light] = case.inputs.to_array();
    let attribute = HeightCorrelatedAttribute::new(mean, correlation).ok();
    let factor = (0.0..=MAX_CORRECTED_LAMBDA)
        .contains(&lambda_view)
        .then(|| correction.factor(lambda_view / (1.0 + lambda_view)));
    let corrected = |view: f32, light: f32| {
        attribute.and_then(|a| cubic_corrected_visible_mean_attribute(a, view, light, correction))
    };
    let values = [
        factor,
        corrected(lambda_view, lambda_light),
        corrected(lambda_light, lambda_view),
        corrected(lambda_view, 0.0),
    ]
    .map(encode);
    CubicResults { values: UVec4::from_array(values) }
}

/// The CPU reference of the kernel `smith_correlated_values`: 4 encoded results,
/// [`correlated_lambda`], [`correlated_visible_mean_attribute`],
/// [`cos_azimuth_difference`] of the two directions, and
/// [`correlated_visible_mean_attribute_for_directions`] over isotropic slopes `σ_n`
/// (`None` where [`HeightCorrelatedAttribute::new`] or [`SlopeDeviation::new`] rejects
/// the raw inputs).
pub(crate) fn reference_correlated_results(
    validated: &Validated<VisibilityCorrection, CorrelatedCase>,
) -> CorrelatedResults {
    let Validated { correction: model, case } = validated;
    let [mean, correlation, lambda_view, lambda_light] = case.inputs.to_array();
    let attribute = HeightCorrelatedAttribute::new(mean, correlation).ok();
    let cos = case.view.w;
    let (view, light) = (case.view.truncate(), case.light.truncate());
    let slopes = SlopeDeviation::isotropic(case.light.w).ok();
    let values = [
        correlated_lambda(lambda_view, lambda_light, cos, model),
        attribute.and_then(|a| correlated_visible_mean_attribute(a, lambda_view, lambda_light, cos, model)),
        Some(cos_azimuth_difference(view, light)),
        slopes
            .zip(attribute)
            .and_then(|(s, a)| correlated_visible_mean_attribute_for_directions(a, view, light, s, model)),
    ]
    .map(encode);
    CorrelatedResults { values: UVec4::from_array(values) }
}
