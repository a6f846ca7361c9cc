//! [`GpuRenderer`]: the cone tracer on wgpu, built once, encoded per frame.
//!
//! One compute pass per frame runs `svo_render_frame` (`shaders/svo_render.wgsl`): a cone
//! per pixel through `svo-tracer`'s WGSL twin (Algorithm 1 with the four models, depth of
//! field, shadow cones and the empty-space skip), in [`TILE`] × [`TILE`] workgroups. The
//! octree's pools, the mask table, the pipeline and the outputs are created in
//! [`GpuRenderer::new`]; a frame ([`GpuRenderer::encode`]) writes the camera and the
//! settings (96 + 64 + 16 bytes through [`wgpu::Queue::write_buffer`]) and records one
//! dispatch: no pipeline creation, no upload of the octree and no readback.
//!
//! Because the camera and the settings go through the queue, they take effect at the next
//! [`wgpu::Queue::submit`]: encode one frame of a renderer per submission (two frames of the
//! same renderer in one submission would both see the last camera).

use abuffer_mask::MaskTable;
use gpu_harness::{Gpu, error_scoped};
use svo_brick::{PackedTree, PoolError};
use svo_tracer::{Camera, TraceSettings};

use crate::error::{RenderError, check, gpu_failed};
use crate::frame::Frame;
use crate::shader::{SvoFrameUniforms, TILE, frame_shader};
use wgsl_gen::ComposedShader;

/// The largest storage binding the device allows, in bytes: the limit to pack an octree for
/// (`PackedTree::with_binding_limit`).
pub fn binding_limit(device: &wgpu::Device) -> u64 {
    let limits = device.limits();
    limits.max_storage_buffer_binding_size.min(limits.max_buffer_size)
}

/// Packs `tree` in `layout` for `device`'s bindings, or says why it does not fit.
pub fn pack_for(
    device: &wgpu::Device,
    tree: &svo_brick::BrickTree,
    layout: svo_brick::VoxelLayout,
) -> Result<PackedTree, RenderError> {
    PackedTree::with_binding_limit(tree, layout, binding_limit(device)).map_err(RenderError::Pools)
}

/// What one frame renders: the camera, the tracer's settings and the image's exposure.
#[derive(Clone, Copy, Debug)]
pub struct FrameSettings<'a> {
    /// The camera (its size must be the renderer's).
    pub camera: &'a Camera,
    /// The model, limits, light and material.
    pub settings: &'a TraceSettings,
    /// The factor on the radiance before the image's sRGB encoding.
    pub exposure: f32,
}

/// The cone tracer on the GPU for one octree, one mask table and one image size.
#[derive(Debug)]
pub struct GpuRenderer {
    size: (u32, u32),
    pipeline: wgpu::ComputePipeline,
    bind_group: wgpu::BindGroup,
    camera: wgpu::Buffer,
    settings: wgpu::Buffer,
    frame: wgpu::Buffer,
    radiance_coverage: wgpu::Buffer,
    elements: wgpu::Buffer,
    image: wgpu::Texture,
    octree_bytes: u64,
}

/// `shader`'s source once naga has validated it (`what` names the kernel in the error).
pub(crate) fn validated_source(shader: &ComposedShader, what: &'static str) -> Result<String, RenderError> {
    shader.validate().map_err(|e| RenderError::Gpu { what, message: e.to_string() })?;
    Ok(shader.source().to_owned())
}

/// The device's binding limit ([`binding_limit`]) once `packed`'s node pool and each of its
/// brick bindings are known to fit in it, or the pool that does not.
pub(crate) fn check_pools(device: &wgpu::Device, packed: &PackedTree) -> Result<u64, RenderError> {
    let limit = binding_limit(device);
    let node_bytes = size_of_val(packed.nodes()) as u64;
    if node_bytes > limit {
        return Err(RenderError::Pools(PoolError::Nodes(node_bytes, limit)));
    }
    let largest = packed.brick_bindings().iter().map(|b| 4 * b.len() as u64).max().unwrap_or(0);
    if largest > limit {
        return Err(RenderError::Pools(PoolError::Bricks(4 * packed.words().len() as u64, limit)));
    }
    Ok(limit)
}

/// An octree on the GPU: its uniforms (binding 0), node pool (3) and brick bindings (4–7),
/// as `svo-brick`'s WGSL twin reads them.
pub(crate) struct OctreeBuffers {
    uniforms: wgpu::Buffer,
    nodes: wgpu::Buffer,
    bricks: Vec<wgpu::Buffer>,
}

impl OctreeBuffers {
    /// Uploads `packed` (checked by [`check_pools`]; call inside an error scope).
    pub(crate) fn upload(device: &wgpu::Device, packed: &PackedTree) -> Self {
        use wgpu::util::DeviceExt;
        let uniforms = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("svo octree uniforms"),
            contents: bytemuck::bytes_of(&packed.uniforms()),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let nodes = storage(device, "svo nodes", bytemuck::cast_slice(packed.nodes()));
        let bricks = packed
            .brick_bindings()
            .iter()
            .map(|words| storage(device, "svo bricks", bytemuck::cast_slice(words)))
            .collect();
        Self { uniforms, nodes, bricks }
    }

