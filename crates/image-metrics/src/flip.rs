//! ꟻLIP, the perceptual error of Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström &
//! Fairchild, *ꟻLIP: A Difference Evaluator for Alternating Images* (Proc. ACM Comput.
//! Graph. Interact. Tech. 3(2), HPG 2020), through NVIDIA's C++ implementation as bound by
//! the `nv-flip` crate, and its magma colour map for error-map images.

use image::{ImageBuffer, Luma, RgbImage, RgbaImage};

use crate::error::{MetricError, check_sizes};

/// The observer's pixels per degree of visual angle every [`flip()`] uses: nv-flip's
/// default, 67 — about a 0.7 m wide 3840-pixel monitor seen from 0.7 m, the paper's
/// default observer.
pub const FLIP_PIXELS_PER_DEGREE: f32 = nv_flip::DEFAULT_PIXELS_PER_DEGREE;

/// A per-pixel ꟻLIP error map, the size of the images, values in `[0, 1]`.
pub type FlipMap = ImageBuffer<Luma<f32>, Vec<f32>>;

/// The ꟻLIP error of a test image against a reference.
#[derive(Clone, Debug, PartialEq)]
pub struct Flip {
    /// The mean of [`Flip::map`], accumulated in `f64`: 0 for identical images, at most
    /// one. (The ꟻLIP tool's pooled mean accumulates in `f32`, so it may differ in the
    /// last digits on large images.)
    pub mean: f64,
    /// The ꟻLIP error at every pixel (the paper's `ΔE_c^(1 − ΔE_f)` of the colour and feature
    /// differences, in `[0, 1]`).
    pub map: FlipMap,
}

/// The ꟻLIP error of `test` against `reference`, both 8-bit sRGB (alpha ignored), at
/// [`FLIP_PIXELS_PER_DEGREE`].
///
/// The images must have the same size, at least 1 × 1 (ꟻLIP's filters clamp at the
/// border, so any size works).
///
/// ```
/// use image::{Rgba, RgbaImage};
///
/// let reference = RgbaImage::from_pixel(16, 16, Rgba([200, 120, 40, 255]));
/// let mut test = reference.clone();
/// test.put_pixel(8, 8, Rgba([0, 0, 0, 255]));
/// let flip = image_metrics::flip(&reference, &test)?;
/// // Largest at the dark pixel (0.24: blurred by the eye's contrast sensitivity).
/// assert!(flip.map.get_pixel(8, 8)[0] > 0.2);
/// assert!(flip.mean > 0.0 && flip.mean < 0.1);
/// let png_ready: image::RgbImage = image_metrics::flip_magma(&flip.map);
/// assert_eq!(png_ready.dimensions(), (16, 16));
/// # Ok::<(), image_metrics::MetricError>(())
/// ```
pub fn flip(reference: &RgbaImage, test: &RgbaImage) -> Result<Flip, MetricError> {
    check_sizes("FLIP", reference.dimensions(), test.dimensions(), 1)?;
    let (width, height) = reference.dimensions();
    let rgb8 = |image: &RgbaImage| -> nv_flip::FlipImageRgb8 {
        let rgb: Vec<u8> = image.pixels().flat_map(|p| [p[0], p[1], p[2]]).collect();
        nv_flip::FlipImageRgb8::with_data(width, height, &rgb)
    };
    let map = nv_flip::flip(rgb8(reference), rgb8(test), FLIP_PIXELS_PER_DEGREE).to_vec();
    let mean = map.iter().map(|&e| f64::from(e)).sum::<f64>() / map.len() as f64;
    let map = FlipMap::from_raw(width, height, map).expect("one value per pixel");
    Ok(Flip { mean, map })
}

