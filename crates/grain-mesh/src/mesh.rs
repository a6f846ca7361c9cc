//! A validated triangle mesh of one grain: positions, unit per-vertex normals, triangles,
//! optional per-vertex material, and its [`GrainBounds`].

use glam::{DVec3, Vec3};

use crate::bounds::GrainBounds;
use crate::error::MeshError;
use crate::material::VertexMaterial;
use crate::topology::EdgeReport;

/// A validated triangle mesh of one grain.
///
/// Invariants, checked by every constructor: at least one triangle, every index in range,
/// every position finite, every normal of unit length, materials (when present) in
/// `[0, 1]`, and finite [`GrainBounds`] with `R > 0` and a positive surface area.
/// Triangles wind counter-clockwise seen from outside (the outward normal is
/// `(b − a) × (c − a)`).
#[derive(Clone, Debug, PartialEq)]
pub struct GrainMesh {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
    materials: Option<Vec<VertexMaterial>>,
    bounds: GrainBounds,
}

impl GrainMesh {
    /// A mesh whose normals are the area-weighted averages of the adjacent triangles'
    /// normals (see [`area_weighted_normals`]).
    pub fn new(positions: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> Result<Self, MeshError> {
        let bounds = validate_geometry(&positions, &triangles)?;
        let normals = area_weighted_normals(&positions, &triangles, bounds.centre);
        Ok(GrainMesh { positions, normals, triangles, materials: None, bounds })
    }

    /// A mesh with the given per-vertex normals (e.g. from an OBJ file), normalised. Each
    /// must be finite and non-zero.
    pub fn with_normals(positions: Vec<Vec3>, normals: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> Result<Self, MeshError> {
        let bounds = validate_geometry(&positions, &triangles)?;
        if normals.len() != positions.len() {
            return Err(MeshError::NormalCountMismatch { normals: normals.len(), vertices: positions.len() });
        }
        let mut unit_normals = Vec::with_capacity(normals.len());
        for (vertex, &normal) in normals.iter().enumerate() {
            let unit = normal.as_dvec3().try_normalize().ok_or(MeshError::InvalidNormal { vertex, normal })?;
            unit_normals.push(unit.as_vec3());
        }
        Ok(GrainMesh { positions, normals: unit_normals, triangles, materials: None, bounds })
    }

    /// The same mesh with one material per vertex.
    pub fn with_materials(self, materials: Vec<VertexMaterial>) -> Result<Self, MeshError> {
        if materials.len() != self.positions.len() {
            return Err(MeshError::MaterialCountMismatch {
                materials: materials.len(),
                vertices: self.positions.len(),
            });
        }
        let in_unit_range = |x: f32| (0.0..=1.0).contains(&x);
        for (vertex, material) in materials.iter().enumerate() {
            if !(material.albedo.to_array().into_iter().all(in_unit_range) && in_unit_range(material.roughness)) {
                return Err(MeshError::InvalidMaterial { vertex, material: *material });
            }
        }
        Ok(GrainMesh { materials: Some(materials), ..self })
    }

    /// Vertex positions.
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// Unit per-vertex normals, one per position.
    pub fn normals(&self) -> &[Vec3] {
        &self.normals
    }

    /// Triangles as vertex indices, counter-clockwise seen from outside.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Per-vertex materials, when the mesh has them (procedural grains do).
    pub fn materials(&self) -> Option<&[VertexMaterial]> {
        self.materials.as_deref()
    }

    /// Centre, inner radius `r` and outer radius `R`, measured at construction.
    pub fn bounds(&self) -> &GrainBounds {
        &self.bounds
    }

    /// The three corner positions of triangle `index`, or `None` past the end.
    pub fn triangle_corners(&self, index: usize) -> Option<[Vec3; 3]> {
        let [a, b, c] = *self.triangles.get(index)?;
        Some([self.positions[a as usize], self.positions[b as usize], self.positions[c as usize]])
    }

    /// How the triangles' edges pair up (closedness and orientation), with vertices at the
    /// same position counted as one.
    pub fn edge_report(&self) -> EdgeReport {
        EdgeReport::of(&self.positions, &self.triangles)
    }
}

/// Checks what [`GrainMesh`] requires of positions and triangles, and measures the bounds.
fn validate_geometry(positions: &[Vec3], triangles: &[[u32; 3]]) -> Result<GrainBounds, MeshError> {
    if triangles.is_empty() {
        return Err(MeshError::NoTriangles);
    }
    if let Some((vertex, &position)) = positions.iter().enumerate().find(|(_, p)| !p.is_finite()) {
        return Err(MeshError::NonFiniteVertex { vertex, position });
    }
    for (triangle, corners) in triangles.iter().enumerate() {
        if let Some(&index) = corners.iter().find(|&&i| i as usize >= positions.len()) {
            return Err(MeshError::IndexOutOfRange { triangle, index, vertex_count: positions.len() });
        }
    }
    GrainBounds::measure(positions, triangles)
}

/// Per-vertex normals: the sum over adjacent triangles of `(b − a) × (c − a)` (twice the
/// area times the unit normal), normalised, so larger triangles weigh more. A vertex whose
/// sum vanishes (used by no triangle, or only by degenerate ones) gets the direction from
/// `centre` to it, or `+z` when it sits at the centre.
///
/// Vertices are not welded: a vertex duplicated along a crease (as in [`crate::HexNut`])
/// gets the normal of its own side only, which keeps sharp edges sharp.
pub fn area_weighted_normals(positions: &[Vec3], triangles: &[[u32; 3]], centre: Vec3) -> Vec<Vec3> {
    let mut sums = vec![DVec3::ZERO; positions.len()];
    for corners in triangles {
        let [a, b, c] = corners.map(|i| positions.get(i as usize).copied().unwrap_or(Vec3::ZERO).as_dvec3());
        let weighted = (b - a).cross(c - a);
        for &i in corners {
            if let Some(sum) = sums.get_mut(i as usize) {
                *sum += weighted;
            }
        }
    }
    sums.iter()
        .zip(positions)
        .map(|(sum, &position)| {
            let fallback = (position - centre).as_dvec3().try_normalize().unwrap_or(DVec3::Z);
            sum.try_normalize().unwrap_or(fallback).as_vec3()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tetrahedron wound outward.
    fn tetrahedron() -> (Vec<Vec3>, Vec<[u32; 3]>) {
        (vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z], vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    }

    #[test]
    fn index_out_of_range_is_an_error() {
        let (positions, mut triangles) = tetrahedron();
        triangles[2] = [0, 3, 9];
        let error = GrainMesh::new(positions, triangles).unwrap_err();
        assert_eq!(error, MeshError::IndexOutOfRange { triangle: 2, index: 9, vertex_count: 4 });
        assert_eq!(error.to_string(), "triangle 2 refers to vertex 9, but the mesh has 4 vertices");
    }

    #[test]
    fn given_normals_are_checked_and_normalised() {
        let (positions, triangles) = tetrahedron();
        let error = GrainMesh::with_normals(positions.clone(), vec![Vec3::Z; 3], triangles.clone()).unwrap_err();
        assert_eq!(error, MeshError::NormalCountMismatch { normals: 3, vertices: 4 });
        let mut normals = vec![Vec3::new(0.0, 0.0, 2.0); 4];
        let mesh = GrainMesh::with_normals(positions.clone(), normals.clone(), triangles.clone()).unwrap();
        assert_eq!(mesh.normals()[0], Vec3::Z);
        normals[1] = Vec3::new(f32::NAN, 0.0, 1.0);
        let error = GrainMesh::with_normals(positions, normals, triangles).unwrap_err();
        assert!(matches!(error, MeshError::InvalidNormal { vertex: 1, .. }), "{error}");
    }

    #[test]
    fn materials_are_checked() {
        let (positions, triangles) = tetrahedron();
        let mesh = GrainMesh::new(positions, triangles).unwrap();
        let good = VertexMaterial { albedo: Vec3::splat(0.5), roughness: 0.5 };
        let error = mesh.clone().with_materials(vec![good; 3]).unwrap_err();
        assert_eq!(error, MeshError::MaterialCountMismatch { materials: 3, vertices: 4 });
        let mut materials = vec![good; 4];
        materials[3].roughness = 1.5;
        let error = mesh.clone().with_materials(materials).unwrap_err();
        assert!(matches!(error, MeshError::InvalidMaterial { vertex: 3, .. }), "{error}");
        assert_eq!(mesh.with_materials(vec![good; 4]).unwrap().materials(), Some(&[good; 4][..]));
    }

    #[test]
    fn unused_vertex_gets_the_direction_from_the_centre() {
        let (mut positions, triangles) = tetrahedron();
        positions.push(Vec3::new(5.0, 0.0, 0.0));
        let mesh = GrainMesh::new(positions, triangles).unwrap();
        let expected = (Vec3::new(5.0, 0.0, 0.0) - mesh.bounds().centre).normalize();
        assert!(mesh.normals()[4].abs_diff_eq(expected, 1e-6));
        // Its distance does not count towards R: only the surface does.
        assert!(mesh.bounds().outer_radius < 1.0);
    }
}
