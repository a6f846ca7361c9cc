//! The mesh G-buffer pass: rasterizes a [`GrainMesh`] seen by any [`CameraUniforms`] into
//! the screen G-buffer of [`GBUFFER_LAYERS`], with integer supersampling.
//!
//! The mesh is drawn at `s×` the target resolution (one sample per fine pixel, depth test
//! `Less`), then a compute pass (`shaders/gbuffer_reduce.wgsl`) reduces each `s × s` block
//! to one texel: coverage = the fraction of covered samples; normal, albedo, roughness,
//! metallic and depth = the mean over the covered samples (the coverage-weighted average),
//! the normal renormalised. Background texels have coverage 0, albedo 0 and depth `+∞`.
//!
//! This pass is the ground truth of the accuracy experiment (perspective cameras) and the
//! baker's renderer ([`crate::bake`], orthographic cameras, which reduces into the atlas
//! layout instead of the screen G-buffer).
//!
//! # View depth
//!
//! The `depth` layer holds the distance along the camera's forward axis: from the eye for
//! perspective cameras (the clip `w`), from the near plane for orthographic ones (whose eye
//! is notional). For the atlas camera of [`CameraUniforms::orthographic`] the near plane is
//! at `centre + R·ω`, so `1 - depth / R = dot(q, ω) / R`, the view depth of
//! [`octahedral_map::ViewFrame::depth`].
//!
//! # Materials
//!
//! Per-vertex [`grain_mesh::VertexMaterial`] when the mesh has them (metallic 0: the
//! grain material has none), else [`DEFAULT_MATERIAL`].

use bytemuck::Zeroable;
use glam::{Vec3, Vec4};
use grain_mesh::{GrainMesh, VertexMaterial};

use crate::gpu_util::{
    GpuError, check_texture_size, compose, loaded_texture_entry, read_texture, scoped, storage_texture_entry,
    uniform_entry,
};
use crate::scene::{CameraUniforms, GBUFFER_LAYERS, GrainInstance, PIXEL_TILE, ReduceParams};

/// The WGSL of the raster pass (composed after the generated declarations).
pub const MESH_GBUFFER_WGSL: &str = include_str!("../shaders/mesh_gbuffer.wgsl");
/// The WGSL of the supersampling reduction (composed after the generated declarations).
pub const GBUFFER_REDUCE_WGSL: &str = include_str!("../shaders/gbuffer_reduce.wgsl");

/// The material of meshes without per-vertex materials: grey albedo 0.7, roughness 0.5,
/// metallic 0.
pub const DEFAULT_MATERIAL: VertexMaterial = VertexMaterial { albedo: Vec3::splat(0.7), roughness: 0.5 };

/// The wgpu formats of [`GBUFFER_LAYERS`], in order.
pub const GBUFFER_FORMATS: [wgpu::TextureFormat; 4] = [
    wgpu::TextureFormat::Rgba16Float,
    wgpu::TextureFormat::Rgba8Unorm,
    wgpu::TextureFormat::Rgba8Unorm,
    wgpu::TextureFormat::R32Float,
];

const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// The depth-buffer format of mesh rasters into the G-buffer.
pub const MESH_DEPTH_FORMAT: wgpu::TextureFormat = DEPTH_FORMAT;

/// One vertex as the raster pass reads it.
#[repr(C)]
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
struct MeshVertex {
    position: [f32; 3],
    normal: [f32; 3],
    albedo: [f32; 3],
    roughness_metallic: [f32; 2],
}

const VERTEX_ATTRIBUTES: [wgpu::VertexAttribute; 4] =
    wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x3, 3 => Float32x2];

/// The vertex buffer layout of [`GpuMesh::vertices`] (position, normal, albedo, roughness
/// and metallic at locations 0–3, as `mesh_gbuffer.wgsl`'s `MeshVertex`).
pub fn mesh_vertex_layout() -> wgpu::VertexBufferLayout<'static> {
    wgpu::VertexBufferLayout {
        array_stride: size_of::<MeshVertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &VERTEX_ATTRIBUTES,
    }
}

