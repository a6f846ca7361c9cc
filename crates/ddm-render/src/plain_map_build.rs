//! The plain distance map built on the GPU in compute (the option Mehra & Kumar point to
//! when they cite GPU distance-field methods, §3.1): one thread per column of voxels runs the CPU's
//! search of `ddm_compress::compute_distance_maps` with `MapKind::Plain` over a
//! [`PlainGpuScene`] (`shaders/plain_map_build.wgsl`, composed after `ddm-compress`'s WGSL
//! twin), each thread a column of [`PLAIN_BUILD_COLUMN`] voxels seeded like the CPU's.
//!
//! [`PlainMapPipeline`] is built once per device; [`PlainMapBuild`] uploads one scene and
//! owns its output buffers, and [`PlainMapBuild::encode`] records the dispatch into the
//! caller's encoder (no readback, no pipeline creation). The values stay on the GPU for
//! whoever binds [`PlainMapBuild::values`]; [`PlainMapBuild::read_back`] returns them as
//! [`DistanceMaps`] for tests and tools.

use ddm_compress::{DistanceMaps, PlainGpuScene};
use gpu_harness::{FrameTimes, Gpu, TimingSource, error_scoped};
use gpu_layout::{GpuConst, gpu_const};
use wgpu::util::DeviceExt;
use wgsl_gen::{ComposedShader, StructDecl, generate_declarations};

use crate::error::{DdmRenderError, check_limit};
use crate::gbuffer::PassTimestamps;
use crate::renderer::{buffer_type, compute_entry};
use crate::timing::TimestampQueries;

/// Side of the build kernel's square workgroups, in columns of voxels
/// (`@workgroup_size(PLAIN_BUILD_TILE, PLAIN_BUILD_TILE, 1)`; the WGSL constant is generated
/// from this one): neighbouring columns visit nearly the same nodes.
pub const PLAIN_BUILD_TILE: u32 = 8;

/// Voxels per thread, a column along z: each voxel tries the triangle nearest the one
/// below first, as the CPU's search tries the previous voxel's along x.
pub const PLAIN_BUILD_COLUMN: u32 = 8;

/// Path of the build kernel, relative to the workspace root.
pub const PLAIN_BUILD_WGSL_PATH: &str = "crates/ddm-render/shaders/plain_map_build.wgsl";
/// The build kernel (entry point `build_plain_map`).
pub const PLAIN_BUILD_WGSL: &str = include_str!("../shaders/plain_map_build.wgsl");

/// Name of the composed build shader (in errors).
pub(crate) const PLAIN_BUILD_SHADER: &str = "ddm_render_plain_map_build";

const ENTRY_POINT: &str = "build_plain_map";

/// The constants of the build kernel that its WGSL declares from Rust.
const PLAIN_BUILD_CONSTANTS: &[GpuConst] = &[gpu_const!(PLAIN_BUILD_TILE: u32), gpu_const!(PLAIN_BUILD_COLUMN: u32)];

/// The Rust structs that the build kernel binds, declared by `ddm-compress`'s twin
/// (checked against the composed shader by this crate's tests).
pub fn plain_build_structs() -> Vec<StructDecl> {
    vec![
        StructDecl::of::<ddm_compress::PlainGpuUniforms>(),
        StructDecl::of::<ddm_compress::PlainGpuNode>(),
        StructDecl::of::<ddm_compress::PlainGpuTriangle>(),
    ]
}

/// The composed build shader: `ddm-compress`'s WGSL twin, the generated
/// [`PLAIN_BUILD_TILE`] and [`PLAIN_BUILD_COLUMN`], then [`PLAIN_BUILD_WGSL`].
pub fn plain_build_shader() -> Result<ComposedShader, DdmRenderError> {
    let constants = generate_declarations(PLAIN_BUILD_SHADER, &[], PLAIN_BUILD_CONSTANTS)
        .map_err(|e| DdmRenderError::InvalidShader { shader: PLAIN_BUILD_SHADER, message: e.to_string() })?;
    Ok(ComposedShader::of_module(&ddm_compress::WGSL)
        .with_part("generated: PLAIN_BUILD_TILE, PLAIN_BUILD_COLUMN", &constants)
        .with_part(PLAIN_BUILD_WGSL_PATH, PLAIN_BUILD_WGSL))
}

