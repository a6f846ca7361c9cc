//! The quadric patches of the zero-distance voxels (§3.1 "Quadratic Surface", steps a–c),
//! stored per voxel for the tracer (Algorithm 3.2), in voxel-local coordinates.
//!
//! For every voxel that the mesostructure crosses (DDM value 0):
//!
//! a. the triangles inside the voxel grown by [`PatchSettings::margin`] ("inside or in
//!    the neighborhood of V") are sampled densely and a quadric is fitted to the samples
//!    (eq. 2, [`quadric_fit::fit_quadric`]);
//! b–c. [`quadric_fit::build_surface`] averages the edge hits and builds the C⁰ triangle /
//!    bilinear patches (Appendix B). A voxel whose quadric crosses none of its edges is
//!    rebuilt from the least-squares plane of its samples (a documented fallback: without
//!    it the voxel would have no patch and rays would pass through it).
//!
//! The tile repeats in x and y, so the construction runs on the grid padded by one voxel
//! on each side in x and y with copies of the opposite border: the edges on the tile's
//! border then average the same hit lists on both sides, and the surface stays C⁰ across
//! tiles too.
//!
//! Each patch is kept as a [`TracePatch`]: its quadric in coordinates relative to the
//! voxel's lowest corner (well scaled in `f32`), and its polygon. A voxel with one patch
//! accepts any hit inside the voxel (the patch's border lies on the voxel's faces); a voxel
//! with several patches (a fan, or separate sheets) accepts a hit on a patch only inside
//! that patch's polygon (see [`inside_polygon`](crate::patch::inside_polygon)).
//!
//! [`PatchSettings::surface`] picks what a voxel keeps: the C⁰ patches above (the
//! paper), the watertight C⁰ patches from decisions shared by neighbours (beyond the
//! paper: [`PatchSurface::Watertight`]), the fitted quadric of step a alone, the mesh's own triangles (exact, bounded
//! by their polygon even when alone: [`crate::exact_patches`]), or per voxel the cheaper
//! of the fitted quadric and the triangles that meets an error budget.

mod crease;
mod subdivided;

use alloc::collections::BTreeMap;
use alloc::vec::Vec;
use core::fmt;

use ddm_compress::Triangle;
use ddm_compress::geometry::{Aabb, triangle_overlaps_box};
use glam::{DVec3, UVec3, Vec2, Vec3, Vec4};
use quadric_fit::surface::{C0Surface, Skipped};
use quadric_fit::{GpuQuadric, Quadric, TangentPlane, build_surface, build_watertight, fit_plane, fit_quadric};

use crate::exact_patches::{probe_directions, representation_error, voxel_triangle_patches};
use crate::ground_truth::MeshRaycaster;
use crate::patch::{BOUNDED_PATCH, TracePatch};
use crate::solid::MeshSides;
use crease::Fallback;

/// What replaces the mesostructure inside a zero-distance voxel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PatchSurface {
    /// The C⁰ patches of §3.1 steps b–c (the paper's construction).
    C0,
    /// The watertight C⁰ surface (beyond the paper): the side of every grid corner from
    /// the mesh's ray winding number, the mesh's own crossing of every edge whose corners
    /// differ, ambiguous faces decided once at their centres ([`crate::solid`]), and the
    /// triangle / bilinear patches of Appendix B through the resulting polygons
    /// ([`quadric_fit::watertight`]). Neighbouring voxels share every decision, so the
    /// patches leave no crack; a feature that crosses no edge (thinner than a voxel
    /// between two corners of one side) is not represented. Where a crease or corner of
    /// flat pieces crosses a voxel, its polygon is fanned around the mesh's feature vertex
    /// and the fans of neighbours are joined across their faces (extended marching cubes'
    /// feature vertices and edge flips), each only where it follows the mesh better: see
    /// [`VoxelPatches::feature_vertex_voxels`] and the `patches::crease` module notes. With
    /// [`PatchSettings::watertight_subdivision`] above 1 the surface is built on cells finer
    /// than the voxels and stored as bounded triangles, so that features thinner than a
    /// voxel are represented too (the `patches::subdivided` module notes).
    Watertight,
    /// Each voxel keeps its fitted quadric of step a as its only patch, intersected
    /// anywhere inside the voxel (Algorithm 3.2 on `Q_V` itself; not C⁰ across voxels, but
    /// it follows sharp edges and corners that the sign-based polygons of step c cut off).
    FittedQuadric,
    /// Each voxel keeps the mesh triangles that touch it as bounded plane patches: the
    /// tracer returns the mesh's own hit (beyond the paper; see [`crate::exact_patches`]).
    Triangles,
    /// Per voxel, the fitted quadric where its hits stay within `max_error` voxels of the
    /// triangles' on the probe segments of [`crate::exact_patches::representation_error`],
    /// else the triangles: the cheapest of the two that meets the budget.
    Adaptive {
        /// The error budget, in voxels.
        max_error: f32,
    },
}

