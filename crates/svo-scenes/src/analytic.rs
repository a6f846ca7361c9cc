//! Closed analytic shapes with exact signed distances and exact gradients: [`Sphere`],
//! [`Torus`] (axis z) and [`AxisBox`].
//!
//! Where the distance is not differentiable (the sphere's centre, the torus's axis and
//! core circle, the box's inner medial planes), the gradient is a one-sided derivative, or
//! zero at a point of symmetry with no preferred direction.

use glam::{Vec2, Vec3};
use svo_brick::{ATTRIBUTE_CHANNELS, SurfaceSource};

use crate::attribute::Attribute;
use crate::error::{SceneError, check, finite, positive};

/// A sphere of centre `centre` and radius `radius`.
#[derive(Clone, Debug)]
pub struct Sphere {
    centre: Vec3,
    radius: f32,
    attribute: Attribute,
}

impl Sphere {
    /// A sphere; the centre must be finite and the radius finite and positive.
    pub fn new(centre: Vec3, radius: f32, attribute: Attribute) -> Result<Self, SceneError> {
        Ok(Sphere {
            centre: finite("Sphere", "centre", centre)?,
            radius: positive("Sphere", "radius", radius)?,
            attribute,
        })
    }

    /// The centre.
    pub fn centre(&self) -> Vec3 {
        self.centre
    }

    /// The radius.
    pub fn radius(&self) -> f32 {
        self.radius
    }
}

impl SurfaceSource for Sphere {
    fn distance(&self, p: Vec3) -> f32 {
        (p - self.centre).length() - self.radius
    }

    /// `(p − c)/|p − c|`; zero at the centre.
    fn gradient(&self, p: Vec3) -> Vec3 {
        (p - self.centre).normalize_or_zero()
    }

    fn attribute(&self, x: Vec3) -> [f32; ATTRIBUTE_CHANNELS] {
        self.attribute.eval(x)
    }
}

/// A torus about the z axis through `centre`: the points at distance `minor` from the
/// circle of radius `major` in the plane `z = centre.z`.
#[derive(Clone, Debug)]
pub struct Torus {
    centre: Vec3,
    major: f32,
    minor: f32,
    attribute: Attribute,
}

impl Torus {
    /// A ring torus: `0 < minor < major`, both finite (a horn or spindle torus has no exact
    /// distance of this form).
    pub fn new(centre: Vec3, major: f32, minor: f32, attribute: Attribute) -> Result<Self, SceneError> {
        let centre = finite("Torus", "centre", centre)?;
        let major = positive("Torus", "major", major)?;
        let minor = positive("Torus", "minor", minor)?;
        let minor = check("Torus", "minor", minor, minor < major, "below major")?;
        Ok(Torus { centre, major, minor, attribute })
    }

    /// The centre.
    pub fn centre(&self) -> Vec3 {
        self.centre
    }

    /// The radius of the core circle.
    pub fn major(&self) -> f32 {
        self.major
    }

    /// The radius of the tube.
    pub fn minor(&self) -> f32 {
        self.minor
    }

    /// `(ρ − major, z)` in the half-plane through `p` and the axis, and the unit radial
    /// direction (zero on the axis).
    fn section(&self, p: Vec3) -> (Vec2, Vec3) {
        let local = p - self.centre;
        let rho = local.truncate().length();
        let radial = if rho > 0.0 { Vec3::new(local.x / rho, local.y / rho, 0.0) } else { Vec3::ZERO };
        (Vec2::new(rho - self.major, local.z), radial)
    }
}

impl SurfaceSource for Torus {
    fn distance(&self, p: Vec3) -> f32 {
        self.section(p).0.length() - self.minor
    }

    /// `(q.x r̂ + q.y ẑ)/|q|` with `q = (ρ − major, z)`; on the axis the radial part is
    /// zero, on the core circle the whole gradient.
    fn gradient(&self, p: Vec3) -> Vec3 {
        let (q, radial) = self.section(p);
        let length = q.length();
        if length > 0.0 { (radial * q.x + Vec3::Z * q.y) / length } else { Vec3::ZERO }
    }

