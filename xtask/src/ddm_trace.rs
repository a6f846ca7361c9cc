//! `cargo xtask ddm-trace [OUT_DIR] [--quick] [--size WxHxD]`: Mehra & Kumar's Tables 1–3,
//! measured (24×24×8 voxel tiles by default, 12×12×6 with `--quick`).
//!
//! For each mesostructure (maze, bricks: height fields; beads, ball: not) on a plane tile,
//! one perspective view over about 2 × 2 tiles is traced per pixel with each method:
//! sphere tracing with the plain distance map (DM) and with the DDMs 2×1, 4×1, 8×1 and 4×2
//! (each stopping at the first zero voxel, as Donnelly's sphere tracing does), DDM 4×1 +
//! quadric (Algorithm 3.1 on the C⁰ patches of §3.1), DDM 4×1 + fitted Q (the same on each
//! voxel's fitted quadric of step a), DDM 4×1 + triangles (the mesh's own triangles per
//! voxel, exact: beyond the paper), DDM 4×1 + adaptive (per voxel the fitted quadric where
//! it stays within 1e-3 voxel of the triangles, else the triangles: see
//! `ddm_tracer::exact_patches`), DM / DDM 4×1 / DDM 4×1 + adaptive with voxel-exit
//! stepping (`... exit`: `ddm_tracer::Stepping::VoxelExit`, beyond the paper; every other
//! row steps by the stored distance as Algorithm 3.1 does), and relief mapping (height fields only; height map
//! at 2 texels per voxel, 32 linear + 8 binary steps). Every pixel is compared with the
//! exact first hit of the original mesh. Every method also runs in the WGSL compute pass
//! (one ray per invocation), on the raw maps for Tables 1/2.
//!
//! Known limits of the inputs, visible in the numbers: the spheres and tori are coarse
//! meshes, whose facets a smooth quadric cannot match to 1e-3 voxel.
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
use std::time::Instant;

use ddm_compress::{DirectionCones, DistanceMapSettings, DistanceMaps, compute_distance_maps};
use ddm_tracer::{
    CompressedMaps, HeightMap, MeshRaycaster, Method, PatchSettings, PatchSurface, Stepping, TraceOutcome,
    TraceSettings, VoxelPatches, relief_trace, trace,
};
use ddm_tracer::{GpuScene, TraceResult};
use glam::{DVec3, UVec3, Vec2, Vec3};
use gpu_harness::Gpu;
use mesostructure::Mesostructure;
use plotters::prelude::*;
use shader_registry::kernel_io::ddm_tracer::TraceRay;

use crate::chart::{draw_legend, drawing_error, render_png};

const MAX_STEPS: u32 = 512;
const COMPRESSION_BLOCK: u32 = 4;
const RELIEF_LINEAR: u32 = 32;
const RELIEF_BINARY: u32 = 8;
/// Error budget (voxels) of the adaptive patches: the accuracy goal.
const ADAPTIVE_BUDGET: f32 = 1e-3;
/// Error budgets (voxels) of the adaptive patches' sweep: memory and accuracy against it.
const BUDGETS: [f32; 6] = [0.3, 0.1, 0.03, 0.01, 3e-3, 1e-3];

/// One camera ray per pixel.
struct View {
    width: u32,
    height: u32,
    rays: Vec<(Vec3, Vec3)>,
}

/// A perspective view from above and to the side of the tile, about 2 × 2 tiles wide.
fn view(dims: UVec3, width: u32, height: u32) -> View {
    let size = dims.as_vec3();
    let target = Vec3::new(size.x, size.y, 0.3 * size.z);
    let eye = target + Vec3::new(-0.9 * size.x, -1.3 * size.y, 1.1 * size.x.max(size.y));
    let forward = (target - eye).normalize();
    let right = forward.cross(Vec3::Z).normalize();
    let up = right.cross(forward);
    let tan = (25.0_f32).to_radians().tan();
    let aspect = width as f32 / height as f32;
    let mut rays = Vec::with_capacity((width * height) as usize);
    for y in 0..height {
        for x in 0..width {
            let u = ((x as f32 + 0.5) / width as f32 * 2.0 - 1.0) * tan * aspect;
            let v = (1.0 - (y as f32 + 0.5) / height as f32 * 2.0) * tan;
            rays.push((eye, (forward + right * u + up * v).normalize()));
        }
    }
    View { width, height, rays }
}

