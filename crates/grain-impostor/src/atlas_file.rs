//! Saving and loading an [`ImpostorAtlas`] as one binary file.
//!
//! Layout (little endian):
//!
//! | offset | bytes | field |
//! | --- | --- | --- |
//! | 0 | 8 | magic `GRNIMPST` |
//! | 8 | 4 | version ([`FILE_VERSION`]) |
//! | 12 | 4 | `n` (views per edge; `N = 2n²`) |
//! | 16 | 4 | `p` (texels per side at level 0) |
//! | 20 | 4 | `R` (`f32`) |
//! | 24 | 4 | `r` (`f32`) |
//! | 28 | 16 | the four layer formats ([`format_code`]), in [`ATLAS_LAYERS`] order |
//! | 44 | 2 | mip level count |
//! | 46 | 2 | view layout: 0 all `2n²` views (Listing 1), 1 compact (no duplicated equator) |
//! | 48 | 8 | data length in bytes |
//! | 56 | 8 | FNV-1a 64 checksum of the data |
//! | 64 | … | data: level 0 first; per level, the four layers in order |
//!
//! Loading checks every field and the checksum, and returns an [`AtlasFileError`] naming
//! the file and the problem; it never panics on bad input.

use std::fmt;
use std::path::{Path, PathBuf};

use octahedral_map::{OctahedralViews, ViewLayout};

use crate::atlas::{AtlasLevel, AtlasMemory, ImpostorAtlas, mip_count};
use crate::scene::ATLAS_LAYERS;

/// The file's magic bytes.
pub const MAGIC: [u8; 8] = *b"GRNIMPST";
/// The version this code writes and reads.
pub const FILE_VERSION: u32 = 1;
/// Size of the header before the data.
pub const HEADER_BYTES: usize = 64;

impl AtlasMemory {
    /// Size of the saved file ([`save_atlas`]): the header and every level's bytes.
    pub fn file_bytes(&self) -> u64 {
        self.gpu_bytes + HEADER_BYTES as u64
    }
}

/// The code of a layer format in the file header: 1 `Rgba8Unorm`, 2 `Rgba8UnormSrgb`,
/// 3 `Rg16Float`, 0 for any other.
pub fn format_code(format: &str) -> u32 {
    match format {
        "Rgba8Unorm" => 1,
        "Rgba8UnormSrgb" => 2,
        "Rg16Float" => 3,
        _ => 0,
    }
}

/// What is wrong with an atlas file.
#[derive(Clone, Debug, PartialEq)]
pub enum AtlasFileProblem {
    /// Reading or writing failed.
    Io(String),
    /// The file does not start with [`MAGIC`].
    BadMagic,
    /// The file's version is not [`FILE_VERSION`].
    UnsupportedVersion {
        /// The version in the file.
        found: u32,
    },
    /// The file is shorter than its header says.
    Truncated {
        /// Bytes the header promises.
        expected: u64,
        /// Bytes present.
        found: u64,
    },
    /// The file has bytes after the data.
    TrailingBytes {
        /// How many.
        extra: u64,
    },
    /// A header field is out of range or inconsistent.
    InvalidHeader(String),
    /// A layer format differs from [`ATLAS_LAYERS`].
    LayerFormatMismatch {
        /// The layer.
        layer: &'static str,
        /// The code in the file.
        found: u32,
        /// The code this version expects.
        expected: u32,
    },
    /// The data's checksum differs from the header's: the data is corrupt.
    ChecksumMismatch {
        /// Checksum in the header.
        stored: u64,
        /// Checksum of the data read.
        computed: u64,
    },
}

/// An atlas file could not be saved or loaded.
#[derive(Clone, Debug, PartialEq)]
pub struct AtlasFileError {
    /// The file.
    pub path: PathBuf,
    /// What went wrong.
    pub problem: AtlasFileProblem,
}

impl fmt::Display for AtlasFileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let path = self.path.display();
        match &self.problem {
            AtlasFileProblem::Io(message) => write!(f, "{path}: {message}"),
            AtlasFileProblem::BadMagic => write!(f, "{path}: not an impostor atlas (bad magic)"),
            AtlasFileProblem::UnsupportedVersion { found } => {
                write!(f, "{path}: atlas file version {found}, this build reads version {FILE_VERSION}")
            }
            AtlasFileProblem::Truncated { expected, found } => {
                write!(f, "{path}: truncated atlas file: {found} bytes, expected {expected}")
            }
            AtlasFileProblem::TrailingBytes { extra } => {
                write!(f, "{path}: {extra} unexpected bytes after the atlas data")
            }
            AtlasFileProblem::InvalidHeader(message) => write!(f, "{path}: invalid atlas header: {message}"),
            AtlasFileProblem::LayerFormatMismatch { layer, found, expected } => {
                write!(f, "{path}: layer {layer} has format code {found}, expected {expected}")
            }
            AtlasFileProblem::ChecksumMismatch { stored, computed } => {
                write!(f, "{path}: corrupt atlas data (checksum {computed:#018x}, header says {stored:#018x})")
            }
        }
    }
}

