//! The error function, in one approximation shared by the CPU and the GPU.
//!
//! WGSL has no `erf`, so the WGSL twin (`smith_erfcx` and friends in
//! `shaders/smith_micro.wgsl`) needs its own; this module is the reference for it, and
//! every other function of the crate calls this one rather than libm's, so that the CPU
//! and the GPU evaluate the same formulas.
//!
//! The approximation is the Chebyshev fit of Numerical Recipes (Press et al., *Numerical
//! Recipes in C*, 2nd ed., §6.2, `erfcc`):
//!
//! `erfc(x) = t · exp(−x² + P(t))`, `t = 1 / (1 + x/2)`, `x ≥ 0`,
//!
//! with `P` the degree-9 polynomial of [`ERFC_COEFFICIENTS`]. Its published fractional
//! error is below 1.2·10⁻⁷ for every `x ≥ 0`. It is evaluated here in the scaled form
//! [`erfcx`]`(x) = exp(x²)·erfc(x) = t·exp(P(t))`, which never underflows, so that
//! `erfc` keeps its relative accuracy until the result itself underflows, and the Smith
//! Λ of [`crate::masking`] can be computed without forming `erfc` at all.
//!
//! Measured in f32 against libm's f64 `erf`/`erfc` (test
//! `measured_error_against_libm`, 2·10⁶ points on `[−10, 10]`):
//!
//! | function | max relative error | max absolute error |
//! |---|---|---|
//! | [`erfcx`] on `[0, 10]` | 4.5·10⁻⁷ | |
//! | [`erfc`] where the result is a normal f32 | 4.1·10⁻⁶ | |
//! | [`erf`] | 3.5·10⁻⁷ | 1.9·10⁻⁷ |
//!
//! (`erfc` loses more than `erfcx` for large `x` because `exp(−x²)` amplifies the f32
//! rounding of `x²` by `x²`.) The tests assert bounds slightly above these figures.

use gpu_layout::f32_bits::{ABS_MASK, INFINITY_BITS};

/// Coefficients `c₀ … c₉` of `P(t) = c₀ + c₁t + … + c₉t⁹` (Numerical Recipes `erfcc`).
pub const ERFC_COEFFICIENTS: [f32; 10] = [
    -1.265_512_2,
    1.000_023_7,
    0.374_091_96,
    0.096_784_18,
    -0.186_288_06,
    0.278_868_07,
    -1.135_204,
    1.488_515_9,
    -0.822_152_2,
    0.170_872_77,
];

/// From this `x` on, [`erfc`] is `0` without evaluation (`erfc(10) = 2·10⁻⁴⁵` is not a
/// normal f32), so that no intermediate overflows (`x²`) on the GPU.
pub const ERFC_ZERO_FROM: f32 = 10.0;

/// Below this `|x|`, [`erf`] uses its Maclaurin series instead of `1 − erfc(|x|)`, which
/// would lose the relative accuracy of small results.
pub const ERF_SERIES_LIMIT: f32 = 0.5;

/// `exp(−x)` is 0 after flushing for `x` above this (`exp(−104) < 10⁻⁴⁵`).
pub(crate) const EXP_ZERO_FROM: f32 = 104.0;

/// Replaces a subnormal value by `+0.0`, as GPUs may (WGSL allows flushing subnormals).
/// The CPU does it explicitly wherever a subnormal could arise, so that both agree.
pub fn flush_subnormal(x: f32) -> f32 {
    if x.to_bits() & INFINITY_BITS == 0 { 0.0 } else { x }
}

/// `true` when `x` is NaN, tested on the bits as the WGSL twin does.
pub(crate) fn is_nan_bits(x: f32) -> bool {
    x.to_bits() & ABS_MASK > INFINITY_BITS
}

/// `true` when `x` is ±∞, tested on the bits as the WGSL twin does.
pub(crate) fn is_infinite_bits(x: f32) -> bool {
    x.to_bits() & ABS_MASK == INFINITY_BITS
}

/// The scaled complementary error function `erfcx(x) = exp(x²)·erfc(x)` for `x ≥ 0`.
///
/// | input | result |
/// |---|---|
/// | `x ≥ 0` finite | `min(t·exp(P(t)), 1)`, relative error < 5·10⁻⁷ |
/// | `x = +∞` | `0` (the limit; `erfcx(x) ~ 1/(x√π)`) |
/// | `x < 0`, `−0.0` | `erfcx(|x|)`: the function is only defined here for `x ≥ 0` |
/// | NaN | `None` |
///
/// WGSL twin: `smith_erfcx`.
pub fn erfcx(x: f32) -> Option<f32> {
    if is_nan_bits(x) {
        return None;
    }
    if is_infinite_bits(x) {
        return Some(0.0);
    }
    let x = flush_subnormal(x).abs();
    let t = 1.0 / (1.0 + 0.5 * x);
    // The fit gives erfcx(0) = 1 + 1 ulp; erfcx ≤ 1 holds exactly, so keep it.
    Some(flush_subnormal((t * libm::expf(erfc_polynomial(t))).min(1.0)))
}

/// `P(t)` in Horner form (the order of evaluation the WGSL twin uses).
fn erfc_polynomial(t: f32) -> f32 {
    let [c0, c1, c2, c3, c4, c5, c6, c7, c8, c9] = ERFC_COEFFICIENTS;
    let mut p = c9;
    for coefficient in [c8, c7, c6, c5, c4, c3, c2, c1, c0] {
        p = p * t + coefficient;
    }
    p
}

