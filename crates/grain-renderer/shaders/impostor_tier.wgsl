// The impostor tier of the multiscale renderer (crates/grain-renderer/src/impostor_tier.rs):
// the splitter's impostor lists splatted into a visibility buffer in compute, then resolved
// into the screen G-buffer. Composed after grain-impostor's cloud sampling functions
// (cloud_sampling_shader: octahedral_map, scene and cloud declarations, cloud_sampling.wgsl),
// the generated declarations of this crate, and one of tier_visibility_64.wgsl /
// tier_visibility_32.wgsl (tier_clear, tier_offer, tier_stored_depth, tier_winner).
//
// Entry points, per frame:
//   tier_arguments   one invocation: one-workgroup-per-element dispatch arguments of each list;
//   tier_clear       per pixel: the visibility buffer ← the mesh tier's depth (composite) or none;
//   tier_splat_small per element of a list, one invocation per grain whose screen rectangle has
//                    at most TIER_SMALL_PIXELS pixels (Schütz-style point rasterisation);
//   tier_splat_large per element, one 8 × 8 workgroup per grain with a larger rectangle;
//   tier_resolve     per pixel: the winning impostor's atlas sample → G-buffer.
// The splats run once per list (occluder candidates, then the rest: the double draw of §9) and,
// on the 32-bit path, twice (depth, then owner) with the same pipeline, so that the depth the
// owner pass compares is computed by the same compiled code as the one it stored.

@group(0) @binding(0) var<uniform> camera: CameraUniforms;
@group(0) @binding(1) var<uniform> sampling: ImpostorSamplingUniforms;
@group(0) @binding(2) var<uniform> cloud: CloudUniforms;
@group(0) @binding(3) var<uniform> tier: TierUniforms;
// Per dispatch (a dynamic offset): which list, and how.
@group(0) @binding(4) var<uniform> tier_pass: TierPass;
@group(0) @binding(5) var<storage, read> instances: array<GrainInstance>;
@group(0) @binding(6) var<storage, read> elements: array<u32>;
// The splitter's counters: count of list l at COUNTER_COUNT + l, first element at COUNTER_OFFSET + l.
@group(0) @binding(7) var<storage, read> lists: array<u32>;
// [0..TIER_STATS): evaluated pixels of list pass 0 and 1, early-Z skips of pass 0 and 1,
// resolved impostor pixels, resolved point pixels.
@group(0) @binding(10) var<storage, read_write> stats: array<atomic<u32>, TIER_STATS>;
@group(0) @binding(11) var atlas_normal_alpha: texture_2d_array<f32>;
@group(0) @binding(12) var atlas_albedo_alpha: texture_2d_array<f32>;
@group(0) @binding(13) var atlas_material_alpha: texture_2d_array<f32>;
@group(0) @binding(14) var atlas_depth_alpha: texture_2d_array<f32>;
@group(0) @binding(15) var atlas_sampler: sampler;

// The mesh tier's depth (tier_clear only).
@group(1) @binding(0) var mesh_depth: texture_2d<f32>;
// The G-buffer (tier_resolve only).
@group(1) @binding(1) var out_normal_coverage: texture_storage_2d<rgba16float, write>;
@group(1) @binding(2) var out_albedo: texture_storage_2d<rgba8unorm, write>;
@group(1) @binding(3) var out_material: texture_storage_2d<rgba8unorm, write>;
@group(1) @binding(4) var out_depth: texture_storage_2d<r32float, write>;
// One-workgroup-per-element dispatch arguments: (x, y, 1) per list of TierUniforms.lists,
// then the raster path's draw arguments from TIER_DRAW_ARGUMENTS (tier_arguments only: the
// splats and draws read them as INDIRECT, which excludes a storage binding).
@group(1) @binding(5) var<storage, read_write> arguments: array<u32>;

fn tier_size() -> vec2<u32> {
    return vec2<u32>(camera.viewport.xy);
}

// Samples per pixel side (TierUniforms.counts.z): the visibility buffer holds s × s samples
// per pixel, at the centres of the pixel's s × s sub-squares (s = 1: the pixel centre).
fn tier_samples() -> u32 {
    return max(tier.counts.z, 1u);
}

// Visibility-buffer index of sample k (row-major within the pixel) of pixel p: row-major in
// the (s·width) × (s·height) sample grid.
fn tier_sample_index(p: vec2<u32>, k: u32) -> u32 {
    let s = tier_samples();
    let q = p * s + vec2<u32>(k % s, k / s);
    return q.y * (tier_size().x * s) + q.x;
}

