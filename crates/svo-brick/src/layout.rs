//! The two packed GPU forms of a [`Voxel`] and their decoding (§5.2, "Memory footprint").
//!
//! | field | [`VoxelLayout::Paper20`] | [`VoxelLayout::Compact16`] | [`VoxelLayout::Compact16Fine8`], finest level |
//! |---|---|---|---|
//! | `h̄` | `f32` (finest-voxel units) | `snorm16`: `h̄ / S_L` in `[−32, 32)`, step `2⁻¹⁰` | as `Compact16` |
//! | `σh²` | `f16` | `f16` of `σh² / S_L²` | — (0) |
//! | `n̄` | octahedral `2 × u16` | octahedral `2 × u16` | octahedral `2 × 12` bits |
//! | `σn²` | `f16` | `f16` | — (0) |
//! | `ā`, `a_s` (RGB) | `6 × u8` | `6 × u8` | `ā`: `3 × u8`; `a_s` — (0) |
//! | bytes | 20 (18 used) | 16 | 8 (16 above the finest level) |
//!
//! `S_L = 2^L` is the voxel size of level `L` in finest voxels. Every decode is exact
//! arithmetic on codes (integer subtractions, products by powers of two, bit
//! reinterpretation of halves), so that the quadrilinear interpolation that follows can
//! be proven contraction-proof ([`crate::sample`]); the scales that are not powers of two
//! (`1/255`, `1/127`, the world voxel size) are applied once, after interpolation.
//!
//! # Round-trip error (each bounded by a test)
//!
//! - `h̄`: exact in `Paper20` (subnormals flush to 0); in `Compact16` within `2^(L−11)`
//!   (half a step) inside `±32 S_L`, clamped outside (the decoded magnitude is then
//!   `≥ 32 S_L − 2^(L−10)`: still a valid lower bound for empty-space skipping).
//! - `σh²`, `σn²`: within half a binary16 ulp (`2⁻¹¹` relative) in `[2⁻¹⁴, 65504]`,
//!   below `2⁻¹⁴` → 0 (GPUs may flush subnormal halves), above → 65504.
//! - `n̄`: the direction within `3√2 · 2⁻¹⁵ ≈ 1.3·10⁻⁴` rad: each octahedral coordinate is
//!   quantised to `2⁻¹⁵` (error ≤ 2⁻¹⁵, the code for +1 being `1 − 2⁻¹⁵`); the unnormalised
//!   decoded vector `(u, v, 1 − |u| − |v|)` then moves by at most `√6 · 2⁻¹⁵`, and its length
//!   is at least `1/√3`. With 12 bits (`Compact16Fine8`'s finest level), `3√2 · 2⁻¹¹ ≈
//!   2.1·10⁻³` rad. Its length `|n̄|` is not stored.
//! - `Compact16Fine8`'s finest level drops `σh²`, `σn²` and `a_s`, which are zero there by
//!   construction (§5.2).
//! - `ā`: clamped to `[0, 1]`, within `1/510`; `a_s`: clamped to `[−1, 1]`, within `1/254`.

use glam::Vec3;

use crate::descriptor::{ATTRIBUTE_CHANNELS, Voxel};
use crate::half::{f32_to_half, half_to_f32};

/// The most `u32` words a voxel takes ([`VoxelLayout::Paper20`]).
pub const MAX_VOXEL_WORDS: usize = 5;

/// `Compact16` stores `h̄ / S_L` with this many steps per level voxel (`2¹⁰`).
pub const COMPACT_DISTANCE_STEPS: f32 = 1024.0;

/// `Compact16` clamps `|h̄| / S_L` to this range (32 level voxels, beyond any brick).
pub const COMPACT_DISTANCE_RANGE: f32 = 32.0;