/// The G-buffer raster of a grain mesh: `module`'s vertex entry point `vertex_entry` over
/// [`mesh_vertex_layout`], `mesh_gbuffer.wgsl`'s `mesh_fragment` into the four
/// [`GBUFFER_FORMATS`] targets, depth test `Less` with writes in [`MESH_DEPTH_FORMAT`]. The
/// mesh pass here and the mesh tier of `grain-renderer` (its own vertex entry point) share it.
pub fn mesh_raster_pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    vertex_entry: &str,
) -> wgpu::RenderPipeline {
    let targets = GBUFFER_FORMATS.map(|format| Some(wgpu::ColorTargetState::from(format)));
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(vertex_entry),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(vertex_entry),
            compilation_options: Default::default(),
            buffers: &[Some(mesh_vertex_layout())],
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
            module,
            entry_point: Some("mesh_fragment"),
            compilation_options: Default::default(),
            targets: &targets,
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// A grain mesh in GPU buffers.
#[derive(Debug)]
pub struct GpuMesh {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
}

impl GpuMesh {
    /// The vertices ([`mesh_vertex_layout`]).
    pub fn vertices(&self) -> &wgpu::Buffer {
        &self.vertices
    }

    /// The triangle indices (`u32`).
    pub fn indices(&self) -> &wgpu::Buffer {
        &self.indices
    }

    /// How many indices (three per triangle).
    pub fn index_count(&self) -> u32 {
        self.index_count
    }

    /// Uploads `mesh` (positions in its own frame; the [`GrainInstance`] of a draw places
    /// it), with its per-vertex materials or [`DEFAULT_MATERIAL`].
    pub fn upload(device: &wgpu::Device, mesh: &GrainMesh) -> Result<Self, GpuError> {
        use wgpu::util::DeviceExt;
        let materials = mesh.materials();
        let vertices: Vec<MeshVertex> = mesh
            .positions()
            .iter()
            .zip(mesh.normals())
            .enumerate()
            .map(|(index, (position, normal))| {
                let material = materials.and_then(|m| m.get(index)).copied().unwrap_or(DEFAULT_MATERIAL);
                MeshVertex {
                    position: position.to_array(),
                    normal: normal.to_array(),
                    albedo: material.albedo.to_array(),
                    roughness_metallic: [material.roughness, 0.0],
                }
            })
            .collect();
        let indices: Vec<u32> = mesh.triangles().iter().flatten().copied().collect();
        let index_count = u32::try_from(indices.len())
            .map_err(|_| GpuError::InvalidRequest(format!("{} indices do not fit a u32 draw", indices.len())))?;
        scoped(device, || GpuMesh {
            vertices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("grain mesh vertices"),
                contents: bytemuck::cast_slice(&vertices),
                usage: wgpu::BufferUsages::VERTEX,
            }),
            indices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("grain mesh indices"),
                contents: bytemuck::cast_slice(&indices),
                usage: wgpu::BufferUsages::INDEX,
            }),
            index_count,
        })
    }
}

/// The screen G-buffer: one texture per entry of [`GBUFFER_LAYERS`] (formats
/// [`GBUFFER_FORMATS`]), usable as storage (written by the passes), render attachment (the mesh tier of
/// `grain-renderer` rasterises into it), sampled texture (read
/// by shading) and copy source (readback).
#[derive(Debug)]
pub struct ScreenGbuffer {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// The textures, in the order of [`GBUFFER_LAYERS`].
    pub textures: [wgpu::Texture; 4],
    /// Their default views.
    pub views: [wgpu::TextureView; 4],
}

impl ScreenGbuffer {
    /// A `width × height` G-buffer (contents undefined until a pass writes it).
    pub fn new(device: &wgpu::Device, (width, height): (u32, u32)) -> Result<Self, GpuError> {
        check_texture_size(device, "screen G-buffer", (width, height, 1))?;
        let textures = scoped(device, || {
            GBUFFER_FORMATS.map(|format| {
                device.create_texture(&wgpu::TextureDescriptor {
                    label: Some("screen G-buffer"),
                    size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage: wgpu::TextureUsages::STORAGE_BINDING
                        | wgpu::TextureUsages::TEXTURE_BINDING
                        | wgpu::TextureUsages::RENDER_ATTACHMENT
                        | wgpu::TextureUsages::COPY_SRC,
                    view_formats: &[],
                })
            })
        })?;
        let views = [0, 1, 2, 3].map(|i| textures[i].create_view(&Default::default()));
        Ok(Self { width, height, textures, views })
    }

