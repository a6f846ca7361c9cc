//! Ground truth: the exact first intersection of a ray with the original triangle mesh of
//! a tile that repeats periodically in x and y (§3.2's rays through a tiled mesostructure),
//! or of a tile alone.
//!
//! A small bounding volume hierarchy (median split along the longest axis) holds the
//! tile's triangles in double precision; a ray is tested against every copy of the tile
//! whose box its segment can reach, and the nearest hit wins. Ray–triangle tests use the
//! Möller–Trumbore formulation in `f64`, edges inclusive, so a ray through a shared edge
//! hits one of the two triangles.

use alloc::vec::Vec;

use ddm_compress::Triangle;
use glam::{DVec3, Vec2, Vec3};

/// Triangles per leaf of the hierarchy.
const LEAF_SIZE: usize = 4;

#[derive(Clone, Copy, Debug)]
struct Node {
    min: DVec3,
    max: DVec3,
    /// Leaf: first triangle; inner: index of the first child (the second follows it).
    first: u32,
    /// Triangles of a leaf, 0 for an inner node.
    count: u32,
}

/// The first intersection of a ray with the mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshHit {
    /// Ray parameter of the hit (`origin + t direction`, `direction` as given).
    pub t: f64,
    /// The hit point (in the ray's unwrapped coordinates, not reduced to the tile).
    pub point: DVec3,
    /// The unit geometric normal of the triangle hit, facing the ray.
    pub normal: DVec3,
}

/// One crossing of a ray with the mesh ([`MeshRaycaster::crossings`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshCrossing {
    /// Ray parameter of the crossing.
    pub t: f64,
    /// Whether the ray leaves the solid there: it runs along the triangle's normal
    /// `(b − a) × (c − a)`, which points out of the solid in an outward-oriented mesh.
    pub exiting: bool,
    /// The smallest barycentric coordinate of the crossing in its triangle: near 0 at an
    /// edge or a vertex, where a neighbouring triangle may report the same crossing.
    pub margin: f64,
}

/// A periodic triangle mesh with a ray hierarchy.
#[derive(Clone, Debug)]
pub struct MeshRaycaster {
    triangles: Vec<[DVec3; 3]>,
    nodes: Vec<Node>,
    period: Vec2,
}

fn triangle_bounds(t: &[DVec3; 3]) -> (DVec3, DVec3) {
    (t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2]))
}

impl MeshRaycaster {
    /// The hierarchy of `triangles`, repeated with period `period` in x and y (`period`
    /// components ≤ 0 or not finite disable the repetition along that axis). Non-finite
    /// triangles are dropped.
    pub fn new(triangles: &[Triangle], period: Vec2) -> Self {
        let mut tris: Vec<[DVec3; 3]> =
            triangles.iter().filter(|t| t.0.iter().all(|v| v.is_finite())).map(|t| t.0.map(Vec3::as_dvec3)).collect();
        let mut nodes = Vec::new();
        if !tris.is_empty() {
            let len = tris.len();
            build(&mut tris, 0, len, &mut nodes);
        }
        Self { triangles: tris, nodes, period }
    }

    /// The period in x and y (a component ≤ 0 or not finite: no repetition along that
    /// axis).
    pub fn period(&self) -> Vec2 {
        self.period
    }

    /// Number of triangles in the hierarchy.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// The first hit of the ray `origin + t direction`, `t ∈ [0, t_max]`, with the mesh and
    /// all its periodic copies, or `None`.
    pub fn first_hit(&self, origin: DVec3, direction: DVec3, t_max: f64) -> Option<MeshHit> {
        let (t0, t1) = self.z_range(origin, direction, 0.0, t_max)?;
        let copies = self.copies(origin + direction * t0, origin + direction * t1);
        let mut best: Option<(f64, usize, DVec3)> = None;
        let mut stack = Vec::with_capacity(64);
        for shift in copies {
            let local = origin - shift;
            let limit = best.map_or(t1, |b| b.0);
            if let Some((t, index)) = self.first_hit_local(local, direction, t0, limit, &mut stack)
                && best.is_none_or(|b| t < b.0)
            {
                best = Some((t, index, shift));
            }
        }
        let (t, index, _) = best?;
        let [a, b, c] = self.triangles[index];
        let mut normal = (b - a).cross(c - a).normalize_or_zero();
        if normal.dot(direction) > 0.0 {
            normal = -normal;
        }
        Some(MeshHit { t, point: origin + direction * t, normal })
    }

    /// The part `[t0, t1]` of `[t_min, t_max]` where the ray is within the mesh's z range
    /// (widened by a little, so that hits on the bounding planes are not lost to rounding),
    /// or `None`.
    fn z_range(&self, origin: DVec3, direction: DVec3, t_min: f64, t_max: f64) -> Option<(f64, f64)> {
        let root = self.nodes.first()?;
        if !(origin.is_finite() && direction.is_finite() && direction != DVec3::ZERO) {
            return None;
        }
        let (mut t0, mut t1) = (t_min, t_max);
        if direction.z == 0.0 {
            if origin.z < root.min.z || origin.z > root.max.z {
                return None;
            }
        } else {
            let (lo, hi) = (root.min.z - 1e-9, root.max.z + 1e-9);
            let (a, b) = ((lo - origin.z) / direction.z, (hi - origin.z) / direction.z);
            t0 = t0.max(a.min(b));
            t1 = t1.min(a.max(b));
        }
        // Also rejects NaN bounds.
        if t0.partial_cmp(&t1).is_none_or(|o| o == core::cmp::Ordering::Greater) {
            return None;
        }
        Some((t0, t1))
    }

