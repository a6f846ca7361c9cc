//! The canonical form of an input direction.
//!
//! Listing 1 of the paper divides the direction by its L1 norm, which is undefined for the
//! zero vector and for NaN or infinite components, and which overflows for huge finite
//! vectors. [`canonical_direction`] gives every `Vec3` a defined, finite image with the
//! same direction, using only operations that are exact on both the CPU and the GPU
//! (bit tests, comparisons, multiplication by a power of two), so that the WGSL twin
//! (`octahedral_canonical_direction`) agrees bit for bit.

use glam::Vec3;
use gpu_layout::f32_bits::{ABS_MASK, INFINITY_BITS};

/// The direction used when the input has no direction: the zero vector, any NaN
/// component, or every component subnormal. It is the pole of the lower hemisphere.
pub const FALLBACK_DIRECTION: Vec3 = Vec3::NEG_Z;

/// The bits of `2⁻⁶³`, the smallest nonzero magnitude of a plain direction's component
/// (see [`is_plain_direction`]).
pub(crate) const PLAIN_MIN_BITS: u32 = (127 - 63) << 23;
/// The bits of `2⁶⁴`, the magnitude that every component of a plain direction stays below.
pub(crate) const PLAIN_END_BITS: u32 = (127 + 64) << 23;

/// Whether `direction` is *plain*: not zero, and every component either `±0` or of
/// magnitude in `[2⁻⁶³, 2⁶⁴)`. One test on the bits classifies every special input
/// (NaN, ±∞, zero, subnormal, huge or tiny) as not plain.
///
/// A plain direction needs no [`canonical_direction`] before Listing 1: its nonzero
/// biased exponents lie in `64..=190`, so the power of two that the canonical form
/// multiplies by makes no component subnormal (`64 + 128 - 190 ≥ 1`) and nothing is
/// flushed; sums of up to six magnitudes stay below `2¹²⁸`, and sums of nonzero magnitudes
/// stay normal. Every rounding in the lookup then commutes with that power of two, and its
/// ratios are bit for bit those of the canonical form.
pub(crate) fn is_plain_direction(direction: Vec3) -> bool {
    let magnitudes = direction.to_array().map(|c| c.to_bits() & ABS_MASK);
    // `m - MIN < END - MIN` (wrapping) is `MIN ≤ m < END` in one comparison.
    let in_range = magnitudes.map(|m| m.wrapping_sub(PLAIN_MIN_BITS) < PLAIN_END_BITS - PLAIN_MIN_BITS);
    let each = (in_range[0] | (magnitudes[0] == 0))
        & (in_range[1] | (magnitudes[1] == 0))
        & (in_range[2] | (magnitudes[2] == 0));
    each & (in_range[0] | in_range[1] | in_range[2])
}

/// Replaces a subnormal value (biased exponent 0) by `+0.0`, as GPUs may (WGSL allows
/// flushing subnormals to zero).
fn flush_subnormal(x: f32) -> f32 {
    if x.to_bits() & INFINITY_BITS == 0 { 0.0 } else { x }
}

/// Returns a finite vector with the direction of `direction`, its largest component in
/// magnitude in `[2, 4)`, or [`FALLBACK_DIRECTION`].
///
/// | input | result |
/// |---|---|
/// | any component NaN | [`FALLBACK_DIRECTION`] |
/// | some component ±∞ (none NaN) | ±1 for each infinite component, 0 for the finite ones |
/// | zero, or all components subnormal | [`FALLBACK_DIRECTION`] |
/// | otherwise | the input times a power of two, subnormal components flushed to 0 |
///
/// Subnormal components are flushed to zero before and after scaling because GPUs may
/// flush them; doing it on the CPU too keeps both twins equal.
pub fn canonical_direction(direction: Vec3) -> Vec3 {
    let bits = direction.to_array().map(|c| c.to_bits() & ABS_MASK);
    if bits.iter().any(|&b| b > INFINITY_BITS) {
        return FALLBACK_DIRECTION;
    }
    if bits.contains(&INFINITY_BITS) {
        return direction.map(|c| if c.to_bits() & ABS_MASK == INFINITY_BITS { c.signum() } else { 0.0 });
    }
    let flushed = direction.map(flush_subnormal);
    let largest = flushed.abs().max_element();
    if largest == 0.0 {
        return FALLBACK_DIRECTION;
    }
    // `largest` is normal: its biased exponent e is in 1..=254. Multiplying by 2^(128 - e)
    // is exact and brings it into [2, 4); the scale's biased exponent 255 - e stays normal.
    let exponent = (largest.to_bits() >> 23) & 0xff;
    let scale = f32::from_bits((255 - exponent) << 23);
    (flushed * scale).map(flush_subnormal)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn special_inputs_have_defined_results() {
        assert_eq!(canonical_direction(Vec3::ZERO), FALLBACK_DIRECTION);
        assert_eq!(canonical_direction(Vec3::new(f32::NAN, 1.0, 0.0)), FALLBACK_DIRECTION);
        assert_eq!(canonical_direction(Vec3::new(f32::INFINITY, 5.0, f32::NEG_INFINITY)), Vec3::new(1.0, 0.0, -1.0));
        let subnormal = f32::from_bits(1);
        assert_eq!(canonical_direction(Vec3::splat(subnormal)), FALLBACK_DIRECTION);
        let huge = f32::from_bits(254 << 23); // 2^127
        assert_eq!(canonical_direction(Vec3::new(huge, -huge, 0.0)), Vec3::new(2.0, -2.0, 0.0));
        let largest = canonical_direction(Vec3::new(f32::MAX, f32::MAX, f32::MAX));
        assert_eq!(largest, Vec3::splat(f32::MAX * 2.0_f32.powi(-126)));
    }

    #[test]
    fn plain_directions_are_classified_by_their_bits() {
        let (min, end) = (f32::from_bits(PLAIN_MIN_BITS), f32::from_bits(PLAIN_END_BITS));
        assert_eq!((min, end), (2.0_f32.powi(-63), 2.0_f32.powi(64)));
        for plain in [
            Vec3::X,
            Vec3::new(-0.0, 0.0, -3.0),
            Vec3::new(0.3, -0.7, 0.2),
            Vec3::splat(min),
            Vec3::splat(-end.next_down()),
        ] {
            assert!(is_plain_direction(plain), "{plain}");
        }
        let special = [
            Vec3::ZERO,
            Vec3::new(-0.0, 0.0, -0.0),
            Vec3::new(1.0, f32::NAN, 0.0),
            Vec3::new(f32::INFINITY, 1.0, 0.0),
            Vec3::new(0.0, 0.0, f32::NEG_INFINITY),
            Vec3::new(1.0, f32::from_bits(1), 0.0),
            Vec3::new(1.0, min.next_down(), 0.0),
            Vec3::new(-end, 1.0, 0.0),
            Vec3::new(1.0, 1.0, f32::MAX),
        ];
        for d in special {
            assert!(!is_plain_direction(d), "{d}");
        }
    }

    #[test]
    fn scaling_keeps_the_direction_exactly() {
        for v in [Vec3::new(3.0, -1.5, 0.25), Vec3::new(1e-30, 2e-30, -7e-31), Vec3::new(1e30, 0.0, 5e29)] {
            let c = canonical_direction(v);
            assert!((2.0..4.0).contains(&c.abs().max_element()));
            let ratio = c.x / v.x;
            assert_eq!(c, v * ratio);
        }
    }
}
