//! Which side of the tile's mesh a point lies on, and where the mesh crosses a grid edge:
//! the decisions of the watertight surface ([`quadric_fit::watertight`]), taken once per
//! grid corner, edge and face of a periodic tile.
//!
//! A point's side is its **ray winding number**: along a ray from the point up and out of
//! the slab, each crossing counts +1 where the ray leaves the solid (it runs along the
//! outward normal) and −1 where it enters. Above the slab everything is outside, so the
//! sum is the number of solids holding the point: 0 outside, 1 inside, 2 where two solids
//! overlap (a bead sunk into the floor). The point is inside when the sum is ≥ 1 (a
//! generalised winding number ≥ ½). Unlike ray parity this counts overlapping closed
//! meshes as their union, and unlike the solid-angle winding number it needs no closed
//! mesh: a periodic height field is the boundary of the solid under it.
//!
//! Rays through an edge or a vertex of the mesh could count one crossing twice or not at
//! all, so a ray with a crossing within [`DEGENERATE_MARGIN`] of a triangle's border is
//! replaced by the next of [`DIRECTIONS`] (tilted, irrational-looking directions). A point
//! lying on the mesh (a crossing at `t ≈ 0` in every direction) is inside: "on the
//! surface counts as solid", one rule for every point.
//!
//! **Grid points on the mesh.** Meshes built on the grid put surfaces exactly through grid
//! corners and faces (a floor at an integer height, a height field's vertices at integer
//! x and y): decided as they are, such corners would put the edge points at the corners and
//! whole patches in voxel faces, where a crossing belongs to either voxel only up to
//! rounding. So every grid decision is taken at the grid point moved by [`SAMPLE_OFFSET`]
//! (a perturbation far below any feature, and far above `f64` rounding): corners, the
//! edges between the moved corners, face centres. A floor at z = 3 then lies just above
//! the moved corners at z = 3, which are outside, and crosses the vertical edges below
//! them. An edge's point is kept [`EDGE_MARGIN`] from the edge's ends, so no patch lies
//! in a voxel face.
//!
//! The grid is periodic in x and y: a corner, edge or face is reduced to the tile before
//! it is decided, and an edge's point is moved back by whole tiles (exact in `f64`), so
//! the copies of a decision on opposite borders of the tile are the same bits. Over a mesh
//! that does not repeat ([`MeshRaycaster::period`] 0) nothing is reduced; the winding rays
//! lean toward the tile's middle instead of by fixed signs, and a grid point on the tile's
//! upper border is moved inward, so that neither leaves the mesh's extent (a height field
//! ends exactly at the borders) before meeting it.

use alloc::collections::BTreeMap;
use alloc::vec::Vec;

use glam::{DVec3, UVec3};
use quadric_fit::surface::{GridEdge, GridFace, GridPoint};
use quadric_fit::watertight::SignedGrid;

use crate::ground_truth::{MeshCrossing, MeshRaycaster};

/// A crossing whose smallest barycentric coordinate is below this is too near an edge or
/// a vertex of its triangle to be counted once for sure: the ray is cast again.
pub const DEGENERATE_MARGIN: f64 = 1e-9;

/// A crossing this close to the ray's origin (in voxels) means the origin lies on the mesh.
pub const ON_SURFACE: f64 = 1e-9;

/// Where the grid decisions are taken: each grid point moved by this (voxels); see the
/// module docs.
pub const SAMPLE_OFFSET: [f64; 3] = [1.0e-6, 1.7e-6, 2.3e-6];

/// The least distance (voxels) of an edge's point from the edge's ends: the patches keep
/// this far from the voxel's corners and faces, well above the `f32` rounding of the
/// tracer's voxel-local coordinates and within the accuracy goals (10⁻³ voxel).
pub const EDGE_MARGIN: f64 = 1e-4;

/// The directions of the winding rays, tried in order until one meets no edge or vertex:
/// upward, tilted by small, mutually irrational-looking slopes so that a ray from a grid
/// point does not run along the grid's lines (where height fields have their edges).
pub const DIRECTIONS: [[f64; 3]; 6] = [
    [0.073_119_2, 0.041_937_7, 1.0],
    [-0.052_786_4, 0.067_233_1, 1.0],
    [0.038_461_5, -0.081_649_7, 1.0],
    [-0.091_287_1, -0.029_411_8, 1.0],
    [0.113_227_5, 0.087_029_3, 1.0],
    [-0.023_570_2, -0.105_409_3, 1.0],
];

