//! Lossless block compression of a distance map (§4, Algorithm A.1) and its access
//! function (Algorithm A.2).
//!
//! The map is cut into `b³` blocks. A block that the mesostructure crosses is copied whole
//! into an atlas, and its lookup-grid entry stores the block's atlas index with
//! [`SURFACE_FLAG`] set; any other block keeps only the minimum of its distances, stored
//! as the bits of a non-negative `f32` (whose sign bit is clear, so the flag is free).
//! Reading a voxel of a crossed block returns its exact value; reading any other voxel
//! returns a smaller or equal value, so sphere tracing stays conservative and the final
//! hit (always found in crossed blocks) is unchanged: the compression is lossless where
//! it matters.

use alloc::vec::Vec;
use core::fmt;

use glam::{UVec3, UVec4};
use gpu_layout::gpu_struct;

/// Set in a lookup-grid entry whose block lives in the atlas; the low 31 bits are then
/// the block's index in the atlas.
pub const SURFACE_FLAG: u32 = 0x8000_0000;

/// A compressed distance map: a coarse lookup grid and an atlas of surface blocks.
#[derive(Clone, Debug, PartialEq)]
pub struct CompressedMap {
    pub(crate) dims: UVec3,
    pub(crate) block: u32,
    pub(crate) grid: Vec<u32>,
    pub(crate) atlas: Vec<f32>,
    /// `grid_dims(dims, block)`, kept so that [`CompressedMap::access`] does not recompute it.
    grid_dims: UVec3,
    /// `log2(block)` for a power-of-two block, [`NOT_POWER_OF_TWO`] otherwise.
    block_shift: u32,
}

/// `CompressedMap::block_shift` of a block side that is not a power of two.
const NOT_POWER_OF_TWO: u32 = u32::MAX;

/// A distance read with [`CompressedMap::access_cell`]: the stored distance and the box
/// of voxels `origin ≤ v < origin + size` from every point of which it holds.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CellDistance {
    /// The stored (conservative) distance.
    pub distance: f32,
    /// The cell's first voxel.
    pub origin: UVec3,
    /// The cell's size in voxels (1 for a single voxel).
    pub size: UVec3,
}

/// The lookup-grid size for `dims` voxels in blocks of `block`.
pub fn grid_dims(dims: UVec3, block: u32) -> UVec3 {
    (dims + UVec3::splat(block - 1)) / block
}

/// The largest block side [`CompressedMap::compress`] accepts.
pub const MAX_BLOCK: u32 = 64;

/// Why [`CompressedMap::compress`] refused its inputs. The checks run in the order of the
/// variants; the first that fails is returned.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CompressError {
    /// The block side is 0 or above [`MAX_BLOCK`].
    InvalidBlock {
        /// The block side given.
        block: u32,
    },
    /// A side of the grid is zero.
    EmptyGrid {
        /// The grid size given.
        dims: UVec3,
    },
    /// The grid has more voxels than a `u32` index reaches (the GPU reads `u32` indices).
    TooManyVoxels {
        /// The grid size given.
        dims: UVec3,
    },
    /// `values` does not have one entry per voxel.
    ValueCount {
        /// Voxels of the grid.
        expected: usize,
        /// Entries of `values`.
        found: usize,
    },
    /// `surface` does not have one entry per voxel.
    SurfaceCount {
        /// Voxels of the grid.
        expected: usize,
        /// Entries of `surface`.
        found: usize,
    },
    /// Value `index` is negative or not finite (a distance is neither).
    InvalidValue {
        /// The value's index in `values`.
        index: usize,
        /// The value.
        value: f32,
    },
    /// The atlas would hold more than 2³¹ blocks or more words than a `u32` index reaches.
    AtlasOverflow,
}

impl fmt::Display for CompressError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::InvalidBlock { block } => {
                write!(f, "compression: the block side {block} is outside 1..={MAX_BLOCK}")
            }
            Self::EmptyGrid { dims } => write!(f, "compression: the grid {dims} has no voxel"),
            Self::TooManyVoxels { dims } => {
                write!(f, "compression: the grid {dims} has more voxels than a u32 index reaches")
            }
            Self::ValueCount { expected, found } => {
                write!(f, "compression: {found} values for {expected} voxels")
            }
            Self::SurfaceCount { expected, found } => {
                write!(f, "compression: {found} surface flags for {expected} voxels")
            }
            Self::InvalidValue { index, value } => {
                write!(f, "compression: value {index} is {value}, not a non-negative finite distance")
            }
            Self::AtlasOverflow => write!(f, "compression: the atlas would exceed 2³¹ blocks or u32 indices"),
        }
    }
}