impl std::error::Error for AtlasFileError {}

/// FNV-1a, 64 bits.
/// The header code of a view layout.
fn layout_code(layout: ViewLayout) -> u16 {
    match layout {
        ViewLayout::Listing1 => 0,
        ViewLayout::Compact => 1,
    }
}

fn layout_from_code(code: u32) -> Option<ViewLayout> {
    match code {
        0 => Some(ViewLayout::Listing1),
        1 => Some(ViewLayout::Compact),
        _ => None,
    }
}

fn fnv1a(bytes: impl Iterator<Item = u8>) -> u64 {
    bytes.fold(0xcbf2_9ce4_8422_2325, |hash, byte| (hash ^ u64::from(byte)).wrapping_mul(0x0100_0000_01b3))
}

/// The file bytes of `atlas`.
pub fn encode_atlas(atlas: &ImpostorAtlas) -> Vec<u8> {
    let data_length: u64 = atlas.levels.iter().map(AtlasLevel::byte_count).sum();
    let checksum = fnv1a(atlas.levels.iter().flat_map(|l| l.layers.iter()).flat_map(|l| l.iter().copied()));
    let mut bytes = Vec::with_capacity(HEADER_BYTES + data_length as usize);
    bytes.extend_from_slice(&MAGIC);
    bytes.extend_from_slice(&FILE_VERSION.to_le_bytes());
    bytes.extend_from_slice(&atlas.views.subdivisions().to_le_bytes());
    bytes.extend_from_slice(&atlas.texels.to_le_bytes());
    bytes.extend_from_slice(&atlas.outer_radius.to_le_bytes());
    bytes.extend_from_slice(&atlas.inner_radius.to_le_bytes());
    for layer in ATLAS_LAYERS {
        bytes.extend_from_slice(&format_code(layer.format).to_le_bytes());
    }
    bytes.extend_from_slice(&(atlas.levels.len() as u16).to_le_bytes());
    bytes.extend_from_slice(&layout_code(atlas.layout).to_le_bytes());
    bytes.extend_from_slice(&data_length.to_le_bytes());
    bytes.extend_from_slice(&checksum.to_le_bytes());
    for level in &atlas.levels {
        for layer in &level.layers {
            bytes.extend_from_slice(layer);
        }
    }
    bytes
}

fn u32_at(bytes: &[u8], offset: usize) -> u32 {
    u32::from_le_bytes([bytes[offset], bytes[offset + 1], bytes[offset + 2], bytes[offset + 3]])
}

fn u64_at(bytes: &[u8], offset: usize) -> u64 {
    u64::from(u32_at(bytes, offset)) | (u64::from(u32_at(bytes, offset + 4)) << 32)
}

