// The sampling functions of impostor clouds (crates/grain-impostor/src/cloud.rs), shared by
// cloud.wgsl and by the impostor tier of grain-renderer. They read the module-scope
// declarations the including shader provides: `camera: CameraUniforms`,
// `sampling: ImpostorSamplingUniforms`, `cloud: CloudUniforms`, the atlas textures
// `atlas_normal_alpha`, `atlas_albedo_alpha`, `atlas_material_alpha`, `atlas_depth_alpha`
// (texture_2d_array<f32>) and `atlas_sampler`.

fn cloud_unproject(ndc: vec3<f32>) -> vec3<f32> {
    let m = mat4x4<f32>(camera.world_from_clip[0], camera.world_from_clip[1], camera.world_from_clip[2], camera.world_from_clip[3]);
    let p = m * vec4<f32>(ndc, 1.0);
    return p.xyz / p.w;
}

fn cloud_clip(p: vec3<f32>) -> vec4<f32> {
    let m = mat4x4<f32>(camera.clip_from_world[0], camera.clip_from_world[1], camera.clip_from_world[2], camera.clip_from_world[3]);
    return m * vec4<f32>(p, 1.0);
}

fn cloud_is_perspective() -> bool {
    return camera.eye.w != 0.0;
}

// World ray of the centre of pixel (x, y): origin at the eye (perspective) or on the near
// plane (orthographic); unit direction.
struct CloudRay {
    origin: vec3<f32>,
    direction: vec3<f32>,
}

fn cloud_pixel_ray(pixel: vec2<f32>) -> CloudRay {
    let ndc = vec2<f32>(2.0 * pixel.x * camera.viewport.z - 1.0, 1.0 - 2.0 * pixel.y * camera.viewport.w);
    let near = cloud_unproject(vec3<f32>(ndc, 0.0));
    let far = cloud_unproject(vec3<f32>(ndc, 1.0));
    var ray: CloudRay;
    ray.origin = select(near, camera.eye.xyz, cloud_is_perspective());
    ray.direction = normalize(far - near);
    return ray;
}

// The camera's forward axis and the origin view depths are measured from.
fn cloud_forward() -> vec3<f32> {
    return normalize(cloud_unproject(vec3<f32>(0.0, 0.0, 1.0)) - cloud_unproject(vec3<f32>(0.0, 0.0, 0.0)));
}

fn cloud_depth_origin() -> vec3<f32> {
    return select(cloud_unproject(vec3<f32>(0.0, 0.0, 0.0)), camera.eye.xyz, cloud_is_perspective());
}

// Rust: glam's Quat * Vec3 (grain → world).
fn cloud_rotate(q: vec4<f32>, v: vec3<f32>) -> vec3<f32> {
    let b = q.xyz;
    let w = q.w;
    return v * (w * w - dot(b, b)) + b * (dot(v, b) * 2.0) + cross(b, v) * (w * 2.0);
}

// Sampling uniforms for this camera: per-grain selection needs rays from the eye.
fn cloud_sampling() -> ImpostorSamplingUniforms {
    var s = sampling;
    if !cloud_is_perspective() {
        s.selection = 0u;
    }
    return s;
}

// What one pixel sees of one grain.
struct CloudHit {
    covered: bool,
    depth: f32,
    alpha: f32,
    local_point: vec3<f32>,
}

// The explicit level of detail: log2 of atlas texels per pixel at the grain (the pixel
// footprint at the grain centre's distance, over the texel size 2R/p, both in world units).
fn cloud_lod(pixel: vec2<f32>, grain: GrainInstance) -> f32 {
    let r0 = cloud_pixel_ray(pixel);
    let r1 = cloud_pixel_ray(pixel + vec2<f32>(1.0, 0.0));
    let t = dot(grain.centre_scale.xyz - r0.origin, r0.direction);
    let footprint = length((r1.origin + t * r1.direction) - (r0.origin + t * r0.direction));
    let texel = grain.centre_scale.w * 2.0 * sampling.outer_radius / f32(cloud.texels);
    return max(log2(max(footprint / texel, 1e-6)), 0.0);
}

fn cloud_view_valid(uv: vec2<f32>, layer: u32) -> bool {
    return all(uv >= vec2<f32>(0.0)) && all(uv <= vec2<f32>(1.0)) && layer < cloud.layers;
}

fn cloud_listing_direction(index: u32) -> vec3<f32> {
    var listing = index;
    if sampling.view_layout == 1u {
        listing = octahedral_listing_index(index, sampling.subdivisions);
    }
    return octahedral_view_direction(listing, sampling.subdivisions);
}

