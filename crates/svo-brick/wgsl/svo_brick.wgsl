// WGSL twin of crates/svo-brick: sampling a pre-filtered sparse voxel octree of Heitz &
// Neyret 2012 (§5.2): descent of the node pool, exact decoding of the Paper20 and
// Compact16 layouts, and contraction-proof quadrilinear interpolation.
//
// Composed after generated/svo_brick.wgsl, which declares OctreeNode, OctreeUniforms and
// every constant (SVO_FRACTION_STEPS, SVO_SPLIT_MASK, ...) from the Rust source
// (src/wgsl.rs lists them). Every function mirrors the Rust function named in its
// comment and is compared with it bit for bit by tests/svo_brick_gpu.rs.
//
// The pools are read-only storage buffers of group 0: binding 3 the nodes
// (svo_brick::PackedTree::nodes), bindings 4-7 the brick pool split into whole bricks
// (PackedTree::brick_bindings; word k in binding 4 + k / words per binding, the unused
// ones a dummy word); the uniforms are a parameter, so a shader may keep them in a uniform
// or a storage buffer.
//
// Bit-exactness on every conforming implementation: every product that feeds an addition
// is exact (powers of two, or a 12-bit by 11-bit product in svo_lerp), so fusing a multiply
// and an add into an fma changes nothing; there is no division, sqrt or transcendental
// before svo_finish; NaN is detected by bit tests.

@group(0) @binding(3) var<storage, read> svo_nodes: array<OctreeNode>;
@group(0) @binding(4) var<storage, read> svo_bricks0: array<u32>;
@group(0) @binding(5) var<storage, read> svo_bricks1: array<u32>;
@group(0) @binding(6) var<storage, read> svo_bricks2: array<u32>;
@group(0) @binding(7) var<storage, read> svo_bricks3: array<u32>;

// Rust: svo_brick::RawVoxel (h̄, σh² in finest voxels; n̄ octahedral, L1-normalised; ā as
// mean_attribute, since `attribute` is a reserved word in WGSL;
// attributes as codes 255 ā, 127 a_s).
struct SvoRawVoxel {
    distance: f32,
    distance_variance: f32,
    normal: vec3<f32>,
    slope_variance: f32,
    mean_attribute: vec3<f32>,
    correlation: vec3<f32>,
}

// A sample and whether the point lies in the domain (Rust: Option<RawSample>).
struct SvoSample {
    voxel: SvoRawVoxel,
    inside: bool,
}

// Where the descent to a level ends (Rust: sample::Found): flag 0 with a brick and its
// node's origin, or SVO_EMPTY / SVO_FULL with the node's level.
struct SvoFound {
    brick: u32,
    level: u32,
    flag: u32,
    origin: vec3<u32>,
}

// Rust: layout::level_scale (2^L from its bits).
fn svo_level_scale(level: u32) -> f32 {
    return bitcast<f32>((127u + min(level, 127u)) << 23u);
}

// Rust: layout::level_inverse_scale (2^-L from its bits).
fn svo_level_inverse_scale(level: u32) -> f32 {
    return bitcast<f32>((127u - min(level, 126u)) << 23u);
}

// Rust: half::half_to_f32 of the low 16 bits, by integer operations (unpack2x16float
// needs a capability, and may flush subnormal halves).
fn svo_half(bits: u32) -> f32 {
    let sign = (bits & 0x8000u) << 16u;
    let exponent = (bits >> 10u) & 0x1fu;
    let mantissa = bits & 0x3ffu;
    if exponent == 0u {
        return bitcast<f32>(bitcast<u32>(f32(mantissa) * (1.0 / 16777216.0)) | sign);
    }
    if exponent == 31u {
        return bitcast<f32>(select(0x7fc00000u, 0x7f800000u, mantissa == 0u) | sign);
    }
    return bitcast<f32>((((exponent + 112u) << 23u) | (mantissa << 13u)) | sign);
}

