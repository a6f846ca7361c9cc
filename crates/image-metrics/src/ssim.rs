//! The SSIM index of Wang, Bovik, Sheikh & Simoncelli, *Image Quality Assessment: From
//! Error Visibility to Structural Similarity* (IEEE TIP 13(4), 2004), computed exactly as
//! scikit-image's `structural_similarity(x, y, gaussian_weights=True, sigma=1.5,
//! use_sample_covariance=False, data_range=255)` computes it.

use image::{ImageBuffer, Luma, RgbaImage};

use crate::error::{MetricError, check_sizes};
use crate::gaussian::{SSIM_WINDOW_RADIUS, gaussian_filter, pairwise_sum};
use crate::luma::rec709_luma;

/// `K1` of eq. 7 (`C1 = (K1 L)²`), as in the paper and scikit-image.
pub const SSIM_K1: f64 = 0.01;

/// `K2` of `C2 = (K2 L)²` (§III-B, after eq. 9), as in the paper and scikit-image.
pub const SSIM_K2: f64 = 0.03;

/// `L`, the dynamic range of the luma values (8-bit images: 255).
pub const SSIM_DATA_RANGE: f64 = 255.0;

/// The smallest width and height SSIM accepts: its 11 × 11 window (scikit-image refuses
/// images smaller than the window).
pub const SSIM_MIN_SIDE: u32 = 2 * SSIM_WINDOW_RADIUS + 1;

/// A per-pixel SSIM map, the size of the images (`S` of scikit-image's `full=True`).
pub type SsimMap = ImageBuffer<Luma<f64>, Vec<f64>>;

/// The structural similarity of a test image to a reference.
#[derive(Clone, Debug, PartialEq)]
pub struct Ssim {
    /// The mean SSIM index (eq. 17, MSSIM) over the map without the window's half-width
    /// (5 px) on each side, as scikit-image's `crop(S, pad).mean()`: 1 for identical
    /// images, lower the more they differ (at least −1).
    pub mean: f64,
    /// The SSIM index (eq. 13) at every pixel, the border included, where the Gaussian
    /// window is extended by reflection (scipy's `mode='reflect'`).
    pub map: SsimMap,
}

/// The SSIM of `test` against `reference` on their Rec. 709 luma ([`crate::rec709_luma`];
/// alpha ignored).
///
/// The images must have the same size, at least [`SSIM_MIN_SIDE`] in both directions.
///
/// ```
/// use image::{Rgba, RgbaImage};
///
/// let reference = RgbaImage::from_fn(32, 32, |x, y| Rgba([(8 * x) as u8, (8 * y) as u8, 128, 255]));
/// let mut test = reference.clone();
/// test.put_pixel(16, 16, Rgba([255, 255, 255, 255]));
/// let ssim = image_metrics::ssim(&reference, &test)?;
/// assert!(ssim.mean < 1.0 && ssim.mean > 0.9);
/// assert!(ssim.map.get_pixel(16, 16)[0] < ssim.map.get_pixel(0, 0)[0]);
/// assert_eq!(image_metrics::ssim(&reference, &reference)?.mean, 1.0);
/// # Ok::<(), image_metrics::MetricError>(())
/// ```
pub fn ssim(reference: &RgbaImage, test: &RgbaImage) -> Result<Ssim, MetricError> {
    check_sizes("SSIM", reference.dimensions(), test.dimensions(), SSIM_MIN_SIDE)?;
    let (width, height) = reference.dimensions();
    ssim_luma(width, height, &rec709_luma(reference), &rec709_luma(test))
}

