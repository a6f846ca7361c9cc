//! The per-voxel search of [`crate::compute_distance_maps`]: every cone of a voxel at once,
//! over the triangle hierarchy, refining box–triangle pairs only where a cone's value
//! depends on it.
//!
//! A pair (piece of the voxel `B`, piece of a triangle `T`) has, per cone `C`, a lower
//! bound `g` of `|m − v|` over `v ∈ B`, `m ∈ T` with `m − v ∈ C`: the largest of the
//! undirected separating-axis gap (the axes of
//! [`crate::geometry::separation_lower_bound`], never below the parent pair's) and the
//! cone-aware duality bounds `h_A(w) / |P_K(w)|` of [`crate::convex_cone`] (`A = T − B`,
//! `K ⊇ C` convex) over the separating axes, the centres' offset projected onto `K` and its
//! polar part (which proves a pair outside the cone). A pair about to be split first gets
//! a short pattern search over `w`, which brings `g` towards the exact pair distance.
//!
//! Upper bounds of a cone's true value come from *witnesses*, real point pairs `(v, m)`
//! with `m − v` in the cone: the triangle point nearest the box centre with its nearest
//! box point when that direction is in the cone, a ray from the box along the projection
//! of the best axis onto the cone to the triangle, and rays from two triangle points back
//! along a cone direction into the box (or touching it). A pair about to be split also
//! casts rays back from the triangle's three corners, where integer geometry often meets a
//! cone only on its boundary (from a voxel inside a maze wall, the steep band `[−90°,
//! −45°]` sees the wall's foot exactly along `−45°`, so that no interior witness exists:
//! before these, 6.5 % of the maze's voxels at 64 × 64 × 16 ended with a finite value and
//! no witness, 0.5 % after), and casts the best-axis ray (the second witness above)
//! against the whole mesh, a few times per cone and voxel: the cone's nearest mesh point
//! often lies on another triangle than the pair's (a floor seen along the band's steepest
//! direction is met beyond the triangle under the box), and without a witness the upper
//! bound stays at the cap, so that no pair can be final and every pair is split down to
//! the tolerance's size. Before the mesh rays, 38 % of the ball tile's voxels (DDM 4×2,
//! 64 × 64 × 16) ended with a cone whose value was finite but which had found no witness.
//!
//! Where the convex cone `K` is larger than `C` (a band of elevations short of the pole or
//! the horizon), the search computes the distance along `K`'s directions instead: its
//! witnesses need `m − v ∈ K` only (up to [`crate::convex_cone::WITNESS_SLACK`], within
//! which the lower bounds hold too). That distance is at most `C`'s, so the values stay
//! lower bounds of `C`'s distance, and the lower bounds, which are `K`'s anyway, can meet
//! the upper bounds: each value ends within about `2 tolerance` of `K`'s distance, as for a
//! convex cone. With witnesses in `C` (as before), `K`'s bounds stayed below them wherever
//! `K`'s extra directions reach nearer geometry (a floor seen through the chord of the band
//! `[−45°, 0°]` is `1 / sin 54.7° ≈ 1.22` depths away along `K`, `√2` along `C`), and every
//! such pair was split down to the tolerance's size for nothing: a DDM 4×2 took 9 times a
//! DDM 4×1's time and now takes about 4.
//!
//! A pair is *final* for a cone once `g ≥ upper − tolerance` (the cone's value, at most the
//! true value, then ends within `tolerance` of it) or once both pieces are smaller than
//! `tolerance` (as in [`crate::geometry::directional_distance_bound`]); pairs that are not
//! final for some cone are split (the larger piece in two) for those cones only.
//!
//! The value of a cone is the minimum of `g` over its final pairs, capped at the grid's
//! diagonal: a lower bound of the true directional distance, since the pair holding the
//! true minimiser `(v*, m*)` is never dropped. A pair is dropped for a cone only when `g`
//! reaches the cone's current minimum (its descendants' bounds are no smaller) or exceeds,
//! with a margin, the best upper bound (which is at least the true value, itself at least
//! `g` of the minimiser's pair). Which witnesses are met first depends on the visiting
//! order, so the values depend on it too, each within about `2 tolerance` of the truth.

use alloc::vec::Vec;

use glam::Vec3;

mod pair_bounds;
mod witness;

pub(crate) use pair_bounds::{AxisDenominators, TriangleAxes};

