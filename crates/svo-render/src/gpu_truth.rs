//! [`GpuVoxelTruth`]: the voxel truth ([`truth::render_voxel_truth`]) on wgpu, so that a
//! supersampled image of the octree's finest level — what a renderer without prefiltering
//! must compute to anti-alias — is timed on the same adapter as the cone tracer, at the
//! paper's sample counts (256 rays per pixel and more).
//!
//! One compute pass per frame (`shaders/svo_truth.wgsl`) runs, for each of the `k × k`
//! footprint strata (times `m × m` lens strata) of [`truth::truth_pixel`] in its order, a
//! dispatch that traces that sample's ray of every pixel, one per shadow ray, and one that
//! shades and adds it to the pixel's sums (with one-invocation dispatches that move the
//! schedule on), then the means. Dispatches rather than loops over the samples in one
//! invocation keep the sums in the CPU's order and run on lavapipe, whose loop limiter
//! (65 535 iterations of a loop and all loops nested in it) ended such loops early: a frame
//! is `k²m²(3 + 2s²) + 1` dispatches. Each ray is sphere-traced through the finest level with `svo-brick`'s WGSL
//! sampler, shaded through `svo-tracer`'s `svo_element_radiance`, with `s × s` shadow rays
//! towards the light's disk. The rays and their jitter are the CPU's (the same hash); the
//! trace is in `f32` from each ray's entry into the domain where the CPU's is in `f64`, so
//! the two agree up to rounding (`tests/svo_truth_gpu.rs` bounds the difference by what
//! doubling `ε` changes on the CPU). Built once for an octree and an image size; a frame
//! ([`GpuVoxelTruth::encode`]) writes the camera and settings and records one dispatch.

use gpu_harness::{Gpu, error_scoped};
use svo_brick::PackedTree;
use svo_tracer::{Camera, TraceSettings};

use crate::error::{RenderError, check, gpu_failed};
use crate::frame::Frame;
use crate::renderer::{OctreeBuffers, buffer, check_pools, output, read_frame_buffers, uniform, validated_source};

/// The kernel's bindings: the octree's uniforms (0), nodes (3) and bricks (4–7), the camera
/// (2), the trace settings (9), the truth's settings (10), the per-pixel sums (11) and
/// evaluations (12), the schedule (13: sample, shadow ray), the output (14) and the pending
/// rays (15).
fn bind_group_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let entry =
        |binding, ty| wgpu::BindGroupLayoutEntry { binding, visibility: wgpu::ShaderStages::COMPUTE, ty, count: None };
    let uniform = wgpu::BindingType::Buffer {
        ty: wgpu::BufferBindingType::Uniform,
        has_dynamic_offset: false,
        min_binding_size: None,
    };
    let storage = |read_only| wgpu::BindingType::Buffer {
        ty: wgpu::BufferBindingType::Storage { read_only },
        has_dynamic_offset: false,
        min_binding_size: None,
    };
    let mut entries = vec![entry(0, uniform), entry(2, uniform), entry(9, uniform), entry(10, uniform)];
    entries.extend((3..=7).map(|b| entry(b, storage(true))));
    entries.extend((11..=15).map(|b| entry(b, storage(false))));
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("svo_render_voxel_truth"),
        entries: &entries,
    })
}
use crate::shader::{GpuTruthSettings, TILE, truth_shader};
use crate::truth::{self, TruthSettings};

/// The smallest `ε` the GPU truth takes, as a fraction of the larger of the domain's size and
/// its corners' largest coordinate: `2⁻²¹`, at least 4 `f32` ulps of both a ray's parameter
/// from its entry (below the diagonal, `√3` sizes) and of the points' coordinates, so that a
/// step of `ε` always moves the ray and the first point, `ε` past the entry, rounds inside
/// ([`GpuVoxelTruth::min_epsilon`]).
pub const MIN_RELATIVE_EPSILON: f32 = 1.0 / (1u32 << 21) as f32;

impl TruthSettings {
    /// The settings' GPU form.
    pub fn to_gpu(&self) -> GpuTruthSettings {
        GpuTruthSettings {
            counts: glam::UVec4::new(
                self.rays_per_axis,
                self.lens_samples_per_axis,
                self.shadow_rays_per_axis,
                self.max_steps,
            ),
            epsilon_jitter: glam::Vec4::new(self.epsilon, f32::from(u8::from(self.jitter)), 0.0, 0.0),
        }
    }
}

