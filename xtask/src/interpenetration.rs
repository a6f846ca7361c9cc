//! `cargo xtask interpenetration [OUT_DIR] [--grains COUNT] [--quick]`: the impostor tier as grains
//! interpenetrate (`docs/failure-modes.md` §1.5). Michel & Boubekeur's piles keep grains
//! apart; a user's pile need not. For the bean, the rock and the nut (the bean and the nut
//! with `--quick`), the pile of `stackings` (2000 grains; 1000 with `--quick`; `--grains COUNT` any other) is generated with its lattice packed
//! tighter, step by step, from the spacing at which the outer balls are disjoint
//! ([`disjoint_spacing`]: no two grains can touch) down to the tightest that keeps the
//! inner balls disjoint ([`tightest_spacing`]: the occlusion culling's hypothesis). At each
//! spacing the pile is drawn with every grain an impostor (`n` 8, `p` 64) and compared
//! with the same pile as meshes 4 × 4 supersampled, whose depth test resolves every
//! intersection exactly (`grain_renderer::point_threshold::measure`: mean ꟻLIP and the
//! standard SSIM over the pile's covered rectangle; the holes the impostors open and the
//! pixels they add, `point_threshold::CoverageDifference`). Writes `interpenetration.csv`, the
//! chart `interpenetration.png` and, at the tightest spacing, each grain's
//! `{grain}_tight_{mesh,impostors,flip}.png`.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use grain_renderer::point_threshold::{self, MeasureView};
use grain_splitter::sweep::Shot;
use plotters::prelude::*;

use crate::chart::{draw_legend, drawing_error, legend_stroke, render_png};
use crate::cli::Args;
use crate::stackings::{PILE_JITTER, bake_atlas, pile_instances_spaced};

/// Grains in each pile (with `--quick`: [`QUICK_GRAINS`]).
const GRAINS: usize = 2000;
/// Grains in each pile with `--quick` (the supersampled meshes dominate the time).
const QUICK_GRAINS: usize = 1000;
/// Spacings measured from [`disjoint_spacing`] to [`tightest_spacing`], both included.
const STEPS: usize = 4;
/// Projected diameters (pixels) at which the pile is compared: the impostor tier's sizes.
const DIAMETERS: [f32; 2] = [8.0, 16.0];
/// The image, pixels.
const SIZE: (u32, u32) = (320, 180);

/// The smallest lattice spacing (in units of `2·R·s_max`, `grain_scenes::StackingSpec::spacing`)
/// at which the outer balls of a pile jittered by `jitter` are disjoint: no two grains can
/// interpenetrate.
pub fn disjoint_spacing(jitter: f32) -> f32 {
    grain_scenes::StackingSpec::disjoint_spacing(jitter)
}

/// The tightest spacing that keeps the inner balls (radius `r`, outer `R`) disjoint,
/// `spacing·(1 − 2·jitter) ≥ r/R` with 2 % to spare (the pile's own rule), and at least
/// half the disjoint spacing (a grain with a tiny inner ball would otherwise collapse the pile).
pub fn tightest_spacing(inner_over_outer: f32, jitter: f32) -> f32 {
    (1.02 * inner_over_outer / (1.0 - 2.0 * jitter)).max(0.5 * disjoint_spacing(jitter))
}

/// `steps` spacings from the disjoint one down to the tightest, evenly spaced.
pub fn spacing_ladder(inner_over_outer: f32, jitter: f32, steps: usize) -> Vec<f32> {
    let (from, to) = (disjoint_spacing(jitter), tightest_spacing(inner_over_outer, jitter));
    (0..steps).map(|k| from + (to - from) * k as f32 / (steps - 1).max(1) as f32).collect()
}

/// One measurement: a grain type at a spacing and a diameter.
struct Row {
    grain: String,
    spacing: f32,
    diameter: f32,
    flip: f64,
    ssim_loss: f64,
    coverage: point_threshold::CoverageDifference,
}

