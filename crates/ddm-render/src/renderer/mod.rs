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
//! | [`DdmRenderPipelines`] | once per device | the raster pipelines, the per-pixel shader module, the bind group layouts; the per-pixel pipelines of each [`TracePipelineConstants`](ddm_tracer::TracePipelineConstants) met, created by the first [`DdmRenderer`] that needs them and shared after |
//! | [`GBufferPass`] | once per base mesh and size | the mesh's vertex and index buffers, the G-buffer textures, the camera uniform |
//! | [`GpuSceneBuffers`] | once per tracer scene | the [`GpuScene`](ddm_tracer::GpuScene)'s uniforms and six storage buffers, its pipeline constants |
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

mod frame;
mod pipelines;
pub(crate) use pipelines::{buffer_type, compute_entry};
mod scene_buffers;
mod target;

use std::sync::Arc;

use ddm_tracer::tangent_space::{BaseRenderParams, BaseRenderPixel};
use gpu_harness::error_scoped;

pub use frame::{DEFAULT_ALBEDO, DEFAULT_NORMAL_TINT, DdmFrame, RenderSettings};
pub use pipelines::DdmRenderPipelines;
use pipelines::{
    COLOR_BINDING, DEPTH_BINDING, GBUFFER_FIRST_BINDING, PARAMS_BINDING, PIXELS_BINDING, PixelPipelines,
    SCENE_FIRST_BINDING, TRACE_UNIFORMS_BINDING,
};
pub use scene_buffers::GpuSceneBuffers;
pub use target::{DdmTarget, TargetKind};

use crate::error::{DdmRenderError, check_limit};
use crate::gbuffer::{GBufferPass, PassTimestamps};
use crate::shaders::RENDER_TILE;

/// The format of [`DdmRenderer::color_target`]'s texture.
pub const COLOR_TARGET_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
/// The format of [`DdmRenderer::color_depth_target`]'s depth texture: per pixel the inverse
/// world distance from the eye of what the colour texture holds (larger is nearer, 0 holds
/// nothing).
pub const DEPTH_TARGET_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Float;

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
