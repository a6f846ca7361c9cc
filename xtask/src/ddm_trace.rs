//! `cargo xtask ddm-trace [OUT_DIR] [--quick] [--size WxHxD] [--resolution WxH] [--timing-rounds N] [--watertight-subdivision N]
//! [--obj PATH | --height-map PNG] [--scale S | --fit-slab] [--height H] [--periodic | --clamp]`: Mehra & Kumar's
//! Tables 1–3, measured by `ddm_experiments::trace_tables` (24×24×8 voxel tiles and 192×144
//! rays by default, 12×12×6 and 96×72 with `--quick`, any grid with `--size`, any view with
//! `--resolution`); this command writes the rows, images and charts.
//! With `--obj` or `--height-map`, on the user's tile instead of the five procedural ones
//! ([`crate::ddm_input`] says what the coordinates mean and what is checked; relief
//! mapping runs on height maps only). With `--clamp` the tile stands alone for the maps,
//! the patches, both tracers and the truth (the mesh's first hit without its copies), and
//! relief mapping, whose height map wraps, is left out.
//!
//! For each mesostructure (maze, bricks: height fields; beads, ball, chain mail: not) one
//! perspective view is traced per pixel with every `ddm_experiments::TraceMethod` (plain
//! DM, DDMs, DDM 4×1 + patches, voxel-exit stepping, relief mapping: the library's
//! `trace_tables` documentation says which is which) on the CPU and in the WGSL compute
//! pass, and compared with the exact first hit of the original mesh.
//!
//! Writes to `OUT_DIR` (default `target/ddm-trace`):
//! - `ddm_trace_methods.csv` (Tables 1/2): steps per ray (mean, max), hit error in voxels
//!   against the mesh (mean, max, share within 1e-3 voxel of the pixels where both hit and
//!   of all pixels the mesh covers), holes (mesh hit, method missed), false hits, CPU
//!   rays/s (one thread, fastest of 5 passes), GPU time of the compute pass (fastest of 5
//!   dispatches; timestamps, lavapipe here) and how many rays' GPU results differ from the
//!   CPU's; `gross` counts hits more than 0.5 voxel from the truth (a ray through a hole
//!   of the surface that hits something behind it);
//! - `ddm_trace_compression.csv` (Table 3): each DDM method on raw and compressed maps
//!   (blocks of 4): hit/miss differences, largest hit-point difference, steps, time ratio
//!   compressed / raw (CPU: median of 15 interleaved pairs of passes; GPU: timestamps);
//!   for the rows that step by the stored distance, the same again with the compressed
//!   maps traced with block cells (`ddm_tracer::Stepping::BlockCells`: a block without
//!   surface crossed in one step, beyond the paper; on raw maps the paper's rule);
//! - `ddm_trace_reference.csv`: each method against the tile's own surface
//!   (`ddm_experiments::reference`: analytic spheres and tori, the height fields'
//!   triangles; not for a user's OBJ): |SDF(hit)| p50/p99/max (voxels), the normal's angle
//!   p50/p99 (degrees), and leaks (rays deeper than τ = 2 × the method's p99 into the solid
//!   before its hit or exit);
//! - `ddm_trace_patches.csv`: per patch construction, the voxels kept as quadrics and as
//!   triangles, the patch count and the bytes the tracer reads;
//! - `ddm_adaptive_budget.csv`: the adaptive patches at error budgets from 0.3 to 1e-3
//!   voxel: voxels per representation, bytes, hit error against the mesh, holes, speed
//!   (one pass);
//! - `ddm_steps_vs_angle.csv`, `ddm_steps_vs_angle.png`: mean sphere-tracing steps of each
//!   map against the view angle (see `ddm_steps`);
//! - `ddm_trace_error_vs_time.png`: mean hit error against CPU time per ray;
//! - `<mesostructure>_<method>.png`: the view shaded from the hit normals (and `_truth`).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use ddm_experiments::gpu::GpuTracer;
use ddm_experiments::reference::ReferenceSurface;
use ddm_experiments::stats::TraceStats;
use ddm_experiments::steps::StepsRow;
use ddm_experiments::trace_tables::{
    BudgetRow, CompressionRow, MethodRow, PatchRow, SteppingComparison, TraceMethod, TraceScene, TraceTablesSettings,
};
use ddm_experiments::view::View;
use glam::Vec3;
use gpu_harness::Gpu;
use plotters::prelude::*;