/// The decisions of [`quadric_fit::build_watertight`] for a periodic tile of `dims` voxels
/// whose mesh is `mesh` (its period `(dims.x, dims.y)`), with counts of the numerically
/// hard cases.
pub struct MeshSides<'a> {
    mesh: &'a MeshRaycaster,
    dims: UVec3,
    corners: BTreeMap<GridPoint, bool>,
    crossings: Vec<MeshCrossing>,
    /// Points whose every winding ray met an edge or a vertex (the last ray's count was
    /// used).
    pub ambiguous_points: u32,
    /// Edges whose ends differ but along which no crossing was found (rounding): their
    /// midpoint was used.
    pub edges_without_crossing: u32,
    /// Points found on the mesh (inside by the rule of the module docs).
    pub points_on_surface: u32,
}

impl<'a> MeshSides<'a> {
    /// The decisions for the tile of `dims` voxels over `mesh`.
    pub fn new(mesh: &'a MeshRaycaster, dims: UVec3) -> Self {
        Self {
            mesh,
            dims,
            corners: BTreeMap::new(),
            crossings: Vec::new(),
            ambiguous_points: 0,
            edges_without_crossing: 0,
            points_on_surface: 0,
        }
    }

    /// Whether `p` (tile coordinates) is inside the solid: its ray winding number is ≥ 1,
    /// or it lies on the mesh (see the module docs).
    pub fn point_inside(&mut self, p: DVec3) -> bool {
        self.winding(p).is_none_or(|w| w >= 1)
    }

    /// The ray winding number of `p`: how many of the mesh's solids hold it; `None` when
    /// `p` lies on the mesh.
    pub fn winding(&mut self, p: DVec3) -> Option<i32> {
        let mut winding = 0;
        let period = self.mesh.period();
        for (attempt, direction) in DIRECTIONS.iter().enumerate() {
            let mut direction = DVec3::from_array(*direction).normalize();
            // Over a mesh that does not repeat, the ray leans toward the tile's middle, so
            // that it does not leave the mesh's extent through a side before meeting it.
            for (axis, (period, size)) in [(period.x, self.dims.x), (period.y, self.dims.y)].into_iter().enumerate() {
                let repeats = period > 0.0 && period.is_finite();
                if !repeats && (p[axis] - 0.5 * f64::from(size)) * direction[axis] > 0.0 {
                    direction[axis] = -direction[axis];
                }
            }
            self.crossings.clear();
            self.mesh.crossings(p, direction, -ON_SURFACE, f64::MAX, &mut self.crossings);
            if self.crossings.iter().any(|c| c.t.abs() <= ON_SURFACE) {
                self.points_on_surface += 1;
                return None;
            }
            winding = self.crossings.iter().map(|c| if c.exiting { 1 } else { -1 }).sum::<i32>();
            if self.crossings.iter().all(|c| c.margin >= DEGENERATE_MARGIN) {
                return Some(winding);
            }
            if attempt + 1 == DIRECTIONS.len() {
                self.ambiguous_points += 1;
            }
        }
        Some(winding)
    }

    /// Where the decision about grid point `p` is taken: `p` moved by [`SAMPLE_OFFSET`],
    /// except along an axis in which the mesh does not repeat, where a point on the tile's
    /// upper border moves inward by it instead (outward it would leave the mesh, whose
    /// surfaces may end exactly there).
    fn sample(&self, p: DVec3) -> DVec3 {
        let period = self.mesh.period();
        let mut offset = DVec3::from_array(SAMPLE_OFFSET);
        for (axis, (period, size)) in [(period.x, self.dims.x), (period.y, self.dims.y)].into_iter().enumerate() {
            let repeats = period > 0.0 && period.is_finite();
            if !repeats && p[axis] >= f64::from(size) {
                offset[axis] = -offset[axis];
            }
        }
        p + offset
    }

    /// The whole tiles to subtract from grid point `p` to bring it into the tile (none
    /// along an axis in which the mesh does not repeat).
    fn tile_shift(&self, p: GridPoint) -> (u32, u32) {
        let period = self.mesh.period();
        let repeats = |period: f32| period > 0.0 && period.is_finite();
        let shift = |p: u32, n: u32, period: f32| if repeats(period) { p - p % n } else { 0 };
        (shift(p.0, self.dims.x, period.x), shift(p.1, self.dims.y, period.y))
    }
}

