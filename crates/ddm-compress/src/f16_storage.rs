//! Distances stored as IEEE 754 binary16 (`f16`), half the bytes of `f32`, **rounded
//! down** so that a stored distance never exceeds the `f32` one: a conservative map stays
//! conservative (a ray stepping by a smaller distance cannot pass the surface that the
//! larger one already cleared). The relative loss is below 2⁻¹⁰ for distances in
//! `[2⁻¹⁴, 65504]`; distances below 2⁻¹⁴ voxel (6.1·10⁻⁵) are stored as 0, and larger ones
//! as 65504.
//!
//! A GPU reads two values per 32-bit word with WGSL's `unpack2x16float`, exactly for
//! normal binary16 values; subnormals are never stored, since some GPUs flush them to
//! zero. So the CPU reference of an `f16` map is the map of the rounded values
//! ([`CompressedMap::with_f16_atlas`]) and the GPU reads the same numbers bit for bit. The
//! conversions are [`gpu_layout::binary16`]'s ([`half_at_most`], [`half_to_f32`]).

use alloc::vec::Vec;

use gpu_layout::binary16::{half_at_most, half_to_f32};

use crate::compress::CompressedMap;

/// `values` rounded down to binary16 ([`half_at_most`]), two per word: value `2k` in
/// the low half of word `k`, `2k + 1` in the high half (the order of WGSL's
/// `unpack2x16float`); an odd count leaves the last high half zero.
pub fn pack_f16_pairs_at_most(values: &[f32]) -> Vec<u32> {
    values
        .chunks(2)
        .map(|pair| {
            let low = u32::from(half_at_most(pair[0]));
            let high = pair.get(1).map_or(0, |&v| u32::from(half_at_most(v)));
            low | high << 16
        })
        .collect()
}

impl CompressedMap {
    /// This map with every atlas value rounded down to binary16 ([`half_at_most`]),
    /// still held as `f32`: the distances a GPU reads from the atlas packed by
    /// [`pack_f16_pairs_at_most`]. The lookup grid (the blocks without surface) keeps its
    /// `f32` values; every distance is at most the original one.
    pub fn with_f16_atlas(&self) -> Self {
        let atlas = self.atlas().iter().map(|&v| half_to_f32(half_at_most(v))).collect();
        Self::from_checked_parts(self.dims(), self.block(), self.grid().to_vec(), atlas)
    }
}

#[cfg(test)]
mod tests {
    use glam::UVec3;

    use super::*;

    #[test]
    fn pairs_pack_low_half_first() {
        let words = pack_f16_pairs_at_most(&[1.0, 2.0, 0.5]);
        assert_eq!(words, [0x4000_3c00, 0x0000_3800]);
    }

    #[test]
    fn an_f16_atlas_never_raises_a_distance_and_keeps_the_grid() {
        let dims = UVec3::new(4, 4, 4);
        let values: Vec<f32> = (0..64).map(|i| 0.1 * i as f32 + 1.0 / 3.0).collect();
        let surface: Vec<bool> = (0..64).map(|i| i < 16).collect();
        let map = CompressedMap::compress(&values, &surface, dims, 2).unwrap();
        let rounded = map.with_f16_atlas();
        assert_eq!(rounded.grid(), map.grid());
        let mut lowered = 0;
        for (r, v) in rounded.atlas().iter().zip(map.atlas()) {
            assert!(r <= v && v - r <= v / 1024.0, "{r} > {v}");
            lowered += usize::from(r < v);
        }
        assert!(lowered > 0, "1/3 + 0.1 i is not a binary16 value");
    }
}