use crate::chart::{draw_legend, drawing_error, legend_stroke, render_png};
use crate::cli::{Args, grid_size, positive};
use crate::ddm_input::{self, Tile, TileSource};

/// GPU dispatches per method; its time is the fastest.
const GPU_DISPATCHES: usize = 5;

/// The command's settings.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// Where the files go.
    pub out: PathBuf,
    /// The tables' settings.
    pub settings: TraceTablesSettings,
    /// The user's tile, else the procedural ones.
    pub tile: Option<TileSource>,
}

impl Options {
    /// `[OUT_DIR] [--quick] [--size WxHxD] [--resolution WxH] [--timing-rounds N]
    /// [--watertight-subdivision N]` (`--size` replaces the tile, not the camera;
    /// `--resolution` the view's rays; `--timing-rounds` the rounds of Table 3's interleaved
    /// time ratio; `--watertight-subdivision` the watertight patches' cells per voxel and
    /// axis, 1 to 8) and the tile flags of [`crate::ddm_input`].
    pub fn from_args(args: &Args<'_>) -> Result<Self, String> {
        let mut settings = if args.flag("quick") { TraceTablesSettings::quick() } else { TraceTablesSettings::full() };
        if let Some(dims) = args.parse_value("size", grid_size)? {
            settings.dims = dims;
        }
        if let Some((width, height)) = args.parse_value("resolution", crate::cli::resolution)? {
            (settings.width, settings.height) = (width, height);
        }
        if let Some(rounds) = args.parse_value("timing-rounds", positive::<usize>)? {
            settings.ratio_rounds = rounds;
        }
        if let Some(cells) = args.parse_value("watertight-subdivision", positive::<u32>)? {
            if cells > ddm_tracer::MAX_WATERTIGHT_SUBDIVISION {
                return Err(format!(
                    "--watertight-subdivision: {cells} is above the limit of {}",
                    ddm_tracer::MAX_WATERTIGHT_SUBDIVISION
                ));
            }
            settings.watertight_subdivision = cells;
        }
        let tile = TileSource::from_args(args)?;
        settings.map_settings.periodic_xy = ddm_input::periodic_from_args(args, tile.as_ref())?;
        Ok(Self { out: args.out_dir(), settings, tile })
    }
}

/// The CSV files and chart data, filled structure by structure.
struct Tables {
    methods: String,
    compression: String,
    reference: String,
    patches: String,
    budgets: String,
    steps: Vec<StepsRow>,
    /// `(mesostructure, method, µs per ray, mean error)`.
    chart_points: Vec<(&'static str, &'static str, f64, f64)>,
    /// How the GPU pass is timed (`timestamps` or `wall clock`).
    timing_name: &'static str,
    /// The chart's time: the GPU pass per ray (`Some(rays per view)`, on an adapter whose
    /// timestamps bracket the work) or the CPU tracer's (`None`: a software adapter).
    gpu_rays: Option<f64>,
    /// Methods without a GPU pass, left off a GPU-time chart.
    uncharted: Vec<&'static str>,
}

impl Tables {
    fn new(timing_name: &'static str, gpu_rays: Option<f64>) -> Self {
        Self {
            methods: String::from(
                "mesostructure,method,mean_steps,max_steps,exhausted,truth_hits,both_hit,holes,false_hits,gross_over_0.5_voxel,mean_error_voxel,max_error_voxel,within_1e-3_of_both_pct,within_1e-3_of_truth_pct,cpu_rays_per_s,gpu_ms,gpu_timing,gpu_differs_from_cpu\n",
            ),
            compression: String::from(
                "mesostructure,method,block,efficiency,raw_mean_steps,compressed_mean_steps,hit_miss_differ,points_differ_over_1e-5_voxel,max_point_difference_voxel,cpu_time_ratio,gpu_time_ratio,block_cells_mean_steps,block_cells_hit_miss_differ,block_cells_points_differ_over_1e-5_voxel,block_cells_max_point_difference_voxel,block_cells_cpu_time_ratio\n",
            ),
            reference: String::from(
                "mesostructure,method,hits,sdf_p50_voxel,sdf_p99_voxel,sdf_max_voxel,normal_p50_deg,normal_p99_deg,leak_tau_voxel,leaks,leak_search_unfinished\n",
            ),
            patches: String::from(
                "mesostructure,patches,quadric_voxels,triangle_voxels,voxels_without_patch,patch_count,bytes\n",
            ),
            budgets: String::from(
                "mesostructure,budget_voxel,quadric_voxels,triangle_voxels,bytes,mean_steps,holes,false_hits,mean_error_voxel,max_error_voxel,within_1e-3_of_truth_pct,cpu_rays_per_s_one_pass\n",
            ),
            steps: Vec::new(),
            chart_points: Vec::new(),
            timing_name,
            gpu_rays,
            uncharted: Vec::new(),
        }
    }