use crate::bvh::TriangleBvh;
use crate::cones::Cone;
use crate::convex_cone::{ConvexCone, box_support};
use crate::geometry::{Aabb, Triangle, box_distance, closest_point_on_triangle};
use pair_bounds::{AXIS_SLOTS, cone_bound, improve_bound};
use witness::{box_witness, contains, mesh_witness, ray_witness};

/// The coordinate axes and their opposites, in the order of
/// `VoxelSearch::axis_denominators`.
const SIGNED_AXES: [Vec3; 6] = [Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z];

/// At most this many rays against the whole mesh ([`witness::mesh_witness`]) per cone and
/// voxel: the first few give the upper bound that the pairs' own witnesses miss; later
/// ones rarely lower it further, and a ray along a corridor crosses many nodes.
const MESH_RAYS_PER_CONE: u8 = 4;

/// At most this many cones are searched together (a bit mask of live cones).
pub(crate) const CONES_PER_SEARCH: usize = 32;

/// The search state of one voxel: per cone the minimum of the final lower bounds so far
/// (`lower`) and the smallest upper bound of the true value seen (`upper`).
pub(crate) struct VoxelSearch<'a> {
    /// The cones searched together (`None`: the plain, undirected distance).
    cones: &'a [Option<Cone>],
    /// The convex cone holding each cone ([`ConvexCone::holding`]).
    convex: [Option<ConvexCone>; CONES_PER_SEARCH],
    /// Per cone, [`ConvexCone::bound_denominator`] of the coordinate axes `+x, −x, +y, −y,
    /// +z, −z` (the hierarchy's node boxes are bounded along them).
    axis_denominators: [[f32; 6]; CONES_PER_SEARCH],
    tolerance: f32,
    lower: [f32; CONES_PER_SEARCH],
    upper: [f32; CONES_PER_SEARCH],
    /// The mesh point of the witness that gave each upper bound.
    witness_points: [Option<Vec3>; CONES_PER_SEARCH],
    /// The hierarchy searched (set by [`VoxelSearch::run`]), for rays against the whole
    /// mesh.
    mesh: Option<&'a TriangleBvh>,
    /// Per cone, the rays against the whole mesh cast so far (at most
    /// [`MESH_RAYS_PER_CONE`]).
    mesh_rays: [u8; CONES_PER_SEARCH],
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
        let mut convex = [None; CONES_PER_SEARCH];
        let mut axis_denominators = [[0.0; 6]; CONES_PER_SEARCH];
        for ((slot, denominators), cone) in convex.iter_mut().zip(&mut axis_denominators).zip(cones) {
            *slot = cone.as_ref().map(ConvexCone::holding);
            if let Some(convex) = slot {
                for (denominator, axis) in denominators.iter_mut().zip(SIGNED_AXES) {
                    *denominator = convex.bound_denominator(axis);
                }
            }
        }
        Self {
            cones,
            convex,
            axis_denominators,
            tolerance,
            lower: [cap; CONES_PER_SEARCH],
            upper: [cap; CONES_PER_SEARCH],
            witness_points: [None; CONES_PER_SEARCH],
            mesh: None,
            mesh_rays: [0; CONES_PER_SEARCH],
        }
    }

    /// Lowers cone `c`'s upper bound to `distance`, the length of a witness reaching the
    /// mesh at `m`.
    fn offer(&mut self, c: usize, distance: f32, m: Vec3) {
        if distance < self.upper[c] {
            self.upper[c] = distance;
            self.witness_points[c] = Some(m);
        }
    }

    /// Offers cone `c` the witnesses from the mesh points `points` back along a direction
    /// of `convex` into `aabb` ([`box_witness`]).
    fn offer_box_witnesses(
        &mut self,
        c: usize,
        convex: &ConvexCone,
        aabb: &Aabb,
        points: impl IntoIterator<Item = Vec3>,
    ) {
        for m in points {
            if let Some(distance) = box_witness(convex, aabb, m) {
                self.offer(c, distance, m);
            }
        }
    }

    /// The mesh points of the witnesses behind the upper bounds (to seed a neighbouring
    /// voxel's search with [`VoxelSearch::seed`]).
    pub(crate) fn witness_points(&self) -> impl Iterator<Item = Vec3> + '_ {
        self.witness_points[..self.cones.len()].iter().flatten().copied()
    }

    /// Starts the upper bounds from witnesses reaching the mesh points `points` (found
    /// for a neighbouring voxel): per cone, the line from each point back along a cone
    /// direction into `voxel` ([`box_witness`]); for the plain map, the distance from the
    /// point to the voxel. Any real witness is valid, so this changes no guarantee; good
    /// upper bounds early let the search drop and finalise pairs sooner.
    pub(crate) fn seed(&mut self, voxel: &Aabb, points: &[Vec3]) {
        for c in 0..self.cones.len() {
            for &m in points {
                let distance = match (&self.cones[c], &self.convex[c]) {
                    (Some(_), Some(convex)) => box_witness(convex, voxel, m),
                    _ => Some(m.distance(m.clamp(voxel.min, voxel.max))),
                };
                if let Some(distance) = distance.filter(|d| d.is_finite()) {
                    self.offer(c, distance, m);
                }
            }
        }
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

    /// Searches the triangles of `bvh` from `voxel`; `axes[i]` are the separating axes of
    /// `bvh.triangles()[i]` ([`TriangleAxes::of`]), `denominators` their bound
    /// denominators for this search's cones.
    pub(crate) fn run(
        &mut self,
        bvh: &'a TriangleBvh,
        axes: &[TriangleAxes],
        denominators: &AxisDenominators,
        voxel: &Aabb,
        stack: &mut Vec<(u32, f32, u32)>,
    ) {
        let all = if self.cones.len() == CONES_PER_SEARCH { u32::MAX } else { (1_u32 << self.cones.len()) - 1 };
        self.mesh = Some(bvh);
        stack.clear();
        if let Some(bounds) = bvh.node_bounds(0) {
            stack.push((0, box_distance(voxel, &bounds), all));
        }
        while let Some((node, gap, mask)) = stack.pop() {
            let mask = self.still_open(mask, gap);
            if mask == 0 {
                continue;
            }
            let Some(bounds) = bvh.node_bounds(node) else { continue };
            let mask = self.node_cones(voxel, &bounds, mask);
            if mask == 0 {
                continue;
            }
            if let Some(indices) = bvh.leaf_indices(node) {
                for &i in indices {
                    let (Some(triangle), Some(triangle_axes)) = (bvh.triangles().get(i as usize), axes.get(i as usize))
                    else {
                        continue;
                    };
                    self.refine_with(voxel, triangle, triangle_axes, denominators.of(i as usize), mask, 0.0);
                }
                continue;
            }
            let Some(children) = bvh.children(node) else { continue };
            let mut entries =
                children.map(|child| (child, bvh.node_bounds(child).map_or(0.0, |b| box_distance(voxel, &b)), mask));
            if entries[0].1 > entries[1].1 {
                entries.swap(0, 1);
            }
            stack.push(entries[1]);
            stack.push(entries[0]);
        }
    }

    /// The cones of `mask` for which a node with box `bounds` can still matter: those
    /// whose cone-aware lower bound ([`ConvexCone::bound`] over the coordinate axes, the
    /// centre offset projected onto the cone and its polar part, which drops cones that
    /// miss the box) is below the cone's current minimum and upper bound.
    fn node_cones(&self, voxel: &Aabb, bounds: &Aabb, mask: u32) -> u32 {
        let (min, max) = (bounds.min - voxel.max, bounds.max - voxel.min);
        let scale = 1.0 + min.abs().max(max.abs()).max_element() + voxel.max.abs().max_element();
        let margin = 4e-7 * scale;
        let offset = bounds.center() - voxel.center();
        let mut open = mask;
        for c in bits(mask) {
            let Some(convex) = &self.convex[c] else { continue };
            let mut g = 0.0_f32;
            for (&axis, &denominator) in SIGNED_AXES.iter().zip(&self.axis_denominators[c]) {
                g = g.max(ConvexCone::bound_over(box_support(min, max, axis) - margin, denominator));
            }
            let q = convex.project(offset);
            let length = q.length();
            let polar = offset - q;
            let polar_length = polar.length();
            if polar_length > 1e-6 * (1.0 + length) {
                let w = polar / polar_length;
                g = g.max(convex.bound(w, box_support(min, max, w) - margin));
            }
            if length > 1e-6 {
                // A unit direction of the cone: no projection needed.
                let q = q / length;
                g = g.max(ConvexCone::bound_within(box_support(min, max, q) - margin));
            }
            let upper = self.upper[c];
            if !(g < self.lower[c] && g <= upper + 1e-4 * (1.0 + upper)) {
                open &= !(1 << c);
            }
        }
        open
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
    /// parent pair's (undirected) lower bound.
    fn refine(&mut self, aabb: &Aabb, triangle: &Triangle, mask: u32, parent: f32) {
        self.refine_with(aabb, triangle, &TriangleAxes::of(triangle), None, mask, parent);
    }

    /// [`VoxelSearch::refine`] with the triangle's separating axes already computed.
    /// `denominators` are the triangle's [`AxisDenominators`] for every cone of the search
    /// (`None`: computed as needed).
    fn refine_with(
        &mut self,
        aabb: &Aabb,
        triangle: &Triangle,
        axes: &TriangleAxes,
        denominators: Option<&[f32]>,
        mask: u32,
        parent: f32,
    ) {
        let apart = axes.apart_from(triangle, aabb);
        let gap = apart.gap.max(parent);
        let mut open = self.still_open(mask, gap);
        if open == 0 {
            return;
        }
        let (cb, rb) = (aabb.center(), aabb.radius());
        let (ct, rt) = (triangle.center(), triangle.radius());
        let small = rb.max(rt) <= self.tolerance;
        // A real point pair: the triangle point nearest the box centre and its nearest
        // box point; an upper bound of every cone containing its direction. Computed once,
        // for the first cone that the bounds leave open.
        let mut nearest_pair: Option<(Vec3, Vec3, f32)> = None;
        let nearest_of = || {
            let nearest = closest_point_on_triangle(cb, triangle);
            let witness = nearest - nearest.clamp(aabb.min, aabb.max);
            (nearest, witness, witness.length())
        };
        for c in bits(open) {
            let mut g = gap;
            match (self.cones[c], self.convex[c]) {
                (Some(_), Some(convex)) => {
                    let convex = &convex;
                    let cone_denominators = denominators.and_then(|d| d.get(c * AXIS_SLOTS..(c + 1) * AXIS_SLOTS));
                    let (bound, best_axis) = cone_bound(convex, triangle, aabb, &apart, cone_denominators);
                    g = g.max(bound);
                    let upper = self.upper[c];
                    if !(g < self.lower[c] && g <= upper + 1e-4 * (1.0 + upper)) {
                        open &= !(1 << c);
                        continue;
                    }
                    let (nearest, witness, witness_distance) = *nearest_pair.get_or_insert_with(nearest_of);
                    if witness_distance.is_finite() && contains(convex, witness) {
                        self.offer(c, witness_distance, nearest);
                    }
                    if let Some(axis) = best_axis
                        && let Some((distance, m)) = ray_witness(convex, aabb, triangle, axis, nearest)
                    {
                        self.offer(c, distance, m);
                    }
                    self.offer_box_witnesses(c, convex, aabb, [nearest, ct]);
                    // About to be split: a local search over `w` first tightens the bound
                    // (towards the exact pair distance, by duality) and aims a witness.
                    if !small
                        && g < self.upper[c] - self.tolerance
                        && let Some(start) = best_axis
                    {
                        // The search stops once the pair is final: a bound above
                        // `upper − tolerance` changes nothing.
                        let enough = self.upper[c] - self.tolerance;
                        let (improved, axis) = improve_bound(convex, triangle, aabb, apart.margin, start, g, enough);
                        g = improved;
                        let upper = self.upper[c];
                        if !(g < self.lower[c] && g <= upper + 1e-4 * (1.0 + upper)) {
                            open &= !(1 << c);
                            continue;
                        }
                        if let Some((distance, m)) = ray_witness(convex, aabb, triangle, axis, nearest) {
                            self.offer(c, distance, m);
                        }
                        // Still to be split: lines from the triangle's corners back into
                        // the box, where a cone that meets the mesh only on its boundary
                        // touches it (a wall's foot seen from inside the wall exactly along
                        // the band's −45°).
                        if g < self.upper[c] - self.tolerance {
                            self.offer_box_witnesses(c, convex, aabb, triangle.0);
                        }
                        // Still to be split: the pairs' witnesses may have missed a nearer
                        // mesh point on another triangle, which a ray finds.
                        if g < self.upper[c] - self.tolerance
                            && self.mesh_rays[c] < MESH_RAYS_PER_CONE
                            && let Some(mesh) = self.mesh
                        {
                            self.mesh_rays[c] += 1;
                            if let Some((distance, m)) = mesh_witness(convex, aabb, axis, nearest, mesh, self.upper[c])
                            {
                                self.offer(c, distance, m);
                            }
                        }
                    }
                }
                _ => {
                    let (nearest, _, witness_distance) = *nearest_pair.get_or_insert_with(nearest_of);
                    if witness_distance.is_finite() {
                        self.offer(c, witness_distance, nearest);
                    }
                }
            }
            if small || g >= self.upper[c] - self.tolerance {
                self.lower[c] = self.lower[c].min(g);
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
            self.refine_with(&halves[first], triangle, axes, denominators, open, gap);
            self.refine_with(&halves[1 - first], triangle, axes, denominators, open, gap);
        } else {
            let halves = triangle.split();
            let first = usize::from(halves[1].center().distance_squared(cb) < halves[0].center().distance_squared(cb));
            self.refine(aabb, &halves[first], open, gap);
            self.refine(aabb, &halves[1 - first], open, gap);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cones::{DirectionCones, azimuth_elevation};
    use crate::test_random::uniform;

    /// The smallest `|m − v|` in `cone` over a grid of triangle and box points (an upper
    /// estimate of the true directional distance), or infinity.
    fn sampled(aabb: &Aabb, triangle: &Triangle, cone: &Cone) -> f32 {
        let [a, b, c] = triangle.0;
        let mut best = f32::INFINITY;
        let n = 14;
        for i in 0..=n {
            for j in 0..=(n - i) {
                let m = a + (b - a) * (i as f32 / n as f32) + (c - a) * (j as f32 / n as f32);
                for k in 0..125 {
                    let t = Vec3::new((k % 5) as f32, ((k / 5) % 5) as f32, (k / 25) as f32) / 4.0;
                    let v = aabb.min + (aabb.max - aabb.min) * t;
                    if let Some((azimuth, elevation)) = azimuth_elevation(m - v)
                        && cone.contains_at(azimuth, elevation)
                    {
                        best = best.min(m.distance(v));
                    }
                }
            }
        }
        best
    }

    #[test]
    fn cone_bounds_are_below_sampled_distances_and_witnesses_above_them() {
        let mut next = uniform(0x2545_f491_4f6c_dd1d);
        let cone_sets = [
            DirectionCones::downward(8, 1).unwrap(),
            DirectionCones::downward(2, 1).unwrap(),
            DirectionCones::full(4, 2).unwrap(),
            DirectionCones::downward(4, 2).unwrap(),
            DirectionCones::full(3, 3).unwrap(),
        ];
        let (mut gap_sum, mut finite, mut witnessed) = (0.0, 0, 0);
        for _ in 0..150 {
            let size = 0.2 + next() * 0.8;
            let aabb = Aabb { min: Vec3::splat(-size / 2.0), max: Vec3::splat(size / 2.0) };
            let mut vertex = || Vec3::new(next(), next(), next()) * 6.0 - 3.0;
            let triangle = Triangle([vertex(), vertex(), vertex()]);
            let axes = TriangleAxes::of(&triangle);
            let apart = axes.apart_from(&triangle, &aabb);
            let nearest = closest_point_on_triangle(aabb.center(), &triangle);
            for cones in cone_sets {
                for index in 0..cones.count() {
                    let cone = cones.cone(index).unwrap();
                    let convex = ConvexCone::holding(&cone);
                    let truth = sampled(&aabb, &triangle, &cone);
                    let (mut bound, axis) = cone_bound(&convex, &triangle, &aabb, &apart, None);
                    // The stored denominators give the same bound.
                    let stored = AxisDenominators::new(&[Some(cone)], core::slice::from_ref(&axes), 1);
                    assert_eq!(cone_bound(&convex, &triangle, &aabb, &apart, stored.of(0)), (bound, axis));
                    bound = bound.max(apart.gap);
                    if let Some(axis) = axis {
                        bound = bound
                            .max(improve_bound(&convex, &triangle, &aabb, apart.margin, axis, bound, f32::INFINITY).0);
                    }
                    assert!(
                        bound <= truth + 1e-5,
                        "{triangle:?} {aabb:?} cone {cone:?}: bound {bound} > sampled {truth}"
                    );
                    if truth.is_finite() {
                        gap_sum += truth - bound;
                        finite += 1;
                    }
                    let witnesses = [
                        axis.and_then(|axis| ray_witness(&convex, &aabb, &triangle, axis, nearest))
                            .map(|(distance, _)| distance),
                        box_witness(&convex, &aabb, nearest),
                        box_witness(&convex, &aabb, triangle.center()),
                    ];
                    for witness in witnesses.into_iter().flatten() {
                        witnessed += 1;
                        assert!(
                            witness >= bound - 1e-4,
                            "{triangle:?} {aabb:?} cone {cone:?}: witness {witness} < bound {bound}"
                        );
                    }
                }
            }
        }
        let mean_gap = gap_sum / finite as f32;
        #[cfg(feature = "std")]
        std::println!("mean gap {mean_gap} over {finite}, {witnessed} witnesses");
        // Compared (a finite sampled value): the two full cone sets cover every direction,
        // so every one of the 150 triangles is seen by a cone of each (a sampled pair lies
        // in some cone); witnesses exist at least as often (the box point nearest a
        // triangle point, in the cone of that direction).
        assert!(finite >= 2 * 150 && witnessed >= 2 * 150, "{finite} {witnessed}");
        // Regression pin (not a property: `sampled` is itself only an upper estimate, and
        // no bound on the cone bounds' looseness is derived): measured mean (sampled −
        // bound) 0.108 voxel over 3128 pairs, 4266 witnesses (0.131 and 3941 before the
        // elevation bands' convex cones were cut), pinned at 0.16.
        assert!(mean_gap < 0.16, "regression pin: mean gap {mean_gap}");
    }

    /// A wall on a floor at `z = 2`, its top at `z = 12`, its side a slope over `x ∈ [15, 16]`
    /// rising from the foot line `x = 15`: the wall's foot (two floor triangles and two slope
    /// triangles per unit of `y`, for `y ∈ [48, 56]`).
    fn wall_foot() -> Vec<Triangle> {
        let mut triangles = Vec::new();
        for y in 48..56 {
            let (y0, y1) = (y as f32, y as f32 + 1.0);
            let floor = |x: f32, y: f32| Vec3::new(x, y, 2.0);
            let top = |y: f32| Vec3::new(16.0, y, 12.0);
            triangles.push(Triangle([floor(14.0, y0), floor(15.0, y0), floor(15.0, y1)]));
            triangles.push(Triangle([floor(14.0, y0), floor(15.0, y1), floor(14.0, y1)]));
            triangles.push(Triangle([floor(15.0, y0), top(y0), top(y1)]));
            triangles.push(Triangle([floor(15.0, y0), top(y1), floor(15.0, y1)]));
        }
        triangles
    }

    #[test]
    fn a_cone_that_meets_the_mesh_only_on_its_boundary_finds_a_witness() {
        // From the voxel [19, 20] × [51, 52] × [5, 6] inside the wall, the steep band
        // [−90°, −45°] towards −x meets the mesh only along −45°: the offset (−4, 0, −4)
        // from the box's edge (19, y, 6) to the foot (15, y, 2) (a slope point
        // (15 + s, y, 2 + 10 s) needs 4 − 10 s ≥ 4 − s, so s = 0; the floor beyond the foot
        // is farther than it is deep). Its distance is 4√2 exactly; the search must end
        // within the tolerance of it, with a witness, not at the cap with every pair split
        // down to the tolerance's size.
        let cones = DirectionCones::downward(4, 2).unwrap();
        let list: Vec<Option<Cone>> = (0..cones.count()).map(|i| cones.cone(i)).collect();
        let voxel = Aabb { min: Vec3::new(19.0, 51.0, 5.0), max: Vec3::new(20.0, 52.0, 6.0) };
        let (tolerance, cap) = (0.25, 100.0);
        let mut search = VoxelSearch::new(&list, tolerance, cap);
        search.run_over_every_triangle(&wall_foot(), &voxel);
        let truth = 4.0 * core::f32::consts::SQRT_2;
        let mut compared = 0;
        for (c, cone) in list.iter().enumerate() {
            let cone = cone.unwrap();
            // The steep cones whose azimuths reach −x (180°): [90°, 180°] and [180°, 270°].
            let towards_foot = cone.elevation_max < -0.7
                && cone.azimuth_min <= core::f32::consts::PI + 1e-6
                && cone.azimuth_max >= core::f32::consts::PI - 1e-6;
            if !towards_foot {
                continue;
            }
            compared += 1;
            let (value, upper) = (search.value(c), search.upper[c]);
            assert!(value <= truth + 1e-4 && value >= truth - tolerance, "cone {c}: value {value}, truth {truth}");
            assert!(upper <= truth + tolerance, "cone {c}: no witness (upper bound {upper})");
        }
        assert_eq!(compared, 2);
    }
}
