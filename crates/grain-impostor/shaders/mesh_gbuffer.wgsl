// Rasterizes a grain mesh into the high-resolution G-buffer (one sample per pixel; the
// supersampling reduction in gbuffer_reduce.wgsl averages s × s blocks). Composed after
// generated.wgsl (CameraUniforms, GrainInstance).

@group(0) @binding(0) var<uniform> camera: CameraUniforms;
// Instanced: draw instance i places the mesh with instances[i].
@group(0) @binding(1) var<storage, read> instances: array<GrainInstance>;

struct MeshVertex {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) albedo: vec3<f32>,
    // (roughness, metallic)
    @location(3) material: vec2<f32>,
}

struct MeshFragment {
    @builtin(position) clip: vec4<f32>,
    @location(0) normal: vec3<f32>,
    @location(1) albedo: vec3<f32>,
    @location(2) material: vec2<f32>,
    @location(3) view_depth: f32,
}

struct GbufferSample {
    @location(0) normal_coverage: vec4<f32>,
    @location(1) albedo: vec4<f32>,
    @location(2) material: vec4<f32>,
    @location(3) depth: f32,
}

// Rotates v by the unit quaternion q = (x, y, z, w).
fn rotate_by_quaternion(q: vec4<f32>, v: vec3<f32>) -> vec3<f32> {
    let t = 2.0 * cross(q.xyz, v);
    return v + q.w * t + cross(q.xyz, t);
}

fn camera_clip_from_world() -> mat4x4<f32> {
    return mat4x4<f32>(camera.clip_from_world[0], camera.clip_from_world[1], camera.clip_from_world[2], camera.clip_from_world[3]);
}

fn camera_world_from_clip() -> mat4x4<f32> {
    return mat4x4<f32>(camera.world_from_clip[0], camera.world_from_clip[1], camera.world_from_clip[2], camera.world_from_clip[3]);
}

// View depth of a world point: the distance along the forward axis from the eye
// (perspective), or from the near plane (orthographic, whose eye is notional).
fn view_depth_of(world: vec3<f32>, clip: vec4<f32>) -> f32 {
    if camera.eye.w != 0.0 {
        return clip.w;
    }
    let near = camera_world_from_clip() * vec4<f32>(0.0, 0.0, 0.0, 1.0);
    return dot(world - near.xyz / near.w, camera.eye.xyz);
}

// The vertex placed by `instance` (also the mesh tier's, in grain-renderer).
fn mesh_place(input: MeshVertex, instance: GrainInstance) -> MeshFragment {
    let world = instance.centre_scale.xyz + instance.centre_scale.w * rotate_by_quaternion(instance.rotation, input.position);
    let clip = camera_clip_from_world() * vec4<f32>(world, 1.0);
    var output: MeshFragment;
    output.clip = clip;
    output.normal = rotate_by_quaternion(instance.rotation, input.normal);
    output.albedo = input.albedo;
    output.material = input.material;
    output.view_depth = view_depth_of(world, clip);
    return output;
}

@vertex
fn mesh_vertex(input: MeshVertex, @builtin(instance_index) instance_index: u32) -> MeshFragment {
    return mesh_place(input, instances[instance_index]);
}

@fragment
fn mesh_fragment(input: MeshFragment) -> GbufferSample {
    var output: GbufferSample;
    let length_squared = dot(input.normal, input.normal);
    let normal = select(vec3<f32>(0.0, 0.0, 1.0), input.normal * inverseSqrt(length_squared), length_squared > 0.0);
    output.normal_coverage = vec4<f32>(normal, 1.0);
    output.albedo = vec4<f32>(input.albedo, 1.0);
    output.material = vec4<f32>(input.material, 0.0, 1.0);
    output.depth = input.view_depth;
    return output;
}
