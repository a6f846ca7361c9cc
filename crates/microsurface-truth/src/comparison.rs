//! Fig. 9 of the paper, measured: ground truth against eq. 17 and MIP-mapping over view
//! angles, for one height field.
//!
//! The attribute is `a(h) = s(h) = 2g(h) − 1` (H5bis, `g` of eq. 5 with the measured `σ_h`
//! about the measured mean height). Any channel `a_c(h) = b_c + k_c s(h)` is an affine
//! image of it, so errors expressed as a fraction of the attribute's range (`2|k_c|`) are
//! the same for every channel: `|Δ E[s]| / 2`.
//!
//! The stored parameters are computed as the paper's pre-computation does (§5.2):
//! `ā = mean(a)`, `a_s = ∫ s·a / ∫ s²` (here exactly 1), so eq. 17 predicts
//! `E[s] = ā + a_s Λ/(Λ + 2)` with `Λ = Λ(v) + Λ(l)`, and MIP-mapping predicts `ā`.
//! [`compare_corrected`] adds eq. 17 with a per-material [`LambdaCorrection`] (applied to
//! the sum, and per direction), e.g. one fitted by
//! [`crate::fit_lambda_correction`] on another realization of the surface.

use glam::{DVec3, Vec3};
use smith_micro::{
    CubicLambdaCorrection, HeightCorrelatedAttribute, LambdaCorrection, SlopeDeviation, SlopeDeviationError,
    VisibilityCorrection,
};

use crate::experiment::VisibleAverage;
use crate::heightfield::HeightField;
use crate::statistics::SurfaceStatistics;

/// One view angle of the comparison.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AngleComparison {
    /// Angle between the view direction and the mean normal, degrees.
    pub view_angle_deg: f64,
    /// Ground truth `E[s]` over visible (and lit) points.
    pub truth: f64,
    /// Monte-Carlo standard error of `truth`.
    pub truth_standard_error: f64,
    /// Eq. 17 as published.
    pub eq17: f64,
    /// Plain MIP-mapping: the constant mean attribute.
    pub mip: f64,
    /// Eq. 17 with the corrected sum `Λ' = c(u) (Λ(v) + Λ(l))`
    /// (`smith_micro::corrected_visible_mean_attribute`); eq. 17 for the identity.
    pub corrected: f64,
    /// Eq. 17 with each direction's Λ corrected, `Λ' = c(u_v) Λ(v) + c(u_l) Λ(l)`.
    pub corrected_per_direction: f64,
    /// The corrected visibility model with separate view and light tables and the
    /// light–view correlation term (`smith_micro::correlated_visible_mean_attribute`).
    pub correlated: f64,
    /// `Λ(v) + Λ(l)` from the measured slope deviations.
    pub lambda: f64,
}

impl AngleComparison {
    /// Eq. 17's error as a fraction of the attribute range.
    pub fn eq17_error(&self) -> f64 {
        (self.eq17 - self.truth).abs() / 2.0
    }

    /// MIP-mapping's error as a fraction of the attribute range.
    pub fn mip_error(&self) -> f64 {
        (self.mip - self.truth).abs() / 2.0
    }

    /// The corrected model's error (correction on the sum) as a fraction of the range.
    pub fn corrected_error(&self) -> f64 {
        (self.corrected - self.truth).abs() / 2.0
    }

    /// The correlated model's error as a fraction of the range.
    pub fn correlated_error(&self) -> f64 {
        (self.correlated - self.truth).abs() / 2.0
    }

    /// The error of the correction applied per direction, as a fraction of the range.
    pub fn corrected_per_direction_error(&self) -> f64 {
        (self.corrected_per_direction - self.truth).abs() / 2.0
    }

