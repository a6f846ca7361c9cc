//! The tracer's pipeline-overridable constants: what stays fixed for a scene (the method,
//! the stepping, the tiling, the block shift, the atlas's storage) is set when a pipeline
//! is created, not read from the uniforms at every step. The WGSL twin declares each as an
//! `override` with the default named below; the driver compiles each setting as its own
//! kernel, without the branches of the other settings (no uber-shader).
//!
//! A renderer creates one pipeline per [`TracePipelineConstants`] it meets, passing
//! [`TracePipelineConstants::constants`] as `wgpu::PipelineCompilationOptions::constants`;
//! [`GpuScene::pipeline_constants`](crate::GpuScene) gives a scene's.

use gpu_layout::{GpuConst, gpu_override};

use crate::trace::{Method, Stepping};

/// [`TracePipelineConstants::method`] for [`crate::Method::SphereTracing`].
pub const METHOD_SPHERE_TRACING: u32 = 0;
/// [`TracePipelineConstants::method`] for [`crate::Method::Quadric`].
pub const METHOD_QUADRIC: u32 = 1;
/// [`TracePipelineConstants::method`] for relief mapping ([`crate::relief_trace`]).
pub const METHOD_RELIEF: u32 = 2;
/// [`TracePipelineConstants::stepping`] for [`crate::Stepping::Distance`].
pub const STEPPING_DISTANCE: u32 = 0;
/// [`TracePipelineConstants::stepping`] for [`crate::Stepping::VoxelExit`].
pub const STEPPING_VOXEL_EXIT: u32 = 1;
/// [`TracePipelineConstants::stepping`] for [`crate::Stepping::BlockCells`].
pub const STEPPING_BLOCK_CELLS: u32 = 2;

/// The code of `method` in [`TracePipelineConstants::method`].
pub(crate) const fn method_code(method: Method) -> u32 {
    match method {
        Method::SphereTracing => METHOD_SPHERE_TRACING,
        Method::Quadric => METHOD_QUADRIC,
    }
}

/// The code of `stepping` in [`TracePipelineConstants::stepping`].
pub(crate) const fn stepping_code(stepping: Stepping) -> u32 {
    match stepping {
        Stepping::Distance => STEPPING_DISTANCE,
        Stepping::VoxelExit => STEPPING_VOXEL_EXIT,
        Stepping::BlockCells => STEPPING_BLOCK_CELLS,
    }
}

/// [`TracePipelineConstants::block_shift`] as the WGSL override holds `None`: index the
/// maps with divisions.
pub const BLOCK_DIVISIONS: u32 = u32::MAX;

const DEFAULT_METHOD: u32 = METHOD_QUADRIC;
const DEFAULT_STEPPING: u32 = STEPPING_DISTANCE;
const DEFAULT_PERIODIC: u32 = 1;
const DEFAULT_BLOCK_SHIFT: u32 = BLOCK_DIVISIONS;
const DEFAULT_ATLAS_F16: u32 = 0;

/// `override TRACE_METHOD: u32`: `METHOD_SPHERE_TRACING`, `METHOD_QUADRIC` or
/// `METHOD_RELIEF` (default quadric).
pub const TRACE_METHOD: GpuConst = gpu_override!(DEFAULT_METHOD: u32 as "TRACE_METHOD");
/// `override TRACE_STEPPING: u32`: `STEPPING_DISTANCE`, `STEPPING_VOXEL_EXIT` or
/// `STEPPING_BLOCK_CELLS` (default distance).
pub const TRACE_STEPPING: GpuConst = gpu_override!(DEFAULT_STEPPING: u32 as "TRACE_STEPPING");
/// `override TRACE_PERIODIC: u32`: 1 for a tile repeating in x and y, 0 for a single tile
/// (default 1).
pub const TRACE_PERIODIC: GpuConst = gpu_override!(DEFAULT_PERIODIC: u32 as "TRACE_PERIODIC");
/// `override TRACE_BLOCK_SHIFT: u32`: `log2` of every map's block side where all share
/// one power-of-two side (index with shifts), [`BLOCK_DIVISIONS`] otherwise (default).
pub const TRACE_BLOCK_SHIFT: GpuConst = gpu_override!(DEFAULT_BLOCK_SHIFT: u32 as "TRACE_BLOCK_SHIFT");
/// `override TRACE_ATLAS_F16: u32`: 1 for an atlas of binary16 pairs rounded down
/// ([`ddm_compress::pack_f16_pairs_at_most`]), 0 for `f32` words (default).
pub const TRACE_ATLAS_F16: GpuConst = gpu_override!(DEFAULT_ATLAS_F16: u32 as "TRACE_ATLAS_F16");

/// How the atlas of a scene's compressed maps is stored on the GPU.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum AtlasStorage {
    /// One `f32` per value: the maps' own distances.
    #[default]
    F32,
    /// Two binary16 values per word, each rounded down (still conservative): half the
    /// bytes. The CPU reference is [`CompressedMaps::with_f16_atlas`](crate::CompressedMaps::with_f16_atlas).
    F16,
}

/// The settings a tracing pipeline is specialised for: the values of the WGSL twin's
/// overridable constants.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct TracePipelineConstants {
    /// `METHOD_SPHERE_TRACING`, `METHOD_QUADRIC` or `METHOD_RELIEF`.
    pub method: u32,
    /// `STEPPING_DISTANCE`, `STEPPING_VOXEL_EXIT` or `STEPPING_BLOCK_CELLS`.
    pub stepping: u32,
    /// Whether the tile repeats in x and y.
    pub periodic: bool,
    /// `log2` of the maps' common power-of-two block side; `None` indexes with divisions.
    pub block_shift: Option<u32>,
    /// The atlas's storage.
    pub atlas: AtlasStorage,
}

impl Default for TracePipelineConstants {
    /// The WGSL defaults: quadric patches, distance stepping, a periodic tile, divisions, an
    /// `f32` atlas.
    fn default() -> Self {
        Self {
            method: DEFAULT_METHOD,
            stepping: DEFAULT_STEPPING,
            periodic: DEFAULT_PERIODIC != 0,
            block_shift: None,
            atlas: AtlasStorage::F32,
        }
    }
}

impl TracePipelineConstants {
    /// Every overridable constant's WGSL name and value, as
    /// `wgpu::PipelineCompilationOptions::constants` takes them.
    pub fn constants(&self) -> [(&'static str, f64); 5] {
        [
            TRACE_METHOD.set(self.method.into()),
            TRACE_STEPPING.set(self.stepping.into()),
            TRACE_PERIODIC.set(u32::from(self.periodic).into()),
            TRACE_BLOCK_SHIFT.set(self.block_shift.unwrap_or(BLOCK_DIVISIONS).into()),
            TRACE_ATLAS_F16.set(u32::from(self.atlas == AtlasStorage::F16).into()),
        ]
    }
}

#[cfg(test)]
mod tests {
    use gpu_layout::GpuConstValue;

    use super::*;

    #[test]
    fn the_default_constants_are_the_wgsl_defaults() {
        let overrides = [TRACE_METHOD, TRACE_STEPPING, TRACE_PERIODIC, TRACE_BLOCK_SHIFT, TRACE_ATLAS_F16];
        for ((name, value), declared) in TracePipelineConstants::default().constants().into_iter().zip(overrides) {
            assert!(declared.overridable);
            assert_eq!(name, declared.name);
            assert_eq!(GpuConstValue::U32(value as u32), declared.value, "{name}");
        }
    }
}
