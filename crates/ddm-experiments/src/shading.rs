//! The tables' images: a view shaded from each pixel's hit normal, so that methods are
//! compared as a person sees them (ꟻLIP, SSIM) and not only by their hit points.

use glam::Vec3;
use image::{Rgba, RgbaImage};

use crate::ExperimentError;
use crate::view::View;

/// Direction toward the light of [`shade_normals`] (normalised there).
pub const LIGHT: Vec3 = Vec3::new(0.45, 0.3, 0.84);
/// Colour of a pixel whose ray hits nothing.
pub const MISS: [u8; 3] = [20, 24, 40];

/// The view shaded from each pixel's unit hit normal (`None`: a miss, [`MISS`]): a sand
/// albedo tinted by the normal (60 % / 40 %), times ambient 0.2 + Lambert 0.8 toward
/// [`LIGHT`]. An error when there is not one normal per pixel.
pub fn shade_normals(view: &View, normals: &[Option<Vec3>]) -> Result<RgbaImage, ExperimentError> {
    let pixels = view.width as usize * view.height as usize;
    if normals.len() != pixels {
        return Err(ExperimentError::settings(
            "normals",
            format!("{} normals for a {}x{} view", normals.len(), view.width, view.height),
        ));
    }
    let light = LIGHT.normalize();
    let mut image = RgbaImage::new(view.width, view.height);
    for (pixel, normal) in image.pixels_mut().zip(normals) {
        *pixel = match normal {
            Some(n) => {
                let shade = 0.2 + 0.8 * n.dot(light).max(0.0);
                let base = Vec3::new(0.85, 0.72, 0.5) * 0.6 + (*n * 0.5 + 0.5) * 0.4;
                let c = base * shade * 255.0;
                Rgba([c.x as u8, c.y as u8, c.z as u8, 255])
            }
            None => Rgba([MISS[0], MISS[1], MISS[2], 255]),
        };
    }
    Ok(image)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn misses_are_dark_lit_faces_bright_and_a_wrong_count_is_an_error() {
        let view = View { width: 2, height: 1, rays: vec![(Vec3::ZERO, -Vec3::Z); 2] };
        let image = shade_normals(&view, &[None, Some(LIGHT.normalize())]).unwrap();
        assert_eq!(image.get_pixel(0, 0).0, [20, 24, 40, 255]);
        assert!(image.get_pixel(1, 0).0[..3].iter().all(|&c| c > 150), "{:?}", image.get_pixel(1, 0));
        assert!(shade_normals(&view, &[None]).unwrap_err().to_string().contains("1 normals for a 2x1 view"));
    }
}
