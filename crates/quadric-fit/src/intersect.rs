//! Ray–quadric intersection (Algorithm 3.2) and the surface normal, in single precision;
//! mirrored by `quadric_first_hit` and `quadric_normal` in `shaders/quadric_fit.wgsl`.
//!
//! Substituting the ray `o + t r` into `Q` gives `α t² + β t + γ = 0` with
//! `α = rᵀ M r`, `β = ∇Q(o) · r` and `γ = Q(o)`. The roots are computed in the stable
//! form `q = -(β + sign(β)√(β² - 4αγ))/2`, `t = γ/q` and `t = q/α` (Press et al.,
//! *Numerical Recipes* §5.6), which has no cancellation and degrades gracefully to the
//! linear root `-γ/β` as `α → 0`: the far root `q/α` is only formed when it is known to be
//! finite and inside the queried range, so no infinity or NaN ever appears, as WGSL
//! requires.

use glam::Vec3;

use crate::gpu_quadric::GpuQuadric;

/// `(α, β, γ)` of `Q(o + t r) = α t² + β t + γ`.
pub fn ray_quadratic(quadric: &GpuQuadric, origin: Vec3, direction: Vec3) -> (f32, f32, f32) {
    let [a, b, c, d, e, f, ..] = quadric.coefficients();
    let r = direction;
    let alpha = a * r.x * r.x + b * r.y * r.y + c * r.z * r.z + d * r.x * r.y + e * r.y * r.z + f * r.z * r.x;
    let beta = gradient(quadric, origin).dot(r);
    let gamma = value(quadric, origin);
    (alpha, beta, gamma)
}

/// `Q(p)` in single precision.
pub fn value(quadric: &GpuQuadric, p: Vec3) -> f32 {
    let [a, b, c, d, e, f, g, h, i, j] = quadric.coefficients();
    a * p.x * p.x
        + b * p.y * p.y
        + c * p.z * p.z
        + d * p.x * p.y
        + e * p.y * p.z
        + f * p.z * p.x
        + g * p.x
        + h * p.y
        + i * p.z
        + j
}

/// `∇Q(p) = 2Mp + L` in single precision.
pub fn gradient(quadric: &GpuQuadric, p: Vec3) -> Vec3 {
    let [a, b, c, d, e, f, g, h, i, _] = quadric.coefficients();
    Vec3::new(
        2.0 * a * p.x + d * p.y + f * p.z + g,
        d * p.x + 2.0 * b * p.y + e * p.z + h,
        f * p.x + e * p.y + 2.0 * c * p.z + i,
    )
}

/// The unit normal `∇Q/|∇Q|` at `p`, or zero where the gradient vanishes (a singular
/// point of the quadric, such as a cone's apex).
pub fn normal(quadric: &GpuQuadric, p: Vec3) -> Vec3 {
    let g = gradient(quadric, p);
    let length = g.length();
    if length > 0.0 { g / length } else { Vec3::ZERO }
}

