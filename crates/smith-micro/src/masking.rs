//! Smith's masking function Λ for Gaussian slopes (eq. 6), isotropic and anisotropic.
//!
//! For a surface whose slopes are Gaussian with standard deviation `σ` along the azimuth
//! of a direction `v` at angle `θ` from the mean normal, Smith (1967) gives, with
//! `μ = cot θ` and `ν = μ / (√2 σ)` (eq. 6 of the paper, rewritten in `ν`):
//!
//! `Λ(ν) = ½ (exp(−ν²) / (ν√π) − erfc(ν))`.
//!
//! The machine extraction of eq. 6 reads `½(√(2/π) σ/μ · exp(−μ²/2σ²) − erfc(μ/√2σ))`,
//! which is the same expression; we re-derived it from Smith's integral
//! `Λ(μ) = (1/μ) ∫_μ^∞ (q − μ) p(q) dq` with `p` the `N(0, σ²)` slope density, and a test
//! checks it against that integral.
//!
//! # Evaluation without cancellation
//!
//! Written as `Λ = ½ exp(−ν²) F(ν)`, `F(ν) = 1/(ν√π) − erfcx(ν)`, the two terms of `F`
//! cancel for large `ν` (`F ≈ 1/(2ν³√π)`, each term ≈ `1/(ν√π)`), which would multiply
//! the f32 rounding of `erfcx` by `2ν²`. So:
//!
//! - `ν < 2` ([`CONTINUED_FRACTION_FROM_NU`]): `F` from [`crate::erf::erfcx`] directly
//!   (cancellation at most ×10);
//! - `ν ≥ 2`: `F = K / (√π ν (ν + K))` with `K` the tail of the continued fraction
//!   `erfcx(ν) = (1/√π) / (ν + (1/2)/(ν + 1/(ν + (3/2)/(ν + …))))`, evaluated with
//!   [`CONTINUED_FRACTION_TERMS`] terms by the forward recurrence (one division). Its
//!   truncation error is below 1.2·10⁻⁸ relative on `[2, ∞)`. Every term is positive, so
//!   nothing cancels.
//! - `ν ≥ 9` ([`LAMBDA_ZERO_FROM_NU`]): Λ < 2·10⁻³⁹ is not a normal f32, and is `0`.
//!
//! Measured against the f64 formula on `ν ∈ (0, 9)` (9·10⁵ points): max relative error
//! 4.5·10⁻⁶, at ν = 8.78, from the f32 rounding of `ν²` inside `exp(−ν²)`.
//!
//! # Cross-check with pbrt-v3
//!
//! pbrt-v3's rational fit of the Beckmann Λ (`a = 1/(α tan θ) = ν`; `0` if `a ≥ 1.6`,
//! else `(1 − 1.259a + 0.396a²)/(3.535a + 2.181a²)`) differs from eq. 6 by at most
//! 3.12·10⁻³ on the visibility `1/(1+Λ)` (at ν ≈ 1.34), and by 1.7 % relative on Λ for
//! ν ≤ 0.5; the test `pbrt_rational_fit_differs_by_its_measured_error` measures it.
//!
//! # Special inputs
//!
//! | input | Λ |
//! |---|---|
//! | normal incidence (`μ = +∞`, `v = +z`) | `0` |
//! | grazing (`μ = 0`, `v_z = ±0`) with `σ > 0` | `+∞` |
//! | below the horizon (`μ < 0`, `v_z < 0`) | `None`: no point of the surface is seen |
//! | `σ = 0` (flat surface), any `μ ≥ 0` | `0`: a plane masks nothing |
//! | `σ_x ≠ σ_y`, `σ` along the azimuth of `v` is `0` | `0` (the surface is flat along `v`) |
//! | `ν` subnormal (flushed to 0, as a GPU may) | `+∞` (Λ < 2.4·10³⁷ for every normal ν) |
//! | `σ < 2⁻³²` ([`MIN_SLOPE_DEVIATION`]) | as `σ = 0` |
//! | `σ < 0`, `σ > 2³²` ([`MAX_SLOPE_DEVIATION`]), NaN inputs, zero or non-finite direction | `None` |

use glam::Vec3;

use crate::erf::{erfcx, flush_subnormal, is_finite_bits, is_infinite_bits, is_nan_bits};