    fn attribute(&self, x: Vec3) -> [f32; ATTRIBUTE_CHANNELS] {
        self.attribute.eval(x)
    }
}

/// An axis-aligned box of centre `centre` and half extents `half_extent`, with sharp edges.
#[derive(Clone, Debug)]
pub struct AxisBox {
    centre: Vec3,
    half_extent: Vec3,
    attribute: Attribute,
}

impl AxisBox {
    /// A box; the centre must be finite and every half extent finite and positive.
    pub fn new(centre: Vec3, half_extent: Vec3, attribute: Attribute) -> Result<Self, SceneError> {
        let centre = finite("AxisBox", "centre", centre)?;
        let positive_extent = half_extent.is_finite() && half_extent.min_element() > 0.0;
        let half_extent = check("AxisBox", "half_extent", half_extent, positive_extent, "finite and positive")?;
        Ok(AxisBox { centre, half_extent, attribute })
    }

    /// The centre.
    pub fn centre(&self) -> Vec3 {
        self.centre
    }

    /// The half extents.
    pub fn half_extent(&self) -> Vec3 {
        self.half_extent
    }
}

impl SurfaceSource for AxisBox {
    /// `|max(q, 0)| + min(max(qx, qy, qz), 0)` with `q = |p − c| − half_extent`.
    fn distance(&self, p: Vec3) -> f32 {
        let q = (p - self.centre).abs() - self.half_extent;
        q.max(Vec3::ZERO).length() + q.max_element().min(0.0)
    }

    /// Outside, `sign(p − c) · max(q, 0)/|max(q, 0)|`; inside, `±` the axis of the nearest
    /// face (the first one on a tie, a one-sided derivative on the inner medial planes).
    fn gradient(&self, p: Vec3) -> Vec3 {
        let local = p - self.centre;
        let sign = Vec3::select(local.cmplt(Vec3::ZERO), Vec3::NEG_ONE, Vec3::ONE);
        let q = local.abs() - self.half_extent;
        let outside = q.max(Vec3::ZERO);
        if outside != Vec3::ZERO {
            return sign * outside / outside.length();
        }
        let axis = if q.x >= q.y && q.x >= q.z {
            Vec3::X
        } else if q.y >= q.z {
            Vec3::Y
        } else {
            Vec3::Z
        };
        sign * axis
    }

