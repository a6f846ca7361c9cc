//! The embeddable renderer: the base mesh's G-buffer raster passes (the G-buffer, then
//! the exit distance), then the per-pixel compute pass that reads the G-buffer textures on
//! the GPU (`textureLoad`), builds each covered pixel's tangent-space ray, traces it
//! through the distance maps with the WGSL tracer of `ddm-tracer`, shades the hit and
//! casts a shadow ray, and writes a target.
//!
//! # Silhouettes
//!
//! On a closed base mesh (the torus) a ray that enters the slab near the silhouette leaves
//! the base mesh's solid again a short way on: the second raster pass stores where, per
//! pixel, and a ray with no hit before that point (nor before the slab's bottom) is
//! [`PIXEL_LEFT_SHELL`](ddm_tracer::tangent_space::PIXEL_LEFT_SHELL): nothing of the object
//! is drawn there, the pixel shows what lies behind, so the mesostructure's own outline
//! replaces the base mesh's (paper Fig. 1 and 8). A ray that reaches the slab's bottom
//! shows the base surface under the mesostructure. On an open mesh seen from one side
//! (the plane tile) there is no second surface and nothing changes.
//!
//! # Objects, and when each is built
//!
//! | object | built | holds |
//! |---|---|---|
//! | [`DdmRenderPipelines`] | once per device | the raster pipelines, the per-pixel shader module, the bind group layouts; the per-pixel pipelines of each [`TracePipelineConstants`] met, created by the first [`DdmRenderer`] that needs them and shared after |
//! | [`GBufferPass`] | once per base mesh and size | the mesh's vertex and index buffers, the G-buffer textures, the camera uniform |
//! | [`GpuSceneBuffers`] | once per tracer scene | the [`GpuScene`]'s uniforms and six storage buffers, its pipeline constants |
//! | [`DdmRenderer`] | once per (G-buffer, scene) | the render-parameter uniform, the compute bind group, its scene's per-pixel pipelines |
//!
//! What stays fixed for a scene (the method, the stepping, the tiling, the maps' block
//! shift, the atlas's storage) is a pipeline-overridable constant of the tracer's WGSL
//! ([`ddm_tracer::pipeline_constants`]): each scene's pipelines are compiled for its
//! setting, without the branches of the others.
//! | [`DdmTarget`] | once per output | the target's bind group: a [`BaseRenderPixel`] buffer or an [`COLOR_TARGET_FORMAT`] texture |
//!
//! Every frame, [`DdmRenderer::encode`] writes two small uniforms with
//! `queue.write_buffer` (the camera, the [`BaseRenderParams`]) and records the two passes:
//! no pipeline, buffer, texture or bind group is created, nothing is read back. Those
//! writes land at the next `queue.submit`, before any of its command buffers run, so
//! frames of one renderer (or of renderers sharing a [`GBufferPass`]) go in separate
//! submissions. Readback for tests and tools is in [`crate::readback`].
//!
//! # Targets
//!
//! - [`DdmRenderer::pixel_target`]: a storage buffer of `width × height`
//!   [`BaseRenderPixel`]s, row-major, row 0 on top: colour and its class
//!   ([`PIXEL_UNCOVERED`](ddm_tracer::tangent_space::PIXEL_UNCOVERED), `PIXEL_MISS`,
//!   `PIXEL_HIT`, `PIXEL_LEFT_SHELL`), tangent-space ray, steps, shadow flag and hit. What
//!   tests and tools read.
//! - [`DdmRenderer::color_target`]: a `width × height` [`COLOR_TARGET_FORMAT`]
//!   (`Rgba16Float`) storage texture: linear colour, alpha 1 where the object is seen (a hit,
//!   or the base surface under the slab), `(0, 0, 0, 0)` elsewhere (off the base mesh, and
//!   where the ray leaves the shell). What an application composites or tone-maps.
//! - [`DdmRenderer::color_depth_target`]: the same colour texture and a
//!   [`DEPTH_TARGET_FORMAT`] (`R32Float`) texture of inverse eye distances, written only
//!   where the pixel is seen nearer than what it holds: several objects (each its own
//!   renderer, one camera) encoded one after the other into one target interpenetrate.
//!   [`DdmTarget::encode_clear`] clears it for a frame; a texel whose base surface lies
//!   behind what the target holds is skipped before its ray is traced.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, PoisonError};

