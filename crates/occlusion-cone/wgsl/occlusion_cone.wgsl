// WGSL twin of crates/occlusion-cone: the conservative occlusion test of Michel &
// Boubekeur 2020, §8, Listing 2, derived again (see the crate documentation). Composed
// after generated/occlusion_cone.wgsl, which declares every constant from the Rust source
// (src/wgsl.rs lists them). Each function mirrors the Rust function named in its comment,
// with the same operations in the same order; tests/occlusion_cone_gpu.rs compares them.
//
// A sphere is vec4(centre.xyz, radius) in camera space (eye at the origin), the layout of
// an occluder-map texel. Inputs are classified with bit tests before any float operation
// (WGSL may assume that no NaN or infinity reaches one).

// Rust: occlusion_cone::cone::within. |x| <= limit on the bits (false for NaN and inf).
fn occlusion_within(x: f32, limit: f32) -> bool {
    return (bitcast<u32>(x) & OCCLUSION_ABS_MASK) <= bitcast<u32>(limit);
}

// Rust: occlusion_cone::in_domain.
fn occlusion_in_domain(sphere: vec4<f32>) -> bool {
    let radius_bits = bitcast<u32>(sphere.w);
    return occlusion_within(sphere.x, OCCLUSION_MAX_COORDINATE) && occlusion_within(sphere.y, OCCLUSION_MAX_COORDINATE)
        && occlusion_within(sphere.z, OCCLUSION_MAX_COORDINATE)
        && radius_bits >= bitcast<u32>(OCCLUSION_MIN_RADIUS) && radius_bits <= bitcast<u32>(OCCLUSION_MAX_RADIUS);
}

// Rust: occlusion_cone::cone::dot (summed in this order).
fn occlusion_dot(a: vec3<f32>, b: vec3<f32>) -> f32 {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}

// Rust: occlusion_cone::cone::cross.
fn occlusion_cross(a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

// Rust: occlusion_cone::is_occluded_by. Whether the grain whose outer sphere is `grain` is
// certainly hidden behind the occluder's inner sphere `occluder` (perspective camera; the
// caller skips the test for an orthographic camera or an empty occluder-map texel).
fn occlusion_is_occluded(occluder: vec4<f32>, grain: vec4<f32>) -> bool {
    if !(occlusion_in_domain(occluder) && occlusion_in_domain(grain)) {
        return false;
    }
    let g0 = occluder.xyz;
    let r = occluder.w;
    let g1 = grain.xyz;
    let r2 = r * r;
    let g0_2 = occlusion_dot(g0, g0);
    if g0_2 <= r2 * OCCLUSION_EYE_CLEARANCE {
        return false;
    }
    let k = max(grain.w, r) / r * OCCLUSION_APEX_ROUNDING;
    let d = g1 - g0 * k;
    if occlusion_dot(g0, d) <= 0.0 {
        return false;
    }
    let c = occlusion_cross(g0, g1);
    let lhs = occlusion_dot(c, c);
    let rhs = r2 * occlusion_dot(d, d);
    let g1_2 = occlusion_dot(g1, g1);
    let rho = sqrt(rhs);
    let reach = sqrt(2.0 * (g1_2 + k * k * g0_2));
    let margin = OCCLUSION_MARGIN * rho * (sqrt(g0_2 * g1_2) + r * reach + rho);
    return lhs + margin < rhs;
}
