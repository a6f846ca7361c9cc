// The frame kernel of svo_render::GpuRenderer: one cone per pixel through svo_tracer's
// WGSL twin (Heitz & Neyret 2012, Algorithm 1), in 8 x 8 tiles. Composed after the
// svo_tracer module (the octree at bindings 3-7, the mask table's words at 8) and the
// generated declarations of crates/svo-render (SvoFrameUniforms, SVO_RENDER_TILE).
//
// Writes, per pixel: (linear radiance, coverage) and the cone elements sampled into
// storage buffers (what the accuracy harness reads back), and the 8-bit sRGB image of
// exposure x radiance into a storage texture (what a frame loop displays).

@group(0) @binding(0) var<uniform> svo_tree: OctreeUniforms;
@group(0) @binding(1) var<uniform> svo_table: MaskTableUniforms;
@group(0) @binding(2) var<uniform> svo_camera: GpuCamera;
@group(0) @binding(9) var<uniform> svo_settings: GpuTraceSettings;
@group(0) @binding(10) var<uniform> svo_frame: SvoFrameUniforms;
@group(0) @binding(11) var<storage, read_write> svo_radiance_coverage: array<vec4<f32>>;
@group(0) @binding(12) var<storage, read_write> svo_elements: array<u32>;
@group(0) @binding(13) var svo_image: texture_storage_2d<rgba8unorm, write>;

// Rust: svo_render::frame::srgb_encode.
fn svo_srgb_encode(linear: f32) -> f32 {
    // NaN compares false both ways: it becomes 0, as in Rust.
    var c = 0.0;
    if linear == linear {
        c = clamp(linear, 0.0, 1.0);
    }
    if c <= 0.0031308 {
        return 12.92 * c;
    }
    return 1.055 * pow(c, 1.0 / 2.4) - 0.055;
}

@compute @workgroup_size(SVO_RENDER_TILE, SVO_RENDER_TILE)
fn svo_render_frame(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = svo_camera.size.xy;
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let cone = svo_pixel_cone(svo_camera, id.x, id.y);
    let result = svo_trace_cone(svo_tree, svo_table, cone, svo_settings);
    let index = id.y * size.x + id.x;
    svo_radiance_coverage[index] = vec4<f32>(result.radiance, result.coverage);
    svo_elements[index] = result.elements;
    let exposure = svo_frame.exposure.x;
    let r = result.radiance * exposure;
    let encoded = vec3<f32>(svo_srgb_encode(r.x), svo_srgb_encode(r.y), svo_srgb_encode(r.z));
    textureStore(svo_image, vec2<i32>(id.xy), vec4<f32>(encoded, 1.0));
}
