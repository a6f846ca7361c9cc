//! Witnesses: real point pairs `(v, m)` of a box and a triangle whose offset `m − v` lies in
//! a cone, whose lengths are upper bounds of the cone's distance.

use glam::Vec3;

use crate::convex_cone::ConvexCone;
use crate::geometry::{Aabb, Triangle};

/// Whether the direction `d` may join a witness pair: in the cone, by
/// [`ConvexCone::contains_within`], when the convex cone is the cone itself; else in the
/// convex cone ([`ConvexCone::contains`]), whose distance the search computes then (see the
/// module documentation).
pub(super) fn contains(convex: &ConvexCone, d: Vec3) -> bool {
    convex.contains_within(d).unwrap_or_else(|| convex.contains(d))
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
    let projected = convex.project(axis).normalize_or_zero();
    let direction = [projected, (projected + 1e-3 * convex.center()).normalize_or_zero()]
        .into_iter()
        .find(|&d| d != Vec3::ZERO && contains(convex, d))?;
    let inside = nearest.clamp(aabb.min, aabb.max);
    let front = Vec3::select(
        direction.cmpgt(Vec3::splat(1e-6)),
        aabb.max,
        Vec3::select(direction.cmplt(Vec3::splat(-1e-6)), aabb.min, inside),
    );
    [front, inside]
        .into_iter()
        .filter_map(|origin| ray_triangle(origin, direction, triangle).map(|t| (t, origin + direction * t)))
        .reduce(|a, b| if b.0 < a.0 { b } else { a })
}

/// A witness (as [`ray_witness`]'s) for a box and a point `m` of the mesh: the distance from `m` back
/// along a direction of the cone (the projection of `m − c_B` onto it, `c_B` the box
/// centre) to where that line enters the box, or `None` when it misses the box.
pub(super) fn box_witness(convex: &ConvexCone, aabb: &Aabb, m: Vec3) -> Option<f32> {
    let projected = convex.project(m - aabb.center()).normalize_or_zero();
    let direction = [projected, (projected + 1e-3 * convex.center()).normalize_or_zero()]
        .into_iter()
        .find(|&d| d != Vec3::ZERO && contains(convex, d))?;
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
    // Rounding can put the entry point a hair outside the box: step a little further in.
    let t = enter + 1e-5 * (1.0 + enter);
    (t <= leave && t.is_finite()).then_some(t)
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
