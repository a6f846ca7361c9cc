//! The smallest gap between the balls of a set of grains, in `O(n)` with a hashed uniform
//! grid: the verification of the stackings' guarantees.

use glam::Vec4;

use crate::rng::mix;

/// `min over i ≠ j of |cᵢ − cⱼ| − radius·(sᵢ + sⱼ)` for grains `centre_scale[i] = (cᵢ, sᵢ)`:
/// the smallest gap between the balls of radius `radius·s` about the centres, negative
/// when two overlap. `+∞` for fewer than two grains, NaN when a value is not finite.
///
/// Computed in `f64` from the `f32` values (so it measures the stored data, not the
/// generator's intermediate values), and exact up to `f64` rounding: pairs are taken from
/// neighbouring cells of a hashed grid of cell size `c`. Pairs further apart than `c` have
/// a gap of at least `c − 2·radius·s_max`; when the smallest gap found is larger, `c` is
/// doubled and the search repeated, until it is not or the grid is one cell wide.
pub fn min_gap(centre_scale: &[Vec4], radius: f32) -> f32 {
    let n = centre_scale.len();
    if n < 2 {
        return f32::INFINITY;
    }
    if !radius.is_finite() || centre_scale.iter().any(|c| !c.is_finite()) {
        return f32::NAN;
    }
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    let mut s_max = 0.0f64;
    for c in centre_scale {
        for k in 0..3 {
            lo[k] = lo[k].min(f64::from(c[k]));
            hi[k] = hi[k].max(f64::from(c[k]));
        }
        s_max = s_max.max(f64::from(c.w).abs());
    }
    let ext = [hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]];
    let diagonal = (ext[0] * ext[0] + ext[1] * ext[1] + ext[2] * ext[2]).sqrt();
    let largest = ext[0].max(ext[1]).max(ext[2]);
    // A first cell size: 1.5 times the mean spacing, flat sets counted as 1/1000 thick.
    let volume: f64 = ext.iter().map(|e| e.max(largest * 1e-3)).product();
    let mut cell = 1.5 * (volume / n as f64).cbrt();
    if !(cell.is_finite() && cell > 0.0) {
        cell = f64::MIN_POSITIVE.max(largest);
    }
    let reach = 2.0 * f64::from(radius) * s_max;
    let mut grid = Grid::with_capacity(n);
    loop {
        let found = grid.min_gap(centre_scale, radius, cell, lo);
        if found <= cell - reach || cell > diagonal {
            return found as f32;
        }
        cell *= 2.0;
    }
}

/// The buffers of a hashed grid, reused between cell sizes.
struct Grid {
    bucket: Vec<u32>,
    start: Vec<u32>,
    order: Vec<u32>,
}

impl Grid {
    fn with_capacity(n: usize) -> Grid {
        Grid { bucket: Vec::with_capacity(n), start: Vec::new(), order: Vec::with_capacity(n) }
    }

    fn min_gap(&mut self, points: &[Vec4], radius: f32, cell: f64, lo: [f64; 3]) -> f64 {
        let n = points.len();
        let mask = n.next_power_of_two() as u64 * 2 - 1;
        let cell_of = |c: &Vec4| -> [i64; 3] {
            let f = |k: usize| ((f64::from(c[k]) - lo[k]) / cell).floor() as i64;
            [f(0), f(1), f(2)]
        };
        let bucket_of = |c: [i64; 3]| -> usize {
            let h = mix(mix(mix(c[0] as u64) ^ c[1] as u64) ^ c[2] as u64);
            (h & mask) as usize
        };
        // Counting sort of the points by bucket.
        self.bucket.clear();
        self.bucket.extend(points.iter().map(|c| bucket_of(cell_of(c)) as u32));
        self.start.clear();
        self.start.resize(mask as usize + 2, 0);
        for &b in &self.bucket {
            self.start[b as usize + 1] += 1;
        }
        for i in 1..self.start.len() {
            self.start[i] += self.start[i - 1];
        }
        self.order.clear();
        self.order.resize(n, 0);
        let mut next = self.start.clone();
        for (i, &b) in self.bucket.iter().enumerate() {
            self.order[next[b as usize] as usize] = i as u32;
            next[b as usize] += 1;
        }
        let r = f64::from(radius);
        let mut best = f64::INFINITY;
        for (i, p) in points.iter().enumerate() {
            let c = cell_of(p);
            let (px, py, pz, ps) = (f64::from(p.x), f64::from(p.y), f64::from(p.z), f64::from(p.w));
            for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        let b = bucket_of([c[0] + dx, c[1] + dy, c[2] + dz]);
                        let range = self.start[b] as usize..self.start[b + 1] as usize;
                        for &j in &self.order[range] {
                            if j as usize <= i {
                                continue;
                            }
                            let q = points[j as usize];
                            let (ex, ey, ez) = (f64::from(q.x) - px, f64::from(q.y) - py, f64::from(q.z) - pz);
                            let gap = (ex * ex + ey * ey + ez * ez).sqrt() - r * (ps + f64::from(q.w));
                            best = best.min(gap);
                        }
                    }
                }
            }
        }
        best
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::{GrainRng, Stream};

    fn brute_force(points: &[Vec4], radius: f32) -> f64 {
        let mut best = f64::INFINITY;
        for i in 0..points.len() {
            for j in i + 1..points.len() {
                let (p, q) = (points[i].to_array().map(f64::from), points[j].to_array().map(f64::from));
                let d2: f64 = (0..3).map(|k| (p[k] - q[k]) * (p[k] - q[k])).sum();
                let gap = d2.sqrt() - f64::from(radius) * (p[3] + q[3]);
                best = best.min(gap);
            }
        }
        best
    }

    #[test]
    fn matches_brute_force_on_random_and_clustered_points() {
        for (seed, spread) in [(1u64, 10.0f64), (2, 1.0), (3, 1000.0)] {
            let mut points: Vec<Vec4> = (0..2000)
                .map(|i| {
                    let mut rng = GrainRng::new(seed, i, Stream::Position);
                    // A dense cluster and a sparse halo, to defeat a fixed cell size.
                    let s = if i % 10 == 0 { spread } else { 1.0 };
                    Vec4::new(
                        (rng.signed() * s) as f32,
                        (rng.signed() * s) as f32,
                        (rng.signed() * s * 0.01) as f32,
                        (0.5 + rng.unit()) as f32,
                    )
                })
                .collect();
            for radius in [0.0, 0.01, 0.3] {
                let fast = min_gap(&points, radius);
                let exact = brute_force(&points, radius) as f32;
                assert_eq!(fast, exact, "seed {seed}, radius {radius}");
            }
            // Two points only, far apart: found after doubling.
            points.truncate(2);
            points[1] = Vec4::new(1e6, 0.0, 0.0, 1.0);
            assert_eq!(min_gap(&points, 1.0), brute_force(&points, 1.0) as f32);
        }
    }

    #[test]
    fn degenerate_inputs() {
        assert_eq!(min_gap(&[], 1.0), f32::INFINITY);
        assert_eq!(min_gap(&[Vec4::ONE], 1.0), f32::INFINITY);
        assert_eq!(min_gap(&[Vec4::ONE, Vec4::ONE], 1.0), -2.0);
        assert!(min_gap(&[Vec4::ONE, Vec4::NAN], 1.0).is_nan());
    }
}
