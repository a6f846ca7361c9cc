//! The face-centred cubic lattice and the order in which its sites are filled.
//!
//! Sites are the integer points `(x, k, z)` with `x + k + z` even, scaled by
//! `u = d/√2`, so the nearest neighbours of a site are its 12 points at distance `d`
//! (`(±1, ±1, 0)` and permutations) and layer `k` (height `y₀ + k·u`) is a checkerboard.
//! Layers are filled bottom-up, so the stacking fills like a pour: every layer but the last
//! is full and taken row by row (`x`, then `z`); the last, partial, layer is taken from its
//! centre outwards, ring by ring (square rings `max(|x − cx|, |z − cz|) = m`, each walked
//! top row, bottom row, left column, right column). Everything is integer arithmetic or
//! correctly rounded `f64` (`+ − × ÷ √`, `floor`), so the order is identical everywhere.

use crate::spec::{Region, StackingSpec};

/// Where the sites of a stacking are.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Layout {
    shape: Shape,
    /// `u = d/√2`, the lattice unit.
    unit: f64,
    /// Height of layer 0.
    y0: f64,
}

#[derive(Clone, Copy, Debug)]
enum Shape {
    /// Footprint `[0, nx) × [0, nz)`, centred on the `y` axis.
    Box { nx: i64, nz: i64 },
    /// Layer `k` is the disk of radius `base − k/slope` (lattice units) about the axis.
    Pile { base: f64, inv_slope: f64 },
}

/// The integer rectangle `[x0, x1] × [z0, z1]` (inclusive) that holds a layer.
type Rect = (i64, i64, i64, i64);

impl Layout {
    /// The layout of `spec` (validated), with layer 0 at height `y0`.
    pub(crate) fn new(spec: &StackingSpec, y0: f64) -> Layout {
        let unit = spec.lattice_distance() / std::f64::consts::SQRT_2;
        let count = spec.count as f64;
        let shape = match spec.region {
            Region::Box { aspect } => {
                let a = aspect.to_array().map(f64::from);
                // λ with λ³·ax·ay·az = 2·count (two cells per site), by bisection: only
                // correctly rounded operations, unlike `cbrt`.
                let target = 2.0 * count / (a[0] * a[1] * a[2]);
                let (mut lo, mut hi) = (0.0f64, 1.0f64);
                while hi * hi * hi < target {
                    hi *= 2.0;
                }
                for _ in 0..80 {
                    let mid = 0.5 * (lo + hi);
                    if mid * mid * mid < target { lo = mid } else { hi = mid }
                }
                let cap = 2.0 * count + 2.0;
                let side = |a: f64| (hi * a).round().clamp(1.0, cap) as i64;
                Shape::Box { nx: side(a[0]), nz: side(a[2]) }
            }
            Region::Pile { slope } => {
                let inv_slope = 1.0 / f64::from(slope);
                let enough = |base: f64| Layout::pile_sites(base, inv_slope, spec.count as u64) >= spec.count as u64;
                let (mut lo, mut hi) = (0.0f64, 1.0f64);
                while !enough(hi) {
                    hi *= 2.0;
                }
                for _ in 0..64 {
                    let mid = 0.5 * (lo + hi);
                    if enough(mid) { hi = mid } else { lo = mid }
                }
                Shape::Pile { base: hi, inv_slope }
            }
        };
        Layout { shape, unit, y0 }
    }

    /// Sites of the pile of base radius `base`, counted until `stop`.
    fn pile_sites(base: f64, inv_slope: f64, stop: u64) -> u64 {
        let shape = Shape::Pile { base, inv_slope };
        let mut total = 0;
        for k in 0.. {
            match layer_count(shape, k) {
                None => break,
                Some(c) => total += c,
            }
            if total >= stop {
                break;
            }
        }
        total
    }

    /// The position of site `(x, k, z)`.
    pub(crate) fn position(&self, x: i64, k: i64, z: i64) -> [f64; 3] {
        let u = self.unit;
        let y = self.y0 + k as f64 * u;
        match self.shape {
            Shape::Box { nx, nz } => {
                [(x as f64 - 0.5 * (nx - 1) as f64) * u, y, (z as f64 - 0.5 * (nz - 1) as f64) * u]
            }
            Shape::Pile { .. } => [x as f64 * u, y, z as f64 * u],
        }
    }

