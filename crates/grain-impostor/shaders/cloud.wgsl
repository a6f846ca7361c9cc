// Impostor cloud → screen G-buffer, in compute passes (crates/grain-impostor/src/cloud.rs).
//
// Composed after shaders/generated/octahedral_map.wgsl, shaders/octahedral_map.wgsl (the
// sampling math, proven equal to the Rust by tests/impostor_sampling_gpu.rs),
// crates/grain-impostor/shaders/generated.wgsl (CameraUniforms, GrainInstance) and
// crates/grain-impostor/shaders/cloud_generated.wgsl (CloudUniforms).
//
// Passes (one dispatch each, in this order):
//   clear_cloud     per pixel: nearest depth and owner ← CLOUD_NONE (u32::MAX);
//   splat_depth     per grain (one workgroup): for each pixel of the screen bounding
//                   rectangle of its outer sphere that the grain covers (blended atlas
//                   α ≥ threshold), atomicMin of the depth's bits (positive floats order
//                   like their bits);
//   splat_owner     the same walk; where the recomputed depth bits equal the minimum,
//                   atomicMin of the grain index (ties: smallest index);
//   resolve_cloud   per pixel: samples the owner's 4 views in all atlas layers and
//                   writes the G-buffer (background: coverage 0, depth +∞).
// Two 32-bit passes instead of one 64-bit (depth << 32 | index) atomicMin: no
// SHADER_INT64_ATOMIC_MIN_MAX needed and no limit on the grain count, at the price of
// walking the grains twice.

@group(0) @binding(0) var<uniform> camera: CameraUniforms;
@group(0) @binding(1) var<uniform> sampling: ImpostorSamplingUniforms;
@group(0) @binding(2) var<uniform> cloud: CloudUniforms;
@group(0) @binding(3) var<storage, read> instances: array<GrainInstance>;
@group(0) @binding(4) var<storage, read_write> nearest_depth: array<atomic<u32>>;
@group(0) @binding(5) var<storage, read_write> owner: array<atomic<u32>>;
@group(0) @binding(6) var atlas_normal_alpha: texture_2d_array<f32>;
@group(0) @binding(7) var atlas_albedo_alpha: texture_2d_array<f32>;
@group(0) @binding(8) var atlas_material_alpha: texture_2d_array<f32>;
@group(0) @binding(9) var atlas_depth_alpha: texture_2d_array<f32>;
@group(0) @binding(10) var atlas_sampler: sampler;
@group(0) @binding(11) var out_normal_coverage: texture_storage_2d<rgba16float, write>;
@group(0) @binding(12) var out_albedo: texture_storage_2d<rgba8unorm, write>;
@group(0) @binding(13) var out_material: texture_storage_2d<rgba8unorm, write>;
@group(0) @binding(14) var out_depth: texture_storage_2d<r32float, write>;

fn cloud_unproject(ndc: vec3<f32>) -> vec3<f32> {
    let m = mat4x4<f32>(camera.world_from_clip[0], camera.world_from_clip[1], camera.world_from_clip[2], camera.world_from_clip[3]);
    let p = m * vec4<f32>(ndc, 1.0);
    return p.xyz / p.w;
}

fn cloud_clip(p: vec3<f32>) -> vec4<f32> {
    let m = mat4x4<f32>(camera.clip_from_world[0], camera.clip_from_world[1], camera.clip_from_world[2], camera.clip_from_world[3]);
    return m * vec4<f32>(p, 1.0);
}

fn cloud_is_perspective() -> bool {
    return camera.eye.w != 0.0;
}

// World ray of the centre of pixel (x, y): origin at the eye (perspective) or on the near
// plane (orthographic); unit direction.
struct CloudRay {
    origin: vec3<f32>,
    direction: vec3<f32>,
}

