// WGSL twin of crates/octahedral-map: view directions on a subdivided octahedron
// (Michel & Boubekeur 2020, §4.2, Listing 1).
//
// Composed after generated/octahedral_map.wgsl, which declares ViewSample, the sampler's
// structs and every constant (limits, fallback direction, float bit masks) from the Rust
// source (src/wgsl.rs lists them). Every function here mirrors the Rust function named in
// its comment and is proven equal to it by tests/octahedral_map_gpu.rs and
// tests/impostor_sampling_gpu.rs.

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
        let negative = (raw & vec3<u32>(OCTAHEDRAL_SIGN_MASK)) != vec3<u32>(0u);
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

// Rust: direction::is_plain_direction. Not zero, every component ±0 or of magnitude in
// [2^-63, 2^64): then the canonical form would change no bit of the sample.
fn octahedral_is_plain_direction(direction: vec3<f32>) -> bool {
    let magnitude = bitcast<vec3<u32>>(direction) & vec3<u32>(OCTAHEDRAL_ABS_MASK);
    // MIN <= m < END in one (wrapping) comparison.
    let in_range = (magnitude - vec3<u32>(OCTAHEDRAL_PLAIN_MIN_BITS))
        < vec3<u32>(OCTAHEDRAL_PLAIN_END_BITS - OCTAHEDRAL_PLAIN_MIN_BITS);
    // `&`, not `&&`: no short-circuit branch.
    return all(in_range | (magnitude == vec3<u32>(0u))) & any(in_range);
}

// Rust: octahedral_map::views::view_sample_from_direction (Listing 1). Classifies the
// input once; only a direction that is not plain takes the canonical form.
fn octahedral_view_sample(direction: vec3<f32>, subdivisions: u32) -> ViewSample {
    let n = clamp(subdivisions, 1u, OCTAHEDRAL_MAX_SUBDIVISIONS);
    var d = direction;
    if !octahedral_is_plain_direction(direction) {
        d = octahedral_canonical_direction(direction);
    }
    return octahedral_view_sample_of_plain(d, n);
}

