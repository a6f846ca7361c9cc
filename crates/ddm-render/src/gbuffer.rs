//! The base-mesh G-buffer: the coarse base mesh rasterized with a perspective camera
//! into four `Rgba32Float` targets, read back as one [`BaseGBufferTexel`] per pixel
//! (world position and coverage, `(∂P/∂u, u)`, `(∂P/∂v, v)`, `(N, view depth)`), linearly
//! interpolated with perspective correction by the rasterizer.

use ddm_tracer::tangent_space::BaseGBufferTexel;
use gpu_harness::{Gpu, HarnessError};
use mesostructure::BaseMesh;
use wgpu::util::DeviceExt;
use wgsl_gen::{StructDecl, generate_declarations};

use crate::base_mesh::{BaseVertex, scaled_vertices};
use crate::camera::{BaseCamera, Camera};

/// The G-buffer targets' format.
const GBUFFER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
/// Bytes per texel of one target.
const TARGET_BYTES: u32 = 16;
/// Number of targets.
const TARGETS: usize = 4;

/// The raster shader; the declarations of [`BaseCamera`] and [`BaseVertex`] are generated
/// from Rust and prepended.
const RASTER_WGSL: &str = r"
@group(0) @binding(0) var<uniform> camera: BaseCamera;
@group(0) @binding(1) var<storage, read> vertices: array<BaseVertex>;

struct Interpolants {
    @builtin(position) clip: vec4<f32>,
    @location(0) position: vec3<f32>,
    @location(1) tangent_u: vec4<f32>,
    @location(2) bitangent_v: vec4<f32>,
    @location(3) normal: vec3<f32>,
}

struct GBufferOut {
    @location(0) position_coverage: vec4<f32>,
    @location(1) tangent_u: vec4<f32>,
    @location(2) bitangent_v: vec4<f32>,
    @location(3) normal_depth: vec4<f32>,
}

@vertex
fn base_vertex(@builtin(vertex_index) index: u32) -> Interpolants {
    let v = vertices[index];
    let m = mat4x4<f32>(camera.clip_from_world[0], camera.clip_from_world[1], camera.clip_from_world[2], camera.clip_from_world[3]);
    return Interpolants(m * vec4<f32>(v.position.xyz, 1.0), v.position.xyz, v.tangent_u, v.bitangent_v, v.normal.xyz);
}

@fragment
fn base_fragment(in: Interpolants) -> GBufferOut {
    let depth = distance(in.position, camera.eye.xyz);
    return GBufferOut(vec4<f32>(in.position, 1.0), in.tangent_u, in.bitangent_v, vec4<f32>(in.normal, depth));
}
";

/// A read-back G-buffer.
#[derive(Clone, Debug)]
pub struct GBuffer {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major texels, row 0 on top.
    pub texels: Vec<BaseGBufferTexel>,
    /// Wall-clock seconds of the raster submission (no timestamps on render passes here).
    pub raster_seconds: f64,
}

/// The raster shader with its generated declarations.
pub fn raster_shader() -> Result<String, HarnessError> {
    let declarations = generate_declarations(
        "ddm_render_raster",
        &[StructDecl::of::<BaseCamera>(), StructDecl::of::<BaseVertex>()],
        &[],
    )
    .map_err(|e| HarnessError::InvalidRequest(e.to_string()))?;
    Ok(format!("{declarations}\n{RASTER_WGSL}"))
}

