//! `cargo xtask svo [OUT_DIR] [--scene NAME | --obj PATH | --height-map PNG] [--zoom K]
//! [--views N] [--pixels N] [--levels L] [--frames N] [--quick]`: the pre-filtered SVO
//! (Heitz & Neyret 2012) of a scene rendered on the GPU along a dolly of `K` octaves
//! (Fig. 8) with every model, each frame against the supersampled truth of the unfiltered
//! surface; the depth-of-field and shadow images of the middle view against theirs; PNGs of
//! every frame beside its truth, `svo_accuracy.csv`, `svo_times.csv`, `svo_effects.csv`,
//! `svo_supersampling.csv` (supersampling itself as a method: the truth's sampling with fewer
//! rays, timed on the CPU, and the octree's finest level supersampled on the tracer's GPU
//! with up to 4 × 4 rays per pixel on a software adapter and 16 × 16 on a hardware one,
//! timed as the tracer, each against the truth; and the truth's own noise floor), and
//! `svo_error_vs_time.png` (ꟻLIP against µs per covered pixel per model and per supersampling
//! rate, each view and the dolly's mean, the Pareto front of the means drawn).
//!
//! `cargo xtask bench-gpu svo` ([`bench()`]) times every model with and without shadows and
//! depth of field at every view and writes `svo.csv`, and the finest voxels supersampled on
//! the same adapter (16 × 16 rays per pixel on a hardware adapter, 4 × 4 on a software one)
//! into `svo_truth.csv`.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use abuffer_mask::MaskTable;
use glam::Vec3;
use gpu_harness::Gpu;
use plotters::prelude::*;
use svo_brick::{BrickSize, VoxelLayout};
use svo_render::accuracy::{AccuracyRow, Comparison, Dolly, DollySettings, compare, dolly_accuracy_with, write_csv};
use svo_render::parallel::threads;
use svo_render::renderer::pack_for;
use svo_render::scene_input::SceneInput;
use svo_render::scenes::Scene;
use svo_render::timing::{BenchSettings, Variant, bench_csv, bench_dolly, frame_work, time_frames, time_voxel_truth};
use svo_render::truth::{TruthSettings, render_source_truth};
use svo_render::{Frame, FrameSettings, GpuRenderer, GpuVoxelTruth};
use svo_tracer::{Camera, Lens, Light, Model, TraceSettings};

use crate::chart::{draw_legend, drawing_error, legend_stroke, render_png};
use crate::cli::{Args, positive};

const BRICK: BrickSize = BrickSize::Eight;
const LAYOUT: VoxelLayout = VoxelLayout::Compact16Fine8;
/// One colour per model, in `Model::ALL` order (the stability charts use them too).
pub const COLOURS: [RGBColor; 4] =
    [RGBColor(200, 30, 30), RGBColor(30, 60, 200), RGBColor(30, 150, 30), RGBColor(200, 140, 0)];

/// The scene of `--scene`, `--obj` or `--height-map` (default `bumpy-sphere`).
pub fn scene_input(args: &Args<'_>) -> SceneInput {
    if let Some(path) = args.value("obj") {
        SceneInput::Obj(path.into())
    } else if let Some(path) = args.value("height-map") {
        SceneInput::HeightMap(path.into())
    } else {
        SceneInput::Named(args.value("scene").unwrap_or("bumpy-sphere").to_owned())
    }
}

/// What both commands set up: the scene, its octree on the GPU, the renderer.
struct Setup {
    gpu: Gpu,
    scene: Scene,
    packed: svo_brick::PackedTree,
    renderer: GpuRenderer,
    voxel: f32,
    size: u32,
}