    /// Eq. 17 with this row's `Λ(v) + Λ(l)` corrected by the cubic `correction`
    /// (`smith_micro::cubic_corrected_visible_mean_attribute`, the attribute `s` with its
    /// mean as in the other models); `None` where the row's Λ or mean is not a valid input
    /// (negative or NaN Λ, a mean `smith_micro::HeightCorrelatedAttribute::new` rejects).
    pub fn cubic_corrected(&self, correction: &CubicLambdaCorrection) -> Option<f64> {
        let stored = HeightCorrelatedAttribute::new(self.mip as f32, 1.0).ok()?;
        smith_micro::cubic_corrected_visible_mean_attribute(stored, self.lambda as f32, 0.0, correction).map(f64::from)
    }

    /// The cubic correction's error as a fraction of the range (1, the largest possible,
    /// where [`AngleComparison::cubic_corrected`] has no value).
    pub fn cubic_error(&self, correction: &CubicLambdaCorrection) -> f64 {
        self.cubic_corrected(correction).map_or(1.0, |value| (value - self.truth).abs() / 2.0)
    }
}

/// Every degree of view angle from 0° to 89°: the sweeps of Fig. 9 and of the Smith-model
/// selector.
pub const EVERY_DEGREE: [f64; 90] = {
    let mut a = [0.0; 90];
    let mut i = 0;
    while i < 90 {
        a[i] = i as f64;
        i += 1;
    }
    a
};

/// The light of a view-and-light sweep: 60° from the mean normal, `azimuth_deg` from the
/// view's azimuth (0).
pub fn light_at_60_deg(azimuth_deg: f64) -> DVec3 {
    let (t, p) = (60_f64.to_radians(), azimuth_deg.to_radians());
    DVec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
}

/// Settings of one sweep.
#[derive(Clone, Copy, Debug)]
pub struct Sweep {
    /// View angles, degrees.
    pub angles_deg: &'static [f64],
    /// View azimuth, radians.
    pub view_azimuth: f64,
    /// Light direction (toward the light); `None` for view-dependency only (Fig. 9).
    pub light: Option<DVec3>,
    /// Rays per angle.
    pub rays: usize,
    /// Seed of the ray positions.
    pub seed: u64,
}

/// `s(h) = 2g(h) − 1` about the measured mean height (eq. 5 and H5bis).
pub fn attribute_s(stats: &SurfaceStatistics, height: f64) -> f64 {
    let h = (height - stats.mean_height) as f32;
    smith_micro::height_cdf(h, stats.height_sigma as f32).map_or(0.0, |g| 2.0 * f64::from(g) - 1.0)
}

/// The measured slope deviations as `smith-micro` takes them, or why they are not valid.
pub fn slope_deviation(stats: &SurfaceStatistics) -> Result<SlopeDeviation, SlopeDeviationError> {
    SlopeDeviation::new(stats.slope_sigma.x as f32, stats.slope_sigma.y as f32)
}

/// The attribute `s` as a voxel stores it (§5.2): its mean over the field's heights (in
/// f64, then as stored) — `ā`, and `a_s` = 1 since the projection `∫ s·a / ∫ s²` of `a = s`
/// is exactly 1. `None` for a mean `HeightCorrelatedAttribute::new` rejects.
pub fn stored_attribute(field: &HeightField, stats: &SurfaceStatistics) -> Option<(f64, HeightCorrelatedAttribute)> {
    let mean = field.heights().iter().map(|&h| attribute_s(stats, h)).sum::<f64>() / field.heights().len() as f64;
    Some((mean, HeightCorrelatedAttribute::new(mean as f32, 1.0).ok()?))
}

/// Runs `sweep` on `field`: ground truth, eq. 17 and MIP-mapping at every angle (the
/// corrected columns equal eq. 17). Returns `None` when the statistics are degenerate (a
/// flat field).
pub fn compare(field: &HeightField, sweep: &Sweep) -> Option<Vec<AngleComparison>> {
    compare_corrected(field, sweep, &LambdaCorrection::IDENTITY)
}

