//! [`Gpu::compute_map`] with extra read-only storage buffers: for kernels that read a
//! scene (maps, patches, atlases) besides their per-element input, uploaded per call
//! ([`Gpu::compute_map_with_storage`]) or once ([`Gpu::upload_storage`],
//! [`Gpu::compute_map_with_uploaded_storage`]).

use bytemuck::Pod;
use wgpu::util::DeviceExt;

use crate::{Gpu, GpuTiming, HarnessError};

/// Read-only storage buffers uploaded once with [`Gpu::upload_storage`], bound at bindings
/// `3..` by [`Gpu::compute_map_with_uploaded_storage`] in as many calls as needed (a scene
/// traced with several kernels or ray sets, a timed call repeated): no upload per call.
#[derive(Debug)]
pub struct UploadedStorage {
    buffers: Vec<wgpu::Buffer>,
}

impl UploadedStorage {
    /// Number of buffers (bound at `3..3 + len`).
    pub fn len(&self) -> usize {
        self.buffers.len()
    }

    /// Whether there is no buffer.
    pub fn is_empty(&self) -> bool {
        self.buffers.is_empty()
    }
}

impl Gpu {
    /// Uploads `storage[k]` into a read-only storage buffer for binding `3 + k` (padded to
    /// a multiple of 4 bytes). Each must be non-empty and fit the adapter's storage-binding
    /// and buffer-size limits, and the bindings (with the input and output) must fit its
    /// storage buffers per stage; violations are errors naming the binding, never panics.
    pub fn upload_storage(&self, storage: &[&[u8]]) -> Result<UploadedStorage, HarnessError> {
        let limits = self.limits();
        let binding_limit = limits.max_storage_buffer_binding_size.min(limits.max_buffer_size);
        let buffers = 2 + storage.len() as u64;
        if buffers > u64::from(limits.max_storage_buffers_per_shader_stage) {
            return Err(HarnessError::TooLarge {
                what: "storage buffers per shader stage".into(),
                requested: buffers,
                limit: u64::from(limits.max_storage_buffers_per_shader_stage),
            });
        }
        for (k, bytes) in storage.iter().enumerate() {
            if bytes.is_empty() {
                return Err(HarnessError::InvalidRequest(format!("storage buffer {} is empty", 3 + k)));
            }
            if bytes.len() as u64 > binding_limit {
                return Err(HarnessError::TooLarge {
                    what: format!("storage buffer {} in bytes", 3 + k),
                    requested: bytes.len() as u64,
                    limit: binding_limit,
                });
            }
        }
        let buffers = self.scoped(|| {
            storage
                .iter()
                .map(|bytes| {
                    let mut padded = bytes.to_vec();
                    padded.resize(padded.len().next_multiple_of(4), 0);
                    self.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                        label: Some("gpu-harness storage"),
                        contents: &padded,
                        usage: wgpu::BufferUsages::STORAGE,
                    })
                })
                .collect()
        })?;
        Ok(UploadedStorage { buffers })
    }

    /// Runs `entry_point` of `wgsl` once per element of `inputs`, like
    /// [`compute_map_timed`](Self::compute_map_timed), with `storage[k]` bound read-only at
    /// binding `3 + k` for every dispatch: [`upload_storage`](Self::upload_storage) then
    /// [`compute_map_with_uploaded_storage`](Self::compute_map_with_uploaded_storage) (see
    /// both for the checks). To run several calls over the same buffers, upload them once
    /// and call the latter.
    pub fn compute_map_with_storage<I: Pod, O: Pod>(
        &self,
        wgsl: &str,
        entry_point: &str,
        uniforms: &[u8],
        inputs: &[I],
        storage: &[&[u8]],
    ) -> Result<(Vec<O>, GpuTiming), HarnessError> {
        // Checked before the upload, which would be wasted otherwise.
        if size_of::<I>() == 0 || size_of::<O>() == 0 {
            return Err(HarnessError::InvalidRequest("compute_map needs non-zero-sized element types".into()));
        }
        let storage = self.upload_storage(storage)?;
        self.compute_map_with_uploaded_storage(wgsl, entry_point, uniforms, inputs, &storage)
    }

    /// [`compute_map_with_storage`](Self::compute_map_with_storage) over buffers uploaded
    /// before: `storage`'s buffers are bound read-only at `3..` for every dispatch. The
    /// kernel's pipeline is compiled on its first call, warmed up and reused after (see the
    /// crate's "Warm calls"); the timing covers the dispatches only (timestamps where available, else the wall time
    /// from submission to completion of each dispatch), never compilation, uploads or
    /// readback. Zero-sized element types and uniforms above the adapter's limit are errors,
    /// never panics.
    pub fn compute_map_with_uploaded_storage<I: Pod, O: Pod>(
        &self,
        wgsl: &str,
        entry_point: &str,
        uniforms: &[u8],
        inputs: &[I],
        storage: &UploadedStorage,
    ) -> Result<(Vec<O>, GpuTiming), HarnessError> {
        self.compute_map_specialized(wgsl, entry_point, &[], uniforms, inputs, storage)
    }

    /// [`compute_map_with_uploaded_storage`](Self::compute_map_with_uploaded_storage) with
    /// the kernel's pipeline-overridable constants (WGSL `override`s) set to `constants`,
    /// `(name, value)` as `wgpu::PipelineCompilationOptions::constants` takes them: each
    /// setting is compiled once, then reused.
    pub fn compute_map_specialized<I: Pod, O: Pod>(
        &self,
        wgsl: &str,
        entry_point: &str,
        constants: &[(&str, f64)],
        uniforms: &[u8],
        inputs: &[I],
        storage: &UploadedStorage,
    ) -> Result<(Vec<O>, GpuTiming), HarnessError> {
        let (input_size, output_size) = (size_of::<I>(), size_of::<O>());
        if input_size == 0 || output_size == 0 {
            return Err(HarnessError::InvalidRequest("compute_map needs non-zero-sized element types".into()));
        }
        let limits = self.limits();
        if uniforms.len() as u64 > limits.max_uniform_buffer_binding_size {
            return Err(HarnessError::TooLarge {
                what: "uniform block size in bytes".into(),
                requested: uniforms.len() as u64,
                limit: limits.max_uniform_buffer_binding_size,
            });
        }
        let chunk_len = self.max_elements_per_dispatch(input_size, output_size);
        if chunk_len == 0 {
            return Err(HarnessError::TooLarge {
                what: "element size in bytes".into(),
                requested: input_size.max(output_size) as u64,
                limit: limits.max_storage_buffer_binding_size,
            });
        }
        let kernel = self.kernel(wgsl, entry_point, constants, storage.len())?;
        let chunk_len = usize::try_from(chunk_len).unwrap_or(usize::MAX);
        self.map_chunks(&kernel, uniforms, inputs, chunk_len, &storage.buffers)
    }
}