// Rust: views::view_sample_of_plain, for a plain or canonical d and n in
// 1..=OCTAHEDRAL_MAX_SUBDIVISIONS. Cancellation-free form of Listing 1's
// (px ± py + 1)(n-1)/2, see the Rust docs; the same bits in other words:
// fma(2, a, |z|) = 2a + |z| (2a is exact, fused or not), and the hemisphere's n² is added
// to the two rows (integer sums reassociate exactly).
fn octahedral_view_sample_of_plain(d: vec3<f32>, n: u32) -> ViewSample {
    let a = abs(d);
    let x_pos = max(d.x, 0.0);
    let y_pos = max(d.y, 0.0);
    let y_neg = a.y - y_pos; // max(-y, 0), exactly
    let twice_l1 = 2.0 * (a.x + a.y + a.z);
    let edge = f32(n - 1u);
    let u = clamp(fma(2.0, x_pos + y_pos, a.z) / twice_l1 * edge, 0.0, edge);
    let v = clamp(fma(2.0, x_pos + y_neg, a.z) / twice_l1 * edge, 0.0, edge);
    let uv_floor = floor(vec2<f32>(u, v));
    let lo = vec2<u32>(uv_floor);
    let hi = vec2<u32>(ceil(vec2<f32>(u, v)));
    let rows = vec2<u32>(lo.x, hi.x) * n + select(0u, n * n, d.z > 0.0);
    var sample: ViewSample;
    sample.indices = vec4<u32>(rows.x + lo.y, rows.y + lo.y, rows.x + hi.y, rows.y + hi.y);
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

// ---------------------------------------------------------------------------------------
// The compact layout (Rust: octahedral_map::compact): each distinct view stored once.

// Rust: compact::compact_view_count.
fn octahedral_compact_view_count(subdivisions: u32) -> u32 {
    let n = clamp(subdivisions, 1u, OCTAHEDRAL_MAX_SUBDIVISIONS);
    if n == 1u {
        return 2u;
    }
    return n * n + (n - 2u) * (n - 2u);
}

// Rust: compact::compact_from_listing_index.
fn octahedral_compact_index(index: u32, subdivisions: u32) -> u32 {
    let n = clamp(subdivisions, 1u, OCTAHEDRAL_MAX_SUBDIVISIONS);
    let per_hemisphere = n * n;
    let i = index % (2u * per_hemisphere);
    if n == 1u || i < per_hemisphere {
        return i;
    }
    let local = i - per_hemisphere;
    let u = local / n;
    let v = local % n;
    if u == 0u || v == 0u || u == n - 1u || v == n - 1u {
        return local;
    }
    return per_hemisphere + (u - 1u) * (n - 2u) + (v - 1u);
}

// Rust: compact::listing_from_compact_index.
fn octahedral_listing_index(compact: u32, subdivisions: u32) -> u32 {
    let n = clamp(subdivisions, 1u, OCTAHEDRAL_MAX_SUBDIVISIONS);
    let per_hemisphere = n * n;
    let c = compact % octahedral_compact_view_count(n);
    if n == 1u || c < per_hemisphere {
        return c;
    }
    let interior = c - per_hemisphere;
    return per_hemisphere + (interior / (n - 2u) + 1u) * n + interior % (n - 2u) + 1u;
}

// ---------------------------------------------------------------------------------------
// View frames (Rust: octahedral_map::ViewFrame).

// Rust: ViewFrame.
struct OctahedralViewFrame {
    right: vec3<f32>,
    up: vec3<f32>,
    direction: vec3<f32>,
}

// Rust: ViewFrame::from_unit_direction (Duff et al. 2017, listing 3).
fn octahedral_view_frame(direction: vec3<f32>) -> OctahedralViewFrame {
    let x = direction.x;
    let y = direction.y;
    let z = direction.z;
    let sign = select(-1.0, 1.0, z >= 0.0);
    let a = -1.0 / (sign + z);
    let b = x * y * a;
    var frame: OctahedralViewFrame;
    frame.right = vec3<f32>(1.0 + sign * x * x * a, sign * b, -sign * x);
    frame.up = vec3<f32>(b, sign + y * y * a, -y);
    frame.direction = direction;
    return frame;
}

// Rust: ViewFrame::texture_coordinates.
fn octahedral_texture_coordinates(frame: OctahedralViewFrame, point: vec3<f32>, extent: f32) -> vec2<f32> {
    let scale = 0.5 / extent;
    return vec2<f32>(0.5 + dot(point, frame.right) * scale, 0.5 - dot(point, frame.up) * scale);
}

// Rust: ViewFrame::depth.
fn octahedral_view_depth(frame: OctahedralViewFrame, point: vec3<f32>, extent: f32) -> f32 {
    return dot(point, frame.direction) / extent;
}

// Rust: ViewFrame::point_at.
fn octahedral_point_at(frame: OctahedralViewFrame, uv: vec2<f32>, depth: f32, extent: f32) -> vec3<f32> {
    let offset_right = (uv.x - 0.5) * 2.0 * extent;
    let offset_up = (0.5 - uv.y) * 2.0 * extent;
    return frame.right * offset_right + frame.up * offset_up + frame.direction * (depth * extent);
}

// ---------------------------------------------------------------------------------------
// Impostor sampling (Rust: octahedral_map::sampling, paper §4.1 and §5).

// Rust: sampling::GrainRay. `invalid_origin` as in Rust.
struct ImpostorGrainRay {
    origin: vec3<f32>,
    direction: vec3<f32>,
    invalid_origin: bool,
}

// Rust: sampling::ray::within. Bit tests first: no NaN or infinity reaches a float compare.
fn impostor_within(v: vec3<f32>, limit: f32) -> bool {
    let magnitude = bitcast<vec3<u32>>(v) & vec3<u32>(OCTAHEDRAL_ABS_MASK);
    if any(magnitude >= vec3<u32>(OCTAHEDRAL_INFINITY_BITS)) {
        return false;
    }
    return all(abs(v) <= vec3<f32>(limit));
}

// Rust: GrainRay::new.
fn impostor_grain_ray_new(origin: vec3<f32>, direction: vec3<f32>) -> ImpostorGrainRay {
    var ray: ImpostorGrainRay;
    ray.direction = normalize(octahedral_canonical_direction(direction));
    let usable = impostor_within(origin, IMPOSTOR_MAX_RAY_ORIGIN_COMPONENT);
    ray.origin = select(vec3<f32>(0.0), origin, usable);
    ray.invalid_origin = !usable;
    return ray;
}

// Rust: sampling::ray::normalized_rotation; vec4(0) where Rust returns None.
fn impostor_normalized_rotation(rotation: vec4<f32>) -> vec4<f32> {
    let magnitude = bitcast<vec4<u32>>(rotation) & vec4<u32>(OCTAHEDRAL_ABS_MASK);
    if any(magnitude >= vec4<u32>(OCTAHEDRAL_INFINITY_BITS)) {
        return vec4<f32>(0.0);
    }
    let a = abs(rotation);
    let largest = max(max(a.x, a.y), max(a.z, a.w));
    if largest < 1.17549435e-38 {
        return vec4<f32>(0.0);
    }
    return normalize(rotation / largest);
}

// Rust: glam's Quat * Vec3 with the conjugate of the unit quaternion `q` (world → grain).
fn impostor_rotate_inverse(q: vec4<f32>, v: vec3<f32>) -> vec3<f32> {
    let b = -q.xyz;
    let w = q.w;
    return v * (w * w - dot(b, b)) + b * (dot(v, b) * 2.0) + cross(b, v) * (w * 2.0);
}

// Rust: GrainRay::from_world (centre_scale = centre xyz and scale w, as GrainInstance).
fn impostor_grain_ray(world_origin: vec3<f32>, world_direction: vec3<f32>, centre_scale: vec4<f32>, rotation: vec4<f32>) -> ImpostorGrainRay {
    let q = impostor_normalized_rotation(rotation);
    let rotation_ok = any(q != vec4<f32>(0.0));
    var direction = world_direction;
    if rotation_ok {
        direction = impostor_rotate_inverse(q, octahedral_canonical_direction(world_direction));
    }
    let scale = centre_scale.w;
    let scale_finite = (bitcast<u32>(scale) & OCTAHEDRAL_ABS_MASK) < OCTAHEDRAL_INFINITY_BITS;
    var ok = rotation_ok && scale_finite;
    if ok {
        ok = scale >= IMPOSTOR_MIN_GRAIN_SCALE && scale <= IMPOSTOR_MAX_GRAIN_SCALE;
    }
    ok = ok && impostor_within(world_origin, IMPOSTOR_MAX_WORLD_COMPONENT) && impostor_within(centre_scale.xyz, IMPOSTOR_MAX_WORLD_COMPONENT);
    var origin = vec3<f32>(0.0);
    if ok {
        let offset = world_origin - centre_scale.xyz;
        ok = impostor_within(offset, IMPOSTOR_MAX_RAY_ORIGIN_COMPONENT * scale);
        if ok {
            origin = impostor_rotate_inverse(q, offset / scale);
        }
    }
    var ray = impostor_grain_ray_new(origin, direction);
    if !ok {
        ray.origin = vec3<f32>(0.0);
        ray.invalid_origin = true;
    }
    return ray;
}

// Rust: GrainRay::closest_point_to_centre.
fn impostor_closest_point(ray: ImpostorGrainRay) -> vec3<f32> {
    return ray.origin - ray.direction * dot(ray.origin, ray.direction);
}

// Rust: sampling::intersect_proxy_sphere; w = 1 for a hit, 0 for None.
fn impostor_intersect_proxy_sphere(ray: ImpostorGrainRay, radius: f32) -> vec4<f32> {
    let closest = impostor_closest_point(ray);
    let half_chord_squared = radius * radius - dot(closest, closest);
    if ray.invalid_origin || half_chord_squared < 0.0 {
        return vec4<f32>(0.0);
    }
    let half_chord = sqrt(half_chord_squared);
    let t_closest = -dot(ray.origin, ray.direction);
    if t_closest - half_chord >= 0.0 {
        return vec4<f32>(closest - ray.direction * half_chord, 1.0);
    }
    if t_closest + half_chord >= 0.0 {
        return vec4<f32>(closest + ray.direction * half_chord, 1.0);
    }
    return vec4<f32>(0.0);
}

// Rust: sampling::planar_point; w = 1 for a hit, 0 for None.
fn impostor_planar_point(ray: ImpostorGrainRay, frame: OctahedralViewFrame) -> vec4<f32> {
    let cosine = dot(ray.direction, frame.direction);
    if abs(cosine) < IMPOSTOR_MIN_PLANE_COSINE {
        return vec4<f32>(0.0);
    }
    let closest = impostor_closest_point(ray);
    return vec4<f32>(closest - ray.direction * (dot(closest, frame.direction) / cosine), 1.0);
}

// Rust: sampling::sample_impostor.
fn impostor_sample(ray: ImpostorGrainRay, uniforms: ImpostorSamplingUniforms) -> ImpostorSample {
    let n = uniforms.subdivisions;
    let toward_camera = select(-ray.direction, ray.origin, uniforms.selection == 1u);
    let views = octahedral_view_sample(toward_camera, n);
    let outer = uniforms.outer_radius;
    let closest = impostor_closest_point(ray);
    let distance = length(closest);
    let misses_grain = ray.invalid_origin || !(distance <= outer);
    var distance_ratio = IMPOSTOR_MAX_DISTANCE_RATIO;
    if !ray.invalid_origin {
        distance_ratio = clamp(distance / outer, 0.0, IMPOSTOR_MAX_DISTANCE_RATIO);
    }
    var proxy = vec4<f32>(0.0);
    if !misses_grain {
        proxy = impostor_intersect_proxy_sphere(ray, 0.5 * (uniforms.inner_radius + outer));
    }
    var coordinates = array<vec2<f32>, 4>(
        vec2<f32>(IMPOSTOR_MISS_TEXTURE_COORDINATE),
        vec2<f32>(IMPOSTOR_MISS_TEXTURE_COORDINATE),
        vec2<f32>(IMPOSTOR_MISS_TEXTURE_COORDINATE),
        vec2<f32>(IMPOSTOR_MISS_TEXTURE_COORDINATE),
    );
    if !misses_grain {
        for (var k = 0u; k < 4u; k++) {
            let frame = octahedral_view_frame(octahedral_view_direction(views.indices[k], n));
            let planar = impostor_planar_point(ray, frame);
            var point = vec4<f32>(0.0);
            if uniforms.mode == 0u {
                point = planar;
            } else if uniforms.mode == 1u {
                point = proxy;
            } else if planar.w == 1.0 && proxy.w == 1.0 {
                var t = distance_ratio;
                if uniforms.mode == 3u {
                    // Rust: sampling::smoothstep(0.2 ρ/R, ρ/R, d/R), spelled out.
                    let proxy_ratio = 0.5 * (uniforms.inner_radius + outer) / outer;
                    let low = 0.2 * proxy_ratio;
                    let s = clamp((distance_ratio - low) / (proxy_ratio - low), 0.0, 1.0);
                    t = s * s * (3.0 - 2.0 * s);
                }
                point = vec4<f32>(planar.xyz * t + proxy.xyz * (1.0 - t), 1.0);
            } else {
                point = select(proxy, planar, planar.w == 1.0);
            }
            if point.w == 1.0 {
                coordinates[k] = clamp(
                    octahedral_texture_coordinates(frame, point.xyz, outer),
                    vec2<f32>(IMPOSTOR_MISS_TEXTURE_COORDINATE),
                    vec2<f32>(IMPOSTOR_MAX_TEXTURE_COORDINATE),
                );
            }
        }
    }
    var sample: ImpostorSample;
    sample.indices = views.indices;
    if uniforms.view_layout == 1u {
        for (var k = 0u; k < 4u; k++) {
            sample.indices[k] = octahedral_compact_index(views.indices[k], n);
        }
    }
    sample.weights = octahedral_view_weights(views);
    sample.texture_coordinates[0] = vec4<f32>(coordinates[0], coordinates[1]);
    sample.texture_coordinates[1] = vec4<f32>(coordinates[2], coordinates[3]);
    sample.distance_ratio = distance_ratio;
    sample.proxy_hit = select(0u, 1u, proxy.w == 1.0);
    sample.padding = vec2<f32>(0.0);
    return sample;
}