/// From this `ν` on, `F(ν)` comes from the continued fraction, not from `erfcx`.
pub const CONTINUED_FRACTION_FROM_NU: f32 = 2.0;
/// Number of terms of the continued fraction of `erfcx` (truncation error < 1.2·10⁻⁸).
pub const CONTINUED_FRACTION_TERMS: u32 = 20;
/// From this `ν` on, Λ is not a normal f32 and is returned as `0`.
pub const LAMBDA_ZERO_FROM_NU: f32 = 9.0;

/// `1/√π`.
pub const FRAC_1_SQRT_PI: f32 = 0.564_189_6;
/// Largest accepted slope deviation, `2³²`: with it no product of this crate overflows
/// f32, which the WGSL twin could not represent. (A slope deviation of 4·10⁹ is a
/// vertical wall for every purpose.)
pub const MAX_SLOPE_DEVIATION: f32 = 4_294_967_296.0;
/// Smaller slope deviations, `< 2⁻³²`, are flat: they are replaced by `0`.
pub const MIN_SLOPE_DEVIATION: f32 = 1.0 / 4_294_967_296.0;

/// Standard deviations of the slopes of a Gaussian surface along the tangent axes x and
/// y of its mean-normal frame (`σ_nx`, `σ_ny` of §5.2; equal for an isotropic surface).
///
/// Each deviation is `0` or in `[MIN_SLOPE_DEVIATION, √2 MAX_SLOPE_DEVIATION]`, never NaN:
/// the constructors accept `[0, MAX_SLOPE_DEVIATION]` (and flush what is below
/// [`MIN_SLOPE_DEVIATION`] to `0`), and the §5.5 convolution of two accepted deviations
/// ([`crate::convolved_slope_deviation`]) reaches at most `√2` times the bound. Every
/// function of the crate relies on it: with it no product overflows f32.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlopeDeviation {
    x: f32,
    y: f32,
}

/// The tangent axis a [`SlopeDeviationError`] is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SlopeAxis {
    /// `σ_nx`.
    X,
    /// `σ_ny`.
    Y,
}

/// Why a [`SlopeDeviation`] constructor rejected its input. `value` is the value given: a
/// deviation, or a variance for [`SlopeDeviation::from_variances`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SlopeDeviationError {
    /// The value is NaN.
    NotANumber {
        /// The axis.
        axis: SlopeAxis,
    },
    /// The value is negative (`−∞` included; `−0.0` is accepted, as `0`).
    Negative {
        /// The axis.
        axis: SlopeAxis,
        /// The value given.
        value: f32,
    },
    /// The deviation is above [`MAX_SLOPE_DEVIATION`] (`+∞` included).
    TooLarge {
        /// The axis.
        axis: SlopeAxis,
        /// The value given.
        value: f32,
    },
}

impl core::fmt::Display for SlopeDeviationError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        let name = |axis: &SlopeAxis| match axis {
            SlopeAxis::X => "x",
            SlopeAxis::Y => "y",
        };
        match self {
            SlopeDeviationError::NotANumber { axis } => write!(f, "the slope deviation along {} is NaN", name(axis)),
            SlopeDeviationError::Negative { axis, value } => {
                write!(f, "the slope deviation along {} is negative ({value})", name(axis))
            }
            SlopeDeviationError::TooLarge { axis, value } => {
                write!(f, "the slope deviation along {} ({value}) is above {MAX_SLOPE_DEVIATION}", name(axis))
            }
        }
    }
}

impl core::error::Error for SlopeDeviationError {}

impl SlopeDeviation {
    /// The deviations `(σ_nx, σ_ny)`, or why not: NaN, negative or above
    /// [`MAX_SLOPE_DEVIATION`] (`x` is checked first). Values below
    /// [`MIN_SLOPE_DEVIATION`] become `0`.
    ///
    /// WGSL twin: `smith_slope_deviation`.
    pub fn new(x: f32, y: f32) -> Result<Self, SlopeDeviationError> {
        let check = |axis: SlopeAxis, s: f32| {
            if is_nan_bits(s) {
                Err(SlopeDeviationError::NotANumber { axis })
            } else if s < 0.0 {
                Err(SlopeDeviationError::Negative { axis, value: s })
            } else if s > MAX_SLOPE_DEVIATION {
                Err(SlopeDeviationError::TooLarge { axis, value: s })
            } else {
                Ok(if s < MIN_SLOPE_DEVIATION { 0.0 } else { s })
            }
        };
        Ok(Self { x: check(SlopeAxis::X, x)?, y: check(SlopeAxis::Y, y)? })
    }

