//! The view of Tables 1–3: one perspective camera ray per pixel, from above and to the
//! side of the tile, about 2 × 2 tiles wide, so that every method is measured on the same
//! mix of steep and grazing rays.

use glam::{UVec3, Vec3};

use crate::ExperimentError;

/// Half the vertical field of view, degrees.
pub const HALF_FOV_Y_DEG: f32 = 25.0;

/// One camera ray per pixel, row by row from the top-left pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct View {
    /// Pixels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// `(origin, unit direction)` of each pixel's ray.
    pub rays: Vec<(Vec3, Vec3)>,
}

/// The camera of [`View::perspective`]: eye and the point it looks at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Where every ray starts.
    pub eye: Vec3,
    /// The point at the centre of the image.
    pub target: Vec3,
}

impl Camera {
    /// The tables' camera for a tile of `dims` voxels: it looks at `(L_x, L_y, 0.3 L_z)`
    /// (the corner shared by four tiles, low in the slab) from `(-0.9 L_x, -1.3 L_y,
    /// 1.1 max(L_x, L_y))` beside it.
    pub fn of_tile(dims: UVec3) -> Self {
        let size = dims.as_vec3();
        Self::beside(Vec3::new(size.x, size.y, 0.3 * size.z), size)
    }

    /// Looking at `target` from `(-0.9 L_x, -1.3 L_y, 1.1 max(L_x, L_y))` beside it.
    fn beside(target: Vec3, size: Vec3) -> Self {
        let eye = target + Vec3::new(-0.9 * size.x, -1.3 * size.y, 1.1 * size.x.max(size.y));
        Self { eye, target }
    }

    /// [`Camera::of_tile`] for a tile that stands alone: it looks at the tile's centre
    /// `(L_x / 2, L_y / 2, 0.3 L_z)` from the same offset, so that the tile fills the
    /// middle of the image with empty space around it.
    pub fn of_single_tile(dims: UVec3) -> Self {
        let size = dims.as_vec3();
        Self::beside(Vec3::new(0.5 * size.x, 0.5 * size.y, 0.3 * size.z), size)
    }
}

impl View {
    /// The perspective view of [`Camera::of_tile`] with `width × height` pixels (square
    /// pixels, vertical half field of view [`HALF_FOV_Y_DEG`]); an error for an empty
    /// image or a tile with a zero size.
    pub fn perspective(dims: UVec3, width: u32, height: u32) -> Result<Self, ExperimentError> {
        if dims.cmpeq(UVec3::ZERO).any() {
            return Err(ExperimentError::settings("dims", format!("every size must be positive, not {dims}")));
        }
        Self::looking(Camera::of_tile(dims), width, height)
    }

    /// The perspective view from `camera` with `width × height` pixels (square pixels,
    /// vertical half field of view [`HALF_FOV_Y_DEG`], the image's up toward +z); an
    /// error for an empty image or a camera that looks straight up or down (or at its
    /// own eye).
    pub fn looking(camera: Camera, width: u32, height: u32) -> Result<Self, ExperimentError> {
        if width == 0 || height == 0 {
            return Err(ExperimentError::settings("width/height", format!("empty image {width}x{height}")));
        }
        let Camera { eye, target } = camera;
        let forward = (target - eye).normalize_or_zero();
        let right = forward.cross(Vec3::Z).normalize_or_zero();
        if right == Vec3::ZERO {
            return Err(ExperimentError::settings(
                "camera",
                format!("from {eye} toward {target}: no image plane with +z up"),
            ));
        }
        let up = right.cross(forward);
        let tan = HALF_FOV_Y_DEG.to_radians().tan();
        let aspect = width as f32 / height as f32;
        let mut rays = Vec::with_capacity(width as usize * height as usize);
        for y in 0..height {
            for x in 0..width {
                let u = ((x as f32 + 0.5) / width as f32 * 2.0 - 1.0) * tan * aspect;
                let v = (1.0 - (y as f32 + 0.5) / height as f32 * 2.0) * tan;
                rays.push((eye, (forward + right * u + up * v).normalize()));
            }
        }
        Ok(Self { width, height, rays })
    }
}

