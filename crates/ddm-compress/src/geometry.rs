//! Boxes, triangles, their overlap test and the hierarchical, conservative lower bound of
//! their (directional) distance.

use glam::Vec3;

use crate::cones::Cone;

/// An axis-aligned box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Minimum corner.
    pub min: Vec3,
    /// Maximum corner.
    pub max: Vec3,
}

/// A triangle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle(pub [Vec3; 3]);

impl Aabb {
    /// The unit voxel `(i, j, k)` of a grid with unit voxels.
    pub fn voxel(i: u32, j: u32, k: u32) -> Self {
        let min = Vec3::new(i as f32, j as f32, k as f32);
        Self { min, max: min + Vec3::ONE }
    }

    pub(crate) fn center(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    pub(crate) fn radius(&self) -> f32 {
        (self.max - self.min).length() * 0.5
    }

    /// The two halves along the longest axis.
    pub(crate) fn split(&self) -> [Self; 2] {
        let size = self.max - self.min;
        let axis = if size.x >= size.y && size.x >= size.z {
            0
        } else if size.y >= size.z {
            1
        } else {
            2
        };
        let middle = (self.min[axis] + self.max[axis]) * 0.5;
        let (mut low, mut high) = (*self, *self);
        low.max[axis] = middle;
        high.min[axis] = middle;
        [low, high]
    }
}

impl Triangle {
    pub(crate) fn center(&self) -> Vec3 {
        let [a, b, c] = self.0;
        (a + b + c) / 3.0
    }

    pub(crate) fn radius(&self) -> f32 {
        let center = self.center();
        self.0.iter().map(|v| v.distance(center)).fold(0.0, f32::max)
    }

    /// The two halves across the midpoint of the longest edge.
    pub(crate) fn split(&self) -> [Self; 2] {
        let [a, b, c] = self.0;
        let edges = [(a, b, c), (b, c, a), (c, a, b)];
        let (p, q, r) = edges
            .into_iter()
            .max_by(|x, y| x.0.distance_squared(x.1).total_cmp(&y.0.distance_squared(y.1)))
            .unwrap_or((a, b, c));
        let m = (p + q) * 0.5;
        [Triangle([p, m, r]), Triangle([m, q, r])]
    }

    /// Whether every vertex is finite.
    pub fn is_finite(&self) -> bool {
        self.0.iter().all(|v| v.is_finite())
    }
}

/// Whether `triangle` intersects `aabb` (separating-axis test, Akenine-Möller 2001): the
/// 3 box normals, the triangle normal and the 9 edge cross products. Touching counts.
pub fn triangle_overlaps_box(triangle: &Triangle, aabb: &Aabb) -> bool {
    // The same test as the WGSL twin's `ddm_triangle_overlaps_box`.
    let center = aabb.center();
    let half = (aabb.max - aabb.min) * 0.5;
    let [a, b, c] = triangle.0.map(|v| v - center);
    let edges = [b - a, c - b, a - c];
    let separated = |axis: Vec3| {
        if axis.length_squared() < DEGENERATE_AXIS_SQUARED {
            return false;
        }
        let (pa, pb, pc) = (a.dot(axis), b.dot(axis), c.dot(axis));
        let r = half.x * axis.x.abs() + half.y * axis.y.abs() + half.z * axis.z.abs();
        pa.min(pb).min(pc) > r || pa.max(pb).max(pc) < -r
    };
    for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
        if separated(axis) {
            return false;
        }
    }
    if separated(edges[0].cross(edges[1])) {
        return false;
    }
    for edge in edges {
        for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
            if separated(edge.cross(axis)) {
                return false;
            }
        }
    }
    true
}

