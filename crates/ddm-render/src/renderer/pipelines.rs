//! The per-device objects of both passes: the raster pipelines, the per-pixel pass's
//! module, bind group layouts and its pipelines per setting of the tracer's pipeline
//! constants.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, PoisonError};

use ddm_tracer::TracePipelineConstants;
use gpu_harness::error_scoped;

use super::{COLOR_TARGET_FORMAT, DEPTH_TARGET_FORMAT};
use crate::error::{DdmRenderError, check_limit};
use crate::gbuffer::{GBUFFER_TEXTURES, GBufferPipeline};
use crate::shaders::{PIXEL_SHADER, RENDER_TILE, pixel_shader};

/// Binding of the tracer's uniforms in group 0.
pub(super) const TRACE_UNIFORMS_BINDING: u32 = 0;
/// First binding of the tracer's scene buffers in group 0 (`shaders/ddm_tracer.wgsl`).
pub(super) const SCENE_FIRST_BINDING: u32 = 3;
/// Number of scene storage buffers ([`GpuScene::storage_bytes`]).
pub(super) const SCENE_BUFFERS: usize = 6;
/// Binding of the [`BaseRenderParams`] uniform in group 0.
pub(super) const PARAMS_BINDING: u32 = 9;
/// First binding of the G-buffer textures in group 0 (then the exit distance).
pub(super) const GBUFFER_FIRST_BINDING: u32 = 10;
/// Binding of the pixel buffer in group 1.
pub(super) const PIXELS_BINDING: u32 = 0;
/// Binding of the colour texture in group 1.
pub(super) const COLOR_BINDING: u32 = 1;
/// Binding of the depth texture in group 1.
pub(super) const DEPTH_BINDING: u32 = 2;
/// The per-pixel pass's entry points, one per target kind: pixels, colour, colour and depth.
pub(super) const PIXEL_ENTRY_POINTS: [&str; 3] = ["render_pixels", "render_color", "render_color_depth"];

/// A compute-stage bind group layout entry of binding `binding`.
pub(crate) fn compute_entry(binding: u32, ty: wgpu::BindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry { binding, visibility: wgpu::ShaderStages::COMPUTE, ty, count: None }
}

/// A buffer binding of type `ty` (no dynamic offset, no minimum size).
pub(crate) fn buffer_type(ty: wgpu::BufferBindingType) -> wgpu::BindingType {
    wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None }
}

/// The per-pixel pass's three pipelines (one per target kind) for one setting of the
/// tracer's pipeline constants.
#[derive(Debug)]
pub(super) struct PixelPipelines {
    pub(super) pixels: wgpu::ComputePipeline,
    pub(super) color: wgpu::ComputePipeline,
    pub(super) color_depth: wgpu::ComputePipeline,
}

/// The compiled pipelines of both passes and their bind group layouts, created once per
/// device and shared by every [`GBufferPass`](crate::GBufferPass) and [`DdmRenderer`](crate::DdmRenderer) built from them: the
/// raster pipelines at once, the per-pixel ones for each setting of the tracer's pipeline
/// constants when a [`DdmRenderer`](crate::DdmRenderer) first needs it. Cloning is cheap and shares the GPU
/// objects (and the per-pixel pipelines compiled so far).
#[derive(Clone, Debug)]
pub struct DdmRenderPipelines {
    gbuffer: GBufferPipeline,
    pub(super) scene_layout: wgpu::BindGroupLayout,
    pub(super) pixels_layout: wgpu::BindGroupLayout,
    pub(super) color_layout: wgpu::BindGroupLayout,
    pub(super) color_depth_layout: wgpu::BindGroupLayout,
    module: wgpu::ShaderModule,
    layouts: [wgpu::PipelineLayout; 3],
    specialized: Arc<Mutex<HashMap<TracePipelineConstants, Arc<PixelPipelines>>>>,
}

impl DdmRenderPipelines {
    /// Validates both composed shaders with naga and builds the raster pipelines and the
    /// per-pixel pass's module and layouts (its pipelines come with the first
    /// [`DdmRenderer`](crate::DdmRenderer) of each setting). Errors name the
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
    pub(super) fn pixel_pipelines(
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

    /// The raster pipeline, for [`GBufferPass::new`](crate::GBufferPass::new).
    pub fn gbuffer(&self) -> &GBufferPipeline {
        &self.gbuffer
    }
}