fn setup(args: &Args<'_>, default_size: u32, default_levels: u32) -> Result<Setup, String> {
    let size = args.parse_value("pixels", positive::<u32>)?.unwrap_or(default_size);
    let levels = args.parse_value("levels", positive::<u32>)?.unwrap_or(default_levels);
    let gpu = Gpu::new().map_err(|e| e.to_string())?;
    let scene = scene_input(args).load().map_err(|e| e.to_string())?;
    let started = Instant::now();
    let tree = scene.build(BRICK, levels).map_err(|e| e.to_string())?;
    let packed = pack_for(&gpu.device, &tree, LAYOUT).map_err(|e| e.to_string())?;
    let table = MaskTable::<4>::paper().ok_or("the paper's mask table cannot be built")?;
    let renderer = GpuRenderer::new(&gpu.device, &packed, &table, (size, size)).map_err(|e| e.to_string())?;
    let voxel = scene.voxel_size(BRICK, levels);
    println!(
        "svo: scene `{}`, {levels} levels of {}³ bricks ({:.0} voxels across), {:.1} MB ({LAYOUT:?}), built in {:.1} s; \
         {size}×{size} px on {}",
        scene.name,
        BRICK.side(),
        scene.domain.size / voxel,
        packed.bytes() as f64 / 1e6,
        started.elapsed().as_secs_f64(),
        gpu.describe()
    );
    Ok(Setup { gpu, scene, packed, renderer, voxel, size })
}

/// The dolly of `--zoom K` octaves (default `octaves`) in `--views N` views, from twice the
/// domain's size.
fn dolly(args: &Args<'_>, setup: &Setup, octaves: f32, views: u32) -> Result<Dolly, String> {
    let octaves = args.parse_value("zoom", positive::<f32>)?.unwrap_or(octaves);
    let views = args.parse_value("views", positive::<u32>)?.unwrap_or(views);
    let far = 2.0 * setup.scene.domain.size;
    Ok(Dolly::towards(&setup.scene, far, octaves, views, setup.size, setup.size))
}

/// The light: above, to the side of and in front of the dolly's target, radius a twentieth
/// of its distance.
fn trace_settings(scene: &Scene, dolly: &Dolly) -> TraceSettings {
    let side = dolly.direction.cross(dolly.up).normalize_or(Vec3::X);
    let offset = (dolly.direction + 0.7 * dolly.up + 0.4 * side).normalize() * (4.0 * scene.domain.size);
    let light = Light { position: scene.target + offset, radius: 0.2 * scene.domain.size, radiance: 3.0 };
    TraceSettings { light, background: Vec3::new(0.05, 0.06, 0.08), ..TraceSettings::default() }
}

fn render(setup: &Setup, camera: &Camera, trace: &TraceSettings) -> Result<Frame, svo_render::RenderError> {
    let mut encoder = setup.gpu.device.create_command_encoder(&Default::default());
    let frame = FrameSettings { camera, settings: trace, exposure: 1.0 };
    setup.renderer.encode(&setup.gpu.queue, &mut encoder, frame)?;
    setup.gpu.queue.submit([encoder.finish()]);
    setup.renderer.read_frame(&setup.gpu)
}

fn save(frame: &Frame, path: &Path) -> Result<(), String> {
    frame.write_png(path, 1.0).map_err(|e| e.to_string())
}

