//! The per-voxel search of [`crate::compute_distance_maps`]: every cone of a voxel at once,
//! over the triangle hierarchy, refining box–triangle pairs only where a cone's value
//! depends on it.
//!
//! A pair (piece of the voxel `B`, piece of a triangle `T`) has
//!
//! - a lower bound `g` of `|m − v|` for every `v ∈ B`, `m ∈ T`
//!   ([`separation_lower_bound`], never below its parent pair's bound);
//! - an azimuth–elevation rectangle holding every direction `m − v`: the directions of
//!   the box `[min T − max B, max T − min B]` ([`DirectionRange::of_box`]).
//!
//! Per cone the pair is then *outside* (the rectangle misses the cone: it contributes nothing),
//! *inside* (the rectangle lies in the cone, [`Cone::relation`]: the cone's value over
//! the pair is the undirected distance, and `g` is final once the pair's upper bound — the
//! distance between the triangle point nearest the box centre and its nearest box point —
//! is within `tolerance` of it), or *partial* (final once both pieces are smaller than
//! `tolerance`, as in [`crate::geometry::directional_distance_bound`]). Pairs that are not
//! final for some cone are split (the larger piece in two) for those cones only.
//!
//! The value of a cone is the minimum of `g` over its final pairs, capped at the grid's
//! diagonal: a lower bound of the true directional distance (every pair `(v, m)` of the
//! cone lies in some final pair, inside or partial). Pruning never changes it: a pair is
//! dropped for a cone when `g` reaches the cone's current minimum (its descendants' bounds
//! are no smaller) or exceeds, with a margin, an *upper bound* of the true value found on
//! the way (a real point pair `(v, m)` with `m − v` in the cone; the value is at most the
//! true value, hence at most that bound).

use alloc::vec::Vec;

use glam::Vec3;

use crate::bvh::TriangleBvh;
use crate::cones::{Cone, ConeRelation, DirectionRange, azimuth_elevation};
use crate::geometry::{Aabb, Triangle, box_distance, closest_point_on_triangle, separation_lower_bound};

/// At most this many cones are searched together (a bit mask of live cones).
pub(crate) const CONES_PER_SEARCH: usize = 32;

/// Margin of the angular tests of bounding-sphere caps (absorbs the rounding of the
/// angle computations).
const ANGLE_MARGIN: f32 = 1e-5;

/// The cap of directions from `a` (centre, radius) to `b`: the direction's azimuth and
/// elevation and the cap's half-angle, or `None` when the spheres overlap.
fn direction_cap(a_center: Vec3, a_radius: f32, b_center: Vec3, b_radius: f32) -> Option<(f32, f32, f32)> {
    let offset = b_center - a_center;
    let distance = offset.length();
    let reach = a_radius + b_radius;
    if distance.is_nan() || distance <= reach * (1.0 + 1e-6) {
        return None;
    }
    let (azimuth, elevation) = azimuth_elevation(offset)?;
    Some((azimuth, elevation, libm::asinf((reach / distance).min(1.0))))
}

/// The search state of one voxel: per cone the minimum of the final lower bounds so far
/// (`lower`) and the smallest upper bound of the true value seen (`upper`).
pub(crate) struct VoxelSearch<'a> {
    /// The cones searched together (`None`: the plain, undirected distance).
    cones: &'a [Option<Cone>],
    tolerance: f32,
    lower: [f32; CONES_PER_SEARCH],
    upper: [f32; CONES_PER_SEARCH],
}

/// Indices of the set bits of `mask`.
fn bits(mut mask: u32) -> impl Iterator<Item = usize> {
    core::iter::from_fn(move || {
        (mask != 0).then(|| {
            let bit = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            bit
        })
    })
}

impl<'a> VoxelSearch<'a> {
    /// A search over `cones` (at most [`CONES_PER_SEARCH`]) whose values are capped at
    /// `cap`.
    pub(crate) fn new(cones: &'a [Option<Cone>], tolerance: f32, cap: f32) -> Self {
        debug_assert!(cones.len() <= CONES_PER_SEARCH);
        Self { cones, tolerance, lower: [cap; CONES_PER_SEARCH], upper: [cap; CONES_PER_SEARCH] }
    }

    /// The value of cone `index` once the search is done.
    pub(crate) fn value(&self, index: usize) -> f32 {
        self.lower[index]
    }

    /// The cones of `mask` for which a pair bounded below by `gap` can still matter.
    fn still_open(&self, mask: u32, gap: f32) -> u32 {
        let mut open = 0;
        for c in bits(mask) {
            let upper = self.upper[c];
            if gap < self.lower[c] && gap <= upper + 1e-4 * (1.0 + upper) {
                open |= 1 << c;
            }
        }
        open
    }