// Screen position (pixels) of sample k of pixel p.
fn tier_sample_position(p: vec2<u32>, k: u32) -> vec2<f32> {
    let s = tier_samples();
    return vec2<f32>(p) + (vec2<f32>(f32(k % s), f32(k / s)) + 0.5) / f32(s);
}

// The grain of element `e` of this pass's list, or TIER_NONE past its end.
fn tier_element_grain(e: u32) -> u32 {
    let list = tier_pass.list;
    if e >= lists[COUNTER_COUNT + list] {
        return TIER_NONE;
    }
    let g = elements[lists[COUNTER_OFFSET + list] + e];
    return select(TIER_NONE, g, g < tier.counts.x);
}

// The view depth of a grain's centre (the G-buffer's depth measure, as cloud_hit's).
fn tier_centre_depth(grain: GrainInstance) -> f32 {
    return dot(grain.centre_scale.xyz - cloud_depth_origin(), cloud_forward());
}

// A lower bound of the view depth of every point a grain's pixels can take (cloud_hit moves
// the blended surface point q, |q − c| ≤ R·s, onto the pixel ray: within √2·R·s of the centre),
// rounded down.
fn tier_nearest_depth(grain: GrainInstance) -> f32 {
    let centre = tier_centre_depth(grain);
    let reach = TIER_REACH * sampling.outer_radius * grain.centre_scale.w;
    return (centre - reach) - TIER_DEPTH_SLACK * (abs(centre) + reach + length(grain.centre_scale.xyz));
}

// The samples of one pixel of one grain: per sample the early-Z test, then the atlas, then
// the visibility buffer. Returns (evaluated, skipped) samples.
fn tier_splat_pixel(x: u32, y: u32, g: u32, grain: GrainInstance, nearest: f32) -> vec2<u32> {
    var counted = vec2<u32>(0u);
    for (var k = 0u; k < tier_samples() * tier_samples(); k++) {
        let i = tier_sample_index(vec2<u32>(x, y), k);
        if tier_pass.early_z != 0u && tier_stored_depth(i) < nearest {
            counted.y += 1u;
            continue;
        }
        let hit = cloud_hit(tier_sample_position(vec2<u32>(x, y), k), grain);
        if hit.covered {
            tier_offer(i, hit.depth, g);
        }
        counted.x += 1u;
    }
    return counted;
}

fn tier_count(counted: vec2<u32>) {
    if counted.x != 0u {
        atomicAdd(&stats[tier_pass.slot], counted.x);
    }
    if counted.y != 0u {
        atomicAdd(&stats[2u + tier_pass.slot], counted.y);
    }
}

fn tier_rectangle_pixels(rect: vec4<u32>) -> u32 {
    return (rect.z - rect.x) * (rect.w - rect.y);
}

@compute @workgroup_size(1)
fn tier_arguments() {
    for (var k = 0u; k < 2u; k++) {
        let count = lists[COUNTER_COUNT + tier.lists[k]];
        let x = min(count, MAX_GROUPS_PER_DIMENSION);
        arguments[3u * k] = x;
        arguments[3u * k + 1u] = select(1u, (count + x - 1u) / max(x, 1u), count != 0u);
        arguments[3u * k + 2u] = 1u;
        // The raster path: 6 vertices (a screen rectangle), one instance per element.
        let draw = TIER_DRAW_ARGUMENTS + 4u * k;
        arguments[draw] = 6u;
        arguments[draw + 1u] = count;
        arguments[draw + 2u] = 0u;
        arguments[draw + 3u] = 0u;
    }
}

@compute @workgroup_size(8, 8)
fn tier_clear(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = tier_size();
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    var depth = bitcast<f32>(POSITIVE_INFINITY_BITS);
    if (tier.counts.y & TIER_COMPOSITE) != 0u {
        depth = textureLoad(mesh_depth, vec2<i32>(id.xy), 0).r;
    }
    for (var k = 0u; k < tier_samples() * tier_samples(); k++) {
        tier_clear_pixel(tier_sample_index(id.xy, k), depth);
    }
}

// Element index of a dispatch of ELEMENT_WORKGROUP invocations per workgroup (the splitter's
// dispatch arguments: element (y · x_count + x) · ELEMENT_WORKGROUP + local).
@compute @workgroup_size(64)
fn tier_splat_small(
    @builtin(workgroup_id) workgroup: vec3<u32>,
    @builtin(num_workgroups) workgroups: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let g = tier_element_grain((workgroup.y * workgroups.x + workgroup.x) * ELEMENT_WORKGROUP + local);
    if g == TIER_NONE {
        return;
    }
    let grain = instances[g];
    let rect = cloud_grain_rectangle(grain);
    if tier_rectangle_pixels(rect) > TIER_SMALL_PIXELS {
        return;
    }
    let nearest = tier_nearest_depth(grain);
    var counted = vec2<u32>(0u);
    for (var y = rect.y; y < rect.w; y++) {
        for (var x = rect.x; x < rect.z; x++) {
            counted += tier_splat_pixel(x, y, g, grain, nearest);
        }
    }
    tier_count(counted);
}

