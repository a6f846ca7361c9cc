//! The CPU side of an impostor atlas: `N = 2n²` views of `p × p` texels per mip level, in
//! the formats of [`ATLAS_LAYERS`] (every channel premultiplied by the coverage α, §4.2).
//!
//! [`AtlasImage`] holds one level in `f32`, un-premultiplied (what the baker reads back
//! and what the mip builder of [`crate::mips`] works on); [`ImpostorAtlas`] holds the
//! quantized bytes of every level, exactly what is uploaded ([`crate::atlas_gpu`]) and
//! saved ([`crate::atlas_file`]).
//!
//! Byte layout of a level's layer: view-major, then rows top to bottom (as
//! [`octahedral_map::ViewFrame`] orders texture rows), then texels left to right; the
//! texel encodings are those of [`ATLAS_LAYERS`]:
//!
//! | layer | bytes |
//! | --- | --- |
//! | `normal_alpha` (`Rgba8Unorm`) | `unorm8((0.5 n + 0.5) α)`, `unorm8(α)` |
//! | `albedo_alpha` (`Rgba8UnormSrgb`) | `srgb8(ρ α)` (the GPU decodes to linear before filtering), `unorm8(α)` |
//! | `material_alpha` (`Rgba8Unorm`) | `unorm8(roughness α)`, `unorm8(metallic α)`, 0, `unorm8(α)` |
//! | `depth_alpha` (`Rg16Float`) | `f16(depth α)`, `f16(α)` |

use glam::{Vec3, Vec4};
use octahedral_map::compact::{compact_view_count, listing_from_compact_index};
use octahedral_map::{OctahedralViews, ViewLayout};

pub use crate::atlas_image::{AtlasImage, AtlasTexel};
use crate::half::{f16_bits_to_f32, f32_to_f16_bits};
use crate::scene::ATLAS_LAYERS;

/// The quantized texels of one mip level: one byte vector per entry of [`ATLAS_LAYERS`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AtlasLevel {
    /// Texels per side at this level.
    pub side: u32,
    /// The bytes of each layer (`N · side² · bytes_per_texel`).
    pub layers: [Vec<u8>; 4],
}

/// An impostor atlas: the view layout, its geometry and every mip level's texels.
#[derive(Clone, Debug, PartialEq)]
pub struct ImpostorAtlas {
    /// The `N = 2n²` view directions.
    pub views: OctahedralViews,
    /// Which views are stored: all `2n²` in Listing 1 order, or each distinct direction
    /// once ([`ViewLayout::Compact`], `2n² − 4(n − 1)` layers, see
    /// [`octahedral_map::compact`]).
    pub layout: ViewLayout,
    /// `p`, texels per side at level 0.
    pub texels: u32,
    /// `R`, the outer radius: each view covers `[-R, R]²` and depths `[-R, R]`.
    pub outer_radius: f32,
    /// `r`, the inner radius.
    pub inner_radius: f32,
    /// Mip levels, level 0 first, down to `1 × 1`.
    pub levels: Vec<AtlasLevel>,
}

/// The number of stored views of `layout` for `views`.
pub fn layer_count(views: OctahedralViews, layout: ViewLayout) -> u32 {
    match layout {
        ViewLayout::Listing1 => views.view_count(),
        ViewLayout::Compact => compact_view_count(views.subdivisions()),
    }
}

/// The number of mip levels of a `side × side` image down to `1 × 1`.
pub fn mip_count(side: u32) -> u32 {
    u32::BITS - side.max(1).leading_zeros()
}

fn unorm8(value: f32) -> u8 {
    (value.clamp(0.0, 1.0) * 255.0).round() as u8
}

/// The sRGB transfer function applied to a linear value in `[0, 1]`, as 8 bits.
pub fn srgb8(linear: f32) -> u8 {
    unorm8(crate::shading::linear_to_srgb(linear))
}

/// The linear value of an 8-bit sRGB code.
pub fn srgb8_to_linear(code: u8) -> f32 {
    let c = f32::from(code) / 255.0;
    if c <= 0.040_45 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
}

