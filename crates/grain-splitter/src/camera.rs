//! The camera as the occluder map and the splitter see it, and the projections both make of
//! a grain's centre (the Rust twins of `shaders/projection.wgsl`).
//!
//! Every quantity a decision depends on is computed with the same operations, in the same
//! order, in Rust and in WGSL: matrix–vector products as sums of scaled columns, the frustum
//! test as a dot product plus the plane offset, the tier test as products compared (no
//! division). Only the centre's pixel and the projected inner radius divide by `w`; WGSL
//! allows a division 2.5 ulp of error, so a centre within a few ulp of a pixel edge may fall
//! in the neighbouring pixel on another adapter (the GPU tests count such grains, see
//! [`Projected::near_pixel_edge`]).

use glam::{Mat4, Vec2, Vec3, Vec4};
use gpu_layout::gpu_struct;

use crate::error::SplitError;

gpu_struct! {
    /// A camera: matrices, frustum planes, viewport and the focal length in pixels.
    pub struct SplitCamera {
        /// World → view space (eye at the origin, looking down `-z`), columns.
        pub view_from_world: [Vec4; 4],
        /// World → clip space (wgpu conventions: clip depth in `[0, 1]`), columns.
        pub clip_from_world: [Vec4; 4],
        /// The six frustum planes in world space, `(n, d)` with `|n| = 1` and the inside
        /// where `n·x + d ≥ 0`: left, right, bottom, top, near, far.
        pub frustum: [Vec4; 6],
        /// `(width, height, 1 / width, 1 / height)` in pixels.
        pub viewport: Vec4,
        /// `(focal, perspective, 0, 0)`: `focal` is `P₁₁·height/2`, pixels per unit of
        /// `y/z` for a perspective camera and pixels per world unit for an orthographic one;
        /// `perspective` is 1 or 0.
        pub projection: Vec4,
    }
}

/// The largest viewport side: texel coordinates are packed in 16 bits by the 32-bit
/// occluder map.
pub const MAX_VIEWPORT_SIDE: u32 = 1 << 15;

impl SplitCamera {
    /// A perspective camera at `eye` looking at `target` (`up` the approximate up vector),
    /// with vertical field of view `fov_y_radians`, rendering `width × height` pixels:
    /// the same matrices as [`grain_impostor::scene::CameraUniforms::perspective`] with the
    /// same arguments, bit for bit.
    pub fn perspective(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        fov_y_radians: f32,
        (width, height): (u32, u32),
        (near, far): (f32, f32),
    ) -> Result<Self, SplitError> {
        let positive = |x: f32| x.is_finite() && x > 0.0;
        let bad = |field: &'static str, reason: &str| SplitError::InvalidCamera { field, reason: reason.into() };
        check_viewport((width, height))?;
        if !positive(fov_y_radians) || fov_y_radians >= std::f32::consts::PI {
            return Err(bad("fov_y_radians", "must be in (0, π)"));
        }
        if !(positive(near) && far.is_finite() && far > near) {
            return Err(bad("near/far", "need 0 < near < far, both finite"));
        }
        let forward = target - eye;
        if !eye.is_finite() || !forward.is_finite() || forward.length_squared() == 0.0 {
            return Err(bad("eye/target", "must be finite and distinct"));
        }
        if forward.cross(up).length_squared() == 0.0 {
            return Err(bad("up", "must not be parallel to the viewing direction"));
        }
        let view = grain_impostor::scene::look_to_rh(eye, forward, up);
        let projection = grain_impostor::scene::perspective_rh(fov_y_radians, width as f32 / height as f32, near, far);
        Self::from_matrices(view, projection, (width, height))
    }

    /// A camera from its world → view transform (eye at the origin, looking down `-z`)
    /// and its view → clip projection: perspective when the projection's last row is
    /// `(0, 0, -1, 0)`, orthographic when it is `(0, 0, 0, 1)`; any other is an error.
    pub fn from_matrices(view_from_world: Mat4, clip_from_view: Mat4, size: (u32, u32)) -> Result<Self, SplitError> {
        check_viewport(size)?;
        let bad = |field: &'static str, reason: &str| SplitError::InvalidCamera { field, reason: reason.into() };
        if !view_from_world.is_finite() || view_from_world.determinant().abs() < f32::MIN_POSITIVE {
            return Err(bad("view_from_world", "must be finite and invertible"));
        }
        if !clip_from_view.is_finite() || clip_from_view.determinant().abs() < f32::MIN_POSITIVE {
            return Err(bad("clip_from_view", "must be finite and invertible"));
        }
        let last_row = clip_from_view.row(3);
        let perspective = if last_row == Vec4::new(0.0, 0.0, -1.0, 0.0) {
            true
        } else if last_row == Vec4::new(0.0, 0.0, 0.0, 1.0) {
            false
        } else {
            return Err(bad("clip_from_view", "last row must be (0, 0, -1, 0) (perspective) or (0, 0, 0, 1)"));
        };
        let (w, h) = (size.0 as f32, size.1 as f32);
        let focal = clip_from_view.y_axis.y * 0.5 * h;
        if !(focal.is_finite() && focal > 0.0) {
            return Err(bad("clip_from_view", "P₁₁ must be positive (y up)"));
        }
        let clip_from_world = clip_from_view * view_from_world;
        let columns = |m: Mat4| m.to_cols_array_2d().map(Vec4::from_array);
        Ok(Self {
            view_from_world: columns(view_from_world),
            clip_from_world: columns(clip_from_world),
            frustum: frustum_planes(clip_from_world),
            viewport: Vec4::new(w, h, 1.0 / w, 1.0 / h),
            projection: Vec4::new(focal, if perspective { 1.0 } else { 0.0 }, 0.0, 0.0),
        })
    }

