// WGSL twin of crates/ddm-tracer's tracer (Mehra & Kumar, Algorithms 3.1-3.3). Composed
// after the quadric_fit module (quadric_first_hit, quadric_normal), the ddm_compress module (the
// compressed-map access of Algorithm A.2) and generated/ddm_tracer.wgsl (the structs and
// constants, from the Rust source: src/wgsl.rs lists them). Each function mirrors the Rust function
// named in its comment; tests/ddm_tracer_gpu.rs proves them equal.
//
// The scene lives in read-only storage buffers at bindings 3-8 (ddm_tracer::GpuScene);
// a kernel declares the uniforms (binding 0) and its own input and output. What stays fixed
// for a scene is a pipeline-overridable constant (TRACE_METHOD, TRACE_STEPPING,
// TRACE_PERIODIC, TRACE_BLOCK_SHIFT, TRACE_ATLAS_F16: GpuScene::pipeline_constants), so that
// each pipeline is compiled without the branches of the other settings.

@group(0) @binding(3) var<storage, read> trace_cone_maps: array<TraceConeMap>;
@group(0) @binding(4) var<storage, read> trace_grid: array<u32>;
@group(0) @binding(5) var<storage, read> trace_atlas: array<u32>;
@group(0) @binding(6) var<storage, read> trace_patch_offsets: array<u32>;
@group(0) @binding(7) var<storage, read> trace_patches: array<TracePatch>;
@group(0) @binding(8) var<storage, read> trace_heights: array<f32>;

// Rust: ddm_tracer::maps::ConeSelector::select. Returns -1 outside the band (Rust: None).
fn trace_select_cone(u: TraceUniforms, direction: vec3<f32>) -> i32 {
    let azimuths = u.cones_rays.x;
    let elevations = u.cones_rays.y;
    if azimuths == 0u {
        return 0;
    }
    let horizontal = sqrt(direction.x * direction.x + direction.y * direction.y);
    let elevation = atan2(direction.z, horizontal);
    var azimuth = atan2(direction.y, direction.x);
    if azimuth < 0.0 {
        azimuth += TRACE_TAU;
    }
    if azimuth >= TRACE_TAU {
        azimuth = 0.0;
    }
    let band = u.elevation_band;
    if !(elevation >= band.x && elevation <= band.y) {
        return -1;
    }
    let a = min(u32(azimuth / TRACE_TAU * f32(azimuths)), azimuths - 1u);
    let t = (elevation - band.x) / (band.y - band.x);
    let e = min(u32(t * f32(elevations)), elevations - 1u);
    return i32(a + azimuths * e);
}

// Rust: ddm_tracer::voxel::unit.
fn trace_unit(direction: vec3<f32>) -> vec3<f32> {
    return direction * (1.0 / sqrt(dot(direction, direction)));
}

// Rust: ddm_tracer::voxel::slab_entry.
fn trace_slab_entry(origin: vec3<f32>, direction: vec3<f32>, size_z: f32) -> f32 {
    return select(0.0, (size_z - origin.z) / direction.z, origin.z > size_z);
}

// Rust: ddm_tracer::voxel::tile_entry (negative for None).
fn trace_tile_entry(origin: vec3<f32>, direction: vec3<f32>, size: vec3<f32>) -> f32 {
    var entry = trace_slab_entry(origin, direction, size.z);
    for (var axis = 0u; axis < 2u; axis++) {
        let o = origin[axis];
        let r = direction[axis];
        if o < 0.0 {
            if r <= 0.0 {
                return -1.0;
            }
            entry = max(entry, -o / r);
        } else if o > size[axis] {
            if r >= 0.0 {
                return -1.0;
            }
            entry = max(entry, (size[axis] - o) / r);
        }
    }
    return entry;
}

// Rust: ddm_tracer::voxel::outside_tile.
fn trace_outside_tile(probe: vec3<f32>, size: vec3<f32>) -> bool {
    return !(probe.x >= 0.0 && probe.y >= 0.0 && probe.x < size.x && probe.y < size.y);
}