pub fn run(args: &Args<'_>) -> Result<(), String> {
    let quick = args.flag("quick");
    let out = args.out_dir();
    std::fs::create_dir_all(&out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let setup = setup(args, if quick { 64 } else { 128 }, if quick { 4 } else { 5 })?;
    let dolly = dolly(args, &setup, if quick { 4.0 } else { 6.0 }, if quick { 3 } else { 4 })?;
    let frames = args.parse_value("frames", positive::<u32>)?.unwrap_or(if setup.gpu.is_software() { 3 } else { 50 });
    let trace = trace_settings(&setup.scene, &dolly);
    let truth = TruthSettings::for_voxel(setup.voxel, if quick { 3 } else { 4 });
    let settings = DollySettings::new(dolly, trace, truth);
    let source = setup.scene.source.as_ref();

    // Accuracy: the GPU's frames against the truth, view by view.
    let mut frames_kept = Vec::new();
    let mut truths = Vec::new();
    let started = Instant::now();
    let table = dolly_accuracy_with(
        source,
        &setup.packed,
        &settings,
        |camera, trace| {
            let frame = render(&setup, camera, trace)?;
            frames_kept.push(frame.clone());
            Ok(frame)
        },
        |view, frame| truths.push((view, frame.clone())),
    )
    .map_err(|e| e.to_string())?;
    println!("svo: dolly of {} views measured in {:.1} s", dolly.views, started.elapsed().as_secs_f64());
    for (row, frame) in table.rows.iter().zip(&frames_kept) {
        save(frame, &out.join(format!("svo_view{}_{}.png", row.view, row.model.name())))?;
    }
    for (view, truth) in &truths {
        save(truth, &out.join(format!("svo_view{view}_truth.png")))?;
    }
    write_csv(&table, &out.join("svo_accuracy.csv")).map_err(|e| e.to_string())?;

    // GPU time per view and model.
    let mut times = String::from("view,model,median_ms,us_per_covered_pixel,elements_per_pixel,timing\n");
    let mut points: Vec<(Model, u32, f64, f64)> = Vec::new();
    println!(
        "{:>4} {:>9} {:>8} {:>7} {:>7} {:>8} {:>7} {:>9} {:>9} {:>10}",
        "view", "model", "px/voxel", "SSIM", "FLIP", "colour", "drift", "gpu ms", "µs/px", "truth ms"
    );
    for row in &table.rows {
        let camera = dolly.camera(row.view).map_err(|e| e.to_string())?;
        let trace = TraceSettings { model: row.model, ..trace };
        let frame = FrameSettings { camera: &camera, settings: &trace, exposure: 1.0 };
        let timed = time_frames(&setup.gpu, &setup.renderer, frame, 1, frames).map_err(|e| e.to_string())?;
        let read = setup.renderer.read_frame(&setup.gpu).map_err(|e| e.to_string())?;
        let (_, per_pixel, elements, _) = frame_work(&read, timed.median());
        print_row(row, timed.median(), per_pixel);
        let timing = format!("{:?}", timed.source);
        let _ = writeln!(
            times,
            "{},{},{:.5},{:.6},{elements:.3},{timing}",
            row.view,
            row.model.name(),
            timed.median(),
            per_pixel
        );
        if per_pixel.is_finite() {
            points.push((row.model, row.view, per_pixel, row.comparison.flip));
        }
    }
    let path = out.join("svo_times.csv");
    std::fs::write(&path, times).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    for model in Model::ALL {
        println!("  {:>11}: zoom drift {:+.4}", model.name(), table.max_drift(model));
    }
    let sampled = supersampling(&setup, &settings, &truths, frames)?;
    write_supersampling(&sampled, &out.join("svo_supersampling.csv"))?;
    print_equal_error(&sampled, &points);
    effects(&setup, &settings, &out)?;
    let adapter = setup.gpu.adapter_info().name.clone();
    chart(&out.join("svo_error_vs_time.png"), &points, &sampled, &adapter, setup.scene.name)?;
    println!(
        "svo: wrote PNGs, svo_accuracy.csv, svo_times.csv, svo_supersampling.csv, svo_effects.csv, \
         svo_error_vs_time.png to {}",
        out.display()
    );
    Ok(())
}

fn print_row(row: &AccuracyRow, gpu_ms: f64, per_pixel: f64) {
    let c = &row.comparison;
    println!(
        "{:>4} {:>9} {:>8.3} {:>7.4} {:>7.4} {:>8.4} {:>+7.4} {:>9.3} {:>9.4} {:>10.1}",
        row.view,
        row.model.name(),
        row.pixel_voxels,
        c.ssim,
        c.flip,
        c.colour_error,
        row.drift,
        gpu_ms,
        per_pixel,
        row.truth_ms
    );
}

/// Where a supersampled render ran, and of what.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Sampled {
    /// The unfiltered source, on the CPU.
    SourceOnCpu,
    /// The octree's finest level, on the tracer's adapter ([`GpuVoxelTruth`]): what a
    /// renderer without prefiltering computes to anti-alias.
    FinestVoxelsOnGpu,
}

/// One render of the truth's own sampling at one view, against the truth.
struct Supersampled {
    view: u32,
    /// What was sampled, where.
    what: Sampled,
    /// `k`: `k × k` rays per pixel.
    rays_per_axis: u32,
    /// Jittered strata (as the truth), or their centres (the noise-floor render).
    jitter: bool,
    /// Wall clock on the CPU, all cores; or the median GPU frame (as the tracer's).
    ms: f64,
    /// `ms` per pixel the truth covers, in µs.
    per_pixel: f64,
    comparison: Comparison,
}

impl Supersampled {
    /// A rate cheaper than the truth's (a method on the chart), not the noise floor.
    fn is_method(&self) -> bool {
        self.jitter
    }
}

