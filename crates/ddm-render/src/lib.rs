//! Mesostructures mapped onto a base mesh and rendered with the DDM tracer, as Mehra &
//! Kumar do (§3): only the coarse base mesh is rasterized, into a G-buffer holding per
//! pixel the texture coordinates, the interpolated tangent frame `(∂P/∂u, ∂P/∂v, N)` and
//! the world position ([`gbuffer`]); a compute pass then reads those textures on the GPU,
//! builds each covered pixel's ray in the mesostructure's tangent space, traces it through
//! the distance maps with the WGSL tracer of `ddm-tracer`, and shades the hit with a
//! shadow ray toward the light ([`renderer`]). The mapping and its approximation are
//! documented in [`ddm_tracer::tangent_space`], the CPU reference of the compute pass's ray.
//!
//! A std crate of its own because it needs wgpu, which `ddm-tracer` (`no_std`) must not
//! depend on, and because both `xtask ddm-render` and the GPU tests use it.
//!
//! # Embedding
//!
//! Built once from a `wgpu::Device`, then encoded per frame into the caller's encoder:
//!
//! ```no_run
//! # fn frame(device: &wgpu::Device, queue: &wgpu::Queue, mesh: &mesostructure::BaseMesh,
//! #          scene: &ddm_tracer::GpuScene, camera: &ddm_render::Camera,
//! #          settings: ddm_render::RenderSettings, output: &wgpu::Texture)
//! #          -> Result<(), ddm_render::DdmRenderError> {
//! use ddm_render::{DdmFrame, DdmRenderPipelines, DdmRenderer, GBufferPass, GpuSceneBuffers};
//! let pipelines = DdmRenderPipelines::new(device)?; // once per device
//! let gbuffer = GBufferPass::new(device, pipelines.gbuffer(), mesh, camera.width, camera.height)?;
//! let scene = GpuSceneBuffers::new(device, scene)?; // uploaded once
//! let renderer = DdmRenderer::new(device, &pipelines, &gbuffer, &scene)?;
//! let target = renderer.color_target(device, output)?; // an Rgba16Float storage texture
//! // Per frame (one frame per submission):
//! let mut encoder = device.create_command_encoder(&Default::default());
//! renderer.encode(queue, &mut encoder, &DdmFrame::new(camera, settings), &target)?;
//! queue.submit([encoder.finish()]);
//! # Ok(()) }
//! ```
//!
//! # Modules
//!
//! - [`base_mesh`]: the plane tile base mesh and the per-vertex scaled frames.
//! - [`camera`]: the perspective camera shared by the raster pass and the CPU rays.
//! - [`gbuffer`]: the raster pass ([`GBufferPipeline`], [`GBufferPass`]) and G-buffer readback.
//! - [`renderer`]: the pipelines, the uploaded scene, the renderer and its targets.
//! - [`readback`]: frames read back for tests and tools, and as images.
//! - [`plain_map_build`]: the plain distance map built on the GPU in compute
//!   ([`PlainMapPipeline`], [`PlainMapBuild`]).
//! - [`shaders`]: the composed WGSL of both passes (`crates/ddm-render/shaders/`).
//! - [`timing`]: frames timed by timestamps or wall clock (`cargo xtask bench-gpu ddm`).
//! - [`error`]: the error type, [`DdmRenderError`].

pub mod base_mesh;
pub mod camera;
pub mod error;
pub mod gbuffer;
pub mod plain_map_build;
pub mod readback;
pub mod renderer;
pub mod shaders;
pub mod timing;

/// The wgpu whose types this crate's API takes and returns, re-exported so that callers
/// name the same version.
pub use wgpu;

pub use base_mesh::{BaseVertex, plane_base_mesh, scaled_vertices};
pub use camera::{BaseCamera, Camera};
pub use error::DdmRenderError;
pub use gbuffer::{
    GBUFFER_FORMAT, GBUFFER_TEXTURES, GBuffer, GBufferPass, GBufferPipeline, PassTimestamps, rasterize_gbuffer,
    read_gbuffer, read_texture,
};
pub use plain_map_build::{PLAIN_BUILD_COLUMN, PLAIN_BUILD_TILE, PlainMapBuild, PlainMapPipeline, build_plain_map};
pub use readback::{PixelReadback, pixels_to_image, render_to_pixels};
pub use renderer::{
    COLOR_TARGET_FORMAT, DEFAULT_ALBEDO, DEFAULT_NORMAL_TINT, DEPTH_TARGET_FORMAT, DdmFrame, DdmRenderPipelines,
    DdmRenderer, DdmTarget, GpuSceneBuffers, RenderSettings, TargetKind,
};
pub use timing::{RendererTimes, time_frames};