/// One method's outcome on every pixel, and its CPU time.
struct Run {
    outcomes: Vec<TraceOutcome>,
    seconds_per_ray: f64,
}

/// Traces every ray with `f`; the time per ray is the fastest of 5 passes (the machine is
/// shared, so the minimum is the least disturbed measurement).
fn timed(rays: &[(Vec3, Vec3)], f: impl Fn(Vec3, Vec3) -> TraceOutcome) -> Run {
    let outcomes: Vec<TraceOutcome> = rays.iter().map(|&(o, d)| f(o, d)).collect();
    let mut best = f64::INFINITY;
    for _ in 0..5 {
        let start = Instant::now();
        for &(o, d) in rays {
            std::hint::black_box(f(o, d));
        }
        best = best.min(start.elapsed().as_secs_f64());
    }
    Run { outcomes, seconds_per_ray: best / rays.len() as f64 }
}

/// Rounds of [`interleaved_time_ratio`].
const RATIO_ROUNDS: usize = 15;

/// `(hit/miss differences, hit points more than 1e-5 voxel apart, the largest hit-point
/// difference)` between two tracings of the same rays.
fn hit_differences(a: &[TraceOutcome], b: &[TraceOutcome]) -> (usize, usize, f32) {
    let (mut differ, mut moved, mut worst) = (0, 0, 0.0_f32);
    for (a, b) in a.iter().zip(b) {
        match (a.hit, b.hit) {
            (Some(a), Some(b)) => {
                let distance = (a.point - b.point).length();
                worst = worst.max(distance);
                moved += usize::from(distance > 1e-5);
            }
            (None, None) => {}
            _ => differ += 1,
        }
    }
    (differ, moved, worst)
}

/// The median over [`RATIO_ROUNDS`] rounds of the time of one pass of `rays` with
/// `packed` over one with `raw`, the two passes of a round in alternating order: a drift
/// of the machine's speed between two timings (±15 % on a shared 2-core VM, more than the
/// difference measured) then cancels, where two separate minima of 5 passes did not.
fn interleaved_time_ratio(
    rays: &[(Vec3, Vec3)],
    raw: impl Fn(Vec3, Vec3) -> TraceOutcome,
    packed: impl Fn(Vec3, Vec3) -> TraceOutcome,
) -> f64 {
    let pass = |f: &dyn Fn(Vec3, Vec3) -> TraceOutcome| {
        let start = Instant::now();
        for &(o, d) in rays {
            std::hint::black_box(f(o, d));
        }
        start.elapsed().as_secs_f64()
    };
    let mut ratios: Vec<f64> = (0..RATIO_ROUNDS)
        .map(|round| {
            if round % 2 == 0 {
                let r = pass(&raw);
                pass(&packed) / r
            } else {
                let p = pass(&packed);
                p / pass(&raw)
            }
        })
        .collect();
    ratios.sort_by(f64::total_cmp);
    ratios[RATIO_ROUNDS / 2]
}

/// Accuracy and cost of one method against the truth.
#[derive(Default)]
struct Stats {
    mean_steps: f64,
    max_steps: u32,
    both_hit: usize,
    truth_hits: usize,
    mean_error: f64,
    max_error: f64,
    within: usize,
    holes: usize,
    false_hits: usize,
    gross: usize,
    exhausted: usize,
}

fn stats(outcomes: &[TraceOutcome], truth: &[Option<DVec3>]) -> Stats {
    let mut s = Stats::default();
    let mut error_sum = 0.0;
    for (outcome, truth) in outcomes.iter().zip(truth) {
        s.mean_steps += f64::from(outcome.steps);
        s.max_steps = s.max_steps.max(outcome.steps);
        s.exhausted += usize::from(outcome.exhausted);
        s.truth_hits += usize::from(truth.is_some());
        match (outcome.hit, truth) {
            (Some(hit), Some(point)) => {
                let error = (hit.point.as_dvec3() - *point).length();
                s.both_hit += 1;
                error_sum += error;
                s.max_error = s.max_error.max(error);
                s.within += usize::from(error <= 1e-3);
                s.gross += usize::from(error > 0.5);
            }
            (None, Some(_)) => s.holes += 1,
            (Some(_), None) => s.false_hits += 1,
            (None, None) => {}
        }
    }
    s.mean_steps /= outcomes.len().max(1) as f64;
    s.mean_error = error_sum / s.both_hit.max(1) as f64;
    s
}

