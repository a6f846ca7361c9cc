//! Flat shapes: the half-space [`Plane`] (the base of displaced planes) and the thin slab
//! [`Plate`], infinite or a disk with sharp rims (the thin parts that break H7).

use glam::{Vec2, Vec3};
use svo_brick::{ATTRIBUTE_CHANNELS, SurfaceSource};

use crate::attribute::Attribute;
use crate::error::{SceneError, check, finite, positive};

/// A unit normal from a finite, non-zero vector.
fn unit_normal(owner: &'static str, normal: Vec3) -> Result<Vec3, SceneError> {
    let unit = normal.try_normalize();
    check(owner, "normal", normal, unit.is_some(), "finite and non-zero")?;
    Ok(unit.unwrap_or(Vec3::Z))
}

/// The half-space below the plane through `point` with outward normal `normal`: the
/// distance is `n·(p − point)`, negative on the side opposite the normal.
#[derive(Clone, Debug)]
pub struct Plane {
    point: Vec3,
    normal: Vec3,
    attribute: Attribute,
}

impl Plane {
    /// A plane; `normal` (normalised here) must be finite and non-zero.
    pub fn new(point: Vec3, normal: Vec3, attribute: Attribute) -> Result<Self, SceneError> {
        Ok(Plane { point: finite("Plane", "point", point)?, normal: unit_normal("Plane", normal)?, attribute })
    }

    /// A point of the plane.
    pub fn point(&self) -> Vec3 {
        self.point
    }

    /// The unit outward normal.
    pub fn normal(&self) -> Vec3 {
        self.normal
    }
}

impl SurfaceSource for Plane {
    fn distance(&self, p: Vec3) -> f32 {
        self.normal.dot(p - self.point)
    }

    fn gradient(&self, _p: Vec3) -> Vec3 {
        self.normal
    }

    fn attribute(&self, x: Vec3) -> [f32; ATTRIBUTE_CHANNELS] {
        self.attribute.eval(x)
    }
}

/// A slab of thickness `2 · half_thickness` about the plane through `centre` normal to
/// `normal`: infinite ([`Plate::infinite`]), or bounded to a disk of radius `radius` about
/// `centre` with sharp rims ([`Plate::disk`], a flat cylinder).
#[derive(Clone, Debug)]
pub struct Plate {
    centre: Vec3,
    normal: Vec3,
    half_thickness: f32,
    radius: f32,
    attribute: Attribute,
}

impl Plate {
    /// An infinite slab; `normal` (normalised here) must be finite and non-zero and
    /// `half_thickness` finite and positive.
    pub fn infinite(centre: Vec3, normal: Vec3, half_thickness: f32, attribute: Attribute) -> Result<Self, SceneError> {
        let centre = finite("Plate", "centre", centre)?;
        let normal = unit_normal("Plate", normal)?;
        let half_thickness = positive("Plate", "half_thickness", half_thickness)?;
        Ok(Plate { centre, normal, half_thickness, radius: f32::INFINITY, attribute })
    }

    /// A disk-shaped slab of radius `radius` (finite and positive).
    pub fn disk(
        centre: Vec3,
        normal: Vec3,
        half_thickness: f32,
        radius: f32,
        attribute: Attribute,
    ) -> Result<Self, SceneError> {
        let radius = positive("Plate", "radius", radius)?;
        Ok(Plate { radius, ..Plate::infinite(centre, normal, half_thickness, attribute)? })
    }

    /// The centre.
    pub fn centre(&self) -> Vec3 {
        self.centre
    }

    /// The unit normal.
    pub fn normal(&self) -> Vec3 {
        self.normal
    }

    /// Half the thickness.
    pub fn half_thickness(&self) -> f32 {
        self.half_thickness
    }

    /// The disk's radius, infinite for an infinite slab.
    pub fn radius(&self) -> f32 {
        self.radius
    }

    /// `(ρ − radius, |a| − half_thickness)` with `a` the height above the mid-plane and `ρ`
    /// the distance to the normal through the centre; the unit radial direction (zero on
    /// that line) and the side `sign(a)`.
    fn section(&self, p: Vec3) -> (Vec2, Vec3, f32) {
        let local = p - self.centre;
        let a = self.normal.dot(local);
        let side = if a < 0.0 { -1.0 } else { 1.0 };
        if self.radius.is_infinite() {
            return (Vec2::new(f32::NEG_INFINITY, a.abs() - self.half_thickness), Vec3::ZERO, side);
        }
        let in_plane = local - self.normal * a;
        let rho = in_plane.length();
        let radial = if rho > 0.0 { in_plane / rho } else { Vec3::ZERO };
        (Vec2::new(rho - self.radius, a.abs() - self.half_thickness), radial, side)
    }
}

