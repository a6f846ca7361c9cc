// The per-pixel pass of a mesostructure mapped onto a base mesh: one G-buffer texel per
// invocation (gpu-harness convention: uniforms at binding 0, G-buffer at 1, pixels at 2,
// workgroups of 64 in a 2-D grid; the tracer's scene at 3-8, declared by
// shaders/ddm_tracer.wgsl; the render parameters at 9).

@group(0) @binding(0) var<uniform> uniforms: TraceUniforms;
@group(0) @binding(1) var<storage, read> gbuffer: array<BaseGBufferTexel>;
@group(0) @binding(2) var<storage, read_write> pixels: array<BaseRenderPixel>;
@group(0) @binding(9) var<storage, read> render_params: array<BaseRenderParams>;

@compute @workgroup_size(64)
fn render_pixels(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = id.x + id.y * groups.x * 64u;
    if index >= arrayLength(&gbuffer) {
        return;
    }
    let texel = gbuffer[index];
    let params = render_params[0];
    if texel.position_coverage.w <= 0.0 {
        pixels[index] = BaseRenderPixel(vec4<f32>(0.0, 0.0, 0.0, RENDER_PIXEL_UNCOVERED), vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0));
        return;
    }
    let slab = params.slab.xyz;
    let frame = render_tangent_frame(texel, slab);
    let ray = render_tangent_ray(texel, frame, params.eye.xyz, slab, f32(uniforms.dims_max_steps.z));
    let result = trace_ray(uniforms, ray[0], ray[1]);
    let light = params.light.xyz;
    let ambient = params.light.w;
    if result.normal_hit.w != 1.0 {
        // The ray leaves the slab (bottom, or past the step budget): the base mesh's own colour.
        let base_normal = normalize(texel.normal_depth.xyz);
        let diffuse = max(dot(base_normal, light), 0.0);
        let color = params.miss_color.xyz * (ambient + (1.0 - ambient) * diffuse);
        pixels[index] = BaseRenderPixel(vec4<f32>(color, RENDER_PIXEL_MISS), vec4<f32>(ray[0], f32(result.counts.x)), vec4<f32>(ray[1], 0.0), vec4<f32>(0.0));
        return;
    }
    let normal = render_normal_to_world(frame, result.normal_hit.xyz);
    var diffuse = max(dot(normal, light), 0.0);
    var shadowed = 0.0;
    if params.slab.w >= 0.0 && diffuse > 0.0 {
        if render_in_shadow(uniforms, result.point_t.xyz, render_to_tangent(frame, light), params.slab.w) {
            diffuse = 0.0;
            shadowed = 1.0;
        }
    }
    // Albedo: warm, tinted by the normal so the relief reads in the images.
    let albedo = vec3<f32>(0.85, 0.72, 0.5) * 0.7 + (normal * 0.5 + 0.5) * 0.3;
    let color = albedo * (ambient + (1.0 - ambient) * diffuse);
    pixels[index] = BaseRenderPixel(
        vec4<f32>(color, RENDER_PIXEL_HIT),
        vec4<f32>(ray[0], f32(result.counts.x)),
        vec4<f32>(ray[1], shadowed),
        result.point_t,
    );
}
