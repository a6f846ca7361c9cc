//! The view directions of the accuracy experiment, and a scene that shows one grain from
//! each direction in a single image (one render per configuration instead of one per view).

use glam::{Quat, Vec3};

use crate::scene::{CameraUniforms, GrainInstance};

/// Vertical field of view of the comparison camera (30°): a moderate perspective, so camera
/// rays are not parallel across a grain, as in the paper's use.
pub const COMPARISON_FOV_Y: f32 = core::f32::consts::PI / 6.0;

/// Fraction of a tile's width that a grain's outer diameter fills.
pub const GRAIN_FILL: f32 = 0.85;

/// `count` unit directions spread evenly over the sphere (the spherical Fibonacci lattice:
/// `z = 1 − (2i + 1)/count`, azimuth `i·π(3 − √5)`), none of them on a pole or the
/// equator plane for `count ≥ 2`, so they test the views between the octahedral ones.
pub fn fibonacci_directions(count: u32) -> Vec<Vec3> {
    let golden_angle = core::f32::consts::PI * (3.0 - 5.0_f32.sqrt());
    (0..count)
        .map(|i| {
            let z = 1.0 - (2.0 * i as f32 + 1.0) / count as f32;
            let radius = (1.0 - z * z).max(0.0).sqrt();
            let azimuth = golden_angle * i as f32;
            Vec3::new(radius * azimuth.cos(), radius * azimuth.sin(), z)
        })
        .collect()
}

/// A grid of copies of one grain, each turned so that the camera sees it from one of the
/// given directions, under a perspective camera: the scene of one accuracy measurement.
#[derive(Clone, Debug)]
pub struct ComparisonScene {
    /// The camera (perspective, looking down −z at the grid in the plane z = 0).
    pub camera: CameraUniforms,
    /// One grain per direction, row by row from the top-left tile.
    pub instances: Vec<GrainInstance>,
    /// For each instance, the grain-local unit direction from its centre toward the eye.
    pub local_directions_to_eye: Vec<Vec3>,
    /// Image size in pixels.
    pub size: (u32, u32),
    /// The on-screen diameter of each grain's outer sphere, in pixels (approximately: the
    /// perspective projection of a sphere off the axis is slightly elongated).
    pub apparent_diameter: f32,
}