/// Runs the sweep.
pub fn run(args: &Args<'_>) -> Result<(), String> {
    let out = args.out_dir();
    let quick = args.flag("quick");
    std::fs::create_dir_all(&out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let gpu = gpu_harness::Gpu::new().map_err(|e| e.to_string())?;
    println!("interpenetration on {}", gpu.describe());
    let names: &[&str] = if quick { &["bean", "nut"] } else { &["bean", "rock", "nut"] };
    let count =
        args.parse_value("grains", crate::cli::positive::<usize>)?.unwrap_or(if quick { QUICK_GRAINS } else { GRAINS });
    let grains = crate::impostor_accuracy::grains(false, &[])?;
    let started = Instant::now();
    let mut rows = Vec::new();
    for &name in names {
        let mesh = &grains.iter().find(|(n, _)| n == name).ok_or_else(|| format!("no procedural grain {name}"))?.1;
        let bounds = mesh.bounds();
        let ratio = bounds.occluder_radius() / bounds.outer_radius;
        let atlas = bake_atlas(&gpu, mesh)?;
        let ladder = spacing_ladder(ratio, PILE_JITTER, STEPS);
        for (k, &spacing) in ladder.iter().enumerate() {
            let (stacking, instances) = pile_instances_spaced(count, mesh, spacing)?;
            let region = stacking.bounds();
            let [wide, ..] = Shot::fig15(region.min, region.max);
            let view = MeasureView { target: wide.target, direction: wide.eye - wide.target, size: SIZE, frames: 1 };
            let measured = point_threshold::measure(&gpu, mesh, &atlas, &instances, view, &DIAMETERS)
                .map_err(|e| format!("{name} at spacing {spacing:.3}: {e}"))?;
            for row in &measured.rows {
                println!(
                    "  {name:>4} spacing {spacing:.3} (r/R {ratio:.2}) {:>4} px: impostors ꟻLIP {:.4}, 1 − SSIM {:.4}, holes {} and added {} pixels of {} covered  [{:.0} s]",
                    row.diameter,
                    row.impostors.flip,
                    row.impostors.ssim_loss,
                    row.impostors.coverage.uncovered,
                    row.impostors.coverage.spurious,
                    row.impostors.coverage.mesh_covered,
                    started.elapsed().as_secs_f64()
                );
                rows.push(Row {
                    grain: name.to_owned(),
                    spacing,
                    diameter: row.diameter,
                    flip: row.impostors.flip,
                    ssim_loss: row.impostors.ssim_loss,
                    coverage: row.impostors.coverage,
                });
            }
            if k + 1 == ladder.len() {
                let largest = measured.rows.last().ok_or("no row measured")?;
                save_images(&out, name, &largest.reference, &largest.impostors.image)?;
            }
        }
    }
    let mut csv = String::from(
        "grain,spacing,diameter_px,impostor_flip,impostor_ssim_loss,mesh_covered_px,impostor_holes_px,impostor_added_px\n",
    );
    for r in &rows {
        let c = r.coverage;
        let _ = writeln!(
            csv,
            "{},{:.4},{},{:.6},{:.6},{},{},{}",
            r.grain, r.spacing, r.diameter, r.flip, r.ssim_loss, c.mesh_covered, c.uncovered, c.spurious
        );
    }
    let path = out.join("interpenetration.csv");
    std::fs::write(&path, csv).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    println!("wrote {}", path.display());
    let path = out.join("interpenetration.png");
    chart(&path, &rows, names, count, &gpu.describe())?;
    println!("wrote {} in {:.0} s", path.display(), started.elapsed().as_secs_f64());
    Ok(())
}

/// The tightest pile's mesh reference, impostor image and ꟻLIP map.
fn save_images(
    out: &Path,
    name: &str,
    reference: &image::RgbaImage,
    impostors: &image::RgbaImage,
) -> Result<(), String> {
    let save = |file: String, result: image::ImageResult<()>| {
        result.map_err(|e| format!("cannot write {}: {e}", out.join(file).display()))
    };
    let file = format!("{name}_tight_mesh.png");
    save(file.clone(), reference.save(out.join(&file)))?;
    let file = format!("{name}_tight_impostors.png");
    save(file.clone(), impostors.save(out.join(&file)))?;
    let flip = image_metrics::flip(reference, impostors).map_err(|e| format!("{name}: {e}"))?;
    let file = format!("{name}_tight_flip.png");
    save(file.clone(), image_metrics::flip_magma(&flip.map).save(out.join(&file)))
}

const COLOURS: [RGBColor; 3] = [RGBColor(140, 86, 75), RGBColor(127, 127, 127), RGBColor(31, 119, 180)];

/// ꟻLIP against the spacing, one line per grain and diameter (dashed-looking thin lines for
/// the smaller diameter).
fn chart(path: &Path, rows: &[Row], names: &[&str], count: usize, adapter: &str) -> Result<(), String> {
    let (x_lo, x_hi) = rows.iter().fold((f32::MAX, 0.0_f32), |(lo, hi), r| (lo.min(r.spacing), hi.max(r.spacing)));
    let y_hi = rows.iter().map(|r| r.flip).fold(0.0, f64::max);
    if rows.is_empty() || y_hi <= 0.0 {
        return Err(format!("{}: nothing to chart", path.display()));
    }
    render_png(path, (1000, 620), |root| {
        let e = drawing_error;
        let root = root
            .titled(
                &format!("Impostors of interpenetrating grains against the meshes (4x4 supersampled), {count} grains"),
                ("sans-serif", 22),
            )
            .map_err(e)?;
        let mut chart = ChartBuilder::on(&root)
            .caption(format!("on {adapter}"), ("sans-serif", 14))
            .margin(12)
            .x_label_area_size(48)
            .y_label_area_size(60)
            .build_cartesian_2d(f64::from(x_hi) * 1.03..f64::from(x_lo) * 0.97, 0.0..y_hi * 1.2)
            .map_err(e)?;
        chart
            .configure_mesh()
            .x_desc("lattice spacing / (2 R s_max): left, no two grains can touch; right, the tightest measured")
            .y_desc("mean FLIP of the impostor tier")
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(e)?;
        for (g, name) in names.iter().enumerate() {
            let colour = COLOURS[g % COLOURS.len()];
            for (d, diameter) in DIAMETERS.into_iter().enumerate() {
                let series: Vec<(f64, f64)> = rows
                    .iter()
                    .filter(|r| r.grain == *name && r.diameter == diameter)
                    .map(|r| (f64::from(r.spacing), r.flip))
                    .collect();
                let width = if d == 0 { 1 } else { 3 };
                chart.draw_series(series.iter().map(|&p| Circle::new(p, 4, colour.filled()))).map_err(e)?;
                chart
                    .draw_series(LineSeries::new(series, colour.stroke_width(width)))
                    .map_err(e)?
                    .label(format!("{name}, {diameter} px"))
                    .legend(legend_stroke(colour, width, 24));
            }
        }
        draw_legend(&mut chart, 15, SeriesLabelPosition::UpperLeft)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ladder_runs_from_disjoint_outer_balls_to_touching_inner_balls() {
        let jitter = 0.05;
        let ladder = spacing_ladder(0.6, jitter, 4);
        assert_eq!(ladder.len(), 4);
        // The first keeps the outer balls apart, the last the inner balls only.
        assert!(ladder[0] * (1.0 - 2.0 * jitter) >= 1.0);
        let last = ladder[3] * (1.0 - 2.0 * jitter);
        assert!((0.6..1.0).contains(&last), "{last}");
        assert!(ladder.windows(2).all(|w| w[1] < w[0]));
        // A tiny inner ball stops at half the disjoint spacing.
        assert_eq!(tightest_spacing(0.01, jitter), 0.5 * disjoint_spacing(jitter));
    }
}