/// Encodes one un-premultiplied texel into the four layers' bytes (premultiplied).
pub fn encode_texel(texel: &AtlasTexel) -> [[u8; 4]; 4] {
    let alpha = texel.alpha.clamp(0.0, 1.0);
    let a8 = unorm8(alpha);
    let n = (0.5 * texel.normal + Vec3::splat(0.5)) * alpha;
    let albedo = texel.albedo * alpha;
    let depth = f32_to_f16_bits(texel.depth * alpha).to_le_bytes();
    let alpha16 = f32_to_f16_bits(alpha).to_le_bytes();
    [
        [unorm8(n.x), unorm8(n.y), unorm8(n.z), a8],
        [srgb8(albedo.x), srgb8(albedo.y), srgb8(albedo.z), a8],
        [unorm8(texel.roughness * alpha), unorm8(texel.metallic * alpha), 0, a8],
        [depth[0], depth[1], alpha16[0], alpha16[1]],
    ]
}

/// Decodes the four layers' bytes of one texel into its premultiplied values, as the GPU
/// reads them: `(0.5n+0.5)α, α`; `ρα, α` (linear); `roughness·α, metallic·α, 0, α`;
/// `depth·α, α, 0, 0`.
pub fn decode_premultiplied(bytes: [[u8; 4]; 4]) -> [Vec4; 4] {
    let unorm = |b: [u8; 4]| Vec4::from_array(b.map(|c| f32::from(c) / 255.0));
    let albedo = bytes[1];
    let d = bytes[3];
    [
        unorm(bytes[0]),
        Vec4::new(
            srgb8_to_linear(albedo[0]),
            srgb8_to_linear(albedo[1]),
            srgb8_to_linear(albedo[2]),
            f32::from(albedo[3]) / 255.0,
        ),
        unorm(bytes[2]),
        Vec4::new(
            f16_bits_to_f32(u16::from_le_bytes([d[0], d[1]])),
            f16_bits_to_f32(u16::from_le_bytes([d[2], d[3]])),
            0.0,
            0.0,
        ),
    ]
}

/// Un-premultiplies decoded layers into a texel; α is the `depth_alpha` layer's (16-bit);
/// texels with α = 0 decode to all zeros.
pub fn unpremultiply(layers: [Vec4; 4]) -> AtlasTexel {
    let alpha = layers[3].y;
    if alpha <= 0.0 {
        return AtlasTexel::default();
    }
    // Each layer is divided by its own stored α, so quantization errors of α do not leak.
    let divide = |value: f32, layer_alpha: f32| if layer_alpha > 0.0 { value / layer_alpha } else { 0.0 };
    let n = layers[0];
    let a = layers[1];
    let m = layers[2];
    AtlasTexel {
        normal: Vec3::new(divide(n.x, n.w), divide(n.y, n.w), divide(n.z, n.w)) * 2.0 - Vec3::ONE,
        albedo: Vec3::new(divide(a.x, a.w), divide(a.y, a.w), divide(a.z, a.w)),
        roughness: divide(m.x, m.w),
        metallic: divide(m.y, m.w),
        depth: layers[3].x / alpha,
        alpha,
    }
}

impl AtlasLevel {
    /// Encodes an `f32` level.
    pub fn encode(image: &AtlasImage) -> Self {
        let mut layers: [Vec<u8>; 4] = Default::default();
        for layer in &mut layers {
            layer.reserve(image.texels.len() * 4);
        }
        for texel in &image.texels {
            for (layer, bytes) in layers.iter_mut().zip(encode_texel(texel)) {
                layer.extend_from_slice(&bytes);
            }
        }
        Self { side: image.side, layers }
    }

    /// The bytes of texel `index` (view-major order) in each layer, or `None` outside.
    pub fn texel_bytes(&self, index: usize) -> Option<[[u8; 4]; 4]> {
        let mut out = [[0u8; 4]; 4];
        for (slot, layer) in out.iter_mut().zip(&self.layers) {
            *slot = layer.get(4 * index..4 * index + 4)?.try_into().ok()?;
        }
        Some(out)
    }

    /// Decodes the level to `f32`, un-premultiplied.
    pub fn decode(&self, views: u32) -> AtlasImage {
        let count = (views * self.side * self.side) as usize;
        let texels = (0..count)
            .map(|i| self.texel_bytes(i).map(|b| unpremultiply(decode_premultiplied(b))).unwrap_or_default())
            .collect();
        AtlasImage { side: self.side, views, texels }
    }

    /// Bytes of this level, all layers.
    pub fn byte_count(&self) -> u64 {
        self.layers.iter().map(|l| l.len() as u64).sum()
    }
}

