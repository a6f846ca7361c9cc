// The splitter (§7, Fig. 7, with §8's culling): per grain a model (a list or a culling
// reason) and a tier kept for the hysteresis; per list a count, an offset, the element list
// and the indirect arguments of its draws — all on the GPU, no counter read back. Composed
// after occlusion_cone's WGSL twin and projection.wgsl, before hiz_common.wgsl and
// hiz_test.wgsl (the Hi-Z test). Passes, in order:
//   split_count     per grain: decide, store the state word, count per block and in total;
//   split_scan      (stable order only) exclusive prefix sums of the block counts;
//   split_offsets   one invocation: list offsets and indirect arguments;
//   split_write_*   per grain: write its index into its list (atomic cursors, or the stable
//                   order from the block prefix and a workgroup scan).

// Occluder-map words: ~index of the nearest grain, 0 for none; pixel p at p * counts.y.
@group(0) @binding(3) var<storage, read> occluder_words: array<u32>;
// Per grain: tier code (bits 0-7, kept across frames) and model (bits 8-15).
@group(0) @binding(4) var<storage, read_write> state: array<u32>;
// count[4], offset[4], cursor[4], culled[4] (see lists.rs).
@group(0) @binding(5) var<storage, read_write> counters: array<atomic<u32>, 16>;
// Per block of SPLIT_WORKGROUP grains: elements per list, then (after split_scan) the
// block's exclusive offsets within each list.
@group(0) @binding(6) var<storage, read_write> block_counts: array<vec4<u32>>;
@group(0) @binding(7) var<storage, read_write> elements: array<u32>;
// Per list: INDIRECT_WORDS words (draw_indexed, draw, dispatch).
@group(0) @binding(8) var<storage, read_write> indirect: array<u32>;

var<workgroup> block_lists: array<atomic<u32>, 4>;
var<workgroup> block_culled: array<atomic<u32>, CULL_REASONS>;
var<workgroup> scan: array<vec4<u32>, 256>;

const NO_GRAIN: u32 = 0xffffffffu;

// Rust: reference::decide. The state word of grain `index`.
fn split_decide(index: u32) -> u32 {
    let grain = grains[index];
    let centre = grain.xyz;
    let radius = params.radii.y * grain.w;
    let projected = split_project(centre);
    let perspective = camera.projection.y != 0.0;
    let twice_radius_focal = 2.0 * radius * camera.projection.x;
    var depth = 1.0;
    if perspective {
        depth = projected.view_depth;
    }
    let flags = params.counts.z;
    var previous = 0u;
    if (flags & FLAG_HYSTERESIS) != 0u {
        previous = state[index] & STATE_TIER_MASK;
    }
    let tier = split_tier(twice_radius_focal, depth, previous);
    let code = tier + 1u;
    if (flags & FLAG_FRUSTUM) != 0u && split_outside_frustum(centre, radius) {
        return code | (CULLED_FRUSTUM << STATE_MODEL_SHIFT);
    }
    var occluder = NO_GRAIN;
    if projected.in_front {
        let texel = split_centre_texel(projected.pixel);
        let word = occluder_words[(texel.y * u32(camera.viewport.x) + texel.x) * params.counts.y];
        if word != 0u {
            occluder = ~word;
        }
    }
    if (flags & FLAG_CONE) != 0u && perspective && occluder != index && occluder < params.counts.x {
        let other = grains[occluder];
        let g0 = split_transform(camera.view_from_world, other.xyz).xyz;
        if occlusion_is_occluded(vec4<f32>(g0, params.radii.x * other.w), vec4<f32>(projected.view, radius)) {
            return code | (CULLED_CONE << STATE_MODEL_SHIFT);
        }
    }
    if (flags & FLAG_HIZ) != 0u && hiz_hides(projected.view, centre, radius) {
        return code | (CULLED_HIZ << STATE_MODEL_SHIFT);
    }
    var model = LIST_POINT;
    if tier == 2u {
        model = LIST_MESH;
    } else if tier == 1u {
        model = select(LIST_IMPOSTOR_REST, LIST_IMPOSTOR_OCCLUDER, occluder == index);
    }
    return code | (model << STATE_MODEL_SHIFT);
}

@compute @workgroup_size(256)
fn split_count(
    @builtin(workgroup_id) workgroup: vec3<u32>,
    @builtin(num_workgroups) workgroups: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let block = split_block(workgroup, workgroups);
    let index = block * SPLIT_WORKGROUP + local;
    if index < params.counts.x {
        let word = split_decide(index);
        state[index] = word;
        let model = (word >> STATE_MODEL_SHIFT) & 0xffu;
        if model < LIST_COUNT {
            atomicAdd(&block_lists[model], 1u);
        } else {
            atomicAdd(&block_culled[model - LIST_COUNT], 1u);
        }
    }
    workgroupBarrier();
    if block >= params.counts.w {
        return;
    }
    if local < LIST_COUNT {
        let count = atomicLoad(&block_lists[local]);
        if count != 0u {
            atomicAdd(&counters[COUNTER_COUNT + local], count);
        }
    } else if local < LIST_COUNT + CULL_REASONS {
        let culled = atomicLoad(&block_culled[local - LIST_COUNT]);
        if culled != 0u {
            atomicAdd(&counters[COUNTER_CULLED + local - LIST_COUNT], culled);
        }
    } else if local == LIST_COUNT + CULL_REASONS {
        block_counts[block] = vec4<u32>(
            atomicLoad(&block_lists[0]),
            atomicLoad(&block_lists[1]),
            atomicLoad(&block_lists[2]),
            atomicLoad(&block_lists[3]),
        );
    }
}