    fn patch_row(&mut self, r: &PatchRow) -> Result<(), String> {
        writeln!(
            self.patches,
            "{},{},{},{},{},{},{}",
            r.mesostructure,
            r.patches.name(),
            r.quadric_voxels,
            r.triangle_voxels,
            r.voxels_without_patch,
            r.patch_count,
            r.bytes
        )
        .map_err(|e| e.to_string())
    }

    fn budget_row(&mut self, r: &BudgetRow) -> Result<(), String> {
        let s = &r.stats;
        writeln!(
            self.budgets,
            "{},{},{},{},{},{:.3},{},{},{:e},{:e},{:.3},{:.0}",
            r.mesostructure,
            r.budget,
            r.quadric_voxels,
            r.triangle_voxels,
            r.bytes,
            s.mean_steps,
            s.holes,
            s.false_hits,
            s.mean_error,
            s.max_error,
            s.within_of_truth_percent(),
            r.cpu_rays_per_second
        )
        .map_err(|e| e.to_string())
    }

    fn compression_row(&mut self, r: &CompressionRow) -> Result<(), String> {
        let columns = |c: &SteppingComparison| {
            let d = &c.differences;
            format!("{},{},{:e},{:.3}", d.hit_miss, d.moved, d.max_distance, c.cpu_time_ratio)
        };
        let block_cells =
            r.block_cells.map_or_else(|| String::from(",,,,"), |c| format!("{:.3},{}", c.mean_steps, columns(&c)));
        let gpu_ratio = r.gpu_time_ratio.map_or_else(|| "n/a".to_owned(), |ratio| format!("{ratio:.3}"));
        writeln!(
            self.compression,
            "{},{},{},{:.3},{:.3},{:.3},{},{gpu_ratio},{block_cells}",
            r.mesostructure,
            r.method.name(),
            r.block,
            r.efficiency,
            r.raw_mean_steps,
            r.compressed.mean_steps,
            columns(&r.compressed)
        )
        .map_err(|e| e.to_string())
    }

    fn method_row(&mut self, row: &MethodRow) -> Result<(), String> {
        let s = &row.stats;
        let (gpu_ms, gpu_differs) = gpu_columns(row);
        writeln!(
            self.methods,
            "{},{},{:.4},{},{},{},{},{},{},{},{:e},{:e},{:.3},{:.3},{:.0},{gpu_ms},{},{gpu_differs}",
            row.mesostructure,
            row.method.name(),
            s.mean_steps,
            s.max_steps,
            s.exhausted,
            s.truth_hits,
            s.both_hit,
            s.holes,
            s.false_hits,
            s.gross,
            s.mean_error,
            s.max_error,
            s.within_of_both_percent(),
            s.within_of_truth_percent(),
            row.cpu_rays_per_second,
            if row.gpu.is_some() { self.timing_name } else { "n/a" }
        )
        .map_err(|e| e.to_string())?;
        if let Some(r) = &row.reference {
            writeln!(
                self.reference,
                "{},{},{},{:e},{:e},{:e},{:.3},{:.3},{:e},{},{}",
                row.mesostructure,
                row.method.name(),
                r.hits,
                r.p50,
                r.p99,
                r.max,
                r.normal_p50,
                r.normal_p99,
                r.tau,
                r.leaks,
                r.unfinished
            )
            .map_err(|e| e.to_string())?;
        }
        let micros_per_ray = match (self.gpu_rays, row.gpu) {
            (None, _) => Some(1e6 / row.cpu_rays_per_second),
            (Some(rays), Some(gpu)) => Some(gpu.seconds * 1e6 / rays),
            (Some(_), None) => None,
        };
        match micros_per_ray {
            Some(time) => self.chart_points.push((row.mesostructure, row.method.name(), time, s.mean_error.max(1e-7))),
            None if !self.uncharted.contains(&row.method.name()) => self.uncharted.push(row.method.name()),
            None => {}
        }
        Ok(())
    }
}