    /// The largest `|coordinate|` of the sites of the first `count` grains.
    pub(crate) fn max_site_coordinate(&self, count: u64) -> f64 {
        let mut k_top = 0;
        let mut total = 0;
        for k in 0.. {
            let Some(c) = layer_count(self.shape, k) else { break };
            total += c;
            k_top = k;
            if total >= count {
                break;
            }
        }
        let horizontal = match self.shape {
            Shape::Box { nx, nz } => 0.5 * (nx.max(nz) - 1) as f64,
            Shape::Pile { base, .. } => base,
        };
        (self.y0 + k_top as f64 * self.unit).abs().max(horizontal * self.unit)
    }

    /// Calls `emit(x, k, z)` for the first `count` sites, in filling order.
    pub(crate) fn for_each_site(&self, count: u64, mut emit: impl FnMut(i64, i64, i64)) {
        let mut remaining = count;
        let mut k = 0;
        while remaining > 0 {
            let Some(c) = layer_count(self.shape, k) else { break };
            if c <= remaining {
                self.full_layer(k, &mut emit);
                remaining -= c;
            } else {
                self.partial_layer(k, remaining, &mut emit);
                remaining = 0;
            }
            k += 1;
        }
    }

    fn full_layer(&self, k: i64, emit: &mut impl FnMut(i64, i64, i64)) {
        let Some((x0, x1, _, _)) = rect(self.shape, k) else { return };
        for x in x0..=x1 {
            let (z0, z1) = z_range(self.shape, k, x);
            // The first z ≥ z0 with x + k + z even.
            let start = z0 + (x + k + z0).rem_euclid(2);
            let mut z = start;
            while z <= z1 {
                emit(x, k, z);
                z += 2;
            }
        }
    }

    fn partial_layer(&self, k: i64, mut remaining: u64, emit: &mut impl FnMut(i64, i64, i64)) {
        let Some((x0, x1, z0, z1)) = rect(self.shape, k) else { return };
        let (cx, cz) = match self.shape {
            Shape::Box { nx, nz } => ((nx - 1) / 2, (nz - 1) / 2),
            Shape::Pile { .. } => (0, 0),
        };
        let shape = self.shape;
        let mut visit = |x: i64, z: i64, remaining: &mut u64| {
            if *remaining > 0 && (x + k + z).rem_euclid(2) == 0 {
                let (lo, hi) = z_range(shape, k, x);
                if (lo..=hi).contains(&z) {
                    emit(x, k, z);
                    *remaining -= 1;
                }
            }
        };
        let rings = (cx - x0).max(x1 - cx).max(cz - z0).max(z1 - cz);
        for m in 0..=rings {
            if remaining == 0 {
                return;
            }
            if m == 0 {
                visit(cx, cz, &mut remaining);
                continue;
            }
            // Top and bottom rows, clipped to the rectangle.
            for z in [cz - m, cz + m] {
                if (z0..=z1).contains(&z) {
                    for x in (cx - m).max(x0)..=(cx + m).min(x1) {
                        visit(x, z, &mut remaining);
                    }
                }
            }
            // Left and right columns without the corners.
            for x in [cx - m, cx + m] {
                if (x0..=x1).contains(&x) {
                    for z in (cz - m + 1).max(z0)..=(cz + m - 1).min(z1) {
                        visit(x, z, &mut remaining);
                    }
                }
            }
        }
    }
}

/// The disk radius (lattice units) of layer `k` of a pile, `None` above the apex.
fn pile_radius(base: f64, inv_slope: f64, k: i64) -> Option<f64> {
    let rho = base - k as f64 * inv_slope;
    (rho >= 0.0).then_some(rho)
}

/// The bounding rectangle of layer `k`; `None` when the layer (and every one above) is empty.
fn rect(shape: Shape, k: i64) -> Option<Rect> {
    match shape {
        Shape::Box { nx, nz } => Some((0, nx - 1, 0, nz - 1)),
        Shape::Pile { base, inv_slope } => {
            let r = pile_radius(base, inv_slope, k)?.floor() as i64;
            Some((-r, r, -r, r))
        }
    }
}

