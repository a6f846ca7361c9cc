//! Regression thresholds for the corrected visibility model (`smith-micro`'s
//! `LambdaCorrection`, fitted by `fit_lambda_correction`), validated honestly: the
//! correction is fitted on one realization (seed A) of each surface and evaluated on an
//! independent realization (seed B) of the same generator, on a view-only sweep (azimuth
//! 0°, the fit used 45° and 135°) and a view-and-light sweep (light 60°, azimuth 90°)
//! that the fit never saw. Thresholds are set just above what was measured (printed by
//! this test), so that a change of the model, the fit or the ground truth fails here.
//!
//! Measured (max error 0–85°, fractions of the attribute range; eq. 17 → corrected):
//! Gaussian ℓ = 12: view 2.49 % → 0.30 %, light 2.74 % → 0.98 %; fBm: view 0.79 % →
//! 0.93 % (worse: the fit on seed A does not transfer), light 0.80 % → 0.74 %; band-pass:
//! view 2.88 % → 0.50 %, light 3.21 % → 1.23 %; cellular: view 2.08 % → 0.53 %, light
//! 1.58 % → 0.81 %; ridged: view 3.62 % → 0.91 %, light 4.03 % → 1.07 %. The ≤ 0.5 %
//! goal is met only on view-only sweeps of the Gaussian-correlation surface (and at the
//! limit on band-pass); the view-and-light sweeps stay near 1 %.
//! `cargo xtask fig9` runs the full-size experiment.

use microsurface_truth::comparison::{AngleComparison, Sweep, compare_corrected, max_error};
use microsurface_truth::{
    HeightField, Spectrum, fit_lambda_correction, generate_cellular, generate_gaussian, generate_ridged,
};

const ANGLES: [f64; 18] =
    [0.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 45.0, 50.0, 55.0, 60.0, 65.0, 70.0, 75.0, 80.0, 85.0];
const SIZE: usize = 384;
const RAYS: usize = 30_000;

/// The largest errors up to 85° of eq. 17 and of the corrected model (on the sum of the
/// Λs) on the view-only and the view-and-light sweeps of `evaluation`, with a correction
/// fitted on `fitting`: `[eq17 view, corrected view, eq17 light, corrected light]`.
fn measure(name: &str, fitting: &HeightField, evaluation: &HeightField) -> [f64; 4] {
    let correction = fit_lambda_correction(fitting, RAYS, 41).expect("the surface is not flat");
    let t = 60_f64.to_radians();
    let light = glam::DVec3::new(0.0, t.sin(), t.cos());
    let view_sweep = Sweep { angles_deg: &ANGLES, view_azimuth: 0.0, light: None, rays: RAYS, seed: 99 };
    let light_sweep = Sweep { angles_deg: &ANGLES, view_azimuth: 0.0, light: Some(light), rays: RAYS, seed: 98 };
    let view = compare_corrected(evaluation, &view_sweep, &correction).expect("the surface is not flat");
    let lit = compare_corrected(evaluation, &light_sweep, &correction).expect("the surface is not flat");
    let max = |rows: &[AngleComparison], error: fn(&AngleComparison) -> f64| max_error(rows, 0.0, 85.0, error);
    let errors = [
        max(&view, AngleComparison::eq17_error),
        max(&view, AngleComparison::corrected_error),
        max(&lit, AngleComparison::eq17_error),
        max(&lit, AngleComparison::corrected_error),
    ];
    println!(
        "{name}: knots {:?}; max error 0-85°: view eq. 17 {:.3}%, corrected {:.3}%; light eq. 17 {:.3}%, corrected {:.3}% (per direction {:.3}%)",
        correction.knots(),
        100.0 * errors[0],
        100.0 * errors[1],
        100.0 * errors[2],
        100.0 * errors[3],
        100.0 * max(&lit, AngleComparison::corrected_per_direction_error),
    );
    errors
}

fn gaussian(spectrum: Spectrum, seed: u64) -> HeightField {
    generate_gaussian(SIZE, spectrum, 0.5, seed).expect("valid generator settings")
}

#[test]
fn corrected_model_on_gaussian_surfaces() {
    let spectra = [
        ("gaussian_correlation", Spectrum::Gaussian { wavelength: 12.0 }),
        ("fbm_power_law", Spectrum::PowerLaw { min_wavelength: 6.0, max_wavelength: 96.0, exponent: 3.0 }),
        ("band_pass", Spectrum::BandPass { wavelength: 16.0, width: 0.1 }),
    ];
    // (surface, limit on the corrected view-only error, on the corrected view+light error)
    let limits = [0.0032, 0.0100, 0.0095, 0.0075, 0.0052, 0.0125];
    for ((name, spectrum), limit) in spectra.into_iter().zip(limits.chunks_exact(2)) {
        let errors = measure(name, &gaussian(spectrum, 101), &gaussian(spectrum, 202));
        assert!(errors[1] <= limit[0], "{name}: corrected view error {} > {}", errors[1], limit[0]);
        assert!(errors[3] <= limit[1], "{name}: corrected light error {} > {}", errors[3], limit[1]);
    }
}

#[test]
fn corrected_model_on_non_gaussian_surfaces() {
    let cellular = |seed| generate_cellular(SIZE, SIZE / 8, 0.5, seed).expect("valid generator settings");
    let ridged = |seed| generate_ridged(SIZE, 12.0, 0.5, seed).expect("valid generator settings");
    for (name, errors, limits) in [
        ("cellular", measure("cellular", &cellular(104), &cellular(204)), [0.0055, 0.0083]),
        ("ridged", measure("ridged", &ridged(105), &ridged(205)), [0.0093, 0.0109]),
    ] {
        assert!(errors[1] <= limits[0], "{name}: corrected view error {} > {}", errors[1], limits[0]);
        assert!(errors[3] <= limits[1], "{name}: corrected light error {} > {}", errors[3], limits[1]);
        // Not made worse: the correction fitted on another realization helps here.
        assert!(errors[1] < errors[0] && errors[3] < errors[2], "{name}: the correction made eq. 17 worse: {errors:?}");
    }
}