    /// The bind group entries of the octree's bindings.
    pub(crate) fn entries(&self) -> Vec<wgpu::BindGroupEntry<'_>> {
        let mut entries = vec![buffer(0, &self.uniforms), buffer(3, &self.nodes)];
        entries.extend(self.bricks.iter().enumerate().map(|(k, b)| buffer(4 + k as u32, b)));
        entries
    }
}

fn storage(device: &wgpu::Device, label: &str, bytes: &[u8]) -> wgpu::Buffer {
    use wgpu::util::DeviceExt;
    device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytes,
        usage: wgpu::BufferUsages::STORAGE,
    })
}

pub(crate) fn uniform(device: &wgpu::Device, label: &str, size: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

pub(crate) fn buffer(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
    wgpu::BindGroupEntry { binding, resource: buffer.as_entire_binding() }
}

pub(crate) fn output(device: &wgpu::Device, label: &str, size: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    })
}

impl GpuRenderer {
    /// The format of [`image`](Self::image): 8-bit sRGB-encoded values in a linear
    /// `Rgba8Unorm` storage texture (storage textures cannot be `*Srgb`).
    pub const IMAGE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

    /// Uploads the octree (`packed`, for instance from [`pack_for`]) and the mask table,
    /// compiles the frame kernel and creates the outputs of a `size` image.
    ///
    /// Errors: a zero size, a mask table of more than 128 samples (the twin's masks are four
    /// words), pools larger than the device's storage bindings (pack with
    /// [`binding_limit`]), or any wgpu validation error.
    pub fn new<const W: usize>(
        device: &wgpu::Device,
        packed: &PackedTree,
        table: &MaskTable<W>,
        size: (u32, u32),
    ) -> Result<Self, RenderError> {
        check(size.0 > 0 && size.1 > 0, "GpuRenderer::size", f64::from(size.0.min(size.1)), "at least 1 × 1 px")?;
        check(W <= 4, "MaskTable::WORDS", W as f64, "at most 4 words (128 samples), the WGSL twin's masks")?;
        let limit = check_pools(device, packed)?;
        let pixels = u64::from(size.0) * u64::from(size.1);
        check(
            16 * pixels <= limit,
            "GpuRenderer::size",
            pixels as f64,
            "at most max_storage_buffer_binding_size / 16 pixels",
        )?;
        let shader_source = validated_source(&frame_shader(), "validating the frame kernel")?;
        error_scoped(device, || {
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("svo_render_frame"),
                source: wgpu::ShaderSource::Wgsl(shader_source.into()),
            });
            let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("svo_render_frame"),
                layout: None,
                module: &module,
                entry_point: Some("svo_render_frame"),
                compilation_options: Default::default(),
                cache: None,
            });
            let octree = OctreeBuffers::upload(device, packed);
            let table_uniforms = {
                use wgpu::util::DeviceExt;
                device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("svo mask table uniforms"),
                    contents: bytemuck::bytes_of(&table.uniforms()),
                    usage: wgpu::BufferUsages::UNIFORM,
                })
            };
            let masks = storage(device, "svo masks", bytemuck::cast_slice(table.words()));
            let camera = uniform(device, "svo camera", size_of::<svo_tracer::GpuCamera>());
            let settings = uniform(device, "svo settings", size_of::<svo_tracer::GpuTraceSettings>());
            let frame = uniform(device, "svo frame", size_of::<SvoFrameUniforms>());
            let radiance_coverage = output(device, "svo radiance and coverage", 16 * pixels);
            let elements = output(device, "svo elements", 4 * pixels);
            let image = device.create_texture(&wgpu::TextureDescriptor {
                label: Some("svo image"),
                size: wgpu::Extent3d { width: size.0, height: size.1, depth_or_array_layers: 1 },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: Self::IMAGE_FORMAT,
                usage: wgpu::TextureUsages::STORAGE_BINDING
                    | wgpu::TextureUsages::TEXTURE_BINDING
                    | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            });
            let view = image.create_view(&Default::default());
            let mut entries = octree.entries();
            entries.extend([
                buffer(1, &table_uniforms),
                buffer(2, &camera),
                buffer(8, &masks),
                buffer(9, &settings),
                buffer(10, &frame),
                buffer(11, &radiance_coverage),
                buffer(12, &elements),
                wgpu::BindGroupEntry { binding: 13, resource: wgpu::BindingResource::TextureView(&view) },
            ]);
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("svo_render_frame"),
                layout: &pipeline.get_bind_group_layout(0),
                entries: &entries,
            });
            Self {
                size,
                pipeline,
                bind_group,
                camera,
                settings,
                frame,
                radiance_coverage,
                elements,
                image,
                octree_bytes: packed.bytes() as u64,
            }
        })
        .map_err(gpu_failed("building the SVO renderer"))
    }

    /// The image size `(width, height)`.
    pub fn size(&self) -> (u32, u32) {
        self.size
    }

    /// The bytes of the octree's pools on the GPU.
    pub fn octree_bytes(&self) -> u64 {
        self.octree_bytes
    }

    /// Records one frame: writes its camera, settings and exposure (see the module docs on
    /// submissions) and dispatches the frame kernel into `encoder`.
    ///
    /// Errors: a camera whose size is not [`size`](Self::size), or a non-finite exposure.
    pub fn encode(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        frame: FrameSettings<'_>,
    ) -> Result<(), RenderError> {
        self.encode_pass(queue, encoder, frame.camera, frame.settings, frame.exposure, None)
    }

    /// [`encode`](Self::encode), with the frame's pass writing GPU timestamps into
    /// `query_set` at `index` (its start) and `index + 1` (its end).
    pub fn encode_timed(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        frame: FrameSettings<'_>,
        query_set: &wgpu::QuerySet,
        index: u32,
    ) -> Result<(), RenderError> {
        let writes = wgpu::ComputePassTimestampWrites {
            query_set,
            beginning_of_pass_write_index: Some(index),
            end_of_pass_write_index: Some(index + 1),
        };
        self.encode_pass(queue, encoder, frame.camera, frame.settings, frame.exposure, Some(writes))
    }

    fn encode_pass(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        camera: &Camera,
        settings: &TraceSettings,
        exposure: f32,
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) -> Result<(), RenderError> {
        let (width, height) = camera.size();
        check(
            (width, height) == self.size,
            "Camera::size",
            f64::from(width) * f64::from(height),
            "the renderer's size (width × height)",
        )?;
        check(exposure.is_finite(), "exposure", f64::from(exposure), "finite")?;
        queue.write_buffer(&self.camera, 0, bytemuck::bytes_of(&camera.to_gpu()));
        queue.write_buffer(&self.settings, 0, bytemuck::bytes_of(&settings.to_gpu()));
        let frame = SvoFrameUniforms { exposure: glam::Vec4::new(exposure, 0.0, 0.0, 0.0) };
        queue.write_buffer(&self.frame, 0, bytemuck::bytes_of(&frame));
        let mut pass = encoder
            .begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some("svo_render_frame"), timestamp_writes });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.dispatch_workgroups(width.div_ceil(TILE), height.div_ceil(TILE), 1);
        Ok(())
    }

    /// The image of the last frame: the sRGB encoding of `exposure × radiance`, alpha 1
    /// ([`IMAGE_FORMAT`](Self::IMAGE_FORMAT); bind it as a texture or copy it out).
    pub fn image(&self) -> &wgpu::Texture {
        &self.image
    }

    /// The last frame's `(linear radiance, coverage)` per pixel, `vec4<f32>`, row-major.
    pub fn radiance_coverage(&self) -> &wgpu::Buffer {
        &self.radiance_coverage
    }

    /// The last frame's cone elements sampled per pixel, `u32`, row-major.
    pub fn elements(&self) -> &wgpu::Buffer {
        &self.elements
    }

    /// Reads the last frame back into a [`Frame`] (waits for the GPU: a tool's call, never
    /// a frame loop's).
    pub fn read_frame(&self, gpu: &Gpu) -> Result<Frame, RenderError> {
        read_frame_buffers(gpu, self.size, &self.radiance_coverage, &self.elements)
    }
}

