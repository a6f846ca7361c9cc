// WGSL twin of crates/smith-micro: Smith masking of Gaussian microsurfaces and the mean
// visible attribute (Heitz & Neyret 2012, eqs. 4-6, 13, 17, §5.5).
//
// Composed after generated/smith_micro.wgsl, which declares the GPU forms of the
// corrections (GpuLambdaCorrection, GpuVisibilityCorrection, GpuCubicLambdaCorrection)
// and the SMITH_* constants (approximation coefficients, thresholds, float bit masks) from
// the Rust source (src/wgsl.rs lists them). A correction argument must come from the
// validated Rust type's to_gpu (LambdaCorrection, VisibilityCorrection,
// CubicLambdaCorrection check their knots and coefficients once per material): the
// functions here do not re-check it. Slopes and attributes arrive as raw voxel data and
// are checked on every call, as the Rust constructors check them. Every function mirrors the Rust function named in its comment, with
// the same formulas in the same order, and is proven equal to it by
// tests/smith_micro_gpu.rs.
//
// WGSL implementations may assume that no NaN or infinity reaches float operations, so
// inputs are classified with integer bit tests, infinities and "None" travel as a
// SmithValue kind, and the Rust reference bounds every input so that no intermediate
// overflows. Subnormals are flushed explicitly, as the Rust reference does.

const SMITH_FINITE: u32 = 0u;
const SMITH_NONE: u32 = 1u;
const SMITH_POSITIVE_INFINITY: u32 = 2u;
const SMITH_NEGATIVE_INFINITY: u32 = 3u;

// A Rust Option<f32>: `value` when kind is SMITH_FINITE, else None or ±∞.
struct SmithValue {
    value: f32,
    kind: u32,
}

fn smith_finite(value: f32) -> SmithValue {
    return SmithValue(value, SMITH_FINITE);
}

fn smith_none() -> SmithValue {
    return SmithValue(0.0, SMITH_NONE);
}

fn smith_positive_infinity() -> SmithValue {
    return SmithValue(0.0, SMITH_POSITIVE_INFINITY);
}

// Rust: encoding::encode.
fn smith_encode(v: SmithValue) -> u32 {
    switch v.kind {
        case 0u: { return bitcast<u32>(v.value); }
        case 2u: { return SMITH_EXPONENT_MASK; }
        case 3u: { return SMITH_EXPONENT_MASK | SMITH_SIGN_MASK; }
        default: { return SMITH_NONE_BITS; }
    }
}

// Rust: erf::flush_subnormal.
fn smith_flush_subnormal(x: f32) -> f32 {
    return select(x, 0.0, (bitcast<u32>(x) & SMITH_EXPONENT_MASK) == 0u);
}

fn smith_flush_subnormal3(v: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(smith_flush_subnormal(v.x), smith_flush_subnormal(v.y), smith_flush_subnormal(v.z));
}

// Rust: erf::is_nan_bits.
fn smith_is_nan(x: f32) -> bool {
    return (bitcast<u32>(x) & SMITH_ABS_MASK) > SMITH_EXPONENT_MASK;
}

// Rust: erf::is_infinite_bits.
fn smith_is_infinite(x: f32) -> bool {
    return (bitcast<u32>(x) & SMITH_ABS_MASK) == SMITH_EXPONENT_MASK;
}

// Rust: erf::is_finite_bits.
fn smith_is_finite(x: f32) -> bool {
    return (bitcast<u32>(x) & SMITH_EXPONENT_MASK) != SMITH_EXPONENT_MASK;
}

fn smith_is_negative(x: f32) -> bool {
    return (bitcast<u32>(x) & SMITH_SIGN_MASK) != 0u;
}

// Rust: erf::erfc_polynomial (Horner, same order).
fn smith_erfc_polynomial(t: f32) -> f32 {
    var p = SMITH_ERFC_C9;
    p = p * t + SMITH_ERFC_C8;
    p = p * t + SMITH_ERFC_C7;
    p = p * t + SMITH_ERFC_C6;
    p = p * t + SMITH_ERFC_C5;
    p = p * t + SMITH_ERFC_C4;
    p = p * t + SMITH_ERFC_C3;
    p = p * t + SMITH_ERFC_C2;
    p = p * t + SMITH_ERFC_C1;
    p = p * t + SMITH_ERFC_C0;
    return p;
}

// Rust: erf::erfcx.
fn smith_erfcx(x_in: f32) -> SmithValue {
    if smith_is_nan(x_in) {
        return smith_none();
    }
    if smith_is_infinite(x_in) {
        return smith_finite(0.0);
    }
    let x = abs(smith_flush_subnormal(x_in));
    let t = 1.0 / (1.0 + 0.5 * x);
    return smith_finite(smith_flush_subnormal(min(t * exp(smith_erfc_polynomial(t)), 1.0)));
}

