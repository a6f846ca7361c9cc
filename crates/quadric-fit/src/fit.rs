//! Least-squares quadric fitting (eq. 2) with a documented plane fallback.
//!
//! Eq. 2 asks for the coefficient vector `c` with `A c ≈ 0`, where row `i` of `A` is
//! `[xᵢ², yᵢ², zᵢ², xᵢyᵢ, yᵢzᵢ, zᵢxᵢ, xᵢ, yᵢ, zᵢ, 1]`. The trivial `c = 0` is excluded by
//! the normalization `‖c‖ = 1`, under which the minimizer of `‖A c‖` is the eigenvector of
//! the smallest eigenvalue of `AᵀA`.
//!
//! That normalization depends on the coordinate frame, so the points are first moved to
//! their centroid and scaled to unit RMS radius; `‖c‖ = 1` holds in that frame, and the
//! result is transformed back and renormalized. Without this step the columns of `A`
//! differ by orders of magnitude and the fit degrades (tested below).

use core::fmt;

use glam::DVec3;

use crate::eigen::symmetric_eigen;
use crate::quadric::Quadric;

/// Which surface a fit produced.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FitKind {
    /// A full quadric: the least-squares solution of eq. 2.
    Quadric,
    /// A plane, because the points do not determine a unique quadric: fewer than 9 of
    /// them, or (nearly) coplanar points, whose quadrics form a family (the plane times any
    /// linear form).
    Plane,
}

/// The result of [`fit_quadric`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QuadricFit {
    /// The fitted surface, unit coefficient vector.
    pub quadric: Quadric,
    /// Whether it is a quadric or the plane fallback.
    pub kind: FitKind,
    /// Root mean square of the first-order distance estimate `|Q|/|∇Q|` over the points.
    pub rms_distance: f64,
}

/// Why [`fit_plane`] or [`fit_quadric`] found no surface through the points. The checks
/// run in the order of the variants; the first that fails is returned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FitError {
    /// Fewer than 3 points: they determine no plane.
    TooFewPoints {
        /// The number of points given.
        count: usize,
    },
    /// A coordinate of point `index` is NaN or infinite.
    NonFinitePoint {
        /// The point's index.
        index: usize,
    },
    /// All points are equal.
    Coincident,
    /// The points lie on one line (within `1e-10` of the largest principal variance).
    Collinear,
    /// An intermediate sum overflowed (coordinates too large for `f64` squares).
    Overflow,
}

impl fmt::Display for FitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::TooFewPoints { count } => write!(f, "quadric fit: {count} points, at least 3 are needed"),
            Self::NonFinitePoint { index } => write!(f, "quadric fit: point {index} is not finite"),
            Self::Coincident => write!(f, "quadric fit: all points are equal"),
            Self::Collinear => write!(f, "quadric fit: the points are collinear"),
            Self::Overflow => write!(f, "quadric fit: the points' coordinates overflow f64 sums"),
        }
    }
}

impl core::error::Error for FitError {}

/// Relative size below which an eigenvalue counts as zero.
const RELATIVE_ZERO: f64 = 1e-10;

/// Centroid and RMS radius of `points` (the first three checks of [`FitError`], then
/// [`FitError::Overflow`] for sums that overflow).
fn normalization(points: &[DVec3]) -> Result<(DVec3, f64), FitError> {
    if points.len() < 3 {
        return Err(FitError::TooFewPoints { count: points.len() });
    }
    if let Some(index) = points.iter().position(|p| !p.is_finite()) {
        return Err(FitError::NonFinitePoint { index });
    }
    let centroid = points.iter().copied().sum::<DVec3>() / points.len() as f64;
    if !centroid.is_finite() {
        return Err(FitError::Overflow);
    }
    if points.iter().all(|&p| p == points[0]) {
        return Err(FitError::Coincident);
    }
    let rms = libm::sqrt(points.iter().map(|p| p.distance_squared(centroid)).sum::<f64>() / points.len() as f64);
    if !rms.is_finite() {
        return Err(FitError::Overflow);
    }
    if rms == 0.0 {
        // Distinct points whose spread vanishes in rounding: as good as one point.
        return Err(FitError::Coincident);
    }
    Ok((centroid, rms))
}

