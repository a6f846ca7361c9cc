//! Occluder fusion on the GPU: the per-pixel depth bound of [`fusion`](mod@crate::fusion) in
//! `f32`, its max pyramid (a "max Hi-Z"), and the grain test the splitter runs after the cone
//! test (model [`CULLED_HIZ`](crate::lists::CULLED_HIZ)).
//!
//! # Rounding
//!
//! The `f64` reference's argument holds for exact arithmetic. In `f32` each quantity is
//! computed with a few rounding errors of relative size `2⁻²⁴` of the magnitudes involved:
//! the view-space centres (`|view| + |world|`), the pixel rays and the entry distances. The
//! shaders absorb them with a **slack** `σ = HIZ_SLACK · (|g| + |c|)` per ball (`g` its view
//! centre, `c` its world centre, [`HIZ_SLACK`] = `2⁻¹⁴`, about 500 times the errors):
//!
//! - an occluder's inner ball is **shrunk** to `r − σ` before its pixel bound is computed:
//!   a computed ray within `σ` of the exact one that enters the shrunk ball at `t` has the
//!   exact ray inside the true ball at `t`, so the bound stays above the exact entry; the
//!   bound is raised by the relative [`HIZ_DEPTH_MARGIN`] for the rounding of `t` itself;
//!   balls with `|g| ≤ 2(r − σ)` (the eye within a diameter) get no bound, so that
//!   `|g|² − r²` cannot cancel;
//! - a tested grain's outer ball is **grown** to `R + σ` for its rectangle, whose edges are
//!   widened by [`HIZ_RECT_MARGIN_PX`], and its nearest distance is taken as
//!   `(|g| − R − σ)(1 − HIZ_DEPTH_MARGIN)`;
//! - the pixel footprints are widened by [`HIZ_FOOTPRINT_MARGIN_PX`] (the rasteriser's own
//!   sub-pixel rounding), as in the reference.
//!
//! The rectangle's tangent-plane quadratic is evaluated in a form without cancellation:
//! its discriminant `q₁² − q₂q₀` equals `R²(|z·a + (a·g) ẑ|² − R²(a_x² + a_y²))` (expand both
//! sides), `z` the view depth and `a` the `x` or `y` row of the projection.
//!
//! Every bound is thus at least the reference's, every rectangle contains the reference's,
//! and every grain the GPU hides the reference hides too: the GPU test checks both, pixel by
//! pixel and grain by grain, and renders the scene with and without culling.

use glam::{DVec3, UVec4, Vec4};
use gpu_layout::{GpuConst, gpu_const, gpu_struct};

use crate::camera::SplitCamera;
use crate::rays::Rays;
use crate::settings::SplitSettings;

/// Relative slack per ball (module docs): `2⁻¹⁴` of `|view centre| + |world centre|`.
pub const HIZ_SLACK: f32 = 1.0 / 16_384.0;
/// Relative margin on the depth bounds and nearest distances (`2⁻¹⁶`).
pub const HIZ_DEPTH_MARGIN: f32 = 1.0 / 65_536.0;
/// How far (pixels) each pixel's footprint is widened, as the reference's
/// [`FOOTPRINT_MARGIN_PX`](crate::fusion::FOOTPRINT_MARGIN_PX).
pub const HIZ_FOOTPRINT_MARGIN_PX: f32 = 1e-3;
/// How far (pixels) a grain's rectangle is widened before its texels are chosen.
pub const HIZ_RECT_MARGIN_PX: f32 = 1.0 / 64.0;
/// Half-side of a grain's square in two-phase culling's phase 1 over its projected inner
/// radius: about the square inscribed in the projected disc (`1/√2`), so that most of its
/// pixels have all four corner rays inside the ball ([`crate::temporal`]).
pub const HIZ_COVER_FACTOR: f32 = 0.7;
/// A texel with no bound (no occluder covers its whole footprint).
pub const HIZ_NONE: f32 = f32::MAX;
/// The most pyramid levels (a side of [`MAX_VIEWPORT_SIDE`](crate::camera::MAX_VIEWPORT_SIDE)
/// = 2¹⁵ halves 15 times down to 1).
pub const HIZ_MAX_LEVELS: u32 = 16;
/// Side of the 2-D workgroups of the pyramid passes.
pub const HIZ_WORKGROUP: u32 = 8;

gpu_struct! {
    /// What the pyramid passes and the grain test read: the pixel rays, the projection's
    /// rows and the pyramid's levels.
    pub struct HizParams {
        /// View-space direction (not normalised) of the ray through the screen point
        /// `(0, 0)`: the ray through `(x, y)` (pixels, `y` down) is
        /// `ray_origin + x·ray_dx + y·ray_dy`.
        pub ray_origin: Vec4,
        /// Change of the ray direction per pixel in `x`.
        pub ray_dx: Vec4,
        /// Change of the ray direction per pixel in `y`.
        pub ray_dy: Vec4,
        /// The `x` row of `clip_from_view` (xyz): `ndc_x = row_x·v / (−v_z)`.
        pub row_x: Vec4,
        /// The `y` row.
        pub row_y: Vec4,
        /// `(width, height, levels, 0)`.
        pub size: UVec4,
        /// Per level: `(width, height, first texel, 0)`; level 0 is the screen.
        pub levels: [UVec4; 16],
    }
}

