//! Why a grain mesh could not be made: the one error type of mesh construction, shared
//! by the mesh ([`crate::mesh`]) and the measurement of its bounds ([`crate::bounds`]).

use std::fmt;

use glam::Vec3;

use crate::material::VertexMaterial;

/// Why a grain mesh could not be made.
#[derive(Clone, Debug, PartialEq)]
pub enum MeshError {
    /// The mesh has no triangle.
    NoTriangles,
    /// A vertex position is NaN or infinite.
    NonFiniteVertex {
        /// Index of the vertex.
        vertex: usize,
        /// Its position.
        position: Vec3,
    },
    /// A triangle refers to a vertex that does not exist.
    IndexOutOfRange {
        /// Index of the triangle.
        triangle: usize,
        /// The vertex index it holds.
        index: u32,
        /// How many vertices the mesh has.
        vertex_count: usize,
    },
    /// Every triangle corner is the same point: `r = R = 0` about any centre.
    ZeroExtent {
        /// The single point.
        point: Vec3,
    },
    /// The corners are not all equal but every triangle has zero area, so the mesh has no
    /// surface to centre or to shade.
    ZeroArea,
    /// The bounds overflow `f32` (coordinates near `f32::MAX`).
    NonFiniteBounds,
    /// The normals do not match the vertices one to one.
    NormalCountMismatch {
        /// How many normals were given.
        normals: usize,
        /// How many vertices the mesh has.
        vertices: usize,
    },
    /// A given normal is NaN, infinite or zero, so it has no direction.
    InvalidNormal {
        /// Index of the vertex.
        vertex: usize,
        /// The normal as given.
        normal: Vec3,
    },
    /// The materials do not match the vertices one to one.
    MaterialCountMismatch {
        /// How many materials were given.
        materials: usize,
        /// How many vertices the mesh has.
        vertices: usize,
    },
    /// A material has an albedo channel or a roughness outside `[0, 1]` (or NaN).
    InvalidMaterial {
        /// Index of the vertex.
        vertex: usize,
        /// The material as given.
        material: VertexMaterial,
    },
    /// A procedural grain's parameter is out of its range.
    InvalidParameter {
        /// The parameter's name.
        name: &'static str,
        /// Its value.
        value: f64,
        /// What it must satisfy.
        requirement: &'static str,
    },
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MeshError::NoTriangles => write!(f, "the mesh has no triangles"),
            MeshError::NonFiniteVertex { vertex, position } => {
                write!(f, "vertex {vertex} has a non-finite position {position}")
            }
            MeshError::IndexOutOfRange { triangle, index, vertex_count } => {
                write!(f, "triangle {triangle} refers to vertex {index}, but the mesh has {vertex_count} vertices")
            }
            MeshError::ZeroExtent { point } => write!(
                f,
                "degenerate mesh: every vertex is the point {point}, so the inner and outer radii are r = R = 0"
            ),
            MeshError::ZeroArea => write!(f, "degenerate mesh: every triangle has zero area"),
            MeshError::NonFiniteBounds => write!(f, "the mesh's radii overflow f32 (coordinates too large)"),
            MeshError::NormalCountMismatch { normals, vertices } => {
                write!(f, "{normals} normals for {vertices} vertices")
            }
            MeshError::InvalidNormal { vertex, normal } => {
                write!(f, "vertex {vertex} has a normal {normal} with no direction (zero, NaN or infinite)")
            }
            MeshError::MaterialCountMismatch { materials, vertices } => {
                write!(f, "{materials} materials for {vertices} vertices")
            }
            MeshError::InvalidMaterial { vertex, material } => write!(
                f,
                "vertex {vertex} has albedo {} and roughness {}, outside [0, 1]",
                material.albedo, material.roughness
            ),
            MeshError::InvalidParameter { name, value, requirement } => {
                write!(f, "parameter {name} = {value}: must be {requirement}")
            }
        }
    }
}

impl std::error::Error for MeshError {}