// Rust: erf::erfc.
fn smith_erfc(x_in: f32) -> SmithValue {
    if smith_is_nan(x_in) {
        return smith_none();
    }
    if smith_is_infinite(x_in) {
        return smith_finite(select(0.0, 2.0, smith_is_negative(x_in)));
    }
    let x = smith_flush_subnormal(x_in);
    let scaled = smith_erfcx(x).value;
    let magnitude = abs(x);
    var tail = 0.0;
    if magnitude < SMITH_ERFC_ZERO_FROM {
        tail = smith_flush_subnormal(scaled * smith_flush_subnormal(exp(-(magnitude * magnitude))));
    }
    return smith_finite(select(tail, 2.0 - tail, x < 0.0));
}

// Rust: erf::erf.
fn smith_erf(x_in: f32) -> SmithValue {
    if smith_is_nan(x_in) {
        return smith_none();
    }
    if smith_is_infinite(x_in) {
        return smith_finite(select(1.0, -1.0, smith_is_negative(x_in)));
    }
    let x = smith_flush_subnormal(x_in);
    let magnitude = abs(x);
    if magnitude < SMITH_ERF_SERIES_LIMIT {
        let s = x * x;
        let series = 1.0
            + s * (-1.0 / 3.0
                + s * (1.0 / 10.0 + s * (-1.0 / 42.0 + s * (1.0 / 216.0 + s * (-1.0 / 1320.0 + s * (1.0 / 9360.0))))));
        return smith_finite(smith_flush_subnormal(1.12837917 * x * series));
    }
    let one_minus = 1.0 - smith_erfc(magnitude).value;
    return smith_finite(select(one_minus, -one_minus, x < 0.0));
}

// Rust: masking::continued_fraction_tail.
fn smith_continued_fraction_tail(nu: f32) -> f32 {
    var a_previous = 1.0;
    var a_current = 0.0;
    var b_previous = 0.0;
    var b_current = 1.0;
    for (var j = 1u; j <= SMITH_CONTINUED_FRACTION_TERMS; j++) {
        let partial = 0.5 * f32(j);
        let a_next = nu * a_current + partial * a_previous;
        let b_next = nu * b_current + partial * b_previous;
        a_previous = a_current;
        a_current = a_next;
        b_previous = b_current;
        b_current = b_next;
    }
    return a_current / b_current;
}

// Rust: masking::smith_lambda_from_nu (eq. 6).
fn smith_lambda_from_nu(nu_in: f32) -> SmithValue {
    if smith_is_nan(nu_in) {
        return smith_none();
    }
    if smith_is_infinite(nu_in) {
        if smith_is_negative(nu_in) {
            return smith_none();
        }
        return smith_finite(0.0);
    }
    let nu = smith_flush_subnormal(nu_in);
    if nu < 0.0 {
        return smith_none();
    }
    if nu == 0.0 {
        return smith_positive_infinity();
    }
    if nu >= SMITH_LAMBDA_ZERO_FROM_NU {
        return smith_finite(0.0);
    }
    let half_gaussian = 0.5 * exp(-(nu * nu));
    var f: f32;
    if nu < SMITH_CONTINUED_FRACTION_FROM_NU {
        f = SMITH_FRAC_1_SQRT_PI / nu - smith_erfcx(nu).value;
    } else {
        let k = smith_continued_fraction_tail(nu);
        f = SMITH_FRAC_1_SQRT_PI * k / (nu * (nu + k));
    }
    return smith_finite(smith_flush_subnormal(half_gaussian * f));
}

// Rust: masking::SlopeDeviation::new. Returns (σx, σy, valid): valid 0 where it returns
// an error.
fn smith_slope_deviation(x: f32, y: f32) -> vec3<f32> {
    let valid_x = !smith_is_nan(x) && smith_is_finite(x) && x >= 0.0 && x <= SMITH_MAX_SLOPE_DEVIATION;
    let valid_y = !smith_is_nan(y) && smith_is_finite(y) && y >= 0.0 && y <= SMITH_MAX_SLOPE_DEVIATION;
    if !(valid_x && valid_y) {
        return vec3<f32>(0.0, 0.0, 0.0);
    }
    let flat_x = select(x, 0.0, x < SMITH_MIN_SLOPE_DEVIATION);
    let flat_y = select(y, 0.0, y < SMITH_MIN_SLOPE_DEVIATION);
    return vec3<f32>(flat_x, flat_y, 1.0);
}

// Rust: masking::smith_lambda (isotropic).
fn smith_lambda_isotropic(mu_in: f32, sigma_in: f32) -> SmithValue {
    let slopes = smith_slope_deviation(sigma_in, sigma_in);
    if slopes.z == 0.0 || smith_is_nan(mu_in) {
        return smith_none();
    }
    let sigma = slopes.x;
    if smith_is_infinite(mu_in) {
        if smith_is_negative(mu_in) {
            return smith_none();
        }
        return smith_finite(0.0);
    }
    let mu = smith_flush_subnormal(mu_in);
    if mu < 0.0 {
        return smith_none();
    }
    let scale = SMITH_SQRT_2 * sigma;
    if sigma == 0.0 || mu >= SMITH_LAMBDA_ZERO_FROM_NU * scale {
        return smith_finite(0.0);
    }
    return smith_lambda_from_nu(smith_flush_subnormal(mu / scale));
}

