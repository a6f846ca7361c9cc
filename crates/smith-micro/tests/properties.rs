//! Property tests: every output is finite (or a documented ±∞ / `None`), Λ ≥ 0,
//! visibilities lie in [0, 1], and the monotonicity the math implies holds.

use glam::Vec3;
use proptest::prelude::*;
use smith_micro::{
    FilteredSurface, HeightCorrelatedAttribute, SlopeDeviation, erf, erfc, erfcx, gaussian_slope_ndf, height_cdf,
    height_visibility, mean_visibility, shade, smith_lambda, smith_lambda_direction, smith_lambda_from_nu,
    visible_mean_attribute,
};

/// Any f32, biased towards the special values.
fn any_value() -> impl Strategy<Value = f32> {
    prop_oneof![
        4 => -2.0_f32..=2.0,
        1 => any::<f32>(),
        1 => prop_oneof![Just(0.0_f32), Just(-0.0), Just(f32::NAN), Just(f32::INFINITY), Just(f32::NEG_INFINITY),
            Just(f32::MIN_POSITIVE), Just(f32::from_bits(1)), Just(f32::MAX)],
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4096))]

    #[test]
    fn lambda_is_nonnegative_and_never_nan(x in any_value(), y in any_value(), z in any_value(),
                                           sx in any_value(), sy in any_value()) {
        let lambda = SlopeDeviation::new(sx, sy).ok().and_then(|slopes| smith_lambda_direction(Vec3::new(x, y, z), slopes));
        if let Some(lambda) = lambda {
            prop_assert!(lambda >= 0.0, "Λ = {lambda}");
        }
        if let Some(lambda) = smith_lambda(x, sx) {
            prop_assert!(lambda >= 0.0);
        }
    }

    #[test]
    fn lambda_decreases_with_nu(a in 0.0_f32..12.0, b in 0.0_f32..12.0) {
        let (low, high) = if a <= b { (a, b) } else { (b, a) };
        let (lambda_low, lambda_high) = (smith_lambda_from_nu(low).unwrap(), smith_lambda_from_nu(high).unwrap());
        prop_assert!(lambda_high <= lambda_low, "Λ({high}) = {lambda_high} > Λ({low}) = {lambda_low}");
    }

    #[test]
    fn lambda_grows_with_roughness(theta in 0.0_f32..1.57, s1 in 0.0_f32..3.0, s2 in 0.0_f32..3.0, phi in -3.2_f32..3.2) {
        let (smooth, rough) = if s1 <= s2 { (s1, s2) } else { (s2, s1) };
        let v = Vec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
        let l_smooth = smith_lambda_direction(v, SlopeDeviation::new(smooth, smooth * 0.5).unwrap()).unwrap();
        let l_rough = smith_lambda_direction(v, SlopeDeviation::new(rough, rough * 0.5).unwrap()).unwrap();
        prop_assert!(l_smooth <= l_rough);
    }

    #[test]
    fn visibilities_are_probabilities(lambda in any_value(), h in any_value(), sigma_h in any_value()) {
        if let Some(v) = height_visibility(lambda, h, sigma_h) {
            prop_assert!((0.0..=1.0).contains(&v), "V = {v}");
        }
        if let Some(g) = height_cdf(h, sigma_h) {
            prop_assert!((0.0..=1.0).contains(&g), "g = {g}");
        }
        if let Some(mean) = mean_visibility(lambda) {
            prop_assert!((0.0..=1.0).contains(&mean));
        }
    }

    #[test]
    fn visibility_decreases_with_lambda_and_grows_with_height(l1 in 0.0_f32..50.0, l2 in 0.0_f32..50.0,
                                                             h1 in -6.0_f32..6.0, h2 in -6.0_f32..6.0) {
        let (lo, hi) = if l1 <= l2 { (l1, l2) } else { (l2, l1) };
        prop_assert!(height_visibility(hi, h1, 1.0).unwrap() <= height_visibility(lo, h1, 1.0).unwrap());
        let (below, above) = if h1 <= h2 { (h1, h2) } else { (h2, h1) };
        prop_assert!(height_visibility(lo, below, 1.0).unwrap() <= height_visibility(lo, above, 1.0).unwrap());
    }

    #[test]
    fn visible_attribute_lies_between_the_mean_and_the_top(mean in -10.0_f32..10.0, correlation in -10.0_f32..10.0,
                                                          lv in any_value(), ll in any_value()) {
        let attribute = HeightCorrelatedAttribute::new(mean, correlation).unwrap();
        if let Some(a) = visible_mean_attribute(attribute, lv, ll) {
            let (low, high) = if correlation >= 0.0 { (mean, mean + correlation) } else { (mean + correlation, mean) };
            prop_assert!(a.is_finite());
            prop_assert!(a >= low - 1e-5 && a <= high + 1e-5, "ā(v,l) = {a} outside [{low}, {high}]");
        }
    }

    #[test]
    fn error_functions_stay_in_their_ranges_and_erf_increases(a in any_value(), b in -12.0_f32..12.0) {
        if let (Some(e), Some(c), Some(x)) = (erf(a), erfc(a), erfcx(a)) {
            prop_assert!((-1.0..=1.0).contains(&e) && (0.0..=2.0).contains(&c) && (0.0..=1.0).contains(&x));
        } else {
            prop_assert!(a.is_nan());
        }
        let (low, high) = if a.is_finite() && a <= b { (a, b) } else { (b, b + 0.01) };
        prop_assert!(erf(low).unwrap() <= erf(high).unwrap());
    }

    #[test]
    fn visible_attribute_moves_towards_the_top_as_masking_grows(l1 in 0.0_f32..1e6, l2 in 0.0_f32..1e6) {
        let attribute = HeightCorrelatedAttribute::new(0.2, 0.5).unwrap();
        let (low, high) = if l1 <= l2 { (l1, l2) } else { (l2, l1) };
        prop_assert!(visible_mean_attribute(attribute, low, 0.0).unwrap() <= visible_mean_attribute(attribute, high, 0.0).unwrap());
    }

    #[test]
    fn shading_is_finite_and_nonnegative(vx in any_value(), vy in any_value(), vz in any_value(),
                                         lx in any_value(), ly in any_value(), lz in any_value(),
                                         sx in any_value(), sy in any_value(), p in any_value(),
                                         mean in 0.0_f32..2.0, fraction in -1.0_f32..=1.0, radiance in any_value()) {
        let slopes = SlopeDeviation::new(sx, sy);
        let brdf_slopes = SlopeDeviation::isotropic(p);
        // ā ≥ |a_s|: the attribute is non-negative at every height.
        let attribute = HeightCorrelatedAttribute::new(mean, mean * fraction).unwrap();
        if let (Ok(slopes), Ok(brdf_slopes)) = (slopes, brdf_slopes) {
            let view = Vec3::new(vx, vy, vz);
            if let Some(d) = gaussian_slope_ndf(view, slopes) {
                prop_assert!(d.is_finite() && d >= 0.0, "D = {d}");
            }
            let surface = FilteredSurface { slopes, brdf_slopes, attribute };
            if let Some(radiance) = shade(view, Vec3::new(lx, ly, lz), surface, radiance) {
                prop_assert!(radiance.is_finite() && radiance >= 0.0, "L = {radiance}");
            }
        }
    }
}
