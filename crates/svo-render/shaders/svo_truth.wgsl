// The voxel truth of svo_render::GpuVoxelTruth (entry points: see svo_truth_primary): the octree's finest level supersampled over
// each pixel's footprint (and lens), sphere-traced, shaded with the base BRDF and the local
// attribute, shadowed by stratified rays towards the area light (crates/svo-render/src/
// truth.rs, which documents the method; each function below mirrors the Rust function named
// in its comment). Composed after the svo_tracer module (svo_pixel_cone, svo_box_interval,
// svo_element_radiance; the octree at bindings 3-7 through svo_brick) and the generated
// declarations of crates/svo-render (GpuTruthSettings, SVO_RENDER_TILE).
//
// Where it departs from the Rust, which traces in f64: each ray is traced from its entry
// into the domain (so that its parameter stays below the domain's diagonal, where an f32
// ulp is far below ε: GpuVoxelTruth refuses an ε under 2^-21 of the domain's size and
// coordinates), and a bisection also stops when its midpoint rounds to an end.

@group(0) @binding(0) var<uniform> svo_tree: OctreeUniforms;
@group(0) @binding(2) var<uniform> svo_camera: GpuCamera;
@group(0) @binding(9) var<uniform> svo_settings: GpuTraceSettings;
@group(0) @binding(10) var<uniform> svo_truth: GpuTruthSettings;
@group(0) @binding(11) var<storage, read_write> svo_sums: array<vec4<f32>>;
@group(0) @binding(12) var<storage, read_write> svo_evaluations: array<u32>;
@group(0) @binding(13) var<storage, read_write> svo_schedule: array<u32>;
@group(0) @binding(14) var<storage, read_write> svo_radiance_coverage: array<vec4<f32>>;
@group(0) @binding(15) var<storage, read_write> svo_pending: array<SvoTruthPending>;

// A pixel's ray between its passes: (hit point, 1 if it hit), (unit normal, shadow rays that
// reached the light), (attribute, 1 if shadow rays are cast), (direction, 0).
struct SvoTruthPending {
    point_hit: vec4<f32>,
    normal_free: vec4<f32>,
    attribute_shadowed: vec4<f32>,
    direction: vec4<f32>,
}

// Rust: truth::hash (Wellons' lowbias32).
fn svo_truth_hash(value: u32) -> u32 {
    var x = value;
    x ^= x >> 16u;
    x *= 0x7feb352du;
    x ^= x >> 15u;
    x *= 0x846ca68bu;
    return x ^ (x >> 16u);
}

// Rust: truth::random (24 bits: exact in f32 as in f64).
fn svo_truth_random(pixel: u32, sample: u32, dimension: u32) -> f32 {
    let h = svo_truth_hash(pixel ^ svo_truth_hash((sample * 0x9e3779b9u) ^ svo_truth_hash(dimension + 0x632be5abu)));
    return f32(h >> 8u) / 16777216.0;
}

// Rust: truth::concentric (Shirley & Chiu's map of [0, 1)^2 onto the unit disk).
fn svo_truth_concentric(a: f32, b: f32) -> vec2<f32> {
    let x = 2.0 * a - 1.0;
    let y = 2.0 * b - 1.0;
    if x == 0.0 && y == 0.0 {
        return vec2<f32>(0.0);
    }
    let quarter = 0.7853981633974483;
    var r = y;
    var phi = 2.0 * quarter - quarter * x / y;
    if abs(x) > abs(y) {
        r = x;
        phi = quarter * y / x;
    }
    return vec2<f32>(r * cos(phi), r * sin(phi));
}

// Rust: truth::VoxelGeometry::distance; (distance, 1 where it is known).
fn svo_truth_distance(p: vec3<f32>) -> vec2<f32> {
    let s = svo_sample(svo_tree, p, 0.0);
    let d = s.voxel.distance;
    let finite = (bitcast<u32>(d) & 0x7fffffffu) < 0x7f800000u;
    return vec2<f32>(d, select(0.0, 1.0, s.inside && finite));
}

// What truth::intersect returns: the hit point (not its parameter), whether there is one,
// and the distance evaluations spent.
struct SvoTruthHit {
    point: vec3<f32>,
    hit: bool,
    evaluations: u32,
}