// Samples coverage and the blended surface point of `grain` along the ray of `pixel`.
fn cloud_hit(pixel: vec2<f32>, grain: GrainInstance) -> CloudHit {
    var hit: CloudHit;
    hit.covered = false;
    let world = cloud_pixel_ray(pixel);
    let ray = impostor_grain_ray(world.origin, world.direction, grain.centre_scale, grain.rotation);
    let s = impostor_sample(ray, cloud_sampling());
    if s.distance_ratio > 1.0 || ray.invalid_origin {
        return hit;
    }
    let lod = cloud_lod(pixel, grain);
    var alpha = 0.0;
    var point = vec3<f32>(0.0);
    for (var k = 0u; k < 4u; k++) {
        let uv = select(s.texture_coordinates[k / 2u].xy, s.texture_coordinates[k / 2u].zw, k % 2u == 1u);
        let layer = s.indices[k];
        if s.weights[k] > 0.0 && cloud_view_valid(uv, layer) {
            let a = textureSampleLevel(atlas_normal_alpha, atlas_sampler, uv, layer, lod).a;
            let depth_alpha = textureSampleLevel(atlas_depth_alpha, atlas_sampler, uv, layer, lod);
            if depth_alpha.g > 0.0 {
                let frame = octahedral_view_frame(cloud_listing_direction(layer));
                let q = octahedral_point_at(frame, uv, depth_alpha.r / depth_alpha.g, sampling.outer_radius);
                point += s.weights[k] * a * q;
            }
            alpha += s.weights[k] * a;
        }
    }
    hit.alpha = alpha;
    if alpha < cloud.coverage_threshold || alpha <= 0.0 {
        return hit;
    }
    // The blended surface point, moved onto the camera ray (nearest point of the ray).
    let q = point / alpha;
    let on_ray = ray.origin + ray.direction * dot(q - ray.origin, ray.direction);
    let world_point = grain.centre_scale.xyz + grain.centre_scale.w * cloud_rotate(impostor_normalized_rotation(grain.rotation), on_ray);
    let depth = dot(world_point - cloud_depth_origin(), cloud_forward());
    if !(depth > 0.0) {
        return hit;
    }
    hit.covered = true;
    hit.depth = depth;
    hit.local_point = on_ray;
    return hit;
}

// The screen rectangle [min, max) of the grain's outer sphere (bounding cube corners);
// empty when a corner is behind the eye plane (perspective grains crossing it are skipped).
fn cloud_grain_rectangle(grain: GrainInstance) -> vec4<u32> {
    let size = vec2<f32>(camera.viewport.xy);
    let extent = grain.centre_scale.w * sampling.outer_radius;
    var lo = size;
    var hi = vec2<f32>(0.0);
    for (var c = 0u; c < 8u; c++) {
        let corner = vec3<f32>(f32(c & 1u), f32((c >> 1u) & 1u), f32((c >> 2u) & 1u)) * 2.0 - 1.0;
        let clip = cloud_clip(grain.centre_scale.xyz + corner * extent);
        if clip.w <= 1e-6 {
            return vec4<u32>(0u);
        }
        let ndc = clip.xy / clip.w;
        let screen = vec2<f32>((ndc.x * 0.5 + 0.5) * size.x, (0.5 - 0.5 * ndc.y) * size.y);
        lo = min(lo, screen);
        hi = max(hi, screen);
    }
    let a = vec2<u32>(clamp(floor(lo), vec2<f32>(0.0), size));
    let b = vec2<u32>(clamp(ceil(hi), vec2<f32>(0.0), size));
    return vec4<u32>(a, b);
}

fn cloud_pixel_index(p: vec2<u32>) -> u32 {
    return p.y * u32(camera.viewport.x) + p.x;
}

// What the G-buffer stores of `grain` at `pixel`: cloud_blend of its views (trilinear, LOD =
// log2 of texels per pixel) and the depth of cloud_hit.
struct CloudSurface {
    normal: vec3<f32>,
    albedo: vec3<f32>,
    material: vec2<f32>,
    depth: f32,
}

fn cloud_surface(pixel: vec2<f32>, grain: GrainInstance) -> CloudSurface {
    let hit = cloud_hit(pixel, grain);
    let world = cloud_pixel_ray(pixel);
    let ray = impostor_grain_ray(world.origin, world.direction, grain.centre_scale, grain.rotation);
    var out = cloud_blend(impostor_sample(ray, cloud_sampling()), cloud_lod(pixel, grain), false, grain.rotation);
    out.depth = hit.depth;
    return out;
}

// The atlas layers of the 4 views of `s` blended with its weights at level `lod` — at each
// view's texture coordinates, or at every view's centre when `centres` (the 1×1 mips of the
// point tier) — un-premultiplied (every layer shares the coverage α, §4.2), the grain-local
// normal decoded and rotated by `rotation` to world space; depth 0.
fn cloud_blend(s: ImpostorSample, lod: f32, centres: bool, rotation: vec4<f32>) -> CloudSurface {
    var normal_alpha = vec4<f32>(0.0);
    var albedo_alpha = vec4<f32>(0.0);
    var material_alpha = vec4<f32>(0.0);
    for (var k = 0u; k < 4u; k++) {
        var uv = select(s.texture_coordinates[k / 2u].xy, s.texture_coordinates[k / 2u].zw, k % 2u == 1u);
        if centres {
            uv = vec2<f32>(0.5);
        }
        let layer = s.indices[k];
        if s.weights[k] > 0.0 && cloud_view_valid(uv, layer) {
            normal_alpha += s.weights[k] * textureSampleLevel(atlas_normal_alpha, atlas_sampler, uv, layer, lod);
            albedo_alpha += s.weights[k] * textureSampleLevel(atlas_albedo_alpha, atlas_sampler, uv, layer, lod);
            material_alpha += s.weights[k] * textureSampleLevel(atlas_material_alpha, atlas_sampler, uv, layer, lod);
        }
    }
    let alpha = max(normal_alpha.a, 1e-6);
    let encoded = normal_alpha.rgb / alpha * 2.0 - 1.0;
    let local_normal = select(vec3<f32>(0.0, 0.0, 1.0), normalize(encoded), dot(encoded, encoded) > 1e-12);
    var out: CloudSurface;
    out.normal = cloud_rotate(impostor_normalized_rotation(rotation), local_normal);
    out.albedo = albedo_alpha.rgb / max(albedo_alpha.a, 1e-6);
    out.material = material_alpha.rg / max(material_alpha.a, 1e-6);
    out.depth = 0.0;
    return out;
}