/// A lower bound of the distance between `triangle` and `aabb` (0 when they touch): the
/// largest gap between their projections on the separating axes of
/// [`triangle_overlaps_box`] (normalised) and on the axis joining their centres. The gap
/// along a unit axis never exceeds the distance; it equals it when the closest points
/// face each other along one of the axes (a face of the box parallel to the triangle, or
/// two edges), and the centre axis makes it at least the bounding-sphere bound
/// `|c_T − c_B| − r_B − r_T`. A relative margin of a few float ulps keeps it below the
/// true distance after rounding.
pub fn separation_lower_bound(triangle: &Triangle, aabb: &Aabb) -> f32 {
    let center = aabb.center();
    let half = (aabb.max - aabb.min) * 0.5;
    let [a, b, c] = triangle.0.map(|v| v - center);
    let edges = [b - a, c - b, a - c];
    let mut gap = 0.0_f32;
    let mut project = |axis: Vec3| {
        let length_squared = axis.length_squared();
        if length_squared.is_nan() || length_squared <= 1e-20 {
            return;
        }
        let axis = axis / libm::sqrtf(length_squared);
        let (pa, pb, pc) = (a.dot(axis), b.dot(axis), c.dot(axis));
        let r = half.x * axis.x.abs() + half.y * axis.y.abs() + half.z * axis.z.abs();
        gap = gap.max(pa.min(pb).min(pc) - r).max(-r - pa.max(pb).max(pc));
    };
    project(Vec3::X);
    project(Vec3::Y);
    project(Vec3::Z);
    project(edges[0].cross(edges[1]));
    project(a + b + c);
    for edge in edges {
        project(edge.cross(Vec3::X));
        project(edge.cross(Vec3::Y));
        project(edge.cross(Vec3::Z));
    }
    let scale = 1.0 + center.abs().max_element() + a.abs().max(b.abs()).max(c.abs()).max_element() + half.max_element();
    (gap - 4e-7 * scale).max(0.0)
}

/// A lower bound of the distance between two boxes (0 when they touch).
pub fn box_distance(a: &Aabb, b: &Aabb) -> f32 {
    let gap = (a.min - b.max).max(b.min - a.max).max(Vec3::ZERO);
    let scale = 1.0 + a.max.abs().max(b.max.abs()).max(a.min.abs()).max(b.min.abs()).max_element();
    (gap.length() - 4e-7 * scale).max(0.0)
}

/// The point of `triangle` nearest to `point` (Ericson, *Real-Time Collision Detection*,
/// §5.1.5: Voronoi regions of the vertices, edges and face).
///
/// A degenerate triangle (a repeated corner, collinear corners, or corners within an angle
/// of about 1e-6 radians of a line) is a segment, for which
/// Ericson's regions divide by zero: the nearest of the points nearest `point` on its three
/// edges is returned instead, the projection onto the segment (the plain map's bounds need
/// a true projection onto the convex triangle).
pub fn closest_point_on_triangle(point: Vec3, triangle: &Triangle) -> Vec3 {
    let [a, b, c] = triangle.0;
    let (ab, ac, ap) = (b - a, c - a, point - a);
    if ab.cross(ac).length_squared() <= DEGENERATE_TRIANGLE_SINE_SQUARED * ab.length_squared() * ac.length_squared() {
        let on_edges = [
            closest_point_on_segment(point, a, b),
            closest_point_on_segment(point, b, c),
            closest_point_on_segment(point, c, a),
        ];
        let mut nearest = on_edges[0];
        for candidate in &on_edges[1..] {
            if candidate.distance_squared(point) < nearest.distance_squared(point) {
                nearest = *candidate;
            }
        }
        return nearest;
    }
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = point - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = point - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denominator = va + vb + vc;
    if denominator.is_nan() || denominator == 0.0 {
        // Degenerate triangle: the nearest of its vertices is still a point of it.
        return [a, b, c]
            .into_iter()
            .min_by(|x, y| x.distance_squared(point).total_cmp(&y.distance_squared(point)))
            .unwrap_or(a);
    }
    let (v, w) = (vb / denominator, vc / denominator);
    a + ab * v + ac * w
}

/// The distance between `aabb` and `triangle` (0 when they touch), less a rounding margin
/// of a few float ulps, so never above the true distance.
///
/// Two disjoint convex polytopes have a closest pair with a vertex of one on the other, or
/// on two edges (a face–face or face–edge pair slides to one of these): the minimum over
/// the triangle's vertices against the box, the box's 8 corners against the triangle
/// ([`closest_point_on_triangle`]) and the 3 × 12 edge pairs (Ericson, *Real-Time Collision
/// Detection*, §5.1.9) is the distance. Each candidate is the distance of a real pair of
/// points, so rounding can only lose the exact minimiser by a second-order amount; the
/// margin covers it. Intersecting pairs ([`triangle_overlaps_box`]) are at distance 0.
pub fn box_triangle_distance(aabb: &Aabb, triangle: &Triangle) -> f32 {
    if triangle_overlaps_box(triangle, aabb) {
        return 0.0;
    }
    let center = aabb.center();
    let half = (aabb.max - aabb.min) * 0.5;
    let local = Triangle(triangle.0.map(|v| v - center));
    let [a, b, c] = local.0;
    let mut best = [a, b, c].iter().map(|&v| v.distance_squared(v.clamp(-half, half))).fold(f32::INFINITY, f32::min);
    let corner = |i: u32| {
        Vec3::new(
            if i & 1 == 0 { -half.x } else { half.x },
            if i & 2 == 0 { -half.y } else { half.y },
            if i & 4 == 0 { -half.z } else { half.z },
        )
    };
    for i in 0..8 {
        let p = corner(i);
        best = best.min(p.distance_squared(closest_point_on_triangle(p, &local)));
    }
    for (p, q) in [(a, b), (b, c), (c, a)] {
        for i in 0..8_u32 {
            // Each box edge once: from corner `i` along each axis whose bit `i` lacks.
            for axis in [1_u32, 2, 4] {
                if i & axis == 0 {
                    best = best.min(segment_distance_squared(p, q, corner(i), corner(i | axis)));
                }
            }
        }
    }
    let scale = 1.0 + center.abs().max_element() + a.abs().max(b.abs()).max(c.abs()).max_element() + half.max_element();
    (libm::sqrtf(best) - BOX_TRIANGLE_MARGIN * scale).max(0.0)
}