/// Rasterizes `mesh` seen by `camera` into a G-buffer (depth test, no culling; uncovered
/// texels are zero). Errors name the limit or the wgpu problem: an image larger than the
/// adapter's 2-D textures, more colour bytes per sample than it allows, a mesh whose
/// frames cannot be scaled ([`scaled_vertices`]).
pub fn rasterize_gbuffer(gpu: &Gpu, mesh: &BaseMesh, camera: &Camera) -> Result<GBuffer, HarnessError> {
    let (width, height) = (camera.width, camera.height);
    let limits = gpu.limits();
    if width == 0 || height == 0 {
        return Err(HarnessError::InvalidRequest(format!("G-buffer {width}×{height} is empty")));
    }
    if width.max(height) > limits.max_texture_dimension_2d {
        return Err(HarnessError::TooLarge {
            what: "G-buffer side in texels".into(),
            requested: u64::from(width.max(height)),
            limit: u64::from(limits.max_texture_dimension_2d),
        });
    }
    let sample_bytes = TARGET_BYTES * TARGETS as u32;
    if sample_bytes > limits.max_color_attachment_bytes_per_sample || TARGETS as u32 > limits.max_color_attachments {
        return Err(HarnessError::TooLarge {
            what: "G-buffer colour bytes per sample".into(),
            requested: u64::from(sample_bytes),
            limit: u64::from(limits.max_color_attachment_bytes_per_sample),
        });
    }
    let vertices =
        scaled_vertices(mesh).ok_or_else(|| HarnessError::InvalidRequest("base mesh frames are degenerate".into()))?;
    let indices: Vec<u32> = mesh.indices.iter().flatten().copied().collect();
    if vertices.is_empty() || indices.is_empty() {
        return Err(HarnessError::InvalidRequest("base mesh is empty".into()));
    }
    let vertex_bytes = (vertices.len() * size_of::<BaseVertex>()) as u64;
    let storage_limit = limits.max_storage_buffer_binding_size.min(limits.max_buffer_size);
    if vertex_bytes > storage_limit {
        return Err(HarnessError::TooLarge {
            what: "base mesh vertices in bytes".into(),
            requested: vertex_bytes,
            limit: storage_limit,
        });
    }
    let index_count = u32::try_from(indices.len()).map_err(|_| HarnessError::TooLarge {
        what: "base mesh indices".into(),
        requested: indices.len() as u64,
        limit: u64::from(u32::MAX),
    })?;
    let reach = mesh.positions.iter().map(|p| (*p - camera.eye).length()).fold(0.0_f32, f32::max);
    let uniforms = camera.uniforms((reach * 1e-3).max(1e-3), reach * 1.5 + 1.0);
    let source = raster_shader()?;
    let row_bytes = width * TARGET_BYTES;
    let padded_row_bytes = row_bytes.next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let extent = wgpu::Extent3d { width, height, depth_or_array_layers: 1 };
    let (readbacks, started) = gpu.scoped(|| {
        let device = &gpu.device;
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("base G-buffer"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let targets: Vec<Option<wgpu::ColorTargetState>> =
            (0..TARGETS).map(|_| Some(wgpu::ColorTargetState::from(GBUFFER_FORMAT))).collect();
        let pipeline = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("base G-buffer"),
            layout: None,
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("base_vertex"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: wgpu::TextureFormat::Depth32Float,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("base_fragment"),
                compilation_options: Default::default(),
                targets: &targets,
            }),
            multiview_mask: None,
            cache: None,
        });
        let camera_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("base G-buffer camera"),
            contents: bytemuck::bytes_of(&uniforms),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let vertex_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("base G-buffer vertices"),
            contents: bytemuck::cast_slice(&vertices),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let index_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("base G-buffer indices"),
            contents: bytemuck::cast_slice(&indices),
            usage: wgpu::BufferUsages::INDEX,
        });
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("base G-buffer"),
            layout: &pipeline.get_bind_group_layout(0),
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: camera_buffer.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: vertex_buffer.as_entire_binding() },
            ],
        });
        let texture = |format, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some("base G-buffer target"),
                size: extent,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let color_usage = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC;
        let textures: Vec<wgpu::Texture> = (0..TARGETS).map(|_| texture(GBUFFER_FORMAT, color_usage)).collect();
        let depth = texture(wgpu::TextureFormat::Depth32Float, wgpu::TextureUsages::RENDER_ATTACHMENT);
        let views: Vec<wgpu::TextureView> = textures.iter().map(|t| t.create_view(&Default::default())).collect();
        let depth_view = depth.create_view(&Default::default());
        let attachments: Vec<Option<wgpu::RenderPassColorAttachment>> = views
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
        let mut encoder = device.create_command_encoder(&Default::default());
        {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("base G-buffer"),
                color_attachments: &attachments,
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &depth_view,
                    depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Discard }),
                    stencil_ops: None,
                }),
                ..Default::default()
            });
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, &bind_group, &[]);
            pass.set_index_buffer(index_buffer.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..index_count, 0, 0..1);
        }
        let readbacks: Vec<wgpu::Buffer> = textures
            .iter()
            .map(|t| {
                let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("base G-buffer readback"),
                    size: u64::from(padded_row_bytes) * u64::from(height),
                    usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                encoder.copy_texture_to_buffer(
                    t.as_image_copy(),
                    wgpu::TexelCopyBufferInfo {
                        buffer: &buffer,
                        layout: wgpu::TexelCopyBufferLayout {
                            offset: 0,
                            bytes_per_row: Some(padded_row_bytes),
                            rows_per_image: Some(height),
                        },
                    },
                    extent,
                );
                buffer
            })
            .collect();
        let started = std::time::Instant::now();
        gpu.queue.submit([encoder.finish()]);
        (readbacks, started)
    })?;
    gpu.wait()?;
    let raster_seconds = started.elapsed().as_secs_f64();
    let size = u64::from(padded_row_bytes) * u64::from(height);
    let mut layers: Vec<Vec<glam::Vec4>> = Vec::with_capacity(TARGETS);
    for buffer in &readbacks {
        let padded = gpu.read_buffer(buffer, size)?;
        let mut texels = Vec::with_capacity((width * height) as usize);
        for row in padded.chunks_exact(padded_row_bytes as usize) {
            texels.extend(bytemuck::pod_collect_to_vec::<u8, glam::Vec4>(&row[..row_bytes as usize]));
        }
        layers.push(texels);
    }
    let texels = (0..(width * height) as usize)
        .map(|i| BaseGBufferTexel {
            position_coverage: layers[0][i],
            tangent_u: layers[1][i],
            bitangent_v: layers[2][i],
            normal_depth: layers[3][i],
        })
        .collect();
    Ok(GBuffer { width, height, texels, raster_seconds })
}

#[cfg(test)]
mod tests {
    use super::*;
    use wgsl_gen::{ComposedShader, check_layout};

    #[test]
    fn raster_shader_validates_and_matches_the_rust_layouts() {
        let source = raster_shader().unwrap();
        let shader = ComposedShader::new("ddm_render_raster").with_part("gbuffer.rs", &source);
        shader.validate().unwrap_or_else(|e| panic!("{e}"));
        let module = shader.parse().unwrap();
        check_layout(&module, &[StructDecl::of::<BaseCamera>(), StructDecl::of::<BaseVertex>()])
            .unwrap_or_else(|e| panic!("{e:?}"));
    }
}
