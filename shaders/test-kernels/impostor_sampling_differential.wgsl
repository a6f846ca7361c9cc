// Differential-test kernels for the impostor sampling part of shaders/octahedral_map.wgsl
// (gpu-harness convention: uniforms at binding 0, input at 1, output at 2, workgroups of
// 64 in a 2-D grid). Entry points with other element types redeclare bindings 1 and 2.

@group(0) @binding(0) var<uniform> sampling: ImpostorSamplingUniforms;
@group(0) @binding(1) var<storage, read> queries: array<ImpostorRayQuery>;
@group(0) @binding(2) var<storage, read_write> samples: array<ImpostorSample>;

fn impostor_kernel_index(id: vec3<u32>, groups: vec3<u32>) -> u32 {
    return id.x + id.y * groups.x * 64u;
}

// GrainRay::from_world then sample_impostor.
@compute @workgroup_size(64)
fn impostor_samples(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = impostor_kernel_index(id, groups);
    if index >= arrayLength(&queries) {
        return;
    }
    let q = queries[index];
    let ray = impostor_grain_ray(q.world_origin.xyz, q.world_direction.xyz, q.centre_scale, q.rotation);
    samples[index] = impostor_sample(ray, sampling);
}

@group(0) @binding(2) var<storage, read_write> rays_out: array<array<vec4<f32>, 2>>;

// GrainRay::from_world: (origin, invalid_origin as 0/1), (direction, 0).
@compute @workgroup_size(64)
fn grain_rays(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = impostor_kernel_index(id, groups);
    if index >= arrayLength(&queries) {
        return;
    }
    let q = queries[index];
    let ray = impostor_grain_ray(q.world_origin.xyz, q.world_direction.xyz, q.centre_scale, q.rotation);
    rays_out[index] = array<vec4<f32>, 2>(vec4<f32>(ray.origin, select(0.0, 1.0, ray.invalid_origin)), vec4<f32>(ray.direction, 0.0));
}

@group(0) @binding(1) var<storage, read> view_indices: array<u32>;
@group(0) @binding(2) var<storage, read_write> compact_out: array<vec4<u32>>;

// (compact index of a Listing 1 index, Listing 1 index of a compact index, count, 0).
@compute @workgroup_size(64)
fn compact_indices(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = impostor_kernel_index(id, groups);
    if index >= arrayLength(&view_indices) {
        return;
    }
    let n = sampling.subdivisions;
    let i = view_indices[index];
    compact_out[index] = vec4<u32>(octahedral_compact_index(i, n), octahedral_listing_index(i, n), octahedral_compact_view_count(n), 0u);
}

@group(0) @binding(1) var<storage, read> frame_inputs: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read_write> frame_out: array<array<vec4<f32>, 2>>;

// ViewFrame of view `bitcast<u32>(w)` with extent = outer_radius: (texture_coordinates,
// depth, 0) of the point xyz, and point_at of those (xyz, 0).
@compute @workgroup_size(64)
fn view_frames(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = impostor_kernel_index(id, groups);
    if index >= arrayLength(&frame_inputs) {
        return;
    }
    let input = frame_inputs[index];
    let frame = octahedral_view_frame(octahedral_view_direction(bitcast<u32>(input.w), sampling.subdivisions));
    let extent = sampling.outer_radius;
    let uv = octahedral_texture_coordinates(frame, input.xyz, extent);
    let depth = octahedral_view_depth(frame, input.xyz, extent);
    frame_out[index] = array<vec4<f32>, 2>(vec4<f32>(uv, depth, 0.0), vec4<f32>(octahedral_point_at(frame, uv, depth, extent), 0.0));
}
