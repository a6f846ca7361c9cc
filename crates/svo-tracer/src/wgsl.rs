//! The crate's WGSL twin (feature `wgsl`): the generated declarations of [`GpuCamera`],
//! [`GpuTraceSettings`] and the constants below, and the functions of
//! `wgsl/svo_tracer.wgsl`, each the twin of the Rust function named in its comment.
//! Composed after `svo-brick`'s, `abuffer-mask`'s and `smith-micro`'s twins.

use gpu_layout::{StructDecl, WgslModule, gpu_const};

use crate::gpu::{GpuCamera, GpuTraceSettings};
use crate::lambert::{FRAC_1_SQRT_2, FRAC_1_SQRT_2PI, RECTIFIED_CUTOFF};
use crate::trace::{ERROR_BOUND_FACTOR, Model, SHADING_POINT_REFINEMENTS, SHADOW_LIFT_VOXELS};

/// The WGSL twin of this crate: `svo_pixel_cone` (the camera's cone of a pixel),
/// `svo_trace_cone` (Algorithm 1 with the four models, depth of field, shadow cones and the
/// empty-space skip) and what they are made of (`svo_element_radiance`, `svo_march_next`,
/// `svo_light_visibility`, …). The octree's pools are bound at 3–7 (by `svo_brick`), the
/// mask table's words at 8.
pub const WGSL: WgslModule = WgslModule {
    name: "svo_tracer",
    declarations: include_str!("../wgsl/generated/svo_tracer.wgsl"),
    library: include_str!("../wgsl/svo_tracer.wgsl"),
    naga_oil_source: concat!(
        include_str!("../wgsl/generated/svo_tracer.naga_oil_header.wgsl"),
        include_str!("../wgsl/generated/svo_tracer.wgsl"),
        include_str!("../wgsl/svo_tracer.wgsl"),
    ),
    dependencies: &[&svo_brick::WGSL, &abuffer_mask::WGSL, &smith_micro::WGSL],
    structs: &[StructDecl::of::<GpuCamera>(), StructDecl::of::<GpuTraceSettings>()],
    constants: &[
        gpu_const!("SVO_MODEL_MASKS": u32 = Model::Masks.index()),
        gpu_const!("SVO_MODEL_ALPHA_BLEND": u32 = Model::AlphaBlend.index()),
        gpu_const!("SVO_MODEL_NEAREST": u32 = Model::Nearest.index()),
        gpu_const!("SVO_MODEL_SEPARATE": u32 = Model::SeparateFiltering.index()),
        gpu_const!("SVO_CONE_PINHOLE": u32 = 0),
        gpu_const!("SVO_CONE_LENS": u32 = 1),
        gpu_const!("SVO_CONE_SHADOW": u32 = 2),
        gpu_const!("SVO_FRAC_1_PI": f32 = core::f32::consts::FRAC_1_PI),
        gpu_const!(ERROR_BOUND_FACTOR: f32 as "SVO_ERROR_BOUND_FACTOR"),
        gpu_const!(SHADOW_LIFT_VOXELS: f32 as "SVO_SHADOW_LIFT_VOXELS"),
        gpu_const!(SHADING_POINT_REFINEMENTS: u32 as "SVO_SHADING_POINT_REFINEMENTS"),
        gpu_const!(FRAC_1_SQRT_2: f32 as "SVO_FRAC_1_SQRT_2"),
        gpu_const!(FRAC_1_SQRT_2PI: f32 as "SVO_FRAC_1_SQRT_2PI"),
        gpu_const!(RECTIFIED_CUTOFF: f32 as "SVO_RECTIFIED_CUTOFF"),
    ],
};
