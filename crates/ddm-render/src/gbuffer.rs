//! The base-mesh G-buffer: the coarse base mesh rasterized with a perspective camera into
//! four `Rgba32Float` textures ([`GBUFFER_FORMAT`]), one per field of
//! [`BaseGBufferTexel`] (world position and coverage, `(∂P/∂u, u)`, `(∂P/∂v, v)`,
//! `(N, view depth)`), linearly interpolated with perspective correction by the rasterizer;
//! then a second raster pass of the same mesh (depth peeling) into an `R32Float` texture
//! ([`EXIT_FORMAT`]): per pixel the distance from the eye to the next surface behind the
//! first one, where the pixel's ray leaves the base mesh's solid (0 where there is none;
//! `ddm_tracer::tangent_space::shell_exit` turns it into the tracer's parameter).
//!
//! - [`GBufferPipeline`]: the raster pipeline, once per device.
//! - [`GBufferPass`]: one base mesh (vertex and index buffers uploaded once) and the
//!   textures of one size; [`GBufferPass::encode`] records a frame's raster pass.
//! - [`read_gbuffer`], [`rasterize_gbuffer`]: readback for tests and tools, after the frame.

use ddm_tracer::tangent_space::BaseGBufferTexel;
use glam::{Vec3, Vec4};
use gpu_harness::{Gpu, error_scoped};
use mesostructure::BaseMesh;
use wgpu::util::DeviceExt;

use crate::base_mesh::{BaseVertex, scaled_vertices};
use crate::camera::{BaseCamera, Camera};
use crate::error::{DdmRenderError, check_limit};
use crate::shaders::{RASTER_SHADER, raster_shader};

/// The format of the G-buffer textures.
pub const GBUFFER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// Number of G-buffer textures (the fields of [`BaseGBufferTexel`], in order).
pub const GBUFFER_TEXTURES: usize = 4;
/// The format of the exit-distance texture (the second raster pass's target).
pub const EXIT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;
/// Bytes per texel of one G-buffer texture.
const TEXEL_BYTES: u32 = 16;
/// The depth buffer's format.
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// `vec4` interpolants the raster pass passes from vertex to fragment stage.
const INTERPOLANTS: u32 = 4;

/// Where a pass writes its timestamps: queries `first` (beginning) and `first + 1` (end)
/// of `query_set`, a [`wgpu::QueryType::Timestamp`] set.
#[derive(Clone, Copy, Debug)]
pub struct PassTimestamps<'a> {
    /// The query set.
    pub query_set: &'a wgpu::QuerySet,
    /// Index of the beginning-of-pass query; the end goes to `first + 1`.
    pub first: u32,
}

impl PassTimestamps<'_> {
    /// `Err` naming the problem when the set is not a timestamp set or lacks the two queries.
    pub(crate) fn check(&self) -> Result<(), DdmRenderError> {
        if !matches!(self.query_set.ty(), wgpu::QueryType::Timestamp) {
            return Err(DdmRenderError::InvalidTimestamps("the query set is not a timestamp query set".into()));
        }
        let count = self.query_set.count();
        if self.first.checked_add(2).is_none_or(|end| end > count) {
            return Err(DdmRenderError::InvalidTimestamps(format!(
                "queries {} and {} do not fit a set of {count}",
                self.first,
                u64::from(self.first) + 1
            )));
        }
        Ok(())
    }

    /// The beginning of the first of two render passes (`end: false`) or the end of the
    /// second (`end: true`).
    fn render_writes(&self, end: bool) -> wgpu::RenderPassTimestampWrites<'_> {
        wgpu::RenderPassTimestampWrites {
            query_set: self.query_set,
            beginning_of_pass_write_index: (!end).then_some(self.first),
            end_of_pass_write_index: end.then_some(self.first + 1),
        }
    }

    pub(crate) fn compute_writes(&self) -> wgpu::ComputePassTimestampWrites<'_> {
        wgpu::ComputePassTimestampWrites {
            query_set: self.query_set,
            beginning_of_pass_write_index: Some(self.first),
            end_of_pass_write_index: Some(self.first + 1),
        }
    }
}

