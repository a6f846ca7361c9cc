// The visibility buffer with 32-bit atomics: depth bits, then the owner. Each list is splatted
// twice by the same pipeline: pass 0 keeps the nearest depth (atomicMin of its bits), pass 1
// lets the grains whose depth bits equal it claim the pixel (atomicMin of the index: ties go
// to the smallest). The depth pass 1 compares is computed by the same compiled code as the one
// pass 0 stored (one pipeline, a uniform selects the atomic), so no compiler contraction can
// make them differ.

@group(0) @binding(8) var<storage, read_write> nearest_depth: array<atomic<u32>>;
@group(0) @binding(9) var<storage, read_write> owner: array<atomic<u32>>;

fn tier_clear_pixel(i: u32, mesh_depth: f32) {
    let mesh = mesh_depth < bitcast<f32>(POSITIVE_INFINITY_BITS);
    atomicStore(&nearest_depth[i], select(POSITIVE_INFINITY_BITS, bitcast<u32>(mesh_depth), mesh));
    atomicStore(&owner[i], select(TIER_NONE, TIER_MESH, mesh));
}

fn tier_offer(i: u32, depth: f32, g: u32) {
    if tier_pass.owner_pass == 0u {
        atomicMin(&nearest_depth[i], bitcast<u32>(depth));
    } else if bitcast<u32>(depth) == atomicLoad(&nearest_depth[i]) {
        atomicMin(&owner[i], g);
    }
}

fn tier_stored_depth(i: u32) -> f32 {
    return bitcast<f32>(atomicLoad(&nearest_depth[i]));
}

fn tier_winner(i: u32) -> u32 {
    return atomicLoad(&owner[i]);
}