// Rust: truth::intersect, from the ray's entry into the domain (see the header). One loop
// whose state is either marching (b < 0) or bisecting (a, b), left by `break` alone, with
// one return after it: lavapipe (Mesa 22.3) miscompiled this function's earlier forms — a
// bisection loop nested in the march, or returns from inside the loop — so that the
// caller's loop over the pixel's samples stopped early.
fn svo_truth_intersect(origin: vec3<f32>, direction: vec3<f32>, limit: f32) -> SvoTruthHit {
    var result: SvoTruthHit;
    result.hit = false;
    result.evaluations = 0u;
    let lo = svo_tree.origin_inverse_size.xyz;
    let hi = lo + svo_tree.voxel_size.x * f32(svo_tree.counts.z);
    let interval = svo_box_interval(origin, direction, lo, hi);
    let base = origin + direction * interval.x;
    let span = min(interval.y, limit) - interval.x;
    let epsilon = svo_truth.epsilon_jitter.x;
    let max_steps = select(0u, svo_truth.counts.w, interval.z != 0.0);
    var t = epsilon;
    var a = 0.0;
    var b = -1.0;
    var has_previous = false;
    var evaluations = 0u;
    var at = -1.0;
    while evaluations < max_steps {
        if b >= 0.0 {
            // Bisecting: the surface lies in (a, b).
            let m = 0.5 * (a + b);
            if m <= a || m >= b {
                at = m;
                break;
            }
            evaluations += 1u;
            let dm = svo_truth_distance(base + direction * m);
            if dm.y == 0.0 {
                break;
            }
            if abs(dm.x) < epsilon {
                at = m;
                break;
            }
            if dm.x > 0.0 {
                a = m;
            } else {
                b = m;
            }
            if b - a <= epsilon * 1e-3 {
                break;
            }
        } else {
            if t > span {
                break;
            }
            evaluations += 1u;
            let d = svo_truth_distance(base + direction * t);
            if d.y == 0.0 {
                break;
            }
            if abs(d.x) < epsilon || (d.x < 0.0 && !has_previous) {
                at = t;
                break;
            }
            if d.x < 0.0 {
                b = t;
            } else {
                a = t;
                has_previous = true;
                t += d.x;
            }
        }
    }
    // A bisection that ran out (steps, an unknown distance, or a bracket below 10^-3 ε)
    // ends at its bracket's middle.
    if at < 0.0 && b >= 0.0 {
        at = 0.5 * (a + b);
    }
    result.hit = at >= 0.0;
    result.point = base + direction * max(at, 0.0);
    result.evaluations = evaluations;
    return result;
}

// Rust: truth::frame_of; (t1, t2) as columns.
fn svo_truth_frame_of(w: vec3<f32>) -> mat2x3<f32> {
    var helper = vec3<f32>(0.0, 1.0, 0.0);
    if abs(w.x) < 0.9 {
        helper = vec3<f32>(1.0, 0.0, 0.0);
    }
    let t1 = normalize(cross(w, helper));
    return mat2x3<f32>(t1, cross(w, t1));
}

// Rust: shadow ray `q` (= j s + i) of truth::light_visibility from `x` (normal `n`) for the
// pixel's sample `seed`: whether it reaches its point of the light's disk, and the
// evaluations spent.
fn svo_truth_shadow_ray(x: vec3<f32>, n: vec3<f32>, pixel: u32, seed: u32, q: u32) -> vec2<u32> {
    let s = svo_truth.counts.z;
    let centre = svo_settings.light.xyz;
    let origin = x + n * (16.0 * svo_truth.epsilon_jitter.x);
    let towards = centre - origin;
    let length2 = dot(towards, towards);
    let finite = (bitcast<u32>(length2) & 0x7fffffffu) < 0x7f800000u;
    if !(length2 > 0.0 && finite) {
        return vec2<u32>(1u, 0u);
    }
    let w = towards * inverseSqrt(length2);
    let frame = svo_truth_frame_of(w);
    let radius = max(svo_settings.light.w, 0.0);
    let i = q % s;
    let j = q / s;
    let sample = seed * 257u + q;
    var ja = 0.5;
    var jb = 0.5;
    if svo_truth.epsilon_jitter.y != 0.0 {
        ja = svo_truth_random(pixel, sample, 5u);
        jb = svo_truth_random(pixel, sample, 6u);
    }
    let disk = svo_truth_concentric((f32(i) + ja) / f32(s), (f32(j) + jb) / f32(s));
    let aim = centre + (frame[0] * disk.x + frame[1] * disk.y) * radius;
    let to = aim - origin;
    let length = length(to);
    if !(length > 0.0) {
        return vec2<u32>(1u, 0u);
    }
    let ray = svo_truth_intersect(origin, to / length, length);
    return vec2<u32>(select(0u, 1u, !ray.hit), ray.evaluations);
}