    /// An isotropic surface, `σ_nx = σ_ny = sigma` (see [`Self::new`]; an error names
    /// the x axis).
    pub fn isotropic(sigma: f32) -> Result<Self, SlopeDeviationError> {
        Self::new(sigma, sigma)
    }

    /// Deviations built from slope variances `(σ_nx², σ_ny²)`, the quantities a voxel
    /// stores and interpolates (§5.2), or why not: a variance NaN, negative, or whose
    /// square root is above [`MAX_SLOPE_DEVIATION`] (`+∞` included; the error holds the
    /// variance).
    pub fn from_variances(x: f32, y: f32) -> Result<Self, SlopeDeviationError> {
        let deviation = |axis: SlopeAxis, variance: f32| {
            if is_nan_bits(variance) {
                return Err(SlopeDeviationError::NotANumber { axis });
            }
            if variance < 0.0 {
                return Err(SlopeDeviationError::Negative { axis, value: variance });
            }
            let deviation = libm::sqrtf(flush_subnormal(variance));
            if is_infinite_bits(variance) || deviation > MAX_SLOPE_DEVIATION {
                return Err(SlopeDeviationError::TooLarge { axis, value: variance });
            }
            Ok(deviation)
        };
        let (x, y) = (deviation(SlopeAxis::X, x)?, deviation(SlopeAxis::Y, y)?);
        Self::new(x, y)
    }

    /// `σ_nx`, the standard deviation of `∂h/∂x`.
    pub fn x(&self) -> f32 {
        self.x
    }

    /// `σ_ny`, the standard deviation of `∂h/∂y`.
    pub fn y(&self) -> f32 {
        self.y
    }

    /// The per-axis convolution of §5.5 (see [`crate::convolved_slope_deviation`]):
    /// deviations that are `0` or at least [`MIN_SLOPE_DEVIATION`] and at most `√2` times
    /// [`MAX_SLOPE_DEVIATION`] when both inputs were accepted.
    pub(crate) fn convolved(x: f32, y: f32) -> Self {
        Self { x, y }
    }
}

/// Λ as a function of `ν = μ / (√2 σ_n)` (eq. 6), the core of every other Λ here.
///
/// | `nu` | Λ |
/// |---|---|
/// | `0`, `−0.0` or subnormal | `+∞` (grazing) |
/// | `(0, 9)` | eq. 6, relative error < 5·10⁻⁶ (measured 4.5·10⁻⁶ at ν = 8.78: the f32 rounding of `ν²` in `exp(−ν²)`, ≈ `ν²·2⁻²⁴`) |
/// | `≥ 9`, `+∞` | `0` |
/// | negative or NaN | `None` |
///
/// WGSL twin: `smith_lambda_from_nu`.
pub fn smith_lambda_from_nu(nu: f32) -> Option<f32> {
    if is_nan_bits(nu) {
        return None;
    }
    let nu = flush_subnormal(nu);
    if nu < 0.0 {
        return None;
    }
    if nu == 0.0 {
        return Some(f32::INFINITY);
    }
    if nu >= LAMBDA_ZERO_FROM_NU {
        return Some(0.0);
    }
    let half_gaussian = 0.5 * libm::expf(-(nu * nu));
    let f = if nu < CONTINUED_FRACTION_FROM_NU {
        FRAC_1_SQRT_PI / nu - erfcx(nu)?
    } else {
        let k = continued_fraction_tail(nu);
        FRAC_1_SQRT_PI * k / (nu * (nu + k))
    };
    Some(flush_subnormal(half_gaussian * f))
}