/// `settings` for the GPU voxel truth: `ε` raised to the least that `f32` rays resolve
/// ([`GpuVoxelTruth::min_epsilon`]) where the finest voxel's `10⁻⁴` is below it, and said.
fn gpu_truth_settings(truth: &GpuVoxelTruth, settings: TruthSettings) -> TruthSettings {
    let epsilon = settings.epsilon.max(truth.min_epsilon());
    if epsilon > settings.epsilon {
        println!(
            "  the GPU voxel truth traces with ε = {epsilon:.3e} (f32's least along its rays) instead of {:.3e}",
            settings.epsilon
        );
    }
    TruthSettings { epsilon, ..settings }
}

/// The GPU voxel truth's rates: `k × k` rays per pixel, up to 16 × 16 (the 256 rays per
/// pixel of a GPU ground truth) on a hardware adapter, 4 × 4 on a software one.
fn gpu_rates(software: bool) -> &'static [u32] {
    if software { &[1, 2, 4] } else { &[1, 2, 4, 8, 16] }
}

/// Supersampling as a method, view by view: the truth's sampling of the unfiltered surface
/// with 1 × 1 and 2 × 2 jittered rays per pixel (those below the truth's `k × k`), timed on
/// the CPU, against the truth; the octree's finest level supersampled on the tracer's
/// adapter ([`GpuVoxelTruth`], [`gpu_rates`]), timed as the tracer is, against the truth;
/// and the truth's noise floor: its own `k × k` rays at the strata's centres against the
/// jittered truth (two independent estimates of the same integral: their difference is
/// about √2 times the truth's own error).
fn supersampling(
    setup: &Setup,
    settings: &DollySettings,
    truths: &[(u32, Frame)],
    frames: u32,
) -> Result<Vec<Supersampled>, String> {
    let gpu_truth =
        GpuVoxelTruth::new(&setup.gpu.device, &setup.packed, (setup.size, setup.size)).map_err(|e| e.to_string())?;
    let software = setup.gpu.is_software();
    let reference = settings.truth;
    let mut cases: Vec<TruthSettings> = [1, 2]
        .into_iter()
        .filter(|&k| k < reference.rays_per_axis)
        .map(|k| TruthSettings { rays_per_axis: k, ..reference })
        .collect();
    cases.push(TruthSettings { jitter: false, ..reference });
    let source = setup.scene.source.as_ref();
    let mut out = Vec::new();
    for (view, truth) in truths {
        let camera = settings.dolly.camera(*view).map_err(|e| e.to_string())?;
        let covered = truth.coverage.iter().filter(|&&c| c > 0.0).count();
        for case in &cases {
            let started = Instant::now();
            let frame = render_source_truth(source, setup.scene.domain, &camera, &settings.trace, case)
                .map_err(|e| e.to_string())?;
            let ms = started.elapsed().as_secs_f64() * 1e3;
            let comparison =
                compare(&frame, truth, settings.trace.background, settings.exposure).map_err(|e| e.to_string())?;
            let per_pixel = if covered > 0 { ms * 1e3 / covered as f64 } else { f64::INFINITY };
            out.push(Supersampled {
                view: *view,
                what: Sampled::SourceOnCpu,
                rays_per_axis: case.rays_per_axis,
                jitter: case.jitter,
                ms,
                per_pixel,
                comparison,
            });
        }
        for &k in gpu_rates(software) {
            let case = gpu_truth_settings(&gpu_truth, TruthSettings { rays_per_axis: k, ..reference });
            let (warm_up, timed) = if software { (0, 1) } else { (1, frames.min(3)) };
            let times = time_voxel_truth(&setup.gpu, &gpu_truth, &camera, &settings.trace, &case, warm_up, timed)
                .map_err(|e| e.to_string())?;
            let frame = gpu_truth.read_frame(&setup.gpu).map_err(|e| e.to_string())?;
            let ms = times.median();
            let comparison =
                compare(&frame, truth, settings.trace.background, settings.exposure).map_err(|e| e.to_string())?;
            let per_pixel = if covered > 0 { ms * 1e3 / covered as f64 } else { f64::INFINITY };
            println!(
                "  view {view}: finest voxels {k}×{k} rays on the GPU: {ms:.2} ms, ꟻLIP {:.4}, SSIM {:.4}",
                comparison.flip, comparison.ssim
            );
            out.push(Supersampled {
                view: *view,
                what: Sampled::FinestVoxelsOnGpu,
                rays_per_axis: k,
                jitter: true,
                ms,
                per_pixel,
                comparison,
            });
        }
    }
    Ok(out)
}