use ddm_tracer::tangent_space::{BaseRenderParams, BaseRenderPixel};
use ddm_tracer::{GpuScene, TracePipelineConstants};
use glam::{Vec3, Vec4};
use gpu_harness::error_scoped;
use wgpu::util::DeviceExt;

use crate::camera::Camera;
use crate::error::{DdmRenderError, check_limit};
use crate::gbuffer::{GBUFFER_TEXTURES, GBufferPass, GBufferPipeline, PassTimestamps};
use crate::shaders::{PIXEL_SHADER, RENDER_TILE, pixel_shader};

/// The format of [`DdmRenderer::color_target`]'s texture.
pub const COLOR_TARGET_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// The format of [`DdmRenderer::color_depth_target`]'s depth texture: per pixel the inverse
/// world distance from the eye of what the colour texture holds (larger is nearer, 0 holds
/// nothing).
pub const DEPTH_TARGET_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

/// Binding of the tracer's uniforms in group 0.
const TRACE_UNIFORMS_BINDING: u32 = 0;
/// First binding of the tracer's scene buffers in group 0 (`shaders/ddm_tracer.wgsl`).
const SCENE_FIRST_BINDING: u32 = 3;
/// Number of scene storage buffers ([`GpuScene::storage_bytes`]).
const SCENE_BUFFERS: usize = 6;
/// Binding of the [`BaseRenderParams`] uniform in group 0.
const PARAMS_BINDING: u32 = 9;
/// First binding of the G-buffer textures in group 0 (then the exit distance).
const GBUFFER_FIRST_BINDING: u32 = 10;
/// Binding of the pixel buffer in group 1.
const PIXELS_BINDING: u32 = 0;
/// Binding of the colour texture in group 1.
const COLOR_BINDING: u32 = 1;
/// Binding of the depth texture in group 1.
const DEPTH_BINDING: u32 = 2;
/// The per-pixel pass's entry points, one per target kind: pixels, colour, colour and depth.
const PIXEL_ENTRY_POINTS: [&str; 3] = ["render_pixels", "render_color", "render_color_depth"];

fn compute_entry(binding: u32, ty: wgpu::BindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry { binding, visibility: wgpu::ShaderStages::COMPUTE, ty, count: None }
}

fn buffer_type(ty: wgpu::BufferBindingType) -> wgpu::BindingType {
    wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None }
}

/// The per-pixel pass's three pipelines (one per target kind) for one setting of the
/// tracer's pipeline constants.
#[derive(Debug)]
struct PixelPipelines {
    pixels: wgpu::ComputePipeline,
    color: wgpu::ComputePipeline,
    color_depth: wgpu::ComputePipeline,
}

/// The compiled pipelines of both passes and their bind group layouts, created once per
/// device and shared by every [`GBufferPass`] and [`DdmRenderer`] built from them: the
/// raster pipelines at once, the per-pixel ones for each setting of the tracer's pipeline
/// constants when a [`DdmRenderer`] first needs it. Cloning is cheap and shares the GPU
/// objects (and the per-pixel pipelines compiled so far).
#[derive(Clone, Debug)]
pub struct DdmRenderPipelines {
    gbuffer: GBufferPipeline,
    scene_layout: wgpu::BindGroupLayout,
    pixels_layout: wgpu::BindGroupLayout,
    color_layout: wgpu::BindGroupLayout,
    color_depth_layout: wgpu::BindGroupLayout,
    module: wgpu::ShaderModule,
    layouts: [wgpu::PipelineLayout; 3],
    specialized: Arc<Mutex<HashMap<TracePipelineConstants, Arc<PixelPipelines>>>>,
}

