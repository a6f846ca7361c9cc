//! `cargo xtask ddm-build [OUT_DIR] [--quick] [--size WxHxD] [--cones MxN | --plain] [--gpu]
//! [--tolerance T] [--obj PATH | --height-map PNG] [--scale S | --fit-slab] [--height H]
//! [--periodic | --clamp]`: how long
//! `ddm_compress::compute_distance_maps` takes to build one map (all its cones, on every
//! core) for every tile (the five procedural ones, or the user's: [`crate::ddm_input`]),
//! against issue 13's budget of [`BUDGET_SECONDS`] for the DDM 4×2 at 128 × 128 × 32 on a
//! 2-core machine.
//!
//! Defaults: 128 × 128 × 32 voxels, the downward DDM 4×2, tolerance 0.25 voxel; `--quick`
//! 32 × 32 × 8 (a smoke run). Writes `ddm_build.csv` into `OUT_DIR` (default
//! `target/ddm-build`): per tile the triangles, grid, map, tolerance, threads, wall-clock
//! seconds, the surface voxels, the mean value off the surface (how tight the map is: at
//! equal time, larger is better) and whether the build kept to the budget. A speed goal:
//! it lives in this command, not in a test.
//!
//! `--plain --gpu` also builds the plain map on the adapter (`ddm_render::PlainMapBuild`,
//! one thread per column of voxels) and writes, per tile, the GPU's median build time over
//! [`GPU_BUILDS`] builds after one warm-up (timestamps on a hardware adapter, wall clock
//! on a software one: the `gpu_timing` column), the layout and upload time, the adapter,
//! and the largest difference from the CPU's map (at most the tolerance: both are lower
//! bounds within it of the exact distance; a larger one, or a surface flag that differs,
//! is an error). The directional maps have no GPU build: `--gpu` without `--plain` is
//! refused.

use std::fmt::Write as _;

use ddm_compress::DistanceMapSettings;
use ddm_experiments::maps::{TableMap, compute_named};
use glam::UVec3;

use crate::cli::{Args, grid_size};
use crate::ddm_input::{self, TileSource};

/// Issue 13's budget for a DDM 4×2 at 128 × 128 × 32 on a 2-core machine, in seconds.
pub const BUDGET_SECONDS: f64 = 30.0;

/// Timed GPU builds per tile with `--gpu` (after one warm-up).
pub const GPU_BUILDS: u32 = 5;

/// The bounds' rounding margins (relative 2e-6 of coordinates below a few hundred) with
/// room for the GPU's own rounding: the CPU and GPU maps may differ by the tolerance plus
/// this.
const ROUNDING_VOXEL: f32 = 1e-3;

/// The plain map built on the GPU for one tile, compared with the CPU's.
struct GpuBuild {
    /// Median build time, in milliseconds.
    median_ms: f64,
    /// How the builds were timed.
    timing: &'static str,
    /// Seconds to lay out the hierarchy and upload it (CPU and transfer).
    setup_seconds: f64,
    /// The largest |GPU − CPU| over the voxels.
    largest_difference: f32,
}

