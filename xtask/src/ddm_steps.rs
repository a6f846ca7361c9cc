//! Sphere-tracing steps against the view angle (part of `cargo xtask ddm-trace`): where
//! the directional distance maps save steps over the plain distance map.
//!
//! Mehra & Kumar credit the DDMs with "faster convergence near the mesostructure
//! boundary" (§3, Table 1). How much they save depends on the view: a ray seen from
//! straight above reaches the surface in a few steps with either map, while a grazing ray
//! crawls along the walls and tops beside it with the plain map, whose distances count
//! surfaces in every direction. Each angle from the vertical in [`ANGLES_DEG`] is traced
//! with parallel rays from a [`GRID`]² lattice over the tile at 8 azimuths (odd multiples
//! of 22.5°, inside the cones of every map), each map stopping at its first zero voxel
//! (the sphere tracing of Tables 1/2), and the mean steps per ray are recorded; the plain
//! map and the DDM 4×1 also with voxel-exit stepping (`ddm_tracer::Stepping::VoxelExit`,
//! beyond the paper: rows `DM exit`, `DDM 4x1 exit`).

use std::fmt::Write as _;
use std::path::Path;

use ddm_compress::DistanceMaps;
use ddm_tracer::{Method, Stepping, TraceSettings, trace};
use glam::{UVec3, Vec3};
use plotters::prelude::*;

use crate::chart::{draw_legend, drawing_error, render_png};

/// View angles from the vertical, degrees.
pub const ANGLES_DEG: [f32; 10] = [0.0, 15.0, 30.0, 45.0, 55.0, 65.0, 70.0, 75.0, 80.0, 85.0];
/// Ray origins per tile axis.
pub const GRID: u32 = 24;
const AZIMUTHS: u32 = 8;
/// The maps also traced with [`Stepping::VoxelExit`], and their rows' names.
const EXIT_NAMES: [(&str, &str); 2] = [("DM", "DM exit"), ("DDM 4x1", "DDM 4x1 exit")];
const MAX_STEPS: u32 = 512;

/// Mean steps of one map at one angle.
pub struct StepsRow {
    mesostructure: &'static str,
    map: &'static str,
    angle_deg: f32,
    mean_steps: f64,
    exhausted: usize,
    rays: usize,
}

/// Traces the rays of every angle with every map of `maps` (named as in `ddm-trace`).
pub fn steps_vs_angle(
    mesostructure: &'static str,
    dims: UVec3,
    maps: &[(&'static str, DistanceMaps)],
) -> Result<Vec<StepsRow>, String> {
    let settings = TraceSettings { method: Method::SphereTracing, max_steps: MAX_STEPS, stepping: Stepping::Distance };
    let mut rows = Vec::new();
    for angle in ANGLES_DEG {
        let theta = angle.to_radians();
        let mut rays = Vec::new();
        for a in 0..AZIMUTHS {
            let phi = (a as f32 + 0.5) * std::f32::consts::TAU / AZIMUTHS as f32;
            let direction = Vec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), -theta.cos());
            for j in 0..GRID {
                for i in 0..GRID {
                    let origin = Vec3::new(
                        (i as f32 + 0.37) * dims.x as f32 / GRID as f32,
                        (j as f32 + 0.61) * dims.y as f32 / GRID as f32,
                        dims.z as f32 + 0.5,
                    );
                    rays.push((origin, direction));
                }
            }
        }
        let exit = TraceSettings { stepping: Stepping::VoxelExit, ..settings };
        let runs =
            maps.iter().map(|(name, map)| (*name, map, settings)).chain(maps.iter().filter_map(|(name, map)| {
                EXIT_NAMES.iter().find(|(of, _)| of == name).map(|(_, exit_name)| (*exit_name, map, exit))
            }));
        for (name, map, settings) in runs {
            let (mut steps, mut exhausted) = (0_u64, 0);
            for &(origin, direction) in &rays {
                let out = trace(map, None, origin, direction, settings);
                steps += u64::from(out.steps);
                exhausted += usize::from(out.exhausted);
            }
            rows.push(StepsRow {
                mesostructure,
                map: name,
                angle_deg: angle,
                mean_steps: steps as f64 / rays.len() as f64,
                exhausted,
                rays: rays.len(),
            });
        }
    }
    if rows.is_empty() {
        return Err("no maps to trace".to_owned());
    }
    Ok(rows)
}

/// Writes `ddm_steps_vs_angle.csv` and `.png` into `out` and prints the ratio of the DDM
/// 4×1's steps to the plain map's per angle.
pub fn write(out: &Path, rows: &[StepsRow]) -> Result<(), String> {
    let mut csv = String::from("mesostructure,map,angle_deg,mean_steps,exhausted,rays,steps_over_dm\n");
    let dm_steps = |row: &StepsRow| {
        rows.iter()
            .find(|r| r.mesostructure == row.mesostructure && r.angle_deg == row.angle_deg && r.map == "DM")
            .map_or(f64::NAN, |r| r.mean_steps)
    };
    for row in rows {
        writeln!(
            csv,
            "{},{},{},{:.4},{},{},{:.4}",
            row.mesostructure,
            row.map,
            row.angle_deg,
            row.mean_steps,
            row.exhausted,
            row.rays,
            row.mean_steps / dm_steps(row)
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
        for angle in ANGLES_DEG {
            print!("{angle:>7}");
        }
        println!();
        for structure in &structures {
            print!("{structure:<12}");
            for angle in ANGLES_DEG {
                let ratio = rows
                    .iter()
                    .find(|r| r.mesostructure == *structure && r.angle_deg == angle && r.map == map)
                    .map_or(f64::NAN, |r| r.mean_steps / dm_steps(r));
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