/// Settings of [`VoxelPatches::build`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatchSettings {
    /// How far around the voxel (in voxels) the surface samples of the fit reach. 0 (the
    /// default: samples inside the closed voxel only) measured best on the maze and bricks,
    /// whose sharp edges otherwise tilt the fits of the flat voxels next to them.
    pub margin: f32,
    /// Subdivisions per triangle edge when sampling (`n (n + 1) / 2` barycentric points).
    pub samples_per_edge: u32,
    /// What each voxel keeps ([`PatchSurface::C0`] by default, the paper's construction).
    pub surface: PatchSurface,
    /// Whether the tile repeats in x and y (the default, as the paper's tiles), so that
    /// the voxels on its border see the opposite border's triangles; otherwise nothing lies
    /// outside the tile. Must be the maps' [`ddm_compress::DistanceMapSettings::periodic_xy`]
    /// (the GPU scene refuses patches built otherwise).
    pub periodic_xy: bool,
    /// [`PatchSurface::Watertight`] on a grid of `n × n × n` cells per voxel (1, the
    /// default: the voxels themselves; at most [`MAX_WATERTIGHT_SUBDIVISION`]): features
    /// thinner than a voxel get a surface, at the price of about `n²` times the triangles
    /// per voxel (see the `patches::subdivided` module notes). Other surfaces ignore it.
    pub watertight_subdivision: u32,
}

impl Default for PatchSettings {
    fn default() -> Self {
        Self {
            margin: 0.0,
            samples_per_edge: 16,
            surface: PatchSurface::C0,
            periodic_xy: true,
            watertight_subdivision: 1,
        }
    }
}

/// The most voxels [`VoxelPatches::build`] accepts: 2²⁴ (as
/// [`ddm_compress::compute_distance_maps`]).
pub const MAX_PATCH_VOXELS: u64 = 1 << 24;

/// The finest [`PatchSettings::watertight_subdivision`]: 8 cells per voxel and axis.
pub const MAX_WATERTIGHT_SUBDIVISION: u32 = 8;

/// Why [`VoxelPatches::build`] refused its inputs. The checks run in the order of the
/// variants; the first that fails is returned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PatchError {
    /// A side of the grid is zero.
    EmptyGrid {
        /// The grid size given.
        dims: UVec3,
    },
    /// The grid has more than `limit` ([`MAX_PATCH_VOXELS`]) voxels.
    TooManyVoxels {
        /// The grid size given.
        dims: UVec3,
        /// The largest number of voxels accepted.
        limit: u64,
    },
    /// `surface` does not have one entry per voxel.
    SurfaceCount {
        /// Voxels of the grid.
        expected: usize,
        /// Entries of `surface`.
        found: usize,
    },
    /// A vertex of triangle `index` (in the slice given) is NaN or infinite.
    NonFiniteTriangle {
        /// The triangle's index.
        index: usize,
    },
    /// [`PatchSettings::watertight_subdivision`] is 0 or above [`MAX_WATERTIGHT_SUBDIVISION`].
    WatertightSubdivision {
        /// The subdivision given.
        subdivision: u32,
    },
}

