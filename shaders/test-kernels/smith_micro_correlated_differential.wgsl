// Differential-test kernel for the corrected, correlated visibility model of
// shaders/smith-micro/smith_micro.wgsl (gpu-harness convention: input at binding 1, output
// at 2, workgroups of 64 in a 2-D grid; the uniform at binding 0 is unused). Each case's
// model is the GpuVisibilityCorrection of a validated smith_micro::VisibilityCorrection
// (VisibilityCorrection::to_gpu). Rust: reference_correlated_results in
// tests/smith_micro_gpu.rs computes the same 4 results.

@group(0) @binding(1) var<storage, read> correlated_cases: array<CorrelatedCase>;
@group(0) @binding(2) var<storage, read_write> correlated_results: array<CorrelatedResults>;

@compute @workgroup_size(64)
fn smith_correlated_values(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = id.x + id.y * groups.x * 64u;
    if index >= arrayLength(&correlated_cases) {
        return;
    }
    let case_ = correlated_cases[index];
    let model = GpuVisibilityCorrection(case_.view_low, case_.view_high, case_.light_low, case_.light_high, case_.correlation);
    let correlated_attribute = case_.inputs.xy;
    let lambda_view = smith_value_of(case_.inputs.z);
    let lambda_light = smith_value_of(case_.inputs.w);
    let cos_difference = smith_value_of(case_.view.w);
    let slopes = smith_slope_deviation(case_.light.w, case_.light.w);
    var out: CorrelatedResults;
    out.values = vec4<u32>(
        smith_encode(smith_correlated_lambda(lambda_view, lambda_light, cos_difference, model)),
        smith_encode(smith_correlated_visible_mean_attribute(correlated_attribute, lambda_view, lambda_light, cos_difference, model)),
        smith_encode(smith_cos_azimuth_difference(case_.view.xyz, case_.light.xyz)),
        smith_encode(smith_correlated_visible_mean_attribute_for_directions(correlated_attribute, case_.view.xyz, case_.light.xyz, slopes, model)),
    );
    correlated_results[index] = out;
}
