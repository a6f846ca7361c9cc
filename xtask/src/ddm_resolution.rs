//! `cargo xtask ddm-resolution [OUT_DIR] [--quick]`: each DDM patch construction against the
//! tile's own surface as the tile is sampled by finer grids (`ddm_experiments::resolution`:
//! 12, 24, 48 and 96 voxels across; 12 and 24 with `--quick`). Writes `ddm_resolution.csv`
//! (|SDF(hit)| p50/p99/max in voxels and the p99 in tile widths, normal angles, leaks) and
//! one chart per tile, `ddm_resolution_<tile>.png`: the p99 in voxels against the voxels
//! across, log–log, one line per construction.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use ddm_experiments::resolution::{ResolutionRow, ResolutionSettings, resolution_sweep};
use ddm_experiments::trace_tables::PatchKind;
use ddm_experiments::{TraceMethod, TraceTablesSettings};
use ddm_tracer::Stepping;
use mesostructure::Mesostructure;
use plotters::prelude::*;

use crate::chart::{draw_legend, drawing_error, legend_stroke, render_png};
use crate::cli::Args;
use crate::ddm_trace::METHOD_COLORS;

/// A construction's colour: that of ddm-trace's DDM 4×1 method with these patches (its
/// paper's stepping), so that the charts of both commands agree.
fn colour(kind: PatchKind) -> RGBColor {
    let settings = TraceTablesSettings::quick();
    TraceMethod::ALL
        .into_iter()
        .find(|m| {
            m.case(&settings).is_some_and(|c| c.patches == Some(kind) && c.settings.stepping == Stepping::Distance)
        })
        .and_then(|m| METHOD_COLORS.iter().find(|(name, _)| *name == m.name()))
        .map_or(BLACK, |(_, colour)| *colour)
}

pub fn run(args: &Args<'_>) -> Result<(), String> {
    let out = args.out_dir();
    std::fs::create_dir_all(&out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let settings = if args.flag("quick") { ResolutionSettings::quick() } else { ResolutionSettings::full() };
    println!(
        "ddm-resolution: {:?} voxels across (depth max(4, n/3)), {}x{} rays, DDM 4x1, every patch construction",
        settings.voxels_across, settings.width, settings.height
    );
    let mut csv = String::from(
        "mesostructure,voxels_across,patches,hits,sdf_p50_voxel,sdf_p99_voxel,sdf_max_voxel,sdf_p99_tile_widths,normal_p50_deg,normal_p99_deg,leak_tau_voxel,leaks,leak_search_unfinished\n",
    );
    for which in Mesostructure::ALL {
        let started = Instant::now();
        let rows = resolution_sweep(which, &settings).map_err(|e| e.to_string())?;
        for row in &rows {
            let a = &row.accuracy;
            writeln!(
                csv,
                "{},{},{},{},{:e},{:e},{:e},{:e},{:.3},{:.3},{:e},{},{}",
                row.mesostructure,
                row.voxels_across,
                row.patches.name(),
                a.hits,
                a.p50,
                a.p99,
                a.max,
                row.p99_tile_widths(),
                a.normal_p50,
                a.normal_p99,
                a.tau,
                a.leaks,
                a.unfinished
            )
            .map_err(|e| e.to_string())?;
        }
        let path = out.join(format!("ddm_resolution_{}.png", which.name()));
        chart(&path, which.name(), &rows)?;
        println!("  {}: {} rows in {:.1} s", which.name(), rows.len(), started.elapsed().as_secs_f64());
    }
    let path = out.join("ddm_resolution.csv");
    std::fs::write(&path, &csv).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    println!("{csv}wrote {} and the charts", path.display());
    Ok(())
}

/// The p99 of |SDF(hit)| (voxels) against the voxels across, log–log, a line per
/// construction.
fn chart(path: &Path, tile: &str, rows: &[ResolutionRow]) -> Result<(), String> {
    let floor = 1e-7_f64;
    let points = |kind: PatchKind| -> Vec<(f64, f64)> {
        rows.iter()
            .filter(|r| r.patches == kind)
            .map(|r| (f64::from(r.voxels_across).log2(), r.accuracy.p99.max(floor).log10()))
            .collect()
    };
    let all: Vec<(f64, f64)> = PatchKind::ALL.into_iter().flat_map(points).collect();
    if all.is_empty() {
        return Err(format!("ddm-resolution: no row for {tile}, nothing to chart"));
    }
    let (mut x_lo, mut x_hi, mut y_lo, mut y_hi) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
    for &(x, y) in &all {
        x_lo = x_lo.min(x);
        x_hi = x_hi.max(x);
        y_lo = y_lo.min(y);
        y_hi = y_hi.max(y);
    }
    let caption = format!("DDM 4x1 patches on {tile}: p99 |SDF(hit)| against the tile's own surface");
    render_png(path, (900, 620), |root| {
        let e = drawing_error;
        let mut chart = ChartBuilder::on(root)
            .caption(caption.as_str(), ("sans-serif", 22))
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(70)
            .build_cartesian_2d((x_lo - 0.2)..(x_hi + 0.2), (y_lo - 0.5)..(y_hi + 1.5))
            .map_err(e)?;
        chart
            .configure_mesh()
            .x_desc("log₂ voxels across")
            .y_desc("log₁₀ p99 |SDF(hit)| (voxels)")
            .label_style(("sans-serif", 16))
            .draw()
            .map_err(e)?;
        for kind in PatchKind::ALL {
            let line = points(kind);
            let colour = colour(kind);
            chart.draw_series(line.iter().map(|&p| Circle::new(p, 4, colour.filled()))).map_err(e)?;
            chart
                .draw_series(LineSeries::new(line, colour.stroke_width(2)))
                .map_err(e)?
                .label(kind.name())
                .legend(legend_stroke(colour, 3, 24));
        }
        draw_legend(&mut chart, 16, SeriesLabelPosition::UpperRight)?;
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_construction_has_its_ddm_trace_colour() {
        let colours: Vec<RGBColor> = PatchKind::ALL.into_iter().map(colour).collect();
        for (i, a) in colours.iter().enumerate() {
            assert!(colours[i + 1..].iter().all(|b| b != a), "{colours:?}");
        }
    }
}
