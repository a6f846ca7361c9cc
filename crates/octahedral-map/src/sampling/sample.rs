//! What the sampler shares with the GPU: its uniforms ([`ImpostorSamplingUniforms`]) and
//! its result ([`ImpostorSample`]), laid out for WGSL.

use glam::{UVec4, Vec2, Vec4};
use gpu_layout::gpu_struct;

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
    /// The four views to blend for one camera ray, their weights and where to read each
    /// of them (§4.1 steps i–iii, §5).
    pub struct ImpostorSample {
        /// The four views of Listing 1 (or their compact indices, see
        /// [`ViewLayout`](crate::sampling::ViewLayout)), in [`ViewSample`](crate::ViewSample) order.
        pub indices: UVec4,
        /// Bilinear weights of the four views ([`ViewSample::weights`](crate::ViewSample::weights)), summing to 1.
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