/// The GPU pass of `maps` and `patches` over `rays`: see [`gpu_scene_run`].
fn gpu_run(
    gpu: &Gpu,
    maps: &CompressedMaps,
    patches: Option<&VoxelPatches>,
    settings: TraceSettings,
    rays: &[(Vec3, Vec3)],
    cpu: &[TraceOutcome],
) -> Result<(f64, usize), String> {
    let scene = GpuScene::new(maps, patches, settings).ok_or("the scene does not pack")?;
    gpu_scene_run(gpu, &scene, rays, cpu)
}

/// The GPU pass of `scene` over `rays` (minimum of 5 timed runs) and how many rays' hits
/// differ from `cpu`'s.
fn gpu_scene_run(
    gpu: &Gpu,
    scene: &GpuScene,
    rays: &[(Vec3, Vec3)],
    cpu: &[TraceOutcome],
) -> Result<(f64, usize), String> {
    let source = shader_registry::test_kernel_source("ddm_tracer_compute")?;
    let inputs: Vec<TraceRay> = rays.iter().map(|&(o, d)| TraceRay::new(o, d)).collect();
    let uniforms = scene.uniforms(inputs.len() as u32);
    let mut best = f64::INFINITY;
    let mut differ = 0;
    for _ in 0..5 {
        let (results, timing): (Vec<TraceResult>, _) = gpu
            .compute_map_with_storage(
                &source,
                "trace_rays",
                bytemuck::bytes_of(&uniforms),
                &inputs,
                &scene.storage_bytes(),
            )
            .map_err(|e| e.to_string())?;
        best = best.min(timing.seconds);
        differ = results
            .iter()
            .zip(cpu)
            .filter(|(g, c)| {
                let same_hit = (g.normal_hit.w == 1.0) == c.hit.is_some();
                let same_point = c.hit.is_none_or(|h| (h.point - g.point_t.truncate()).length() <= 1e-4);
                !(same_hit && same_point && g.counts.x == c.steps)
            })
            .count();
    }
    Ok((best, differ))
}

