//! `cargo xtask bench-gpu stackings [OUT_DIR] [--sizes LIST] [--frames N]`: the multiscale
//! renderer (`grain-renderer`) stage by stage over a backward dolly of 5 frames at 1920×1080,
//! on piles of coffee beans and of sand grains (`rock`), for each visibility buffer the adapter
//! has (64-bit, 32-bit) with the software early-Z of the double draw on and off; per row the
//! median of `N` timings of each stage (GPU timestamps at stage boundaries on a GPU, wall clock
//! on a software adapter), grains per list, culled grains, and the impostor tier's atlas
//! evaluations and early-Z skips per pixel; writes `stackings.csv` into `OUT_DIR` (default
//! `target/bench-gpu/stackings`).
//!
//! Sizes default to 20k and 200k on a software adapter and add 1.6M and 20M on a GPU.

use std::fmt::Write as _;
use std::time::Instant;

use grain_renderer::bench::{StageTimes, time_frame};
use grain_renderer::impostor_tier::TIER_STATS;
use grain_renderer::renderer::NO_POINT_TIER;
use grain_renderer::{ImpostorTier, RendererOptions, StackingRenderer, Stage, TierSettings, VisibilityKind};
use grain_splitter::sweep::Shot;
use grain_splitter::{OccluderMapKind, SplitCounters, TierThresholds};

use crate::cli::{Args, positive};
use crate::impostor_cloud::load_grain;
use crate::stackings::{dolly, scene};

const SIZE: (u32, u32) = (1920, 1080);
const DOLLY_FRAMES: u32 = 5;
const DEFAULT_REPEATS: u32 = 3;
const SCENES: [&str; 2] = ["bean", "rock"];

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

