//! Whole-frame image-error metrics of renders against references, computed as the field
//! computes them:
//!
//! - **SSIM** (Wang, Bovik, Sheikh & Simoncelli, *Image Quality Assessment: From Error
//!   Visibility to Structural Similarity*, IEEE TIP 13(4), 2004): the SSIM index of eq. 13
//!   on Rec. 709 luma, with the paper's 11 × 11 Gaussian window (σ = 1.5), `K1 = 0.01`,
//!   `K2 = 0.03`, `L = 255`, and the mean of eq. 17 — exactly as scikit-image's
//!   `structural_similarity(x, y, gaussian_weights=True, sigma=1.5,
//!   use_sample_covariance=False, data_range=255)` computes it (same window truncation,
//!   `mode='reflect'` borders and 5-pixel crop of the mean; checked against scikit-image
//!   to 1e-9 by the tests).
//! - **ꟻLIP** (Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström & Fairchild, *ꟻLIP: A
//!   Difference Evaluator for Alternating Images*, HPG 2020): NVIDIA's implementation
//!   through the `nv-flip` crate at its default 67 pixels per degree, with the magma
//!   colour map for error-map images.
//!
//! ```
//! use image::{Rgba, RgbaImage};
//!
//! let reference = RgbaImage::from_fn(64, 48, |x, y| Rgba([(4 * x) as u8, (5 * y) as u8, 90, 255]));
//! let mut test = reference.clone();
//! for x in 20..30 {
//!     test.put_pixel(x, 24, Rgba([255, 255, 255, 255])); // a bright streak
//! }
//!
//! let ssim = image_metrics::ssim(&reference, &test)?;
//! assert!(ssim.mean < 1.0);
//! assert_eq!(ssim.map.dimensions(), (64, 48));
//!
//! let flip = image_metrics::flip(&reference, &test)?;
//! assert!(flip.mean > 0.0);
//! let error_image: image::RgbImage = image_metrics::flip_magma(&flip.map); // save as PNG
//! assert_eq!(error_image.dimensions(), (64, 48));
//!
//! // Different sizes are an error, not a panic.
//! let small = RgbaImage::new(8, 8);
//! assert!(matches!(
//!     image_metrics::ssim(&reference, &small),
//!     Err(image_metrics::MetricError::SizeMismatch { .. })
//! ));
//! # Ok::<(), image_metrics::MetricError>(())
//! ```
//!
//! # API
//!
//! - [`ssim()`] on RGBA images, [`ssim_luma`] on `f64` luma planes, both giving [`Ssim`]
//!   (mean and per-pixel [`SsimMap`]); [`rec709_luma`] is the plane [`ssim()`] uses.
//! - [`flip()`] giving [`Flip`] (mean and per-pixel [`FlipMap`]), [`flip_magma`] the map
//!   as an RGB image.
//! - [`MetricError`]: different sizes, images too small, planes of the wrong length or
//!   with non-finite values.

mod error;
mod flip;
mod gaussian;
mod luma;
mod ssim;

pub use error::MetricError;
pub use flip::{FLIP_PIXELS_PER_DEGREE, Flip, FlipMap, flip, flip_magma};
pub use gaussian::{SSIM_SIGMA, SSIM_WINDOW_RADIUS};
pub use luma::{REC709_LUMA, rec709_luma};
pub use ssim::{SSIM_DATA_RANGE, SSIM_K1, SSIM_K2, SSIM_MIN_SIDE, Ssim, SsimMap, ssim, ssim_luma};
