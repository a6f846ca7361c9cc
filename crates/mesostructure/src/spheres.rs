//! Planes and spheres: the beads and ball mesostructures.

use ddm_compress::Triangle;
use glam::{UVec3, Vec3};

/// A horizontal plane at `z` over a tile of `size` voxels: two triangles per unit cell.
pub fn plane(size: UVec3, z: f32) -> Vec<Triangle> {
    super::HeightField::from_fn(size.x, size.y, |_, _| z).triangles()
}

/// A UV sphere of `segments` azimuthal and `segments / 2` polar steps (`segments ≥ 4`), its
/// vertices on the sphere (the mesh lies inside it).
pub fn sphere(center: Vec3, radius: f32, segments: u32) -> Vec<Triangle> {
    let segments = segments.max(4);
    let rings = segments / 2;
    let point = |ring: u32, step: u32| {
        let theta = std::f32::consts::PI * ring as f32 / rings as f32;
        let phi = std::f32::consts::TAU * (step % segments) as f32 / segments as f32;
        center + radius * Vec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos())
    };
    let mut triangles = Vec::new();
    for ring in 0..rings {
        for step in 0..segments {
            let (a, b, c, d) =
                (point(ring, step), point(ring, step + 1), point(ring + 1, step), point(ring + 1, step + 1));
            if ring > 0 {
                triangles.push(Triangle([a, c, b]));
            }
            if ring + 1 < rings {
                triangles.push(Triangle([b, c, d]));
            }
        }
    }
    triangles
}

/// Spheres on a floor: the analytic surface that [`beads`] and [`ball`] tessellate.
#[derive(Clone, Debug, PartialEq)]
pub struct SpheresOnFloor {
    /// Height of the horizontal floor (the solid lies below it).
    pub floor: f32,
    /// The spheres' centres and radii.
    pub spheres: Vec<(Vec3, f32)>,
    /// Azimuthal steps of each sphere's tessellation ([`sphere`]).
    pub segments: u32,
}

impl SpheresOnFloor {
    /// The floor and the spheres as triangles.
    pub fn triangles(&self, size: UVec3) -> Vec<Triangle> {
        let mut triangles = plane(size, self.floor);
        for &(center, radius) in &self.spheres {
            triangles.extend(sphere(center, radius, self.segments));
        }
        triangles
    }
}

/// The beads of [`beads`]: a plane at `0.25 size.z` and a 2 × 2 array of spheres sunk by a
/// third of their radius into it.
pub fn bead_spheres(size: UVec3) -> SpheresOnFloor {
    let (sx, sy, sz) = (size.x as f32, size.y as f32, size.z as f32);
    let floor = 0.25 * sz;
    // Radius: fits 2 beads per side with a small gap, and below the tile's top.
    let radius = (0.22 * sx.min(sy)).min((sz - floor) / (1.0 + 2.0 / 3.0) * 0.95);
    let mut spheres = Vec::with_capacity(4);
    for j in 0..2 {
        for i in 0..2 {
            let center =
                Vec3::new((i as f32 + 0.5) * sx / 2.0, (j as f32 + 0.5) * sy / 2.0, floor + radius * 2.0 / 3.0);
            spheres.push((center, radius));
        }
    }
    SpheresOnFloor { floor, spheres, segments: 16 }
}

/// Beads on a tile of `size` voxels: [`bead_spheres`] tessellated.
pub fn beads(size: UVec3) -> Vec<Triangle> {
    bead_spheres(size).triangles(size)
}

/// The ball of [`ball`]: the plane at `0.15 size.z` and one sphere centred in x and y,
/// floating a tenth of the height above the plane.
pub fn ball_sphere(size: UVec3) -> SpheresOnFloor {
    let (sx, sy, sz) = (size.x as f32, size.y as f32, size.z as f32);
    let floor = 0.15 * sz;
    let radius = (0.35 * sx.min(sy)).min(0.35 * sz);
    let center = Vec3::new(0.5 * sx, 0.5 * sy, floor + 0.1 * sz + radius);
    SpheresOnFloor { floor, spheres: vec![(center, radius)], segments: 24 }
}

/// A ball above a plane on a tile of `size` voxels: [`ball_sphere`] tessellated.
pub fn ball(size: UVec3) -> Vec<Triangle> {
    ball_sphere(size).triangles(size)
}
