//! Test support shared by the modules' tests: a seeded generator and the checks every
//! source must pass (1-Lipschitz distance, gradient equal to finite differences).

use glam::Vec3;
use svo_brick::SurfaceSource;

/// `SplitMix64`: a small seeded generator, enough for test points.
pub(crate) struct Rng(u64);

impl Rng {
    pub(crate) fn new(seed: u64) -> Self {
        Rng(seed)
    }

    pub(crate) fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`.
    pub(crate) fn f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }

    pub(crate) fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.f32()
    }

    pub(crate) fn vec3(&mut self, min: Vec3, max: Vec3) -> Vec3 {
        Vec3::new(self.range(min.x, max.x), self.range(min.y, max.y), self.range(min.z, max.z))
    }

    pub(crate) fn unit(&mut self) -> Vec3 {
        loop {
            let v = self.vec3(Vec3::splat(-1.0), Vec3::ONE);
            let l = v.length();
            if l > 0.1 && l <= 1.0 {
                return v / l;
            }
        }
    }
}

/// Asserts `|d(p) − d(q)| ≤ |p − q|` on `pairs` random pairs in the box (half of them
/// independent, half at distances from 10⁻³ to 10⁻¹ of the box's extent), up to `f32`
/// rounding, and `|∇d| ≤ 1` at the first points. Returns the largest ratio seen.
pub(crate) fn assert_lipschitz<S: SurfaceSource>(source: &S, min: Vec3, max: Vec3, pairs: usize, seed: u64) -> f32 {
    let mut rng = Rng::new(seed);
    let extent = (max - min).length();
    let mut worst = 0.0f32;
    for k in 0..pairs {
        let p = rng.vec3(min, max);
        let q =
            if k % 2 == 0 { rng.vec3(min, max) } else { p + rng.unit() * extent * 10f32.powf(rng.range(-3.0, -1.0)) };
        let (dp, dq) = (source.distance(p), source.distance(q));
        let gap = p.distance(q);
        let slack = 2e-6 * (extent + dp.abs() + dq.abs());
        assert!((dp - dq).abs() <= gap * (1.0 + 1e-5) + slack, "|d({p}) - d({q})| = |{dp} - {dq}| > {gap}");
        if gap > 0.0 {
            worst = worst.max((dp - dq).abs() / gap);
        }
        if k < pairs / 4 {
            let g = source.gradient(p).length();
            assert!(g <= 1.0 + 1e-5, "|∇d({p})| = {g} > 1");
        }
    }
    worst
}

/// Asserts that the gradient equals central differences of step `h` within `tolerance` at
/// `count` random points of the box where `smooth` holds. Returns how many were checked.
pub(crate) fn assert_gradient_matches<S: SurfaceSource>(
    source: &S,
    min: Vec3,
    max: Vec3,
    count: usize,
    h: f32,
    tolerance: f32,
    smooth: impl Fn(Vec3) -> bool,
) -> usize {
    let mut rng = Rng::new(7);
    let mut checked = 0;
    for _ in 0..count {
        let p = rng.vec3(min, max);
        if !smooth(p) {
            continue;
        }
        let d = |e: Vec3| (source.distance(p + e * h) - source.distance(p - e * h)) / (2.0 * h);
        let differences = Vec3::new(d(Vec3::X), d(Vec3::Y), d(Vec3::Z));
        let gradient = source.gradient(p);
        assert!(
            (gradient - differences).length() <= tolerance,
            "at {p}: gradient {gradient}, central differences {differences}"
        );
        checked += 1;
    }
    checked
}
