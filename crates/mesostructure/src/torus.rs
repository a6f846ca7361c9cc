//! Tori: closed torus meshes, the chain-mail mesostructure (interlocked rings, periodic in
//! x and y) and a torus base mesh with texture coordinates and tangent frames, the curved
//! surface onto which the paper maps its mesostructures.

use std::f32::consts::TAU;

use ddm_compress::Triangle;
use glam::{UVec2, UVec3, Vec2, Vec3};

/// A torus: the tube of radius `minor_radius` around the circle of radius `major_radius`
/// centred at `center` in the plane orthogonal to `axis`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ring {
    /// Centre of the centre circle.
    pub center: Vec3,
    /// Unit normal of the centre circle's plane.
    pub axis: Vec3,
    /// Radius of the centre circle.
    pub major_radius: f32,
    /// Radius of the tube.
    pub minor_radius: f32,
}

impl Ring {
    /// Two unit vectors spanning the centre circle's plane, `(e1, e2, axis)` right-handed.
    fn plane_basis(&self) -> (Vec3, Vec3) {
        let helper = if self.axis.x.abs() < 0.9 { Vec3::X } else { Vec3::Y };
        let e1 = self.axis.cross(helper).normalize();
        (e1, self.axis.cross(e1))
    }

    /// The point of the centre circle at angle `theta`.
    pub fn centerline(&self, theta: f32) -> Vec3 {
        let (e1, e2) = self.plane_basis();
        self.center + self.major_radius * (theta.cos() * e1 + theta.sin() * e2)
    }

    /// A closed, outward-oriented mesh of `segments` steps around the centre circle and
    /// `sides` around the tube (each at least 3), its vertices on the torus.
    pub fn triangles(&self, segments: u32, sides: u32) -> Vec<Triangle> {
        let (segments, sides) = (segments.max(3), sides.max(3));
        let (e1, e2) = self.plane_basis();
        let point = |i: u32, j: u32| {
            let (theta, phi) = (TAU * (i % segments) as f32 / segments as f32, TAU * (j % sides) as f32 / sides as f32);
            let radial = theta.cos() * e1 + theta.sin() * e2;
            self.center
                + (self.major_radius + self.minor_radius * phi.cos()) * radial
                + self.minor_radius * phi.sin() * self.axis
        };
        let mut triangles = Vec::with_capacity(2 * (segments * sides) as usize);
        for i in 0..segments {
            for j in 0..sides {
                let (a, b, c, d) = (point(i, j), point(i + 1, j), point(i + 1, j + 1), point(i, j + 1));
                triangles.push(Triangle([a, b, c]));
                triangles.push(Triangle([a, c, d]));
            }
        }
        triangles
    }
}

/// The rings of [`chain_mail`] on a tile of `size` voxels.
///
/// Flat rings (axis z) sit at the centres of an `nx × ny` grid of cells of `a × b` voxels;
/// standing rings on the cell walls link each flat ring to its four neighbours (axis y on
/// the walls `x = i a`, axis x on the walls `y = j b`). With `s = min(a, b)`: flat rings
/// have centre radius `0.375 s`, standing ones `a/2 − 0.1875 s` (resp. `b/2 − 0.1875 s`),
/// all tubes `0.075 s`. Then each standing ring passes through the holes of the two flat
/// rings it joins with `0.0375 s` of clearance, and the x- and y-standing rings stay
/// `0.265 s − 0.15 s` apart. The cells are chosen as few as keep every ring inside
/// `0.05 size.z .. 0.95 size.z` (`a ≤ 1.2 size.z`). Standing rings on the tile's border
/// walls straddle it: the mesh reaches out of the tile in x and y by up to a ring, and
/// its copies shifted by the tile size complete it (as [`ddm_compress::compute_distance_maps`]
/// does with `periodic_xy`).
pub fn chain_mail_rings(size: UVec3) -> Vec<Ring> {
    let (sx, sy, sz) = (size.x.max(1) as f32, size.y.max(1) as f32, size.z.max(1) as f32);
    let nx = (sx / (1.2 * sz)).ceil().max(1.0) as u32;
    let ny = (sy / (1.2 * sz)).ceil().max(1.0) as u32;
    let (a, b) = (sx / nx as f32, sy / ny as f32);
    let s = a.min(b);
    let tube = 0.075 * s;
    let z = 0.5 * sz;
    let mut rings = Vec::with_capacity(3 * (nx * ny) as usize);
    for j in 0..ny {
        for i in 0..nx {
            let (x, y) = ((i as f32 + 0.5) * a, (j as f32 + 0.5) * b);
            rings.push(Ring { center: Vec3::new(x, y, z), axis: Vec3::Z, major_radius: 0.375 * s, minor_radius: tube });
            rings.push(Ring {
                center: Vec3::new(i as f32 * a, y, z),
                axis: Vec3::Y,
                major_radius: 0.5 * a - 0.1875 * s,
                minor_radius: tube,
            });
            rings.push(Ring {
                center: Vec3::new(x, j as f32 * b, z),
                axis: Vec3::X,
                major_radius: 0.5 * b - 0.1875 * s,
                minor_radius: tube,
            });
        }
    }
    rings
}

