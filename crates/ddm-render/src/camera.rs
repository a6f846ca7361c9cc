//! The perspective camera of the raster pass, and the same camera's rays on the CPU.

use glam::{Mat4, Vec3, Vec4};
use gpu_layout::gpu_struct;

gpu_struct! {
    /// The raster pass's uniforms.
    pub struct BaseCamera {
        /// World → clip space (wgpu conventions: depth in `[0, 1]`), columns.
        pub clip_from_world: [Vec4; 4],
        /// Eye position in `xyz`, `w` 1.
        pub eye: Vec4,
    }
}

/// A pinhole camera at `eye` looking at `target`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position.
    pub eye: Vec3,
    /// The point looked at.
    pub target: Vec3,
    /// Approximate up vector.
    pub up: Vec3,
    /// Half the vertical field of view, radians.
    pub half_fov_y: f32,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
}

impl Camera {
    /// The camera's orthonormal `(forward, right, up)`.
    fn basis(&self) -> (Vec3, Vec3, Vec3) {
        let forward = (self.target - self.eye).normalize();
        let right = forward.cross(self.up).normalize();
        (forward, right, right.cross(forward))
    }

    /// The unit direction of the ray through the centre of pixel `(x, y)` (row 0 on top),
    /// the ray the raster pass samples there.
    pub fn pixel_direction(&self, x: u32, y: u32) -> Vec3 {
        let (forward, right, up) = self.basis();
        let tan = self.half_fov_y.tan();
        let aspect = self.width as f32 / self.height as f32;
        let u = ((x as f32 + 0.5) / self.width as f32 * 2.0 - 1.0) * tan * aspect;
        let v = (1.0 - (y as f32 + 0.5) / self.height as f32 * 2.0) * tan;
        (forward + right * u + up * v).normalize()
    }

    /// The raster uniforms, clipping at `near` and `far`.
    pub fn uniforms(&self, near: f32, far: f32) -> BaseCamera {
        // Right-handed view (camera looks down −z) and wgpu's [0, 1] clip depth.
        let (forward, right, up) = self.basis();
        let view = Mat4::from_cols(
            Vec4::new(right.x, up.x, -forward.x, 0.0),
            Vec4::new(right.y, up.y, -forward.y, 0.0),
            Vec4::new(right.z, up.z, -forward.z, 0.0),
            Vec4::new(-right.dot(self.eye), -up.dot(self.eye), forward.dot(self.eye), 1.0),
        );
        let f = 1.0 / self.half_fov_y.tan();
        let aspect = self.width as f32 / self.height as f32;
        let projection = Mat4::from_cols(
            Vec4::new(f / aspect, 0.0, 0.0, 0.0),
            Vec4::new(0.0, f, 0.0, 0.0),
            Vec4::new(0.0, 0.0, far / (near - far), -1.0),
            Vec4::new(0.0, 0.0, near * far / (near - far), 0.0),
        );
        let m = projection * view;
        BaseCamera { clip_from_world: [m.x_axis, m.y_axis, m.z_axis, m.w_axis], eye: self.eye.extend(1.0) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pixel_rays_project_to_their_pixel() {
        let camera = Camera {
            eye: Vec3::new(-3.0, -5.0, 9.0),
            target: Vec3::new(4.0, 4.0, 1.0),
            up: Vec3::Z,
            half_fov_y: 0.4,
            width: 64,
            height: 48,
        };
        let u = camera.uniforms(0.1, 100.0);
        let m = Mat4::from_cols(u.clip_from_world[0], u.clip_from_world[1], u.clip_from_world[2], u.clip_from_world[3]);
        for (x, y) in [(0, 0), (63, 47), (10, 30), (40, 5)] {
            let p = camera.eye + camera.pixel_direction(x, y) * 7.0;
            let clip = m * p.extend(1.0);
            let ndc = clip.truncate() / clip.w;
            let px = (ndc.x + 1.0) * 0.5 * 64.0;
            let py = (1.0 - ndc.y) * 0.5 * 48.0;
            assert!((px - (x as f32 + 0.5)).abs() < 1e-3 && (py - (y as f32 + 0.5)).abs() < 1e-3, "{px} {py}");
        }
    }
}
