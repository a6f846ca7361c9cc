//! Tests of the impostor samplers.

use glam::{Quat, Vec2, Vec3};

use super::*;
use crate::CompactViews;

fn sampler(n: u32, mode: SamplingMode, selection: ViewSelection) -> ImpostorSampler {
    ImpostorSampler::new(OctahedralViews::new(n).unwrap(), 1.0, 0.6, mode, ViewLayout::Listing1, selection).unwrap()
}

#[test]
fn invalid_radii_are_rejected() {
    let views = OctahedralViews::new(4).unwrap();
    for (outer, inner) in [(1.0, 0.0), (1.0, 1.5), (f32::NAN, 0.5), (1.0, f32::NAN), (f32::INFINITY, 1.0), (-1.0, -2.0)]
    {
        let s = ImpostorSampler::new(
            views,
            outer,
            inner,
            SamplingMode::Mixed,
            ViewLayout::Listing1,
            ViewSelection::PerFragment,
        );
        assert!(s.is_none(), "R={outer} r={inner}");
    }
}

#[test]
fn a_ray_along_a_view_direction_reads_the_projection_of_its_origin_in_every_mode() {
    let views = OctahedralViews::new(8).unwrap();
    for index in [0, 9, 27, 63, 64, 100, 127] {
        let omega = views.view_direction(index).unwrap();
        let frame = ViewFrame::from_direction(omega).unwrap();
        // Origin 5 units in front of the plane, offset by (0.2, -0.1) in the view's frame.
        let origin = omega * 5.0 + frame.right * 0.2 - frame.up * 0.1;
        let ray = GrainRay::new(origin, -omega);
        for mode in SamplingMode::ALL {
            let sample = sampler(8, mode, ViewSelection::PerFragment).sample(&ray);
            let k = (0..4).find(|&k| sample.weights[k] > 1.0 - 1e-5).unwrap();
            let expected = Vec2::new(0.5 + 0.1, 0.5 + 0.05);
            // The origin, 5 R away, is built and then projected with a few `f32`
            // operations each rounding by ulp(5) / 2 = 2.4e-7, scaled by 1 / (2R) into
            // texture coordinates: 2e-6 allows 16 of them (measured ≤ 3e-7).
            assert!(sample.view_texture_coordinates(k).distance(expected) < 2e-6, "{mode:?} view {index}");
            assert!((sample.distance_ratio - 0.05_f32.sqrt()).abs() < 1e-6);
            assert_eq!(sample.proxy_hit, 1);
        }
    }
}

#[test]
fn spherical_and_mixed_samples_follow_their_definitions() {
    let s = sampler(6, SamplingMode::Spherical, ViewSelection::PerFragment);
    let p = sampler(6, SamplingMode::Planar, ViewSelection::PerFragment);
    let m = sampler(6, SamplingMode::Mixed, ViewSelection::PerFragment);
    let views = OctahedralViews::new(6).unwrap();
    let ray = GrainRay::new(Vec3::new(3.0, 0.4, 2.0), Vec3::new(-1.0, -0.05, -0.6));
    let hit = intersect_proxy_sphere(&ray, 0.8).unwrap();
    assert!((hit.length() - 0.8).abs() < 1e-6);
    let (ss, ps, ms) = (s.sample(&ray), p.sample(&ray), m.sample(&ray));
    assert_eq!(ss.indices, ps.indices);
    let t = ms.distance_ratio;
    for k in 0..4 {
        let frame = ViewFrame::from_direction(views.view_direction(ss.indices[k]).unwrap()).unwrap();
        // S: the sphere hit projected along ω (texture coordinates ignore depth).
        assert!(ss.view_texture_coordinates(k).distance(frame.texture_coordinates(hit, 1.0)) < 1e-6);
        // P: on the ray and on the plane.
        let planar = planar_point(&ray, &frame).unwrap();
        assert!(planar.dot(frame.direction).abs() < 1e-5);
        assert!((planar - ray.origin).cross(ray.direction).length() < 1e-5);
        assert!(ps.view_texture_coordinates(k).distance(frame.texture_coordinates(planar, 1.0)) < 1e-6);
        // M = t P + (1 - t) S.
        let expected = ps.view_texture_coordinates(k) * t + ss.view_texture_coordinates(k) * (1.0 - t);
        assert!(ms.view_texture_coordinates(k).distance(expected) < 1e-6);
    }
}

