//! Regression thresholds for the corrected visibility model (`smith-micro`'s
//! `VisibilityCorrection`: view table, light table and light–view correlation term,
//! fitted by `fit_visibility_correction`), validated honestly: the model is fitted on two
//! realizations of each Gaussian surface's generator (seeds A₁, A₂) and evaluated on a
//! third, independent one (seed B), on a view-only sweep (azimuth 0°) and a
//! view-and-light sweep (light 60°, azimuth 90°), 0–85°. The fit never sees seed B, nor
//! these sweeps' rays. Non-Gaussian surfaces (textures) are fitted on their own height
//! map, with other rays, azimuths and lights (see `corrected_model_on_non_gaussian_surfaces`).
//!
//! Two more view-and-light sweeps, with the light at the view's azimuth and opposite
//! (20 000 rays per angle), assert only that the corrected model beats eq. 17 there
//! (measured, eq. 17 → corrected, 0° / 180°: Gaussian 2.267 → 0.890 / 4.056 → 1.287 %;
//! fBm 1.186 → 0.548 / 1.920 → 1.116 %; band-pass 2.460 → 0.831 / 3.574 → 1.423 %;
//! cellular 1.148 → 0.441 / 3.612 → 3.266 %; ridged 2.351 → 0.916 / 6.043 → 1.834 %).
//!
//! Thresholds are set just above what was measured (printed by this test), so that a
//! change of the model, the fit or the ground truth fails here. At this size (512², 40 000
//! rays per angle) the Monte-Carlo standard error of one angle is 0.13–0.19 % of the
//! attribute range (printed), so about 0.3 % of each maximum is noise; `cargo xtask fig9`
//! measures at 1024² with 200 000 rays.
//!
//! Measured values: see `LIMITS` below.

use microsurface_truth::comparison::{AngleComparison, Sweep, compare_models, max_error};
use microsurface_truth::{
    CUBIC_DEVIATION_BUDGET, CubicLambdaCorrection, HeightField, LambdaCorrection, Spectrum, fit_visibility_correction,
    generate_cellular, generate_gaussian, generate_ridged,
};

const ANGLES: [f64; 18] =
    [0.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 45.0, 50.0, 55.0, 60.0, 65.0, 70.0, 75.0, 80.0, 85.0];
const SIZE: usize = 512;
/// Rays per direction pair of the fit, on each of the two fitting realizations.
const FIT_RAYS: usize = 10_000;
/// Rays per angle of the evaluation sweeps.
const RAYS: usize = 40_000;

/// Rays per angle of the two sweeps with the light at the view's azimuth and opposite.
const AZIMUTH_RAYS: usize = 20_000;

/// The largest errors up to 85° on the view-only and the view-and-light sweeps of
/// `evaluation`, with the model fitted on `fitting`:
/// `[eq17 view, corrected view, eq17 light, corrected light, eq17 and corrected with the
/// light at the view's azimuth, eq17 and corrected with the light opposite, cubic view,
/// the cubic's deviation from the table]`, the cubic being the one through the view table
/// (`CubicLambdaCorrection::fit_to_table`).
fn measure(name: &str, fitting: &[HeightField], evaluation: &HeightField) -> [f64; 10] {
    let model = fit_visibility_correction(fitting, FIT_RAYS, 41).expect("the surfaces are not flat");
    let t = 60_f64.to_radians();
    let light = glam::DVec3::new(0.0, t.sin(), t.cos());
    let view_sweep = Sweep { angles_deg: &ANGLES, view_azimuth: 0.0, light: None, rays: RAYS, seed: 99 };
    let light_sweep = Sweep { angles_deg: &ANGLES, view_azimuth: 0.0, light: Some(light), rays: RAYS, seed: 98 };
    let identity = LambdaCorrection::IDENTITY;
    let view = compare_models(evaluation, &view_sweep, &identity, &model).expect("the surface is not flat");
    let lit = compare_models(evaluation, &light_sweep, &identity, &model).expect("the surface is not flat");
    let azimuth_sweep = |x: f64, seed: u64| {
        let light = glam::DVec3::new(x * t.sin(), 0.0, t.cos());
        let sweep = Sweep { angles_deg: &ANGLES, view_azimuth: 0.0, light: Some(light), rays: AZIMUTH_RAYS, seed };
        compare_models(evaluation, &sweep, &identity, &model).expect("the surface is not flat")
    };
    let (same, opposite) = (azimuth_sweep(1.0, 97), azimuth_sweep(-1.0, 96));
    let max = |rows: &[AngleComparison], error: fn(&AngleComparison) -> f64| max_error(rows, 0.0, 85.0, error);
    let standard_error = |rows: &[AngleComparison]| max(rows, |r| r.truth_standard_error / 2.0);
    let cubic = CubicLambdaCorrection::fit_to_table(&model.view()).expect("the cubic stays in range");
    let errors = [
        max(&view, AngleComparison::eq17_error),
        max(&view, AngleComparison::correlated_error),
        max(&lit, AngleComparison::eq17_error),
        max(&lit, AngleComparison::correlated_error),
        max(&same, AngleComparison::eq17_error),
        max(&same, AngleComparison::correlated_error),
        max(&opposite, AngleComparison::eq17_error),
        max(&opposite, AngleComparison::correlated_error),
        max_error(&view, 0.0, 85.0, |row| row.cubic_error(&cubic)),
        f64::from(cubic.deviation_from(&model.view())),
    ];
    println!(
        "{name}: view {:?}, light {:?}, rho {:?}\n  max error 0-85°: view eq. 17 {:.3}%, corrected {:.3}%; \
         light eq. 17 {:.3}%, corrected {:.3}% (standard error per angle ≤ {:.3}%, {:.3}%); \
         light at 0°: eq. 17 {:.3}%, corrected {:.3}%; at 180°: eq. 17 {:.3}%, corrected {:.3}%; \
         view, cubic {:?}: {:.3}% (deviates {:.3}% from the table)",
        model.view().knots(),
        model.light().knots(),
        model.correlation_coefficients(),
        100.0 * errors[0],
        100.0 * errors[1],
        100.0 * errors[2],
        100.0 * errors[3],
        100.0 * standard_error(&view),
        100.0 * standard_error(&lit),
        100.0 * errors[4],
        100.0 * errors[5],
        100.0 * errors[6],
        100.0 * errors[7],
        cubic.coefficients(),
        100.0 * errors[8],
        100.0 * errors[9],
    );
    errors
}