// Rust: ddm_tracer::voxel::voxel_entry.
fn trace_voxel_entry(local: vec3<f32>, direction: vec3<f32>) -> f32 {
    var entry = 0.0;
    for (var axis = 0u; axis < 3u; axis++) {
        let r = direction[axis];
        if r != 0.0 {
            let wall = select(1.0, 0.0, r > 0.0);
            entry = max(entry, (wall - local[axis]) / r);
        }
    }
    return entry;
}

// Rust: ddm_tracer::voxel::voxel_exit.
fn trace_voxel_exit(local: vec3<f32>, direction: vec3<f32>) -> f32 {
    return trace_cell_exit(local, direction, vec3<f32>(1.0));
}

// Rust: ddm_tracer::voxel::cell_exit.
fn trace_cell_exit(local: vec3<f32>, direction: vec3<f32>, size: vec3<f32>) -> f32 {
    var exit = 3.40282347e38;
    for (var axis = 0u; axis < 3u; axis++) {
        let r = direction[axis];
        if r != 0.0 {
            let wall = select(0.0, size[axis], r > 0.0);
            exit = min(exit, (wall - local[axis]) / r);
        }
    }
    return max(exit, 0.0);
}

// Rust: ddm_tracer::trace::entry_wall_normal.
fn trace_entry_wall_normal(local: vec3<f32>, direction: vec3<f32>) -> vec3<f32> {
    var best = 3.40282347e38;
    var normal = vec3<f32>(0.0, 0.0, 1.0);
    for (var axis = 0u; axis < 3u; axis++) {
        let r = direction[axis];
        if r == 0.0 {
            continue;
        }
        let wall = select(0.0, 1.0, r < 0.0);
        let distance = abs(local[axis] - wall);
        if distance < best {
            best = distance;
            normal = vec3<f32>(0.0);
            normal[axis] = select(-1.0, 1.0, r < 0.0);
        }
    }
    return normal;
}

// Rust: ddm_tracer::patch::quadric_of.
fn trace_quadric_of(piece: TracePatch) -> GpuQuadric {
    return GpuQuadric(piece.abcd, piece.efgh, piece.ij_corners.xy, vec2<f32>(0.0));
}

// Rust: ddm_tracer::patch::inside_polygon.
fn trace_inside_polygon(piece: TracePatch, p: vec3<f32>) -> bool {
    let n = piece.normal.xyz;
    var corners = array<vec3<f32>, 4>(piece.corners[0].xyz, piece.corners[1].xyz, piece.corners[2].xyz, piece.corners[3].xyz);
    let count = select(3u, 4u, piece.ij_corners.z > 3.5);
    for (var i = 0u; i < count; i++) {
        let a = corners[i];
        let b = corners[(i + 1u) % count];
        let edge = b - a;
        let side = dot(cross(edge, p - a), n);
        if side < -TRACE_POLYGON_TOLERANCE * length(edge) {
            return false;
        }
    }
    return true;
}

// A stored distance and the cell of voxels `origin ≤ v < origin + size` it holds for
// (Rust: ddm_compress::CellDistance).
struct TraceCell {
    origin: vec3<u32>,
    size: vec3<u32>,
    distance: f32,
}

// Rust: the atlas value `index` of GpuScene::atlas, stored as TRACE_ATLAS_F16 says
// (binary16 pairs: CompressedMaps::with_f16_atlas's values; else f32 bits).
fn trace_atlas_value(index: u32) -> f32 {
    if TRACE_ATLAS_F16 != 0u {
        return ddm_f16_pair_value(trace_atlas[index >> 1u], index);
    }
    return bitcast<f32>(trace_atlas[index]);
}

