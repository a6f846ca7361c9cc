//! Our SSIM against scikit-image's on the committed fixtures (`tests/fixtures/`, made and
//! measured once by `make_fixtures.py` with scikit-image 0.26.0).
//!
//! # Tolerance: 1e-9, absolute, on the mean and on every map sample
//!
//! Both sides compute in `f64` with the same formulas in the same order (Rec. 709 luma
//! left to right, scipy's kernel and symmetric correlation loop, columns then rows,
//! scikit-image's eq. 13 expression, numpy's pairwise sum of the crop). What may differ:
//! `exp` in the kernel weights (at most an ulp or two between libms, `gaussian.rs` checks
//! ≤ 2 ulp), and numpy's choice of summation order for the mean where it differs from
//! the plain pairwise sum we mirror. The filtered means and second moments
//! are sums of non-negative terms, so they carry a relative error of ~10 ε ≈ 2e-15; the
//! variances `E[x²] − E[x]²` lose it to cancellation as an absolute error of at most
//! ~255² · 10 ε ≈ 1.5e-10, which enters eq. 13 next to `C2 = (0.03 · 255)² ≈ 58.5`: a
//! relative error of ~3e-12 in each factor, so |ΔSSIM| ≲ 1e-11 per pixel and for the mean.
//! 1e-9 leaves a margin of 100 over that bound and is still 10⁵ times smaller than what a
//! wrong window, boundary mode, crop or constant changes here (≥ 1e-4 on these images;
//! the border samples move by 0.07 with `mode='nearest'` instead of `'reflect'`).
//! Observed on x86-64 Linux: every mean and map sample bit-identical to scikit-image's.
//!
//! The cropped mean never reads past the border (every window it averages is centred at
//! least 5 px inside), so the boundary mode is tested by the map samples alone; most of
//! them lie within 5 px of the border.

use std::path::{Path, PathBuf};

use image_metrics::{Ssim, ssim};

const TOLERANCE: f64 = 1e-9;

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures")
}

fn load(name: &str) -> image::RgbaImage {
    let path = fixtures().join(format!("{name}.png"));
    image::open(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display())).into_rgba8()
}

/// The CSV's data rows (comment and header lines skipped), split at commas.
fn rows(file: &str) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(fixtures().join(file)).expect(file);
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.is_empty())
        .skip(1)
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect()
}

fn measure(reference: &str, test: &str) -> Ssim {
    ssim(&load(reference), &load(test)).expect("the fixtures have the same size")
}

#[test]
fn fixtures_are_what_the_script_describes() {
    for name in ["a", "b", "c"] {
        let image = load(name);
        assert_eq!(image.dimensions(), (64, 48), "{name}.png");
        let bytes = std::fs::metadata(fixtures().join(format!("{name}.png"))).unwrap().len();
        assert!(bytes < 10_000, "{name}.png is {bytes} bytes: keep the fixtures small");
    }
}

#[test]
fn mean_ssim_equals_scikit_images() {
    let references = rows("ssim_reference.csv");
    assert!(references.len() >= 4, "identical, two distorted pairs and one more");
    for row in &references {
        let [reference, test, value] = &row[..] else { panic!("bad row {row:?}") };
        let expected: f64 = value.parse().unwrap();
        let ours = measure(reference, test).mean;
        let difference = ours - expected;
        eprintln!("SSIM({reference}, {test}): ours {ours:?}, scikit-image {expected:?}, difference {difference:e}");
        assert!(difference.abs() <= TOLERANCE, "SSIM({reference}, {test}) = {ours}, scikit-image says {expected}");
        if reference == test {
            assert_eq!(ours, 1.0);
        }
    }
}

#[test]
fn ssim_map_equals_scikit_images_border_included() {
    let samples = rows("ssim_map_samples.csv");
    assert!(samples.len() >= 200);
    let mut border = 0;
    let mut worst: f64 = 0.0;
    let mut maps = std::collections::BTreeMap::new();
    for row in &samples {
        let [reference, test, x, y, value] = &row[..] else { panic!("bad row {row:?}") };
        let map = &maps.entry((reference.clone(), test.clone())).or_insert_with(|| measure(reference, test)).map;
        let (x, y): (u32, u32) = (x.parse().unwrap(), y.parse().unwrap());
        let expected: f64 = value.parse().unwrap();
        let ours = map.get_pixel(x, y)[0];
        assert!(
            (ours - expected).abs() <= TOLERANCE,
            "SSIM map of ({reference}, {test}) at ({x}, {y}): ours {ours}, scikit-image {expected}"
        );
        worst = worst.max((ours - expected).abs());
        // Pixels whose window leaves the image: there the boundary mode decides the value.
        if x < 5 || y < 5 || x > 58 || y > 42 {
            border += 1;
        }
    }
    eprintln!("{} map samples ({border} on the border), largest difference {worst:e}", samples.len());
    assert!(border >= 100, "the samples cover the border: {border}");
}
