//! Copying GPU buffers back to the CPU.

use crate::{Gpu, HarnessError};

impl Gpu {
    /// Reads the first `size` bytes of `buffer`, which must have `COPY_SRC` usage, through
    /// a staging buffer. Waits for all submitted work.
    pub fn read_buffer(&self, buffer: &wgpu::Buffer, size: u64) -> Result<Vec<u8>, HarnessError> {
        if size == 0 {
            return Ok(Vec::new());
        }
        let staging = self.scoped(|| {
            let staging = self.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("gpu-harness readback"),
                size,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let mut encoder = self.device.create_command_encoder(&Default::default());
            encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, size);
            self.queue.submit([encoder.finish()]);
            staging
        })?;
        self.map_and_read(&staging)
    }

    /// Maps `staging` (with `MAP_READ` usage, no pending writes) and returns its bytes.
    pub(crate) fn map_and_read(&self, staging: &wgpu::Buffer) -> Result<Vec<u8>, HarnessError> {
        let (sender, receiver) = std::sync::mpsc::channel();
        let slice = staging.slice(..);
        slice.map_async(wgpu::MapMode::Read, move |result| {
            // The receiver outlives the wait below; a closed channel only means the
            // caller has already given up, so the send result is irrelevant.
            let _ = sender.send(result);
        });
        self.wait()?;
        receiver
            .recv()
            .map_err(|e| HarnessError::Readback(e.to_string()))?
            .map_err(|e| HarnessError::Readback(e.to_string()))?;
        let bytes = slice.get_mapped_range().map_err(|e| HarnessError::Readback(e.to_string()))?.to_vec();
        staging.unmap();
        Ok(bytes)
    }
}