/// `K(ν) = (1/2)/(ν + 1/(ν + (3/2)/(ν + …)))` with [`CONTINUED_FRACTION_TERMS`] terms,
/// from the forward recurrence `A_j = ν A_{j−1} + (j/2) A_{j−2}` (same for `B`), for
/// `2 ≤ ν < 9`: the convergents stay below `10²⁰`, far from f32 overflow.
fn continued_fraction_tail(nu: f32) -> f32 {
    // Convergents of b₀ + a₁/(b₁ + a₂/(b₂ + …)) with b₀ = 0, b_j = ν, a_j = j/2.
    let (mut a_previous, mut a_current) = (1.0_f32, 0.0_f32);
    let (mut b_previous, mut b_current) = (0.0_f32, 1.0_f32);
    for j in 1..=CONTINUED_FRACTION_TERMS {
        let partial = 0.5 * j as f32;
        let a_next = nu * a_current + partial * a_previous;
        let b_next = nu * b_current + partial * b_previous;
        (a_previous, a_current) = (a_current, a_next);
        (b_previous, b_current) = (b_current, b_next);
    }
    a_current / b_current
}

/// Isotropic Λ of a direction at `μ = cot θ` from the mean normal over slopes of
/// deviation `sigma` (eq. 6). See the module's table for every special case.
///
/// WGSL twin: `smith_lambda_isotropic`.
pub fn smith_lambda(mu: f32, sigma: f32) -> Option<f32> {
    let sigma = SlopeDeviation::isotropic(sigma).ok()?.x;
    if is_nan_bits(mu) {
        return None;
    }
    let mu = flush_subnormal(mu);
    if mu < 0.0 {
        return None;
    }
    let scale = core::f32::consts::SQRT_2 * sigma;
    // ν ≥ 9 gives 0; testing it by a product avoids overflowing μ/(√2σ).
    if sigma == 0.0 || is_infinite_bits(mu) || mu >= LAMBDA_ZERO_FROM_NU * scale {
        return Some(0.0);
    }
    smith_lambda_from_nu(flush_subnormal(mu / scale))
}

/// `ν = v_z / √(2 (σ_x² v_x² + σ_y² v_y²))` of a direction `v` in the mean-normal frame
/// (z along the mean normal), or `None` for a zero or non-finite `v` or one below the
/// horizon (`v_z < 0`).
///
/// This is `μ / (√2 σ_n(v))` with `μ = cot θ = v_z / √(v_x² + v_y²)` and the projected
/// deviation `σ_n(v)² = σ_x² cos² φ + σ_y² sin² φ` of [`projected_slope_deviation`]: the
/// `√(v_x² + v_y²)` cancels, so normal incidence needs no special case (`ν = +∞`).
/// Returns `+∞` when the denominator is 0 (normal incidence or flat along `v`).
///
/// WGSL twin: `smith_nu_of_direction`.
pub fn nu_of_direction(direction: Vec3, slopes: SlopeDeviation) -> Option<f32> {
    let v = canonical_direction(direction)?;
    if v.z < 0.0 {
        return None;
    }
    let along_x = flush_subnormal(slopes.x * v.x.abs());
    let along_y = flush_subnormal(slopes.y * v.y.abs());
    let larger = along_x.max(along_y);
    if larger == 0.0 {
        return Some(f32::INFINITY);
    }
    let ratio = along_x.min(along_y) / larger;
    let denominator = larger * libm::sqrtf(2.0 + 2.0 * ratio * ratio);
    // v_z < 4: the quotient overflows only where the denominator is below 1.
    if denominator < 1.0 && v.z > f32::MAX * denominator {
        return Some(f32::INFINITY);
    }
    Some(flush_subnormal(v.z / denominator))
}

/// Λ of a direction `v` given in the mean-normal frame (eq. 6 with the anisotropic
/// `σ_n(v)`), or `None` as [`nu_of_direction`]. `v` need not be normalized.
///
/// WGSL twin: `smith_lambda_direction`.
pub fn smith_lambda_direction(direction: Vec3, slopes: SlopeDeviation) -> Option<f32> {
    smith_lambda_from_nu(nu_of_direction(direction, slopes)?)
}

/// `σ_n(v)`: the deviation of the slopes along the azimuth `φ` of `v`,
/// `√(σ_x² cos² φ + σ_y² sin² φ)`, or `None` when `v` has no azimuth (`v_x = v_y = 0`)
/// or is zero or non-finite.
pub fn projected_slope_deviation(direction: Vec3, slopes: SlopeDeviation) -> Option<f32> {
    let v = canonical_direction(direction)?;
    let horizontal = libm::sqrtf(v.x * v.x + v.y * v.y);
    if horizontal == 0.0 {
        return None;
    }
    let (cos_phi, sin_phi) = (v.x / horizontal, v.y / horizontal);
    Some(libm::hypotf(slopes.x * cos_phi, slopes.y * sin_phi))
}