/// The build kernel's pipeline and bind group layout, built once per device.
#[derive(Debug)]
pub struct PlainMapPipeline {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

impl PlainMapPipeline {
    /// Composes, validates (naga) and builds the kernel. Errors name the shader file and
    /// line, or the wgpu error.
    pub fn new(device: &wgpu::Device) -> Result<Self, DdmRenderError> {
        let shader = plain_build_shader()?;
        shader
            .validate()
            .map_err(|e| DdmRenderError::InvalidShader { shader: PLAIN_BUILD_SHADER, message: e.to_string() })?;
        Ok(error_scoped(device, || {
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(PLAIN_BUILD_SHADER),
                source: wgpu::ShaderSource::Wgsl(shader.source().into()),
            });
            let entry = |binding: u32, ty: wgpu::BufferBindingType| compute_entry(binding, buffer_type(ty));
            let read = wgpu::BufferBindingType::Storage { read_only: true };
            let write = wgpu::BufferBindingType::Storage { read_only: false };
            let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("ddm-render plain map build"),
                entries: &[
                    entry(0, wgpu::BufferBindingType::Uniform),
                    entry(1, read),
                    entry(2, read),
                    entry(3, write),
                    entry(4, write),
                ],
            });
            let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("ddm-render plain map build"),
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
            let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(ENTRY_POINT),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(ENTRY_POINT),
                compilation_options: Default::default(),
                cache: None,
            });
            Self { pipeline, layout }
        })?)
    }
}

/// One scene uploaded for [`PlainMapPipeline`], with its output buffers (one `f32` value
/// and one `u32` surface flag per voxel, `STORAGE | COPY_SRC`).
#[derive(Debug)]
pub struct PlainMapBuild {
    scene: PlainGpuScene,
    bind_group: wgpu::BindGroup,
    values: wgpu::Buffer,
    surface: wgpu::Buffer,
    workgroups: [u32; 3],
    pipeline: wgpu::ComputePipeline,
}

