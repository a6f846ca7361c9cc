//! IEEE 754 binary16 ("half") conversions for packed GPU layouts, shared by the crates
//! that store values in 16 bits: round to nearest even ([`f32_to_half`]) or down
//! ([`half_at_most`], for bounds) on the way in, exact on the way out ([`half_to_f32`], as
//! WGSL's `unpack2x16float`). Subnormal halves are never produced, since a GPU may flush
//! them: magnitudes below the smallest normal half (2⁻¹⁴) encode as zero (or, rounding a
//! negative value down, as `−2⁻¹⁴`).

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

/// The bits of the largest binary16 value at most `x` that is not subnormal: **rounded
/// down**, so that a stored bound never exceeds the `f32` one (a conservative distance
/// stays conservative). `x` above [`HALF_MAX`] (finite) → [`HALF_MAX`], ±∞ kept,
/// `0 ≤ x < 2⁻¹⁴` → `+0`, `−2⁻¹⁴ < x < 0` → `−2⁻¹⁴`, NaN → `+0` (where no bound is known,
/// zero is the one that is always safe). The relative loss is below 2⁻¹⁰ in
/// `[2⁻¹⁴, 65504]`, the absolute loss below 2⁻¹⁴ under it.
pub fn half_at_most(x: f32) -> u16 {
    if x.is_nan() {
        return 0;
    }
    let magnitude = match half_magnitude_toward_zero(x.abs()) {
        // A subnormal magnitude: zero, toward which it rounded.
        m if m < 0x0400 => 0,
        m => m,
    };
    // Rounding a magnitude toward zero rounds a positive value down; a negative value
    // rounds down by going one binary16 step away from zero unless it was exact.
    if x >= 0.0 || half_to_f32(magnitude) == x.abs() {
        magnitude | if x < 0.0 { 0x8000 } else { 0 }
    } else if magnitude == 0 {
        // Below zero, the first value that is not subnormal.
        0x8400
    } else {
        0x8000 | (magnitude + 1)
    }
}

/// The binary16 bits (sign clear) of the largest magnitude at most `magnitude` (≥ 0, not
/// NaN), subnormals included.
fn half_magnitude_toward_zero(magnitude: f32) -> u16 {
    if magnitude == f32::INFINITY {
        return 0x7c00;
    }
    if magnitude >= HALF_MAX {
        return 0x7bff;
    }
    let bits = magnitude.to_bits();
    let exponent = ((bits >> 23) & 0xff) as i32 - 127;
    if exponent >= -14 {
        // A normal binary16: its exponent, and the f32 mantissa's top 10 bits (truncated).
        let mantissa = (bits & 0x7f_ffff) >> 13;
        (((exponent + 15) as u32) << 10 | mantissa) as u16
    } else {
        // Zero or subnormal: whole multiples of 2⁻²⁴ (the product is exact, below 2¹⁰).
        (magnitude * 16_777_216.0) as u16
    }
}

#[cfg(test)]
mod tests {
    use half::f16;
    use proptest::prelude::*;

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
            (HALF_MIN_POSITIVE, -HALF_MIN_POSITIVE)
        } else if value == HALF_MIN_POSITIVE {
            (step(bits + 1), 0.0)
        } else if value == -HALF_MIN_POSITIVE {
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
                assert!(half_to_f32(bits).is_nan());
                continue;
            }
            let value = half_to_f32(bits);
            assert_eq!(value.to_bits(), reference.to_f32().to_bits(), "bits {bits:#06x}");
            let bound = half_to_f32(half_at_most(value));
            if storable(bits) {
                assert_eq!(bound, value, "bits {bits:#06x}");
            } else {
                // A subnormal: the storable value below it.
                assert_eq!(bound, if value > 0.0 { 0.0 } else { -HALF_MIN_POSITIVE }, "bits {bits:#06x}");
            }
            compared += 1;
        }
        assert_eq!(compared, 65536 - 2046, "every binary16 value that is not NaN");
    }

    #[test]
    fn values_between_two_binary16_values_round_to_the_lower() {
        let mut compared = 0;
        for bits in (0..=0x7bff_u16).chain(0x8000..=0xfbff).filter(|&b| storable(b)) {
            let value = half_to_f32(bits);
            let (_, lower) = neighbours(bits);
            // The f32 just above a binary16 value rounds to it, the one just below to the
            // binary16 value below it.
            assert_eq!(half_to_f32(half_at_most(value.next_up())), value, "{bits:#06x}");
            assert_eq!(half_to_f32(half_at_most(value.next_down())), lower, "{bits:#06x}");
            compared += 1;
        }
        assert_eq!(compared, 2 * (0x7c00 - 0x0400) + 2, "every finite binary16 value but the subnormals");
        assert_eq!(half_at_most(70_000.0), 0x7bff);
        assert_eq!(half_at_most(f32::INFINITY), 0x7c00);
        assert_eq!(half_at_most(f32::NAN), 0);
        assert_eq!(half_to_f32(half_at_most(-70_000.0)), f32::NEG_INFINITY);
        assert_eq!(half_to_f32(half_at_most(1e-5)), 0.0);
        assert_eq!(half_to_f32(half_at_most(-1e-5)), -HALF_MIN_POSITIVE);
    }

    proptest! {
        /// The bound's defining property on any finite `f32`: at most the value, and the
        /// next binary16 value above it is above the value (it is the largest such).
        #[test]
        fn the_bound_is_the_largest_binary16_value_at_most_the_value(bits in any::<u32>()) {
            let value = f32::from_bits(bits);
            prop_assume!(value.is_finite() && value.abs() < 65504.0);
            let bound = half_at_most(value);
            prop_assert!(half_to_f32(bound) <= value);
            prop_assert!(neighbours(bound).0 > value, "{value:e}: bound {:e}", half_to_f32(bound));
            // Within binary16's precision: a relative 2⁻¹⁰ for normal values, 2⁻¹⁴ absolute below.
            let loss = value - half_to_f32(bound);
            prop_assert!(loss <= (value.abs() / 1024.0).max(HALF_MIN_POSITIVE));
        }
    }
}