    /// Reads the G-buffer back to the CPU.
    pub fn read(&self, device: &wgpu::Device, queue: &wgpu::Queue) -> Result<GbufferImage, GpuError> {
        let read = |i: usize| read_texture(device, queue, &self.textures[i], GBUFFER_LAYERS[i].bytes_per_texel);
        let normal_bytes = read(0)?;
        let unorm = |bytes: Vec<u8>| -> Vec<Vec4> {
            bytes
                .chunks_exact(4)
                .map(|t| Vec4::from_array([t[0], t[1], t[2], t[3]].map(|b| f32::from(b) / 255.0)))
                .collect()
        };
        let normal_coverage = normal_bytes
            .chunks_exact(8)
            .map(|t| {
                Vec4::from_array(
                    [0, 2, 4, 6].map(|o| crate::half::f16_bits_to_f32(u16::from_le_bytes([t[o], t[o + 1]]))),
                )
            })
            .collect();
        let depth = read(3)?.chunks_exact(4).map(|t| f32::from_le_bytes([t[0], t[1], t[2], t[3]])).collect();
        Ok(GbufferImage {
            width: self.width,
            height: self.height,
            normal_coverage,
            albedo: unorm(read(1)?),
            material: unorm(read(2)?),
            depth,
        })
    }
}

/// A screen G-buffer on the CPU, rows top to bottom, decoded to `f32`.
#[derive(Clone, Debug, PartialEq)]
pub struct GbufferImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// World normal (`xyz`) and coverage (`w`).
    pub normal_coverage: Vec<Vec4>,
    /// Linear albedo (`rgb`).
    pub albedo: Vec<Vec4>,
    /// Roughness (`x`), metallic (`y`).
    pub material: Vec<Vec4>,
    /// View depth (`+∞` on the background).
    pub depth: Vec<f32>,
}

impl GbufferImage {
    /// The index of pixel `(x, y)`, or `None` outside the image.
    pub fn index(&self, x: u32, y: u32) -> Option<usize> {
        (x < self.width && y < self.height).then(|| (y * self.width + x) as usize)
    }
}

/// High-resolution render targets of `layers` array layers, `s×` the output size.
pub(crate) struct FineTargets {
    textures: [wgpu::Texture; 4],
    depth: wgpu::Texture,
    layers: u32,
}

impl FineTargets {
    pub(crate) fn new(device: &wgpu::Device, (width, height): (u32, u32), layers: u32) -> Result<Self, GpuError> {
        check_texture_size(device, "supersampled G-buffer", (width, height, layers))?;
        let size = wgpu::Extent3d { width, height, depth_or_array_layers: layers };
        let create = |format, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some("supersampled G-buffer"),
                size,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        scoped(device, || {
            let usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
            FineTargets {
                textures: GBUFFER_FORMATS.map(|format| create(format, usage)),
                depth: create(DEPTH_FORMAT, wgpu::TextureUsages::RENDER_ATTACHMENT),
                layers,
            }
        })
    }

    fn layer_view(texture: &wgpu::Texture, layer: u32) -> wgpu::TextureView {
        texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2),
            base_array_layer: layer,
            array_layer_count: Some(1),
            ..Default::default()
        })
    }

    fn array_view(texture: &wgpu::Texture) -> wgpu::TextureView {
        texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        })
    }
}

/// The pipelines of the mesh G-buffer pass and its two reductions.
#[derive(Debug)]
pub struct MeshGbufferPass {
    raster: wgpu::RenderPipeline,
    raster_layout: wgpu::BindGroupLayout,
    reduce_source_layout: wgpu::BindGroupLayout,
    reduce_gbuffer_layout: wgpu::BindGroupLayout,
    reduce_atlas_layout: wgpu::BindGroupLayout,
    reduce_gbuffer: wgpu::ComputePipeline,
    reduce_atlas: wgpu::ComputePipeline,
    camera_stride: u64,
}

