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
//! ([`CompressedMap::with_f16_atlas`]) and the GPU reads the same numbers bit for bit.

use alloc::vec::Vec;

use crate::compress::CompressedMap;

/// Bits of binary16's largest finite value, 65504.
const F16_MAX_BITS: u16 = 0x7bff;
/// Bits of binary16's positive infinity.
const F16_INFINITY_BITS: u16 = 0x7c00;
/// 2⁻²⁴, binary16's smallest subnormal.
const F16_SUBNORMAL_STEP: f32 = 1.0 / 16_777_216.0;
/// 2⁻¹⁴, binary16's smallest normal value.
pub const F16_MIN_NORMAL: f32 = 1.0 / 16_384.0;

/// The bits of the largest binary16 value that is at most `value` and not subnormal: the
/// largest positive one (65504) where `value` is finite and larger, infinities kept, `+0`
/// for `0 ≤ value < 2⁻¹⁴` and `-2⁻¹⁴` for `-2⁻¹⁴ < value < 0`. NaN gives `+0`: where no
/// bound is known, zero is the one that is always safe.
pub fn f16_bits_at_most(value: f32) -> u16 {
    if value.is_nan() {
        return 0;
    }
    let magnitude = match f16_magnitude_toward_zero(value.abs()) {
        // A subnormal magnitude: zero, toward which it rounded.
        m if m < 0x0400 => 0,
        m => m,
    };
    // Rounding a magnitude toward zero rounds a positive value down; a negative value
    // rounds down by going one binary16 step away from zero unless it was exact.
    if value >= 0.0 || f16_bits_to_f32(magnitude) == value.abs() {
        magnitude | if value < 0.0 { 0x8000 } else { 0 }
    } else if magnitude == 0 {
        // Below zero, the first value that is not subnormal.
        0x8400
    } else {
        0x8000 | (magnitude + 1)
    }
}

/// The binary16 bits (sign clear) of the largest magnitude at most `magnitude` (≥ 0, not NaN).
fn f16_magnitude_toward_zero(magnitude: f32) -> u16 {
    if magnitude == f32::INFINITY {
        return F16_INFINITY_BITS;
    }
    if magnitude >= 65504.0 {
        return F16_MAX_BITS;
    }
    let bits = magnitude.to_bits();
    let exponent = ((bits >> 23) & 0xff) as i32 - 127;
    if exponent >= -14 {
        // A normal binary16: its exponent, and the f32 mantissa's top 10 bits (truncated).
        let mantissa = (bits & 0x7f_ffff) >> 13;
        (((exponent + 15) as u32) << 10 | mantissa) as u16
    } else {
        // Zero or subnormal: whole multiples of 2⁻²⁴ (the product is exact, below 2¹⁰).
        (magnitude / F16_SUBNORMAL_STEP) as u16
    }
}

/// The value of binary16 `bits`, exactly (every binary16 value is an `f32`). WGSL twin:
/// one half of `unpack2x16float`.
pub fn f16_bits_to_f32(bits: u16) -> f32 {
    let sign = u32::from(bits & 0x8000) << 16;
    let exponent = u32::from(bits >> 10) & 0x1f;
    let mantissa = u32::from(bits & 0x3ff);
    let magnitude = match exponent {
        0 => mantissa as f32 * F16_SUBNORMAL_STEP,
        0x1f if mantissa == 0 => f32::INFINITY,
        0x1f => f32::NAN,
        _ => f32::from_bits((exponent + 127 - 15) << 23 | mantissa << 13),
    };
    f32::from_bits(magnitude.to_bits() | sign)
}

/// `values` rounded down to binary16 ([`f16_bits_at_most`]), two per word: value `2k` in
/// the low half of word `k`, `2k + 1` in the high half (the order of WGSL's
/// `unpack2x16float`); an odd count leaves the last high half zero.
pub fn pack_f16_pairs_at_most(values: &[f32]) -> Vec<u32> {
    values
        .chunks(2)
        .map(|pair| {
            let low = u32::from(f16_bits_at_most(pair[0]));
            let high = pair.get(1).map_or(0, |&v| u32::from(f16_bits_at_most(v)));
            low | high << 16
        })
        .collect()
}

impl CompressedMap {
    /// This map with every atlas value rounded down to binary16 ([`f16_bits_at_most`]),
    /// still held as `f32`: the distances a GPU reads from the atlas packed by
    /// [`pack_f16_pairs_at_most`]. The lookup grid (the blocks without surface) keeps its
    /// `f32` values; every distance is at most the original one.
    pub fn with_f16_atlas(&self) -> Self {
        let atlas = self.atlas().iter().map(|&v| f16_bits_to_f32(f16_bits_at_most(v))).collect();
        Self::from_checked_parts(self.dims(), self.block(), self.grid().to_vec(), atlas)
    }
}

