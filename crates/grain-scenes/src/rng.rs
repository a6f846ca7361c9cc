//! A counter-based random number generator: every random value of a stacking is a pure
//! function of `(seed, grain id, stream, counter)`, so grains are generated
//! independently and identically on every platform.
//!
//! The mixing function is the finaliser of `SplitMix64` (Steele, Lea & Flood 2014; the
//! constants of Vigna's `splitmix64.c`). A [`GrainRng`] is a `SplitMix64` sequence whose
//! starting state is a hash of `(seed, id, stream)`: its `k`-th output is
//! `mix(key + (k + 1)·γ)` with `γ = 0x9E37_79B9_7F4A_7C15`. Floating-point values are made
//! from the top 53 bits and only `+ − × ÷ √` (correctly rounded in IEEE 754), never a
//! transcendental function, so generation is bit-identical everywhere.

/// The `SplitMix64` increment (the golden ratio as a 64-bit fraction).
const GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;

/// The `SplitMix64` finaliser: a bijection of `u64` with full avalanche.
pub const fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A hash of `(seed, id, stream)`: each input goes through [`mix`] before the next is
/// folded in, so nearby seeds, ids and streams give unrelated keys.
pub const fn hash3(seed: u64, id: u64, stream: u64) -> u64 {
    let a = mix(seed.wrapping_add(GAMMA));
    let b = mix(a ^ id.wrapping_mul(GAMMA).wrapping_add(0x632B_E59B_D9B4_E019));
    mix(b ^ stream.wrapping_mul(0xD1B5_4A32_D192_ED03).wrapping_add(GAMMA))
}

/// The random streams of a grain: one per attribute, so that changing how one attribute
/// is drawn never changes another.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u64)]
pub enum Stream {
    /// Position jitter (rejection sampling in the unit ball).
    Position = 1,
    /// Orientation (Marsaglia's uniform quaternion).
    Orientation = 2,
    /// Scale jitter.
    Scale = 3,
    /// The procedural attribute `t` of Fig. 16 (colour).
    Colour = 4,
    /// Shake: oscillation direction and phase.
    ShakeOffset = 5,
    /// Shake: spin axis and phase.
    ShakeSpin = 6,
}

/// The random sequence of one stream of one grain.
#[derive(Clone, Debug)]
pub struct GrainRng {
    state: u64,
}

impl GrainRng {
    /// The sequence of `stream` for grain `id` of the stacking with `seed`.
    pub const fn new(seed: u64, id: u64, stream: Stream) -> GrainRng {
        GrainRng { state: hash3(seed, id, stream as u64) }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(GAMMA);
        mix(self.state)
    }

    /// A uniform value in `[0, 1)`: the top 53 bits times `2⁻⁵³` (exact).
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// A uniform value in `[-1, 1)`.
    pub fn signed(&mut self) -> f64 {
        2.0 * self.unit() - 1.0
    }
}

/// How many candidates the rejection samplers draw before giving up; a grain falls back to
/// a fixed value with probability below `(1 − π/6)^64 < 10⁻²⁰`.
pub const MAX_TRIES: u32 = 64;

/// A uniform point of the closed unit ball, by rejection from the cube `[-1, 1)³`
/// (acceptance `π/6`); the centre after [`MAX_TRIES`] rejections.
pub fn in_unit_ball(rng: &mut GrainRng) -> [f64; 3] {
    for _ in 0..MAX_TRIES {
        let p = [rng.signed(), rng.signed(), rng.signed()];
        if p[0] * p[0] + p[1] * p[1] + p[2] * p[2] <= 1.0 {
            return p;
        }
    }
    [0.0; 3]
}

/// A point of the open unit disk (acceptance `π/4`); `None` after [`MAX_TRIES`] rejections.
fn in_unit_disk(rng: &mut GrainRng) -> Option<(f64, f64, f64)> {
    for _ in 0..MAX_TRIES {
        let (x, y) = (rng.signed(), rng.signed());
        let s = x * x + y * y;
        if s < 1.0 && s > 0.0 {
            return Some((x, y, s));
        }
    }
    None
}

/// A uniform unit vector (Marsaglia 1972): `(2x√(1−s), 2y√(1−s), 1 − 2s)` for `(x, y)`
/// uniform in the unit disk and `s = x² + y²`; `+y` after [`MAX_TRIES`] rejections.
pub fn unit_vector(rng: &mut GrainRng) -> [f64; 3] {
    match in_unit_disk(rng) {
        Some((x, y, s)) => {
            let k = 2.0 * (1.0 - s).sqrt();
            [k * x, k * y, 1.0 - 2.0 * s]
        }
        None => [0.0, 1.0, 0.0],
    }
}

/// A uniform unit quaternion `[x, y, z, w]` (Marsaglia 1972, uniform on S³): `(x₁, y₁)` and
/// `(x₂, y₂)` uniform in the unit disk, `q = (x₁, y₁, x₂k, y₂k)` with `k = √((1 − s₁)/s₂)`,
/// renormalised in `f64`; the identity after [`MAX_TRIES`] rejections.
pub fn unit_quaternion(rng: &mut GrainRng) -> [f64; 4] {
    let (Some((x1, y1, s1)), Some((x2, y2, s2))) = (in_unit_disk(rng), in_unit_disk(rng)) else {
        return [0.0, 0.0, 0.0, 1.0];
    };
    let k = ((1.0 - s1) / s2).sqrt();
    normalize4([x1, y1, x2 * k, y2 * k])
}

/// `q / |q|` in `f64`.
pub(crate) fn normalize4(q: [f64; 4]) -> [f64; 4] {
    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    [q[0] / n, q[1] / n, q[2] / n, q[3] / n]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splitmix_matches_the_reference_sequence() {
        // Vigna's splitmix64.c with state 0: the first outputs.
        let mut state = 0u64;
        let mut next = || {
            state = state.wrapping_add(GAMMA);
            mix(state)
        };
        assert_eq!(next(), 0xE220_A839_7B1D_CDAF);
        assert_eq!(next(), 0x6E78_9E6A_A1B9_65F4);
    }

    #[test]
    fn streams_and_ids_are_independent() {
        let a = GrainRng::new(7, 0, Stream::Position).next_u64();
        let b = GrainRng::new(7, 1, Stream::Position).next_u64();
        let c = GrainRng::new(7, 0, Stream::Scale).next_u64();
        let d = GrainRng::new(8, 0, Stream::Position).next_u64();
        assert!(a != b && a != c && a != d && b != c);
    }

    #[test]
    fn samples_are_in_range_and_roughly_uniform() {
        let n = 20_000;
        let mut mean = [0.0f64; 3];
        for id in 0..n {
            let mut rng = GrainRng::new(1, id, Stream::Orientation);
            let u = rng.unit();
            assert!((0.0..1.0).contains(&u));
            let q = unit_quaternion(&mut rng);
            let n2: f64 = q.iter().map(|c| c * c).sum();
            assert!((n2 - 1.0).abs() < 1e-12);
            let v = unit_vector(&mut rng);
            let v2: f64 = v.iter().map(|c| c * c).sum();
            assert!((v2 - 1.0).abs() < 1e-12);
            let p = in_unit_ball(&mut rng);
            assert!(p.iter().map(|c| c * c).sum::<f64>() <= 1.0);
            for k in 0..3 {
                mean[k] += v[k] / n as f64;
            }
        }
        // The mean of n uniform unit vectors has standard deviation 1/√(3n) ≈ 0.004 per axis.
        for m in mean {
            assert!(m.abs() < 0.02, "{mean:?}");
        }
    }
}
