// The plain distance map built on the GPU, a column of voxels per thread: the search of
// ddm_compress::compute_distance_maps with MapKind::Plain (crates/ddm-compress/src/ddm.rs's
// compute_row, src/bvh.rs's any_overlaps, src/plain.rs's voxel_distance) over the buffers
// of a ddm_compress::PlainGpuScene. Composed after ddm-compress's WGSL twin (the per-pair
// functions and the generated PlainGpu* declarations) and the generated PLAIN_BUILD_TILE
// and PLAIN_BUILD_COLUMN. Each thread walks a column of PLAIN_BUILD_COLUMN voxels up z, and
// each voxel first tries the triangle nearest the one below (the CPU seeds along x the same
// way): a close minimum at once, so that the traversal skips most of the hierarchy. The
// visiting order differs from the CPU's, so the values may too, each within the tolerance
// of the exact distance and never above it (tests/ddm_plain_map_gpu.rs).

@group(0) @binding(0) var<uniform> scene: PlainGpuUniforms;
@group(0) @binding(1) var<storage, read> nodes: array<PlainGpuNode>;
@group(0) @binding(2) var<storage, read> triangles: array<PlainGpuTriangle>;
@group(0) @binding(3) var<storage, read_write> values: array<f32>;
@group(0) @binding(4) var<storage, read_write> surface: array<u32>;

fn is_leaf(word: u32) -> bool {
    return (word & DDM_PLAIN_GPU_LEAF) != 0u;
}

fn leaf_first(word: u32) -> u32 {
    return word & ((1u << DDM_PLAIN_GPU_FIRST_BITS) - 1u);
}

fn leaf_count(word: u32) -> u32 {
    return (word & ~DDM_PLAIN_GPU_LEAF) >> DDM_PLAIN_GPU_FIRST_BITS;
}

fn max_component(v: vec3<f32>) -> f32 {
    return max(max(v.x, v.y), v.z);
}

// Whether a box reaches another (the CPU's node test of any_overlaps).
fn boxes_meet(a_min: vec3<f32>, a_max: vec3<f32>, b_min: vec3<f32>, b_max: vec3<f32>) -> bool {
    return !(any(a_min > b_max) || any(a_max < b_min));
}

// Rust: ddm_compress::TriangleBvh::any_overlaps over this hierarchy: the nodes whose boxes
// reach the voxel widened by DDM_OVERLAP_BOX_MARGIN, then the exact test on their leaves'
// triangles.
fn overlaps_any(voxel_min: vec3<f32>, voxel_max: vec3<f32>) -> bool {
    let margin = DDM_OVERLAP_BOX_MARGIN * (1.0 + max_component(abs(voxel_max)));
    let wide_min = voxel_min - margin;
    let wide_max = voxel_max + margin;
    var stack: array<u32, DDM_PLAIN_GPU_STACK>;
    var top = 0u;
    if boxes_meet(scene.root_min_tolerance.xyz, scene.root_max_cap.xyz, wide_min, wide_max) {
        stack[0] = scene.dims_root.w;
        top = 1u;
    }
    while top > 0u {
        top -= 1u;
        let word = stack[top];
        if is_leaf(word) {
            let first = leaf_first(word);
            for (var t = first; t < first + leaf_count(word); t++) {
                let triangle = triangles[t];
                if ddm_triangle_overlaps_box(voxel_min, voxel_max, triangle.a.xyz, triangle.b.xyz, triangle.c.xyz) {
                    return true;
                }
            }
        } else {
            let node = nodes[word];
            if boxes_meet(node.second_min.xyz, node.second_max.xyz, wide_min, wide_max) {
                stack[top] = node.children.y;
                top += 1u;
            }
            if boxes_meet(node.first_min.xyz, node.first_max.xyz, wide_min, wide_max) {
                stack[top] = node.children.x;
                top += 1u;
            }
        }
    }
    return false;
}

// What voxel_distance found: the value, and the triangle that gave it (NO_TRIANGLE if none).
struct Found {
    value: f32,
    nearest: u32,
}

const NO_TRIANGLE: u32 = 0xffffffffu;

