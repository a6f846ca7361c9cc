//! CPU = GPU differential test of `shaders/smith_micro.wgsl` against the `smith-micro`
//! crate: 16 functions on every case, special inputs included.
//!
//! Whether a result is `None`, ±∞ or finite must agree exactly. Finite results must agree
//! within a relative tolerance of 1e-5 (about 80 ulp: WGSL allows several ulp for `exp`,
//! `log` and division and may contract FMAs, and the formulas chain a dozen operations),
//! widened only by the condition number of the formula where it is larger: Vulkan's
//! `3 + 2|x|` ulp bound on `exp(x)` for arguments like `−ν²` (Λ at ν = 9 carries ~150 ulp
//! from `exp` alone), `Λ·|ln g|` for `g^Λ`, and the cancellation of `ā + a_s x` near 0
//! for the attributes. Each tolerance is computed per case in `tolerances`.
//!
//! The corrected eq. 17 (`LambdaCorrection`) has its own kernel and test,
//! `corrected_functions_match_the_cpu_reference`, with its tolerance in
//! `correction_tolerances`. The correlated model (`VisibilityCorrection`: view and light
//! tables and the light–view correlation `ρ(cos Δφ)`) has
//! `correlated_functions_match_the_cpu_reference`, with `correlated_tolerances`, and the
//! cubic (`CubicLambdaCorrection`) `cubic_correction_matches_the_cpu_reference`.
//!
//! The corrections are validated types: each case of those kernels is built from a
//! correction its constructor accepted, the GPU gets its `to_gpu` form (which the WGSL
//! twins do not re-check) and the CPU reference evaluates the correction itself
//! ([`Validated`]). A special value that the constructor rejects gives no case (the
//! constructors' own tests check that they reject it); slopes and attributes stay raw
//! inputs of every kernel, checked on the GPU, and the reference gives `None` where their
//! constructors reject them.

use glam::{Vec3, Vec4};
use integration_tests::{gpu, random_unit_directions, special_directions};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use shader_registry::kernel_io::smith_micro::{
    CorrectionCase, CorrectionResults, CorrelatedCase, CorrelatedResults, CubicCase, CubicResults, SmithCase,
    SmithResults,
};

use smith_micro::{
    CubicLambdaCorrection, GpuCubicLambdaCorrection, GpuVisibilityCorrection, LambdaCorrection, NONE_BITS,
    SlopeDeviation, VisibilityCorrection, corrected_lambda, correlated_lambda, nu_of_direction,
};

mod smith_micro_reference;

use smith_micro_reference::{
    Validated, correction_case, reference_correction_results, reference_correlated_results, reference_cubic_results,
    reference_results,
};

const NAMES: [&str; 16] = [
    "erf",
    "erfc",
    "erfcx",
    "lambda(nu)",
    "lambda(mu,sigma)",
    "lambda(view)",
    "lambda(light)",
    "1/(1+lambda)",
    "g(h)",
    "ln g(h)",
    "g(h)^lambda",
    "a(h)",
    "abar(v,l)",
    "D(view)",
    "shade (eq. 13)",
    "nu(view)",
];

/// Scalars that stress every function: signed zeros, NaN, ±∞, subnormals, the limits of
/// the accepted ranges and the thresholds of the approximations.
const SPECIAL_SCALARS: [f32; 26] = [
    0.0,
    -0.0,
    1.0,
    -1.0,
    0.5,
    -0.5,
    2.0,
    9.0,
    10.0,
    1e-3,
    f32::NAN,
    f32::INFINITY,
    f32::NEG_INFINITY,
    f32::MIN_POSITIVE,
    1e-40,
    f32::MAX,
    -f32::MAX,
    1e-30,
    3e30,
    4_294_967_296.0,
    2.3283064e-10,
    5e9,
    18_446_744_073_709_551_616.0,
    1e20,
    1.9999999,
    0.0625,
];

fn log_uniform(rng: &mut SmallRng, low: f32, high: f32) -> f32 {
    (rng.random_range(low.ln()..high.ln())).exp()
}

fn random_case(rng: &mut SmallRng, view: Vec3, light: Vec3) -> SmithCase {
    let sigma_h = log_uniform(rng, 1e-3, 10.0);
    SmithCase {
        view: view.extend(if rng.random_bool(0.5) {
            rng.random_range(0.0..10.0)
        } else {
            log_uniform(rng, 1e-6, 10.0)
        }),
        light: light.extend(rng.random_range(-11.0..11.0)),
        slopes: Vec4::new(
            if rng.random_bool(0.05) { 0.0 } else { log_uniform(rng, 1e-3, 4.0) },
            log_uniform(rng, 1e-3, 4.0),
            log_uniform(rng, 1e-3, 1.0),
            if rng.random_bool(0.05) { 0.0 } else { log_uniform(rng, 1e-3, 1.0) },
        ),
        scalars: Vec4::new(
            log_uniform(rng, 1e-4, 1e3),
            log_uniform(rng, 1e-3, 4.0),
            rng.random_range(-8.0..8.0) * sigma_h,
            sigma_h,
        ),
        material: Vec4::new(
            rng.random_range(-2.0..2.0),
            rng.random_range(-2.0..2.0),
            log_uniform(rng, 1e-3, 1e3),
            if rng.random_bool(0.1) { 0.0 } else { log_uniform(rng, 1e-6, 1e6) },
        ),
    }
}