    /// The shifts of the tile's copies whose boxes the segment `p0`–`p1` can reach.
    fn copies(&self, p0: DVec3, p1: DVec3) -> Vec<DVec3> {
        let Some(root) = self.nodes.first() else { return Vec::new() };
        let span = |axis: usize, period: f32| -> (i64, i64) {
            if !(period > 0.0 && period.is_finite()) {
                return (0, 0);
            }
            let period = f64::from(period);
            let (lo, hi) = (p0[axis].min(p1[axis]), p0[axis].max(p1[axis]));
            // Copies k with [min + kP, max + kP] meeting [lo, hi].
            let first = libm::floor((lo - root.max[axis]) / period) as i64;
            let last = libm::ceil((hi - root.min[axis]) / period) as i64;
            (first, last.max(first))
        };
        let (x0, x1) = span(0, self.period.x);
        let (y0, y1) = span(1, self.period.y);
        let copy = |k: i64, period: f32| if k == 0 { 0.0 } else { k as f64 * f64::from(period) };
        let mut shifts = Vec::new();
        for ky in y0..=y1 {
            for kx in x0..=x1 {
                shifts.push(DVec3::new(copy(kx, self.period.x), copy(ky, self.period.y), 0.0));
            }
        }
        shifts
    }

    /// Every crossing of the ray `origin + t direction`, `t ∈ [t_min, t_max]`, with the mesh
    /// and its periodic copies, appended to `out` in no particular order. A ray through an
    /// edge or a vertex may report one crossing per triangle there; [`MeshCrossing::margin`]
    /// tells such crossings apart.
    pub fn crossings(&self, origin: DVec3, direction: DVec3, t_min: f64, t_max: f64, out: &mut Vec<MeshCrossing>) {
        let Some((t0, t1)) = self.z_range(origin, direction, t_min, t_max) else { return };
        let mut stack = Vec::with_capacity(64);
        for shift in self.copies(origin + direction * t0, origin + direction * t1) {
            let local = origin - shift;
            self.visit_triangles(local, direction, t0, t1, &mut stack, |_, triangle| {
                if let Some((t, margin)) = ray_triangle_margin(triangle, local, direction)
                    && t >= t0
                    && t <= t1
                {
                    let [a, b, c] = *triangle;
                    let exiting = (b - a).cross(c - a).dot(direction) > 0.0;
                    out.push(MeshCrossing { t, exiting, margin });
                }
                None
            });
        }
    }

    /// Calls `visit` with the index and the vertices of every triangle of the leaves whose
    /// boxes the ray `origin + t direction` meets within `[t_min, t_max]`; a `visit` that
    /// returns `Some(t)` lowers `t_max` to `t` for the rest of the traversal.
    fn visit_triangles(
        &self,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        mut t_max: f64,
        stack: &mut Vec<u32>,
        mut visit: impl FnMut(usize, &[DVec3; 3]) -> Option<f64>,
    ) {
        let inverse = direction.recip();
        stack.clear();
        stack.push(0);
        while let Some(index) = stack.pop() {
            let node = self.nodes[index as usize];
            if !slab_test(node.min, node.max, origin, inverse, t_min, t_max) {
                continue;
            }
            if node.count == 0 {
                stack.push(node.first);
                stack.push(node.first + 1);
                continue;
            }
            for index in node.first as usize..(node.first + node.count) as usize {
                if let Some(t) = visit(index, &self.triangles[index]) {
                    t_max = t;
                }
            }
        }
    }

    fn first_hit_local(
        &self,
        origin: DVec3,
        direction: DVec3,
        t_min: f64,
        t_max: f64,
        stack: &mut Vec<u32>,
    ) -> Option<(f64, usize)> {
        let mut best = None;
        let mut limit = t_max;
        self.visit_triangles(origin, direction, t_min, t_max, stack, |index, triangle| {
            let t = ray_triangle(triangle, origin, direction).filter(|&t| t >= t_min && t <= limit)?;
            limit = t;
            best = Some((t, index));
            Some(t)
        });
        best
    }
}

/// Whether the ray meets the box within `[t_min, t_max]` (infinite inverse components
/// are handled by IEEE arithmetic; a NaN from `0 · ∞` counts as inside).
fn slab_test(min: DVec3, max: DVec3, origin: DVec3, inverse: DVec3, t_min: f64, t_max: f64) -> bool {
    let (mut lo, mut hi) = (t_min, t_max);
    for axis in 0..3 {
        let a = (min[axis] - origin[axis]) * inverse[axis];
        let b = (max[axis] - origin[axis]) * inverse[axis];
        let (near, far) = if a <= b { (a, b) } else { (b, a) };
        if near.is_nan() || far.is_nan() {
            if origin[axis] < min[axis] || origin[axis] > max[axis] {
                return false;
            }
            continue;
        }
        lo = lo.max(near);
        hi = hi.min(far);
    }
    lo <= hi * (1.0 + 1e-12) + 1e-12
}