impl MeshGbufferPass {
    /// Compiles the pipelines.
    pub fn new(device: &wgpu::Device) -> Result<Self, GpuError> {
        let camera_size = size_of::<CameraUniforms>() as u64;
        let alignment = u64::from(device.limits().min_uniform_buffer_offset_alignment);
        let camera_stride = camera_size.next_multiple_of(alignment);
        scoped(device, || {
            let raster_module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("mesh G-buffer raster"),
                source: wgpu::ShaderSource::Wgsl(compose(&[MESH_GBUFFER_WGSL]).into()),
            });
            let reduce_module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("G-buffer reduction"),
                source: wgpu::ShaderSource::Wgsl(compose(&[GBUFFER_REDUCE_WGSL]).into()),
            });
            let stages = wgpu::ShaderStages::VERTEX_FRAGMENT;
            let raster_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("mesh G-buffer raster"),
                entries: &[
                    uniform_entry(0, stages, true, camera_size),
                    wgpu::BindGroupLayoutEntry {
                        binding: 1,
                        visibility: wgpu::ShaderStages::VERTEX,
                        ty: wgpu::BindingType::Buffer {
                            ty: wgpu::BufferBindingType::Storage { read_only: true },
                            has_dynamic_offset: false,
                            min_binding_size: wgpu::BufferSize::new(size_of::<GrainInstance>() as u64),
                        },
                        count: None,
                    },
                ],
            });
            let raster_pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("mesh G-buffer raster"),
                bind_group_layouts: &[Some(&raster_layout)],
                immediate_size: 0,
            });
            let raster = mesh_raster_pipeline(device, &raster_pipeline_layout, &raster_module, "mesh_vertex");
            let array = wgpu::TextureViewDimension::D2Array;
            let reduce_source_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("G-buffer reduction source"),
                entries: &[
                    uniform_entry(0, wgpu::ShaderStages::COMPUTE, false, size_of::<ReduceParams>() as u64),
                    loaded_texture_entry(1, array),
                    loaded_texture_entry(2, array),
                    loaded_texture_entry(3, array),
                    loaded_texture_entry(4, array),
                ],
            });
            let reduce_gbuffer_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("G-buffer reduction output"),
                entries: &[0, 1, 2, 3].map(|i| storage_texture_entry(i, GBUFFER_FORMATS[i as usize])),
            });
            let reduce_atlas_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("atlas reduction output"),
                entries: &[wgpu::BindGroupLayoutEntry {
                    binding: 4,
                    visibility: wgpu::ShaderStages::COMPUTE,
                    ty: wgpu::BindingType::Buffer {
                        ty: wgpu::BufferBindingType::Storage { read_only: false },
                        has_dynamic_offset: false,
                        min_binding_size: None,
                    },
                    count: None,
                }],
            });
            let compute = |output: &wgpu::BindGroupLayout, entry: &str| {
                let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                    label: Some(entry),
                    bind_group_layouts: &[Some(&reduce_source_layout), Some(output)],
                    immediate_size: 0,
                });
                device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(entry),
                    layout: Some(&layout),
                    module: &reduce_module,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    cache: None,
                })
            };
            let reduce_gbuffer = compute(&reduce_gbuffer_layout, "reduce_to_gbuffer");
            let reduce_atlas = compute(&reduce_atlas_layout, "reduce_to_atlas");
            MeshGbufferPass {
                raster,
                raster_layout,
                reduce_source_layout,
                reduce_gbuffer_layout,
                reduce_atlas_layout,
                reduce_gbuffer,
                reduce_atlas,
                camera_stride,
            }
        })
    }

    /// Renders one copy of `mesh` per entry of `instances` (an instanced draw; none gives
    /// an empty G-buffer), seen by `camera`, into `target` with `s × s` supersampling
    /// (`supersampling ≥ 1`). The camera's own viewport size is not used: the target's
    /// size is.
    #[allow(clippy::too_many_arguments)]
    pub fn render(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        mesh: &GpuMesh,
        camera: &CameraUniforms,
        instances: &[GrainInstance],
        supersampling: u32,
        target: &ScreenGbuffer,
    ) -> Result<(), GpuError> {
        let fine_size = fine_size(supersampling, (target.width, target.height))?;
        let limit = device.limits().max_storage_buffer_binding_size;
        let instance_bytes = size_of_val(instances) as u64;
        if instance_bytes > limit {
            return Err(GpuError::TooLarge {
                what: "grain instances in bytes".into(),
                requested: instance_bytes,
                limit,
            });
        }
        let fine = FineTargets::new(device, fine_size, 1)?;
        let params =
            ReduceParams { size: glam::UVec4::new(supersampling, target.width, target.height, 1), extent: Vec4::ONE };
        scoped(device, || {
            let mut encoder = device.create_command_encoder(&Default::default());
            self.encode_raster(device, &mut encoder, mesh, std::slice::from_ref(camera), instances, &fine);
            let output = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("G-buffer reduction output"),
                layout: &self.reduce_gbuffer_layout,
                entries: &[0, 1, 2, 3].map(|i| wgpu::BindGroupEntry {
                    binding: i,
                    resource: wgpu::BindingResource::TextureView(&target.views[i as usize]),
                }),
            });
            self.encode_reduce(device, &mut encoder, &self.reduce_gbuffer, &params, &fine, &output);
            queue.submit([encoder.finish()]);
        })
    }

    /// Encodes the raster of `mesh` (one instanced draw of all `instances`) once per
    /// camera, camera `i` into array layer `i` of `fine` (one render pass per layer, all in
    /// one encoder).
    pub(crate) fn encode_raster(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        mesh: &GpuMesh,
        cameras: &[CameraUniforms],
        instances: &[GrainInstance],
        fine: &FineTargets,
    ) {
        use wgpu::util::DeviceExt;
        let stride = self.camera_stride as usize;
        let mut camera_bytes = vec![0u8; stride * cameras.len()];
        for (slot, camera) in camera_bytes.chunks_exact_mut(stride).zip(cameras) {
            slot[..size_of::<CameraUniforms>()].copy_from_slice(bytemuck::bytes_of(camera));
        }
        let camera_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("mesh G-buffer cameras"),
            contents: &camera_bytes,
            usage: wgpu::BufferUsages::UNIFORM,
        });
        // A storage binding cannot be empty: with no instance, bind one unused zero instance.
        let placeholder = [GrainInstance::zeroed()];
        let instance_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("mesh G-buffer instances"),
            contents: bytemuck::cast_slice(if instances.is_empty() { &placeholder } else { instances }),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("mesh G-buffer raster"),
            layout: &self.raster_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &camera_buffer,
                        offset: 0,
                        size: wgpu::BufferSize::new(size_of::<CameraUniforms>() as u64),
                    }),
                },
                wgpu::BindGroupEntry { binding: 1, resource: instance_buffer.as_entire_binding() },
            ],
        });
        for (layer, _) in (0..fine.layers).zip(cameras) {
            let views = [0, 1, 2, 3].map(|i| FineTargets::layer_view(&fine.textures[i], layer));
            let depth_view = FineTargets::layer_view(&fine.depth, layer);
            let attachments = views.each_ref().map(|view| {
                Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })
            });
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("mesh G-buffer raster"),
                color_attachments: &attachments,
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth_view,
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Discard }),
                    stencil_ops: None,
                }),
                ..Default::default()
            });
            pass.set_pipeline(&self.raster);
            // An offset beyond u32 (never for the batch sizes used) becomes a wgpu validation
            // error reported by the caller's error scope, not a wrong camera.
            let offset = u32::try_from(u64::from(layer) * self.camera_stride).unwrap_or(u32::MAX);
            pass.set_bind_group(0, &bind_group, &[offset]);
            pass.set_vertex_buffer(0, mesh.vertices.slice(..));
            pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..mesh.index_count, 0, 0..instances.len() as u32);
        }
    }

    /// Encodes one reduction of `fine` with `pipeline` into the `output` bind group.
    fn encode_reduce(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        pipeline: &wgpu::ComputePipeline,
        params: &ReduceParams,
        fine: &FineTargets,
        output: &wgpu::BindGroup,
    ) {
        use wgpu::util::DeviceExt;
        let params_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("G-buffer reduction parameters"),
            contents: bytemuck::bytes_of(params),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let views = [0, 1, 2, 3].map(|i| FineTargets::array_view(&fine.textures[i]));
        let mut entries = vec![wgpu::BindGroupEntry { binding: 0, resource: params_buffer.as_entire_binding() }];
        for (binding, view) in (1..).zip(&views) {
            entries.push(wgpu::BindGroupEntry { binding, resource: wgpu::BindingResource::TextureView(view) });
        }
        let source = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("G-buffer reduction source"),
            layout: &self.reduce_source_layout,
            entries: &entries,
        });
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &source, &[]);
        pass.set_bind_group(1, output, &[]);
        pass.dispatch_workgroups(params.size.y.div_ceil(PIXEL_TILE), params.size.z.div_ceil(PIXEL_TILE), params.size.w);
    }

    /// Renders `mesh` (placed by `instance`) with each of `cameras` (`s×` supersampled,
    /// `side × side` output texels, one array layer each of `fine`), reduces into the
    /// atlas layout (4 un-premultiplied `vec4` per texel, see `gbuffer_reduce.wgsl`) and
    /// reads the result back. `extent` is the atlas's `R`.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn render_atlas_views(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        mesh: &GpuMesh,
        cameras: &[CameraUniforms],
        instance: &GrainInstance,
        (supersampling, side, extent): (u32, u32, f32),
        fine: &FineTargets,
    ) -> Result<Vec<Vec4>, GpuError> {
        let layers = cameras.len() as u32;
        let params = ReduceParams {
            size: glam::UVec4::new(supersampling, side, side, layers),
            extent: Vec4::new(extent, 0.0, 0.0, 0.0),
        };
        let size = u64::from(side) * u64::from(side) * u64::from(layers) * 64;
        let output_buffer = scoped(device, || {
            let output_buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("atlas reduction output"),
                size,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            let mut encoder = device.create_command_encoder(&Default::default());
            self.encode_raster(device, &mut encoder, mesh, cameras, std::slice::from_ref(instance), fine);
            let output = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("atlas reduction output"),
                layout: &self.reduce_atlas_layout,
                entries: &[wgpu::BindGroupEntry { binding: 4, resource: output_buffer.as_entire_binding() }],
            });
            self.encode_reduce(device, &mut encoder, &self.reduce_atlas, &params, fine, &output);
            queue.submit([encoder.finish()]);
            output_buffer
        })?;
        let bytes = crate::gpu_util::read_buffer(device, queue, &output_buffer, size)?;
        Ok(bytemuck::pod_collect_to_vec(&bytes))
    }
}

