//! The ground truth of the multiscale renderer: every grain as its mesh, `4 × 4`
//! supersampled (`grain_impostor::accuracy::REFERENCE_SUPERSAMPLING`, the sampling the
//! measured impostor table was made with), shaded by the same deferred pass.

use grain_impostor::accuracy::REFERENCE_SUPERSAMPLING;
use grain_impostor::mesh_gbuffer::{GbufferImage, GpuMesh, MeshGbufferPass, ScreenGbuffer};
use grain_impostor::scene::{GrainInstance, ShadingUniforms};
use grain_impostor::shading::ShadingPass;

use crate::error::RenderError;
use crate::renderer::StackingCamera;

/// The mesh reference of one scene, built once.
pub struct MeshReference {
    pass: MeshGbufferPass,
    shading: ShadingPass,
    mesh: GpuMesh,
    placed: Vec<GrainInstance>,
    size: (u32, u32),
}

fn error(e: &dyn std::fmt::Display) -> RenderError {
    RenderError::InvalidInput(e.to_string())
}

impl MeshReference {
    /// Uploads `mesh` and places `grains` (each grain's centre replaces the mesh's bounds
    /// centre, as the renderer's tiers do) for `size`-pixel renders.
    pub fn new(
        device: &wgpu::Device,
        mesh: &grain_mesh::GrainMesh,
        grains: &[GrainInstance],
        size: (u32, u32),
    ) -> Result<Self, RenderError> {
        let centre = mesh.bounds().centre;
        let placed = grains
            .iter()
            .map(|g| {
                let rotation = glam::Quat::from_vec4(g.rotation);
                GrainInstance::new(
                    g.centre_scale.truncate() - rotation * (g.centre_scale.w * centre),
                    g.centre_scale.w,
                    rotation,
                )
            })
            .collect();
        Ok(Self {
            pass: MeshGbufferPass::new(device).map_err(|e| error(&e))?,
            shading: ShadingPass::new(device).map_err(|e| error(&e))?,
            mesh: GpuMesh::upload(device, mesh).map_err(|e| error(&e))?,
            placed,
            size,
        })
    }

    /// The shaded reference image from `camera` lit by `lighting`, and its G-buffer (the
    /// covered fraction of each pixel in `normal_coverage.w`).
    pub fn render(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        camera: &StackingCamera,
        lighting: &ShadingUniforms,
    ) -> Result<(image::RgbaImage, GbufferImage), RenderError> {
        let gbuffer = ScreenGbuffer::new(device, self.size).map_err(|e| error(&e))?;
        self.pass
            .render(device, queue, &self.mesh, &camera.uniforms, &self.placed, REFERENCE_SUPERSAMPLING, &gbuffer)
            .map_err(|e| error(&e))?;
        let target = self.shading.create_target(device, &gbuffer).map_err(|e| error(&e))?;
        self.shading.shade(device, queue, &camera.uniforms, lighting, &gbuffer, &target).map_err(|e| error(&e))?;
        let image = grain_impostor::shading::read_image(device, queue, &target).map_err(|e| error(&e))?;
        Ok((image, gbuffer.read(device, queue).map_err(|e| error(&e))?))
    }
}
