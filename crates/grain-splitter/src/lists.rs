//! What the splitter writes: per-grain state words, the element lists, their counters and
//! the indirect arguments of the draws and dispatches that consume them (§7, Fig. 7).
//!
//! # Lists
//!
//! The element buffer holds [`LIST_COUNT`] lists next to each other, each a run of grain
//! indices: meshes, impostors that are **occluder candidates** (they own the occluder-map
//! texel of their own centre: the thin shell of nearest grains that §9 draws first),
//! the other impostors, and points. List `l` starts at `offset[l]` (the exclusive prefix
//! sum of the counts) and holds `count[l]` indices.
//!
//! # Culled grains
//!
//! A grain in no list was culled, for one reason, counted in [`SplitCounters::culled`]:
//! outside the frustum ([`CULLED_FRUSTUM`]), hidden by its occluder's inner sphere
//! ([`CULLED_CONE`], `occlusion-cone`), or hidden by the fused occluders of the pixels it
//! covers ([`CULLED_HIZ`], [`crate::hiz`]); the tests run in that order.
//!
//! # State word (one `u32` per grain, kept across frames)
//!
//! Bits 0–7: `1 + tier` of the last frame ([`crate::Tier::code`], 0 = no history), read for
//! the hysteresis and rewritten every frame, culled grains included. Bits 8–15: this frame's
//! model: a list index or a `CULLED_*` code.

use bytemuck::{Pod, Zeroable};
use gpu_layout::{GpuConst, gpu_const};

/// The list of grains drawn as meshes.
pub const LIST_MESH: u32 = 0;
/// The list of impostors that are occluder candidates (drawn first, §9).
pub const LIST_IMPOSTOR_OCCLUDER: u32 = 1;
/// The list of the other impostors.
pub const LIST_IMPOSTOR_REST: u32 = 2;
/// The list of grains drawn as points.
pub const LIST_POINT: u32 = 3;
/// How many lists there are.
pub const LIST_COUNT: u32 = 4;
/// Model code of a grain outside the frustum.
pub const CULLED_FRUSTUM: u32 = 4;
/// Model code of a grain hidden by its occluder (Listing 2).
pub const CULLED_CONE: u32 = 5;
/// Model code of a grain hidden by the fused occluders (the Hi-Z test, [`crate::hiz`]).
pub const CULLED_HIZ: u32 = 6;
/// How many culling reasons [`SplitCounters::culled`] counts (the last slot is unused).
pub const CULL_REASONS: u32 = 3;

/// Mask of the tier code in a state word.
pub const STATE_TIER_MASK: u32 = 0xff;
/// Shift of the model code in a state word.
pub const STATE_MODEL_SHIFT: u32 = 8;

/// Invocations per workgroup of the per-grain passes (a grain *block*).
pub const SPLIT_WORKGROUP: u32 = 256;
/// Workgroup size the dispatch arguments of the lists are computed for: one invocation
/// per element, `(x, y, 1)` workgroups with element `(y·x_count + x)·ELEMENT_WORKGROUP +
/// local index` (see [`ListIndirect::dispatch`]).
pub const ELEMENT_WORKGROUP: u32 = 64;
/// The largest workgroup count of one dispatch dimension the splitter uses (WebGPU's
/// guaranteed minimum of `max_compute_workgroups_per_dimension`).
pub const MAX_GROUPS_PER_DIMENSION: u32 = 65_535;

/// Offsets of the counter arrays in the counters buffer (in `u32`s).
pub const COUNTER_COUNT: u32 = 0;
/// Offset of the list offsets.
pub const COUNTER_OFFSET: u32 = 4;
/// Offset of the write cursors (the atomic write pass).
pub const COUNTER_CURSOR: u32 = 8;
/// Offset of the culled counts.
pub const COUNTER_CULLED: u32 = 12;
/// `u32`s in the counters buffer.
pub const COUNTER_WORDS: u32 = 16;

/// `u32`s of one list's indirect arguments.
pub const INDIRECT_WORDS: u32 = 12;
/// Offset (in `u32`s) of the `draw_indexed_indirect` arguments in a list's block.
pub const INDIRECT_DRAW_INDEXED: u32 = 0;
/// Offset of the `draw_indirect` arguments.
pub const INDIRECT_DRAW: u32 = 5;
/// Offset of the `dispatch_workgroups_indirect` arguments.
pub const INDIRECT_DISPATCH: u32 = 9;

/// The counters buffer as read back (`COUNTER_WORDS` `u32`s).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct SplitCounters {
    /// Elements per list.
    pub count: [u32; 4],
    /// First element of each list (exclusive prefix sum of `count`).
    pub offset: [u32; 4],
    /// Write cursors of the atomic write pass (equal to `count` after a frame); zero for
    /// the stable order.
    pub cursor: [u32; 4],
    /// Culled grains by reason: frustum, cone, Hi-Z (the last slot is unused).
    pub culled: [u32; 4],
}

