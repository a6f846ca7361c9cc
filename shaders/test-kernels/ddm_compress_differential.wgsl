// Differential-test kernel for shaders/ddm_compress.wgsl (gpu-harness convention:
// uniforms at binding 0, input at 1, output at 2, workgroups of 64 in a 2-D grid).
// Input element 0 holds (query_offset, shift, f16, 0): shift 0 to index with divisions,
// log2(block) + 1 to index with shifts (ddm_*_index_shifted); f16 1 for an atlas of binary16
// pairs (pack_f16_pairs_at_most), 0 for f32 words. Elements 1.. hold the lookup grid's
// words followed by the atlas's (four per element, atlas from word map.grid_atlas_base.w);
// the queries (voxel x, y, z, unused) start at element query_offset. Outputs for non-query
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
    let shift = words_and_queries[0].y;
    var grid_index = ddm_grid_index(voxel, map);
    if shift != 0u {
        grid_index = ddm_grid_index_shifted(voxel, map, shift - 1u);
    }
    let entry = ddm_word(grid_index);
    if ddm_entry_is_surface(entry) {
        var atlas_index = ddm_atlas_index(entry, voxel, map.dims_block.w);
        if shift != 0u {
            atlas_index = ddm_atlas_index_shifted(entry, voxel, shift - 1u);
        }
        var distance = bitcast<f32>(ddm_word(map.grid_atlas_base.w + atlas_index));
        if words_and_queries[0].z != 0u {
            distance = ddm_f16_pair_value(ddm_word(map.grid_atlas_base.w + atlas_index / 2u), atlas_index);
        }
        results[index] = vec4<f32>(distance, 1.0, 1.0, 0.0);
    } else {
        results[index] = vec4<f32>(ddm_entry_distance(entry), 0.0, 1.0, 0.0);
    }
}