impl fmt::Display for PatchError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::EmptyGrid { dims } => write!(f, "patches: the grid {dims} has no voxel"),
            Self::TooManyVoxels { dims, limit } => {
                write!(f, "patches: the grid {dims} has more than the limit of {limit} voxels")
            }
            Self::SurfaceCount { expected, found } => {
                write!(f, "patches: {found} surface flags for {expected} voxels")
            }
            Self::NonFiniteTriangle { index } => write!(f, "patches: triangle {index} has a non-finite vertex"),
            Self::WatertightSubdivision { subdivision } => {
                write!(f, "patches: watertight_subdivision {subdivision} is not in 1..={MAX_WATERTIGHT_SUBDIVISION}")
            }
        }
    }
}

impl core::error::Error for PatchError {}

/// The patches of every voxel, in compressed sparse row form.
#[derive(Clone, Debug, PartialEq)]
pub struct VoxelPatches {
    /// Grid size in voxels.
    pub dims: UVec3,
    /// `offsets[v]..offsets[v + 1]` are voxel `v`'s patches (`v = x + dims.x (y + dims.y z)`);
    /// `voxels + 1` entries.
    pub offsets: Vec<u32>,
    /// All patches.
    pub patches: Vec<TracePatch>,
    /// Surface voxels that got no patch (the fitted quadric crosses none of their edges).
    pub voxels_without_patch: u32,
    /// Voxels whose patches are a quadric (fitted, or the C⁰ patches).
    pub quadric_voxels: u32,
    /// Voxels whose patches are exact triangles.
    pub triangle_voxels: u32,
    /// Voxels with patches that are not surface voxels (their distance is not 0), so the
    /// tracer never intersects those patches: 0 unless the mesh's sides were decided
    /// wrongly ([`PatchSurface::Watertight`]) or a fitted surface reaches into them.
    pub patch_voxels_off_surface: u32,
    /// Voxels of [`PatchSurface::Watertight`] whose polygon is fanned around its feature
    /// vertex (a crease or a corner of the mesh crosses them; see
    /// [`PatchSurface::Watertight`]); cells of voxels with
    /// [`PatchSettings::watertight_subdivision`] above 1.
    pub feature_vertex_voxels: u32,
    /// Whether they were built for a tile repeating in x and y ([`PatchSettings::periodic_xy`]).
    pub periodic_xy: bool,
}