/// The supersampled size `s·(width, height)`, or an error for `s = 0` or an overflow.
pub(crate) fn fine_size(supersampling: u32, (width, height): (u32, u32)) -> Result<(u32, u32), GpuError> {
    if supersampling == 0 {
        return Err(GpuError::InvalidRequest("supersampling factor 0 (must be ≥ 1)".into()));
    }
    match (width.checked_mul(supersampling), height.checked_mul(supersampling)) {
        (Some(w), Some(h)) => Ok((w, h)),
        _ => Err(GpuError::InvalidRequest(format!("{width}×{height} × {supersampling} overflows"))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use wgsl_gen::ComposedShader;

    #[test]
    fn raster_and_reduction_shaders_validate() {
        for (name, source) in [("mesh_gbuffer", MESH_GBUFFER_WGSL), ("gbuffer_reduce", GBUFFER_REDUCE_WGSL)] {
            let shader = ComposedShader::new(name)
                .with_part(crate::scene::GENERATED_WGSL_PATH, crate::scene::GENERATED_WGSL)
                .with_part(format!("crates/grain-impostor/shaders/{name}.wgsl"), source);
            shader.validate().unwrap_or_else(|e| panic!("{e}"));
        }
    }

    #[test]
    fn gbuffer_formats_match_the_shared_layer_table() {
        for (format, layer) in GBUFFER_FORMATS.iter().zip(GBUFFER_LAYERS) {
            assert_eq!(format!("{format:?}"), layer.format);
            assert_eq!(format.block_copy_size(None), Some(layer.bytes_per_texel));
        }
    }

    #[test]
    fn supersampled_size_rejects_zero_and_overflow() {
        assert_eq!(fine_size(3, (10, 20)), Ok((30, 60)));
        assert!(fine_size(0, (10, 20)).is_err());
        assert!(fine_size(u32::MAX, (10, 20)).is_err());
    }
}