    /// Whether the camera is a perspective one.
    pub fn is_perspective(&self) -> bool {
        self.projection.y != 0.0
    }

    /// `(width, height)` in pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.viewport.x as u32, self.viewport.y as u32)
    }

    /// Projects a grain's centre. Twin of `split_project` (WGSL).
    pub fn project(&self, centre: Vec3) -> Projected {
        let view = transform(&self.view_from_world, centre);
        let clip = transform(&self.clip_from_world, centre);
        let pixel = if clip.w > 0.0 {
            let inverse_w = 1.0 / clip.w;
            let ndc = Vec2::new(clip.x * inverse_w, clip.y * inverse_w);
            Some(Vec2::new((ndc.x * 0.5 + 0.5) * self.viewport.x, (0.5 - ndc.y * 0.5) * self.viewport.y))
        } else {
            None
        };
        Projected { view: view.truncate(), view_depth: -view.z, pixel }
    }
}

/// What the passes make of a grain's centre.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projected {
    /// The centre in view space (eye at the origin).
    pub view: Vec3,
    /// Its depth along the viewing direction (`-view.z`).
    pub view_depth: f32,
    /// Its position in pixels (`x` right, `y` down, pixel `(i, j)` covers `[i, i+1) × [j, j+1)`),
    /// or `None` when it is not in front of the eye (`w ≤ 0`).
    pub pixel: Option<Vec2>,
}

impl Projected {
    /// The pixel holding the centre, clamped to the viewport; `None` behind the eye (or for
    /// a non-finite position). Twin of `split_centre_texel`.
    pub fn centre_texel(&self, (width, height): (u32, u32)) -> Option<(u32, u32)> {
        let pixel = self.pixel?;
        if !pixel.is_finite() {
            return None;
        }
        let clamp = |x: f32, side: u32| x.floor().clamp(0.0, side as f32 - 1.0) as u32;
        Some((clamp(pixel.x, width), clamp(pixel.y, height)))
    }

    /// Whether the centre lies within `ulps` units in the last place (relative to the
    /// viewport size) of a pixel edge, where a division rounded differently on another
    /// adapter could move it to the neighbouring pixel.
    pub fn near_pixel_edge(&self, (width, height): (u32, u32), ulps: f32) -> bool {
        let Some(pixel) = self.pixel else { return false };
        let near = |x: f32, side: u32| {
            let tolerance = ulps * f32::EPSILON * side as f32;
            (x - x.round()).abs() <= tolerance
        };
        near(pixel.x, width) || near(pixel.y, height)
    }
}

/// `m · (p, 1)` as `m₀ p.x + m₁ p.y + m₂ p.z + m₃` (columns `mᵢ`), summed in this order.
/// Twin of `split_transform`.
pub(crate) fn transform(m: &[Vec4; 4], p: Vec3) -> Vec4 {
    m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3]
}

/// The six planes of the frustum of `clip_from_world` (Gribb & Hartmann's rows: `w ± x`,
/// `w ± y`, `z` and `w − z` for wgpu's `[0, 1]` depth), normalised.
fn frustum_planes(clip_from_world: Mat4) -> [Vec4; 6] {
    let [r0, r1, r2, r3] = [0, 1, 2, 3].map(|i| clip_from_world.row(i));
    [r3 + r0, r3 - r0, r3 + r1, r3 - r1, r2, r3 - r2].map(|plane| plane / plane.truncate().length())
}

