// The base-mesh G-buffer raster pass of ddm-render (crates/ddm-render/src/gbuffer.rs).
// Composed after the declarations of BaseCamera and BaseVertex, generated from Rust at run
// time (ddm_render::raster_shader). One draw of the indexed base mesh, vertices pulled from
// a storage buffer; four Rgba32Float targets in the field order of BaseGBufferTexel
// (ddm_tracer::tangent_space), interpolated with perspective correction. A second pass
// (exit_fragment) draws the same mesh again into one R32Float target: per pixel the
// distance to the nearest surface behind the first one (depth peeling), where the ray
// leaves the base mesh's solid (ddm_tracer::tangent_space::shell_exit).

@group(0) @binding(0) var<uniform> camera: BaseCamera;
@group(0) @binding(1) var<storage, read> vertices: array<BaseVertex>;
// The first pass's (N, view distance) texture, read by the second pass only.
@group(1) @binding(0) var front_normal_depth: texture_2d<f32>;

struct Interpolants {
    @builtin(position) clip: vec4<f32>,
    @location(0) position: vec3<f32>,
    @location(1) tangent_u: vec4<f32>,
    @location(2) bitangent_v: vec4<f32>,
    @location(3) normal: vec3<f32>,
}

struct GBufferOut {
    @location(0) position_coverage: vec4<f32>,
    @location(1) tangent_u: vec4<f32>,
    @location(2) bitangent_v: vec4<f32>,
    @location(3) normal_depth: vec4<f32>,
}

@vertex
fn base_vertex(@builtin(vertex_index) index: u32) -> Interpolants {
    let v = vertices[index];
    let m = mat4x4<f32>(camera.clip_from_world[0], camera.clip_from_world[1], camera.clip_from_world[2], camera.clip_from_world[3]);
    return Interpolants(m * vec4<f32>(v.position.xyz, 1.0), v.position.xyz, v.tangent_u, v.bitangent_v, v.normal.xyz);
}

@fragment
fn base_fragment(in: Interpolants) -> GBufferOut {
    let depth = distance(in.position, camera.eye.xyz);
    return GBufferOut(vec4<f32>(in.position, 1.0), in.tangent_u, in.bitangent_v, vec4<f32>(in.normal, depth));
}

// The second pass: the distance of this fragment when it lies behind the pixel's first
// surface by more than RASTER_PEEL_MARGIN of that surface's distance (the first surface
// itself, drawn again, is discarded); the depth test keeps the nearest. Pixels without a
// first surface keep the cleared 0.
@fragment
fn exit_fragment(in: Interpolants) -> @location(0) f32 {
    let front = textureLoad(front_normal_depth, vec2<u32>(in.clip.xy), 0).w;
    let depth = distance(in.position, camera.eye.xyz);
    if !(front > 0.0) || depth <= front * (1.0 + RASTER_PEEL_MARGIN) {
        discard;
    }
    return depth;
}
