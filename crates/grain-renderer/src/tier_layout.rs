//! The tiers' uniform blocks and constants, declared here and generated into WGSL
//! ([`crate::shaders`]).

use glam::{UVec4, Vec4};
use gpu_layout::{GpuConst, gpu_const, gpu_struct};

/// A pixel no grain covers, or past a list's end.
pub const TIER_NONE: u32 = u32::MAX;
/// The owner of a pixel the mesh tier covers (composite mode).
pub const TIER_MESH: u32 = u32::MAX - 1;
/// The largest screen rectangle, in pixels, splatted by one invocation.
pub const TIER_SMALL_PIXELS: u32 = 64;
/// Counters in [`ImpostorTier::stats`](crate::ImpostorTier::stats): evaluated pixels of the first and second list,
/// early-Z skips of the first and second list, resolved impostor pixels, resolved point pixels.
pub const TIER_STATS: u32 = 6;
/// The bit of a visibility-buffer owner that marks a grain of the point list (grain indices
/// stay below it).
pub const TIER_POINT_BIT: u32 = 1 << 31;
/// `u32` sums per pixel of the point tier: weight, albedo (3), normal (3), roughness.
pub const TIER_POINT_SUMS: u32 = 8;
/// The largest radius, in pixels, of a point grain's disc (a grain that large belongs to the
/// impostor tier; the bound caps one invocation's work at 9 × 9 pixels).
pub const TIER_POINT_MAX_RADIUS: f32 = 4.0;
/// Fixed-point scale of the point tier's sums: 10 bits per value in `[0, 1]` (sums of up to
/// 4·10⁶ grains per pixel fit a `u32`).
pub const TIER_POINT_SCALE: f32 = 1023.0;
/// Flag bit of [`TierUniforms::counts`]: composite over the mesh tier's depth.
pub const TIER_COMPOSITE: u32 = 1;
/// The early-Z reach over `R·s`: `√2`, raised by one part in 10⁶ to round up.
pub const TIER_REACH: f32 = std::f32::consts::SQRT_2 * 1.000_001;
/// Relative slack of the early-Z bound (`2⁻¹²` of the magnitudes involved; `f32` rounding
/// is `2⁻²⁴` of them).
pub const TIER_DEPTH_SLACK: f32 = 1.0 / 4096.0;

/// The most visibility samples per pixel side ([`ImpostorTier::with_samples`](crate::ImpostorTier::with_samples)).
pub const TIER_MAX_SAMPLES: u32 = 4;

/// Words of [`ImpostorTier`](crate::ImpostorTier)'s argument buffer: per impostor list,
/// the dispatch of its large grains (3 words), then per impostor list the raster path's
/// `draw_indirect` arguments (4 words: 6 vertices, one instance per element).
pub const TIER_ARGUMENT_WORDS: u32 = 14;
/// The first word of the raster path's draw arguments in the argument buffer.
pub const TIER_DRAW_ARGUMENTS: u32 = 6;

/// The constants the shaders share with this module.
pub(crate) const TIER_CONSTANTS: &[GpuConst] = &[
    gpu_const!(TIER_NONE: u32),
    gpu_const!(TIER_MESH: u32),
    gpu_const!(TIER_SMALL_PIXELS: u32),
    gpu_const!(TIER_STATS: u32),
    gpu_const!(TIER_POINT_BIT: u32),
    gpu_const!(TIER_POINT_SUMS: u32),
    gpu_const!(TIER_POINT_SCALE: f32),
    gpu_const!(TIER_POINT_MAX_RADIUS: f32),
    gpu_const!(TIER_COMPOSITE: u32),
    gpu_const!(TIER_REACH: f32),
    gpu_const!(TIER_DEPTH_SLACK: f32),
    gpu_const!(TIER_DRAW_ARGUMENTS: u32),
];

gpu_struct! {
    /// Per-frame settings of the tier.
    pub struct TierUniforms {
        /// `(instance count, flags, samples per pixel side, 0)`.
        pub counts: UVec4,
        /// `(first list, second list, 0, 0)`: the splitter's list indices drawn in order.
        pub lists: UVec4,
        /// Raster path: `(depth scale, its inverse, 0, 0)`, powers of two that map view
        /// depths up to the far plane into the depth attachment's `[0, 1]` exactly
        /// ([`raster_depth_scale`](crate::impostor_raster::raster_depth_scale)).
        pub raster: Vec4,
    }
}

gpu_struct! {
    /// What one splat dispatch draws (one entry per list and pass, dynamic offsets).
    pub struct TierPass {
        /// The splitter's list index.
        pub list: u32,
        /// 1: skip pixels whose stored depth is nearer than the grain can be.
        pub early_z: u32,
        /// 32-bit path: 0 the depth pass, 1 the owner pass.
        pub owner_pass: u32,
        /// Which counters of [`ImpostorTier::stats`](crate::ImpostorTier::stats) this pass adds to (0 or 1).
        pub slot: u32,
    }
}

gpu_struct! {
    /// The mesh tier's settings.
    pub struct MeshTierUniforms {
        /// `(the splitter's mesh list, 0, 0, 0)`.
        pub list: UVec4,
        /// The point of the mesh's frame placed at each grain's centre (its bounds centre),
        /// `w` unused.
        pub centre: Vec4,
    }
}