/// The smallest `t` in `[t_min, t_max]` where the ray `origin + t direction` meets the
/// quadric (Algorithm 3.2, restricted to the voxel's ray segment), or `None`.
///
/// | case | result |
/// |---|---|
/// | a coordinate, coefficient or bound not finite, or `t_min > t_max` | `None` |
/// | `α = β = 0` (`Q` constant along the ray, including a ray inside a plane) | `None` |
/// | `β² < 4αγ` (the line misses the quadric) | `None` |
/// | double root at `t = 0` (`β = γ = 0`) | `Some(0)` if `0` is in range |
pub fn first_hit(quadric: &GpuQuadric, origin: Vec3, direction: Vec3, t_min: f32, t_max: f32) -> Option<f32> {
    let finite = quadric.coefficients().iter().all(|c| c.is_finite())
        && origin.is_finite()
        && direction.is_finite()
        && t_min.is_finite()
        && t_max.is_finite();
    if !finite || t_min > t_max {
        return None;
    }
    let (alpha, beta, gamma) = ray_quadratic(quadric, origin, direction);
    if alpha == 0.0 && beta == 0.0 {
        return None;
    }
    let discriminant = beta * beta - 4.0 * alpha * gamma;
    if discriminant < 0.0 {
        return None;
    }
    let root = libm::sqrtf(discriminant);
    let q = -0.5 * (beta + if beta >= 0.0 { root } else { -root });
    let in_range = |t: f32| t >= t_min && t <= t_max;
    let near = if q != 0.0 { gamma / q } else { 0.0 };
    // The far root q/α, formed only when |q/α| ≤ 2·max(|t_min|, |t_max|) so it is finite.
    let bound = 2.0 * t_min.abs().max(t_max.abs());
    let far = if q.abs() <= alpha.abs() * bound && alpha != 0.0 { Some(q / alpha) } else { None };
    match (in_range(near), far.filter(|&t| in_range(t))) {
        (true, Some(t)) => Some(near.min(t)),
        (true, None) => Some(near),
        (false, far) => far,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::quadric::Quadric;

    fn sphere(radius: f64) -> GpuQuadric {
        GpuQuadric::from_quadric(
            &Quadric::new([1.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, -radius * radius]).unwrap(),
        )
    }

    #[test]
    fn hits_a_sphere_from_outside_and_inside() {
        let s = sphere(0.5);
        let t = first_hit(&s, Vec3::new(0.0, 0.0, -2.0), Vec3::Z, 0.0, 10.0).unwrap();
        assert!((t - 1.5).abs() < 1e-6);
        let t = first_hit(&s, Vec3::ZERO, Vec3::X, 0.0, 10.0).unwrap();
        assert!((t - 0.5).abs() < 1e-6);
        assert!(first_hit(&s, Vec3::new(0.0, 0.6, -2.0), Vec3::Z, 0.0, 10.0).is_none());
        // Range restriction: the second root only.
        let t = first_hit(&s, Vec3::new(0.0, 0.0, -2.0), Vec3::Z, 2.0, 10.0).unwrap();
        assert!((t - 2.5).abs() < 1e-6);
        let n = normal(&s, Vec3::new(0.0, 0.0, -0.5));
        assert!((n - Vec3::NEG_Z).length() < 1e-6);
    }

    #[test]
    fn planes_and_near_planes_use_the_linear_root() {
        let plane = GpuQuadric::from_quadric(&Quadric::plane(glam::DVec3::Z, -0.25).unwrap());
        let t = first_hit(&plane, Vec3::new(0.3, 0.3, 1.0), Vec3::NEG_Z, 0.0, 5.0).unwrap();
        assert!((t - 0.75).abs() < 1e-6);
        // A ray inside the plane: Q is constant along it.
        assert!(first_hit(&plane, Vec3::new(0.0, 0.0, 0.25), Vec3::X, 0.0, 5.0).is_none());
        // A barely curved surface z = 0.25 + 1e-9 x²: no overflow, the near root.
        let mut nearly = plane;
        nearly.abcd.x = -1e-9;
        let t = first_hit(&nearly, Vec3::new(0.0, 0.0, 1.0), Vec3::NEG_Z, 0.0, 5.0).unwrap();
        assert!((t - 0.75).abs() < 1e-6);
    }

    #[test]
    fn non_finite_inputs_miss() {
        let s = sphere(0.5);
        assert!(first_hit(&s, Vec3::NAN, Vec3::Z, 0.0, 1.0).is_none());
        assert!(first_hit(&s, Vec3::ZERO, Vec3::Z, 0.0, f32::INFINITY).is_none());
        assert!(first_hit(&s, Vec3::ZERO, Vec3::Z, 1.0, 0.0).is_none());
        assert_eq!(
            normal(
                &GpuQuadric::from_quadric(&Quadric::new([1.0, 1.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]).unwrap()),
                Vec3::ZERO
            ),
            Vec3::ZERO
        );
    }
}