/// Runs the subject.
pub fn run(args: &Args<'_>, counts: Option<Vec<usize>>) -> Result<(), String> {
    let gpu = gpu_harness::Gpu::new().map_err(|e| e.to_string())?;
    let adapter = format!("\"{}\"", gpu.adapter_info().name.replace('"', "\"\""));
    let counts = counts.unwrap_or(if gpu.is_software() {
        vec![20_000, 200_000]
    } else {
        vec![20_000, 200_000, 1_600_000, 20_000_000]
    });
    let repeats = args.parse_value("frames", positive::<u32>)?.unwrap_or(DEFAULT_REPEATS);
    let out = args.out_dir();
    std::fs::create_dir_all(&out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let mut kinds = vec![VisibilityKind::TwoPass32];
    if ImpostorTier::supports_atomic64(&gpu.device) {
        kinds.insert(0, VisibilityKind::Atomic64);
    }
    println!(
        "bench-gpu stackings on {} ({DOLLY_FRAMES} dolly frames, median of {repeats} each, {}×{})",
        gpu.describe(),
        SIZE.0,
        SIZE.1
    );
    let mut csv = String::from("adapter,timing,scene,grains,frame,distance,visibility,early_z,");
    for stage in Stage::ALL {
        let _ = write!(csv, "{}_ms,", stage.name());
    }
    csv += "total_ms,mesh,impostor_occluder,impostor_rest,point,culled_frustum,culled_cone,culled_hiz,\
            evaluated_per_pixel,early_z_skips_per_pixel,resolved_pixels\n";
    let rows = grain_impostor::choice::measured_accuracy()?;
    let lighting = grain_renderer::renderer::pile_lighting();
    for &count in &counts {
        for scene_name in SCENES {
            let started = Instant::now();
            let (name, mesh) = load_grain(None, scene_name)?;
            let bounds = mesh.bounds();
            let (inner, outer) = (bounds.occluder_radius(), bounds.outer_radius);
            let mesh_above = TierThresholds::from_impostor_table(&rows, &name, 0.05, NO_POINT_TIER, 1.1)
                .map_err(|e| e.to_string())?
                .mesh_above();
            let (stacking, grains, atlas) = scene(&gpu, count, &mesh)?;
            let region = stacking.bounds();
            let shots = Shot::fig15(region.min, region.max);
            println!(
                "  {count} {name} (r/R = {:.2}, meshes above {mesh_above:.1} px): scene and atlas in {:.1} s",
                inner / outer,
                started.elapsed().as_secs_f64()
            );
            for &visibility in &kinds {
                let options = RendererOptions {
                    size: SIZE,
                    capacity: grains.len() as u32,
                    mesh_above,
                    point_below: NO_POINT_TIER,
                    band: 1.1,
                    occluder_map: OccluderMapKind::Auto,
                    visibility,
                    culling: true,
                };
                let renderer = StackingRenderer::new(&gpu.device, &gpu.queue, &mesh, &atlas, options)
                    .map_err(|e| format!("{count} {name}: {e}"))?;
                let scene = renderer.upload(&gpu.device, &grains).map_err(|e| format!("{count} {name}: {e}"))?;
                for early_z in [true, false] {
                    let tier = TierSettings { early_z, ..TierSettings::default() };
                    for k in 0..DOLLY_FRAMES {
                        let camera = dolly(&shots, k, DOLLY_FRAMES, SIZE)?;
                        // One untimed frame: the two-phase history and the hysteresis settle.
                        time_frame(&gpu, &renderer, &scene, &camera, &lighting, tier).map_err(|e| e.to_string())?;
                        let mut samples: Vec<StageTimes> = Vec::new();
                        for _ in 0..repeats {
                            samples.push(
                                time_frame(&gpu, &renderer, &scene, &camera, &lighting, tier)
                                    .map_err(|e| e.to_string())?,
                            );
                        }
                        let stage_ms: Vec<f64> =
                            (0..4).map(|s| median(samples.iter().map(|t| t.ms[s]).collect())).collect();
                        let total = median(samples.iter().map(StageTimes::total).collect());
                        let counters = gpu
                            .read_buffer(renderer.splitter().counters(), size_of::<SplitCounters>() as u64)
                            .map_err(|e| e.to_string())?;
                        let c: SplitCounters = bytemuck::pod_read_unaligned(&counters);
                        let stats = gpu
                            .read_buffer(renderer.impostor_tier().stats(), u64::from(TIER_STATS) * 4)
                            .map_err(|e| e.to_string())?;
                        let stats: [u32; TIER_STATS as usize] = bytemuck::pod_read_unaligned(&stats);
                        let pixels = f64::from(SIZE.0 * SIZE.1);
                        let evaluated = f64::from(stats[0] + stats[1]) / pixels;
                        let skipped = f64::from(stats[2] + stats[3]) / pixels;
                        let distance = (camera.uniforms.eye.truncate() - shots[0].target).length();
                        println!(
                            "    {visibility:?} early-Z {early_z} frame {k}: {total:.2} ms ({}); lists {:?}, culled {:?}, atlas evaluations {evaluated:.2}/px, skips {skipped:.2}/px",
                            Stage::ALL
                                .iter()
                                .zip(&stage_ms)
                                .map(|(s, ms)| format!("{} {ms:.2}", s.name()))
                                .collect::<Vec<_>>()
                                .join(", "),
                            c.count,
                            &c.culled[..3]
                        );
                        let timing = format!("{:?}", samples[0].source);
                        let _ = write!(
                            csv,
                            "{adapter},{timing},{name},{count},{k},{distance:.3},{visibility:?},{early_z},"
                        );
                        for ms in &stage_ms {
                            let _ = write!(csv, "{ms:.4},");
                        }
                        let _ = writeln!(
                            csv,
                            "{total:.4},{},{},{},{},{},{},{},{evaluated:.4},{skipped:.4},{}",
                            c.count[0],
                            c.count[1],
                            c.count[2],
                            c.count[3],
                            c.culled[0],
                            c.culled[1],
                            c.culled[2],
                            stats[4]
                        );
                    }
                }
            }
        }
    }
    let path = out.join("stackings.csv");
    std::fs::write(&path, csv).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    println!("wrote {}", path.display());
    Ok(())
}