fn svo_sign(x: f32) -> f32 {
    return select(-1.0, 1.0, x >= 0.0);
}

// Rust: layout::octahedral_decode.
fn svo_octahedral_decode(word: u32) -> vec3<f32> {
    return svo_octahedral_decode_bits(word & 0xffffu, word >> 16u, 16u);
}

// Rust: layout::octahedral_decode_bits.
fn svo_octahedral_decode_bits(code_u: u32, code_v: u32, bits: u32) -> vec3<f32> {
    let half = f32(1u << (bits - 1u));
    let step = bitcast<f32>((128u - bits) << 23u);
    let u = (f32(code_u) - half) * step;
    let v = (f32(code_v) - half) * step;
    let z = 1.0 - abs(u) - abs(v);
    if z >= 0.0 {
        return vec3<f32>(u, v, z);
    }
    return vec3<f32>((1.0 - abs(v)) * svo_sign(u), (1.0 - abs(u)) * svo_sign(v), z);
}

fn svo_byte(word: u32, k: u32) -> f32 {
    return f32((word >> (8u * k)) & 0xffu);
}

// Word k of binding `binding` of the brick pool.
fn svo_brick_word(binding: u32, k: u32) -> u32 {
    switch binding {
        case 0u: { return svo_bricks0[k]; }
        case 1u: { return svo_bricks1[k]; }
        case 2u: { return svo_bricks2[k]; }
        default: { return svo_bricks3[k]; }
    }
}

// The `count` words of one voxel from word `first` of the pool.
fn svo_voxel_words(tree: OctreeUniforms, first: u32, count: u32) -> array<u32, 5> {
    let binding = first / tree.pools.z;
    let local = first - binding * tree.pools.z;
    var w: array<u32, 5>;
    for (var k = 0u; k < count; k++) {
        w[k] = svo_brick_word(binding, local + k);
    }
    return w;
}

// Rust: VoxelLayout::decode_raw.
fn svo_decode_raw(tree: OctreeUniforms, w: array<u32, 5>, level: u32) -> SvoRawVoxel {
    var r: SvoRawVoxel;
    if tree.shape.z == SVO_LAYOUT_COMPACT16_FINE8 && level == 0u {
        r.distance = (f32(w[0] & 0xffffu) - 32768.0) * (1.0 / SVO_COMPACT_DISTANCE_STEPS);
        r.normal = svo_octahedral_decode_bits((w[0] >> 16u) & 0xfffu, (w[0] >> 28u) | ((w[1] & 0xffu) << 4u), 12u);
        r.mean_attribute = vec3<f32>(svo_byte(w[1], 1u), svo_byte(w[1], 2u), svo_byte(w[1], 3u));
        return r;
    }
    if tree.shape.z == SVO_LAYOUT_PAPER20 {
        let w1 = w[1];
        let w3 = w[3];
        let w4 = w[4];
        r.distance = bitcast<f32>(w[0]);
        r.distance_variance = svo_half(w1);
        r.normal = svo_octahedral_decode(w[2]);
        r.slope_variance = svo_half(w1 >> 16u);
        r.mean_attribute = vec3<f32>(svo_byte(w3, 0u), svo_byte(w3, 1u), svo_byte(w3, 2u));
        r.correlation = vec3<f32>(svo_byte(w3, 3u), svo_byte(w4, 0u), svo_byte(w4, 1u)) - 128.0;
    } else {
        let w0 = w[0];
        let w2 = w[2];
        let w3 = w[3];
        let scale = svo_level_scale(level);
        let step = scale * (1.0 / SVO_COMPACT_DISTANCE_STEPS);
        r.distance = (f32(w0 & 0xffffu) - 32768.0) * step;
        r.distance_variance = svo_half(w0 >> 16u) * (scale * scale);
        r.normal = svo_octahedral_decode(w[1]);
        r.slope_variance = svo_half(w2);
        r.mean_attribute = vec3<f32>(svo_byte(w2, 2u), svo_byte(w2, 3u), svo_byte(w3, 0u));
        r.correlation = vec3<f32>(svo_byte(w3, 1u), svo_byte(w3, 2u), svo_byte(w3, 3u)) - 128.0;
    }
    return r;
}