impl DdmRenderPipelines {
    /// Validates both composed shaders with naga and builds the raster pipelines and the
    /// per-pixel pass's module and layouts (its pipelines come with the first
    /// [`DdmRenderer`] of each setting). Errors name the
    /// device limit the passes exceed (bind groups, bindings per group, storage buffers,
    /// sampled and storage textures, uniform buffers per stage, workgroup size) or the
    /// shader problem.
    pub fn new(device: &wgpu::Device) -> Result<Self, DdmRenderError> {
        let gbuffer = GBufferPipeline::new(device)?;
        let limits = device.limits();
        check_limit("bind groups of the per-pixel pass (max_bind_groups)", 2, limits.max_bind_groups.into())?;
        check_limit(
            "bindings in the per-pixel pass's group 0 (max_bindings_per_bind_group)",
            u64::from(GBUFFER_FIRST_BINDING) + GBUFFER_TEXTURES as u64 + 1,
            limits.max_bindings_per_bind_group.into(),
        )?;
        check_limit(
            "storage buffers of the per-pixel pass (max_storage_buffers_per_shader_stage)",
            SCENE_BUFFERS as u64 + 1,
            limits.max_storage_buffers_per_shader_stage.into(),
        )?;
        check_limit(
            "G-buffer textures read by the per-pixel pass (max_sampled_textures_per_shader_stage)",
            GBUFFER_TEXTURES as u64 + 1,
            limits.max_sampled_textures_per_shader_stage.into(),
        )?;
        check_limit(
            "storage textures of the per-pixel pass (max_storage_textures_per_shader_stage)",
            2,
            limits.max_storage_textures_per_shader_stage.into(),
        )?;
        check_limit(
            "uniform buffers of the per-pixel pass (max_uniform_buffers_per_shader_stage)",
            2,
            limits.max_uniform_buffers_per_shader_stage.into(),
        )?;
        check_limit(
            "per-pixel workgroup side (max_compute_workgroup_size_x)",
            RENDER_TILE.into(),
            limits.max_compute_workgroup_size_x.into(),
        )?;
        check_limit(
            "per-pixel workgroup side (max_compute_workgroup_size_y)",
            RENDER_TILE.into(),
            limits.max_compute_workgroup_size_y.into(),
        )?;
        check_limit(
            "per-pixel workgroup invocations (max_compute_invocations_per_workgroup)",
            u64::from(RENDER_TILE) * u64::from(RENDER_TILE),
            limits.max_compute_invocations_per_workgroup.into(),
        )?;
        let shader = pixel_shader()?;
        shader
            .validate()
            .map_err(|e| DdmRenderError::InvalidShader { shader: PIXEL_SHADER, message: e.to_string() })?;
        Ok(error_scoped(device, || {
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(PIXEL_SHADER),
                source: wgpu::ShaderSource::Wgsl(shader.source().into()),
            });
            let uniform = buffer_type(wgpu::BufferBindingType::Uniform);
            let mut entries = vec![compute_entry(TRACE_UNIFORMS_BINDING, uniform)];
            entries.extend((0..SCENE_BUFFERS as u32).map(|k| {
                compute_entry(
                    SCENE_FIRST_BINDING + k,
                    buffer_type(wgpu::BufferBindingType::Storage { read_only: true }),
                )
            }));
            entries.push(compute_entry(PARAMS_BINDING, uniform));
            entries.extend((0..GBUFFER_TEXTURES as u32 + 1).map(|k| {
                compute_entry(
                    GBUFFER_FIRST_BINDING + k,
                    wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: false },
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                )
            }));
            let scene_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("ddm-render per-pixel scene and G-buffer"),
                entries: &entries,
            });
            let pixels_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("ddm-render pixel target"),
                entries: &[compute_entry(
                    PIXELS_BINDING,
                    buffer_type(wgpu::BufferBindingType::Storage { read_only: false }),
                )],
            });
            let storage_texture = |binding, access, format| {
                compute_entry(
                    binding,
                    wgpu::BindingType::StorageTexture {
                        access,
                        format,
                        view_dimension: wgpu::TextureViewDimension::D2,
                    },
                )
            };
            let color_entry =
                storage_texture(COLOR_BINDING, wgpu::StorageTextureAccess::WriteOnly, COLOR_TARGET_FORMAT);
            let color_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("ddm-render colour target"),
                entries: &[color_entry],
            });
            let color_depth_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("ddm-render colour and depth target"),
                entries: &[
                    color_entry,
                    storage_texture(DEPTH_BINDING, wgpu::StorageTextureAccess::ReadWrite, DEPTH_TARGET_FORMAT),
                ],
            });
            let layout = |entry: &str, target_layout: &wgpu::BindGroupLayout| {
                device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                    label: Some(entry),
                    bind_group_layouts: &[Some(&scene_layout), Some(target_layout)],
                    immediate_size: 0,
                })
            };
            let layouts = [
                layout(PIXEL_ENTRY_POINTS[0], &pixels_layout),
                layout(PIXEL_ENTRY_POINTS[1], &color_layout),
                layout(PIXEL_ENTRY_POINTS[2], &color_depth_layout),
            ];
            Self {
                gbuffer,
                scene_layout,
                pixels_layout,
                color_layout,
                color_depth_layout,
                module,
                layouts,
                specialized: Arc::default(),
            }
        })?)
    }

    /// The per-pixel pipelines for `constants`: compiled on the first call for them (with
    /// `constants` as the pipelines' overridable constants), then shared.
    fn pixel_pipelines(
        &self,
        device: &wgpu::Device,
        constants: TracePipelineConstants,
    ) -> Result<Arc<PixelPipelines>, DdmRenderError> {
        // Held while compiling: another renderer of the same setting waits for this one.
        let mut specialized = self.specialized.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(pipelines) = specialized.get(&constants) {
            return Ok(Arc::clone(pipelines));
        }
        let values = constants.constants();
        let pipelines = error_scoped(device, || {
            let [pixels, color, color_depth] = std::array::from_fn(|k| {
                device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                    label: Some(PIXEL_ENTRY_POINTS[k]),
                    layout: Some(&self.layouts[k]),
                    module: &self.module,
                    entry_point: Some(PIXEL_ENTRY_POINTS[k]),
                    compilation_options: wgpu::PipelineCompilationOptions { constants: &values, ..Default::default() },
                    cache: None,
                })
            });
            Arc::new(PixelPipelines { pixels, color, color_depth })
        })?;
        specialized.insert(constants, Arc::clone(&pipelines));
        Ok(pipelines)
    }

    /// How many settings of the tracer's pipeline constants have per-pixel pipelines.
    pub fn specialized_count(&self) -> usize {
        self.specialized.lock().unwrap_or_else(PoisonError::into_inner).len()
    }

    /// The raster pipeline, for [`GBufferPass::new`].
    pub fn gbuffer(&self) -> &GBufferPipeline {
        &self.gbuffer
    }
}

