// The bindings every pass of the grain splitter shares, and the projections of a grain's
// centre. Composed after generated.wgsl (SplitCamera, SplitParams and the constants of the
// Rust modules camera, settings and lists). Each function mirrors the Rust function named in
// its comment, with the same operations in the same order.

@group(0) @binding(0) var<uniform> camera: SplitCamera;
@group(0) @binding(1) var<uniform> params: SplitParams;
// Per grain: world centre (xyz) and scale (w).
@group(0) @binding(2) var<storage, read> grains: array<vec4<f32>>;

// The grain an invocation of a per-grain pass handles: (x, y) workgroups of SPLIT_WORKGROUP.
fn split_block(workgroup: vec3<u32>, workgroups: vec3<u32>) -> u32 {
    return workgroup.y * workgroups.x + workgroup.x;
}

// The grain of invocation `local` of that workgroup.
fn split_grain(workgroup: vec3<u32>, workgroups: vec3<u32>, local: u32) -> u32 {
    return split_block(workgroup, workgroups) * SPLIT_WORKGROUP + local;
}

// Rust: camera::transform. m · (p, 1) as a sum of scaled columns, in this order.
fn split_transform(m: array<vec4<f32>, 4>, p: vec3<f32>) -> vec4<f32> {
    return m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3];
}

struct SplitProjected {
    view: vec3<f32>,
    view_depth: f32,
    pixel: vec2<f32>,
    in_front: bool,
}

// Rust: SplitCamera::project.
fn split_project(centre: vec3<f32>) -> SplitProjected {
    let view = split_transform(camera.view_from_world, centre);
    let clip = split_transform(camera.clip_from_world, centre);
    var out: SplitProjected;
    out.view = view.xyz;
    out.view_depth = -view.z;
    out.in_front = clip.w > 0.0;
    if out.in_front {
        let inverse_w = 1.0 / clip.w;
        let ndc = vec2<f32>(clip.x * inverse_w, clip.y * inverse_w);
        out.pixel = vec2<f32>((ndc.x * 0.5 + 0.5) * camera.viewport.x, (0.5 - ndc.y * 0.5) * camera.viewport.y);
    }
    return out;
}

// Rust: Projected::centre_texel (for a centre in front of the eye).
fn split_centre_texel(pixel: vec2<f32>) -> vec2<u32> {
    return vec2<u32>(clamp(floor(pixel), vec2<f32>(0.0), camera.viewport.xy - 1.0));
}

struct SplitSplat {
    min: vec2<u32>,
    max: vec2<u32>,
    depth_bits: u32,
    valid: bool,
}

// Rust: reference::splat. The grain's square in the occluder map.
fn split_splat(grain: vec4<f32>) -> SplitSplat {
    return split_splat_with(grain, params.radii.z);
}

// Rust: reference::splat with the splat factor `factor` (temporal::cover_square).
fn split_splat_with(grain: vec4<f32>, factor: f32) -> SplitSplat {
    var out: SplitSplat;
    out.valid = false;
    let radius = params.radii.x * grain.w;
    if !(radius > 0.0) {
        return out;
    }
    let projected = split_project(grain.xyz);
    if !projected.in_front {
        return out;
    }
    let depth = projected.view_depth;
    if !(depth > 0.0) {
        return out;
    }
    let focal = camera.projection.x;
    var radius_pixels = radius * focal;
    if camera.projection.y != 0.0 {
        radius_pixels = radius * focal / depth;
    }
    let half = min(factor * radius_pixels, params.radii.w);
    let size = camera.viewport.xy;
    let lo = clamp(floor(projected.pixel - half), vec2<f32>(-1.0), size);
    let hi = clamp(floor(projected.pixel + half), vec2<f32>(-1.0), size);
    if hi.x < 0.0 || hi.y < 0.0 || lo.x >= size.x || lo.y >= size.y {
        return out;
    }
    out.min = vec2<u32>(clamp(lo, vec2<f32>(0.0), size - 1.0));
    out.max = vec2<u32>(clamp(hi, vec2<f32>(0.0), size - 1.0));
    out.depth_bits = bitcast<u32>(depth);
    out.valid = true;
    return out;
}

// Rust: reference::outside_frustum.
fn split_outside_frustum(centre: vec3<f32>, radius: f32) -> bool {
    for (var i = 0u; i < 6u; i++) {
        let plane = camera.frustum[i];
        let x = plane.x * centre.x;
        let y = plane.y * centre.y;
        let z = plane.z * centre.z;
        let distance = x + y + z + plane.w;
        let slack = FRUSTUM_MARGIN * (abs(x) + abs(y) + abs(z) + abs(plane.w) + radius);
        if distance < -(radius + slack) {
            return true;
        }
    }
    return false;
}

// Rust: TierThresholds::tier (one boundary). `thresholds` = (up, down, plain, 0);
// `previous` = 1 + the last tier, 0 = no history; `boundary` = the tier above it.
fn split_above(thresholds: vec4<f32>, boundary: u32, previous: u32, twice_radius_focal: f32, depth: f32) -> bool {
    var threshold = thresholds.z;
    if previous != 0u {
        threshold = select(thresholds.x, thresholds.y, previous - 1u >= boundary);
    }
    return twice_radius_focal > threshold * depth;
}

// Rust: TierThresholds::tier. 0 point, 1 impostor, 2 mesh.
fn split_tier(twice_radius_focal: f32, depth: f32, previous: u32) -> u32 {
    if !(depth > 0.0) {
        return 2u;
    }
    if split_above(params.mesh_thresholds, 2u, previous, twice_radius_focal, depth) {
        return 2u;
    }
    if split_above(params.point_thresholds, 1u, previous, twice_radius_focal, depth) {
        return 1u;
    }
    return 0u;
}