impl ImpostorAtlas {
    /// The atlas whose level 0 is `level0` (`N` views of `p × p` texels, `p` a power of
    /// two), with its full mip chain built by [`crate::mips::build_mip_chain`]; `None`
    /// when the sizes disagree, `p` is not a power of two or the radii are not
    /// `0 ≤ r ≤ R`, `R > 0`, finite.
    pub fn from_level0(
        views: OctahedralViews,
        outer_radius: f32,
        inner_radius: f32,
        level0: AtlasImage,
    ) -> Option<Self> {
        let valid_radii = outer_radius.is_finite()
            && outer_radius > 0.0
            && inner_radius.is_finite()
            && (0.0..=outer_radius).contains(&inner_radius);
        if !valid_radii || level0.views != views.view_count() || !level0.side.is_power_of_two() {
            return None;
        }
        if level0.texels.len() != (level0.views * level0.side * level0.side) as usize {
            return None;
        }
        let texels = level0.side;
        let levels = crate::mips::build_mip_chain(level0).iter().map(AtlasLevel::encode).collect();
        Some(Self { views, layout: ViewLayout::Listing1, texels, outer_radius, inner_radius, levels })
    }

    /// The decoded (un-premultiplied) texel `(x, y)` of `view` at mip `level`.
    pub fn texel(&self, level: usize, view: u32, x: u32, y: u32) -> Option<AtlasTexel> {
        let bytes = self.texel_bytes(level, view, x, y)?;
        Some(unpremultiply(decode_premultiplied(bytes)))
    }

    /// The raw bytes of texel `(x, y)` of `view` at mip `level`, one array per layer.
    pub fn texel_bytes(&self, level: usize, view: u32, x: u32, y: u32) -> Option<[[u8; 4]; 4]> {
        let level_data = self.levels.get(level)?;
        let side = level_data.side;
        if view >= self.layer_count() || x >= side || y >= side {
            return None;
        }
        level_data.texel_bytes(((view as usize * side as usize) + y as usize) * side as usize + x as usize)
    }

    /// The number of stored views (texture array layers) of [`layout`](Self::layout).
    pub fn layer_count(&self) -> u32 {
        layer_count(self.views, self.layout)
    }

    /// The same atlas without the duplicated equator views: layer `c` of the result is
    /// layer `listing_from_compact_index(c)` of `self` (an exact copy, so renders with
    /// [`ViewLayout::Compact`] read the same texels). A compact atlas is returned as is.
    pub fn to_compact(&self) -> Self {
        if self.layout == ViewLayout::Compact {
            return self.clone();
        }
        let n = self.views.subdivisions();
        let compact_layers = compact_view_count(n);
        let levels = self
            .levels
            .iter()
            .map(|level| {
                let texels_per_view = level.side as usize * level.side as usize;
                let mut layers = level.layers.clone();
                for (bytes, layer) in layers.iter_mut().zip(&level.layers) {
                    let per_view = texels_per_view * (layer.len() / texels_per_view / self.layer_count() as usize);
                    *bytes = (0..compact_layers)
                        .flat_map(|c| {
                            let listing = listing_from_compact_index(c, n) as usize;
                            layer[listing * per_view..(listing + 1) * per_view].iter().copied()
                        })
                        .collect();
                }
                AtlasLevel { side: level.side, layers }
            })
            .collect();
        Self { layout: ViewLayout::Compact, levels, ..self.clone() }
    }

    /// The memory of this atlas.
    pub fn memory(&self) -> AtlasMemory {
        AtlasMemory::of_layers(self.layer_count(), self.texels)
    }
}

/// Memory of an atlas of `N` views at `p` texels with full mip chains in the formats of
/// [`ATLAS_LAYERS`] (16 bytes per texel): on the GPU (texture arrays) and on disk
/// ([`crate::atlas_file`]: the same bytes plus the header).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AtlasMemory {
    /// Bytes of each mip level, all layers, all views.
    pub bytes_per_level: Vec<u64>,
    /// Sum of `bytes_per_level`: the GPU texture memory (before driver padding).
    pub gpu_bytes: u64,
}

impl AtlasMemory {
    /// The memory of an atlas storing all `2n²` views of `views` at `p` texels (full mip
    /// chain, [`ViewLayout::Listing1`]).
    pub fn of(views: OctahedralViews, p: u32) -> Self {
        Self::of_layers(views.view_count(), p)
    }