impl PlainMapBuild {
    /// Uploads `scene` and creates the output buffers. Errors name the buffer or the
    /// dispatch size that exceeds a limit of `device`.
    pub fn new(
        device: &wgpu::Device,
        pipeline: &PlainMapPipeline,
        scene: &PlainGpuScene,
    ) -> Result<Self, DdmRenderError> {
        let limits = device.limits();
        let binding_limit = limits.max_storage_buffer_binding_size.min(limits.max_buffer_size);
        let node_bytes: &[u8] = bytemuck::cast_slice(scene.nodes());
        let triangle_bytes: &[u8] = bytemuck::cast_slice(scene.triangles());
        let output_bytes = scene.voxel_count() as u64 * 4;
        check_limit(
            "plain map nodes in bytes (max_storage_buffer_binding_size)",
            node_bytes.len() as u64,
            binding_limit,
        )?;
        check_limit(
            "plain map triangles in bytes (max_storage_buffer_binding_size)",
            triangle_bytes.len() as u64,
            binding_limit,
        )?;
        check_limit("plain map values in bytes (max_storage_buffer_binding_size)", output_bytes, binding_limit)?;
        let dims = scene.dims();
        let workgroups =
            [dims.x.div_ceil(PLAIN_BUILD_TILE), dims.y.div_ceil(PLAIN_BUILD_TILE), dims.z.div_ceil(PLAIN_BUILD_COLUMN)];
        for groups in workgroups {
            check_limit(
                "plain map workgroups per dimension (max_compute_workgroups_per_dimension)",
                u64::from(groups),
                u64::from(limits.max_compute_workgroups_per_dimension),
            )?;
        }
        Ok(error_scoped(device, || {
            let storage = |label: &str, contents: &[u8]| {
                device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(label),
                    contents,
                    usage: wgpu::BufferUsages::STORAGE,
                })
            };
            let uniforms = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("ddm-render plain map uniforms"),
                contents: bytemuck::bytes_of(&scene.uniforms()),
                usage: wgpu::BufferUsages::UNIFORM,
            });
            let nodes = storage("ddm-render plain map nodes", node_bytes);
            let triangles = storage("ddm-render plain map triangles", triangle_bytes);
            let output = |label: &str| {
                device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size: output_bytes,
                    usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                })
            };
            let values = output("ddm-render plain map values");
            let surface = output("ddm-render plain map surface flags");
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("ddm-render plain map build"),
                layout: &pipeline.layout,
                entries: &[
                    wgpu::BindGroupEntry { binding: 0, resource: uniforms.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 1, resource: nodes.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 2, resource: triangles.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 3, resource: values.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 4, resource: surface.as_entire_binding() },
                ],
            });
            Self { scene: scene.clone(), bind_group, values, surface, workgroups, pipeline: pipeline.pipeline.clone() }
        })?)
    }

    /// Records the build into `encoder`: every voxel's value and surface flag.
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder) {
        self.record(encoder, None);
    }

    /// [`PlainMapBuild::encode`] with the pass's beginning and end written to
    /// `timestamps`. Errors when the set is not a timestamp set or lacks the two queries.
    pub fn encode_timed(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        timestamps: PassTimestamps<'_>,
    ) -> Result<(), DdmRenderError> {
        timestamps.check()?;
        self.record(encoder, Some(timestamps));
        Ok(())
    }

    fn record(&self, encoder: &mut wgpu::CommandEncoder, timestamps: Option<PassTimestamps<'_>>) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("ddm-render plain map build"),
            timestamp_writes: timestamps.map(|t| wgpu::ComputePassTimestampWrites {
                query_set: t.query_set,
                beginning_of_pass_write_index: Some(t.first),
                end_of_pass_write_index: Some(t.first + 1),
            }),
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.bind_group, &[]);
        let [x, y, z] = self.workgroups;
        pass.dispatch_workgroups(x, y, z);
    }

    /// Times `builds` builds after `warm_up` untimed ones, each its own submission: by
    /// timestamps on a hardware adapter that has them, by wall clock from submission to
    /// completion elsewhere (a software adapter's timestamps do not bracket the work).
    /// Errors name the count that is zero or the GPU operation that failed.
    pub fn time_builds(&self, gpu: &Gpu, warm_up: u32, builds: u32) -> Result<FrameTimes, DdmRenderError> {
        if builds == 0 {
            return Err(DdmRenderError::InvalidSettings("timed builds must be at least 1"));
        }
        let submit = |timestamps: Option<PassTimestamps<'_>>| -> Result<(), DdmRenderError> {
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            match timestamps {
                Some(t) => self.encode_timed(&mut encoder, t)?,
                None => self.encode(&mut encoder),
            }
            gpu.scoped(|| gpu.queue.submit([encoder.finish()]))?;
            Ok(())
        };
        for _ in 0..warm_up {
            submit(None)?;
        }
        gpu.wait()?;
        if gpu.timing_source() == TimingSource::Timestamps {
            let count = builds
                .checked_mul(2)
                .ok_or(DdmRenderError::InvalidSettings("timed builds overflow the timestamp queries"))?;
            let queries = TimestampQueries::new(gpu, "ddm-render plain map build timestamps", count)?;
            for k in 0..builds {
                submit(Some(PassTimestamps { query_set: &queries.set, first: 2 * k }))?;
            }
            let ticks = queries.read(gpu)?;
            let ms_per_tick = f64::from(gpu.queue.get_timestamp_period()) * 1e-6;
            let ms = ticks.chunks_exact(2).map(|t| t[1].saturating_sub(t[0]) as f64 * ms_per_tick).collect();
            return Ok(FrameTimes { ms, source: TimingSource::Timestamps });
        }
        let mut ms = Vec::with_capacity(builds as usize);
        for _ in 0..builds {
            let started = std::time::Instant::now();
            submit(None)?;
            gpu.wait()?;
            ms.push(started.elapsed().as_secs_f64() * 1e3);
        }
        Ok(FrameTimes { ms, source: TimingSource::WallClock })
    }

    /// The values, one `f32` per voxel `x + dims.x (y + dims.y z)` (0 where a triangle
    /// crosses the voxel).
    pub fn values(&self) -> &wgpu::Buffer {
        &self.values
    }

    /// The surface flags, one `u32` per voxel (1 where a triangle crosses it).
    pub fn surface(&self) -> &wgpu::Buffer {
        &self.surface
    }

    /// The scene this build was made for.
    pub fn scene(&self) -> &PlainGpuScene {
        &self.scene
    }

    /// Reads back what the last submitted [`PlainMapBuild::encode`] wrote, as the CPU's
    /// [`DistanceMaps`] type (waits for the GPU).
    pub fn read_back(&self, gpu: &Gpu) -> Result<DistanceMaps, DdmRenderError> {
        let bytes = self.scene.voxel_count() as u64 * 4;
        let values = gpu.read_buffer(&self.values, bytes)?;
        let surface = gpu.read_buffer(&self.surface, bytes)?;
        let values: Vec<f32> = bytemuck::pod_collect_to_vec(&values);
        let surface: Vec<u32> = bytemuck::pod_collect_to_vec(&surface);
        Ok(self.scene.distance_maps(&values, &surface)?)
    }
}

/// Builds the plain map of `scene` on `gpu` in one submission and reads it back (tests and
/// tools; a renderer keeps one [`PlainMapPipeline`] and encodes [`PlainMapBuild`]s).
pub fn build_plain_map(gpu: &Gpu, scene: &PlainGpuScene) -> Result<DistanceMaps, DdmRenderError> {
    let pipeline = PlainMapPipeline::new(&gpu.device)?;
    let build = PlainMapBuild::new(&gpu.device, &pipeline, scene)?;
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    build.encode(&mut encoder);
    gpu.queue.submit([encoder.finish()]);
    build.read_back(gpu)
}

#[cfg(test)]
mod tests {
    use super::*;
    use wgsl_gen::check_layout;

    #[test]
    fn the_build_shader_validates_and_matches_the_rust_layouts() {
        let validated = plain_build_shader().unwrap().validate().unwrap_or_else(|e| panic!("{e}"));
        check_layout(&validated.module, &plain_build_structs()).unwrap_or_else(|e| panic!("{e:?}"));
        let point = validated.module.entry_points.iter().find(|e| e.name == ENTRY_POINT).expect("the entry point");
        assert_eq!(point.workgroup_size, [PLAIN_BUILD_TILE, PLAIN_BUILD_TILE, 1]);
    }
}
