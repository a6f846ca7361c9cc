//! Running a compute kernel over a slice, chunked to the adapter's limits.

use std::sync::PoisonError;
use std::sync::atomic::Ordering;
use std::time::Instant;

use bytemuck::Pod;
use wgpu::util::DeviceExt;

use crate::kernel_cache::Kernel;
use crate::timing::PassTimer;
use crate::{Gpu, GpuTiming, HarnessError, TimingSource};

/// Invocations per workgroup that [`Gpu::compute_map`] assumes: kernels declare
/// `@workgroup_size(64)`.
pub const WORKGROUP_SIZE: u32 = 64;

fn storage_entry(binding: u32, read_only: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

impl Gpu {
    /// The pipeline of `entry_point` of `wgsl` with the harness's bind group layout: the
    /// uniform block at binding 0, the input at 1, the output at 2, and `scene_buffers`
    /// read-only storage buffers at bindings `3..` (see
    /// [`compute_map_with_storage`](Self::compute_map_with_storage)). Compiled on the first
    /// call for that source, entry point and buffer count, then taken from the cache; a
    /// kernel that fails to compile is not cached (the next call reports the error again).
    /// `constants` set the source's pipeline-overridable constants (WGSL `override`s); each
    /// setting is its own kernel.
    pub(crate) fn kernel(
        &self,
        wgsl: &str,
        entry_point: &str,
        constants: &[(&str, f64)],
        scene_buffers: usize,
    ) -> Result<Kernel, HarnessError> {
        let settings = constants.iter().map(|&(name, value)| (name.to_owned(), value.to_bits())).collect();
        let key = (wgsl.to_owned(), entry_point.to_owned(), scene_buffers, settings);
        // Held while compiling: a second thread asking for the same kernel waits for it
        // instead of compiling it again (compilation is serialized by the error scopes anyway).
        let mut kernels = self.kernels.kernels.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(kernel) = kernels.get(&key) {
            return Ok(kernel.clone());
        }
        let kernel = self.compile_kernel(wgsl, entry_point, constants, scene_buffers)?;
        self.kernels.compilations.fetch_add(1, Ordering::Relaxed);
        kernels.insert(key, kernel.clone());
        Ok(kernel)
    }

    /// How many kernels this device has compiled so far.
    #[cfg(test)]
    pub(crate) fn kernel_compilations(&self) -> usize {
        self.kernels.compilations.load(Ordering::Relaxed)
    }

    /// How many untimed warm-up dispatches this device has run so far.
    #[cfg(test)]
    pub(crate) fn kernel_warm_ups(&self) -> usize {
        self.kernels.warm_ups.load(Ordering::Relaxed)
    }

    fn compile_kernel(
        &self,
        wgsl: &str,
        entry_point: &str,
        constants: &[(&str, f64)],
        scene_buffers: usize,
    ) -> Result<Kernel, HarnessError> {
        self.scoped(|| {
            let module = self.device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(entry_point),
                source: wgpu::ShaderSource::Wgsl(wgsl.into()),
            });
            let uniform = wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            };
            let mut entries = vec![uniform, storage_entry(1, true), storage_entry(2, false)];
            entries.extend((0..scene_buffers).map(|k| storage_entry(3 + k as u32, true)));
            let layout = self.device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("gpu-harness compute_map"),
                entries: &entries,
            });
            let pipeline_layout = self.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("gpu-harness compute_map"),
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
            let pipeline = self.device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry_point),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(entry_point),
                compilation_options: wgpu::PipelineCompilationOptions { constants, ..Default::default() },
                cache: None,
            });
            Kernel::new(pipeline, layout)
        })
    }

    /// The most elements of the larger of `I` and `O` that one dispatch may handle: the
    /// storage-binding and buffer-size limits, and the 2-D dispatch limit.
    pub fn max_elements_per_dispatch(&self, input_size: usize, output_size: usize) -> u64 {
        let limits = self.limits();
        let element = input_size.max(output_size).max(1) as u64;
        let binding = limits.max_storage_buffer_binding_size.min(limits.max_buffer_size);
        let groups = u64::from(limits.max_compute_workgroups_per_dimension);
        // Saturating: an adapter may report u32::MAX workgroups per dimension.
        (binding / element).min(groups.saturating_mul(groups).saturating_mul(u64::from(WORKGROUP_SIZE)))
    }

    /// Runs `entry_point` of `wgsl` once per element of `inputs` (see the crate's kernel
    /// convention) and returns one `O` per input. `uniforms` are bound at binding 0 (a
    /// 16-byte zero block when empty).
    ///
    /// Inputs larger than one storage binding are processed in chunks. Zero-sized element
    /// types and uniforms above the adapter's limit are errors, never panics.
    pub fn compute_map<I: Pod, O: Pod>(
        &self,
        wgsl: &str,
        entry_point: &str,
        uniforms: &[u8],
        inputs: &[I],
    ) -> Result<Vec<O>, HarnessError> {
        self.compute_map_timed(wgsl, entry_point, uniforms, inputs).map(|(outputs, _)| outputs)
    }

    /// [`compute_map`](Self::compute_map), also returning the GPU time of the dispatches
    /// (summed over chunks): timestamps where the adapter has them, else the wall time from
    /// each dispatch's submission to its completion; never compilation, uploads or readback,
    /// and always of a warm pipeline (see the crate's "Warm calls").
    pub fn compute_map_timed<I: Pod, O: Pod>(
        &self,
        wgsl: &str,
        entry_point: &str,
        uniforms: &[u8],
        inputs: &[I],
    ) -> Result<(Vec<O>, GpuTiming), HarnessError> {
        self.compute_map_in_chunks(wgsl, entry_point, uniforms, inputs, u64::MAX)
    }

    /// [`compute_map_timed`](Self::compute_map_timed) with at most `max_chunk_elements`
    /// elements per dispatch (further bounded by the adapter's limits), to bound memory
    /// use or to exercise chunk boundaries. Kernels see chunk-local indices.
    pub fn compute_map_in_chunks<I: Pod, O: Pod>(
        &self,
        wgsl: &str,
        entry_point: &str,
        uniforms: &[u8],
        inputs: &[I],
        max_chunk_elements: u64,
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
        let chunk_len = self.max_elements_per_dispatch(input_size, output_size).min(max_chunk_elements);
        if max_chunk_elements == 0 {
            return Err(HarnessError::InvalidRequest("chunks must hold at least one element".into()));
        }
        if chunk_len == 0 {
            return Err(HarnessError::TooLarge {
                what: "element size in bytes".into(),
                requested: input_size.max(output_size) as u64,
                limit: limits.max_storage_buffer_binding_size,
            });
        }
        let kernel = self.kernel(wgsl, entry_point, &[], 0)?;
        let chunk_len = usize::try_from(chunk_len).unwrap_or(usize::MAX);
        self.map_chunks(&kernel, uniforms, inputs, chunk_len, &[])
    }

    /// Runs `kernel` over `inputs` in chunks of `chunk_len` (≥ 1) elements with `scene`
    /// bound at `3..`, and sums the dispatches' times. A kernel never dispatched before
    /// first runs one untimed workgroup over the first elements into a scratch output, so
    /// that whatever a driver defers to a pipeline's first use (lazy compilation, first-use
    /// allocation) stays out of the timing: every timed dispatch runs a warm pipeline.
    pub(crate) fn map_chunks<I: Pod, O: Pod>(
        &self,
        kernel: &Kernel,
        uniforms: &[u8],
        inputs: &[I],
        chunk_len: usize,
        scene: &[wgpu::Buffer],
    ) -> Result<(Vec<O>, GpuTiming), HarnessError> {
        let output_size = size_of::<O>();
        let uniform_buffer = self.scoped(|| {
            let mut uniform_bytes = uniforms.to_vec();
            uniform_bytes.resize(uniform_bytes.len().next_multiple_of(16).max(16), 0);
            self.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("gpu-harness uniforms"),
                contents: &uniform_bytes,
                usage: wgpu::BufferUsages::UNIFORM,
            })
        })?;
        if !inputs.is_empty() && !kernel.warm.swap(true, Ordering::AcqRel) {
            let first = &inputs[..inputs.len().min(WORKGROUP_SIZE as usize).min(chunk_len.max(1))];
            self.dispatch_chunk(kernel, &uniform_buffer, first, output_size, scene, None)?;
            self.kernels.warm_ups.fetch_add(1, Ordering::Relaxed);
        }
        let mut outputs = Vec::with_capacity(inputs.len());
        let mut seconds = 0.0;
        let timer = PassTimer::new(self);
        for chunk in inputs.chunks(chunk_len.max(1)) {
            let (bytes, chunk_seconds) =
                self.dispatch_chunk(kernel, &uniform_buffer, chunk, output_size, scene, timer.as_ref())?;
            outputs.extend(bytemuck::pod_collect_to_vec::<u8, O>(&bytes));
            seconds += chunk_seconds;
        }
        let source = if timer.is_some() { TimingSource::Timestamps } else { TimingSource::WallClock };
        Ok((outputs, GpuTiming { seconds, source }))
    }

    /// One dispatch over `chunk` (non-empty) into a new output buffer, read back; its time
    /// from `timer` (timestamps), else the wall time from submission to completion.
    fn dispatch_chunk<I: Pod>(
        &self,
        kernel: &Kernel,
        uniform_buffer: &wgpu::Buffer,
        chunk: &[I],
        output_size: usize,
        scene: &[wgpu::Buffer],
        timer: Option<&PassTimer>,
    ) -> Result<(Vec<u8>, f64), HarnessError> {
        let output_bytes = (chunk.len() * output_size) as u64;
        let groups = (chunk.len() as u64).div_ceil(u64::from(WORKGROUP_SIZE));
        let max_groups = u64::from(self.limits().max_compute_workgroups_per_dimension);
        let groups_x = groups.min(max_groups).max(1) as u32;
        let groups_y = groups.div_ceil(u64::from(groups_x)) as u32;
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
            entries.extend(
                scene
                    .iter()
                    .zip(3_u32..)
                    .map(|(buffer, binding)| wgpu::BindGroupEntry { binding, resource: buffer.as_entire_binding() }),
            );
            let bind_group = self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("gpu-harness compute_map"),
                layout: &kernel.layout,
                entries: &entries,
            });
            let mut encoder = self.device.create_command_encoder(&Default::default());
            {
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("gpu-harness compute_map"),
                    timestamp_writes: timer.map(PassTimer::compute_writes),
                });
                pass.set_pipeline(&kernel.pipeline);
                pass.set_bind_group(0, &bind_group, &[]);
                pass.dispatch_workgroups(groups_x, groups_y, 1);
            }
            if let Some(timer) = timer {
                timer.resolve(&mut encoder);
            }
            let started = Instant::now();
            self.queue.submit([encoder.finish()]);
            (output, started)
        })?;
        self.wait()?;
        let wall = started.elapsed().as_secs_f64();
        let seconds = match timer {
            Some(timer) => timer.read_seconds(self)?,
            None => wall,
        };
        Ok((self.read_buffer(&output, output_bytes)?, seconds))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A device on wgpu's noop backend: it creates and validates pipelines and maps
    /// buffers but executes nothing, so these tests need no adapter (they count
    /// compilations, not results; `tests/harness_gpu.rs` checks results on a real one).
    fn noop_gpu() -> Gpu {
        let mut descriptor = wgpu::InstanceDescriptor::new_without_display_handle();
        descriptor.backends = wgpu::Backends::NOOP;
        descriptor.backend_options.noop = wgpu::NoopBackendOptions::enabled();
        let instance = wgpu::Instance::new(descriptor);
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default()))
            .expect("the noop backend always has an adapter");
        Gpu::on_adapter(adapter, wgpu::Features::empty()).expect("the noop adapter creates devices")
    }

    const KERNEL: &str = "
