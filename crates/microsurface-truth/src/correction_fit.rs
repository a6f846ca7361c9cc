//! Fitting `smith-micro`'s per-material [`LambdaCorrection`] to ray-traced ground truth.
//!
//! Eq. 17 predicts the visible attribute `E[s] − ā = x(Λ) = Λ/(Λ + 2)` (with `a = s`,
//! `a_s = 1`, see [`crate::comparison`]); the correction replaces Λ by `Λ' = c(u) Λ`,
//! `u = Λ/(1 + Λ)`, with `c` piecewise linear through eight knots. The knots are fitted
//! to a view-only sweep (`Λ(l) = 0`) of the ground truth by Gauss–Newton on the squared
//! error of `E[s]` weighted by its Monte-Carlo variance — not on the factor
//! `Λ_needed/Λ`, which the noise dominates at small Λ where `∂x/∂c = 2Λ/(cΛ + 2)²`
//! vanishes. A weak prior (knots near 1, small second differences) decides the knots the
//! data cannot (`u = 0`, where Λ = 0 makes `c` irrelevant); every step is clamped to
//! `[MIN_FITTED_FACTOR, MAX_FITTED_FACTOR]`.

use std::fmt;

use smith_micro::correction::CORRECTION_KNOTS;
use smith_micro::{LambdaCorrection, LambdaCorrectionError, VisibilityCorrectionError};

use crate::comparison::{Sweep, compare};
use crate::heightfield::HeightField;

/// View angles (degrees) of the fitting sweep: dense where Λ changes fast (above 60°),
/// where eq. 17's error lives; up to 89° (Λ ≈ 11 at an RMS slope of 0.5).
pub const FIT_ANGLES_DEG: [f64; 24] = [
    0.0, 20.0, 35.0, 45.0, 52.0, 58.0, 62.0, 66.0, 69.0, 72.0, 74.0, 76.0, 78.0, 79.5, 81.0, 82.0, 83.0, 84.0, 85.0,
    86.0, 87.0, 87.5, 88.0, 89.0,
];

/// View azimuths (degrees) of the fitting sweep: two, so that the fit averages over
/// the surface's orientation (and more Monte-Carlo samples).
pub const FIT_AZIMUTHS_DEG: [f64; 2] = [45.0, 135.0];

/// Smallest fitted factor (a sane range, well inside `smith-micro`'s accepted one).
pub const MIN_FITTED_FACTOR: f64 = 0.3;
/// Largest fitted factor.
pub const MAX_FITTED_FACTOR: f64 = 3.5;

/// Prior standard deviation of each knot around 1 (weak: the data decide where they can).
const KNOT_PRIOR_DEVIATION: f64 = 0.5;
/// Prior standard deviation of the knots' second differences (smoothness).
const CURVATURE_PRIOR_DEVIATION: f64 = 0.15;
/// Floor on the Monte-Carlo standard error used as a weight, so no sample dominates.
const STANDARD_ERROR_FLOOR: f64 = 1e-3;
const GAUSS_NEWTON_ITERATIONS: usize = 12;

/// Why a fit of a correction to ray-traced ground truth failed
/// ([`fit_lambda_correction`], [`fit_to_samples`], [`crate::fit_correlation`],
/// [`crate::fit_samples`], [`crate::fit_visibility_correction`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FitError {
    /// The surface's statistics give no sweep: its measured slope deviations are not valid
    /// [`smith_micro::SlopeDeviation`]s, or a ray-traced sweep has no result.
    DegenerateSurface,
    /// No sample has a finite positive Λ (a flat field) and a finite ground truth, or no
    /// held-out sample can be evaluated.
    NoUsableSamples,
    /// The normal equations of a Gauss–Newton step are singular.
    Singular,
    /// `smith-micro` rejects the fitted table (the fit keeps its knots in
    /// `[MIN_FITTED_FACTOR, MAX_FITTED_FACTOR]`, inside the accepted range).
    Correction(LambdaCorrectionError),
    /// `smith-micro` rejects the fitted correlation coefficients (the fit keeps them in
    /// `[−8, 8]`, inside the accepted range).
    Visibility(VisibilityCorrectionError),
}

impl fmt::Display for FitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FitError::DegenerateSurface => write!(f, "degenerate surface: no sweep of its statistics"),
            FitError::NoUsableSamples => write!(f, "no usable ground-truth sample (flat surface?)"),
            FitError::Singular => write!(f, "singular normal equations"),
            FitError::Correction(error) => write!(f, "fitted table rejected: {error}"),
            FitError::Visibility(error) => write!(f, "fitted correlation rejected: {error}"),
        }
    }
}

