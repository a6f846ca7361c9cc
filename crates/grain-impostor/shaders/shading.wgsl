// Deferred shading of the screen G-buffer: one directional light, Lambert diffuse plus a
// GGX microfacet specular with the separable Smith G and Schlick's Fresnel, a uniform
// ambient term and a background colour, composited by coverage, written as sRGB-encoded
// RGBA8. Composed after generated.wgsl (CameraUniforms, ShadingUniforms).

@group(0) @binding(0) var<uniform> camera: CameraUniforms;
@group(0) @binding(1) var<uniform> shading: ShadingUniforms;
@group(0) @binding(2) var gbuffer_normal_coverage: texture_2d<f32>;
@group(0) @binding(3) var gbuffer_albedo: texture_2d<f32>;
@group(0) @binding(4) var gbuffer_material: texture_2d<f32>;
@group(0) @binding(5) var shaded: texture_storage_2d<rgba8unorm, write>;


fn unproject(ndc: vec3<f32>) -> vec3<f32> {
    let world_from_clip = mat4x4<f32>(camera.world_from_clip[0], camera.world_from_clip[1], camera.world_from_clip[2], camera.world_from_clip[3]);
    let point = world_from_clip * vec4<f32>(ndc, 1.0);
    return point.xyz / point.w;
}

// GGX (Trowbridge-Reitz) normal distribution, alpha = roughness².
fn ggx_distribution(n_dot_h: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    let d = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
    return a2 / (PI * d * d);
}

// Smith's masking term of GGX for one direction.
fn smith_g1(n_dot_x: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    return 2.0 * n_dot_x / (n_dot_x + sqrt(a2 + (1.0 - a2) * n_dot_x * n_dot_x));
}

fn linear_to_srgb(linear: vec3<f32>) -> vec3<f32> {
    let c = clamp(linear, vec3<f32>(0.0), vec3<f32>(1.0));
    return select(1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055, 12.92 * c, c <= vec3<f32>(0.0031308));
}

// The outgoing linear radiance of a surface point with unit normal n toward unit v.
fn shade_surface(n: vec3<f32>, v: vec3<f32>, albedo: vec3<f32>, roughness: f32, metallic: f32) -> vec3<f32> {
    let l = shading.light_direction.xyz;
    let n_dot_l = dot(n, l);
    let n_dot_v = max(dot(n, v), 1e-4);
    var direct = vec3<f32>(0.0);
    if n_dot_l > 0.0 {
        let h = normalize(l + v);
        let alpha = max(roughness * roughness, 1e-3);
        let f0 = mix(vec3<f32>(0.04), albedo, metallic);
        let fresnel = f0 + (1.0 - f0) * pow(1.0 - max(dot(h, v), 0.0), 5.0);
        let g = smith_g1(n_dot_l, alpha) * smith_g1(n_dot_v, alpha);
        let specular = fresnel * ggx_distribution(max(dot(n, h), 0.0), alpha) * g / (4.0 * n_dot_l * n_dot_v);
        let diffuse = (1.0 - metallic) * albedo / PI;
        direct = (diffuse + specular) * shading.light_colour.rgb * n_dot_l;
    }
    return direct + shading.ambient.rgb * albedo;
}

@compute @workgroup_size(PIXEL_TILE, PIXEL_TILE, 1)
fn shade(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(shaded);
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let texel = vec2<i32>(id.xy);
    let normal_coverage = textureLoad(gbuffer_normal_coverage, texel, 0);
    let coverage = clamp(normal_coverage.a, 0.0, 1.0);
    var colour = shading.background.rgb;
    if coverage > 0.0 {
        let uv = (vec2<f32>(id.xy) + 0.5) / vec2<f32>(size);
        let ndc = vec2<f32>(2.0 * uv.x - 1.0, 1.0 - 2.0 * uv.y);
        let ray = normalize(unproject(vec3<f32>(ndc, 1.0)) - unproject(vec3<f32>(ndc, 0.0)));
        let length_squared = dot(normal_coverage.xyz, normal_coverage.xyz);
        let n = select(-ray, normal_coverage.xyz * inverseSqrt(length_squared), length_squared > 1e-12);
        let material = textureLoad(gbuffer_material, texel, 0);
        let albedo = textureLoad(gbuffer_albedo, texel, 0).rgb;
        let lit = shade_surface(n, -ray, albedo, material.r, material.g);
        colour = mix(shading.background.rgb, lit, coverage);
    }
    textureStore(shaded, id.xy, vec4<f32>(linear_to_srgb(colour), 1.0));
}
