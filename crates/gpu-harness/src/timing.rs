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

impl fmt::Display for GpuTiming {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let source = match self.source {
            TimingSource::Timestamps => "GPU timestamps",
            TimingSource::WallClock => "wall clock: the adapter has no timestamp queries",
        };
        write!(f, "{:.4} ms ({source})", self.seconds * 1e3)
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
