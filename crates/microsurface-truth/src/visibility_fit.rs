//! Fitting `smith-micro`'s [`VisibilityCorrection`] (view table, light table, light–view
//! correlation `ρ(cos Δφ)`) to ray-traced ground truth, on several realizations of a
//! surface at once so that the fit describes the material rather than one realization's
//! noise.
//!
//! Three kinds of samples of `x = E[s] − ā` (see [`crate::comparison`]), from each field:
//! 1. view-only sweeps ([`FIT_ANGLES_DEG`] × [`FIT_AZIMUTHS_DEG`]): `x = x(c_v Λ(v))`,
//!    fitted by [`fit_to_samples`] → the view table `c_v`;
//! 2. light sweeps at normal view (the same angles, for the light): `x = x(c_l Λ(l))`,
//!    → the light table `c_l`;
//! 3. view sweeps ([`CORRELATION_VIEW_ANGLES_DEG`]) under the lights of
//!    [`CORRELATION_LIGHTS_DEG`] (several azimuth differences): with both tables fixed,
//!    `x = x(A + B − ρ min(A, B))` is fitted for `ρ = ρ₀ + ρ₁ c + ρ₂ c²`, `c = cos Δφ`,
//!    by Gauss–Newton on the Monte-Carlo-weighted squared error with a weak prior
//!    `ρᵢ ~ N(0, 2²)`.
//!
//! Each part is then shrunk toward eq. 17 as far as a leave-one-out validation over the
//! realizations asks ([`fit_visibility_correction`]).

use glam::DVec3;
use smith_micro::correlated::{MAX_CORRELATION, MIN_CORRELATION};
use smith_micro::{LambdaCorrection, VisibilityCorrection, corrected_lambda, cos_azimuth_difference};

use crate::comparison::{attribute_s, slope_deviation};
use crate::correction_fit::{FIT_ANGLES_DEG, FIT_AZIMUTHS_DEG, FitError, FitSample, fit_to_samples, solve};
use crate::experiment::VisibleAverage;
use crate::heightfield::HeightField;
use crate::statistics::SurfaceStatistics;

/// View angles (degrees) of the correlation sweeps.
pub const CORRELATION_VIEW_ANGLES_DEG: [f64; 10] = [45.0, 55.0, 62.0, 68.0, 73.0, 77.0, 80.0, 83.0, 85.0, 87.0];

/// Lights of the correlation sweeps: (angle from the normal, azimuth difference to the
/// view), degrees.
pub const CORRELATION_LIGHTS_DEG: [(f64, f64); 8] =
    [(55.0, 0.0), (55.0, 45.0), (55.0, 90.0), (55.0, 135.0), (55.0, 180.0), (72.0, 0.0), (72.0, 90.0), (72.0, 180.0)];

/// Prior standard deviation of each `ρ` coefficient around 0.
const CORRELATION_PRIOR_DEVIATION: f64 = 2.0;
/// Floor on the Monte-Carlo standard error used as a weight.
const STANDARD_ERROR_FLOOR: f64 = 1e-3;
const GAUSS_NEWTON_ITERATIONS: usize = 10;

/// One ground-truth sample with both a view and a light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairSample {
    /// Smith's `Λ(v)` (eq. 6) from the measured slopes, as `smith-micro` evaluates it.
    pub lambda_view: f32,
    /// Smith's `Λ(l)`.
    pub lambda_light: f32,
    /// `cos Δφ` of the view and light azimuths.
    pub cos_azimuth_difference: f32,
    /// The ray-traced `E[s] − ā`.
    pub visible: f64,
    /// Its Monte-Carlo standard error.
    pub standard_error: f64,
}

/// The ground-truth samples the fit uses (see the module documentation).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct VisibilitySamples {
    /// View-only samples (`Λ(l) = 0`).
    pub view: Vec<FitSample>,
    /// Light samples at normal view (`Λ(v) = 0`), `lambda` = `Λ(l)`.
    pub light: Vec<FitSample>,
    /// Samples with both directions off the normal.
    pub pairs: Vec<PairSample>,
}

fn direction(theta_deg: f64, phi_deg: f64) -> DVec3 {
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    DVec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
}