impl core::error::Error for CompressError {}

impl CompressedMap {
    /// Compresses `values` (one per voxel, index `x + dims.x (y + dims.y z)`) with
    /// `surface` marking crossed voxels, in `block³` blocks.
    ///
    /// # Errors
    ///
    /// A [`CompressError`]: a block side of 0 or above [`MAX_BLOCK`], an empty or too large
    /// grid, `values` or `surface` of the wrong length, a negative or non-finite value
    /// (with its index), or an atlas past `u32` indices.
    pub fn compress(values: &[f32], surface: &[bool], dims: UVec3, block: u32) -> Result<Self, CompressError> {
        if block == 0 || block > MAX_BLOCK {
            return Err(CompressError::InvalidBlock { block });
        }
        if dims.cmpeq(UVec3::ZERO).any() {
            return Err(CompressError::EmptyGrid { dims });
        }
        let voxels = u64::from(dims.x) * u64::from(dims.y);
        let voxels = voxels.checked_mul(u64::from(dims.z)).filter(|&v| v <= u64::from(u32::MAX));
        let Some(voxels) = voxels.and_then(|v| usize::try_from(v).ok()) else {
            return Err(CompressError::TooManyVoxels { dims });
        };
        if values.len() != voxels {
            return Err(CompressError::ValueCount { expected: voxels, found: values.len() });
        }
        if surface.len() != voxels {
            return Err(CompressError::SurfaceCount { expected: voxels, found: surface.len() });
        }
        if let Some((index, &value)) = values.iter().enumerate().find(|(_, v)| !(v.is_finite() && **v >= 0.0)) {
            return Err(CompressError::InvalidValue { index, value });
        }
        let g = grid_dims(dims, block);
        let mut grid = Vec::with_capacity((g.x * g.y * g.z) as usize);
        let mut atlas = Vec::new();
        for bz in 0..g.z {
            for by in 0..g.y {
                for bx in 0..g.x {
                    let origin = UVec3::new(bx, by, bz) * block;
                    let mut crossed = false;
                    let mut minimum = f32::INFINITY;
                    let mut copy = Vec::with_capacity((block * block * block) as usize);
                    for z in 0..block {
                        for y in 0..block {
                            for x in 0..block {
                                let p = origin + UVec3::new(x, y, z);
                                if p.cmplt(dims).all() {
                                    let i = (p.x + dims.x * (p.y + dims.y * p.z)) as usize;
                                    crossed |= surface[i];
                                    minimum = minimum.min(values[i]);
                                    copy.push(values[i]);
                                } else {
                                    copy.push(0.0); // outside the map: never read
                                }
                            }
                        }
                    }
                    if crossed {
                        let index = u32::try_from(atlas.len() / copy.len())
                            .ok()
                            .filter(|i| i & SURFACE_FLAG == 0 && atlas.len() + copy.len() <= u32::MAX as usize)
                            .ok_or(CompressError::AtlasOverflow)?;
                        grid.push(SURFACE_FLAG | index);
                        atlas.extend(copy);
                    } else {
                        grid.push((minimum + 0.0).to_bits()); // + 0.0 turns -0.0 into +0.0
                    }
                }
            }
        }
        Ok(Self::from_checked_parts(dims, block, grid, atlas))
    }

    /// The map from parts that [`CompressedMap::compress`] or the decoder have checked
    /// (`block` in `1..=64`, `grid` of `grid_dims(dims, block)` entries whose atlas
    /// indices lie in `atlas`).
    pub(crate) fn from_checked_parts(dims: UVec3, block: u32, grid: Vec<u32>, atlas: Vec<f32>) -> Self {
        let block_shift = if block.is_power_of_two() { block.trailing_zeros() } else { NOT_POWER_OF_TWO };
        Self { dims, block, grid, atlas, grid_dims: grid_dims(dims, block), block_shift }
    }

    /// The map's size in voxels.
    pub fn dims(&self) -> UVec3 {
        self.dims
    }

    /// The block side in voxels.
    pub fn block(&self) -> u32 {
        self.block
    }

    /// `log2` of the block side when it is a power of two (the shift of
    /// [`grid_index_shifted`] and [`atlas_index_shifted`]), `None` otherwise.
    pub fn block_shift(&self) -> Option<u32> {
        (self.block_shift != NOT_POWER_OF_TWO).then_some(self.block_shift)
    }

    /// The lookup grid's entries.
    pub fn grid(&self) -> &[u32] {
        &self.grid
    }