fn write_supersampling(rows: &[Supersampled], path: &Path) -> Result<(), String> {
    let mut csv = String::from("view,sampled,rays_per_axis,strata,ms,us_per_covered_pixel,threads,ssim,flip,rmse\n");
    for r in rows {
        let _ = writeln!(
            csv,
            "{},{},{},{},{:.3},{:.6},{},{:.6},{:.6},{:.6}",
            r.view,
            match r.what {
                Sampled::SourceOnCpu => "source (CPU wall clock)",
                Sampled::FinestVoxelsOnGpu => "finest voxels (GPU, as the tracer)",
            },
            r.rays_per_axis,
            if r.jitter { "jittered" } else { "centres (noise floor)" },
            r.ms,
            r.per_pixel,
            threads(),
            r.comparison.ssim,
            r.comparison.flip,
            r.comparison.rmse
        );
    }
    std::fs::write(path, csv).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// Per view: the cheapest supersampling rate whose ꟻLIP is at most the masks' ꟻLIP and its
/// time against the masks' (or, where no rate tried reaches it, a lower bound of the ratio:
/// the largest rate's), beside the truth's noise floor.
fn print_equal_error(sampled: &[Supersampled], points: &[(Model, u32, f64, f64)]) {
    println!(
        "  supersampling (the source on the CPU, {} threads; the finest voxels on the GPU) against the masks on the \
         GPU, at equal ꟻLIP:",
        threads()
    );
    for &(_, view, masks_us, masks_flip) in points.iter().filter(|p| p.0 == Model::Masks) {
        let floor = sampled.iter().find(|r| r.view == view && !r.is_method()).map_or(f64::NAN, |r| r.comparison.flip);
        let line = |what: Sampled| {
            let rates: Vec<&Supersampled> =
                sampled.iter().filter(|r| r.view == view && r.is_method() && r.what == what).collect();
            let reached = rates.iter().find(|r| r.comparison.flip <= masks_flip);
            match (reached, rates.last()) {
                (Some(r), _) => format!(
                    "{k}×{k} rays reach it (ꟻLIP {:.4}) at {:.3}× the masks' time",
                    r.comparison.flip,
                    r.per_pixel / masks_us,
                    k = r.rays_per_axis
                ),
                (None, Some(r)) => format!(
                    "{k}×{k} rays do not (ꟻLIP {:.4}): more than {:.3}× the masks' time",
                    r.comparison.flip,
                    r.per_pixel / masks_us,
                    k = r.rays_per_axis
                ),
                (None, None) => "no rate below the truth's was tried".to_owned(),
            }
        };
        println!(
            "    view {view}: masks ꟻLIP {masks_flip:.4}, {masks_us:.3} µs/px; source on the CPU: {}; finest voxels \
             on the GPU: {}; truth noise floor ꟻLIP {floor:.4}",
            line(Sampled::SourceOnCpu),
            line(Sampled::FinestVoxelsOnGpu)
        );
    }
}

/// Depth of field and soft shadows at the middle view, each against its own truth.
fn effects(setup: &Setup, settings: &DollySettings, out: &Path) -> Result<(), String> {
    let view = settings.dolly.views / 2;
    let pinhole = settings.dolly.camera(view).map_err(|e| e.to_string())?;
    let distance = settings.dolly.distance(view);
    let lens = Lens { aperture: 0.03 * distance, focus: 1.3 * distance };
    let defocused = pinhole.with_lens(lens).map_err(|e| e.to_string())?;
    let shadowed = TraceSettings { shadow_cones: 1, ..settings.trace };
    let shadow_truth = TruthSettings { shadow_rays_per_axis: 3, ..settings.truth };
    let cases = [("dof", defocused, settings.trace, settings.truth), ("shadows", pinhole, shadowed, shadow_truth)];
    let mut csv = String::from("effect,model,ssim,flip,rmse,colour_error,silhouette_bias\n");
    for (name, camera, trace, truth_settings) in cases {
        let source = setup.scene.source.as_ref();
        let truth = render_source_truth(source, setup.scene.domain, &camera, &trace, &truth_settings)
            .map_err(|e| e.to_string())?;
        save(&truth, &out.join(format!("svo_{name}_truth.png")))?;
        for model in [Model::Masks, Model::AlphaBlend] {
            let frame = render(setup, &camera, &TraceSettings { model, ..trace }).map_err(|e| e.to_string())?;
            save(&frame, &out.join(format!("svo_{name}_{}.png", model.name())))?;
            let c = compare(&frame, &truth, trace.background, 1.0).map_err(|e| e.to_string())?;
            println!(
                "  {name} ({}): SSIM {:.4}, FLIP {:.4}, RMSE {:.4}, colour error {:.4}, silhouette bias {:+.4}",
                model.name(),
                c.ssim,
                c.flip,
                c.rmse,
                c.colour_error,
                c.silhouette.bias
            );
            let _ = writeln!(
                csv,
                "{name},{},{:.6},{:.6},{:.6},{:.6},{:.6}",
                model.name(),
                c.ssim,
                c.flip,
                c.rmse,
                c.colour_error,
                c.silhouette.bias
            );
        }
    }
    let path = out.join("svo_effects.csv");
    std::fs::write(&path, csv).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// The points on the lower-left hull of `(time, error)`: none is both slower and worse
/// (`model_select::pareto_front`, infinities left out).
pub fn pareto_front(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let finite: Vec<(f64, f64)> = points.iter().copied().filter(|p| p.0.is_finite() && p.1.is_finite()).collect();
    model_select::pareto_front(&finite).into_iter().map(|i| finite[i]).collect()
}

const SUPERSAMPLING_COLOURS: [RGBColor; 2] = [RGBColor(90, 90, 90), RGBColor(150, 60, 160)];
const FLOOR_GREY: RGBColor = RGBColor(140, 140, 140);
/// The GPU voxel truth's rates, in [`gpu_rates`] order (teal, lightening with the rate).
const VOXEL_SUPERSAMPLING_COLOURS: [RGBColor; 5] = [
    RGBColor(0, 90, 90),
    RGBColor(0, 120, 120),
    RGBColor(0, 150, 150),
    RGBColor(60, 180, 180),
    RGBColor(120, 205, 205),
];

fn chart(
    path: &Path,
    points: &[(Model, u32, f64, f64)],
    sampled: &[Supersampled],
    adapter: &str,
    scene: &str,
) -> Result<(), String> {
    if points.is_empty() {
        return Err("svo: no view covered any pixel, nothing to chart".into());
    }
    let methods: Vec<&Supersampled> = sampled.iter().filter(|r| r.is_method() && r.per_pixel.is_finite()).collect();
    let floors: Vec<f64> = sampled.iter().filter(|r| !r.is_method()).map(|r| r.comparison.flip).collect();
    let (mut x_lo, mut x_hi, mut y_hi) = (f64::INFINITY, 0.0_f64, 0.0_f64);
    let xy = points.iter().map(|p| (p.2, p.3)).chain(methods.iter().map(|r| (r.per_pixel, r.comparison.flip)));
    for (x, y) in xy {
        x_lo = x_lo.min(x);
        x_hi = x_hi.max(x);
        y_hi = y_hi.max(y);
    }
    let (x_lo, x_hi) = (x_lo * 0.8, x_hi * 1.25);
    let caption =
        format!("SVO `{scene}`: error against time (tracer, voxels: {adapter}; source: CPU, {} threads)", threads());
    render_png(path, (1100, 750), |root| {
        let e = drawing_error;
        let mut chart = ChartBuilder::on(root)
            .caption(caption.as_str(), ("sans-serif", 22))
            .margin(20)
            .x_label_area_size(50)
            .y_label_area_size(70)
            .build_cartesian_2d((x_lo..x_hi).log_scale(), 0.0_f64..(1.1 * y_hi).max(1e-3))
            .map_err(e)?;
        chart
            .configure_mesh()
            .x_desc("µs per covered pixel (tracer, voxels: median GPU frame; source: CPU wall clock)")
            .y_desc("FLIP against the supersampled truth")
            .label_style(("sans-serif", 18))
            .draw()
            .map_err(e)?;
        // Each method's views, thin; its mean over the dolly, large: the fair comparison
        // (the views differ in cost and error for every method alike).
        let mut means = Vec::new();
        let mut series_of = |series: Vec<(f64, f64)>, colour: RGBColor, label: String| -> Result<(), String> {
            if series.is_empty() {
                return Ok(());
            }
            chart.draw_series(LineSeries::new(series.clone(), colour.mix(0.35).stroke_width(1))).map_err(e)?;
            chart.draw_series(series.iter().map(|&p| Circle::new(p, 3, colour.mix(0.5).filled()))).map_err(e)?;
            let n = series.len() as f64;
            let mean = (series.iter().map(|p| p.0).sum::<f64>() / n, series.iter().map(|p| p.1).sum::<f64>() / n);
            means.push(mean);
            chart
                .draw_series([Circle::new(mean, 9, colour.filled())])
                .map_err(e)?
                .label(label)
                .legend(legend_stroke(colour, 4, 24));
            Ok(())
        };
        for (k, model) in Model::ALL.into_iter().enumerate() {
            let series = points.iter().filter(|p| p.0 == model).map(|p| (p.2, p.3)).collect();
            series_of(series, COLOURS[k % COLOURS.len()], format!("{} (dolly mean; small: each view)", model.name()))?;
        }
        for (i, rate) in [1, 2].into_iter().enumerate() {
            let series = methods
                .iter()
                .filter(|r| r.what == Sampled::SourceOnCpu && r.rays_per_axis == rate)
                .map(|r| (r.per_pixel, r.comparison.flip))
                .collect();
            series_of(series, SUPERSAMPLING_COLOURS[i], format!("supersampling {rate}×{rate} rays (source, CPU)"))?;
        }
        for (i, &rate) in gpu_rates(false).iter().enumerate() {
            let series = methods
                .iter()
                .filter(|r| r.what == Sampled::FinestVoxelsOnGpu && r.rays_per_axis == rate)
                .map(|r| (r.per_pixel, r.comparison.flip))
                .collect();
            let colour = VOXEL_SUPERSAMPLING_COLOURS[i % VOXEL_SUPERSAMPLING_COLOURS.len()];
            series_of(series, colour, format!("finest voxels {rate}×{rate} rays (GPU)"))?;
        }
        if !floors.is_empty() {
            let floor = floors.iter().sum::<f64>() / floors.len() as f64;
            chart
                .draw_series(LineSeries::new([(x_lo, floor), (x_hi, floor)], FLOOR_GREY.stroke_width(1)))
                .map_err(e)?
                .label("the truth's noise floor (centred vs jittered strata, dolly mean)")
                .legend(legend_stroke(FLOOR_GREY, 1, 24));
        }
        chart
            .draw_series(LineSeries::new(pareto_front(&means), BLACK.stroke_width(2)))
            .map_err(e)?
            .label("Pareto front of the means")
            .legend(legend_stroke(BLACK, 2, 24));
        draw_legend(&mut chart, 16, SeriesLabelPosition::UpperRight)
    })
}

/// `cargo xtask bench-gpu svo [OUT_DIR]`: every model plain, with one shadow cone and with
/// a lens, at every view of the dolly (default 1024² and 8 octaves in 9 views on a GPU, 50
/// frames after 5; 128², 4 views and 3 frames after 1 on a software adapter), into
/// `svo.csv`.
pub fn bench(args: &Args<'_>) -> Result<(), String> {
    let out = args.out_dir();
    std::fs::create_dir_all(&out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let software = Gpu::new().map_err(|e| e.to_string())?.is_software();
    let setup = setup(args, if software { 128 } else { 1024 }, if software { 5 } else { 7 })?;
    let dolly = dolly(args, &setup, 8.0, if software { 4 } else { 9 })?;
    let frames = args.parse_value("frames", positive::<u32>)?.unwrap_or(if software { 3 } else { 50 });
    let trace = trace_settings(&setup.scene, &dolly);
    let lens_distance = dolly.distance(dolly.views / 2);
    let settings = BenchSettings {
        dolly,
        trace,
        models: Model::ALL.to_vec(),
        variants: vec![
            Variant::Plain,
            Variant::Shadows,
            Variant::DepthOfField(Lens { aperture: 0.03 * lens_distance, focus: 1.3 * lens_distance }),
        ],
        warm_up: if software { 1 } else { 5 },
        frames,
    };
    let started = Instant::now();
    let rows = bench_dolly(&setup.gpu, &setup.renderer, &settings, |r| {
        println!(
            "  view {} ({:.3}) {:>11} {:>7}: {:.3} ms (p10 {:.3}, p90 {:.3}), {} covered px, {:.5} µs/px, {:.1} elements/px",
            r.view,
            r.distance,
            r.model.name(),
            r.variant,
            r.median_ms,
            r.p10_ms,
            r.p90_ms,
            r.covered_pixels,
            r.us_per_covered_pixel,
            r.elements_per_covered_pixel
        );
    })
    .map_err(|e| e.to_string())?;
    let adapter = setup.gpu.adapter_info().name.clone();
    let csv = bench_csv(&rows, &adapter, setup.renderer.size(), setup.scene.name);
    let path = out.join("svo.csv");
    std::fs::write(&path, csv).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    // The finest voxels supersampled on the same adapter (what anti-aliasing costs without
    // prefiltering): the largest of gpu_rates, plain, at every view; the median of 3 frames
    // after 1 (a 16 × 16 frame at 1024² is ~10⁹ rays: the command must end in 5 minutes).
    let truth =
        GpuVoxelTruth::new(&setup.gpu.device, &setup.packed, (setup.size, setup.size)).map_err(|e| e.to_string())?;
    let k = *gpu_rates(software).last().unwrap_or(&1);
    let truth_settings = gpu_truth_settings(&truth, TruthSettings::for_voxel(setup.voxel, k));
    let mut truth_csv = String::from(
        "adapter,scene,width,height,view,distance,rays_per_pixel,median_ms,us_per_covered_pixel,masks_median_ms,\
         masks_ratio,frames,timing\n",
    );
    for view in 0..settings.dolly.views {
        let camera = settings.dolly.camera(view).map_err(|e| e.to_string())?;
        let times = time_voxel_truth(
            &setup.gpu,
            &truth,
            &camera,
            &settings.trace,
            &truth_settings,
            settings.warm_up.min(1),
            settings.frames.min(3),
        )
        .map_err(|e| e.to_string())?;
        let frame = truth.read_frame(&setup.gpu).map_err(|e| e.to_string())?;
        let (_, per_pixel, _, _) = frame_work(&frame, times.median());
        let masks = rows
            .iter()
            .find(|r| r.view == view && r.model == Model::Masks && r.variant == Variant::Plain.name())
            .map_or(f64::NAN, |r| r.median_ms);
        println!(
            "  view {view}: finest voxels {k}×{k} rays on the GPU {:.3} ms, {per_pixel:.5} µs/px ({:.1}× the masks)",
            times.median(),
            times.median() / masks
        );
        let _ = writeln!(
            truth_csv,
            "{},{},{},{},{view},{:.6},{},{:.5},{:.6},{masks:.5},{:.3},{},{:?}",
            adapter.replace(',', ";"),
            setup.scene.name,
            setup.size,
            setup.size,
            settings.dolly.distance(view),
            k * k,
            times.median(),
            per_pixel,
            times.median() / masks,
            times.ms.len(),
            times.source
        );
    }
    let truth_path = out.join("svo_truth.csv");
    std::fs::write(&truth_path, truth_csv).map_err(|e| format!("cannot write {}: {e}", truth_path.display()))?;
    println!(
        "bench-gpu svo: {} rows in {:.1} s, wrote {} and {}",
        rows.len(),
        started.elapsed().as_secs_f64(),
        path.display(),
        truth_path.display()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pareto_front_keeps_what_nothing_beats() {
        let points = [(1.0, 0.5), (2.0, 0.3), (3.0, 0.4), (4.0, 0.1), (0.5, 0.9), (f64::NAN, 0.0)];
        assert_eq!(pareto_front(&points), vec![(0.5, 0.9), (1.0, 0.5), (2.0, 0.3), (4.0, 0.1)]);
    }
}
