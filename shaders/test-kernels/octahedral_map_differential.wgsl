// Differential-test kernels for shaders/octahedral_map.wgsl (gpu-harness convention:
// uniforms at binding 0, input at 1, output at 2, workgroups of 64 in a 2-D grid). Entry
// points with other element types redeclare bindings 1 and 2; WGSL allows this as long as
// no entry point uses two variables with the same binding.

@group(0) @binding(0) var<uniform> uniforms: OctahedralUniforms;
@group(0) @binding(1) var<storage, read> directions: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read_write> samples: array<ViewSample>;

fn octahedral_kernel_index(id: vec3<u32>, groups: vec3<u32>) -> u32 {
    return id.x + id.y * groups.x * 64u;
}

@compute @workgroup_size(64)
fn view_samples(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = octahedral_kernel_index(id, groups);
    if index >= arrayLength(&directions) {
        return;
    }
    samples[index] = octahedral_view_sample(directions[index].xyz, uniforms.subdivisions);
}

@group(0) @binding(1) var<storage, read> view_indices: array<u32>;
@group(0) @binding(2) var<storage, read_write> view_directions_out: array<vec4<f32>>;

@compute @workgroup_size(64)
fn view_directions(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = octahedral_kernel_index(id, groups);
    if index >= arrayLength(&view_indices) {
        return;
    }
    view_directions_out[index] = vec4<f32>(octahedral_view_direction(view_indices[index], uniforms.subdivisions), 0.0);
}

@group(0) @binding(2) var<storage, read_write> weights_out: array<vec4<f32>>;

@compute @workgroup_size(64)
fn view_weights(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = octahedral_kernel_index(id, groups);
    if index >= arrayLength(&directions) {
        return;
    }
    weights_out[index] = octahedral_view_weights(octahedral_view_sample(directions[index].xyz, uniforms.subdivisions));
}