/// A [`GpuScene`] uploaded once: its uniforms (`ray_count` 0: the tracer's WGSL does not
/// read it, the pass covers the G-buffer) and its six storage buffers (bindings 3–8 of
/// `shaders/ddm_tracer.wgsl`). Cloning is cheap and shares the buffers.
#[derive(Clone, Debug)]
pub struct GpuSceneBuffers {
    uniforms: wgpu::Buffer,
    storage: [wgpu::Buffer; SCENE_BUFFERS],
    constants: TracePipelineConstants,
}

impl GpuSceneBuffers {
    /// Uploads `scene`. Errors name the storage buffer (binding) that exceeds the device's
    /// storage-binding or buffer-size limit, or is empty.
    pub fn new(device: &wgpu::Device, scene: &GpuScene) -> Result<Self, DdmRenderError> {
        let limits = device.limits();
        let bytes = scene.storage_bytes();
        const NAMES: [&str; SCENE_BUFFERS] = [
            "scene cone maps (binding 3)",
            "scene lookup grid (binding 4)",
            "scene atlas (binding 5)",
            "scene patch offsets (binding 6)",
            "scene patches (binding 7)",
            "scene relief heights (binding 8)",
        ];
        for (name, data) in NAMES.iter().zip(bytes) {
            if data.is_empty() {
                return Err(DdmRenderError::EmptySceneBuffer(name));
            }
            check_limit(name, data.len() as u64, limits.max_storage_buffer_binding_size.min(limits.max_buffer_size))?;
        }
        Ok(error_scoped(device, || {
            let uniforms = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("ddm-render tracer uniforms"),
                contents: bytemuck::bytes_of(&scene.uniforms(0)),
                usage: wgpu::BufferUsages::UNIFORM,
            });
            let storage = std::array::from_fn(|k| {
                let mut padded = bytes[k].to_vec();
                padded.resize(padded.len().next_multiple_of(4), 0);
                device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(NAMES[k]),
                    contents: &padded,
                    usage: wgpu::BufferUsages::STORAGE,
                })
            });
            Self { uniforms, storage, constants: scene.pipeline_constants }
        })?)
    }

    /// The pipeline constants of the scene (its renderers' pipelines are specialised for them).
    pub fn pipeline_constants(&self) -> TracePipelineConstants {
        self.constants
    }
}