/// How a voxel is packed for the GPU.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum VoxelLayout {
    /// The paper's precision (§5.2): `h̄` in `f32`, the rest in 16 and 8 bits; 20 bytes.
    Paper20,
    /// 16 bytes: `h̄` relative to the level's voxel size in 16 bits.
    Compact16,
    /// `Compact16` above the finest level, 8 bytes at the finest level, where every
    /// variance and `a_s` is zero (§5.2: "possibly less at the deepest level where
    /// `σp² = 0`"): `h̄` as in `Compact16`, `n̄` octahedral in `2 × 12` bits, `ā` in `3 × u8`.
    /// Three quarters of a tree's bricks are at the finest level.
    Compact16Fine8,
}

impl VoxelLayout {
    /// Every layout.
    pub const ALL: [VoxelLayout; 3] = [VoxelLayout::Paper20, VoxelLayout::Compact16, VoxelLayout::Compact16Fine8];

    /// `u32` words per voxel above the finest level (the most a voxel takes).
    pub const fn words(self) -> usize {
        match self {
            VoxelLayout::Paper20 => 5,
            VoxelLayout::Compact16 | VoxelLayout::Compact16Fine8 => 4,
        }
    }

    /// `u32` words per voxel of level `level`.
    pub const fn words_at(self, level: u32) -> usize {
        match self {
            VoxelLayout::Compact16Fine8 if level == 0 => 2,
            _ => self.words(),
        }
    }

    /// Bytes per voxel above the finest level.
    pub const fn bytes(self) -> usize {
        4 * self.words()
    }

    /// Bytes per voxel of level `level`.
    pub const fn bytes_at(self, level: u32) -> usize {
        4 * self.words_at(level)
    }

    /// The layout's index on the GPU (`OctreeUniforms::layout`).
    pub const fn index(self) -> u32 {
        match self {
            VoxelLayout::Paper20 => 0,
            VoxelLayout::Compact16 => 1,
            VoxelLayout::Compact16Fine8 => 2,
        }
    }