#[test]
fn misses_follow_the_documented_rules() {
    let miss = Vec2::splat(MISS_TEXTURE_COORDINATE);
    // d = 0.9: outside the proxy sphere (ρ = 0.8), inside the outer sphere.
    let ray = GrainRay::new(Vec3::new(0.0, 0.9, 5.0), Vec3::NEG_Z);
    let spherical = sampler(8, SamplingMode::Spherical, ViewSelection::PerFragment).sample(&ray);
    let planar = sampler(8, SamplingMode::Planar, ViewSelection::PerFragment).sample(&ray);
    let mixed = sampler(8, SamplingMode::Mixed, ViewSelection::PerFragment).sample(&ray);
    assert_eq!(spherical.proxy_hit, 0);
    for k in 0..4 {
        assert_eq!(spherical.view_texture_coordinates(k), miss);
        assert_eq!(mixed.view_texture_coordinates(k), planar.view_texture_coordinates(k));
        assert_ne!(planar.view_texture_coordinates(k), miss);
    }
    // d = 1.1 > R: a miss in every mode.
    let outside = GrainRay::new(Vec3::new(0.0, 1.1, 5.0), Vec3::NEG_Z);
    for mode in SamplingMode::ALL {
        let sample = sampler(8, mode, ViewSelection::PerFragment).sample(&outside);
        assert!((sample.distance_ratio - 1.1).abs() < 1e-6);
        for k in 0..4 {
            assert_eq!(sample.view_texture_coordinates(k), miss, "{mode:?}");
        }
    }
    // n = 1: the poles; a ray in the equator plane is parallel to both view planes.
    let grazing = GrainRay::new(Vec3::new(5.0, 0.0, 0.1), Vec3::NEG_X);
    let planar = sampler(1, SamplingMode::Planar, ViewSelection::PerFragment).sample(&grazing);
    let mixed = sampler(1, SamplingMode::Mixed, ViewSelection::PerFragment).sample(&grazing);
    let spherical = sampler(1, SamplingMode::Spherical, ViewSelection::PerFragment).sample(&grazing);
    for k in 0..4 {
        assert_eq!(planar.view_texture_coordinates(k), miss);
        assert_eq!(mixed.view_texture_coordinates(k), spherical.view_texture_coordinates(k));
    }
}

#[test]
fn per_grain_selection_uses_the_eye_direction() {
    let eye = Vec3::new(0.3, -2.0, 4.0);
    let ray = GrainRay::new(eye, Vec3::new(0.1, 0.3, -1.0));
    let per_grain = sampler(8, SamplingMode::Mixed, ViewSelection::PerGrainFromEye).sample(&ray);
    let per_fragment = sampler(8, SamplingMode::Mixed, ViewSelection::PerFragment).sample(&ray);
    let views = OctahedralViews::new(8).unwrap();
    assert_eq!(per_grain.indices, views.sample(eye).indices);
    assert_eq!(per_fragment.indices, views.sample(-ray.direction).indices);
    assert_ne!(per_grain.indices, per_fragment.indices);
}

#[test]
fn compact_layout_returns_the_compact_indices_of_the_same_views() {
    let views = OctahedralViews::new(5).unwrap();
    let compact = CompactViews::new(views);
    for direction in [Vec3::new(0.3, 0.2, 0.01), Vec3::new(-0.5, 0.1, 0.4), Vec3::new(0.2, 0.9, -0.3)] {
        let ray = GrainRay::new(direction * 3.0, -direction);
        let make = |layout| {
            ImpostorSampler::new(views, 1.0, 0.5, SamplingMode::Mixed, layout, ViewSelection::PerFragment).unwrap()
        };
        let listing = make(ViewLayout::Listing1).sample(&ray);
        let packed = make(ViewLayout::Compact).sample(&ray);
        assert_eq!(listing.weights, packed.weights);
        assert_eq!(listing.texture_coordinates, packed.texture_coordinates);
        for k in 0..4 {
            assert_eq!(Some(packed.indices[k]), compact.compact_index(listing.indices[k]));
        }
    }
}

#[test]
fn rotated_and_scaled_grains_sample_like_their_local_frame() {
    let rotation = Quat::from_euler(glam::EulerRot::XYZ, 0.3, -1.1, 2.0);
    let (centre, scale) = (Vec3::new(10.0, -3.0, 2.0), 2.5);
    let local_origin = Vec3::new(0.2, 0.3, 6.0);
    let local_direction = Vec3::new(-0.01, -0.05, -1.0).normalize();
    let world_origin = centre + rotation * (local_origin * scale);
    let world_direction = rotation * local_direction * 7.0;
    let ray = GrainRay::from_world(world_origin, world_direction, centre, scale, rotation);
    assert!(ray.origin.distance(local_origin) < 1e-5);
    assert!(ray.direction.distance(local_direction) < 1e-6);
}

#[test]
fn every_input_has_a_defined_finite_result() {
    let specials =
        [0.0, -0.0, f32::NAN, f32::INFINITY, f32::NEG_INFINITY, f32::MAX, f32::MIN_POSITIVE, 1e30, -0.5, 1.0];
    let mut count = 0;
    for mode in SamplingMode::ALL {
        for selection in [ViewSelection::PerFragment, ViewSelection::PerGrainFromEye] {
            let s = sampler(3, mode, selection);
            for &a in &specials {
                for &b in &specials {
                    for &c in &specials {
                        for ray in [
                            GrainRay::new(Vec3::new(a, b, c), Vec3::new(c, a, b)),
                            GrainRay::from_world(
                                Vec3::new(a, 1.0, c),
                                Vec3::new(b, -1.0, 0.5),
                                Vec3::ZERO,
                                b,
                                Quat::from_xyzw(a, 0.0, c, 1.0),
                            ),
                        ] {
                            let sample = s.sample(&ray);
                            assert!(
                                sample.weights.is_finite() && sample.texture_coordinates.iter().all(|t| t.is_finite())
                            );
                            assert!(sample.distance_ratio.is_finite() && sample.indices.max_element() < 18);
                            count += 1;
                        }
                    }
                }
            }
        }
    }
    assert_eq!(count, SamplingMode::ALL.len() * 2 * 2 * 1000);
}
