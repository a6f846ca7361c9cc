//! Timing [`GpuRenderer`] and [`GpuVoxelTruth`] frames, and the benchmark of a dolly (`cargo xtask bench-gpu svo`).
//!
//! A frame is timed by GPU timestamps at the start and the end of its compute pass where
//! the adapter has them and is not a software one; by wall clock around its submission and
//! completion otherwise (lavapipe's timestamps do not bracket the work). Every frame is its
//! own submission (the renderer's rule), after `warm_up` untimed frames; the figure is the
//! median.

pub use gpu_harness::FrameTimes;
use gpu_harness::{Gpu, TimingSource};
use svo_tracer::{Camera, Lens, Model, TraceSettings};

use crate::accuracy::Dolly;
use crate::error::{RenderError, check, gpu_failed};
use crate::frame::Frame;
use crate::gpu_truth::GpuVoxelTruth;
use crate::renderer::{FrameSettings, GpuRenderer};
use crate::truth::TruthSettings;

/// Renders `warm_up` untimed frames, then `frames` timed ones (see the module docs).
pub fn time_frames(
    gpu: &Gpu,
    renderer: &GpuRenderer,
    frame: FrameSettings<'_>,
    warm_up: u32,
    frames: u32,
) -> Result<FrameTimes, RenderError> {
    time_passes(
        gpu,
        |encoder, timestamps| match timestamps {
            Some((set, index)) => renderer.encode_timed(&gpu.queue, encoder, frame, set, index),
            None => renderer.encode(&gpu.queue, encoder, frame),
        },
        warm_up,
        frames,
    )
}

/// [`time_frames`] for the GPU voxel truth: `warm_up` untimed frames of `truth` with
/// `camera`, `trace` and `settings`, then `frames` timed ones.
pub fn time_voxel_truth(
    gpu: &Gpu,
    truth: &GpuVoxelTruth,
    camera: &Camera,
    trace: &TraceSettings,
    settings: &TruthSettings,
    warm_up: u32,
    frames: u32,
) -> Result<FrameTimes, RenderError> {
    time_passes(
        gpu,
        |encoder, timestamps| {
            let writes = timestamps.map(|(query_set, index)| wgpu::ComputePassTimestampWrites {
                query_set,
                beginning_of_pass_write_index: Some(index),
                end_of_pass_write_index: Some(index + 1),
            });
            truth.encode(&gpu.queue, encoder, camera, trace, settings, writes)
        },
        warm_up,
        frames,
    )
}

/// Times the one compute pass that `record` encodes, given the query set and the index of
/// its start timestamp to write (or none); see the module docs.
fn time_passes(
    gpu: &Gpu,
    record: impl Fn(&mut wgpu::CommandEncoder, Option<(&wgpu::QuerySet, u32)>) -> Result<(), RenderError>,
    warm_up: u32,
    frames: u32,
) -> Result<FrameTimes, RenderError> {
    check(frames >= 1, "frames", f64::from(frames), "at least 1")?;
    let submit = |timestamps: Option<(&wgpu::QuerySet, u32)>| -> Result<(), RenderError> {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        record(&mut encoder, timestamps)?;
        gpu.queue.submit([encoder.finish()]);
        Ok(())
    };
    for _ in 0..warm_up {
        submit(None)?;
    }
    gpu.wait().map_err(gpu_failed("waiting for the warm-up frames"))?;
    if gpu.timing_source() == TimingSource::Timestamps {
        let count = 2 * frames;
        let (set, resolve) = gpu
            .scoped(|| {
                let set = gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
                    label: Some("svo frame timestamps"),
                    ty: wgpu::QueryType::Timestamp,
                    count,
                });
                let resolve = gpu.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("svo frame timestamps"),
                    size: 8 * u64::from(count),
                    usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                });
                (set, resolve)
            })
            .map_err(gpu_failed("creating the timestamp queries"))?;
        for k in 0..frames {
            submit(Some((&set, 2 * k)))?;
        }
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        encoder.resolve_query_set(&set, 0..count, &resolve, 0);
        gpu.queue.submit([encoder.finish()]);
        let bytes = gpu.read_buffer(&resolve, 8 * u64::from(count)).map_err(gpu_failed("reading the timestamps"))?;
        let ticks: Vec<u64> = bytemuck::pod_collect_to_vec(&bytes);
        let period = f64::from(gpu.queue.get_timestamp_period());
        let ms = ticks.chunks_exact(2).map(|t| t[1].saturating_sub(t[0]) as f64 * period * 1e-6).collect();
        return Ok(FrameTimes { ms, source: TimingSource::Timestamps });
    }
    let mut ms = Vec::with_capacity(frames as usize);
    for _ in 0..frames {
        let started = std::time::Instant::now();
        submit(None)?;
        gpu.wait().map_err(gpu_failed("waiting for a frame"))?;
        ms.push(started.elapsed().as_secs_f64() * 1e3);
    }
    Ok(FrameTimes { ms, source: TimingSource::WallClock })
}