    /// A short name for tables.
    pub const fn name(self) -> &'static str {
        match self {
            VoxelLayout::Paper20 => "paper20",
            VoxelLayout::Compact16 => "compact16",
            VoxelLayout::Compact16Fine8 => "compact16-fine8",
        }
    }

    /// Packs `voxel` (finest-voxel units) of level `level` into the first
    /// [`words_at(level)`](Self::words_at) of the result.
    pub fn encode(self, voxel: &Voxel, level: u32) -> [u32; MAX_VOXEL_WORDS] {
        if self == VoxelLayout::Compact16Fine8 && level == 0 {
            let distance = compact_distance(voxel.distance, 0);
            let [u, v] = octahedral_codes(voxel.normal, 12);
            let a = voxel.attribute.map(unorm8);
            return [distance | u << 16 | (v & 0xf) << 28, v >> 4 | a[0] << 8 | a[1] << 16 | a[2] << 24, 0, 0, 0];
        }
        let layout = if self == VoxelLayout::Compact16Fine8 { VoxelLayout::Compact16 } else { self };
        let [u, v] = octahedral_codes(voxel.normal, 16);
        let a = voxel.attribute.map(unorm8);
        let s = voxel.correlation.map(snorm8);
        let half = |x: f32| u32::from(f32_to_half(x));
        match layout {
            VoxelLayout::Paper20 => {
                let distance = if voxel.distance.is_normal() { voxel.distance } else { 0.0 };
                [
                    distance.to_bits(),
                    half(voxel.distance_variance) | half(voxel.slope_variance) << 16,
                    u | v << 16,
                    a[0] | a[1] << 8 | a[2] << 16 | s[0] << 24,
                    s[1] | s[2] << 8,
                ]
            }
            _ => {
                let scale = level_scale(level);
                let distance = compact_distance(voxel.distance, level);
                let variance = voxel.distance_variance / (scale * scale);
                [
                    distance | half(variance) << 16,
                    u | v << 16,
                    half(voxel.slope_variance) | a[0] << 16 | a[1] << 24,
                    a[2] | s[0] << 8 | s[1] << 16 | s[2] << 24,
                    0,
                ]
            }
        }
    }

    /// The voxel of level `level` packed in `words`, decoded to the interpolation's exact
    /// intermediate form.
    pub fn decode_raw(self, words: &[u32], level: u32) -> RawVoxel {
        let byte = |w: u32, k: u32| ((w >> (8 * k)) & 0xff) as f32;
        if self == VoxelLayout::Compact16Fine8 && level == 0 {
            let u = (words[0] >> 16) & 0xfff;
            let v = (words[0] >> 28) | (words[1] & 0xff) << 4;
            return RawVoxel {
                distance: ((words[0] & 0xffff) as f32 - 32768.0) * (1.0 / COMPACT_DISTANCE_STEPS),
                distance_variance: 0.0,
                normal: octahedral_decode_bits(u, v, 12),
                slope_variance: 0.0,
                attribute: [byte(words[1], 1), byte(words[1], 2), byte(words[1], 3)],
                correlation: [0.0; ATTRIBUTE_CHANNELS],
            };
        }
        let half_lo = |w: u32| half_to_f32(w as u16);
        let half_hi = |w: u32| half_to_f32((w >> 16) as u16);
        let signed = |w: u32, k: u32| byte(w, k) - 128.0;
        match self {
            VoxelLayout::Paper20 => RawVoxel {
                distance: f32::from_bits(words[0]),
                distance_variance: half_lo(words[1]),
                normal: octahedral_decode(words[2]),
                slope_variance: half_hi(words[1]),
                attribute: [byte(words[3], 0), byte(words[3], 1), byte(words[3], 2)],
                correlation: [signed(words[3], 3), signed(words[4], 0), signed(words[4], 1)],
            },
            VoxelLayout::Compact16 | VoxelLayout::Compact16Fine8 => {
                let scale = level_scale(level);
                let step = scale * (1.0 / COMPACT_DISTANCE_STEPS);
                RawVoxel {
                    distance: ((words[0] & 0xffff) as f32 - 32768.0) * step,
                    distance_variance: half_hi(words[0]) * (scale * scale),
                    normal: octahedral_decode(words[1]),
                    slope_variance: half_lo(words[2]),
                    attribute: [byte(words[2], 2), byte(words[2], 3), byte(words[3], 0)],
                    correlation: [signed(words[3], 1), signed(words[3], 2), signed(words[3], 3)],
                }
            }
        }
    }

    /// [`encode`](Self::encode) then decode: what the GPU sees of `voxel`.
    pub fn round_trip(self, voxel: &Voxel, level: u32) -> Voxel {
        self.decode_raw(&self.encode(voxel, level), level).finish()
    }
}

/// A decoded voxel before the final scales: `h̄` and `σh²` in finest-voxel units, `n̄` as
/// the unnormalised octahedral vector (`|x| + |y| + |z| = 1`), attributes as codes
/// (`ā·255`, `a_s·127`). Every field is an exact function of the codes, the same bits on
/// the CPU and in WGSL.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RawVoxel {
    /// `h̄`, finest-voxel units.
    pub distance: f32,
    /// `σh²`, finest-voxel units².
    pub distance_variance: f32,
    /// `n̄` up to its length (octahedral, L1-normalised).
    pub normal: Vec3,
    /// `σn²`.
    pub slope_variance: f32,
    /// `255 ā` per channel.
    pub attribute: [f32; ATTRIBUTE_CHANNELS],
    /// `127 a_s` per channel.
    pub correlation: [f32; ATTRIBUTE_CHANNELS],
}

impl RawVoxel {
    /// The voxel in finest-voxel units: attributes scaled, `n̄` normalised (a zero `n̄` stays
    /// zero).
    pub fn finish(self) -> Voxel {
        Voxel {
            distance: self.distance,
            distance_variance: self.distance_variance,
            normal: self.normal.normalize_or_zero(),
            slope_variance: self.slope_variance,
            attribute: self.attribute.map(|a| a * (1.0 / 255.0)),
            correlation: self.correlation.map(|s| s * (1.0 / 127.0)),
        }
    }
}

