//! A hex nut: a hexagonal prism with a cylindrical through hole.

use std::f64::consts::PI;

use glam::{DVec3, Vec3};

use super::{require, require_positive};
use crate::error::MeshError;
use crate::material::VertexMaterial;
use crate::mesh::GrainMesh;

/// A hex nut centred at the origin, its axis along `z`, two of its six corners on the
/// `x` axis — the paper's example of a grain that breaks the quasi-spherical hypothesis
/// (§10, "a tubular element, e.g. a threaded nut"). The thread is not modelled.
///
/// The hole is a regular polygon of [`HexNut::hole_segments`] sides inscribed in the
/// circle of radius [`HexNut::hole_radius`], so the nearest surface point to the axis is
/// at the polygon's apothem `hole_radius · cos(π / hole_segments)`: that is the nut's
/// inner radius `r` about its centre, while its centre lies in the hole, outside the
/// material (its occluder radius is 0, see [`crate::bounds`]).
///
/// Faces meeting at a sharp edge (the six flats, the two end faces, the hole) have their
/// own vertices, so the area-weighted normals stay flat on each; the hole's wall is
/// smooth. The surface is closed once vertices at equal positions are welded.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HexNut {
    /// Distance between opposite flats (the wrench size).
    pub across_flats: f32,
    /// Height along `z`.
    pub height: f32,
    /// Radius of the through hole, less than `0.95 · across_flats / 2`.
    pub hole_radius: f32,
    /// Sides of the polygon approximating the hole: a multiple of 6, from 6 to 600.
    pub hole_segments: u32,
    /// Material of every vertex.
    pub material: VertexMaterial,
}

impl Default for HexNut {
    /// ISO 4032 proportions for a thread diameter of 1: 1.6 across flats, 0.8 high, hole
    /// radius 0.5, in 48 segments; zinc-plated steel.
    fn default() -> Self {
        HexNut {
            across_flats: 1.6,
            height: 0.8,
            hole_radius: 0.5,
            hole_segments: 48,
            material: VertexMaterial { albedo: Vec3::new(0.56, 0.57, 0.58), roughness: 0.35 },
        }
    }
}

impl HexNut {
    /// The nut's mesh.
    pub fn mesh(&self) -> Result<GrainMesh, MeshError> {
        require_positive("across_flats", self.across_flats)?;
        require_positive("height", self.height)?;
        require_positive("hole_radius", self.hole_radius)?;
        require(
            "hole_radius",
            self.hole_radius,
            self.hole_radius < 0.95 * 0.5 * self.across_flats,
            "less than 0.95 · across_flats / 2",
        )?;
        let segments = self.hole_segments;
        require(
            "hole_segments",
            segments as f32,
            segments.is_multiple_of(6) && (6..=600).contains(&segments),
            "a multiple of 6 from 6 to 600",
        )?;
        let segments = segments as usize;
        let apothem = 0.5 * f64::from(self.across_flats);
        let hole_radius = f64::from(self.hole_radius);
        let half_height = 0.5 * f64::from(self.height);
        let angle = |i: usize| 2.0 * PI * (i % segments) as f64 / segments as f64;
        // Point i of the hole polygon / of the hexagon (at the same angle), at height z.
        // Each is computed by one expression so equal points are bit-identical.
        let hole_point = |i: usize, z: f64| DVec3::new(hole_radius * angle(i).cos(), hole_radius * angle(i).sin(), z);
        let hexagon_point = |i: usize, z: f64| {
            let per_flat = segments / 6;
            let i = i % segments;
            let (flat, step) = (i / per_flat, i % per_flat);
            // Corners at angles 0°, 60°, …: walk along the flat from corner `flat`.
            let corner = |k: usize| {
                let a = PI / 3.0 * (k % 6) as f64;
                DVec3::new(a.cos(), a.sin(), 0.0) * (apothem / (PI / 6.0).cos())
            };
            let t = step as f64 / per_flat as f64;
            let p = corner(flat).lerp(corner(flat + 1), t);
            DVec3::new(p.x, p.y, z)
        };

        let mut builder = Builder::default();
        for (z, outward_up) in [(half_height, true), (-half_height, false)] {
            // End face: a ring of quads between hole and hexagon.
            let base = builder.positions.len() as u32;
            for i in 0..segments {
                builder.positions.push(hole_point(i, z));
                builder.positions.push(hexagon_point(i, z));
            }
            let ring = |i: usize| base + 2 * (i % segments) as u32;
            for i in 0..segments {
                let (hole, hexagon, next_hole, next_hexagon) = (ring(i), ring(i) + 1, ring(i + 1), ring(i + 1) + 1);
                builder.quad([hole, hexagon, next_hexagon, next_hole], !outward_up);
            }
        }
        for flat in 0..6 {
            let per_flat = segments / 6;
            let steps = (flat * per_flat..=(flat + 1) * per_flat).collect::<Vec<_>>();
            builder.wall(&steps, hexagon_point, half_height, false);
        }
        builder.wall(&(0..=segments).collect::<Vec<_>>(), hole_point, half_height, true);

        let positions = builder.positions.iter().map(|p| p.as_vec3()).collect::<Vec<_>>();
        let materials = vec![self.material; positions.len()];
        GrainMesh::new(positions, builder.triangles)?.with_materials(materials)
    }
}

/// Positions and triangles being assembled.
#[derive(Default)]
struct Builder {
    positions: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
}

impl Builder {
    /// Two triangles for the quad `abcd` (counter-clockwise), or `adcb` when `reversed`.
    fn quad(&mut self, [a, b, c, d]: [u32; 4], reversed: bool) {
        if reversed {
            self.triangles.extend([[a, c, b], [a, d, c]]);
        } else {
            self.triangles.extend([[a, b, c], [a, c, d]]);
        }
    }

    /// A vertical wall through the points `point(i, ±half_height)` for consecutive `steps`,
    /// with its own vertices, facing away from the axis (or towards it when `inward`).
    fn wall(&mut self, steps: &[usize], point: impl Fn(usize, f64) -> DVec3, half_height: f64, inward: bool) {
        let base = self.positions.len() as u32;
        for &i in steps {
            self.positions.push(point(i, -half_height));
            self.positions.push(point(i, half_height));
        }
        for k in 0..steps.len().saturating_sub(1) as u32 {
            let (bottom, top, next_bottom, next_top) =
                (base + 2 * k, base + 2 * k + 1, base + 2 * k + 2, base + 2 * k + 3);
            self.quad([bottom, next_bottom, next_top, top], inward);
        }
    }
}