// Rust: masking::canonical_direction. Returns (direction, 1) or (0, 0, 0, 0) for None.
fn smith_canonical_direction(direction: vec3<f32>) -> vec4<f32> {
    if !(smith_is_finite(direction.x) && smith_is_finite(direction.y) && smith_is_finite(direction.z)) {
        return vec4<f32>(0.0);
    }
    let flushed = smith_flush_subnormal3(direction);
    let largest = max(max(abs(flushed.x), abs(flushed.y)), abs(flushed.z));
    if largest == 0.0 {
        return vec4<f32>(0.0);
    }
    let exponent = (bitcast<u32>(largest) >> 23u) & 0xffu;
    let scale = bitcast<f32>((255u - exponent) << 23u);
    return vec4<f32>(smith_flush_subnormal3(flushed * scale), 1.0);
}

// Rust: masking::nu_of_direction. `slopes` from smith_slope_deviation.
fn smith_nu_of_direction(direction: vec3<f32>, slopes: vec3<f32>) -> SmithValue {
    let canonical = smith_canonical_direction(direction);
    if canonical.w == 0.0 || slopes.z == 0.0 {
        return smith_none();
    }
    let v = canonical.xyz;
    if v.z < 0.0 {
        return smith_none();
    }
    let along_x = smith_flush_subnormal(slopes.x * abs(v.x));
    let along_y = smith_flush_subnormal(slopes.y * abs(v.y));
    let larger = max(along_x, along_y);
    if larger == 0.0 {
        return smith_positive_infinity();
    }
    let ratio = min(along_x, along_y) / larger;
    let denominator = larger * sqrt(2.0 + 2.0 * ratio * ratio);
    if denominator < 1.0 && v.z > SMITH_F32_MAX * denominator {
        return smith_positive_infinity();
    }
    return smith_finite(smith_flush_subnormal(v.z / denominator));
}

// Rust: masking::smith_lambda_direction.
fn smith_lambda_direction(direction: vec3<f32>, slopes: vec3<f32>) -> SmithValue {
    let nu = smith_nu_of_direction(direction, slopes);
    switch nu.kind {
        case 0u: { return smith_lambda_from_nu(nu.value); }
        case 2u: { return smith_finite(0.0); }
        default: { return smith_none(); }
    }
}

// Rust: masking::mean_visibility.
fn smith_mean_visibility(lambda: SmithValue) -> SmithValue {
    switch lambda.kind {
        case 0u: {
            if smith_is_nan(lambda.value) || lambda.value < 0.0 {
                return smith_none();
            }
            return smith_finite(smith_flush_subnormal(1.0 / (1.0 + lambda.value)));
        }
        case 2u: { return smith_finite(0.0); }
        default: { return smith_none(); }
    }
}

// A raw f32 as the Rust functions see it: NaN → None, ±∞ → infinite kinds.
fn smith_value_of(x: f32) -> SmithValue {
    if smith_is_nan(x) {
        return smith_none();
    }
    if smith_is_infinite(x) {
        return SmithValue(0.0, select(SMITH_POSITIVE_INFINITY, SMITH_NEGATIVE_INFINITY, smith_is_negative(x)));
    }
    return smith_finite(x);
}

// Rust: height::standardized_height. Returns (t, decided g, kind): kind 0 = t valid,
// 1 = g decided (σ_h = 0 or h = ±∞), 2 = None.
fn smith_standardized_height(height_in: f32, deviation_in: f32) -> vec3<f32> {
    if smith_is_nan(height_in) || smith_is_nan(deviation_in) {
        return vec3<f32>(0.0, 0.0, 2.0);
    }
    if !smith_is_finite(deviation_in) {
        return vec3<f32>(0.0, 0.0, 2.0);
    }
    let deviation = smith_flush_subnormal(deviation_in);
    if !(deviation >= 0.0 && deviation <= SMITH_MAX_HEIGHT_DEVIATION) {
        return vec3<f32>(0.0, 0.0, 2.0);
    }
    if !smith_is_finite(height_in) {
        return vec3<f32>(0.0, select(1.0, 0.0, smith_is_negative(height_in)), 1.0);
    }
    let height = smith_flush_subnormal(height_in);
    if deviation == 0.0 {
        return vec3<f32>(0.0, select(0.0, 1.0, height >= 0.0), 1.0);
    }
    let scale = SMITH_SQRT_2 * deviation;
    if abs(height) >= SMITH_STANDARDIZED_HEIGHT_LIMIT * scale {
        return vec3<f32>(select(SMITH_STANDARDIZED_HEIGHT_LIMIT, -SMITH_STANDARDIZED_HEIGHT_LIMIT, height < 0.0), 0.0, 0.0);
    }
    return vec3<f32>(smith_flush_subnormal(height / scale), 0.0, 0.0);
}