// Rust: CompressedMap::access_cell, through <CompressedMaps as DistanceSource> (the
// distance is CompressedMap::access's: Algorithm A.2; with the cell: the voxel in a surface
// block, the block clipped to the map elsewhere; 0 and the voxel outside the map). With
// TRACE_BLOCK_SHIFT, shifts instead of divisions (the Rust's power-of-two path).
fn trace_map_cell(cone: u32, voxel: vec3<u32>) -> TraceCell {
    let entry_map = trace_cone_maps[cone];
    let map = CompressedMapUniforms(entry_map.dims_block, entry_map.grid_atlas_base);
    if !ddm_voxel_in_map(voxel, map) {
        return TraceCell(voxel, vec3<u32>(1u), 0.0);
    }
    let shifted = TRACE_BLOCK_SHIFT != TRACE_BLOCK_DIVISIONS;
    // Masked so that the unused branch of the divisions' setting shifts by less than 32
    // bits (a constant shift of 32 or more is invalid WGSL).
    let shift = TRACE_BLOCK_SHIFT & 31u;
    var grid_index: u32;
    if shifted {
        grid_index = ddm_grid_index_shifted(voxel, map, shift);
    } else {
        grid_index = ddm_grid_index(voxel, map);
    }
    let entry = trace_grid[entry_map.grid_base.x + grid_index];
    if ddm_entry_is_surface(entry) {
        var atlas_index: u32;
        if shifted {
            atlas_index = ddm_atlas_index_shifted(entry, voxel, shift);
        } else {
            atlas_index = ddm_atlas_index(entry, voxel, map.dims_block.w);
        }
        return TraceCell(voxel, vec3<u32>(1u), trace_atlas_value(map.grid_atlas_base.w + atlas_index));
    }
    let block = map.dims_block.w;
    var origin: vec3<u32>;
    if shifted {
        origin = (voxel >> vec3<u32>(shift)) << vec3<u32>(shift);
    } else {
        origin = voxel / block * block;
    }
    return TraceCell(origin, min(vec3<u32>(block), map.dims_block.xyz - origin), ddm_entry_distance(entry));
}

// Rust: ddm_tracer::patch::patch_hit. Returns vec3(t, piece index, 1) for a hit and
// vec3(0) for a miss; `first` and `count` select the voxel's patches.
fn trace_patch_hit(first: u32, count: u32, local: vec3<f32>, direction: vec3<f32>, t_exit: f32) -> vec3<f32> {
    var best = vec3<f32>(0.0);
    for (var k = 0u; k < count; k++) {
        let piece = trace_patches[first + k];
        let hit = quadric_first_hit(trace_quadric_of(piece), local, direction, -TRACE_NUDGE, t_exit);
        if hit.y == 0.0 {
            continue;
        }
        let clipped = count > 1u || piece.ij_corners.w == TRACE_BOUNDED_PATCH;
        if clipped && !trace_inside_polygon(piece, local + direction * hit.x) {
            continue;
        }
        if best.z == 0.0 || hit.x < best.x {
            best = vec3<f32>(hit.x, f32(k), 1.0);
        }
    }
    return best;
}

fn trace_miss(steps: u32, cone: u32, exhausted: u32) -> TraceResult {
    return TraceResult(vec4<f32>(0.0), vec4<f32>(0.0), vec4<u32>(steps, cone, exhausted, 0u));
}

// Rust: ddm_tracer::relief::HeightMap::texel.
fn relief_texel(x: i32, y: i32, w: i32, h: i32) -> f32 {
    return trace_heights[((x % w) + w) % w + w * (((y % h) + h) % h)];
}

// Rust: ddm_tracer::relief::HeightMap::height (bilinear, periodic).
fn relief_height(u: TraceUniforms, p: vec2<f32>) -> f32 {
    let s = u.relief.z;
    let w = i32(u.dims_max_steps.x * s);
    let h = i32(u.dims_max_steps.y * s);
    let q = p * f32(s) - 0.5;
    let fx = floor(q.x);
    let fy = floor(q.y);
    let x = i32(fx);
    let y = i32(fy);
    let a = q.x - fx;
    let b = q.y - fy;
    let lower = relief_texel(x, y, w, h) * (1.0 - a) + relief_texel(x + 1, y, w, h) * a;
    let upper = relief_texel(x, y + 1, w, h) * (1.0 - a) + relief_texel(x + 1, y + 1, w, h) * a;
    return lower * (1.0 - b) + upper * b;
}

