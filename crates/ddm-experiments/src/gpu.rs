//! The WGSL tracer (`shaders/ddm_tracer.wgsl`, one ray per compute invocation) over the
//! tables' rays: the compute pass's time (the fastest of a few dispatches; GPU timestamps
//! where the adapter has them) and how many rays' results differ from the CPU reference.

use ddm_tracer::{CompressedMaps, TraceOutcome, TraceSettings, VoxelPatches};
use ddm_tracer::{GpuScene, TraceResult};
use gpu_harness::Gpu;
use shader_registry::kernel_io::ddm_tracer::TraceRay;

use crate::ExperimentError;
use crate::timing::Ray;

/// A GPU hit point further than this (voxels) from the CPU's counts as a difference.
pub const POINT_TOLERANCE: f32 = 1e-4;

/// The GPU pass's time and its agreement with the CPU.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GpuRun {
    /// Seconds of the fastest dispatch.
    pub seconds: f64,
    /// Rays whose hit/miss, hit point (beyond [`POINT_TOLERANCE`]) or step count differ
    /// from the CPU's.
    pub differs: usize,
}

/// The WGSL source of the tracer's compute kernel: `ddm-tracer`'s WGSL twin composed with
/// the `ddm_tracer_compute` test kernel (one ray per invocation). The one place this crate
/// reads the shader registry.
fn kernel_source() -> Result<String, ExperimentError> {
    shader_registry::test_kernel_source("ddm_tracer_compute").map_err(ExperimentError::Gpu)
}

/// The compute tracer on one device, its kernel composed once.
pub struct GpuTracer<'g> {
    gpu: &'g Gpu,
    source: String,
    dispatches: usize,
}

impl<'g> GpuTracer<'g> {
    /// The tracer on `gpu`, timing the fastest of `dispatches` dispatches (at least one).
    pub fn new(gpu: &'g Gpu, dispatches: usize) -> Result<Self, ExperimentError> {
        Ok(Self { gpu, source: kernel_source()?, dispatches: dispatches.max(1) })
    }

    /// `"timestamps"` or `"wall clock"`: how the pass is timed on this adapter.
    pub fn timing_name(&self) -> &'static str {
        if self.gpu.has_timestamps() { "timestamps" } else { "wall clock" }
    }

    /// The pass over `rays` on `maps` and `patches` with `settings`: see
    /// [`GpuTracer::run_scene`].
    ///
    /// # Errors
    ///
    /// [`ExperimentError::Gpu`] with the [`ddm_tracer::GpuSceneError`] when the scene does
    /// not pack, or as [`GpuTracer::run_scene`].
    pub fn run(
        &self,
        maps: &CompressedMaps,
        patches: Option<&VoxelPatches>,
        settings: TraceSettings,
        rays: &[Ray],
        cpu: &[TraceOutcome],
    ) -> Result<GpuRun, ExperimentError> {
        let scene = GpuScene::new(maps, patches, settings)
            .map_err(|e| ExperimentError::Gpu(format!("the scene does not pack into the GPU buffers: {e}")))?;
        self.run_scene(&scene, rays, cpu)
    }

    /// The pass of `scene` over `rays`, and how many of its results differ from `cpu`'s
    /// outcomes (of the last dispatch).
    pub fn run_scene(&self, scene: &GpuScene, rays: &[Ray], cpu: &[TraceOutcome]) -> Result<GpuRun, ExperimentError> {
        let inputs: Vec<TraceRay> = rays.iter().map(|&(o, d)| TraceRay::new(o, d)).collect();
        let ray_count = u32::try_from(inputs.len())
            .map_err(|_| ExperimentError::Gpu(format!("{} rays do not fit a dispatch", inputs.len())))?;
        let uniforms = scene.uniforms(ray_count);
        // The scene is uploaded once and the kernel compiled (and warmed up) by the harness
        // once: every timed dispatch is a warm one over resident buffers.
        let storage =
            self.gpu.upload_storage(&scene.storage_bytes()).map_err(|e| ExperimentError::Gpu(e.to_string()))?;
        // The pipeline specialised for the scene: the method, stepping, tiling, block
        // shift and atlas storage are the kernel's overrides, not uniforms.
        let constants = scene.pipeline_constants.constants();
        let mut best = f64::INFINITY;
        let mut differs = 0;
        for _ in 0..self.dispatches {
            let (results, timing): (Vec<TraceResult>, _) = self
                .gpu
                .compute_map_specialized(
                    &self.source,
                    "trace_rays",
                    &constants,
                    bytemuck::bytes_of(&uniforms),
                    &inputs,
                    &storage,
                )
                .map_err(|e| ExperimentError::Gpu(e.to_string()))?;
            best = best.min(timing.seconds);
            differs = gpu_differences(&results, cpu);
        }
        Ok(GpuRun { seconds: best, differs })
    }
}

/// Rays whose GPU result differs from the CPU outcome: hit against miss, hit points more
/// than [`POINT_TOLERANCE`] apart, or another step count.
pub fn gpu_differences(results: &[TraceResult], cpu: &[TraceOutcome]) -> usize {
    results
        .iter()
        .zip(cpu)
        .filter(|(g, c)| {
            let same_hit = (g.normal_hit.w == 1.0) == c.hit.is_some();
            let same_point = c.hit.is_none_or(|h| (h.point - g.point_t.truncate()).length() <= POINT_TOLERANCE);
            !(same_hit && same_point && g.counts.x == c.steps)
        })
        .count()
}

#[cfg(test)]
mod tests {
    use ddm_tracer::TraceHit;
    use glam::{UVec3, UVec4, Vec3, Vec4};

    use super::*;

    /// The GPU result a faithful twin returns for `outcome`.
    fn result_of(outcome: &TraceOutcome) -> TraceResult {
        match outcome.hit {
            Some(h) => TraceResult {
                point_t: h.point.extend(h.t),
                normal_hit: h.normal.extend(1.0),
                counts: UVec4::new(outcome.steps, outcome.cone, 0, 0),
            },
            None => TraceResult {
                point_t: Vec4::ZERO,
                normal_hit: Vec4::ZERO,
                counts: UVec4::new(outcome.steps, outcome.cone, 0, 0),
            },
        }
    }

    #[test]
    fn a_faithful_twin_differs_nowhere_and_each_change_counts_once() {
        let hit = TraceHit { t: 2.0, point: Vec3::new(1.0, 2.0, 0.5), normal: Vec3::Z, voxel: UVec3::ZERO };
        let cpu = [
            TraceOutcome { hit: Some(hit), steps: 7, exhausted: false, cone: 1 },
            TraceOutcome { hit: None, steps: 3, exhausted: false, cone: 0 },
            TraceOutcome { hit: Some(hit), steps: 4, exhausted: false, cone: 2 },
        ];
        let mut gpu: Vec<TraceResult> = cpu.iter().map(result_of).collect();
        assert_eq!(gpu_differences(&gpu, &cpu), 0);
        gpu[0].point_t.x += 0.5 * POINT_TOLERANCE; // within the tolerance
        assert_eq!(gpu_differences(&gpu, &cpu), 0);
        gpu[0].point_t.x += 2.0 * POINT_TOLERANCE; // moved
        gpu[1].normal_hit.w = 1.0; // a hit where the CPU missed
        gpu[2].counts.x += 1; // another step count
        assert_eq!(gpu_differences(&gpu, &cpu), 3);
    }
}