// Rust: sample::lerp (the split keeps both products exact).
fn svo_lerp(a: f32, b: f32, t: f32) -> f32 {
    let d = b - a;
    let hi = bitcast<f32>(bitcast<u32>(d) & SVO_SPLIT_MASK);
    let lo = d - hi;
    return (a + hi * t) + lo * t;
}

fn svo_lerp3(a: vec3<f32>, b: vec3<f32>, t: f32) -> vec3<f32> {
    let d = b - a;
    let hi = bitcast<vec3<f32>>(bitcast<vec3<u32>>(d) & vec3<u32>(SVO_SPLIT_MASK));
    let lo = d - hi;
    return (a + hi * t) + lo * t;
}

// Rust: sample::lerp_raw.
fn svo_lerp_raw(a: SvoRawVoxel, b: SvoRawVoxel, t: f32) -> SvoRawVoxel {
    var r: SvoRawVoxel;
    r.distance = svo_lerp(a.distance, b.distance, t);
    r.distance_variance = svo_lerp(a.distance_variance, b.distance_variance, t);
    r.normal = svo_lerp3(a.normal, b.normal, t);
    r.slope_variance = svo_lerp(a.slope_variance, b.slope_variance, t);
    r.mean_attribute = svo_lerp3(a.mean_attribute, b.mean_attribute, t);
    r.correlation = svo_lerp3(a.correlation, b.correlation, t);
    return r;
}

// Rust: sample::split_fraction, (⌊x⌋, ⌊(x − ⌊x⌋) 2048⌋ / 2048).
fn svo_split_fraction(x: f32) -> vec2<f32> {
    let i = floor(x);
    return vec2<f32>(i, floor((x - i) * SVO_FRACTION_STEPS) * (1.0 / SVO_FRACTION_STEPS));
}

// Rust: PackedTree::tree_position.
fn svo_tree_position(tree: OctreeUniforms, p: vec3<f32>) -> vec3<f32> {
    return (p - tree.origin_inverse_size.xyz) * tree.origin_inverse_size.w;
}

// Rust: PackedTree::cell (inside: all of q in [0, resolution)).
fn svo_inside(tree: OctreeUniforms, q: vec3<f32>) -> bool {
    let resolution = f32(tree.counts.z);
    return all(q >= vec3<f32>(0.0)) && all(q < vec3<f32>(resolution));
}

// Rust: PackedTree::find.
fn svo_find(tree: OctreeUniforms, cell: vec3<u32>, level: u32) -> SvoFound {
    var node_level = tree.shape.x - 1u;
    var index = 0u;
    var origin = vec3<u32>(0u);
    loop {
        if node_level <= level {
            break;
        }
        let node = svo_nodes[index];
        if node.child == 0u {
            return SvoFound(0u, node_level, node.brick, origin);
        }
        let half = 1u << (tree.shape.y + node_level - 1u);
        let bits = select(vec3<u32>(0u), vec3<u32>(1u), (cell - origin) >= vec3<u32>(half));
        origin += bits * half;
        index = node.child + (bits.x | (bits.y << 1u) | (bits.z << 2u));
        node_level -= 1u;
    }
    let brick = svo_nodes[index].brick;
    if brick >= SVO_FULL {
        return SvoFound(0u, node_level, brick, origin);
    }
    return SvoFound(brick, node_level, 0u, origin);
}

// Rust: PackedTree::empty_voxel.
fn svo_empty_voxel(level: u32, flag: u32) -> SvoRawVoxel {
    var r: SvoRawVoxel;
    let bound = SVO_EMPTY_DISTANCE * svo_level_scale(level);
    r.distance = select(bound, -bound, flag == SVO_FULL);
    return r;
}