/// Builds the plain map of `triangles` on `gpu` and compares it with the CPU's `cpu`.
fn gpu_build(
    gpu: &gpu_harness::Gpu,
    pipeline: &ddm_render::PlainMapPipeline,
    name: &str,
    dims: UVec3,
    triangles: &[ddm_compress::Triangle],
    settings: DistanceMapSettings,
    cpu: &ddm_compress::DistanceMaps,
) -> Result<GpuBuild, String> {
    let started = std::time::Instant::now();
    let scene = ddm_compress::PlainGpuScene::new(dims, triangles, settings).map_err(|e| format!("{name}: {e}"))?;
    let build = ddm_render::PlainMapBuild::new(&gpu.device, pipeline, &scene).map_err(|e| format!("{name}: {e}"))?;
    gpu.wait().map_err(|e| e.to_string())?;
    let setup_seconds = started.elapsed().as_secs_f64();
    let times = build.time_builds(gpu, 1, GPU_BUILDS).map_err(|e| format!("{name}: {e}"))?;
    let maps = build.read_back(gpu).map_err(|e| format!("{name}: {e}"))?;
    if let Some(voxel) = (0..maps.surface.len()).find(|&v| maps.surface[v] != cpu.surface[v]) {
        return Err(format!("{name}: the GPU's surface flag of voxel {voxel} differs from the CPU's"));
    }
    let mut largest_difference = 0.0_f32;
    for (voxel, (g, c)) in maps.values[0].iter().zip(&cpu.values[0]).enumerate() {
        let difference = (g - c).abs();
        if difference > settings.tolerance + ROUNDING_VOXEL {
            return Err(format!(
                "{name}: voxel {voxel}: the GPU's value {g} and the CPU's {c} differ by more than the tolerance"
            ));
        }
        largest_difference = largest_difference.max(difference);
    }
    Ok(GpuBuild { median_ms: times.median(), timing: times.source.name(), setup_seconds, largest_difference })
}

/// `--cones MxN`: the downward DDM with `M` azimuth and `N` elevation intervals.
fn cones(text: &str) -> Result<(u32, u32), String> {
    let parts: Result<Vec<u32>, _> = text.split('x').map(str::parse).collect();
    match parts.as_deref() {
        Ok(&[m, n]) if m > 0 && n > 0 => Ok((m, n)),
        _ => Err("expected two positive counts MxN (azimuths x elevations)".to_owned()),
    }
}

/// A positive, finite tolerance in voxels.
fn tolerance(text: &str) -> Result<f32, String> {
    match text.parse::<f32>() {
        Ok(t) if t > 0.0 && t.is_finite() => Ok(t),
        _ => Err("expected a positive finite number of voxels".to_owned()),
    }
}

