// Supersampling reduction: each output texel averages an s × s block of the
// high-resolution G-buffer written by mesh_gbuffer.wgsl, weighting by coverage (the mean
// over the covered samples; coverage = covered fraction). Composed after generated.wgsl.

@group(0) @binding(0) var<uniform> params: ReduceParams;
@group(0) @binding(1) var fine_normal_coverage: texture_2d_array<f32>;
@group(0) @binding(2) var fine_albedo: texture_2d_array<f32>;
@group(0) @binding(3) var fine_material: texture_2d_array<f32>;
@group(0) @binding(4) var fine_depth: texture_2d_array<f32>;

// Screen G-buffer outputs (reduce_to_gbuffer).
@group(1) @binding(0) var out_normal_coverage: texture_storage_2d<rgba16float, write>;
@group(1) @binding(1) var out_albedo: texture_storage_2d<rgba8unorm, write>;
@group(1) @binding(2) var out_material: texture_storage_2d<rgba8unorm, write>;
@group(1) @binding(3) var out_depth: texture_storage_2d<r32float, write>;

// Atlas output (reduce_to_atlas; its group 1 holds only this binding): 4 vec4 per texel,
// un-premultiplied:
// (normal, α), (albedo, α), (roughness, metallic, 0, α), (depth, 0, 0, α).
@group(1) @binding(4) var<storage, read_write> out_atlas: array<vec4<f32>>;

struct ReducedTexel {
    normal: vec3<f32>,
    coverage: f32,
    albedo: vec3<f32>,
    material: vec2<f32>,
    depth: f32,
}


fn reduce_block(texel: vec2<u32>, layer: u32) -> ReducedTexel {
    let factor = params.size.x;
    var normal_sum = vec3<f32>(0.0);
    var albedo_sum = vec3<f32>(0.0);
    var material_sum = vec2<f32>(0.0);
    var depth_sum = 0.0;
    var covered = 0u;
    for (var j = 0u; j < factor; j += 1u) {
        for (var i = 0u; i < factor; i += 1u) {
            let fine = vec2<i32>(texel * factor + vec2<u32>(i, j));
            let normal_coverage = textureLoad(fine_normal_coverage, fine, i32(layer), 0);
            if normal_coverage.a > 0.5 {
                covered += 1u;
                normal_sum += normal_coverage.xyz;
                albedo_sum += textureLoad(fine_albedo, fine, i32(layer), 0).rgb;
                material_sum += textureLoad(fine_material, fine, i32(layer), 0).rg;
                depth_sum += textureLoad(fine_depth, fine, i32(layer), 0).r;
            }
        }
    }
    var reduced: ReducedTexel;
    if covered == 0u {
        reduced.normal = vec3<f32>(0.0);
        reduced.coverage = 0.0;
        reduced.albedo = vec3<f32>(0.0);
        reduced.material = vec2<f32>(0.0);
        reduced.depth = bitcast<f32>(POSITIVE_INFINITY_BITS);
        return reduced;
    }
    let count = f32(covered);
    let length_squared = dot(normal_sum, normal_sum);
    // Opposite normals cancelling exactly keep the first sample's direction undefined:
    // fall back to +z rather than NaN.
    reduced.normal = select(vec3<f32>(0.0, 0.0, 1.0), normal_sum * inverseSqrt(length_squared), length_squared > 1e-12);
    reduced.coverage = count / f32(factor * factor);
    reduced.albedo = albedo_sum / count;
    reduced.material = material_sum / count;
    reduced.depth = depth_sum / count;
    return reduced;
}

@compute @workgroup_size(PIXEL_TILE, PIXEL_TILE, 1)
fn reduce_to_gbuffer(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.size.y || id.y >= params.size.z {
        return;
    }
    let reduced = reduce_block(id.xy, 0u);
    textureStore(out_normal_coverage, id.xy, vec4<f32>(reduced.normal, reduced.coverage));
    textureStore(out_albedo, id.xy, vec4<f32>(reduced.albedo, 1.0));
    textureStore(out_material, id.xy, vec4<f32>(reduced.material, 0.0, 0.0));
    textureStore(out_depth, id.xy, vec4<f32>(reduced.depth, 0.0, 0.0, 0.0));
}

@compute @workgroup_size(PIXEL_TILE, PIXEL_TILE, 1)
fn reduce_to_atlas(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x >= params.size.y || id.y >= params.size.z || id.z >= params.size.w {
        return;
    }
    let reduced = reduce_block(id.xy, id.z);
    let base = 4u * ((id.z * params.size.z + id.y) * params.size.y + id.x);
    let alpha = reduced.coverage;
    // Depth in the view's convention: 1 - (distance from the near plane) / R = dot(q, ω) / R.
    let depth = select(0.0, 1.0 - reduced.depth / params.extent.x, alpha > 0.0);
    out_atlas[base] = vec4<f32>(reduced.normal, alpha);
    out_atlas[base + 1u] = vec4<f32>(reduced.albedo, alpha);
    out_atlas[base + 2u] = vec4<f32>(reduced.material, 0.0, alpha);
    out_atlas[base + 3u] = vec4<f32>(depth, 0.0, 0.0, alpha);
}
