// The occluder map with 32-bit atomics (adapters without 64-bit atomic min/max), in two
// passes: the first keeps max(~depth_bits) per pixel and stores each grain's key and square;
// the second lets the grains whose *stored* key equals the pixel's keep max(~index). The
// second pass compares the key the first one wrote, never a depth computed again (a compiler
// contracting the projection differently in two entry points would otherwise leave pixels
// with a depth and no grain). The result equals the 64-bit map's. Composed after
// projection.wgsl.

@group(0) @binding(3) var<storage, read_write> occluder_depth: array<atomic<u32>>;
@group(0) @binding(4) var<storage, read_write> occluder_ids: array<atomic<u32>>;
// Per grain: (~depth_bits or 0 for none, min x | min y << 16, max x | max y << 16, 0).
@group(0) @binding(5) var<storage, read_write> splats: array<vec4<u32>>;

@compute @workgroup_size(256)
fn occluder_depth_32(
    @builtin(workgroup_id) workgroup: vec3<u32>,
    @builtin(num_workgroups) workgroups: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let index = split_grain(workgroup, workgroups, local);
    if index >= params.counts.x {
        return;
    }
    let splat = split_splat(grains[index]);
    if !splat.valid {
        splats[index] = vec4<u32>(0u);
        return;
    }
    let key = ~splat.depth_bits;
    splats[index] = vec4<u32>(key, splat.min.x | (splat.min.y << 16u), splat.max.x | (splat.max.y << 16u), 0u);
    let width = u32(camera.viewport.x);
    for (var y = splat.min.y; y <= splat.max.y; y++) {
        for (var x = splat.min.x; x <= splat.max.x; x++) {
            atomicMax(&occluder_depth[y * width + x], key);
        }
    }
}

@compute @workgroup_size(256)
fn occluder_id_32(
    @builtin(workgroup_id) workgroup: vec3<u32>,
    @builtin(num_workgroups) workgroups: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let index = split_grain(workgroup, workgroups, local);
    if index >= params.counts.x {
        return;
    }
    let splat = splats[index];
    if splat.x == 0u {
        return;
    }
    let width = u32(camera.viewport.x);
    for (var y = splat.y >> 16u; y <= splat.z >> 16u; y++) {
        for (var x = splat.y & 0xffffu; x <= (splat.z & 0xffffu); x++) {
            let pixel = y * width + x;
            if atomicLoad(&occluder_depth[pixel]) == splat.x {
                atomicMax(&occluder_ids[pixel], ~index);
            }
        }
    }
}
