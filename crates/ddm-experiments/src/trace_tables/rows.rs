//! The rows of the tables' CSV files, as the scene's steps return them.

use glam::Vec3;

use super::{PatchKind, TraceMethod};
use crate::gpu::GpuRun;
use crate::reference::ReferenceAccuracy;
use crate::stats::{HitDifferences, TraceStats};

/// One row of `ddm_trace_patches.csv`: the memory of one patch construction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PatchRow {
    /// The mesostructure.
    pub mesostructure: &'static str,
    /// The construction.
    pub patches: PatchKind,
    /// Voxels kept as quadrics.
    pub quadric_voxels: u32,
    /// Voxels kept as triangles.
    pub triangle_voxels: u32,
    /// Surface voxels without a patch.
    pub voxels_without_patch: u32,
    /// Patches.
    pub patch_count: usize,
    /// Bytes the tracer reads.
    pub bytes: usize,
}

/// One row of `ddm_adaptive_budget.csv`: the adaptive patches at one error budget, traced
/// with the DDM 4×1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BudgetRow {
    /// The mesostructure.
    pub mesostructure: &'static str,
    /// The error budget, voxels.
    pub budget: f32,
    /// Voxels kept as quadrics.
    pub quadric_voxels: u32,
    /// Voxels kept as triangles.
    pub triangle_voxels: u32,
    /// Bytes the tracer reads.
    pub bytes: usize,
    /// The outcomes against the truth.
    pub stats: TraceStats,
    /// CPU rays per second of one pass.
    pub cpu_rays_per_second: f64,
}

/// One row of `ddm_trace_methods.csv` (Tables 1/2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MethodRow {
    /// The mesostructure.
    pub mesostructure: &'static str,
    /// The method.
    pub method: TraceMethod,
    /// The outcomes against the truth.
    pub stats: TraceStats,
    /// The outcomes against the tile's own surface ([`crate::reference`](mod@crate::reference)), when the scene
    /// has one.
    pub reference: Option<ReferenceAccuracy>,
    /// CPU rays per second (one thread, fastest pass).
    pub cpu_rays_per_second: f64,
    /// The GPU pass on the raw maps, when a GPU was given.
    pub gpu: Option<GpuRun>,
}

/// The compressed maps traced with another stepping, against the raw maps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SteppingComparison {
    /// Mean steps on the compressed maps.
    pub mean_steps: f64,
    /// Differences from the raw maps' outcomes.
    pub differences: HitDifferences,
    /// CPU time ratio compressed / raw (interleaved median).
    pub cpu_time_ratio: f64,
}

/// One row of `ddm_trace_compression.csv` (Table 3): a method on raw and compressed maps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CompressionRow {
    /// The mesostructure.
    pub mesostructure: &'static str,
    /// The method.
    pub method: TraceMethod,
    /// Block side of the compression.
    pub block: u32,
    /// Compression efficiency of the method's maps.
    pub efficiency: f64,
    /// Mean steps on the raw maps.
    pub raw_mean_steps: f64,
    /// The compressed maps traced with the method's own stepping.
    pub compressed: SteppingComparison,
    /// GPU time ratio compressed / raw, when a GPU was given.
    pub gpu_time_ratio: Option<f64>,
    /// For methods that step by the stored distance, the compressed maps traced with
    /// block cells (`Stepping::BlockCells`, beyond the paper).
    pub block_cells: Option<SteppingComparison>,
}

/// What one method gives: its Tables 1/2 row, its Table 3 row (map-based methods) and the
/// hit normal of each pixel (for the images).
#[derive(Clone, Debug, PartialEq)]
pub struct MethodResult {
    /// Tables 1/2.
    pub row: MethodRow,
    /// Table 3 (`None` for relief mapping).
    pub compression: Option<CompressionRow>,
    /// The hit normal of each pixel, `None` for a miss.
    pub normals: Vec<Option<Vec3>>,
}
