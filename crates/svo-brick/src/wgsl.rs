//! The crate's WGSL twin (feature `wgsl`): the generated declarations of [`OctreeNode`],
//! [`OctreeUniforms`] and the constants below, and the functions of
//! `wgsl/svo_brick.wgsl`, each the twin of the Rust function named in its comment.

use gpu_layout::{StructDecl, WgslModule, gpu_const};

use crate::layout::COMPACT_DISTANCE_STEPS;
use crate::octree::{EMPTY_DISTANCE, OctreeNode};
use crate::sample::{FRACTION_STEPS, OctreeUniforms, SPLIT_MASK};

/// The WGSL twin of this crate: the node pool's descent (`svo_find`), exact decoding
/// (`svo_decode_raw`, `svo_octahedral_decode`), the contraction-proof interpolation
/// (`svo_lerp`, `svo_trilinear`), the quadrilinear and nearest samples (`svo_sample_raw`,
/// `svo_sample_nearest_raw`) and the final scaling (`svo_finish`); no dependencies. The
/// pools are bound at group 0, bindings 3 (nodes) and 4 (brick words).
pub const WGSL: WgslModule = WgslModule {
    name: "svo_brick",
    declarations: include_str!("../wgsl/generated/svo_brick.wgsl"),
    library: include_str!("../wgsl/svo_brick.wgsl"),
    naga_oil_source: concat!(
        include_str!("../wgsl/generated/svo_brick.naga_oil_header.wgsl"),
        include_str!("../wgsl/generated/svo_brick.wgsl"),
        include_str!("../wgsl/svo_brick.wgsl"),
    ),
    dependencies: &[],
    structs: &[StructDecl::of::<OctreeNode>(), StructDecl::of::<OctreeUniforms>()],
    constants: &[
        gpu_const!(FRACTION_STEPS: f32 as "SVO_FRACTION_STEPS"),
        gpu_const!(SPLIT_MASK: u32 as "SVO_SPLIT_MASK"),
        gpu_const!(COMPACT_DISTANCE_STEPS: f32 as "SVO_COMPACT_DISTANCE_STEPS"),
        gpu_const!("SVO_EMPTY": u32 = OctreeNode::EMPTY),
        gpu_const!(EMPTY_DISTANCE: f32 as "SVO_EMPTY_DISTANCE"),
        gpu_const!("SVO_FULL": u32 = OctreeNode::FULL),
        gpu_const!("SVO_LAYOUT_PAPER20": u32 = crate::VoxelLayout::Paper20.index()),
        gpu_const!("SVO_LAYOUT_COMPACT16": u32 = crate::VoxelLayout::Compact16.index()),
        gpu_const!("SVO_LAYOUT_COMPACT16_FINE8": u32 = crate::VoxelLayout::Compact16Fine8.index()),
    ],
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gpu_structs_have_their_wgsl_sizes() {
        assert_eq!(size_of::<OctreeNode>(), 8);
        assert_eq!(size_of::<OctreeUniforms>(), 80);
    }
}
