//! Reading frames back, for tests and tools: built on [`DdmRenderer`], after the frame
//! (never inside [`DdmRenderer::encode`]).
//!
//! - [`PixelReadback`]: a pixel target buffer made once, read back after any frame.
//! - [`render_to_pixels`]: one frame rendered and read back, in one call.
//! - [`pixels_to_image`]: read-back pixels as an 8-bit image.

use ddm_tracer::tangent_space::{BaseRenderPixel, PIXEL_HIT, PIXEL_MISS};
use gpu_harness::Gpu;

use crate::error::DdmRenderError;
use crate::renderer::{DdmFrame, DdmRenderer, DdmTarget};

/// A storage buffer of [`BaseRenderPixel`]s (`STORAGE | COPY_SRC`) and its target, made
/// once for a renderer's size and read back after each frame that wrote it.
#[derive(Debug)]
pub struct PixelReadback {
    buffer: wgpu::Buffer,
    target: DdmTarget,
    bytes: u64,
}

impl PixelReadback {
    /// The buffer and target for `renderer` (and any renderer of the same size built from
    /// the same pipelines). Errors name the device limit the size exceeds.
    pub fn new(gpu: &Gpu, renderer: &DdmRenderer) -> Result<Self, DdmRenderError> {
        let bytes = renderer.pixel_bytes();
        crate::error::check_limit("pixel target in bytes (max_buffer_size)", bytes, gpu.limits().max_buffer_size)?;
        let buffer = gpu.scoped(|| {
            gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("ddm-render pixel readback target"),
                size: bytes,
                usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        })?;
        let target = renderer.pixel_target(&gpu.device, &buffer)?;
        Ok(Self { buffer, target, bytes })
    }

    /// The target to pass to [`DdmRenderer::encode`].
    pub fn target(&self) -> &DdmTarget {
        &self.target
    }

    /// The pixels the last submitted frame wrote (waits for the GPU), row-major, row 0 on
    /// top.
    pub fn read(&self, gpu: &Gpu) -> Result<Vec<BaseRenderPixel>, DdmRenderError> {
        Ok(bytemuck::pod_collect_to_vec(&gpu.read_buffer(&self.buffer, self.bytes)?))
    }
}

/// Renders `frame` with `renderer` into a new [`PixelReadback`], submits it and reads the
/// pixels back. For many frames, keep one [`PixelReadback`] and call
/// [`DdmRenderer::encode`] per frame instead.
pub fn render_to_pixels(
    gpu: &Gpu,
    renderer: &DdmRenderer,
    frame: &DdmFrame<'_>,
) -> Result<Vec<BaseRenderPixel>, DdmRenderError> {
    let readback = PixelReadback::new(gpu, renderer)?;
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    renderer.encode(&gpu.queue, &mut encoder, frame, readback.target())?;
    gpu.scoped(|| gpu.queue.submit([encoder.finish()]))?;
    readback.read(gpu)
}

/// The shaded pixels as an sRGB-ish 8-bit image (`background` where the base mesh does
/// not cover the pixel). Pixels beyond `width × height` are ignored; missing ones stay
/// `background`.
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
