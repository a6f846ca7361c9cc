//! The two shaders of this crate, composed from its own WGSL (`crates/ddm-render/shaders/`)
//! and declarations generated from Rust at run time:
//!
//! - [`raster_shader`]: the G-buffer raster pass, `shaders/gbuffer_raster.wgsl` after the
//!   declarations of [`BaseCamera`] and [`BaseVertex`];
//! - [`pixel_shader`]: the per-pixel pass, `shaders/ddm_render_pixels.wgsl` after the
//!   tracer's library (the `ddm_render` module of `shader-registry`, taken in one private
//!   function, `tracer_library`) and the declaration of [`RENDER_TILE`].

use ddm_tracer::TraceUniforms;
use ddm_tracer::tangent_space::{BaseGBufferTexel, BaseRenderParams, BaseRenderPixel};
use gpu_layout::{GpuConst, gpu_const};
use wgsl_gen::{ComposedShader, StructDecl, generate_declarations};

use crate::base_mesh::BaseVertex;
use crate::camera::BaseCamera;
use crate::error::DdmRenderError;

/// Side of the per-pixel pass's square workgroups, in pixels (`@workgroup_size(RENDER_TILE,
/// RENDER_TILE)`; the WGSL constant is generated from this one).
pub const RENDER_TILE: u32 = 8;

/// Path of the raster pass's hand-written WGSL, relative to the workspace root.
pub const RASTER_WGSL_PATH: &str = "crates/ddm-render/shaders/gbuffer_raster.wgsl";
/// The raster pass's hand-written WGSL.
pub const RASTER_WGSL: &str = include_str!("../shaders/gbuffer_raster.wgsl");
/// Path of the per-pixel pass's kernel, relative to the workspace root.
pub const PIXELS_WGSL_PATH: &str = "crates/ddm-render/shaders/ddm_render_pixels.wgsl";
/// The per-pixel pass's kernel (entry points `render_pixels` and `render_color`).
pub const PIXELS_WGSL: &str = include_str!("../shaders/ddm_render_pixels.wgsl");

/// Name of the composed raster shader (in errors).
pub(crate) const RASTER_SHADER: &str = "ddm_render_raster";
/// Name of the composed per-pixel shader (in errors).
pub(crate) const PIXEL_SHADER: &str = "ddm_render_pixels";

/// The constants of the per-pixel pass that its WGSL declares from Rust.
const PIXEL_CONSTANTS: &[GpuConst] = &[gpu_const!(RENDER_TILE: u32)];

/// How far behind the first surface (a fraction of its distance from the eye) a fragment
/// of the second raster pass must lie to count as the surface where the ray leaves the
/// base mesh's solid: the first surface drawn again interpolates the same distance, and
/// 10⁻⁵ (about 80 `f32` ulps) keeps rounding from passing it off as a second surface.
pub const PEEL_MARGIN: f32 = 1e-5;

/// The constants of the raster passes that their WGSL declares from Rust.
const RASTER_CONSTANTS: &[GpuConst] = &[gpu_const!(PEEL_MARGIN: f32 as "RASTER_PEEL_MARGIN")];

/// The Rust structs whose generated declarations the raster shader composes with.
pub fn raster_structs() -> Vec<StructDecl> {
    vec![StructDecl::of::<BaseCamera>(), StructDecl::of::<BaseVertex>()]
}

/// The Rust structs that the per-pixel shader binds or builds, all declared by the
/// tracer's library (checked against the composed shader by this crate's tests).
pub fn pixel_structs() -> Vec<StructDecl> {
    vec![
        StructDecl::of::<TraceUniforms>(),
        StructDecl::of::<BaseGBufferTexel>(),
        StructDecl::of::<BaseRenderParams>(),
        StructDecl::of::<BaseRenderPixel>(),
    ]
}

/// The composed raster shader (both passes): generated declarations, then [`RASTER_WGSL`].
pub fn raster_shader() -> Result<ComposedShader, DdmRenderError> {
    let declarations = generate_declarations(RASTER_SHADER, &raster_structs(), RASTER_CONSTANTS)
        .map_err(|e| DdmRenderError::InvalidShader { shader: RASTER_SHADER, message: e.to_string() })?;
    Ok(ComposedShader::new(RASTER_SHADER)
        .with_part("generated: BaseCamera, BaseVertex, RASTER_PEEL_MARGIN", &declarations)
        .with_part(RASTER_WGSL_PATH, RASTER_WGSL))
}

/// The composed per-pixel shader: the tracer's library, the generated [`RENDER_TILE`],
/// then [`PIXELS_WGSL`].
pub fn pixel_shader() -> Result<ComposedShader, DdmRenderError> {
    let constants = generate_declarations(PIXEL_SHADER, &[], PIXEL_CONSTANTS)
        .map_err(|e| DdmRenderError::InvalidShader { shader: PIXEL_SHADER, message: e.to_string() })?;
    Ok(tracer_library()?.with_part("generated: RENDER_TILE", &constants).with_part(PIXELS_WGSL_PATH, PIXELS_WGSL))
}

/// The WGSL library that the per-pixel kernel calls: `ddm-tracer`'s WGSL twin
/// ([`ddm_tracer::WGSL`]: the tracer and the tangent-space functions, after the
/// `quadric_fit` and `ddm_compress` twins it calls).
fn tracer_library() -> Result<ComposedShader, DdmRenderError> {
    Ok(ComposedShader::of_module(&ddm_tracer::WGSL))
}

#[cfg(test)]
mod tests {
    use super::*;
    use wgsl_gen::check_layout;

    #[test]
    fn raster_shader_validates_and_matches_the_rust_layouts() {
        let validated = raster_shader().unwrap().validate().unwrap_or_else(|e| panic!("{e}"));
        check_layout(&validated.module, &raster_structs()).unwrap_or_else(|e| panic!("{e:?}"));
        let entries: Vec<&str> = validated.module.entry_points.iter().map(|e| e.name.as_str()).collect();
        assert_eq!(entries, ["base_vertex", "base_fragment", "exit_fragment"]);
    }

    #[test]
    fn pixel_shader_validates_and_matches_the_rust_layouts() {
        let validated = pixel_shader().unwrap().validate().unwrap_or_else(|e| panic!("{e}"));
        check_layout(&validated.module, &pixel_structs()).unwrap_or_else(|e| panic!("{e:?}"));
        for entry in ["render_pixels", "render_color"] {
            let point = validated.module.entry_points.iter().find(|e| e.name == entry);
            let point = point.unwrap_or_else(|| panic!("no entry point {entry}"));
            assert_eq!(point.workgroup_size, [RENDER_TILE, RENDER_TILE, 1], "{entry}");
        }
    }
}
