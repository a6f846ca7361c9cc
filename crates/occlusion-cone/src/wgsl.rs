//! The crate's WGSL twin (feature `wgsl`): the generated constants below and the functions
//! of `wgsl/occlusion_cone.wgsl`, each the twin of the Rust function named in its comment.

use gpu_layout::f32_bits::ABS_MASK;
use gpu_layout::{WgslModule, gpu_const};

use crate::cone::{APEX_ROUNDING, EYE_CLEARANCE, MARGIN, MAX_COORDINATE, MAX_RADIUS, MIN_RADIUS};

/// The WGSL twin of this crate: `occlusion_in_domain` and `occlusion_is_occluded` (the
/// test of [`is_occluded_by`](crate::is_occluded_by) on `vec4(centre, radius)` spheres, the
/// layout of an occluder-map texel); no dependencies.
pub const WGSL: WgslModule = WgslModule {
    name: "occlusion_cone",
    declarations: include_str!("../wgsl/generated/occlusion_cone.wgsl"),
    library: include_str!("../wgsl/occlusion_cone.wgsl"),
    naga_oil_source: concat!(
        include_str!("../wgsl/generated/occlusion_cone.naga_oil_header.wgsl"),
        include_str!("../wgsl/generated/occlusion_cone.wgsl"),
        include_str!("../wgsl/occlusion_cone.wgsl"),
    ),
    dependencies: &[],
    structs: &[],
    constants: &[
        gpu_const!(MAX_COORDINATE: f32 as "OCCLUSION_MAX_COORDINATE"),
        gpu_const!(MIN_RADIUS: f32 as "OCCLUSION_MIN_RADIUS"),
        gpu_const!(MAX_RADIUS: f32 as "OCCLUSION_MAX_RADIUS"),
        gpu_const!(MARGIN: f32 as "OCCLUSION_MARGIN"),
        gpu_const!(APEX_ROUNDING: f32 as "OCCLUSION_APEX_ROUNDING"),
        gpu_const!(EYE_CLEARANCE: f32 as "OCCLUSION_EYE_CLEARANCE"),
        gpu_const!(ABS_MASK: u32 as "OCCLUSION_ABS_MASK"),
    ],
};