// The light's direction from `x` (Rust: normalize_or_zero).
fn svo_truth_light_direction(x: vec3<f32>) -> vec3<f32> {
    let to_light = svo_settings.light.xyz - x;
    let length2 = dot(to_light, to_light);
    if length2 > 0.0 && (bitcast<u32>(length2) & 0x7fffffffu) < 0x7f800000u {
        return to_light * inverseSqrt(length2);
    }
    return vec3<f32>(0.0);
}

// The pixel's sample svo_schedule[0] (in the Rust's order: j, i, lj, li), its shadow ray
// svo_schedule[1]; (sample, shadow ray, whether the sample exists).
fn svo_truth_scheduled(pixel_cone: SvoCone) -> vec3<u32> {
    let k = svo_truth.counts.x;
    let lens = pixel_cone.kind == SVO_CONE_LENS && pixel_cone.aperture > 0.0;
    let m = select(1u, svo_truth.counts.y, lens);
    let sample = svo_schedule[0];
    return vec3<u32>(sample, svo_schedule[1], select(0u, 1u, sample < k * k * m * m));
}

// Rust: truth_pixel's ray of one sample and the first half of truth::shade_ray, for
// truth::VoxelGeometry: the pixel's ray of sample svo_schedule[0], its hit and what
// shading needs, into svo_pending (its evaluations added to the pixel's, written for
// sample 0).
//
// A frame runs, per sample in the Rust's order, svo_truth_primary, then per shadow ray
// svo_truth_shadow and svo_truth_next_shadow, then svo_truth_accumulate and
// svo_truth_next_sample, then svo_truth_resolve once. The sums are the Rust's sequence;
// the passes, rather than loops over the samples and shadow rays in one invocation, run
// on lavapipe, whose loop limiter (Mesa 22.3's gallivm: 65 535 iterations of a loop and
// every loop nested in it, per invocation) ended such loops early.
@compute @workgroup_size(SVO_RENDER_TILE, SVO_RENDER_TILE)
fn svo_truth_primary(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = svo_camera.size.xy;
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let cone = svo_pixel_cone(svo_camera, id.x, id.y);
    let pixel = id.y * size.x + id.x;
    let scheduled = svo_truth_scheduled(cone);
    if scheduled.z == 0u {
        return;
    }
    let sample = scheduled.x;
    let k = svo_truth.counts.x;
    let lens = cone.kind == SVO_CONE_LENS && cone.aperture > 0.0;
    let m = select(1u, svo_truth.counts.y, lens);
    let li = sample % m;
    let lj = (sample / m) % m;
    let i = (sample / (m * m)) % k;
    let j = sample / (m * m * k);
    var jitters = vec4<f32>(0.5);
    if svo_truth.epsilon_jitter.y != 0.0 {
        jitters = vec4<f32>(
            svo_truth_random(pixel, sample, 0u),
            svo_truth_random(pixel, sample, 1u),
            svo_truth_random(pixel, sample, 2u),
            svo_truth_random(pixel, sample, 3u),
        );
    }
    let u = (f32(i) + jitters.x) / f32(k) - 0.5;
    // y down in the image, `up` up in the footprint: stratum rows top to bottom.
    let v = 0.5 - (f32(j) + jitters.y) / f32(k);
    let d = cone.direction + (cone.right * u + cone.up * v) * cone.spread;
    var origin = cone.origin;
    var direction = normalize(d);
    if lens {
        let disk = svo_truth_concentric((f32(li) + jitters.z) / f32(m), (f32(lj) + jitters.w) / f32(m));
        origin = cone.origin + (cone.right * disk.x + cone.up * disk.y) * (0.5 * cone.aperture);
        let focus = cone.origin + d * cone.focus;
        direction = normalize(focus - origin);
    }
    let hit = svo_truth_intersect(origin, direction, 3.4028235e38);
    var pending: SvoTruthPending;
    pending.point_hit = vec4<f32>(hit.point, select(0.0, 1.0, hit.hit));
    pending.direction = vec4<f32>(direction, 0.0);
    if hit.hit {
        let s = svo_sample(svo_tree, hit.point, 0.0);
        if s.inside {
            pending.normal_free = vec4<f32>(s.voxel.normal, 0.0);
            pending.attribute_shadowed = vec4<f32>(s.voxel.mean_attribute, 0.0);
        }
        let light = svo_truth_light_direction(hit.point);
        let shadowed = svo_truth.counts.z > 0u && dot(pending.normal_free.xyz, light) > 0.0;
        pending.attribute_shadowed.w = select(0.0, 1.0, shadowed);
    }
    svo_pending[pixel] = pending;
    if sample == 0u {
        svo_evaluations[pixel] = hit.evaluations;
    } else {
        svo_truth_add_evaluations(pixel, hit.evaluations);
    }
}

