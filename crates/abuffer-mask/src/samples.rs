//! Deterministic Poisson-disk sample positions in the pixel footprint (§5.4, §6: "masks
//! with 128 Poisson-distributed samples").
//!
//! The paper does not say how its samples were made. Here they come from Mitchell's
//! best-candidate algorithm: each new sample is, among `CANDIDATES_PER_SAMPLE × k`
//! uniformly random candidates (`k` samples placed so far), the one farthest from all
//! placed samples. Distances are toroidal (the unit square wraps around), so samples do not
//! crowd the pixel's edges and the pattern stays Poisson-disk across tiled pixels. The
//! random numbers come from a fixed `SplitMix64` stream, so the pattern is the same on every
//! machine; coordinates are multiples of `2⁻²⁴` plus `2⁻²⁵`, exact in `f32` and strictly
//! inside `(0, 1)`.
//!
//! Minimum toroidal distances achieved (asserted by the tests, printed by
//! `tests/accuracy.rs`): N = 32: 0.1412, N = 64: 0.0953, N = 128: 0.0702, i.e. 0.743,
//! 0.709 and 0.739 of the hexagonal-packing spacing `sqrt(2 / (√3 N))` (see
//! [`SamplePattern::relative_radius`]).

use glam::Vec2;

/// The largest supported sample count (`N = 128`, four 32-bit words, as in the paper §6).
pub const MAX_SAMPLES: usize = 128;

/// Candidates drawn per already-placed sample in the best-candidate algorithm.
pub const CANDIDATES_PER_SAMPLE: usize = 32;

/// The fixed seed of the sample patterns.
pub const SAMPLE_SEED: u64 = 0x4845_4954_5a32_3031; // "HEITZ201"

/// `SplitMix64` (Steele, Lea & Flood 2014): a tiny, fixed, portable integer PRNG.
#[derive(Clone, Copy, Debug)]
struct SplitMix64(u64);

impl SplitMix64 {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// A coordinate `(k + 1/2) 2⁻²⁴`, `k` uniform in `0..2²⁴`: exact in `f32`, in `(0, 1)`.
    fn next_coordinate(&mut self) -> f32 {
        let k = (self.next_u64() >> 40) as u32;
        (k as f32 + 0.5) * (1.0 / 16_777_216.0)
    }
}

/// Squared toroidal distance between two points of the unit square.
fn toroidal_distance_squared(a: Vec2, b: Vec2) -> f32 {
    let d = (a - b).abs();
    let wrapped = d.min(Vec2::ONE - d);
    wrapped.length_squared()
}

/// `N` sample positions in the unit pixel footprint `[0, 1]²`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SamplePattern {
    positions: [Vec2; MAX_SAMPLES],
    count: usize,
}

impl SamplePattern {
    /// The deterministic Poisson-disk pattern of `count` samples (best candidate, see the
    /// module docs), or `None` when `count` is 0 or above [`MAX_SAMPLES`].
    pub fn poisson_disk(count: usize) -> Option<Self> {
        if count == 0 || count > MAX_SAMPLES {
            return None;
        }
        let mut rng = SplitMix64(SAMPLE_SEED ^ count as u64);
        let mut positions = [Vec2::ZERO; MAX_SAMPLES];
        positions[0] = Vec2::new(rng.next_coordinate(), rng.next_coordinate());
        for placed in 1..count {
            let mut best = (f32::NEG_INFINITY, Vec2::ZERO);
            for _ in 0..CANDIDATES_PER_SAMPLE * placed {
                let candidate = Vec2::new(rng.next_coordinate(), rng.next_coordinate());
                let nearest = positions[..placed]
                    .iter()
                    .map(|&p| toroidal_distance_squared(p, candidate))
                    .fold(f32::INFINITY, f32::min);
                if nearest > best.0 {
                    best = (nearest, candidate);
                }
            }
            positions[placed] = best.1;
        }
        Some(Self { positions, count })
    }

    /// The number of samples `N`.
    pub fn len(&self) -> usize {
        self.count
    }

    /// Always false: a pattern has at least one sample.
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// The sample positions in `[0, 1]²`; sample `k` is bit `k` of a mask.
    pub fn positions(&self) -> &[Vec2] {
        &self.positions[..self.count]
    }

    /// The samples in the centred footprint coordinates `ω = 2p − 1 ∈ (−1, 1)²` used by
    /// the half-plane test of §5.4 (see [`crate::half_plane`]).
    pub fn footprint_point(&self, index: usize) -> Option<Vec2> {
        self.positions().get(index).map(|&p| p * 2.0 - Vec2::ONE)
    }

    /// The smallest toroidal distance between two samples, in `[0, 1]²` units
    /// (`f32::INFINITY` for one sample).
    pub fn min_distance(&self) -> f32 {
        let p = self.positions();
        let mut best = f32::INFINITY;
        for (i, &a) in p.iter().enumerate() {
            for &b in &p[i + 1..] {
                best = best.min(toroidal_distance_squared(a, b));
            }
        }
        libm::sqrtf(best)
    }

    /// [`min_distance`](Self::min_distance) relative to `sqrt(2 / (√3 N))`, the spacing of
    /// a hexagonal packing of `N` points in the unit area: the usual quality measure of a
    /// Poisson-disk pattern (0.65–0.85 is considered good).
    pub fn relative_radius(&self) -> f32 {
        let hexagonal = libm::sqrtf(2.0 / (libm::sqrtf(3.0) * self.count as f32));
        self.min_distance() / hexagonal
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn patterns_are_deterministic_and_in_the_open_unit_square() {
        for n in [32, 64, 128] {
            let a = SamplePattern::poisson_disk(n).unwrap();
            assert_eq!(a, SamplePattern::poisson_disk(n).unwrap());
            assert_eq!(a.len(), n);
            assert!(a.positions().iter().all(|p| p.cmpgt(Vec2::ZERO).all() && p.cmplt(Vec2::ONE).all()));
        }
        assert!(SamplePattern::poisson_disk(0).is_none());
        assert!(SamplePattern::poisson_disk(129).is_none());
    }

    #[test]
    fn patterns_are_poisson_disk() {
        // The definition of a good Poisson-disk pattern (Lagae & Dutré, "A comparison of
        // methods for generating Poisson disk distributions", 2008): relative radius in
        // [0.65, 0.85] — below, samples clump; above, the pattern nears a lattice and
        // aliases. The measured distances (module docs) are pinned by
        // `tests/accuracy.rs`.
        for n in [32, 64, 128] {
            let pattern = SamplePattern::poisson_disk(n).unwrap();
            let rho = pattern.relative_radius();
            assert!((0.65..=0.85).contains(&rho), "N={n}: relative radius {rho}");
        }
    }

    #[test]
    fn samples_fill_the_footprint_evenly() {
        // Every quarter of the pixel holds N/4 ± N/16 samples (a uniform random set of
        // 128 points would often miss this).
        for n in [32, 64, 128] {
            let pattern = SamplePattern::poisson_disk(n).unwrap();
            for quarter in 0..4 {
                let lo = Vec2::new((quarter % 2) as f32 * 0.5, (quarter / 2) as f32 * 0.5);
                let inside =
                    pattern.positions().iter().filter(|p| p.cmpge(lo).all() && p.cmplt(lo + 0.5).all()).count();
                assert!(inside.abs_diff(n / 4) <= n / 16, "N={n} quarter {quarter}: {inside}");
            }
        }
    }
}
