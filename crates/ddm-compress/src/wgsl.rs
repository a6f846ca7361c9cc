//! The crate's WGSL twin (feature `wgsl`): the generated declarations of
//! [`CompressedMapUniforms`], [`SURFACE_FLAG`], the plain map's GPU layout
//! ([`PlainGpuNode`], [`PlainGpuTriangle`], [`PlainGpuUniforms`]) and the constants of its
//! search; the functions of `wgsl/ddm_compress.wgsl`, the twins of the compressed map's
//! access (Algorithm A.2), and of `wgsl/plain_map.wgsl`, the twins of the plain map's
//! per-pair bounds.

use gpu_layout::{StructDecl, WgslModule, gpu_const};

use crate::bvh::OVERLAP_BOX_MARGIN;
use crate::compress::{CompressedMapUniforms, SURFACE_FLAG};
use crate::geometry::{
    BOX_TRIANGLE_MARGIN, DEGENERATE_AXIS_SQUARED, DEGENERATE_SEGMENT_SQUARED, DEGENERATE_TRIANGLE_SINE_SQUARED,
};
use crate::plain::{GAP_SLACK, MARGIN, MAX_PROJECTIONS};
use crate::plain_gpu::{
    PLAIN_GPU_FIRST_BITS, PLAIN_GPU_LEAF, PLAIN_GPU_STACK, PlainGpuNode, PlainGpuTriangle, PlainGpuUniforms,
};

/// The WGSL twin of this crate: `ddm_grid_index`, `ddm_atlas_index`,
/// `ddm_entry_is_surface`, `ddm_entry_distance` (the compressed map's access, Algorithm
/// A.2); `ddm_plain_pair_lower_bound`, `ddm_box_triangle_distance`,
/// `ddm_triangle_overlaps_box`, `ddm_box_gap_squared` and what they call (the plain map's
/// per-pair search, [`crate::plain_gpu`]); no dependencies.
pub const WGSL: WgslModule = WgslModule {
    name: "ddm_compress",
    declarations: include_str!("../wgsl/generated/ddm_compress.wgsl"),
    library: concat!(include_str!("../wgsl/ddm_compress.wgsl"), include_str!("../wgsl/plain_map.wgsl")),
    naga_oil_source: concat!(
        include_str!("../wgsl/generated/ddm_compress.naga_oil_header.wgsl"),
        include_str!("../wgsl/generated/ddm_compress.wgsl"),
        include_str!("../wgsl/ddm_compress.wgsl"),
        include_str!("../wgsl/plain_map.wgsl"),
    ),
    dependencies: &[],
    structs: &[
        StructDecl::of::<CompressedMapUniforms>(),
        StructDecl::of::<PlainGpuNode>(),
        StructDecl::of::<PlainGpuTriangle>(),
        StructDecl::of::<PlainGpuUniforms>(),
    ],
    constants: &[
        gpu_const!(SURFACE_FLAG: u32 as "DDM_SURFACE_FLAG"),
        gpu_const!(PLAIN_GPU_LEAF: u32 as "DDM_PLAIN_GPU_LEAF"),
        gpu_const!(PLAIN_GPU_FIRST_BITS: u32 as "DDM_PLAIN_GPU_FIRST_BITS"),
        gpu_const!(PLAIN_GPU_STACK: u32 as "DDM_PLAIN_GPU_STACK"),
        gpu_const!(MAX_PROJECTIONS: u32 as "DDM_PLAIN_MAX_PROJECTIONS"),
        gpu_const!(MARGIN: f32 as "DDM_PLAIN_MARGIN"),
        gpu_const!(GAP_SLACK: f32 as "DDM_PLAIN_GAP_SLACK"),
        gpu_const!(OVERLAP_BOX_MARGIN: f32 as "DDM_OVERLAP_BOX_MARGIN"),
        gpu_const!(BOX_TRIANGLE_MARGIN: f32 as "DDM_BOX_TRIANGLE_MARGIN"),
        gpu_const!(DEGENERATE_AXIS_SQUARED: f32 as "DDM_DEGENERATE_AXIS_SQUARED"),
        gpu_const!(DEGENERATE_SEGMENT_SQUARED: f32 as "DDM_DEGENERATE_SEGMENT_SQUARED"),
        gpu_const!(DEGENERATE_TRIANGLE_SINE_SQUARED: f32 as "DDM_DEGENERATE_TRIANGLE_SINE_SQUARED"),
    ],
};