/// Parses file bytes into an atlas.
pub fn decode_atlas(bytes: &[u8]) -> Result<ImpostorAtlas, AtlasFileProblem> {
    let found = bytes.len() as u64;
    if bytes.len() < MAGIC.len() || bytes[..MAGIC.len()] != MAGIC {
        return Err(if MAGIC.starts_with(bytes) {
            AtlasFileProblem::Truncated { expected: HEADER_BYTES as u64, found }
        } else {
            AtlasFileProblem::BadMagic
        });
    }
    if bytes.len() < 12 {
        return Err(AtlasFileProblem::Truncated { expected: HEADER_BYTES as u64, found });
    }
    let version = u32_at(bytes, 8);
    if version != FILE_VERSION {
        return Err(AtlasFileProblem::UnsupportedVersion { found: version });
    }
    if bytes.len() < HEADER_BYTES {
        return Err(AtlasFileProblem::Truncated { expected: HEADER_BYTES as u64, found });
    }
    let invalid = |message: String| AtlasFileProblem::InvalidHeader(message);
    let n = u32_at(bytes, 12);
    let p = u32_at(bytes, 16);
    let outer_radius = f32::from_bits(u32_at(bytes, 20));
    let inner_radius = f32::from_bits(u32_at(bytes, 24));
    let views = OctahedralViews::new(n).ok_or_else(|| invalid(format!("view subdivisions n = {n}")))?;
    if !p.is_power_of_two() || p > 1 << 16 {
        return Err(invalid(format!("texels per side p = {p} (a power of two ≤ 65536)")));
    }
    if !(outer_radius.is_finite()
        && outer_radius > 0.0
        && inner_radius.is_finite()
        && (0.0..=outer_radius).contains(&inner_radius))
    {
        return Err(invalid(format!("radii r = {inner_radius}, R = {outer_radius} (need 0 ≤ r ≤ R, R > 0)")));
    }
    for (i, layer) in ATLAS_LAYERS.iter().enumerate() {
        let code = u32_at(bytes, 28 + 4 * i);
        let expected = format_code(layer.format);
        if code != expected {
            return Err(AtlasFileProblem::LayerFormatMismatch { layer: layer.name, found: code, expected });
        }
    }
    let levels = u32_at(bytes, 44) & 0xffff;
    let layout_value = u32_at(bytes, 44) >> 16;
    let layout = layout_from_code(layout_value).ok_or_else(|| invalid(format!("view layout code {layout_value}")))?;
    let layers = crate::atlas::layer_count(views, layout);
    if levels != mip_count(p) {
        return Err(invalid(format!("{levels} mip levels, a {p}-texel atlas has {}", mip_count(p))));
    }
    let expected_length = AtlasMemory::of_layers(layers, p).gpu_bytes;
    let data_length = u64_at(bytes, 48);
    if data_length != expected_length {
        return Err(invalid(format!("data length {data_length}, n = {n} and p = {p} need {expected_length}")));
    }
    let expected_total = HEADER_BYTES as u64 + data_length;
    if found < expected_total {
        return Err(AtlasFileProblem::Truncated { expected: expected_total, found });
    }
    if found > expected_total {
        return Err(AtlasFileProblem::TrailingBytes { extra: found - expected_total });
    }
    let data = &bytes[HEADER_BYTES..];
    let stored = u64_at(bytes, 56);
    let computed = fnv1a(data.iter().copied());
    if stored != computed {
        return Err(AtlasFileProblem::ChecksumMismatch { stored, computed });
    }
    let mut offset = 0;
    let mut atlas_levels = Vec::with_capacity(levels as usize);
    for level in 0..levels {
        let side = (p >> level).max(1);
        let layers = ATLAS_LAYERS.map(|layer| {
            let length =
                (u64::from(layers) * u64::from(side) * u64::from(side) * u64::from(layer.bytes_per_texel)) as usize;
            let slice = data[offset..offset + length].to_vec();
            offset += length;
            slice
        });
        atlas_levels.push(AtlasLevel { side, layers });
    }
    Ok(ImpostorAtlas { views, layout, texels: p, outer_radius, inner_radius, levels: atlas_levels })
}

/// Writes `atlas` to `path`.
pub fn save_atlas(atlas: &ImpostorAtlas, path: impl AsRef<Path>) -> Result<(), AtlasFileError> {
    let path = path.as_ref();
    std::fs::write(path, encode_atlas(atlas))
        .map_err(|e| AtlasFileError { path: path.to_owned(), problem: AtlasFileProblem::Io(e.to_string()) })
}

