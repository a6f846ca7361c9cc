//! Crease and corner voxels of the watertight surface (beyond the paper; issue: "crease
//! voxels — a feature vertex and a fan from it — either keeps C⁰").
//!
//! The polygons of [`quadric_fit::watertight`] join points on a voxel's edges, so where a
//! sharp edge of the mesh (a wall's top, a box's corner, a bead on the floor) crosses a
//! voxel, the polygon's patch cuts it off. Two steps of extended marching cubes
//! (Kobbelt, Botsch, Schwanecke & Seidel, SIGGRAPH 2001, §3.2–3.3) put it back:
//!
//! 1. **Feature vertex.** A voxel with one polygon gets the least-squares point of the
//!    planes of the mesh's triangles in it ([`quadric_fit::feature`], about the polygon's
//!    mean), where those planes fix two or three directions (a crease or a corner), meet in
//!    it within [`FEATURE_RMS`] (flat pieces, not a curved surface) and put it at least
//!    [`FEATURE_MARGIN`] inside the voxel. The polygon becomes the fan of bounded triangles
//!    around it.
//! 2. **Edge flips.** A fan meets a face of its voxel in the polygon's straight segment, so
//!    a crease running from voxel to voxel is still cut at each face. Where the voxels on
//!    both sides of a face have feature vertices `a` and `b` and share the segment `P Q`
//!    on the face, the two fan triangles `a P Q` and `b Q P` become `a P b` and `a b Q`:
//!    the same border, with the crease `a b` through the face. Each of the two stands in
//!    both voxels (it lies in their union, a box); a voxel's tracer keeps only hits inside
//!    its own segment of the ray.
//!
//! Both steps keep every voxel's border (the polygon's segments on its faces, or the two
//! flipped triangles' outer edges), so the surface stays closed. Each is kept only where
//! it does not follow the mesh worse: a fan where its
//! [`representation_error`] against the voxel's own triangles is below the polygon's
//! patches', a flip where neither voxel's error grows (a flip that helps only near one face
//! leaves a voxel's largest error, set elsewhere, as it was, and is kept).

use alloc::collections::BTreeMap;
use alloc::vec::Vec;

use glam::{DVec3, IVec3, UVec3, Vec3};
use quadric_fit::surface::{C0Surface, GridEdge, GridPoint, SurfaceLoop, VoxelSurface};
use quadric_fit::{TangentPlane, feature_vertex};

use super::{mean, trace_patch};
use crate::exact_patches::representation_error;
use crate::patch::{BOUNDED_PATCH, TracePatch};

/// A feature vertex is kept only this far (voxels) inside its voxel. Nearer a face, the
/// fan's triangles lie almost in the face, where a crossing belongs to either voxel only
/// up to rounding; and a crease on a face or an edge of the voxel (a maze's walls stand on
/// grid planes) is followed by the polygon's own segment there already.
pub const FEATURE_MARGIN: f64 = 1e-2;

/// A feature vertex is kept only where the planes meet in it within this root mean square
/// distance (voxels): a crease or corner of flat pieces, not a curved surface.
pub const FEATURE_RMS: f64 = 1e-2;

/// A voxel whose polygon is fanned around its feature vertex.
struct FeatureVoxel {
    /// The feature vertex (tile coordinates).
    vertex: DVec3,
    /// The polygon's points (tile coordinates) and the edges they lie on, in order.
    points: Vec<DVec3>,
    edges: Vec<GridEdge>,
    /// The mesh's own triangles in the voxel (voxel-local), the yardstick.
    exact: Vec<TracePatch>,
    /// Flipped segments: segment `i` (points `i`, `i + 1`) and the neighbour's feature
    /// vertex across its face, moved into this voxel's tile frame.
    flips: BTreeMap<usize, DVec3>,
    /// [`representation_error`] of [`FeatureVoxel::triangles`] with its flips.
    error: f32,
}

impl FeatureVoxel {
    /// The voxel's triangles (tile coordinates): the fan around the vertex, each flipped
    /// segment's fan triangle replaced by the two flipped triangles.
    fn triangles(&self, flips: &BTreeMap<usize, DVec3>) -> Vec<[DVec3; 3]> {
        let n = self.points.len();
        let mut out = Vec::with_capacity(n + flips.len());
        for i in 0..n {
            let (p, q) = (self.points[i], self.points[(i + 1) % n]);
            match flips.get(&i) {
                Some(&other) => out.extend([[self.vertex, p, other], [self.vertex, other, q]]),
                None => out.push([self.vertex, p, q]),
            }
        }
        out
    }