/// Everything the per-pixel pass needs per frame besides the camera: the mapping of the
/// mesostructure's slab onto the base mesh, the light, shadows and the miss colour
/// (written with the camera's eye as the frame's [`BaseRenderParams`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderSettings {
    /// `(L_x, L_y, L_z / h)`: voxels per texture unit along `u` and `v`, voxels per world
    /// unit along `−N` (see `ddm_tracer::tangent_space`). Finite and positive.
    pub slab: Vec3,
    /// Direction toward the (directional) light, world space, normally unit. Finite, non-zero.
    pub light: Vec3,
    /// Ambient term in `[0, 1]`.
    pub ambient: f32,
    /// Shadow rays: how far short of the shaded point (voxels) a hit must be to shadow it
    /// (finite, ≥ 0); `None` casts no shadow ray.
    pub shadow_tolerance: Option<f32>,
    /// Colour of the base mesh where the ray misses the mesostructure (linear RGB, finite);
    /// `None` draws no base surface: such a pixel shows what lies behind, as where the ray
    /// leaves the base mesh's solid (an object standing alone on its base, like a tile
    /// built with `periodic_xy: false` holding one ball).
    pub miss_color: Option<Vec3>,
    /// The mesostructure's albedo (linear RGB, finite and ≥ 0): [`DEFAULT_ALBEDO`] is
    /// `xtask ddm-render`'s warm sand.
    pub albedo: Vec3,
    /// How much of the albedo is replaced by the shading normal's colour `0.5 n + 0.5`
    /// (in `[0, 1]`; [`DEFAULT_NORMAL_TINT`]), so that the relief reads in the images.
    pub normal_tint: f32,
}

/// The albedo of `xtask ddm-render`'s images.
pub const DEFAULT_ALBEDO: Vec3 = Vec3::new(0.85, 0.72, 0.5);
/// The normal tint of `xtask ddm-render`'s images.
pub const DEFAULT_NORMAL_TINT: f32 = 0.3;

impl RenderSettings {
    /// The frame's [`BaseRenderParams`] for a camera at `eye`. Errors name the field that
    /// is out of range.
    pub fn params(&self, eye: Vec3) -> Result<BaseRenderParams, DdmRenderError> {
        if !(self.slab.is_finite() && self.slab.min_element() > 0.0) {
            return Err(DdmRenderError::InvalidSettings("slab must be finite and positive"));
        }
        if !(self.light.is_finite() && self.light.length_squared() > 0.0) {
            return Err(DdmRenderError::InvalidSettings("light must be finite and non-zero"));
        }
        if !(0.0..=1.0).contains(&self.ambient) {
            return Err(DdmRenderError::InvalidSettings("ambient must lie in [0, 1]"));
        }
        let tolerance = match self.shadow_tolerance {
            Some(t) if t.is_finite() && t >= 0.0 => t,
            Some(_) => return Err(DdmRenderError::InvalidSettings("shadow_tolerance must be finite and ≥ 0")),
            None => -1.0,
        };
        if !self.miss_color.is_none_or(Vec3::is_finite) {
            return Err(DdmRenderError::InvalidSettings("miss_color must be finite"));
        }
        if !(self.albedo.is_finite() && self.albedo.min_element() >= 0.0) {
            return Err(DdmRenderError::InvalidSettings("albedo must be finite and ≥ 0"));
        }
        if !(0.0..=1.0).contains(&self.normal_tint) {
            return Err(DdmRenderError::InvalidSettings("normal_tint must lie in [0, 1]"));
        }
        if !eye.is_finite() {
            return Err(DdmRenderError::InvalidCamera("eye must be finite"));
        }
        Ok(BaseRenderParams {
            eye: eye.extend(0.0),
            light: self.light.extend(self.ambient),
            slab: self.slab.extend(tolerance),
            miss_color: self.miss_color.map_or(Vec4::ZERO, |c| c.extend(1.0)),
            albedo: self.albedo.extend(self.normal_tint),
        })
    }
}

/// One frame's inputs.
#[derive(Clone, Copy, Debug)]
pub struct DdmFrame<'a> {
    /// The camera; its size must be the G-buffer's.
    pub camera: &'a Camera,
    /// Slab mapping, light, shadows, miss colour.
    pub settings: RenderSettings,
    /// Where the raster pass writes its beginning and end timestamps, if anywhere.
    pub raster_timestamps: Option<PassTimestamps<'a>>,
    /// Where the per-pixel pass writes its beginning and end timestamps, if anywhere.
    pub trace_timestamps: Option<PassTimestamps<'a>>,
}

impl<'a> DdmFrame<'a> {
    /// A frame without timestamps.
    pub fn new(camera: &'a Camera, settings: RenderSettings) -> Self {
        Self { camera, settings, raster_timestamps: None, trace_timestamps: None }
    }
}