// Rust: PackedTree::brick_offset.
fn svo_brick_offset(tree: OctreeUniforms, brick: u32) -> u32 {
    let side = (1u << tree.shape.y) + 1u;
    let stored = side * side * side;
    let first_fine = tree.pools.y;
    if brick < first_fine {
        return brick * stored * tree.shape.w;
    }
    return first_fine * stored * tree.shape.w + (brick - first_fine) * stored * tree.pools.x;
}

// Rust: PackedTree::stored_voxel (word k of the pool in binding k / words per binding).
fn svo_stored_voxel(tree: OctreeUniforms, brick: u32, index: vec3<u32>, level: u32) -> SvoRawVoxel {
    let side = (1u << tree.shape.y) + 1u;
    let count = select(tree.shape.w, tree.pools.x, level == 0u);
    let voxel = (index.z * side + index.y) * side + index.x;
    let first = svo_brick_offset(tree, brick) + voxel * count;
    return svo_decode_raw(tree, svo_voxel_words(tree, first, count), level);
}

// Rust: PackedTree::trilinear_in_brick.
fn svo_trilinear_in_brick(tree: OctreeUniforms, q: vec3<f32>, brick: u32, origin: vec3<u32>, level: u32) -> SvoRawVoxel {
    let inverse = svo_level_inverse_scale(level);
    let local = q * inverse - vec3<f32>(origin >> vec3<u32>(level));
    let n = f32(1u << tree.shape.y);
    let sx = svo_split_fraction(local.x);
    let sy = svo_split_fraction(local.y);
    let sz = svo_split_fraction(local.z);
    let base = vec3<u32>(clamp(vec3<f32>(sx.x, sy.x, sz.x), vec3<f32>(0.0), vec3<f32>(n - 1.0)));
    let t = vec3<f32>(sx.y, sy.y, sz.y);
    let x00 = svo_lerp_raw(svo_stored_voxel(tree, brick, base, level), svo_stored_voxel(tree, brick, base + vec3<u32>(1u, 0u, 0u), level), t.x);
    let x10 = svo_lerp_raw(svo_stored_voxel(tree, brick, base + vec3<u32>(0u, 1u, 0u), level), svo_stored_voxel(tree, brick, base + vec3<u32>(1u, 1u, 0u), level), t.x);
    let x01 = svo_lerp_raw(svo_stored_voxel(tree, brick, base + vec3<u32>(0u, 0u, 1u), level), svo_stored_voxel(tree, brick, base + vec3<u32>(1u, 0u, 1u), level), t.x);
    let x11 = svo_lerp_raw(svo_stored_voxel(tree, brick, base + vec3<u32>(0u, 1u, 1u), level), svo_stored_voxel(tree, brick, base + vec3<u32>(1u, 1u, 1u), level), t.x);
    let y0 = svo_lerp_raw(x00, x10, t.y);
    let y1 = svo_lerp_raw(x01, x11, t.y);
    return svo_lerp_raw(y0, y1, t.z);
}

// Rust: PackedTree::trilinear.
fn svo_trilinear(tree: OctreeUniforms, q: vec3<f32>, cell: vec3<u32>, level: u32) -> SvoRawVoxel {
    let found = svo_find(tree, cell, level);
    if found.flag != 0u {
        return svo_empty_voxel(found.level, found.flag);
    }
    return svo_trilinear_in_brick(tree, q, found.brick, found.origin, level);
}

fn svo_clamped_lod(tree: OctreeUniforms, lod: f32) -> f32 {
    if (bitcast<u32>(lod) & 0x7fffffffu) > 0x7f800000u {
        return 0.0;
    }
    return clamp(lod, 0.0, f32(tree.shape.x - 1u));
}

