//! The signed distance of a closed triangle mesh ([`MeshSurface`]): the distance to the
//! nearest triangle through a BVH, signed by angle-weighted pseudo-normals.

use std::collections::HashMap;
use std::path::Path;

use glam::{DVec3, Vec3};
use grain_mesh::GrainMesh;
use grain_mesh::topology::weld_by_position;
use svo_brick::{ATTRIBUTE_CHANNELS, Cell, SurfaceSample, SurfaceSource};

use crate::attribute::Attribute;
use crate::bvh::{Bvh, Feature, closest_feature};
use crate::error::SceneError;

/// Most subdivisions `k` of a triangle's edges in
/// [`surface_samples`](SurfaceSource::surface_samples) (`k²` samples per triangle).
pub const MAX_TRIANGLE_SUBDIVISION: u32 = 1024;

/// One triangle with what the queries need.
#[derive(Clone, Debug)]
struct Triangle {
    corners: [DVec3; 3],
    /// The unit face normal (zero for a zero-area triangle).
    normal: DVec3,
    /// The pseudo-normal of edge `k` (corner `k` to `k + 1`): the sum of the adjacent
    /// faces' unit normals.
    edge_normals: [DVec3; 3],
    /// The pseudo-normal of corner `k`: the sum of the adjacent faces' unit normals
    /// weighted by their angles there.
    vertex_normals: [DVec3; 3],
    area: f64,
    longest_edge: f64,
    centroid: Vec3,
}

/// A point of the mesh nearest to a query.
#[derive(Clone, Copy, Debug)]
struct Closest {
    point: DVec3,
    /// The distance, negative inside.
    signed: f64,
    /// The pseudo-normal of the feature the point lies on (not normalised).
    pseudo_normal: DVec3,
}

/// The surface of a closed, consistently oriented triangle mesh.
///
/// **Distance.** The distance to the nearest triangle, found through a BVH (binary, median
/// splits; a query visits `O(log n)` leaves for points near the surface), negative where
/// `(p − x) · N < 0`, with `x` the nearest point and `N` the angle-weighted pseudo-normal
/// of the feature (face, edge or vertex) it lies on — Bærentzen & Aanæs, *Signed Distance
/// Computation Using the Angle Weighted Pseudonormal* (IEEE TVCG 2005), which proves the
/// sign right for every point of a closed, oriented, manifold mesh. Vertices at equal
/// positions are welded (as `grain_mesh`'s [`EdgeReport`](grain_mesh::EdgeReport) does),
/// so meshes split along creases get the pseudo-normals of the whole surface. Computed in
/// `f64`.
///
/// **Gradient.** `sign · (p − x)/|p − x|` (exact for a distance field; a one-sided
/// derivative on the medial axis), and the unit pseudo-normal on the surface.
///
/// **Samples.** A triangle belongs to the cell holding its centroid: for each such triangle
/// [`surface_samples`](SurfaceSource::surface_samples) splits it into `k²` congruent
/// sub-triangles with `k = ⌈longest edge / spacing⌉` (at most
/// [`MAX_TRIANGLE_SUBDIVISION`]), one sample at each sub-triangle's centroid with the face
/// normal and the sub-triangle's area. Samples of a triangle that straddles the cell's
/// boundary may lie outside it; over a partition of space every triangle is sampled once.
#[derive(Clone, Debug)]
pub struct MeshSurface {
    triangles: Vec<Triangle>,
    bvh: Bvh,
    area: f64,
    bounds: (Vec3, Vec3),
    attribute: Attribute,
}

impl MeshSurface {
    /// The surface of `mesh`, which must be closed and consistently oriented
    /// ([`GrainMesh::edge_report`]); `attribute` is a function of the surface point or a
    /// constant.
    pub fn new(mesh: &GrainMesh, attribute: Attribute) -> Result<Self, SceneError> {
        MeshSurface::build(mesh, None, attribute)
    }

    /// The surface of the closed mesh in the OBJ file at `path` (see
    /// [`grain_mesh::load_obj`]). Errors name the file.
    pub fn from_obj(path: impl AsRef<Path>, attribute: Attribute) -> Result<Self, SceneError> {
        let path = path.as_ref();
        let mesh = grain_mesh::load_obj(path)?;
        MeshSurface::build(&mesh, Some(path), attribute)
    }