/// Smith's mean visibility of a surface seen from a direction with masking `lambda`:
/// `∫ g'(h) g(h)^Λ dh = 1 / (1 + Λ)` (eq. 4 integrated over the heights; the `V̄(l)` of
/// eq. 13 for the light direction). `+∞ → 0`; NaN or negative `lambda` → `None`.
///
/// WGSL twin: `smith_mean_visibility`.
pub fn mean_visibility(lambda: f32) -> Option<f32> {
    if is_nan_bits(lambda) || lambda < 0.0 {
        return None;
    }
    Some(flush_subnormal(1.0 / (1.0 + lambda)))
}

/// `direction` scaled by a power of two so that its largest component is in `[2, 4)`,
/// subnormal components flushed; `None` for zero, NaN or infinite components. Exact, so
/// the WGSL twin (`smith_canonical_direction`) gets the same bits.
pub fn canonical_direction(direction: Vec3) -> Option<Vec3> {
    if !direction.to_array().iter().all(|&c| is_finite_bits(c)) {
        return None;
    }
    let flushed = direction.map(flush_subnormal);
    let largest = flushed.abs().max_element();
    if largest == 0.0 {
        return None;
    }
    let exponent = (largest.to_bits() >> 23) & 0xff;
    let scale = f32::from_bits((255 - exponent) << 23);
    Some((flushed * scale).map(flush_subnormal))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Λ in f64 by the direct formula (fine in f64 up to ν ≈ 9: cancellation ×2ν²).
    pub(crate) fn lambda_f64(nu: f64) -> f64 {
        0.5 * (libm::exp(-nu * nu) / (nu * libm::sqrt(core::f64::consts::PI)) - libm::erfc(nu))
    }

    /// `(1/μ) ∫_μ^∞ (q − μ) p(q) dq` by Simpson's rule, `p` the N(0, σ²) density.
    fn lambda_by_integration(mu: f64, sigma: f64) -> f64 {
        let steps = 20_000;
        let upper = mu + 40.0 * sigma;
        let h = (upper - mu) / f64::from(steps);
        let integrand = |q: f64| {
            (q - mu) * libm::exp(-q * q / (2.0 * sigma * sigma)) / (sigma * libm::sqrt(2.0 * core::f64::consts::PI))
        };
        let mut sum = integrand(mu) + integrand(upper);
        for i in 1..steps {
            let weight = if i % 2 == 1 { 4.0 } else { 2.0 };
            sum += weight * integrand(mu + h * f64::from(i));
        }
        sum * h / 3.0 / mu
    }

    #[test]
    fn eq6_matches_smiths_integral() {
        for sigma in [0.05_f64, 0.3, 1.0, 2.5] {
            for mu in [0.02_f64, 0.1, 0.5, 1.0, 2.0, 5.0] {
                let nu = mu / (core::f64::consts::SQRT_2 * sigma);
                if nu > 6.0 {
                    continue;
                }
                let integral = lambda_by_integration(mu, sigma);
                let closed = lambda_f64(nu);
                assert!(
                    (closed - integral).abs() <= 1e-9 * integral.max(1e-3),
                    "μ={mu} σ={sigma}: {closed} vs {integral}"
                );
                let ours = f64::from(smith_lambda(mu as f32, sigma as f32).unwrap());
                assert!((ours - integral).abs() <= 2e-6 * integral + 1e-30, "μ={mu} σ={sigma}: {ours} vs {integral}");
            }
        }
    }

    #[test]
    fn measured_error_against_the_f64_formula() {
        let mut worst = (0.0_f64, 0.0_f64);
        for i in 1..=900_000 {
            let nu32 = i as f32 * 1e-5;
            let nu = f64::from(nu32);
            let exact = lambda_f64(nu);
            if exact < f64::from(f32::MIN_POSITIVE) {
                continue;
            }
            let ours = f64::from(smith_lambda_from_nu(nu32).unwrap());
            if (ours - exact).abs() / exact > worst.0 {
                worst = ((ours - exact).abs() / exact, nu);
            }
        }
        #[cfg(feature = "std")]
        std::println!("Λ(ν) max relative error on (0, 9): {:.3e} at ν = {:.4}", worst.0, worst.1);
        assert!(worst.0 < 5e-6, "{worst:?}");
    }

    /// pbrt-v3's rational fit of the Beckmann Λ (`BeckmannDistribution::Lambda`), with
    /// `α = √2 σ` and `a = 1/(α tan θ) = ν`.
    fn pbrt_lambda(a: f64) -> f64 {
        if a >= 1.6 { 0.0 } else { (1.0 - 1.259 * a + 0.396 * a * a) / (3.535 * a + 2.181 * a * a) }
    }

    #[test]
    fn pbrt_rational_fit_differs_by_its_measured_error() {
        // The fit's own error, measured here against eq. 6 on ν ∈ [10⁻³, 1.6): the
        // error on the Smith visibility 1/(1+Λ), max |ΔΛ|/(1+Λ), is 3.12·10⁻³ (at
        // ν ≈ 1.34); the relative error on Λ is below 1.7 % for ν ≤ 0.5 but reaches
        // 100 % near the cut (the fit turns negative just below ν = 1.6, where
        // Λ = 1.8·10⁻³). Our Λ, 10⁴ times more accurate, must reproduce this figure.
        let mut worst_visibility = (0.0_f64, 0.0_f64);
        let mut worst_relative_low = 0.0_f64;
        for i in 0..160_000 {
            let nu = 1e-3 + f64::from(i) * 1e-5;
            if nu >= 1.6 {
                break;
            }
            let ours = f64::from(smith_lambda_from_nu(nu as f32).unwrap());
            let difference = (ours - pbrt_lambda(nu)).abs();
            if difference / (1.0 + ours) > worst_visibility.0 {
                worst_visibility = (difference / (1.0 + ours), nu);
            }
            if nu <= 0.5 {
                worst_relative_low = worst_relative_low.max(difference / ours);
            }
        }
        #[cfg(feature = "std")]
        std::println!(
            "pbrt fit: max |ΔΛ|/(1+Λ) = {:.4e} at ν = {:.4}, max relative on ν ≤ 0.5 = {worst_relative_low:.3e}",
            worst_visibility.0,
            worst_visibility.1
        );
        assert!((3.05e-3..3.2e-3).contains(&worst_visibility.0), "{worst_visibility:?}");
        assert!((1.30..1.38).contains(&worst_visibility.1), "{worst_visibility:?}");
        assert!((0.015..0.018).contains(&worst_relative_low), "{worst_relative_low:e}");
    }

    #[test]
    fn special_inputs_have_defined_results() {
        let iso = SlopeDeviation::isotropic(0.4).unwrap();
        assert_eq!(smith_lambda_direction(Vec3::Z, iso), Some(0.0));
        assert_eq!(smith_lambda_direction(Vec3::X, iso), Some(f32::INFINITY));
        assert_eq!(smith_lambda_direction(Vec3::new(1.0, 0.0, -0.0), iso), Some(f32::INFINITY));
        assert_eq!(smith_lambda_direction(Vec3::new(1.0, 0.0, -0.1), iso), None);
        assert_eq!(smith_lambda_direction(Vec3::ZERO, iso), None);
        assert_eq!(smith_lambda_direction(Vec3::new(f32::NAN, 0.0, 1.0), iso), None);
        assert_eq!(smith_lambda_direction(Vec3::new(f32::INFINITY, 0.0, 1.0), iso), None);
        let flat = SlopeDeviation::isotropic(0.0).unwrap();
        assert_eq!(smith_lambda_direction(Vec3::X, flat), Some(0.0));
        // Anisotropic: flat along x, rough along y.
        let grooves = SlopeDeviation::new(0.0, 0.5).unwrap();
        assert_eq!(smith_lambda_direction(Vec3::new(1.0, 0.0, 0.1), grooves), Some(0.0));
        assert!(smith_lambda_direction(Vec3::new(0.0, 1.0, 0.1), grooves).unwrap() > 1.0);
        assert_eq!(
            SlopeDeviation::new(-1.0, 0.0),
            Err(SlopeDeviationError::Negative { axis: SlopeAxis::X, value: -1.0 })
        );
        assert_eq!(
            SlopeDeviation::new(0.0, f32::INFINITY),
            Err(SlopeDeviationError::TooLarge { axis: SlopeAxis::Y, value: f32::INFINITY })
        );
        assert_eq!(SlopeDeviation::new(f32::NAN, 0.0), Err(SlopeDeviationError::NotANumber { axis: SlopeAxis::X }));
        assert_eq!(SlopeDeviation::new(-0.0, 0.5).map(|s| s.x().to_bits()), Ok(0.0_f32.to_bits()));
        assert_eq!(smith_lambda(f32::INFINITY, 0.3), Some(0.0));
        assert_eq!(smith_lambda(0.0, 0.3), Some(f32::INFINITY));
        assert_eq!(smith_lambda(0.0, 0.0), Some(0.0));
        assert_eq!(smith_lambda(-1.0, 0.3), None);
        assert_eq!(smith_lambda(1.0, f32::INFINITY), None);
        assert_eq!(smith_lambda(f32::MAX, 1e-9), Some(0.0));
        assert_eq!(
            SlopeDeviation::new(1e-10, 5e9),
            Err(SlopeDeviationError::TooLarge { axis: SlopeAxis::Y, value: 5e9 })
        );
        assert_eq!(SlopeDeviation::new(1e-10, 1.0), Ok(SlopeDeviation { x: 0.0, y: 1.0 }));
        // Variances: the error holds the variance given.
        assert_eq!(SlopeDeviation::from_variances(0.25, 0.0), SlopeDeviation::new(0.5, 0.0));
        assert_eq!(
            SlopeDeviation::from_variances(0.25, -1e-3),
            Err(SlopeDeviationError::Negative { axis: SlopeAxis::Y, value: -1e-3 })
        );
        assert_eq!(
            SlopeDeviation::from_variances(1e30, 0.0),
            Err(SlopeDeviationError::TooLarge { axis: SlopeAxis::X, value: 1e30 })
        );
        assert_eq!(
            SlopeDeviation::from_variances(f32::INFINITY, 0.0),
            Err(SlopeDeviationError::TooLarge { axis: SlopeAxis::X, value: f32::INFINITY })
        );
        assert_eq!(
            SlopeDeviation::from_variances(0.0, f32::NAN),
            Err(SlopeDeviationError::NotANumber { axis: SlopeAxis::Y })
        );
        assert_eq!(smith_lambda_from_nu(f32::INFINITY), Some(0.0));
        assert_eq!(smith_lambda_from_nu(f32::from_bits(1)), Some(f32::INFINITY));
        assert!(smith_lambda_from_nu(2e-38).unwrap().is_finite());
        assert_eq!(mean_visibility(f32::INFINITY), Some(0.0));
        assert_eq!(mean_visibility(-1.0), None);
        // Extreme but accepted slopes: no overflow, no underflow to a wrong limit.
        let steep = SlopeDeviation::isotropic(MAX_SLOPE_DEVIATION).unwrap();
        let lambda = smith_lambda_direction(Vec3::new(1.0, 0.0, 1.0), steep).unwrap();
        assert!(lambda.is_finite() && lambda > 1e9);
        let shallow = SlopeDeviation::isotropic(MIN_SLOPE_DEVIATION).unwrap();
        assert_eq!(nu_of_direction(Vec3::new(1.0, 0.0, 1.0), shallow).map(|nu| nu > 1e9), Some(true));
        assert_eq!(nu_of_direction(Vec3::new(1e-30, 0.0, 1.0), shallow), Some(f32::INFINITY));
    }

    #[test]
    fn anisotropic_lambda_uses_the_projected_deviation() {
        let slopes = SlopeDeviation::new(0.2, 0.7).unwrap();
        for (theta, phi) in [(0.3_f32, 0.0_f32), (1.2, 0.7), (1.5, 2.0), (0.9, -1.1)] {
            let v = Vec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
            let sigma = projected_slope_deviation(v, slopes).unwrap();
            let expected = (0.04 * phi.cos().powi(2) + 0.49 * phi.sin().powi(2)).sqrt();
            assert!((sigma - expected).abs() < 1e-6);
            let mu = theta.cos() / theta.sin();
            let isotropic = smith_lambda(mu, sigma).unwrap();
            let anisotropic = smith_lambda_direction(v * 3.0, slopes).unwrap();
            assert!((isotropic - anisotropic).abs() <= 2e-5 * isotropic, "{isotropic} vs {anisotropic}");
        }
        assert_eq!(projected_slope_deviation(Vec3::Z, slopes), None);
    }
}
