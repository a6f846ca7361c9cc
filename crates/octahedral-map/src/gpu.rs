//! Structs and constants shared with the WGSL twin, `shaders/octahedral_map.wgsl`.
//!
//! Their WGSL declarations are generated into `shaders/generated/octahedral_map.wgsl` by
//! `cargo xtask codegen`; a test checks that the WGSL layout equals this one.

use glam::{UVec2, UVec4, Vec2, Vec4};
use gpu_layout::{GpuConst, gpu_const, gpu_struct};

use crate::direction::FALLBACK_DIRECTION;
use crate::sampling::{
    MAX_DISTANCE_RATIO, MAX_GRAIN_SCALE, MAX_RAY_ORIGIN_COMPONENT, MAX_TEXTURE_COORDINATE, MAX_WORLD_COMPONENT,
    MIN_GRAIN_SCALE, MIN_PLANE_COSINE, MISS_TEXTURE_COORDINATE,
};
use crate::views::MAX_SUBDIVISIONS;

gpu_struct! {
    /// The four views nearest to a direction and their interpolation coefficients
    /// (Listing 1 of the paper).
    pub struct ViewSample {
        /// `(i0, i1, i2, i3)`: the views at `(⌊u⌋,⌊v⌋)`, `(⌈u⌉,⌊v⌋)`, `(⌊u⌋,⌈v⌉)`,
        /// `(⌈u⌉,⌈v⌉)` of the direction's hemisphere.
        pub indices: UVec4,
        /// `α = fract(u, v)`: `α.x` interpolates `(i0, i2) → (i1, i3)`, `α.y`
        /// interpolates `(i0, i1) → (i2, i3)`.
        pub alpha: Vec2,
        /// Explicit padding to WGSL's 16-byte struct alignment; always zero.
        pub padding: Vec2,
    }
}

impl ViewSample {
    /// The bilinear weights of `indices`, summing to 1:
    /// `((1-αx)(1-αy), αx(1-αy), (1-αx)αy, αx αy)`.
    pub fn weights(&self) -> [f32; 4] {
        let Vec2 { x, y } = self.alpha;
        [(1.0 - x) * (1.0 - y), x * (1.0 - y), (1.0 - x) * y, x * y]
    }
}

gpu_struct! {
    /// Uniforms of a pass that samples an octahedral impostor.
    pub struct OctahedralUniforms {
        /// `n`, the number of views along an edge of a hemisphere's square.
        pub subdivisions: u32,
        /// `N = 2n²`.
        pub view_count: u32,
        /// Explicit padding to 16 bytes (uniform buffers); always zero.
        pub padding: UVec2,
    }
}

impl OctahedralUniforms {
    /// The uniforms of `views`.
    pub fn new(views: crate::OctahedralViews) -> Self {
        Self { subdivisions: views.subdivisions(), view_count: views.view_count(), padding: UVec2::ZERO }
    }
}

gpu_struct! {
    /// Uniforms of a pass that samples quasi-spherical impostors (§5); build them with
    /// [`ImpostorSampler::uniforms`](crate::sampling::ImpostorSampler::uniforms), which
    /// validates the radii.
    pub struct ImpostorSamplingUniforms {
        /// `n`, the number of views along an edge of a hemisphere's square.
        pub subdivisions: u32,
        /// [`SamplingMode`](crate::sampling::SamplingMode) as `u32`: 0 planar, 1 spherical,
        /// 2 mixed.
        pub mode: u32,
        /// [`ViewLayout`](crate::sampling::ViewLayout) as `u32`: 0 Listing 1 indices, 1
        /// compact indices.
        pub view_layout: u32,
        /// [`ViewSelection`](crate::sampling::ViewSelection) as `u32`: 0 per fragment, 1 per
        /// grain (from the eye at the ray origin).
        pub selection: u32,
        /// `R`, the grain's outer radius; also the half-size of each view's square.
        pub outer_radius: f32,
        /// `r`, the grain's inner radius.
        pub inner_radius: f32,
        /// Explicit padding to 16 bytes; always zero.
        pub padding: Vec2,
    }
}

