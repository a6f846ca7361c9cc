//! Offscreen rendering into an `RgbaImage`.

use crate::{Gpu, HarnessError};

/// The format of [`Gpu::render_to_image`]'s target.
pub const RENDER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

impl Gpu {
    /// Draws `vertex_count` vertices (a triangle list without vertex buffers: the vertex
    /// shader derives positions from `@builtin(vertex_index)`) with `vertex_entry` and
    /// `fragment_entry` of `wgsl` into a cleared `width × height` RGBA8 target, and reads
    /// it back.
    ///
    /// Sizes of zero or above the adapter's 2-D texture limit are errors.
    pub fn render_to_image(
        &self,
        wgsl: &str,
        vertex_entry: &str,
        fragment_entry: &str,
        (width, height): (u32, u32),
        vertex_count: u32,
    ) -> Result<image::RgbaImage, HarnessError> {
        let limit = self.limits().max_texture_dimension_2d;
        if width == 0 || height == 0 {
            return Err(HarnessError::InvalidRequest(format!("render target {width}×{height} is empty")));
        }
        if width.max(height) > limit {
            return Err(HarnessError::TooLarge {
                what: "render target side in texels".into(),
                requested: u64::from(width.max(height)),
                limit: u64::from(limit),
            });
        }
        let target = self.scoped(|| {
            let module = self.device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("gpu-harness render"),
                source: wgpu::ShaderSource::Wgsl(wgsl.into()),
            });
            let pipeline = self.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some("gpu-harness render"),
                layout: None,
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some(vertex_entry),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: None,
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(fragment_entry),
                    compilation_options: Default::default(),
                    targets: &[Some(RENDER_FORMAT.into())],
                }),
                multiview_mask: None,
                cache: None,
            });
            let extent = wgpu::Extent3d { width, height, depth_or_array_layers: 1 };
            let target = self.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("gpu-harness render target"),
                size: extent,
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: RENDER_FORMAT,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            });
            let view = target.create_view(&Default::default());
            let mut encoder = self.device.create_command_encoder(&Default::default());
            {
                let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("gpu-harness render"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: &view,
                        depth_slice: None,
                        resolve_target: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                            store: wgpu::StoreOp::Store,
                        },
                    })],
                    ..Default::default()
                });
                pass.set_pipeline(&pipeline);
                pass.draw(0..vertex_count, 0..1);
            }
            self.queue.submit([encoder.finish()]);
            target
        })?;
        self.read_rgba8_texture(&target)
    }

    /// Reads a 2-D RGBA8 texture (`Rgba8Unorm` or `Rgba8UnormSrgb`, with `COPY_SRC` usage)
    /// back as an image. Waits for all submitted work.
    pub fn read_rgba8_texture(&self, texture: &wgpu::Texture) -> Result<image::RgbaImage, HarnessError> {
        let format = texture.format();
        if !matches!(format, wgpu::TextureFormat::Rgba8Unorm | wgpu::TextureFormat::Rgba8UnormSrgb) {
            return Err(HarnessError::InvalidRequest(format!("reading a {format:?} texture as RGBA8")));
        }
        let (width, height) = (texture.width(), texture.height());
        let row_bytes = width * 4;
        let padded_row_bytes = row_bytes.next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        let readback_size = u64::from(padded_row_bytes) * u64::from(height);
        let readback = self.scoped(|| {
            let readback = self.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("gpu-harness texture readback"),
                size: readback_size,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let mut encoder = self.device.create_command_encoder(&Default::default());
            encoder.copy_texture_to_buffer(
                texture.as_image_copy(),
                wgpu::TexelCopyBufferInfo {
                    buffer: &readback,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(padded_row_bytes),
                        rows_per_image: Some(height),
                    },
                },
                wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
            );
            self.queue.submit([encoder.finish()]);
            readback
        })?;
        let padded = self.map_and_read(&readback)?;
        let mut pixels = Vec::with_capacity((row_bytes * height) as usize);
        for row in padded.chunks_exact(padded_row_bytes as usize) {
            pixels.extend_from_slice(&row[..row_bytes as usize]);
        }
        image::RgbaImage::from_raw(width, height, pixels)
            .ok_or_else(|| HarnessError::Readback("texture readback has the wrong size".into()))
    }
}