fn test_cases() -> Vec<SmithCase> {
    let mut rng = SmallRng::seed_from_u64(5);
    let mut cases = Vec::new();
    // Every field set to each special scalar in turn, the others random.
    for &special in &SPECIAL_SCALARS {
        for field in 0..20 {
            for _ in 0..8 {
                let view =
                    Vec3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-0.2..1.0));
                let mut case = random_case(&mut rng, view, Vec3::new(0.3, -0.2, 0.9));
                let mut floats: [f32; 20] = bytemuck::cast(case);
                floats[field] = special;
                case = bytemuck::cast(floats);
                cases.push(case);
            }
        }
        let all: [f32; 20] = [special; 20];
        cases.push(bytemuck::cast(all));
    }
    // Special directions for both view and light: axes, the horizon, NaN, ∞, zero,
    // subnormal and huge components.
    let directions = special_directions();
    for (i, &d) in directions.iter().enumerate() {
        let other = directions[(i * 7919 + 13) % directions.len()];
        cases.push(random_case(&mut rng, d, Vec3::new(0.1, 0.2, 1.0)));
        cases.push(random_case(&mut rng, Vec3::new(-0.4, 0.1, 0.8), d));
        cases.push(random_case(&mut rng, d, other));
    }
    // Normal incidence, grazing and σx ≠ σy extremes.
    for &(sx, sy) in &[(0.0, 0.5), (0.5, 0.0), (1e-3, 4.0), (4.0, 1e-3), (2.3283064e-10, 4_294_967_296.0)] {
        for d in [
            Vec3::Z,
            Vec3::X,
            Vec3::Y,
            Vec3::new(1.0, 1.0, 1e-6),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(0.0, 1.0, 1e-30),
        ] {
            let mut case = random_case(&mut rng, d, d);
            case.slopes.x = sx;
            case.slopes.y = sy;
            cases.push(case);
        }
    }
    // Random cases over the upper hemisphere (and a little below).
    let views = random_unit_directions(110_000, 11);
    let lights = random_unit_directions(110_000, 12);
    for (v, l) in views.into_iter().zip(lights) {
        let flip = |d: Vec3| if d.z < -0.2 { Vec3::new(d.x, d.y, -d.z) } else { d };
        cases.push(random_case(&mut rng, flip(v), flip(l)));
    }
    cases
}

/// The relative difference of two finite results, with the f32 flush threshold as the
/// floor of the scale (values near it may be flushed on one side only).
fn relative_difference(cpu: f32, gpu: f32) -> f64 {
    f64::from((cpu - gpu).abs()) / f64::from(cpu.abs().max(gpu.abs()).max(f32::MIN_POSITIVE * 16.0))
}

/// The base relative tolerance of a transcendental result: 1e-5, about 80 ulp. WGSL
/// (Vulkan) allows `exp` and `log` errors of several ulp, division 2.5 ulp, and lets the
/// compiler contract `a*b+c` into an FMA; the Horner and continued-fraction evaluations
/// chain a dozen such operations.
const BASE: f64 = 1e-5;

/// The relative tolerance of `exp(−a)` and of anything computed through it: Vulkan
/// bounds the error of `exp(x)` by `3 + 2|x|` ulp; we allow twice that, or [`BASE`].
fn exp_tolerance(argument: f64) -> f64 {
    BASE.max(2.0 * (3.0 + 2.0 * argument.abs()) * f64::from(f32::EPSILON) / 2.0)
}

