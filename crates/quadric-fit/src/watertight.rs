//! A watertight C⁰ surface from decisions shared by neighbouring voxels (beyond the
//! paper's sketch of §3.1 c).
//!
//! [`build_surface`](crate::build_surface) lets each voxel classify its corners and its
//! ambiguous faces with *its own* quadric, so two neighbours can disagree about a shared
//! face and leave a crack between their patches. Here every decision is taken once, for
//! the grid, and read by every voxel that needs it:
//!
//! - each grid **corner** is inside or outside the solid ([`SignedGrid::inside`]);
//! - an **edge** is crossed iff its two corners differ, and its point
//!   ([`SignedGrid::crossing`]) is asked once;
//! - an **ambiguous face** (corners alternating around it) is decided once by the side of
//!   its centre ([`SignedGrid::face_centre_inside`]), with the rule of
//!   [`build_surface`](crate::build_surface): corners on the centre's side are joined
//!   through the centre.
//!
//! The builder memoises every answer, so the result does not depend on the implementor
//! answering consistently. Each face then holds the same segments for both voxels that
//! share it (0, 1 or 2 segments between the same edge points), every crossed edge of a
//! voxel has exactly two neighbours on the voxel's faces, and the cycles close: the
//! polygons of neighbouring voxels meet edge to edge and the patches spanning them
//! ([`polygon_patches`](crate::surface::polygon_patches)) form a closed surface that
//! separates the inside corners from the outside ones — marching cubes' topology with
//! the patches of Appendix B.
//!
//! ```
//! use glam::DVec3;
//! use quadric_fit::surface::{GridEdge, GridFace, GridPoint};
//! use quadric_fit::watertight::{SignedGrid, build_watertight};
//!
//! /// A sphere of radius 1.6 about (2, 2, 2).
//! struct Ball;
//! impl SignedGrid for Ball {
//!     fn inside(&mut self, p: GridPoint) -> bool {
//!         (DVec3::new(p.0 as f64, p.1 as f64, p.2 as f64) - DVec3::splat(2.0)).length() < 1.6
//!     }
//!     fn crossing(&mut self, edge: GridEdge) -> DVec3 {
//!         let (a, b) = (edge.point(0.0), edge.point(1.0));
//!         let (da, db) = ((a - 2.0).length() - 1.6, (b - 2.0).length() - 1.6);
//!         a + (b - a) * (da / (da - db))
//!     }
//!     fn face_centre_inside(&mut self, face: GridFace) -> bool {
//!         (face.centre() - DVec3::splat(2.0)).length() < 1.6
//!     }
//! }
//! let voxels = (0..4).flat_map(|i| (0..4).flat_map(move |j| (0..4).map(move |k| (i, j, k))));
//! let surface = build_watertight(voxels, &mut Ball);
//! assert!(surface.skipped.is_empty());
//! assert_eq!(surface.voxels.len(), 56); // every voxel the sphere's corner signs cut
//! ```

use alloc::collections::BTreeMap;
use alloc::vec::Vec;

use glam::DVec3;

use crate::surface::{
    C0Surface, GridEdge, GridFace, GridPoint, Skipped, VoxelSurface, edge_offsets, face_links, offset, surface_loops,
    trace_loops,
};

/// The decisions of [`build_watertight`], each asked once per corner, edge or face of the
/// grid (in grid coordinates: voxel `(i, j, k)` is `[i, i+1] × [j, j+1] × [k, k+1]`).
pub trait SignedGrid {
    /// Whether the grid point `p` is inside the solid.
    fn inside(&mut self, p: GridPoint) -> bool;

    /// The point where the surface crosses `edge`, asked only for an edge whose two ends
    /// differ in [`inside`](Self::inside). It should lie on the edge (the patches pass
    /// through it); the builder keeps it as given.
    fn crossing(&mut self, edge: GridEdge) -> DVec3;

    /// Whether the centre of `face` is inside, asked only for a face whose corners
    /// alternate (an ambiguous face).
    fn face_centre_inside(&mut self, face: GridFace) -> bool;
}

/// Memoised answers of a [`SignedGrid`].
struct Decisions<'a, G: SignedGrid> {
    grid: &'a mut G,
    corners: BTreeMap<GridPoint, bool>,
    faces: BTreeMap<GridFace, bool>,
}

impl<G: SignedGrid> Decisions<'_, G> {
    fn inside(&mut self, p: GridPoint) -> bool {
        if let Some(&inside) = self.corners.get(&p) {
            return inside;
        }
        let inside = self.grid.inside(p);
        self.corners.insert(p, inside);
        inside
    }

    fn face_inside(&mut self, face: GridFace) -> bool {
        if let Some(&inside) = self.faces.get(&face) {
            return inside;
        }
        let inside = self.grid.face_centre_inside(face);
        self.faces.insert(face, inside);
        inside
    }
}