/// The compiled raster pipelines (the G-buffer and the exit distance) and their bind group
/// layouts (camera uniform, vertex storage buffer; the first pass's normal-depth texture),
/// created once per device and shared by every [`GBufferPass`].
#[derive(Clone, Debug)]
pub struct GBufferPipeline {
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    exit_pipeline: wgpu::RenderPipeline,
    exit_layout: wgpu::BindGroupLayout,
}

impl GBufferPipeline {
    /// Validates the composed raster shader with naga and builds the pipeline. Errors name
    /// the device limit the G-buffer exceeds (colour attachments, bytes per sample,
    /// inter-stage variables, vertex-stage storage buffers) or the shader problem.
    pub fn new(device: &wgpu::Device) -> Result<Self, DdmRenderError> {
        let limits = device.limits();
        let targets = GBUFFER_TEXTURES as u32;
        check_limit(
            "G-buffer colour attachments (max_color_attachments)",
            targets.into(),
            limits.max_color_attachments.into(),
        )?;
        check_limit(
            "G-buffer colour bytes per sample (max_color_attachment_bytes_per_sample)",
            u64::from(targets * TEXEL_BYTES),
            limits.max_color_attachment_bytes_per_sample.into(),
        )?;
        check_limit(
            "raster interpolants (max_inter_stage_shader_variables)",
            INTERPOLANTS.into(),
            limits.max_inter_stage_shader_variables.into(),
        )?;
        let shader = raster_shader()?;
        shader
            .validate()
            .map_err(|e| DdmRenderError::InvalidShader { shader: RASTER_SHADER, message: e.to_string() })?;
        Ok(error_scoped(device, || {
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(RASTER_SHADER),
                source: wgpu::ShaderSource::Wgsl(shader.source().into()),
            });
            let buffer_entry = |binding, ty, visibility| wgpu::BindGroupLayoutEntry {
                binding,
                visibility,
                ty: wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None },
                count: None,
            };
            let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("ddm-render G-buffer"),
                entries: &[
                    buffer_entry(
                        0,
                        wgpu::BufferBindingType::Uniform,
                        wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT,
                    ),
                    buffer_entry(1, wgpu::BufferBindingType::Storage { read_only: true }, wgpu::ShaderStages::VERTEX),
                ],
            });
            let exit_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("ddm-render G-buffer exit distance"),
                entries: &[wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                }],
            });
            let pipeline = |label, layouts: &[Option<&wgpu::BindGroupLayout>], entry, targets: &[_]| {
                let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                    label: Some(label),
                    bind_group_layouts: layouts,
                    immediate_size: 0,
                });
                device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some(label),
                    layout: Some(&pipeline_layout),
                    vertex: wgpu::VertexState {
                        module: &module,
                        entry_point: Some("base_vertex"),
                        compilation_options: Default::default(),
                        buffers: &[],
                    },
                    primitive: wgpu::PrimitiveState::default(),
                    depth_stencil: Some(wgpu::DepthStencilState {
                        format: DEPTH_FORMAT,
                        depth_write_enabled: Some(true),
                        depth_compare: Some(wgpu::CompareFunction::Less),
                        stencil: Default::default(),
                        bias: Default::default(),
                    }),
                    multisample: wgpu::MultisampleState::default(),
                    fragment: Some(wgpu::FragmentState {
                        module: &module,
                        entry_point: Some(entry),
                        compilation_options: Default::default(),
                        targets,
                    }),
                    multiview_mask: None,
                    cache: None,
                })
            };
            let targets: Vec<Option<wgpu::ColorTargetState>> =
                (0..GBUFFER_TEXTURES).map(|_| Some(wgpu::ColorTargetState::from(GBUFFER_FORMAT))).collect();
            let gbuffer = pipeline("ddm-render G-buffer", &[Some(&layout)], "base_fragment", &targets);
            let exit_pipeline = pipeline(
                "ddm-render G-buffer exit distance",
                &[Some(&layout), Some(&exit_layout)],
                "exit_fragment",
                &[Some(wgpu::ColorTargetState::from(EXIT_FORMAT))],
            );
            Self { pipeline: gbuffer, layout, exit_pipeline, exit_layout }
        })?)
    }
}