    /// [`representation_error`] of the voxel's triangles with `flips` (its lowest corner
    /// `origin`).
    fn error(&self, origin: DVec3, flips: &BTreeMap<usize, DVec3>, directions: &[Vec3]) -> f32 {
        let patches = bounded_triangles(&self.triangles(flips), origin);
        representation_error(&patches, &self.exact, directions)
    }
}

/// The bounded plane patches of `triangles` (tile coordinates) relative to `origin`;
/// degenerate triangles are left out.
pub(super) fn bounded_triangles(triangles: &[[DVec3; 3]], origin: DVec3) -> Vec<TracePatch> {
    let mut out = Vec::with_capacity(triangles.len());
    for &corners in triangles {
        bounded_triangle(corners, origin, &mut out);
    }
    out
}

/// The bounded plane patch of `corners` (tile coordinates) relative to `origin`; nothing for
/// a degenerate triangle.
fn bounded_triangle(corners: [DVec3; 3], origin: DVec3, out: &mut Vec<TracePatch>) {
    let Ok(quadric) = quadric_fit::triangle_quadric(corners[0], corners[1], corners[2]) else { return };
    if let Some(mut patch) = trace_patch(&quadric, &corners, origin) {
        patch.ij_corners.w = BOUNDED_PATCH;
        out.push(patch);
    }
}

/// The voxel's lowest corner, tile coordinates.
pub(super) fn corner_of(voxel: GridPoint) -> DVec3 {
    DVec3::new(f64::from(voxel.0), f64::from(voxel.1), f64::from(voxel.2))
}

/// The patches of a watertight voxel without a feature vertex: the polygon's own triangle or
/// bilinear patch where the voxel has one polygon of at most 4 points, else each polygon's
/// fan around the mean of its points; voxel-local (`origin` the voxel's lowest corner).
pub(super) fn polygon_patches(voxel: &VoxelSurface, origin: DVec3, out: &mut Vec<TracePatch>) {
    let single = voxel.loops.len() == 1 && voxel.loops[0].points.len() <= 4;
    for surface_loop in &voxel.loops {
        if single {
            for patch in &surface_loop.patches {
                out.extend(trace_patch(&patch.quadric, &patch.polygon, origin));
            }
        } else {
            out.extend(bounded_triangles(&mean_fan(&surface_loop.points), origin));
        }
    }
}

/// The triangles (tile coordinates) of a watertight voxel without a feature vertex when
/// every patch must be bounded: each polygon's fan around the mean of its points.
pub(super) fn polygon_triangles(voxel: &VoxelSurface) -> Vec<[DVec3; 3]> {
    let mut out = Vec::new();
    for surface_loop in &voxel.loops {
        out.extend(mean_fan(&surface_loop.points));
    }
    out
}

/// The polygon `points` (tile coordinates) as the fan of triangles `C, Pi, Pi+1` around the
/// mean `C` of its points (inside the voxel, which is convex and holds the points on its
/// border). The fan folds over where the polygon is not convex seen from `C`.
fn mean_fan(points: &[DVec3]) -> Vec<[DVec3; 3]> {
    let centre = mean(points);
    (0..points.len()).map(|i| [centre, points[i], points[(i + 1) % points.len()]]).collect()
}

/// What a crease voxel's fan is measured against.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Fallback {
    /// [`polygon_patches`]: the polygon's own triangle or bilinear patch, or mean fans.
    PolygonPatches,
    /// [`polygon_triangles`]: mean fans only (every patch bounded).
    MeanFans,
}

