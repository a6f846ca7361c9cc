//! `cargo xtask svo-stability [OUT_DIR] [--quick]`: the SVO tracer where the paper's
//! hypotheses fail (`svo_render::stability`): thin plates (H7), strong curvature and box
//! corners (H6), non-Gaussian micro-surfaces (H3) and grazing views, each relaxed step by
//! step with every model against the supersampled truth. Writes `stability.csv`, one CSV per
//! sweep, and one chart per sweep and view, `svo_stability_<sweep>_<view>.png`: ꟻLIP and the
//! coverage error over every pixel against the relaxed parameter, one line per model.

use std::path::Path;
use std::time::Instant;

use abuffer_mask::MaskTable;
use plotters::prelude::*;
use svo_render::stability::{self, StabilitySettings, StabilityTable, Sweep};
use svo_tracer::Model;

use crate::chart::{draw_legend, drawing_error, legend_stroke, render_png};
use crate::cli::Args;
use crate::svo::COLOURS;

pub fn run(args: &Args<'_>) -> Result<(), String> {
    let out = args.out_dir();
    std::fs::create_dir_all(&out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let settings = if args.flag("quick") { StabilitySettings::quick() } else { StabilitySettings::default() };
    let table = MaskTable::<4>::paper().ok_or("the paper's mask table cannot be built")?;
    println!(
        "svo-stability: {} rows ({}×{} px, {} levels of 4³ bricks, truth {k}×{k} rays per pixel, CPU tracer)",
        settings.rows(&Sweep::ALL),
        settings.width,
        settings.height,
        settings.levels,
        k = settings.truth_rays_per_axis
    );
    let mut all = StabilityTable::default();
    for sweep in Sweep::ALL {
        let started = Instant::now();
        let rows = stability::run(&[sweep], &settings, &table).map_err(|e| e.to_string())?;
        println!("  {}: {} rows in {:.1} s", sweep.name(), rows.rows.len(), started.elapsed().as_secs_f64());
        for variant in rows.variants(sweep) {
            let path = out.join(format!("svo_stability_{}_{variant}.png", sweep.name()));
            chart(&path, &rows, sweep, variant)?;
        }
        all.rows.extend(rows.rows);
    }
    let files = stability::write_folder(&all, &out).map_err(|e| e.to_string())?;
    println!("svo-stability: wrote {} CSV files and the charts to {}", files.len(), out.display());
    Ok(())
}

/// The chart's abscissa: `log₂` of a length parameter (the steps halve), the angle itself.
fn abscissa(sweep: Sweep, parameter: f32) -> f64 {
    if sweep == Sweep::Grazing { f64::from(parameter) } else { f64::from(parameter).log2() }
}

/// A step of a model's line: the abscissa, ꟻLIP and the coverage error.
#[derive(Clone, Copy)]
struct Point {
    x: f64,
    flip: f64,
    coverage: f64,
}

/// What a panel plots of a point.
type Metric = fn(&Point) -> f64;

/// One sweep's view: ꟻLIP (left) and the coverage error over every pixel (right) against the
/// relaxed parameter, a line per model.
fn chart(path: &Path, table: &StabilityTable, sweep: Sweep, variant: &str) -> Result<(), String> {
    let series: Vec<(Model, Vec<Point>)> = Model::ALL
        .into_iter()
        .map(|model| {
            let points: Vec<Point> = table
                .series(sweep, variant, model)
                .map(|r| Point { x: abscissa(sweep, r.parameter), flip: r.comparison.flip, coverage: r.coverage_error })
                .filter(|p| p.x.is_finite() && p.flip.is_finite() && p.coverage.is_finite())
                .collect();
            (model, points)
        })
        .filter(|(_, points)| !points.is_empty())
        .collect();
    if series.is_empty() {
        return Err(format!("svo-stability: no finite row for {} ({variant}), nothing to chart", sweep.name()));
    }
    let points = series.iter().flat_map(|(_, p)| p.iter());
    let (mut x_lo, mut x_hi, mut flip_hi, mut coverage_hi) = (f64::INFINITY, f64::NEG_INFINITY, 0.0_f64, 0.0_f64);
    for p in points {
        x_lo = x_lo.min(p.x);
        x_hi = x_hi.max(p.x);
        flip_hi = flip_hi.max(p.flip);
        coverage_hi = coverage_hi.max(p.coverage);
    }
    let pad = 0.05 * (x_hi - x_lo).max(1e-3);
    let (x_lo, x_hi) = (x_lo - pad, x_hi + pad);
    let x_desc = if sweep == Sweep::Grazing {
        format!("{} (relaxed towards the right)", sweep.parameter())
    } else {
        format!(
            "log₂ {} (relaxed towards the {})",
            sweep.parameter(),
            if sweep.relaxed_upwards() { "right" } else { "left" }
        )
    };
    let caption = format!("SVO stability: {} ({variant}), every model against the truth", sweep.name());
    render_png(path, (1400, 620), |root| {
        let e = drawing_error;
        let root = root.titled(&caption, ("sans-serif", 24)).map_err(e)?;
        let panels = root.split_evenly((1, 2));
        let metrics: [(&str, f64, Metric); 2] = [
            ("FLIP against the truth", flip_hi, |p| p.flip),
            ("coverage error, mean |Δ| over every pixel", coverage_hi, |p| p.coverage),
        ];
        for (panel, (y_desc, y_hi, value)) in panels.iter().zip(metrics) {
            let mut chart = ChartBuilder::on(panel)
                .margin(15)
                .x_label_area_size(45)
                .y_label_area_size(65)
                .build_cartesian_2d(x_lo..x_hi, 0.0_f64..(1.45 * y_hi).max(1e-3))
                .map_err(e)?;
            chart
                .configure_mesh()
                .x_desc(x_desc.as_str())
                .y_desc(y_desc)
                .label_style(("sans-serif", 16))
                .draw()
                .map_err(e)?;
            for (model, points) in &series {
                let k = Model::ALL.iter().position(|m| m == model).unwrap_or(0);
                let colour = COLOURS[k % COLOURS.len()];
                let line: Vec<(f64, f64)> = points.iter().map(|p| (p.x, value(p))).collect();
                chart.draw_series(line.iter().map(|&p| Circle::new(p, 4, colour.filled()))).map_err(e)?;
                chart
                    .draw_series(LineSeries::new(line, colour.stroke_width(2)))
                    .map_err(e)?
                    .label(model.name())
                    .legend(legend_stroke(colour, 3, 24));
            }
            // The headroom above the data holds the legend.
            draw_legend(&mut chart, 16, SeriesLabelPosition::UpperRight)?;
        }
        Ok(())
    })
}
