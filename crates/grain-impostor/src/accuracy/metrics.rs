//! SSIM and RMSE between a reference render and a test render.
//!
//! # SSIM
//!
//! SSIM comes from the maintained `image-compare` crate (0.5,
//! `gray_similarity_structure(Algorithm::MSSIMSimple, ..)`), computed on the Rec. 709 luma of
//! the 8-bit sRGB images. Its window: **non-overlapping 8 × 8 pixel windows** (the last row
//! and column of windows are clipped at the image border), SSIM per window with
//! `c1 = (0.01·255)²` and `c2 = (0.03·255)²`, averaged with equal weights over windows, no
//! Gaussian weighting. Note that `image-compare` sums (co)variances over the window instead
//! of averaging them, which amounts to using `c2 / 64` for full windows: its scores are a
//! little stricter than textbook SSIM on low-contrast windows. Scores are comparable between
//! our configurations, which is what the experiment needs; they are not comparable to the
//! absolute values printed in the paper.
//!
//! # RMSE
//!
//! Root mean square error over all pixels and the three colour channels, in `[0, 1]` units
//! of the 8-bit sRGB values.

use image::{GrayImage, RgbaImage};

/// How far a test render is from the reference.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImageError {
    /// Mean SSIM of the luma (1 = identical), see the module documentation.
    pub ssim: f64,
    /// RMSE of the sRGB colour channels in `[0, 1]`.
    pub rmse: f64,
}

/// Why two images could not be compared.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum MetricError {
    /// The images differ in size.
    SizeMismatch {
        /// Reference size.
        reference: (u32, u32),
        /// Test size.
        test: (u32, u32),
    },
    /// An image has no pixel.
    Empty,
    /// `image-compare` refused the input (its message).
    Compare(String),
}

impl core::fmt::Display for MetricError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::SizeMismatch { reference, test } => {
                write!(
                    f,
                    "cannot compare a {}×{} render with a {}×{} reference",
                    test.0, test.1, reference.0, reference.1
                )
            }
            Self::Empty => write!(f, "cannot compare empty images"),
            Self::Compare(message) => write!(f, "image-compare failed: {message}"),
        }
    }
}

impl std::error::Error for MetricError {}

fn luma(image: &RgbaImage) -> GrayImage {
    GrayImage::from_fn(image.width(), image.height(), |x, y| {
        let [r, g, b, _] = image.get_pixel(x, y).0;
        let y = 0.2126 * f64::from(r) + 0.7152 * f64::from(g) + 0.0722 * f64::from(b);
        image::Luma([y.round().clamp(0.0, 255.0) as u8])
    })
}

/// SSIM and RMSE of `test` against `reference` (alpha is ignored).
pub fn compare_images(reference: &RgbaImage, test: &RgbaImage) -> Result<ImageError, MetricError> {
    if reference.dimensions() != test.dimensions() {
        return Err(MetricError::SizeMismatch { reference: reference.dimensions(), test: test.dimensions() });
    }
    if reference.width() == 0 || reference.height() == 0 {
        return Err(MetricError::Empty);
    }
    let similarity =
        image_compare::gray_similarity_structure(&image_compare::Algorithm::MSSIMSimple, &luma(reference), &luma(test))
            .map_err(|e| MetricError::Compare(e.to_string()))?;
    let mut squared = 0.0;
    for (a, b) in reference.pixels().zip(test.pixels()) {
        for channel in 0..3 {
            let difference = (f64::from(a.0[channel]) - f64::from(b.0[channel])) / 255.0;
            squared += difference * difference;
        }
    }
    let count = 3.0 * f64::from(reference.width()) * f64::from(reference.height());
    Ok(ImageError { ssim: similarity.score, rmse: (squared / count).sqrt() })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn gradient(width: u32, height: u32, shift: u8) -> RgbaImage {
        RgbaImage::from_fn(width, height, |x, y| {
            let v = ((x * 7 + y * 3) % 200) as u8;
            image::Rgba([v.saturating_add(shift), v / 2, 255 - v, 255])
        })
    }

    #[test]
    fn identical_images_score_one_and_zero() {
        let image = gradient(40, 24, 0);
        let error = compare_images(&image, &image).unwrap();
        assert!((error.ssim - 1.0).abs() < 1e-12);
        assert_eq!(error.rmse, 0.0);
    }

    #[test]
    fn a_shifted_channel_lowers_ssim_and_gives_the_expected_rmse() {
        let reference = gradient(40, 24, 0);
        let test = gradient(40, 24, 30);
        let error = compare_images(&reference, &test).unwrap();
        assert!(error.ssim < 1.0);
        // Only the red channel changes, by 30/255 wherever it does not saturate (v ≤ 199 + 30 < 255).
        let expected = ((30.0_f64 / 255.0).powi(2) / 3.0).sqrt();
        assert!((error.rmse - expected).abs() < 1e-9, "{} vs {expected}", error.rmse);
    }

    #[test]
    fn mismatched_or_empty_images_are_errors() {
        let a = gradient(8, 8, 0);
        let b = gradient(9, 8, 0);
        assert_eq!(compare_images(&a, &b), Err(MetricError::SizeMismatch { reference: (8, 8), test: (9, 8) }));
        assert_eq!(compare_images(&RgbaImage::new(0, 0), &RgbaImage::new(0, 0)), Err(MetricError::Empty));
    }
}
