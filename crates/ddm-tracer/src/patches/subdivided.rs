//! The watertight surface built on a finer grid, for features thinner than a voxel
//! (beyond the paper; issue: "features thinner than a voxel — the paper's *compute at
//! higher resolution* as sub-voxel patches in the same layout").
//!
//! The watertight polygons join points on the edges whose corners differ in side, so a
//! feature that crosses no edge (a chain-mail tube thinner than a voxel, passing between
//! two corners of one side) is not represented at all. With
//! [`PatchSettings::watertight_subdivision`](super::PatchSettings::watertight_subdivision)
//! `s > 1` the same construction runs on the grid of `s × s × s` cells per voxel (the
//! mesh scaled by `s`), restricted to the cells of the voxels that the mesh touches (a
//! cell whose corners differ lies in one: the mesh crosses its edges), with its crease
//! cells, and every cell's polygons become bounded triangles in the voxel holding the cell:
//! the same per-voxel patch layout, so the tracer and its WGSL twin read them unchanged.
//!
//! Every cell's decisions are shared with its neighbours as in the voxel grid, so the
//! triangles of all voxels still form one closed surface; a voxel holds more of them
//! (about `s²` times as many where the surface is smooth), which the tracer pays for in
//! every step that enters the voxel.

use alloc::collections::{BTreeMap, BTreeSet};
use alloc::vec::Vec;

use ddm_compress::Triangle;
use glam::{DVec3, UVec3, Vec3};
use quadric_fit::build_watertight;
use quadric_fit::surface::GridPoint;

use super::crease::{Fallback, bounded_triangles, corner_of, crease_triangles, polygon_triangles};
use super::voxel_planes;
use crate::exact_patches::voxel_triangle_patches;
use crate::ground_truth::MeshRaycaster;
use crate::patch::TracePatch;
use crate::solid::MeshSides;

/// A voxel's triangles (voxel coordinates) and the corner bits of those kept.
type VoxelTriangles = (Vec<[DVec3; 3]>, BTreeSet<[[u64; 3]; 3]>);

/// What [`subdivided_watertight`] reads: the tile and its mesh.
pub(super) struct Tile<'a> {
    /// Voxels of the tile.
    pub dims: UVec3,
    /// Whether it repeats in x and y.
    pub periodic: bool,
    /// The mesh (tile coordinates).
    pub triangles: &'a [Triangle],
    /// The mesh around the padded grid (tile coordinates + (1, 1, 0)).
    pub tiled: &'a [[Vec3; 3]],
    /// The triangles of each padded voxel (indices into `tiled`).
    pub bins: &'a BTreeMap<(u32, u32, u32), Vec<u32>>,
    /// The voxels the mesh touches (index `x + dims.x (y + dims.y z)`).
    pub surface: &'a [bool],
}

/// The patches (voxel-local) of each voxel of `tile` from the watertight surface of the
/// grid subdivided `subdivision` times per axis (see the module docs), and how many cells
/// got a feature vertex.
pub(super) fn subdivided_watertight(
    tile: &Tile<'_>,
    subdivision: u32,
    directions: &[Vec3],
) -> (BTreeMap<GridPoint, Vec<TracePatch>>, u32) {
    let (dims, s) = (tile.dims, subdivision);
    let scale = s as f32;
    let fine_dims = dims * s;
    let scaled: Vec<Triangle> = tile.triangles.iter().map(|t| Triangle(t.0.map(|v| v * scale))).collect();
    let period = if tile.periodic { glam::Vec2::new(fine_dims.x as f32, fine_dims.y as f32) } else { glam::Vec2::ZERO };
    let mesh = MeshRaycaster::new(&scaled, period);
    let mut sides = MeshSides::new(&mesh, fine_dims);
    let mut cells = Vec::new();
    for z in 0..dims.z {
        for y in 0..dims.y {
            for x in 0..dims.x {
                if !tile.surface[(x + dims.x * (y + dims.y * z)) as usize] {
                    continue;
                }
                for k in 0..s {
                    for j in 0..s {
                        for i in 0..s {
                            cells.push((x * s + i, y * s + j, z * s + k));
                        }
                    }
                }
            }
        }
    }
    let surface = build_watertight(cells, &mut sides);
    // A cell's mesh triangles, in cell coordinates, from its voxel's bin.
    let to_cells = |t: &[Vec3; 3]| t.map(|v| (v - Vec3::new(1.0, 1.0, 0.0)) * scale);
    let planes_and_exact = |cell: GridPoint| {
        let key = (cell.0 / s + 1, cell.1 / s + 1, cell.2 / s);
        let list = tile.bins.get(&key).map_or(&[][..], Vec::as_slice);
        let triangles: Vec<[Vec3; 3]> = list.iter().map(|&t| to_cells(&tile.tiled[t as usize])).collect();
        let origin = corner_of(cell);
        let planes = voxel_planes(triangles.iter(), origin);
        let mut exact = Vec::new();
        voxel_triangle_patches(triangles.iter(), origin.as_vec3(), &mut exact);
        (planes, exact)
    };
    let creases =
        crease_triangles(&surface, (fine_dims, tile.periodic), planes_and_exact, directions, Fallback::MeanFans);
    // Each cell's triangles into its voxel, in voxel coordinates; a flipped pair listed by
    // two cells of one voxel is kept once.
    let mut voxels: BTreeMap<GridPoint, VoxelTriangles> = BTreeMap::new();
    let inverse = 1.0 / f64::from(s);
    for (&cell, cell_surface) in &surface.voxels {
        let triangles = creases.get(&cell).cloned().unwrap_or_else(|| polygon_triangles(cell_surface));
        let (list, seen) = voxels.entry((cell.0 / s, cell.1 / s, cell.2 / s)).or_default();
        for triangle in triangles {
            let mut key = triangle.map(|p| p.to_array().map(f64::to_bits));
            key.sort_unstable();
            if seen.insert(key) {
                list.push(triangle.map(|p| p * inverse));
            }
        }
    }
    let patches =
        voxels.into_iter().map(|(voxel, (list, _))| (voxel, bounded_triangles(&list, corner_of(voxel)))).collect();
    (patches, creases.len() as u32)
}