// Rust: height::height_cdf (eq. 5).
fn smith_height_cdf(height: f32, deviation: f32) -> SmithValue {
    let standardized = smith_standardized_height(height, deviation);
    if standardized.z == 2.0 {
        return smith_none();
    }
    if standardized.z == 1.0 {
        return smith_finite(standardized.y);
    }
    let t = standardized.x;
    if t < 0.0 {
        return smith_finite(smith_flush_subnormal(0.5 * smith_erfc(-t).value));
    }
    return smith_finite(1.0 - 0.5 * smith_erfc(t).value);
}

// Rust: height::log_one_minus.
fn smith_log_one_minus(y: f32) -> f32 {
    if y < SMITH_LOG_ONE_MINUS_SERIES_LIMIT {
        let series = 1.0
            + y * (1.0 / 2.0
                + y * (1.0 / 3.0 + y * (1.0 / 4.0 + y * (1.0 / 5.0 + y * (1.0 / 6.0 + y * (1.0 / 7.0 + y / 8.0))))));
        return smith_flush_subnormal(-y * series);
    }
    return log(1.0 - y);
}

// Rust: height::log_height_cdf. −∞ is SMITH_NEGATIVE_INFINITY.
fn smith_log_height_cdf(height: f32, deviation: f32) -> SmithValue {
    let standardized = smith_standardized_height(height, deviation);
    if standardized.z == 2.0 {
        return smith_none();
    }
    if standardized.z == 1.0 {
        if standardized.y == 1.0 {
            return smith_finite(0.0);
        }
        return SmithValue(0.0, SMITH_NEGATIVE_INFINITY);
    }
    let t = standardized.x;
    if t < 0.0 {
        let magnitude = -t;
        return smith_finite(log(0.5 * smith_erfcx(magnitude).value) - magnitude * magnitude);
    }
    return smith_finite(smith_log_one_minus(0.5 * smith_erfc(t).value));
}

// Rust: height::height_visibility (eq. 4).
fn smith_height_visibility(lambda_in: SmithValue, height: f32, deviation: f32) -> SmithValue {
    var lambda = lambda_in;
    lambda.value = smith_flush_subnormal(lambda.value);
    if lambda.kind == SMITH_NONE || lambda.kind == SMITH_NEGATIVE_INFINITY
        || (lambda.kind == SMITH_FINITE && lambda.value < 0.0) {
        return smith_none();
    }
    let log_cdf = smith_log_height_cdf(height, deviation);
    if log_cdf.kind == SMITH_NONE {
        return smith_none();
    }
    let lambda_is_zero = lambda.kind == SMITH_FINITE && lambda.value == 0.0;
    if lambda_is_zero || (log_cdf.kind == SMITH_FINITE && log_cdf.value == 0.0) {
        return smith_finite(1.0);
    }
    if lambda.kind != SMITH_FINITE || log_cdf.kind != SMITH_FINITE {
        return smith_finite(0.0);
    }
    let magnitude = -log_cdf.value;
    if magnitude >= 1.0 && lambda.value > SMITH_EXP_ZERO_FROM / magnitude {
        return smith_finite(0.0);
    }
    return smith_finite(smith_flush_subnormal(exp(-(lambda.value * magnitude))));
}

// Rust: the check of attribute::HeightCorrelatedAttribute::new (None where it returns an
// error): (ā, a_s) come raw from voxel data.
fn smith_attribute_is_valid(correlated_attribute: vec2<f32>) -> bool {
    return !smith_is_nan(correlated_attribute.x) && smith_is_finite(correlated_attribute.x) && abs(correlated_attribute.x) <= SMITH_MAX_ATTRIBUTE_MAGNITUDE
        && !smith_is_nan(correlated_attribute.y) && smith_is_finite(correlated_attribute.y) && abs(correlated_attribute.y) <= SMITH_MAX_ATTRIBUTE_MAGNITUDE;
}

// Rust: height::attribute_at_height (H5bis). `correlated_attribute` = (ā, a_s).
fn smith_attribute_at_height(correlated_attribute: vec2<f32>, height: f32, deviation: f32) -> SmithValue {
    let g = smith_height_cdf(height, deviation);
    if g.kind != SMITH_FINITE || !smith_attribute_is_valid(correlated_attribute) {
        return smith_none();
    }
    let s = 2.0 * g.value - 1.0;
    return smith_finite(correlated_attribute.x + correlated_attribute.y * s);
}

// Rust: attribute::visible_fraction_of_finite (Λ/(Λ + 2) of eq. 17 for a finite,
// flushed Λ ≥ 0).
fn smith_visible_fraction_of_finite(lambda: f32) -> f32 {
    if lambda == 0.0 {
        return 0.0;
    }
    return 1.0 / (1.0 + 2.0 / lambda);
}