@compute @workgroup_size(8, 8)
fn tier_splat_large(
    @builtin(workgroup_id) workgroup: vec3<u32>,
    @builtin(num_workgroups) workgroups: vec3<u32>,
    @builtin(local_invocation_id) local: vec3<u32>,
) {
    let g = tier_element_grain(workgroup.y * workgroups.x + workgroup.x);
    if g == TIER_NONE {
        return;
    }
    let grain = instances[g];
    let rect = cloud_grain_rectangle(grain);
    if tier_rectangle_pixels(rect) <= TIER_SMALL_PIXELS {
        return;
    }
    let nearest = tier_nearest_depth(grain);
    var counted = vec2<u32>(0u);
    for (var y = rect.y + local.y; y < rect.w; y += 8u) {
        for (var x = rect.x + local.x; x < rect.z; x += 8u) {
            counted += tier_splat_pixel(x, y, g, grain, nearest);
        }
    }
    tier_count(counted);
}

// Resolves pixel p from its s × s samples as the mesh reference's supersampling reduces
// (gbuffer_reduce.wgsl): coverage is the covered fraction; normal (normalised sum, a single
// sample's own), albedo, material and depth are means over the covered samples. In composite
// mode the samples the mesh tier won count as covered and the pixel keeps the mesh tier's
// values when they are at least half of its samples (its attributes cannot be read here).
@compute @workgroup_size(8, 8)
fn tier_resolve(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = tier_size();
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let p = vec2<i32>(id.xy);
    let composite = (tier.counts.y & TIER_COMPOSITE) != 0u;
    let n = tier_samples() * tier_samples();
    var normal_sum = vec3<f32>(0.0);
    var albedo_sum = vec3<f32>(0.0);
    var material_sum = vec2<f32>(0.0);
    var depth_sum = 0.0;
    var covered = 0u;
    var meshes = 0u;
    var impostors = 0u;
    var points = 0u;
    let pixel = id.y * size.x + id.x;
    let point = tier_point_average(pixel);
    for (var k = 0u; k < n; k++) {
        let i = tier_sample_index(id.xy, k);
        let g = tier_winner(i);
        let is_point = g < TIER_MESH && (g & TIER_POINT_BIT) != 0u;
        let is_impostor = !is_point && g < tier.counts.x;
        meshes += select(0u, 1u, g == TIER_MESH);
        if is_impostor {
            let surface = cloud_surface(tier_sample_position(id.xy, k), instances[g]);
            normal_sum += surface.normal;
            albedo_sum += surface.albedo;
            material_sum += surface.material;
            depth_sum += surface.depth;
            impostors += 1u;
            covered += 1u;
        }
        if is_point && point.valid {
            normal_sum += point.surface.normal;
            albedo_sum += point.surface.albedo;
            material_sum += point.surface.material;
            depth_sum += tier_stored_depth(i);
            points += 1u;
            covered += 1u;
        }
    }
    if covered == 0u || (composite && 2u * meshes >= n) {
        if !composite && covered == 0u {
            textureStore(out_normal_coverage, p, vec4<f32>(0.0));
            textureStore(out_albedo, p, vec4<f32>(0.0));
            textureStore(out_material, p, vec4<f32>(0.0));
            textureStore(out_depth, p, vec4<f32>(bitcast<f32>(POSITIVE_INFINITY_BITS), 0.0, 0.0, 0.0));
        }
        return;
    }
    let count = f32(covered);
    var normal = normal_sum;
    if covered > 1u {
        let length_squared = dot(normal, normal);
        normal = select(vec3<f32>(0.0, 0.0, 1.0), normal * inverseSqrt(length_squared), length_squared > 1e-12);
    }
    let coverage = f32(covered + select(0u, meshes, composite)) / f32(n);
    textureStore(out_normal_coverage, p, vec4<f32>(normal, coverage));
    textureStore(out_albedo, p, vec4<f32>(albedo_sum / count, 1.0));
    textureStore(out_material, p, vec4<f32>(material_sum / count, 0.0, 0.0));
    textureStore(out_depth, p, vec4<f32>(depth_sum / count, 0.0, 0.0, 0.0));
    if impostors != 0u {
        atomicAdd(&stats[4u], 1u);
    }
    if points != 0u {
        atomicAdd(&stats[5u], 1u);
    }
}
