//! Procedural test grains, each a closed, outward-wound mesh with per-vertex material:
//!
//! - [`Ball`]: a sphere (the ideal grain, `r/R → 1`).
//! - [`CoffeeBean`]: an ellipsoid with a domed side, a flatter side and a crease along it.
//! - [`SandGrain`]: a rock — an ellipsoid displaced along its radius by band-limited noise
//!   from a seed (same seed, same grain, on every platform).
//! - [`HexNut`]: a hexagonal prism with a cylindrical through hole, the paper's
//!   counter-example (§10): not quasi-spherical, its centre lies outside the material.
//!
//! The first three deform a subdivided icosahedron by maps that are one-to-one on the
//! sphere, so they stay closed and free of self-intersections.

mod bean;
mod nut;
mod rock;

pub use bean::CoffeeBean;
pub use nut::HexNut;
pub use rock::SandGrain;

use std::collections::HashMap;

use glam::{DVec3, Vec3};

use crate::error::MeshError;
use crate::material::VertexMaterial;
use crate::mesh::GrainMesh;

/// Most icosahedron subdivisions a procedural grain accepts (7: 327 680 triangles).
pub const MAX_SUBDIVISIONS: u32 = 7;

/// A sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ball {
    /// Radius, positive.
    pub radius: f32,
    /// Icosahedron subdivisions, at most [`MAX_SUBDIVISIONS`] (`20 · 4^s` triangles).
    pub subdivisions: u32,
    /// Material of every vertex.
    pub material: VertexMaterial,
}

impl Default for Ball {
    /// A unit ball of 5 120 triangles, white plastic.
    fn default() -> Self {
        Ball { radius: 1.0, subdivisions: 4, material: VertexMaterial { albedo: Vec3::splat(0.8), roughness: 0.3 } }
    }
}

impl Ball {
    /// The ball's mesh.
    pub fn mesh(&self) -> Result<GrainMesh, MeshError> {
        require_positive("radius", self.radius)?;
        let (unit, triangles) = icosphere(self.subdivisions)?;
        let positions = unit.iter().map(|u| (*u * f64::from(self.radius)).as_vec3()).collect();
        let materials = vec![self.material; unit.len()];
        GrainMesh::new(positions, triangles)?.with_materials(materials)
    }
}

/// A subdivided icosahedron projected on the unit sphere: unit vertices and outward-wound
/// triangles. Each subdivision splits every triangle into four at its edge midpoints.
pub fn icosphere(subdivisions: u32) -> Result<(Vec<DVec3>, Vec<[u32; 3]>), MeshError> {
    if subdivisions > MAX_SUBDIVISIONS {
        return Err(MeshError::InvalidParameter {
            name: "subdivisions",
            value: f64::from(subdivisions),
            requirement: "at most 7",
        });
    }
    let phi = (1.0 + 5.0_f64.sqrt()) / 2.0;
    let mut vertices: Vec<DVec3> = [
        (-1.0, phi, 0.0),
        (1.0, phi, 0.0),
        (-1.0, -phi, 0.0),
        (1.0, -phi, 0.0),
        (0.0, -1.0, phi),
        (0.0, 1.0, phi),
        (0.0, -1.0, -phi),
        (0.0, 1.0, -phi),
        (phi, 0.0, -1.0),
        (phi, 0.0, 1.0),
        (-phi, 0.0, -1.0),
        (-phi, 0.0, 1.0),
    ]
    .map(|(x, y, z)| DVec3::new(x, y, z).normalize())
    .to_vec();
    let mut triangles: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
        let mut midpoint = |i: u32, j: u32, vertices: &mut Vec<DVec3>| {
            *midpoints.entry((i.min(j), i.max(j))).or_insert_with(|| {
                vertices.push((vertices[i as usize] + vertices[j as usize]).normalize());
                (vertices.len() - 1) as u32
            })
        };
        let mut finer = Vec::with_capacity(triangles.len() * 4);
        for [a, b, c] in triangles {
            let ab = midpoint(a, b, &mut vertices);
            let bc = midpoint(b, c, &mut vertices);
            let ca = midpoint(c, a, &mut vertices);
            finer.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        triangles = finer;
    }
    Ok((vertices, triangles))
}

/// `Err(InvalidParameter)` unless `value` is finite and positive.
fn require_positive(name: &'static str, value: f32) -> Result<(), MeshError> {
    require(name, value, value.is_finite() && value > 0.0, "finite and positive")
}

/// `Err(InvalidParameter)` naming `requirement` unless `holds`.
fn require(name: &'static str, value: f32, holds: bool, requirement: &'static str) -> Result<(), MeshError> {
    if holds { Ok(()) } else { Err(MeshError::InvalidParameter { name, value: f64::from(value), requirement }) }
}

/// Linear interpolation of materials, `t` clamped to `[0, 1]`.
fn mix_materials(a: VertexMaterial, b: VertexMaterial, t: f64) -> VertexMaterial {
    let t = t.clamp(0.0, 1.0) as f32;
    VertexMaterial { albedo: a.albedo.lerp(b.albedo, t), roughness: a.roughness + (b.roughness - a.roughness) * t }
}