/// What a [`DdmTarget`] writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TargetKind {
    /// A storage buffer of [`BaseRenderPixel`]s.
    Pixels,
    /// A [`COLOR_TARGET_FORMAT`] storage texture.
    Color,
    /// A [`COLOR_TARGET_FORMAT`] and a [`DEPTH_TARGET_FORMAT`] storage texture, depth-tested.
    ColorDepth,
}

/// The output of the per-pixel pass: its bind group, built once by
/// [`DdmRenderer::pixel_target`] or [`DdmRenderer::color_target`] for a G-buffer size.
#[derive(Clone, Debug)]
pub struct DdmTarget {
    bind_group: wgpu::BindGroup,
    kind: TargetKind,
    width: u32,
    height: u32,
    /// The colour and depth views a [`TargetKind::ColorDepth`] target clears.
    clear_views: Option<(wgpu::TextureView, wgpu::TextureView)>,
}

impl DdmTarget {
    /// Records a render pass that clears a [`TargetKind::ColorDepth`] target's textures to
    /// zero (nothing drawn): once per frame, before the first object's
    /// [`DdmRenderer::encode`]. Errors for another kind of target.
    pub fn encode_clear(&self, encoder: &mut wgpu::CommandEncoder) -> Result<(), DdmRenderError> {
        let Some((color, depth)) = &self.clear_views else {
            return Err(DdmRenderError::InvalidTarget {
                what: "the target to clear",
                problem: "only a colour and depth target is cleared by the renderer".into(),
            });
        };
        let attachment = |view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        drop(encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("ddm-render clear colour and depth"),
            color_attachments: &[attachment(color), attachment(depth)],
            ..Default::default()
        }));
        Ok(())
    }

    /// What the target receives.
    pub fn kind(&self) -> TargetKind {
        self.kind
    }

    /// `(width, height)` in pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }
}

/// A tracer scene mapped onto a base mesh, rendered per frame into a target (see the
/// [module documentation](self)). Cloning is cheap and shares the GPU objects.
#[derive(Clone, Debug)]
pub struct DdmRenderer {
    pipelines: DdmRenderPipelines,
    pixel_pipelines: Arc<PixelPipelines>,
    gbuffer: GBufferPass,
    params: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    workgroups: (u32, u32),
}