/// Runs the measurement.
pub fn run(args: &Args<'_>) -> Result<(), String> {
    let quick = args.flag("quick");
    let dims = args.parse_value("size", grid_size)?.unwrap_or(if quick {
        UVec3::new(32, 32, 8)
    } else {
        UVec3::new(128, 128, 32)
    });
    let on_gpu = args.flag("gpu");
    if on_gpu && !args.flag("plain") {
        return Err("--gpu: only the plain map has a GPU build; add --plain".to_owned());
    }
    let table_map = if args.flag("plain") {
        TableMap::DM
    } else {
        let (m, n) = args.parse_value("cones", cones)?.unwrap_or((4, 2));
        TableMap::ddm(Box::leak(format!("DDM {m}x{n}").into_boxed_str()), m, n)
    };
    let tolerance = args.parse_value("tolerance", tolerance)?.unwrap_or(0.25);
    let tile = TileSource::from_args(args)?;
    let periodic = ddm_input::periodic_from_args(args, tile.as_ref())?;
    let tiles = ddm_input::tiles(tile.as_ref(), dims, periodic)?;
    let out = args.out_dir();
    std::fs::create_dir_all(&out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let budgeted = table_map.name == "DDM 4x2" && dims == UVec3::new(128, 128, 32);
    println!(
        "ddm-build: the {} at {}x{}x{} voxels, tolerance {tolerance} voxel, {threads} threads, {}; {}{}",
        table_map.name,
        dims.x,
        dims.y,
        dims.z,
        if periodic { "periodic in x and y" } else { "a single tile (--clamp)" },
        ddm_input::describe(tile.as_ref()),
        if budgeted { format!("; budget {BUDGET_SECONDS} s per tile on 2 cores") } else { String::new() }
    );
    let gpu = if on_gpu {
        let gpu = gpu_harness::Gpu::new().map_err(|e| e.to_string())?;
        println!("ddm-build: the plain map also on {}", gpu.describe());
        let pipeline = ddm_render::PlainMapPipeline::new(&gpu.device).map_err(|e| e.to_string())?;
        Some((gpu, pipeline))
    } else {
        None
    };
    let mut csv = String::from(
        "tile,triangles,size,map,tolerance_voxel,threads,seconds,surface_voxels,mean_value_off_surface_voxel,budget_s,within_budget,gpu_adapter,gpu_median_ms,gpu_timing,gpu_setup_s,gpu_largest_difference_voxel\n",
    );
    println!("{:<10} {:>9} {:>9} {:>14} {:>8}", "tile", "triangles", "time s", "surface voxels", "mean");
    for tile in &tiles {
        let settings = DistanceMapSettings { tolerance, periodic_xy: tile.periodic_xy };
        let named = compute_named(tile.name, dims, &tile.triangles, table_map, settings).map_err(|e| e.to_string())?;
        let maps = &named.maps;
        let surface = maps.surface.iter().filter(|&&s| s).count();
        let (mut sum, mut count) = (0.0_f64, 0_u64);
        for map in &maps.values {
            for (value, _) in map.iter().zip(&maps.surface).filter(|(_, s)| !**s) {
                sum += f64::from(*value);
                count += 1;
            }
        }
        let mean = if count == 0 { f64::NAN } else { sum / count as f64 };
        let (budget, within) = if budgeted {
            (format!("{BUDGET_SECONDS}"), (named.seconds <= BUDGET_SECONDS).to_string())
        } else {
            (String::new(), String::new())
        };
        println!("{:<10} {:>9} {:>9.2} {:>14} {:>8.3}", tile.name, tile.triangles.len(), named.seconds, surface, mean);
        let gpu_columns = match &gpu {
            Some((gpu, pipeline)) => {
                let built = gpu_build(gpu, pipeline, tile.name, dims, &tile.triangles, settings, maps)?;
                println!(
                    "{:<10} on the GPU: {:.3} ms ({}), set-up {:.3} s, largest |GPU - CPU| {:.4} voxel",
                    "", built.median_ms, built.timing, built.setup_seconds, built.largest_difference
                );
                format!(
                    "{},{:.4},{},{:.4},{:.5}",
                    gpu.adapter_info().name.replace(',', " "),
                    built.median_ms,
                    built.timing,
                    built.setup_seconds,
                    built.largest_difference
                )
            }
            None => ",,,,".to_owned(),
        };
        writeln!(
            csv,
            "{},{},{}x{}x{},{},{tolerance},{threads},{:.3},{surface},{mean:.5},{budget},{within},{gpu_columns}",
            tile.name,
            tile.triangles.len(),
            dims.x,
            dims.y,
            dims.z,
            table_map.name,
            named.seconds
        )
        .map_err(|e| e.to_string())?;
    }
    let path = out.join("ddm_build.csv");
    std::fs::write(&path, &csv).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    println!("wrote {}", path.display());
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gpu_without_plain_is_refused_before_any_work() {
        let command = crate::commands::command("ddm-build").expect("the ddm-build command");
        let words: Vec<String> = ["--gpu", "--quick"].map(String::from).to_vec();
        let Ok(crate::cli::Parsed::Run(args)) = command.parse(&words) else { panic!("--gpu --quick should parse") };
        let error = run(&args).unwrap_err();
        assert!(error.contains("--gpu") && error.contains("add --plain"), "{error}");
    }

    #[test]
    fn cone_counts_and_tolerances_are_checked() {
        assert_eq!(cones("4x2"), Ok((4, 2)));
        for bad in ["4", "4x0", "x2", "4x2x1", "ax2"] {
            assert!(cones(bad).is_err(), "{bad}");
        }
        assert_eq!(tolerance("0.05"), Ok(0.05));
        for bad in ["0", "-1", "nan", "inf", "a"] {
            assert!(tolerance(bad).is_err(), "{bad}");
        }
    }
}
