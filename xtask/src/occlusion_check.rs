//! `cargo xtask occlusion-check [--cases N] [--seed S]`: `occlusion-cone`'s conservativeness
//! check (`occlusion_cone::check_conservative`): `N` random configurations (10⁷ by
//! default) decided by the `f32` test and by the exact `f64` answer. Prints the counts;
//! fails when a visible grain is culled.

use std::time::Instant;

use crate::cli::{Args, positive};

/// Configurations decided by default.
pub const DEFAULT_CASES: u64 = 10_000_000;

/// Any `u64`, decimal or `0x` hexadecimal.
pub fn seed(text: &str) -> Result<u64, String> {
    let parsed = match text.strip_prefix("0x") {
        Some(hex) => u64::from_str_radix(hex, 16),
        None => text.parse::<u64>(),
    };
    parsed.map_err(|_| "expected an unsigned integer (decimal or 0x hexadecimal)".to_owned())
}

pub fn run(args: &Args<'_>) -> Result<(), String> {
    let cases = args.parse_value("cases", positive::<u64>)?.unwrap_or(DEFAULT_CASES);
    let seed = args.parse_value("seed", seed)?.unwrap_or(0x0cc1_0de5);
    let started = Instant::now();
    let report = occlusion_cone::check_conservative(cases, seed);
    let seconds = started.elapsed().as_secs_f64();
    println!("occlusion-check: {} configurations (seed {seed:#x}) in {seconds:.1} s", report.cases);
    println!(
        "  exact answer: {} hidden, {} visible, {} within f64 rounding of the boundary, {} undefined (eye inside the occluder)",
        report.hidden, report.visible, report.boundary, report.undefined
    );
    println!("  f32 test: {} culled", report.culled);
    println!("  visible grains culled: {} (must be 0)", report.visible_culled);
    println!(
        "  hidden grains culled: {} of {} ({:.2} %; the rest lie within the rounding margin of the cone's boundary, or have R < r and are tested as R = r)",
        report.hidden_culled,
        report.hidden,
        100.0 * report.found_fraction()
    );
    if report.visible_culled > 0 {
        return Err(format!("{} visible grains were culled: the test is not conservative", report.visible_culled));
    }
    Ok(())
}
