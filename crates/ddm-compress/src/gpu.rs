//! Structs and constants shared with the WGSL twin `shaders/ddm_compress.wgsl`.

use glam::UVec4;
use gpu_layout::{GpuConst, gpu_const, gpu_struct};

use crate::compress::{CompressedMap, SURFACE_FLAG, grid_dims};

gpu_struct! {
    /// What a shader needs to read a [`CompressedMap`]: its size, block and grid size.
    pub struct CompressedMapUniforms {
        /// `(dims.x, dims.y, dims.z, block)`.
        pub dims_block: UVec4,
        /// `(grid.x, grid.y, grid.z, atlas_base)`: the lookup grid's size, and the index of
        /// the atlas's first word in the buffer it is read from (0 with its own binding).
        pub grid_atlas_base: UVec4,
    }
}

impl CompressedMapUniforms {
    /// The uniforms of `map`, its atlas starting at word `atlas_base`.
    pub fn new(map: &CompressedMap, atlas_base: u32) -> Self {
        let g = grid_dims(map.dims(), map.block());
        Self { dims_block: map.dims().extend(map.block()), grid_atlas_base: g.extend(atlas_base) }
    }
}

/// Constants of this crate that the WGSL twin uses, for `cargo xtask codegen`.
pub const WGSL_CONSTANTS: &[GpuConst] = &[gpu_const!(SURFACE_FLAG: u32 as "DDM_SURFACE_FLAG")];
