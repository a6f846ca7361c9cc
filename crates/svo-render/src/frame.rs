//! A rendered image: linear radiance, coverage and work per pixel, and its 8-bit sRGB form.

use std::path::Path;

use glam::Vec3;
use image::RgbaImage;

use crate::error::RenderError;

/// A rendered image, row-major with `y` down: what the cone tracer ([`crate::cpu::render`])
/// and the ground truths ([`crate::truth`]) return.
#[derive(Clone, Debug, PartialEq)]
pub struct Frame {
    /// Pixels across.
    pub width: u32,
    /// Pixels down.
    pub height: u32,
    /// Linear radiance per pixel, background included.
    pub radiance: Vec<Vec3>,
    /// The covered fraction of each pixel's footprint, in `[0, 1]`.
    pub coverage: Vec<f32>,
    /// The work per pixel: cone elements sampled (the tracer) or distance evaluations of
    /// all rays (the ground truths).
    pub elements: Vec<u32>,
}

/// The sRGB transfer function of a linear value clamped to `[0, 1]` (IEC 61966-2-1).
pub fn srgb_encode(linear: f32) -> f32 {
    let c = if linear.is_nan() { 0.0 } else { linear.clamp(0.0, 1.0) };
    if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 }
}

impl Frame {
    /// A frame from per-pixel `(radiance, coverage, elements)`, row-major.
    pub(crate) fn from_pixels(width: u32, height: u32, pixels: Vec<(Vec3, f32, u32)>) -> Result<Self, RenderError> {
        if pixels.len() != width as usize * height as usize {
            return Err(RenderError::FrameSize { size: (width, height), pixels: pixels.len() });
        }
        let mut frame = Frame {
            width,
            height,
            radiance: Vec::with_capacity(pixels.len()),
            coverage: Vec::with_capacity(pixels.len()),
            elements: Vec::with_capacity(pixels.len()),
        };
        for (radiance, coverage, elements) in pixels {
            frame.radiance.push(radiance);
            frame.coverage.push(coverage);
            frame.elements.push(elements);
        }
        Ok(frame)
    }

    /// The number of pixels.
    pub fn pixels(&self) -> usize {
        self.width as usize * self.height as usize
    }

    /// `Err(FrameSize)` unless every per-pixel vector holds `width × height` values.
    pub fn check(&self) -> Result<(), RenderError> {
        let n = self.pixels();
        for len in [self.radiance.len(), self.coverage.len(), self.elements.len()] {
            if len != n {
                return Err(RenderError::FrameSize { size: (self.width, self.height), pixels: len });
            }
        }
        Ok(())
    }

    /// The mean radiance over every pixel (background included; zero for an empty frame).
    pub fn mean_radiance(&self) -> Vec3 {
        let sum = self.radiance.iter().fold(glam::DVec3::ZERO, |s, r| s + r.as_dvec3());
        (sum / self.radiance.len().max(1) as f64).as_vec3()
    }

    /// The mean colour of the geometry alone: `Σ (L − (1 − c) background) / Σ c` over the
    /// pixels (radiance `L`, coverage `c`), the colour a viewer attributes to the surface
    /// whatever its size on screen (zero where nothing is covered).
    pub fn surface_mean(&self, background: Vec3) -> Vec3 {
        let (mut sum, mut weight) = (glam::DVec3::ZERO, 0.0_f64);
        for (r, &c) in self.radiance.iter().zip(&self.coverage) {
            sum += (*r - background * (1.0 - c)).as_dvec3();
            weight += f64::from(c);
        }
        if weight > 0.0 { (sum / weight).as_vec3() } else { Vec3::ZERO }
    }

    /// The mean of [`elements`](Self::elements) per pixel.
    pub fn mean_elements(&self) -> f64 {
        self.elements.iter().map(|&e| f64::from(e)).sum::<f64>() / self.elements.len().max(1) as f64
    }

    /// The root-mean-square difference of the linear radiance against `reference`, over every
    /// channel of every pixel.
    pub fn rmse(&self, reference: &Frame) -> Result<f64, RenderError> {
        self.same_size(reference)?;
        let sum: f64 =
            self.radiance.iter().zip(&reference.radiance).map(|(a, b)| (*a - *b).as_dvec3().length_squared()).sum();
        Ok((sum / (3 * self.pixels().max(1)) as f64).sqrt())
    }

