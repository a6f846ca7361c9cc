// Differential-test kernels for shaders/quadric_fit.wgsl (gpu-harness convention:
// uniforms at binding 0, input at 1, output at 2, workgroups of 64 in a 2-D grid).
// QuadricRayQuery is generated from crates/quadric-fit/src/gpu.rs.

@group(0) @binding(1) var<storage, read> queries: array<QuadricRayQuery>;
@group(0) @binding(2) var<storage, read_write> results: array<vec4<f32>>;

fn quadric_kernel_index(id: vec3<u32>, groups: vec3<u32>) -> u32 {
    return id.x + id.y * groups.x * 64u;
}

fn quadric_of_query(query: QuadricRayQuery) -> GpuQuadric {
    return GpuQuadric(query.abcd, query.efgh, query.ij_t_range.xy, vec2<f32>(0.0));
}

// Output: (t, hit ? 1 : 0, 0, 0).
@compute @workgroup_size(64)
fn first_hits(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = quadric_kernel_index(id, groups);
    if index >= arrayLength(&queries) {
        return;
    }
    let query = queries[index];
    let hit = quadric_first_hit(quadric_of_query(query), query.origin.xyz, query.direction.xyz, query.ij_t_range.z, query.ij_t_range.w);
    results[index] = vec4<f32>(hit, 0.0, 0.0);
}

// Output: the unit normal at the query's origin, w = 0.
@compute @workgroup_size(64)
fn normals(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = quadric_kernel_index(id, groups);
    if index >= arrayLength(&queries) {
        return;
    }
    let query = queries[index];
    results[index] = vec4<f32>(quadric_normal(quadric_of_query(query), query.origin.xyz), 0.0);
}