/// The SSIM of two luma planes (`width × height` values each, row-major, in
/// `[0, `[`SSIM_DATA_RANGE`]`]`: `C1` and `C2` assume that range).
///
/// Fails on planes of the wrong length, smaller than [`SSIM_MIN_SIDE`], or holding a
/// non-finite value.
pub fn ssim_luma(width: u32, height: u32, reference: &[f64], test: &[f64]) -> Result<Ssim, MetricError> {
    let expected = width as usize * height as usize;
    for (plane, values) in [("reference", reference), ("test", test)] {
        if values.len() != expected {
            return Err(MetricError::LengthMismatch { plane, expected, actual: values.len() });
        }
    }
    check_sizes("SSIM", (width, height), (width, height), SSIM_MIN_SIDE)?;
    for (plane, values) in [("reference", reference), ("test", test)] {
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            let at = ((i % width as usize) as u32, (i / width as usize) as u32);
            return Err(MetricError::NonFinite { plane, at, value: values[i] });
        }
    }

    let (w, h) = (width as usize, height as usize);
    let product = |a: &[f64], b: &[f64]| -> Vec<f64> { a.iter().zip(b).map(|(a, b)| a * b).collect() };
    // The local statistics of eq. 14–16: Gaussian-weighted means and (population)
    // variances and covariance, as E[x²] − E[x]² like scikit-image.
    let ux = gaussian_filter(reference, w, h);
    let uy = gaussian_filter(test, w, h);
    let uxx = gaussian_filter(&product(reference, reference), w, h);
    let uyy = gaussian_filter(&product(test, test), w, h);
    let uxy = gaussian_filter(&product(reference, test), w, h);

    let c1 = (SSIM_K1 * SSIM_DATA_RANGE) * (SSIM_K1 * SSIM_DATA_RANGE);
    let c2 = (SSIM_K2 * SSIM_DATA_RANGE) * (SSIM_K2 * SSIM_DATA_RANGE);
    let map: Vec<f64> = (0..expected)
        .map(|i| {
            let (ux, uy) = (ux[i], uy[i]);
            let vx = uxx[i] - ux * ux;
            let vy = uyy[i] - uy * uy;
            let vxy = uxy[i] - ux * uy;
            // Eq. 13: ((2 μx μy + C1)(2 σxy + C2)) / ((μx² + μy² + C1)(σx² + σy² + C2)).
            let a1 = 2.0 * ux * uy + c1;
            let a2 = 2.0 * vxy + c2;
            let b1 = ux * ux + uy * uy + c1;
            let b2 = vx + vy + c2;
            (a1 * a2) / (b1 * b2)
        })
        .collect();

    // scikit-image's `crop(S, pad).mean()`: numpy's pairwise sum of the cropped values in
    // row-major order, divided by their count.
    let pad = SSIM_WINDOW_RADIUS as usize;
    let cropped: Vec<f64> =
        map.chunks_exact(w).skip(pad).take(h - 2 * pad).flat_map(|row| &row[pad..w - pad]).copied().collect();
    let mean = pairwise_sum(&cropped) / cropped.len() as f64;
    let map = SsimMap::from_raw(width, height, map).expect("one value per pixel");
    Ok(Ssim { mean, map })
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::Rgba;

    fn pattern(width: u32, height: u32) -> RgbaImage {
        RgbaImage::from_fn(width, height, |x, y| {
            let v = (x * 37 + y * 91 + (x * y) % 13) % 256;
            Rgba([v as u8, (255 - v) as u8, ((x * 16) % 256) as u8, 255])
        })
    }

    #[test]
    fn identical_images_give_one_everywhere() {
        let image = pattern(20, 13);
        let ssim = ssim(&image, &image).unwrap();
        assert_eq!(ssim.mean, 1.0);
        assert!(ssim.map.pixels().all(|p| (p[0] - 1.0).abs() <= 1e-12));
        assert_eq!(ssim.map.dimensions(), (20, 13));
    }

    #[test]
    fn alpha_is_ignored_and_the_index_is_symmetric() {
        let a = pattern(24, 16);
        let mut b = a.clone();
        for (i, p) in b.pixels_mut().enumerate() {
            p[1] = p[1].wrapping_add((i % 7) as u8 * 9);
        }
        let mut b_alpha = b.clone();
        for (i, p) in b_alpha.pixels_mut().enumerate() {
            p[3] = (i % 256) as u8;
        }
        let ab = ssim(&a, &b).unwrap();
        assert!(ab.mean < 0.99, "{}", ab.mean);
        assert_eq!(ab, ssim(&a, &b_alpha).unwrap());
        // Eq. 13 is symmetric in x and y; only rounding may differ.
        assert!((ab.mean - ssim(&b, &a).unwrap().mean).abs() <= 1e-15);
    }

    #[test]
    fn bad_inputs_are_errors() {
        let a = pattern(16, 16);
        assert_eq!(ssim(&a, &pattern(16, 15)), Err(MetricError::SizeMismatch { reference: (16, 16), test: (16, 15) }));
        let small = pattern(10, 40);
        assert_eq!(ssim(&small, &small), Err(MetricError::TooSmall { metric: "SSIM", size: (10, 40), min_side: 11 }));
        assert!(ssim(&pattern(11, 11), &pattern(11, 11)).is_ok());
        let plane = vec![1.0; 121];
        assert_eq!(
            ssim_luma(11, 11, &plane, &plane[..120]),
            Err(MetricError::LengthMismatch { plane: "test", expected: 121, actual: 120 })
        );
        let mut nan = plane.clone();
        nan[11 * 3 + 2] = f64::NAN;
        let err = ssim_luma(11, 11, &nan, &plane).unwrap_err();
        assert!(matches!(err, MetricError::NonFinite { plane: "reference", at: (2, 3), .. }), "{err}");
        assert!(ssim(&RgbaImage::new(0, 0), &RgbaImage::new(0, 0)).is_err());
    }

    #[test]
    fn structure_and_luminance_terms_lower_the_index() {
        // A brightness offset lowers the luminance term only, an inversion the structure.
        let a = pattern(32, 24);
        let luma = rec709_luma(&a);
        let brighter: Vec<f64> = luma.iter().map(|v| v * 0.5 + 60.0).collect();
        let inverted: Vec<f64> = luma.iter().map(|v| 255.0 - v).collect();
        let s_brighter = ssim_luma(32, 24, &luma, &brighter).unwrap().mean;
        let s_inverted = ssim_luma(32, 24, &luma, &inverted).unwrap().mean;
        assert!(s_brighter < 1.0 && s_brighter > 0.0, "{s_brighter}");
        assert!(s_inverted < 0.0, "anti-correlated structure: {s_inverted}");
    }
}
