//! The per-pixel compute pass: `shaders/kernels/ddm_render_compute.wgsl` composed with the
//! registered `ddm_render` module (which brings the `ddm_tracer` module and its
//! dependencies), run over the G-buffer with the tracer's scene bound at 3–8 and the
//! [`BaseRenderParams`] at 9.

use ddm_tracer::GpuScene;
use ddm_tracer::tangent_space::{BaseRenderParams, BaseRenderPixel, PIXEL_HIT, PIXEL_MISS};
use gpu_harness::{Gpu, GpuTiming, HarnessError};

use crate::gbuffer::GBuffer;

/// The composed WGSL source of the per-pixel pass.
pub fn pixel_pass_source() -> Result<String, HarnessError> {
    let shader = wgsl_gen::ComposedShader::of_module(&ddm_tracer::WGSL).with_part(
        "shaders/kernels/ddm_render_compute.wgsl",
        include_str!("../../../shaders/kernels/ddm_render_compute.wgsl"),
    );
    Ok(shader.source().to_owned())
}

/// The result of [`render_pixels`].
#[derive(Clone, Debug)]
pub struct PixelPass {
    /// One shaded pixel per G-buffer texel.
    pub pixels: Vec<BaseRenderPixel>,
    /// The compute pass's time (GPU timestamps where the adapter has them).
    pub timing: GpuTiming,
}

/// Traces and shades every texel of `gbuffer` through `scene` (whose method, maps and
/// patches decide the tracer) with `params`.
pub fn render_pixels(
    gpu: &Gpu,
    gbuffer: &GBuffer,
    scene: &GpuScene,
    params: &BaseRenderParams,
) -> Result<PixelPass, HarnessError> {
    let source = pixel_pass_source()?;
    let uniforms = scene.uniforms(gbuffer.texels.len() as u32);
    let [a, b, c, d, e, f] = scene.storage_bytes();
    let storage: [&[u8]; 7] = [a, b, c, d, e, f, bytemuck::bytes_of(params)];
    let (pixels, timing) = gpu.compute_map_with_storage(
        &source,
        "render_pixels",
        bytemuck::bytes_of(&uniforms),
        &gbuffer.texels,
        &storage,
    )?;
    Ok(PixelPass { pixels, timing })
}

/// The shaded pixels as an sRGB-ish 8-bit image (`background` where the base mesh does
/// not cover the pixel).
pub fn pixels_to_image(pixels: &[BaseRenderPixel], width: u32, height: u32, background: [u8; 3]) -> image::RgbImage {
    let mut image = image::RgbImage::from_pixel(width, height, image::Rgb(background));
    for (out, pixel) in image.pixels_mut().zip(pixels) {
        if pixel.color.w == PIXEL_HIT || pixel.color.w == PIXEL_MISS {
            let c = pixel.color.truncate().clamp(glam::Vec3::ZERO, glam::Vec3::ONE).powf(1.0 / 2.2) * 255.0;
            *out = image::Rgb([c.x as u8, c.y as u8, c.z as u8]);
        }
    }
    image
}
