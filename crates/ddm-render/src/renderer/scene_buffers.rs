//! A tracer scene uploaded once for the per-pixel pass.

use ddm_tracer::{GpuScene, TracePipelineConstants};
use gpu_harness::error_scoped;
use wgpu::util::DeviceExt;

use super::pipelines::SCENE_BUFFERS;
use crate::error::{DdmRenderError, check_limit};

/// A [`GpuScene`] uploaded once: its uniforms (`ray_count` 0: the tracer's WGSL does not
/// read it, the pass covers the G-buffer) and its six storage buffers (bindings 3–8 of
/// `shaders/ddm_tracer.wgsl`). Cloning is cheap and shares the buffers.
#[derive(Clone, Debug)]
pub struct GpuSceneBuffers {
    pub(super) uniforms: wgpu::Buffer,
    pub(super) storage: [wgpu::Buffer; SCENE_BUFFERS],
    pub(super) constants: TracePipelineConstants,
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