/// [`compare`] with eq. 17 also evaluated with `correction` (on the sum of the Λs and per
/// direction). Returns `None` when the statistics are degenerate.
pub fn compare_corrected(
    field: &HeightField,
    sweep: &Sweep,
    correction: &LambdaCorrection,
) -> Option<Vec<AngleComparison>> {
    compare_models(field, sweep, correction, &VisibilityCorrection::IDENTITY)
}

/// [`compare_corrected`] with the correlated model `visibility` evaluated as well (its
/// column equals eq. 17 for [`VisibilityCorrection::IDENTITY`]). Returns `None` when the
/// statistics are degenerate (slope deviations or a mean attribute `smith-micro` rejects,
/// a sweep without result).
pub fn compare_models(
    field: &HeightField,
    sweep: &Sweep,
    correction: &LambdaCorrection,
    visibility: &VisibilityCorrection,
) -> Option<Vec<AngleComparison>> {
    let stats = SurfaceStatistics::measure(field);
    let slopes = slope_deviation(&stats).ok()?;
    let (mean, stored) = stored_attribute(field, &stats)?;
    let lambda_light = match sweep.light {
        Some(l) => smith_micro::smith_lambda_direction(l.as_vec3(), slopes)?,
        None => 0.0,
    };
    let truth = VisibleAverage::new(field, sweep.rays, sweep.seed);
    let mut rows = Vec::with_capacity(sweep.angles_deg.len());
    for &angle in sweep.angles_deg {
        let (theta, phi) = (angle.to_radians(), sweep.view_azimuth);
        let view = DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
        let lambda_view =
            smith_micro::smith_lambda_direction(Vec3::new(view.x as f32, view.y as f32, view.z as f32), slopes)?;
        let eq17 = smith_micro::visible_mean_attribute(stored, lambda_view, lambda_light)?;
        let corrected = smith_micro::corrected_visible_mean_attribute(stored, lambda_view, lambda_light, correction)?;
        let corrected_per_direction = smith_micro::visible_mean_attribute(
            stored,
            smith_micro::corrected_lambda(lambda_view, correction)?,
            smith_micro::corrected_lambda(lambda_light, correction)?,
        )?;
        let light_direction = sweep.light.map_or(Vec3::Z, |l| l.as_vec3());
        let cos = smith_micro::cos_azimuth_difference(view.as_vec3(), light_direction);
        let correlated =
            smith_micro::correlated_visible_mean_attribute(stored, lambda_view, lambda_light, cos, visibility)?;
        let estimate = truth.mean_attribute(view, sweep.light, |h| attribute_s(&stats, h))?;
        rows.push(AngleComparison {
            view_angle_deg: angle,
            truth: estimate.mean,
            truth_standard_error: estimate.standard_error,
            eq17: f64::from(eq17),
            mip: mean,
            corrected: f64::from(corrected),
            corrected_per_direction: f64::from(corrected_per_direction),
            correlated: f64::from(correlated),
            lambda: f64::from(lambda_view + lambda_light),
        });
    }
    Some(rows)
}

/// The largest eq. 17 and MIP errors (fractions of the range) over rows with
/// `view_angle_deg` in `[low, high]`.
pub fn max_errors(rows: &[AngleComparison], low: f64, high: f64) -> (f64, f64) {
    rows.iter()
        .filter(|r| (low..=high).contains(&r.view_angle_deg))
        .fold((0.0, 0.0), |(e, m), r| (e.max(r.eq17_error()), m.max(r.mip_error())))
}

/// The largest `error(row)` over rows with `view_angle_deg` in `[low, high]` (0 for none),
/// e.g. `max_error(&rows, 70.0, 85.0, AngleComparison::corrected_error)`.
pub fn max_error(rows: &[AngleComparison], low: f64, high: f64, error: impl Fn(&AngleComparison) -> f64) -> f64 {
    rows.iter().filter(|r| (low..=high).contains(&r.view_angle_deg)).map(error).fold(0.0, f64::max)
}
