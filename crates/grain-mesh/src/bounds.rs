//! The quasi-spherical bound of Michel & Boubekeur (2020, §1): the grain's surface lies
//! between two spheres centred at the grain's centre, of inner radius `r` and outer radius
//! `R`; the closer `r/R` is to 1, the better their impostors, sampling and occlusion
//! culling work (§5, §8, Fig. 15).
//!
//! # Definitions
//!
//! - **Centre** ([`CentreKind`]): the *volume centroid* (centre of mass at uniform
//!   density) when the mesh is closed and consistently oriented — where a rigid-body
//!   simulation of the stacking places and rotates the grain, so the impostor sphere
//!   stays put as the grain tumbles. For an open or inconsistently wound mesh the enclosed
//!   volume is undefined and the *area-weighted surface centroid* is used instead.
//! - **Outer radius `R`**: the largest distance from the centre to a point of the surface.
//!   The farthest point of a triangle from a point is one of its corners, so this is the
//!   largest centre–corner distance, exactly.
//! - **Inner radius `r`**: the distance from the centre to the *nearest point of the
//!   surface* (exact point–triangle distances, not vertex distances), so the surface lies
//!   in the shell `r ≤ |x − c| ≤ R`. For a grain with a through hole, such as a hex nut,
//!   whose centre lies in the hole, `r` is the distance to the hole's wall: the open ball
//!   of radius `r` touches no surface but contains **no material either**.
//! - **Occluder radius**: §8 culls a grain when another grain's inner sphere hides its
//!   outer sphere, which is sound only if the inner ball is *inside the solid*. That holds
//!   when the centre is inside the solid (winding number ≈ ±1) and `r > 0`;
//!   [`GrainBounds::occluder_radius`] is then `r`, and `0` otherwise (the nut).

use glam::{DVec3, Vec3};

use crate::error::MeshError;
use crate::topology::EdgeReport;

/// Which centre a [`GrainBounds`] is measured about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CentreKind {
    /// Centroid of the enclosed solid (closed, consistently oriented meshes).
    VolumeCentroid,
    /// Area-weighted centroid of the triangles (open or inconsistently oriented meshes,
    /// or closed ones that enclose no volume).
    SurfaceCentroid,
}

/// Centre, inner and outer radii of a grain, and the measures they come from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GrainBounds {
    /// The grain's centre.
    pub centre: Vec3,
    /// Which centroid [`GrainBounds::centre`] is.
    pub centre_kind: CentreKind,
    /// `r`: distance from the centre to the nearest point of the surface.
    pub inner_radius: f32,
    /// `R`: distance from the centre to the farthest point of the surface.
    pub outer_radius: f32,
    /// Total triangle area.
    pub surface_area: f32,
    /// Signed enclosed volume by the divergence theorem (negative when the triangles wind
    /// inward); `None` when the mesh is not closed and consistently oriented.
    pub volume: Option<f32>,
    /// Generalised winding number of the surface about the centre: ≈ 1 inside a closed
    /// outward-wound solid, ≈ 0 outside (e.g. in a nut's hole).
    pub winding_number: f32,
}

impl GrainBounds {
    /// `r/R`, the paper's measure of how spherical a grain is (1 for a sphere).
    pub fn radius_ratio(&self) -> f32 {
        self.inner_radius / self.outer_radius
    }

    /// Whether the centre is inside the solid and off the surface.
    pub fn centre_inside_solid(&self) -> bool {
        self.winding_number.abs() >= 0.5 && self.inner_radius > 0.0
    }

    /// Radius of the ball about the centre that is filled with material and may serve as
    /// an occluder (§8): `r` when the centre is inside the solid, else 0.
    pub fn occluder_radius(&self) -> f32 {
        if self.centre_inside_solid() { self.inner_radius } else { 0.0 }
    }