    /// `Err(SizeMismatch)` unless both frames have the same size and hold all their pixels.
    pub fn same_size(&self, reference: &Frame) -> Result<(), RenderError> {
        self.check()?;
        reference.check()?;
        if (self.width, self.height) != (reference.width, reference.height) {
            return Err(RenderError::SizeMismatch {
                reference: (reference.width, reference.height),
                test: (self.width, self.height),
            });
        }
        Ok(())
    }

    /// The 8-bit sRGB image of `exposure × radiance`, clamped to `[0, 1]` before encoding
    /// (alpha 255). Missing pixels (a malformed frame) are black.
    pub fn to_rgba8(&self, exposure: f32) -> RgbaImage {
        let byte = |v: f32| (255.0 * srgb_encode(v * exposure) + 0.5) as u8;
        RgbaImage::from_fn(self.width, self.height, |x, y| {
            let r = self.radiance.get(y as usize * self.width as usize + x as usize).copied().unwrap_or(Vec3::ZERO);
            image::Rgba([byte(r.x), byte(r.y), byte(r.z), 255])
        })
    }

    /// The coverage as an 8-bit grey image (linear: 255 = covered), for inspection.
    pub fn coverage_rgba8(&self) -> RgbaImage {
        RgbaImage::from_fn(self.width, self.height, |x, y| {
            let c = self.coverage.get(y as usize * self.width as usize + x as usize).copied().unwrap_or(0.0);
            let g = (255.0 * if c.is_nan() { 0.0 } else { c.clamp(0.0, 1.0) } + 0.5) as u8;
            image::Rgba([g, g, g, 255])
        })
    }

    /// Writes [`to_rgba8`](Self::to_rgba8) as a PNG at `path` (its folder must exist).
    pub fn write_png(&self, path: &Path, exposure: f32) -> Result<(), RenderError> {
        write_png(&self.to_rgba8(exposure), path)
    }
}

/// Writes an RGBA image as a PNG at `path`.
pub fn write_png(image: &RgbaImage, path: &Path) -> Result<(), RenderError> {
    image
        .save_with_format(path, image::ImageFormat::Png)
        .map_err(|source| RenderError::Png { path: path.to_path_buf(), source })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame() -> Frame {
        Frame {
            width: 2,
            height: 1,
            radiance: vec![Vec3::new(0.0, 0.5, 2.0), Vec3::splat(0.1)],
            coverage: vec![1.0, 0.0],
            elements: vec![3, 1],
        }
    }

    #[test]
    fn the_srgb_image_is_clamped_and_encoded() {
        let image = frame().to_rgba8(1.0);
        assert_eq!(image.get_pixel(0, 0).0, [0, 188, 255, 255]);
        assert_eq!(image.get_pixel(1, 0).0, [89, 89, 89, 255]);
        assert!((srgb_encode(0.5) - 0.735_357).abs() < 1e-5);
        assert_eq!(srgb_encode(f32::NAN), 0.0);
    }

    #[test]
    fn statistics_and_sizes() {
        let f = frame();
        assert!((f.mean_elements() - 2.0).abs() < 1e-12);
        assert_eq!(f.surface_mean(Vec3::splat(0.1)), Vec3::new(0.0, 0.5, 2.0));
        assert_eq!(f.rmse(&f).unwrap(), 0.0);
        let small = Frame { width: 1, radiance: vec![Vec3::ZERO], coverage: vec![0.0], elements: vec![0], ..f.clone() };
        assert!(matches!(f.rmse(&small), Err(RenderError::SizeMismatch { .. })));
        let broken = Frame { coverage: vec![], ..f };
        assert!(matches!(broken.check(), Err(RenderError::FrameSize { pixels: 0, .. })));
    }

    #[test]
    fn pngs_round_trip_and_bad_paths_name_the_file() {
        let f = frame();
        let path = std::env::temp_dir().join(format!("svo-render-frame-{}.png", std::process::id()));
        f.write_png(&path, 1.0).unwrap();
        let back = image::open(&path).unwrap().to_rgba8();
        assert_eq!(back, f.to_rgba8(1.0));
        let _ = std::fs::remove_file(&path);
        let missing = Path::new("/nonexistent-folder-of-svo-render/frame.png");
        let error = f.write_png(missing, 1.0).unwrap_err();
        assert!(error.to_string().contains("nonexistent-folder-of-svo-render"), "{error}");
    }
}