/// The complementary error function `erfc(x) = 1 − erf(x)`.
///
/// | input | result |
/// |---|---|
/// | `0 ≤ x < 10` | `erfcx(x)·exp(−x²)`, subnormal results flushed to `0` (from `x ≈ 9.2`) |
/// | `x ≥ 10` ([`ERFC_ZERO_FROM`]) | `0` |
/// | `x < 0` | `2 − erfc(−x)` |
/// | `±∞` | `0`, `2` |
/// | NaN | `None` |
///
/// WGSL twin: `smith_erfc`.
pub fn erfc(x: f32) -> Option<f32> {
    let x = flush_subnormal(x);
    let scaled = erfcx(x)?;
    let magnitude = x.abs();
    let tail = if magnitude >= ERFC_ZERO_FROM {
        0.0
    } else {
        flush_subnormal(scaled * flush_subnormal(libm::expf(-(magnitude * magnitude))))
    };
    Some(if x < 0.0 { 2.0 - tail } else { tail })
}

/// The error function.
///
/// | input | result |
/// |---|---|
/// | `|x| < 0.5` ([`ERF_SERIES_LIMIT`]) | Maclaurin series to `x¹³` (relative error < 10⁻⁷) |
/// | otherwise | `sign(x)·(1 − erfc(|x|))` |
/// | `±∞` | `±1` |
/// | NaN | `None` |
///
/// WGSL twin: `smith_erf`.
pub fn erf(x: f32) -> Option<f32> {
    if is_nan_bits(x) {
        return None;
    }
    let x = flush_subnormal(x);
    let magnitude = x.abs();
    if magnitude < ERF_SERIES_LIMIT {
        // erf(x) = 2/√π · Σ (−1)ⁿ x^(2n+1) / (n! (2n+1)).
        let s = x * x;
        let series = 1.0
            + s * (-1.0 / 3.0
                + s * (1.0 / 10.0 + s * (-1.0 / 42.0 + s * (1.0 / 216.0 + s * (-1.0 / 1320.0 + s * (1.0 / 9360.0))))));
        return Some(flush_subnormal(core::f32::consts::FRAC_2_SQRT_PI * x * series));
    }
    let one_minus = 1.0 - erfc(magnitude)?;
    Some(if x < 0.0 { -one_minus } else { one_minus })
}

/// Whether `x` is finite, tested on the bits.
pub(crate) fn is_finite_bits(x: f32) -> bool {
    !is_nan_bits(x) && !is_infinite_bits(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn relative(ours: f32, exact: f64) -> f64 {
        if exact == 0.0 { f64::from(ours).abs() } else { ((f64::from(ours) - exact) / exact).abs() }
    }

    #[test]
    fn measured_error_against_libm() {
        let mut worst_erfcx = 0.0_f64;
        let mut worst_erfc = 0.0_f64;
        let mut worst_erf_relative = 0.0_f64;
        let mut worst_erf_absolute = 0.0_f64;
        let count = 2_000_000;
        for i in 0..=count {
            let x = -10.0 + 20.0 * f64::from(i) / f64::from(count);
            let x32 = x as f32;
            let xd = f64::from(x32);
            if x32 >= 0.0 && xd < 26.0 {
                let exact = libm::erfc(xd) * libm::exp(xd * xd);
                worst_erfcx = worst_erfcx.max(relative(erfcx(x32).unwrap(), exact));
            }
            let exact_erfc = libm::erfc(xd);
            if exact_erfc >= f64::from(f32::MIN_POSITIVE) {
                worst_erfc = worst_erfc.max(relative(erfc(x32).unwrap(), exact_erfc));
            }
            let ours = erf(x32).unwrap();
            worst_erf_relative = worst_erf_relative.max(relative(ours, libm::erf(xd)));
            worst_erf_absolute = worst_erf_absolute.max((f64::from(ours) - libm::erf(xd)).abs());
        }
        #[cfg(feature = "std")]
        std::println!(
            "erfcx max rel {worst_erfcx:.3e}, erfc max rel {worst_erfc:.3e}, erf max rel {worst_erf_relative:.3e}, erf max abs {worst_erf_absolute:.3e}"
        );
        assert!(worst_erfcx < 5.0e-7, "erfcx: {worst_erfcx:e}");
        assert!(worst_erfc < 4.5e-6, "erfc: {worst_erfc:e}");
        assert!(worst_erf_relative < 4.0e-7, "erf relative: {worst_erf_relative:e}");
        assert!(worst_erf_absolute < 2.0e-7, "erf absolute: {worst_erf_absolute:e}");
    }

    #[test]
    fn special_inputs_have_defined_results() {
        assert_eq!(erf(f32::NAN), None);
        assert_eq!(erfc(f32::NAN), None);
        assert_eq!(erfcx(-f32::NAN), None);
        assert_eq!(erf(f32::INFINITY), Some(1.0));
        assert_eq!(erf(f32::NEG_INFINITY), Some(-1.0));
        assert_eq!(erfc(f32::INFINITY), Some(0.0));
        assert_eq!(erfc(f32::NEG_INFINITY), Some(2.0));
        assert_eq!(erfcx(f32::INFINITY), Some(0.0));
        assert_eq!(erf(0.0), Some(0.0));
        assert_eq!(erf(f32::from_bits(1)), Some(0.0));
        assert_eq!(erfc(10.0), Some(0.0));
        assert_eq!(erfcx(-2.0), erfcx(2.0));
        assert_eq!(erfcx(0.0), Some(1.0));
        assert_eq!(erfc(0.0), Some(1.0));
    }

    #[test]
    fn erf_is_odd_and_erfc_complements_it() {
        for i in 0..2000 {
            let x = i as f32 * 0.005;
            assert_eq!(erf(-x), erf(x).map(|v| -v));
            let sum = erf(x).unwrap() + erfc(x).unwrap();
            assert!((sum - 1.0).abs() < 3e-7, "x={x}: erf + erfc = {sum}");
        }
    }
}
