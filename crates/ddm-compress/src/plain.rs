//! The plain distance map's per-voxel search: the Euclidean distance from a voxel (a box)
//! to the mesh, bounded from below within `tolerance`, over the triangle hierarchy.
//!
//! For one box `B` and one triangle `T`, alternating projections (von Neumann's method
//! for two convex sets) walk towards their closest pair: `q₀` is the point of `T` nearest
//! the box centre `c`, `pₖ` the point of `B` nearest `qₖ₋₁` and `qₖ` the point of `T`
//! nearest `pₖ`. Each step certifies both sides of the pair distance `D(B, T)`:
//!
//! - `|pₖ − qₖ| ≥ D(B, T)`: a real pair of points;
//! - `(c − qₖ)·n − h(n) ≤ D(B, T)` with `n` the unit vector from `qₖ` to the point it is
//!   nearest to (`c` for `k = 0`, `pₖ` after) and `h(n) = ½ (|nₓ| + |n_y| + |n_z|)` the
//!   unit box's support: `qₖ` is a projection onto the convex `T`, so the plane through
//!   `qₖ` normal to `n` has all of `T` on its far side, and every point of `B` lies at
//!   least `(c − qₖ)·n − h(n)` in front of it.
//!
//! The pair is settled once the bounds are within `tolerance` (or the lower bound reaches
//! the voxel's current minimum, so that it cannot lower it); a pair that has not settled
//! after [`MAX_PROJECTIONS`] steps (edges nearly parallel make the method slow) takes the
//! exact distance of [`box_triangle_distance`]. The voxel's value is the minimum of the
//! pairs' lower bounds: a lower bound of the distance from the box to the mesh within
//! `tolerance` of it. Since the first step's bound is at least `|c − q₀| − √3/2`, the value
//! is never below the distance from the voxel's centre less half its diagonal, the
//! conservative bound that a point-sampled distance field gives.
//!
//! The search runs over [`PlainHierarchy`], the triangle hierarchy laid out for it (both
//! children's boxes in their parent, leaves of up to [`LEAF_TRIANGLES`] triangles stored
//! side by side with their boxes). Nodes are visited nearest first (the gap between the
//! voxel and the node's box) and skipped once that gap reaches the current minimum, as are
//! triangles whose box is that far; the previous voxel's nearest triangle is tried first,
//! which usually sets a close minimum at once.

use alloc::vec::Vec;

use glam::Vec3;

use crate::bvh::TriangleBvh;
use crate::geometry::{Aabb, Triangle, box_triangle_distance, closest_point_on_triangle};

/// The most alternating projections per box–triangle pair before the exact distance is
/// computed instead.
pub(crate) const MAX_PROJECTIONS: u32 = 6;

/// The most triangles of a [`PlainHierarchy`] leaf.
pub(crate) const LEAF_TRIANGLES: u32 = 12;

/// The relative rounding margin of the certified lower bounds (a few float ulps of the
/// coordinates, as in [`crate::geometry::separation_lower_bound`]).
pub(crate) const MARGIN: f32 = 2e-6;

/// The relative rounding slack of the squared box gaps that the hierarchy's search compares
/// with the current minimum ([`PlainHierarchy::voxel_distance`]).
pub(crate) const GAP_SLACK: f32 = 4e-7;

/// A certified lower bound of `D(aabb, triangle)` within `tolerance` of it, or at least
/// `best` (then possibly looser): see the module documentation. `true` in the second place
/// when the exact distance had to be computed.
///
/// `magnitude` bounds the magnitude of the triangle's vertex coordinates (it sets the
/// rounding margin, [`rounding_margin`]).
pub(crate) fn pair_lower_bound(
    aabb: &Aabb,
    triangle: &Triangle,
    tolerance: f32,
    best: f32,
    magnitude: f32,
) -> (f32, bool) {
    let center = aabb.center();
    let half = (aabb.max - aabb.min) * 0.5;
    // Relative to the box centre: the projections then round at the scale of the distance.
    let local = Triangle(triangle.0.map(|v| v - center));
    let margin = rounding_margin(aabb, magnitude);
    let support = |n: Vec3| half.dot(n.abs());
    let mut q = closest_point_on_triangle(Vec3::ZERO, &local);
    let mut lower = f32::NEG_INFINITY;
    let to_center = -q;
    let length = to_center.length();
    if length > 0.0 {
        let n = to_center / length;
        lower = length - support(n) - margin;
    }
    for _ in 0..MAX_PROJECTIONS {
        if lower >= best {
            return (lower.max(0.0), false);
        }
        let p = q.clamp(-half, half);
        let upper = p.distance(q);
        if upper - lower.max(0.0) <= tolerance {
            return (lower.max(0.0), false);
        }
        q = closest_point_on_triangle(p, &local);
        let gap = p - q;
        let length = gap.length();
        if length > 0.0 {
            let n = gap / length;
            lower = lower.max(-q.dot(n) - support(n) - margin);
        } else {
            // The box touches the triangle.
            return (0.0, false);
        }
    }
    if lower >= best {
        return (lower.max(0.0), false);
    }
    (box_triangle_distance(aabb, triangle), true)
}