/// `map` as an RGB image through ꟻLIP's magma colour map (nv-flip's 256-entry table,
/// black for 0 to pale yellow for 1): each value clamped to `[0, 1]` (NaN as 1) and looked
/// up at `⌊255 v + ½⌋`, as nv-flip's `apply_color_lut` does. Ready to save as PNG.
pub fn flip_magma(map: &FlipMap) -> RgbImage {
    let lut = nv_flip::magma_lut().to_vec();
    RgbImage::from_fn(map.width(), map.height(), |x, y| {
        let v = map.get_pixel(x, y)[0];
        let v = if v.is_nan() { 1.0 } else { v.clamp(0.0, 1.0) };
        let i = 3 * (v * 255.0 + 0.5) as usize;
        image::Rgb([lut[i], lut[i + 1], lut[i + 2]])
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::Rgba;

    /// A deterministic pattern with edges and smooth regions.
    fn pattern(width: u32, height: u32) -> RgbaImage {
        RgbaImage::from_fn(width, height, |x, y| {
            let checker = if (x / 6 + y / 6) % 2 == 0 { 60 } else { 190 };
            Rgba([checker, (x * 255 / width.max(1)) as u8, (y * 255 / height.max(1)) as u8, 255])
        })
    }

    /// `image` plus a deterministic per-channel perturbation of up to `±amplitude`.
    fn noisy(image: &RgbaImage, amplitude: i32) -> RgbaImage {
        let mut out = image.clone();
        for (i, p) in out.pixels_mut().enumerate() {
            for c in 0..3 {
                let hash = (i as u32 * 3 + c as u32).wrapping_mul(2_654_435_761) >> 16;
                let offset = (hash % (2 * amplitude as u32 + 1)) as i32 - amplitude;
                p[c] = (i32::from(p[c]) + offset).clamp(0, 255) as u8;
            }
        }
        out
    }

    #[test]
    fn identical_images_have_no_error() {
        let image = pattern(40, 30);
        let flip = flip(&image, &image).unwrap();
        assert_eq!(flip.mean, 0.0);
        assert!(flip.map.pixels().all(|p| p[0] == 0.0));
        assert_eq!(flip.map.dimensions(), (40, 30));
    }

    #[test]
    fn error_grows_with_the_distortion() {
        let image = pattern(48, 40);
        let means: Vec<f64> = [2, 8, 32, 96].iter().map(|&a| flip(&image, &noisy(&image, a)).unwrap().mean).collect();
        assert!(means[0] > 0.0, "{means:?}");
        assert!(means.windows(2).all(|w| w[0] < w[1]), "{means:?}");
        for m in &means {
            assert!(*m <= 1.0);
        }
    }

    #[test]
    fn error_is_symmetric_bounded_and_ignores_alpha() {
        let a = pattern(33, 21);
        let b = noisy(&a, 40);
        let ab = flip(&a, &b).unwrap();
        let ba = flip(&b, &a).unwrap();
        // The error's terms (HyAB colour difference, feature-magnitude difference) are symmetric.
        assert!((ab.mean - ba.mean).abs() <= 1e-6, "{} vs {}", ab.mean, ba.mean);
        assert!(ab.map.pixels().all(|p| (0.0..=1.0).contains(&p[0])));
        let mut b_alpha = b.clone();
        for (i, p) in b_alpha.pixels_mut().enumerate() {
            p[3] = (i * 7 % 256) as u8;
        }
        assert_eq!(flip(&a, &b_alpha).unwrap(), ab);
        // The mean is the map's, the same as the ꟻLIP tool's pooled mean up to its f32 sum.
        let pool = nv_flip::FlipPool::from_image(&nv_flip::FlipImageFloat::with_data(33, 21, ab.map.as_raw()));
        assert!((ab.mean - f64::from(pool.mean())).abs() <= 1e-6, "{} vs {}", ab.mean, pool.mean());
    }

    #[test]
    fn a_local_change_stays_local() {
        let image = pattern(96, 96);
        let mut test = image.clone();
        test.put_pixel(10, 10, Rgba([255, 0, 255, 255]));
        let flip = flip(&image, &test).unwrap();
        assert!(flip.map.get_pixel(10, 10)[0] > 0.3, "{}", flip.map.get_pixel(10, 10)[0]);
        // Beyond ꟻLIP's filter radii at 67 px/° (spatial and feature filters, well under
        // 40 px together) the images agree exactly.
        assert_eq!(flip.map.get_pixel(90, 90)[0], 0.0);
        assert_eq!(flip.map.get_pixel(10, 80)[0], 0.0);
    }

    #[test]
    fn tiny_and_mismatched_images() {
        let one = RgbaImage::from_pixel(1, 1, Rgba([10, 20, 30, 255]));
        let other = RgbaImage::from_pixel(1, 1, Rgba([250, 20, 30, 255]));
        let tiny = flip(&one, &other).unwrap();
        assert!(tiny.mean > 0.0 && tiny.mean <= 1.0, "{}", tiny.mean);
        assert_eq!(
            flip(&pattern(8, 8), &pattern(8, 9)),
            Err(MetricError::SizeMismatch { reference: (8, 8), test: (8, 9) })
        );
        let empty = RgbaImage::new(0, 5);
        assert_eq!(flip(&empty, &empty), Err(MetricError::TooSmall { metric: "FLIP", size: (0, 5), min_side: 1 }));
    }

    #[test]
    fn magma_is_nv_flips_lookup() {
        let values: Vec<f32> = (0..=1000).map(|i| i as f32 / 1000.0).collect();
        let map = FlipMap::from_raw(1001, 1, values.clone()).unwrap();
        let ours = flip_magma(&map);
        let theirs = nv_flip::FlipImageFloat::with_data(1001, 1, &values).apply_color_lut(&nv_flip::magma_lut());
        assert_eq!(ours.as_raw(), &theirs.to_vec());
        // Out of range and NaN: clamped, NaN as the maximum.
        let odd = FlipMap::from_raw(4, 1, vec![-3.0, 7.0, f32::NAN, 1.0]).unwrap();
        let odd = flip_magma(&odd);
        assert_eq!(odd.get_pixel(0, 0), ours.get_pixel(0, 0));
        assert_eq!(odd.get_pixel(1, 0), ours.get_pixel(1000, 0));
        assert_eq!(odd.get_pixel(2, 0), ours.get_pixel(1000, 0));
        assert_eq!(odd.get_pixel(0, 0).0, [0, 0, 4], "magma starts near black");
        assert!(ours.get_pixel(1000, 0).0.iter().all(|&c| c > 180), "and ends pale");
    }
}
