//! Pixel cones (§4.1–4.2): a pinhole or thin-lens camera gives each pixel one cone whose
//! width grows with distance.

use glam::Vec3;

/// A thin lens for depth of field.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lens {
    /// The aperture's diameter `A` (world units).
    pub aperture: f32,
    /// The distance `f` of the plane in focus.
    pub focus: f32,
}

/// A perspective camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    position: Vec3,
    right: Vec3,
    up: Vec3,
    forward: Vec3,
    pixel_size: f32,
    width: u32,
    height: u32,
    lens: Option<Lens>,
}

/// Why a camera could not be made.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CameraError {
    /// The eye, target or up vector is not finite, the eye equals the target, or up is
    /// parallel to the view direction.
    Frame,
    /// The vertical field of view is not in `(0, π)` radians.
    FieldOfView(f32),
    /// The image has no pixels.
    Size(u32, u32),
    /// The lens' aperture is negative or its focus not positive (or not finite).
    Lens(Lens),
}

impl core::fmt::Display for CameraError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            CameraError::Frame => write!(f, "camera eye, target and up do not define a frame"),
            CameraError::FieldOfView(fov) => write!(f, "field of view {fov} rad is not in (0, π)"),
            CameraError::Size(w, h) => write!(f, "image size {w}×{h} has no pixels"),
            CameraError::Lens(lens) => write!(f, "lens aperture {} / focus {} invalid", lens.aperture, lens.focus),
        }
    }
}

impl core::error::Error for CameraError {}

impl Camera {
    /// A camera at `eye` looking at `target`, `up` giving the image's vertical, with a
    /// vertical field of view `fov_y` (radians) and `width × height` pixels.
    pub fn look_at(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        fov_y: f32,
        width: u32,
        height: u32,
    ) -> Result<Self, CameraError> {
        if !(eye.is_finite() && target.is_finite() && up.is_finite()) {
            return Err(CameraError::Frame);
        }
        let forward = (target - eye).try_normalize().ok_or(CameraError::Frame)?;
        let right = forward.cross(up).try_normalize().ok_or(CameraError::Frame)?;
        let up = right.cross(forward);
        if !(fov_y > 0.0 && fov_y < core::f32::consts::PI) {
            return Err(CameraError::FieldOfView(fov_y));
        }
        if width == 0 || height == 0 {
            return Err(CameraError::Size(width, height));
        }
        let pixel_size = 2.0 * libm::tanf(0.5 * fov_y) / height as f32;
        Ok(Self { position: eye, right, up, forward, pixel_size, width, height, lens: None })
    }

    /// The same camera with a thin lens (depth of field).
    pub fn with_lens(self, lens: Lens) -> Result<Self, CameraError> {
        if !(lens.aperture >= 0.0 && lens.aperture.is_finite() && lens.focus > 0.0 && lens.focus.is_finite()) {
            return Err(CameraError::Lens(lens));
        }
        Ok(Self { lens: Some(lens), ..self })
    }

    /// The image size.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// The eye.
    pub fn position(&self) -> Vec3 {
        self.position
    }

    /// The image's right axis.
    pub fn right(&self) -> Vec3 {
        self.right
    }

    /// The image's up axis.
    pub fn up(&self) -> Vec3 {
        self.up
    }

    /// The view axis.
    pub fn forward(&self) -> Vec3 {
        self.forward
    }

    /// The lens, if any.
    pub fn lens(&self) -> Option<Lens> {
        self.lens
    }

    /// The pixel's side at unit distance along the view axis.
    pub fn pixel_size(&self) -> f32 {
        self.pixel_size
    }

    /// The cone of pixel `(x, y)` (`y` down), through the pixel's centre.
    pub fn pixel_cone(&self, x: u32, y: u32) -> Cone {
        let u = (x as f32 + 0.5 - 0.5 * self.width as f32) * self.pixel_size;
        let v = (0.5 * self.height as f32 - (y as f32 + 0.5)) * self.pixel_size;
        let ray = self.forward + self.right * u + self.up * v;
        let length = ray.length();
        let direction = ray / length;
        // The footprint's axes: the image's right and up, made orthogonal to the ray, so
        // that the masks of successive elements share one frame.
        let right = (self.right - direction * self.right.dot(direction)).normalize();
        let up = direction.cross(right);
        // Per unit distance along the ray the pixel spans pixel_size / length of the image
        // plane at distance 1 along the axis, foreshortened: length⁻¹ per unit along the ray
        // (the pixel's solid angle shrinks off axis); keep the on-axis width for a square
        // footprint.
        let spread = self.pixel_size / length;
        Cone { origin: self.position, direction, right, up, spread, lens: self.lens }
    }
}