/// One base mesh rasterized into G-buffer textures of one size: the mesh's vertices
/// ([`scaled_vertices`]) and indices uploaded once, the textures, the camera uniform and
/// the bind group created once. [`encode`](Self::encode) writes the camera uniform and
/// records the raster pass, nothing else. Cloning is cheap and shares the GPU objects.
#[derive(Clone, Debug)]
pub struct GBufferPass {
    pipeline: GBufferPipeline,
    camera: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
    bind_group: wgpu::BindGroup,
    textures: [wgpu::Texture; GBUFFER_TEXTURES],
    views: [wgpu::TextureView; GBUFFER_TEXTURES],
    exit_texture: wgpu::Texture,
    exit_view: wgpu::TextureView,
    /// Group 1 of the exit pass: the normal-depth texture of the first.
    exit_bind_group: wgpu::BindGroup,
    depth: wgpu::TextureView,
    /// Centre and radius of a sphere around the mesh, for the clip planes.
    bounds: (Vec3, f32),
    width: u32,
    height: u32,
}

impl GBufferPass {
    /// Uploads `mesh` and creates `width × height` G-buffer textures (usages
    /// `RENDER_ATTACHMENT | TEXTURE_BINDING | COPY_SRC`) for `pipeline`. Errors name the
    /// problem: an empty size or one beyond `max_texture_dimension_2d`, a mesh that is
    /// empty, whose frames cannot be scaled ([`scaled_vertices`]) or whose buffers exceed
    /// the device's buffer limits.
    pub fn new(
        device: &wgpu::Device,
        pipeline: &GBufferPipeline,
        mesh: &BaseMesh,
        width: u32,
        height: u32,
    ) -> Result<Self, DdmRenderError> {
        let limits = device.limits();
        if width == 0 || height == 0 {
            return Err(DdmRenderError::EmptySize { width, height });
        }
        check_limit(
            "G-buffer side in texels (max_texture_dimension_2d)",
            width.max(height).into(),
            limits.max_texture_dimension_2d.into(),
        )?;
        if mesh.positions.is_empty() || mesh.indices.is_empty() {
            return Err(DdmRenderError::InvalidMesh("no vertices or no triangles"));
        }
        let vertices = scaled_vertices(mesh).ok_or(DdmRenderError::InvalidMesh(
            "attribute lists of different lengths, an index out of range, or a vertex whose \
             one-ring does not span both texture directions",
        ))?;
        let indices: Vec<u32> = mesh.indices.iter().flatten().copied().collect();
        let vertex_bytes = (vertices.len() * size_of::<BaseVertex>()) as u64;
        check_limit(
            "base mesh vertices in bytes (max_storage_buffer_binding_size)",
            vertex_bytes,
            limits.max_storage_buffer_binding_size,
        )?;
        check_limit("base mesh vertices in bytes (max_buffer_size)", vertex_bytes, limits.max_buffer_size)?;
        let index_bytes = (indices.len() * size_of::<u32>()) as u64;
        check_limit("base mesh indices in bytes (max_buffer_size)", index_bytes, limits.max_buffer_size)?;
        let index_count = u32::try_from(indices.len()).map_err(|_| DdmRenderError::TooLarge {
            what: "base mesh indices (u32 draw count)",
            requested: indices.len() as u64,
            limit: u32::MAX.into(),
        })?;
        let bounds =
            bounding_sphere(&mesh.positions).ok_or(DdmRenderError::InvalidMesh("a vertex position is not finite"))?;
        let extent = wgpu::Extent3d { width, height, depth_or_array_layers: 1 };
        let pass = error_scoped(device, || {
            let camera = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("ddm-render G-buffer camera"),
                size: size_of::<BaseCamera>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let vertex_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("ddm-render base mesh vertices"),
                contents: bytemuck::cast_slice(&vertices),
                usage: wgpu::BufferUsages::STORAGE,
            });
            let index_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("ddm-render base mesh indices"),
                contents: bytemuck::cast_slice(&indices),
                usage: wgpu::BufferUsages::INDEX,
            });
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("ddm-render G-buffer"),
                layout: &pipeline.layout,
                entries: &[
                    wgpu::BindGroupEntry { binding: 0, resource: camera.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 1, resource: vertex_buffer.as_entire_binding() },
                ],
            });
            let texture = |label, format, usage| {
                device.create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: extent,
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage,
                    view_formats: &[],
                })
            };
            let usage = wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC;
            let textures: [wgpu::Texture; GBUFFER_TEXTURES] =
                std::array::from_fn(|_| texture("ddm-render G-buffer", GBUFFER_FORMAT, usage));
            let views = std::array::from_fn(|k| textures[k].create_view(&Default::default()));
            let depth = texture("ddm-render G-buffer depth", DEPTH_FORMAT, wgpu::TextureUsages::RENDER_ATTACHMENT)
                .create_view(&Default::default());
            let exit_texture = texture("ddm-render G-buffer exit distance", EXIT_FORMAT, usage);
            let exit_view = exit_texture.create_view(&Default::default());
            let exit_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("ddm-render G-buffer exit distance"),
                layout: &pipeline.exit_layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(&views[GBUFFER_TEXTURES - 1]),
                }],
            });
            Self {
                pipeline: pipeline.clone(),
                camera,
                indices: index_buffer,
                index_count,
                bind_group,
                textures,
                views,
                exit_texture,
                exit_view,
                exit_bind_group,
                depth,
                bounds,
                width,
                height,
            }
        })?;
        Ok(pass)
    }

    /// Width in pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The G-buffer textures, in the field order of [`BaseGBufferTexel`] (uncovered
    /// texels are zero after a frame).
    pub fn textures(&self) -> &[wgpu::Texture; GBUFFER_TEXTURES] {
        &self.textures
    }

    /// Views of [`textures`](Self::textures), as the per-pixel pass binds them.
    pub fn views(&self) -> &[wgpu::TextureView; GBUFFER_TEXTURES] {
        &self.views
    }

    /// The exit-distance texture ([`EXIT_FORMAT`]): per pixel the distance from the eye to
    /// the next base-mesh surface behind the first, 0 where there is none.
    pub fn exit_texture(&self) -> &wgpu::Texture {
        &self.exit_texture
    }

    /// The view of [`exit_texture`](Self::exit_texture) that the per-pixel pass binds.
    pub fn exit_view(&self) -> &wgpu::TextureView {
        &self.exit_view
    }

    /// The raster uniforms for `camera`: clip planes around the mesh's bounding sphere
    /// (`near = max(10⁻³ reach, 10⁻³)`, `far = 1.5 reach + 1`, `reach` the distance from
    /// the eye to the sphere's far side). Errors name the camera field that is unusable.
    pub fn camera_uniforms(&self, camera: &Camera) -> Result<BaseCamera, DdmRenderError> {
        if (camera.width, camera.height) != (self.width, self.height) {
            return Err(DdmRenderError::SizeMismatch {
                what: "the camera's image",
                expected: (self.width, self.height),
                found: (camera.width, camera.height),
            });
        }
        if !(camera.eye.is_finite() && camera.target.is_finite() && camera.up.is_finite()) {
            return Err(DdmRenderError::InvalidCamera("eye, target and up must be finite"));
        }
        let forward = camera.target - camera.eye;
        if forward.length_squared() == 0.0 {
            return Err(DdmRenderError::InvalidCamera("target equals eye"));
        }
        if forward.cross(camera.up).length_squared() == 0.0 {
            return Err(DdmRenderError::InvalidCamera("up is zero or parallel to the view direction"));
        }
        if !(camera.half_fov_y > 0.0 && camera.half_fov_y < std::f32::consts::FRAC_PI_2) {
            return Err(DdmRenderError::InvalidCamera("half_fov_y must lie in (0, π/2)"));
        }
        let (centre, radius) = self.bounds;
        let reach = (camera.eye - centre).length() + radius;
        let uniforms = camera.uniforms((reach * 1e-3).max(1e-3), reach * 1.5 + 1.0);
        if !uniforms.clip_from_world.iter().all(|c| c.is_finite()) {
            return Err(DdmRenderError::InvalidCamera("the view-projection matrix is not finite"));
        }
        Ok(uniforms)
    }

    /// Records the two raster passes for `camera` (its size must be the G-buffer's) into
    /// `encoder`, after writing the camera uniform with `queue.write_buffer`: the G-buffer,
    /// then the exit distance. That write lands at the next `queue.submit`, before any of
    /// its command buffers run: submit each frame before encoding the next one with the
    /// same pass. `timestamps`, when given, receives the first pass's beginning and the
    /// second's end.
    pub fn encode(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        camera: &Camera,
        timestamps: Option<PassTimestamps<'_>>,
    ) -> Result<(), DdmRenderError> {
        let uniforms = self.camera_uniforms(camera)?;
        if let Some(t) = &timestamps {
            t.check()?;
        }
        queue.write_buffer(&self.camera, 0, bytemuck::bytes_of(&uniforms));
        let attachments: Vec<Option<wgpu::RenderPassColorAttachment>> = self
            .views
            .iter()
            .map(|view| {
                Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })
            })
            .collect();
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("ddm-render G-buffer"),
            color_attachments: &attachments,
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.depth,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Discard }),
                stencil_ops: None,
            }),
            timestamp_writes: timestamps.as_ref().map(|t| t.render_writes(false)),
            ..Default::default()
        });
        pass.set_pipeline(&self.pipeline.pipeline);
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.index_count, 0, 0..1);
        drop(pass);
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("ddm-render G-buffer exit distance"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &self.exit_view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.depth,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Discard }),
                stencil_ops: None,
            }),
            timestamp_writes: timestamps.as_ref().map(|t| t.render_writes(true)),
            ..Default::default()
        });
        pass.set_pipeline(&self.pipeline.exit_pipeline);
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.set_bind_group(1, &self.exit_bind_group, &[]);
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(0..self.index_count, 0, 0..1);
        Ok(())
    }
}

