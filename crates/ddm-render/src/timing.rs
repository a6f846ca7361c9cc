//! Timing [`DdmRenderer`] frames, for `cargo xtask bench-gpu ddm`.
//!
//! A frame is the renderer's whole [`DdmRenderer::encode`]: the G-buffer raster pass and
//! the per-pixel pass, each frame its own submission (the renderer's rule), after
//! `warm_up` untimed frames. On a hardware adapter with timestamp queries both passes
//! write their beginning and end: the frame's time runs from the raster pass's beginning
//! to the per-pixel pass's end, and the per-pixel pass is also timed alone. Elsewhere
//! (lavapipe's timestamps do not bracket the work) the frame is timed by wall clock from
//! submission to completion, and the per-pixel pass is not timed alone.

use gpu_harness::{FrameTimes, Gpu, TimingSource};

use crate::error::DdmRenderError;
use crate::gbuffer::PassTimestamps;
use crate::renderer::{DdmFrame, DdmRenderer, DdmTarget};

/// Timestamps per frame: the raster pass's two, then the per-pixel pass's two.
const QUERIES_PER_FRAME: u32 = 4;

/// A timestamp query set and the buffer its queries resolve into.
pub(crate) struct TimestampQueries {
    pub(crate) set: wgpu::QuerySet,
    resolve: wgpu::Buffer,
    count: u32,
}

impl TimestampQueries {
    /// `count` timestamp queries labelled `label`.
    pub(crate) fn new(gpu: &Gpu, label: &'static str, count: u32) -> Result<Self, DdmRenderError> {
        Ok(gpu.scoped(|| {
            let set = gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some(label),
                ty: wgpu::QueryType::Timestamp,
                count,
            });
            let resolve = gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: 8 * u64::from(count),
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            Self { set, resolve, count }
        })?)
    }

    /// Resolves every query (after the submissions that wrote them) and reads the ticks.
    pub(crate) fn read(&self, gpu: &Gpu) -> Result<Vec<u64>, DdmRenderError> {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        encoder.resolve_query_set(&self.set, 0..self.count, &self.resolve, 0);
        gpu.scoped(|| gpu.queue.submit([encoder.finish()]))?;
        Ok(bytemuck::pod_collect_to_vec(&gpu.read_buffer(&self.resolve, 8 * u64::from(self.count))?))
    }
}

/// The times of a renderer's frames.
#[derive(Clone, Debug, PartialEq)]
pub struct RendererTimes {
    /// Whole frames (raster and per-pixel pass).
    pub frame: FrameTimes,
    /// The per-pixel pass alone, where timestamps time it.
    pub trace: Option<FrameTimes>,
}

/// Renders `warm_up` untimed frames of `frame` (its own timestamp fields are ignored) into
/// `target`, then `frames` timed ones (see the module documentation). Errors name the
/// count that is zero, the frame's field that is wrong or the GPU operation that failed.
pub fn time_frames(
    gpu: &Gpu,
    renderer: &DdmRenderer,
    frame: &DdmFrame<'_>,
    target: &DdmTarget,
    warm_up: u32,
    frames: u32,
) -> Result<RendererTimes, DdmRenderError> {
    if frames == 0 {
        return Err(DdmRenderError::InvalidSettings("timed frames must be at least 1"));
    }
    let plain = DdmFrame { raster_timestamps: None, trace_timestamps: None, ..*frame };
    let submit = |frame: &DdmFrame<'_>| -> Result<(), DdmRenderError> {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        renderer.encode(&gpu.queue, &mut encoder, frame, target)?;
        gpu.scoped(|| gpu.queue.submit([encoder.finish()]))?;
        Ok(())
    };
    for _ in 0..warm_up {
        submit(&plain)?;
    }
    gpu.wait()?;
    if gpu.timing_source() == TimingSource::Timestamps {
        let count = QUERIES_PER_FRAME
            .checked_mul(frames)
            .ok_or(DdmRenderError::InvalidSettings("timed frames overflow the timestamp queries"))?;
        let queries = TimestampQueries::new(gpu, "ddm-render frame timestamps", count)?;
        let set = &queries.set;
        for k in 0..frames {
            let first = QUERIES_PER_FRAME * k;
            submit(&DdmFrame {
                raster_timestamps: Some(PassTimestamps { query_set: set, first }),
                trace_timestamps: Some(PassTimestamps { query_set: set, first: first + 2 }),
                ..plain
            })?;
        }
        let ticks = queries.read(gpu)?;
        let ms_per_tick = f64::from(gpu.queue.get_timestamp_period()) * 1e-6;
        let span = |t: &[u64], from: usize| t[3].saturating_sub(t[from]) as f64 * ms_per_tick;
        let per_frame = || ticks.chunks_exact(QUERIES_PER_FRAME as usize);
        return Ok(RendererTimes {
            frame: FrameTimes { ms: per_frame().map(|t| span(t, 0)).collect(), source: TimingSource::Timestamps },
            trace: Some(FrameTimes { ms: per_frame().map(|t| span(t, 2)).collect(), source: TimingSource::Timestamps }),
        });
    }
    let mut ms = Vec::with_capacity(frames as usize);
    for _ in 0..frames {
        let started = std::time::Instant::now();
        submit(&plain)?;
        gpu.wait()?;
        ms.push(started.elapsed().as_secs_f64() * 1e3);
    }
    Ok(RendererTimes { frame: FrameTimes { ms, source: TimingSource::WallClock }, trace: None })
}
