// WGSL twin of crates/ddm-tracer/src/tangent_space.rs: a mesostructure mapped onto a
// base mesh (Mehra & Kumar §3). Part of the ddm_tracer module's library, after
// ddm_tracer.wgsl (it traces shadow rays with trace_ray); each function mirrors the Rust
// function named in its comment, tests/ddm_render_gpu.rs checks them against it.

// Rust: ddm_tracer::tangent_space::TangentFrame::new, as the rows (to_x, to_y, to_z) of
// the world -> tangent-space map. A degenerate frame gives zero rows (callers check
// coverage first; the G-buffer of a covered pixel never holds a zero frame).
fn render_tangent_frame(texel: BaseGBufferTexel, slab: vec3<f32>) -> mat3x3<f32> {
    let tu = texel.tangent_u.xyz;
    let tv = texel.bitangent_v.xyz;
    let n = texel.normal_depth.xyz;
    let tu2 = dot(tu, tu);
    let tv2 = dot(tv, tv);
    let n2 = dot(n, n);
    if !(tu2 > 0.0 && tv2 > 0.0 && n2 > 0.0) {
        return mat3x3<f32>(vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0));
    }
    return mat3x3<f32>(tu * (slab.x / tu2), tv * (slab.y / tv2), n * (slab.z / sqrt(n2)));
}

// Rust: TangentFrame::to_tangent (the columns of `frame` are its rows).
fn render_to_tangent(frame: mat3x3<f32>, world: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(frame[0], world), dot(frame[1], world), dot(frame[2], world));
}

// Rust: TangentFrame::normal_to_world.
fn render_normal_to_world(frame: mat3x3<f32>, normal: vec3<f32>) -> vec3<f32> {
    let n = frame * normal;
    let len2 = dot(n, n);
    return select(vec3<f32>(0.0), n * (1.0 / sqrt(len2)), len2 > 0.0);
}

// Rust: ddm_tracer::tangent_space::tangent_space_ray, for a covered texel: the origin on
// top of the slab in the first column, the direction in the second.
fn render_tangent_ray(texel: BaseGBufferTexel, frame: mat3x3<f32>, eye: vec3<f32>, slab: vec3<f32>, size_z: f32) -> mat2x3<f32> {
    let origin = vec3<f32>(texel.tangent_u.w * slab.x, texel.bitangent_v.w * slab.y, size_z);
    return mat2x3<f32>(origin, render_to_tangent(frame, texel.position_coverage.xyz - eye));
}

// Rust: ddm_tracer::tangent_space::shell_exit.
fn render_shell_exit(front_distance: f32, exit_distance: f32, direction: vec3<f32>) -> f32 {
    if !(exit_distance > front_distance && front_distance > 0.0) {
        return RENDER_NO_EXIT;
    }
    let t = (exit_distance / front_distance - 1.0) * length(direction);
    return select(RENDER_NO_EXIT, t, t <= RENDER_NO_EXIT);
}

// Rust: ddm_tracer::tangent_space::eye_distance.
fn render_eye_distance(front_distance: f32, direction: vec3<f32>, t: f32) -> f32 {
    return front_distance + t * front_distance / length(direction);
}

// Rust: ddm_tracer::tangent_space::slab_bottom.
fn render_slab_bottom(direction: vec3<f32>, size_z: f32) -> f32 {
    let len = length(direction);
    if !(direction.z < 0.0 && len <= RENDER_NO_EXIT) {
        return RENDER_NO_EXIT;
    }
    return size_z * len / -direction.z;
}

// Rust: ddm_tracer::tangent_space::pixel_class (`hit` false: no hit, `t` unused).
fn render_pixel_class(hit: bool, t: f32, shell_exit: f32, slab_bottom: f32) -> f32 {
    if hit && t <= shell_exit {
        return RENDER_PIXEL_HIT;
    }
    return select(RENDER_PIXEL_MISS, RENDER_PIXEL_LEFT_SHELL, shell_exit < slab_bottom);
}

// Rust: ddm_tracer::tangent_space::in_shadow (relief scenes run relief mapping through
// trace_ray). Whether the tangent-space point `p` is in shadow for the tangent-space light direction
// `l` (pointing toward the light): a light below the tangent plane shadows; otherwise a
// ray from where the shadow ray leaves the top of the slab is traced back toward `p`
// (the tracer only follows descending rays), and a hit more than `tolerance` voxels
// before `p` shadows it.
fn render_in_shadow(u: TraceUniforms, p: vec3<f32>, l: vec3<f32>, tolerance: f32) -> bool {
    if !(l.z > 0.0) {
        return true;
    }
    let size_z = f32(u.dims_max_steps.z);
    let top = p + l * ((size_z - p.z) / l.z);
    let distance = length(top - p);
    let shadow = trace_ray(u, top, -l);
    return shadow.normal_hit.w == 1.0 && shadow.point_t.w < distance - tolerance;
}
