// WGSL twin of crates/quadric-fit's single-precision ray intersection (Mehra & Kumar,
// eq. 1 and Algorithm 3.2). Composed after shaders/generated/quadric_fit.wgsl, which
// declares GpuQuadric from the Rust source. Each function mirrors the Rust function named
// in its comment; tests/quadric_fit_gpu.rs proves them equal.

// Rust: quadric_fit::intersect::value.
fn quadric_value(q: GpuQuadric, p: vec3<f32>) -> f32 {
    return q.abcd.x * p.x * p.x + q.abcd.y * p.y * p.y + q.abcd.z * p.z * p.z + q.abcd.w * p.x * p.y
        + q.efgh.x * p.y * p.z + q.efgh.y * p.z * p.x
        + q.efgh.z * p.x
        + q.efgh.w * p.y
        + q.ij.x * p.z
        + q.ij.y;
}

// Rust: quadric_fit::intersect::gradient.
fn quadric_gradient(q: GpuQuadric, p: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(
        2.0 * q.abcd.x * p.x + q.abcd.w * p.y + q.efgh.y * p.z + q.efgh.z,
        q.abcd.w * p.x + 2.0 * q.abcd.y * p.y + q.efgh.x * p.z + q.efgh.w,
        q.efgh.y * p.x + q.efgh.x * p.y + 2.0 * q.abcd.z * p.z + q.ij.x,
    );
}

// Rust: quadric_fit::intersect::normal. Zero where the gradient vanishes.
fn quadric_normal(q: GpuQuadric, p: vec3<f32>) -> vec3<f32> {
    let g = quadric_gradient(q, p);
    let length = length(g);
    return select(vec3<f32>(0.0), g / length, length > 0.0);
}

// Rust: quadric_fit::intersect::first_hit. Returns vec2(t, 1.0) for a hit and
// vec2(0.0, 0.0) for a miss (Rust: None). The caller guarantees finite inputs (WGSL may
// assume no NaN or infinity); t_min > t_max misses as in Rust.
fn quadric_first_hit(q: GpuQuadric, origin: vec3<f32>, direction: vec3<f32>, t_min: f32, t_max: f32) -> vec2<f32> {
    if t_min > t_max {
        return vec2<f32>(0.0);
    }
    let r = direction;
    let alpha = q.abcd.x * r.x * r.x + q.abcd.y * r.y * r.y + q.abcd.z * r.z * r.z + q.abcd.w * r.x * r.y
        + q.efgh.x * r.y * r.z + q.efgh.y * r.z * r.x;
    let beta = dot(quadric_gradient(q, origin), r);
    let gamma = quadric_value(q, origin);
    if alpha == 0.0 && beta == 0.0 {
        return vec2<f32>(0.0);
    }
    let discriminant = beta * beta - 4.0 * alpha * gamma;
    if discriminant < 0.0 {
        return vec2<f32>(0.0);
    }
    let root = sqrt(discriminant);
    let q_stable = -0.5 * (beta + select(-root, root, beta >= 0.0));
    let near = select(0.0, gamma / q_stable, q_stable != 0.0);
    let near_in = near >= t_min && near <= t_max;
    let bound = 2.0 * max(abs(t_min), abs(t_max));
    let far_exists = abs(q_stable) <= abs(alpha) * bound && alpha != 0.0;
    // Divide by 1 instead of 0 when the far root does not exist; the value is unused then.
    let far = q_stable / select(1.0, alpha, far_exists);
    let far_in = far_exists && far >= t_min && far <= t_max;
    if near_in && far_in {
        return vec2<f32>(min(near, far), 1.0);
    }
    if near_in {
        return vec2<f32>(near, 1.0);
    }
    if far_in {
        return vec2<f32>(far, 1.0);
    }
    return vec2<f32>(0.0);
}