    /// The atlas, `block³` values per surface block.
    pub fn atlas(&self) -> &[f32] {
        &self.atlas
    }

    /// The stored distance of `voxel` (Algorithm A.2), or `None` outside the map.
    ///
    /// Power-of-two blocks (the usual 2, 4, 8) take shifts and masks instead of the six
    /// integer divisions of [`grid_index`] and [`atlas_index`]; the indices are the same.
    /// The lookup grid's size and the shift are computed once, when the map is made.
    #[inline]
    pub fn access(&self, voxel: UVec3) -> Option<f32> {
        let entry = self.entry_of(voxel)?;
        if entry & SURFACE_FLAG == 0 {
            return Some(f32::from_bits(entry));
        }
        self.atlas_value(entry, voxel)
    }

    /// The lookup-grid entry of `voxel`'s block, `None` outside the map.
    #[inline]
    fn entry_of(&self, voxel: UVec3) -> Option<u32> {
        if !voxel.cmplt(self.dims).all() {
            return None;
        }
        let index = if self.block_shift != NOT_POWER_OF_TWO {
            grid_index_shifted(voxel, self.grid_dims, self.block_shift)
        } else {
            grid_index(voxel, self.dims, self.block)
        };
        self.grid.get(index as usize).copied()
    }

    /// The atlas value of `voxel` in the surface block of lookup entry `entry`.
    #[inline]
    fn atlas_value(&self, entry: u32, voxel: UVec3) -> Option<f32> {
        let shift = self.block_shift;
        let index = if shift != NOT_POWER_OF_TWO {
            atlas_index_shifted(entry, voxel, shift)
        } else {
            atlas_index(entry, voxel, self.block)
        };
        self.atlas.get(index as usize).copied()
    }

    /// The stored distance of `voxel` with the cell of voxels it holds for, or `None`
    /// outside the map: in a surface block the voxel itself, with its exact value; in any
    /// other block the whole block (clipped to the map), whose minimum bounds the distance
    /// from every point of every voxel in it. A tracer that steps to the cell's exit wall
    /// before using the distance (`ddm_tracer::Stepping::VoxelExit`) then crosses a block
    /// without surface in one step. The distance is [`CompressedMap::access`]'s.
    ///
    /// WGSL twin: `trace_map_cell` in `ddm_tracer.wgsl`.
    #[inline]
    pub fn access_cell(&self, voxel: UVec3) -> Option<CellDistance> {
        let entry = self.entry_of(voxel)?;
        if entry & SURFACE_FLAG != 0 {
            let distance = self.atlas_value(entry, voxel)?;
            return Some(CellDistance { distance, origin: voxel, size: UVec3::ONE });
        }
        let origin = if self.block_shift != NOT_POWER_OF_TWO {
            (voxel >> self.block_shift) << self.block_shift
        } else {
            voxel / self.block * self.block
        };
        let size = UVec3::splat(self.block).min(self.dims - origin);
        Some(CellDistance { distance: f32::from_bits(entry), origin, size })
    }

    /// Bytes of the uncompressed map (4 per voxel) over bytes of lookup grid plus atlas.
    pub fn compression_efficiency(&self) -> f64 {
        let uncompressed = 4.0 * f64::from(self.dims.x) * f64::from(self.dims.y) * f64::from(self.dims.z);
        uncompressed / (4.0 * (self.grid.len() + self.atlas.len()) as f64)
    }
}

/// Index of `voxel`'s block in the lookup grid. WGSL twin: `ddm_grid_index`.
pub fn grid_index(voxel: UVec3, dims: UVec3, block: u32) -> u32 {
    let g = grid_dims(dims, block);
    let b = voxel / block;
    b.x + g.x * (b.y + g.y * b.z)
}

/// Index in the atlas of `voxel` inside the surface block of lookup entry `entry`.
/// WGSL twin: `ddm_atlas_index`.
pub fn atlas_index(entry: u32, voxel: UVec3, block: u32) -> u32 {
    let local = voxel % block;
    (entry & !SURFACE_FLAG) * block * block * block + local.x + block * (local.y + block * local.z)
}

/// [`grid_index`] for blocks of side `1 << shift`, whose lookup grid is `grid`
/// (`grid_dims(dims, 1 << shift)`): shifts instead of divisions, the same index. WGSL twin:
/// `ddm_grid_index_shifted`.
#[inline]
pub fn grid_index_shifted(voxel: UVec3, grid: UVec3, shift: u32) -> u32 {
    let b = voxel >> shift;
    b.x + grid.x * (b.y + grid.y * b.z)
}