// Rust: attribute::is_valid_lambda (a Λ of eq. 6: +∞ or a finite value ≥ 0).
fn smith_lambda_is_valid(lambda: SmithValue) -> bool {
    return lambda.kind == SMITH_POSITIVE_INFINITY || (lambda.kind == SMITH_FINITE && lambda.value >= 0.0);
}

// Rust: attribute::visible_mean_attribute (eq. 17). `correlated_attribute` = (ā, a_s).
fn smith_visible_mean_attribute(correlated_attribute: vec2<f32>, lambda_view: SmithValue, lambda_light: SmithValue) -> SmithValue {
    if !(smith_lambda_is_valid(lambda_view) && smith_lambda_is_valid(lambda_light) && smith_attribute_is_valid(correlated_attribute)) {
        return smith_none();
    }
    var visible_fraction = 1.0;
    let any_infinite = lambda_view.kind == SMITH_POSITIVE_INFINITY || lambda_light.kind == SMITH_POSITIVE_INFINITY;
    if !any_infinite && !(lambda_view.value > SMITH_F32_MAX - lambda_light.value) {
        visible_fraction = smith_visible_fraction_of_finite(smith_flush_subnormal(lambda_view.value + lambda_light.value));
    }
    return smith_finite(correlated_attribute.x + correlated_attribute.y * visible_fraction);
}

// Rust: attribute::visible_mean_attribute_for_directions.
fn smith_visible_mean_attribute_for_directions(correlated_attribute: vec2<f32>, view: vec3<f32>, light: vec3<f32>, slopes: vec3<f32>) -> SmithValue {
    let lambda_view = smith_lambda_direction(view, slopes);
    let lambda_light = smith_lambda_direction(light, slopes);
    if lambda_view.kind == SMITH_NONE || lambda_light.kind == SMITH_NONE {
        return smith_none();
    }
    return smith_visible_mean_attribute(correlated_attribute, lambda_view, lambda_light);
}

// A per-material correction of Λ (Rust: correction::LambdaCorrection), as
// GpuLambdaCorrection (declared in generated/smith_micro.wgsl): factors at u = i/7, knots
// 0-3 in `low`, 4-7 in `high`. It must come from LambdaCorrection::to_gpu: every knot is
// in [SMITH_MIN_CORRECTION_FACTOR, SMITH_MAX_CORRECTION_FACTOR], and nothing here checks it.

// Rust: correction::LambdaCorrection::factor, for u in [0, 1]. `correction` from
// LambdaCorrection::to_gpu.
fn smith_correction_factor(correction: GpuLambdaCorrection, u: f32) -> f32 {
    let knots = array<f32, 8>(
        correction.low.x, correction.low.y, correction.low.z, correction.low.w,
        correction.high.x, correction.high.y, correction.high.z, correction.high.w,
    );
    let t = clamp(u, 0.0, 1.0) * f32(SMITH_CORRECTION_SEGMENTS);
    let index = min(u32(t), SMITH_CORRECTION_SEGMENTS - 1u);
    let fraction = t - f32(index);
    let k0 = knots[index];
    let k1 = knots[index + 1u];
    return k0 + fraction * (k1 - k0);
}

// The flushed sum Λ(v) + Λ(l) that the corrections of the sum scale, or -1 where the
// corrected Λ is +∞ and the visible fraction 1: a Λ is +∞, the sum overflows, or it
// exceeds SMITH_MAX_CORRECTED_LAMBDA (Rust: correction::visible_mean_attribute_of_corrected_sum).
fn smith_sum_to_correct(lambda_view: SmithValue, lambda_light: SmithValue) -> f32 {
    let any_infinite = lambda_view.kind == SMITH_POSITIVE_INFINITY || lambda_light.kind == SMITH_POSITIVE_INFINITY;
    if any_infinite || lambda_view.value > SMITH_F32_MAX - lambda_light.value {
        return -1.0;
    }
    let lambda = smith_flush_subnormal(lambda_view.value + lambda_light.value);
    return select(lambda, -1.0, lambda > SMITH_MAX_CORRECTED_LAMBDA);
}

// Rust: correction::corrected_lambda. `correction` from LambdaCorrection::to_gpu (not
// re-checked).
fn smith_corrected_lambda(lambda: SmithValue, correction: GpuLambdaCorrection) -> SmithValue {
    if !smith_lambda_is_valid(lambda) {
        return smith_none();
    }
    if lambda.kind == SMITH_POSITIVE_INFINITY || lambda.value > SMITH_MAX_CORRECTED_LAMBDA {
        return smith_positive_infinity();
    }
    let flushed = smith_flush_subnormal(lambda.value);
    let u = flushed / (1.0 + flushed);
    return smith_finite(smith_flush_subnormal(smith_correction_factor(correction, u) * flushed));
}