/// Per-function relative tolerances of one case, from the condition of each formula
/// (the exp argument, or the cancellation in `ā + a_s x`). `cpu` are the reference's
/// decoded results.
fn tolerances(case: &SmithCase, cpu: &[f32; 16]) -> [f64; 16] {
    let x = f64::from(case.light.w);
    let slopes = SlopeDeviation::new(case.slopes.x, case.slopes.y).ok();
    let nu_squared = |nu: Option<f32>| nu.filter(|n| n.is_finite()).map_or(0.0, |n| f64::from(n) * f64::from(n));
    let nu_light = slopes.and_then(|s| nu_of_direction(case.light.truncate(), s));
    let [mu, sigma, height, deviation] = case.scalars.to_array().map(f64::from);
    let [mean, correlation, _, lambda] = case.material.to_array().map(f64::from);
    let nu_isotropic = mu / (std::f64::consts::SQRT_2 * sigma);
    let t = height / (std::f64::consts::SQRT_2 * deviation);
    let t_squared = if t.is_finite() { t * t } else { 0.0 };
    let lambda_view = exp_tolerance(nu_squared(Some(cpu[15])));
    let lambda_light = exp_tolerance(nu_squared(nu_light));
    let log_g = exp_tolerance(t_squared);
    let exponent = if lambda.is_finite() && cpu[9].is_finite() { lambda * f64::from(cpu[9]).abs() } else { 0.0 };
    let visibility = (1.0 + exponent) * log_g + exp_tolerance(exponent);
    // ā + a_s·x: an absolute error of a_s·Δx plus rounding, relative to the result.
    let relative_to = |absolute: f64, value: f32| absolute / f64::from(value.abs()).max(1e-30);
    let sum_rounding = 1e-6 * (mean.abs() + correlation.abs());
    let attribute_at_height = relative_to(2.0 * correlation.abs() * log_g + sum_rounding, cpu[11]);
    let visible_attribute = relative_to(correlation.abs() * lambda_view.max(lambda_light) + sum_rounding, cpu[12]);
    let lobe = exp_tolerance(104.0);
    [
        exp_tolerance(x * x),
        exp_tolerance(x * x),
        BASE,
        exp_tolerance(nu_squared(Some(case.view.w))),
        exp_tolerance(if nu_isotropic.is_finite() { nu_isotropic * nu_isotropic } else { 0.0 }),
        lambda_view,
        lambda_light,
        BASE,
        log_g,
        log_g,
        visibility,
        BASE.max(attribute_at_height),
        BASE.max(visible_attribute),
        lobe,
        lobe + lambda_view + lambda_light + BASE.max(visible_attribute),
        BASE,
    ]
}

#[test]
fn every_function_matches_the_cpu_reference() {
    let source = shader_registry::test_kernel_source("smith_micro_differential").unwrap_or_else(|e| panic!("{e}"));
    let cases = test_cases();
    assert!(cases.len() >= 100_000);
    let gpu_results: Vec<SmithResults> = gpu().compute_map(&source, "smith_values", &[0_u8; 16], &cases).unwrap();
    let mut worst = [(0.0_f64, 0.0_f64, 0_usize); 16];
    let mut kind_mismatches = Vec::new();
    let mut out_of_tolerance = Vec::new();
    for (index, (case, gpu_result)) in cases.iter().zip(&gpu_results).enumerate() {
        let cpu_bits: [u32; 16] = bytemuck::cast(reference_results(case).values);
        let gpu_bits: [u32; 16] = bytemuck::cast(gpu_result.values);
        let tolerance = tolerances(case, &cpu_bits.map(f32::from_bits));
        for (function, (&c, &g)) in cpu_bits.iter().zip(&gpu_bits).enumerate() {
            let (cpu, gpu) = (f32::from_bits(c), f32::from_bits(g));
            let special = |bits: u32, value: f32| bits == NONE_BITS || !value.is_finite();
            if special(c, cpu) || special(g, gpu) {
                if c != g {
                    kind_mismatches.push((NAMES[function], index, cpu, gpu));
                }
                continue;
            }
            let difference = relative_difference(cpu, gpu);
            let ratio = difference / tolerance[function];
            if ratio > 1.0 {
                out_of_tolerance.push((NAMES[function], index, cpu, gpu, difference, tolerance[function]));
            }
            let entry = &mut worst[function];
            entry.0 = entry.0.max(difference);
            if ratio > entry.1 {
                entry.1 = ratio;
                entry.2 = index;
            }
        }
    }
    println!("{} cases", cases.len());
    for (name, (difference, ratio, index)) in NAMES.iter().zip(worst) {
        println!(
            "{name:>16}: max relative difference {difference:.3e}, max difference / tolerance {ratio:.3} (case {index})"
        );
    }
    assert!(
        kind_mismatches.is_empty(),
        "{} results differ in kind (None / ±∞ / finite), e.g. {:?}",
        kind_mismatches.len(),
        &kind_mismatches[..kind_mismatches.len().min(10)]
    );
    assert!(
        out_of_tolerance.is_empty(),
        "{} results differ beyond their tolerance, e.g. {:?}",
        out_of_tolerance.len(),
        &out_of_tolerance[..out_of_tolerance.len().min(10)]
    );
}