/// One pixel's cone: an apex (the lens centre), a unit axis, the footprint frame and the
/// width `w(z) = z s + A |z − f| / f` (§4.1; the lens term with a thin lens of aperture `A`
/// focused at `f`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cone {
    /// The apex.
    pub origin: Vec3,
    /// The unit axis.
    pub direction: Vec3,
    /// The footprint's first axis (unit, ⟂ `direction`).
    pub right: Vec3,
    /// The footprint's second axis (unit, ⟂ both).
    pub up: Vec3,
    /// The pixel's width per unit distance `s`.
    pub spread: f32,
    /// The lens, if any.
    pub lens: Option<Lens>,
}

impl Cone {
    /// The width at distance `z` along the axis.
    pub fn width(&self, z: f32) -> f32 {
        let pinhole = z * self.spread;
        match self.lens {
            Some(lens) => pinhole + lens.aperture * libm::fabsf(z - lens.focus) / lens.focus,
            None => pinhole,
        }
    }

    /// Whether the rays of the footprint have crossed the axis at `z`: past the focal plane,
    /// the lens' rays through a footprint point `ω` arrive at `−ω` (the image of the lens is
    /// inverted), so the footprint's mask is turned by π there. (The paper is silent; a 2D
    /// mask cannot hold the 4D pixel × lens ray family, and this keeps the correlation of
    /// successive elements along each axis-symmetric half of it.)
    pub fn crossed(&self, z: f32) -> bool {
        self.lens.is_some_and(|lens| lens.aperture > 0.0 && z > lens.focus)
    }

    /// The point at distance `z` on the axis.
    pub fn point(&self, z: f32) -> Vec3 {
        self.origin + self.direction * z
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_centre_pixel_looks_forward_and_cones_widen_linearly() {
        let camera = Camera::look_at(Vec3::ZERO, Vec3::Z * 5.0, Vec3::Y, 0.5, 64, 64).unwrap();
        let cone = camera.pixel_cone(32, 32);
        assert!((cone.direction - Vec3::Z).length() < 0.01);
        assert!((cone.width(2.0) - 2.0 * cone.width(1.0)).abs() < 1e-6);
        assert!(cone.right.dot(cone.direction).abs() < 1e-6 && cone.up.dot(cone.direction).abs() < 1e-6);
        let lens = camera.with_lens(Lens { aperture: 0.1, focus: 2.0 }).unwrap().pixel_cone(32, 32);
        assert!(lens.width(2.0) < lens.width(1.0) && lens.width(2.0) < lens.width(3.0));
        assert!(!lens.crossed(1.9) && lens.crossed(2.1));
    }

    #[test]
    fn bad_cameras_are_errors() {
        assert_eq!(Camera::look_at(Vec3::ZERO, Vec3::ZERO, Vec3::Y, 0.5, 8, 8), Err(CameraError::Frame));
        assert_eq!(Camera::look_at(Vec3::ZERO, Vec3::Y, Vec3::Y, 0.5, 8, 8), Err(CameraError::Frame));
        assert_eq!(Camera::look_at(Vec3::ZERO, Vec3::Z, Vec3::Y, 4.0, 8, 8), Err(CameraError::FieldOfView(4.0)));
        assert_eq!(Camera::look_at(Vec3::ZERO, Vec3::Z, Vec3::Y, 0.5, 0, 8), Err(CameraError::Size(0, 8)));
        let camera = Camera::look_at(Vec3::ZERO, Vec3::Z, Vec3::Y, 0.5, 8, 8).unwrap();
        assert!(camera.with_lens(Lens { aperture: -1.0, focus: 1.0 }).is_err());
    }
}