/// Chain mail on a tile of `size` voxels: the interlocked rings of [`chain_mail_rings`],
/// each a closed mesh of 24 × 8 quads. Not a height field: rays pass through the rings.
pub fn chain_mail(size: UVec3) -> Vec<Triangle> {
    chain_mail_rings(size).iter().flat_map(|ring| ring.triangles(24, 8)).collect()
}

/// A triangle mesh with texture coordinates and a tangent frame per vertex: the curved
/// base surface onto which a mesostructure tile is mapped.
#[derive(Clone, Debug, PartialEq)]
pub struct BaseMesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Texture coordinates; one unit is one mesostructure tile.
    pub uvs: Vec<Vec2>,
    /// Unit `∂position/∂u` directions.
    pub tangents: Vec<Vec3>,
    /// Unit `∂position/∂v` directions.
    pub bitangents: Vec<Vec3>,
    /// Unit outward normals, `tangent × bitangent`.
    pub normals: Vec<Vec3>,
    /// Counter-clockwise (seen from outside) vertex triples.
    pub indices: Vec<[u32; 3]>,
}

/// A torus base mesh: centre radius `major_radius`, tube radius `minor_radius`
/// (`0 < minor_radius < major_radius`), `segments × sides` quads, the texture repeating
/// `repeats.x` times around the centre circle and `repeats.y` times around the tube.
///
/// `P(θ, φ) = ((R + r cos φ) cos θ, (R + r cos φ) sin θ, r sin φ)` with `θ = 2π u / repeats.x`,
/// `φ = 2π v / repeats.y`. The parametrisation is orthogonal, so the frame
/// `(∂P/∂u, ∂P/∂v, n)` normalised is orthonormal:
/// `t = (−sin θ, cos θ, 0)`, `b = (−sin φ cos θ, −sin φ sin θ, cos φ)`,
/// `n = t × b = (cos φ cos θ, cos φ sin θ, sin φ)`. The seam vertices are duplicated
/// (same position and frame, `u` or `v` larger by the repeat count), so texture
/// coordinates grow continuously across every triangle. `None` for invalid radii, fewer
/// than 3 segments or sides, or zero repeats.
pub fn torus_base_mesh(
    major_radius: f32,
    minor_radius: f32,
    segments: u32,
    sides: u32,
    repeats: UVec2,
) -> Option<BaseMesh> {
    let valid = minor_radius > 0.0 && minor_radius < major_radius && major_radius.is_finite();
    if !valid || segments < 3 || sides < 3 || repeats.x == 0 || repeats.y == 0 {
        return None;
    }
    let count = ((segments + 1) * (sides + 1)) as usize;
    let mut mesh = BaseMesh {
        positions: Vec::with_capacity(count),
        uvs: Vec::with_capacity(count),
        tangents: Vec::with_capacity(count),
        bitangents: Vec::with_capacity(count),
        normals: Vec::with_capacity(count),
        indices: Vec::with_capacity(2 * (segments * sides) as usize),
    };
    for i in 0..=segments {
        for j in 0..=sides {
            let (fu, fv) = (i as f32 / segments as f32, j as f32 / sides as f32);
            // The seam uses the angles of the first row, so positions match exactly.
            let (theta, phi) = (TAU * (i % segments) as f32 / segments as f32, TAU * (j % sides) as f32 / sides as f32);
            let (st, ct, sp, cp) = (theta.sin(), theta.cos(), phi.sin(), phi.cos());
            mesh.positions.push(Vec3::new(
                (major_radius + minor_radius * cp) * ct,
                (major_radius + minor_radius * cp) * st,
                minor_radius * sp,
            ));
            mesh.uvs.push(Vec2::new(fu * repeats.x as f32, fv * repeats.y as f32));
            let tangent = Vec3::new(-st, ct, 0.0);
            let bitangent = Vec3::new(-sp * ct, -sp * st, cp);
            mesh.tangents.push(tangent);
            mesh.bitangents.push(bitangent);
            mesh.normals.push(tangent.cross(bitangent));
        }
    }
    let index = |i: u32, j: u32| i * (sides + 1) + j;
    for i in 0..segments {
        for j in 0..sides {
            let (a, b, c, d) = (index(i, j), index(i + 1, j), index(i + 1, j + 1), index(i, j + 1));
            mesh.indices.push([a, b, c]);
            mesh.indices.push([a, c, d]);
        }
    }
    Some(mesh)
}