/// The results of `entry` of the `smith_micro` test kernel `kernel` over `cases`, as the
/// encoded bits of each case's four results.
fn run_kernel<C: bytemuck::Pod, R: bytemuck::Pod>(
    kernel: &str,
    entry: &str,
    cases: &[C],
    bits: impl Fn(&R) -> [u32; 4],
) -> Vec<[u32; 4]> {
    let source = shader_registry::test_kernel_source(kernel).unwrap_or_else(|e| panic!("{e}"));
    let results: Vec<R> = gpu().compute_map(&source, entry, &[0_u8; 16], cases).unwrap();
    results.iter().map(bits).collect()
}

/// The relative tolerance of `ā + a_s x`, `x` carrying the relative error `lambda` (as
/// `Λ'/(Λ' + 2)` inherits its Λ's), with the rounding of the sum: the cancellation of
/// `ā + a_s x` turns the absolute errors into a relative one of the result `value`.
fn attribute_tolerance(mean: f32, correlation: f32, lambda: f64, value: f32) -> f64 {
    let sum_rounding = 1e-6 * (f64::from(mean).abs() + f64::from(correlation).abs());
    BASE.max((f64::from(correlation).abs() * lambda + sum_rounding) / f64::from(value.abs()).max(1e-30))
}

/// Compares four encoded results per case, CPU (`reference`) against GPU: `None` and
/// non-finite results must have the same bits, finite ones differ by at most their
/// tolerance (relative, or absolute where `absolute` says so). Prints the worst
/// difference and difference / tolerance per result and fails with examples.
fn check_four_results<C>(
    label: &str,
    names: [&str; 4],
    cases: &[C],
    gpu_bits: &[[u32; 4]],
    reference: impl Fn(&C) -> [u32; 4],
    tolerances: impl Fn(&C, &[f32; 4]) -> [f64; 4],
    absolute: [bool; 4],
) {
    assert!(cases.len() >= 100_000 && gpu_bits.len() == cases.len());
    let mut worst = [(0.0_f64, 0.0_f64); 4];
    let mut failures = Vec::new();
    for (index, (case, gpu_bits)) in cases.iter().zip(gpu_bits).enumerate() {
        let cpu_bits = reference(case);
        let tolerance = tolerances(case, &cpu_bits.map(f32::from_bits));
        for (function, (&c, &g)) in cpu_bits.iter().zip(gpu_bits).enumerate() {
            let (cpu, gpu) = (f32::from_bits(c), f32::from_bits(g));
            let special = |bits: u32, value: f32| bits == NONE_BITS || !value.is_finite();
            if special(c, cpu) || special(g, gpu) {
                if c != g {
                    failures.push((names[function], index, cpu, gpu, f64::INFINITY));
                }
                continue;
            }
            let difference =
                if absolute[function] { f64::from((cpu - gpu).abs()) } else { relative_difference(cpu, gpu) };
            let ratio = difference / tolerance[function];
            if ratio > 1.0 {
                failures.push((names[function], index, cpu, gpu, difference));
            }
            worst[function] = (worst[function].0.max(difference), worst[function].1.max(ratio));
        }
    }
    println!("{} {label} cases", cases.len());
    for (name, (difference, ratio)) in names.iter().zip(worst) {
        println!("{name:>30}: max difference {difference:.3e}, max difference / tolerance {ratio:.3}");
    }
    assert!(
        failures.is_empty(),
        "{} results differ in kind or beyond their tolerance, e.g. {:?}",
        failures.len(),
        &failures[..failures.len().min(10)]
    );
}

/// Random `(ā, a_s, Λ(v), Λ(l))` for the correction kernels: attributes in `[−2, 2]`, Λs
/// log-uniform in `[1e-6, 1e6]` or (5 %) zero.
fn random_inputs(rng: &mut SmallRng) -> Vec4 {
    let (mean, correlation) = (rng.random_range(-2.0..2.0), rng.random_range(-2.0..2.0));
    let view = random_lambda(rng);
    Vec4::new(mean, correlation, view, random_lambda(rng))
}

/// A Λ log-uniform in `[1e-6, 1e6]`, or (5 %) zero.
fn random_lambda(rng: &mut SmallRng) -> f32 {
    if rng.random_bool(0.05) { 0.0 } else { log_uniform(rng, 1e-6, 1e6) }
}

/// Knot values that stress the correction: the accepted range's ends and just outside,
/// NaN, ±∞, zero, negative and subnormal. Only those [`LambdaCorrection::from_knots`]
/// accepts give cases (the ends, 1 and 2); the others are the constructor's tests'.
const SPECIAL_KNOTS: [f32; 12] =
    [0.25, 4.0, 1.0, 0.2499999, 4.0000005, f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 0.0, -1.0, 1e-40, 2.0];

/// A random valid table: knots log-uniform in the accepted range (drawn again in the rare
/// case that rounding puts one outside), or (5 %) the identity.
fn random_table(rng: &mut SmallRng) -> LambdaCorrection {
    if rng.random_bool(0.05) {
        return LambdaCorrection::IDENTITY;
    }
    loop {
        let knots: [f32; 8] = std::array::from_fn(|_| log_uniform(rng, 0.25, 4.0));
        if let Ok(table) = LambdaCorrection::from_knots(knots) {
            return table;
        }
    }
}

