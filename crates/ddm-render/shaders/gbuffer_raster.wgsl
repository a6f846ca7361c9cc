// The base-mesh G-buffer raster pass of ddm-render (crates/ddm-render/src/gbuffer.rs).
// Composed after the declarations of BaseCamera and BaseVertex, generated from Rust at run
// time (ddm_render::raster_shader). One draw of the indexed base mesh, vertices pulled from
// a storage buffer; four Rgba32Float targets in the field order of BaseGBufferTexel
// (ddm_tracer::tangent_space), interpolated with perspective correction.

@group(0) @binding(0) var<uniform> camera: BaseCamera;
@group(0) @binding(1) var<storage, read> vertices: array<BaseVertex>;

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