impl VoxelPatches {
    /// Fits and builds the patches of every voxel with `surface[v]` (index as in
    /// [`ddm_compress::DistanceMaps`]) from `triangles` (voxel coordinates, the tile
    /// `[0, dims.x] × [0, dims.y]` repeating in x and y, or alone where
    /// [`PatchSettings::periodic_xy`] is false).
    ///
    /// # Errors
    ///
    /// A [`PatchError`]: an empty grid or one of more than [`MAX_PATCH_VOXELS`] voxels,
    /// `surface` without one entry per voxel, a non-finite triangle (with its index), or a
    /// watertight subdivision out of range.
    pub fn build(
        dims: UVec3,
        triangles: &[Triangle],
        surface: &[bool],
        settings: PatchSettings,
    ) -> Result<Self, PatchError> {
        if dims.cmpeq(UVec3::ZERO).any() {
            return Err(PatchError::EmptyGrid { dims });
        }
        let voxels = u128::from(dims.x) * u128::from(dims.y) * u128::from(dims.z);
        if voxels > u128::from(MAX_PATCH_VOXELS) {
            return Err(PatchError::TooManyVoxels { dims, limit: MAX_PATCH_VOXELS });
        }
        let voxels = voxels as usize; // at most MAX_PATCH_VOXELS
        if surface.len() != voxels {
            return Err(PatchError::SurfaceCount { expected: voxels, found: surface.len() });
        }
        if let Some(index) = triangles.iter().position(|t| !t.is_finite()) {
            return Err(PatchError::NonFiniteTriangle { index });
        }
        let subdivision = settings.watertight_subdivision;
        if !(1..=MAX_WATERTIGHT_SUBDIVISION).contains(&subdivision) {
            return Err(PatchError::WatertightSubdivision { subdivision });
        }
        // The mesh around the padded grid: the tile and its 8 neighbours, moved by +1 voxel
        // in x and y (padded voxel (i, j, k) is tile voxel (i - 1, j - 1, k) mod dims); a
        // tile that does not repeat has no neighbours and its padding voxels no surface.
        let periodic = settings.periodic_xy;
        let (sx, sy) = (dims.x as f32, dims.y as f32);
        let neighbours = if periodic { -1..=1 } else { 0..=0 };
        let mut tiled = Vec::with_capacity(triangles.len() * if periodic { 9 } else { 1 });
        for oy in neighbours.clone() {
            for ox in neighbours.clone() {
                let shift = Vec3::new(ox as f32 * sx + 1.0, oy as f32 * sy + 1.0, 0.0);
                tiled.extend(triangles.iter().map(|t| t.0.map(|v| v + shift)));
            }
        }
        let padded = UVec3::new(dims.x + 2, dims.y + 2, dims.z);
        // Triangles per padded voxel, from their grown bounding boxes; a box touching a
        // voxel's face counts (a floor at an integer height belongs to the voxels on both
        // sides of it).
        let mut bins: BTreeMap<(u32, u32, u32), Vec<u32>> = BTreeMap::new();
        let is_surface = |i: u32, j: u32, k: u32| {
            if !periodic && (i == 0 || j == 0 || i > dims.x || j > dims.y) {
                return false;
            }
            let x = (i + dims.x - 1) % dims.x;
            let y = (j + dims.y - 1) % dims.y;
            surface[(x + dims.x * (y + dims.y * k)) as usize]
        };
        for (index, t) in tiled.iter().enumerate() {
            let lo = t[0].min(t[1]).min(t[2]) - Vec3::splat(settings.margin);
            let hi = t[0].max(t[1]).max(t[2]) + Vec3::splat(settings.margin);
            let range = |lo: f32, hi: f32, n: u32| {
                ((libm::ceilf(lo) - 1.0).max(0.0) as i64, (libm::floorf(hi) as i64).min(i64::from(n) - 1))
            };
            let (x0, x1) = range(lo.x, hi.x, padded.x);
            let (y0, y1) = range(lo.y, hi.y, padded.y);
            let (z0, z1) = range(lo.z, hi.z, padded.z);
            for k in z0..=z1 {
                for j in y0..=y1 {
                    for i in x0..=x1 {
                        let (i, j, k) = (i as u32, j as u32, k as u32);
                        if is_surface(i, j, k) {
                            bins.entry((i, j, k)).or_default().push(index as u32);
                        }
                    }
                }
            }
        }
        // Step a: one quadric per surface voxel of the padded grid (not needed for exact
        // triangles).
        let mut quadrics = BTreeMap::new();
        let mut points = Vec::new();
        let fit_needed = !matches!(settings.surface, PatchSurface::Triangles | PatchSurface::Watertight);
        for (&(i, j, k), list) in bins.iter().filter(|_| fit_needed) {
            let lo = DVec3::new(f64::from(i), f64::from(j), f64::from(k)) - f64::from(settings.margin);
            let hi = lo + 1.0 + 2.0 * f64::from(settings.margin);
            points.clear();
            for &t in list {
                sample_triangle(&tiled[t as usize], settings.samples_per_edge, lo, hi, &mut points);
            }
            if let Ok(fit) = fit_quadric(&points) {
                quadrics.insert((i, j, k), fit.quadric);
            }
        }
        let built = if settings.surface == PatchSurface::C0 {
            Some(c0_surface(&mut quadrics, &bins, &tiled, settings))
        } else {
            None
        };
        let watertight_kind = settings.surface == PatchSurface::Watertight;
        let watertight = (watertight_kind && subdivision == 1).then(|| {
            let mesh = MeshRaycaster::new(triangles, if periodic { Vec2::new(sx, sy) } else { Vec2::ZERO });
            let mut sides = MeshSides::new(&mesh, dims);
            let voxels = (0..dims.z).flat_map(|z| (0..dims.y).flat_map(move |y| (0..dims.x).map(move |x| (x, y, z))));
            build_watertight(voxels, &mut sides)
        });
        let directions = probe_directions();
        // The watertight voxels whose patches are built apart (voxel-local): the crease and
        // corner voxels' fans and flips, or with subdivision every voxel's cells.
        let (watertight_patches, feature_vertex_voxels) = if let Some(surface) = &watertight {
            let planes_and_exact = |(x, y, z): (u32, u32, u32)| {
                let key = (x + 1, y + 1, z);
                let origin = DVec3::new(f64::from(key.0), f64::from(key.1), f64::from(key.2));
                let list = bins.get(&key).map_or(&[][..], Vec::as_slice);
                let planes = voxel_planes(list.iter().map(|&t| &tiled[t as usize]), origin);
                let mut exact = Vec::new();
                voxel_triangle_patches(list.iter().map(|&t| &tiled[t as usize]), origin.as_vec3(), &mut exact);
                (planes, exact)
            };
            let creases = crease::crease_triangles(
                surface,
                (dims, periodic),
                planes_and_exact,
                &directions,
                Fallback::PolygonPatches,
            );
            let count = creases.len() as u32;
            let patches = creases
                .into_iter()
                .map(|(voxel, list)| (voxel, crease::bounded_triangles(&list, crease::corner_of(voxel))))
                .collect();
            (patches, count)
        } else if watertight_kind {
            let tile = subdivided::Tile { dims, periodic, triangles, tiled: &tiled, bins: &bins, surface };
            subdivided::subdivided_watertight(&tile, subdivision, &directions)
        } else {
            (BTreeMap::new(), 0)
        };
        let mut offsets = Vec::with_capacity(voxels + 1);
        let mut patches = Vec::new();
        let (mut voxels_without_patch, mut quadric_voxels, mut triangle_voxels) = (0, 0, 0);
        let mut patch_voxels_off_surface = 0;
        let mut exact = Vec::new();
        offsets.push(0);
        for z in 0..dims.z {
            for y in 0..dims.y {
                for x in 0..dims.x {
                    let index = (x + dims.x * (y + dims.y * z)) as usize;
                    let key = (x + 1, y + 1, z);
                    let origin = DVec3::new(f64::from(key.0), f64::from(key.1), f64::from(key.2));
                    let fitted = || quadrics.get(&key).and_then(|q| fitted_patch(q, origin));
                    let triangles = |out: &mut Vec<TracePatch>| {
                        let list = bins.get(&key).map_or(&[][..], Vec::as_slice);
                        voxel_triangle_patches(list.iter().map(|&t| &tiled[t as usize]), origin.as_vec3(), out);
                    };
                    let before = patches.len();
                    match settings.surface {
                        PatchSurface::C0 => {
                            if let Some(voxel) = built.as_ref().and_then(|b| b.voxels.get(&key)) {
                                for surface_loop in &voxel.loops {
                                    for patch in &surface_loop.patches {
                                        if let Some(p) = trace_patch(&patch.quadric, &patch.polygon, origin) {
                                            patches.push(p);
                                        }
                                    }
                                }
                            }
                        }
                        PatchSurface::Watertight => {
                            let tile_origin = DVec3::new(f64::from(x), f64::from(y), f64::from(z));
                            if let Some(built) = watertight_patches.get(&(x, y, z)) {
                                patches.extend_from_slice(built);
                            } else if let Some(voxel) = watertight.as_ref().and_then(|b| b.voxels.get(&(x, y, z))) {
                                crease::polygon_patches(voxel, tile_origin, &mut patches);
                            }
                        }
                        PatchSurface::FittedQuadric => patches.extend(fitted()),
                        PatchSurface::Triangles => triangles(&mut patches),
                        PatchSurface::Adaptive { max_error } => {
                            exact.clear();
                            triangles(&mut exact);
                            match fitted() {
                                Some(quadric) if representation_error(&[quadric], &exact, &directions) <= max_error => {
                                    patches.push(quadric);
                                }
                                _ => patches.extend_from_slice(&exact),
                            }
                        }
                    }
                    let added = &patches[before..];
                    if !added.is_empty() {
                        if added.iter().any(|p| p.ij_corners.w == BOUNDED_PATCH) {
                            triangle_voxels += 1;
                        } else {
                            quadric_voxels += 1;
                        }
                    }
                    if surface[index] && added.is_empty() {
                        voxels_without_patch += 1;
                    }
                    if !surface[index] && !added.is_empty() {
                        patch_voxels_off_surface += 1;
                    }
                    offsets.push(patches.len() as u32);
                }
            }
        }
        Ok(Self {
            dims,
            offsets,
            patches,
            voxels_without_patch,
            quadric_voxels,
            triangle_voxels,
            patch_voxels_off_surface,
            feature_vertex_voxels,
            periodic_xy: periodic,
        })
    }

