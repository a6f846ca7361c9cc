//! How many views an impostor needs: the validity half-angle of a view (eq. 4) and the
//! angular spacing of the layout (§6, Fig. 6).
//!
//! A view rendered at `p × p` texels samples the right texel only while the angle `θ`
//! between its axis and the actual view direction satisfies eq. 4,
//! `|θ| ≤ arccos √(1 / (1 + 1/p²))`. Since `cos θ = 1/√(1 + tan² θ)`, this bound is
//! exactly `θ ≤ atan(1/p)`, which is how it is computed here: the `arccos` form loses
//! most of its digits near 1 (at p = 256 an f32 `acos` is off by about 1e-4 relative).
//!
//! The paper then compares the validity cone, of full angle `2θ`, with "the maximum
//! angle between two neighbor points of the octahedron"; [`min_subdivisions_for_texels`]
//! implements that criterion. Neighbours are the 4-neighbours of the `(u, v)` grid of
//! [`crate::views`] (the edges of the interpolation cells). Note that this criterion
//! alone does not make every direction lie within `θ` of a view — a cell's centre is
//! farther from its corners than half an edge — as the xtask chart of the mean and
//! maximum angle to the nearest view shows.

use glam::DVec3;

use crate::views::{MAX_SUBDIVISIONS, OctahedralViews};

/// The validity half-angle in radians of a view rendered at `texels × texels` (eq. 4),
/// `atan(1/p)`, or `None` when `texels` is 0.
pub fn validity_half_angle(texels: u32) -> Option<f64> {
    (texels > 0).then(|| libm::atan(1.0 / f64::from(texels)))
}

/// The angle in radians between two directions, accurate also for tiny angles.
pub fn angle_between(a: DVec3, b: DVec3) -> f64 {
    libm::atan2(a.cross(b).length(), a.dot(b))
}

/// The largest angle in radians between two neighbouring views of `n = subdivisions`, or
/// `None` when `subdivisions` is invalid (see [`OctahedralViews::new`]).
///
/// For `n = 1` the two views are the poles and the result is π. Cost: `O(n²)`.
pub fn max_neighbour_angle(subdivisions: u32) -> Option<f64> {
    let views = OctahedralViews::new(subdivisions)?;
    let n = subdivisions;
    if n == 1 {
        return Some(core::f64::consts::PI);
    }
    // The upper hemisphere mirrors the lower one, so the lower one suffices.
    let direction = |u: u32, v: u32| views.view_direction_f64(u * n + v).unwrap_or(DVec3::Z);
    let mut largest = 0.0_f64;
    for u in 0..n {
        for v in 0..n {
            let here = direction(u, v);
            if u + 1 < n {
                largest = largest.max(angle_between(here, direction(u + 1, v)));
            }
            if v + 1 < n {
                largest = largest.max(angle_between(here, direction(u, v + 1)));
            }
        }
    }
    Some(largest)
}

/// The smallest `n` whose neighbour spacing fits the validity cone of a `texels`-texel
/// view: `max_neighbour_angle(n) ≤ 2 · validity_half_angle(texels)` (§6).
///
/// Returns `None` when `texels` is 0 or when no `n ≤ limit` fits, with `limit` the
/// smaller of `max_subdivisions` and [`MAX_SUBDIVISIONS`]. The spacing never increases
/// monotonically with `n` (checked by a test up to n = 256), so the search is a doubling
/// followed by a bisection, `O(n² log n)` in all.
pub fn min_subdivisions_for_texels(texels: u32, max_subdivisions: u32) -> Option<u32> {
    let cone = 2.0 * validity_half_angle(texels)?;
    let limit = max_subdivisions.min(MAX_SUBDIVISIONS);
    let fits = |n: u32| max_neighbour_angle(n).is_some_and(|angle| angle <= cone);
    if limit == 0 {
        return None;
    }
    // Doubling: find `high` that fits, with `high / 2` not fitting (or high = 1).
    let mut high = 1_u32;
    while !fits(high) {
        if high >= limit {
            return None;
        }
        high = (high * 2).min(limit);
    }
    let mut low = high / 2; // does not fit (or is 0)
    while high - low > 1 {
        let middle = low + (high - low) / 2;
        if fits(middle) { high = middle } else { low = middle }
    }
    Some(high)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eq4_half_angle_matches_the_arccos_form() {
        for p in [1_u32, 2, 16, 64, 128, 256, 4096] {
            let p_f = f64::from(p);
            let arccos_form = libm::acos(libm::sqrt(1.0 / (1.0 + 1.0 / (p_f * p_f))));
            let ours = validity_half_angle(p).unwrap();
            assert!((ours - arccos_form).abs() < 1e-7, "p={p}: {ours} vs {arccos_form}");
        }
        assert_eq!(validity_half_angle(0), None);
    }

    #[test]
    fn neighbour_spacing_decreases_with_n() {
        let mut previous = max_neighbour_angle(1).unwrap();
        for n in 2..=256 {
            let angle = max_neighbour_angle(n).unwrap();
            assert!(angle <= previous, "n={n}: {angle} > {previous}");
            previous = angle;
        }
        // n = 2: four equator views per hemisphere, 90° apart.
        let right_angle = max_neighbour_angle(2).unwrap();
        assert!((right_angle - core::f64::consts::FRAC_PI_2).abs() < 1e-12);
        assert_eq!(max_neighbour_angle(0), None);
    }

    #[test]
    fn smallest_n_is_the_first_that_fits() {
        for p in [4_u32, 16, 64, 128] {
            let n = min_subdivisions_for_texels(p, 4096).unwrap();
            let cone = 2.0 * validity_half_angle(p).unwrap();
            assert!(max_neighbour_angle(n).unwrap() <= cone);
            assert!(max_neighbour_angle(n - 1).unwrap() > cone, "p={p}, n={n}");
        }
        assert_eq!(min_subdivisions_for_texels(0, 4096), None);
        assert_eq!(min_subdivisions_for_texels(128, 8), None);
    }
}
