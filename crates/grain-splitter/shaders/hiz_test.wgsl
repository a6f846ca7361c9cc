// The splitter's Hi-Z test (Rust: hiz, and fusion::DepthPyramid::hides, its f64 reference).
// Composed into the split shader after split.wgsl and hiz_common.wgsl.

// Every level of the pyramid (hiz.wgsl).
@group(0) @binding(9) var<storage, read> pyramid: array<f32>;
@group(0) @binding(10) var<uniform> hiz: HizParams;

// The ndc range over the ball B(g, radius) of `row · v / (−v_z)` (fusion::Rays::bounds).
fn hiz_range(row: vec3<f32>, g: vec3<f32>, radius: f32) -> vec2<f32> {
    let depth = -g.z;
    let a = dot(row, g);
    let r2 = radius * radius;
    let q2 = depth * depth - r2;
    let q1 = a * depth + r2 * row.z;
    let u = depth * row + vec3<f32>(0.0, 0.0, a);
    let root = radius * sqrt(max(dot(u, u) - r2 * (row.x * row.x + row.y * row.y), 0.0));
    return vec2<f32>((q1 - root) / q2, (q1 + root) / q2);
}

// Whether the outer ball (view centre `g`, world centre `world`, radius `radius`) is hidden
// by the fused occluders: its grown rectangle's texels at the level where it spans ≤ 2 × 2.
fn hiz_hides(g: vec3<f32>, world: vec3<f32>, radius: f32) -> bool {
    let grown = radius + hiz_slack(g, world);
    let distance = length(g);
    if !(-g.z - grown > 0.0) || !(distance > grown) {
        return false;
    }
    let near = (distance - grown) * (1.0 - HIZ_DEPTH_MARGIN);
    let size = vec2<f32>(hiz.size.xy);
    let sx = hiz_range(hiz.row_x.xyz, g, grown);
    let sy = hiz_range(hiz.row_y.xyz, g, grown);
    let m = HIZ_RECT_MARGIN_PX;
    let lo = floor(vec2<f32>((sx.x + 1.0) * 0.5 * size.x, (1.0 - sy.y) * 0.5 * size.y) - m);
    let hi = floor(vec2<f32>((sx.y + 1.0) * 0.5 * size.x, (1.0 - sy.x) * 0.5 * size.y) + m);
    let first = max(lo, vec2<f32>(0.0));
    let last = min(hi, size - 1.0);
    // Also false for NaN bounds.
    if !(first.x <= last.x && first.y <= last.y) {
        return false;
    }
    let p0 = vec2<u32>(first);
    let p1 = vec2<u32>(last);
    var k = 0u;
    while k + 1u < hiz.size.z && ((p1.x >> k) - (p0.x >> k) > 1u || (p1.y >> k) - (p0.y >> k) > 1u) {
        k++;
    }
    let level = hiz.levels[k];
    var bound = 0.0;
    for (var y = p0.y >> k; y <= p1.y >> k; y++) {
        for (var x = p0.x >> k; x <= p1.x >> k; x++) {
            bound = max(bound, pyramid[level.z + y * level.x + x]);
        }
    }
    return near > bound;
}