/// The centre of the positions' bounding box and the largest distance from it; `None`
/// when a position is not finite (or there is none).
fn bounding_sphere(positions: &[Vec3]) -> Option<(Vec3, f32)> {
    if positions.is_empty() || !positions.iter().all(|p| p.is_finite()) {
        return None;
    }
    let (min, max) =
        positions.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
    let centre = (min + max) * 0.5;
    let radius = positions.iter().map(|p| (*p - centre).length()).fold(0.0_f32, f32::max);
    Some((centre, radius))
}

/// A read-back G-buffer.
#[derive(Clone, Debug)]
pub struct GBuffer {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major texels, row 0 on top.
    pub texels: Vec<BaseGBufferTexel>,
    /// Row-major exit distances ([`GBufferPass::exit_texture`]), row 0 on top.
    pub exit_distances: Vec<f32>,
}

/// The texels of `texture` (mip 0, layer 0) as bytes, rows unpadded, row 0 on top, after
/// all submitted work. The texture needs `COPY_SRC` usage and an uncompressed colour
/// format (its texel size is the format's block copy size).
pub fn read_texture(gpu: &Gpu, texture: &wgpu::Texture) -> Result<Vec<u8>, DdmRenderError> {
    let bytes_per_texel = match texture.format().block_copy_size(None) {
        Some(bytes) if texture.format().block_dimensions() == (1, 1) => bytes,
        _ => {
            return Err(DdmRenderError::InvalidTarget {
                what: "texture to read back",
                problem: format!("format {:?} has no single-texel copy size", texture.format()),
            });
        }
    };
    let (width, height) = (texture.width(), texture.height());
    let row_bytes = width.checked_mul(bytes_per_texel).ok_or(DdmRenderError::TooLarge {
        what: "texture row in bytes",
        requested: u64::from(width) * u64::from(bytes_per_texel),
        limit: u32::MAX.into(),
    })?;
    let padded_row_bytes = row_bytes.next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let size = u64::from(padded_row_bytes) * u64::from(height);
    check_limit("texture readback in bytes (max_buffer_size)", size, gpu.limits().max_buffer_size)?;
    let buffer = gpu.scoped(|| {
        let buffer = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("ddm-render texture readback"),
            size,
            usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        encoder.copy_texture_to_buffer(
            texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &buffer,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(padded_row_bytes),
                    rows_per_image: Some(height),
                },
            },
            wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
        );
        gpu.queue.submit([encoder.finish()]);
        buffer
    })?;
    let padded = gpu.read_buffer(&buffer, size)?;
    let mut bytes = Vec::with_capacity(row_bytes as usize * height as usize);
    for row in padded.chunks_exact(padded_row_bytes as usize) {
        bytes.extend_from_slice(&row[..row_bytes as usize]);
    }
    Ok(bytes)
}

