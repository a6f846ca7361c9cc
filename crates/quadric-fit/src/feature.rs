//! The feature vertex of a cell that a crease or a corner crosses: the least-squares
//! point of the surface's tangent planes (beyond the paper).
//!
//! The polygons of [`watertight`](crate::watertight) join points on the voxel's edges, so
//! a voxel that a sharp edge crosses (a wall's top, a box's corner) gets a polygon that
//! cuts the edge off. Extended marching cubes (Kobbelt, Botsch, Schwanecke & Seidel,
//! *Feature sensitive surface extraction from volume data*, SIGGRAPH 2001, §3) and dual
//! contouring (Ju, Losasso, Schaefer & Warren, *Dual contouring of Hermite data*,
//! SIGGRAPH 2002, §2.1, the QEF of eq. 1) put a vertex inside such a cell instead:
//!
//! ```text
//! x* = argmin_x Σᵢ (nᵢ · (x − pᵢ))²
//! ```
//!
//! over the tangent planes `(nᵢ, pᵢ)` of the surface in the cell. With `A = Σ nᵢ nᵢᵀ`
//! and `b = Σ nᵢ (nᵢ · (pᵢ − m))` the minimiser nearest to a mass point `m` is
//! `x* = m + A⁺ b`. Directions in which `A`'s eigenvalue is below [`RANK_THRESHOLD`] times
//! its largest are left to `m` (the truncated pseudo-inverse of Lindstrom, *Out-of-core
//! simplification of large polygonal models*, SIGGRAPH 2000, §4.1, which dual contouring
//! uses): along a crease the planes do not fix the vertex, and nearly parallel planes
//! would fix it far away. The number of directions kept, [`FeatureVertex::rank`], tells a
//! plane (1) from a crease (2) and a corner (3).
//!
//! ```
//! use glam::DVec3;
//! use quadric_fit::feature::{TangentPlane, feature_vertex};
//!
//! // A wall's top edge along x: its top z = 0.6 and its side y = 0.3.
//! let planes = [
//!     TangentPlane { normal: DVec3::Z, point: DVec3::new(0.2, 0.1, 0.6) },
//!     TangentPlane { normal: DVec3::Y, point: DVec3::new(0.7, 0.3, 0.2) },
//! ];
//! let vertex = feature_vertex(&planes, DVec3::new(0.5, 0.15, 0.3)).unwrap();
//! assert_eq!(vertex.rank, 2);
//! assert!((vertex.point - DVec3::new(0.5, 0.3, 0.6)).length() < 1e-12);
//! ```

use glam::DVec3;

use crate::eigen::symmetric_eigen;

/// Eigenvalues of `A = Σ nᵢ nᵢᵀ` below this fraction of the largest are treated as 0
/// (singular values of the plane matrix below 0.1 of the largest, dual contouring's
/// truncation).
pub const RANK_THRESHOLD: f64 = 1e-2;

/// A tangent plane of the surface: a unit normal and a point on the plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TangentPlane {
    /// The plane's normal (normalised by [`feature_vertex`]; its sign does not matter).
    pub normal: DVec3,
    /// A point of the plane.
    pub point: DVec3,
}

/// The least-squares point of a set of tangent planes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FeatureVertex {
    /// The minimiser nearest to the mass point.
    pub point: DVec3,
    /// How many directions the planes fix: 1 on a plane, 2 on a crease, 3 at a corner.
    pub rank: u8,
    /// The root mean square of the point's distances to the planes: 0 where all the
    /// planes meet in it.
    pub rms_distance: f64,
}

