//! `cargo xtask bench-gpu stackings [OUT_DIR] [--grains LIST] [--frames N] [--dolly-frames LIST]
//! [--scene NAME | --obj PATH --mesh-above PX] [--samples S] [--resolution WxH]`: the multiscale
//! renderer (`grain-renderer`) stage by stage (occluder map, split, meshes, impostor and point
//! visibility, resolve, shading) over a backward dolly of 5 frames at 1920×1080 (`--resolution`
//! another size; `--dolly-frames 0,4` only those of the five, 0 the close-up and 4 the whole
//! pile), on piles of coffee beans and of sand grains
//! (`rock`; `--scene` picks one procedural grain, `--obj` any OBJ grain, whose mesh threshold
//! `--mesh-above` must give), for each visibility buffer the adapter has (64-bit, 32-bit) and
//! each impostor path: compute with the software early-Z of the double draw on and off, and
//! raster (sprites, hardware depth test), with `S × S` visibility samples per pixel
//! (`--samples`, 1 by default). Per row (one frame of the dolly) the median of `N`
//! timings of each stage (GPU timestamps at stage boundaries on a GPU, wall clock on a software
//! adapter), grains per list, culled grains, and the impostor tier's atlas evaluations and
//! early-Z skips per pixel; writes `stackings.csv` into `OUT_DIR` (default
//! `target/bench-gpu/stackings`).
//!
//! Grain counts default to 20k and 200k on a software adapter and add 1.6M and 20M on a GPU;
//! a count whose buffers exceed the adapter's limits is skipped with a message naming the
//! limit (and listed at the end), the others run.

use std::fmt::Write as _;
use std::time::Instant;

use grain_mesh::GrainMesh;
use grain_renderer::bench::{StageTimes, time_frame};
use grain_renderer::impostor_tier::TIER_STATS;
use grain_renderer::renderer::NO_POINT_TIER;
use grain_renderer::{
    ImpostorPath, ImpostorTier, RendererOptions, StackingRenderer, Stage, TierSettings, VisibilityKind,
};
use grain_splitter::sweep::Shot;
use grain_splitter::{OccluderMapKind, SplitCounters};

use crate::cli::{Args, positive};
use crate::impostor_cloud::{GRAINS, load_grain};
use crate::stackings::{bake_atlas, dolly, mesh_threshold, pile_instances, pixels, samples_per_side};

const SIZE: (u32, u32) = (1920, 1080);
const DOLLY_FRAMES: u32 = 5;
const DEFAULT_REPEATS: u32 = 3;
const SCENES: [&str; 2] = ["bean", "rock"];