// Rust: correction::corrected_visible_mean_attribute (eq. 17 with Λ' = c(u) Λ on the sum
// Λ = Λ(v) + Λ(l)): eq. 17's code with the table lookup on the finite sum, which is all it
// adds. `correction` from LambdaCorrection::to_gpu (not re-checked); the attribute is.
fn smith_corrected_visible_mean_attribute(correlated_attribute: vec2<f32>, lambda_view: SmithValue, lambda_light: SmithValue, correction: GpuLambdaCorrection) -> SmithValue {
    if !(smith_lambda_is_valid(lambda_view) && smith_lambda_is_valid(lambda_light) && smith_attribute_is_valid(correlated_attribute)) {
        return smith_none();
    }
    var visible_fraction = 1.0;
    let lambda = smith_sum_to_correct(lambda_view, lambda_light);
    if lambda >= 0.0 {
        let u = lambda / (1.0 + lambda);
        visible_fraction = smith_visible_fraction_of_finite(smith_flush_subnormal(smith_correction_factor(correction, u) * lambda));
    }
    return smith_finite(correlated_attribute.x + correlated_attribute.y * visible_fraction);
}

// The correction of Λ as a cubic (Rust: cubic_correction::CubicLambdaCorrection), as
// GpuCubicLambdaCorrection (declared in generated/smith_micro.wgsl):
// Λ' = c(u) Λ, c(u) = c0 + u (c1 + u (c2 + u c3)). It must come from
// CubicLambdaCorrection::to_gpu: c stays in [SMITH_MIN_CORRECTION_FACTOR,
// SMITH_MAX_CORRECTION_FACTOR] on [0, 1], and nothing here checks it.

// Rust: cubic_correction::CubicLambdaCorrection::factor. `correction` from
// CubicLambdaCorrection::to_gpu.
fn smith_cubic_correction_factor(correction: GpuCubicLambdaCorrection, u: f32) -> f32 {
    let c = correction.coefficients;
    return c.x + u * (c.y + u * (c.z + u * c.w));
}

// Rust: cubic_correction::cubic_corrected_visible_mean_attribute. `correction` from
// CubicLambdaCorrection::to_gpu (not re-checked); the attribute is.
fn smith_cubic_corrected_visible_mean_attribute(correlated_attribute: vec2<f32>, lambda_view: SmithValue, lambda_light: SmithValue, correction: GpuCubicLambdaCorrection) -> SmithValue {
    if !(smith_lambda_is_valid(lambda_view) && smith_lambda_is_valid(lambda_light) && smith_attribute_is_valid(correlated_attribute)) {
        return smith_none();
    }
    var visible_fraction = 1.0;
    let lambda = smith_sum_to_correct(lambda_view, lambda_light);
    if lambda >= 0.0 {
        let u = lambda / (1.0 + lambda);
        visible_fraction = smith_visible_fraction_of_finite(smith_flush_subnormal(smith_cubic_correction_factor(correction, u) * lambda));
    }
    return smith_finite(correlated_attribute.x + correlated_attribute.y * visible_fraction);
}

// The corrected visibility model with a light-view correlation term (Rust:
// correlated::VisibilityCorrection), as GpuVisibilityCorrection (declared in
// generated/smith_micro.wgsl): Λ' = A + B − ρ(cos Δφ) min(A, B), A = c_v Λ(v),
// B = c_l Λ(l). It must come from VisibilityCorrection::to_gpu: both tables valid and
// |ρᵢ| ≤ SMITH_MAX_CORRELATION_COEFFICIENT, and nothing here checks it.

// Rust: correlated::VisibilityCorrection::correlation_at (cos Δφ as a SmithValue: None
// reads as 0, ±∞ as ±1). `model` from VisibilityCorrection::to_gpu.
fn smith_view_light_correlation(model: GpuVisibilityCorrection, cos_difference: SmithValue) -> f32 {
    var c = 0.0;
    if cos_difference.kind == SMITH_FINITE {
        c = clamp(cos_difference.value, -1.0, 1.0);
    } else if cos_difference.kind == SMITH_POSITIVE_INFINITY {
        c = 1.0;
    } else if cos_difference.kind == SMITH_NEGATIVE_INFINITY {
        c = -1.0;
    }
    let r = model.correlation;
    return clamp(r.x + c * (r.y + c * r.z), SMITH_MIN_CORRELATION, SMITH_MAX_CORRELATION);
}

// Rust: correlated::correlated_lambda. `model` from VisibilityCorrection::to_gpu (not
// re-checked).
fn smith_correlated_lambda(lambda_view: SmithValue, lambda_light: SmithValue, cos_difference: SmithValue, model: GpuVisibilityCorrection) -> SmithValue {
    let view = smith_corrected_lambda(lambda_view, GpuLambdaCorrection(model.view_low, model.view_high));
    let light = smith_corrected_lambda(lambda_light, GpuLambdaCorrection(model.light_low, model.light_high));
    if view.kind == SMITH_NONE || light.kind == SMITH_NONE {
        return smith_none();
    }
    if view.kind == SMITH_POSITIVE_INFINITY || light.kind == SMITH_POSITIVE_INFINITY {
        return smith_positive_infinity();
    }
    let rho = smith_view_light_correlation(model, cos_difference);
    return smith_finite(smith_flush_subnormal((view.value + light.value) - rho * min(view.value, light.value)));
}

