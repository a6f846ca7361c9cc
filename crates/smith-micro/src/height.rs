//! Gaussian heights: the height CDF `g(h)` (eq. 5), Smith's visibility of a height
//! `V(v, h) = g(h)^Λ(v)` (eq. 4), and the height-correlated attribute `a(h)` of
//! hypothesis H5bis.
//!
//! Heights are `N(0, σ_h²)` about the mean surface, `h` grows outwards (a higher point is
//! more visible), and `g(h) = 1 − ½ erfc(h / (√2 σ_h))` is their CDF.
//!
//! | input | `g(h)` | `V(Λ, h)` |
//! |---|---|---|
//! | `σ_h = 0` (flat) | `1` for `h ≥ 0`, `0` for `h < 0` (the CDF of the constant 0) | `1` / `0` (`Λ > 0`) |
//! | `h = +∞` / `−∞` | `1` / `0` | `1` / `0` (`Λ > 0`) |
//! | `Λ = 0` (normal incidence, flat surface) | | `1` for every `h`, also where `g = 0` |
//! | `Λ = +∞` (grazing) | | `0`, except `1` where `g(h) = 1` exactly |
//! | `σ_h < 0`, `σ_h = ±∞`, NaN `h`, `σ_h` or `Λ`, `Λ < 0` | `None` | `None` |
//!
//! `V` is computed as `exp(Λ · ln g(h))` with `ln g` from [`crate::erf::erfcx`] for
//! `h < 0` (no underflow: `ln g = ln(½ erfcx(t)) − t²`, `t = −h/(√2σ_h)`) and from a
//! series of `ln(1 − y)` for small `y = ½ erfc(t)`, `h > 0`.

use crate::attribute::HeightCorrelatedAttribute;
use crate::erf::{EXP_ZERO_FROM, erfc, erfcx, flush_subnormal, is_finite_bits, is_infinite_bits, is_nan_bits};

/// Below this `y`, `ln(1 − y)` uses its series (8 terms, truncation < 10⁻⁹ relative).
pub const LOG_ONE_MINUS_SERIES_LIMIT: f32 = 0.0625;
/// Largest accepted height deviation `σ_h`, `2⁶⁴` (so that `√2 σ_h` and the products
/// below never overflow f32, which the WGSL twin could not represent).
pub const MAX_HEIGHT_DEVIATION: f32 = 18_446_744_073_709_551_616.0;
/// `|t| = |h|/(√2 σ_h)` is clamped to `2⁶²`: beyond it `g` is exactly 0 or 1 in f32 and
/// `t²` still fits in f32.
pub const STANDARDIZED_HEIGHT_LIMIT: f32 = 4_611_686_018_427_387_904.0;

/// `t = h / (√2 σ_h)`, or `Err(g)` when the CDF is decided without it (`σ_h = 0` or
/// `h = ±∞`), or `None` for invalid input.
fn standardized_height(height: f32, height_deviation: f32) -> Option<Result<f32, f32>> {
    if is_nan_bits(height) || is_nan_bits(height_deviation) {
        return None;
    }
    let (height, deviation) = (flush_subnormal(height), flush_subnormal(height_deviation));
    if !(0.0..=MAX_HEIGHT_DEVIATION).contains(&deviation) {
        return None;
    }
    if deviation == 0.0 || !is_finite_bits(height) {
        return Some(Err(if height >= 0.0 { 1.0 } else { 0.0 }));
    }
    let scale = core::f32::consts::SQRT_2 * deviation;
    if height.abs() >= STANDARDIZED_HEIGHT_LIMIT * scale {
        return Some(Ok(if height < 0.0 { -STANDARDIZED_HEIGHT_LIMIT } else { STANDARDIZED_HEIGHT_LIMIT }));
    }
    Some(Ok(flush_subnormal(height / scale)))
}