impl ComparisonScene {
    /// The scene showing a grain of outer radius `outer_radius` from each of `directions`
    /// (grain-local, toward the eye) at an on-screen diameter of `apparent_diameter` pixels;
    /// `None` when there is no direction, a direction is zero or not finite, or the sizes are
    /// not finite and positive.
    pub fn new(directions: &[Vec3], outer_radius: f32, apparent_diameter: f32) -> Option<Self> {
        let positive = |x: f32| x.is_finite() && x > 0.0;
        if directions.is_empty()
            || !positive(outer_radius)
            || !(apparent_diameter.is_finite() && apparent_diameter >= 1.0)
        {
            return None;
        }
        let directions: Vec<Vec3> = directions.iter().map(|d| d.try_normalize()).collect::<Option<_>>()?;
        let count = directions.len() as u32;
        let columns = (count as f32).sqrt().ceil() as u32;
        let rows = count.div_ceil(columns);
        let tile = (apparent_diameter / GRAIN_FILL).ceil() as u32;
        let size = (columns * tile, rows * tile);
        // World units per pixel in the plane z = 0, and the eye distance that gives it.
        let world_per_pixel = 2.0 * outer_radius / apparent_diameter;
        let distance = 0.5 * size.1 as f32 * world_per_pixel / (0.5 * COMPARISON_FOV_Y).tan();
        let eye = Vec3::new(0.0, 0.0, distance);
        let camera = CameraUniforms::perspective(
            eye,
            Vec3::ZERO,
            Vec3::Y,
            COMPARISON_FOV_Y,
            size,
            (0.5 * distance, 2.0 * distance),
        )?;
        let spacing = tile as f32 * world_per_pixel;
        let golden_angle = core::f32::consts::PI * (3.0 - 5.0_f32.sqrt());
        let mut instances = Vec::with_capacity(directions.len());
        for (k, local) in directions.iter().enumerate() {
            let (row, column) = ((k as u32 / columns) as f32, (k as u32 % columns) as f32);
            let centre = Vec3::new(
                (column - 0.5 * (columns - 1) as f32) * spacing,
                (0.5 * (rows - 1) as f32 - row) * spacing,
                0.0,
            );
            let to_eye = (eye - centre).normalize();
            // Turn the grain so that `local` points at the eye, then roll it about that axis
            // by a different angle per tile so the views also vary in their in-plane rotation.
            let rotation =
                Quat::from_axis_angle(to_eye, golden_angle * k as f32) * Quat::from_rotation_arc(*local, to_eye);
            instances.push(GrainInstance::new(centre, 1.0, rotation));
        }
        Some(Self { camera, instances, local_directions_to_eye: directions, size, apparent_diameter })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec4;

    #[test]
    fn fibonacci_directions_are_unit_and_cover_the_sphere() {
        let directions = fibonacci_directions(64);
        assert_eq!(directions.len(), 64);
        for d in &directions {
            assert!((d.length() - 1.0).abs() < 1e-5);
        }
        // Every direction of a fine test set has a lattice point within 20° (the lattice's
        // covering radius for 64 points is about 15°).
        for probe in fibonacci_directions(2000) {
            let best = directions.iter().map(|d| d.dot(probe)).fold(-1.0_f32, f32::max);
            assert!(best > 20.0_f32.to_radians().cos(), "{probe} is {}° away", best.acos().to_degrees());
        }
    }

    #[test]
    fn each_grain_faces_the_eye_with_its_direction_and_has_the_requested_size() {
        let directions = fibonacci_directions(64);
        let (radius, diameter) = (1.3, 40.0);
        let scene = ComparisonScene::new(&directions, radius, diameter).unwrap();
        assert_eq!(scene.instances.len(), 64);
        assert_eq!(scene.size, (8 * 48, 8 * 48));
        let eye = scene.camera.eye.truncate();
        let clip_from_world = scene.camera.clip_from_world();
        let to_pixels = |p: Vec3| {
            let clip = clip_from_world * p.extend(1.0);
            glam::Vec2::new(clip.x / clip.w, clip.y / clip.w)
                * 0.5
                * glam::Vec2::new(scene.size.0 as f32, scene.size.1 as f32)
        };
        for (grain, local) in scene.instances.iter().zip(&scene.local_directions_to_eye) {
            let centre = grain.centre_scale.truncate();
            let rotation = Quat::from_vec4(grain.rotation);
            assert!((rotation * *local).dot((eye - centre).normalize()) > 1.0 - 1e-5);
            // A point of the outer sphere's equator (seen from the eye) lies about a radius
            // away from the centre on screen.
            let side = (eye - centre).normalize().cross(Vec3::Y).normalize() * radius;
            let apparent_radius = to_pixels(centre + side).distance(to_pixels(centre));
            assert!((apparent_radius - 0.5 * diameter).abs() < 0.03 * diameter, "{apparent_radius}");
        }
        // The grid fits the image: every centre projects inside it.
        for grain in &scene.instances {
            let clip = clip_from_world * Vec4::from((grain.centre_scale.truncate(), 1.0));
            assert!((clip.x / clip.w).abs() < 1.0 && (clip.y / clip.w).abs() < 1.0);
        }
    }

    #[test]
    fn bad_inputs_give_no_scene() {
        assert!(ComparisonScene::new(&[], 1.0, 32.0).is_none());
        assert!(ComparisonScene::new(&[Vec3::ZERO], 1.0, 32.0).is_none());
        assert!(ComparisonScene::new(&[Vec3::Z], f32::NAN, 32.0).is_none());
        assert!(ComparisonScene::new(&[Vec3::Z], 1.0, 0.5).is_none());
    }
}
