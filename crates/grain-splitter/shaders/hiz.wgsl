// Occluder fusion's pyramid on the GPU (Rust: hiz, and fusion's f64 reference). Composed after
// generated.wgsl, projection.wgsl and hiz_common.wgsl. Passes, in order:
//   hiz_cover    (two-phase only) per grain kept last frame: D(p) over its inscribed square,
//                the smallest per pixel (Rust: temporal::cover_bounds);
//   hiz_bound    per pixel: the bound D(p) of the pixel's occluder, or the cover's if smaller
//                (level 0);
//   hiz_reduce   per texel of level k ≥ 1 (k from hiz_level): the max of its 2 × 2 children.

// Occluder-map words: ~index of the nearest grain, 0 for none; pixel p at p * params.counts.y.
@group(0) @binding(3) var<storage, read> occluder_words: array<u32>;
// Every level, one after another (hiz.levels[k].z is level k's first texel).
@group(0) @binding(4) var<storage, read_write> pyramid: array<f32>;
@group(0) @binding(5) var<uniform> hiz: HizParams;
// (k, 0, 0, 0): the level hiz_reduce writes (a dynamic offset per level).
@group(0) @binding(6) var<uniform> hiz_level: vec4<u32>;

// Per pixel: the largest ~bits(D) of the covering grains (0: none), cleared every frame.
@group(0) @binding(7) var<storage, read_write> cover: array<atomic<u32>>;
// Per grain: last frame's state word (model in bits 8-15).
@group(0) @binding(8) var<storage, read> state: array<u32>;

// Rust: fusion::Rays::pixel_bound for the inner ball of `grain` (world centre, scale),
// shrunk by its slack.
fn hiz_ball_bound(x: u32, y: u32, grain: vec4<f32>) -> f32 {
    let g = split_transform(camera.view_from_world, grain.xyz).xyz;
    let r = params.radii.x * grain.w - hiz_slack(g, grain.xyz);
    let g2 = dot(g, g);
    if !(r > 0.0) || !(g2 > 4.0 * r * r) {
        return HIZ_NONE;
    }
    let m = HIZ_FOOTPRINT_MARGIN_PX;
    let lo = vec2<f32>(f32(x) - m, f32(y) - m);
    let hi = vec2<f32>(f32(x) + 1.0 + m, f32(y) + 1.0 + m);
    var bound = 0.0;
    for (var corner = 0u; corner < 4u; corner++) {
        let p = select(lo, hi, vec2<bool>((corner & 1u) != 0u, (corner & 2u) != 0u));
        let d = normalize(hiz.ray_origin.xyz + hiz.ray_dx.xyz * p.x + hiz.ray_dy.xyz * p.y);
        let c = dot(d, g);
        let q = cross(d, g);
        let discriminant = r * r - dot(q, q);
        if !(c > 0.0 && discriminant >= 0.0) {
            return HIZ_NONE;
        }
        bound = max(bound, (g2 - r * r) / (c + sqrt(discriminant)));
    }
    return bound * (1.0 + HIZ_DEPTH_MARGIN);
}

// The bound of the occluder-map texel (x, y).
fn hiz_map_bound(x: u32, y: u32) -> f32 {
    let word = occluder_words[(y * hiz.size.x + x) * params.counts.y];
    if word == 0u || ~word >= params.counts.x {
        return HIZ_NONE;
    }
    return hiz_ball_bound(x, y, grains[~word]);
}

@compute @workgroup_size(256)
fn hiz_cover(
    @builtin(workgroup_id) workgroup: vec3<u32>,
    @builtin(num_workgroups) workgroups: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let index = split_grain(workgroup, workgroups, local);
    if index >= params.counts.x || ((state[index] >> STATE_MODEL_SHIFT) & 0xffu) >= LIST_COUNT {
        return;
    }
    let grain = grains[index];
    let square = split_splat_with(grain, HIZ_COVER_FACTOR);
    if !square.valid {
        return;
    }
    for (var y = square.min.y; y <= square.max.y; y++) {
        for (var x = square.min.x; x <= square.max.x; x++) {
            let bound = hiz_ball_bound(x, y, grain);
            if bound < HIZ_NONE {
                atomicMax(&cover[y * hiz.size.x + x], ~bitcast<u32>(bound));
            }
        }
    }
}

@compute @workgroup_size(8, 8)
fn hiz_bound(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x < hiz.size.x && id.y < hiz.size.y {
        let pixel = id.y * hiz.size.x + id.x;
        var bound = hiz_map_bound(id.x, id.y);
        if (params.counts.z & FLAG_TEMPORAL) != 0u {
            let word = atomicLoad(&cover[pixel]);
            if word != 0u {
                bound = min(bound, bitcast<f32>(~word));
            }
        }
        pyramid[pixel] = bound;
    }
}

@compute @workgroup_size(8, 8)
fn hiz_reduce(@builtin(global_invocation_id) id: vec3<u32>) {
    let k = hiz_level.x;
    let level = hiz.levels[k];
    let finer = hiz.levels[k - 1u];
    if id.x >= level.x || id.y >= level.y {
        return;
    }
    var bound = 0.0;
    for (var child = 0u; child < 4u; child++) {
        let x = 2u * id.x + (child & 1u);
        let y = 2u * id.y + (child >> 1u);
        if x < finer.x && y < finer.y {
            bound = max(bound, pyramid[finer.z + y * finer.x + x]);
        }
    }
    pyramid[level.z + id.y * level.x + id.x] = bound;
}