/// One level of the pyramid, as [`HizParams::levels`] stores it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PyramidLevel {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Index of its first texel in the pyramid buffer (levels are stored one after another,
    /// row-major).
    pub offset: u32,
}

/// The levels of the pyramid of a `width × height` screen, halving (rounding up) down to
/// 1 × 1, as [`DepthPyramid`](crate::DepthPyramid) builds them.
pub fn pyramid_levels((width, height): (u32, u32)) -> Vec<PyramidLevel> {
    let mut levels = vec![PyramidLevel { width, height, offset: 0 }];
    while let Some(&last) = levels.last().filter(|l| l.width > 1 || l.height > 1) {
        levels.push(PyramidLevel {
            width: last.width.div_ceil(2),
            height: last.height.div_ceil(2),
            offset: last.offset + last.width * last.height,
        });
    }
    levels
}

/// Texels in all levels of the pyramid of a screen.
pub fn pyramid_texels(size: (u32, u32)) -> u64 {
    pyramid_levels(size).iter().map(|l| u64::from(l.width) * u64::from(l.height)).sum()
}

impl HizParams {
    /// The parameters for `camera`; `None` where fusion does not apply (an orthographic
    /// camera, or a perspective matrix whose pixel rays miss the eye: see
    /// [`fusion`](mod@crate::fusion)).
    pub fn new(camera: &SplitCamera) -> Option<Self> {
        let rays = Rays::new(camera)?;
        let (origin, dx, dy) = rays.affine();
        let v = |d: DVec3| d.as_vec3().extend(0.0);
        let size = camera.size();
        let levels = pyramid_levels(size);
        let mut table = [UVec4::ZERO; 16];
        for (slot, level) in table.iter_mut().zip(&levels) {
            *slot = UVec4::new(level.width, level.height, level.offset, 0);
        }
        Some(Self {
            ray_origin: v(origin),
            ray_dx: v(dx),
            ray_dy: v(dy),
            row_x: v(rays.a),
            row_y: v(rays.b),
            size: UVec4::new(size.0, size.1, levels.len() as u32, 0),
            levels: table,
        })
    }
}

impl SplitSettings {
    /// Whether the Hi-Z test runs for `camera` (on, a solid core, a camera fusion covers).
    pub fn hiz_applies(&self, camera: &SplitCamera) -> bool {
        self.hiz_culling && self.occluder_radius > 0.0 && HizParams::new(camera).is_some()
    }
}

/// The constants the shaders share with this module.
pub const HIZ_CONSTANTS: &[GpuConst] = &[
    gpu_const!(HIZ_SLACK: f32),
    gpu_const!(HIZ_DEPTH_MARGIN: f32),
    gpu_const!(HIZ_FOOTPRINT_MARGIN_PX: f32),
    gpu_const!(HIZ_RECT_MARGIN_PX: f32),
    gpu_const!(HIZ_COVER_FACTOR: f32),
    gpu_const!(HIZ_NONE: f32),
    gpu_const!(HIZ_MAX_LEVELS: u32),
    gpu_const!(HIZ_WORKGROUP: u32),
];

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn levels_halve_down_to_one_texel_and_are_stored_one_after_another() {
        let levels = pyramid_levels((1920, 1080));
        assert_eq!(levels.len(), 12);
        assert_eq!((levels[1].width, levels[1].height, levels[1].offset), (960, 540, 1920 * 1080));
        assert_eq!((levels[11].width, levels[11].height), (1, 1));
        let largest = pyramid_levels((1 << 15, 1));
        assert_eq!(largest.len() as u32, HIZ_MAX_LEVELS);
        assert_eq!(pyramid_texels((3, 1)), 3 + 2 + 1);
        assert_eq!(pyramid_levels((1, 1)).len(), 1);
    }

    #[test]
    fn the_affine_rays_are_the_reference_rays() {
        let camera =
            SplitCamera::perspective(Vec3::new(3.0, 4.0, 20.0), Vec3::ZERO, Vec3::Y, 0.8, (160, 90), (0.1, 100.0))
                .unwrap();
        let params = HizParams::new(&camera).unwrap();
        let rays = Rays::new(&camera).unwrap();
        for (x, y) in [(0.0, 0.0), (160.0, 0.0), (17.5, 80.25), (160.0, 90.0)] {
            let affine = (params.ray_origin + params.ray_dx * x + params.ray_dy * y).truncate().as_dvec3();
            let reference = rays.direction(f64::from(x), f64::from(y));
            assert!(affine.normalize().distance(reference) < 1e-6, "{x}, {y}");
        }
        let ortho = SplitCamera::from_matrices(
            glam::Mat4::IDENTITY,
            grain_impostor::scene::orthographic_rh(2.0, 0.5, 10.0),
            (64, 64),
        )
        .unwrap();
        assert!(HizParams::new(&ortho).is_none(), "no fusion for orthographic cameras");
    }
}
