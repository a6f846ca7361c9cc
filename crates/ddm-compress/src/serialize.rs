//! A versioned binary form of [`CompressedMap`] that rejects corrupt or inconsistent
//! data with a clear error.
//!
//! Layout (little endian): magic `b"DDMC"`, version `u32`, dims `3 × u32`, block `u32`,
//! grid length `u32`, atlas length `u32`, then the grid (`u32` each) and the atlas
//! (`f32` each).

use alloc::vec::Vec;
use core::fmt;

use glam::UVec3;

use crate::compress::{CompressedMap, MAX_BLOCK, SURFACE_FLAG, grid_dims};

const MAGIC: [u8; 4] = *b"DDMC";
/// Magic number and seven header words.
const HEADER_BYTES: usize = 4 + 7 * 4;
/// The format version written by [`CompressedMap::to_bytes`].
pub const FORMAT_VERSION: u32 = 1;

/// Why bytes are not a valid compressed map.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum DecodeError {
    /// The data ends before byte `needed`.
    Truncated {
        /// Bytes needed.
        needed: usize,
        /// Bytes available.
        available: usize,
    },
    /// The magic number is not `DDMC`.
    BadMagic,
    /// The version is not [`FORMAT_VERSION`].
    UnsupportedVersion(u32),
    /// Sizes in the header contradict each other.
    Inconsistent(&'static str),
    /// Grid entry `index` points past the atlas or holds an invalid distance.
    BadEntry {
        /// The entry's index in the grid.
        index: usize,
    },
    /// Atlas value `index` is negative or not finite.
    BadAtlasValue {
        /// The value's index in the atlas.
        index: usize,
    },
    /// Bytes remain after the atlas.
    TrailingBytes(usize),
}

impl fmt::Display for DecodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DecodeError::Truncated { needed, available } => {
                write!(f, "compressed DDM truncated: {needed} bytes needed, {available} present")
            }
            DecodeError::BadMagic => write!(f, "not a compressed DDM (bad magic number)"),
            DecodeError::UnsupportedVersion(v) => {
                write!(f, "compressed DDM version {v} is not supported (expected {FORMAT_VERSION})")
            }
            DecodeError::Inconsistent(what) => write!(f, "inconsistent compressed DDM: {what}"),
            DecodeError::BadEntry { index } => write!(f, "compressed DDM grid entry {index} is invalid"),
            DecodeError::BadAtlasValue { index } => write!(f, "compressed DDM atlas value {index} is invalid"),
            DecodeError::TrailingBytes(n) => write!(f, "{n} unexpected bytes after the compressed DDM"),
        }
    }
}

impl core::error::Error for DecodeError {}

struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn word(&mut self) -> Result<u32, DecodeError> {
        let end = self.at + 4;
        let chunk =
            self.bytes.get(self.at..end).ok_or(DecodeError::Truncated { needed: end, available: self.bytes.len() })?;
        self.at = end;
        Ok(u32::from_le_bytes([chunk[0], chunk[1], chunk[2], chunk[3]]))
    }
}