impl SurfaceSource for Plate {
    /// The exact distance of the 2D rectangle `q = (ρ − radius, |a| − half_thickness)`:
    /// `|max(q, 0)| + min(max(qx, qy), 0)` (`|a| − half_thickness` when infinite).
    fn distance(&self, p: Vec3) -> f32 {
        let (q, _, _) = self.section(p);
        if self.radius.is_infinite() {
            return q.y;
        }
        q.max(Vec2::ZERO).length() + q.max_element().min(0.0)
    }

    /// Outside, `(max(qx, 0) r̂ + max(qy, 0) sign(a) n)/|max(q, 0)|`; inside, the direction
    /// of the nearer of the rim (`r̂`) and the faces (`sign(a) n`).
    fn gradient(&self, p: Vec3) -> Vec3 {
        let (q, radial, side) = self.section(p);
        let outside = q.max(Vec2::ZERO);
        if outside != Vec2::ZERO {
            (radial * outside.x + self.normal * (side * outside.y)) / outside.length()
        } else if q.x > q.y {
            radial
        } else {
            self.normal * side
        }
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
    fn plane_and_plate_distances_are_exact() {
        let plane = Plane::new(Vec3::new(0.0, 0.0, 1.0), Vec3::new(0.0, 0.0, 3.0), Attribute::grey()).unwrap();
        assert!(close(plane.distance(Vec3::new(4.0, -2.0, 0.5)), -0.5));
        assert_eq!(plane.gradient(Vec3::ZERO), Vec3::Z);
        let slab = Plate::infinite(Vec3::ZERO, Vec3::new(0.0, 0.0, 2.0), 0.1, Attribute::grey()).unwrap();
        assert!(close(slab.distance(Vec3::new(5.0, -3.0, 0.3)), 0.2));
        assert!(close(slab.distance(Vec3::new(5.0, -3.0, -0.3)), 0.2));
        assert!(close(slab.distance(Vec3::ZERO), -0.1));
        assert_eq!(slab.gradient(Vec3::new(1.0, 1.0, -0.05)), -Vec3::Z);
        let disk = Plate::disk(Vec3::ZERO, Vec3::Z, 0.1, 1.0, Attribute::grey()).unwrap();
        assert!(close(disk.distance(Vec3::new(2.0, 0.0, 0.0)), 1.0));
        assert!(close(disk.distance(Vec3::new(0.0, 0.0, 1.0)), 0.9));
        assert!(close(disk.distance(Vec3::new(0.0, -2.0, 1.1)), 2f32.sqrt()));
        assert!(close(disk.distance(Vec3::new(0.95, 0.0, 0.0)), -0.05));
        assert_eq!(disk.gradient(Vec3::new(0.0, 0.95, 0.0)), Vec3::Y);
        let error = Plate::disk(Vec3::ZERO, Vec3::ZERO, 0.1, 1.0, Attribute::grey()).unwrap_err();
        assert!(error.to_string().contains("Plate.normal"), "{error}");
        let error = Plate::disk(Vec3::ZERO, Vec3::Z, 0.1, f32::INFINITY, Attribute::grey()).unwrap_err();
        assert!(error.to_string().contains("Plate.radius"), "{error}");
    }

    #[test]
    fn flat_shapes_are_1_lipschitz_and_their_gradients_exact() {
        let (min, max) = (Vec3::splat(-2.0), Vec3::splat(2.0));
        let normal = Vec3::new(1.0, 2.0, 3.0).normalize();
        let slab = Plate::infinite(Vec3::new(0.1, 0.0, 0.0), normal, 0.2, Attribute::grey()).unwrap();
        let disk = Plate::disk(Vec3::new(0.1, 0.0, 0.0), normal, 0.2, 1.0, Attribute::grey()).unwrap();
        let plane = Plane::new(Vec3::ZERO, normal, Attribute::grey()).unwrap();
        assert!(assert_lipschitz(&slab, min, max, 10_000, 4) > 0.99);
        assert!(assert_lipschitz(&disk, min, max, 10_000, 5) > 0.99);
        assert!(assert_lipschitz(&plane, min, max, 10_000, 6) > 0.99);
        let smooth_slab = |p: Vec3| normal.dot(p - slab.centre()).abs() > 0.01;
        assert!(assert_gradient_matches(&slab, min, max, 300, 1e-3, 2e-3, smooth_slab) > 250);
        let smooth_disk = |p: Vec3| {
            let (q, _, _) = disk.section(p);
            // Off the inner medial cone, the rims and the axis.
            smooth_slab(p) && (q.x - q.y).abs() > 0.01 && q.x.abs() > 0.01 && q.y.abs() > 0.01 && q.x > -0.99
        };
        assert!(assert_gradient_matches(&disk, min, max, 300, 1e-3, 2e-3, smooth_disk) > 200);
    }
}