/// The watertight C⁰ surface through `voxels` (see the module docs). Voxels whose eight
/// corners agree have no surface and are not listed anywhere; a voxel touching coordinate
/// `u32::MAX` is [`Skipped::OutOfRange`]. [`VoxelSurface::double_hits`] is 0: whether an
/// edge between two corners of one side crosses the surface twice is the caller's to
/// count.
pub fn build_watertight(voxels: impl IntoIterator<Item = GridPoint>, grid: &mut impl SignedGrid) -> C0Surface {
    let mut decisions = Decisions { grid, corners: BTreeMap::new(), faces: BTreeMap::new() };
    let mut surface = C0Surface::default();
    let mut crossed_voxels = Vec::new();
    for voxel in voxels {
        if voxel.0 == u32::MAX || voxel.1 == u32::MAX || voxel.2 == u32::MAX {
            surface.skipped.insert(voxel, Skipped::OutOfRange);
            continue;
        }
        let mut inside = [false; 8];
        for (c, slot) in inside.iter_mut().enumerate() {
            *slot = decisions.inside(offset(voxel, [(c & 1) as u32, ((c >> 1) & 1) as u32, ((c >> 2) & 1) as u32]));
        }
        if inside.iter().all(|&s| s == inside[0]) {
            continue;
        }
        let mut crossed = [false; 12];
        for (l, slot) in crossed.iter_mut().enumerate() {
            let (axis, off) = edge_offsets(l);
            let mut far = off;
            far[axis] = 1;
            let index = |o: [u32; 3]| (o[0] + 2 * o[1] + 4 * o[2]) as usize;
            *slot = inside[index(off)] != inside[index(far)];
            if *slot {
                let edge = GridEdge { axis: axis as u8, corner: offset(voxel, off) };
                surface.edge_points.entry(edge).or_insert_with(|| decisions.grid.crossing(edge));
            }
        }
        let links = face_links(&inside, &crossed, |normal, side| {
            let mut corner = [voxel.0, voxel.1, voxel.2];
            corner[normal] += side;
            decisions.face_inside(GridFace { normal: normal as u8, corner: (corner[0], corner[1], corner[2]) })
        });
        crossed_voxels.push((voxel, links, crossed));
    }
    for (voxel, links, crossed) in crossed_voxels {
        let Some(cycles) = trace_loops(&links, &crossed) else {
            // Cannot happen: shared corner signs give every crossed edge two neighbours.
            surface.skipped.insert(voxel, Skipped::Open);
            continue;
        };
        let loops = surface_loops(voxel, &cycles, &surface.edge_points);
        surface.voxels.insert(voxel, VoxelSurface { loops, double_hits: 0 });
    }
    surface
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Random corner signs: every face segment of a voxel appears, with the same two
    /// points, in the neighbour across the face, and every cycle has at least 3 points.
    #[test]
    fn random_signs_give_closed_polygons_that_neighbours_share() {
        struct Random(u64);
        impl Random {
            fn bit(&self, p: GridPoint, salt: u64) -> bool {
                let mut h = self.0 ^ salt;
                for v in [p.0, p.1, p.2] {
                    h = (h ^ u64::from(v)).wrapping_mul(0x9e37_79b9_7f4a_7c15);
                    h ^= h >> 29;
                }
                h & 1 == 1
            }
        }
        impl SignedGrid for Random {
            fn inside(&mut self, p: GridPoint) -> bool {
                self.bit(p, 1)
            }
            fn crossing(&mut self, edge: GridEdge) -> DVec3 {
                edge.point(0.25 + 0.5 * f64::from(u8::from(self.bit(edge.corner, 7 + u64::from(edge.axis)))))
            }
            fn face_centre_inside(&mut self, face: GridFace) -> bool {
                self.bit(face.corner, 3 + u64::from(face.normal))
            }
        }
        for seed in 0..8 {
            let n = 6;
            let voxels: Vec<GridPoint> =
                (0..n).flat_map(|i| (0..n).flat_map(move |j| (0..n).map(move |k| (i, j, k)))).collect();
            let surface = build_watertight(voxels.iter().copied(), &mut Random(seed));
            assert!(surface.skipped.is_empty(), "{:?}", surface.skipped);
            assert!(surface.voxels.len() > 100, "seed {seed}: {} voxels", surface.voxels.len());
            // Segments per face, keyed by the face, from both sides.
            let mut segments: BTreeMap<GridFace, [Vec<[GridEdge; 2]>; 2]> = BTreeMap::new();
            for (&voxel, vs) in &surface.voxels {
                for l in &vs.loops {
                    assert!(l.points.len() >= 3);
                    for i in 0..l.edges.len() {
                        let (a, b) = (l.edges[i], l.edges[(i + 1) % l.edges.len()]);
                        // The face both edges bound: its normal runs along neither edge, and
                        // both edges lie at the same level along it.
                        let at = |e: GridEdge, axis: usize| [e.corner.0, e.corner.1, e.corner.2][axis];
                        let normal = (0..3)
                            .find(|&x| x != usize::from(a.axis) && x != usize::from(b.axis) && at(a, x) == at(b, x))
                            .expect("linked edges bound a common face");
                        let level = |e: GridEdge| at(e, normal);
                        let mut corner = [voxel.0, voxel.1, voxel.2];
                        let side = usize::from(level(a) != corner[normal]);
                        corner[normal] = level(a);
                        let face = GridFace { normal: normal as u8, corner: (corner[0], corner[1], corner[2]) };
                        let mut pair = [a, b];
                        pair.sort();
                        segments.entry(face).or_default()[side].push(pair);
                    }
                }
            }
            let mut shared = 0;
            for (face, [low, high]) in &mut segments {
                let level = [face.corner.0, face.corner.1, face.corner.2][usize::from(face.normal)];
                if level == 0 || level == n {
                    continue; // the grid's border: one side only
                }
                low.sort();
                high.sort();
                assert_eq!(low, high, "seed {seed}: face {face:?}");
                shared += 1;
            }
            assert!(shared > 100, "seed {seed}: {shared} shared faces");
        }
    }
}
