//! The orthographic camera of each precomputed view, and the mapping between points of a
//! grain and texels of a view (§4.2: "the view index represents a direction and the
//! texel coordinate a position offset").
//!
//! # Conventions (shared by the baker, the samplers and their WGSL twins)
//!
//! - View `i` has the unit direction `ω = OctahedralViews::view_direction(i)`, pointing
//!   from the grain centre **toward** the camera: the camera looks along `-ω`. A camera
//!   ray with direction `r` (in the grain's local frame) therefore samples the views
//!   nearest to `-r`.
//! - The view plane passes through the grain centre, perpendicular to `ω`, with the
//!   orthonormal, right-handed basis `(right, up, ω)` of [`ViewFrame::from_direction`]
//!   (`right × up = ω`).
//! - A view covers the square `[-R, R]²` of its plane, `R` the grain's outer radius (or
//!   any extent chosen at bake time): texture coordinate `(0, 0)` is the top-left corner
//!   (`-R·right + R·up`), `(1, 1)` the bottom-right one, as texture rows are stored top
//!   to bottom.
//! - Depth is the signed distance `dot(q, ω) / R` of a point `q` (relative to the centre)
//!   in front of the plane: `+1` is the point of the outer sphere nearest to the camera.

use glam::{Vec2, Vec3};

/// The orthographic camera frame of one precomputed view: an orthonormal, right-handed
/// basis with `right × up = direction`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewFrame {
    /// The view plane's horizontal axis (texture `u` grows along it).
    pub right: Vec3,
    /// The view plane's vertical axis (texture `v` grows against it).
    pub up: Vec3,
    /// The unit view direction `ω`, from the grain centre toward the camera.
    pub direction: Vec3,
}

impl ViewFrame {
    /// The frame of the unit direction `direction`, or `None` when `direction` is not
    /// finite or not unit length within `1e-4`.
    ///
    /// The basis is the branch-free construction of Duff et al., *Building an Orthonormal
    /// Basis, Revisited* (JCGT 2017), listing 3, with the sign of `z` taken by
    /// `z >= 0` (so `-0.0` uses the upper branch). It is continuous everywhere except
    /// across `z = 0`, which does not matter here: each view has its own frame, and
    /// samplers compute texel coordinates per view.
    pub fn from_direction(direction: Vec3) -> Option<Self> {
        if !direction.is_finite() || (direction.length_squared() - 1.0).abs() > 2e-4 {
            return None;
        }
        Some(Self::from_unit_direction(direction))
    }

    /// [`from_direction`](Self::from_direction) without the unit-length check, for
    /// directions known to be unit (the views of a layout). Mirrored by the WGSL
    /// `octahedral_view_frame`.
    pub(crate) fn from_unit_direction(direction: Vec3) -> Self {
        let Vec3 { x, y, z } = direction;
        let sign = if z >= 0.0 { 1.0 } else { -1.0 };
        let a = -1.0 / (sign + z);
        let b = x * y * a;
        let right = Vec3::new(1.0 + sign * x * x * a, sign * b, -sign * x);
        let up = Vec3::new(b, sign + y * y * a, -y);
        Self { right, up, direction }
    }

    /// The texture coordinates in `[0, 1]²` (for points inside the square) of the
    /// orthographic projection of `point` (relative to the grain centre) on this view,
    /// whose square has half-size `extent`.
    pub fn texture_coordinates(&self, point: Vec3, extent: f32) -> Vec2 {
        let scale = 0.5 / extent;
        Vec2::new(0.5 + point.dot(self.right) * scale, 0.5 - point.dot(self.up) * scale)
    }

    /// The signed depth `dot(point, ω) / extent` of `point` in front of the view plane.
    pub fn depth(&self, point: Vec3, extent: f32) -> f32 {
        point.dot(self.direction) / extent
    }

    /// The point (relative to the grain centre) at texture coordinates `uv` and signed
    /// depth `depth`, the inverse of [`texture_coordinates`](Self::texture_coordinates)
    /// and [`depth`](Self::depth).
    pub fn point_at(&self, uv: Vec2, depth: f32, extent: f32) -> Vec3 {
        let offset_right = (uv.x - 0.5) * 2.0 * extent;
        let offset_up = (0.5 - uv.y) * 2.0 * extent;
        self.right * offset_right + self.up * offset_up + self.direction * (depth * extent)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::OctahedralViews;

    fn assert_orthonormal(frame: &ViewFrame) {
        for axis in [frame.right, frame.up, frame.direction] {
            assert!((axis.length() - 1.0).abs() < 1e-5, "{frame:?}");
        }
        assert!(frame.right.dot(frame.up).abs() < 1e-5, "{frame:?}");
        assert!(frame.right.dot(frame.direction).abs() < 1e-5, "{frame:?}");
        assert!(frame.up.dot(frame.direction).abs() < 1e-5, "{frame:?}");
        assert!(frame.right.cross(frame.up).distance(frame.direction) < 1e-5, "{frame:?}");
    }

    #[test]
    fn every_view_of_several_layouts_has_an_orthonormal_right_handed_frame() {
        for n in [1, 2, 3, 8, 10, 12, 33] {
            let views = OctahedralViews::new(n).unwrap();
            for index in 0..views.view_count() {
                let direction = views.view_direction(index).unwrap();
                assert_orthonormal(&ViewFrame::from_direction(direction).unwrap());
            }
        }
        for direction in [Vec3::Z, Vec3::NEG_Z, Vec3::X, Vec3::NEG_Y, Vec3::new(0.0, 0.0, -0.0) + Vec3::NEG_Z] {
            assert_orthonormal(&ViewFrame::from_direction(direction).unwrap());
        }
    }

    #[test]
    fn non_unit_or_non_finite_directions_have_no_frame() {
        for direction in
            [Vec3::ZERO, Vec3::splat(1.0), Vec3::new(f32::NAN, 0.0, 1.0), Vec3::new(0.0, f32::INFINITY, 0.0)]
        {
            assert_eq!(ViewFrame::from_direction(direction), None);
        }
    }

    #[test]
    fn texture_coordinates_and_depth_invert_point_at() {
        let frame = ViewFrame::from_direction(Vec3::new(0.3, -0.4, 0.5).normalize()).unwrap();
        let extent = 2.5;
        for (uv, depth) in [(Vec2::new(0.5, 0.5), 0.0), (Vec2::new(0.0, 1.0), 0.7), (Vec2::new(0.9, 0.2), -0.3)] {
            let point = frame.point_at(uv, depth, extent);
            assert!(frame.texture_coordinates(point, extent).distance(uv) < 1e-6);
            assert!((frame.depth(point, extent) - depth).abs() < 1e-6);
        }
        // The top-left corner is -R·right + R·up; the centre projects to the middle.
        let corner = frame.point_at(Vec2::ZERO, 0.0, extent);
        assert!(corner.distance(extent * (frame.up - frame.right)) < 1e-5);
        assert_eq!(frame.texture_coordinates(Vec3::ZERO, extent), Vec2::splat(0.5));
        // The camera-facing point of the outer sphere has depth +1.
        assert!((frame.depth(frame.direction * extent, extent) - 1.0).abs() < 1e-6);
    }
}
