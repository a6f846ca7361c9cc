//! Property tests: whatever the input, the `f32` test culls only grains that the exact
//! answer says are hidden (or within `f64` rounding of the boundary), and only grains whose
//! sampled surface points are all hidden from the eye.

use glam::Vec3;
use occlusion_cone::exact::sampled_points_hidden;
use occlusion_cone::{Exact, Sphere, hidden_exact, is_occluded_by};
use proptest::prelude::*;

/// Coordinates over several scales, with the special values now and then.
fn coordinate() -> impl Strategy<Value = f32> {
    prop_oneof![
        8 => -50.0_f32..50.0,
        1 => any::<f32>(),
        1 => prop::sample::select(vec![0.0, -0.0, f32::NAN, f32::INFINITY, 1e-30, 2e6]),
    ]
}

fn radius() -> impl Strategy<Value = f32> {
    prop_oneof![8 => 0.01_f32..5.0, 1 => any::<f32>(), 1 => prop::sample::select(vec![0.0, -1.0, 1e-7, 1e7])]
}

fn sphere() -> impl Strategy<Value = Sphere> {
    (coordinate(), coordinate(), coordinate(), radius())
        .prop_map(|(x, y, z, radius)| Sphere { centre: Vec3::new(x, y, z), radius })
}

/// An occluder and a grain placed inside or near its occlusion cone, so that culling
/// happens often (the arbitrary pairs above rarely occlude).
fn occluded_pair() -> impl Strategy<Value = (Sphere, Sphere)> {
    (0.05_f32..2.0, 1.0_f32..3.0, 1.5_f32..200.0, -1.2_f32..1.2, 0.0_f32..6.3, 0.01_f32..100.0).prop_map(
        |(r, ratio, distance, angle, phi, t)| {
            let g0 = Vec3::new(0.3, -0.2, -1.0).normalize() * (r * distance);
            let u = g0.normalize();
            let alpha = (1.0 / distance).asin();
            let e1 = u.any_orthonormal_vector();
            let e2 = u.cross(e1);
            let beta = alpha * angle;
            let w = u * beta.cos() + (e1 * phi.cos() + e2 * phi.sin()) * beta.sin();
            let big_r = r * ratio;
            let grain = g0 * ratio + w * (t * big_r);
            (Sphere { centre: g0, radius: r }, Sphere { centre: grain, radius: big_r })
        },
    )
}

fn exact(occluder: Sphere, grain: Sphere) -> Exact {
    hidden_exact(
        occluder.centre.as_dvec3(),
        f64::from(occluder.radius),
        grain.centre.as_dvec3(),
        f64::from(grain.radius),
    )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(20_000))]

    #[test]
    fn arbitrary_pairs_are_culled_only_when_hidden(occluder in sphere(), grain in sphere()) {
        if is_occluded_by(occluder, grain) {
            prop_assert!(matches!(exact(occluder, grain), Exact::Hidden | Exact::Boundary), "{occluder:?} {grain:?}");
        }
    }

    #[test]
    fn pairs_near_the_cone_are_culled_only_when_hidden((occluder, grain) in occluded_pair()) {
        if is_occluded_by(occluder, grain) {
            prop_assert!(matches!(exact(occluder, grain), Exact::Hidden | Exact::Boundary), "{occluder:?} {grain:?}");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]

    /// The brute-force check, independent of the exact answer's derivation: every sampled
    /// point of a culled grain's sphere is hidden from the eye.
    #[test]
    fn culled_grains_have_only_hidden_points((occluder, grain) in occluded_pair()) {
        if is_occluded_by(occluder, grain) {
            prop_assert!(sampled_points_hidden(
                occluder.centre.as_dvec3(),
                f64::from(occluder.radius),
                grain.centre.as_dvec3(),
                f64::from(grain.radius),
                16,
            ));
        }
    }
}

/// The pairs near the cone do produce both outcomes (so the properties above are not
/// vacuous): counted over a fixed grid of the same parameters.
#[test]
fn the_near_cone_pairs_cull_and_keep() {
    let (mut culled, mut kept) = (0, 0);
    for i in 0..2000_u32 {
        let f = |m: u32| f64::from(i.wrapping_mul(m) % 1009) as f32 / 1009.0;
        let (r, ratio, distance) = (0.05 + 1.95 * f(3), 1.0 + 2.0 * f(7), 1.5 + 198.5 * f(11));
        let g0 = Vec3::new(0.3, -0.2, -1.0).normalize() * (r * distance);
        let u = g0.normalize();
        let beta = (1.0 / distance).asin() * (2.4 * f(13) - 1.2);
        let w = u * beta.cos() + u.any_orthonormal_vector() * beta.sin();
        let grain = Sphere { centre: g0 * ratio + w * (0.01 + 99.99 * f(17)) * (r * ratio), radius: r * ratio };
        if is_occluded_by(Sphere { centre: g0, radius: r }, grain) { culled += 1 } else { kept += 1 }
    }
    assert!(culled > 200 && kept > 200, "{culled} culled, {kept} kept");
}