fn cloud_pixel_ray(pixel: vec2<f32>) -> CloudRay {
    let ndc = vec2<f32>(2.0 * pixel.x * camera.viewport.z - 1.0, 1.0 - 2.0 * pixel.y * camera.viewport.w);
    let near = cloud_unproject(vec3<f32>(ndc, 0.0));
    let far = cloud_unproject(vec3<f32>(ndc, 1.0));
    var ray: CloudRay;
    ray.origin = select(near, camera.eye.xyz, cloud_is_perspective());
    ray.direction = normalize(far - near);
    return ray;
}

// The camera's forward axis and the origin view depths are measured from.
fn cloud_forward() -> vec3<f32> {
    return normalize(cloud_unproject(vec3<f32>(0.0, 0.0, 1.0)) - cloud_unproject(vec3<f32>(0.0, 0.0, 0.0)));
}

fn cloud_depth_origin() -> vec3<f32> {
    return select(cloud_unproject(vec3<f32>(0.0, 0.0, 0.0)), camera.eye.xyz, cloud_is_perspective());
}

// Rust: glam's Quat * Vec3 (grain → world).
fn cloud_rotate(q: vec4<f32>, v: vec3<f32>) -> vec3<f32> {
    let b = q.xyz;
    let w = q.w;
    return v * (w * w - dot(b, b)) + b * (dot(v, b) * 2.0) + cross(b, v) * (w * 2.0);
}

// Sampling uniforms for this camera: per-grain selection needs rays from the eye.
fn cloud_sampling() -> ImpostorSamplingUniforms {
    var s = sampling;
    if !cloud_is_perspective() {
        s.selection = 0u;
    }
    return s;
}

// What one pixel sees of one grain.
struct CloudHit {
    covered: bool,
    depth: f32,
    alpha: f32,
    local_point: vec3<f32>,
}

// The explicit level of detail: log2 of atlas texels per pixel at the grain (the pixel
// footprint at the grain centre's distance, over the texel size 2R/p, both in world units).
fn cloud_lod(pixel: vec2<f32>, grain: GrainInstance) -> f32 {
    let r0 = cloud_pixel_ray(pixel);
    let r1 = cloud_pixel_ray(pixel + vec2<f32>(1.0, 0.0));
    let t = dot(grain.centre_scale.xyz - r0.origin, r0.direction);
    let footprint = length((r1.origin + t * r1.direction) - (r0.origin + t * r0.direction));
    let texel = grain.centre_scale.w * 2.0 * sampling.outer_radius / f32(cloud.texels);
    return max(log2(max(footprint / texel, 1e-6)), 0.0);
}

fn cloud_view_valid(uv: vec2<f32>, layer: u32) -> bool {
    return all(uv >= vec2<f32>(0.0)) && all(uv <= vec2<f32>(1.0)) && layer < cloud.layers;
}

fn cloud_listing_direction(index: u32) -> vec3<f32> {
    var listing = index;
    if sampling.view_layout == 1u {
        listing = octahedral_listing_index(index, sampling.subdivisions);
    }
    return octahedral_view_direction(listing, sampling.subdivisions);
}