/// The feature vertex of `planes` nearest to `mass_point` (see the module docs); `None`
/// when there is no plane, a value is not finite or a normal is zero.
pub fn feature_vertex(planes: &[TangentPlane], mass_point: DVec3) -> Option<FeatureVertex> {
    if planes.is_empty() || !mass_point.is_finite() {
        return None;
    }
    let mut a = [[0.0_f64; 3]; 3];
    let mut b = DVec3::ZERO;
    let mut unit = alloc::vec::Vec::with_capacity(planes.len());
    for plane in planes {
        let n = plane.normal.try_normalize()?;
        if !plane.point.is_finite() {
            return None;
        }
        for (i, row) in a.iter_mut().enumerate() {
            for (j, cell) in row.iter_mut().enumerate() {
                *cell += n[i] * n[j];
            }
        }
        b += n * n.dot(plane.point - mass_point);
        unit.push((n, plane.point));
    }
    let (values, vectors) = symmetric_eigen(&a)?;
    let largest = values[2];
    let mut offset = DVec3::ZERO;
    let mut rank = 0;
    for (value, vector) in values.iter().zip(vectors) {
        if *value > RANK_THRESHOLD * largest {
            let v = DVec3::from_array(vector);
            offset += v * (v.dot(b) / value);
            rank += 1;
        }
    }
    let point = mass_point + offset;
    let squares: f64 = unit.iter().map(|(n, p)| n.dot(point - *p)).map(|d| d * d).sum();
    Some(FeatureVertex { point, rank, rms_distance: libm::sqrt(squares / unit.len() as f64) })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plane(normal: DVec3, point: DVec3) -> TangentPlane {
        TangentPlane { normal, point }
    }

    #[test]
    fn a_corner_of_three_planes_is_found_exactly() {
        // A box corner at (0.7, 0.4, 0.55), the planes given by unnormalised normals and
        // several points each.
        let corner = DVec3::new(0.7, 0.4, 0.55);
        let planes = [
            plane(DVec3::X * 3.0, corner + DVec3::new(0.0, -0.3, -0.2)),
            plane(DVec3::NEG_Y, corner + DVec3::new(-0.4, 0.0, -0.1)),
            plane(DVec3::Z * 0.5, corner + DVec3::new(-0.2, -0.2, 0.0)),
            plane(DVec3::Z, corner + DVec3::new(-0.6, -0.1, 0.0)),
        ];
        let vertex = feature_vertex(&planes, DVec3::splat(0.5)).unwrap();
        assert_eq!(vertex.rank, 3);
        assert!((vertex.point - corner).length() < 1e-12, "{:?}", vertex.point);
        assert!(vertex.rms_distance < 1e-12);
    }

    #[test]
    fn a_plane_projects_the_mass_point_and_nearly_parallel_planes_do_not_fix_a_crease() {
        // One plane: the mass point's projection.
        let vertex = feature_vertex(&[plane(DVec3::Z, DVec3::new(3.0, 1.0, 0.25))], DVec3::splat(0.5)).unwrap();
        assert_eq!(vertex.rank, 1);
        assert!((vertex.point - DVec3::new(0.5, 0.5, 0.25)).length() < 1e-12);
        // Two planes 1° apart (eigenvalue ratio sin²(0.5°)·… far below the threshold):
        // their intersection line lies 29 units away along y; the vertex stays near the
        // mass point, on their mean plane.
        let tilt = 1.0_f64.to_radians();
        let planes = [
            plane(DVec3::Z, DVec3::new(0.0, 0.0, 0.5)),
            plane(DVec3::new(0.0, libm::sin(tilt), libm::cos(tilt)), DVec3::new(0.0, 0.5, 0.5)),
        ];
        let vertex = feature_vertex(&planes, DVec3::new(0.5, 0.5, 0.4)).unwrap();
        assert_eq!(vertex.rank, 1);
        assert!((vertex.point - DVec3::new(0.5, 0.5, 0.5)).length() < 0.01, "{:?}", vertex.point);
        assert!(vertex.rms_distance < 0.01);
    }

    #[test]
    fn the_residual_measures_planes_that_do_not_meet() {
        // Two parallel planes 0.2 apart: the vertex is halfway, 0.1 from each.
        let planes = [plane(DVec3::Z, DVec3::new(0.0, 0.0, 0.4)), plane(DVec3::NEG_Z, DVec3::new(1.0, 0.0, 0.6))];
        let vertex = feature_vertex(&planes, DVec3::ZERO).unwrap();
        assert_eq!(vertex.rank, 1);
        assert!((vertex.point - DVec3::new(0.0, 0.0, 0.5)).length() < 1e-12);
        assert!((vertex.rms_distance - 0.1).abs() < 1e-12);
    }

    #[test]
    fn bad_input_gives_none() {
        assert_eq!(feature_vertex(&[], DVec3::ZERO), None);
        assert_eq!(feature_vertex(&[plane(DVec3::ZERO, DVec3::ZERO)], DVec3::ZERO), None);
        assert_eq!(feature_vertex(&[plane(DVec3::Z, DVec3::NAN)], DVec3::ZERO), None);
        assert_eq!(feature_vertex(&[plane(DVec3::Z, DVec3::ZERO)], DVec3::INFINITY), None);
    }
}