/// The squared length below which a cross product is no separating axis (parallel edges)
/// in [`triangle_overlaps_box`].
pub(crate) const DEGENERATE_AXIS_SQUARED: f32 = 1e-20;

/// The relative rounding margin of [`box_triangle_distance`] (its distance less this times
/// the coordinates' scale stays below the exact distance).
pub(crate) const BOX_TRIANGLE_MARGIN: f32 = 2e-6;

/// The squared segment length below which [`segment_distance_squared`] treats a segment as
/// a point.
pub(crate) const DEGENERATE_SEGMENT_SQUARED: f32 = 1e-12;

/// The squared sine of the angle at a triangle's first corner at or below which
/// [`closest_point_on_triangle`] treats it as a segment (about 1e-6 radians).
pub(crate) const DEGENERATE_TRIANGLE_SINE_SQUARED: f32 = 1e-12;

/// The point of the segment `a b` nearest to `point` (`a` when the segment is a point).
pub fn closest_point_on_segment(point: Vec3, a: Vec3, b: Vec3) -> Vec3 {
    let ab = b - a;
    let length_squared = ab.length_squared();
    if length_squared <= 0.0 {
        return a;
    }
    a + ab * ((point - a).dot(ab) / length_squared).clamp(0.0, 1.0)
}

/// The squared distance between segments `p1 q1` and `p2 q2`: that of the pair of points
/// Ericson's closest-point method (*Real-Time Collision Detection*, §5.1.9) finds, clamped
/// to the segments (so always that of a real pair).
pub fn segment_distance_squared(p1: Vec3, q1: Vec3, p2: Vec3, q2: Vec3) -> f32 {
    let (d1, d2, r) = (q1 - p1, q2 - p2, p1 - p2);
    let (a, e, f) = (d1.length_squared(), d2.length_squared(), d2.dot(r));
    const DEGENERATE: f32 = DEGENERATE_SEGMENT_SQUARED;
    let (s, t) = if a <= DEGENERATE && e <= DEGENERATE {
        (0.0, 0.0)
    } else if a <= DEGENERATE {
        (0.0, (f / e).clamp(0.0, 1.0))
    } else {
        let c = d1.dot(r);
        if e <= DEGENERATE {
            ((-c / a).clamp(0.0, 1.0), 0.0)
        } else {
            let b = d1.dot(d2);
            let denominator = a * e - b * b;
            let s = if denominator > 0.0 { ((b * f - c * e) / denominator).clamp(0.0, 1.0) } else { 0.0 };
            let t = (b * s + f) / e;
            if t < 0.0 {
                ((-c / a).clamp(0.0, 1.0), 0.0)
            } else if t > 1.0 {
                (((b - c) / a).clamp(0.0, 1.0), 1.0)
            } else {
                (s, t)
            }
        }
    };
    (p1 + d1 * s).distance_squared(p2 + d2 * t)
}

