//! Witnesses: real point pairs `(v, m)` of a box and a triangle whose offset `m − v` lies in
//! a cone, whose lengths are upper bounds of the cone's distance.

use glam::Vec3;

use crate::bvh::TriangleBvh;
use crate::convex_cone::ConvexCone;
use crate::geometry::{Aabb, Triangle};

/// Whether the direction `d` may join a witness pair: in the cone, by
/// [`ConvexCone::contains_within`], when the convex cone is the cone itself; else in the
/// convex cone up to [`crate::convex_cone::WITNESS_SLACK`] ([`ConvexCone::contains_nearly`]),
/// whose distance the search computes then (see the module documentation).
pub(super) fn contains(convex: &ConvexCone, d: Vec3) -> bool {
    convex.contains_within(d).unwrap_or_else(|| convex.contains_nearly(d))
}

/// The unit direction of `projected` (a projection onto the cone), nudged towards the
/// cone's centre when rounding leaves it outside, or `None` when neither is in the cone.
fn witness_direction(convex: &ConvexCone, projected: Vec3) -> Option<Vec3> {
    let projected = projected.normalize_or_zero();
    [projected, (projected + 1e-3 * convex.center()).normalize_or_zero()]
        .into_iter()
        .find(|&d| d != Vec3::ZERO && contains(convex, d))
}

/// The corner of `aabb` farthest along `direction`, taking `inside`'s coordinate along the
/// axes that `direction` (nearly) does not move along.
fn front_of(aabb: &Aabb, direction: Vec3, inside: Vec3) -> Vec3 {
    Vec3::select(
        direction.cmpgt(Vec3::splat(1e-6)),
        aabb.max,
        Vec3::select(direction.cmplt(Vec3::splat(-1e-6)), aabb.min, inside),
    )
}

/// A witness for the pair (`aabb`, `triangle`) of the cone that `convex` holds (or of
/// `convex` itself, see [`contains`]): the length of a ray from a point of the box, in a
/// direction of the cone, to the triangle, or `None` when the
/// rays tried miss. The direction is the projection of `axis` onto the cone (nudged
/// towards the cone's centre when rounding leaves it on the boundary); the rays leave
/// from the box's front in that direction and from the box point nearest `nearest`.
/// Also returns the point of the triangle reached.
pub(super) fn ray_witness(
    convex: &ConvexCone,
    aabb: &Aabb,
    triangle: &Triangle,
    axis: Vec3,
    nearest: Vec3,
) -> Option<(f32, Vec3)> {
    let direction = witness_direction(convex, convex.project(axis))?;
    let inside = nearest.clamp(aabb.min, aabb.max);
    [front_of(aabb, direction, inside), inside]
        .into_iter()
        .filter_map(|origin| ray_triangle(origin, direction, triangle).map(|t| (t, origin + direction * t)))
        .reduce(|a, b| if b.0 < a.0 { b } else { a })
}

/// A witness (as [`ray_witness`]'s) for a box and a point `m` of the mesh: the distance from `m` back
/// along a direction of the cone (the projection of `m − c_B` onto it, `c_B` the box
/// centre) to where that line enters the box, or `None` when it misses the box. A line
/// that only touches the box (along an edge: the only contact of a cone that meets the
/// mesh on its boundary) counts: the box point is the entry point clamped into the box,
/// and the pair's own direction must pass [`contains`].
pub(super) fn box_witness(convex: &ConvexCone, aabb: &Aabb, m: Vec3) -> Option<f32> {
    let direction = witness_direction(convex, convex.project(m - aabb.center()))?;
    // The points m − t d, t ≥ 0, inside the box: the slab intervals of t.
    let (mut enter, mut leave) = (0.0_f32, f32::INFINITY);
    for axis in 0..3 {
        let (d, p) = (direction[axis], m[axis]);
        if d.abs() < 1e-12 {
            if p < aabb.min[axis] || p > aabb.max[axis] {
                return None;
            }
            continue;
        }
        let (t1, t2) = ((p - aabb.min[axis]) / d, (p - aabb.max[axis]) / d);
        enter = enter.max(t1.min(t2));
        leave = leave.min(t1.max(t2));
    }
    // A little past the entry point where the line crosses the box; the entry point where
    // it only touches it (rounding can put `leave` a hair before `enter`).
    let step = 1e-5 * (1.0 + enter);
    if !(enter <= leave + step && enter.is_finite()) {
        return None;
    }
    let t = if enter + step <= leave { enter + step } else { enter };
    let v = (m - direction * t).clamp(aabb.min, aabb.max);
    let offset = m - v;
    contains(convex, offset).then(|| offset.length())
}

/// The distance along the unit `direction` from `origin` to `triangle` (Möller–Trumbore),
/// or `None` when the ray misses it.
pub(super) fn ray_triangle(origin: Vec3, direction: Vec3, triangle: &Triangle) -> Option<f32> {
    let [a, b, c] = triangle.0;
    let (e1, e2) = (b - a, c - a);
    let p = direction.cross(e2);
    let det = e1.dot(p);
    if det.is_nan() || det.abs() < 1e-12 {
        return None;
    }
    let s = origin - a;
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = direction.dot(q) / det;
    let t = e2.dot(q) / det;
    (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t >= 0.0 && t.is_finite()).then_some(t)
}

