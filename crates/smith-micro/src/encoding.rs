//! How the crate's results cross the CPU/GPU boundary: as bits.
//!
//! WGSL has no `Option` and WGSL implementations may assume that no NaN or infinity
//! reaches float operations, so the WGSL twin carries a result as a value and a kind
//! (finite, none, ±∞) and writes it out as bits: [`encode`] (WGSL `smith_encode`) maps
//! `None` to [`NONE_BITS`] (a NaN, which no function of this crate returns) and every
//! other value, ±∞ included, to its own bits.

/// The bits that stand for `None` in GPU results: the canonical quiet NaN.
pub const NONE_BITS: u32 = 0x7fc0_0000;

/// `value`'s bits, or [`NONE_BITS`] for `None` (WGSL twin: `smith_encode`).
pub fn encode(value: Option<f32>) -> u32 {
    value.map_or(NONE_BITS, f32::to_bits)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encoding_keeps_every_value_and_marks_none() {
        assert_eq!(encode(None), NONE_BITS);
        assert!(f32::from_bits(NONE_BITS).is_nan());
        assert_eq!(encode(Some(f32::INFINITY)), f32::INFINITY.to_bits());
        assert_eq!(encode(Some(-0.0)), (-0.0_f32).to_bits());
        assert_eq!(encode(Some(0.5)), 0.5_f32.to_bits());
    }
}