// Samples coverage and the blended surface point of `grain` along the ray of `pixel`.
fn cloud_hit(pixel: vec2<f32>, grain: GrainInstance) -> CloudHit {
    var hit: CloudHit;
    hit.covered = false;
    let world = cloud_pixel_ray(pixel);
    let ray = impostor_grain_ray(world.origin, world.direction, grain.centre_scale, grain.rotation);
    let s = impostor_sample(ray, cloud_sampling());
    if s.distance_ratio > 1.0 || ray.invalid_origin {
        return hit;
    }
    let lod = cloud_lod(pixel, grain);
    var alpha = 0.0;
    var point = vec3<f32>(0.0);
    for (var k = 0u; k < 4u; k++) {
        let uv = select(s.texture_coordinates[k / 2u].xy, s.texture_coordinates[k / 2u].zw, k % 2u == 1u);
        let layer = s.indices[k];
        if s.weights[k] > 0.0 && cloud_view_valid(uv, layer) {
            let a = textureSampleLevel(atlas_normal_alpha, atlas_sampler, uv, layer, lod).a;
            let depth_alpha = textureSampleLevel(atlas_depth_alpha, atlas_sampler, uv, layer, lod);
            if depth_alpha.g > 0.0 {
                let frame = octahedral_view_frame(cloud_listing_direction(layer));
                let q = octahedral_point_at(frame, uv, depth_alpha.r / depth_alpha.g, sampling.outer_radius);
                point += s.weights[k] * a * q;
            }
            alpha += s.weights[k] * a;
        }
    }
    hit.alpha = alpha;
    if alpha < cloud.coverage_threshold || alpha <= 0.0 {
        return hit;
    }
    // The blended surface point, moved onto the camera ray (nearest point of the ray).
    let q = point / alpha;
    let on_ray = ray.origin + ray.direction * dot(q - ray.origin, ray.direction);
    let world_point = grain.centre_scale.xyz + grain.centre_scale.w * cloud_rotate(impostor_normalized_rotation(grain.rotation), on_ray);
    let depth = dot(world_point - cloud_depth_origin(), cloud_forward());
    if !(depth > 0.0) {
        return hit;
    }
    hit.covered = true;
    hit.depth = depth;
    hit.local_point = on_ray;
    return hit;
}

// The screen rectangle [min, max) of the grain's outer sphere (bounding cube corners);
// empty when a corner is behind the eye plane (perspective grains crossing it are skipped).
fn cloud_grain_rectangle(grain: GrainInstance) -> vec4<u32> {
    let size = vec2<f32>(camera.viewport.xy);
    let extent = grain.centre_scale.w * sampling.outer_radius;
    var lo = size;
    var hi = vec2<f32>(0.0);
    for (var c = 0u; c < 8u; c++) {
        let corner = vec3<f32>(f32(c & 1u), f32((c >> 1u) & 1u), f32((c >> 2u) & 1u)) * 2.0 - 1.0;
        let clip = cloud_clip(grain.centre_scale.xyz + corner * extent);
        if clip.w <= 1e-6 {
            return vec4<u32>(0u);
        }
        let ndc = clip.xy / clip.w;
        let screen = vec2<f32>((ndc.x * 0.5 + 0.5) * size.x, (0.5 - 0.5 * ndc.y) * size.y);
        lo = min(lo, screen);
        hi = max(hi, screen);
    }
    let a = vec2<u32>(clamp(floor(lo), vec2<f32>(0.0), size));
    let b = vec2<u32>(clamp(ceil(hi), vec2<f32>(0.0), size));
    return vec4<u32>(a, b);
}

fn cloud_pixel_index(p: vec2<u32>) -> u32 {
    return p.y * u32(camera.viewport.x) + p.x;
}

@compute @workgroup_size(PIXEL_TILE, PIXEL_TILE)
fn clear_cloud(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.viewport.xy);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let i = cloud_pixel_index(id.xy);
    atomicStore(&nearest_depth[i], CLOUD_NONE);
    atomicStore(&owner[i], CLOUD_NONE);
}

fn cloud_grain_index(group: vec3<u32>, groups: vec3<u32>) -> u32 {
    return group.x + group.y * groups.x;
}

// The walk of both splat passes: every pixel of grain `g`'s screen rectangle, the workgroup's
// 8 × 8 invocations striding over it. The depth pass keeps the nearest covering depth per
// pixel; the owner pass (`owner_pass`) then lets the grain whose depth equals it claim the
// pixel (the smallest index among equal depths).
fn cloud_splat(g: u32, local: vec3<u32>, owner_pass: bool) {
    if g >= cloud.grain_count {
        return;
    }
    let grain = instances[g];
    let rect = cloud_grain_rectangle(grain);
    for (var y = rect.y + local.y; y < rect.w; y += PIXEL_TILE) {
        for (var x = rect.x + local.x; x < rect.z; x += PIXEL_TILE) {
            let hit = cloud_hit(vec2<f32>(f32(x) + 0.5, f32(y) + 0.5), grain);
            if !hit.covered {
                continue;
            }
            let i = cloud_pixel_index(vec2<u32>(x, y));
            if !owner_pass {
                atomicMin(&nearest_depth[i], bitcast<u32>(hit.depth));
            } else if bitcast<u32>(hit.depth) == atomicLoad(&nearest_depth[i]) {
                atomicMin(&owner[i], g);
            }
        }
    }
}

