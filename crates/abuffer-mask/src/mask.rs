//! Binary coverage masks of `N = 32 × WORDS` samples and their set algebra (§5.3,
//! Algorithm 1, lines 10–11), after Carpenter's A-buffer \[Car84\].
//!
//! Bit `k` of a mask (bit `k % 32` of word `k / 32`) is set when sample `k` of the
//! [`SamplePattern`](crate::SamplePattern) is covered. The coverage of a mask is
//! `popcount / N`, an estimate of the covered fraction of the pixel footprint.
//!
//! [`ConeAccumulator`] is Algorithm 1 itself: line 10 adds the radiance of a cone element
//! weighted by the samples it covers that nothing in front covered, `bitcount(1_A \ α) / N`,
//! and line 11 adds those samples to the accumulated occlusion `α = α ∪ 1_A`. Because the
//! same samples are reused, two fragments that cover the *same* half of the pixel cover it
//! once (Fig. 4): the union of equal masks is the mask itself, where α-blending
//! (eq. 12, `α_d = α (1 − α_{d−1})`) would accumulate `0.5 + 0.5 × 0.5 = 0.75`.

/// A mask of `32 × WORDS` samples; word `w` holds samples `32w .. 32w + 32`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(transparent)]
pub struct Mask<const WORDS: usize> {
    /// The bits, sample `k` at bit `k % 32` of word `k / 32`.
    pub words: [u32; WORDS],
}

/// A mask of `N = 32` samples.
pub type Mask32 = Mask<1>;
/// A mask of `N = 64` samples.
pub type Mask64 = Mask<2>;
/// A mask of `N = 128` samples (the paper's choice, §6).
pub type Mask128 = Mask<4>;

impl<const WORDS: usize> Default for Mask<WORDS> {
    fn default() -> Self {
        Self::EMPTY
    }
}

impl<const WORDS: usize> Mask<WORDS> {
    /// The number of samples `N = 32 × WORDS`.
    pub const SAMPLES: usize = 32 * WORDS;
    /// No sample covered.
    pub const EMPTY: Self = Self { words: [0; WORDS] };
    /// Every sample covered.
    pub const FULL: Self = Self { words: [u32::MAX; WORDS] };

    /// The mask whose bit `k` is `covered(k)`, for `k` in `0..N`.
    pub fn from_fn(mut covered: impl FnMut(usize) -> bool) -> Self {
        let mut mask = Self::EMPTY;
        for k in 0..Self::SAMPLES {
            if covered(k) {
                mask.words[k / 32] |= 1 << (k % 32);
            }
        }
        mask
    }

    /// Whether sample `k` is covered (false for `k ≥ N`).
    pub fn contains(&self, k: usize) -> bool {
        self.words.get(k / 32).is_some_and(|w| w >> (k % 32) & 1 == 1)
    }

    /// `self ∪ other` (Algorithm 1, line 11).
    pub fn union(self, other: Self) -> Self {
        Self { words: core::array::from_fn(|w| self.words[w] | other.words[w]) }
    }

    /// `self ∩ other`.
    pub fn intersection(self, other: Self) -> Self {
        Self { words: core::array::from_fn(|w| self.words[w] & other.words[w]) }
    }

    /// `self \ other`: the samples of `self` not in `other` (Algorithm 1, line 10,
    /// `1_A \ α`).
    pub fn difference(self, other: Self) -> Self {
        Self { words: core::array::from_fn(|w| self.words[w] & !other.words[w]) }
    }

    /// The samples not in `self`.
    pub fn complement(self) -> Self {
        Self { words: self.words.map(|w| !w) }
    }

    /// The number of covered samples, `bitcount` in Algorithm 1.
    pub fn popcount(&self) -> u32 {
        self.words.iter().map(|w| w.count_ones()).sum()
    }

    /// `popcount / N` in `[0, 1]`. `N` is a power of two times 32 for the supported sizes,
    /// so this is exact (and equal to the WGSL twin's `f32(count) * coverage_scale`).
    pub fn coverage(&self) -> f32 {
        self.popcount() as f32 * (1.0 / Self::SAMPLES as f32)
    }
}

/// Algorithm 1 of the paper (lines 3–4, 10–11): front-to-back accumulation of cone elements
/// along one pixel's cone, with occlusion tracked as a mask.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ConeAccumulator<const WORDS: usize> {
    /// `α`, the samples occluded by the elements added so far (line 3).
    pub occlusion: Mask<WORDS>,
    /// `L`, the mean incoming radiance of the pixel so far (line 4).
    pub radiance: f32,
}

impl<const WORDS: usize> ConeAccumulator<WORDS> {
    /// Nothing accumulated: `α = ∅`, `L = 0`.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a cone element with mask `coverage` (`1_A`) and outgoing radiance `radiance`
    /// (`L_d`): `L += L_d bitcount(1_A \ α) / N` (line 10), then `α = α ∪ 1_A` (line 11).
    pub fn add(&mut self, coverage: Mask<WORDS>, radiance: f32) {
        self.radiance += radiance * coverage.difference(self.occlusion).coverage();
        self.occlusion = self.occlusion.union(coverage);
    }

    /// The fraction of the pixel occluded so far, `bitcount(α) / N`.
    pub fn opacity(&self) -> f32 {
        self.occlusion.coverage()
    }
}

/// The opacity that α-blending (eq. 12, `α_d = α_[z_d, z_d+1] (1 − α_{d−1})`, i.e. the
/// uncorrelated hypothesis) accumulates from `alphas`, front to back: `1 − Π (1 − α_d)`.
pub fn alpha_blended_opacity(alphas: impl IntoIterator<Item = f32>) -> f32 {
    1.0 - alphas.into_iter().fold(1.0, |transmittance, alpha| transmittance * (1.0 - alpha))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn set_algebra_on_known_bits() {
        let a = Mask64::from_fn(|k| k < 40);
        let b = Mask64::from_fn(|k| (20..50).contains(&k));
        assert_eq!(a.words, [u32::MAX, 0xff]);
        assert_eq!(a.union(b).popcount(), 50);
        assert_eq!(a.intersection(b).popcount(), 20);
        assert_eq!(a.difference(b).popcount(), 20);
        assert_eq!(b.difference(a).popcount(), 10);
        assert_eq!(a.complement().popcount(), 24);
        assert!(a.contains(39) && !a.contains(40) && !a.contains(64));
        assert_eq!(Mask128::FULL.coverage(), 1.0);
        assert_eq!(Mask32::EMPTY.coverage(), 0.0);
        assert_eq!(Mask128::from_fn(|k| k % 4 == 0).coverage(), 0.25);
    }

    #[test]
    fn accumulator_counts_each_sample_once() {
        let left = Mask32::from_fn(|k| k < 16);
        let right = Mask32::from_fn(|k| k >= 16);
        let mut cone = ConeAccumulator::new();
        cone.add(left, 2.0);
        cone.add(left, 100.0); // hidden behind the first element: contributes nothing
        cone.add(right, 4.0);
        assert_eq!(cone.radiance, 2.0 * 0.5 + 4.0 * 0.5);
        assert_eq!(cone.opacity(), 1.0);
    }

    #[test]
    fn alpha_blending_saturates() {
        assert_eq!(alpha_blended_opacity([0.5, 0.5]), 0.75);
        assert_eq!(alpha_blended_opacity([]), 0.0);
    }
}
