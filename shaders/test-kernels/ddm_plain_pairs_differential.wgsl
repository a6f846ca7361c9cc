// Differential-test kernel for shaders/ddm-compress/plain_map.wgsl (gpu-harness convention:
// input at binding 1, output at 2, workgroups of 64 in a 2-D grid). Each query is a
// PlainGpuTriangle (generated from crates/ddm-compress/src/plain_gpu.rs) read as a pair: the
// triangle (a, b, c), the box [min.xyz, max.xyz], the tolerance in min.w.

@group(0) @binding(1) var<storage, read> pairs: array<PlainGpuTriangle>;
@group(0) @binding(2) var<storage, read_write> results: array<vec4<f32>>;

fn pair_index(id: vec3<u32>, groups: vec3<u32>) -> u32 {
    return id.x + id.y * groups.x * 64u;
}

// Output: (1 if the triangle overlaps the box else 0, the exact box-triangle distance, the
// plain map's pair bound with no current minimum, the squared distance from the triangle's
// edge a b to the box's edge from its minimum along x).
@compute @workgroup_size(64)
fn pair_bounds(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = pair_index(id, groups);
    if index >= arrayLength(&pairs) {
        return;
    }
    let pair = pairs[index];
    let overlaps = ddm_triangle_overlaps_box(pair.min.xyz, pair.max.xyz, pair.a.xyz, pair.b.xyz, pair.c.xyz);
    let exact = ddm_box_triangle_distance(pair.min.xyz, pair.max.xyz, pair.a.xyz, pair.b.xyz, pair.c.xyz);
    let magnitude = max(max(max(abs(pair.a.xyz), abs(pair.b.xyz)), abs(pair.c.xyz)), vec3<f32>(0.0));
    let bound = ddm_plain_pair_lower_bound(
        pair.min.xyz,
        pair.max.xyz,
        pair.a.xyz,
        pair.b.xyz,
        pair.c.xyz,
        pair.min.w,
        3.4028235e38,
        max(max(magnitude.x, magnitude.y), magnitude.z),
    );
    let box_edge_end = vec3<f32>(pair.max.x, pair.min.y, pair.min.z);
    let segments = ddm_segment_distance_squared(pair.a.xyz, pair.b.xyz, pair.min.xyz, box_edge_end);
    results[index] = vec4<f32>(select(0.0, 1.0, overlaps), exact, bound, segments);
}

// Output: the point of the triangle nearest the box's centre, w = 0.
@compute @workgroup_size(64)
fn closest_points(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = pair_index(id, groups);
    if index >= arrayLength(&pairs) {
        return;
    }
    let pair = pairs[index];
    let center = (pair.min.xyz + pair.max.xyz) * 0.5;
    results[index] = vec4<f32>(ddm_closest_point_on_triangle(center, pair.a.xyz, pair.b.xyz, pair.c.xyz), 0.0);
}
