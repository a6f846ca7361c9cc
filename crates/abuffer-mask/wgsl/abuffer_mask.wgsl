// WGSL twin of crates/abuffer-mask: sub-pixel coverage masks of Heitz & Neyret 2012
// (§5.3 Algorithm 1, §5.4).
//
// Composed after generated/abuffer_mask.wgsl, which declares MaskTableUniforms and every
// constant (ABUFFER_V_SATURATION, ABUFFER_MAX_SAMPLES, the index clamp, float bit masks)
// from the Rust source (src/wgsl.rs lists them). Every function here
// mirrors the Rust function named in its comment and is compared with it by
// tests/abuffer_mask_gpu.rs.
//
// A mask is a vec4<u32> whatever N (words beyond N / 32 are zero). The table is the flat
// u32 buffer of MaskTable::words: the mask of cell c occupies words c W .. c W + W.
//
// Table indices must be bit-identical to the CPU's: each index uses a single f32
// multiplication (correctly rounded in WGSL) by a scale computed on the CPU, then floor
// and integer arithmetic. No add follows a multiply (so FMA contraction cannot change
// anything) and non-finite inputs are classified by bit tests before any float operation.

// Rust: TableLayout::theta_index.
fn abuffer_theta_index(theta: f32, table: MaskTableUniforms) -> u32 {
    if (bitcast<u32>(theta) & ABUFFER_ABS_MASK) >= ABUFFER_INFINITY_BITS {
        return 0u;
    }
    let t = clamp(theta * table.theta_scale, -ABUFFER_INDEX_CLAMP, ABUFFER_INDEX_CLAMP);
    let i = i32(floor(t));
    let count = i32(table.theta_count);
    return u32((i % count + count) % count);
}

// Rust: TableLayout::v_index.
fn abuffer_v_index(v: f32, table: MaskTableUniforms) -> u32 {
    let bits = bitcast<u32>(v);
    let magnitude = bits & ABUFFER_ABS_MASK;
    if magnitude > ABUFFER_INFINITY_BITS {
        return 0u;
    }
    if magnitude == ABUFFER_INFINITY_BITS {
        return select(table.v_count - 1u, 0u, bits != magnitude);
    }
    let t = clamp(v * table.v_scale, -ABUFFER_INDEX_CLAMP, ABUFFER_INDEX_CLAMP);
    let j = i32(floor(t)) + i32(table.v_count / 2u);
    return u32(clamp(j, 0, i32(table.v_count) - 1));
}

// Rust: TableLayout::cell_index.
fn abuffer_cell_index(theta: f32, v: f32, table: MaskTableUniforms) -> u32 {
    return abuffer_theta_index(theta, table) * table.v_count + abuffer_v_index(v, table);
}

// Rust: MaskTable::cell_mask (the index of the cell's first word in MaskTable::words).
fn abuffer_mask_word_offset(cell: u32, table: MaskTableUniforms) -> u32 {
    return cell * table.words_per_mask;
}

// Rust: Mask::union (Algorithm 1, line 11).
fn abuffer_mask_union(a: vec4<u32>, b: vec4<u32>) -> vec4<u32> {
    return a | b;
}

// Rust: Mask::intersection.
fn abuffer_mask_intersection(a: vec4<u32>, b: vec4<u32>) -> vec4<u32> {
    return a & b;
}

// Rust: Mask::difference (Algorithm 1, line 10: 1_A \ α).
fn abuffer_mask_difference(a: vec4<u32>, b: vec4<u32>) -> vec4<u32> {
    return a & ~b;
}

// Rust: Mask::popcount (bitcount in Algorithm 1).
fn abuffer_mask_popcount(mask: vec4<u32>) -> u32 {
    let counts = countOneBits(mask);
    return counts.x + counts.y + counts.z + counts.w;
}

// Rust: Mask::coverage. coverage_scale = 1 / N is a power of two: the product is exact.
fn abuffer_mask_coverage(mask: vec4<u32>, table: MaskTableUniforms) -> f32 {
    return f32(abuffer_mask_popcount(mask)) * table.coverage_scale;
}

// Rust: half_plane::flush_subnormal (componentwise).
fn abuffer_flush_subnormal(v: vec4<f32>) -> vec4<f32> {
    let is_subnormal = (bitcast<vec4<u32>>(v) & vec4<u32>(ABUFFER_INFINITY_BITS)) == vec4<u32>(0u);
    return select(v, vec4<f32>(0.0), is_subnormal);
}

// Rust: HalfPlane::from_cone_element (§5.4 with |n_z|, see the Rust docs). Returns (θ, v).
// Not bit-exact (sqrt, atan2 and the division are approximate on GPUs); the test compares
// with a tolerance and requires equal table indices away from cell boundaries. Expects
// |n_x|, |n_y| < 1e18 so that n_x² + n_y² stays finite.
fn abuffer_half_plane(distance: f32, normal: vec3<f32>, radius: f32, half_length: f32) -> vec2<f32> {
    let empty = vec2<f32>(0.0, -ABUFFER_V_SATURATION);
    let first = vec4<f32>(distance, normal);
    let second = vec4<f32>(radius, half_length, 0.0, 0.0);
    let infinity = vec4<u32>(ABUFFER_INFINITY_BITS);
    if any((bitcast<vec4<u32>>(first) & vec4<u32>(ABUFFER_ABS_MASK)) >= infinity)
        || any((bitcast<vec4<u32>>(second) & vec4<u32>(ABUFFER_ABS_MASK)) >= infinity) {
        return empty;
    }
    let a = abuffer_flush_subnormal(first);
    let b = abuffer_flush_subnormal(second);
    if !(b.x > 0.0 && b.y >= 0.0) {
        return empty;
    }
    let offset = b.y * abs(a.w) - a.x;
    let rho = sqrt(a.y * a.y + a.z * a.z);
    let limit = b.x * rho;
    if abs(offset) >= ABUFFER_V_SATURATION * limit {
        return vec2<f32>(0.0, select(-ABUFFER_V_SATURATION, ABUFFER_V_SATURATION, offset >= 0.0));
    }
    return vec2<f32>(atan2(a.z, a.y), offset / limit);
}
