//! One frame's inputs: the camera, the shading settings and the timestamp sets.

use ddm_tracer::tangent_space::BaseRenderParams;
use glam::{Vec3, Vec4};

use crate::camera::Camera;
use crate::error::DdmRenderError;
use crate::gbuffer::PassTimestamps;

/// Everything the per-pixel pass needs per frame besides the camera: the mapping of the
/// mesostructure's slab onto the base mesh, the light, shadows and the miss colour
/// (written with the camera's eye as the frame's [`BaseRenderParams`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderSettings {
    /// `(L_x, L_y, L_z / h)`: voxels per texture unit along `u` and `v`, voxels per world
    /// unit along `−N` (see `ddm_tracer::tangent_space`). Finite and positive.
    pub slab: Vec3,
    /// Direction toward the (directional) light, world space, normally unit. Finite, non-zero.
    pub light: Vec3,
    /// Ambient term in `[0, 1]`.
    pub ambient: f32,
    /// Shadow rays: how far short of the shaded point (voxels) a hit must be to shadow it
    /// (finite, ≥ 0); `None` casts no shadow ray.
    pub shadow_tolerance: Option<f32>,
    /// Colour of the base mesh where the ray misses the mesostructure (linear RGB, finite);
    /// `None` draws no base surface: such a pixel shows what lies behind, as where the ray
    /// leaves the base mesh's solid (an object standing alone on its base, like a tile
    /// built with `periodic_xy: false` holding one ball).
    pub miss_color: Option<Vec3>,
    /// The mesostructure's albedo (linear RGB, finite and ≥ 0): [`DEFAULT_ALBEDO`] is
    /// `xtask ddm-render`'s warm sand.
    pub albedo: Vec3,
    /// How much of the albedo is replaced by the shading normal's colour `0.5 n + 0.5`
    /// (in `[0, 1]`; [`DEFAULT_NORMAL_TINT`]), so that the relief reads in the images.
    pub normal_tint: f32,
}

/// The albedo of `xtask ddm-render`'s images.
pub const DEFAULT_ALBEDO: Vec3 = Vec3::new(0.85, 0.72, 0.5);
/// The normal tint of `xtask ddm-render`'s images.
pub const DEFAULT_NORMAL_TINT: f32 = 0.3;

impl RenderSettings {
    /// The frame's [`BaseRenderParams`] for a camera at `eye`. Errors name the field that
    /// is out of range.
    pub fn params(&self, eye: Vec3) -> Result<BaseRenderParams, DdmRenderError> {
        if !(self.slab.is_finite() && self.slab.min_element() > 0.0) {
            return Err(DdmRenderError::InvalidSettings("slab must be finite and positive"));
        }
        if !(self.light.is_finite() && self.light.length_squared() > 0.0) {
            return Err(DdmRenderError::InvalidSettings("light must be finite and non-zero"));
        }
        if !(0.0..=1.0).contains(&self.ambient) {
            return Err(DdmRenderError::InvalidSettings("ambient must lie in [0, 1]"));
        }
        let tolerance = match self.shadow_tolerance {
            Some(t) if t.is_finite() && t >= 0.0 => t,
            Some(_) => return Err(DdmRenderError::InvalidSettings("shadow_tolerance must be finite and ≥ 0")),
            None => -1.0,
        };
        if !self.miss_color.is_none_or(Vec3::is_finite) {
            return Err(DdmRenderError::InvalidSettings("miss_color must be finite"));
        }
        if !(self.albedo.is_finite() && self.albedo.min_element() >= 0.0) {
            return Err(DdmRenderError::InvalidSettings("albedo must be finite and ≥ 0"));
        }
        if !(0.0..=1.0).contains(&self.normal_tint) {
            return Err(DdmRenderError::InvalidSettings("normal_tint must lie in [0, 1]"));
        }
        if !eye.is_finite() {
            return Err(DdmRenderError::InvalidCamera("eye must be finite"));
        }
        Ok(BaseRenderParams {
            eye: eye.extend(0.0),
            light: self.light.extend(self.ambient),
            slab: self.slab.extend(tolerance),
            miss_color: self.miss_color.map_or(Vec4::ZERO, |c| c.extend(1.0)),
            albedo: self.albedo.extend(self.normal_tint),
        })
    }
}

/// One frame's inputs.
#[derive(Clone, Copy, Debug)]
pub struct DdmFrame<'a> {
    /// The camera; its size must be the G-buffer's.
    pub camera: &'a Camera,
    /// Slab mapping, light, shadows, miss colour.
    pub settings: RenderSettings,
    /// Where the raster pass writes its beginning and end timestamps, if anywhere.
    pub raster_timestamps: Option<PassTimestamps<'a>>,
    /// Where the per-pixel pass writes its beginning and end timestamps, if anywhere.
    pub trace_timestamps: Option<PassTimestamps<'a>>,
}

impl<'a> DdmFrame<'a> {
    /// A frame without timestamps.
    pub fn new(camera: &'a Camera, settings: RenderSettings) -> Self {
        Self { camera, settings, raster_timestamps: None, trace_timestamps: None }
    }
}
