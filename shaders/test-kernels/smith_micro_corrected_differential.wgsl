// Differential-test kernel for the corrected eq. 17 of shaders/smith-micro/smith_micro.wgsl
// (gpu-harness convention: input at binding 1, output at 2, workgroups of 64 in a 2-D
// grid; the uniform at binding 0 is unused). Each case's correction is the
// GpuLambdaCorrection of a validated smith_micro::LambdaCorrection (LambdaCorrection::to_gpu).
// Rust: reference_correction_results in tests/smith_micro_gpu.rs computes the same 4 results.

@group(0) @binding(1) var<storage, read> correction_cases: array<CorrectionCase>;
@group(0) @binding(2) var<storage, read_write> correction_results: array<CorrectionResults>;

@compute @workgroup_size(64)
fn smith_corrected_values(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = id.x + id.y * groups.x * 64u;
    if index >= arrayLength(&correction_cases) {
        return;
    }
    let case_ = correction_cases[index];
    let correction = GpuLambdaCorrection(case_.knots_low, case_.knots_high);
    let correlated_attribute = case_.inputs.xy;
    let lambda_view = smith_value_of(case_.inputs.z);
    let lambda_light = smith_value_of(case_.inputs.w);
    let corrected_view = smith_corrected_lambda(lambda_view, correction);
    let corrected_light = smith_corrected_lambda(lambda_light, correction);
    var per_direction = smith_none();
    if corrected_view.kind != SMITH_NONE && corrected_light.kind != SMITH_NONE {
        per_direction = smith_visible_mean_attribute(correlated_attribute, corrected_view, corrected_light);
    }
    var out: CorrectionResults;
    out.values = vec4<u32>(
        smith_encode(corrected_view),
        smith_encode(corrected_light),
        smith_encode(smith_corrected_visible_mean_attribute(correlated_attribute, lambda_view, lambda_light, correction)),
        smith_encode(per_direction),
    );
    correction_results[index] = out;
}
