//! The splitter's settings, validated, and the uniform block the shaders read them from.

use glam::{UVec4, Vec4};
use gpu_layout::{GpuConst, gpu_const, gpu_struct};

use crate::error::SplitError;
use crate::tiers::TierThresholds;

/// The paper's splat size for the occluder map (§8: "between 0.15 to 0.20 times the inner
/// radius r"): the half-side of a grain's square, in pixels, is this factor times its
/// projected inner radius.
pub const DEFAULT_SPLAT_FACTOR: f32 = 0.2;

/// The largest half-side of an occluder-map square, in pixels. It bounds one invocation's
/// work for grains near the camera (a square of at most `(2·8 + 1)²` texels); a smaller
/// square only leaves some texels to farther occluders, which keeps the culling
/// conservative.
pub const MAX_SPLAT_HALF: f32 = 8.0;

/// Relative rounding margin of the frustum test: a grain is outside a plane only when its
/// signed distance is below `-(R s) - FRUSTUM_MARGIN·(|n_x c_x| + |n_y c_y| + |n_z c_z| + |d| + R s)`.
/// The dot product's rounding error is below `3·2⁻²⁴` times that sum and the planes are
/// normalised to a few ulp; `2⁻¹⁶` covers both with room for the camera's own rounding.
pub const FRUSTUM_MARGIN: f32 = 1.0 / 65_536.0;

/// Flag bit: frustum culling on.
pub const FLAG_FRUSTUM: u32 = 1;
/// Flag bit: occlusion culling (Listing 2) on.
pub const FLAG_CONE: u32 = 2;
/// Flag bit: hysteresis on (off: every frame uses the plain thresholds).
pub const FLAG_HYSTERESIS: u32 = 4;
/// Flag bit: the Hi-Z test of the fused occluders on ([`crate::hiz`]).
pub const FLAG_HIZ: u32 = 8;
/// Flag bit: two-phase culling on (last frame's visible grains cover their discs,
/// [`crate::temporal`]); only with [`FLAG_HIZ`].
pub const FLAG_TEMPORAL: u32 = 16;

/// What the splitter does with each grain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SplitSettings {
    /// Radius of the ball about a grain's centre that is filled with material, at scale 1
    /// (`grain_mesh::GrainBounds::occluder_radius`: `r` when the centre is inside the solid,
    /// 0 for a grain with a hole such as the nut). 0 disables occlusion culling.
    pub occluder_radius: f32,
    /// `R`, the outer radius at scale 1.
    pub outer_radius: f32,
    /// Occluder-map splat half-side over the projected occluder radius
    /// ([`DEFAULT_SPLAT_FACTOR`]); in `(0, 4]`.
    pub splat_factor: f32,
    /// Tier thresholds and hysteresis.
    pub thresholds: TierThresholds,
    /// Cull grains outside the frustum.
    pub frustum_culling: bool,
    /// Cull grains hidden by their occluder (Listing 2, `occlusion-cone`).
    pub cone_culling: bool,
    /// Cull grains hidden by the fused occluders of the pixels they cover (beyond the paper:
    /// a max pyramid of per-pixel depth bounds, [`crate::hiz`]; perspective cameras only).
    pub hiz_culling: bool,
    /// With `hiz_culling`: the grains the previous frame kept splat their inscribed squares
    /// into the pyramid's first level (temporal two-phase culling, [`crate::temporal`]).
    pub temporal_occluders: bool,
    /// Index count of the mesh tier's mesh (the indexed indirect draws' first argument).
    pub mesh_index_count: u32,
    /// Vertex count of one impostor or point sprite (the non-indexed draws').
    pub sprite_vertex_count: u32,
}

impl SplitSettings {
    /// Settings with the paper's splat factor, every culling on, and no draw sizes.
    pub fn new(occluder_radius: f32, outer_radius: f32, thresholds: TierThresholds) -> Self {
        Self {
            occluder_radius,
            outer_radius,
            splat_factor: DEFAULT_SPLAT_FACTOR,
            thresholds,
            frustum_culling: true,
            cone_culling: true,
            hiz_culling: true,
            temporal_occluders: true,
            mesh_index_count: 0,
            sprite_vertex_count: 6,
        }
    }