// Adds `n` to the pixel's evaluations, saturating (Rust: u32::saturating_add).
fn svo_truth_add_evaluations(pixel: u32, n: u32) {
    let before = svo_evaluations[pixel];
    let total = before + n;
    svo_evaluations[pixel] = select(total, 0xffffffffu, total < before);
}

// Rust: one ray of truth::light_visibility: the pixel's shadow ray svo_schedule[1], where
// its sample hit with the light above its horizon.
@compute @workgroup_size(SVO_RENDER_TILE, SVO_RENDER_TILE)
fn svo_truth_shadow(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = svo_camera.size.xy;
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let cone = svo_pixel_cone(svo_camera, id.x, id.y);
    let pixel = id.y * size.x + id.x;
    let scheduled = svo_truth_scheduled(cone);
    let pending = svo_pending[pixel];
    if scheduled.z == 0u || pending.attribute_shadowed.w == 0.0 {
        return;
    }
    let ray = svo_truth_shadow_ray(pending.point_hit.xyz, pending.normal_free.xyz, pixel, scheduled.x, scheduled.y);
    svo_pending[pixel].normal_free.w = pending.normal_free.w + f32(ray.x);
    svo_truth_add_evaluations(pixel, ray.y);
}

// Rust: the end of truth::shade_ray and the sum of truth::truth_pixel: the sample's
// radiance (the background for a miss) and hit added to the pixel's sums (written for
// sample 0).
@compute @workgroup_size(SVO_RENDER_TILE, SVO_RENDER_TILE)
fn svo_truth_accumulate(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = svo_camera.size.xy;
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let cone = svo_pixel_cone(svo_camera, id.x, id.y);
    let pixel = id.y * size.x + id.x;
    let scheduled = svo_truth_scheduled(cone);
    if scheduled.z == 0u {
        return;
    }
    let pending = svo_pending[pixel];
    var radiance = svo_settings.background_floor.xyz;
    let hit = pending.point_hit.w != 0.0;
    if hit {
        var voxel: SvoRawVoxel;
        voxel.normal = pending.normal_free.xyz;
        voxel.mean_attribute = pending.attribute_shadowed.xyz;
        var visibility = 1.0;
        if pending.attribute_shadowed.w != 0.0 {
            let s = svo_truth.counts.z;
            visibility = pending.normal_free.w / f32(max(s * s, 1u));
        }
        let light = svo_truth_light_direction(pending.point_hit.xyz);
        radiance = svo_element_radiance(voxel, -pending.direction.xyz, light, svo_settings, false, visibility);
    }
    let added = vec4<f32>(radiance, select(0.0, 1.0, hit));
    if scheduled.x == 0u {
        svo_sums[pixel] = added;
    } else {
        svo_sums[pixel] += added;
    }
}

// Moves the schedule to the next shadow ray (one invocation, between passes).
@compute @workgroup_size(1)
fn svo_truth_next_shadow() {
    svo_schedule[1] += 1u;
}

// Moves the schedule to the next sample's first shadow ray (one invocation, between passes).
@compute @workgroup_size(1)
fn svo_truth_next_sample() {
    svo_schedule[0] += 1u;
    svo_schedule[1] = 0u;
}

// Rust: the end of truth::truth_pixel: (mean radiance, covered fraction) per pixel.
@compute @workgroup_size(SVO_RENDER_TILE, SVO_RENDER_TILE)
fn svo_truth_resolve(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = svo_camera.size.xy;
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let pixel = id.y * size.x + id.x;
    let lens = svo_camera.size.z == SVO_CONE_LENS && svo_camera.lens.x > 0.0;
    let m = select(1u, svo_truth.counts.y, lens);
    let n = f32(max(svo_truth.counts.x * svo_truth.counts.x * m * m, 1u));
    let sums = svo_sums[pixel];
    svo_radiance_coverage[pixel] = vec4<f32>(sums.xyz / n, sums.w / n);
}
