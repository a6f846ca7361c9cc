// Differential-test kernels for crates/svo-brick/wgsl/svo_brick.wgsl (gpu-harness
// convention: uniforms at binding 0, input at 1, output at 2, workgroups of 64 in a 2-D
// grid; the octree's node and brick pools at bindings 3 and 4, as the module declares).
//
// Input: (p.xyz, lod) per query, world units. Output: four vec4<u32> per query, the bits of
// (h̄, σh², σn², inside), (n̄, 0), (ā, 0), (a_s, 0).

@group(0) @binding(0) var<uniform> tree: OctreeUniforms;
@group(0) @binding(1) var<storage, read> queries: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read_write> results: array<array<vec4<u32>, 4>>;

fn svo_kernel_index(id: vec3<u32>, groups: vec3<u32>) -> u32 {
    return id.x + id.y * groups.x * 64u;
}

fn svo_kernel_write(index: u32, s: SvoSample) {
    let v = s.voxel;
    results[index] = array<vec4<u32>, 4>(
        vec4<u32>(bitcast<u32>(v.distance), bitcast<u32>(v.distance_variance), bitcast<u32>(v.slope_variance), u32(s.inside)),
        vec4<u32>(bitcast<vec3<u32>>(v.normal), 0u),
        vec4<u32>(bitcast<vec3<u32>>(v.mean_attribute), 0u),
        vec4<u32>(bitcast<vec3<u32>>(v.correlation), 0u),
    );
}

// PackedTree::sample_raw.
@compute @workgroup_size(64)
fn quadrilinear(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = svo_kernel_index(id, groups);
    if index >= arrayLength(&queries) {
        return;
    }
    let q = queries[index];
    svo_kernel_write(index, svo_sample_raw(tree, q.xyz, q.w));
}

// PackedTree::sample_nearest before finish.
@compute @workgroup_size(64)
fn nearest(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = svo_kernel_index(id, groups);
    if index >= arrayLength(&queries) {
        return;
    }
    let q = queries[index];
    svo_kernel_write(index, svo_sample_nearest_raw(tree, q.xyz, q.w));
}

// PackedTree::sample (svo_finish after svo_sample_raw).
@compute @workgroup_size(64)
fn finished(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = svo_kernel_index(id, groups);
    if index >= arrayLength(&queries) {
        return;
    }
    let q = queries[index];
    var s = svo_sample_raw(tree, q.xyz, q.w);
    s.voxel = svo_finish(tree, s.voxel);
    svo_kernel_write(index, s);
}