/// Measures the samples of [`VisibilitySamples`] on `field`, `rays` rays per direction
/// pair, ray seeds from `seed`. `None` for degenerate statistics (slope deviations
/// `smith-micro` rejects).
pub fn collect_samples(field: &HeightField, rays: usize, seed: u64) -> Option<VisibilitySamples> {
    let stats = SurfaceStatistics::measure(field);
    let slopes = slope_deviation(&stats).ok()?;
    let mean = field.heights().iter().map(|&h| attribute_s(&stats, h)).sum::<f64>() / field.heights().len() as f64;
    let lambda = |d: DVec3| smith_micro::smith_lambda_direction(d.as_vec3(), slopes);
    let mut next_seed = seed;
    let mut measure = |view: DVec3, light: Option<DVec3>| {
        next_seed = next_seed.wrapping_add(1);
        VisibleAverage::new(field, rays, next_seed).mean_attribute(view, light, |h| attribute_s(&stats, h))
    };
    let mut samples = VisibilitySamples::default();
    for &azimuth in &FIT_AZIMUTHS_DEG {
        for &angle in &FIT_ANGLES_DEG {
            let d = direction(angle, azimuth);
            let l = f64::from(lambda(d)?);
            if let Some(e) = measure(d, None) {
                samples.view.push(FitSample { lambda: l, visible: e.mean - mean, standard_error: e.standard_error });
            }
            if let Some(e) = measure(DVec3::Z, Some(d)) {
                samples.light.push(FitSample { lambda: l, visible: e.mean - mean, standard_error: e.standard_error });
            }
        }
    }
    for (k, &(light_angle, difference)) in CORRELATION_LIGHTS_DEG.iter().enumerate() {
        let view_azimuth = 20.0 + 45.0 * k as f64;
        let light = direction(light_angle, view_azimuth + difference);
        for &angle in &CORRELATION_VIEW_ANGLES_DEG {
            let view = direction(angle, view_azimuth);
            let Some(e) = measure(view, Some(light)) else { continue };
            samples.pairs.push(PairSample {
                lambda_view: lambda(view)?,
                lambda_light: lambda(light)?,
                cos_azimuth_difference: cos_azimuth_difference(view.as_vec3(), light.as_vec3()),
                visible: e.mean - mean,
                standard_error: e.standard_error,
            });
        }
    }
    Some(samples)
}

/// Fits the correlation coefficients `(ρ₀, ρ₁, ρ₂)` to `pairs` with the tables `view`
/// and `light` fixed, or why not: no pair is usable ([`FitError::NoUsableSamples`]) or the
/// normal equations are singular ([`FitError::Singular`]).
pub fn fit_correlation(
    pairs: &[PairSample],
    view: &LambdaCorrection,
    light: &LambdaCorrection,
) -> Result<[f64; 3], FitError> {
    let usable: Vec<(f64, f64, f64, &PairSample)> = pairs
        .iter()
        .filter(|p| p.visible.is_finite() && p.standard_error.is_finite())
        .filter_map(|p| {
            let a = f64::from(corrected_lambda(p.lambda_view, view)?);
            let b = f64::from(corrected_lambda(p.lambda_light, light)?);
            (a.is_finite() && b.is_finite() && a.min(b) > 0.0).then_some((
                a + b,
                a.min(b),
                f64::from(p.cos_azimuth_difference),
                p,
            ))
        })
        .collect();
    if usable.is_empty() {
        return Err(FitError::NoUsableSamples);
    }
    let mut rho = [0.0_f64; 3];
    for _ in 0..GAUSS_NEWTON_ITERATIONS {
        let mut matrix = [[0.0_f64; 3]; 3];
        let mut gradient = [0.0_f64; 3];
        for &(sum, min, c, p) in &usable {
            let basis = [1.0, c, c * c];
            let r: f64 = basis.iter().zip(&rho).map(|(b, r)| b * r).sum();
            let clamped = r.clamp(f64::from(MIN_CORRELATION), f64::from(MAX_CORRELATION));
            let lambda = (sum - clamped * min).max(0.0);
            let model = lambda / (lambda + 2.0);
            // Where ρ is clamped the model does not depend on the coefficients: such a
            // sample (e.g. one that asks for ρ > 1) must not pull on ρ elsewhere.
            let slope = if clamped == r { -min * 2.0 / (lambda + 2.0).powi(2) } else { 0.0 };
            let weight = 1.0 / (p.standard_error.powi(2) + STANDARD_ERROR_FLOOR.powi(2));
            let residual = p.visible - model;
            for i in 0..3 {
                gradient[i] += weight * slope * basis[i] * residual;
                for j in 0..3 {
                    matrix[i][j] += weight * slope * slope * basis[i] * basis[j];
                }
            }
        }
        let ridge = 1.0 / CORRELATION_PRIOR_DEVIATION.powi(2);
        for i in 0..3 {
            matrix[i][i] += ridge;
            gradient[i] -= ridge * rho[i];
        }
        let step = solve(matrix, gradient).ok_or(FitError::Singular)?;
        for (r, d) in rho.iter_mut().zip(step) {
            *r = (*r + d).clamp(-8.0, 8.0);
        }
    }
    Ok(rho)
}

