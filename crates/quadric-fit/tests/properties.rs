//! Property tests: no panic and defined results on any input; exactness of the patch
//! quadrics; the single-precision intersection against a double-precision root finder.

use glam::{DVec3, Vec3};
use proptest::prelude::*;
use quadric_fit::{FitError, FitKind, GpuQuadric, Quadric, bilinear_quadric, first_hit, fit_quadric};

fn coordinate() -> impl Strategy<Value = f64> {
    prop_oneof![8 => -2.0_f64..2.0, 1 => Just(0.0), 1 => any::<f64>()]
}

fn point() -> impl Strategy<Value = DVec3> {
    (coordinate(), coordinate(), coordinate()).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn fitting_any_points_never_panics(points in proptest::collection::vec(point(), 0..40)) {
        match fit_quadric(&points) {
            Ok(fit) => {
                prop_assert!(fit.quadric.coefficients.iter().all(|c| c.is_finite()));
                prop_assert!(points.len() >= 3);
                if points.len() < 9 {
                    prop_assert_eq!(fit.kind, FitKind::Plane);
                }
            }
            // Each error is true of the input it names.
            Err(FitError::TooFewPoints { count }) => prop_assert!(count == points.len() && count < 3),
            Err(FitError::NonFinitePoint { index }) => prop_assert!(!points[index].is_finite()),
            Err(FitError::Coincident) => prop_assert!(points.iter().all(|p| (*p - points[0]).length() < 1e-150)),
            Err(FitError::Collinear | FitError::Overflow) => prop_assert!(points.iter().all(|p| p.is_finite())),
        }
    }

    #[test]
    fn bilinear_patches_lie_on_their_quadric(
        corners in proptest::array::uniform4((0.0_f64..1.0, 0.0_f64..1.0, 0.0_f64..1.0)),
        u in 0.0_f64..=1.0,
        v in 0.0_f64..=1.0,
    ) {
        let [p1, p2, p3, p4] = corners.map(|(x, y, z)| DVec3::new(x, y, z));
        if let Some(q) = bilinear_quadric(p1, p2, p3, p4) {
            let x = (1.0 - u) * (1.0 - v) * p1 + u * (1.0 - v) * p2 + u * v * p3 + (1.0 - u) * v * p4;
            let scale = q.gradient(x).length().max(1e-12);
            prop_assert!(q.value(x).abs() / scale < 1e-9, "distance {}", q.value(x).abs() / scale);
        }
    }

    #[test]
    fn single_precision_hits_are_double_precision_roots(
        coefficients in proptest::array::uniform10(-1.0_f64..1.0),
        origin in (-0.5_f32..1.5, -0.5_f32..1.5, -0.5_f32..1.5),
        direction in (-1.0_f32..1.0, -1.0_f32..1.0, -1.0_f32..1.0),
        t_max in 0.1_f32..3.0,
    ) {
        let Some(quadric) = Quadric::new(coefficients) else { return Ok(()) };
        let gpu = GpuQuadric::from_quadric(&quadric.normalized());
        let origin = Vec3::new(origin.0, origin.1, origin.2);
        let direction = Vec3::new(direction.0, direction.1, direction.2);
        if let Some(t) = first_hit(&gpu, origin, direction, 0.0, t_max) {
            prop_assert!((0.0..=t_max).contains(&t));
            // The hit point is on the single-precision quadric up to rounding.
            let exact = Quadric::new(gpu.coefficients().map(f64::from)).unwrap();
            let p = origin.as_dvec3() + f64::from(t) * direction.as_dvec3();
            let g = exact.gradient(p).length();
            if g > 1e-3 {
                prop_assert!(exact.value(p).abs() / g < 1e-5, "distance {}", exact.value(p).abs() / g);
            }
        }
    }
}
