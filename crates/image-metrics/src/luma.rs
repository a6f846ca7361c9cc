//! Rec. 709 luma of 8-bit RGBA images, the plane SSIM is computed on.

use image::RgbaImage;

/// The Rec. 709 luma weights of R, G and B (ITU-R BT.709, item 3.2), applied to the
/// 8-bit sRGB-encoded values as they are (gamma-encoded luma, no linearisation).
pub const REC709_LUMA: [f64; 3] = [0.2126, 0.7152, 0.0722];

/// The Rec. 709 luma `Y = 0.2126 R + 0.7152 G + 0.0722 B` of every pixel, row-major, on
/// the 8-bit values as `f64` in `[0, 255]` (not rounded back to 8 bits; alpha ignored).
///
/// Evaluated as numpy evaluates `0.2126 * r + 0.7152 * g + 0.0722 * b`, left to right.
pub fn rec709_luma(image: &RgbaImage) -> Vec<f64> {
    let [kr, kg, kb] = REC709_LUMA;
    image.pixels().map(|p| kr * f64::from(p[0]) + kg * f64::from(p[1]) + kb * f64::from(p[2])).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::Rgba;

    #[test]
    fn luma_weights_and_alpha() {
        let mut image = RgbaImage::new(4, 1);
        image.put_pixel(0, 0, Rgba([255, 255, 255, 0]));
        image.put_pixel(1, 0, Rgba([255, 0, 0, 255]));
        image.put_pixel(2, 0, Rgba([0, 255, 0, 17]));
        image.put_pixel(3, 0, Rgba([10, 20, 30, 255]));
        let y = rec709_luma(&image);
        assert!((y[0] - 255.0).abs() <= 1e-12, "the weights sum to 1: {}", y[0]);
        assert_eq!(y[1], 0.2126 * 255.0);
        assert_eq!(y[2], 0.7152 * 255.0);
        // Not rounded to 8 bits: 2.126 + 14.304 + 2.166.
        assert!((y[3] - 18.596).abs() <= 1e-12, "{}", y[3]);
    }
}
