//! Regression thresholds for the Fig. 9 experiment (fixed seeds): eq. 17's maximum error
//! up to 85° on Gaussian and non-Gaussian surfaces, set just above what was measured
//! (printed by this test: 1.47 %, 0.58 %, 3.16 % on the Gaussian, fBm and band-pass
//! spectra; 3.64 % and 1.93 % on the cellular and ridged surfaces, with the Gaussian
//! fields synthesized over every lattice frequency), so that a change of
//! the model, the ground truth or the generators fails here; and MIP-mapping's error
//! (23-28 %) as a floor. `cargo xtask fig9` runs the full-size experiment.

use microsurface_truth::comparison::{Sweep, compare, max_errors};
use microsurface_truth::{Spectrum, generate_cellular, generate_gaussian, generate_ridged};

const ANGLES: [f64; 18] =
    [0.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 45.0, 50.0, 55.0, 60.0, 65.0, 70.0, 75.0, 80.0, 85.0];
const SIZE: usize = 384;
const RAYS: usize = 30_000;

/// Measured (eq. 17 max error, MIP max error) up to 85°, as fractions of the attribute
/// range, for each surface; and the thresholds asserted.
fn check(name: &str, field: &microsurface_truth::HeightField, eq17_limit: f64, mip_floor: f64) {
    let sweep = Sweep { angles_deg: &ANGLES, view_azimuth: 0.0, light: None, rays: RAYS, seed: 99 };
    let rows = compare(field, &sweep).expect("the surface is not flat");
    let (eq17, mip) = max_errors(&rows, 0.0, 85.0);
    println!("{name}: eq. 17 max error {:.3}%, MIP max error {:.3}%", 100.0 * eq17, 100.0 * mip);
    assert!(eq17 <= eq17_limit, "{name}: eq. 17 error {eq17} > {eq17_limit}");
    // MIP-mapping ignores view dependency: at 85° it is off by about a quarter of the range.
    assert!(mip >= mip_floor, "{name}: MIP error {mip} < {mip_floor}: the ground truth lost its view dependency");
    assert!(eq17 < mip / 5.0, "{name}: eq. 17 ({eq17}) is not much better than MIP ({mip})");
}

#[test]
fn gaussian_surfaces() {
    let gaussian = generate_gaussian(SIZE, Spectrum::Gaussian { wavelength: 12.0 }, 0.5, 1).unwrap();
    check("gaussian_correlation", &gaussian, 0.0155, 0.2);
    let fbm = generate_gaussian(
        SIZE,
        Spectrum::PowerLaw { min_wavelength: 6.0, max_wavelength: 96.0, exponent: 3.0 },
        0.5,
        2,
    )
    .unwrap();
    check("fbm_power_law", &fbm, 0.0062, 0.2);
    let band = generate_gaussian(SIZE, Spectrum::BandPass { wavelength: 16.0, width: 0.1 }, 0.5, 3).unwrap();
    check("band_pass", &band, 0.0330, 0.2);
}

#[test]
fn non_gaussian_surfaces() {
    check("cellular", &generate_cellular(SIZE, SIZE / 8, 0.5, 4).unwrap(), 0.039, 0.2);
    check("ridged", &generate_ridged(SIZE, 12.0, 0.5, 5).unwrap(), 0.0205, 0.2);
}
