// The tracer's compute pass: one ray per invocation (gpu-harness convention: uniforms at
// binding 0, rays at 1, results at 2, workgroups of 64 in a 2-D grid; the scene at 3-7,
// declared by shaders/ddm_tracer.wgsl).

@group(0) @binding(0) var<uniform> uniforms: TraceUniforms;
@group(0) @binding(1) var<storage, read> rays: array<TraceRay>;
@group(0) @binding(2) var<storage, read_write> results: array<TraceResult>;

@compute @workgroup_size(64)
fn trace_rays(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = id.x + id.y * groups.x * 64u;
    if index >= arrayLength(&rays) {
        return;
    }
    let ray = rays[index];
    results[index] = trace_ray(uniforms, ray.origin.xyz, ray.direction.xyz);
}