// Rust: ddm_tracer::relief::HeightMap::normal.
fn relief_normal(u: TraceUniforms, p: vec2<f32>) -> vec3<f32> {
    let h = 1.0 / f32(u.relief.z);
    let dx = relief_height(u, p + vec2<f32>(h, 0.0)) - relief_height(u, p - vec2<f32>(h, 0.0));
    let dy = relief_height(u, p + vec2<f32>(0.0, h)) - relief_height(u, p - vec2<f32>(0.0, h));
    return normalize(vec3<f32>(-dx, -dy, 2.0 * h));
}

// Rust: the below-the-height-map test of ddm_tracer::relief::relief_trace.
fn relief_below(u: TraceUniforms, start: vec3<f32>, d: vec3<f32>, t: f32) -> bool {
    let p = start + d * t;
    return p.z <= relief_height(u, p.xy);
}

// Rust: ddm_tracer::relief::relief_trace (linear then binary search).
fn relief_trace_ray(u: TraceUniforms, origin: vec3<f32>, direction: vec3<f32>) -> TraceResult {
    let d = trace_unit(direction);
    if !(d.z < 0.0) {
        return trace_miss(0u, 0u, 0u);
    }
    let dims = u.dims_max_steps.xyz;
    let size_z = f32(dims.z);
    let t_enter = trace_slab_entry(origin, d, size_z);
    let start = origin + d * t_enter;
    let t_bottom = -start.z / d.z;
    let linear = max(u.relief.x, 1u);
    let dt = t_bottom / f32(linear);
    var steps = 0u;
    var lo = 0.0;
    var hi = 0.0;
    var found = false;
    for (var i = 1u; i <= linear; i++) {
        let t = dt * f32(i);
        steps += 1u;
        if relief_below(u, start, d, t) {
            hi = t;
            found = true;
            break;
        }
        lo = t;
    }
    if !found {
        return trace_miss(steps, 0u, 0u);
    }
    for (var k = 0u; k < u.relief.y; k++) {
        let mid = 0.5 * (lo + hi);
        steps += 1u;
        if relief_below(u, start, d, mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let t = 0.5 * (lo + hi);
    let p = start + d * t;
    let idims = vec3<i32>(dims);
    let vx = ((i32(floor(p.x)) % idims.x) + idims.x) % idims.x;
    let vy = ((i32(floor(p.y)) % idims.y) + idims.y) % idims.y;
    let vz = u32(clamp(floor(p.z), 0.0, max(size_z - 1.0, 0.0)));
    let voxel_index = u32(vx) + dims.x * (u32(vy) + dims.y * vz);
    return TraceResult(vec4<f32>(p, t_enter + t), vec4<f32>(relief_normal(u, p.xy), 1.0), vec4<u32>(steps, 0u, 0u, voxel_index));
}

// Rust: ddm_tracer::trace::trace (Algorithm 3.1 with 3.2 and 3.3), reading the compressed
// maps and patches of the storage buffers. The caller guarantees finite input.
// With TRACE_METHOD == TRACE_METHOD_RELIEF it runs relief_trace_ray instead.
fn trace_ray(u: TraceUniforms, origin: vec3<f32>, direction: vec3<f32>) -> TraceResult {
    return trace_ray_within(u, origin, direction, TRACE_NO_LIMIT);
}

// Rust: ddm_tracer::trace_within (relief scenes run relief mapping, without the limit).
fn trace_ray_within(u: TraceUniforms, origin: vec3<f32>, direction: vec3<f32>, max_t: f32) -> TraceResult {
    if TRACE_METHOD == TRACE_METHOD_RELIEF {
        return relief_trace_ray(u, origin, direction);
    }
    let dims = u.dims_max_steps.xyz;
    if any(dims == vec3<u32>(0u)) {
        return trace_miss(0u, 0u, 0u);
    }
    let d = trace_unit(direction);
    if !(d.z < 0.0) {
        return trace_miss(0u, 0u, 0u);
    }
    let selected = trace_select_cone(u, d);
    if selected < 0 {
        return trace_miss(0u, 0u, 0u);
    }
    let cone = u32(selected);
    let size = vec3<f32>(dims);
    let periodic = TRACE_PERIODIC != 0u;
    var t_enter = trace_slab_entry(origin, d, size.z);
    var step_cap = min(size.x, size.y);
    if !periodic {
        t_enter = trace_tile_entry(origin, d, size);
        // Negative: the ray never enters (Rust: None); not finite: Rust's filter.
        if !(t_enter >= 0.0 && t_enter <= 3.40282347e38) {
            return trace_miss(0u, cone, 0u);
        }
        step_cap = 3.40282347e38;
    }
    let start = origin + d * t_enter;
    let idims = vec3<i32>(dims);
    var t = 0.0;
    var steps = 0u;
    while steps < u.dims_max_steps.w {
        let p = start + d * t;
        let probe = p + d * TRACE_NUDGE;
        if probe.z < 0.0 || t_enter + t > max_t || (!periodic && trace_outside_tile(probe, size)) {
            return trace_miss(steps, cone, 0u);
        }
        let v = vec3<i32>(i32(floor(probe.x)), i32(floor(probe.y)), min(i32(floor(probe.z)), idims.z - 1));
        let wrapped = vec3<u32>(u32(((v.x % idims.x) + idims.x) % idims.x), u32(((v.y % idims.y) + idims.y) % idims.y), u32(v.z));
        steps += 1u;
        let cell = trace_map_cell(cone, wrapped);
        let value = cell.distance;
        if value > 0.0 {
            var inside = 0.0;
            let block = any(cell.size != vec3<u32>(1u));
            if TRACE_STEPPING == TRACE_STEPPING_VOXEL_EXIT || (TRACE_STEPPING == TRACE_STEPPING_BLOCK_CELLS && block) {
                // To the exit wall of the cell (the voxel, or a block without surface).
                let corner = vec3<f32>(v) - vec3<f32>(wrapped - cell.origin);
                inside = trace_cell_exit(p - corner, d, vec3<f32>(cell.size));
            }
            t += min(inside + value, step_cap);
            continue;
        }
        let corner = vec3<f32>(v);
        let voxel_index = wrapped.x + dims.x * (wrapped.y + dims.y * wrapped.z);
        if TRACE_METHOD == TRACE_METHOD_SPHERE_TRACING {
            let normal = trace_entry_wall_normal(p - corner, d);
            return TraceResult(vec4<f32>(p, t_enter + t), vec4<f32>(normal, 1.0), vec4<u32>(steps, cone, 0u, voxel_index));
        }
        let start_local = start - corner;
        let t_in = trace_voxel_entry(start_local, d);
        let entry = start_local + d * t_in;
        let t_exit = trace_voxel_exit(entry, d);
        let first = trace_patch_offsets[voxel_index];
        let count = trace_patch_offsets[voxel_index + 1u] - first;
        let hit = trace_patch_hit(first, count, entry, d, t_exit);
        if hit.z != 0.0 {
            let th = hit.x;
            var n = quadric_normal(trace_quadric_of(trace_patches[first + u32(hit.y)]), entry + d * th);
            if dot(n, d) > 0.0 {
                n = -n;
            }
            return TraceResult(vec4<f32>(start + d * (t_in + th), t_enter + t_in + th), vec4<f32>(n, 1.0), vec4<u32>(steps, cone, 0u, voxel_index));
        }
        t = max(t, t_in + t_exit);
    }
    return trace_miss(steps, cone, 1u);
}