impl GpuRenderer {
    /// Reads the last frame's [`image`](Self::image) back (waits for the GPU).
    pub fn read_image(&self, gpu: &Gpu) -> Result<image::RgbaImage, RenderError> {
        gpu.read_rgba8_texture(&self.image).map_err(gpu_error)
    }
}

/// A [`Frame`] of `size` read back from a kernel's `(linear radiance, coverage)` buffer
/// (`vec4<f32>` per pixel) and its work buffer (`u32` per pixel), row-major (waits for the
/// GPU).
pub(crate) fn read_frame_buffers(
    gpu: &Gpu,
    size: (u32, u32),
    radiance_coverage: &wgpu::Buffer,
    work: &wgpu::Buffer,
) -> Result<Frame, RenderError> {
    let pixels = size.0 as usize * size.1 as usize;
    let radiance = gpu.read_buffer(radiance_coverage, 16 * pixels as u64).map_err(gpu_error)?;
    let work = gpu.read_buffer(work, 4 * pixels as u64).map_err(gpu_error)?;
    let radiance: Vec<[f32; 4]> = bytemuck::pod_collect_to_vec(&radiance);
    let work: Vec<u32> = bytemuck::pod_collect_to_vec(&work);
    let pixels = radiance.iter().zip(work).map(|(r, e)| (glam::Vec3::new(r[0], r[1], r[2]), r[3], e)).collect();
    Frame::from_pixels(size.0, size.1, pixels)
}

pub(crate) fn gpu_error(e: gpu_harness::HarnessError) -> RenderError {
    gpu_failed("reading the frame back")(e)
}