/// `g(h)`, the CDF of `N(0, σ_h²)` heights (eq. 5), `σ_h = height_deviation`.
///
/// WGSL twin: `smith_height_cdf`.
pub fn height_cdf(height: f32, height_deviation: f32) -> Option<f32> {
    let t = match standardized_height(height, height_deviation)? {
        Ok(t) => t,
        Err(g) => return Some(g),
    };
    if t < 0.0 { Some(flush_subnormal(0.5 * erfc(-t)?)) } else { Some(1.0 - 0.5 * erfc(t)?) }
}

/// `ln g(h)` (see the module docs), `≤ 0`; `−∞` where `g = 0`.
///
/// WGSL twin: `smith_log_height_cdf`.
pub fn log_height_cdf(height: f32, height_deviation: f32) -> Option<f32> {
    let t = match standardized_height(height, height_deviation)? {
        Ok(t) => t,
        Err(g) => return Some(if g == 1.0 { 0.0 } else { f32::NEG_INFINITY }),
    };
    if t < 0.0 {
        let magnitude = -t;
        // ln(½ erfcx(|t|)) − t², both terms ≤ 0: no cancellation.
        return Some(libm::logf(0.5 * erfcx(magnitude)?) - magnitude * magnitude);
    }
    Some(log_one_minus(0.5 * erfc(t)?))
}

/// `ln(1 − y)` for `y ∈ [0, ½]`: a series below [`LOG_ONE_MINUS_SERIES_LIMIT`], where
/// `1 − y` would round away the digits of `y`.
fn log_one_minus(y: f32) -> f32 {
    if y < LOG_ONE_MINUS_SERIES_LIMIT {
        let series = 1.0
            + y * (1.0 / 2.0
                + y * (1.0 / 3.0 + y * (1.0 / 4.0 + y * (1.0 / 5.0 + y * (1.0 / 6.0 + y * (1.0 / 7.0 + y / 8.0))))));
        flush_subnormal(-y * series)
    } else {
        libm::logf(1.0 - y)
    }
}

/// Smith's probability that a point at height `h` is visible from a direction with
/// masking `lambda` (eq. 4): `V = g(h)^Λ`. See the module's table for special cases.
///
/// WGSL twin: `smith_height_visibility`.
pub fn height_visibility(lambda: f32, height: f32, height_deviation: f32) -> Option<f32> {
    if is_nan_bits(lambda) || lambda < 0.0 {
        return None;
    }
    let lambda = flush_subnormal(lambda);
    let log_cdf = log_height_cdf(height, height_deviation)?;
    if lambda == 0.0 || log_cdf == 0.0 {
        return Some(1.0);
    }
    // Λ·|ln g| > 104 gives 0, tested without overflowing the product (or ∞·x).
    let magnitude = -log_cdf;
    if is_infinite_bits(lambda) || is_infinite_bits(magnitude) {
        return Some(0.0);
    }
    if magnitude >= 1.0 && lambda > EXP_ZERO_FROM / magnitude {
        return Some(0.0);
    }
    Some(flush_subnormal(libm::expf(-(lambda * magnitude))))
}