    /// Searches the triangles of `bvh` from `voxel`.
    pub(crate) fn run(&mut self, bvh: &TriangleBvh, voxel: &Aabb, stack: &mut Vec<(u32, f32, u32)>) {
        let all = if self.cones.len() == CONES_PER_SEARCH { u32::MAX } else { (1_u32 << self.cones.len()) - 1 };
        stack.clear();
        if let Some(bounds) = bvh.node_bounds(0) {
            stack.push((0, box_distance(voxel, &bounds), all));
        }
        while let Some((node, gap, mask)) = stack.pop() {
            let mask = self.still_open(mask, gap);
            if mask == 0 {
                continue;
            }
            if let Some(triangles) = bvh.leaf(node) {
                for triangle in triangles {
                    self.refine(voxel, triangle, mask, 0.0);
                }
                continue;
            }
            let Some(children) = bvh.children(node) else { continue };
            let mut entries = children.map(|child| {
                let bounds = bvh.node_bounds(child).unwrap_or(*voxel);
                let gap = box_distance(voxel, &bounds);
                // Cones whose directions all miss the node's box are dropped.
                let mut open = self.still_open(mask, gap);
                let range = DirectionRange::of_box(bounds.min - voxel.max, bounds.max - voxel.min);
                let cap = direction_cap(voxel.center(), voxel.radius(), bounds.center(), bounds.radius());
                for c in bits(open) {
                    let Some(cone) = &self.cones[c] else { continue };
                    let outside = range.is_some_and(|range| cone.relation(&range) == ConeRelation::Outside)
                        || cap.is_some_and(|(azimuth, elevation, spread)| {
                            cone.angle_lower_bound_at(azimuth, elevation) > spread + ANGLE_MARGIN
                        });
                    if outside {
                        open &= !(1 << c);
                    }
                }
                (child, gap, open)
            });
            if entries[0].1 > entries[1].1 {
                entries.swap(0, 1);
            }
            for entry in entries.into_iter().rev() {
                if entry.2 != 0 {
                    stack.push(entry);
                }
            }
        }
    }

    /// The search without the hierarchy: every triangle refined in turn (tests compare
    /// it with [`VoxelSearch::run`]).
    #[cfg(test)]
    pub(crate) fn run_over_every_triangle(&mut self, triangles: &[Triangle], voxel: &Aabb) {
        let all = if self.cones.len() == CONES_PER_SEARCH { u32::MAX } else { (1_u32 << self.cones.len()) - 1 };
        for triangle in triangles {
            self.refine(voxel, triangle, all, 0.0);
        }
    }

    /// Refines the pair (`aabb`, `triangle`) for the cones of `mask`; `parent` is the
    /// parent pair's lower bound.
    fn refine(&mut self, aabb: &Aabb, triangle: &Triangle, mask: u32, parent: f32) {
        let gap = separation_lower_bound(triangle, aabb).max(parent);
        let mut open = self.still_open(mask, gap);
        if open == 0 {
            return;
        }
        let (cb, rb) = (aabb.center(), aabb.radius());
        let (ct, rt) = (triangle.center(), triangle.radius());
        let small = rb.max(rt) <= self.tolerance;
        let (tmin, tmax) = triangle.bounds();
        let range = DirectionRange::of_box(tmin - aabb.max, tmax - aabb.min);
        let cap = direction_cap(cb, rb, ct, rt);
        // A real point pair: the triangle point nearest the box centre and its nearest
        // box point; an upper bound of every cone containing its direction.
        let mut witness: Option<(f32, Option<(f32, f32)>)> = None;
        let witness_of = |witness: &mut Option<(f32, Option<(f32, f32)>)>| {
            *witness.get_or_insert_with(|| {
                let m = closest_point_on_triangle(cb, triangle);
                let v = m.clamp(aabb.min, aabb.max);
                ((m - v).length(), azimuth_elevation(m - v))
            })
        };
        for c in bits(open) {
            let inside = match (&self.cones[c], &range) {
                (None, _) => true,
                (Some(cone), range) => {
                    let by_range = range.as_ref().map_or(ConeRelation::Partial, |range| cone.relation(range));
                    let by_cap = cap.map_or(ConeRelation::Partial, |(azimuth, elevation, spread)| {
                        if cone.angle_lower_bound_at(azimuth, elevation) > spread + ANGLE_MARGIN {
                            ConeRelation::Outside
                        } else if cone.inside_margin_at(azimuth, elevation) > spread + ANGLE_MARGIN {
                            ConeRelation::Inside
                        } else {
                            ConeRelation::Partial
                        }
                    });
                    if by_range == ConeRelation::Outside || by_cap == ConeRelation::Outside {
                        open &= !(1 << c);
                        continue;
                    }
                    by_range == ConeRelation::Inside || by_cap == ConeRelation::Inside
                }
            };
            let (distance, direction) = witness_of(&mut witness);
            let witnessed = match (&self.cones[c], direction) {
                (None, _) => true,
                (Some(cone), Some((azimuth, elevation))) => inside || cone.contains_at(azimuth, elevation),
                (Some(_), None) => false,
            };
            if witnessed && distance.is_finite() {
                self.upper[c] = self.upper[c].min(distance);
            }
            if small || (inside && distance - gap <= self.tolerance) {
                self.lower[c] = self.lower[c].min(gap);
                open &= !(1 << c);
            }
        }
        if open == 0 {
            return;
        }
        if rb >= rt {
            let halves = aabb.split();
            // The half nearer the triangle first: it lowers the minimum sooner.
            let first = usize::from(halves[1].center().distance_squared(ct) < halves[0].center().distance_squared(ct));
            self.refine(&halves[first], triangle, open, gap);
            self.refine(&halves[1 - first], triangle, open, gap);
        } else {
            let halves = triangle.split();
            let first = usize::from(halves[1].center().distance_squared(cb) < halves[0].center().distance_squared(cb));
            self.refine(aabb, &halves[first], open, gap);
            self.refine(aabb, &halves[1 - first], open, gap);
        }
    }
}
