// The per-pixel pass of ddm-render (Mehra & Kumar §3; crates/ddm-render/src/renderer.rs):
// one invocation per G-buffer texel, in workgroups of RENDER_TILE × RENDER_TILE. Composed
// after the registered ddm_render module (the generated declarations of
// ddm_tracer::tangent_space and shaders/ddm_render.wgsl, after the ddm_tracer module,
// whose scene is bound at group 0, bindings 3-8) and the generated constants of this pass.
//
// Group 0 (one bind group per renderer): 0 the tracer's uniforms, 9 the render parameters,
// 10-13 the G-buffer textures (Rgba32Float, the fields of BaseGBufferTexel in order, read
// with textureLoad: the values the raster pass wrote, bit for bit), 14 the exit distance
// (R32Float, the second raster pass's).
// Group 1 (one bind group per target): binding 0, the shaded pixels (render_pixels); or
// binding 1, a colour texture (render_color); or bindings 1 and 2, a colour texture and
// the inverse eye distance of what it holds (render_color_depth).

@group(0) @binding(0) var<uniform> uniforms: TraceUniforms;
@group(0) @binding(9) var<uniform> render_params: BaseRenderParams;
@group(0) @binding(10) var gbuffer_position_coverage: texture_2d<f32>;
@group(0) @binding(11) var gbuffer_tangent_u: texture_2d<f32>;
@group(0) @binding(12) var gbuffer_bitangent_v: texture_2d<f32>;
@group(0) @binding(13) var gbuffer_normal_depth: texture_2d<f32>;
@group(0) @binding(14) var gbuffer_exit_distance: texture_2d<f32>;
@group(1) @binding(0) var<storage, read_write> target_pixels: array<BaseRenderPixel>;
@group(1) @binding(1) var target_color: texture_storage_2d<rgba16float, write>;
@group(1) @binding(2) var target_depth: texture_storage_2d<r32float, read_write>;

// The G-buffer texel at `p` (inside the textures).
fn load_gbuffer_texel(p: vec2<u32>) -> BaseGBufferTexel {
    return BaseGBufferTexel(
        textureLoad(gbuffer_position_coverage, p, 0),
        textureLoad(gbuffer_tangent_u, p, 0),
        textureLoad(gbuffer_bitangent_v, p, 0),
        textureLoad(gbuffer_normal_depth, p, 0),
    );
}