/// The G-buffer of `pass` as the last submitted frame left it, copied back (the exact
/// `f32` values that the per-pixel pass reads with `textureLoad`).
pub fn read_gbuffer(gpu: &Gpu, pass: &GBufferPass) -> Result<GBuffer, DdmRenderError> {
    let [position_coverage, tangent_u, bitangent_v, normal_depth] = &pass.textures;
    let read = |texture| -> Result<Vec<Vec4>, DdmRenderError> {
        Ok(bytemuck::pod_collect_to_vec(&read_texture(gpu, texture)?))
    };
    let layers = [read(position_coverage)?, read(tangent_u)?, read(bitangent_v)?, read(normal_depth)?];
    let count = pass.width as usize * pass.height as usize;
    if layers.iter().any(|layer| layer.len() != count) {
        return Err(DdmRenderError::Gpu(gpu_harness::HarnessError::Readback(format!(
            "a G-buffer texture read back with the wrong texel count (expected {count})"
        ))));
    }
    let exit_distances: Vec<f32> = bytemuck::pod_collect_to_vec(&read_texture(gpu, &pass.exit_texture)?);
    if exit_distances.len() != count {
        return Err(DdmRenderError::Gpu(gpu_harness::HarnessError::Readback(format!(
            "the exit-distance texture read back with the wrong texel count (expected {count})"
        ))));
    }
    let [p, t, b, n] = layers;
    let texels = p
        .into_iter()
        .zip(t)
        .zip(b)
        .zip(n)
        .map(|(((position_coverage, tangent_u), bitangent_v), normal_depth)| BaseGBufferTexel {
            position_coverage,
            tangent_u,
            bitangent_v,
            normal_depth,
        })
        .collect();
    Ok(GBuffer { width: pass.width, height: pass.height, texels, exit_distances })
}

/// Rasterizes `mesh` seen by `camera` into a G-buffer of the camera's size and reads it
/// back (depth test, no culling; uncovered texels are zero): a [`GBufferPipeline`] and a
/// [`GBufferPass`] built for this one frame. To rasterize many frames, build those once
/// and call [`GBufferPass::encode`] per frame.
pub fn rasterize_gbuffer(gpu: &Gpu, mesh: &BaseMesh, camera: &Camera) -> Result<GBuffer, DdmRenderError> {
    let pipeline = GBufferPipeline::new(&gpu.device)?;
    let pass = GBufferPass::new(&gpu.device, &pipeline, mesh, camera.width, camera.height)?;
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    pass.encode(&gpu.queue, &mut encoder, camera, None)?;
    gpu.scoped(|| gpu.queue.submit([encoder.finish()]))?;
    read_gbuffer(gpu, &pass)
}
