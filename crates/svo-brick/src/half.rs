//! IEEE 754 binary16 conversions for the packed layouts: round-to-nearest-even on the way
//! in, exact on the way out (as WGSL's `unpack2x16float`). Subnormal halves are never
//! produced, since a GPU may flush them: magnitudes below the smallest normal half
//! (2⁻¹⁴) encode as zero.

/// The smallest positive normal binary16 value, `2⁻¹⁴`.
pub const HALF_MIN_POSITIVE: f32 = 6.103_515_6e-5;

/// The largest finite binary16 value, 65504.
pub const HALF_MAX: f32 = 65504.0;

/// `x` as binary16 bits, rounded to nearest even; NaN → 0, magnitudes above
/// [`HALF_MAX`] (and ±∞) → ±[`HALF_MAX`], below [`HALF_MIN_POSITIVE`] → ±0.
pub fn f32_to_half(x: f32) -> u16 {
    if x.is_nan() {
        return 0;
    }
    let bits = x.to_bits();
    let sign = ((bits >> 16) & 0x8000) as u16;
    let magnitude = f32::from_bits(bits & 0x7fff_ffff);
    if magnitude < HALF_MIN_POSITIVE {
        return sign;
    }
    if magnitude >= HALF_MAX {
        return sign | 0x7bff;
    }
    let m = magnitude.to_bits();
    let exponent = (m >> 23) as i32 - 127 + 15; // 1 ..= 30
    let mantissa = m & 0x007f_ffff;
    // Keep 10 of the 23 mantissa bits, rounding to nearest even; a carry out of the
    // mantissa correctly increments the exponent.
    let kept = mantissa >> 13;
    let rest = mantissa & 0x1fff;
    let mut half = ((exponent as u32) << 10) | kept;
    if rest > 0x1000 || (rest == 0x1000 && kept & 1 == 1) {
        half += 1;
    }
    // Rounding can reach 65520 → clamp to the largest finite value.
    sign | (half.min(0x7bff) as u16)
}

/// The binary16 `bits` as `f32` (exact); subnormal halves decode exactly too.
pub fn half_to_f32(bits: u16) -> f32 {
    let sign = u32::from(bits & 0x8000) << 16;
    let exponent = u32::from((bits >> 10) & 0x1f);
    let mantissa = u32::from(bits & 0x3ff);
    let magnitude = match exponent {
        0 => mantissa as f32 * (1.0 / 16_777_216.0), // 2⁻²⁴ per step
        31 => {
            if mantissa == 0 {
                f32::INFINITY
            } else {
                f32::NAN
            }
        }
        _ => f32::from_bits(((exponent + 127 - 15) << 23) | (mantissa << 13)),
    };
    f32::from_bits(magnitude.to_bits() | sign)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_normal_half_round_trips_exactly() {
        for bits in 0..0x7c00_u16 {
            let x = half_to_f32(bits);
            let expected = if x < HALF_MIN_POSITIVE { 0 } else { bits };
            assert_eq!(f32_to_half(x), expected, "{bits:#06x} = {x}");
            assert_eq!(f32_to_half(-x), expected | 0x8000);
        }
    }

    #[test]
    fn rounding_is_to_nearest_even_within_half_an_ulp() {
        for k in 0..20_000 {
            let x = 1e-4 + k as f32 * 3.27;
            let back = half_to_f32(f32_to_half(x));
            // Half an ulp of binary16: 2^(e − 11) relative to the binade.
            let ulp = f32::from_bits((x.to_bits() & 0x7f80_0000) - (10 << 23));
            assert!((back - x).abs() <= 0.5 * ulp, "{x} → {back}");
        }
        assert_eq!(f32_to_half(1.0 + 1.0 / 2048.0), 0x3c00); // tie → even
        assert_eq!(f32_to_half(1.0 + 3.0 / 2048.0), 0x3c02);
        assert_eq!(f32_to_half(1e9), 0x7bff);
        assert_eq!(f32_to_half(f32::NAN), 0);
        assert_eq!(f32_to_half(1e-6), 0);
    }
}
