//! The cost axis of the accuracy sweep: the time of the impostor cloud pass
//! ([`crate::cloud::ImpostorCloudPass`]: clear, depth splat, owner splat, resolve) that draws a
//! comparison scene, so that each atlas configuration's error can be charted against the time
//! it costs on the GPU as well as against its memory.
//!
//! On an adapter with trustworthy timestamps the time is the span from the first pass's start
//! to the last pass's end ([`TimingSource::Timestamps`]); on a software adapter, whose
//! timestamps do not bracket the work, it is the wall time from submission to completion
//! ([`TimingSource::WallClock`]: it includes the driver's submission overhead). The caller picks
//! the clock (`gpu_harness::Gpu::has_timestamps` and `is_software` say which applies); the
//! figure kept is the fastest of [`SweepTiming::passes`] passes.

use gpu_harness::TimingSource;

use crate::gpu_util::{GpuError, read_buffer, wait};

/// Whether and how each impostor render of the sweep is timed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SweepTiming {
    /// Timed passes per configuration (the fastest is kept); at least 1.
    pub passes: u32,
    /// The clock: timestamps at the start and end of each of the cloud's passes, or the wall
    /// time from submission to the queue's completion.
    pub clock: TimingSource,
}

/// The number of timestamps one cloud pass writes (start and end of its four passes).
pub(crate) const CLOUD_TIMESTAMPS: u32 = 8;

/// A query set for one cloud pass and its resolve buffer.
pub(crate) struct CloudTimer {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
}

impl CloudTimer {
    const BYTES: u64 = CLOUD_TIMESTAMPS as u64 * 8;

    /// A timer on `device` (which must have `TIMESTAMP_QUERY`).
    pub(crate) fn new(device: &wgpu::Device) -> Self {
        Self {
            queries: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("impostor sweep timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: CLOUD_TIMESTAMPS,
            }),
            resolve: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("impostor sweep timestamp resolve"),
                size: Self::BYTES,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
        }
    }

    /// The query set the cloud pass writes into.
    pub(crate) fn queries(&self) -> &wgpu::QuerySet {
        &self.queries
    }

    /// Records the resolve of the pass's timestamps.
    pub(crate) fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.resolve_query_set(&self.queries, 0..CLOUD_TIMESTAMPS, &self.resolve, 0);
    }

    /// Milliseconds from the first timestamp to the last, once the submission resolving them
    /// has completed.
    pub(crate) fn read_ms(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<f64, GpuError> {
        let bytes = read_buffer(device, queue, &self.resolve, Self::BYTES)?;
        let ticks: [u64; CLOUD_TIMESTAMPS as usize] = bytemuck::pod_read_unaligned(&bytes);
        let period_ns = f64::from(queue.get_timestamp_period());
        Ok(ticks[CLOUD_TIMESTAMPS as usize - 1].saturating_sub(ticks[0]) as f64 * period_ns * 1e-6)
    }
}

/// Times `record` (which records one cloud pass, writing its timestamps into the given query
/// set when there is one) with `timing`: the fastest of its passes, in milliseconds.
pub(crate) fn fastest_ms(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    timing: SweepTiming,
    mut record: impl FnMut(&mut wgpu::CommandEncoder, Option<&wgpu::QuerySet>) -> Result<(), crate::cloud::CloudError>,
) -> Result<f64, super::SweepError> {
    if timing.passes == 0 {
        return Err(super::SweepError::Invalid("timing.passes is 0: at least one pass must be timed".into()));
    }
    let timer = match timing.clock {
        TimingSource::Timestamps if device.features().contains(wgpu::Features::TIMESTAMP_QUERY) => {
            Some(CloudTimer::new(device))
        }
        TimingSource::Timestamps => {
            return Err(super::SweepError::Invalid(
                "timing.clock is Timestamps but the device has no TIMESTAMP_QUERY".into(),
            ));
        }
        TimingSource::WallClock => None,
    };
    let mut fastest = f64::INFINITY;
    for _ in 0..timing.passes {
        let mut encoder =
            device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("timed impostor cloud") });
        record(&mut encoder, timer.as_ref().map(CloudTimer::queries))?;
        if let Some(timer) = &timer {
            timer.resolve(&mut encoder);
        }
        let start = std::time::Instant::now();
        queue.submit([encoder.finish()]);
        wait(device)?;
        let ms = match &timer {
            Some(timer) => timer.read_ms(device, queue)?,
            None => start.elapsed().as_secs_f64() * 1e3,
        };
        fastest = fastest.min(ms);
    }
    Ok(fastest)
}