impl std::error::Error for FitError {}

impl From<LambdaCorrectionError> for FitError {
    fn from(error: LambdaCorrectionError) -> Self {
        FitError::Correction(error)
    }
}

impl From<VisibilityCorrectionError> for FitError {
    fn from(error: VisibilityCorrectionError) -> Self {
        FitError::Visibility(error)
    }
}

/// One ground-truth sample of the visible attribute: `x = E[s] − ā` at a Smith `Λ`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitSample {
    /// `Λ(v) + Λ(l)` from the measured slope deviations (eq. 6).
    pub lambda: f64,
    /// The ray-traced `E[s] − ā`, which eq. 17 models as `Λ/(Λ + 2)`.
    pub visible: f64,
    /// The Monte-Carlo standard error of `visible`.
    pub standard_error: f64,
}

/// Fits a [`LambdaCorrection`] to view-only sweeps ([`FIT_ANGLES_DEG`] at each of
/// [`FIT_AZIMUTHS_DEG`], `rays` rays per angle, ray seeds from `seed`) of `field`'s
/// ground truth, or why not: degenerate statistics, a flat field (no usable sample) or a
/// singular fit.
pub fn fit_lambda_correction(field: &HeightField, rays: usize, seed: u64) -> Result<LambdaCorrection, FitError> {
    let mut samples = Vec::new();
    for (i, azimuth) in FIT_AZIMUTHS_DEG.iter().enumerate() {
        let sweep = Sweep {
            angles_deg: &FIT_ANGLES_DEG,
            view_azimuth: azimuth.to_radians(),
            light: None,
            rays,
            seed: seed.wrapping_add(i as u64),
        };
        let rows = compare(field, &sweep).ok_or(FitError::DegenerateSurface)?;
        samples.extend(rows.iter().map(|r| FitSample {
            lambda: r.lambda,
            visible: r.truth - r.mip,
            standard_error: r.truth_standard_error,
        }));
    }
    fit_to_samples(&samples)
}

/// The weights of the piecewise linear hat functions at `u ∈ [0, 1]`: (knot, weight)
/// pairs of the two knots around `u`, as `LambdaCorrection::factor` interpolates.
fn hat_weights(u: f64) -> [(usize, f64); 2] {
    let segments = (CORRECTION_KNOTS - 1) as f64;
    let t = u.clamp(0.0, 1.0) * segments;
    let index = (t as usize).min(CORRECTION_KNOTS - 2);
    let fraction = t - index as f64;
    [(index, 1.0 - fraction), (index + 1, fraction)]
}

/// Fits the knots to `samples` (see the module's documentation), or why not: no sample
/// has a finite positive Λ ([`FitError::NoUsableSamples`]) or the normal equations are
/// singular ([`FitError::Singular`]).
pub fn fit_to_samples(samples: &[FitSample]) -> Result<LambdaCorrection, FitError> {
    let usable: Vec<&FitSample> = samples
        .iter()
        .filter(|s| s.lambda.is_finite() && s.lambda > 0.0 && s.visible.is_finite() && s.standard_error.is_finite())
        .collect();
    if usable.is_empty() {
        return Err(FitError::NoUsableSamples);
    }
    const N: usize = CORRECTION_KNOTS;
    let mut knots = [1.0_f64; N];
    for _ in 0..GAUSS_NEWTON_ITERATIONS {
        let mut matrix = [[0.0_f64; N]; N];
        let mut gradient = [0.0_f64; N];
        for sample in &usable {
            let lambda = sample.lambda;
            let hats = hat_weights(lambda / (1.0 + lambda));
            let factor: f64 = hats.iter().map(|&(i, w)| w * knots[i]).sum();
            let corrected = factor * lambda;
            let model = corrected / (corrected + 2.0);
            let slope = 2.0 * lambda / (corrected + 2.0).powi(2);
            let weight = 1.0 / (sample.standard_error.powi(2) + STANDARD_ERROR_FLOOR.powi(2));
            let residual = sample.visible - model;
            for &(i, wi) in &hats {
                gradient[i] += weight * slope * wi * residual;
                for &(j, wj) in &hats {
                    matrix[i][j] += weight * slope * slope * wi * wj;
                }
            }
        }
        // Prior: knots ~ N(1, 0.5²), second differences ~ N(0, 0.15²).
        let ridge = 1.0 / KNOT_PRIOR_DEVIATION.powi(2);
        for i in 0..N {
            matrix[i][i] += ridge;
            gradient[i] -= ridge * (knots[i] - 1.0);
        }
        let smooth = 1.0 / CURVATURE_PRIOR_DEVIATION.powi(2);
        for i in 1..N - 1 {
            let stencil = [(i - 1, 1.0), (i, -2.0), (i + 1, 1.0)];
            let curvature: f64 = stencil.iter().map(|&(k, s)| s * knots[k]).sum();
            for &(a, sa) in &stencil {
                gradient[a] -= smooth * sa * curvature;
                for &(b, sb) in &stencil {
                    matrix[a][b] += smooth * sa * sb;
                }
            }
        }
        let step = solve(matrix, gradient).ok_or(FitError::Singular)?;
        for (knot, delta) in knots.iter_mut().zip(step) {
            *knot = (*knot + delta).clamp(MIN_FITTED_FACTOR, MAX_FITTED_FACTOR);
        }
    }
    Ok(LambdaCorrection::from_knots(knots.map(|k| k as f32))?)
}