/// [`atlas_index`] for blocks of side `1 << shift`: shifts and masks instead of
/// divisions and products, the same index. WGSL twin: `ddm_atlas_index_shifted`.
#[inline]
pub fn atlas_index_shifted(entry: u32, voxel: UVec3, shift: u32) -> u32 {
    let local = voxel & UVec3::splat((1 << shift) - 1);
    ((((entry & !SURFACE_FLAG) << shift | local.z) << shift | local.y) << shift) | local.x
}

gpu_struct! {
    /// What a shader needs to read a [`CompressedMap`]: its size, block and grid size.
    pub struct CompressedMapUniforms {
        /// `(dims.x, dims.y, dims.z, block)`.
        pub dims_block: UVec4,
        /// `(grid.x, grid.y, grid.z, atlas_base)`: the lookup grid's size, and the index of
        /// the atlas's first word in the buffer it is read from (0 with its own binding).
        pub grid_atlas_base: UVec4,
    }
}

impl CompressedMapUniforms {
    /// The uniforms of `map`, its atlas starting at word `atlas_base`.
    pub fn new(map: &CompressedMap, atlas_base: u32) -> Self {
        let g = grid_dims(map.dims(), map.block());
        Self { dims_block: map.dims().extend(map.block()), grid_atlas_base: g.extend(atlas_base) }
    }
}

#[cfg(test)]
mod tests {
    use alloc::string::ToString;

    use super::*;

    #[test]
    fn shifted_indices_equal_the_divisions() {
        let mut compared = 0;
        for shift in 0..4 {
            let block = 1 << shift;
            let dims = UVec3::new(9, 6, 5);
            let grid = grid_dims(dims, block);
            for entry in [SURFACE_FLAG, SURFACE_FLAG | 1, SURFACE_FLAG | 37] {
                for z in 0..dims.z {
                    for y in 0..dims.y {
                        for x in 0..dims.x {
                            let voxel = UVec3::new(x, y, z);
                            assert_eq!(grid_index_shifted(voxel, grid, shift), grid_index(voxel, dims, block));
                            assert_eq!(atlas_index_shifted(entry, voxel, shift), atlas_index(entry, voxel, block));
                            compared += 1;
                        }
                    }
                }
            }
        }
        assert_eq!(compared, 4 * 3 * 9 * 6 * 5);
    }

    #[test]
    fn a_cell_is_its_voxel_in_a_surface_block_and_the_clipped_block_elsewhere() {
        let dims = UVec3::new(9, 7, 5);
        let n = (dims.x * dims.y * dims.z) as usize;
        let values: Vec<f32> = (0..n).map(|i| 1.0 + (i % 11) as f32).collect();
        let index = |v: UVec3| (v.x + dims.x * (v.y + dims.y * v.z)) as usize;
        // Surface only in the voxel (1, 1, 1).
        let surface: Vec<bool> = (0..n).map(|i| i == index(UVec3::ONE)).collect();
        for block in [1, 2, 3, 4] {
            let map = CompressedMap::compress(&values, &surface, dims, block).unwrap();
            for z in 0..dims.z {
                for y in 0..dims.y {
                    for x in 0..dims.x {
                        let v = UVec3::new(x, y, z);
                        let cell = map.access_cell(v).unwrap();
                        assert_eq!(Some(cell.distance), map.access(v), "block {block} {v}");
                        assert!(v.cmpge(cell.origin).all() && v.cmplt(cell.origin + cell.size).all());
                        assert!((cell.origin + cell.size).cmple(dims).all(), "block {block} {v}: {cell:?}");
                        if cell.size == UVec3::ONE {
                            continue;
                        }
                        // The value bounds every voxel of the cell, and the cell holds no surface.
                        for cz in cell.origin.z..cell.origin.z + cell.size.z {
                            for cy in cell.origin.y..cell.origin.y + cell.size.y {
                                for cx in cell.origin.x..cell.origin.x + cell.size.x {
                                    let w = UVec3::new(cx, cy, cz);
                                    assert!(cell.distance <= values[index(w)] && !surface[index(w)]);
                                }
                            }
                        }
                    }
                }
            }
            // Voxels of the surface block are their own cells; with blocks of 1 all are.
            assert_eq!(map.access_cell(UVec3::ONE).unwrap().size, UVec3::ONE);
            assert_eq!(map.access_cell(dims), None);
            if block == 1 {
                assert_eq!(map.access_cell(UVec3::new(3, 2, 1)).unwrap().size, UVec3::ONE);
            }
        }
    }

