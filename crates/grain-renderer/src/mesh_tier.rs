//! The mesh tier (§3, Fig. 2 ②): the grains the splitter sends to the mesh list, drawn as
//! instances of the grain's mesh with **one `draw_indexed_indirect`** whose instance count
//! the splitter wrote on the GPU; each instance finds its grain as
//! `elements[offset[mesh list] + instance_index]`. The raster is `grain-impostor`'s mesh
//! G-buffer pass (same vertex placement and fragment outputs, `mesh_gbuffer.wgsl`), into the
//! screen G-buffer directly: it clears the G-buffer, so it runs first in a frame.

use glam::{UVec4, Vec3};
use grain_impostor::mesh_gbuffer::{GpuMesh, MESH_DEPTH_FORMAT, ScreenGbuffer, mesh_raster_pipeline};
use grain_impostor::scene::CameraUniforms;
use grain_splitter::{GrainSplitter, LIST_MESH};

use crate::error::RenderError;
use crate::inputs::ListInputs;
use crate::shaders::mesh_tier_shader;
use crate::tier_layout::MeshTierUniforms;

/// Which layer of a frame a mesh tier draws ([`MeshTier::encode_layer`]).
#[derive(Clone, Copy)]
pub enum MeshLayer<'a> {
    /// The first grain type: clears the G-buffer and the depth buffer.
    First,
    /// A further grain type, over the first's G-buffer contents and depth buffer.
    Over(&'a MeshTier),
}

/// The bind group of one set of inputs.
pub struct MeshTierBindings {
    bind_group: wgpu::BindGroup,
    indirect: wgpu::Buffer,
}

/// The mesh tier of one grain mesh at one viewport size, built once.
pub struct MeshTier {
    size: (u32, u32),
    pipeline: wgpu::RenderPipeline,
    layout: wgpu::BindGroupLayout,
    camera: wgpu::Buffer,
    uniforms: wgpu::Buffer,
    depth: wgpu::TextureView,
    mesh: GpuMesh,
    centre: Vec3,
}

fn buffer_entry(binding: u32, ty: wgpu::BufferBindingType, stages: wgpu::ShaderStages) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: stages,
        ty: wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None },
        count: None,
    }
}