// Rust: correlated::correlated_visible_mean_attribute: eq. 17's code with the two table
// lookups, ρ and the combination on finite Λs. A Λ that is not flushed first gives the
// same bits: a subnormal Λ makes c Λ subnormal, flushed to 0. `model` from
// VisibilityCorrection::to_gpu (not re-checked); the attribute is.
fn smith_correlated_visible_mean_attribute(correlated_attribute: vec2<f32>, lambda_view: SmithValue, lambda_light: SmithValue, cos_difference: SmithValue, model: GpuVisibilityCorrection) -> SmithValue {
    if !(smith_lambda_is_valid(lambda_view) && smith_lambda_is_valid(lambda_light) && smith_attribute_is_valid(correlated_attribute)) {
        return smith_none();
    }
    var visible_fraction = 1.0;
    let any_infinite = lambda_view.kind == SMITH_POSITIVE_INFINITY || lambda_light.kind == SMITH_POSITIVE_INFINITY;
    // Above SMITH_MAX_CORRECTED_LAMBDA a corrected Λ is +∞, and so is Λ': the fraction stays 1.
    if !any_infinite && !(max(lambda_view.value, lambda_light.value) > SMITH_MAX_CORRECTED_LAMBDA) {
        let view = lambda_view.value;
        let light = lambda_light.value;
        let a = smith_flush_subnormal(smith_correction_factor(GpuLambdaCorrection(model.view_low, model.view_high), view / (1.0 + view)) * view);
        let b = smith_flush_subnormal(smith_correction_factor(GpuLambdaCorrection(model.light_low, model.light_high), light / (1.0 + light)) * light);
        let rho = smith_view_light_correlation(model, cos_difference);
        visible_fraction = smith_visible_fraction_of_finite(smith_flush_subnormal((a + b) - rho * min(a, b)));
    }
    return smith_finite(correlated_attribute.x + correlated_attribute.y * visible_fraction);
}

// Rust: correlated::cos_azimuth_difference.
fn smith_cos_azimuth_difference(view: vec3<f32>, light: vec3<f32>) -> SmithValue {
    let finite = smith_is_finite(view.x) && smith_is_finite(view.y) && smith_is_finite(light.x) && smith_is_finite(light.y)
        && !smith_is_nan(view.x) && !smith_is_nan(view.y) && !smith_is_nan(light.x) && !smith_is_nan(light.y);
    if !finite {
        return smith_finite(0.0);
    }
    let a = vec2<f32>(smith_flush_subnormal(view.x), smith_flush_subnormal(view.y));
    let b = vec2<f32>(smith_flush_subnormal(light.x), smith_flush_subnormal(light.y));
    let largest_a = max(abs(a.x), abs(a.y));
    let largest_b = max(abs(b.x), abs(b.y));
    if largest_a == 0.0 || largest_b == 0.0 {
        return smith_finite(1.0);
    }
    let sa = vec2<f32>(smith_flush_subnormal(a.x / largest_a), smith_flush_subnormal(a.y / largest_a));
    let sb = vec2<f32>(smith_flush_subnormal(b.x / largest_b), smith_flush_subnormal(b.y / largest_b));
    let lengths = sqrt(sa.x * sa.x + sa.y * sa.y) * sqrt(sb.x * sb.x + sb.y * sb.y);
    return smith_finite(smith_flush_subnormal(clamp((sa.x * sb.x + sa.y * sb.y) / lengths, -1.0, 1.0)));
}

// Rust: correlated::correlated_visible_mean_attribute_for_directions. `model` from
// VisibilityCorrection::to_gpu (not re-checked).
fn smith_correlated_visible_mean_attribute_for_directions(correlated_attribute: vec2<f32>, view: vec3<f32>, light: vec3<f32>, slopes: vec3<f32>, model: GpuVisibilityCorrection) -> SmithValue {
    let lambda_view = smith_lambda_direction(view, slopes);
    let lambda_light = smith_lambda_direction(light, slopes);
    if lambda_view.kind == SMITH_NONE || lambda_light.kind == SMITH_NONE {
        return smith_none();
    }
    let cos_difference = smith_cos_azimuth_difference(view, light);
    return smith_correlated_visible_mean_attribute(correlated_attribute, lambda_view, lambda_light, cos_difference, model);
}

// Rust: shading::scaled_hypot.
fn smith_scaled_hypot(a: f32, b: f32) -> f32 {
    let larger = max(a, b);
    let smaller = min(a, b);
    if larger == 0.0 {
        return 0.0;
    }
    let ratio = smaller / larger;
    return larger * sqrt(1.0 + ratio * ratio);
}