/// The crease voxels of a watertight `surface` (tile of `dims` voxels, repeating in x and
/// y when `periodic`) and their triangles (tile coordinates; a flipped pair stands in the
/// lists of both voxels), keyed by voxel (see the module docs); a fan is kept where it
/// follows the mesh better than `fallback`. `planes_and_exact(voxel)` gives the planes of the mesh's triangles crossing the
/// voxel and their bounded patches, both voxel-local; `directions` are
/// [`crate::exact_patches::probe_directions`].
pub(super) fn crease_triangles(
    surface: &C0Surface,
    (dims, periodic): (UVec3, bool),
    mut planes_and_exact: impl FnMut(GridPoint) -> (Vec<TangentPlane>, Vec<TracePatch>),
    directions: &[Vec3],
    fallback: Fallback,
) -> BTreeMap<GridPoint, Vec<[DVec3; 3]>> {
    let mut features: BTreeMap<GridPoint, FeatureVoxel> = BTreeMap::new();
    let mut current = Vec::new();
    for (&voxel, voxel_surface) in &surface.voxels {
        let [SurfaceLoop { points, edges, .. }] = voxel_surface.loops.as_slice() else { continue };
        let origin = corner_of(voxel);
        let (planes, exact) = planes_and_exact(voxel);
        let local = planes.iter().map(|p| TangentPlane { normal: p.normal, point: p.point + origin });
        let planes: Vec<TangentPlane> = local.collect();
        let Some(vertex) = feature_vertex(&planes, mean(points)) else { continue };
        if vertex.rank < 2 || vertex.rms_distance > FEATURE_RMS {
            continue;
        }
        let local = vertex.point - origin;
        if local.cmplt(DVec3::splat(FEATURE_MARGIN)).any() || local.cmpgt(DVec3::splat(1.0 - FEATURE_MARGIN)).any() {
            continue;
        }
        let mut feature = FeatureVoxel {
            vertex: vertex.point,
            points: points.clone(),
            edges: edges.clone(),
            exact,
            flips: BTreeMap::new(),
            error: 0.0,
        };
        let fan_error = feature.error(origin, &BTreeMap::new(), directions);
        current.clear();
        match fallback {
            Fallback::PolygonPatches => polygon_patches(voxel_surface, origin, &mut current),
            Fallback::MeanFans => current.extend(bounded_triangles(&polygon_triangles(voxel_surface), origin)),
        }
        if fan_error < representation_error(&current, &feature.exact, directions) {
            feature.error = fan_error;
            features.insert(voxel, feature);
        }
    }
    // Step 2: each face between two feature voxels, once (from the lower voxel's side).
    let keys: Vec<GridPoint> = features.keys().copied().collect();
    for a in keys {
        for i in 0..features[&a].points.len() {
            let Some((b, shift, j)) = neighbour_segment(&features, a, i, dims, periodic) else { continue };
            if b <= a || features[&a].flips.contains_key(&i) || features[&b].flips.contains_key(&j) {
                continue;
            }
            let (va, vb) = (features[&a].vertex, features[&b].vertex + shift);
            let mut flips_a = features[&a].flips.clone();
            flips_a.insert(i, vb);
            let mut flips_b = features[&b].flips.clone();
            flips_b.insert(j, va - shift);
            let error_a = features[&a].error(corner_of(a), &flips_a, directions);
            let error_b = features[&b].error(corner_of(b), &flips_b, directions);
            if error_a <= features[&a].error && error_b <= features[&b].error {
                let fa = features.get_mut(&a).expect("a key of the map");
                (fa.flips, fa.error) = (flips_a, error_a);
                let fb = features.get_mut(&b).expect("a key of the map");
                (fb.flips, fb.error) = (flips_b, error_b);
            }
        }
    }
    features.iter().map(|(&voxel, f)| (voxel, f.triangles(&f.flips))).collect()
}

/// The feature voxel across the face that holds segment `i` of voxel `a`'s polygon, the
/// shift from its tile coordinates into `a`'s frame, and the index of the same segment in
/// its polygon; `None` when the neighbour lies outside the grid, is no feature voxel, or
/// does not hold the segment.
fn neighbour_segment(
    features: &BTreeMap<GridPoint, FeatureVoxel>,
    a: GridPoint,
    i: usize,
    dims: UVec3,
    periodic: bool,
) -> Option<(GridPoint, DVec3, usize)> {
    let edges = &features[&a].edges;
    let (e, f) = (edges[i], edges[(i + 1) % edges.len()]);
    // Grid coordinates fit `i32`: the grid has at most 2²⁴ voxels.
    let at = |g: GridEdge| IVec3::new(g.corner.0 as i32, g.corner.1 as i32, g.corner.2 as i32);
    // The face both edges lie on: its normal is along neither edge, and both edges lie at
    // the same level along it.
    let normal = (0..3).find(|&n| n != usize::from(e.axis) && n != usize::from(f.axis) && at(e)[n] == at(f)[n])?;
    let voxel = IVec3::new(a.0 as i32, a.1 as i32, a.2 as i32);
    let mut across = voxel;
    across[normal] += if at(e)[normal] == voxel[normal] { -1 } else { 1 };
    // Into the tile (or out of the grid).
    let size = dims.as_ivec3();
    let mut wrapped = across;
    for axis in 0..3 {
        if across[axis] < 0 || across[axis] >= size[axis] {
            if axis == 2 || !periodic {
                return None;
            }
            wrapped[axis] = across[axis].rem_euclid(size[axis]);
        }
    }
    let shift = across - wrapped;
    let b = (wrapped.x as u32, wrapped.y as u32, wrapped.z as u32);
    let other = features.get(&b)?;
    let n = other.edges.len();
    let moved = |g: GridEdge| (g.axis, at(g) + shift);
    let j = (0..n).find(|&j| {
        let (g, h) = (moved(other.edges[j]), moved(other.edges[(j + 1) % n]));
        (g, h) == ((e.axis, at(e)), (f.axis, at(f))) || (h, g) == ((e.axis, at(e)), (f.axis, at(f)))
    })?;
    Some((b, shift.as_dvec3(), j))
}
