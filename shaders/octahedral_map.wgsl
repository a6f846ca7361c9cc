// WGSL twin of crates/octahedral-map: view directions on a subdivided octahedron
// (Michel & Boubekeur 2020, §4.2, Listing 1).
//
// Composed after shaders/generated/octahedral_map.wgsl, which declares ViewSample,
// OctahedralUniforms, OCTAHEDRAL_MAX_SUBDIVISIONS and OCTAHEDRAL_FALLBACK_DIRECTION from
// the Rust source. Every function here mirrors the Rust function named in its comment and
// is proven equal to it by tests/octahedral_map_gpu.rs.

const OCTAHEDRAL_ABS_MASK: u32 = 0x7fffffffu;
const OCTAHEDRAL_INFINITY_BITS: u32 = 0x7f800000u;

// Rust: direction::flush_subnormal (componentwise).
fn octahedral_flush_subnormal(v: vec3<f32>) -> vec3<f32> {
    let is_subnormal = (bitcast<vec3<u32>>(v) & vec3<u32>(OCTAHEDRAL_INFINITY_BITS)) == vec3<u32>(0u);
    return select(v, vec3<f32>(0.0), is_subnormal);
}

// Rust: octahedral_map::canonical_direction. Classifies with integer bit tests, since WGSL
// implementations may assume that no NaN or infinity reaches float operations.
fn octahedral_canonical_direction(direction: vec3<f32>) -> vec3<f32> {
    let raw = bitcast<vec3<u32>>(direction);
    let magnitude = raw & vec3<u32>(OCTAHEDRAL_ABS_MASK);
    if any(magnitude > vec3<u32>(OCTAHEDRAL_INFINITY_BITS)) {
        return OCTAHEDRAL_FALLBACK_DIRECTION;
    }
    let infinite = magnitude == vec3<u32>(OCTAHEDRAL_INFINITY_BITS);
    if any(infinite) {
        let negative = (raw & vec3<u32>(0x80000000u)) != vec3<u32>(0u);
        return select(vec3<f32>(0.0), select(vec3<f32>(1.0), vec3<f32>(-1.0), negative), infinite);
    }
    let flushed = octahedral_flush_subnormal(direction);
    let largest = max(max(abs(flushed.x), abs(flushed.y)), abs(flushed.z));
    if largest == 0.0 {
        return OCTAHEDRAL_FALLBACK_DIRECTION;
    }
    // Multiply by the exact power of two 2^(128 - e) that brings `largest` into [2, 4).
    let exponent = (bitcast<u32>(largest) >> 23u) & 0xffu;
    let scale = bitcast<f32>((255u - exponent) << 23u);
    return octahedral_flush_subnormal(flushed * scale);
}

// Rust: octahedral_map::views::view_sample_from_direction (Listing 1).
fn octahedral_view_sample(direction: vec3<f32>, subdivisions: u32) -> ViewSample {
    let n = clamp(subdivisions, 1u, OCTAHEDRAL_MAX_SUBDIVISIONS);
    let d = octahedral_canonical_direction(direction);
    // Cancellation-free form of Listing 1's (px ± py + 1)(n-1)/2, see the Rust docs.
    let x_pos = max(d.x, 0.0);
    let x_neg = max(-d.x, 0.0);
    let y_pos = max(d.y, 0.0);
    let y_neg = max(-d.y, 0.0);
    let z_abs = abs(d.z);
    let twice_l1 = 2.0 * (x_pos + x_neg + y_pos + y_neg + z_abs);
    let edge = f32(n - 1u);
    let u = clamp((2.0 * (x_pos + y_pos) + z_abs) / twice_l1 * edge, 0.0, edge);
    let v = clamp((2.0 * (x_pos + y_neg) + z_abs) / twice_l1 * edge, 0.0, edge);
    let uv_floor = floor(vec2<f32>(u, v));
    let lo = vec2<u32>(uv_floor);
    let hi = vec2<u32>(ceil(vec2<f32>(u, v)));
    let hemisphere = select(0u, n * n, d.z > 0.0);
    var sample: ViewSample;
    sample.indices = vec4<u32>(lo.x * n + lo.y, hi.x * n + lo.y, lo.x * n + hi.y, hi.x * n + hi.y) + hemisphere;
    sample.alpha = vec2<f32>(u, v) - uv_floor;
    sample.padding = vec2<f32>(0.0);
    return sample;
}

// Rust: ViewSample::weights.
fn octahedral_view_weights(sample: ViewSample) -> vec4<f32> {
    let a = sample.alpha;
    return vec4<f32>((1.0 - a.x) * (1.0 - a.y), a.x * (1.0 - a.y), (1.0 - a.x) * a.y, a.x * a.y);
}

// Rust: OctahedralViews::view_direction. Returns vec3(0) where Rust returns None
// (view_index >= 2n²).
fn octahedral_view_direction(view_index: u32, subdivisions: u32) -> vec3<f32> {
    let n = clamp(subdivisions, 1u, OCTAHEDRAL_MAX_SUBDIVISIONS);
    let per_hemisphere = n * n;
    if view_index >= 2u * per_hemisphere {
        return vec3<f32>(0.0);
    }
    let upper = view_index >= per_hemisphere;
    if n == 1u {
        return vec3<f32>(0.0, 0.0, select(-1.0, 1.0, upper));
    }
    let local = view_index % per_hemisphere;
    let edge = i32(n) - 1;
    let u = i32(local / n);
    let v = i32(local % n);
    let x = u + v - edge;
    let y = u - v;
    let z = edge - abs(x) - abs(y);
    return normalize(vec3<f32>(f32(x), f32(y), f32(select(-z, z, upper))));
}