/// A variant of the tracer's settings that the benchmark times for every model.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Variant {
    /// Pinhole camera, no shadows.
    Plain,
    /// One shadow cone per pixel.
    Shadows,
    /// A thin lens (depth of field).
    DepthOfField(Lens),
}

impl Variant {
    /// The variant's name in tables.
    pub fn name(self) -> &'static str {
        match self {
            Variant::Plain => "plain",
            Variant::Shadows => "shadows",
            Variant::DepthOfField(_) => "dof",
        }
    }
}

/// One row of the benchmark: one model and variant at one view of the dolly.
#[derive(Clone, Debug, PartialEq)]
pub struct BenchRow {
    /// The view's index along the dolly.
    pub view: u32,
    /// The view's distance from the target.
    pub distance: f32,
    /// The model.
    pub model: Model,
    /// The variant.
    pub variant: &'static str,
    /// The median GPU milliseconds of a frame.
    pub median_ms: f64,
    /// The 10 % and 90 % quantiles.
    pub p10_ms: f64,
    /// See [`p10_ms`](Self::p10_ms).
    pub p90_ms: f64,
    /// Pixels with coverage above zero.
    pub covered_pixels: u64,
    /// `median_ms · 1000 / covered_pixels` (∞ without covered pixels).
    pub us_per_covered_pixel: f64,
    /// The mean cone elements sampled per pixel, over every pixel.
    pub elements_per_pixel: f64,
    /// The mean cone elements sampled per covered pixel.
    pub elements_per_covered_pixel: f64,
    /// Timed frames.
    pub frames: u32,
    /// How they were timed.
    pub source: TimingSource,
}

/// The covered pixels, µs per covered pixel and elements of a read-back frame.
pub fn frame_work(frame: &Frame, median_ms: f64) -> (u64, f64, f64, f64) {
    let covered: Vec<usize> = (0..frame.pixels()).filter(|&k| frame.coverage[k] > 0.0).collect();
    let n = covered.len() as u64;
    let per_pixel = if n > 0 { median_ms * 1e3 / n as f64 } else { f64::INFINITY };
    let covered_elements = covered.iter().map(|&k| f64::from(frame.elements[k])).sum::<f64>() / n.max(1) as f64;
    (n, per_pixel, frame.mean_elements(), covered_elements)
}

/// What [`bench_dolly`] times.
#[derive(Clone, Debug, PartialEq)]
pub struct BenchSettings {
    /// The views (their size is the renderer's).
    pub dolly: Dolly,
    /// The tracer's settings; the model and the variant replace their fields.
    pub trace: TraceSettings,
    /// The models timed.
    pub models: Vec<Model>,
    /// The variants timed.
    pub variants: Vec<Variant>,
    /// Untimed frames before each view's timed ones.
    pub warm_up: u32,
    /// Timed frames per view, model and variant.
    pub frames: u32,
}

