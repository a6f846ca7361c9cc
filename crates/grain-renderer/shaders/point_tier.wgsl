// The point tier (Fig. 2 ④; crates/grain-renderer/src/impostor_tier.rs): grains of the
// splitter's point list, each a small disc (its outer radius projected, at most
// TIER_POINT_MAX_RADIUS pixels, always the centre's pixel), in the impostor tier's visibility
// buffer (owner tagged with TIER_POINT_BIT), then accumulated: every point grain within its
// own diameter of the depth that won its pixel adds its colour, normal and roughness — read
// from the atlas' 1×1 mips, blended over the 4 views of §5 — to fixed-point sums, so that a
// pixel of sub-pixel grains shows their average instead of one of them (aliasing). Composed
// after impostor_tier.wgsl.

// Per pixel: TIER_POINT_SUMS u32 (weight, albedo rgb, normal xyz, roughness), fixed point.
@group(0) @binding(16) var<storage, read_write> point_sums: array<atomic<u32>>;

// The point grain's pixel and depth (its centre's depth less the atlas' inner radius: the
// nearest its surface can be); none behind the eye or off screen.
struct TierPoint {
    pixel: vec2<u32>,
    screen: vec2<f32>,
    radius: f32,
    depth: f32,
    valid: bool,
}

fn tier_point(grain: GrainInstance) -> TierPoint {
    var out: TierPoint;
    out.valid = false;
    let clip = cloud_clip(grain.centre_scale.xyz);
    if !(clip.w > 0.0) {
        return out;
    }
    let ndc = clip.xy / clip.w;
    let size = camera.viewport.xy;
    let screen = vec2<f32>((ndc.x * 0.5 + 0.5) * size.x, (0.5 - 0.5 * ndc.y) * size.y);
    if !(all(screen >= vec2<f32>(0.0)) && all(screen < size)) {
        return out;
    }
    out.depth = tier_centre_depth(grain) - sampling.inner_radius * grain.centre_scale.w;
    out.pixel = vec2<u32>(screen);
    out.screen = screen;
    // The outer radius over the world size of a pixel at the centre's distance.
    let r0 = cloud_pixel_ray(screen);
    let r1 = cloud_pixel_ray(screen + vec2<f32>(1.0, 0.0));
    let t = dot(grain.centre_scale.xyz - r0.origin, r0.direction);
    let footprint = length((r1.origin + t * r1.direction) - (r0.origin + t * r0.direction));
    out.radius = min(sampling.outer_radius * grain.centre_scale.w / max(footprint, 1e-30), TIER_POINT_MAX_RADIUS);
    out.valid = out.depth > 0.0;
    return out;
}

// The grain's 1×1-mip surface seen from the eye (the 4 views' blend of §5, un-premultiplied).
fn tier_point_surface(grain: GrainInstance) -> CloudSurface {
    let origin = select(cloud_depth_origin(), camera.eye.xyz, cloud_is_perspective());
    var direction = cloud_forward();
    if cloud_is_perspective() {
        direction = normalize(grain.centre_scale.xyz - origin);
    }
    let ray = impostor_grain_ray(origin, direction, grain.centre_scale, grain.rotation);
    let lod = log2(f32(max(cloud.texels, 1u)));
    return cloud_blend(impostor_sample(ray, cloud_sampling()), lod, true, grain.rotation);
}

// One invocation per element of the point list (the splitter's dispatch arguments).
fn tier_point_grain(workgroup: vec3<u32>, workgroups: vec3<u32>, local: u32) -> u32 {
    return tier_element_grain((workgroup.y * workgroups.x + workgroup.x) * ELEMENT_WORKGROUP + local);
}

@compute @workgroup_size(64)
fn tier_point_splat(
    @builtin(workgroup_id) workgroup: vec3<u32>,
    @builtin(num_workgroups) workgroups: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let g = tier_point_grain(workgroup, workgroups, local);
    if g == TIER_NONE {
        return;
    }
    let point = tier_point(instances[g]);
    if !point.valid {
        return;
    }
    let reach = i32(ceil(point.radius));
    for (var dy = -reach; dy <= reach; dy++) {
        for (var dx = -reach; dx <= reach; dx++) {
            let p = tier_disc_pixel(point, dx, dy);
            if p.x >= 0 {
                for (var k = 0u; k < tier_samples() * tier_samples(); k++) {
                    tier_offer(tier_sample_index(vec2<u32>(p), k), point.depth, g | TIER_POINT_BIT);
                }
            }
        }
    }
}

