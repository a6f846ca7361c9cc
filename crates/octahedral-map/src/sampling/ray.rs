//! Camera rays in a grain's local frame, and where they meet the view plane and the proxy
//! sphere of a quasi-spherical impostor (§5).

use glam::{Quat, Vec3};

use crate::direction::canonical_direction;

/// Origins farther than this from the grain centre (in any component, grain units) are
/// treated as missing the grain: squaring them could overflow `f32`.
pub const MAX_RAY_ORIGIN_COMPONENT: f32 = 1.0e18;

/// World-space coordinates (ray origin, grain centre) beyond this magnitude make the ray
/// unusable: their difference could overflow `f32`.
pub const MAX_WORLD_COMPONENT: f32 = 1.0e36;

/// The smallest grain scale [`GrainRay::from_world`] accepts.
pub const MIN_GRAIN_SCALE: f32 = 1.0e-18;

/// The largest grain scale [`GrainRay::from_world`] accepts.
pub const MAX_GRAIN_SCALE: f32 = 1.0e18;

/// A camera ray in a grain's local frame: the origin relative to the grain centre (in the
/// units of the grain's mesh, where `r` and `R` are measured) and a unit direction.
///
/// Build it with [`GrainRay::new`] or [`GrainRay::from_world`], which give every input a
/// defined value.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GrainRay {
    /// Ray origin relative to the grain centre; `(0, 0, 0)` when the input was unusable.
    pub origin: Vec3,
    /// Unit direction in which the ray travels.
    pub direction: Vec3,
    /// Whether the input was unusable (see [`GrainRay::new`], [`GrainRay::from_world`]):
    /// such a ray samples nothing (every texture coordinate is a miss).
    pub invalid_origin: bool,
}

/// Whether every component of `v` is finite with magnitude at most `limit` (`limit`
/// finite). Written as comparisons on the bit patterns' magnitudes and floats known to be
/// finite, as the WGSL twin must (WGSL may assume that no NaN or ∞ reaches float
/// operations).
fn within(v: Vec3, limit: f32) -> bool {
    v.to_array().iter().all(|c| (c.to_bits() & 0x7fff_ffff) < 0x7f80_0000 && c.abs() <= limit)
}

impl GrainRay {
    /// A grain-local ray. `direction` need not be normalized: it goes through
    /// [`canonical_direction`] (zero or NaN directions become
    /// [`FALLBACK_DIRECTION`](crate::FALLBACK_DIRECTION)) and is then normalized. An
    /// origin with a NaN, ±∞ or a component beyond [`MAX_RAY_ORIGIN_COMPONENT`] is
    /// unusable.
    pub fn new(origin: Vec3, direction: Vec3) -> Self {
        let direction = canonical_direction(direction).normalize();
        let usable = within(origin, MAX_RAY_ORIGIN_COMPONENT);
        Self { origin: if usable { origin } else { Vec3::ZERO }, direction, invalid_origin: !usable }
    }

    /// The ray `world_origin + t·world_direction` in the local frame of a grain at
    /// `centre`, uniformly scaled by `scale` (world units per grain unit) and rotated by
    /// `rotation` (grain → world, normalized here): `origin = rotation⁻¹(world_origin −
    /// centre) / scale`, `direction = rotation⁻¹ world_direction` (then as in
    /// [`GrainRay::new`]). Mirrored by the WGSL `impostor_grain_ray`.
    ///
    /// The ray is unusable when `world_origin` or `centre` has a component that is not
    /// finite or beyond [`MAX_WORLD_COMPONENT`], when `scale` is not in
    /// `[MIN_GRAIN_SCALE, MAX_GRAIN_SCALE]` (NaN included), when `rotation` has a
    /// non-finite component or is (sub)normal-zero, or when the local origin would exceed
    /// [`MAX_RAY_ORIGIN_COMPONENT`]. The direction is defined in every case.
    pub fn from_world(world_origin: Vec3, world_direction: Vec3, centre: Vec3, scale: f32, rotation: Quat) -> Self {
        let rotation = normalized_rotation(rotation);
        let direction = rotation.map_or(world_direction, |q| q.conjugate() * canonical_direction(world_direction));
        let scale_ok = (MIN_GRAIN_SCALE..=MAX_GRAIN_SCALE).contains(&scale);
        let origin = match rotation {
            Some(q) if scale_ok && within(world_origin, MAX_WORLD_COMPONENT) && within(centre, MAX_WORLD_COMPONENT) => {
                let offset = world_origin - centre;
                within(offset, MAX_RAY_ORIGIN_COMPONENT * scale).then(|| q.conjugate() * (offset / scale))
            }
            _ => None,
        };
        match origin {
            Some(origin) => Self::new(origin, direction),
            None => Self { invalid_origin: true, ..Self::new(Vec3::ZERO, direction) },
        }
    }