/// Cases of `smith_corrected_values`: random valid tables and inputs; every input set to
/// each special scalar in turn, and every knot to each special knot (and scalar) that
/// [`LambdaCorrection::from_knots`] accepts. Returns the cases and the number of special
/// knot values the constructor rejected (no case: a GPU correction cannot hold them).
fn correction_cases() -> (Vec<Validated<LambdaCorrection, CorrectionCase>>, usize) {
    let mut rng = SmallRng::seed_from_u64(17);
    let mut cases = Vec::new();
    let mut rejected = 0;
    for &special in SPECIAL_SCALARS.iter().chain(&SPECIAL_KNOTS) {
        for field in 0..12 {
            for _ in 0..8 {
                let base = correction_case(random_table(&mut rng), random_inputs(&mut rng));
                let mut floats: [f32; 12] = bytemuck::cast(base.case);
                floats[field] = special;
                let mut knots = [0.0; 8];
                knots.copy_from_slice(&floats[..8]);
                match LambdaCorrection::from_knots(knots) {
                    Ok(table) => cases.push(correction_case(table, Vec4::from_slice(&floats[8..]))),
                    Err(_) => rejected += 1,
                }
            }
        }
    }
    while cases.len() < 110_000 {
        cases.push(correction_case(random_table(&mut rng), random_inputs(&mut rng)));
    }
    (cases, rejected)
}

/// Relative tolerances of the 4 corrected results of one case. `c(u)` interpolates the
/// knots at `t = 7u`, with `u = Λ/(1+Λ)` a division (2.5 ulp in Vulkan) and `7u` and the
/// interpolation rounded or FMA-contracted: an error of a few ulp in `t` moves `c` by
/// `|Δk|` times it, and `c` is continuous across knots, so a different segment choice
/// near a knot costs no more. Relative to `c` this is `30 ε |Δk|/c` (ε = 2⁻²³, generous),
/// plus 4 ε for the products; `Λ'/(Λ'+2)` inherits at most `Λ'`'s relative error, and the
/// attribute adds the cancellation of `ā + a_s x` as in `tolerances`.
fn correction_tolerances(validated: &Validated<LambdaCorrection, CorrectionCase>, cpu: &[f32; 4]) -> [f64; 4] {
    let knots = validated.correction.knots().map(f64::from);
    let epsilon = f64::from(f32::EPSILON);
    let lambda_tolerance = |lambda: f32| {
        let lambda = f64::from(lambda);
        if !(lambda.is_finite() && lambda > 0.0) {
            return BASE;
        }
        let t = (lambda / (1.0 + lambda)) * 7.0;
        let index = (t as usize).min(6);
        let (k0, k1) = (knots[index], knots[index + 1]);
        let factor = k0 + (t - index as f64) * (k1 - k0);
        BASE.max(4.0 * epsilon + 30.0 * epsilon * (k1 - k0).abs() / factor.abs().max(1e-30))
    };
    let [mean, correlation, lambda_view, lambda_light] = validated.case.inputs.to_array();
    let view = lambda_tolerance(lambda_view);
    let light = lambda_tolerance(lambda_light);
    let sum = lambda_tolerance(lambda_view + lambda_light);
    let attribute = |lambda: f64, value: f32| attribute_tolerance(mean, correlation, lambda, value);
    [view, light, attribute(sum, cpu[2]), attribute(view.max(light), cpu[3])]
}

#[test]
fn corrected_functions_match_the_cpu_reference() {
    const CORRECTION_NAMES: [&str; 4] =
        ["corrected lambda(view)", "corrected lambda(light)", "abar corrected sum", "abar corrected per direction"];
    let (cases, rejected) = correction_cases();
    println!("{rejected} special knot values rejected by LambdaCorrection::from_knots (no case)");
    let gpu_cases: Vec<CorrectionCase> = cases.iter().map(|v| v.case).collect();
    let gpu_bits = run_kernel(
        "smith_micro_corrected_differential",
        "smith_corrected_values",
        &gpu_cases,
        |r: &CorrectionResults| r.values.to_array(),
    );
    check_four_results(
        "correction",
        CORRECTION_NAMES,
        &cases,
        &gpu_bits,
        |case| reference_correction_results(case).values.to_array(),
        correction_tolerances,
        [false; 4],
    );
}

/// Correlation coefficients that stress `ρ`: the accepted bound and just beyond, NaN, ±∞.
/// Only those [`VisibilityCorrection::new`] accepts give cases.
const SPECIAL_COEFFICIENTS: [f32; 8] = [16.0, -16.0, 16.000002, 0.0, 1.0, f32::NAN, f32::INFINITY, -1e-40];