/// `S_L = 2^L` as `f32` (exact).
pub(crate) fn level_scale(level: u32) -> f32 {
    f32::from_bits((127 + level.min(127)) << 23)
}

/// `2^−L` as `f32`, built from its bits (a WGSL division need not be exact).
pub(crate) fn level_inverse_scale(level: u32) -> f32 {
    f32::from_bits((127 - level.min(126)) << 23)
}

fn unorm8(x: f32) -> u32 {
    if x.is_nan() { 0 } else { libm::roundf(x.clamp(0.0, 1.0) * 255.0) as u32 }
}

fn snorm8(x: f32) -> u32 {
    if x.is_nan() { 128 } else { (libm::roundf(x.clamp(-1.0, 1.0) * 127.0) as i32 + 128) as u32 }
}

/// `h̄ / S_L` as `Compact16`'s offset 16-bit code.
fn compact_distance(distance: f32, level: u32) -> u32 {
    let relative = distance / level_scale(level) * COMPACT_DISTANCE_STEPS;
    let code = if relative.is_nan() { 0.0 } else { libm::roundf(relative) };
    (code.clamp(-32768.0, 32767.0) as i32 + 32768) as u32
}

/// The `bits`-bit octahedral codes of the direction of `n` (Meyer et al. 2010's map; any
/// length, a zero or non-finite `n` → `+z`): each coordinate in `[−1, 1)` with step
/// `2^(1 − bits)`.
fn octahedral_codes(n: Vec3, bits: u32) -> [u32; 2] {
    let half = (1u32 << (bits - 1)) as f32;
    let l1 = libm::fabsf(n.x) + libm::fabsf(n.y) + libm::fabsf(n.z);
    if !l1.is_finite() || l1 <= 0.0 {
        return [half as u32, half as u32];
    }
    let p = n / l1;
    let (u, v) = if p.z >= 0.0 {
        (p.x, p.y)
    } else {
        ((1.0 - libm::fabsf(p.y)) * sign(p.x), (1.0 - libm::fabsf(p.x)) * sign(p.y))
    };
    [u, v].map(|c| (libm::roundf(c * half).clamp(-half, half - 1.0) as i32 + half as i32) as u32)
}

fn sign(x: f32) -> f32 {
    if x >= 0.0 { 1.0 } else { -1.0 }
}

/// The unnormalised octahedral vector of the 16-bit codes in `word` (`u` low, `v` high).
pub(crate) fn octahedral_decode(word: u32) -> Vec3 {
    octahedral_decode_bits(word & 0xffff, word >> 16, 16)
}