/// Möller–Trumbore in `f64`, edges inclusive: the ray parameter of the hit, or `None`
/// for a miss or a ray parallel to the triangle.
pub fn ray_triangle(triangle: &[DVec3; 3], origin: DVec3, direction: DVec3) -> Option<f64> {
    ray_triangle_margin(triangle, origin, direction).map(|(t, _)| t)
}

/// [`ray_triangle`] with the hit's smallest barycentric coordinate.
fn ray_triangle_margin(triangle: &[DVec3; 3], origin: DVec3, direction: DVec3) -> Option<(f64, f64)> {
    let [a, b, c] = *triangle;
    let (e1, e2) = (b - a, c - a);
    let p = direction.cross(e2);
    let det = e1.dot(p);
    if det == 0.0 || !det.is_finite() {
        return None;
    }
    let inv = 1.0 / det;
    let s = origin - a;
    let u = s.dot(p) * inv;
    if !(-1e-12..=1.0 + 1e-12).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = direction.dot(q) * inv;
    if v < -1e-12 || u + v > 1.0 + 1e-12 {
        return None;
    }
    Some((e2.dot(q) * inv, u.min(v).min(1.0 - u - v)))
}

fn build(tris: &mut [[DVec3; 3]], start: usize, end: usize, nodes: &mut Vec<Node>) {
    nodes.push(Node { min: DVec3::ZERO, max: DVec3::ZERO, first: 0, count: 0 });
    build_into(tris, start, end, nodes, 0);
}

/// Builds the subtree of `tris[start..end]` into the reserved slot `slot`.
fn build_into(tris: &mut [[DVec3; 3]], start: usize, end: usize, nodes: &mut Vec<Node>, slot: usize) {
    let (mut min, mut max) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for t in &tris[start..end] {
        let (lo, hi) = triangle_bounds(t);
        min = min.min(lo);
        max = max.max(hi);
    }
    if end - start <= LEAF_SIZE {
        nodes[slot] = Node { min, max, first: start as u32, count: (end - start) as u32 };
        return;
    }
    let size = max - min;
    let axis = if size.x >= size.y && size.x >= size.z {
        0
    } else if size.y >= size.z {
        1
    } else {
        2
    };
    let key = |t: &[DVec3; 3]| t[0][axis] + t[1][axis] + t[2][axis];
    tris[start..end].sort_unstable_by(|a, b| key(a).total_cmp(&key(b)));
    let middle = start + (end - start) / 2;
    let children = nodes.len();
    nodes.push(Node { min, max, first: 0, count: 0 });
    nodes.push(Node { min, max, first: 0, count: 0 });
    build_into(tris, start, middle, nodes, children);
    build_into(tris, middle, end, nodes, children + 1);
    nodes[slot] = Node { min, max, first: children as u32, count: 0 };
}

#[cfg(test)]
mod tests {
    use super::*;

    fn brute(tris: &[Triangle], origin: DVec3, direction: DVec3, period: Vec2) -> Option<f64> {
        let mut best: Option<f64> = None;
        // Rays descend at least 17° over 4 voxels: at most 13 voxels sideways, 2 tiles of 8.
        for kx in -2..=2 {
            for ky in -2..=2 {
                let shift = DVec3::new(f64::from(kx as f32 * period.x), f64::from(ky as f32 * period.y), 0.0);
                for t in tris {
                    let t = t.0.map(|v| v.as_dvec3() + shift);
                    if let Some(h) = ray_triangle(&t, origin, direction)
                        && h >= 0.0
                        && best.is_none_or(|b| h < b)
                    {
                        best = Some(h);
                    }
                }
            }
        }
        best
    }

    #[test]
    fn periodic_hierarchy_matches_brute_force() {
        let size = glam::UVec3::new(8, 8, 4);
        let tris = mesostructure::beads(size);
        let caster = MeshRaycaster::new(&tris, Vec2::new(8.0, 8.0));
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut hits = 0;
        for _ in 0..200 {
            let origin = DVec3::new(next() * 8.0, next() * 8.0, 4.0);
            let direction = DVec3::new(next() * 2.0 - 1.0, next() * 2.0 - 1.0, -0.3 - next()).normalize();
            let fast = caster.first_hit(origin, direction, 1e3).map(|h| h.t);
            let slow = brute(&tris, origin, direction, Vec2::new(8.0, 8.0));
            match (fast, slow) {
                (Some(a), Some(b)) => {
                    assert!((a - b).abs() < 1e-9, "{a} vs {b}");
                    hits += 1;
                }
                (None, None) => {}
                other => panic!("{origin} {direction}: {other:?}"),
            }
        }
        assert!(hits > 150);
    }
}