    /// The bytes the tracer reads for the patches: the patches and the offsets.
    pub fn byte_size(&self) -> usize {
        self.patches.len() * size_of::<TracePatch>() + self.offsets.len() * 4
    }

    /// The patches of voxel `v` (tile coordinates), empty outside the grid.
    pub fn of_voxel(&self, voxel: UVec3) -> &[TracePatch] {
        if !voxel.cmplt(self.dims).all() {
            return &[];
        }
        let v = (voxel.x + self.dims.x * (voxel.y + self.dims.y * voxel.z)) as usize;
        let (a, b) = (self.offsets[v] as usize, self.offsets[v + 1] as usize);
        &self.patches[a..b]
    }
}

/// Steps b–c on the fitted `quadrics` (padded grid). A fitted quadric that crosses none of
/// its voxel's edges (a surface curving inside the voxel, or a fit whose second sheet
/// takes over) leaves a hole; such voxels get the least-squares plane of their samples
/// instead (it passes through their centroid, inside the voxel, so it crosses some edges).
fn c0_surface(
    quadrics: &mut BTreeMap<(u32, u32, u32), Quadric>,
    bins: &BTreeMap<(u32, u32, u32), Vec<u32>>,
    tiled: &[[Vec3; 3]],
    settings: PatchSettings,
) -> C0Surface {
    let mut built = build_surface(quadrics);
    let mut replaced = false;
    let mut points = Vec::new();
    for (&key, &why) in &built.skipped {
        if why != Skipped::NoCrossing {
            continue;
        }
        let Some(list) = bins.get(&key) else { continue };
        let lo = DVec3::new(f64::from(key.0), f64::from(key.1), f64::from(key.2)) - f64::from(settings.margin);
        let hi = lo + 1.0 + 2.0 * f64::from(settings.margin);
        points.clear();
        for &t in list {
            sample_triangle(&tiled[t as usize], settings.samples_per_edge, lo, hi, &mut points);
        }
        if let Ok(plane) = fit_plane(&points) {
            quadrics.insert(key, plane.quadric);
            replaced = true;
        }
    }
    if replaced {
        built = build_surface(quadrics);
    }
    built
}