    /// The memory of an atlas of `layers` stored views at `p` texels (full mip chain).
    pub fn of_layers(layers: u32, p: u32) -> Self {
        let per_texel: u64 = ATLAS_LAYERS.iter().map(|l| u64::from(l.bytes_per_texel)).sum();
        let bytes_per_level: Vec<u64> = (0..mip_count(p))
            .map(|level| {
                let side = u64::from((p >> level).max(1));
                side * side * u64::from(layers) * per_texel
            })
            .collect();
        let gpu_bytes = bytes_per_level.iter().sum();
        Self { bytes_per_level, gpu_bytes }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mip_counts() {
        assert_eq!(mip_count(1), 1);
        assert_eq!(mip_count(2), 2);
        assert_eq!(mip_count(32), 6);
        assert_eq!(mip_count(128), 8);
    }

    /// Half an ulp of `x` in IEEE half precision (normal range).
    fn half_f16_ulp(x: f32) -> f32 {
        0.5 * 2.0_f32.powi(x.abs().log2().floor() as i32 - 10)
    }

    #[test]
    fn texel_encoding_round_trips_within_quantization() {
        let texels = [
            AtlasTexel {
                normal: Vec3::new(0.48, -0.6, 0.64),
                albedo: Vec3::new(0.8, 0.2, 0.05),
                roughness: 0.3,
                metallic: 0.6,
                depth: -0.42,
                alpha: 0.75,
            },
            AtlasTexel {
                normal: Vec3::new(-0.8, 0.0, 0.6),
                albedo: Vec3::new(0.01, 0.5, 0.99),
                roughness: 0.95,
                metallic: 0.02,
                depth: 0.9,
                alpha: 0.31,
            },
            AtlasTexel {
                normal: Vec3::new(0.0, 1.0, 0.0),
                albedo: Vec3::splat(0.18),
                roughness: 0.5,
                metallic: 0.0,
                depth: 0.05,
                alpha: 1.0,
            },
        ];
        for texel in texels {
            let back = unpremultiply(decode_premultiplied(encode_texel(&texel)));
            // The quantization bounds. A value `x` stored premultiplied in 8 bits and divided
            // by its layer's 8-bit α is off by `(½/255 + x |α − α₈|) / α₈` (the code's
            // rounding, and the α it was multiplied with against the one it is divided
            // by); the normal's `(0.5 n + 0.5)` mapping doubles it; sRGB codes round by
            // half a code step, which in linear units is at most half the larger of the
            // neighbouring decoded gaps; depth and α are half floats (half an ulp each,
            // depth divided by the half-float α). Plus 1e-6 of f32 rounding.
            let a8 = f32::from(unorm8(texel.alpha)) / 255.0;
            let a16 = f16_bits_to_f32(f32_to_f16_bits(texel.alpha));
            let byte = |x: f32| (0.5 / 255.0 + x * (texel.alpha - a8).abs()) / a8 + 1e-6;
            let srgb = |x: f32| {
                let code = srgb8(x * texel.alpha);
                let below = if code > 0 { srgb8_to_linear(code) - srgb8_to_linear(code - 1) } else { 0.0 };
                let above = if code < 255 { srgb8_to_linear(code + 1) - srgb8_to_linear(code) } else { 0.0 };
                (0.5 * below.max(above) + x * (texel.alpha - a8).abs()) / a8 + 1e-6
            };
            for k in 0..3 {
                let mapped = 0.5 * texel.normal[k] + 0.5;
                assert!((back.normal[k] - texel.normal[k]).abs() <= 2.0 * byte(mapped), "{texel:?} -> {back:?}");
                assert!((back.albedo[k] - texel.albedo[k]).abs() <= srgb(texel.albedo[k]), "{texel:?} -> {back:?}");
            }
            assert!((back.roughness - texel.roughness).abs() <= byte(texel.roughness), "{back:?}");
            assert!((back.metallic - texel.metallic).abs() <= byte(texel.metallic), "{back:?}");
            let depth = texel.depth * texel.alpha;
            let depth_bound = (half_f16_ulp(depth) + texel.depth.abs() * (texel.alpha - a16).abs()) / a16 + 1e-6;
            assert!((back.depth - texel.depth).abs() <= depth_bound, "{back:?}");
            assert!((back.alpha - texel.alpha).abs() <= half_f16_ulp(texel.alpha), "{back:?}");
        }
        assert_eq!(unpremultiply(decode_premultiplied(encode_texel(&AtlasTexel::default()))), AtlasTexel::default());
    }

    #[test]
    fn memory_of_the_papers_atlas() {
        let memory = AtlasMemory::of(OctahedralViews::new(8).unwrap(), 128);
        assert_eq!(memory.bytes_per_level[0], 128 * 128 * 128 * 16);
        assert_eq!(memory.bytes_per_level.len(), 8);
        assert_eq!(*memory.bytes_per_level.last().unwrap(), 128 * 16);
        assert_eq!(memory.gpu_bytes, memory.bytes_per_level.iter().sum::<u64>());
    }
}