/// The GPU columns of a method row: milliseconds and rays that differ from the CPU.
fn gpu_columns(row: &MethodRow) -> (String, String) {
    row.gpu.map_or(("n/a".to_owned(), "n/a".to_owned()), |g| (format!("{:.3}", g.seconds * 1e3), g.differs.to_string()))
}

/// Runs the experiment.
pub fn run(args: &Args<'_>) -> Result<(), String> {
    let Options { out, settings, tile } = Options::from_args(args)?;
    let (dims, width, height) = (settings.dims, settings.width, settings.height);
    let tiles = ddm_input::tiles(tile.as_ref(), dims, settings.map_settings.periodic_xy)?;
    std::fs::create_dir_all(&out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let gpu = Gpu::new().map_err(|e| e.to_string())?;
    println!(
        "DDM tracing (Tables 1-3): {}x{}x{} voxels per tile, {width}x{height} rays, {}, GPU: {}",
        dims.x,
        dims.y,
        dims.z,
        ddm_input::describe(tile.as_ref()),
        gpu.describe()
    );
    if gpu.is_software() {
        println!("(GPU times are from a software rasterizer's compute: lavapipe on the CPU, not a GPU)");
    }
    let tracer = GpuTracer::new(&gpu, GPU_DISPATCHES).map_err(|e| e.to_string())?;
    // The chart's time is the GPU's where its timestamps bracket the work, else the CPU's.
    let gpu_rays =
        (gpu.timing_source() == gpu_harness::TimingSource::Timestamps).then_some(f64::from(width) * f64::from(height));
    let mut tables = Tables::new(tracer.timing_name(), gpu_rays);
    let time_axis = match gpu_rays {
        Some(_) => format!("GPU µs per ray (timestamps, passes of {} rays) on {}", width * height, gpu.describe()),
        None => format!("CPU µs per ray, one thread (the adapter is software: {})", gpu.describe()),
    };
    for tile in tiles {
        trace_structure(tile, &settings, &tracer, &out, &mut tables)?;
    }
    write_tables(&out, &settings, &tables, &time_axis)
}

/// Every table's rows of one structure, its images, and its printed method table.
fn trace_structure(
    tile: Tile,
    settings: &TraceTablesSettings,
    tracer: &GpuTracer<'_>,
    out: &Path,
    tables: &mut Tables,
) -> Result<(), String> {
    let error = |e: ddm_experiments::ExperimentError| e.to_string();
    let mut scene =
        TraceScene::from_triangles(tile.name, tile.triangles, tile.height_field, settings).map_err(error)?;
    scene.reference = tile.structure.map(|structure| ReferenceSurface::of(structure, settings.dims));
    let view = &scene.view;
    write_image(&out.join(format!("{}_truth.png", scene.name)), view, &scene.truth.normals)?;
    let patches = &scene.patches;
    println!(
        "\n{} ({} triangles): maps {:.1} s, C0 + fitted patches {:.2} s ({} C0 patches, {} surface voxels without one), triangles + adaptive {:.2} s, watertight {:.2} s ({} patches)",
        scene.name,
        scene.triangles.len(),
        scene.maps_seconds,
        patches.c0_fitted_seconds,
        patches.c0.patches.len(),
        patches.c0.voxels_without_patch,
        patches.triangles_adaptive_seconds,
        patches.watertight_seconds,
        patches.watertight.patches.len()
    );
    for row in scene.patch_rows() {
        tables.patch_row(&row)?;
    }
    for row in scene.budget_rows().map_err(error)? {
        tables.budget_row(&row)?;
    }
    tables.steps.extend(scene.steps_rows().map_err(error)?);
    let mut rows = Vec::new();
    for method in TraceMethod::ALL {
        let Some(result) = scene.run_method(method, Some(tracer)).map_err(error)? else {
            continue;
        };
        if let Some(compression) = &result.compression {
            tables.compression_row(compression)?;
        }
        write_image(&out.join(format!("{}_{}.png", scene.name, image_name(method))), view, &result.normals)?;
        rows.push(result.row);
    }
    print_methods(&rows);
    for row in &rows {
        tables.method_row(row)?;
    }
    Ok(())
}

/// The file-name part of a method's image: `ddm4x1_quadric` for `DDM 4x1 + quadric`,
/// `relief` for relief mapping.
/// A method's part of an image file name (`ddm4x1_adaptive`, `relief`).
pub fn image_name(method: TraceMethod) -> String {
    match method {
        TraceMethod::Relief => "relief".to_owned(),
        _ => method.name().replace(' ', "").replace('+', "_").to_lowercase(),
    }
}

/// Prints one structure's method table (Tables 1/2).
fn print_methods(rows: &[MethodRow]) {
    println!(
        "{:<18} {:>6} {:>5} {:>6} {:>6} {:>6} {:>9} {:>8} {:>8} {:>8} {:>10} {:>9} {:>6}",
        "method",
        "steps",
        "max",
        "holes",
        "false",
        "gross",
        "mean err",
        "max err",
        "<1e-3 %",
        "of truth",
        "CPU ray/s",
        "GPU ms",
        "GPU≠"
    );
    for row in rows {
        let s: &TraceStats = &row.stats;
        let (gpu_ms, gpu_differs) = gpu_columns(row);
        println!(
            "{:<18} {:>6.2} {:>5} {:>6} {:>6} {:>6} {:>9.2e} {:>8.3} {:>8.2} {:>8.2} {:>10.0} {:>9} {:>6}",
            row.method.name(),
            s.mean_steps,
            s.max_steps,
            s.holes,
            s.false_hits,
            s.gross,
            s.mean_error,
            s.max_error,
            s.within_of_both_percent(),
            s.within_of_truth_percent(),
            row.cpu_rays_per_second,
            gpu_ms,
            gpu_differs
        );
    }
}

/// Writes the CSV files and charts, and prints the patch, budget and Table 3 rows.
fn write_tables(out: &Path, settings: &TraceTablesSettings, tables: &Tables, time_axis: &str) -> Result<(), String> {
    let write = |name: &str, text: &str| {
        let path = out.join(name);
        std::fs::write(&path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        println!("wrote {}", path.display());
        Ok::<(), String>(())
    };
    write("ddm_trace_methods.csv", &tables.methods)?;
    write("ddm_trace_compression.csv", &tables.compression)?;
    write("ddm_trace_reference.csv", &tables.reference)?;
    println!("\nEach method against the tile's own surface:\n{}", tables.reference);
    write("ddm_trace_patches.csv", &tables.patches)?;
    write("ddm_adaptive_budget.csv", &tables.budgets)?;
    println!("\nAdaptive patches against the error budget (DDM 4x1):\n{}", tables.budgets);
    println!("\nPatch memory (adaptive: budget {} voxel):\n{}", settings.adaptive_budget, tables.patches);
    crate::ddm_steps::write(out, &tables.steps, &settings.steps.angles_deg)?;
    println!(
        "\nTable 3 (tracing with vs without compression, blocks of {}):\n{}",
        settings.compression_block, tables.compression
    );
    error_chart(&out.join("ddm_trace_error_vs_time.png"), &tables.chart_points, time_axis)?;
    let uncharted = if tables.uncharted.is_empty() {
        String::new()
    } else {
        format!(" (without a GPU pass, not charted: {})", tables.uncharted.join(", "))
    };
    println!("wrote {}: {time_axis}{uncharted}", out.join("ddm_trace_error_vs_time.png").display());
    Ok(())
}

/// Writes the view shaded from each hit's normal (`ddm_experiments::shading`).
fn write_image(path: &Path, view: &View, normals: &[Option<Vec3>]) -> Result<(), String> {
    let image = ddm_experiments::shading::shade_normals(view, normals).map_err(|e| e.to_string())?;
    image::DynamicImage::ImageRgba8(image)
        .to_rgb8()
        .save(path)
        .map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// Each method's colour in the charts (`ddm_steps` uses the maps' entries).
pub const METHOD_COLORS: [(&str, RGBColor); 14] = [
    ("DM", RGBColor(120, 120, 120)),
    ("DDM 2x1", RGBColor(230, 159, 0)),
    ("DDM 4x1", RGBColor(0, 114, 178)),
    ("DDM 8x1", RGBColor(86, 180, 233)),
    ("DDM 4x2", RGBColor(240, 228, 66)),
    ("DDM 4x1 + quadric", RGBColor(213, 94, 0)),
    ("DDM 4x1 + fitted Q", RGBColor(204, 121, 167)),
    ("relief 32+8", RGBColor(0, 158, 115)),
    ("DDM 4x1 + triangles", RGBColor(0, 0, 0)),
    ("DDM 4x1 + adaptive", RGBColor(150, 40, 40)),
    ("DDM 4x1 + watertight", RGBColor(0, 170, 170)),
    ("DM exit", RGBColor(60, 60, 60)),
    ("DDM 4x1 exit", RGBColor(0, 60, 110)),
    ("DDM 4x1 + adaptive exit", RGBColor(90, 20, 20)),
];

/// Mean hit error against time per ray (`time_axis` says whose), one colour per method, one
/// marker per mesostructure, and each mesostructure's Pareto front (`model_select::pareto_front`)
/// drawn with its methods labelled.
fn error_chart(path: &Path, points: &[(&str, &str, f64, f64)], time_axis: &str) -> Result<(), String> {
    let (x_min, x_max) = points.iter().fold((f64::INFINITY, 0.0_f64), |(lo, hi), p| (lo.min(p.2), hi.max(p.2)));
    let (y_min, y_max) = points.iter().fold((f64::INFINITY, 0.0_f64), |(lo, hi), p| (lo.min(p.3), hi.max(p.3)));
    render_png(path, (1200, 700), |root| {
        let mut chart = ChartBuilder::on(root)
            .caption(
                "Hit error vs time per ray, Pareto fronts (maze: disc, bricks: square, beads: triangle, ball: cross, chain mail: ring)",
                ("sans-serif", 20),
            )
            .margin(16)
            .x_label_area_size(48)
            .y_label_area_size(70)
            .build_cartesian_2d((x_min * 0.7..x_max * 1.4).log_scale(), (y_min * 0.5..y_max * 2.0).log_scale())
            .map_err(drawing_error)?;
        chart
            .configure_mesh()
            .x_labels(12)
            .y_labels(12)
            .x_label_formatter(&|x| format!("{x:.2}"))
            .y_label_formatter(&|y| if *y >= 0.01 { format!("{y:.2}") } else { format!("{y:.0e}") })
            .x_desc(time_axis)
            .y_desc("mean hit error (voxels) where both hit")
            .label_style(("sans-serif", 16))
            .draw()
            .map_err(drawing_error)?;
        for &(method, color) in &METHOD_COLORS {
            let mine: Vec<_> = points.iter().filter(|p| p.1 == method).collect();
            let series = mine.iter().map(|p| {
                let at = (p.2, p.3);
                let style = color.filled();
                match p.0 {
                    "maze" => Circle::new(at, 6, style).into_dyn(),
                    "bricks" => {
                        Rectangle::new([(at.0 * 0.97, at.1 * 0.9), (at.0 * 1.03, at.1 * 1.1)], style).into_dyn()
                    }
                    "beads" => TriangleMarker::new(at, 7, style).into_dyn(),
                    "ball" => Cross::new(at, 6, color.stroke_width(3)).into_dyn(),
                    _ => Circle::new(at, 6, color.stroke_width(2)).into_dyn(),
                }
            });
            chart
                .draw_series(series)
                .map_err(drawing_error)?
                .label(method)
                .legend(move |(x, y)| Circle::new((x + 8, y), 5, color.filled()));
        }
        let mut structures: Vec<&str> = Vec::new();
        for p in points {
            if !structures.contains(&p.0) {
                structures.push(p.0);
            }
        }
        for (k, structure) in structures.iter().enumerate() {
            let mine: Vec<_> = points.iter().filter(|p| p.0 == *structure).collect();
            let at: Vec<(f64, f64)> = mine.iter().map(|p| (p.2, p.3)).collect();
            let front = model_select::pareto_front(&at);
            let line = chart
                .draw_series(LineSeries::new(front.iter().map(|&i| at[i]), BLACK.mix(0.5).stroke_width(1)))
                .map_err(drawing_error)?;
            if k == 0 {
                line.label("Pareto front, per structure").legend(legend_stroke(BLACK, 1, 20));
            }
            chart
                .draw_series(front.iter().map(|&i| {
                    EmptyElement::at(at[i]) + Text::new(mine[i].1.to_owned(), (6, -12), ("sans-serif", 11).into_font())
                }))
                .map_err(drawing_error)?;
        }
        draw_legend(&mut chart, 16, SeriesLabelPosition::UpperRight)
    })
}