/// The unnormalised octahedral vector of two `bits`-bit codes: exact dyadic arithmetic
/// only.
pub(crate) fn octahedral_decode_bits(u: u32, v: u32, bits: u32) -> Vec3 {
    let half = (1u32 << (bits - 1)) as f32;
    let step = f32::from_bits((128 - bits) << 23); // 2^(1 − bits)
    let u = (u as f32 - half) * step;
    let v = (v as f32 - half) * step;
    let z = 1.0 - libm::fabsf(u) - libm::fabsf(v);
    if z >= 0.0 {
        Vec3::new(u, v, z)
    } else {
        Vec3::new((1.0 - libm::fabsf(v)) * sign(u), (1.0 - libm::fabsf(u)) * sign(v), z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn voxels() -> impl Iterator<Item = (Voxel, u32)> {
        let mut state = 0x1234_5678_u32;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            state as f32 / u32::MAX as f32
        };
        (0..20_000).map(move |k| {
            let level = k % 7;
            let scale = level_scale(level);
            let normal = Vec3::new(next() - 0.5, next() - 0.5, next() - 0.5) * (0.1 + next());
            let voxel = Voxel {
                distance: (next() - 0.5) * 40.0 * scale,
                distance_variance: (next() * next()) * scale * scale,
                normal,
                slope_variance: next() * next() * 4.0,
                attribute: [next(), next(), next()],
                correlation: [next() - 0.5, next() * 2.0 - 1.0, next() - 0.5],
            };
            (voxel, level)
        })
    }

    /// Half a binary16 ulp of `x` (or the flush threshold below the normal range).
    fn half_bound(x: f32) -> f32 {
        if x < crate::half::HALF_MIN_POSITIVE { crate::half::HALF_MIN_POSITIVE } else { x * (1.0 / 2048.0) }
    }

    #[test]
    fn round_trips_stay_within_the_documented_bounds() {
        let mut compared = 0;
        for (voxel, level) in voxels() {
            let scale = level_scale(level);
            for layout in VoxelLayout::ALL {
                let fine8 = layout == VoxelLayout::Compact16Fine8 && level == 0;
                let bits = if fine8 { 12 } else { 16 };
                let normal_bound = 3.0 * core::f32::consts::SQRT_2 / (1u32 << (bits - 1)) as f32 + 1e-6;
                // The finest level's voxels have no variances nor correlations (§5.2).
                let voxel = if fine8 {
                    Voxel { distance_variance: 0.0, slope_variance: 0.0, correlation: [0.0; 3], ..voxel }
                } else {
                    voxel
                };
                let back = layout.round_trip(&voxel, level);
                match layout {
                    VoxelLayout::Paper20 => assert_eq!(back.distance, voxel.distance),
                    VoxelLayout::Compact16 | VoxelLayout::Compact16Fine8 => {
                        let clamped = voxel.distance.clamp(-32.0 * scale, (32.0 - 1.0 / 1024.0) * scale);
                        assert!((back.distance - clamped).abs() <= scale / 2048.0, "{voxel:?} {back:?}");
                    }
                }
                let variance_scale = if layout == VoxelLayout::Paper20 { 1.0 } else { scale * scale };
                let dv = (back.distance_variance - voxel.distance_variance).abs();
                assert!(dv <= half_bound(voxel.distance_variance / variance_scale) * variance_scale);
                assert!((back.slope_variance - voxel.slope_variance).abs() <= half_bound(voxel.slope_variance));
                // The chord between unit vectors (acos of a dot product near 1 cannot resolve
                // 10⁻⁴ rad in f32); the angle is 2 asin(chord / 2), within 10⁻¹² of it here.
                let angle = (back.normal - voxel.normal.normalize()).length();
                assert!(angle <= normal_bound, "{angle} for {:?}", voxel.normal);
                for c in 0..ATTRIBUTE_CHANNELS {
                    assert!((back.attribute[c] - voxel.attribute[c]).abs() <= 1.0 / 510.0 + 1e-7);
                    let s = voxel.correlation[c].clamp(-1.0, 1.0);
                    assert!((back.correlation[c] - s).abs() <= 1.0 / 254.0 + 1e-7);
                }
                compared += 1;
            }
        }
        assert_eq!(compared, 60_000);
    }

    #[test]
    fn octahedral_decoding_is_exact_dyadic_and_l1_normalised() {
        for word in [0, 0xffff_ffff, 0x8000_8000, 0x0000_ffff, 0x1234_abcd, 0x7fff_0001] {
            let n = octahedral_decode(word);
            assert_eq!(n.x.abs() + n.y.abs() + n.z.abs(), 1.0, "{word:#x}");
            for c in n.to_array() {
                assert_eq!(c * 32768.0, libm::roundf(c * 32768.0));
            }
        }
        assert_eq!(octahedral_decode(0x8000_8000), Vec3::Z);
        assert_eq!(VoxelLayout::Paper20.round_trip(&Voxel::default(), 0).normal, Vec3::Z);
    }

    #[test]
    fn layouts_have_the_documented_sizes() {
        assert_eq!(VoxelLayout::Paper20.bytes(), 20);
        assert_eq!(VoxelLayout::Compact16.bytes(), 16);
        assert_eq!((VoxelLayout::Compact16Fine8.bytes_at(0), VoxelLayout::Compact16Fine8.bytes_at(1)), (8, 16));
        assert_eq!(level_scale(0), 1.0);
        assert_eq!(level_scale(5), 32.0);
    }
}
