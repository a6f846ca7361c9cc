//! The 10-coefficient quadric of eq. 1,
//! `Q(x, y, z) = Ax² + By² + Cz² + Dxy + Eyz + Fzx + Gx + Hy + Iz + J`.

use glam::{DMat3, DVec3};

/// Why a quadric (or a patch's quadric) could not be made.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum QuadricError {
    /// A coefficient is NaN or infinite (the first such index, in eq. 1's order).
    NonFiniteCoefficient {
        /// Index in `[A, B, C, D, E, F, G, H, I, J]`.
        index: usize,
    },
    /// Every coefficient is zero: the equation describes no surface.
    ZeroCoefficients,
    /// A plane's normal is the zero vector.
    ZeroNormal,
    /// [`Quadric::in_frame`]'s scale is zero or not finite.
    InvalidScale {
        /// The scale given.
        scale: f64,
    },
    /// A patch corner is NaN or infinite (its index among the corners).
    NonFinitePoint {
        /// Index of the corner.
        index: usize,
    },
    /// The patch's corners are collinear or coincident: they span no surface.
    Degenerate,
}

impl core::fmt::Display for QuadricError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::NonFiniteCoefficient { index } => write!(f, "quadric coefficient {index} is not finite"),
            Self::ZeroCoefficients => write!(f, "every quadric coefficient is zero: no surface"),
            Self::ZeroNormal => write!(f, "the plane's normal is zero"),
            Self::InvalidScale { scale } => write!(f, "frame scale {scale} is zero or not finite"),
            Self::NonFinitePoint { index } => write!(f, "patch corner {index} is not finite"),
            Self::Degenerate => write!(f, "the patch's corners are collinear or coincident"),
        }
    }
}

impl core::error::Error for QuadricError {}

/// A quadric surface `Q(p) = 0` with the coefficients of eq. 1, in double precision.
///
/// Coefficients are in the paper's order `[A, B, C, D, E, F, G, H, I, J]`, finite and not
/// all zero (every constructor checks it, so no function re-checks it). A quadric and any
/// non-zero multiple of it describe the same surface; [`Quadric::normalized`] gives the
/// unit coefficient vector with a non-negative first non-zero coefficient.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quadric {
    coefficients: [f64; 10],
}

impl Quadric {
    /// The quadric with the given coefficients; an error when one is not finite or all are
    /// zero (which describes no surface).
    pub fn new(coefficients: [f64; 10]) -> Result<Self, QuadricError> {
        if let Some(index) = coefficients.iter().position(|c| !c.is_finite()) {
            return Err(QuadricError::NonFiniteCoefficient { index });
        }
        if coefficients.iter().all(|&c| c == 0.0) {
            return Err(QuadricError::ZeroCoefficients);
        }
        Ok(Self { coefficients })
    }

    /// `[A, B, C, D, E, F, G, H, I, J]` of eq. 1.
    pub fn coefficients(&self) -> [f64; 10] {
        self.coefficients
    }

    /// The plane `normal · p + offset = 0` as a (degree-one) quadric, normalized; an error
    /// when `normal` is zero or a value is not finite.
    pub fn plane(normal: DVec3, offset: f64) -> Result<Self, QuadricError> {
        if normal == DVec3::ZERO {
            return Err(QuadricError::ZeroNormal);
        }
        Self::new([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, normal.x, normal.y, normal.z, offset]).map(Self::normalized)
    }

    /// The quadric `pᵀ M p + L · p + J` for a symmetric `M` (its off-diagonal entries are
    /// half the cross coefficients D, E, F); errors as [`Quadric::new`].
    pub fn from_matrix(m: DMat3, l: DVec3, j: f64) -> Result<Self, QuadricError> {
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
    /// result is `Q(origin + scale p')`, normalized. An error when `scale` is zero or not
    /// finite, or the moved coefficients overflow.
    pub fn in_frame(&self, origin: DVec3, scale: f64) -> Result<Self, QuadricError> {
        if !(scale.is_finite() && scale != 0.0) {
            return Err(QuadricError::InvalidScale { scale });
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
        assert_eq!(s.in_frame(origin, 0.0), Err(QuadricError::InvalidScale { scale: 0.0 }));
    }

    #[test]
    fn degenerate_coefficients_are_rejected() {
        assert_eq!(Quadric::new([0.0; 10]), Err(QuadricError::ZeroCoefficients));
        let mut one_nan = [1.0; 10];
        one_nan[3] = f64::NAN;
        assert_eq!(Quadric::new(one_nan), Err(QuadricError::NonFiniteCoefficient { index: 3 }));
        assert_eq!(Quadric::new([f64::INFINITY; 10]), Err(QuadricError::NonFiniteCoefficient { index: 0 }));
        assert_eq!(Quadric::plane(DVec3::ZERO, 1.0), Err(QuadricError::ZeroNormal));
        assert_eq!(Quadric::plane(DVec3::Z, f64::NAN), Err(QuadricError::NonFiniteCoefficient { index: 9 }));
        let mut message = alloc::string::String::new();
        core::fmt::write(&mut message, format_args!("{}", QuadricError::NonFiniteCoefficient { index: 9 })).unwrap();
        assert!(message.contains("coefficient 9"), "{message}");
        assert!(Quadric::plane(DVec3::Z, -0.5).unwrap().is_plane());
    }
}
