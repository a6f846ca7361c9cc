// Impostor cloud → screen G-buffer, in compute passes (crates/grain-impostor/src/cloud.rs).
//
// Composed after shaders/generated/octahedral_map.wgsl, shaders/octahedral_map.wgsl (the
// sampling math, proven equal to the Rust by tests/impostor_sampling_gpu.rs),
// crates/grain-impostor/shaders/generated.wgsl (CameraUniforms, GrainInstance),
// crates/grain-impostor/shaders/cloud_generated.wgsl (CloudUniforms) and cloud_sampling.wgsl
// (the sampling functions).
//
// Passes (one dispatch each, in this order):
//   clear_cloud     per pixel: nearest depth and owner ← CLOUD_NONE (u32::MAX);
//   splat_depth     per grain (one workgroup): for each pixel of the screen bounding
//                   rectangle of its outer sphere that the grain covers (blended atlas
//                   α ≥ threshold), atomicMin of the depth's bits (positive floats order
//                   like their bits);
//   splat_owner     the same walk; where the recomputed depth bits equal the minimum,
//                   atomicMin of the grain index (ties: smallest index); both are the entry
//                   point splat_cloud, run twice with cloud.owner_pass 0 and 1;
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

// Both splat passes: one pipeline, run twice, `cloud.owner_pass` selecting the atomic — so
// the depth the owner pass compares comes from the same compiled code as the one the depth
// pass stored (two entry points could be contracted differently and leave holes).
@compute @workgroup_size(PIXEL_TILE, PIXEL_TILE)
fn splat_cloud(@builtin(workgroup_id) group: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>, @builtin(local_invocation_id) local: vec3<u32>) {
    cloud_splat(cloud_grain_index(group, groups), local, cloud.owner_pass != 0u);
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
    let surface = cloud_surface(vec2<f32>(id.xy) + 0.5, instances[g]);
    textureStore(out_normal_coverage, p, vec4<f32>(surface.normal, 1.0));
    textureStore(out_albedo, p, vec4<f32>(surface.albedo, 1.0));
    textureStore(out_material, p, vec4<f32>(surface.material, 0.0, 0.0));
    textureStore(out_depth, p, vec4<f32>(surface.depth, 0.0, 0.0, 0.0));
}