    /// Checks every field; the error names the first bad one.
    pub fn validate(&self) -> Result<(), SplitError> {
        let bad = |field: &'static str, reason: String| Err(SplitError::InvalidSetting { field, reason });
        if !(self.outer_radius.is_finite() && self.outer_radius > 0.0) {
            return bad("outer_radius", format!("{}: must be finite and positive", self.outer_radius));
        }
        if !(self.occluder_radius.is_finite() && (0.0..=self.outer_radius).contains(&self.occluder_radius)) {
            return bad("occluder_radius", format!("{}: must be in [0, outer_radius]", self.occluder_radius));
        }
        if !(self.splat_factor.is_finite() && self.splat_factor > 0.0 && self.splat_factor <= 4.0) {
            return bad("splat_factor", format!("{}: must be in (0, 4]", self.splat_factor));
        }
        Ok(())
    }

    /// The uniform block for `grain_count` grains and an occluder map whose ids are
    /// `id_stride` words apart (2: the 64-bit map, 1: the 32-bit one); `hiz`: whether the
    /// Hi-Z test runs this frame ([`SplitSettings::hiz_applies`], in [`crate::hiz`]).
    pub(crate) fn params(&self, grain_count: u32, id_stride: u32, blocks: u32, hiz: bool) -> SplitParams {
        let flags = if self.frustum_culling { FLAG_FRUSTUM } else { 0 }
            | if self.cone_culling && self.occluder_radius > 0.0 { FLAG_CONE } else { 0 }
            | if hiz { FLAG_HIZ } else { 0 }
            | if hiz && self.temporal_occluders { FLAG_TEMPORAL } else { 0 }
            | if self.thresholds.band() > 1.0 { FLAG_HYSTERESIS } else { 0 };
        let [pu, pd, pp] = self.thresholds.point_boundary();
        let [mu, md, mp] = self.thresholds.mesh_boundary();
        SplitParams {
            counts: UVec4::new(grain_count, id_stride, flags, blocks),
            radii: Vec4::new(self.occluder_radius, self.outer_radius, self.splat_factor, MAX_SPLAT_HALF),
            point_thresholds: Vec4::new(pu, pd, pp, 0.0),
            mesh_thresholds: Vec4::new(mu, md, mp, 0.0),
            draw: UVec4::new(self.mesh_index_count, self.sprite_vertex_count, 0, 0),
        }
    }
}

gpu_struct! {
    /// The settings as the shaders read them.
    pub struct SplitParams {
        /// `(grain count, occluder-map id stride, flags, grain blocks)`.
        pub counts: UVec4,
        /// `(occluder radius r, outer radius R, splat factor, largest splat half-side)`.
        pub radii: Vec4,
        /// `(up, down, plain, 0)` thresholds of the point | impostor boundary (pixels).
        pub point_thresholds: Vec4,
        /// `(up, down, plain, 0)` thresholds of the impostor | mesh boundary (pixels).
        pub mesh_thresholds: Vec4,
        /// `(mesh index count, sprite vertex count, 0, 0)`.
        pub draw: UVec4,
    }
}

/// The constants the shaders share with this module.
pub const SETTINGS_CONSTANTS: &[GpuConst] = &[
    gpu_const!(FRUSTUM_MARGIN: f32),
    gpu_const!(FLAG_FRUSTUM: u32),
    gpu_const!(FLAG_CONE: u32),
    gpu_const!(FLAG_HYSTERESIS: u32),
    gpu_const!(FLAG_HIZ: u32),
    gpu_const!(FLAG_TEMPORAL: u32),
];

#[cfg(test)]
mod tests {
    use super::*;

    fn settings() -> SplitSettings {
        SplitSettings::new(0.5, 1.0, TierThresholds::new(2.0, 40.0, 1.1).unwrap())
    }

    #[test]
    fn bad_settings_name_the_field() {
        let e = |s: SplitSettings| s.validate().unwrap_err().to_string();
        assert!(settings().validate().is_ok());
        assert!(e(SplitSettings { outer_radius: 0.0, ..settings() }).contains("outer_radius"));
        assert!(e(SplitSettings { occluder_radius: 2.0, ..settings() }).contains("occluder_radius"));
        assert!(e(SplitSettings { occluder_radius: -0.1, ..settings() }).contains("occluder_radius"));
        assert!(e(SplitSettings { splat_factor: 0.0, ..settings() }).contains("splat_factor"));
    }

    #[test]
    fn flags_follow_the_settings() {
        let p = settings().params(10, 2, 1, false);
        assert_eq!(p.counts.z, FLAG_FRUSTUM | FLAG_CONE | FLAG_HYSTERESIS);
        let no_occluder = SplitSettings { occluder_radius: 0.0, ..settings() }.params(10, 2, 1, false);
        assert_eq!(no_occluder.counts.z & FLAG_CONE, 0, "a grain with no solid core cannot occlude");
    }
}