/// The case of `smith_correlated_values` for `model` (its [`GpuVisibilityCorrection`]) and
/// the other inputs, `(ā, a_s, Λ(v), Λ(l))`, `(view, cos Δφ)` and `(light, σ_n)`.
fn correlated_case(
    model: VisibilityCorrection,
    inputs: Vec4,
    view: Vec4,
    light: Vec4,
) -> Validated<VisibilityCorrection, CorrelatedCase> {
    let [view_low, view_high, light_low, light_high, correlation]: [Vec4; 5] =
        bytemuck::cast::<GpuVisibilityCorrection, _>(model.to_gpu());
    let case = CorrelatedCase { view_low, view_high, light_low, light_high, correlation, inputs, view, light };
    Validated { correction: model, case }
}

/// The model of the correction fields of a [`CorrelatedCase`] (the floats of its first
/// five `vec4`s), if [`VisibilityCorrection::new`] and [`LambdaCorrection::from_knots`]
/// accept it.
fn correlated_model_of(floats: &[f32; 32]) -> Option<VisibilityCorrection> {
    let table = |from: usize| {
        let mut knots = [0.0; 8];
        knots.copy_from_slice(&floats[from..from + 8]);
        LambdaCorrection::from_knots(knots).ok()
    };
    // The fourth correlation component is unused (0 in `to_gpu`).
    if floats[19] != 0.0 {
        return None;
    }
    VisibilityCorrection::new(table(0)?, table(8)?, [floats[16], floats[17], floats[18]]).ok()
}

/// Cases of `smith_correlated_values`: random valid models, inputs and directions; every
/// scalar field set to each special value in turn (where the field belongs to the model,
/// only if its constructors accept it); each special direction against random ones.
/// Returns the cases and the number of special values the model's constructors rejected.
fn correlated_cases() -> (Vec<Validated<VisibilityCorrection, CorrelatedCase>>, usize) {
    let mut rng = SmallRng::seed_from_u64(23);
    let directions = random_unit_directions(4_096, 29);
    let mut specials = special_directions();
    specials.extend([Vec3::new(1e-40, 0.0, 1.0), Vec3::new(3e38, -3e38, 1.0), Vec3::new(f32::NAN, 0.0, 1.0)]);
    let case = |rng: &mut SmallRng, view: Vec3, light: Vec3| {
        let (view_table, light_table) = (random_table(rng), random_table(rng));
        let rho = [rng.random_range(-16.0..16.0), rng.random_range(-4.0..4.0), rng.random_range(-4.0..4.0)];
        let model = VisibilityCorrection::new(view_table, light_table, rho).expect("coefficients in range");
        let inputs =
            Vec4::new(rng.random_range(-2.0..2.0), rng.random_range(-2.0..2.0), random_lambda(rng), random_lambda(rng));
        correlated_case(
            model,
            inputs,
            view.extend(rng.random_range(-1.2..1.2)),
            light.extend(log_uniform(rng, 1e-3, 10.0)),
        )
    };
    let mut cases = Vec::new();
    let mut rejected = 0;
    // Every scalar field set to each special value in turn (directions: each special
    // direction against random ones).
    let pick = |rng: &mut SmallRng| directions[rng.random_range(0..directions.len())];
    for &special in SPECIAL_SCALARS.iter().chain(&SPECIAL_KNOTS).chain(&SPECIAL_COEFFICIENTS) {
        for field in 0..32 {
            for _ in 0..4 {
                let (v, l) = (pick(&mut rng), pick(&mut rng));
                let base = case(&mut rng, v, l).case;
                let mut floats: [f32; 32] = bytemuck::cast(base);
                floats[field] = special;
                let Some(model) = correlated_model_of(&floats) else {
                    rejected += 1;
                    continue;
                };
                let vec = |i: usize| Vec4::from_slice(&floats[4 * i..4 * i + 4]);
                cases.push(correlated_case(model, vec(5), vec(6), vec(7)));
            }
        }
    }
    for &d in &specials {
        for _ in 0..8 {
            let other = pick(&mut rng);
            cases.push(case(&mut rng, d, other));
            cases.push(case(&mut rng, other, d));
        }
    }
    while cases.len() < 110_000 {
        let (v, l) = (pick(&mut rng), pick(&mut rng));
        cases.push(case(&mut rng, v, l));
    }
    (cases, rejected)
}