/// Shrinkage steps toward eq. 17 tried by the leave-one-out validation of
/// [`fit_visibility_correction`]: `c = 1 + α (c_fit − 1)`, `ρ = α ρ_fit`.
pub const SHRINKAGE_STEPS: [f64; 9] = [0.0, 0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875, 1.0];

/// Fits a [`VisibilityCorrection`] to the pooled samples of `fields` (independent
/// realizations of one material, of any sizes): `rays` rays per direction pair, ray
/// seeds from `seed`; or why not ([`FitError`]: degenerate statistics, flat fields, a
/// singular fit).
///
/// Each part of the model (view table, light table, correlation) is then shrunk toward
/// eq. 17 by the factor `α` of [`SHRINKAGE_STEPS`] that minimizes the worst held-out
/// error: with two fields or more, the model fitted without one realization predicts
/// that realization's samples (leave one out); with one field (a texture), the model
/// fitted on every other sample direction predicts the others, and the reverse. The
/// worst fold counts. Last, the whole model is shrunk by one common factor chosen the
/// same way on all samples together, whose candidates include `0`, eq. 17 itself: the
/// model returned is never worse than eq. 17 on the held-out samples. A material whose
/// realizations differ from each other more than from eq. 17 (realization noise, not
/// Monte-Carlo noise, which the weights already cover) so keeps eq. 17 where a
/// correction would not transfer.
pub fn fit_visibility_correction(
    fields: &[HeightField],
    rays: usize,
    seed: u64,
) -> Result<VisibilityCorrection, FitError> {
    let per_field: Vec<VisibilitySamples> = fields
        .iter()
        .enumerate()
        .map(|(i, field)| collect_samples(field, rays, seed.wrapping_add(10_000 * i as u64)))
        .collect::<Option<_>>()
        .ok_or(FitError::DegenerateSurface)?;
    let full = fit_samples(&pool(per_field.iter()))?;
    // One field: two folds of alternate sample directions.
    let fold_sets: Vec<VisibilitySamples> = if per_field.len() < 2 {
        per_field.first().map(halves).ok_or(FitError::NoUsableSamples)?.into()
    } else {
        per_field
    };
    let folds: Vec<(VisibilityCorrection, &VisibilitySamples)> = (0..fold_sets.len())
        .map(|held_out| {
            let rest = fold_sets.iter().enumerate().filter(|&(i, _)| i != held_out).map(|(_, s)| s);
            fit_samples(&pool(rest)).map(|model| (model, &fold_sets[held_out]))
        })
        .collect::<Result<_, _>>()?;
    // Each part in turn: the view table, the light table, then ρ with both tables shrunk.
    let mut alphas = [1.0_f64; 3];
    for part in 0..3 {
        let error = |alpha: f64| {
            let mut trial = alphas;
            trial[part] = alpha;
            // The worst fold: shrink until the correction helps every held-out realization.
            folds
                .iter()
                .map(|(model, held_out)| held_out_error(&shrink(model, trial).ok()?, held_out, part))
                .try_fold(0.0_f64, |worst, e| e.map(|e| worst.max(e)))
        };
        let best = SHRINKAGE_STEPS
            .iter()
            .filter_map(|&alpha| error(alpha).map(|e| (alpha, e)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .ok_or(FitError::NoUsableSamples)?;
        alphas[part] = best.0;
    }
    // The whole model, toward eq. 17 (α = 0) when the parts together do not transfer.
    let total_error = |alpha: f64| {
        let trial = alphas.map(|a| a * alpha);
        folds
            .iter()
            .map(|(model, held_out)| {
                let shrunk = shrink(model, trial).ok()?;
                (0..3).map(|part| held_out_error(&shrunk, held_out, part)).sum::<Option<f64>>()
            })
            .try_fold(0.0_f64, |worst, e| e.map(|e| worst.max(e)))
    };
    let common = SHRINKAGE_STEPS
        .iter()
        .filter_map(|&alpha| total_error(alpha).map(|e| (alpha, e)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .ok_or(FitError::NoUsableSamples)?
        .0;
    shrink(&full, alphas.map(|a| a * common))
}

/// `samples` split into two folds: every other sample direction of each kind.
fn halves(samples: &VisibilitySamples) -> [VisibilitySamples; 2] {
    fn split<T: Clone>(items: &[T]) -> [Vec<T>; 2] {
        let pick = |parity: usize| items.iter().skip(parity).step_by(2).cloned().collect();
        [pick(0), pick(1)]
    }
    let ([view_a, view_b], [light_a, light_b], [pairs_a, pairs_b]) =
        (split(&samples.view), split(&samples.light), split(&samples.pairs));
    [
        VisibilitySamples { view: view_a, light: light_a, pairs: pairs_a },
        VisibilitySamples { view: view_b, light: light_b, pairs: pairs_b },
    ]
}

/// The samples of `sets`, pooled.
fn pool<'a>(sets: impl Iterator<Item = &'a VisibilitySamples>) -> VisibilitySamples {
    let mut pooled = VisibilitySamples::default();
    for samples in sets {
        pooled.view.extend_from_slice(&samples.view);
        pooled.light.extend_from_slice(&samples.light);
        pooled.pairs.extend_from_slice(&samples.pairs);
    }
    pooled
}

/// `model` shrunk toward eq. 17 by `[α_view, α_light, α_ρ]` (valid for `α ∈ [0, 1]`:
/// each knot moves toward 1, each coefficient toward 0).
fn shrink(model: &VisibilityCorrection, alphas: [f64; 3]) -> Result<VisibilityCorrection, FitError> {
    let table = |table: LambdaCorrection, alpha: f64| {
        LambdaCorrection::from_knots(table.knots().map(|k| (1.0 + alpha * (f64::from(k) - 1.0)) as f32))
    };
    let rho = model.correlation_coefficients().map(|r| (alphas[2] * f64::from(r)) as f32);
    Ok(VisibilityCorrection::new(table(model.view(), alphas[0])?, table(model.light(), alphas[1])?, rho)?)
}

/// The sum of squared errors of `model` on one part of `samples` (0: view, 1: light,
/// 2: pairs), `None` where the model gives none.
fn held_out_error(model: &VisibilityCorrection, samples: &VisibilitySamples, part: usize) -> Option<f64> {
    let x = |lambda: f32| f64::from(lambda / (lambda + 2.0));
    let squared = |model: f64, truth: f64| (model - truth).powi(2);
    match part {
        0 => samples
            .view
            .iter()
            .map(|s| Some(squared(x(corrected_lambda(s.lambda as f32, &model.view())?), s.visible)))
            .sum(),
        1 => samples
            .light
            .iter()
            .map(|s| Some(squared(x(corrected_lambda(s.lambda as f32, &model.light())?), s.visible)))
            .sum(),
        _ => samples
            .pairs
            .iter()
            .map(|p| {
                let lambda =
                    smith_micro::correlated_lambda(p.lambda_view, p.lambda_light, p.cos_azimuth_difference, model)?;
                Some(squared(if lambda.is_finite() { x(lambda) } else { 1.0 }, p.visible))
            })
            .sum(),
    }
}

/// Fits a [`VisibilityCorrection`] to `samples` (see the module documentation), or why
/// not ([`fit_to_samples`], [`fit_correlation`]).
pub fn fit_samples(samples: &VisibilitySamples) -> Result<VisibilityCorrection, FitError> {
    let view = fit_to_samples(&samples.view)?;
    let light = fit_to_samples(&samples.light)?;
    let rho = fit_correlation(&samples.pairs, &view, &light)?;
    Ok(VisibilityCorrection::new(view, light, rho.map(|r| r as f32))?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_a_known_correlation() {
        let view = LambdaCorrection::from_knots([1.4, 1.35, 1.3, 1.25, 1.2, 1.15, 1.1, 1.05]).unwrap();
        let light = LambdaCorrection::from_knots([2.2, 2.0, 1.7, 1.5, 1.35, 1.25, 1.15, 1.1]).unwrap();
        let truth = VisibilityCorrection::new(view, light, [0.3, 0.95, -0.2]).unwrap();
        let mut pairs = Vec::new();
        for i in 0..60 {
            let (lambda_view, lambda_light) = (0.02 * 1.1_f32.powi(i), 0.05 + 0.01 * (i % 7) as f32);
            let cos = -1.0 + 2.0 * (i % 5) as f32 / 4.0;
            let lambda = smith_micro::correlated_lambda(lambda_view, lambda_light, cos, &truth).unwrap();
            let visible = f64::from(lambda / (lambda + 2.0));
            pairs.push(PairSample {
                lambda_view,
                lambda_light,
                cos_azimuth_difference: cos,
                visible,
                standard_error: 1e-3,
            });
        }
        let rho = fit_correlation(&pairs, &view, &light).unwrap();
        for (fitted, expected) in rho.iter().zip([0.3, 0.95, -0.2]) {
            assert!((fitted - expected).abs() < 0.02, "{rho:?}");
        }
        assert_eq!(fit_correlation(&[], &view, &light), Err(FitError::NoUsableSamples));
        // Pairs with a direction at the normal (min(A, B) = 0) say nothing about ρ.
        let at_normal: Vec<PairSample> = pairs.iter().map(|p| PairSample { lambda_light: 0.0, ..*p }).collect();
        assert_eq!(fit_correlation(&at_normal, &view, &light), Err(FitError::NoUsableSamples));
    }
}
