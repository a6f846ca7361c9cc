//! Property tests of the view layout against brute force.

use glam::{DVec3, Vec3};
use octahedral_map::{OctahedralViews, canonical_direction};
use proptest::prelude::*;

/// Largest dot product between `direction` and any of `views`' directions, by brute force.
fn brute_force_best_dot(views: OctahedralViews, direction: DVec3) -> f64 {
    (0..views.view_count())
        .map(|i| views.view_direction_f64(i).unwrap().dot(direction))
        .fold(f64::NEG_INFINITY, f64::max)
}

/// Any finite or special f32, biased towards the cases Listing 1 finds hard.
fn component() -> impl Strategy<Value = f32> {
    prop_oneof![
        6 => -1.0_f32..=1.0,
        1 => Just(0.0_f32),
        1 => Just(-0.0_f32),
        1 => any::<f32>(),
        1 => prop_oneof![Just(f32::NAN), Just(f32::INFINITY), Just(f32::NEG_INFINITY), Just(f32::MIN_POSITIVE), Just(f32::MAX)],
    ]
}

fn direction() -> impl Strategy<Value = Vec3> {
    (component(), component(), component()).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// A direction close to a stored view, an equator view or a cell edge: where the nearest
/// view changes.
fn near_a_view() -> impl Strategy<Value = (u32, Vec3)> {
    (1_u32..=40, any::<u32>(), -1.0_f32..=1.0, -1.0_f32..=1.0, -1.0_f32..=1.0, 1e-7_f32..0.3).prop_map(
        |(n, index, x, y, z, offset)| {
            let views = OctahedralViews::new(n).unwrap();
            let view = views.view_direction(index % views.view_count()).unwrap();
            (n, view + Vec3::new(x, y, z) * offset)
        },
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4000))]

    #[test]
    fn the_nearest_view_is_one_of_the_four_near_views((n, d) in near_a_view()) {
        let views = OctahedralViews::new(n).unwrap();
        let unit = canonical_direction(d).as_dvec3().normalize();
        let best = brute_force_best_dot(views, unit);
        let ours = views.view_direction_f64(views.nearest_view(d)).unwrap().dot(unit);
        prop_assert!(ours >= best - 1e-12, "n={} d={:?}: ours {} brute force {}", n, d, ours, best);
    }

    #[test]
    fn indices_and_weights_are_in_range(n in 1_u32..=64, d in direction()) {
        let views = OctahedralViews::new(n).unwrap();
        let sample = views.sample(d);
        for index in sample.indices.to_array() {
            prop_assert!(index < views.view_count());
        }
        prop_assert!(sample.alpha.cmpge(glam::Vec2::ZERO).all() && sample.alpha.cmplt(glam::Vec2::ONE).all());
        let weights = sample.weights();
        for w in weights {
            prop_assert!((0.0..=1.0).contains(&w));
        }
        prop_assert!((weights.iter().sum::<f32>() - 1.0).abs() < 1e-6);
    }

    #[test]
    fn the_nearest_view_is_one_of_the_four(n in 1_u32..=40, d in direction()) {
        let views = OctahedralViews::new(n).unwrap();
        let unit = canonical_direction(d).as_dvec3().normalize();
        let best = brute_force_best_dot(views, unit);
        let ours = views.view_direction_f64(views.nearest_view(d)).unwrap().dot(unit);
        // Equal up to f64 rounding: equator views exist twice, so compare by direction.
        prop_assert!(ours >= best - 1e-12, "n={} d={:?}: ours {} brute force {}", n, d, ours, best);
    }
}

/// Any f32 at all (bit patterns), for the no-panic property of the samplers.
fn any_bits() -> impl Strategy<Value = f32> {
    prop_oneof![3 => component(), 1 => any::<u32>().prop_map(f32::from_bits)]
}

proptest! {
    /// Every world ray, grain and sampler configuration has a finite, in-range sample:
    /// indices below the layout's view count, weights in [0, 1] summing to 1, texture
    /// coordinates in [MISS_TEXTURE_COORDINATE, MAX_TEXTURE_COORDINATE].
    #[test]
    fn impostor_samples_are_defined_for_any_input(
        origin in direction(),
        ray_direction in direction(),
        centre in direction(),
        scale in any_bits(),
        rotation in (any_bits(), any_bits(), any_bits(), any_bits()),
        n in 1_u32..=16,
        mode in 0_usize..4,
        compact in any::<bool>(),
        per_grain in any::<bool>(),
        inner in 0.01_f32..=1.0,
    ) {
        use octahedral_map::sampling::{MAX_TEXTURE_COORDINATE, MISS_TEXTURE_COORDINATE};
        use octahedral_map::{CompactViews, GrainRay, ImpostorSampler, SamplingMode, ViewLayout, ViewSelection};
        let views = OctahedralViews::new(n).unwrap();
        let layout = if compact { ViewLayout::Compact } else { ViewLayout::Listing1 };
        let selection = if per_grain { ViewSelection::PerGrainFromEye } else { ViewSelection::PerFragment };
        let sampler = ImpostorSampler::new(views, 1.0, inner, SamplingMode::ALL[mode], layout, selection).unwrap();
        let rotation = glam::Quat::from_xyzw(rotation.0, rotation.1, rotation.2, rotation.3);
        let ray = GrainRay::from_world(origin, ray_direction, centre, scale, rotation);
        prop_assert!(ray.origin.is_finite() && ray.direction.is_finite());
        prop_assert!((ray.direction.length() - 1.0).abs() < 1e-5);
        let sample = sampler.sample(&ray);
        let count = if compact { CompactViews::new(views).view_count() } else { views.view_count() };
        prop_assert!(sample.indices.max_element() < count);
        prop_assert!(sample.weights.min_element() >= 0.0 && sample.weights.max_element() <= 1.0);
        prop_assert!((sample.weights.element_sum() - 1.0).abs() < 1e-5);
        for t in sample.texture_coordinates {
            prop_assert!(t.min_element() >= MISS_TEXTURE_COORDINATE && t.max_element() <= MAX_TEXTURE_COORDINATE);
        }
        prop_assert!(sample.distance_ratio.is_finite());
    }
}