// Inclusive prefix sum of `scan` over the workgroup (Hillis & Steele), then the barrier.
fn split_workgroup_scan(local: u32) {
    for (var step = 1u; step < 256u; step <<= 1u) {
        var add = vec4<u32>(0u);
        if local >= step {
            add = scan[local - step];
        }
        workgroupBarrier();
        scan[local] += add;
        workgroupBarrier();
    }
}

// One workgroup: each invocation sums a run of blocks, the runs are scanned, and each run is
// rewritten with its exclusive offsets.
@compute @workgroup_size(256)
fn split_scan(@builtin(local_invocation_index) local: u32) {
    let blocks = params.counts.w;
    let run = (blocks + 255u) / 256u;
    let first = min(local * run, blocks);
    let last = min(first + run, blocks);
    var sum = vec4<u32>(0u);
    for (var b = first; b < last; b++) {
        sum += block_counts[b];
    }
    scan[local] = sum;
    workgroupBarrier();
    split_workgroup_scan(local);
    var running = scan[local] - sum;
    for (var b = first; b < last; b++) {
        let count = block_counts[b];
        block_counts[b] = running;
        running += count;
    }
}

// Rust: ListIndirect::new, and the exclusive prefix sum of the counts.
@compute @workgroup_size(1)
fn split_offsets() {
    var offset = 0u;
    for (var list = 0u; list < LIST_COUNT; list++) {
        let count = atomicLoad(&counters[COUNTER_COUNT + list]);
        atomicStore(&counters[COUNTER_OFFSET + list], offset);
        atomicStore(&counters[COUNTER_CURSOR + list], 0u);
        offset += count;
        let groups = count / ELEMENT_WORKGROUP + select(0u, 1u, count % ELEMENT_WORKGROUP != 0u);
        let x = min(groups, MAX_GROUPS_PER_DIMENSION);
        var y = 1u;
        if groups != 0u {
            y = (groups + x - 1u) / x;
        }
        let base = list * INDIRECT_WORDS;
        indirect[base + INDIRECT_DRAW_INDEXED] = params.draw.x;
        indirect[base + INDIRECT_DRAW_INDEXED + 1u] = count;
        indirect[base + INDIRECT_DRAW_INDEXED + 2u] = 0u;
        indirect[base + INDIRECT_DRAW_INDEXED + 3u] = 0u;
        indirect[base + INDIRECT_DRAW_INDEXED + 4u] = 0u;
        indirect[base + INDIRECT_DRAW] = params.draw.y;
        indirect[base + INDIRECT_DRAW + 1u] = count;
        indirect[base + INDIRECT_DRAW + 2u] = 0u;
        indirect[base + INDIRECT_DRAW + 3u] = 0u;
        indirect[base + INDIRECT_DISPATCH] = x;
        indirect[base + INDIRECT_DISPATCH + 1u] = y;
        indirect[base + INDIRECT_DISPATCH + 2u] = 1u;
    }
}

// Atomic order (GrainViewer's): a cursor per list; the order within a list varies.
@compute @workgroup_size(256)
fn split_write_atomic(
    @builtin(workgroup_id) workgroup: vec3<u32>,
    @builtin(num_workgroups) workgroups: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let index = split_grain(workgroup, workgroups, local);
    if index >= params.counts.x {
        return;
    }
    let model = (state[index] >> STATE_MODEL_SHIFT) & 0xffu;
    if model >= LIST_COUNT {
        return;
    }
    let slot = atomicAdd(&counters[COUNTER_CURSOR + model], 1u);
    elements[atomicLoad(&counters[COUNTER_OFFSET + model]) + slot] = index;
}

// Stable order: ascending grain index within each list, from the block's exclusive offsets
// and the rank of the grain among its block's grains of the same list.
@compute @workgroup_size(256)
fn split_write_stable(
    @builtin(workgroup_id) workgroup: vec3<u32>,
    @builtin(num_workgroups) workgroups: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let block = split_block(workgroup, workgroups);
    let index = block * SPLIT_WORKGROUP + local;
    var model = LIST_COUNT;
    if index < params.counts.x {
        model = (state[index] >> STATE_MODEL_SHIFT) & 0xffu;
    }
    var one_hot = vec4<u32>(0u);
    if model < LIST_COUNT {
        one_hot[model] = 1u;
    }
    scan[local] = one_hot;
    workgroupBarrier();
    split_workgroup_scan(local);
    if model < LIST_COUNT {
        let rank = scan[local] - one_hot;
        let start = atomicLoad(&counters[COUNTER_OFFSET + model]) + block_counts[block][model];
        elements[start + rank[model]] = index;
    }
}