impl MeshTier {
    /// Uploads `mesh` (modelled around `mesh.bounds().centre`, which each grain's centre
    /// replaces), validates the shader with naga and builds the pipeline and depth buffer.
    pub fn new(device: &wgpu::Device, size: (u32, u32), mesh: &grain_mesh::GrainMesh) -> Result<Self, RenderError> {
        let (width, height) = size;
        let limit = device.limits().max_texture_dimension_2d;
        if width == 0 || height == 0 || width > limit || height > limit {
            return Err(RenderError::InvalidSetting {
                field: "size",
                reason: format!("{size:?}: must be non-empty and at most {limit} per side"),
            });
        }
        let shader = mesh_tier_shader();
        shader.validate().map_err(|e| RenderError::InvalidShader(e.to_string()))?;
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(shader.name()),
            source: wgpu::ShaderSource::Wgsl(shader.source().to_owned().into()),
        });
        let read = wgpu::BufferBindingType::Storage { read_only: true };
        let uniform = wgpu::BufferBindingType::Uniform;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("mesh tier"),
            entries: &[
                buffer_entry(0, uniform, wgpu::ShaderStages::VERTEX_FRAGMENT),
                buffer_entry(1, read, wgpu::ShaderStages::VERTEX),
                buffer_entry(2, read, wgpu::ShaderStages::VERTEX),
                buffer_entry(3, read, wgpu::ShaderStages::VERTEX),
                buffer_entry(4, uniform, wgpu::ShaderStages::VERTEX),
            ],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("mesh tier"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = mesh_raster_pipeline(device, &pipeline_layout, &module, "mesh_tier_vertex");
        let buffer = |label: &str, size: usize| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        };
        let depth = device
            .create_texture(&wgpu::TextureDescriptor {
                label: Some("mesh tier depth"),
                size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: MESH_DEPTH_FORMAT,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
                view_formats: &[],
            })
            .create_view(&Default::default());
        let gpu_mesh = GpuMesh::upload(device, mesh).map_err(|e| RenderError::InvalidInput(e.to_string()))?;
        Ok(Self {
            size,
            pipeline,
            layout,
            camera: buffer("mesh tier camera", size_of::<CameraUniforms>()),
            uniforms: buffer("mesh tier settings", size_of::<MeshTierUniforms>()),
            depth,
            mesh: gpu_mesh,
            centre: mesh.bounds().centre,
        })
    }

    /// The mesh's index count: the splitter's `SplitSettings::mesh_index_count`.
    pub fn index_count(&self) -> u32 {
        self.mesh.index_count()
    }

    /// The bind group of `inputs`.
    pub fn bind(&self, device: &wgpu::Device, inputs: &ListInputs<'_>) -> Result<MeshTierBindings, RenderError> {
        if !inputs.indirect.usage().contains(wgpu::BufferUsages::INDIRECT) {
            return Err(RenderError::InvalidInput("the splitter's indirect buffer needs INDIRECT usage".into()));
        }
        fn whole(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
            wgpu::BindGroupEntry { binding, resource: buffer.as_entire_binding() }
        }
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("mesh tier"),
            layout: &self.layout,
            entries: &[
                whole(0, &self.camera),
                whole(1, inputs.instances),
                whole(2, inputs.elements),
                whole(3, inputs.counters),
                whole(4, &self.uniforms),
            ],
        });
        Ok(MeshTierBindings { bind_group, indirect: inputs.indirect.clone() })
    }

    /// Writes the camera through `queue` and records the mesh list's draw into `gbuffer`
    /// (one render pass that first clears it to the background: coverage 0, depth `+∞`).
    pub fn encode(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        bindings: &MeshTierBindings,
        camera: &CameraUniforms,
        gbuffer: &ScreenGbuffer,
    ) -> Result<(), RenderError> {
        self.encode_layer(queue, encoder, bindings, camera, gbuffer, MeshLayer::First)
    }

    /// The raster depth buffer this tier clears (and another grain type's tier may draw
    /// over: [`MeshLayer::Over`]).
    pub fn depth(&self) -> &wgpu::TextureView {
        &self.depth
    }

    /// [`MeshTier::encode`] as a layer of a scene of several grain types: the first clears
    /// the G-buffer and its own depth buffer; each further type draws over both, testing
    /// against the first's depth buffer (every type's meshes in one depth test).
    pub fn encode_layer(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        bindings: &MeshTierBindings,
        camera: &CameraUniforms,
        gbuffer: &ScreenGbuffer,
        layer: MeshLayer<'_>,
    ) -> Result<(), RenderError> {
        if (gbuffer.width, gbuffer.height) != self.size {
            return Err(RenderError::InvalidInput(format!(
                "the G-buffer is {}×{}, the mesh tier {:?}",
                gbuffer.width, gbuffer.height, self.size
            )));
        }
        queue.write_buffer(&self.camera, 0, bytemuck::bytes_of(camera));
        let uniforms = MeshTierUniforms { list: UVec4::new(LIST_MESH, 0, 0, 0), centre: self.centre.extend(0.0) };
        queue.write_buffer(&self.uniforms, 0, bytemuck::bytes_of(&uniforms));
        let clears = [
            wgpu::Color::TRANSPARENT,
            wgpu::Color::TRANSPARENT,
            wgpu::Color::TRANSPARENT,
            wgpu::Color { r: f64::INFINITY, g: 0.0, b: 0.0, a: 0.0 },
        ];
        let (depth, depth_load) = match layer {
            MeshLayer::First => (&self.depth, wgpu::LoadOp::Clear(1.0)),
            MeshLayer::Over(first) => {
                if first.size != self.size {
                    return Err(RenderError::InvalidInput(format!(
                        "a mesh tier of {:?} over one of {:?}",
                        self.size, first.size
                    )));
                }
                (&first.depth, wgpu::LoadOp::Load)
            }
        };
        let attachments: Vec<Option<wgpu::RenderPassColorAttachment<'_>>> = gbuffer
            .views
            .iter()
            .zip(clears)
            .map(|(view, clear)| {
                let load = match layer {
                    MeshLayer::First => wgpu::LoadOp::Clear(clear),
                    MeshLayer::Over(_) => wgpu::LoadOp::Load,
                };
                Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target: None,
                    ops: wgpu::Operations { load, store: wgpu::StoreOp::Store },
                })
            })
            .collect();
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("mesh tier"),
            color_attachments: &attachments,
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: depth,
                depth_ops: Some(wgpu::Operations { load: depth_load, store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            }),
            ..Default::default()
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &bindings.bind_group, &[]);
        pass.set_vertex_buffer(0, self.mesh.vertices().slice(..));
        pass.set_index_buffer(self.mesh.indices().slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed_indirect(&bindings.indirect, GrainSplitter::indirect_offset(LIST_MESH));
        Ok(())
    }
}
