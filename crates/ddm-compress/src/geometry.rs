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
    fn split(&self) -> [Self; 2] {
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
    fn split(&self) -> [Self; 2] {
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
    let center = aabb.center();
    let half = (aabb.max - aabb.min) * 0.5;
    let [a, b, c] = triangle.0.map(|v| v - center);
    let edges = [b - a, c - b, a - c];
    let separated = |axis: Vec3| {
        if axis.length_squared() < 1e-20 {
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
}