#[cfg(test)]
mod tests {
    use glam::UVec3;
    use half::f16;
    use proptest::prelude::*;

    use super::*;

    /// Whether binary16 `bits` can be stored: not NaN, not subnormal.
    fn storable(bits: u16) -> bool {
        let value = f16::from_bits(bits);
        !value.is_nan() && (value.is_normal() || value.is_infinite() || value == f16::ZERO)
    }

    /// The storable binary16 neighbours of finite storable `bits`: the next value above and
    /// below (zero's are ±2⁻¹⁴).
    fn neighbours(bits: u16) -> (f32, f32) {
        let step = |b: u16| f16::from_bits(b).to_f32();
        let value = step(bits);
        if value == 0.0 {
            (F16_MIN_NORMAL, -F16_MIN_NORMAL)
        } else if value == F16_MIN_NORMAL {
            (step(bits + 1), 0.0)
        } else if value == -F16_MIN_NORMAL {
            (0.0, step(bits + 1))
        } else if value > 0.0 {
            (step(bits + 1), step(bits - 1))
        } else {
            (step(bits - 1), step(bits + 1))
        }
    }

    #[test]
    fn every_binary16_value_converts_exactly_and_is_its_own_bound() {
        let mut compared = 0;
        for bits in 0..=u16::MAX {
            let reference = f16::from_bits(bits);
            if reference.is_nan() {
                assert!(f16_bits_to_f32(bits).is_nan());
                continue;
            }
            let value = f16_bits_to_f32(bits);
            assert_eq!(value.to_bits(), reference.to_f32().to_bits(), "bits {bits:#06x}");
            let bound = f16_bits_to_f32(f16_bits_at_most(value));
            if storable(bits) {
                assert_eq!(bound, value, "bits {bits:#06x}");
            } else {
                // A subnormal: the storable value below it.
                assert_eq!(bound, if value > 0.0 { 0.0 } else { -F16_MIN_NORMAL }, "bits {bits:#06x}");
            }
            compared += 1;
        }
        assert_eq!(compared, 65536 - 2046, "every binary16 value that is not NaN");
    }

    #[test]
    fn values_between_two_binary16_values_round_to_the_lower() {
        let mut compared = 0;
        for bits in (0..=0x7bff_u16).chain(0x8000..=0xfbff).filter(|&b| storable(b)) {
            let value = f16_bits_to_f32(bits);
            let (_, lower) = neighbours(bits);
            // The f32 just above a binary16 value rounds to it, the one just below to the
            // binary16 value below it.
            assert_eq!(f16_bits_to_f32(f16_bits_at_most(value.next_up())), value, "{bits:#06x}");
            assert_eq!(f16_bits_to_f32(f16_bits_at_most(value.next_down())), lower, "{bits:#06x}");
            compared += 1;
        }
        assert_eq!(compared, 2 * (0x7c00 - 0x0400) + 2, "every finite binary16 value but the subnormals");
        assert_eq!(f16_bits_at_most(70_000.0), F16_MAX_BITS);
        assert_eq!(f16_bits_at_most(f32::INFINITY), F16_INFINITY_BITS);
        assert_eq!(f16_bits_at_most(f32::NAN), 0);
        assert_eq!(f16_bits_to_f32(f16_bits_at_most(-70_000.0)), f32::NEG_INFINITY);
        assert_eq!(f16_bits_to_f32(f16_bits_at_most(1e-5)), 0.0);
        assert_eq!(f16_bits_to_f32(f16_bits_at_most(-1e-5)), -F16_MIN_NORMAL);
    }

    proptest! {
        /// The bound's defining property on any finite `f32`: at most the value, and the
        /// next binary16 value above it is above the value (it is the largest such).
        #[test]
        fn the_bound_is_the_largest_binary16_value_at_most_the_value(bits in any::<u32>()) {
            let value = f32::from_bits(bits);
            prop_assume!(value.is_finite() && value.abs() < 65504.0);
            let bound = f16_bits_at_most(value);
            prop_assert!(f16_bits_to_f32(bound) <= value);
            prop_assert!(neighbours(bound).0 > value, "{value:e}: bound {:e}", f16_bits_to_f32(bound));
            // Within binary16's precision: a relative 2⁻¹⁰ for normal values, 2⁻¹⁴ absolute below.
            let loss = value - f16_bits_to_f32(bound);
            prop_assert!(loss <= (value.abs() / 1024.0).max(F16_MIN_NORMAL));
        }
    }

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
