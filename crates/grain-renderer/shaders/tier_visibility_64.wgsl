// The visibility buffer with 64-bit atomics (SHADER_INT64_ATOMIC_MIN_MAX): one atomicMin of
// (depth bits << 32) | grain per covered pixel; depths are positive, so their bits order like
// them, and ties go to the smallest index. The mesh tier's pixels hold (depth, TIER_MESH).

@group(0) @binding(8) var<storage, read_write> visibility: array<atomic<u64>>;

fn tier_key(depth: f32, g: u32) -> u64 {
    return (u64(bitcast<u32>(depth)) << 32u) | u64(g);
}

fn tier_clear_pixel(i: u32, mesh_depth: f32) {
    var key = tier_key(bitcast<f32>(POSITIVE_INFINITY_BITS), TIER_NONE);
    if mesh_depth < bitcast<f32>(POSITIVE_INFINITY_BITS) {
        key = tier_key(mesh_depth, TIER_MESH);
    }
    atomicStore(&visibility[i], key);
}

fn tier_offer(i: u32, depth: f32, g: u32) {
    atomicMin(&visibility[i], tier_key(depth, g));
}

fn tier_stored_depth(i: u32) -> f32 {
    return bitcast<f32>(u32(atomicLoad(&visibility[i]) >> 32u));
}

fn tier_winner(i: u32) -> u32 {
    return u32(atomicLoad(&visibility[i]));
}
