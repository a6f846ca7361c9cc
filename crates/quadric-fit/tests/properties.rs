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

/// `Σ |kᵢ mᵢ(p)|` over the quadric's ten monomials at `p`: the scale of the rounding of
/// `Q(p)` (each term within a few ulp of itself).
fn term_magnitude(k: &[f64; 10], p: DVec3) -> f64 {
    let m = [p.x * p.x, p.y * p.y, p.z * p.z, p.x * p.y, p.y * p.z, p.z * p.x, p.x, p.y, p.z, 1.0];
    k.iter().zip(m).map(|(k, m)| (k * m).abs()).sum()
}

proptest! {
    // Cases that cannot be compared (a degenerate patch, a quadric that is not one, a miss,
    // a vanishing gradient) are rejected with `prop_assume!`, so each test compares 2000
    // cases; proptest fails when it rejects more than `max_global_rejects`: random rays
    // hit their random quadric in about half of the cases, so 8000 rejects (a hit rate
    // below 20 %) mean the generator broke.
    #![proptest_config(ProptestConfig { cases: 2000, max_global_rejects: 8000, ..ProptestConfig::default() })]

    #[test]
    fn fitting_any_points_never_panics(points in proptest::collection::vec(point(), 0..40)) {
        match fit_quadric(&points) {
            Ok(fit) => {
                prop_assert!(fit.quadric.coefficients().iter().all(|c| c.is_finite()));
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
        let q = bilinear_quadric(p1, p2, p3, p4);
        prop_assume!(q.is_ok());
        let q = q.unwrap();
        let x = (1.0 - u) * (1.0 - v) * p1 + u * (1.0 - v) * p2 + u * v * p3 + (1.0 - u) * v * p4;
        // Exact in real arithmetic: |Q(x)| is the `f64` rounding of its terms (and of x),
        // 64 ε of their magnitude allows ~20 roundings on either side.
        let rounding = 64.0 * f64::EPSILON * term_magnitude(&q.coefficients(), x);
        prop_assert!(q.value(x).abs() <= rounding, "|Q| {} > rounding bound {rounding}", q.value(x).abs());
    }

    #[test]
    fn single_precision_hits_are_double_precision_roots(
        coefficients in proptest::array::uniform10(-1.0_f64..1.0),
        origin in (-0.5_f32..1.5, -0.5_f32..1.5, -0.5_f32..1.5),
        direction in (-1.0_f32..1.0, -1.0_f32..1.0, -1.0_f32..1.0),
        t_max in 0.1_f32..3.0,
    ) {
        let quadric = Quadric::new(coefficients);
        prop_assume!(quadric.is_ok());
        let gpu = GpuQuadric::from_quadric(&quadric.unwrap().normalized());
        let origin = Vec3::new(origin.0, origin.1, origin.2);
        let direction = Vec3::new(direction.0, direction.1, direction.2);
        let hit = first_hit(&gpu, origin, direction, 0.0, t_max);
        prop_assume!(hit.is_some());
        let t = hit.unwrap();
        prop_assert!((0.0..=t_max).contains(&t));
        // The hit point is on the single-precision quadric up to rounding: the `f32`
        // evaluation of Q along the ray rounds by ~32 ε of its terms' magnitude (the
        // bound of `tests/quadric_fit_gpu.rs`), which moves the root by that over the
        // slope `|r · ∇Q| ≤ |r| |∇Q|`, i.e. the point by that over the gradient; and the
        // root itself is rounded to an `f32` (ε t |r| along the ray).
        let exact = Quadric::new(gpu.coefficients().map(f64::from)).unwrap();
        let (o, r) = (origin.as_dvec3(), direction.as_dvec3());
        let p = o + f64::from(t) * r;
        let g = exact.gradient(p).length();
        let magnitude = term_magnitude(&exact.coefficients(), o.abs() + f64::from(t) * r.abs());
        let rounding = 32.0 * f64::from(f32::EPSILON) * magnitude;
        // A gradient within rounding of zero leaves the distance undefined.
        prop_assume!(g > 10.0 * rounding);
        let bound = rounding / g + f64::from(f32::EPSILON) * f64::from(t) * r.length();
        let distance = exact.value(p).abs() / g;
        prop_assert!(distance <= bound, "distance {distance}, bound {bound}");
    }
}