    /// The point of the ray's line nearest to the grain centre:
    /// `origin − (origin·direction) direction`.
    pub fn closest_point_to_centre(&self) -> Vec3 {
        self.origin - self.direction * self.origin.dot(self.direction)
    }

    /// The ray parameter `t` of [`closest_point_to_centre`](Self::closest_point_to_centre):
    /// `−origin·direction`.
    pub fn closest_point_parameter(&self) -> f32 {
        -self.origin.dot(self.direction)
    }
}

/// `rotation` divided by its largest component magnitude, then normalized (robust for
/// any finite input), or `None` when a component is not finite or all are zero or
/// subnormal.
fn normalized_rotation(rotation: Quat) -> Option<Quat> {
    let v = glam::Vec4::from(rotation);
    let bits = v.to_array().map(|c| c.to_bits() & 0x7fff_ffff);
    if bits.iter().any(|&b| b >= 0x7f80_0000) {
        return None;
    }
    let largest = v.abs().max_element();
    if largest < f32::MIN_POSITIVE {
        return None;
    }
    Some(Quat::from_vec4((v / largest).normalize()))
}

/// The first point (parameter `t ≥ 0`) where `ray` meets the sphere of radius `radius`
/// centred on the grain, or `None` when its line passes farther than `radius` from the
/// centre or the sphere lies behind the origin. A ray starting inside the sphere gets the
/// exit point (as `GrainViewer`'s `intersectRaySphere`).
///
/// Computed from the closest point `c` of the line: `hit = c ∓ h·direction` with
/// `h = √(radius² − |c|²)`, so the result does not lose precision when the origin is far
/// away.
pub fn intersect_proxy_sphere(ray: &GrainRay, radius: f32) -> Option<Vec3> {
    let closest = ray.closest_point_to_centre();
    let half_chord_squared = radius * radius - closest.length_squared();
    if ray.invalid_origin || half_chord_squared < 0.0 {
        return None;
    }
    let half_chord = libm::sqrtf(half_chord_squared);
    let t_closest = ray.closest_point_parameter();
    if t_closest - half_chord >= 0.0 {
        Some(closest - ray.direction * half_chord)
    } else if t_closest + half_chord >= 0.0 {
        Some(closest + ray.direction * half_chord)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn world_rays_become_local_rays() {
        let rotation = Quat::from_rotation_z(core::f32::consts::FRAC_PI_2);
        let ray = GrainRay::from_world(
            Vec3::new(1.0, 5.0, 0.0),
            Vec3::new(0.0, -2.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            2.0,
            rotation,
        );
        // World offset (0, 4, 0) / 2 = (0, 2, 0), rotated by -90° about z: (2, 0, 0).
        assert!(ray.origin.distance(Vec3::new(2.0, 0.0, 0.0)) < 1e-6);
        assert!(ray.direction.distance(Vec3::NEG_X) < 1e-6);
        assert!(!ray.invalid_origin);
        for scale in [0.0, -1.0, f32::NAN, f32::INFINITY] {
            assert!(GrainRay::from_world(Vec3::ONE, Vec3::X, Vec3::ZERO, scale, Quat::IDENTITY).invalid_origin);
        }
        assert!(
            GrainRay::from_world(Vec3::ONE, Vec3::X, Vec3::ZERO, 1.0, Quat::from_xyzw(0.0, 0.0, 0.0, 0.0))
                .invalid_origin
        );
        assert!(GrainRay::new(Vec3::new(f32::NAN, 0.0, 0.0), Vec3::X).invalid_origin);
        assert_eq!(GrainRay::new(Vec3::ONE, Vec3::ZERO).direction, crate::FALLBACK_DIRECTION);
    }

    #[test]
    fn proxy_sphere_hits_near_side_exit_point_and_misses() {
        let ray = GrainRay::new(Vec3::new(0.0, 0.5, 10.0), Vec3::NEG_Z);
        let hit = intersect_proxy_sphere(&ray, 1.0).unwrap();
        assert!(hit.distance(Vec3::new(0.0, 0.5, 0.75_f32.sqrt())) < 1e-6);
        // From inside: the exit point.
        let inside = GrainRay::new(Vec3::new(0.0, 0.0, 0.2), Vec3::NEG_Z);
        assert!(intersect_proxy_sphere(&inside, 1.0).unwrap().distance(Vec3::NEG_Z) < 1e-6);
        // Behind the origin, and beside the sphere.
        assert_eq!(intersect_proxy_sphere(&GrainRay::new(Vec3::new(0.0, 0.0, 5.0), Vec3::Z), 1.0), None);
        assert_eq!(intersect_proxy_sphere(&GrainRay::new(Vec3::new(0.0, 1.5, 5.0), Vec3::NEG_Z), 1.0), None);
    }
}
