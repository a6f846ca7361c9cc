//! Timing the occluder map and the splitter on the GPU (`cargo xtask bench-gpu culling`):
//! GPU timestamp queries where they bracket the work, wall clock around each pass's
//! submission otherwise (software adapters such as lavapipe, whose timestamps do not),
//! medians over the frames after a warm-up.

use gpu_harness::{Gpu, TimingSource};

use crate::camera::SplitCamera;
use crate::error::SplitError;
use crate::lists::SplitCounters;
use crate::splitter::{GrainSplitter, SplitBindings, SplitTimestamps};

/// How many frames to time.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BenchFrames {
    /// Untimed frames first (pipelines warm, caches filled).
    pub warm_up: u32,
    /// Timed frames (at least 1).
    pub timed: u32,
}

/// The medians of the timed frames, and the counters of the last one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BenchResult {
    /// Median milliseconds of the occluder map pass.
    pub map_ms: f64,
    /// Median milliseconds of the splitter's passes.
    pub split_ms: f64,
    /// Median milliseconds of both (per frame, then the median).
    pub total_ms: f64,
    /// How the times were measured.
    pub source: TimingSource,
    /// Frames timed.
    pub frames: u32,
    /// The counters after the last frame (read back after the timing).
    pub counters: SplitCounters,
}

fn median(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

fn wgpu_error(e: impl std::fmt::Display) -> SplitError {
    SplitError::Wgpu(e.to_string())
}

/// Runs `frames` frames of `splitter` over `grain_count` grains seen by `camera` and
/// returns the medians. Timestamps are used when the device has them and is not a
/// software adapter.
pub fn time_frames(
    gpu: &Gpu,
    splitter: &GrainSplitter,
    bindings: &SplitBindings,
    camera: &SplitCamera,
    grain_count: u32,
    frames: BenchFrames,
) -> Result<BenchResult, SplitError> {
    if frames.timed == 0 {
        return Err(SplitError::InvalidSetting { field: "frames", reason: "at least one frame must be timed".into() });
    }
    let source = gpu.timing_source();
    let queries = (source == TimingSource::Timestamps).then(|| {
        let set = gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
            label: Some("splitter timestamps"),
            ty: wgpu::QueryType::Timestamp,
            count: 4,
        });
        let resolve = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("splitter timestamp resolve"),
            size: 32,
            usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            mapped_at_creation: false,
        });
        (set, resolve)
    });
    let period_ns = f64::from(gpu.queue.get_timestamp_period());
    let (mut map, mut split, mut total) = (Vec::new(), Vec::new(), Vec::new());
    for frame in 0..frames.warm_up + frames.timed {
        let (map_ms, split_ms) = match &queries {
            Some((set, resolve)) => {
                let mut encoder = gpu.device.create_command_encoder(&Default::default());
                let timestamps = Some(SplitTimestamps { query_set: set, first: 0 });
                splitter.encode(&gpu.queue, &mut encoder, bindings, camera, grain_count, timestamps)?;
                encoder.resolve_query_set(set, 0..4, resolve, 0);
                gpu.queue.submit([encoder.finish()]);
                let bytes = gpu.read_buffer(resolve, 32).map_err(wgpu_error)?;
                let ticks: [u64; 4] = bytemuck::pod_read_unaligned(&bytes);
                let ms = |a: u64, b: u64| b.saturating_sub(a) as f64 * period_ns * 1e-6;
                (ms(ticks[0], ticks[1]), ms(ticks[2], ticks[3]))
            }
            None => {
                let started = std::time::Instant::now();
                let mut encoder = gpu.device.create_command_encoder(&Default::default());
                splitter.encode_occluder_map(&gpu.queue, &mut encoder, bindings, camera, grain_count, None)?;
                gpu.queue.submit([encoder.finish()]);
                gpu.wait().map_err(wgpu_error)?;
                let map_ms = started.elapsed().as_secs_f64() * 1e3;
                let started = std::time::Instant::now();
                let mut encoder = gpu.device.create_command_encoder(&Default::default());
                splitter.encode_split(&mut encoder, bindings, grain_count, None)?;
                gpu.queue.submit([encoder.finish()]);
                gpu.wait().map_err(wgpu_error)?;
                (map_ms, started.elapsed().as_secs_f64() * 1e3)
            }
        };
        if frame >= frames.warm_up {
            map.push(map_ms);
            split.push(split_ms);
            total.push(map_ms + split_ms);
        }
    }
    let bytes = gpu.read_buffer(splitter.counters(), size_of::<SplitCounters>() as u64).map_err(wgpu_error)?;
    Ok(BenchResult {
        map_ms: median(&mut map),
        split_ms: median(&mut split),
        total_ms: median(&mut total),
        source,
        frames: frames.timed,
        counters: bytemuck::pod_read_unaligned(&bytes),
    })
}