/// The `z` range (inclusive) of row `x` of layer `k`; empty (`lo > hi`) outside.
fn z_range(shape: Shape, k: i64, x: i64) -> (i64, i64) {
    match shape {
        Shape::Box { nz, .. } => (0, nz - 1),
        Shape::Pile { base, inv_slope } => match pile_radius(base, inv_slope, k) {
            Some(rho) => {
                let h = rho * rho - (x * x) as f64;
                if h < 0.0 {
                    return (1, 0);
                }
                let m = h.sqrt().floor() as i64;
                (-m, m)
            }
            None => (1, 0),
        },
    }
}

/// How many sites layer `k` has; `None` when the layer (and every one above) is empty.
fn layer_count(shape: Shape, k: i64) -> Option<u64> {
    let (x0, x1, _, _) = rect(shape, k)?;
    if let Shape::Box { nx, nz } = shape {
        let cells = nx as u64 * nz as u64;
        // Cells with x + z even: half, plus one when both sides are odd.
        let even = (cells + u64::from(nx % 2 == 1 && nz % 2 == 1)) / 2;
        return Some(if k % 2 == 0 { even } else { cells - even });
    }
    let mut total = 0u64;
    for x in x0..=x1 {
        let (z0, z1) = z_range(shape, k, x);
        if z0 <= z1 {
            let start = z0 + (x + k + z0).rem_euclid(2);
            if start <= z1 {
                total += ((z1 - start) / 2 + 1) as u64;
            }
        }
    }
    Some(total)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spec::GrainRadii;
    use glam::Vec3;
    use std::collections::HashSet;

    fn layout(count: usize, region: Region) -> (Layout, StackingSpec) {
        let mut spec = StackingSpec::new(count, GrainRadii::new(0.5, 1.0).unwrap());
        spec.region = region;
        (Layout::new(&spec, 1.0), spec)
    }

    fn sites(l: &Layout, count: u64) -> Vec<(i64, i64, i64)> {
        let mut v = Vec::new();
        l.for_each_site(count, |x, k, z| v.push((x, k, z)));
        v
    }

    #[test]
    fn sites_are_distinct_fcc_points_bottom_up() {
        let regions = [
            Region::Box { aspect: Vec3::ONE },
            Region::Box { aspect: Vec3::new(3.0, 1.0, 0.5) },
            Region::Box { aspect: Vec3::new(1.0, 1000.0, 1.0) },
            Region::Pile { slope: 0.6 },
            Region::Pile { slope: 20.0 },
        ];
        for region in regions {
            for count in [1, 2, 7, 1000, 4321] {
                let (l, _) = layout(count, region);
                let s = sites(&l, count as u64);
                assert_eq!(s.len(), count, "{region:?}");
                let set: HashSet<_> = s.iter().copied().collect();
                assert_eq!(set.len(), count, "{region:?}: repeated sites");
                assert!(s.iter().all(|&(x, k, z)| (x + k + z).rem_euclid(2) == 0));
                assert!(s.windows(2).all(|w| w[0].1 <= w[1].1), "{region:?}: not bottom-up");
            }
        }
    }

    #[test]
    fn the_partial_layer_grows_from_the_centre() {
        let (l, _) = layout(1000, Region::Pile { slope: 0.6 });
        let s = sites(&l, 1000);
        let top = s.last().unwrap().1;
        // The first site of the top layer is its centre (or a neighbour, by parity).
        let first = s.iter().find(|p| p.1 == top).unwrap();
        assert!(first.0.abs() <= 1 && first.2.abs() <= 1, "{first:?}");
    }

    #[test]
    fn the_pile_is_the_smallest_cone_that_holds_count() {
        for count in [1u64, 10, 1000, 20_000] {
            let (l, _) = layout(count as usize, Region::Pile { slope: 0.6 });
            let Shape::Pile { base, inv_slope } = l.shape else { unreachable!() };
            assert!(Layout::pile_sites(base, inv_slope, u64::MAX) >= count);
            // One grain fits in the cone of radius 0 (its apex is a site).
            let smaller = Layout::pile_sites(base * 0.999, inv_slope, u64::MAX);
            assert!(smaller < count || base < 1e-9, "{count}: {base}");
        }
    }
}