gpu_struct! {
    /// One camera ray in world space and the grain it samples (the layout of
    /// `grain-impostor`'s `GrainInstance` follows the ray): the input of the differential
    /// test kernel of [`sample_impostor`](crate::sampling::sample_impostor).
    pub struct ImpostorRayQuery {
        /// World-space ray origin (`xyz`; `w` ignored).
        pub world_origin: Vec4,
        /// World-space ray direction (`xyz`; need not be unit; `w` ignored).
        pub world_direction: Vec4,
        /// Grain centre (`xyz`) and uniform scale (`w`).
        pub centre_scale: Vec4,
        /// Grain rotation, grain → world, as a quaternion `(x, y, z, w)` (normalized by the
        /// sampler).
        pub rotation: Vec4,
    }
}

gpu_struct! {
    /// The four views to blend for one camera ray, their weights and where to read each
    /// of them (§4.1 steps i–iii, §5).
    pub struct ImpostorSample {
        /// The four views of Listing 1 (or their compact indices, see
        /// [`ViewLayout`](crate::sampling::ViewLayout)), in [`ViewSample`] order.
        pub indices: UVec4,
        /// Bilinear weights of the four views ([`ViewSample::weights`]), summing to 1.
        pub weights: Vec4,
        /// Texture coordinates to read in each view: `(uv0, uv1)` in the first vector,
        /// `(uv2, uv3)` in the second. Coordinates outside `[0, 1]²` mean "transparent";
        /// a miss is exactly `(MISS_TEXTURE_COORDINATE, MISS_TEXTURE_COORDINATE)`; all
        /// coordinates are clamped to `[MISS_TEXTURE_COORDINATE, MAX_TEXTURE_COORDINATE]`.
        pub texture_coordinates: [Vec4; 2],
        /// `d / R`, the distance from the grain centre to the ray's line over the outer
        /// radius (§5), clamped to `[0, MAX_DISTANCE_RATIO]`; `MAX_DISTANCE_RATIO` for an
        /// unusable ray.
        pub distance_ratio: f32,
        /// 1 when the ray meets the proxy sphere of radius `(r + R) / 2`, else 0.
        pub proxy_hit: u32,
        /// Explicit padding to 16 bytes; always zero.
        pub padding: Vec2,
    }
}

impl ImpostorSample {
    /// The texture coordinates of view `k` (0..4) of [`indices`](Self::indices).
    pub fn view_texture_coordinates(&self, k: usize) -> Vec2 {
        let pair = self.texture_coordinates[(k / 2) % 2];
        if k.is_multiple_of(2) { pair.truncate().truncate() } else { Vec2::new(pair.z, pair.w) }
    }
}

/// Constants of this crate that the WGSL twin uses, for `cargo xtask codegen`.
pub const WGSL_CONSTANTS: &[GpuConst] = &[
    gpu_const!(MAX_SUBDIVISIONS: u32 as "OCTAHEDRAL_MAX_SUBDIVISIONS"),
    gpu_const!(FALLBACK_DIRECTION: Vec3 as "OCTAHEDRAL_FALLBACK_DIRECTION"),
    gpu_const!(MISS_TEXTURE_COORDINATE: f32 as "IMPOSTOR_MISS_TEXTURE_COORDINATE"),
    gpu_const!(MAX_TEXTURE_COORDINATE: f32 as "IMPOSTOR_MAX_TEXTURE_COORDINATE"),
    gpu_const!(MIN_PLANE_COSINE: f32 as "IMPOSTOR_MIN_PLANE_COSINE"),
    gpu_const!(MAX_DISTANCE_RATIO: f32 as "IMPOSTOR_MAX_DISTANCE_RATIO"),
    gpu_const!(MAX_RAY_ORIGIN_COMPONENT: f32 as "IMPOSTOR_MAX_RAY_ORIGIN_COMPONENT"),
    gpu_const!(MAX_WORLD_COMPONENT: f32 as "IMPOSTOR_MAX_WORLD_COMPONENT"),
    gpu_const!(MIN_GRAIN_SCALE: f32 as "IMPOSTOR_MIN_GRAIN_SCALE"),
    gpu_const!(MAX_GRAIN_SCALE: f32 as "IMPOSTOR_MAX_GRAIN_SCALE"),
];

/// Per-item layout assertions that do not need naga.
#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn structs_have_the_expected_sizes() {
        assert_eq!(size_of::<ViewSample>(), 32);
        assert_eq!(size_of::<OctahedralUniforms>(), 16);
        assert_eq!(size_of::<ImpostorSamplingUniforms>(), 32);
        assert_eq!(size_of::<ImpostorRayQuery>(), 64);
        assert_eq!(size_of::<ImpostorSample>(), 80);
        let _ = UVec4::ZERO;
    }
}