/// Tolerances of the 4 correlated results of one case: `Λ'` carries each table's
/// interpolation error (as `correction_tolerances`, ≤ 30 ε |Δk|/c relative) and the
/// rounding of `ρ = ρ₀ + c(ρ₁ + c ρ₂)` (≤ 8 ε (|ρ₀|+|ρ₁|+|ρ₂|) absolute, FMA contraction),
/// which moves `Λ'` by at most that times `min(A, B)`, plus 8 ε for the sums; all of these
/// relative to `A + B + 2 min(A, B)`, the largest term of `Λ' = A + B − ρ min(A, B)`
/// (`ρ` up to 2 cancels down to `|A − B|`, so `Λ'` carries them amplified by
/// `(A + B + 2 min)/Λ'`, and the attributes by `2 (A + B + 2 min)/(Λ' + 2)²`, the slope of
/// `x = Λ'/(Λ' + 2)` times `Λ'`); `cos Δφ` is compared absolutely (1e-6: a few
/// ulp of its inputs); the attributes add the cancellation of `ā + a_s x` (as
/// `correction_tolerances`), and the directions' Λs the `exp` bound of `tolerances`.
fn correlated_tolerances(validated: &Validated<VisibilityCorrection, CorrelatedCase>, cpu: &[f32; 4]) -> [f64; 4] {
    let Validated { correction: model, case } = validated;
    let epsilon = f64::from(f32::EPSILON);
    let table_tolerance = |table: LambdaCorrection, lambda: f64| {
        let knots = table.knots().map(f64::from);
        if !(lambda.is_finite() && lambda > 0.0) {
            return 0.0;
        }
        let t = (lambda / (1.0 + lambda)) * 7.0;
        let index = (t as usize).min(6);
        let (k0, k1) = (knots[index], knots[index + 1]);
        let factor = k0 + (t - index as f64) * (k1 - k0);
        30.0 * epsilon * (k1 - k0).abs() / factor.abs().max(1e-30)
    };
    let [mean, correlation, lambda_view, lambda_light] = case.inputs.to_array().map(f64::from);
    let rho_rounding =
        8.0 * epsilon * model.correlation_coefficients().iter().map(|&r| f64::from(r).abs()).sum::<f64>();
    let lambda = |view: f64, light: f64| {
        BASE.max(
            table_tolerance(model.view(), view) + table_tolerance(model.light(), light) + rho_rounding + 8.0 * epsilon,
        )
    };
    // The cancellation in Λ' (see above), from the CPU's corrected Λs; 1 where they are
    // not finite positive.
    let corrected = |lambda: f64, table: LambdaCorrection| {
        corrected_lambda(lambda as f32, &table).map(f64::from).filter(|l| l.is_finite())
    };
    let (terms, lambda_prime) = match (
        corrected(lambda_view, model.view()),
        corrected(lambda_light, model.light()),
        correlated_lambda(lambda_view as f32, lambda_light as f32, 0.0, model),
    ) {
        (Some(a), Some(b), Some(_)) if cpu[0].is_finite() => (a + b + 2.0 * a.min(b), f64::from(cpu[0])),
        _ => (0.0, 0.0),
    };
    let amplification = if terms > 0.0 { (terms / lambda_prime.max(1e-30)).max(1.0) } else { 1.0 };
    let attribute_amplification = if terms > 0.0 { (2.0 * terms / (lambda_prime + 2.0).powi(2)).max(1.0) } else { 1.0 };
    let relative_to = |absolute: f64, value: f32| absolute / f64::from(value.abs()).max(1e-30);
    let sum_rounding = 1e-6 * (mean.abs() + correlation.abs());
    let attribute = |lambda: f64, value: f32| {
        BASE.max(relative_to(correlation.abs() * lambda * attribute_amplification + sum_rounding, value))
    };
    // The directions' Λs: Λ(ν) through exp(−ν²), ν ≤ cot θ / (√2 σ).
    let slopes = SlopeDeviation::isotropic(case.light.w).ok();
    let nu_squared = |d: Vec3| {
        slopes.and_then(|s| nu_of_direction(d, s)).filter(|n| n.is_finite()).map_or(0.0, |n| f64::from(n).powi(2))
    };
    let directions_lambda =
        exp_tolerance(nu_squared(case.view.truncate())).max(exp_tolerance(nu_squared(case.light.truncate())));
    let for_directions = attribute(lambda(1.0, 1.0) + directions_lambda + 64.0 * epsilon, cpu[3]);
    [
        lambda(lambda_view, lambda_light) * amplification,
        attribute(lambda(lambda_view, lambda_light), cpu[1]),
        1e-6,
        for_directions,
    ]
}

#[test]
fn correlated_functions_match_the_cpu_reference() {
    const CORRELATED_NAMES: [&str; 4] =
        ["correlated lambda", "abar correlated", "cos azimuth difference", "abar correlated (directions)"];
    let (cases, rejected) = correlated_cases();
    println!(
        "{rejected} special model values rejected by VisibilityCorrection::new / LambdaCorrection::from_knots (no case)"
    );
    let gpu_cases: Vec<CorrelatedCase> = cases.iter().map(|v| v.case).collect();
    let gpu_bits = run_kernel(
        "smith_micro_correlated_differential",
        "smith_correlated_values",
        &gpu_cases,
        |r: &CorrelatedResults| r.values.to_array(),
    );
    // cos Δφ absolutely, the others relatively.
    check_four_results(
        "correlated",
        CORRELATED_NAMES,
        &cases,
        &gpu_bits,
        |case| reference_correlated_results(case).values.to_array(),
        correlated_tolerances,
        [false, false, true, false],
    );
}