// Rust: ddm_compress::plain::PlainHierarchy::voxel_distance: the minimum of
// ddm_plain_pair_lower_bound over the triangles, capped, `seed` (a triangle, or
// NO_TRIANGLE) tried first, the nodes visited nearest first and skipped (as are triangles)
// once their squared gap reaches the current minimum plus its rounding slack.
fn voxel_distance(voxel_min: vec3<f32>, voxel_max: vec3<f32>, seed: u32) -> Found {
    let tolerance = scene.root_min_tolerance.w;
    let magnitude = scene.magnitude.x;
    var found = scene.root_max_cap.w;
    var nearest = NO_TRIANGLE;
    if seed != NO_TRIANGLE {
        let triangle = triangles[seed];
        found = min(found, ddm_plain_pair_lower_bound(
            voxel_min,
            voxel_max,
            triangle.a.xyz,
            triangle.b.xyz,
            triangle.c.xyz,
            tolerance,
            found,
            magnitude,
        ));
        if found < scene.root_max_cap.w {
            nearest = seed;
        }
    }
    let slack = DDM_PLAIN_GAP_SLACK * (1.0 + max(max_component(max(abs(voxel_min), abs(voxel_max))), magnitude));
    var words: array<u32, DDM_PLAIN_GPU_STACK>;
    var gaps: array<f32, DDM_PLAIN_GPU_STACK>;
    words[0] = scene.dims_root.w;
    gaps[0] = ddm_box_gap_squared(voxel_min, voxel_max, scene.root_min_tolerance.xyz, scene.root_max_cap.xyz);
    var top = 1u;
    while top > 0u {
        top -= 1u;
        let word = words[top];
        let reach = (found + slack) * (found + slack);
        if gaps[top] >= reach {
            continue;
        }
        if is_leaf(word) {
            let first = leaf_first(word);
            for (var t = first; t < first + leaf_count(word); t++) {
                let triangle = triangles[t];
                let limit = (found + slack) * (found + slack);
                if ddm_box_gap_squared(voxel_min, voxel_max, triangle.min.xyz, triangle.max.xyz) >= limit {
                    continue;
                }
                let bound = ddm_plain_pair_lower_bound(
                    voxel_min,
                    voxel_max,
                    triangle.a.xyz,
                    triangle.b.xyz,
                    triangle.c.xyz,
                    tolerance,
                    found,
                    magnitude,
                );
                if bound < found {
                    found = bound;
                    nearest = t;
                }
            }
        } else {
            let node = nodes[word];
            let first_gap = ddm_box_gap_squared(voxel_min, voxel_max, node.first_min.xyz, node.first_max.xyz);
            let second_gap = ddm_box_gap_squared(voxel_min, voxel_max, node.second_min.xyz, node.second_max.xyz);
            // The far child first on the stack, so that the near one is visited first.
            var near_word = node.children.x;
            var near_gap = first_gap;
            var far_word = node.children.y;
            var far_gap = second_gap;
            if second_gap < first_gap {
                near_word = node.children.y;
                near_gap = second_gap;
                far_word = node.children.x;
                far_gap = first_gap;
            }
            if far_gap < reach {
                words[top] = far_word;
                gaps[top] = far_gap;
                top += 1u;
            }
            if near_gap < reach {
                words[top] = near_word;
                gaps[top] = near_gap;
                top += 1u;
            }
        }
    }
    return Found(found, nearest);
}

@compute @workgroup_size(PLAIN_BUILD_TILE, PLAIN_BUILD_TILE, 1)
fn build_plain_map(@builtin(global_invocation_id) id: vec3<u32>) {
    let dims = scene.dims_root.xyz;
    if id.x >= dims.x || id.y >= dims.y {
        return;
    }
    var seed = NO_TRIANGLE;
    let first = id.z * PLAIN_BUILD_COLUMN;
    for (var z = first; z < min(first + PLAIN_BUILD_COLUMN, dims.z); z++) {
        let voxel = vec3<u32>(id.xy, z);
        let index = voxel.x + dims.x * (voxel.y + dims.y * voxel.z);
        let voxel_min = vec3<f32>(voxel);
        let voxel_max = voxel_min + vec3<f32>(1.0);
        if overlaps_any(voxel_min, voxel_max) {
            values[index] = 0.0;
            surface[index] = 1u;
            continue;
        }
        let found = voxel_distance(voxel_min, voxel_max, seed);
        values[index] = found.value;
        surface[index] = 0u;
        if found.nearest != NO_TRIANGLE {
            seed = found.nearest;
        }
    }
}