// Traces and shades one texel: its tangent-space ray (render_tangent_ray, CPU reference
// ddm_tracer::tangent_space::tangent_space_ray), its class (render_pixel_class: a hit
// beyond where the ray leaves the base mesh's solid, `exit` away from the eye, is no
// hit), the hit's shading normal in world space, Lambert + ambient, and a shadow ray
// toward the light (render_in_shadow).
fn shade_texel(texel: BaseGBufferTexel, exit: f32) -> BaseRenderPixel {
    let params = render_params;
    if texel.position_coverage.w <= 0.0 {
        return BaseRenderPixel(vec4<f32>(0.0, 0.0, 0.0, RENDER_PIXEL_UNCOVERED), vec4<f32>(0.0), vec4<f32>(0.0), vec4<f32>(0.0));
    }
    let slab = params.slab.xyz;
    let frame = render_tangent_frame(texel, slab);
    let ray = render_tangent_ray(texel, frame, params.eye.xyz, slab, f32(uniforms.dims_max_steps.z));
    // The trace stops where the ray leaves the base mesh's solid: nothing beyond is seen.
    let shell_exit = render_shell_exit(texel.normal_depth.w, exit, ray[1]);
    let result = trace_ray_within(uniforms, ray[0], ray[1], shell_exit);
    let light = params.light.xyz;
    let ambient = params.light.w;
    let pixel_class = render_pixel_class(
        result.normal_hit.w == 1.0,
        result.point_t.w,
        shell_exit,
        render_slab_bottom(ray[1], f32(uniforms.dims_max_steps.z)),
    );
    // The ray leaves the base mesh's solid before any hit, or misses where no base surface
    // is drawn (miss_color.w 0): what lies behind shows.
    if pixel_class == RENDER_PIXEL_LEFT_SHELL || (pixel_class == RENDER_PIXEL_MISS && params.miss_color.w == 0.0) {
        return BaseRenderPixel(vec4<f32>(0.0, 0.0, 0.0, RENDER_PIXEL_LEFT_SHELL), vec4<f32>(ray[0], f32(result.counts.x)), vec4<f32>(ray[1], 0.0), vec4<f32>(0.0));
    }
    if pixel_class == RENDER_PIXEL_MISS {
        // The ray reaches the slab's bottom (or the step cap): the base mesh's own colour.
        let base_normal = normalize(texel.normal_depth.xyz);
        let diffuse = max(dot(base_normal, light), 0.0);
        let color = params.miss_color.xyz * (ambient + (1.0 - ambient) * diffuse);
        return BaseRenderPixel(vec4<f32>(color, RENDER_PIXEL_MISS), vec4<f32>(ray[0], f32(result.counts.x)), vec4<f32>(ray[1], 0.0), vec4<f32>(0.0));
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
    // The albedo, tinted by the normal so the relief reads in the images.
    let tint = params.albedo.w;
    let albedo = params.albedo.xyz * (1.0 - tint) + (normal * 0.5 + 0.5) * tint;
    let color = albedo * (ambient + (1.0 - ambient) * diffuse);
    return BaseRenderPixel(
        vec4<f32>(color, RENDER_PIXEL_HIT),
        vec4<f32>(ray[0], f32(result.counts.x)),
        vec4<f32>(ray[1], shadowed),
        result.point_t,
    );
}

// Every texel into `target_pixels`, row-major (index x + y * width, row 0 on top).
@compute @workgroup_size(RENDER_TILE, RENDER_TILE)
fn render_pixels(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(gbuffer_position_coverage);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    target_pixels[id.x + id.y * size.x] = shade_texel(load_gbuffer_texel(id.xy), textureLoad(gbuffer_exit_distance, id.xy, 0).x);
}

// Every texel into `target_color`: linear colour, alpha 1 where the object is seen (a hit,
// or the base surface under the slab) and 0 (with colour 0) elsewhere: off the base mesh,
// and where the ray leaves the base mesh's solid without a hit.
@compute @workgroup_size(RENDER_TILE, RENDER_TILE)
fn render_color(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(gbuffer_position_coverage);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let pixel = shade_texel(load_gbuffer_texel(id.xy), textureLoad(gbuffer_exit_distance, id.xy, 0).x);
    let seen = pixel.color.w == RENDER_PIXEL_HIT || pixel.color.w == RENDER_PIXEL_MISS;
    let coverage = select(0.0, 1.0, seen);
    textureStore(target_color, id.xy, vec4<f32>(pixel.color.xyz, coverage));
}

// The world distance from the eye of what a seen pixel shows (render_eye_distance): its
// hit, or where its ray reaches the slab's bottom.
fn pixel_eye_distance(texel: BaseGBufferTexel, pixel: BaseRenderPixel) -> f32 {
    let d = pixel.ray_direction.xyz;
    let bottom = render_slab_bottom(d, f32(uniforms.dims_max_steps.z));
    let t = select(bottom, pixel.hit.w, pixel.color.w == RENDER_PIXEL_HIT);
    return render_eye_distance(texel.normal_depth.w, d, t);
}

// Every seen texel (a hit, or the base surface under the slab) nearer than what the
// target holds into `target_color` (alpha 1) and its inverse eye distance into
// `target_depth` (larger is nearer, 0 holds nothing): objects drawn one after the other
// into one target interpenetrate. A texel whose base surface already lies behind what the
// target holds is skipped before its ray is traced (every hit lies behind the surface).
@compute @workgroup_size(RENDER_TILE, RENDER_TILE)
fn render_color_depth(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(gbuffer_position_coverage);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let texel = load_gbuffer_texel(id.xy);
    let stored = textureLoad(target_depth, id.xy).x;
    if texel.position_coverage.w <= 0.0 || 1.0 / texel.normal_depth.w <= stored {
        return;
    }
    let pixel = shade_texel(texel, textureLoad(gbuffer_exit_distance, id.xy, 0).x);
    if !(pixel.color.w == RENDER_PIXEL_HIT || pixel.color.w == RENDER_PIXEL_MISS) {
        return;
    }
    let inverse = 1.0 / pixel_eye_distance(texel, pixel);
    if inverse > stored {
        textureStore(target_depth, id.xy, vec4<f32>(inverse, 0.0, 0.0, 0.0));
        textureStore(target_color, id.xy, vec4<f32>(pixel.color.xyz, 1.0));
    }
}
