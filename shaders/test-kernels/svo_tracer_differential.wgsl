// Differential-test kernel for crates/svo-tracer/wgsl/svo_tracer.wgsl (gpu-harness
// convention: uniforms at binding 0, input at 1, output at 2; the octree at 3-7 and the
// mask table's words at 8, as the modules declare).
//
// Input: (x, y, 0, 0) pixels. Output per pixel: (radiance, coverage), (elements, 0, 0, 0).

struct SvoTracerKernelUniforms {
    tree: OctreeUniforms,
    table: MaskTableUniforms,
    camera: GpuCamera,
    settings: GpuTraceSettings,
}

@group(0) @binding(0) var<uniform> uniforms: SvoTracerKernelUniforms;
@group(0) @binding(1) var<storage, read> pixels: array<vec4<u32>>;
@group(0) @binding(2) var<storage, read_write> results: array<array<vec4<f32>, 2>>;

// trace::trace_cone of Camera::pixel_cone.
@compute @workgroup_size(64)
fn trace_pixels(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = id.x + id.y * groups.x * 64u;
    if index >= arrayLength(&pixels) {
        return;
    }
    let pixel = pixels[index];
    let cone = svo_pixel_cone(uniforms.camera, pixel.x, pixel.y);
    let result = svo_trace_cone(uniforms.tree, uniforms.table, cone, uniforms.settings);
    results[index] = array<vec4<f32>, 2>(vec4<f32>(result.radiance, result.coverage), vec4<f32>(f32(result.elements), 0.0, 0.0, 0.0));
}