// Rust: PackedTree::sample_raw (inside = false: Rust's None).
fn svo_sample_raw(tree: OctreeUniforms, p: vec3<f32>, lod: f32) -> SvoSample {
    var result: SvoSample;
    let q = svo_tree_position(tree, p);
    result.inside = svo_inside(tree, q);
    if !result.inside {
        return result;
    }
    let cell = vec3<u32>(floor(q));
    let split = svo_split_fraction(svo_clamped_lod(tree, lod));
    let fine = u32(split.x);
    let coarse = min(fine + 1u, tree.shape.x - 1u);
    let t = select(split.y, 0.0, coarse == fine);
    let a = svo_trilinear(tree, q, cell, fine);
    let b = svo_trilinear(tree, q, cell, coarse);
    result.voxel = svo_lerp_raw(a, b, t);
    return result;
}

// Rust: PackedTree::sample_nearest before PackedTree::finish.
fn svo_sample_nearest_raw(tree: OctreeUniforms, p: vec3<f32>, lod: f32) -> SvoSample {
    var result: SvoSample;
    let q = svo_tree_position(tree, p);
    result.inside = svo_inside(tree, q);
    if !result.inside {
        return result;
    }
    let cell = vec3<u32>(floor(q));
    let level = u32(floor(svo_clamped_lod(tree, lod) + 0.5));
    let found = svo_find(tree, cell, level);
    if found.flag != 0u {
        result.voxel = svo_empty_voxel(found.level, found.flag);
    } else {
        let nearest = vec3<u32>(floor(q * svo_level_inverse_scale(level) + 0.5));
        result.voxel = svo_stored_voxel(tree, found.brick, nearest - (found.origin >> vec3<u32>(level)), level);
    }
    return result;
}

// Rust: PackedTree::finish (world units, n̄ normalised; a zero n̄ stays zero). Not
// bit-exact: the normalisation's sqrt and division have WGSL's accuracy.
fn svo_finish(tree: OctreeUniforms, raw: SvoRawVoxel) -> SvoRawVoxel {
    var r = raw;
    let size = tree.voxel_size.x;
    r.distance = raw.distance * size;
    r.distance_variance = raw.distance_variance * (size * size);
    let length2 = dot(raw.normal, raw.normal);
    r.normal = select(vec3<f32>(0.0), raw.normal * inverseSqrt(length2), length2 > 0.0);
    r.mean_attribute = raw.mean_attribute * (1.0 / 255.0);
    r.correlation = raw.correlation * (1.0 / 127.0);
    return r;
}

// Rust: PackedTree::sample (svo_finish of svo_sample_raw).
fn svo_sample(tree: OctreeUniforms, p: vec3<f32>, lod: f32) -> SvoSample {
    var s = svo_sample_raw(tree, p, lod);
    if s.inside {
        s.voxel = svo_finish(tree, s.voxel);
    }
    return s;
}

// Rust: PackedTree::sample_nearest.
fn svo_sample_nearest(tree: OctreeUniforms, p: vec3<f32>, lod: f32) -> SvoSample {
    var s = svo_sample_nearest_raw(tree, p, lod);
    if s.inside {
        s.voxel = svo_finish(tree, s.voxel);
    }
    return s;
}

// Rust: svo_brick::EmptyRegion (found = false: Rust's None).
struct SvoEmptyRegion {
    min: vec3<f32>,
    found: bool,
    max: vec3<f32>,
    level: u32,
    inside: bool,
}

// Rust: PackedTree::empty_region.
fn svo_empty_region(tree: OctreeUniforms, p: vec3<f32>, level: u32) -> SvoEmptyRegion {
    var region: SvoEmptyRegion;
    let q = svo_tree_position(tree, p);
    if !svo_inside(tree, q) {
        return region;
    }
    let found = svo_find(tree, vec3<u32>(floor(q)), min(level, tree.shape.x - 1u));
    if found.flag == 0u {
        return region;
    }
    let size = tree.voxel_size.x;
    let side = f32((1u << tree.shape.y) << found.level) * size;
    region.min = tree.origin_inverse_size.xyz + vec3<f32>(found.origin) * size;
    region.max = region.min + side;
    region.found = true;
    region.level = found.level;
    region.inside = found.flag == SVO_FULL;
    return region;
}
