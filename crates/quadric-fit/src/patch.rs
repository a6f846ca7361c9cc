//! Triangle and bilinear patches as quadrics (Appendix B, derived again here).
//!
//! A bilinear patch through `P1..P4` (in order) is
//! `X(u, v) = (1-u)(1-v)P1 + u(1-v)P2 + uv P3 + (1-u)v P4 = d + u b + v c + uv a`
//! with `a = P1 + P3 - P2 - P4`, `b = P2 - P1`, `c = P4 - P1`, `d = P1` (Appendix B).
//! Eliminating `u` and `v`: with `n_a = b × c`, `n_b = c × a`, `n_c = a × b` and
//! `Δ = a · (b × c)`, dotting `X - d` with each normal isolates one term:
//!
//! ```text
//! (X - d)·n_b = u Δ,    (X - d)·n_c = v Δ,    (X - d)·n_a = uv Δ
//! ```
//!
//! so every point of the patch satisfies the quadric
//! `Q(X) = ((X - d)·n_b)((X - d)·n_c) / Δ - (X - d)·n_a = 0` (a hyperbolic paraboloid).
//! When `Δ = 0` the four points are coplanar and the patch is planar; its plane is used.
//! A triangle patch is always planar: its quadric is the plane through the three points.

use glam::{DMat3, DVec3};

use crate::quadric::{Quadric, QuadricError};

/// `Δ` below this fraction of `|a||b||c|` counts as coplanar.
const COPLANAR: f64 = 1e-9;

/// The first corner of `points` that is not finite.
fn non_finite_corner(points: &[DVec3]) -> Result<(), QuadricError> {
    match points.iter().position(|p| !p.is_finite()) {
        Some(index) => Err(QuadricError::NonFinitePoint { index }),
        None => Ok(()),
    }
}

/// The plane through three points; an error when one is not finite
/// ([`QuadricError::NonFinitePoint`]) or they are collinear ([`QuadricError::Degenerate`]).
pub fn triangle_quadric(p1: DVec3, p2: DVec3, p3: DVec3) -> Result<Quadric, QuadricError> {
    non_finite_corner(&[p1, p2, p3])?;
    let normal = (p2 - p1).cross(p3 - p1);
    if !normal.is_finite() || normal.length_squared() <= f64::MIN_POSITIVE {
        return Err(QuadricError::Degenerate);
    }
    Quadric::plane(normal, -normal.dot(p1))
}

/// The quadric through the bilinear patch `P1, P2, P3, P4` (in order around the patch),
/// or the plane of a planar patch (Newell's normal); an error when a corner is not finite
/// ([`QuadricError::NonFinitePoint`]) or the corners are collinear or coincident
/// ([`QuadricError::Degenerate`]).
pub fn bilinear_quadric(p1: DVec3, p2: DVec3, p3: DVec3, p4: DVec3) -> Result<Quadric, QuadricError> {
    non_finite_corner(&[p1, p2, p3, p4])?;
    let a = p1 + p3 - p2 - p4;
    let b = p2 - p1;
    let c = p4 - p1;
    let d = p1;
    let (n_a, n_b, n_c) = (b.cross(c), c.cross(a), a.cross(b));
    let delta = a.dot(n_a);
    if delta.abs() <= COPLANAR * a.length() * b.length() * c.length() {
        // Planar (or degenerate) quad: Newell's normal is robust for any planar polygon.
        let points = [p1, p2, p3, p4];
        let mut normal = DVec3::ZERO;
        for i in 0..4 {
            let (p, q) = (points[i], points[(i + 1) % 4]);
            normal += DVec3::new((p.y - q.y) * (p.z + q.z), (p.z - q.z) * (p.x + q.x), (p.x - q.x) * (p.y + q.y));
        }
        let centroid = (p1 + p2 + p3 + p4) / 4.0;
        if normal.length_squared() <= f64::MIN_POSITIVE {
            return Err(QuadricError::Degenerate);
        }
        return Quadric::plane(normal, -normal.dot(centroid));
    }
    // Expand ((X-d)·n_b)((X-d)·n_c)/Δ - (X-d)·n_a into pᵀMp + L·p + J.
    let outer = DMat3::from_cols(n_b * n_c.x, n_b * n_c.y, n_b * n_c.z);
    let m = (outer + outer.transpose()) * (0.5 / delta);
    let (db, dc) = (n_b.dot(d), n_c.dot(d));
    let l = -(n_b * dc + n_c * db) / delta - n_a;
    let j = db * dc / delta + n_a.dot(d);
    Quadric::from_matrix(m, l, j).map(Quadric::normalized)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_point_of_a_twisted_patch_is_on_its_quadric() {
        let (p1, p2, p3, p4) = (
            DVec3::new(0.0, 0.0, 0.1),
            DVec3::new(1.0, 0.0, 0.7),
            DVec3::new(1.0, 1.0, 0.2),
            DVec3::new(0.0, 1.0, 0.9),
        );
        let q = bilinear_quadric(p1, p2, p3, p4).unwrap();
        assert!(!q.is_plane());
        for i in 0..=10 {
            for j in 0..=10 {
                let (u, v) = (f64::from(i) / 10.0, f64::from(j) / 10.0);
                let x = (1.0 - u) * (1.0 - v) * p1 + u * (1.0 - v) * p2 + u * v * p3 + (1.0 - u) * v * p4;
                assert!(q.value(x).abs() < 1e-12, "({u}, {v}): {}", q.value(x));
            }
        }
        // A point off the patch is off the quadric.
        assert!(q.value(DVec3::new(0.5, 0.5, 2.0)).abs() > 1e-3);
    }

    #[test]
    fn planar_and_degenerate_patches() {
        let q = bilinear_quadric(DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y).unwrap();
        assert!(q.is_plane());
        assert!(q.value(DVec3::new(0.3, 0.9, 0.0)).abs() < 1e-15);
        assert_eq!(
            bilinear_quadric(DVec3::ZERO, DVec3::X, DVec3::X * 2.0, DVec3::X * 3.0),
            Err(QuadricError::Degenerate)
        );
        assert_eq!(
            bilinear_quadric(DVec3::X, DVec3::NAN, DVec3::Y, DVec3::Z),
            Err(QuadricError::NonFinitePoint { index: 1 })
        );
        assert_eq!(triangle_quadric(DVec3::ZERO, DVec3::X, DVec3::X * 2.0), Err(QuadricError::Degenerate));
        assert_eq!(
            triangle_quadric(DVec3::ZERO, DVec3::X, DVec3::splat(f64::INFINITY)),
            Err(QuadricError::NonFinitePoint { index: 2 })
        );
        let t = triangle_quadric(DVec3::X, DVec3::Y, DVec3::Z).unwrap();
        assert!(t.value(DVec3::splat(1.0 / 3.0)).abs() < 1e-15);
    }
}
