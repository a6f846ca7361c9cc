// The raster path of the impostor tier (crates/grain-renderer/src/impostor_raster.rs): each
// grain of an impostor list drawn as a sprite — its screen rectangle (cloud_grain_rectangle,
// the compute splat's pixels) as two triangles, one instance per list element through
// draw_indirect — whose fragments evaluate the same cloud_hit as the compute splat, discard
// what it does not cover, and write the grain's index and its view depth, scaled into [0, 1]
// by a power of two, under the hardware depth test (Less: the first drawn wins ties). A compute
// pass then offers each pixel's winner to the visibility buffer (composited over the mesh
// tier's depth there), and the compute path's point splats and resolve follow unchanged.
// Composed after impostor_tier.wgsl and point_tier.wgsl.

// The raster pass's results (tier_raster_merge only).
@group(1) @binding(0) var raster_owner: texture_2d<u32>;
@group(1) @binding(1) var raster_depth: texture_depth_2d;

struct TierRasterVertex {
    @builtin(position) position: vec4<f32>,
    @location(0) @interpolate(flat) grain: u32,
}

struct TierRasterFragment {
    @location(0) owner: u32,
    @builtin(frag_depth) depth: f32,
}

// Corner k of the two triangles (0, 0), (1, 0), (0, 1), (0, 1), (1, 0), (1, 1).
fn tier_raster_corner(k: u32) -> vec2<f32> {
    let corners = array<vec2<f32>, 6>(
        vec2<f32>(0.0, 0.0), vec2<f32>(1.0, 0.0), vec2<f32>(0.0, 1.0),
        vec2<f32>(0.0, 1.0), vec2<f32>(1.0, 0.0), vec2<f32>(1.0, 1.0),
    );
    return corners[min(k, 5u)];
}

@vertex
fn tier_raster_vertex(@builtin(vertex_index) vertex: u32, @builtin(instance_index) element: u32) -> TierRasterVertex {
    var out: TierRasterVertex;
    out.grain = tier_element_grain(element);
    // Past the list's end or off screen: every corner at one point (no fragment).
    out.position = vec4<f32>(-2.0, -2.0, 0.0, 1.0);
    if out.grain == TIER_NONE {
        return out;
    }
    // The rectangle's pixel edges: the centres inside it are exactly the splat's pixels.
    let rect = vec4<f32>(cloud_grain_rectangle(instances[out.grain]));
    let pixel = mix(rect.xy, rect.zw, tier_raster_corner(vertex));
    let size = camera.viewport.xy;
    out.position = vec4<f32>(2.0 * pixel.x / size.x - 1.0, 1.0 - 2.0 * pixel.y / size.y, 0.0, 1.0);
    return out;
}

@fragment
fn tier_raster_fragment(in: TierRasterVertex) -> TierRasterFragment {
    // Counted as the compute path counts its evaluated pixels: one atlas evaluation each.
    atomicAdd(&stats[tier_pass.slot], 1u);
    // The target is the sample grid: s × s fragments per pixel.
    let hit = cloud_hit(in.position.xy / f32(tier_samples()), instances[in.grain]);
    if !hit.covered {
        discard;
    }
    var out: TierRasterFragment;
    out.owner = in.grain;
    out.depth = hit.depth * tier.raster.x;
    return out;
}

@compute @workgroup_size(8, 8)
fn tier_raster_merge(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = tier_size();
    if id.x >= size.x || id.y >= size.y {
        return;
    }
    let s = tier_samples();
    for (var k = 0u; k < s * s; k++) {
        let q = vec2<i32>(id.xy * s + vec2<u32>(k % s, k / s));
        let owner = textureLoad(raster_owner, q, 0).r;
        if owner != TIER_NONE {
            let depth = textureLoad(raster_depth, q, 0) * tier.raster.y;
            tier_offer(tier_sample_index(id.xy, k), depth, owner);
        }
    }
}