fn rms_distance(quadric: &Quadric, points: &[DVec3]) -> f64 {
    let sum: f64 = points
        .iter()
        .map(|&p| {
            let d = quadric.distance_estimate(p).unwrap_or(0.0);
            d * d
        })
        .sum();
    libm::sqrt(sum / points.len() as f64)
}

/// The least-squares plane through `points` (smallest principal axis).
///
/// # Errors
///
/// A [`FitError`]: fewer than 3 points, a non-finite point (with its index), coincident
/// or collinear points, or sums that overflow.
pub fn fit_plane(points: &[DVec3]) -> Result<QuadricFit, FitError> {
    let (centroid, _) = normalization(points)?;
    let mut covariance = [[0.0; 3]; 3];
    for p in points {
        let d = (*p - centroid).to_array();
        for i in 0..3 {
            for j in 0..3 {
                covariance[i][j] += d[i] * d[j];
            }
        }
    }
    let (values, vectors) = symmetric_eigen(&covariance).ok_or(FitError::Overflow)?;
    // Collinear points: two vanishing principal variances.
    if values[1] <= RELATIVE_ZERO * values[2] {
        return Err(FitError::Collinear);
    }
    let normal = DVec3::from_array(vectors[0]);
    let quadric = Quadric::plane(normal, -normal.dot(centroid)).map_err(|_| FitError::Overflow)?;
    Ok(QuadricFit { quadric, kind: FitKind::Plane, rms_distance: rms_distance(&quadric, points) })
}

/// Fits a quadric to `points` by least squares (eq. 2), in a normalized frame.
///
/// | input | result |
/// |---|---|
/// | fewer than 3 points | [`FitError::TooFewPoints`] |
/// | a coordinate NaN or ∞ | [`FitError::NonFinitePoint`] |
/// | coincident points | [`FitError::Coincident`] |
/// | collinear points | [`FitError::Collinear`] |
/// | coordinates whose squares overflow | [`FitError::Overflow`] |
/// | fewer than 9 points, or coplanar points | [`FitKind::Plane`]: the least-squares plane |
/// | otherwise | [`FitKind::Quadric`] |
///
/// # Errors
///
/// The [`FitError`]s of the table.
pub fn fit_quadric(points: &[DVec3]) -> Result<QuadricFit, FitError> {
    let (centroid, scale) = normalization(points)?;
    let plane = fit_plane(points)?;
    if points.len() < 9 {
        return Ok(plane);
    }
    let mut scatter = [[0.0; 10]; 10];
    for p in points {
        let q = (*p - centroid) / scale;
        let row = [q.x * q.x, q.y * q.y, q.z * q.z, q.x * q.y, q.y * q.z, q.z * q.x, q.x, q.y, q.z, 1.0];
        for i in 0..10 {
            for j in i..10 {
                scatter[i][j] += row[i] * row[j];
            }
        }
    }
    let (values, vectors) = symmetric_eigen(&scatter).ok_or(FitError::Overflow)?;
    // Points on a plane satisfy every quadric (plane)·(linear form): a 4-dimensional
    // null space. A unique quadric needs a single (near-)zero eigenvalue.
    if values[1] <= RELATIVE_ZERO * values[9] {
        return Ok(plane);
    }
    let in_unit_frame = Quadric::new(vectors[0]).map_err(|_| FitError::Overflow)?;
    // Back to world coordinates: Q(p) = Q'((p - centroid) / scale).
    let quadric = in_unit_frame.in_frame(-centroid / scale, 1.0 / scale).map_err(|_| FitError::Overflow)?;
    Ok(QuadricFit { quadric, kind: FitKind::Quadric, rms_distance: rms_distance(&quadric, points) })
}

#[cfg(test)]
mod tests {
    extern crate std;
    use std::string::ToString;
    use std::vec::Vec;

    use glam::DMat3;

    use super::*;

    fn sphere_points(center: DVec3, radius: f64, count: usize) -> Vec<DVec3> {
        let golden = 2.399_963_229_728_653;
        (0..count)
            .map(|i| {
                let z = 1.0 - 2.0 * (i as f64 + 0.5) / count as f64;
                let r = libm::sqrt(1.0 - z * z);
                let phi = golden * i as f64;
                center + radius * DVec3::new(r * libm::cos(phi), r * libm::sin(phi), z)
            })
            .collect()
    }