    fn build(mesh: &GrainMesh, path: Option<&Path>, attribute: Attribute) -> Result<Self, SceneError> {
        let report = mesh.edge_report();
        if !report.is_closed_and_oriented() {
            return Err(SceneError::OpenMesh { path: path.map(Path::to_path_buf), report });
        }
        let welded = weld_by_position(mesh.positions());
        let corners: Vec<[DVec3; 3]> =
            mesh.triangles().iter().map(|t| t.map(|i| mesh.positions()[i as usize].as_dvec3())).collect();
        let normals: Vec<DVec3> =
            corners.iter().map(|[a, b, c]| (*b - *a).cross(*c - *a).normalize_or_zero()).collect();
        let mut vertex_sums = vec![DVec3::ZERO; mesh.positions().len()];
        let mut edge_sums: HashMap<(u32, u32), DVec3> = HashMap::new();
        let ids: Vec<[u32; 3]> = mesh.triangles().iter().map(|t| t.map(|i| welded[i as usize])).collect();
        for ((ids, corners), &normal) in ids.iter().zip(&corners).zip(&normals) {
            for k in 0..3 {
                let (u, v) = (corners[(k + 1) % 3] - corners[k], corners[(k + 2) % 3] - corners[k]);
                vertex_sums[ids[k] as usize] += normal * u.cross(v).length().atan2(u.dot(v));
                let (from, to) = (ids[k], ids[(k + 1) % 3]);
                *edge_sums.entry((from.min(to), from.max(to))).or_default() += normal;
            }
        }
        let triangles: Vec<Triangle> = corners
            .iter()
            .zip(&ids)
            .zip(&normals)
            .map(|((&corners, ids), &normal)| {
                let [a, b, c] = corners;
                let edge = |k: usize| {
                    let (from, to) = (ids[k], ids[(k + 1) % 3]);
                    edge_sums.get(&(from.min(to), from.max(to))).copied().unwrap_or(normal)
                };
                Triangle {
                    corners,
                    normal,
                    edge_normals: [edge(0), edge(1), edge(2)],
                    vertex_normals: ids.map(|i| vertex_sums[i as usize]),
                    area: 0.5 * (b - a).cross(c - a).length(),
                    longest_edge: a.distance(b).max(b.distance(c)).max(c.distance(a)),
                    centroid: ((a + b + c) / 3.0).as_vec3(),
                }
            })
            .collect();
        let bvh = Bvh::new(&corners);
        let area = triangles.iter().map(|t| t.area).sum();
        let (lo, hi) = corners
            .iter()
            .flatten()
            .fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &p| (lo.min(p), hi.max(p)));
        let bounds = (lo.as_vec3(), hi.as_vec3());
        Ok(MeshSurface { triangles, bvh, area, bounds, attribute })
    }

    /// The number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// The total surface area.
    pub fn surface_area(&self) -> f64 {
        self.area
    }

    /// The mesh's axis-aligned bounds `(min, max)`.
    pub fn bounds(&self) -> (Vec3, Vec3) {
        self.bounds
    }

    /// The point of the mesh nearest to `p`.
    pub fn closest_point(&self, p: Vec3) -> Vec3 {
        self.closest(p).point.as_vec3()
    }

    fn closest(&self, p: Vec3) -> Closest {
        let p = p.as_dvec3();
        let nearest =
            self.bvh.nearest(p, |t| p.distance_squared(closest_feature(p, self.triangles[t as usize].corners).0));
        let Some((t, squared)) = nearest else {
            return Closest { point: p, signed: f64::INFINITY, pseudo_normal: DVec3::ZERO };
        };
        let triangle = &self.triangles[t as usize];
        let (point, feature) = closest_feature(p, triangle.corners);
        let pseudo_normal = match feature {
            Feature::Vertex(k) => triangle.vertex_normals[k],
            Feature::Edge(k) => triangle.edge_normals[k],
            Feature::Face => triangle.normal,
        };
        let distance = squared.sqrt();
        let signed = if (p - point).dot(pseudo_normal) < 0.0 { -distance } else { distance };
        Closest { point, signed, pseudo_normal }
    }
}

impl SurfaceSource for MeshSurface {
    fn distance(&self, p: Vec3) -> f32 {
        self.closest(p).signed as f32
    }

    fn gradient(&self, p: Vec3) -> Vec3 {
        let closest = self.closest(p);
        match (p.as_dvec3() - closest.point).try_normalize() {
            Some(direction) => (direction * closest.signed.signum()).as_vec3(),
            None => closest.pseudo_normal.normalize_or_zero().as_vec3(),
        }
    }

    fn attribute(&self, x: Vec3) -> [f32; ATTRIBUTE_CHANNELS] {
        self.attribute.eval(x)
    }

    /// Stratified samples of the triangles whose centroids lie in `cell` (see
    /// [`MeshSurface`]); nothing for a `spacing` that is not finite and positive.
    fn surface_samples(&self, cell: Cell, spacing: f32, out: &mut Vec<SurfaceSample>) {
        if !(spacing > 0.0 && spacing.is_finite()) {
            return;
        }
        self.bvh.overlapping(cell.min.as_dvec3(), cell.max.as_dvec3(), |t| {
            let triangle = &self.triangles[t as usize];
            if !cell.contains(triangle.centroid) || triangle.area <= 0.0 {
                return;
            }
            let k = (triangle.longest_edge / f64::from(spacing)).ceil().clamp(1.0, f64::from(MAX_TRIANGLE_SUBDIVISION));
            let k = k as u32;
            let [a, b, c] = triangle.corners;
            let (ab, ac) = ((b - a) / f64::from(k), (c - a) / f64::from(k));
            let area = (triangle.area / f64::from(k * k)) as f32;
            let normal = triangle.normal.as_vec3();
            let mut push = |u: f64, v: f64| {
                let position = (a + ab * u + ac * v).as_vec3();
                out.push(SurfaceSample { position, normal, area, attribute: self.attribute.eval(position) });
            };
            for i in 0..k {
                for j in 0..k - i {
                    let (u, v) = (f64::from(i), f64::from(j));
                    // The sub-triangle (i, j), (i + 1, j), (i, j + 1) …
                    push(u + 1.0 / 3.0, v + 1.0 / 3.0);
                    // … and, inside, the inverted one (i + 1, j), (i, j + 1), (i + 1, j + 1).
                    if i + j + 1 < k {
                        push(u + 2.0 / 3.0, v + 2.0 / 3.0);
                    }
                }
            }
        });
    }
}

#[cfg(test)]
mod tests;