impl Camera {
    /// Pixels per voxel at the target of a `height`-row view from this camera (the
    /// focal length in pixels, `height / 2 / tan(HALF_FOV_Y_DEG)`, over the distance):
    /// how magnified the tile is.
    pub fn pixels_per_voxel(self, height: u32) -> f64 {
        let focal = f64::from(height) / 2.0 / f64::from(HALF_FOV_Y_DEG).to_radians().tan();
        focal / f64::from(self.eye.distance(self.target))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DIMS: UVec3 = UVec3::new(12, 12, 6);

    #[test]
    fn a_single_pixel_looks_at_the_target() {
        let view = View::perspective(DIMS, 1, 1).unwrap();
        let Camera { eye, target } = Camera::of_tile(DIMS);
        assert_eq!(view.rays.len(), 1);
        let (origin, direction) = view.rays[0];
        assert_eq!(origin, eye);
        assert!((direction - (target - eye).normalize()).length() < 1e-6);
    }

    #[test]
    fn rays_are_unit_start_at_the_eye_and_look_down() {
        let view = View::perspective(DIMS, 8, 6).unwrap();
        assert_eq!(view.rays.len(), 48);
        let eye = Camera::of_tile(DIMS).eye;
        for &(origin, direction) in &view.rays {
            assert_eq!(origin, eye);
            assert!((direction.length() - 1.0).abs() < 1e-6);
            assert!(direction.z < 0.0, "{direction}");
        }
    }

    #[test]
    fn the_field_of_view_is_symmetric_with_the_half_angle_at_the_edges() {
        // With 2 rows the pixel centres sit at ±half the half-height: tan = tan(25°) / 2.
        let (width, height) = (4, 2);
        let view = View::perspective(DIMS, width, height).unwrap();
        let Camera { eye, target } = Camera::of_tile(DIMS);
        let forward = (target - eye).normalize();
        let angle = |i: usize| view.rays[i].1.angle_between(forward);
        // Mirror pixels (x, y) and (w-1-x, h-1-y) are as far from the centre.
        for y in 0..height {
            for x in 0..width {
                let (a, b) = ((y * width + x) as usize, ((height - 1 - y) * width + (width - 1 - x)) as usize);
                assert!((angle(a) - angle(b)).abs() < 1e-5);
            }
        }
        // The top row's vertical offset: its rays lie in planes at atan(tan(25°)/2) above forward.
        let up = forward.cross(Vec3::Z).normalize().cross(forward);
        let top = view.rays[0].1;
        let vertical = (top.dot(up) / top.dot(forward)).atan();
        let expected = (HALF_FOV_Y_DEG.to_radians().tan() / 2.0).atan();
        assert!((vertical - expected).abs() < 1e-5, "{vertical} vs {expected}");
    }

    #[test]
    fn empty_inputs_are_errors_naming_the_field() {
        let error = View::perspective(DIMS, 0, 4).unwrap_err();
        assert!(error.to_string().contains("width/height"), "{error}");
        let error = View::perspective(UVec3::new(4, 0, 2), 4, 4).unwrap_err();
        assert!(error.to_string().contains("dims"), "{error}");
        let down = Camera { eye: Vec3::new(1.0, 1.0, 9.0), target: Vec3::ONE };
        let error = View::looking(down, 4, 4).unwrap_err();
        assert!(error.to_string().contains("camera"), "{error}");
    }

    #[test]
    fn pixels_per_voxel_halve_with_twice_the_distance_and_double_with_twice_the_rows() {
        let near = Camera { eye: Vec3::new(0.0, -4.0, 3.0), target: Vec3::ZERO };
        let far = Camera { eye: near.eye * 2.0, ..near };
        let at = near.pixels_per_voxel(72);
        // 36 / tan(25°) / 5.
        assert!((at - 36.0 / 25_f64.to_radians().tan() / 5.0).abs() < 1e-9, "{at}");
        assert!((far.pixels_per_voxel(72) - at / 2.0).abs() < 1e-9);
        assert!((near.pixels_per_voxel(144) - 2.0 * at).abs() < 1e-9);
    }
}
