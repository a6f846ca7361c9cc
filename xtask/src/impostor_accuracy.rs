//! `cargo xtask impostor-accuracy [OUT_DIR] [--quick] [--obj PATH]...`: SSIM and RMSE of octahedral
//! impostors against the mesh (Michel & Boubekeur 2020, Fig. 13) for the four procedural
//! grains, every `(n, p)`, the three sampling modes and two screen sizes; CSV + charts, and
//! per grain a strip `mesh | planar | spherical | mixed` of 16 views (the paper's Fig. 12).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use grain_impostor::accuracy::{
    AccuracySweep, SweepRow, SweepSettings, SweepTiming, rows_to_csv, sampling_mode_name, view_layout_name,
};
use grain_impostor::atlas_gpu::AtlasTextures;
use grain_impostor::bake::{BakeSettings, Baker, Progress};
use grain_mesh::{Ball, CoffeeBean, GrainMesh, HexNut, SandGrain, load_obj};
use octahedral_map::{SamplingMode, ViewLayout};
use plotters::prelude::*;

use crate::chart::{draw_legend, drawing_error, legend_stroke, render_png};
use crate::cli::Args;

const MIB: f64 = 1024.0 * 1024.0;

fn mode_colour(mode: SamplingMode) -> RGBColor {
    match mode {
        SamplingMode::Planar => RGBColor(31, 119, 180),
        SamplingMode::Spherical => RGBColor(44, 160, 44),
        SamplingMode::Mixed => RGBColor(214, 39, 40),
        SamplingMode::MixedSmooth => RGBColor(148, 103, 189),
    }
}

/// The procedural grains (ball and bean; with rock and nut unless `quick`) and the OBJ files.
pub(crate) fn grains(quick: bool, objs: &[PathBuf]) -> Result<Vec<(String, GrainMesh)>, String> {
    let error = |e: grain_mesh::MeshError| e.to_string();
    let mut grains = vec![
        ("ball".to_owned(), Ball::default().mesh().map_err(error)?),
        ("bean".to_owned(), CoffeeBean::default().mesh().map_err(error)?),
    ];
    if !quick {
        grains.push(("rock".to_owned(), SandGrain::default().mesh().map_err(error)?));
        grains.push(("nut".to_owned(), HexNut::default().mesh().map_err(error)?));
    }
    for path in objs {
        let name = path.file_stem().map_or_else(|| "grain".into(), |s| s.to_string_lossy().into_owned());
        grains.push((name, load_obj(path).map_err(|e| e.to_string())?));
    }
    Ok(grains)
}