impl SignedGrid for MeshSides<'_> {
    fn inside(&mut self, p: GridPoint) -> bool {
        let (sx, sy) = self.tile_shift(p);
        let key = (p.0 - sx, p.1 - sy, p.2);
        if let Some(&inside) = self.corners.get(&key) {
            return inside;
        }
        let point = DVec3::new(f64::from(key.0), f64::from(key.1), f64::from(key.2));
        let inside = self.point_inside(self.sample(point));
        self.corners.insert(key, inside);
        inside
    }

    /// Where the edge leaves the union of the solids: along the edge the winding number
    /// changes by one at each crossing of the mesh, and the edge's point is the median of
    /// the crossings where it changes between 0 and ≥ 1 (an odd number of them, the ends
    /// differing). Crossings of surfaces inside the union (a floor running through a bead)
    /// change the number between 1 and 2 and are passed over.
    fn crossing(&mut self, edge: GridEdge) -> DVec3 {
        let (sx, sy) = self.tile_shift(edge.corner);
        let local = GridEdge { axis: edge.axis, corner: (edge.corner.0 - sx, edge.corner.1 - sy, edge.corner.2) };
        let shift = DVec3::new(f64::from(sx), f64::from(sy), 0.0);
        let (start, end) = (self.sample(local.point(0.0)), self.sample(local.point(1.0)));
        let (start_winding, end_winding) = (self.winding(start), self.winding(end));
        let axis = usize::from(edge.axis % 3);
        let mut direction = DVec3::ZERO;
        direction[axis] = 1.0;
        self.crossings.clear();
        // 1, unless the end moved inward from the tile's border.
        let length = if self.sample(DVec3::ZERO) == self.sample(local.point(1.0)) - local.point(1.0) {
            1.0
        } else {
            end[axis] - start[axis]
        };
        self.mesh.crossings(start, direction, -ON_SURFACE, length + ON_SURFACE, &mut self.crossings);
        let mut crossings: Vec<(f64, i32)> =
            self.crossings.iter().map(|c| (c.t.clamp(0.0, 1.0), if c.exiting { -1 } else { 1 })).collect();
        crossings.sort_by(|a, b| a.0.total_cmp(&b.0));
        // A crossing on an edge or vertex of the mesh is reported by each triangle there.
        crossings.dedup_by(|a, b| (a.0 - b.0).abs() <= ON_SURFACE && a.1 == b.1);
        // The winding number before each crossing, from whichever end is off the mesh.
        let mut transitions = Vec::new();
        let total: i32 = crossings.iter().map(|c| c.1).sum();
        if let Some(mut w) = start_winding.or(end_winding.map(|w| w - total)) {
            for &(t, change) in &crossings {
                if (w >= 1) != (w + change >= 1) {
                    transitions.push(t);
                }
                w += change;
            }
        } else {
            transitions.extend(crossings.iter().map(|c| c.0));
        }
        let t = if transitions.is_empty() {
            self.edges_without_crossing += 1;
            0.5
        } else {
            transitions[(transitions.len() - 1) / 2]
        };
        local.point(t.clamp(EDGE_MARGIN, 1.0 - EDGE_MARGIN)) + shift
    }

    fn face_centre_inside(&mut self, face: GridFace) -> bool {
        let (sx, sy) = self.tile_shift(face.corner);
        let local = GridFace { normal: face.normal, corner: (face.corner.0 - sx, face.corner.1 - sy, face.corner.2) };
        let centre = self.sample(local.centre());
        self.point_inside(centre)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec2;

    #[test]
    fn sides_of_the_tiles_are_those_of_their_construction() {
        let dims = UVec3::new(12, 12, 6);
        // Beads: floor at 1.5, spheres of radius 2.64 centred 1.76 above it at (3, 3), ...
        let beads = mesostructure::beads(dims);
        let mesh = MeshRaycaster::new(&beads, Vec2::new(12.0, 12.0));
        let mut sides = MeshSides::new(&mesh, dims);
        assert!(sides.point_inside(DVec3::new(6.0, 6.0, 1.0)), "under the floor");
        assert!(!sides.point_inside(DVec3::new(6.0, 6.0, 2.0)), "above the floor, between beads");
        assert!(sides.point_inside(DVec3::new(3.0, 3.0, 3.0)), "in a bead");
        assert!(sides.point_inside(DVec3::new(3.0, 3.0, 1.2)), "in a bead and under the floor");
        assert!(!sides.point_inside(DVec3::new(3.0, 3.0, 5.9)), "above a bead");
        // Across the tile's border: the same bead seen from the copy at x + 12.
        assert!(sides.inside((15, 3, 3)));
        // Chain mail: in a ring's tube and in its hole.
        let rings = mesostructure::chain_mail_rings(dims);
        let mail = mesostructure::chain_mail(dims);
        let mesh = MeshRaycaster::new(&mail, Vec2::new(12.0, 12.0));
        let mut sides = MeshSides::new(&mesh, dims);
        let ring = rings[0];
        let in_tube = ring.center + DVec3::X.as_vec3() * ring.major_radius;
        assert!(sides.point_inside(in_tube.as_dvec3()), "in the tube at {in_tube}");
        assert!(!sides.point_inside(ring.center.as_dvec3()), "in the ring's hole");
        assert_eq!((sides.ambiguous_points, sides.edges_without_crossing), (0, 0));
    }
}