@compute @workgroup_size(PIXEL_TILE, PIXEL_TILE)
fn splat_depth(@builtin(workgroup_id) group: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_id) local: vec3<u32>) {
    cloud_splat(cloud_grain_index(group, groups), local, false);
}

@compute @workgroup_size(PIXEL_TILE, PIXEL_TILE)
fn splat_owner(@builtin(workgroup_id) group: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_id) local: vec3<u32>) {
    cloud_splat(cloud_grain_index(group, groups), local, true);
}

@compute @workgroup_size(PIXEL_TILE, PIXEL_TILE)
fn resolve_cloud(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = vec2<u32>(camera.viewport.xy);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let p = vec2<i32>(id.xy);
    let g = atomicLoad(&owner[cloud_pixel_index(id.xy)]);
    if g == CLOUD_NONE || g >= cloud.grain_count {
        textureStore(out_normal_coverage, p, vec4<f32>(0.0));
        textureStore(out_albedo, p, vec4<f32>(0.0));
        textureStore(out_material, p, vec4<f32>(0.0));
        textureStore(out_depth, p, vec4<f32>(bitcast<f32>(POSITIVE_INFINITY_BITS), 0.0, 0.0, 0.0));
        return;
    }
    let grain = instances[g];
    let pixel = vec2<f32>(id.xy) + 0.5;
    let hit = cloud_hit(pixel, grain);
    let world = cloud_pixel_ray(pixel);
    let ray = impostor_grain_ray(world.origin, world.direction, grain.centre_scale, grain.rotation);
    let s = impostor_sample(ray, cloud_sampling());
    let lod = cloud_lod(pixel, grain);
    var normal_alpha = vec4<f32>(0.0);
    var albedo_alpha = vec4<f32>(0.0);
    var material_alpha = vec4<f32>(0.0);
    for (var k = 0u; k < 4u; k++) {
        let uv = select(s.texture_coordinates[k / 2u].xy, s.texture_coordinates[k / 2u].zw, k % 2u == 1u);
        let layer = s.indices[k];
        if s.weights[k] > 0.0 && cloud_view_valid(uv, layer) {
            normal_alpha += s.weights[k] * textureSampleLevel(atlas_normal_alpha, atlas_sampler, uv, layer, lod);
            albedo_alpha += s.weights[k] * textureSampleLevel(atlas_albedo_alpha, atlas_sampler, uv, layer, lod);
            material_alpha += s.weights[k] * textureSampleLevel(atlas_material_alpha, atlas_sampler, uv, layer, lod);
        }
    }
    // Un-premultiply (every layer shares the coverage α, §4.2), decode, rotate to world.
    let alpha = max(normal_alpha.a, 1e-6);
    let encoded = normal_alpha.rgb / alpha * 2.0 - 1.0;
    let local_normal = select(vec3<f32>(0.0, 0.0, 1.0), normalize(encoded), dot(encoded, encoded) > 1e-12);
    let normal = cloud_rotate(impostor_normalized_rotation(grain.rotation), local_normal);
    textureStore(out_normal_coverage, p, vec4<f32>(normal, 1.0));
    textureStore(out_albedo, p, vec4<f32>(albedo_alpha.rgb / max(albedo_alpha.a, 1e-6), 1.0));
    textureStore(out_material, p, vec4<f32>(material_alpha.rg / max(material_alpha.a, 1e-6), 0.0, 0.0));
    textureStore(out_depth, p, vec4<f32>(hit.depth, 0.0, 0.0, 0.0));
}