    #[test]
    fn recovers_a_small_sphere() {
        let points = sphere_points(DVec3::new(3.0, -2.0, 1.0), 0.05, 64);
        let fit = fit_quadric(&points).unwrap();
        assert_eq!(fit.kind, FitKind::Quadric);
        assert!(fit.rms_distance < 1e-12, "{}", fit.rms_distance);
    }

    #[test]
    fn recovers_a_far_away_small_sphere() {
        let (center, radius) = (DVec3::new(1000.0, -250.0, 30.0), 0.01);
        let points = sphere_points(center, radius, 64);
        let fit = fit_quadric(&points).unwrap();
        assert_eq!(fit.kind, FitKind::Quadric);
        // Evaluating a world-frame quadric at |p| ≈ 1000 cancels terms of size A|p|² down
        // to a gradient of size 2Ar: the f64 noise floor of |Q|/|∇Q| is ε|p|²/(2r).
        let noise_floor = f64::EPSILON * center.length_squared() / (2.0 * radius);
        assert!(fit.rms_distance < 10.0 * noise_floor, "{} vs floor {noise_floor}", fit.rms_distance);
        // A sphere: equal squared coefficients, no cross terms.
        let [a, b, c, d, e, f, ..] = fit.quadric.coefficients();
        assert!((a - b).abs() < 1e-6 * a.abs() && (a - c).abs() < 1e-6 * a.abs(), "{:?}", fit.quadric);
        assert!(d.abs() + e.abs() + f.abs() < 1e-6 * a.abs());
    }

    #[test]
    fn coplanar_and_few_points_fall_back_to_the_plane() {
        let z = DVec3::new(1.0, 2.0, 3.0).normalize();
        let (x, y) = z.any_orthonormal_pair();
        let frame = DMat3::from_cols(x, y, z);
        let points: Vec<DVec3> = (0..30)
            .map(|i| frame * DVec3::new(libm::sin(f64::from(i) * 1.7), libm::cos(f64::from(i) * 0.9), 0.5))
            .collect();
        let fit = fit_quadric(&points).unwrap();
        assert_eq!(fit.kind, FitKind::Plane);
        assert!(fit.rms_distance < 1e-12);
        assert_eq!(fit_quadric(&points[..8]).unwrap().kind, FitKind::Plane);
    }

    #[test]
    fn each_degenerate_input_has_its_error() {
        use FitError::*;
        assert_eq!(fit_quadric(&[]), Err(TooFewPoints { count: 0 }));
        assert_eq!(fit_plane(&[DVec3::X, DVec3::Y]), Err(TooFewPoints { count: 2 }));
        let mut with_nan = [DVec3::X; 12];
        with_nan[3] = DVec3::NAN;
        assert_eq!(fit_quadric(&with_nan), Err(NonFinitePoint { index: 3 }));
        with_nan[3] = DVec3::new(0.0, f64::NEG_INFINITY, 0.0);
        assert_eq!(fit_plane(&with_nan), Err(NonFinitePoint { index: 3 }));
        assert_eq!(fit_quadric(&[DVec3::ONE; 20]), Err(Coincident));
        assert_eq!(fit_plane(&[DVec3::ONE; 3]), Err(Coincident));
        let line: [DVec3; 12] = core::array::from_fn(|i| DVec3::splat(i as f64));
        assert_eq!(fit_quadric(&line), Err(Collinear));
        assert_eq!(fit_plane(&line[..3]), Err(Collinear));
        let far = [DVec3::splat(1e300), DVec3::new(-1e300, 1e300, 0.0), DVec3::new(0.0, -1e300, 1e300)];
        assert_eq!(fit_plane(&far), Err(Overflow));
        assert_eq!(fit_quadric(&far), Err(Overflow));
        // Three points in general position are a plane.
        assert_eq!(fit_plane(&[DVec3::X, DVec3::Y, DVec3::Z]).map(|f| f.kind), Ok(FitKind::Plane));
        let message = fit_quadric(&with_nan).unwrap_err().to_string();
        assert!(message.contains("point 3"), "{message}");
    }
}