/// Valid cubic corrections: random coefficients kept when
/// [`CubicLambdaCorrection::from_coefficients`] accepts them, the identity, and cubics
/// fitted to random tables; Λs and attributes as in `correction_cases`, with every input
/// set to each special scalar in turn.
fn cubic_cases() -> Vec<Validated<CubicLambdaCorrection, CubicCase>> {
    let mut rng = SmallRng::seed_from_u64(31);
    let correction = |rng: &mut SmallRng| loop {
        if rng.random_bool(0.05) {
            return CubicLambdaCorrection::IDENTITY;
        }
        if rng.random_bool(0.3) {
            if let Ok(cubic) = CubicLambdaCorrection::fit_to_table(&random_table(rng)) {
                return cubic;
            }
            continue;
        }
        let candidate: [f32; 4] =
            std::array::from_fn(|i| if i == 0 { rng.random_range(0.25..4.0) } else { rng.random_range(-6.0..6.0) });
        if let Ok(cubic) = CubicLambdaCorrection::from_coefficients(candidate) {
            return cubic;
        }
    };
    let case = |correction: CubicLambdaCorrection, inputs: Vec4| {
        let coefficients: Vec4 = bytemuck::cast::<GpuCubicLambdaCorrection, _>(correction.to_gpu());
        Validated { correction, case: CubicCase { coefficients, inputs } }
    };
    let mut cases = Vec::new();
    for &special in &SPECIAL_SCALARS {
        for input in 0..4 {
            for _ in 0..8 {
                let mut inputs = random_inputs(&mut rng);
                inputs[input] = special;
                cases.push(case(correction(&mut rng), inputs));
            }
        }
    }
    while cases.len() < 110_000 {
        let c = correction(&mut rng);
        cases.push(case(c, random_inputs(&mut rng)));
    }
    cases
}

/// Relative tolerances of the 4 cubic results of one case. `u = Λ/(1+Λ)` is a division
/// (2.5 ulp in Vulkan): `c` moves by at most `|c′| 3ε` with `|c′| ≤ |c₁| + 2|c₂| + 3|c₃|`;
/// Horner's three multiply–adds (rounded or FMA-contracted) add at most
/// `8 ε (|c₀| + |c₁| + |c₂| + |c₃|)`; relative to `c ≥ 0.25`. The attributes inherit it
/// through `Λ'` as in `correction_tolerances`.
fn cubic_tolerances(validated: &Validated<CubicLambdaCorrection, CubicCase>, cpu: &[f32; 4]) -> [f64; 4] {
    let Validated { correction, case } = validated;
    let [c0, c1, c2, c3] = correction.coefficients().map(|c| f64::from(c).abs());
    let epsilon = f64::from(f32::EPSILON);
    let lambda_tolerance = |lambda: f32| {
        let factor = f64::from(correction.factor(lambda / (1.0 + lambda)));
        BASE.max(
            4.0 * epsilon
                + (3.0 * (c1 + 2.0 * c2 + 3.0 * c3) + 8.0 * (c0 + c1 + c2 + c3)) * epsilon / factor.abs().max(0.25),
        )
    };
    let [mean, correlation, lambda_view, lambda_light] = case.inputs.to_array();
    let sum = lambda_tolerance(lambda_view + lambda_light);
    let view = lambda_tolerance(lambda_view);
    let attribute = |lambda: f64, value: f32| attribute_tolerance(mean, correlation, lambda, value);
    [view, attribute(sum, cpu[1]), attribute(sum, cpu[2]), attribute(view, cpu[3])]
}

#[test]
fn cubic_correction_matches_the_cpu_reference() {
    const CUBIC_NAMES: [&str; 4] = ["cubic factor", "abar cubic (v, l)", "abar cubic (l, v)", "abar cubic (v, 0)"];
    let cases = cubic_cases();
    let gpu_cases: Vec<CubicCase> = cases.iter().map(|v| v.case).collect();
    let gpu_bits =
        run_kernel("smith_micro_cubic_differential", "smith_cubic_corrected_values", &gpu_cases, |r: &CubicResults| {
            r.values.to_array()
        });
    check_four_results(
        "cubic",
        CUBIC_NAMES,
        &cases,
        &gpu_bits,
        |case| reference_cubic_results(case).values.to_array(),
        cubic_tolerances,
        [false; 4],
    );
}
