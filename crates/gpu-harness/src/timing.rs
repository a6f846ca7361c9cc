//! GPU timing: timestamp queries when the adapter has them, wall time otherwise.

use std::fmt;

use crate::{Gpu, HarnessError};

/// How a [`GpuTiming`] was measured.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimingSource {
    /// GPU timestamp queries written at the start and end of each pass.
    Timestamps,
    /// Wall-clock time around submission and completion (includes driver overhead); used
    /// when the adapter lacks `TIMESTAMP_QUERY`.
    WallClock,
}

/// A measured GPU duration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GpuTiming {
    /// Duration in seconds.
    pub seconds: f64,
    /// How it was measured.
    pub source: TimingSource,
}

impl Gpu {
    /// How GPU work is timed on this adapter: timestamps where it has them and is hardware,
    /// the wall clock otherwise (a software adapter's timestamps do not bracket the work).
    pub fn timing_source(&self) -> TimingSource {
        if self.has_timestamps() && !self.is_software() { TimingSource::Timestamps } else { TimingSource::WallClock }
    }
}

impl TimingSource {
    /// The source's name in tables and charts: "GPU timestamps" or "wall clock".
    pub fn name(self) -> &'static str {
        match self {
            Self::Timestamps => "GPU timestamps",
            Self::WallClock => "wall clock",
        }
    }
}

impl fmt::Display for GpuTiming {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let source = match self.source {
            TimingSource::Timestamps => "GPU timestamps",
            TimingSource::WallClock => "wall clock: the adapter has no timestamp queries",
        };
        write!(f, "{:.4} ms ({source})", self.seconds * 1e3)
    }
}

/// The times of repeated frames of one configuration (a benchmark's raw figures).
#[derive(Clone, Debug, PartialEq)]
pub struct FrameTimes {
    /// Milliseconds per timed frame, in order.
    pub ms: Vec<f64>,
    /// How they were measured.
    pub source: TimingSource,
}

impl FrameTimes {
    /// The median (the mean of the middle two for an even count; 0 without frames).
    pub fn median(&self) -> f64 {
        self.quantile(0.5)
    }

    /// The `q`-quantile, `q ∈ [0, 1]` (clamped), linearly interpolated between order
    /// statistics; 0 without frames.
    pub fn quantile(&self, q: f64) -> f64 {
        if self.ms.is_empty() {
            return 0.0;
        }
        let mut sorted = self.ms.clone();
        sorted.sort_by(f64::total_cmp);
        let position = q.clamp(0.0, 1.0) * (sorted.len() - 1) as f64;
        let (low, high) = (position.floor() as usize, position.ceil() as usize);
        sorted[low] + (sorted[high] - sorted[low]) * (position - low as f64)
    }
}

/// A pair of timestamp queries and their resolve buffers.
pub(crate) struct PassTimer {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
}

impl PassTimer {
    /// A timer if the device has timestamp queries.
    pub(crate) fn new(gpu: &Gpu) -> Option<Self> {
        gpu.has_timestamps().then(|| Self {
            queries: gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("gpu-harness timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: 2,
            }),
            resolve: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("gpu-harness timestamp resolve"),
                size: 16,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
        })
    }

    pub(crate) fn compute_writes(&self) -> wgpu::ComputePassTimestampWrites<'_> {
        wgpu::ComputePassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: Some(0),
            end_of_pass_write_index: Some(1),
        }
    }

    pub(crate) fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.resolve_query_set(&self.queries, 0..2, &self.resolve, 0);
    }

    /// Seconds between the two timestamps, once the resolving submission completed.
    pub(crate) fn read_seconds(&self, gpu: &Gpu) -> Result<f64, HarnessError> {
        let bytes = gpu.read_buffer(&self.resolve, 16)?;
        let ticks: [u64; 2] = bytemuck::pod_read_unaligned(&bytes);
        let period_ns = f64::from(gpu.queue.get_timestamp_period());
        Ok(ticks[1].saturating_sub(ticks[0]) as f64 * period_ns * 1e-9)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_interpolate_between_order_statistics() {
        let times = FrameTimes { ms: vec![4.0, 1.0, 3.0, 2.0], source: TimingSource::WallClock };
        assert_eq!(times.median(), 2.5);
        assert_eq!(times.quantile(0.0), 1.0);
        assert_eq!(times.quantile(2.0), 4.0);
        assert!((times.quantile(0.1) - 1.3).abs() < 1e-12);
        assert_eq!(FrameTimes { ms: Vec::new(), source: TimingSource::Timestamps }.median(), 0.0);
    }
}