/// The voxel truth on the GPU for one octree and one image size (see the module docs).
#[derive(Debug)]
pub struct GpuVoxelTruth {
    size: (u32, u32),
    /// The larger of the domain's size and its corners' largest coordinate.
    domain_size: f32,
    primary: wgpu::ComputePipeline,
    shadow: wgpu::ComputePipeline,
    next_shadow: wgpu::ComputePipeline,
    accumulate: wgpu::ComputePipeline,
    next_sample: wgpu::ComputePipeline,
    resolve: wgpu::ComputePipeline,
    bind_group: wgpu::BindGroup,
    camera: wgpu::Buffer,
    settings: wgpu::Buffer,
    truth: wgpu::Buffer,
    schedule: wgpu::Buffer,
    radiance_coverage: wgpu::Buffer,
    evaluations: wgpu::Buffer,
}

impl GpuVoxelTruth {
    /// Uploads the octree (`packed`, for instance from [`crate::renderer::pack_for`]),
    /// compiles the kernel and creates the outputs of a `size` image.
    ///
    /// Errors: a zero size, pools larger than the device's storage bindings, an image whose
    /// outputs exceed them, or any wgpu validation error.
    pub fn new(device: &wgpu::Device, packed: &PackedTree, size: (u32, u32)) -> Result<Self, RenderError> {
        check(size.0 > 0 && size.1 > 0, "GpuVoxelTruth::size", f64::from(size.0.min(size.1)), "at least 1 × 1 px")?;
        let limit = check_pools(device, packed)?;
        let pixels = u64::from(size.0) * u64::from(size.1);
        check(
            64 * pixels <= limit,
            "GpuVoxelTruth::size",
            pixels as f64,
            "at most max_storage_buffer_binding_size / 64 pixels (64 bytes per pixel between passes)",
        )?;
        let source = validated_source(&truth_shader(), "validating the voxel truth's kernel")?;
        let domain = truth::packed_domain(packed);
        let extent = domain.origin.abs().max((domain.origin + domain.size).abs()).max_element();
        let domain_size = domain.size.max(extent);
        error_scoped(device, || {
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("svo_render_voxel_truth"),
                source: wgpu::ShaderSource::Wgsl(source.into()),
            });
            let layout = bind_group_layout(device);
            let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("svo_render_voxel_truth"),
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
            let pipeline = |entry_point: &str| {
                device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(entry_point),
                    layout: Some(&pipeline_layout),
                    module: &module,
                    entry_point: Some(entry_point),
                    compilation_options: Default::default(),
                    cache: None,
                })
            };
            let octree = OctreeBuffers::upload(device, packed);
            let camera = uniform(device, "svo truth camera", size_of::<svo_tracer::GpuCamera>());
            let settings = uniform(device, "svo truth trace settings", size_of::<svo_tracer::GpuTraceSettings>());
            let truth = uniform(device, "svo truth settings", size_of::<GpuTruthSettings>());
            let sums = output(device, "svo truth sums", 16 * pixels);
            let evaluations = output(device, "svo truth evaluations", 4 * pixels);
            let pending = output(device, "svo truth pending rays", 64 * pixels);
            let schedule = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("svo truth schedule"),
                size: 8,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let radiance_coverage = output(device, "svo truth radiance and coverage", 16 * pixels);
            let mut entries = octree.entries();
            entries.extend([
                buffer(2, &camera),
                buffer(9, &settings),
                buffer(10, &truth),
                buffer(11, &sums),
                buffer(12, &evaluations),
                buffer(13, &schedule),
                buffer(14, &radiance_coverage),
                buffer(15, &pending),
            ]);
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("svo_render_voxel_truth"),
                layout: &layout,
                entries: &entries,
            });
            Self {
                size,
                domain_size,
                primary: pipeline("svo_truth_primary"),
                shadow: pipeline("svo_truth_shadow"),
                next_shadow: pipeline("svo_truth_next_shadow"),
                accumulate: pipeline("svo_truth_accumulate"),
                next_sample: pipeline("svo_truth_next_sample"),
                resolve: pipeline("svo_truth_resolve"),
                bind_group,
                camera,
                settings,
                truth,
                schedule,
                radiance_coverage,
                evaluations,
            }
        })
        .map_err(gpu_failed("building the GPU voxel truth"))
    }

    /// The image size `(width, height)`.
    pub fn size(&self) -> (u32, u32) {
        self.size
    }

    /// The smallest [`TruthSettings::epsilon`] this octree's truth takes on the GPU:
    /// [`MIN_RELATIVE_EPSILON`] of the larger of the domain's size and its corners' largest
    /// coordinate.
    pub fn min_epsilon(&self) -> f32 {
        MIN_RELATIVE_EPSILON * self.domain_size
    }

    /// Records one frame: writes the camera, the trace settings (light, material,
    /// background) and the truth's settings, and dispatches the kernel into `encoder`. As
    /// with [`crate::GpuRenderer`], encode one frame per submission.
    ///
    /// Errors: a camera whose size is not [`size`](Self::size), settings that
    /// [`TruthSettings::validate`] refuses, or an `ε` below [`MIN_RELATIVE_EPSILON`] of the
    /// domain's size and coordinates.
    pub fn encode(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        camera: &Camera,
        trace: &TraceSettings,
        settings: &TruthSettings,
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), RenderError> {
        let (width, height) = camera.size();
        check(
            (width, height) == self.size,
            "Camera::size",
            f64::from(width) * f64::from(height),
            "the voxel truth's size (width × height)",
        )?;
        settings.validate()?;
        let floor = self.min_epsilon();
        check(
            settings.epsilon >= floor,
            "TruthSettings::epsilon",
            f64::from(settings.epsilon),
            "at least GpuVoxelTruth::min_epsilon (2⁻²¹ of the domain's size and coordinates: f32 along a ray)",
        )?;
        queue.write_buffer(&self.camera, 0, bytemuck::bytes_of(&camera.to_gpu()));
        queue.write_buffer(&self.settings, 0, bytemuck::bytes_of(&trace.to_gpu()));
        queue.write_buffer(&self.truth, 0, bytemuck::bytes_of(&settings.to_gpu()));
        queue.write_buffer(&self.schedule, 0, bytemuck::bytes_of(&[0u32; 2]));
        let lens = camera.lens().is_some_and(|lens| lens.aperture > 0.0);
        let k = settings.rays_per_axis;
        let m = if lens { settings.lens_samples_per_axis } else { 1 };
        let (groups_x, groups_y) = (width.div_ceil(TILE), height.div_ceil(TILE));
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("svo_render_voxel_truth"),
            timestamp_writes,
        });
        pass.set_bind_group(0, &self.bind_group, &[]);
        let shadow_rays = settings.shadow_rays_per_axis * settings.shadow_rays_per_axis;
        for _ in 0..k * k * m * m {
            pass.set_pipeline(&self.primary);
            pass.dispatch_workgroups(groups_x, groups_y, 1);
            for _ in 0..shadow_rays {
                pass.set_pipeline(&self.shadow);
                pass.dispatch_workgroups(groups_x, groups_y, 1);
                pass.set_pipeline(&self.next_shadow);
                pass.dispatch_workgroups(1, 1, 1);
            }
            pass.set_pipeline(&self.accumulate);
            pass.dispatch_workgroups(groups_x, groups_y, 1);
            pass.set_pipeline(&self.next_sample);
            pass.dispatch_workgroups(1, 1, 1);
        }
        pass.set_pipeline(&self.resolve);
        pass.dispatch_workgroups(groups_x, groups_y, 1);
        Ok(())
    }

    /// The last frame's `(linear radiance, coverage)` per pixel, `vec4<f32>`, row-major.
    pub fn radiance_coverage(&self) -> &wgpu::Buffer {
        &self.radiance_coverage
    }

    /// Reads the last frame back into a [`Frame`], its work being the distance evaluations
    /// per pixel (waits for the GPU: a tool's call, never a frame loop's).
    pub fn read_frame(&self, gpu: &Gpu) -> Result<Frame, RenderError> {
        read_frame_buffers(gpu, self.size, &self.radiance_coverage, &self.evaluations)
    }
}
