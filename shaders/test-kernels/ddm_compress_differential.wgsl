// Differential-test kernel for shaders/ddm_compress.wgsl (gpu-harness convention:
// uniforms at binding 0, input at 1, output at 2, workgroups of 64 in a 2-D grid).
// Input element 0 holds (query_offset, 0, 0, 0); elements 1.. hold the lookup grid's words
// followed by the atlas's (four per element, atlas from word map.grid_atlas_base.w); the
// queries (voxel x, y, z, unused) start at element query_offset. Outputs for non-query
// elements are zero; a query outputs (distance, 1 if in a surface block, 1 if inside the
// map, 0).

@group(0) @binding(0) var<uniform> map: CompressedMapUniforms;
@group(0) @binding(1) var<storage, read> words_and_queries: array<vec4<u32>>;
@group(0) @binding(2) var<storage, read_write> results: array<vec4<f32>>;

fn ddm_word(index: u32) -> u32 {
    return words_and_queries[1u + index / 4u][index % 4u];
}

@compute @workgroup_size(64)
fn access(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = id.x + id.y * groups.x * 64u;
    if index >= arrayLength(&words_and_queries) {
        return;
    }
    let query_offset = words_and_queries[0].x;
    if index < query_offset {
        results[index] = vec4<f32>(0.0);
        return;
    }
    let voxel = words_and_queries[index].xyz;
    if !ddm_voxel_in_map(voxel, map) {
        results[index] = vec4<f32>(0.0);
        return;
    }
    let entry = ddm_word(ddm_grid_index(voxel, map));
    if ddm_entry_is_surface(entry) {
        let word = ddm_word(map.grid_atlas_base.w + ddm_atlas_index(entry, voxel, map.dims_block.w));
        results[index] = vec4<f32>(bitcast<f32>(word), 1.0, 1.0, 0.0);
    } else {
        results[index] = vec4<f32>(ddm_entry_distance(entry), 0.0, 1.0, 0.0);
    }
}