/// A witness of the box `aabb` against the whole mesh (the hierarchy `bvh`) rather than one
/// triangle: rays from the box's front and from the box point nearest `nearest`, along
/// the projection of `axis` onto the cone (as [`ray_witness`]'s), to the first triangle
/// they meet within `max_t`. It is the pair witnesses' fallback: where the cone's nearest
/// mesh point lies on another triangle than the pair's (a floor seen along the band's
/// steepest direction lands beyond the triangle below the box), the pairs alone find no
/// witness, the upper bound stays at the cap, and every pair is split down to the
/// tolerance's size. Returns the ray's length and the mesh point it reaches.
pub(super) fn mesh_witness(
    convex: &ConvexCone,
    aabb: &Aabb,
    axis: Vec3,
    nearest: Vec3,
    bvh: &TriangleBvh,
    max_t: f32,
) -> Option<(f32, Vec3)> {
    let direction = witness_direction(convex, convex.project(axis))?;
    let inside = nearest.clamp(aabb.min, aabb.max);
    let mut best: Option<(f32, Vec3)> = None;
    for origin in [front_of(aabb, direction, inside), inside] {
        let limit = best.map_or(max_t, |b| b.0);
        if let Some(t) = mesh_ray(bvh, origin, direction, limit) {
            best = Some((t, origin + direction * t));
        }
    }
    best
}

/// The length along the unit `direction` from `origin` to a triangle of `bvh` that the
/// ray meets within `max_t` (the nearest, unless the hierarchy is deeper than the
/// traversal's fixed stack or a box test rounds a node away: a witness needs a real hit,
/// not the nearest), or `None`.
pub(super) fn mesh_ray(bvh: &TriangleBvh, origin: Vec3, direction: Vec3, max_t: f32) -> Option<f32> {
    let inverse = direction.recip();
    // Where the ray enters node `node`'s box before `limit`, by the slab test.
    let entry = |node: u32, limit: f32| -> Option<f32> {
        let b = bvh.node_bounds(node)?;
        let (t1, t2) = ((b.min - origin) * inverse, (b.max - origin) * inverse);
        let near = t1.min(t2).max_element().max(0.0);
        let far = t1.max(t2).min_element().min(limit);
        (near <= far).then_some(near)
    };
    let mut stack = [(0_u32, 0.0_f32); 64];
    let mut top = 0;
    let mut best = max_t;
    let mut found = false;
    if let Some(t) = entry(0, best) {
        stack[0] = (0, t);
        top = 1;
    }
    while top > 0 {
        top -= 1;
        let (node, near) = stack[top];
        if near > best {
            continue;
        }
        if let Some(indices) = bvh.leaf_indices(node) {
            for &i in indices {
                if let Some(triangle) = bvh.triangles().get(i as usize)
                    && let Some(t) = ray_triangle(origin, direction, triangle)
                    && t < best
                {
                    (best, found) = (t, true);
                }
            }
        } else if let Some(children) = bvh.children(node) {
            // The nearer child on top of the stack: its hits shorten the ray for the other.
            let mut entries = children.map(|child| entry(child, best).map(|t| (child, t)));
            if let [Some(a), Some(b)] = entries
                && a.1 < b.1
            {
                entries = [Some(b), Some(a)];
            }
            for entry in entries.into_iter().flatten() {
                if top < stack.len() {
                    stack[top] = entry;
                    top += 1;
                }
            }
        }
    }
    found.then_some(best)
}

#[cfg(test)]
mod tests {
    use alloc::vec::Vec;

    use super::*;
    use crate::test_random::uniform;

    #[test]
    fn mesh_rays_meet_the_nearest_triangle_that_every_triangle_tried_in_turn_meets() {
        let mut next = uniform(0x9e37_79b9_7f4a_7c15);
        let triangles: Vec<Triangle> = (0..300)
            .map(|_| {
                let centre = Vec3::new(next(), next(), next()) * 20.0;
                let mut vertex = || centre + Vec3::new(next(), next(), next()) * 3.0 - 1.5;
                Triangle([vertex(), vertex(), vertex()])
            })
            .collect();
        let bvh = TriangleBvh::new(triangles.clone());
        let (mut hits, mut misses) = (0, 0);
        for _ in 0..2000 {
            let origin = Vec3::new(next(), next(), next()) * 20.0;
            let direction = (Vec3::new(next(), next(), next()) * 2.0 - 1.0).normalize_or_zero();
            if direction == Vec3::ZERO {
                continue;
            }
            let max_t = 5.0 + next() * 20.0;
            let every = triangles
                .iter()
                .filter_map(|t| ray_triangle(origin, direction, t))
                .filter(|&t| t < max_t)
                .reduce(f32::min);
            match (mesh_ray(&bvh, origin, direction, max_t), every) {
                (Some(t), Some(u)) => {
                    assert!((t - u).abs() <= 1e-4 * (1.0 + u), "{origin} {direction}: {t} vs {u}");
                    hits += 1;
                }
                (None, None) => misses += 1,
                (found, expected) => panic!("{origin} {direction}: {found:?} vs {expected:?}"),
            }
        }
        // Both outcomes compared often (the triangles fill about a tenth of the box).
        assert!(hits >= 200 && misses >= 200, "{hits} hits, {misses} misses");
    }
}
