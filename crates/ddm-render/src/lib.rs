//! Mesostructures mapped onto a base mesh and rendered with the DDM tracer, as Mehra &
//! Kumar do (§3): only the coarse base mesh is rasterized, into a G-buffer holding per
//! pixel the texture coordinates, the interpolated tangent frame `(∂P/∂u, ∂P/∂v, N)` and
//! the world position ([`gbuffer`]); a compute pass then builds each covered pixel's ray
//! in the mesostructure's tangent space, traces it through the distance maps with the
//! WGSL tracer of `ddm-tracer`, and shades the hit with a shadow ray toward the light
//! ([`pixel_pass`]). The mapping and its approximation are documented in
//! [`ddm_tracer::tangent_space`], the CPU reference of the compute pass's ray.
//!
//! A std crate of its own because it needs wgpu, which `ddm-tracer` (`no_std`) must not
//! depend on, and because both `xtask ddm-render` and the GPU tests use it.
//!
//! # Modules
//!
//! - [`base_mesh`]: the plane tile base mesh and the per-vertex scaled frames.
//! - [`camera`]: the perspective camera shared by the raster pass and the CPU rays.
//! - [`gbuffer`]: the raster pass.
//! - [`pixel_pass`]: the per-pixel trace and shading in compute.

pub mod base_mesh;
pub mod camera;
pub mod gbuffer;
pub mod pixel_pass;

pub use base_mesh::{BaseVertex, plane_base_mesh, scaled_vertices};
pub use camera::{BaseCamera, Camera};
pub use gbuffer::{GBuffer, rasterize_gbuffer};
pub use pixel_pass::{PixelPass, pixels_to_image, render_pixels};
