//! An [`ImpostorAtlas`] on the GPU: one `D2Array` texture per entry of
//! [`ATLAS_LAYERS`] (`N` layers, the full mip chain), and a trilinear sampler. The
//! impostor cloud pass binds [`AtlasTextures::views`] and [`AtlasTextures::sampler`].

use crate::atlas::ImpostorAtlas;
use crate::gpu_util::{GpuError, check_texture_size, scoped};
use crate::scene::ATLAS_LAYERS;

/// The wgpu formats of [`ATLAS_LAYERS`], in order.
pub const ATLAS_FORMATS: [wgpu::TextureFormat; 4] = [
    wgpu::TextureFormat::Rgba8Unorm,
    wgpu::TextureFormat::Rgba8UnormSrgb,
    wgpu::TextureFormat::Rgba8Unorm,
    wgpu::TextureFormat::Rg16Float,
];

/// An uploaded atlas.
#[derive(Debug)]
pub struct AtlasTextures {
    /// One texture per entry of [`ATLAS_LAYERS`]: `p × p × N`, all mip levels.
    pub textures: [wgpu::Texture; 4],
    /// `D2Array` views of all layers and levels, in [`ATLAS_LAYERS`] order.
    pub views: [wgpu::TextureView; 4],
    /// Trilinear filtering (linear within and between mips), clamped to the edges.
    pub sampler: wgpu::Sampler,
}

impl AtlasTextures {
    /// Uploads every level of `atlas`.
    pub fn upload(device: &wgpu::Device, queue: &wgpu::Queue, atlas: &ImpostorAtlas) -> Result<Self, GpuError> {
        let layers = atlas.layer_count();
        check_texture_size(device, "impostor atlas", (atlas.texels, atlas.texels, layers))?;
        let mip_level_count = atlas.levels.len() as u32;
        scoped(device, || {
            let textures = [0, 1, 2, 3].map(|i| {
                let texture = device.create_texture(&wgpu::TextureDescriptor {
                    label: Some(ATLAS_LAYERS[i].name),
                    size: wgpu::Extent3d { width: atlas.texels, height: atlas.texels, depth_or_array_layers: layers },
                    mip_level_count,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format: ATLAS_FORMATS[i],
                    usage: wgpu::TextureUsages::TEXTURE_BINDING
                        | wgpu::TextureUsages::COPY_DST
                        | wgpu::TextureUsages::COPY_SRC,
                    view_formats: &[],
                });
                for (level, data) in atlas.levels.iter().enumerate() {
                    queue.write_texture(
                        wgpu::TexelCopyTextureInfo {
                            texture: &texture,
                            mip_level: level as u32,
                            origin: wgpu::Origin3d::ZERO,
                            aspect: wgpu::TextureAspect::All,
                        },
                        &data.layers[i],
                        wgpu::TexelCopyBufferLayout {
                            offset: 0,
                            bytes_per_row: Some(data.side * ATLAS_LAYERS[i].bytes_per_texel),
                            rows_per_image: Some(data.side),
                        },
                        wgpu::Extent3d { width: data.side, height: data.side, depth_or_array_layers: layers },
                    );
                }
                texture
            });
            let views = textures.each_ref().map(|texture| {
                texture.create_view(&wgpu::TextureViewDescriptor {
                    dimension: Some(wgpu::TextureViewDimension::D2Array),
                    ..Default::default()
                })
            });
            let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("impostor atlas trilinear"),
                address_mode_u: wgpu::AddressMode::ClampToEdge,
                address_mode_v: wgpu::AddressMode::ClampToEdge,
                address_mode_w: wgpu::AddressMode::ClampToEdge,
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                mipmap_filter: wgpu::MipmapFilterMode::Linear,
                ..Default::default()
            });
            AtlasTextures { textures, views, sampler }
        })
    }

    /// Reads back mip `level` of layer `layer` (an index into [`ATLAS_LAYERS`]), all
    /// views, tightly packed as in [`crate::atlas::AtlasLevel::layers`].
    pub fn read_level(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        layer: usize,
        level: u32,
    ) -> Result<Vec<u8>, GpuError> {
        let texture = self
            .textures
            .get(layer)
            .ok_or_else(|| GpuError::InvalidRequest(format!("atlas layer {layer} of {}", ATLAS_LAYERS.len())))?;
        if level >= texture.mip_level_count() {
            return Err(GpuError::InvalidRequest(format!("mip level {level} of {}", texture.mip_level_count())));
        }
        let side = (texture.width() >> level).max(1);
        let views = texture.depth_or_array_layers();
        let row_bytes = side * ATLAS_LAYERS[layer].bytes_per_texel;
        let padded_row_bytes = row_bytes.next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
        let size = u64::from(padded_row_bytes) * u64::from(side) * u64::from(views);
        let buffer = scoped(device, || {
            let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("atlas readback"),
                size,
                usage: wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let mut encoder = device.create_command_encoder(&Default::default());
            encoder.copy_texture_to_buffer(
                wgpu::TexelCopyTextureInfo {
                    texture,
                    mip_level: level,
                    origin: wgpu::Origin3d::ZERO,
                    aspect: wgpu::TextureAspect::All,
                },
                wgpu::TexelCopyBufferInfo {
                    buffer: &buffer,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(padded_row_bytes),
                        rows_per_image: Some(side),
                    },
                },
                wgpu::Extent3d { width: side, height: side, depth_or_array_layers: views },
            );
            queue.submit([encoder.finish()]);
            buffer
        })?;
        let padded = crate::gpu_util::read_buffer(device, queue, &buffer, size)?;
        let mut bytes = Vec::with_capacity((row_bytes * side * views) as usize);
        for row in padded.chunks_exact(padded_row_bytes as usize) {
            bytes.extend_from_slice(&row[..row_bytes as usize]);
        }
        Ok(bytes)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn atlas_formats_match_the_shared_layer_table() {
        for (format, layer) in ATLAS_FORMATS.iter().zip(ATLAS_LAYERS) {
            assert_eq!(format!("{format:?}"), layer.format);
            assert_eq!(format.block_copy_size(None), Some(layer.bytes_per_texel));
        }
    }
}