/// Writes the view shaded from each hit's normal (misses dark).
fn write_image(path: &Path, view: &View, normals: &[Option<Vec3>]) -> Result<(), String> {
    let light = Vec3::new(0.45, 0.3, 0.84).normalize();
    let mut image = image::RgbImage::new(view.width, view.height);
    for (pixel, normal) in image.pixels_mut().zip(normals) {
        *pixel = match normal {
            Some(n) => {
                let diffuse = n.dot(light).max(0.0);
                let shade = 0.2 + 0.8 * diffuse;
                let base = Vec3::new(0.85, 0.72, 0.5) * 0.6 + (*n * 0.5 + 0.5) * 0.4;
                let c = base * shade * 255.0;
                image::Rgb([c.x as u8, c.y as u8, c.z as u8])
            }
            None => image::Rgb([20, 24, 40]),
        };
    }
    image.save(path).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// A method of the tables.
struct MethodRow {
    name: &'static str,
    stats: Stats,
    cpu_rays_per_second: f64,
    gpu: Option<(f64, usize)>,
}

/// Runs the experiment; `args` are `[OUT_DIR] [--quick]`.
pub fn run(args: &[&str], default_out: PathBuf) -> Result<(), String> {
    let mut out = default_out;
    let mut quick = false;
    let mut size = None;
    let mut args = args.iter();
    while let Some(&arg) = args.next() {
        match arg {
            "--quick" => quick = true,
            "--size" => size = Some(crate::ddm_compression::parse_size(args.next().copied())?),
            _ => out = PathBuf::from(arg),
        }
    }
    std::fs::create_dir_all(&out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let (dims, width, height) = if quick { (UVec3::new(12, 12, 6), 96, 72) } else { (UVec3::new(24, 24, 8), 192, 144) };
    let dims = size.unwrap_or(dims);
    let settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: true };
    let gpu = Gpu::new().map_err(|e| e.to_string())?;
    println!(
        "DDM tracing (Tables 1-3): {}x{}x{} voxels per tile, {width}x{height} rays, GPU: {}",
        dims.x,
        dims.y,
        dims.z,
        gpu.describe()
    );
    if gpu.is_software() {
        println!("(GPU times are from a software rasterizer's compute: lavapipe on the CPU, not a GPU)");
    }
    let view = view(dims, width, height);
    let mut methods_csv = String::from(
        "mesostructure,method,mean_steps,max_steps,exhausted,truth_hits,both_hit,holes,false_hits,gross_over_0.5_voxel,mean_error_voxel,max_error_voxel,within_1e-3_of_both_pct,within_1e-3_of_truth_pct,cpu_rays_per_s,gpu_ms,gpu_timing,gpu_differs_from_cpu\n",
    );
    let mut compression_csv = String::from(
        "mesostructure,method,block,efficiency,raw_mean_steps,compressed_mean_steps,hit_miss_differ,points_differ_over_1e-5_voxel,max_point_difference_voxel,cpu_time_ratio,gpu_time_ratio,block_cells_mean_steps,block_cells_hit_miss_differ,block_cells_points_differ_over_1e-5_voxel,block_cells_max_point_difference_voxel,block_cells_cpu_time_ratio\n",
    );
    let mut patches_csv =
        String::from("mesostructure,patches,quadric_voxels,triangle_voxels,voxels_without_patch,patch_count,bytes\n");
    let mut steps_rows = Vec::new();
    let mut budget_csv = String::from(
        "mesostructure,budget_voxel,quadric_voxels,triangle_voxels,bytes,mean_steps,holes,false_hits,mean_error_voxel,max_error_voxel,within_1e-3_of_truth_pct,cpu_rays_per_s_one_pass\n",
    );
    let timing_name = if gpu.has_timestamps() { "timestamps" } else { "wall clock" };
    let mut chart_points: Vec<(&'static str, &'static str, f64, f64)> = Vec::new();
    for structure in Mesostructure::ALL {
        let triangles = structure.triangles(dims);
        let mesh = MeshRaycaster::new(&triangles, Vec2::new(dims.x as f32, dims.y as f32));
        let truth: Vec<Option<(DVec3, DVec3)>> = view
            .rays
            .iter()
            .map(|&(o, d)| mesh.first_hit(o.as_dvec3(), d.as_dvec3(), 1e4).map(|h| (h.point, h.normal)))
            .collect();
        let truth_points: Vec<Option<DVec3>> = truth.iter().map(|t| t.map(|t| t.0)).collect();
        let truth_normals: Vec<Option<Vec3>> = truth.iter().map(|t| t.map(|t| t.1.as_vec3())).collect();
        write_image(&out.join(format!("{}_truth.png", structure.name())), &view, &truth_normals)?;
        let start = Instant::now();
        let mut maps: Vec<(&'static str, DistanceMaps)> = Vec::new();
        for (name, cones) in [
            ("DM", None),
            ("DDM 2x1", DirectionCones::downward(2, 1)),
            ("DDM 4x1", DirectionCones::downward(4, 1)),
            ("DDM 8x1", DirectionCones::downward(8, 1)),
            ("DDM 4x2", DirectionCones::downward(4, 2)),
        ] {
            let m = compute_distance_maps(dims, &triangles, cones, settings)
                .ok_or_else(|| format!("{}: invalid scene", structure.name()))?;
            maps.push((name, m));
        }
        let maps_seconds = start.elapsed().as_secs_f64();
        let start = Instant::now();
        let patches = VoxelPatches::build(dims, &triangles, &maps[0].1.surface, PatchSettings::default())
            .ok_or("patch construction failed")?;
        let fitted_settings = PatchSettings { surface: PatchSurface::FittedQuadric, ..PatchSettings::default() };
        let fitted = VoxelPatches::build(dims, &triangles, &maps[0].1.surface, fitted_settings)
            .ok_or("patch construction failed")?;
        let patch_seconds = start.elapsed().as_secs_f64();
        let start = Instant::now();
        let exact_settings = PatchSettings { surface: PatchSurface::Triangles, ..PatchSettings::default() };
        let exact = VoxelPatches::build(dims, &triangles, &maps[0].1.surface, exact_settings)
            .ok_or("patch construction failed")?;
        let adaptive_settings = PatchSettings {
            surface: PatchSurface::Adaptive { max_error: ADAPTIVE_BUDGET },
            ..PatchSettings::default()
        };
        let adaptive = VoxelPatches::build(dims, &triangles, &maps[0].1.surface, adaptive_settings)
            .ok_or("patch construction failed")?;
        println!(
            "\n{} ({} triangles): maps {maps_seconds:.1} s, C0 + fitted patches {patch_seconds:.2} s ({} C0 patches, {} surface voxels without one), triangles + adaptive {:.2} s",
            structure.name(),
            triangles.len(),
            patches.patches.len(),
            patches.voxels_without_patch,
            start.elapsed().as_secs_f64()
        );
        for (name, set) in [("C0", &patches), ("fitted", &fitted), ("triangles", &exact), ("adaptive", &adaptive)] {
            writeln!(
                patches_csv,
                "{},{name},{},{},{},{},{}",
                structure.name(),
                set.quadric_voxels,
                set.triangle_voxels,
                set.voxels_without_patch,
                set.patches.len(),
                set.byte_size()
            )
            .map_err(|e| e.to_string())?;
        }
        for budget in BUDGETS {
            let settings =
                PatchSettings { surface: PatchSurface::Adaptive { max_error: budget }, ..Default::default() };
            let set = VoxelPatches::build(dims, &triangles, &maps[0].1.surface, settings)
                .ok_or("patch construction failed")?;
            let quadric = TraceSettings { method: Method::Quadric, max_steps: MAX_STEPS, stepping: Stepping::Distance };
            let start = Instant::now();
            let outcomes: Vec<TraceOutcome> =
                view.rays.iter().map(|&(o, d)| trace(&maps[2].1, Some(&set), o, d, quadric)).collect();
            let seconds_per_ray = start.elapsed().as_secs_f64() / view.rays.len() as f64;
            let s = stats(&outcomes, &truth_points);
            writeln!(
                budget_csv,
                "{},{budget},{},{},{},{:.3},{},{},{:e},{:e},{:.3},{:.0}",
                structure.name(),
                set.quadric_voxels,
                set.triangle_voxels,
                set.byte_size(),
                s.mean_steps,
                s.holes,
                s.false_hits,
                s.mean_error,
                s.max_error,
                100.0 * s.within as f64 / s.truth_hits.max(1) as f64,
                1.0 / seconds_per_ray
            )
            .map_err(|e| e.to_string())?;
        }
        steps_rows.extend(
            crate::ddm_steps::steps_vs_angle(structure.name(), dims, &maps)
                .map_err(|e| format!("{}: {e}", structure.name()))?,
        );
        let mut rows: Vec<MethodRow> = Vec::new();
        let sphere =
            TraceSettings { method: Method::SphereTracing, max_steps: MAX_STEPS, stepping: Stepping::Distance };
        let quadric = TraceSettings { method: Method::Quadric, max_steps: MAX_STEPS, stepping: Stepping::Distance };
        let mut cases: Vec<(&'static str, &DistanceMaps, Option<&VoxelPatches>, TraceSettings)> =
            maps.iter().map(|(name, m)| (*name, m, None, sphere)).collect();
        cases.push(("DDM 4x1 + quadric", &maps[2].1, Some(&patches), quadric));
        cases.push(("DDM 4x1 + fitted Q", &maps[2].1, Some(&fitted), quadric));
        cases.push(("DDM 4x1 + triangles", &maps[2].1, Some(&exact), quadric));
        cases.push(("DDM 4x1 + adaptive", &maps[2].1, Some(&adaptive), quadric));
        let exit = |settings| TraceSettings { stepping: Stepping::VoxelExit, ..settings };
        cases.push(("DM exit", &maps[0].1, None, exit(sphere)));
        cases.push(("DDM 4x1 exit", &maps[2].1, None, exit(sphere)));
        cases.push(("DDM 4x1 + adaptive exit", &maps[2].1, Some(&adaptive), exit(quadric)));
        for (name, raw, patch_set, trace_settings) in cases {
            let run = timed(&view.rays, |o, d| trace(raw, patch_set, o, d, trace_settings));
            let raw_gpu = CompressedMaps::compress(raw, 1).ok_or("cannot pack the raw maps")?;
            let gpu_result = gpu_run(&gpu, &raw_gpu, patch_set, trace_settings, &view.rays, &run.outcomes)?;
            // Table 3: the same method on compressed maps.
            let compressed = CompressedMaps::compress(raw, COMPRESSION_BLOCK).ok_or("cannot compress")?;
            // The compressed maps traced with `settings`: outcomes, and the time ratio to
            // the raw maps traced as in Tables 1/2.
            let on_compressed = |settings: TraceSettings| {
                let outcomes: Vec<TraceOutcome> =
                    view.rays.iter().map(|&(o, d)| trace(&compressed, patch_set, o, d, settings)).collect();
                let ratio = interleaved_time_ratio(
                    &view.rays,
                    |o, d| trace(raw, patch_set, o, d, trace_settings),
                    |o, d| trace(&compressed, patch_set, o, d, settings),
                );
                (outcomes, ratio)
            };
            let (packed, cpu_time_ratio) = on_compressed(trace_settings);
            let packed_gpu = gpu_run(&gpu, &compressed, patch_set, trace_settings, &view.rays, &packed)?;
            let (differ, moved, worst) = hit_differences(&run.outcomes, &packed);
            let mean = |o: &[TraceOutcome]| o.iter().map(|o| f64::from(o.steps)).sum::<f64>() / o.len() as f64;
            // The paper's rule on raw maps against block cells on compressed maps (the
            // same rule on raw maps: `Stepping::BlockCells`); voxel-exit rows cross blocks
            // as cells already.
            let block_cells = if trace_settings.stepping == Stepping::Distance {
                let (packed, ratio) = on_compressed(TraceSettings { stepping: Stepping::BlockCells, ..trace_settings });
                let (differ, moved, worst) = hit_differences(&run.outcomes, &packed);
                format!("{:.3},{differ},{moved},{worst:e},{ratio:.3}", mean(&packed))
            } else {
                String::from(",,,,")
            };
            writeln!(
                compression_csv,
                "{},{name},{COMPRESSION_BLOCK},{:.3},{:.3},{:.3},{differ},{moved},{worst:e},{:.3},{:.3},{block_cells}",
                structure.name(),
                compressed.compression_efficiency(),
                mean(&run.outcomes),
                mean(&packed),
                cpu_time_ratio,
                packed_gpu.0 / gpu_result.0
            )
            .map_err(|e| e.to_string())?;
            let normals: Vec<Option<Vec3>> = run.outcomes.iter().map(|o| o.hit.map(|h| h.normal)).collect();
            let file = format!("{}_{}.png", structure.name(), name.replace(' ', "").replace('+', "_").to_lowercase());
            write_image(&out.join(file), &view, &normals)?;
            rows.push(MethodRow {
                name,
                stats: stats(&run.outcomes, &truth_points),
                cpu_rays_per_second: 1.0 / run.seconds_per_ray,
                gpu: Some(gpu_result),
            });
        }
        if matches!(structure, Mesostructure::Maze(_) | Mesostructure::Bricks) {
            let height_map = HeightMap::from_mesh(&mesh, dims, 2);
            let size_z = dims.z as f32;
            let run = timed(&view.rays, |o, d| relief_trace(&height_map, size_z, o, d, RELIEF_LINEAR, RELIEF_BINARY));
            let normals: Vec<Option<Vec3>> = run.outcomes.iter().map(|o| o.hit.map(|h| h.normal)).collect();
            write_image(&out.join(format!("{}_relief.png", structure.name())), &view, &normals)?;
            let scene = GpuScene::new(&CompressedMaps::compress(&maps[0].1, 1).ok_or("cannot pack")?, None, sphere)
                .and_then(|s| s.with_relief(&height_map, RELIEF_LINEAR, RELIEF_BINARY))
                .ok_or("the relief scene does not pack")?;
            let gpu_result = gpu_scene_run(&gpu, &scene, &view.rays, &run.outcomes)?;
            rows.push(MethodRow {
                name: "relief 32+8",
                stats: stats(&run.outcomes, &truth_points),
                cpu_rays_per_second: 1.0 / run.seconds_per_ray,
                gpu: Some(gpu_result),
            });
        }
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
        for row in &rows {
            let s = &row.stats;
            let within_both = 100.0 * s.within as f64 / s.both_hit.max(1) as f64;
            let within_truth = 100.0 * s.within as f64 / s.truth_hits.max(1) as f64;
            let (gpu_ms, gpu_differs) = row.gpu.map_or(("n/a".to_owned(), "n/a".to_owned()), |(sec, differ)| {
                (format!("{:.3}", sec * 1e3), differ.to_string())
            });
            println!(
                "{:<18} {:>6.2} {:>5} {:>6} {:>6} {:>6} {:>9.2e} {:>8.3} {:>8.2} {:>8.2} {:>10.0} {:>9} {:>6}",
                row.name,
                s.mean_steps,
                s.max_steps,
                s.holes,
                s.false_hits,
                s.gross,
                s.mean_error,
                s.max_error,
                within_both,
                within_truth,
                row.cpu_rays_per_second,
                gpu_ms,
                gpu_differs
            );
            writeln!(
                methods_csv,
                "{},{},{:.4},{},{},{},{},{},{},{},{:e},{:e},{:.3},{:.3},{:.0},{gpu_ms},{},{gpu_differs}",
                structure.name(),
                row.name,
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
                within_both,
                within_truth,
                row.cpu_rays_per_second,
                if row.gpu.is_some() { timing_name } else { "n/a" }
            )
            .map_err(|e| e.to_string())?;
            chart_points.push((structure.name(), row.name, 1e6 / row.cpu_rays_per_second, s.mean_error.max(1e-7)));
        }
    }
    let write = |name: &str, text: &str| {
        let path = out.join(name);
        std::fs::write(&path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        println!("wrote {}", path.display());
        Ok::<(), String>(())
    };
    write("ddm_trace_methods.csv", &methods_csv)?;
    write("ddm_trace_compression.csv", &compression_csv)?;
    write("ddm_trace_patches.csv", &patches_csv)?;
    write("ddm_adaptive_budget.csv", &budget_csv)?;
    println!("\nAdaptive patches against the error budget (DDM 4x1):\n{budget_csv}");
    println!("\nPatch memory (adaptive: budget {ADAPTIVE_BUDGET} voxel):\n{patches_csv}");
    crate::ddm_steps::write(&out, &steps_rows)?;
    println!("\nTable 3 (tracing with vs without compression, blocks of {COMPRESSION_BLOCK}):\n{compression_csv}");
    error_chart(&out.join("ddm_trace_error_vs_time.png"), &chart_points)?;
    println!("wrote {}", out.join("ddm_trace_error_vs_time.png").display());
    Ok(())
}

/// Each method's colour in the charts (`ddm_steps` uses the maps' entries).
pub const METHOD_COLORS: [(&str, RGBColor); 13] = [
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
    ("DM exit", RGBColor(60, 60, 60)),
    ("DDM 4x1 exit", RGBColor(0, 60, 110)),
    ("DDM 4x1 + adaptive exit", RGBColor(90, 20, 20)),
];

/// Mean hit error against CPU time per ray, one colour per method, one marker per
/// mesostructure.
fn error_chart(path: &Path, points: &[(&str, &str, f64, f64)]) -> Result<(), String> {
    let (x_min, x_max) = points.iter().fold((f64::INFINITY, 0.0_f64), |(lo, hi), p| (lo.min(p.2), hi.max(p.2)));
    let (y_min, y_max) = points.iter().fold((f64::INFINITY, 0.0_f64), |(lo, hi), p| (lo.min(p.3), hi.max(p.3)));
    render_png(path, (900, 620), |root| {
        let mut chart = ChartBuilder::on(root)
            .caption(
                "Hit error vs CPU time per ray (maze: disc, bricks: square, beads: triangle, ball: cross, chain mail: ring)",
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
            .x_desc("CPU time per ray (µs, one thread)")
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
        draw_legend(&mut chart, 16, SeriesLabelPosition::UpperRight)
    })
}