/// The single, unbounded patch of a voxel's fitted `quadric` (grid coordinates),
/// relative to the voxel corner `origin`.
fn fitted_patch(quadric: &Quadric, origin: DVec3) -> Option<TracePatch> {
    let local = quadric.in_frame(origin, 1.0).ok()?;
    let gpu = GpuQuadric::from_quadric(&local);
    Some(TracePatch {
        abcd: gpu.abcd,
        efgh: gpu.efgh,
        ij_corners: Vec4::new(gpu.ij.x, gpu.ij.y, 0.0, 0.0),
        ..bytemuck::Zeroable::zeroed()
    })
}

/// The [`TracePatch`] of `quadric` (grid coordinates) and its polygon, relative to the
/// voxel corner `origin`; `None` for more than 4 corners or a quadric that does not survive
/// the change of frame.
fn trace_patch(quadric: &Quadric, polygon: &[DVec3], origin: DVec3) -> Option<TracePatch> {
    if polygon.len() < 3 || polygon.len() > 4 {
        return None;
    }
    let local = quadric.in_frame(origin, 1.0).ok()?;
    let gpu = GpuQuadric::from_quadric(&local);
    let corner = |i: usize| {
        let p = polygon[i.min(polygon.len() - 1)] - origin;
        p.as_vec3().extend(0.0)
    };
    // Newell's normal of the polygon: the projection direction of the polygon test.
    let mut normal = DVec3::ZERO;
    for i in 0..polygon.len() {
        let (a, b) = (polygon[i] - origin, polygon[(i + 1) % polygon.len()] - origin);
        normal += DVec3::new((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    }
    let normal = normal.normalize_or_zero().as_vec3();
    Some(TracePatch {
        abcd: gpu.abcd,
        efgh: gpu.efgh,
        ij_corners: Vec4::new(gpu.ij.x, gpu.ij.y, polygon.len() as f32, 0.0),
        normal: normal.extend(0.0),
        corners: [corner(0), corner(1), corner(2), corner(3)],
    })
}

/// The mean of `points`.
fn mean(points: &[DVec3]) -> DVec3 {
    points.iter().sum::<DVec3>() / points.len() as f64
}

/// The planes of the `triangles` (grid coordinates) that cross the unit voxel with lowest
/// corner `origin`, relative to `origin`.
fn voxel_planes<'a>(triangles: impl IntoIterator<Item = &'a [Vec3; 3]>, origin: DVec3) -> Vec<TangentPlane> {
    let corner = origin.as_vec3();
    let voxel = Aabb { min: corner, max: corner + Vec3::ONE };
    triangles
        .into_iter()
        .filter(|t| triangle_overlaps_box(&Triangle(**t), &voxel))
        .filter_map(|t| {
            let [a, b, c] = t.map(|v| v.as_dvec3() - origin);
            let normal = (b - a).cross(c - a);
            (normal.length_squared() > f64::MIN_POSITIVE).then_some(TangentPlane { normal, point: a })
        })
        .collect()
}

/// Barycentric samples of `triangle` on an `n`-step grid, kept when inside `[lo, hi]`.
fn sample_triangle(triangle: &[Vec3; 3], n: u32, lo: DVec3, hi: DVec3, out: &mut Vec<DVec3>) {
    let n = n.max(1);
    let [a, b, c] = triangle.map(Vec3::as_dvec3);
    for i in 0..=n {
        for j in 0..=n - i {
            let (u, v) = (f64::from(i) / f64::from(n), f64::from(j) / f64::from(n));
            let p = a + (b - a) * u + (c - a) * v;
            if p.cmpge(lo).all() && p.cmple(hi).all() {
                out.push(p);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use alloc::string::ToString;

    use super::*;
    use ddm_compress::{DistanceMapSettings, MapKind, compute_distance_maps};

    #[test]
    fn each_invalid_input_has_its_error() {
        use PatchError::*;
        let settings = PatchSettings::default();
        let floor = mesostructure::plane(UVec3::new(4, 4, 2), 0.5);
        let flat = UVec3::new(4, 4, 0);
        assert_eq!(VoxelPatches::build(flat, &floor, &[], settings), Err(EmptyGrid { dims: flat }));
        let big = UVec3::new(1 << 12, 1 << 12, 2);
        assert_eq!(VoxelPatches::build(big, &floor, &[], settings), Err(TooManyVoxels { dims: big, limit: 1 << 24 }));
        let huge = UVec3::splat(u32::MAX);
        assert_eq!(
            VoxelPatches::build(huge, &floor, &[], settings),
            Err(TooManyVoxels { dims: huge, limit: MAX_PATCH_VOXELS })
        );
        let dims = UVec3::new(4, 4, 2);
        assert_eq!(
            VoxelPatches::build(dims, &floor, &[false; 31], settings),
            Err(SurfaceCount { expected: 32, found: 31 })
        );
        let mut broken = floor.clone();
        broken[1].0[2].z = f32::INFINITY;
        let error = VoxelPatches::build(dims, &broken, &[true; 32], settings).unwrap_err();
        assert_eq!(error, NonFiniteTriangle { index: 1 });
        assert!(error.to_string().contains("triangle 1"), "{error}");
        assert!(VoxelPatches::build(dims, &floor, &[true; 32], settings).is_ok());
        for subdivision in [0, MAX_WATERTIGHT_SUBDIVISION + 1] {
            let settings = PatchSettings { watertight_subdivision: subdivision, ..settings };
            let error = VoxelPatches::build(dims, &floor, &[true; 32], settings).unwrap_err();
            assert_eq!(error, WatertightSubdivision { subdivision });
            assert!(error.to_string().contains("watertight_subdivision"), "{error}");
        }
    }

    /// A box standing alone: the voxels its vertical edges cross get feature vertices,
    /// and a ray aimed 0.02 voxel beside an edge meets the box's side there, where the
    /// polygon's patch (through points on the voxel's edges) cuts the edge off.
    #[test]
    fn a_boxs_edges_are_kept_by_the_crease_voxels() {
        let dims = UVec3::new(12, 12, 6);
        let (lo, hi) = (Vec3::new(3.3, 4.2, 0.4), Vec3::new(8.6, 7.7, 4.4));
        let corner = |i: usize| Vec3::select(glam::BVec3::new(i & 1 != 0, i & 2 != 0, i & 4 != 0), hi, lo);
        let faces = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
        let tris: Vec<Triangle> = faces
            .iter()
            .flat_map(|&[a, b, c, d]| {
                [Triangle([corner(a), corner(b), corner(c)]), Triangle([corner(a), corner(c), corner(d)])]
            })
            .collect();
        let settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: false };
        let maps = compute_distance_maps(dims, &tris, MapKind::Plain, settings).unwrap();
        let settings =
            PatchSettings { surface: PatchSurface::Watertight, periodic_xy: false, ..PatchSettings::default() };
        let patches = VoxelPatches::build(dims, &tris, &maps.surface, settings).unwrap();
        // The 4 vertical edges cross 4 voxels each; the 8 horizontal edges more.
        assert!(patches.feature_vertex_voxels >= 16, "{} feature voxels", patches.feature_vertex_voxels);
        // Voxel (8, 7, 2) holds the edge x = 8.6, y = 7.7: locally (0.6, 0.7). A ray from
        // the +x wall at y = 0.68 meets the side x = 0.6 after 0.4.
        let voxel = UVec3::new(8, 7, 2);
        let hit =
            crate::patch::patch_hit(patches.of_voxel(voxel), Vec3::new(1.0, 0.68, 0.5), Vec3::NEG_X, 1.0).map(|h| h.0);
        assert!(hit.is_some_and(|t| (t - 0.4).abs() < 1e-4), "{hit:?}");
        assert_eq!(patches.patch_voxels_off_surface, 0);
    }

    #[test]
    fn a_tilted_plane_gets_one_patch_per_surface_voxel_matching_the_plane() {
        let dims = UVec3::new(6, 6, 4);
        let field = |x: f32, y: f32| 1.3 + 0.2 * x + 0.1 * y;
        // A plane is not periodic; build it over the tile only and check interior voxels.
        let tris = mesostructure::HeightField::from_fn(6, 6, field).triangles();
        let maps = compute_distance_maps(
            dims,
            &tris,
            MapKind::Plain,
            DistanceMapSettings { tolerance: 0.25, periodic_xy: false },
        )
        .unwrap();
        let patches = VoxelPatches::build(dims, &tris, &maps.surface, PatchSettings::default()).unwrap();
        let mut checked = 0;
        for z in 0..4 {
            // Voxels whose fits reach past the tile see the wrapped (non-matching) plane.
            for y in 2..4 {
                for x in 2..4 {
                    let list = patches.of_voxel(UVec3::new(x, y, z));
                    for patch in list {
                        // The patch's polygon corners lie on the plane.
                        for corner in &patch.corners[..3] {
                            let p = corner.truncate() + Vec3::new(x as f32, y as f32, z as f32);
                            assert!((p.z - field(p.x, p.y)).abs() < 1e-3, "{p}");
                        }
                        checked += 1;
                    }
                }
            }
        }
        assert!(checked >= 4);
    }
}