impl CompressedMap {
    /// The binary form (see the module docs).
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(HEADER_BYTES + 4 * (self.grid.len() + self.atlas.len()));
        out.extend_from_slice(&MAGIC);
        let header = [
            FORMAT_VERSION,
            self.dims.x,
            self.dims.y,
            self.dims.z,
            self.block,
            self.grid.len() as u32,
            self.atlas.len() as u32,
        ];
        for word in header.into_iter().chain(self.grid.iter().copied()).chain(self.atlas.iter().map(|v| v.to_bits())) {
            out.extend_from_slice(&word.to_le_bytes());
        }
        out
    }

    /// Parses and validates [`to_bytes`](Self::to_bytes) output.
    pub fn from_bytes(bytes: &[u8]) -> Result<Self, DecodeError> {
        if bytes.get(..4).ok_or(DecodeError::Truncated { needed: 4, available: bytes.len() })? != MAGIC {
            return Err(DecodeError::BadMagic);
        }
        let mut r = Reader { bytes, at: 4 };
        let version = r.word()?;
        if version != FORMAT_VERSION {
            return Err(DecodeError::UnsupportedVersion(version));
        }
        let dims = UVec3::new(r.word()?, r.word()?, r.word()?);
        let block = r.word()?;
        let (grid_len, atlas_len) = (r.word()? as usize, r.word()? as usize);
        if dims.cmpeq(UVec3::ZERO).any() || block == 0 || block > MAX_BLOCK {
            return Err(DecodeError::Inconsistent("empty grid or block size outside 1..=64"));
        }
        let g = grid_dims(dims, block);
        if (g.x as usize).checked_mul(g.y as usize).and_then(|n| n.checked_mul(g.z as usize)) != Some(grid_len) {
            return Err(DecodeError::Inconsistent("lookup grid length does not match dims / block"));
        }
        let block_len = (block * block * block) as usize;
        if atlas_len % block_len != 0 {
            return Err(DecodeError::Inconsistent("atlas length is not a whole number of blocks"));
        }
        let needed = HEADER_BYTES + 4 * (grid_len + atlas_len);
        if bytes.len() < needed {
            return Err(DecodeError::Truncated { needed, available: bytes.len() });
        }
        let grid: Vec<u32> = (0..grid_len).map(|_| r.word()).collect::<Result<_, _>>()?;
        let atlas: Vec<f32> = (0..atlas_len).map(|_| r.word().map(f32::from_bits)).collect::<Result<_, _>>()?;
        if bytes.len() > needed {
            return Err(DecodeError::TrailingBytes(bytes.len() - needed));
        }
        let atlas_blocks = atlas_len / block_len;
        let mut used = alloc::vec![false; atlas_blocks];
        for (index, &entry) in grid.iter().enumerate() {
            if entry & SURFACE_FLAG != 0 {
                let block_index = (entry & !SURFACE_FLAG) as usize;
                if block_index >= atlas_blocks || core::mem::replace(&mut used[block_index], true) {
                    return Err(DecodeError::BadEntry { index });
                }
            } else if !f32::from_bits(entry).is_finite() {
                return Err(DecodeError::BadEntry { index });
            }
        }
        if let Some(index) = atlas.iter().position(|v| !(v.is_finite() && *v >= 0.0)) {
            return Err(DecodeError::BadAtlasValue { index });
        }
        Ok(Self::from_checked_parts(dims, block, grid, atlas))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> CompressedMap {
        let values: Vec<f32> = (0..64).map(|i| (i % 5) as f32).collect();
        let surface: Vec<bool> = (0..64).map(|i| i % 13 == 0).collect();
        CompressedMap::compress(&values, &surface, UVec3::splat(4), 2).unwrap()
    }

    #[test]
    fn round_trips() {
        let map = sample();
        assert_eq!(CompressedMap::from_bytes(&map.to_bytes()), Ok(map));
    }

    #[test]
    fn corruption_is_reported() {
        let bytes = sample().to_bytes();
        assert_eq!(CompressedMap::from_bytes(b"nope"), Err(DecodeError::BadMagic));
        assert!(matches!(CompressedMap::from_bytes(&bytes[..bytes.len() - 1]), Err(DecodeError::Truncated { .. })));
        let mut extra = bytes.clone();
        extra.push(0);
        assert_eq!(CompressedMap::from_bytes(&extra), Err(DecodeError::TrailingBytes(1)));
        let mut version = bytes.clone();
        version[4] = 9;
        assert_eq!(CompressedMap::from_bytes(&version), Err(DecodeError::UnsupportedVersion(9)));
        let mut dims = bytes.clone();
        dims[8] = 5; // dims.x = 5 no longer matches the grid length
        assert!(matches!(CompressedMap::from_bytes(&dims), Err(DecodeError::Inconsistent(_))));
        // A grid entry pointing past the atlas.
        let mut entry = bytes.clone();
        let first_entry = HEADER_BYTES;
        entry[first_entry..first_entry + 4].copy_from_slice(&(SURFACE_FLAG | 999).to_le_bytes());
        assert_eq!(CompressedMap::from_bytes(&entry), Err(DecodeError::BadEntry { index: 0 }));
        let mut nan = bytes.clone();
        let last = nan.len() - 4;
        nan[last..].copy_from_slice(&f32::NAN.to_bits().to_le_bytes());
        assert!(matches!(CompressedMap::from_bytes(&nan), Err(DecodeError::BadAtlasValue { .. })));
    }
}
