//! The crate's WGSL twin (feature `wgsl`): the generated declarations of the structs and
//! constants below, and the functions of `wgsl/ddm_tracer.wgsl` (the tracer) and
//! `wgsl/tangent_space.wgsl` (a base mesh's pixel in tangent space), each the twin of the
//! Rust function named in its comment. The scene's fixed settings are `override`s
//! ([`crate::pipeline_constants`]). Composed after `quadric-fit`'s and
//! `ddm-compress`'s twins, which it calls.

use gpu_layout::{StructDecl, WgslModule, gpu_const};

use crate::gpu_scene::{TraceConeMap, TraceResult, TraceUniforms};
use crate::patch::{BOUNDED_PATCH, POLYGON_TOLERANCE, TracePatch};
use crate::pipeline_constants::{
    BLOCK_DIVISIONS, METHOD_QUADRIC, METHOD_RELIEF, METHOD_SPHERE_TRACING, STEPPING_BLOCK_CELLS, STEPPING_DISTANCE,
    STEPPING_VOXEL_EXIT, TRACE_ATLAS_F16, TRACE_BLOCK_SHIFT, TRACE_METHOD, TRACE_PERIODIC, TRACE_STEPPING,
};
use crate::tangent_space::{
    BaseGBufferTexel, BaseRenderParams, BaseRenderPixel, NO_EXIT, PIXEL_HIT, PIXEL_LEFT_SHELL, PIXEL_MISS,
    PIXEL_UNCOVERED,
};
use crate::trace::NO_LIMIT;
use crate::voxel::NUDGE;

/// The WGSL twin of this crate: `trace_ray` (Algorithms 3.1–3.3 and relief mapping over
/// the scene of [`GpuScene`](crate::GpuScene), bound at 3–8) and the tangent-space pixel
/// functions (`render_tangent_frame`, `render_tangent_ray`, `render_in_shadow`, …); after
/// `quadric_fit` and `ddm_compress`.
pub const WGSL: WgslModule = WgslModule {
    name: "ddm_tracer",
    declarations: include_str!("../wgsl/generated/ddm_tracer.wgsl"),
    library: concat!(include_str!("../wgsl/ddm_tracer.wgsl"), include_str!("../wgsl/tangent_space.wgsl")),
    naga_oil_source: concat!(
        include_str!("../wgsl/generated/ddm_tracer.naga_oil_header.wgsl"),
        include_str!("../wgsl/generated/ddm_tracer.wgsl"),
        include_str!("../wgsl/ddm_tracer.wgsl"),
        include_str!("../wgsl/tangent_space.wgsl"),
    ),
    dependencies: &[&quadric_fit::WGSL, &ddm_compress::WGSL],
    structs: &[
        StructDecl::of::<TracePatch>(),
        StructDecl::of::<TraceUniforms>(),
        StructDecl::of::<TraceConeMap>(),
        StructDecl::of::<TraceResult>(),
        StructDecl::of::<BaseGBufferTexel>(),
        StructDecl::of::<BaseRenderParams>(),
        StructDecl::of::<BaseRenderPixel>(),
    ],
    constants: &[
        gpu_const!(METHOD_SPHERE_TRACING: u32 as "TRACE_METHOD_SPHERE_TRACING"),
        gpu_const!(METHOD_QUADRIC: u32 as "TRACE_METHOD_QUADRIC"),
        gpu_const!(METHOD_RELIEF: u32 as "TRACE_METHOD_RELIEF"),
        gpu_const!(NUDGE: f32 as "TRACE_NUDGE"),
        gpu_const!(NO_LIMIT: f32 as "TRACE_NO_LIMIT"),
        gpu_const!(POLYGON_TOLERANCE: f32 as "TRACE_POLYGON_TOLERANCE"),
        gpu_const!(BOUNDED_PATCH: f32 as "TRACE_BOUNDED_PATCH"),
        gpu_const!(STEPPING_DISTANCE: u32 as "TRACE_STEPPING_DISTANCE"),
        gpu_const!(STEPPING_VOXEL_EXIT: u32 as "TRACE_STEPPING_VOXEL_EXIT"),
        gpu_const!(STEPPING_BLOCK_CELLS: u32 as "TRACE_STEPPING_BLOCK_CELLS"),
        gpu_const!("TRACE_TAU": f32 = core::f32::consts::TAU),
        gpu_const!(BLOCK_DIVISIONS: u32 as "TRACE_BLOCK_DIVISIONS"),
        TRACE_METHOD,
        TRACE_STEPPING,
        TRACE_PERIODIC,
        TRACE_BLOCK_SHIFT,
        TRACE_ATLAS_F16,
        gpu_const!(PIXEL_UNCOVERED: f32 as "RENDER_PIXEL_UNCOVERED"),
        gpu_const!(PIXEL_MISS: f32 as "RENDER_PIXEL_MISS"),
        gpu_const!(PIXEL_HIT: f32 as "RENDER_PIXEL_HIT"),
        gpu_const!(PIXEL_LEFT_SHELL: f32 as "RENDER_PIXEL_LEFT_SHELL"),
        gpu_const!(NO_EXIT: f32 as "RENDER_NO_EXIT"),
    ],
};