/// Times every model and variant at every view of the dolly with `renderer` (whose size
/// must be the dolly's), reading each view's last frame back for its coverage and work.
/// `progress` is called after each row.
pub fn bench_dolly(
    gpu: &Gpu,
    renderer: &GpuRenderer,
    settings: &BenchSettings,
    mut progress: impl FnMut(&BenchRow),
) -> Result<Vec<BenchRow>, RenderError> {
    settings.dolly.validate()?;
    let mut rows = Vec::new();
    for view in 0..settings.dolly.views {
        let pinhole = settings.dolly.camera(view)?;
        for &variant in &settings.variants {
            let camera: Camera = match variant {
                Variant::DepthOfField(lens) => {
                    pinhole.with_lens(lens).map_err(|source| RenderError::Camera { view, source })?
                }
                Variant::Plain | Variant::Shadows => pinhole,
            };
            for &model in &settings.models {
                let shadow_cones = match variant {
                    Variant::Shadows => settings.trace.shadow_cones.max(1),
                    Variant::Plain | Variant::DepthOfField(_) => 0,
                };
                let trace = TraceSettings { model, shadow_cones, ..settings.trace };
                let frame = FrameSettings { camera: &camera, settings: &trace, exposure: 1.0 };
                let times = time_frames(gpu, renderer, frame, settings.warm_up, settings.frames)?;
                let read = renderer.read_frame(gpu)?;
                let median_ms = times.median();
                let (covered_pixels, us_per_covered_pixel, elements_per_pixel, elements_per_covered_pixel) =
                    frame_work(&read, median_ms);
                let row = BenchRow {
                    view,
                    distance: settings.dolly.distance(view),
                    model,
                    variant: variant.name(),
                    median_ms,
                    p10_ms: times.quantile(0.1),
                    p90_ms: times.quantile(0.9),
                    covered_pixels,
                    us_per_covered_pixel,
                    elements_per_pixel,
                    elements_per_covered_pixel,
                    frames: settings.frames,
                    source: times.source,
                };
                progress(&row);
                rows.push(row);
            }
        }
    }
    Ok(rows)
}

/// The rows as CSV, with the adapter and the image size in every row.
pub fn bench_csv(rows: &[BenchRow], adapter: &str, size: (u32, u32), scene: &str) -> String {
    use std::fmt::Write as _;
    let mut csv = String::from(
        "adapter,scene,width,height,view,distance,model,variant,median_ms,p10_ms,p90_ms,covered_pixels,\
         us_per_covered_pixel,elements_per_pixel,elements_per_covered_pixel,frames,timing\n",
    );
    let adapter = adapter.replace(',', ";");
    for r in rows {
        let timing = match r.source {
            TimingSource::Timestamps => "timestamps",
            TimingSource::WallClock => "wall-clock",
        };
        let _ = writeln!(
            csv,
            "{adapter},{scene},{},{},{},{:.6},{},{},{:.5},{:.5},{:.5},{},{:.6},{:.3},{:.3},{},{timing}",
            size.0,
            size.1,
            r.view,
            r.distance,
            r.model.name(),
            r.variant,
            r.median_ms,
            r.p10_ms,
            r.p90_ms,
            r.covered_pixels,
            r.us_per_covered_pixel,
            r.elements_per_pixel,
            r.elements_per_covered_pixel,
            r.frames
        );
    }
    csv
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn work_counts_covered_pixels_only() {
        let frame = Frame {
            width: 2,
            height: 1,
            radiance: vec![glam::Vec3::ZERO; 2],
            coverage: vec![0.5, 0.0],
            elements: vec![6, 2],
        };
        let (n, us, all, covered) = frame_work(&frame, 1.0);
        assert_eq!((n, us, all, covered), (1, 1000.0, 4.0, 6.0));
    }
}
