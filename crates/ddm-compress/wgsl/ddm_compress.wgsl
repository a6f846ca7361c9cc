// WGSL twin of crates/ddm-compress's access function (Mehra & Kumar, Algorithm A.2).
// Composed after generated/ddm_compress.wgsl, which declares
// CompressedMapUniforms and DDM_SURFACE_FLAG from the Rust source. Each function mirrors
// the Rust function named in its comment; tests/ddm_compress_gpu.rs proves them equal.
//
// A caller reads the lookup-grid entry at ddm_grid_index; if ddm_entry_is_surface, the
// distance is the atlas word at atlas_base + ddm_atlas_index, else ddm_entry_distance.

// Rust: ddm_compress::compress::grid_index.
fn ddm_grid_index(voxel: vec3<u32>, map: CompressedMapUniforms) -> u32 {
    let b = voxel / map.dims_block.w;
    return b.x + map.grid_atlas_base.x * (b.y + map.grid_atlas_base.y * b.z);
}

// Rust: ddm_compress::compress::atlas_index.
fn ddm_atlas_index(entry: u32, voxel: vec3<u32>, block: u32) -> u32 {
    let local = voxel % block;
    return (entry & ~DDM_SURFACE_FLAG) * block * block * block + local.x + block * (local.y + block * local.z);
}

// Rust: ddm_compress::compress::grid_index_shifted (blocks of side 1 << shift).
fn ddm_grid_index_shifted(voxel: vec3<u32>, map: CompressedMapUniforms, shift: u32) -> u32 {
    let b = voxel >> vec3<u32>(shift);
    return b.x + map.grid_atlas_base.x * (b.y + map.grid_atlas_base.y * b.z);
}

// Rust: ddm_compress::compress::atlas_index_shifted (blocks of side 1 << shift).
fn ddm_atlas_index_shifted(entry: u32, voxel: vec3<u32>, shift: u32) -> u32 {
    let local = voxel & vec3<u32>((1u << shift) - 1u);
    return (((((entry & ~DDM_SURFACE_FLAG) << shift) | local.z) << shift | local.y) << shift) | local.x;
}

// Rust: the flag test of CompressedMap::access.
fn ddm_entry_is_surface(entry: u32) -> bool {
    return (entry & DDM_SURFACE_FLAG) != 0u;
}

// Rust: the distance of a non-surface entry in CompressedMap::access (the f32's bits).
fn ddm_entry_distance(entry: u32) -> f32 {
    return bitcast<f32>(entry);
}

// Rust: gpu_layout::binary16::half_to_f32 of value `index` of the words that
// pack_f16_pairs_at_most packed (`word` is word index / 2): value 2k in the low half.
// Decoded with integer operations (unpack2x16float needs a capability some backends
// lack); exact for every value half_at_most stores, which are never subnormal.
fn ddm_f16_pair_value(word: u32, index: u32) -> f32 {
    let bits = select(word & 0xffffu, word >> 16u, (index & 1u) != 0u);
    let sign = (bits & 0x8000u) << 16u;
    let exponent = (bits >> 10u) & 0x1fu;
    if exponent == 0u {
        return bitcast<f32>(sign);
    }
    // Rebias 15 → 127; the all-ones exponent (infinity) stays all ones.
    let rebiased = select(exponent + 112u, 255u, exponent == 31u);
    return bitcast<f32>(sign | (rebiased << 23u) | ((bits & 0x3ffu) << 13u));
}

// Rust: the bounds test of CompressedMap::access.
fn ddm_voxel_in_map(voxel: vec3<u32>, map: CompressedMapUniforms) -> bool {
    return all(voxel < map.dims_block.xyz);
}