/// The rounding margin of the bounds of a pair of `aabb` and a triangle whose vertex
/// coordinates are at most `magnitude` in size: [`MARGIN`] times the largest coordinate of
/// the triangle relative to the box centre (at most `|c| + magnitude`) plus the centre's.
fn rounding_margin(aabb: &Aabb, magnitude: f32) -> f32 {
    let center = aabb.center().abs().max_element();
    MARGIN * (1.0 + 2.0 * center + magnitude)
}

/// What the search of one voxel found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PlainValue {
    /// The lower bound of the voxel's distance to the mesh (at most the cap).
    pub(crate) value: f32,
    /// The triangle whose bound gave `value`, if any did (an index into the hierarchy's
    /// triangles in leaf order, [`PlainHierarchy::triangle`]).
    pub(crate) nearest: Option<u32>,
}

/// A child of a [`PlainNode`]: an inner node's index, or a leaf's range of triangles.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Child {
    Node(u32),
    Leaf { first: u32, count: u32 },
}

/// An inner node of [`PlainHierarchy`]: both children's boxes side by side, so that one
/// visit reads one node.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PlainNode {
    pub(crate) bounds: [Aabb; 2],
    pub(crate) children: [Child; 2],
}

/// The triangle hierarchy laid out for the plain map's search: a [`TriangleBvh`]'s
/// nodes with their children's boxes, and its triangles (with their boxes) copied in leaf
/// order, so that a leaf's triangles lie side by side.
#[derive(Clone, Debug)]
pub(crate) struct PlainHierarchy {
    pub(crate) nodes: Vec<PlainNode>,
    /// A root that is a leaf (at most a leaf's worth of triangles), or the first node.
    pub(crate) root: Option<(Aabb, Child)>,
    pub(crate) triangles: Vec<Triangle>,
    pub(crate) triangle_bounds: Vec<Aabb>,
    /// The largest vertex coordinate magnitude (for the rounding margins).
    pub(crate) magnitude: f32,
}

impl PlainHierarchy {
    /// Lays out `bvh` for [`PlainHierarchy::voxel_distance`].
    pub(crate) fn new(bvh: &TriangleBvh) -> Self {
        let mut hierarchy = Self {
            nodes: Vec::new(),
            root: None,
            triangles: Vec::with_capacity(bvh.triangles().len()),
            triangle_bounds: Vec::with_capacity(bvh.triangles().len()),
            magnitude: 0.0,
        };
        if let Some(bounds) = bvh.node_bounds(0) {
            hierarchy.magnitude = bounds.min.abs().max(bounds.max.abs()).max_element();
            let root = hierarchy.lay_out(bvh, 0);
            hierarchy.root = Some((bounds, root));
        }
        hierarchy
    }

    /// Appends the subtree of `bvh`'s node `index` and returns how to reach it.
    fn lay_out(&mut self, bvh: &TriangleBvh, index: u32) -> Child {
        if let Some(leaf) = bvh.leaf_indices(index) {
            let first = self.triangles.len() as u32;
            for &triangle in leaf {
                let triangle = bvh.triangles()[triangle as usize];
                let [a, b, c] = triangle.0;
                self.triangles.push(triangle);
                self.triangle_bounds.push(Aabb { min: a.min(b).min(c), max: a.max(b).max(c) });
            }
            return Child::Leaf { first, count: leaf.len() as u32 };
        }
        let Some(children) = bvh.children(index) else {
            return Child::Leaf { first: 0, count: 0 };
        };
        let slot = self.nodes.len();
        let empty = Aabb { min: Vec3::ZERO, max: Vec3::ZERO };
        self.nodes.push(PlainNode { bounds: [empty; 2], children: [Child::Leaf { first: 0, count: 0 }; 2] });
        for (k, child) in children.into_iter().enumerate() {
            let bounds = bvh.node_bounds(child).unwrap_or(empty);
            let laid_out = self.lay_out(bvh, child);
            self.nodes[slot].bounds[k] = bounds;
            self.nodes[slot].children[k] = laid_out;
        }
        // Two small leaves (laid out one after the other) become one: a node visit costs
        // more than the boxes of a few more triangles.
        if let [Child::Leaf { first, count }, Child::Leaf { count: second, .. }] = self.nodes[slot].children
            && count + second <= LEAF_TRIANGLES
            && slot + 1 == self.nodes.len()
        {
            self.nodes.pop();
            return Child::Leaf { first, count: count + second };
        }
        Child::Node(slot as u32)
    }

