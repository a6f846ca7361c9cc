//! The bit layout of an IEEE 754 `f32`, for classifying floats with integer tests.
//!
//! WGSL implementations may assume that no NaN or infinity reaches a float operation, so
//! the WGSL twins classify inputs by their bits; the Rust references do the same with the
//! same masks, and each crate generates them into its WGSL (prefixed, since WGSL has one
//! namespace) instead of writing the numbers twice.

/// Every bit but the sign: `bits & ABS_MASK` is the magnitude's bits.
pub const ABS_MASK: u32 = 0x7fff_ffff;
/// The sign bit.
pub const SIGN_MASK: u32 = 0x8000_0000;
/// The bits of `+∞`, which are also the exponent mask: a magnitude above it is a NaN, equal
/// to it is ±∞, and a value whose exponent bits are all zero is zero or subnormal.
pub const INFINITY_BITS: u32 = 0x7f80_0000;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn masks_match_the_standard_library() {
        assert_eq!(INFINITY_BITS, f32::INFINITY.to_bits());
        assert_eq!(SIGN_MASK, (-0.0_f32).to_bits());
        assert_eq!(ABS_MASK, !SIGN_MASK);
        assert!(f32::from_bits(INFINITY_BITS + 1).is_nan());
    }
}