/// Solves `matrix · x = rhs` by Gaussian elimination with partial pivoting; `None` when a
/// pivot vanishes.
pub(crate) fn solve<const N: usize>(mut matrix: [[f64; N]; N], mut rhs: [f64; N]) -> Option<[f64; N]> {
    for column in 0..N {
        let pivot = (column..N).max_by(|&a, &b| matrix[a][column].abs().total_cmp(&matrix[b][column].abs()))?;
        if matrix[pivot][column].abs() < 1e-300 || !matrix[pivot][column].is_finite() {
            return None;
        }
        matrix.swap(column, pivot);
        rhs.swap(column, pivot);
        let pivot_row = matrix[column];
        for row in column + 1..N {
            let ratio = matrix[row][column] / pivot_row[column];
            for (entry, &above) in matrix[row].iter_mut().zip(&pivot_row).skip(column) {
                *entry -= ratio * above;
            }
            rhs[row] -= ratio * rhs[column];
        }
    }
    let mut x = [0.0_f64; N];
    for row in (0..N).rev() {
        let tail: f64 = (row + 1..N).map(|k| matrix[row][k] * x[k]).sum();
        x[row] = (rhs[row] - tail) / matrix[row][row];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Samples of a surface whose true factor is `truth(Λ)`, without noise.
    fn synthetic(truth: impl Fn(f64) -> f64) -> Vec<FitSample> {
        (0..80)
            .map(|i| {
                let lambda = 0.02 * 1.08_f64.powi(i);
                let corrected = truth(lambda) * lambda;
                FitSample { lambda, visible: corrected / (corrected + 2.0), standard_error: 2e-3 }
            })
            .collect()
    }

    #[test]
    fn recovers_a_known_factor() {
        let truth = |lambda: f64| 0.8 + 0.4 * lambda / (1.0 + lambda);
        let samples = synthetic(truth);
        let correction = fit_to_samples(&samples).unwrap();
        for sample in &samples {
            let model = f64::from(
                smith_micro::corrected_visible_mean_attribute(
                    smith_micro::HeightCorrelatedAttribute::new(0.0, 1.0).unwrap(),
                    sample.lambda as f32,
                    0.0,
                    &correction,
                )
                .unwrap(),
            );
            assert!((model - sample.visible).abs() < 1e-3, "Λ = {}: {model} vs {}", sample.lambda, sample.visible);
        }
    }

    #[test]
    fn eq17_data_give_the_identity() {
        let correction = fit_to_samples(&synthetic(|_| 1.0)).unwrap();
        for knot in correction.knots() {
            assert!((knot - 1.0).abs() < 1e-3, "{:?}", correction.knots());
        }
    }

    #[test]
    fn degenerate_samples_are_reported_and_extreme_data_stay_in_range() {
        assert_eq!(fit_to_samples(&[]), Err(FitError::NoUsableSamples));
        let flat = [FitSample { lambda: 0.0, visible: 0.0, standard_error: 0.0 }];
        assert_eq!(fit_to_samples(&flat), Err(FitError::NoUsableSamples));
        let unmeasured = [FitSample { lambda: 0.5, visible: f64::NAN, standard_error: 1e-3 }];
        assert_eq!(fit_to_samples(&unmeasured), Err(FitError::NoUsableSamples));
        let extreme = fit_to_samples(&synthetic(|_| 10.0)).unwrap();
        let range = MIN_FITTED_FACTOR as f32..=MAX_FITTED_FACTOR as f32;
        assert!(extreme.knots().iter().all(|k| range.contains(k)), "{:?}", extreme.knots());
    }
}