/// The attribute at height `h` under hypothesis H5bis: `a(h) = ā + a_s s(h)` with
/// `s(h) = 2g(h) − 1`. `None` as [`height_cdf`] (the attribute is valid by construction,
/// [`HeightCorrelatedAttribute::new`]; the WGSL twin checks the raw `(ā, a_s)` it is given).
///
/// WGSL twin: `smith_attribute_at_height`.
pub fn attribute_at_height(attribute: HeightCorrelatedAttribute, height: f32, height_deviation: f32) -> Option<f32> {
    let s = 2.0 * height_cdf(height, height_deviation)? - 1.0;
    Some(attribute.at(s))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cdf_matches_libm_and_is_monotone() {
        let mut previous = 0.0_f32;
        for i in -4000..=4000 {
            let h = i as f32 * 0.003;
            let g = height_cdf(h, 0.7).unwrap();
            // The exact CDF at the same f32 t = h/(√2σ) that `height_cdf` forms, so that
            // only erfc's own error remains (the rounding of t is amplified by 2t²).
            let t = f64::from(h / (core::f32::consts::SQRT_2 * 0.7));
            let exact = 0.5 * libm::erfc(-t);
            let tolerance = 4.5e-6; // erfc's measured bound (module `erf`)
            if exact < f64::from(f32::MIN_POSITIVE) {
                assert_eq!(g, 0.0, "h={h}: subnormal results are flushed");
            } else {
                assert!((f64::from(g) - exact).abs() <= tolerance * exact, "h={h}: {g} vs {exact}");
            }
            assert!(g >= previous);
            previous = g;
            let log = log_height_cdf(h, 0.7).unwrap();
            // ln g in f64 without the cancellation of ln(1 − y) for tiny y.
            let exact_log = if t < 0.0 { libm::log(exact) } else { libm::log1p(-0.5 * libm::erfc(t)) };
            let log_error = (f64::from(log) - exact_log).abs() / exact_log.abs().max(1e-300);
            if exact_log.abs() < f64::from(f32::MIN_POSITIVE) {
                assert_eq!(log, 0.0, "h={h}: subnormal results are flushed");
            } else {
                assert!(log_error <= tolerance, "h={h}: ln g = {log} vs {exact_log}, relative {log_error:e}");
            }
        }
    }

    #[test]
    fn visibility_is_g_to_the_lambda() {
        for (lambda, h) in [(0.3_f32, -1.0_f32), (2.0, 0.5), (10.0, 2.0), (0.01, -3.0)] {
            let expected = f64::from(height_cdf(h, 1.0).unwrap()).powf(f64::from(lambda));
            let v = f64::from(height_visibility(lambda, h, 1.0).unwrap());
            assert!((v - expected).abs() <= 3e-6 * expected, "Λ={lambda} h={h}: {v} vs {expected}");
        }
    }

    #[test]
    fn special_inputs_have_defined_results() {
        assert_eq!(height_cdf(0.0, 0.0), Some(1.0));
        assert_eq!(height_cdf(-1e-3, 0.0), Some(0.0));
        assert_eq!(height_cdf(f32::INFINITY, 1.0), Some(1.0));
        assert_eq!(height_cdf(f32::NEG_INFINITY, 1.0), Some(0.0));
        assert_eq!(height_cdf(0.0, 1.0), Some(0.5));
        assert_eq!(height_cdf(f32::NAN, 1.0), None);
        assert_eq!(height_cdf(0.0, -1.0), None);
        assert_eq!(height_cdf(0.0, f32::INFINITY), None);
        assert_eq!(height_cdf(0.0, 1e20), None);
        assert_eq!(height_cdf(f32::MAX, 1e-30), Some(1.0));
        assert_eq!(height_visibility(f32::MAX, -f32::MAX, 1e-30), Some(0.0));
        assert!(log_height_cdf(-f32::MAX, 1e-30).unwrap().is_finite());
        assert_eq!(height_visibility(0.0, f32::NEG_INFINITY, 1.0), Some(1.0));
        assert_eq!(height_visibility(f32::INFINITY, 0.0, 1.0), Some(0.0));
        assert_eq!(height_visibility(f32::INFINITY, f32::INFINITY, 1.0), Some(1.0));
        assert_eq!(height_visibility(1.0, -1.0, 0.0), Some(0.0));
        assert_eq!(height_visibility(-1.0, 0.0, 1.0), None);
        assert_eq!(height_visibility(f32::NAN, 0.0, 1.0), None);
        // Deep points: g underflows, ln g does not.
        assert!(log_height_cdf(-100.0, 1.0).unwrap().is_finite());
        assert_eq!(height_visibility(1e-6, -100.0, 1.0).map(|v| v > 0.0), Some(true));
    }
}
