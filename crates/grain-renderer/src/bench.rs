//! Timing a frame stage by stage (`cargo xtask stackings`): GPU timestamps at the
//! boundaries of empty compute passes around each stage where the adapter has them and is
//! not a software one, wall clock around each stage's own submission otherwise (lavapipe's
//! timestamps do not bracket the work).

use gpu_harness::{Gpu, TimingSource};
use grain_impostor::scene::ShadingUniforms;

use crate::error::RenderError;
use crate::impostor_tier::TierSettings;
use crate::renderer::{SceneBindings, StackingCamera, StackingRenderer, Stage};

/// Milliseconds per stage of one frame, in [`Stage::ALL`]'s order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StageTimes {
    /// Per stage.
    pub ms: [f64; Stage::ALL.len()],
    /// How they were measured.
    pub source: TimingSource,
}

impl StageTimes {
    /// The whole frame.
    pub fn total(&self) -> f64 {
        self.ms.iter().sum()
    }
}

fn harness(e: impl std::fmt::Display) -> RenderError {
    RenderError::InvalidInput(e.to_string())
}

/// Renders one frame, timing each stage (see the module docs).
pub fn time_frame(
    gpu: &Gpu,
    renderer: &StackingRenderer,
    scene: &SceneBindings,
    camera: &StackingCamera,
    lighting: &ShadingUniforms,
    settings: TierSettings,
) -> Result<StageTimes, RenderError> {
    let hardware = gpu.timing_source() == TimingSource::Timestamps;
    let mut ms = [0.0; Stage::ALL.len()];
    if hardware {
        let count = 2 * Stage::ALL.len() as u32;
        let set = gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("stage timestamps"),
            ty: wgpu::QueryType::Timestamp,
            count,
        });
        let resolve = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("stage timestamps"),
            size: u64::from(count) * 8,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        let mark = |encoder: &mut wgpu::CommandEncoder, index: u32| {
            encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("stage boundary"),
                timestamp_writes: Some(wgpu::ComputePassTimestampWrites {
                    query_set: &set,
                    beginning_of_pass_write_index: Some(index),
                    end_of_pass_write_index: None,
                }),
            });
        };
        for (k, stage) in Stage::ALL.into_iter().enumerate() {
            mark(&mut encoder, 2 * k as u32);
            renderer.encode_stage(&gpu.queue, &mut encoder, scene, camera, lighting, settings, stage)?;
            mark(&mut encoder, 2 * k as u32 + 1);
        }
        encoder.resolve_query_set(&set, 0..count, &resolve, 0);
        gpu.queue.submit([encoder.finish()]);
        let bytes = gpu.read_buffer(&resolve, u64::from(count) * 8).map_err(harness)?;
        let ticks: Vec<u64> = bytemuck::pod_collect_to_vec(&bytes);
        let period = f64::from(gpu.queue.get_timestamp_period());
        for k in 0..Stage::ALL.len() {
            ms[k] = ticks[2 * k + 1].saturating_sub(ticks[2 * k]) as f64 * period * 1e-6;
        }
        return Ok(StageTimes { ms, source: TimingSource::Timestamps });
    }
    for (k, stage) in Stage::ALL.into_iter().enumerate() {
        let started = std::time::Instant::now();
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        renderer.encode_stage(&gpu.queue, &mut encoder, scene, camera, lighting, settings, stage)?;
        gpu.queue.submit([encoder.finish()]);
        gpu.wait().map_err(harness)?;
        ms[k] = started.elapsed().as_secs_f64() * 1e3;
    }
    Ok(StageTimes { ms, source: TimingSource::WallClock })
}
