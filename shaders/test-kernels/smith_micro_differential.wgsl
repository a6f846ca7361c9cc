// Differential-test kernel for shaders/smith-micro/smith_micro.wgsl (gpu-harness
// convention: input at binding 1, output at 2, workgroups of 64 in a 2-D grid; the uniform
// at binding 0 is unused). Rust: reference_results in tests/smith_micro_gpu.rs computes the
// same 16 results.

@group(0) @binding(1) var<storage, read> cases: array<SmithCase>;
@group(0) @binding(2) var<storage, read_write> results: array<SmithResults>;

fn smith_kernel_index(id: vec3<u32>, groups: vec3<u32>) -> u32 {
    return id.x + id.y * groups.x * 64u;
}

@compute @workgroup_size(64)
fn smith_values(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = smith_kernel_index(id, groups);
    if index >= arrayLength(&cases) {
        return;
    }
    let case_ = cases[index];
    let view = case_.view.xyz;
    let light = case_.light.xyz;
    let x = case_.light.w;
    let slopes = smith_slope_deviation(case_.slopes.x, case_.slopes.y);
    let brdf_slopes = smith_slope_deviation(case_.slopes.z, case_.slopes.w);
    let correlated_attribute = case_.material.xy;
    let radiance = case_.material.z;
    let lambda = smith_value_of(case_.material.w);
    let height = case_.scalars.z;
    let deviation = case_.scalars.w;

    var out: SmithResults;
    out.values[0] = vec4<u32>(
        smith_encode(smith_erf(x)),
        smith_encode(smith_erfc(x)),
        smith_encode(smith_erfcx(x)),
        smith_encode(smith_lambda_from_nu(case_.view.w)),
    );
    out.values[1] = vec4<u32>(
        smith_encode(smith_lambda_isotropic(case_.scalars.x, case_.scalars.y)),
        smith_encode(smith_lambda_direction(view, slopes)),
        smith_encode(smith_lambda_direction(light, slopes)),
        smith_encode(smith_mean_visibility(lambda)),
    );
    out.values[2] = vec4<u32>(
        smith_encode(smith_height_cdf(height, deviation)),
        smith_encode(smith_log_height_cdf(height, deviation)),
        smith_encode(smith_height_visibility(lambda, height, deviation)),
        smith_encode(smith_attribute_at_height(correlated_attribute, height, deviation)),
    );
    out.values[3] = vec4<u32>(
        smith_encode(smith_visible_mean_attribute_for_directions(correlated_attribute, view, light, slopes)),
        smith_encode(smith_gaussian_slope_ndf(view, smith_convolved_slope_deviation(slopes, brdf_slopes))),
        smith_encode(smith_shade(view, light, slopes, brdf_slopes, correlated_attribute, radiance)),
        smith_encode(smith_nu_of_direction(view, slopes)),
    );
    results[index] = out;
}