    fn attribute(&self, x: Vec3) -> [f32; ATTRIBUTE_CHANNELS] {
        self.attribute.eval(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::{assert_gradient_matches, assert_lipschitz};

    fn close(a: f32, b: f32) -> bool {
        (a - b).abs() <= 1e-6 * (1.0 + b.abs())
    }

    #[test]
    fn sphere_distances_are_exact() {
        let sphere = Sphere::new(Vec3::new(1.0, 2.0, 3.0), 2.0, Attribute::grey()).unwrap();
        let c = sphere.centre();
        assert!(close(sphere.distance(c + Vec3::new(3.0, 0.0, 0.0)), 1.0));
        assert!(close(sphere.distance(c + Vec3::new(0.0, 1.0, 0.0)), -1.0));
        assert!(close(sphere.distance(c), -2.0));
        assert_eq!(sphere.gradient(c + Vec3::new(0.0, 0.0, 5.0)), Vec3::Z);
        assert_eq!(sphere.gradient(c), Vec3::ZERO);
        assert!(Sphere::new(Vec3::ZERO, 0.0, Attribute::grey()).unwrap_err().to_string().contains("Sphere.radius"));
        assert!(Sphere::new(Vec3::NAN, 1.0, Attribute::grey()).unwrap_err().to_string().contains("Sphere.centre"));
    }

    #[test]
    fn torus_distances_are_exact() {
        let torus = Torus::new(Vec3::ZERO, 2.0, 0.5, Attribute::grey()).unwrap();
        assert!(close(torus.distance(Vec3::new(2.0, 0.0, 0.0)), -0.5));
        assert!(close(torus.distance(Vec3::new(0.0, 3.0, 0.0)), 0.5));
        assert!(close(torus.distance(Vec3::new(-2.0, 0.0, 1.0)), 0.5));
        assert!(close(torus.distance(Vec3::ZERO), 1.5));
        assert!(close(torus.distance(Vec3::new(0.0, 0.0, 1.0)), 5f32.sqrt() - 0.5));
        assert!(torus.gradient(Vec3::new(0.0, 3.0, 0.0)).abs_diff_eq(Vec3::Y, 1e-6));
        assert!(torus.gradient(Vec3::new(0.0, 0.0, 1.0)).abs_diff_eq(Vec3::new(0.0, 0.0, 5f32.sqrt().recip()), 1e-6));
        let error = Torus::new(Vec3::ZERO, 1.0, 1.0, Attribute::grey()).unwrap_err();
        assert!(error.to_string().contains("Torus.minor"), "{error}");
    }

    #[test]
    fn box_distances_are_exact() {
        let b = AxisBox::new(Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0), Attribute::grey()).unwrap();
        assert!(close(b.distance(Vec3::new(2.0, 0.0, 0.0)), 1.0));
        assert!(close(b.distance(Vec3::new(-2.0, 3.0, 0.0)), 2f32.sqrt()));
        assert!(close(b.distance(Vec3::new(2.0, -3.0, 4.0)), 3f32.sqrt()));
        assert!(close(b.distance(Vec3::ZERO), -1.0));
        assert!(close(b.distance(Vec3::new(0.0, 1.5, 0.0)), -0.5));
        assert_eq!(b.gradient(Vec3::new(0.0, -1.5, 0.0)), -Vec3::Y);
        assert!(b.gradient(Vec3::new(2.0, -3.0, 4.0)).abs_diff_eq(Vec3::new(1.0, -1.0, 1.0) / 3f32.sqrt(), 1e-6));
        let error = AxisBox::new(Vec3::ZERO, Vec3::new(1.0, 0.0, 1.0), Attribute::grey()).unwrap_err();
        assert!(error.to_string().contains("AxisBox.half_extent"), "{error}");
    }

    #[test]
    fn shapes_are_1_lipschitz_with_unit_gradients() {
        let (min, max) = (Vec3::splat(-4.0), Vec3::splat(4.0));
        let sphere = Sphere::new(Vec3::new(0.5, 0.0, 0.0), 2.0, Attribute::grey()).unwrap();
        let torus = Torus::new(Vec3::ZERO, 2.0, 0.5, Attribute::grey()).unwrap();
        let b = AxisBox::new(Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0), Attribute::grey()).unwrap();
        for worst in [
            assert_lipschitz(&sphere, min, max, 10_000, 1),
            assert_lipschitz(&torus, min, max, 10_000, 2),
            assert_lipschitz(&b, min, max, 10_000, 3),
        ] {
            // Exact distances: some pairs come close to ratio 1.
            assert!(worst > 0.99, "{worst}");
        }
    }

    #[test]
    fn gradients_equal_finite_differences() {
        let (min, max) = (Vec3::splat(-4.0), Vec3::splat(4.0));
        let sphere = Sphere::new(Vec3::new(0.5, 0.0, 0.0), 2.0, Attribute::grey()).unwrap();
        let n = assert_gradient_matches(&sphere, min, max, 500, 1e-3, 2e-3, |p| p.distance(sphere.centre()) > 0.1);
        assert!(n > 450);
        let torus = Torus::new(Vec3::ZERO, 2.0, 0.5, Attribute::grey()).unwrap();
        let smooth = |p: Vec3| p.truncate().length() > 0.1 && (torus.distance(p) + 0.5) > 0.1;
        assert!(assert_gradient_matches(&torus, min, max, 500, 1e-3, 2e-3, smooth) > 400);
        let b = AxisBox::new(Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0), Attribute::grey()).unwrap();
        let smooth = |p: Vec3| {
            let mut q = (p.abs() - b.half_extent()).to_array();
            q.sort_by(f32::total_cmp);
            // Off the inner medial planes, and off the edges (where two q are near 0).
            (q[2] - q[1]).abs() > 0.01 && !(q[1] > -0.01 && q[1] < 0.01) && p.abs().min_element() > 0.01
        };
        assert!(assert_gradient_matches(&b, min, max, 500, 1e-3, 2e-3, smooth) > 400);
    }
}