@group(0) @binding(0) var<uniform> factor: vec4<u32>;
@group(0) @binding(1) var<storage, read> input: array<u32>;
@group(0) @binding(2) var<storage, read_write> output: array<u32>;
@group(0) @binding(3) var<storage, read> scene: array<u32>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = id.x + id.y * groups.x * 64u;
    if index >= arrayLength(&input) {
        return;
    }
    output[index] = input[index] * factor.x;
}

@compute @workgroup_size(64)
fn with_scene(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = id.x + id.y * groups.x * 64u;
    if index >= arrayLength(&input) {
        return;
    }
    output[index] = input[index] + scene[0];
}

override OFFSET: u32 = 0u;

@compute @workgroup_size(64)
fn with_offset(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = id.x + id.y * groups.x * 64u;
    if index >= arrayLength(&input) {
        return;
    }
    output[index] = input[index] + scene[0] + OFFSET;
}
";

    #[test]
    fn a_second_call_reuses_the_compiled_kernel() {
        let gpu = noop_gpu();
        let inputs: Vec<u32> = (0..1000).collect();
        let uniforms = bytemuck::bytes_of(&[2_u32; 4]);
        assert_eq!(gpu.kernel_compilations(), 0);
        let _: Vec<u32> = gpu.compute_map(KERNEL, "main", uniforms, &inputs).unwrap();
        // Compiled, and warmed up once before its timed dispatch.
        assert_eq!((gpu.kernel_compilations(), gpu.kernel_warm_ups()), (1, 1));
        // Same kernel: timed, chunked, other uniforms and inputs; no compilation, no warm-up.
        let _: (Vec<u32>, _) = gpu.compute_map_timed(KERNEL, "main", &[], &inputs[..10]).unwrap();
        let _: (Vec<u32>, _) = gpu.compute_map_in_chunks(KERNEL, "main", uniforms, &inputs, 100).unwrap();
        assert_eq!((gpu.kernel_compilations(), gpu.kernel_warm_ups()), (1, 1));
        // Another entry point, and the same one with a scene buffer (another layout).
        let scene = [7_u32];
        let _: (Vec<u32>, _) =
            gpu.compute_map_with_storage(KERNEL, "with_scene", &[], &inputs, &[bytemuck::bytes_of(&scene)]).unwrap();
        assert_eq!(gpu.kernel_compilations(), 2);
        let uploaded = gpu.upload_storage(&[bytemuck::bytes_of(&scene)]).unwrap();
        for _ in 0..3 {
            let _: (Vec<u32>, _) =
                gpu.compute_map_with_uploaded_storage(KERNEL, "with_scene", &[], &inputs, &uploaded).unwrap();
        }
        assert_eq!(gpu.kernel_compilations(), 2);
        let _: (Vec<u32>, _) =
            gpu.compute_map_with_uploaded_storage(KERNEL, "main", uniforms, &inputs, &uploaded).unwrap();
        assert_eq!(gpu.kernel_compilations(), 3);
        // Another source (one more space) is another kernel.
        let other = format!("{KERNEL} ");
        let _: Vec<u32> = gpu.compute_map(&other, "main", uniforms, &inputs).unwrap();
        assert_eq!((gpu.kernel_compilations(), gpu.kernel_warm_ups()), (4, 4));
        // Each setting of the overridable constants is its own kernel, compiled once.
        for offset in [1.0, 2.0, 1.0] {
            let _: (Vec<u32>, _) = gpu
                .compute_map_specialized(KERNEL, "with_offset", &[("OFFSET", offset)], &[], &inputs, &uploaded)
                .unwrap();
        }
        assert_eq!(gpu.kernel_compilations(), 6);
    }

    #[test]
    fn a_kernel_first_called_without_inputs_is_warmed_up_by_its_first_dispatch() {
        let gpu = noop_gpu();
        let _: Vec<u32> = gpu.compute_map(KERNEL, "main", &[], &[] as &[u32]).unwrap();
        assert_eq!((gpu.kernel_compilations(), gpu.kernel_warm_ups()), (1, 0));
        for _ in 0..2 {
            let _: Vec<u32> = gpu.compute_map(KERNEL, "main", &[], &[1_u32, 2, 3]).unwrap();
        }
        assert_eq!((gpu.kernel_compilations(), gpu.kernel_warm_ups()), (1, 1));
    }

    #[test]
    fn a_kernel_that_fails_to_compile_is_not_cached() {
        let gpu = noop_gpu();
        for _ in 0..2 {
            let result = gpu.compute_map::<u32, u32>(KERNEL, "missing_entry_point", &[], &[1]);
            assert!(matches!(result, Err(HarnessError::Wgpu(_))), "{result:?}");
        }
        assert_eq!(gpu.kernel_compilations(), 0);
        let _: Vec<u32> = gpu.compute_map(KERNEL, "main", &[], &[1_u32]).unwrap();
        assert_eq!(gpu.kernel_compilations(), 1);
    }
}
