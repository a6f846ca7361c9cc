//! The 10-coefficient quadric of eq. 1,
//! `Q(x, y, z) = Ax² + By² + Cz² + Dxy + Eyz + Fzx + Gx + Hy + Iz + J`.

use glam::{DMat3, DVec3};

/// A quadric surface `Q(p) = 0` with the coefficients of eq. 1, in double precision.
///
/// Coefficients are stored in the paper's order `[A, B, C, D, E, F, G, H, I, J]`.
/// A quadric and any non-zero multiple of it describe the same surface; constructors
/// return it normalized to a unit coefficient vector (see [`Quadric::normalized`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quadric {
    /// `[A, B, C, D, E, F, G, H, I, J]` of eq. 1.
    pub coefficients: [f64; 10],
}

impl Quadric {
    /// The quadric with the given coefficients, or `None` if one is not finite or all are
    /// zero (which describes no surface).
    pub fn new(coefficients: [f64; 10]) -> Option<Self> {
        let finite = coefficients.iter().all(|c| c.is_finite());
        let nonzero = coefficients.iter().any(|&c| c != 0.0);
        (finite && nonzero).then_some(Self { coefficients })
    }

    /// The plane `normal · p + offset = 0` as a (degree-one) quadric, or `None` when
    /// `normal` is zero or a value is not finite.
    pub fn plane(normal: DVec3, offset: f64) -> Option<Self> {
        if normal == DVec3::ZERO {
            return None;
        }
        Self::new([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, normal.x, normal.y, normal.z, offset]).map(Self::normalized)
    }

    /// The quadric `pᵀ M p + L · p + J` for a symmetric `M` (its off-diagonal entries are
    /// half the cross coefficients D, E, F).
    pub fn from_matrix(m: DMat3, l: DVec3, j: f64) -> Option<Self> {
        let c = [
            m.x_axis.x,
            m.y_axis.y,
            m.z_axis.z,
            2.0 * m.x_axis.y,
            2.0 * m.y_axis.z,
            2.0 * m.x_axis.z,
            l.x,
            l.y,
            l.z,
            j,
        ];
        Self::new(c)
    }

    /// The symmetric matrix `M` of the quadratic part.
    pub fn quadratic_matrix(&self) -> DMat3 {
        let [a, b, c, d, e, f, ..] = self.coefficients;
        DMat3::from_cols(
            DVec3::new(a, d / 2.0, f / 2.0),
            DVec3::new(d / 2.0, b, e / 2.0),
            DVec3::new(f / 2.0, e / 2.0, c),
        )
    }

    /// The linear part `L = (G, H, I)`.
    pub fn linear(&self) -> DVec3 {
        DVec3::new(self.coefficients[6], self.coefficients[7], self.coefficients[8])
    }

    /// The constant `J`.
    pub fn constant(&self) -> f64 {
        self.coefficients[9]
    }

    /// `Q(p)`.
    pub fn value(&self, p: DVec3) -> f64 {
        let [a, b, c, d, e, f, g, h, i, j] = self.coefficients;
        a * p.x * p.x
            + b * p.y * p.y
            + c * p.z * p.z
            + d * p.x * p.y
            + e * p.y * p.z
            + f * p.z * p.x
            + g * p.x
            + h * p.y
            + i * p.z
            + j
    }

    /// `∇Q(p) = 2Mp + L`, normal to the surface at a point of it.
    pub fn gradient(&self, p: DVec3) -> DVec3 {
        2.0 * (self.quadratic_matrix() * p) + self.linear()
    }

    /// First-order distance estimate `|Q(p)| / |∇Q(p)|` (Taubin 1991), or `None` where
    /// the gradient vanishes.
    pub fn distance_estimate(&self, p: DVec3) -> Option<f64> {
        let g = self.gradient(p).length();
        (g > 0.0).then(|| self.value(p).abs() / g)
    }

    /// The same surface with a unit coefficient vector and a non-negative first non-zero
    /// coefficient (so that equal surfaces compare equal).
    pub fn normalized(self) -> Self {
        let norm = libm::sqrt(self.coefficients.iter().map(|c| c * c).sum::<f64>());
        let sign = self.coefficients.iter().find(|&&c| c != 0.0).map_or(1.0, |c| c.signum());
        Self { coefficients: self.coefficients.map(|c| c * sign / norm) }
    }

    /// The quadric in coordinates `p' = (p - origin) / scale`: if `self` is `Q(p)`, the
    /// result is `Q(origin + scale p')`. `None` if `scale` is zero or not finite.
    pub fn in_frame(&self, origin: DVec3, scale: f64) -> Option<Self> {
        if !(scale.is_finite() && scale != 0.0) {
            return None;
        }
        // Q(o + s p') = s² p'ᵀMp' + s (2Mo + L)·p' + Q(o)
        let m = self.quadratic_matrix() * (scale * scale);
        let l = self.gradient(origin) * scale;
        Self::from_matrix(m, l, self.value(origin)).map(Self::normalized)
    }

    /// Whether the quadratic part is exactly zero (the quadric is a plane).
    pub fn is_plane(&self) -> bool {
        self.coefficients[..6].iter().all(|&c| c == 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_sphere() -> Quadric {
        Quadric::new([1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0]).unwrap()
    }

    #[test]
    fn value_and_gradient_of_a_sphere() {
        let s = unit_sphere();
        assert_eq!(s.value(DVec3::X), 0.0);
        assert_eq!(s.gradient(DVec3::Y), DVec3::new(0.0, 2.0, 0.0));
        assert!((s.distance_estimate(DVec3::new(0.0, 0.0, 1.1)).unwrap() - 0.0954).abs() < 1e-3);
    }

    #[test]
    fn change_of_frame_keeps_the_surface() {
        let s = unit_sphere();
        let (origin, scale) = (DVec3::new(0.5, -2.0, 1.0), 0.25);
        let t = s.in_frame(origin, scale).unwrap();
        for p in [DVec3::X, DVec3::new(0.0, 0.6, 0.8), DVec3::new(-0.48, 0.0, 0.6 * 1.46)] {
            let q = (p - origin) / scale;
            let expected = s.value(p) / libm::sqrt(s.coefficients.iter().map(|c| c * c).sum());
            let ratio = t.value(q) / expected.max(1e-300);
            assert!(s.value(p).abs() < 1e-12 || ratio.is_finite(), "{p}");
            if s.value(p).abs() < 1e-12 {
                assert!(t.value(q).abs() < 1e-9, "{p} -> {q}: {}", t.value(q));
            }
        }
        assert!(s.in_frame(origin, 0.0).is_none());
    }

    #[test]
    fn degenerate_coefficients_are_rejected() {
        assert!(Quadric::new([0.0; 10]).is_none());
        assert!(Quadric::new([f64::NAN; 10]).is_none());
        assert!(Quadric::plane(DVec3::ZERO, 1.0).is_none());
        assert!(Quadric::plane(DVec3::Z, -0.5).unwrap().is_plane());
    }
}
