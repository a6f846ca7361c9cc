// Differential-test kernel of the occlusion_cone module (gpu-harness convention: uniforms
// at binding 0, input at 1, output at 2, workgroups of 64 in a 2-D grid). Each input is a
// pair of spheres vec4(centre, radius): the occluder's inner sphere, then the grain's
// outer sphere; each output is 1 when occlusion_is_occluded culls the grain, else 0.

@group(0) @binding(0) var<uniform> unused: vec4<u32>;
@group(0) @binding(1) var<storage, read> pairs: array<mat2x4<f32>>;
@group(0) @binding(2) var<storage, read_write> culled: array<u32>;

@compute @workgroup_size(64)
fn occlusion_decisions(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = id.x + id.y * groups.x * 64u;
    if index >= arrayLength(&pairs) {
        return;
    }
    let pair = pairs[index];
    culled[index] = select(0u, 1u, occlusion_is_occluded(pair[0], pair[1]));
}