// Rust: shading::convolved_slope_deviation (§5.5). Keeps the validity flag in z.
fn smith_convolved_slope_deviation(surface: vec3<f32>, brdf: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(smith_scaled_hypot(surface.x, brdf.x), smith_scaled_hypot(surface.y, brdf.y), surface.z * brdf.z);
}

// Rust: shading::gaussian_slope_ndf.
fn smith_gaussian_slope_ndf(normal: vec3<f32>, slopes: vec3<f32>) -> SmithValue {
    let canonical = smith_canonical_direction(normal);
    if canonical.w == 0.0 || slopes.z == 0.0 {
        return smith_none();
    }
    if slopes.x == 0.0 || slopes.y == 0.0 {
        return smith_none();
    }
    if canonical.z <= 0.0 {
        return smith_finite(0.0);
    }
    let m = smith_flush_subnormal3(canonical.xyz / length(canonical.xyz));
    let x = m.x / slopes.x;
    let y = m.y / slopes.y;
    let q = 0.5 * (x * x + y * y);
    let z_squared = smith_flush_subnormal(m.z * m.z);
    if q >= SMITH_EXP_ZERO_FROM * z_squared {
        return smith_finite(0.0);
    }
    let gaussian = smith_flush_subnormal(exp(-(q / z_squared)));
    let denominator = smith_flush_subnormal(SMITH_TAU * slopes.x * slopes.y * smith_flush_subnormal(z_squared * z_squared));
    if denominator == 0.0 {
        return smith_none();
    }
    return smith_finite(smith_flush_subnormal(gaussian / denominator));
}

// Rust: shading::checked_mul.
fn smith_checked_mul(a: f32, b: f32) -> SmithValue {
    if abs(b) > 1.0 && abs(a) > SMITH_F32_MAX / abs(b) {
        return smith_none();
    }
    return smith_finite(smith_flush_subnormal(a * b));
}

// Rust: shading::checked_div (b > 0).
fn smith_checked_div(a: f32, b: f32) -> SmithValue {
    if b < 1.0 && abs(a) > SMITH_F32_MAX * b {
        return smith_none();
    }
    return smith_finite(smith_flush_subnormal(a / b));
}

// Rust: shading::shade (eq. 13). `correlated_attribute` = (ā, a_s); slopes from
// smith_slope_deviation. Invalid slopes or attribute give None first, as the Rust
// constructors of FilteredSurface's fields reject them (so an unlit point with an invalid
// attribute is None, not 0).
fn smith_shade(view: vec3<f32>, light: vec3<f32>, slopes: vec3<f32>, brdf_slopes: vec3<f32>, correlated_attribute: vec2<f32>, radiance: f32) -> SmithValue {
    if slopes.z == 0.0 || brdf_slopes.z == 0.0 || !smith_attribute_is_valid(correlated_attribute) {
        return smith_none();
    }
    if smith_is_nan(radiance) || !smith_is_finite(radiance) || !(radiance >= 0.0 && radiance <= SMITH_MAX_LIGHT_RADIANCE) {
        return smith_none();
    }
    let canonical_view = smith_canonical_direction(view);
    let canonical_light = smith_canonical_direction(light);
    if canonical_view.w == 0.0 || canonical_light.w == 0.0 {
        return smith_none();
    }
    let v = smith_flush_subnormal3(canonical_view.xyz / length(canonical_view.xyz));
    let l = smith_flush_subnormal3(canonical_light.xyz / length(canonical_light.xyz));
    if v.z <= 0.0 {
        return smith_none();
    }
    if l.z <= 0.0 {
        return smith_finite(0.0);
    }
    let lambda_view = smith_lambda_direction(v, slopes);
    let lambda_light = smith_lambda_direction(l, slopes);
    if lambda_view.kind == SMITH_NONE || lambda_light.kind == SMITH_NONE {
        return smith_none();
    }
    let visible_attribute = smith_visible_mean_attribute(correlated_attribute, lambda_view, lambda_light);
    if visible_attribute.kind != SMITH_FINITE {
        return smith_none();
    }
    let lobe = smith_gaussian_slope_ndf(v + l, smith_convolved_slope_deviation(slopes, brdf_slopes));
    if lobe.kind != SMITH_FINITE {
        return smith_none();
    }
    let visibility = smith_flush_subnormal(smith_mean_visibility(lambda_view).value * smith_mean_visibility(lambda_light).value);
    let reflected = smith_checked_div(smith_flush_subnormal(lobe.value * visibility), 4.0 * v.z);
    if reflected.kind != SMITH_FINITE {
        return smith_none();
    }
    let scaled = smith_checked_mul(visible_attribute.value, reflected.value);
    if scaled.kind != SMITH_FINITE {
        return smith_none();
    }
    return smith_checked_mul(radiance, scaled.value);
}