/// Reads an atlas from `path`.
pub fn load_atlas(path: impl AsRef<Path>) -> Result<ImpostorAtlas, AtlasFileError> {
    let path = path.as_ref();
    let error = |problem| AtlasFileError { path: path.to_owned(), problem };
    let bytes = std::fs::read(path).map_err(|e| error(AtlasFileProblem::Io(e.to_string())))?;
    decode_atlas(&bytes).map_err(error)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::atlas::{AtlasImage, AtlasTexel};
    use glam::Vec3;

    fn small_atlas() -> ImpostorAtlas {
        let views = OctahedralViews::new(2).unwrap();
        let side = 8;
        let texels = (0..views.view_count() * side * side)
            .map(|i| AtlasTexel {
                normal: Vec3::Z,
                albedo: Vec3::splat((i % 7) as f32 / 7.0),
                roughness: 0.4,
                metallic: 0.0,
                depth: 0.5,
                alpha: if i % 3 == 0 { 0.0 } else { 1.0 },
            })
            .collect();
        ImpostorAtlas::from_level0(views, 1.5, 0.9, AtlasImage { side, views: views.view_count(), texels }).unwrap()
    }

    fn temp_path(name: &str) -> PathBuf {
        std::env::temp_dir().join(format!("grain-impostor-{}-{name}.atlas", std::process::id()))
    }

    #[test]
    fn save_then_load_gives_the_same_atlas_and_the_reported_size() {
        let atlas = small_atlas();
        let path = temp_path("roundtrip");
        save_atlas(&atlas, &path).unwrap();
        assert_eq!(std::fs::metadata(&path).unwrap().len(), atlas.memory().file_bytes());
        assert_eq!(load_atlas(&path).unwrap(), atlas);
        std::fs::remove_file(&path).unwrap();
    }

    #[test]
    fn compact_atlases_round_trip_and_keep_one_copy_of_each_view() {
        let atlas = small_atlas();
        let compact = atlas.to_compact();
        assert_eq!(compact.layout, ViewLayout::Compact);
        // n = 2: 8 views, of which the 4 equator views are stored twice.
        assert_eq!((atlas.layer_count(), compact.layer_count()), (8, 4));
        assert!(compact.memory().gpu_bytes * 2 == atlas.memory().gpu_bytes);
        let n = atlas.views.subdivisions();
        for level in 0..atlas.levels.len() {
            let side = atlas.levels[level].side;
            for c in 0..compact.layer_count() {
                let listing = octahedral_map::compact::listing_from_compact_index(c, n);
                for (x, y) in [(0, 0), (side - 1, side / 2)] {
                    assert_eq!(compact.texel_bytes(level, c, x, y), atlas.texel_bytes(level, listing, x, y));
                }
            }
        }
        assert_eq!(decode_atlas(&encode_atlas(&compact)).unwrap(), compact);
        assert_eq!(encode_atlas(&compact).len() as u64, compact.memory().file_bytes());
        let mut bad_layout = encode_atlas(&compact);
        bad_layout[46] = 7;
        assert!(matches!(decode_atlas(&bad_layout), Err(AtlasFileProblem::InvalidHeader(m)) if m.contains("layout")));
    }

    #[test]
    fn every_kind_of_bad_file_is_a_named_error() {
        let bytes = encode_atlas(&small_atlas());
        let problem = |bytes: &[u8]| decode_atlas(bytes).unwrap_err();
        // Truncated anywhere: in the magic, in the header, in the data.
        for length in [0, 4, 10, 40, HEADER_BYTES, bytes.len() - 1] {
            assert!(matches!(problem(&bytes[..length]), AtlasFileProblem::Truncated { .. }), "length {length}");
        }
        let mut extra = bytes.clone();
        extra.push(0);
        assert_eq!(problem(&extra), AtlasFileProblem::TrailingBytes { extra: 1 });
        let mut magic = bytes.clone();
        magic[0] = b'X';
        assert_eq!(problem(&magic), AtlasFileProblem::BadMagic);
        let mut version = bytes.clone();
        version[8] = 7;
        assert_eq!(problem(&version), AtlasFileProblem::UnsupportedVersion { found: 7 });
        let mut corrupt = bytes.clone();
        *corrupt.last_mut().unwrap() ^= 0x10;
        assert!(matches!(problem(&corrupt), AtlasFileProblem::ChecksumMismatch { .. }));
        let mut format = bytes.clone();
        format[28] = 9;
        assert!(matches!(
            problem(&format),
            AtlasFileProblem::LayerFormatMismatch { layer: "normal_alpha", found: 9, .. }
        ));
        for (offset, value) in [(12, 0u32), (16, 48), (20, f32::NAN.to_bits()), (24, 2.0f32.to_bits()), (44, 3)] {
            let mut header = bytes.clone();
            header[offset..offset + 4].copy_from_slice(&value.to_le_bytes());
            assert!(matches!(problem(&header), AtlasFileProblem::InvalidHeader(_)), "offset {offset}");
        }
        // The file-level error names the path.
        let path = temp_path("truncated");
        std::fs::write(&path, &bytes[..100]).unwrap();
        let error = load_atlas(&path).unwrap_err();
        assert_eq!(error.path, path);
        assert!(error.to_string().contains("truncated") && error.to_string().contains(&path.display().to_string()));
        std::fs::remove_file(&path).unwrap();
        let missing = load_atlas(temp_path("missing")).unwrap_err();
        assert!(matches!(missing.problem, AtlasFileProblem::Io(_)));
    }
}
