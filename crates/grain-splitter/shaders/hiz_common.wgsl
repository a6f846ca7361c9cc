// Shared by the pyramid passes (hiz.wgsl) and the grain test (hiz_test.wgsl). Rust: hiz.

// The slack of a ball centred at `view` (view space) and `world` (module docs of hiz.rs).
fn hiz_slack(view: vec3<f32>, world: vec3<f32>) -> f32 {
    return HIZ_SLACK * (length(view) + length(world));
}