    /// Measures positions and triangles already checked to be finite and in range.
    pub(crate) fn measure(positions: &[Vec3], triangles: &[[u32; 3]]) -> Result<GrainBounds, MeshError> {
        let corners = |t: &[u32; 3]| t.map(|i| positions[i as usize].as_dvec3());
        // f64 sums: cubes of f32 coordinates cannot overflow.
        let mut area_sum = 0.0;
        let mut area_moment = DVec3::ZERO;
        let mut volume_sum = 0.0;
        let mut volume_moment = DVec3::ZERO;
        for t in triangles {
            let [a, b, c] = corners(t);
            let area = 0.5 * (b - a).cross(c - a).length();
            area_sum += area;
            area_moment += area * (a + b + c) / 3.0;
            // Signed volume of the tetrahedron (origin, a, b, c) and its centroid.
            let volume = a.dot(b.cross(c)) / 6.0;
            volume_sum += volume;
            volume_moment += volume * (a + b + c) / 4.0;
        }
        if area_sum == 0.0 {
            let first = positions[triangles[0][0] as usize];
            let all_equal = triangles.iter().flatten().all(|&i| positions[i as usize] == first);
            return Err(if all_equal { MeshError::ZeroExtent { point: first } } else { MeshError::ZeroArea });
        }
        let closed = EdgeReport::of(positions, triangles).is_closed_and_oriented();
        // A closed mesh encloses volume unless it is flat (e.g. two coincident sheets); a
        // sphere has volume / area^1.5 ≈ 0.094.
        let encloses_volume = closed && volume_sum.abs() > 1e-6 * area_sum.powf(1.5);
        let (centre, centre_kind) = if encloses_volume {
            (volume_moment / volume_sum, CentreKind::VolumeCentroid)
        } else {
            (area_moment / area_sum, CentreKind::SurfaceCentroid)
        };
        let mut inner_squared = f64::INFINITY;
        let mut outer_squared: f64 = 0.0;
        let mut solid_angle = 0.0;
        for t in triangles {
            let [a, b, c] = corners(t).map(|p| p - centre);
            inner_squared = inner_squared.min(closest_point_on_triangle(DVec3::ZERO, a, b, c).length_squared());
            outer_squared = outer_squared.max(a.length_squared()).max(b.length_squared()).max(c.length_squared());
            solid_angle += triangle_solid_angle(a, b, c);
        }
        let bounds = GrainBounds {
            centre: centre.as_vec3(),
            centre_kind,
            inner_radius: inner_squared.sqrt() as f32,
            outer_radius: outer_squared.sqrt() as f32,
            surface_area: area_sum as f32,
            volume: closed.then_some(volume_sum as f32),
            winding_number: (solid_angle / (4.0 * std::f64::consts::PI)) as f32,
        };
        let finite = bounds.centre.is_finite()
            && bounds.outer_radius.is_finite()
            && bounds.surface_area.is_finite()
            && bounds.volume.is_none_or(f32::is_finite);
        if !finite {
            return Err(MeshError::NonFiniteBounds);
        }
        Ok(bounds)
    }
}

/// Signed solid angle subtended at the origin by triangle `abc` (Van Oosterom & Strackee
/// 1983), positive when `abc` winds counter-clockwise seen from the origin's outside.
fn triangle_solid_angle(a: DVec3, b: DVec3, c: DVec3) -> f64 {
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let numerator = a.dot(b.cross(c));
    let denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    2.0 * numerator.atan2(denominator)
}

/// The point of triangle `abc` nearest to `p` (Ericson, *Real-Time Collision Detection*,
/// §5.1.5), exact for degenerate triangles too.
pub fn closest_point_on_triangle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denominator = va + vb + vc;
    if denominator == 0.0 {
        // Collinear corners that the edge tests above did not settle: nearest corner.
        return [a, b, c].into_iter().fold(a, |best, q| if q.distance(p) < best.distance(p) { q } else { best });
    }
    a + ab * (vb / denominator) + ac * (vc / denominator)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closest_point_regions() {
        let (a, b, c) = (DVec3::ZERO, DVec3::X, DVec3::Y);
        let cases = [
            (DVec3::new(0.2, 0.2, 1.0), DVec3::new(0.2, 0.2, 0.0)),  // face
            (DVec3::new(-1.0, -1.0, 0.0), a),                        // corner a
            (DVec3::new(2.0, -0.5, 0.0), b),                         // corner b
            (DVec3::new(0.5, -1.0, 3.0), DVec3::new(0.5, 0.0, 0.0)), // edge ab
            (DVec3::new(1.0, 1.0, 0.0), DVec3::new(0.5, 0.5, 0.0)),  // edge bc
        ];
        for (p, expected) in cases {
            let got = closest_point_on_triangle(p, a, b, c);
            assert!(got.distance(expected) < 1e-12, "{p} → {got}, expected {expected}");
        }
        // Degenerate triangle (a segment): nearest point on the segment.
        let got = closest_point_on_triangle(DVec3::new(0.5, 1.0, 0.0), a, b, b);
        assert!(got.distance(DVec3::new(0.5, 0.0, 0.0)) < 1e-12, "{got}");
    }

    #[test]
    fn solid_angle_of_an_octant() {
        // The triangle X, Y, Z subtends one eighth of the sphere at the origin.
        let omega = triangle_solid_angle(DVec3::X, DVec3::Y, DVec3::Z);
        assert!((omega - std::f64::consts::PI / 2.0).abs() < 1e-12, "{omega}");
        assert!((triangle_solid_angle(DVec3::X, DVec3::Z, DVec3::Y) + omega).abs() < 1e-12);
    }
}