    #[test]
    fn the_power_of_two_path_reads_the_same_entries_as_the_generic_indices() {
        let dims = UVec3::new(9, 7, 5);
        let n = (dims.x * dims.y * dims.z) as usize;
        let values: Vec<f32> = (0..n).map(|i| i as f32).collect();
        let surface: Vec<bool> = (0..n).map(|i| i % 3 == 0).collect();
        for block in [1, 2, 3, 4, 5, 8, 16] {
            let map = CompressedMap::compress(&values, &surface, dims, block).unwrap();
            for z in 0..dims.z {
                for y in 0..dims.y {
                    for x in 0..dims.x {
                        let v = UVec3::new(x, y, z);
                        let entry = map.grid[grid_index(v, dims, block) as usize];
                        let expected = if entry & SURFACE_FLAG == 0 {
                            f32::from_bits(entry)
                        } else {
                            map.atlas[atlas_index(entry, v, block) as usize]
                        };
                        assert_eq!(map.access(v).map(f32::to_bits), Some(expected.to_bits()), "block {block}, {v}");
                    }
                }
            }
        }
    }

    #[test]
    fn surface_blocks_are_exact_and_others_conservative() {
        let dims = UVec3::new(5, 4, 3);
        let n = 60;
        let values: Vec<f32> = (0..n).map(|i| (i % 7) as f32 * 0.5).collect();
        let surface: Vec<bool> = (0..n).map(|i| i == 7 || i == 40).collect();
        let map = CompressedMap::compress(&values, &surface, dims, 2).unwrap();
        for z in 0..3 {
            for y in 0..4 {
                for x in 0..5 {
                    let i = (x + 5 * (y + 4 * z)) as usize;
                    let stored = map.access(UVec3::new(x, y, z)).unwrap();
                    let crossed_block = surface.iter().enumerate().any(|(j, &s)| {
                        let (jx, jy, jz) = (j as u32 % 5, (j as u32 / 5) % 4, j as u32 / 20);
                        s && jx / 2 == x / 2 && jy / 2 == y / 2 && jz / 2 == z / 2
                    });
                    if crossed_block {
                        assert_eq!(stored, values[i]);
                    } else {
                        assert!(stored <= values[i]);
                    }
                }
            }
        }
        assert_eq!(map.access(dims), None);
        assert!(map.compression_efficiency() > 1.0);
    }

    #[test]
    fn each_invalid_input_has_its_error() {
        use CompressError::*;
        let dims = UVec3::ONE;
        assert_eq!(CompressedMap::compress(&[1.0], &[false], dims, 0), Err(InvalidBlock { block: 0 }));
        assert_eq!(CompressedMap::compress(&[1.0], &[false], dims, 65), Err(InvalidBlock { block: 65 }));
        assert!(CompressedMap::compress(&[1.0], &[false], dims, MAX_BLOCK).is_ok());
        let flat = UVec3::new(4, 0, 2);
        assert_eq!(CompressedMap::compress(&[], &[], flat, 2), Err(EmptyGrid { dims: flat }));
        let huge = UVec3::new(1 << 16, 1 << 16, 2);
        assert_eq!(CompressedMap::compress(&[], &[], huge, 2), Err(TooManyVoxels { dims: huge }));
        let huge = UVec3::splat(u32::MAX);
        assert_eq!(CompressedMap::compress(&[], &[], huge, 2), Err(TooManyVoxels { dims: huge }));
        assert_eq!(CompressedMap::compress(&[1.0, 2.0], &[false], dims, 1), Err(ValueCount { expected: 1, found: 2 }));
        assert_eq!(CompressedMap::compress(&[1.0], &[], dims, 1), Err(SurfaceCount { expected: 1, found: 0 }));
        let two = UVec3::new(2, 1, 1);
        assert!(matches!(
            CompressedMap::compress(&[0.5, f32::NAN], &[false; 2], two, 1),
            Err(InvalidValue { index: 1, value }) if value.is_nan()
        ));
        assert_eq!(
            CompressedMap::compress(&[-1.0, 0.5], &[false; 2], two, 1),
            Err(InvalidValue { index: 0, value: -1.0 })
        );
        assert_eq!(
            CompressedMap::compress(&[0.5, f32::INFINITY], &[false; 2], two, 1),
            Err(InvalidValue { index: 1, value: f32::INFINITY })
        );
        let message = CompressedMap::compress(&[1.0], &[], dims, 1).unwrap_err().to_string();
        assert!(message.contains("0 surface flags for 1 voxels"), "{message}");
    }
}
