// Differential-test kernels for shaders/abuffer_mask.wgsl (gpu-harness convention:
// uniforms at binding 0, input at 1, output at 2, workgroups of 64 in a 2-D grid).
//
// The mask table travels in the input buffer: elements 0 .. query_offset hold
// MaskTable::words (4 words per vec4, zero-padded), the queries follow. Invocations on
// table elements write zeros. Entry points with other element types redeclare bindings
// 1 and 2.

struct AbufferDifferentialUniforms {
    table: MaskTableUniforms,
    query_offset: u32,
    padding0: u32,
    padding1: u32,
    padding2: u32,
}

@group(0) @binding(0) var<uniform> uniforms: AbufferDifferentialUniforms;
@group(0) @binding(1) var<storage, read> table_and_queries: array<vec4<u32>>;
@group(0) @binding(2) var<storage, read_write> results: array<vec4<u32>>;

fn abuffer_kernel_index(id: vec3<u32>, groups: vec3<u32>) -> u32 {
    return id.x + id.y * groups.x * 64u;
}

fn abuffer_table_mask(cell: u32) -> vec4<u32> {
    var mask = vec4<u32>(0u);
    let start = abuffer_mask_word_offset(cell, uniforms.table);
    for (var w = 0u; w < min(uniforms.table.words_per_mask, 4u); w++) {
        let word = start + w;
        mask[w] = table_and_queries[word / 4u][word % 4u];
    }
    return mask;
}

// Query (θa, va, θb, vb) as f32 bits → (cell a, cell b, popcount(a ∪ b), popcount(a \ b)).
@compute @workgroup_size(64)
fn mask_queries(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = abuffer_kernel_index(id, groups);
    if index >= arrayLength(&table_and_queries) {
        return;
    }
    if index < uniforms.query_offset {
        results[index] = vec4<u32>(0u);
        return;
    }
    let q = bitcast<vec4<f32>>(table_and_queries[index]);
    let cell_a = abuffer_cell_index(q.x, q.y, uniforms.table);
    let cell_b = abuffer_cell_index(q.z, q.w, uniforms.table);
    let a = abuffer_table_mask(cell_a);
    let b = abuffer_table_mask(cell_b);
    results[index] = vec4<u32>(
        cell_a,
        cell_b,
        abuffer_mask_popcount(abuffer_mask_union(a, b)),
        abuffer_mask_popcount(abuffer_mask_difference(a, b)),
    );
}

// Same queries → bits of coverage(a ∪ b), coverage(a \ b), coverage(a ∩ b), and
// popcount(a ∩ b).
@compute @workgroup_size(64)
fn mask_coverages(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = abuffer_kernel_index(id, groups);
    if index >= arrayLength(&table_and_queries) {
        return;
    }
    if index < uniforms.query_offset {
        results[index] = vec4<u32>(0u);
        return;
    }
    let q = bitcast<vec4<f32>>(table_and_queries[index]);
    let a = abuffer_table_mask(abuffer_cell_index(q.x, q.y, uniforms.table));
    let b = abuffer_table_mask(abuffer_cell_index(q.z, q.w, uniforms.table));
    let table = uniforms.table;
    results[index] = vec4<u32>(
        bitcast<u32>(abuffer_mask_coverage(abuffer_mask_union(a, b), table)),
        bitcast<u32>(abuffer_mask_coverage(abuffer_mask_difference(a, b), table)),
        bitcast<u32>(abuffer_mask_coverage(abuffer_mask_intersection(a, b), table)),
        abuffer_mask_popcount(abuffer_mask_intersection(a, b)),
    );
}

@group(0) @binding(1) var<storage, read> cone_elements: array<array<vec4<f32>, 2>>;

// Cone element ((n_x, n_y, n_z, h̄), (r_d, l_d, -, -)) → (θ bits, v bits, cell index, 0).
@compute @workgroup_size(64)
fn half_planes(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = abuffer_kernel_index(id, groups);
    if index >= arrayLength(&cone_elements) {
        return;
    }
    let element = cone_elements[index];
    let plane = abuffer_half_plane(element[0].w, element[0].xyz, element[1].x, element[1].y);
    let cell = abuffer_cell_index(plane.x, plane.y, uniforms.table);
    results[index] = vec4<u32>(bitcast<u32>(plane.x), bitcast<u32>(plane.y), cell, 0u);
}
