//! Sphere-tracing steps against the view angle (part of `cargo xtask ddm-trace`): the rows
//! of `ddm_experiments::steps` (where the directional distance maps save steps over the
//! plain distance map, §3, Table 1) written as `ddm_steps_vs_angle.csv`, printed as ratios
//! to the plain map and charted per mesostructure.

use std::fmt::Write as _;
use std::path::Path;

use ddm_experiments::steps::StepsRow;
use plotters::prelude::*;

use crate::chart::{draw_legend, drawing_error, render_png};

/// Writes `ddm_steps_vs_angle.csv` and `.png` into `out` and prints the ratio of the DDM
/// 4×1's steps (and the exit rows') to the plain map's at each of `angles_deg`.
pub fn write(out: &Path, rows: &[StepsRow], angles_deg: &[f32]) -> Result<(), String> {
    let mut csv = String::from("mesostructure,map,angle_deg,mean_steps,exhausted,rays,steps_over_dm\n");
    for row in rows {
        writeln!(
            csv,
            "{},{},{},{:.4},{},{},{:.4}",
            row.mesostructure, row.map, row.angle_deg, row.mean_steps, row.exhausted, row.rays, row.steps_over_dm
        )
        .map_err(|e| e.to_string())?;
    }
    let path = out.join("ddm_steps_vs_angle.csv");
    std::fs::write(&path, &csv).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    println!("wrote {}", path.display());
    let mut structures: Vec<&str> = rows.iter().map(|r| r.mesostructure).collect();
    structures.dedup();
    for (map, what) in [
        ("DDM 4x1", "DDM 4x1 / DM, both with the paper's distance stepping"),
        ("DDM 4x1 exit", "DDM 4x1 with voxel-exit stepping / DM with the paper's stepping"),
        ("DM exit", "DM with voxel-exit stepping / DM with the paper's stepping"),
    ] {
        println!("\nSteps of {what}, per view angle from the vertical:");
        print!("{:<12}", "angle");
        for angle in angles_deg {
            print!("{angle:>7}");
        }
        println!();
        for structure in &structures {
            print!("{structure:<12}");
            for &angle in angles_deg {
                let ratio = rows
                    .iter()
                    .find(|r| r.mesostructure == *structure && r.angle_deg == angle && r.map == map)
                    .map_or(f64::NAN, |r| r.steps_over_dm);
                print!("{ratio:>7.3}");
            }
            println!();
        }
    }
    let path = out.join("ddm_steps_vs_angle.png");
    chart(&path, rows, &structures)?;
    println!("wrote {}", path.display());
    Ok(())
}

/// One panel per mesostructure: mean steps against the view angle, one line per map.
fn chart(path: &Path, rows: &[StepsRow], structures: &[&str]) -> Result<(), String> {
    let maps: Vec<(&str, RGBColor)> = crate::ddm_trace::METHOD_COLORS[..5]
        .iter()
        .copied()
        .chain(crate::ddm_trace::METHOD_COLORS.iter().copied().filter(|(name, _)| name.ends_with(" exit")))
        .collect();
    let width = 360 * structures.len().max(1) as u32;
    render_png(path, (width, 420), |root| {
        let panels = root.split_evenly((1, structures.len().max(1)));
        for (panel, structure) in panels.iter().zip(structures) {
            let mine: Vec<&StepsRow> = rows.iter().filter(|r| r.mesostructure == *structure).collect();
            let top = mine.iter().map(|r| r.mean_steps).fold(1.0_f64, f64::max) * 1.1;
            let mut chart = ChartBuilder::on(panel)
                .caption(format!("{structure}: mean steps per ray"), ("sans-serif", 18))
                .margin(10)
                .x_label_area_size(40)
                .y_label_area_size(44)
                .build_cartesian_2d(0.0_f32..85.0, 0.0..top)
                .map_err(drawing_error)?;
            chart
                .configure_mesh()
                .x_desc("view angle from the vertical (°)")
                .label_style(("sans-serif", 14))
                .draw()
                .map_err(drawing_error)?;
            for &(map, color) in &maps {
                let line: Vec<(f32, f64)> =
                    mine.iter().filter(|r| r.map == map).map(|r| (r.angle_deg, r.mean_steps)).collect();
                chart
                    .draw_series(LineSeries::new(line, color.stroke_width(2)))
                    .map_err(drawing_error)?
                    .label(map)
                    .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], color.stroke_width(2)));
            }
            draw_legend(&mut chart, 13, SeriesLabelPosition::UpperLeft)?;
        }
        Ok(())
    })
}