pub(crate) fn check_viewport((width, height): (u32, u32)) -> Result<(), SplitError> {
    if width == 0 || height == 0 || width > MAX_VIEWPORT_SIDE || height > MAX_VIEWPORT_SIDE {
        return Err(SplitError::InvalidCamera {
            field: "size",
            reason: format!("{width}×{height}: each side must be in 1..={MAX_VIEWPORT_SIDE}"),
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> SplitCamera {
        SplitCamera::perspective(Vec3::new(0.0, 2.0, 10.0), Vec3::ZERO, Vec3::Y, 0.8, (64, 48), (0.1, 100.0)).unwrap()
    }

    #[test]
    fn matrices_equal_the_impostor_camera_bit_for_bit() {
        let ours = camera();
        let theirs = grain_impostor::scene::CameraUniforms::perspective(
            Vec3::new(0.0, 2.0, 10.0),
            Vec3::ZERO,
            Vec3::Y,
            0.8,
            (64, 48),
            (0.1, 100.0),
        )
        .unwrap();
        assert_eq!(ours.clip_from_world, theirs.clip_from_world);
    }

    #[test]
    fn the_target_projects_to_the_centre_and_the_frustum_contains_it() {
        let camera = camera();
        let projected = camera.project(Vec3::ZERO);
        let pixel = projected.pixel.unwrap();
        assert!((pixel - Vec2::new(32.0, 24.0)).length() < 1e-3, "{pixel}");
        assert!((projected.view_depth - Vec3::new(0.0, 2.0, 10.0).length()).abs() < 1e-4);
        for plane in camera.frustum {
            assert!((plane.truncate().length() - 1.0).abs() < 1e-6);
            assert!(plane.truncate().dot(Vec3::ZERO) + plane.w > 0.0);
        }
        // A point behind the eye has no pixel and is outside the near plane.
        let behind = Vec3::new(0.0, 2.5, 12.0);
        assert_eq!(camera.project(behind).pixel, None);
        assert!(camera.frustum[4].truncate().dot(behind) + camera.frustum[4].w < 0.0);
    }

    #[test]
    fn the_focal_length_gives_the_projected_size() {
        // A segment of length L at depth z, perpendicular to the view, spans focal·L/z pixels.
        let camera = camera();
        let direction = Vec3::new(0.0, 2.0, 10.0).normalize();
        let up = Vec3::Y - direction * direction.y;
        let (a, b) = (camera.project(-up.normalize() * 0.5), camera.project(up.normalize() * 0.5));
        let span = (a.pixel.unwrap() - b.pixel.unwrap()).length();
        let expected = camera.projection.x / a.view_depth.min(b.view_depth);
        assert!((span - expected).abs() < 0.01 * expected, "{span} vs {expected}");
    }

    #[test]
    fn bad_cameras_are_errors_naming_the_field() {
        let e = |r: Result<SplitCamera, SplitError>| r.unwrap_err().to_string();
        assert!(
            e(SplitCamera::perspective(Vec3::ZERO, Vec3::ZERO, Vec3::Y, 0.8, (64, 48), (0.1, 1.0))).contains("eye")
        );
        assert!(e(SplitCamera::perspective(Vec3::Z, Vec3::ZERO, Vec3::Z, 0.8, (64, 48), (0.1, 1.0))).contains("up"));
        assert!(e(SplitCamera::perspective(Vec3::Z, Vec3::ZERO, Vec3::Y, 0.8, (0, 48), (0.1, 1.0))).contains("size"));
        assert!(e(SplitCamera::perspective(Vec3::Z, Vec3::ZERO, Vec3::Y, 4.0, (8, 8), (0.1, 1.0))).contains("fov"));
        assert!(e(SplitCamera::perspective(Vec3::Z, Vec3::ZERO, Vec3::Y, 0.8, (8, 8), (1.0, 0.5))).contains("near"));
        let skewed = Mat4::from_cols(Vec4::X, Vec4::Y, Vec4::new(0.0, 0.0, 1.0, -1.0), Vec4::new(0.0, 0.0, 0.0, 1.0));
        assert!(e(SplitCamera::from_matrices(Mat4::IDENTITY, skewed, (8, 8))).contains("clip_from_view"));
    }

    #[test]
    fn orthographic_cameras_are_recognised() {
        let projection = grain_impostor::scene::orthographic_rh(2.0, 0.5, 10.0);
        let camera = SplitCamera::from_matrices(Mat4::IDENTITY, projection, (32, 32)).unwrap();
        assert!(!camera.is_perspective());
        assert!((camera.projection.x - 8.0).abs() < 1e-6, "16 pixels per 2 units");
    }

    #[test]
    fn pixels_clamp_to_the_viewport_and_edges_are_flagged() {
        let p = Projected { view: Vec3::ZERO, view_depth: 1.0, pixel: Some(Vec2::new(-3.0, 70.5)) };
        assert_eq!(p.centre_texel((64, 48)), Some((0, 47)));
        let edge = Projected { pixel: Some(Vec2::new(12.0 + 1e-6, 5.5)), ..p };
        assert!(edge.near_pixel_edge((64, 48), 8.0));
        let inside = Projected { pixel: Some(Vec2::new(12.25, 5.5)), ..p };
        assert!(!inside.near_pixel_edge((64, 48), 8.0));
    }
}