/// The indirect arguments of one list, laid out as wgpu reads them.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct ListIndirect {
    /// `draw_indexed_indirect`: index count (the mesh's), instance count (the list's count),
    /// first index 0, base vertex 0, first instance 0. The vertex shader finds its grain as
    /// `elements[offset[list] + instance_index]` (a first instance would need the
    /// `INDIRECT_FIRST_INSTANCE` feature).
    pub draw_indexed: [u32; 5],
    /// `draw_indirect`: vertex count (a sprite's), instance count, first vertex 0, first
    /// instance 0.
    pub draw: [u32; 4],
    /// `dispatch_workgroups_indirect`: `(x, y, 1)` workgroups of [`ELEMENT_WORKGROUP`]
    /// covering the list, `x ≤ MAX_GROUPS_PER_DIMENSION`; `(0, 1, 1)` for an empty list.
    pub dispatch: [u32; 3],
}

impl ListIndirect {
    /// The arguments of a list of `count` elements. Twin of `split_offsets` (WGSL).
    pub fn new(count: u32, mesh_index_count: u32, sprite_vertex_count: u32) -> Self {
        let groups = count.div_ceil(ELEMENT_WORKGROUP);
        let x = groups.min(MAX_GROUPS_PER_DIMENSION);
        let y = if groups == 0 { 1 } else { groups.div_ceil(x) };
        Self {
            draw_indexed: [mesh_index_count, count, 0, 0, 0],
            draw: [sprite_vertex_count, count, 0, 0],
            dispatch: [x, y, 1],
        }
    }
}

/// The model code in a state word.
pub fn state_model(state: u32) -> u32 {
    (state >> STATE_MODEL_SHIFT) & 0xff
}

/// The tier code in a state word.
pub fn state_tier(state: u32) -> u32 {
    state & STATE_TIER_MASK
}

/// The constants the shaders share with this module.
pub const LIST_CONSTANTS: &[GpuConst] = &[
    gpu_const!(LIST_MESH: u32),
    gpu_const!(LIST_IMPOSTOR_OCCLUDER: u32),
    gpu_const!(LIST_IMPOSTOR_REST: u32),
    gpu_const!(LIST_POINT: u32),
    gpu_const!(LIST_COUNT: u32),
    gpu_const!(CULLED_FRUSTUM: u32),
    gpu_const!(CULLED_CONE: u32),
    gpu_const!(CULLED_HIZ: u32),
    gpu_const!(CULL_REASONS: u32),
    gpu_const!(STATE_TIER_MASK: u32),
    gpu_const!(STATE_MODEL_SHIFT: u32),
    gpu_const!(SPLIT_WORKGROUP: u32),
    gpu_const!(ELEMENT_WORKGROUP: u32),
    gpu_const!(MAX_GROUPS_PER_DIMENSION: u32),
    gpu_const!(COUNTER_COUNT: u32),
    gpu_const!(COUNTER_OFFSET: u32),
    gpu_const!(COUNTER_CURSOR: u32),
    gpu_const!(COUNTER_CULLED: u32),
    gpu_const!(INDIRECT_WORDS: u32),
    gpu_const!(INDIRECT_DRAW_INDEXED: u32),
    gpu_const!(INDIRECT_DRAW: u32),
    gpu_const!(INDIRECT_DISPATCH: u32),
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layouts_match_the_word_offsets() {
        assert_eq!(size_of::<SplitCounters>(), COUNTER_WORDS as usize * 4);
        assert_eq!(size_of::<ListIndirect>(), INDIRECT_WORDS as usize * 4);
        let words: [u32; 12] = bytemuck::cast(ListIndirect::new(1000, 36, 6));
        assert_eq!(words[INDIRECT_DRAW_INDEXED as usize..][..2], [36, 1000]);
        assert_eq!(words[INDIRECT_DRAW as usize..][..2], [6, 1000]);
        assert_eq!(words[INDIRECT_DISPATCH as usize..][..3], [16, 1, 1]);
    }

    #[test]
    fn dispatches_cover_every_element_within_the_dimension_limit() {
        for count in [0, 1, 64, 65, 4_194_240, 4_194_241, 20_000_000, u32::MAX] {
            let [x, y, z] = ListIndirect::new(count, 0, 0).dispatch;
            assert!(x <= MAX_GROUPS_PER_DIMENSION && z == 1 && y >= 1);
            let covered = u64::from(x) * u64::from(y) * u64::from(ELEMENT_WORKGROUP);
            assert!(covered >= u64::from(count), "{count}");
            assert!(covered < u64::from(count) + u64::from(x) * u64::from(ELEMENT_WORKGROUP) + 64, "{count}: tight");
        }
    }
}