/// A lower bound of `min |m − v|` over `v ∈ aabb`, `m ∈ triangle` with `m − v` inside
/// `cone` (any direction when `cone` is `None`), or `f32::INFINITY` when no such pair
/// exists. Never larger than the true value.
///
/// Bounding spheres give `|m − v| ≥ |c_T − c_B| − r_B − r_T`, and every direction from the
/// box to the triangle lies within `asin((r_B + r_T) / |c_T − c_B|)` of the centres'
/// direction; a pair is discarded only when that whole set provably misses the cone
/// ([`Cone::angle_lower_bound`]). The larger piece is halved until it is smaller than
/// `tolerance`, so the bound is within about `2·tolerance` of the truth. A piece's bound is
/// never below its parent's (the parent's bound holds for the piece too), which makes the
/// pruning of pieces whose bound cannot beat `best` exact: `best.min(result)` is the same
/// for any `best`, so the visiting order of triangles never changes a map.
pub fn directional_distance_bound(
    aabb: &Aabb,
    triangle: &Triangle,
    cone: Option<&Cone>,
    tolerance: f32,
    best: f32,
) -> f32 {
    bound_below(aabb, triangle, cone, tolerance, best, 0.0)
}

/// [`directional_distance_bound`] of a piece whose parent pair is bounded by `parent`.
fn bound_below(aabb: &Aabb, triangle: &Triangle, cone: Option<&Cone>, tolerance: f32, best: f32, parent: f32) -> f32 {
    let (cb, rb) = (aabb.center(), aabb.radius());
    let (ct, rt) = (triangle.center(), triangle.radius());
    let offset = ct - cb;
    let distance = offset.length();
    let reach = rb + rt;
    let bound = (distance - reach).max(parent);
    if bound >= best {
        return f32::INFINITY;
    }
    if let Some(cone) = cone
        && distance > reach
    {
        let spread = libm::asinf((reach / distance).min(1.0));
        // A small margin absorbs the rounding of the angle computations.
        if cone.angle_lower_bound(offset) > spread + 1e-5 {
            return f32::INFINITY;
        }
    }
    if rb.max(rt) <= tolerance {
        return bound;
    }
    let mut best = best;
    let children: [(Aabb, Triangle); 2] = if rb >= rt {
        let [l, h] = aabb.split();
        [(l, *triangle), (h, *triangle)]
    } else {
        let [l, h] = triangle.split();
        [(*aabb, l), (*aabb, h)]
    };
    for (b, t) in children {
        best = best.min(bound_below(&b, &t, cone, tolerance, best, bound));
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overlap_test_agrees_with_simple_cases() {
        let unit = Aabb::voxel(0, 0, 0);
        let inside = Triangle([Vec3::splat(0.2), Vec3::new(0.8, 0.2, 0.2), Vec3::new(0.2, 0.8, 0.5)]);
        assert!(triangle_overlaps_box(&inside, &unit));
        let crossing = Triangle([Vec3::new(-1.0, -1.0, 0.5), Vec3::new(3.0, -1.0, 0.5), Vec3::new(-1.0, 3.0, 0.5)]);
        assert!(triangle_overlaps_box(&crossing, &unit));
        let above = Triangle([Vec3::new(-1.0, -1.0, 1.5), Vec3::new(3.0, -1.0, 1.5), Vec3::new(-1.0, 3.0, 1.5)]);
        assert!(!triangle_overlaps_box(&above, &unit));
        // Near a corner but outside along the diagonal: only an edge axis separates it.
        let diagonal = Triangle([Vec3::new(1.6, 0.0, 1.6), Vec3::new(0.0, 1.6, 1.6), Vec3::new(1.6, 1.6, 0.0)]);
        assert!(!triangle_overlaps_box(&diagonal, &unit));
    }

    #[test]
    fn undirected_bound_is_tight_for_a_parallel_plane() {
        let unit = Aabb::voxel(0, 0, 0);
        let above = Triangle([Vec3::new(-1.0, -1.0, 3.0), Vec3::new(3.0, -1.0, 3.0), Vec3::new(-1.0, 3.0, 3.0)]);
        let d = directional_distance_bound(&unit, &above, None, 0.01, f32::INFINITY);
        assert!(d <= 2.0 && d > 1.95, "{d}");
    }

    /// Exact box–triangle distance by dense sampling of the triangle (upper estimate).
    fn sampled_box_triangle_distance(triangle: &Triangle, aabb: &Aabb) -> f32 {
        let [a, b, c] = triangle.0;
        let mut best = f32::INFINITY;
        for i in 0..=60 {
            for j in 0..=(60 - i) {
                let p = a + (b - a) * (i as f32 / 60.0) + (c - a) * (j as f32 / 60.0);
                best = best.min(p.distance(p.clamp(aabb.min, aabb.max)));
            }
        }
        best
    }

    #[test]
    fn box_triangle_distance_is_the_sampled_distance_within_its_resolution() {
        let unit = Aabb::voxel(0, 0, 0);
        let below = Triangle([Vec3::new(-1.0, -1.0, -2.0), Vec3::new(3.0, -1.0, -2.0), Vec3::new(-1.0, 3.0, -2.0)]);
        let d = box_triangle_distance(&unit, &below);
        assert!(d <= 2.0 && d > 2.0 - 1e-4, "{d}");
        // Edge to edge: a segment along y at x = 2, z = 2 is √2 from the box edge x = z = 1.
        let skew = Triangle([Vec3::new(2.0, -3.0, 2.0), Vec3::new(2.0, 4.0, 2.0), Vec3::new(5.0, 0.5, 5.0)]);
        let d = box_triangle_distance(&unit, &skew);
        assert!((d - 2.0_f32.sqrt()).abs() < 1e-4, "{d}");
        let mut next = crate::test_random::uniform(0x9f1c_3a5d_77e2_0b49_u64);
        let mut compared = 0;
        for _ in 0..300 {
            let mut vertex = || Vec3::new(next(), next(), next()) * 6.0 - 2.5;
            let triangle = Triangle([vertex(), vertex(), vertex()]);
            let d = box_triangle_distance(&unit, &triangle);
            // The sampled distance is an upper estimate within the sampling's spacing
            // (the triangle's longest edge / 60, its edges below 6√3).
            let sampled = sampled_box_triangle_distance(&triangle, &unit);
            assert!(d <= sampled + 1e-5, "{triangle:?}: {d} > sampled {sampled}");
            assert!(d >= sampled - 6.0 * 3.0_f32.sqrt() / 60.0, "{triangle:?}: {d} ≪ sampled {sampled}");
            assert!(d >= separation_lower_bound(&triangle, &unit) - 1e-4, "{triangle:?}");
            if triangle_overlaps_box(&triangle, &unit) {
                assert_eq!(d, 0.0, "{triangle:?}");
            }
            compared += 1;
        }
        assert_eq!(compared, 300);
    }

    #[test]
    fn separation_bound_is_below_the_distance_and_exact_for_faces() {
        let unit = Aabb::voxel(0, 0, 0);
        let below = Triangle([Vec3::new(-1.0, -1.0, -2.0), Vec3::new(3.0, -1.0, -2.0), Vec3::new(-1.0, 3.0, -2.0)]);
        let d = separation_lower_bound(&below, &unit);
        assert!(d <= 2.0 && d > 2.0 - 1e-5, "{d}");
        let mut next = crate::test_random::uniform(0x2545_f491_4f6c_dd1d_u64);
        let (mut ratio_sum, mut ratio_count) = (0.0, 0);
        for _ in 0..300 {
            let mut vertex = || Vec3::new(next(), next(), next()) * 6.0 - 2.5;
            let triangle = Triangle([vertex(), vertex(), vertex()]);
            let truth = sampled_box_triangle_distance(&triangle, &unit);
            let bound = separation_lower_bound(&triangle, &unit);
            assert!(bound <= truth + 1e-5, "{triangle:?}: bound {bound} > {truth}");
            assert_eq!(bound == 0.0, triangle_overlaps_box(&triangle, &unit) || truth < 1e-3, "{triangle:?}");
            if truth > 0.1 {
                ratio_sum += bound / truth;
                ratio_count += 1;
            }
            // The nearest point lies on the triangle: no point of it is nearer the centre.
            let p = closest_point_on_triangle(unit.center(), &triangle);
            assert!(
                p.distance(unit.center())
                    <= sampled_box_triangle_distance(&triangle, &Aabb { min: unit.center(), max: unit.center() })
                        + 1e-5
            );
        }
        // Compared for tightness: the triangles farther than 0.1 voxel; their vertices
        // spread over [-2.5, 3.5]³ around the unit box, so most are (measured 178 of 300).
        assert!(ratio_count * 2 >= 300, "{ratio_count}");
        separation_tightness_pin(ratio_sum / ratio_count as f32, ratio_count);
    }

    /// Regression pin of how tight the separation bound is (not a property: the bound is
    /// exact only for face-to-face configurations, and no guarantee on its ratio to the
    /// distance is derived): the mean `bound / distance` over the random triangles farther
    /// than 0.1 voxel, measured 0.983 over 178 triangles, pinned at 0.95.
    fn separation_tightness_pin(mean_ratio: f32, count: usize) {
        assert!(mean_ratio > 0.95, "regression pin: mean ratio {mean_ratio} over {count}");
    }
}