    /// Triangle `index` in leaf order (as [`PlainValue::nearest`] names it).
    #[cfg(test)]
    pub(crate) fn triangle(&self, index: u32) -> Option<&Triangle> {
        self.triangles.get(index as usize)
    }

    /// The plain distance map's value of `voxel`: the minimum over the triangles of
    /// [`pair_lower_bound`], capped at `cap`, trying `seed` (a [`PlainValue::nearest`])
    /// first.
    pub(crate) fn voxel_distance(
        &self,
        voxel: &Aabb,
        tolerance: f32,
        cap: f32,
        seed: Option<u32>,
        stack: &mut Vec<(Child, f32)>,
    ) -> PlainValue {
        let mut found = PlainValue { value: cap, nearest: None };
        let Some((root_bounds, root)) = self.root else {
            return found;
        };
        // Boxes are compared by their squared gap to the voxel: a box is skipped once its
        // gap reaches the current minimum plus the gap's rounding slack (a few ulps of the
        // coordinates), so that no box that could lower it is skipped.
        let slack = GAP_SLACK * (1.0 + voxel.min.abs().max(voxel.max.abs()).max_element().max(self.magnitude));
        let reach = |value: f32| (value + slack) * (value + slack);
        let offer = |index: u32, found: &mut PlainValue| {
            if gap_squared(voxel, &self.triangle_bounds[index as usize]) >= reach(found.value) {
                return;
            }
            let triangle = &self.triangles[index as usize];
            let (bound, _) = pair_lower_bound(voxel, triangle, tolerance, found.value, self.magnitude);
            if bound < found.value {
                found.value = bound;
                found.nearest = Some(index);
            }
        };
        if let Some(seed) = seed.filter(|&s| (s as usize) < self.triangles.len()) {
            offer(seed, &mut found);
        }
        stack.clear();
        stack.push((root, gap_squared(voxel, &root_bounds)));
        while let Some((child, gap)) = stack.pop() {
            if gap >= reach(found.value) {
                continue;
            }
            match child {
                Child::Leaf { first, count } => {
                    for triangle in first..first + count {
                        if Some(triangle) != seed {
                            offer(triangle, &mut found);
                        }
                    }
                }
                Child::Node(index) => {
                    let node = &self.nodes[index as usize];
                    let gaps = [gap_squared(voxel, &node.bounds[0]), gap_squared(voxel, &node.bounds[1])];
                    let (near, far) = if gaps[0] <= gaps[1] { (0, 1) } else { (1, 0) };
                    let limit = reach(found.value);
                    if gaps[far] < limit {
                        stack.push((node.children[far], gaps[far]));
                    }
                    if gaps[near] < limit {
                        stack.push((node.children[near], gaps[near]));
                    }
                }
            }
        }
        found
    }
}

