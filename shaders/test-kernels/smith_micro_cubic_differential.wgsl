// Differential-test kernel for the cubic correction of shaders/smith-micro/smith_micro.wgsl
// (gpu-harness convention: input at binding 1, output at 2, workgroups of 64 in a 2-D
// grid; the uniform at binding 0 is unused). Each case's correction is the
// GpuCubicLambdaCorrection of a validated smith_micro::CubicLambdaCorrection
// (CubicLambdaCorrection::to_gpu). Rust: reference_cubic_results in tests/smith_micro_gpu.rs
// computes the same 4 results.

@group(0) @binding(1) var<storage, read> cubic_cases: array<CubicCase>;
@group(0) @binding(2) var<storage, read_write> cubic_results: array<CubicResults>;

@compute @workgroup_size(64)
fn smith_cubic_corrected_values(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = id.x + id.y * groups.x * 64u;
    if index >= arrayLength(&cubic_cases) {
        return;
    }
    let case_ = cubic_cases[index];
    let correction = GpuCubicLambdaCorrection(case_.coefficients);
    let correlated_attribute = case_.inputs.xy;
    let lambda_view = smith_value_of(case_.inputs.z);
    let lambda_light = smith_value_of(case_.inputs.w);
    var factor = smith_none();
    if lambda_view.kind == SMITH_FINITE && lambda_view.value >= 0.0 && lambda_view.value <= SMITH_MAX_CORRECTED_LAMBDA {
        factor = smith_finite(smith_cubic_correction_factor(correction, lambda_view.value / (1.0 + lambda_view.value)));
    }
    var out: CubicResults;
    out.values = vec4<u32>(
        smith_encode(factor),
        smith_encode(smith_cubic_corrected_visible_mean_attribute(correlated_attribute, lambda_view, lambda_light, correction)),
        smith_encode(smith_cubic_corrected_visible_mean_attribute(correlated_attribute, lambda_light, lambda_view, correction)),
        smith_encode(smith_cubic_corrected_visible_mean_attribute(correlated_attribute, lambda_view, smith_finite(0.0), correction)),
    );
    cubic_results[index] = out;
}