/// Asserts the corrected model's errors against `limits` (view, light, cubic view) and
/// that it is not worse than eq. 17 on any of the four sweeps, nor the cubic on the view.
fn check(name: &str, errors: [f64; 10], limits: [f64; 3]) {
    assert!(errors[8] <= limits[2], "{name}: cubic view error {} > {}", errors[8], limits[2]);
    assert!(errors[8] < errors[0], "{name}: the cubic is worse than eq. 17 (view): {errors:?}");
    assert!(errors[1] <= limits[0], "{name}: corrected view error {} > {}", errors[1], limits[0]);
    assert!(errors[3] <= limits[1], "{name}: corrected light error {} > {}", errors[3], limits[1]);
    assert!(errors[1] < errors[0], "{name}: the corrected model is worse than eq. 17 (view): {errors:?}");
    assert!(errors[3] < errors[2], "{name}: the corrected model is worse than eq. 17 (light): {errors:?}");
    assert!(errors[5] < errors[4], "{name}: the corrected model is worse than eq. 17 (light at 0°): {errors:?}");
    assert!(errors[7] < errors[6], "{name}: the corrected model is worse than eq. 17 (light at 180°): {errors:?}");
}

#[test]
fn corrected_model_on_gaussian_surfaces() {
    let spectra = [
        ("gaussian_correlation", Spectrum::Gaussian { wavelength: 12.0 }, LIMITS[0]),
        ("fbm_power_law", Spectrum::PowerLaw { min_wavelength: 6.0, max_wavelength: 96.0, exponent: 3.0 }, LIMITS[1]),
        ("band_pass", Spectrum::BandPass { wavelength: 16.0, width: 0.1 }, LIMITS[2]),
    ];
    for (name, spectrum, limits) in spectra {
        let field = |seed| generate_gaussian(SIZE, spectrum, 0.5, seed).expect("valid generator settings");
        let errors = measure(name, &[field(101), field(102)], &field(202));
        check(name, errors, limits);
        // The cubic replaces the table on Gaussian surfaces (measured deviations 0.159,
        // 0.100, 0.222 %; the textures' 0.252 and 0.464 % keep their tables).
        assert!(errors[9] <= f64::from(CUBIC_DEVIATION_BUDGET), "{name}: {errors:?}");
    }
}

/// A non-Gaussian surface is a texture, not a statistical process: its model is fitted
/// on the height map it is used with (as a renderer's pre-computation would), with rays,
/// azimuths (45°, 135°) and lights other than those of the evaluation sweeps.
#[test]
fn corrected_model_on_non_gaussian_surfaces() {
    let cellular = generate_cellular(SIZE, SIZE / 8, 0.5, 204).expect("valid generator settings");
    let ridged = generate_ridged(SIZE, 12.0, 0.5, 205).expect("valid generator settings");
    check("cellular", measure("cellular", std::slice::from_ref(&cellular), &cellular), LIMITS[3]);
    check("ridged", measure("ridged", std::slice::from_ref(&ridged), &ridged), LIMITS[4]);
}

/// Limits on the corrected model's max error 0–85° (view only, view and light, cubic) for the
/// Gaussian-correlation, fBm, band-pass, cellular and ridged surfaces, just above the
/// measured values (fractions of the attribute range; eq. 17 → corrected, measured):
/// Gaussian ℓ = 12: view 2.400 % → 0.409 %, light 2.662 % → 0.689 %; fBm: view 0.480 % →
/// 0.389 %, light 0.510 % → 0.345 %; band-pass: view 3.286 % → 0.227 %, light 3.045 % →
/// 0.648 %; cellular (own map): view 0.392 % → 0.338 %, light 1.586 % → 0.589 %; ridged
/// (own map): view 3.052 % → 0.276 %, light 3.561 % → 0.846 % (with `ρ` clamped to
/// `[−2, 2]`; the cellular light sweep was 0.508 % with `[−2, 1]`, which made the
/// cellular texture worse than eq. 17 at `Δφ = 180°` on `cargo xtask fig9`). The ≤ 0.5 %
/// goal is met on every view-only sweep and on the fBm view-and-light sweep; the other
/// view-and-light sweeps miss it at this size (0.59–0.85 %). Third: the least-squares
/// cubic through the fitted view table, view only (measured 0.343, 0.304, 0.228, 0.337,
/// 0.370 %).
const LIMITS: [[f64; 3]; 5] = [
    [0.0045, 0.0072, 0.0037],
    [0.0043, 0.0038, 0.0033],
    [0.0026, 0.0069, 0.0026],
    [0.0038, 0.0062, 0.0037],
    [0.0031, 0.0089, 0.0040],
];