// Pixel (dx, dy) from the centre's pixel if it is in the point's disc (its centre within the
// radius, or the centre's own pixel) and on screen; x = -1 otherwise.
fn tier_disc_pixel(point: TierPoint, dx: i32, dy: i32) -> vec2<i32> {
    let p = vec2<i32>(point.pixel) + vec2<i32>(dx, dy);
    let size = vec2<i32>(tier_size());
    let inside = distance(vec2<f32>(p) + 0.5, point.screen) <= point.radius || (dx == 0 && dy == 0);
    if !inside || p.x < 0 || p.y < 0 || p.x >= size.x || p.y >= size.y {
        return vec2<i32>(-1);
    }
    return p;
}

fn tier_fixed(x: f32, scale: f32) -> u32 {
    return u32(clamp(x, 0.0, 1.0) * scale + 0.5);
}

@compute @workgroup_size(64)
fn tier_point_accumulate(
    @builtin(workgroup_id) workgroup: vec3<u32>,
    @builtin(num_workgroups) workgroups: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let g = tier_point_grain(workgroup, workgroups, local);
    if g == TIER_NONE {
        return;
    }
    let grain = instances[g];
    let point = tier_point(grain);
    if !point.valid {
        return;
    }
    let thickness = 2.0 * sampling.outer_radius * grain.centre_scale.w;
    let surface = tier_point_surface(grain);
    let n = surface.normal * 0.5 + 0.5;
    let reach = i32(ceil(point.radius));
    for (var dy = -reach; dy <= reach; dy++) {
        for (var dx = -reach; dx <= reach; dx++) {
            let p = tier_disc_pixel(point, dx, dy);
            if p.x < 0 {
                continue;
            }
            // The first of the pixel's samples a point grain won (they all take the same depth).
            var won = TIER_NONE;
            for (var k = 0u; k < tier_samples() * tier_samples(); k++) {
                let i = tier_sample_index(vec2<u32>(p), k);
                let winner = tier_winner(i);
                if won == TIER_NONE && winner < TIER_MESH && (winner & TIER_POINT_BIT) != 0u {
                    won = i;
                }
            }
            if won == TIER_NONE || point.depth > tier_stored_depth(won) + thickness {
                continue;
            }
            let base = (u32(p.y) * tier_size().x + u32(p.x)) * TIER_POINT_SUMS;
            atomicAdd(&point_sums[base], 1u);
            atomicAdd(&point_sums[base + 1u], tier_fixed(surface.albedo.r, TIER_POINT_SCALE));
            atomicAdd(&point_sums[base + 2u], tier_fixed(surface.albedo.g, TIER_POINT_SCALE));
            atomicAdd(&point_sums[base + 3u], tier_fixed(surface.albedo.b, TIER_POINT_SCALE));
            atomicAdd(&point_sums[base + 4u], tier_fixed(n.x, TIER_POINT_SCALE));
            atomicAdd(&point_sums[base + 5u], tier_fixed(n.y, TIER_POINT_SCALE));
            atomicAdd(&point_sums[base + 6u], tier_fixed(n.z, TIER_POINT_SCALE));
            atomicAdd(&point_sums[base + 7u], tier_fixed(surface.material.x, TIER_POINT_SCALE));
        }
    }
}

fn tier_point_sum(i: u32, k: u32, weight: f32) -> f32 {
    return f32(atomicLoad(&point_sums[i * TIER_POINT_SUMS + k])) / (weight * TIER_POINT_SCALE);
}

// The accumulated average of the point grains of pixel i (row-major pixel index); invalid
// where none was accumulated. Its depth is left 0: the resolve takes each sample's.
struct TierPointAverage {
    valid: bool,
    surface: CloudSurface,
}

fn tier_point_average(i: u32) -> TierPointAverage {
    var out: TierPointAverage;
    let weight = f32(atomicLoad(&point_sums[i * TIER_POINT_SUMS]));
    out.valid = weight > 0.0;
    if !out.valid {
        return out;
    }
    out.surface.albedo = vec3<f32>(tier_point_sum(i, 1u, weight), tier_point_sum(i, 2u, weight), tier_point_sum(i, 3u, weight));
    let encoded = vec3<f32>(tier_point_sum(i, 4u, weight), tier_point_sum(i, 5u, weight), tier_point_sum(i, 6u, weight)) * 2.0 - 1.0;
    out.surface.normal = select(vec3<f32>(0.0, 0.0, 1.0), normalize(encoded), dot(encoded, encoded) > 1e-12);
    out.surface.material = vec2<f32>(tier_point_sum(i, 7u, weight), 0.0);
    return out;
}