/// The squared Euclidean gap between two boxes (0 when they overlap), as computed.
fn gap_squared(a: &Aabb, b: &Aabb) -> f32 {
    (a.min - b.max).max(b.min - a.max).max(Vec3::ZERO).length_squared()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_random::uniform;

    /// The largest vertex coordinate magnitude of `triangle`.
    fn magnitude(triangle: &Triangle) -> f32 {
        triangle.0.iter().map(|v| v.abs().max_element()).fold(0.0, f32::max)
    }

    /// A random triangle within `spread` of the unit voxel's centre.
    fn random_triangle(next: &mut impl FnMut() -> f32, spread: f32) -> Triangle {
        let anchor = Vec3::new(next(), next(), next()) * 2.0 * spread - spread + 0.5;
        let mut vertex = || anchor + (Vec3::new(next(), next(), next()) - 0.5) * 2.5;
        Triangle([vertex(), vertex(), vertex()])
    }

    #[test]
    fn pair_bounds_lie_below_the_exact_distance_and_within_tolerance_of_it() {
        let voxel = Aabb::voxel(0, 0, 0);
        let mut next = uniform(0x51ed_270b_8a3c_4f11);
        let (mut compared, mut exact_fallbacks, mut largest_gap) = (0, 0, 0.0_f32);
        for tolerance in [0.01, 0.05, 0.25] {
            for _ in 0..3000 {
                let triangle = random_triangle(&mut next, 4.0);
                let exact = box_triangle_distance(&voxel, &triangle);
                let (bound, fell_back) =
                    pair_lower_bound(&voxel, &triangle, tolerance, f32::INFINITY, magnitude(&triangle));
                // `box_triangle_distance` is itself a lower bound after its rounding
                // margin; the slack covers both margins (coordinates below 8).
                assert!(bound <= exact + 1e-4, "bound {bound} above the exact {exact} for {triangle:?}");
                assert!(bound >= exact - tolerance - 1e-4, "bound {bound} more than {tolerance} below {exact}");
                largest_gap = largest_gap.max(exact - bound);
                compared += 1;
                exact_fallbacks += u32::from(fell_back);
            }
        }
        std::println!("{compared} pairs, {exact_fallbacks} took the exact distance, largest gap {largest_gap}");
        assert_eq!(compared, 9000);
    }

    #[test]
    fn hierarchy_search_is_within_tolerance_of_every_triangle_and_names_its_nearest() {
        // 150 triangles scattered through a 10³ grid, every voxel searched with no seed and
        // with a seed that is usually far: the result must not depend on the seed.
        let mut next = uniform(0x2b7e_1516_28ae_d2a6);
        let triangles: Vec<Triangle> = (0..150)
            .map(|_| {
                let anchor = Vec3::new(next(), next(), next()) * 10.0;
                let mut vertex = || anchor + (Vec3::new(next(), next(), next()) - 0.5) * 2.0;
                Triangle([vertex(), vertex(), vertex()])
            })
            .collect();
        let hierarchy = PlainHierarchy::new(&TriangleBvh::new(triangles.clone()));
        let (tolerance, cap) = (0.1, 100.0);
        let mut stack = Vec::new();
        let mut compared = 0;
        for index in 0..1000_u32 {
            let voxel = Aabb::voxel(index % 10, (index / 10) % 10, index / 100);
            let exact = triangles.iter().map(|t| box_triangle_distance(&voxel, t)).fold(cap, f32::min);
            for seed in [None, Some(index % 150)] {
                let found = hierarchy.voxel_distance(&voxel, tolerance, cap, seed, &mut stack);
                assert!(found.value <= exact + 1e-4, "voxel {index}: {} above the exact {exact}", found.value);
                assert!(found.value >= exact - tolerance - 1e-4, "voxel {index}: {} ≪ the exact {exact}", found.value);
                let nearest = found.nearest.and_then(|n| hierarchy.triangle(n));
                let nearest = nearest.unwrap_or_else(|| panic!("voxel {index}: no nearest triangle"));
                let nearest_exact = box_triangle_distance(&voxel, nearest);
                assert!(nearest_exact <= found.value + tolerance + 1e-4, "voxel {index}: nearest at {nearest_exact}");
                compared += 1;
            }
        }
        assert_eq!(compared, 2000);
    }

    #[test]
    fn a_pair_bound_stops_once_it_reaches_the_current_minimum() {
        // A floor 3 below the voxel: the first bound (3 less the margin) settles it at once.
        let voxel = Aabb::voxel(0, 0, 0);
        let floor = Triangle([Vec3::new(-5.0, -5.0, -3.0), Vec3::new(5.0, -5.0, -3.0), Vec3::new(0.0, 5.0, -3.0)]);
        let (bound, exact) = pair_lower_bound(&voxel, &floor, 1e-6, 1.0, 5.0);
        assert!(!exact && (1.0..=3.0).contains(&bound), "{bound}");
        let (bound, _) = pair_lower_bound(&voxel, &floor, 1e-3, f32::INFINITY, 5.0);
        assert!((bound - 3.0).abs() < 1e-3, "{bound}");
    }

    #[test]
    fn degenerate_triangles_are_bounded_within_tolerance_too() {
        // A repeated corner and three collinear corners: segments, whose closest points
        // must not come out as NaN (which the search would take for a touching pair).
        let voxel = Aabb::voxel(0, 0, 0);
        let (a, b) = (Vec3::new(2.0, 0.0, 3.0), Vec3::new(-1.0, -2.0, -1.0));
        let mut compared = 0;
        for triangle in [
            Triangle([a, a, b]),
            Triangle([a, b, b]),
            Triangle([b, a, a]),
            Triangle([a, (a + b) * 0.5, b]),
            Triangle([a, a, a]),
        ] {
            let exact = box_triangle_distance(&voxel, &triangle);
            for tolerance in [0.01, 0.25] {
                let (bound, _) = pair_lower_bound(&voxel, &triangle, tolerance, f32::INFINITY, magnitude(&triangle));
                assert!(bound <= exact + 1e-4 && bound >= exact - tolerance - 1e-4, "{triangle:?}: {bound} vs {exact}");
                compared += 1;
            }
        }
        assert_eq!(compared, 10);
    }

    #[test]
    fn a_box_touching_a_triangle_is_at_distance_zero() {
        let voxel = Aabb::voxel(0, 0, 0);
        let touching = Triangle([Vec3::new(1.0, 1.0, 1.0), Vec3::new(3.0, 1.0, 1.0), Vec3::new(1.0, 3.0, 2.0)]);
        assert_eq!(pair_lower_bound(&voxel, &touching, 0.01, f32::INFINITY, 3.0).0, 0.0);
    }
}
