//! [`Gpu::compute_map`] with extra read-only storage buffers: for kernels that read a
//! scene (maps, patches, atlases) besides their per-element input, uploaded per call
//! ([`Gpu::compute_map_with_storage`]) or once ([`Gpu::upload_storage`],
//! [`Gpu::compute_map_with_uploaded_storage`]).

use bytemuck::Pod;
use wgpu::util::DeviceExt;

use crate::compute::{Kernel, WORKGROUP_SIZE};
use crate::timing::PassTimer;
use crate::{Gpu, GpuTiming, HarnessError, TimingSource};

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
    /// kernel's pipeline is compiled on its first call and reused after (see [`Gpu`]); the
    /// timing covers the dispatches only (timestamps where available, else the wall time
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
        let Kernel { pipeline, layout } = self.kernel(wgsl, entry_point, storage.len())?;
        let uniform_buffer = self.scoped(|| {
            let mut uniform_bytes = uniforms.to_vec();
            uniform_bytes.resize(uniform_bytes.len().next_multiple_of(16).max(16), 0);
            self.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("gpu-harness uniforms"),
                contents: &uniform_bytes,
                usage: wgpu::BufferUsages::UNIFORM,
            })
        })?;
        let timer = PassTimer::new(self);
        let mut outputs = Vec::with_capacity(inputs.len());
        let mut seconds = 0.0;
        let chunk_len = usize::try_from(chunk_len).unwrap_or(usize::MAX);
        for chunk in inputs.chunks(chunk_len) {
            let output_bytes = (chunk.len() * output_size) as u64;
            let groups = (chunk.len() as u64).div_ceil(u64::from(WORKGROUP_SIZE));
            let max_groups = u64::from(limits.max_compute_workgroups_per_dimension);
            let groups_x = groups.min(max_groups) as u32;
            let groups_y = groups.div_ceil(u64::from(groups_x.max(1))) as u32;
            let (output, started) = self.scoped(|| {
                let input = self.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("gpu-harness input"),
                    contents: bytemuck::cast_slice(chunk),
                    usage: wgpu::BufferUsages::STORAGE,
                });
                let output = self.device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("gpu-harness output"),
                    size: output_bytes,
                    usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                });
                let mut entries = vec![
                    wgpu::BindGroupEntry { binding: 0, resource: uniform_buffer.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 1, resource: input.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 2, resource: output.as_entire_binding() },
                ];
                for (k, buffer) in storage.buffers.iter().enumerate() {
                    entries.push(wgpu::BindGroupEntry { binding: 3 + k as u32, resource: buffer.as_entire_binding() });
                }
                let bind_group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("gpu-harness compute_map_with_storage"),
                    layout: &layout,
                    entries: &entries,
                });
                let mut encoder = self.device.create_command_encoder(&Default::default());
                {
                    let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                        label: Some("gpu-harness compute_map_with_storage"),
                        timestamp_writes: timer.as_ref().map(PassTimer::compute_writes),
                    });
                    pass.set_pipeline(&pipeline);
                    pass.set_bind_group(0, &bind_group, &[]);
                    pass.dispatch_workgroups(groups_x, groups_y, 1);
                }
                if let Some(timer) = &timer {
                    timer.resolve(&mut encoder);
                }
                let started = std::time::Instant::now();
                self.queue.submit([encoder.finish()]);
                (output, started)
            })?;
            self.wait()?;
            let wall = started.elapsed().as_secs_f64();
            seconds += match &timer {
                Some(timer) => timer.read_seconds(self)?,
                None => wall,
            };
            outputs.extend(bytemuck::pod_collect_to_vec::<u8, O>(&self.read_buffer(&output, output_bytes)?));
        }
        let source = if timer.is_some() { TimingSource::Timestamps } else { TimingSource::WallClock };
        Ok((outputs, GpuTiming { seconds, source }))
    }
}