impl DdmRenderer {
    /// The renderer of `scene` on `gbuffer`'s base mesh and size, with `pipelines` (the
    /// ones `gbuffer` was built with), compiling the per-pixel pipelines of the scene's
    /// pipeline constants if no renderer has yet. Errors name the device limit the size
    /// exceeds (workgroups per dimension) or the compilation's error.
    pub fn new(
        device: &wgpu::Device,
        pipelines: &DdmRenderPipelines,
        gbuffer: &GBufferPass,
        scene: &GpuSceneBuffers,
    ) -> Result<Self, DdmRenderError> {
        let limits = device.limits();
        let workgroups = (gbuffer.width().div_ceil(RENDER_TILE), gbuffer.height().div_ceil(RENDER_TILE));
        check_limit(
            "per-pixel workgroups per dimension (max_compute_workgroups_per_dimension)",
            workgroups.0.max(workgroups.1).into(),
            limits.max_compute_workgroups_per_dimension.into(),
        )?;
        let pixel_pipelines = pipelines.pixel_pipelines(device, scene.constants)?;
        Ok(error_scoped(device, || {
            let params = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("ddm-render parameters"),
                size: size_of::<BaseRenderParams>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let mut entries = vec![
                wgpu::BindGroupEntry { binding: TRACE_UNIFORMS_BINDING, resource: scene.uniforms.as_entire_binding() },
                wgpu::BindGroupEntry { binding: PARAMS_BINDING, resource: params.as_entire_binding() },
            ];
            entries.extend(
                scene
                    .storage
                    .iter()
                    .zip(SCENE_FIRST_BINDING..)
                    .map(|(buffer, binding)| wgpu::BindGroupEntry { binding, resource: buffer.as_entire_binding() }),
            );
            let views = gbuffer.views().iter().chain([gbuffer.exit_view()]);
            entries.extend(views.zip(GBUFFER_FIRST_BINDING..).map(|(view, binding)| wgpu::BindGroupEntry {
                binding,
                resource: wgpu::BindingResource::TextureView(view),
            }));
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("ddm-render per-pixel scene and G-buffer"),
                layout: &pipelines.scene_layout,
                entries: &entries,
            });
            Self {
                pipelines: pipelines.clone(),
                pixel_pipelines,
                gbuffer: gbuffer.clone(),
                params,
                bind_group,
                workgroups,
            }
        })?)
    }

    /// The G-buffer pass (its textures, its size).
    pub fn gbuffer(&self) -> &GBufferPass {
        &self.gbuffer
    }

    /// `(width, height)` in pixels: the G-buffer's and every target's.
    pub fn size(&self) -> (u32, u32) {
        (self.gbuffer.width(), self.gbuffer.height())
    }

    /// Bytes of the pixel target: `width × height` [`BaseRenderPixel`]s.
    pub fn pixel_bytes(&self) -> u64 {
        let (width, height) = self.size();
        u64::from(width) * u64::from(height) * size_of::<BaseRenderPixel>() as u64
    }

    /// A target writing [`BaseRenderPixel`]s into the first [`pixel_bytes`](Self::pixel_bytes)
    /// bytes of `buffer`, which needs `STORAGE` usage. Errors name what the buffer lacks or
    /// the storage-binding limit the size exceeds.
    pub fn pixel_target(&self, device: &wgpu::Device, buffer: &wgpu::Buffer) -> Result<DdmTarget, DdmRenderError> {
        let bytes = self.pixel_bytes();
        check_limit(
            "pixel target in bytes (max_storage_buffer_binding_size)",
            bytes,
            device.limits().max_storage_buffer_binding_size,
        )?;
        if !buffer.usage().contains(wgpu::BufferUsages::STORAGE) {
            return Err(DdmRenderError::InvalidTarget {
                what: "pixel target buffer",
                problem: "it lacks STORAGE usage".into(),
            });
        }
        if buffer.size() < bytes {
            return Err(DdmRenderError::InvalidTarget {
                what: "pixel target buffer",
                problem: format!(
                    "{} bytes, {bytes} needed for {}×{} pixels",
                    buffer.size(),
                    self.size().0,
                    self.size().1
                ),
            });
        }
        let size = wgpu::BufferSize::new(bytes)
            .ok_or(DdmRenderError::InvalidTarget { what: "pixel target buffer", problem: "zero bytes".into() })?;
        let bind_group = error_scoped(device, || {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("ddm-render pixel target"),
                layout: &self.pipelines.pixels_layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: PIXELS_BINDING,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer,
                        offset: 0,
                        size: Some(size),
                    }),
                }],
            })
        })?;
        let (width, height) = self.size();
        Ok(DdmTarget { bind_group, kind: TargetKind::Pixels, width, height, clear_views: None })
    }

    /// A target writing colours into mip 0 of `texture`: a 2-D, single-sampled,
    /// [`COLOR_TARGET_FORMAT`] texture of the G-buffer's size with `STORAGE_BINDING` usage.
    /// Errors name what the texture lacks.
    pub fn color_target(&self, device: &wgpu::Device, texture: &wgpu::Texture) -> Result<DdmTarget, DdmRenderError> {
        let usage = wgpu::TextureUsages::STORAGE_BINDING;
        let view = self.target_view("colour target texture", texture, COLOR_TARGET_FORMAT, usage)?;
        let bind_group = error_scoped(device, || {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("ddm-render colour target"),
                layout: &self.pipelines.color_layout,
                entries: &[wgpu::BindGroupEntry {
                    binding: COLOR_BINDING,
                    resource: wgpu::BindingResource::TextureView(&view),
                }],
            })
        })?;
        let (width, height) = self.size();
        Ok(DdmTarget { bind_group, kind: TargetKind::Color, width, height, clear_views: None })
    }

    /// A target that several renderers (of the same size, sharing one camera) draw into one
    /// after the other, each pixel keeping the nearest: colours into `color` as
    /// [`color_target`](Self::color_target) does, and per pixel the inverse world distance
    /// from the eye of what it holds into `depth` ([`DEPTH_TARGET_FORMAT`]; 0 holds
    /// nothing). A pixel is written only where the object is seen (a hit, or the base
    /// surface under the slab) nearer than what `depth` holds, so two DDM-mapped objects
    /// interpenetrate (paper: "interpenetrations"); any pass that writes the inverse eye
    /// distance into `depth` (a plain mesh's) composes the same way. Both textures need
    /// `STORAGE_BINDING | RENDER_ATTACHMENT` usage (the latter for
    /// [`DdmTarget::encode_clear`]). Errors name the texture and what it lacks.
    pub fn color_depth_target(
        &self,
        device: &wgpu::Device,
        color: &wgpu::Texture,
        depth: &wgpu::Texture,
    ) -> Result<DdmTarget, DdmRenderError> {
        let usage = wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::RENDER_ATTACHMENT;
        let color_view = self.target_view("colour target texture", color, COLOR_TARGET_FORMAT, usage)?;
        let depth_view = self.target_view("depth target texture", depth, DEPTH_TARGET_FORMAT, usage)?;
        let bind_group = error_scoped(device, || {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("ddm-render colour and depth target"),
                layout: &self.pipelines.color_depth_layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: COLOR_BINDING,
                        resource: wgpu::BindingResource::TextureView(&color_view),
                    },
                    wgpu::BindGroupEntry {
                        binding: DEPTH_BINDING,
                        resource: wgpu::BindingResource::TextureView(&depth_view),
                    },
                ],
            })
        })?;
        let (width, height) = self.size();
        Ok(DdmTarget {
            bind_group,
            kind: TargetKind::ColorDepth,
            width,
            height,
            clear_views: Some((color_view, depth_view)),
        })
    }

    /// The view of mip 0 of a target texture, after checking its format, usages, shape and
    /// size; errors name `what` and the problem.
    fn target_view(
        &self,
        what: &'static str,
        texture: &wgpu::Texture,
        format: wgpu::TextureFormat,
        usage: wgpu::TextureUsages,
    ) -> Result<wgpu::TextureView, DdmRenderError> {
        if texture.format() != format {
            return Err(DdmRenderError::InvalidTarget {
                what,
                problem: format!("format {:?}, {format:?} needed", texture.format()),
            });
        }
        if !texture.usage().contains(usage) {
            return Err(DdmRenderError::InvalidTarget { what, problem: format!("it lacks {:?} usage", usage) });
        }
        if texture.dimension() != wgpu::TextureDimension::D2
            || texture.depth_or_array_layers() != 1
            || texture.sample_count() != 1
        {
            return Err(DdmRenderError::InvalidTarget {
                what,
                problem: "it is not a single-layer, single-sampled 2-D texture".into(),
            });
        }
        if (texture.width(), texture.height()) != self.size() {
            return Err(DdmRenderError::SizeMismatch {
                what,
                expected: self.size(),
                found: (texture.width(), texture.height()),
            });
        }
        Ok(texture.create_view(&wgpu::TextureViewDescriptor {
            label: Some(what),
            dimension: Some(wgpu::TextureViewDimension::D2),
            base_mip_level: 0,
            mip_level_count: Some(1),
            ..Default::default()
        }))
    }

    /// Records one frame into `encoder`: the G-buffer raster pass for `frame.camera`, then
    /// the per-pixel pass into `target`. Writes the camera and [`BaseRenderParams`] uniforms
    /// with `queue.write_buffer` (they land at the next `queue.submit`: one frame per
    /// submission). Nothing is created or read back. Errors (before anything is written or
    /// recorded) name the camera or settings field, the target size or the timestamp set
    /// that is wrong.
    pub fn encode(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        frame: &DdmFrame<'_>,
        target: &DdmTarget,
    ) -> Result<(), DdmRenderError> {
        if target.size() != self.size() {
            return Err(DdmRenderError::SizeMismatch {
                what: "the target",
                expected: self.size(),
                found: target.size(),
            });
        }
        let params = frame.settings.params(frame.camera.eye)?;
        self.gbuffer.camera_uniforms(frame.camera)?;
        if let Some(t) = &frame.trace_timestamps {
            t.check()?;
        }
        self.gbuffer.encode(queue, encoder, frame.camera, frame.raster_timestamps)?;
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
        let pipeline = match target.kind {
            TargetKind::Pixels => &self.pixel_pipelines.pixels,
            TargetKind::Color => &self.pixel_pipelines.color,
            TargetKind::ColorDepth => &self.pixel_pipelines.color_depth,
        };
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("ddm-render per-pixel trace"),
            timestamp_writes: frame.trace_timestamps.as_ref().map(PassTimestamps::compute_writes),
        });
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &self.bind_group, &[]);
        pass.set_bind_group(1, &target.bind_group, &[]);
        pass.dispatch_workgroups(self.workgroups.0, self.workgroups.1, 1);
        Ok(())
    }
}

#[cfg(test)]
mod tests;
