// The occluder map with one 64-bit atomic per pixel (SHADER_INT64_ATOMIC_MIN_MAX): every
// grain's square keeps max(~depth_bits << 32 | ~index), i.e. the nearest centre and, among
// equal depths, the lowest index; 0 (the cleared value) means no occluder. The splitter
// reads the low word (~index) of each pixel. Composed after projection.wgsl.

@group(0) @binding(3) var<storage, read_write> occluder_map: array<atomic<u64>>;

@compute @workgroup_size(256)
fn occluder_splat_64(
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
        return;
    }
    let key = (u64(~splat.depth_bits) << 32u) | u64(~index);
    let width = u32(camera.viewport.x);
    for (var y = splat.min.y; y <= splat.max.y; y++) {
        for (var x = splat.min.x; x <= splat.max.x; x++) {
            atomicMax(&occluder_map[y * width + x], key);
        }
    }
}