fn write_csv(path: &Path, rows: &[SweepRow]) -> Result<(), String> {
    std::fs::write(path, rows_to_csv(rows)).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// The upper envelope (best SSIM at or below each memory size) of `points` sorted by memory.
fn upper_envelope(mut points: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut envelope: Vec<(f64, f64)> = Vec::new();
    for point in points {
        if envelope.last().is_none_or(|last| point.1 > last.1) {
            envelope.push(point);
        }
    }
    envelope
}

fn draw_chart(path: &Path, rows: &[SweepRow], diameter: f32, grain_names: &[String]) -> Result<(), String> {
    render_png(path, (1400, 1000), |root| {
        let e = drawing_error;
        let root = root
            .titled(
                &format!("Impostor SSIM vs atlas memory (grains {diameter} px wide; dots: every (n, p), lines: best per memory)"),
                ("sans-serif", 26),
            )
            .map_err(e)?;
        let panels = root.split_evenly((2, grain_names.len().div_ceil(2).max(1)));
        for (panel, grain) in panels.iter().zip(grain_names) {
            let mine: Vec<&SweepRow> =
                rows.iter().filter(|r| &r.grain == grain && r.apparent_diameter == diameter).collect();
            let (min_ssim, max_mib, min_mib) = mine.iter().fold((1.0_f64, 0.1_f64, f64::MAX), |(s, hi, lo), r| {
                let mib = r.atlas_bytes as f64 / MIB;
                (s.min(r.error.ssim), hi.max(mib), lo.min(mib))
            });
            let y_low = (min_ssim - 0.02).clamp(0.0, 0.99);
            let mut chart = ChartBuilder::on(panel)
                .caption(grain, ("sans-serif", 22))
                .margin(12)
                .x_label_area_size(45)
                .y_label_area_size(60)
                .build_cartesian_2d((min_mib.min(max_mib) * 0.8..max_mib * 1.25).log_scale(), y_low..1.0)
                .map_err(e)?;
            chart
                .configure_mesh()
                .x_desc("atlas memory, MiB (full mips, log scale)")
                .y_desc("SSIM against the mesh")
                .label_style(("sans-serif", 15))
                .draw()
                .map_err(e)?;
            for mode in SamplingMode::ALL {
                let colour = mode_colour(mode);
                let points: Vec<(f64, f64)> = mine
                    .iter()
                    .filter(|r| r.mode == mode && r.layout == ViewLayout::Listing1)
                    .map(|r| (r.atlas_bytes as f64 / MIB, r.error.ssim))
                    .collect();
                chart.draw_series(points.iter().map(|&p| Circle::new(p, 3, colour.filled()))).map_err(e)?;
                chart
                    .draw_series(LineSeries::new(upper_envelope(points), colour.stroke_width(2)))
                    .map_err(e)?
                    .label(sampling_mode_name(mode))
                    .legend(legend_stroke(colour, 3, 20));
            }
            let compact: Vec<(f64, f64)> = mine
                .iter()
                .filter(|r| r.mode == SamplingMode::Mixed && r.layout == ViewLayout::Compact)
                .map(|r| (r.atlas_bytes as f64 / MIB, r.error.ssim))
                .collect();
            // A lighter red than mixed sampling's: the same mode, another layout.
            let colour = RGBColor(240, 140, 140);
            chart.draw_series(compact.iter().map(|&p| Cross::new(p, 4, colour.stroke_width(1)))).map_err(e)?;
            chart
                .draw_series(LineSeries::new(upper_envelope(compact), colour.stroke_width(1)))
                .map_err(e)?
                .label("mixed, compact layout (no duplicated equator)")
                .legend(legend_stroke(colour, 1, 20));
            draw_legend(&mut chart, 16, SeriesLabelPosition::LowerRight)?;
        }
        Ok(())
    })
}

/// Timed cloud passes per configuration (the fastest is charted).
const TIMED_PASSES: u32 = 5;

/// A configuration's short label on the time chart: `n8 p64 mixed` (`, compact` for the
/// compact layout).
fn configuration_label(r: &SweepRow) -> String {
    let layout = if r.layout == ViewLayout::Compact { ", compact" } else { "" };
    format!("n{} p{} {}{layout}", r.subdivisions, r.texels, sampling_mode_name(r.mode))
}

/// SSIM loss (1 − SSIM) against the cloud pass's time for every configuration at `diameter`,
/// one panel per grain, with the Pareto front (`model_select::pareto_front`) drawn and its
/// configurations labelled; `time_axis` names the adapter and the clock.
fn draw_time_chart(
    path: &Path,
    rows: &[SweepRow],
    diameter: f32,
    grain_names: &[String],
    time_axis: &str,
) -> Result<(), String> {
    render_png(path, (1400, 1000), |root| {
        let e = drawing_error;
        let root = root
            .titled(
                &format!(
                    "Impostor error vs time (grains {diameter} px wide; dots: every (n, p, mode), crosses: compact layout, black: Pareto front)"
                ),
                ("sans-serif", 22),
            )
            .map_err(e)?;
        let panels = root.split_evenly((2, grain_names.len().div_ceil(2).max(1)));
        for (panel, grain) in panels.iter().zip(grain_names) {
            let mine: Vec<(&SweepRow, f64, f64)> = rows
                .iter()
                .filter(|r| &r.grain == grain && r.apparent_diameter == diameter)
                .filter_map(|r| Some((r, r.cloud_ms?, 1.0 - r.error.ssim)))
                .filter(|(_, ms, _)| ms.is_finite() && *ms > 0.0)
                .collect();
            if mine.is_empty() {
                return Err(format!("{}: no timed configuration of {grain} at {diameter} px", path.display()));
            }
            let (lo_ms, hi_ms, hi_loss) = mine
                .iter()
                .fold((f64::MAX, 0.0_f64, 0.0_f64), |(a, b, c), &(_, ms, loss)| (a.min(ms), b.max(ms), c.max(loss)));
            let mut chart = ChartBuilder::on(panel)
                .caption(grain, ("sans-serif", 22))
                .margin(12)
                .x_label_area_size(45)
                .y_label_area_size(60)
                .build_cartesian_2d(lo_ms * 0.9..hi_ms * 1.1, 0.0..(hi_loss * 1.1).max(1e-3))
                .map_err(e)?;
            chart
                .configure_mesh()
                .x_desc(time_axis)
                .y_desc("1 − SSIM against the mesh")
                .x_labels(8)
                .y_labels(8)
                .x_label_formatter(&|ms| format!("{ms:.3}"))
                .y_label_formatter(&|loss| format!("{loss:.3}"))
                .label_style(("sans-serif", 14))
                .draw()
                .map_err(e)?;
            for mode in SamplingMode::ALL {
                let colour = mode_colour(mode);
                let of_mode = |layout| {
                    mine.iter()
                        .filter(move |(r, ..)| r.mode == mode && r.layout == layout)
                        .map(|&(_, ms, loss)| (ms, loss))
                };
                chart
                    .draw_series(of_mode(ViewLayout::Listing1).map(|p| Circle::new(p, 4, colour.filled())))
                    .map_err(e)?
                    .label(sampling_mode_name(mode))
                    .legend(legend_stroke(colour, 3, 20));
                chart
                    .draw_series(of_mode(ViewLayout::Compact).map(|p| Cross::new(p, 5, colour.stroke_width(2))))
                    .map_err(e)?;
            }
            let points: Vec<(f64, f64)> = mine.iter().map(|&(_, ms, loss)| (ms, loss)).collect();
            let front = model_select::pareto_front(&points);
            chart
                .draw_series(LineSeries::new(front.iter().map(|&i| points[i]), BLACK.stroke_width(2)))
                .map_err(e)?
                .label("Pareto front")
                .legend(legend_stroke(BLACK, 2, 20));
            chart
                .draw_series(front.iter().map(|&i| {
                    EmptyElement::at(points[i])
                        + Text::new(configuration_label(mine[i].0), (6, -14), ("sans-serif", 13).into_font())
                }))
                .map_err(e)?;
            draw_legend(&mut chart, 15, SeriesLabelPosition::UpperRight)?;
        }
        Ok(())
    })
}

/// The markdown table of SSIM at `(n, p)` for every grain, mode and diameter.
fn table(rows: &[SweepRow], n: u32, p: u32) -> String {
    let mut out = format!(
        "SSIM (RMSE) at n = {n}, p = {p}\n\n| grain | px | planar | spherical | mixed | mixed, smooth (GrainViewer) |\n|---|---|---|---|---|---|\n"
    );
    let mut keys: Vec<(String, u32)> = Vec::new();
    let rows: Vec<&SweepRow> = rows.iter().filter(|r| r.layout == ViewLayout::Listing1).collect();
    for r in rows.iter().filter(|r| r.subdivisions == n && r.texels == p) {
        let key = (r.grain.clone(), r.apparent_diameter as u32);
        if !keys.contains(&key) {
            keys.push(key);
        }
    }
    for (grain, diameter) in keys {
        let _ = write!(out, "| {grain} | {diameter} |");
        for mode in SamplingMode::ALL {
            let cell = rows.iter().find(|r| {
                r.grain == grain
                    && r.apparent_diameter as u32 == diameter
                    && r.mode == mode
                    && r.subdivisions == n
                    && r.texels == p
            });
            match cell {
                Some(r) => {
                    let _ = write!(out, " {:.4} ({:.4}) |", r.error.ssim, r.error.rmse);
                }
                None => out += " – |",
            }
        }
        out += "\n";
    }
    out
}

/// Saves, side by side, the mesh reference and the impostor renders of the three modes
/// (16 views) at `(n, p, diameter)`: the paper's Fig. 12 for our grains.
fn save_strip(
    sweep: &AccuracySweep,
    gpu: &gpu_harness::Gpu,
    mesh: &GrainMesh,
    (n, p, diameter): (u32, u32, f32),
    path: &Path,
) -> Result<(), String> {
    let error = |e: grain_impostor::accuracy::SweepError| e.to_string();
    let scene = AccuracySweep::scene(mesh, 16, diameter).map_err(error)?;
    let bake = BakeSettings { progress: Progress::Hidden, ..BakeSettings::new(n, p) };
    let atlas = Baker::new(&gpu.device)
        .map_err(|e| e.to_string())?
        .bake(&gpu.device, &gpu.queue, mesh, &bake)
        .map_err(|e| e.to_string())?;
    let textures = AtlasTextures::upload(&gpu.device, &gpu.queue, &atlas).map_err(|e| e.to_string())?;
    let mut images = vec![sweep.reference(&gpu.device, &gpu.queue, mesh, &scene).map_err(error)?];
    for mode in SamplingMode::ALL {
        images.push(sweep.impostor(&gpu.device, &gpu.queue, &atlas, &textures, &scene, mode).map_err(error)?);
    }
    let (width, height) = scene.size;
    let mut strip = image::RgbaImage::new(width * images.len() as u32, height);
    for (k, image) in images.iter().enumerate() {
        image::imageops::replace(&mut strip, image, i64::from(k as u32 * width), 0);
    }
    strip.save(path).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// The command's settings: `[OUT_DIR] [--quick] [--obj PATH]...`.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// Where the files go.
    pub out: PathBuf,
    /// Two grains and a small sweep.
    pub quick: bool,
    /// Grains loaded from OBJ files, besides the procedural ones.
    pub objs: Vec<PathBuf>,
}

impl Options {
    /// The options of `args`.
    pub fn from_args(args: &Args<'_>) -> Self {
        Self {
            out: args.out_dir(),
            quick: args.flag("quick"),
            objs: args.values("obj").into_iter().map(PathBuf::from).collect(),
        }
    }
}

/// Runs the experiment (each `--obj` adds a grain loaded from an OBJ file).
pub fn run(args: &Args<'_>) -> Result<(), String> {
    let Options { out, quick, objs } = Options::from_args(args);
    std::fs::create_dir_all(&out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let settings = if quick {
        SweepSettings {
            subdivisions: vec![4, 8],
            texels: vec![32, 64],
            modes: SamplingMode::ALL.to_vec(),
            layouts: vec![ViewLayout::Listing1, ViewLayout::Compact],
            view_count: 16,
            apparent_diameters: vec![32.0],
            timing: None,
        }
    } else {
        SweepSettings::full()
    };
    let grains = grains(quick, &objs)?;
    let gpu = gpu_harness::Gpu::new().map_err(|e| e.to_string())?;
    println!("impostor accuracy on {}", gpu.describe());
    // Timestamps only where they bracket the work (not on a software adapter).
    let clock = gpu.timing_source();
    let settings = SweepSettings { timing: Some(SweepTiming { passes: TIMED_PASSES, clock }), ..settings };
    let sweep = AccuracySweep::new(&gpu.device).map_err(|e| e.to_string())?;
    let start = Instant::now();
    let rows = sweep
        .run(&gpu.device, &gpu.queue, &grains, &settings, |r| {
            println!(
                "{:>5} n={:<2} p={:<3} {:>9} {:>7} {:>3} px  SSIM {:.4}  RMSE {:.4}  {:.2} MiB  {:.3} ms  [{:.0} s]",
                r.grain,
                r.subdivisions,
                r.texels,
                sampling_mode_name(r.mode),
                view_layout_name(r.layout),
                r.apparent_diameter,
                r.error.ssim,
                r.error.rmse,
                r.atlas_bytes as f64 / MIB,
                r.cloud_ms.unwrap_or(f64::NAN),
                start.elapsed().as_secs_f64()
            );
        })
        .map_err(|e| e.to_string())?;
    let csv = out.join("impostor_accuracy.csv");
    write_csv(&csv, &rows)?;
    println!("wrote {}", csv.display());
    let names: Vec<String> = grains.iter().map(|(name, _)| name.clone()).collect();
    for &diameter in &settings.apparent_diameters {
        let path = out.join(format!("impostor_ssim_vs_memory_{diameter}px.png"));
        draw_chart(&path, &rows, diameter, &names)?;
        println!("wrote {}", path.display());
        let path = out.join(format!("impostor_ssim_vs_time_{diameter}px.png"));
        let axis = format!("cloud pass ms on {}, {} (fastest of {TIMED_PASSES})", gpu.describe(), clock.name());
        draw_time_chart(&path, &rows, diameter, &names, &axis)?;
        println!("wrote {}", path.display());
    }
    let (n, p) = if quick { (8, 64) } else { (8, 128) };
    let diameter = settings.apparent_diameters.iter().copied().fold(0.0, f32::max);
    for (name, mesh) in &grains {
        let path = out.join(format!("impostor_{name}_n{n}_p{p}_{diameter}px.png"));
        save_strip(&sweep, &gpu, mesh, (n, p, diameter), &path)?;
        println!("wrote {}", path.display());
    }
    let summary = table(&rows, n, p);
    std::fs::write(out.join("impostor_accuracy_n8.md"), &summary).map_err(|e| e.to_string())?;
    println!("\n{summary}");
    Ok(())
}
