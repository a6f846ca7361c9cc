//! A coffee bean: a domed side, a flatter side, and a crease along the flat side.

use glam::{DVec3, Vec3};

use super::{icosphere, mix_materials, require, require_positive};
use crate::error::MeshError;
use crate::material::VertexMaterial;
use crate::mesh::GrainMesh;

/// A coffee bean, its long axis along `x`, its domed side towards `+z` and its flat side,
/// with the crease along `x`, towards `−z`.
///
/// A unit-sphere point `u` maps to `(a·uₓ, b·u_y, z)` with `z = dome_height·u_z` on the
/// domed side and `z = u_z·(flat_depth − crease_depth·g)` on the flat side, where
/// `g = exp(−(u_y / crease_width)²)` is the crease profile. The map is one-to-one (so the
/// bean has no self-intersection) as long as `crease_depth < dome_height + flat_depth`:
/// the crease floor then stays below the dome above it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoffeeBean {
    /// Half-length along `x`.
    pub half_length: f32,
    /// Half-width along `y`.
    pub half_width: f32,
    /// Height of the domed side above the `z = 0` plane.
    pub dome_height: f32,
    /// Depth of the flat side below the `z = 0` plane, away from the crease.
    pub flat_depth: f32,
    /// How far the crease cuts into the flat side at its deepest (at `u_y = 0`).
    pub crease_depth: f32,
    /// Gaussian half-width of the crease, as a fraction of the half-width.
    pub crease_width: f32,
    /// Icosahedron subdivisions, at most [`super::MAX_SUBDIVISIONS`].
    pub subdivisions: u32,
    /// Material of the bean's skin.
    pub skin: VertexMaterial,
    /// Material in the crease (the paler silver skin).
    pub crease: VertexMaterial,
}

impl Default for CoffeeBean {
    /// A roasted arabica-like bean 2 × 1.5 × 0.9 units (about 11 × 8 × 5 mm scaled to a
    /// half-length of 1), 20 480 triangles, brown with a pale crease.
    fn default() -> Self {
        CoffeeBean {
            half_length: 1.0,
            half_width: 0.75,
            dome_height: 0.6,
            flat_depth: 0.3,
            crease_depth: 0.2,
            crease_width: 0.1,
            subdivisions: 5,
            skin: VertexMaterial { albedo: Vec3::new(0.30, 0.17, 0.09), roughness: 0.45 },
            crease: VertexMaterial { albedo: Vec3::new(0.55, 0.42, 0.28), roughness: 0.7 },
        }
    }
}

impl CoffeeBean {
    /// The bean's mesh.
    pub fn mesh(&self) -> Result<GrainMesh, MeshError> {
        require_positive("half_length", self.half_length)?;
        require_positive("half_width", self.half_width)?;
        require_positive("dome_height", self.dome_height)?;
        require_positive("flat_depth", self.flat_depth)?;
        require_positive("crease_width", self.crease_width)?;
        require(
            "crease_depth",
            self.crease_depth,
            self.crease_depth >= 0.0 && self.crease_depth < self.dome_height + self.flat_depth,
            "at least 0 and less than dome_height + flat_depth",
        )?;
        let (unit, triangles) = icosphere(self.subdivisions)?;
        let mut positions = Vec::with_capacity(unit.len());
        let mut materials = Vec::with_capacity(unit.len());
        for u in &unit {
            let crease_profile = (-(u.y / f64::from(self.crease_width)).powi(2)).exp();
            let z = if u.z >= 0.0 {
                f64::from(self.dome_height) * u.z
            } else {
                u.z * (f64::from(self.flat_depth) - f64::from(self.crease_depth) * crease_profile)
            };
            positions
                .push(DVec3::new(f64::from(self.half_length) * u.x, f64::from(self.half_width) * u.y, z).as_vec3());
            let in_crease = if u.z < 0.0 { crease_profile * (-u.z).min(0.5) * 2.0 } else { 0.0 };
            materials.push(mix_materials(self.skin, self.crease, in_crease));
        }
        GrainMesh::new(positions, triangles)?.with_materials(materials)
    }
}