/// `--dolly-frames`: distinct frame indices of the dolly, ascending, each below
/// [`DOLLY_FRAMES`].
fn dolly_frames(text: &str) -> Result<Vec<u32>, String> {
    let frames: Vec<u32> = text
        .split(',')
        .map(|k| match k.parse::<u32>() {
            Ok(k) if k < DOLLY_FRAMES => Ok(k),
            _ => Err(format!("`{k}` is not a dolly frame: expected 0 to {}", DOLLY_FRAMES - 1)),
        })
        .collect::<Result<_, _>>()?;
    if frames.windows(2).any(|w| w[0] >= w[1]) {
        return Err("frames must be distinct and ascending".to_owned());
    }
    Ok(frames)
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

/// The impostor paths of a row: compute with and without the software early-Z, raster.
const PATHS: [(ImpostorPath, bool); 3] =
    [(ImpostorPath::Compute, true), (ImpostorPath::Compute, false), (ImpostorPath::Raster, false)];

/// The grains benchmarked: `--obj` (with `--mesh-above`), `--scene`, or the bean and the rock.
fn grains(args: &Args<'_>) -> Result<Vec<(String, GrainMesh, f32)>, String> {
    let given = args.parse_value("mesh-above", pixels)?;
    if let Some(path) = args.value("obj") {
        let path = std::path::Path::new(path);
        let (name, mesh) = load_grain(Some(path), "")?;
        return Ok(vec![(name.clone(), mesh, mesh_threshold(given, Some(path), &name)?)]);
    }
    let names: Vec<&str> = match args.value("scene") {
        Some(name) if GRAINS.contains(&name) => vec![name],
        Some(name) => return Err(format!("--scene {name}: expected one of {}", GRAINS.join(", "))),
        None => SCENES.to_vec(),
    };
    names
        .into_iter()
        .map(|name| {
            let (name, mesh) = load_grain(None, name)?;
            let above = mesh_threshold(given, None, &name)?;
            Ok((name, mesh, above))
        })
        .collect()
}

/// Runs the subject.
pub fn run(args: &Args<'_>, counts: Option<Vec<usize>>) -> Result<(), String> {
    let grains = grains(args)?;
    let gpu = gpu_harness::Gpu::new().map_err(|e| e.to_string())?;
    let adapter = format!("\"{}\"", gpu.adapter_info().name.replace('"', "\"\""));
    let counts = counts.unwrap_or(if gpu.is_software() {
        vec![20_000, 200_000]
    } else {
        vec![20_000, 200_000, 1_600_000, 20_000_000]
    });
    let repeats = args.parse_value("frames", positive::<u32>)?.unwrap_or(DEFAULT_REPEATS);
    let dolly_frames = args.parse_value("dolly-frames", dolly_frames)?.unwrap_or_else(|| (0..DOLLY_FRAMES).collect());
    let size = args.parse_value("resolution", crate::cli::resolution)?.unwrap_or(SIZE);
    let samples = args.parse_value("samples", samples_per_side)?.unwrap_or(1);
    let out = args.out_dir();
    std::fs::create_dir_all(&out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let mut kinds = vec![VisibilityKind::TwoPass32];
    if ImpostorTier::supports_atomic64(&gpu.device) {
        kinds.insert(0, VisibilityKind::Atomic64);
    }
    println!(
        "bench-gpu stackings on {} (dolly frames {dolly_frames:?} of {DOLLY_FRAMES}, median of {repeats} each, {}×{})",
        gpu.describe(),
        size.0,
        size.1
    );
    let mut csv =
        String::from("adapter,timing,scene,grains,samples,width,height,frame,distance,visibility,path,early_z,");
    for stage in Stage::ALL {
        let _ = write!(csv, "{}_ms,", stage.name());
    }
    csv += "total_ms,mesh,impostor_occluder,impostor_rest,point,culled_frustum,culled_cone,culled_hiz,\
            evaluated_per_pixel,early_z_skips_per_pixel,resolved_pixels\n";
    let lighting = grain_renderer::renderer::pile_lighting();
    let mut skipped = Vec::new();
    for (name, mesh, mesh_above) in &grains {
        let started = Instant::now();
        let atlas = bake_atlas(&gpu, mesh)?;
        let bounds = mesh.bounds();
        println!(
            "  {name} (r/R = {:.2}, meshes above {mesh_above:.1} px): atlas in {:.1} s",
            bounds.occluder_radius() / bounds.outer_radius,
            started.elapsed().as_secs_f64()
        );
        for &count in &counts {
            let capacity = u32::try_from(count).map_err(|_| format!("{count} grains: more than a u32 can count"))?;
            let renderers: Result<Vec<StackingRenderer>, _> = kinds
                .iter()
                .map(|&visibility| {
                    let options = RendererOptions {
                        size,
                        capacity,
                        mesh_above: *mesh_above,
                        point_below: NO_POINT_TIER,
                        band: 1.1,
                        occluder_map: OccluderMapKind::Auto,
                        visibility,
                        culling: true,
                        samples,
                    };
                    StackingRenderer::new(&gpu.device, &gpu.queue, mesh, &atlas, options)
                })
                .collect();
            let renderers = match renderers {
                Ok(renderers) => renderers,
                Err(e) => {
                    println!("  {count} {name}: skipped on this adapter: {e}");
                    skipped.push(format!("{count} {name}: {e}"));
                    continue;
                }
            };
            let started = Instant::now();
            let (stacking, instances) = pile_instances(count, mesh)?;
            let region = stacking.bounds();
            let shots = Shot::fig15(region.min, region.max);
            println!("  {count} {name}: pile in {:.1} s", started.elapsed().as_secs_f64());
            for renderer in &renderers {
                let visibility = renderer.impostor_tier().kind();
                let scene = renderer.upload(&gpu.device, &instances).map_err(|e| format!("{count} {name}: {e}"))?;
                for (path, early_z) in PATHS {
                    let tier = TierSettings { early_z, path, ..TierSettings::default() };
                    for &k in &dolly_frames {
                        let camera = dolly(&shots, k, DOLLY_FRAMES, size)?;
                        // One untimed frame: the two-phase history and the hysteresis settle.
                        time_frame(&gpu, renderer, &scene, &camera, &lighting, tier).map_err(|e| e.to_string())?;
                        let mut timings: Vec<StageTimes> = Vec::new();
                        for _ in 0..repeats {
                            timings.push(
                                time_frame(&gpu, renderer, &scene, &camera, &lighting, tier)
                                    .map_err(|e| e.to_string())?,
                            );
                        }
                        let row = Row::measure(&gpu, renderer, &timings, size)?;
                        let distance = (camera.uniforms.eye.truncate() - shots[0].target).length();
                        let path_name = match path {
                            ImpostorPath::Compute => "compute",
                            ImpostorPath::Raster => "raster",
                        };
                        println!("    {visibility:?} {path_name} early-Z {early_z} frame {k}: {}", row.describe());
                        let timing = format!("{:?}", timings[0].source);
                        let _ = write!(
                            csv,
                            "{adapter},{timing},{name},{count},{samples},{},{},{k},{distance:.3},{visibility:?},{path_name},{early_z},",
                            size.0, size.1
                        );
                        row.write_csv(&mut csv);
                    }
                }
            }
        }
    }
    let path = out.join("stackings.csv");
    std::fs::write(&path, csv).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    println!("wrote {}", path.display());
    if !skipped.is_empty() {
        println!("skipped (the adapter's limits): {}", skipped.join("; "));
    }
    Ok(())
}

/// One row's figures.
struct Row {
    /// The image, pixels.
    size: (u32, u32),
    stage_ms: Vec<f64>,
    total: f64,
    counters: SplitCounters,
    stats: [u32; TIER_STATS as usize],
}

impl Row {
    fn measure(
        gpu: &gpu_harness::Gpu,
        renderer: &StackingRenderer,
        samples: &[StageTimes],
        size: (u32, u32),
    ) -> Result<Self, String> {
        let stage_ms = (0..Stage::ALL.len()).map(|s| median(samples.iter().map(|t| t.ms[s]).collect())).collect();
        let total = median(samples.iter().map(StageTimes::total).collect());
        let stats =
            gpu.read_buffer(renderer.impostor_tier().stats(), u64::from(TIER_STATS) * 4).map_err(|e| e.to_string())?;
        Ok(Self {
            size,
            stage_ms,
            total,
            counters: renderer.read_counters(gpu).map_err(|e| e.to_string())?,
            stats: bytemuck::pod_read_unaligned(&stats),
        })
    }

    fn per_pixel(&self) -> (f64, f64) {
        let pixels = f64::from(self.size.0 * self.size.1);
        (f64::from(self.stats[0] + self.stats[1]) / pixels, f64::from(self.stats[2] + self.stats[3]) / pixels)
    }

    fn describe(&self) -> String {
        let (evaluated, skipped) = self.per_pixel();
        format!(
            "{:.2} ms ({}); lists {:?}, culled {:?}, atlas evaluations {evaluated:.2}/px, skips {skipped:.2}/px",
            self.total,
            Stage::ALL
                .iter()
                .zip(&self.stage_ms)
                .map(|(s, ms)| format!("{} {ms:.2}", s.name()))
                .collect::<Vec<_>>()
                .join(", "),
            self.counters.count,
            &self.counters.culled[..3]
        )
    }

    fn write_csv(&self, csv: &mut String) {
        for ms in &self.stage_ms {
            let _ = write!(csv, "{ms:.4},");
        }
        let (evaluated, skipped) = self.per_pixel();
        let (c, s) = (&self.counters, &self.stats);
        let _ = writeln!(
            csv,
            "{:.4},{},{},{},{},{},{},{},{evaluated:.4},{skipped:.4},{}",
            self.total, c.count[0], c.count[1], c.count[2], c.count[3], c.culled[0], c.culled[1], c.culled[2], s[4]
        );
    }
}

#[cfg(test)]
mod tests {
    use super::dolly_frames;

    #[test]
    fn dolly_frames_are_distinct_ascending_indices_of_the_dolly() {
        assert_eq!(dolly_frames("0,4").unwrap(), vec![0, 4]);
        assert_eq!(dolly_frames("2").unwrap(), vec![2]);
        assert!(dolly_frames("5").unwrap_err().contains("`5` is not a dolly frame: expected 0 to 4"));
        assert!(dolly_frames("0,x").unwrap_err().contains("`x`"));
        assert!(dolly_frames("4,0").unwrap_err().contains("ascending"));
        assert!(dolly_frames("1,1").unwrap_err().contains("distinct"));
    }
}
