//! The crate's WGSL twin (feature `wgsl`): the generated declarations of the structs and
//! constants below, and the functions of `wgsl/octahedral_map.wgsl`, each the twin of the
//! Rust function named in its comment.

use gpu_layout::f32_bits::{ABS_MASK, INFINITY_BITS, SIGN_MASK};
use gpu_layout::{StructDecl, WgslModule, gpu_const};

use crate::direction::{FALLBACK_DIRECTION, PLAIN_END_BITS, PLAIN_MIN_BITS};
use crate::sampling::{
    ImpostorSample, ImpostorSamplingUniforms, MAX_DISTANCE_RATIO, MAX_GRAIN_SCALE, MAX_RAY_ORIGIN_COMPONENT,
    MAX_TEXTURE_COORDINATE, MAX_WORLD_COMPONENT, MIN_GRAIN_SCALE, MIN_PLANE_COSINE, MISS_TEXTURE_COORDINATE,
};
use crate::views::{MAX_SUBDIVISIONS, ViewSample};

/// The WGSL twin of this crate: the view layout (`octahedral_view_sample`,
/// `octahedral_view_direction`, …, Listing 1), the compact layout, the view frames and the
/// impostor sampler (`impostor_sample`, §5); no dependencies.
pub const WGSL: WgslModule = WgslModule {
    name: "octahedral_map",
    declarations: include_str!("../wgsl/generated/octahedral_map.wgsl"),
    library: include_str!("../wgsl/octahedral_map.wgsl"),
    naga_oil_source: concat!(
        include_str!("../wgsl/generated/octahedral_map.naga_oil_header.wgsl"),
        include_str!("../wgsl/generated/octahedral_map.wgsl"),
        include_str!("../wgsl/octahedral_map.wgsl"),
    ),
    dependencies: &[],
    structs: &[
        StructDecl::of::<ViewSample>(),
        StructDecl::of::<ImpostorSamplingUniforms>(),
        StructDecl::of::<ImpostorSample>(),
    ],
    constants: &[
        gpu_const!(MAX_SUBDIVISIONS: u32 as "OCTAHEDRAL_MAX_SUBDIVISIONS"),
        gpu_const!(FALLBACK_DIRECTION: Vec3 as "OCTAHEDRAL_FALLBACK_DIRECTION"),
        gpu_const!(ABS_MASK: u32 as "OCTAHEDRAL_ABS_MASK"),
        gpu_const!(SIGN_MASK: u32 as "OCTAHEDRAL_SIGN_MASK"),
        gpu_const!(INFINITY_BITS: u32 as "OCTAHEDRAL_INFINITY_BITS"),
        gpu_const!(PLAIN_MIN_BITS: u32 as "OCTAHEDRAL_PLAIN_MIN_BITS"),
        gpu_const!(PLAIN_END_BITS: u32 as "OCTAHEDRAL_PLAIN_END_BITS"),
        gpu_const!(MISS_TEXTURE_COORDINATE: f32 as "IMPOSTOR_MISS_TEXTURE_COORDINATE"),
        gpu_const!(MAX_TEXTURE_COORDINATE: f32 as "IMPOSTOR_MAX_TEXTURE_COORDINATE"),
        gpu_const!(MIN_PLANE_COSINE: f32 as "IMPOSTOR_MIN_PLANE_COSINE"),
        gpu_const!(MAX_DISTANCE_RATIO: f32 as "IMPOSTOR_MAX_DISTANCE_RATIO"),
        gpu_const!(MAX_RAY_ORIGIN_COMPONENT: f32 as "IMPOSTOR_MAX_RAY_ORIGIN_COMPONENT"),
        gpu_const!(MAX_WORLD_COMPONENT: f32 as "IMPOSTOR_MAX_WORLD_COMPONENT"),
        gpu_const!(MIN_GRAIN_SCALE: f32 as "IMPOSTOR_MIN_GRAIN_SCALE"),
        gpu_const!(MAX_GRAIN_SCALE: f32 as "IMPOSTOR_MAX_GRAIN_SCALE"),
    ],
};

#[cfg(test)]
mod tests {
    use super::*;

    /// Layout sizes that do not need naga (the registry's tests compare every field's
    /// offset with naga's layout).
    #[test]
    fn structs_have_the_expected_sizes() {
        assert_eq!(size_of::<ViewSample>(), 32);
        assert_eq!(size_of::<ImpostorSamplingUniforms>(), 32);
        assert_eq!(size_of::<ImpostorSample>(), 80);
    }
}
