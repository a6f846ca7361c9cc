//! `cargo xtask bench-gpu SUBJECT [OUT_DIR] [--grains LIST] [--frames N]`; subject `ddm`
//! (`--quick`, `--size WxHxD`, `--resolution WxH` and the tile flags of `xtask ddm-render`)
//! is [`crate::bench_ddm`]; subject `stackings`
//! (which also takes `--scene NAME`, `--obj PATH`, `--mesh-above PX`, `--samples S`)
//! is [`crate::bench_stackings`]; subject `svo` (`--scene NAME`, `--obj PATH`,
//! `--height-map PNG`, `--pixels N`, `--levels L`, `--zoom K`, `--views N`) is
//! [`crate::svo::bench`]. `culling`: GPU time of the
//! occluder map and the splitter (`grain_splitter::bench`) on piles of coffee beans and of
//! balls from `grain-scenes` at 1920×1080, in two shots (the whole pile; close, most grains outside the
//! frustum and the nearest as meshes), for each occluder map the adapter has (64-bit, 32-bit),
//! each culling (the paper's cone; + the Hi-Z test of occluder fusion; + two-phase, last
//! frame's visible grains as occluders) and list order (atomic, stable; both only for the cone
//! and two-phase), with grains per tier and the culled fractions by frustum, cone and Hi-Z;
//! writes `culling.csv` into `OUT_DIR` (default `target/bench-gpu/culling`). The Hi-Z
//! passes (cover, bounds, reduction) are timed with the occluder map.
//!
//! Sizes default to 20k and 200k on a software adapter and add 1.6M and 20M on a GPU;
//! a size whose buffers exceed the adapter's limits is an error naming the limit.

use std::fmt::Write as _;
use std::str::FromStr;
use std::time::Instant;

use grain_scenes::{GrainRadii, Region, Stacking, StackingSize, StackingSpec};
use grain_splitter::bench::{BenchFrames, time_frames};
use grain_splitter::sweep::Shot;
use grain_splitter::{GrainSplitter, ListOrder, OccluderMapKind, SplitSettings, SplitterOptions, TierThresholds};

use crate::cli::{Args, positive};

const SIZE: (u32, u32) = (1920, 1080);
const WARM_UP: u32 = 5;
/// The cullings and list orders measured: both orders where the order is the question.
const CULLINGS: [(&str, ListOrder); 5] = [
    ("cone", ListOrder::Atomic),
    ("cone", ListOrder::Stable),
    ("hiz", ListOrder::Atomic),
    ("two-phase", ListOrder::Atomic),
    ("two-phase", ListOrder::Stable),
];
/// Timed frames by default (the issue asks for the median of at least 50).
const DEFAULT_FRAMES: u32 = 60;

/// A grain count: a paper size (`20k`, `200k`, `1.6M`, `20M`) or a positive integer.
pub(crate) fn grain_count(word: &str) -> Result<usize, String> {
    let word = word.trim();
    StackingSize::from_str(word)
        .map(|size| size.count())
        .or_else(|_| positive::<usize>(word))
        .map_err(|_| format!("`{word}` is neither a paper size (20k, 200k, 1.6M, 20M) nor a positive integer"))
}

/// A comma-separated list of grain counts ([`grain_count`]).
fn grain_counts(text: &str) -> Result<Vec<usize>, String> {
    text.split(',').map(grain_count).collect()
}

/// A pile of balls (`r = R = 1`): the pile of `cargo xtask culling-chart`, where the cone and
/// the Hi-Z test cull (they cull nothing on the beans, whose measured `r/R` is 0.22).
fn ball_pile(count: usize) -> Result<Stacking, String> {
    crate::culling_chart::pile(count)
}

/// A pile of coffee beans (the measured `r` and `R` of `grain_mesh::CoffeeBean`), denser
/// than touching outer balls (inner balls disjoint by construction).
fn bean_pile(count: usize) -> Result<(Stacking, f32, f32), String> {
    let bean = grain_mesh::CoffeeBean::default().mesh().map_err(|e| e.to_string())?;
    let (r, outer) = (bean.bounds().occluder_radius(), bean.bounds().outer_radius);
    let mut spec = StackingSpec::new(count, GrainRadii::new(r, outer).map_err(|e| e.to_string())?);
    spec.seed = 9;
    spec.region = Region::Pile { slope: 0.6 };
    spec.scale_jitter = 0.1;
    spec.jitter = 0.05;
    spec.spacing = 0.85;
    Ok((Stacking::generate(&spec).map_err(|e| e.to_string())?, r, outer))
}

pub fn run(args: &Args<'_>) -> Result<(), String> {
    if args.subject() != "stackings" && args.value("dolly-frames").is_some() {
        return Err(format!("bench-gpu {}: --dolly-frames applies to `bench-gpu stackings` only", args.subject()));
    }
    const SVO_ONLY: [&str; 5] = ["height-map", "pixels", "levels", "zoom", "views"];
    const DDM_ONLY: [&str; 7] = ["quick", "size", "scale", "fit-slab", "height", "periodic", "clamp"];
    if args.subject() == "ddm" {
        for flag in ["grains", "scene", "mesh-above", "samples", "pixels", "levels", "zoom", "views"] {
            if args.value(flag).is_some() {
                return Err(format!("bench-gpu ddm: --{flag} does not apply to `bench-gpu ddm`"));
            }
        }
        return crate::bench_ddm::run(args);
    }
    for flag in DDM_ONLY {
        if args.flag(flag) {
            return Err(format!("bench-gpu {}: --{flag} applies to `bench-gpu ddm` only", args.subject()));
        }
    }
    if args.subject() == "svo" {
        for flag in ["grains", "mesh-above", "samples", "resolution"] {
            if args.value(flag).is_some() {
                return Err(format!("bench-gpu svo: --{flag} does not apply to `bench-gpu svo`"));
            }
        }
        return crate::svo::bench(args);
    }
    for flag in SVO_ONLY {
        if args.value(flag).is_some() {
            return Err(format!("bench-gpu {}: --{flag} applies to `bench-gpu svo` only", args.subject()));
        }
    }
    if args.subject() == "stackings" {
        return crate::bench_stackings::run(args, args.parse_value("grains", grain_counts)?);
    }
    for flag in ["scene", "obj", "mesh-above", "samples"] {
        if args.value(flag).is_some() {
            return Err(format!("bench-gpu culling: --{flag} applies to `bench-gpu stackings` and `svo` only"));
        }
    }
    let gpu = gpu_harness::Gpu::new().map_err(|e| e.to_string())?;
    // Quoted for CSV: adapter names hold commas ("llvmpipe (LLVM 15.0.6, 256 bits)").
    let adapter = format!("\"{}\"", gpu.adapter_info().name.replace('"', "\"\""));
    let default_sizes =
        if gpu.is_software() { vec![20_000, 200_000] } else { vec![20_000, 200_000, 1_600_000, 20_000_000] };
    let counts = args.parse_value("grains", grain_counts)?.unwrap_or(default_sizes);
    let timed = args.parse_value("frames", positive::<u32>)?.unwrap_or(DEFAULT_FRAMES);
    let size = args.parse_value("resolution", crate::cli::resolution)?.unwrap_or(SIZE);
    let out = args.out_dir();
    std::fs::create_dir_all(&out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let has_64 = GrainSplitter::supports_atomic64(&gpu.device);
    let mut kinds = vec![OccluderMapKind::TwoPass32];
    if has_64 {
        kinds.insert(0, OccluderMapKind::Atomic64);
    }
    println!("bench-gpu culling on {} ({} timed frames after {WARM_UP}, {}×{})", gpu.describe(), timed, size.0, size.1);
    let rows = measure_table(&gpu, &adapter, &counts, &kinds, timed, size)?;
    let path = out.join("culling.csv");
    std::fs::write(&path, rows).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    println!("wrote {}", path.display());
    Ok(())
}

fn measure_table(
    gpu: &gpu_harness::Gpu,
    adapter: &str,
    counts: &[usize],
    kinds: &[OccluderMapKind],
    timed: u32,
    size: (u32, u32),
) -> Result<String, String> {
    let mut csv = String::from(
        "adapter,timing,scene,grains,shot,width,height,occluder_map,order,frames,map_ms,split_ms,total_ms,\
         culling,mesh,impostor_occluder,impostor_rest,point,culled_frustum,culled_cone,culled_hiz,\
         frustum_fraction,cone_fraction,hiz_fraction\n",
    );
    let rows = grain_impostor::choice::measured_accuracy()?;
    for (&count, scene) in counts.iter().flat_map(|c| [(c, "beans"), (c, "balls")]) {
        let started = Instant::now();
        let (stacking, r, outer) = if scene == "beans" { bean_pile(count)? } else { (ball_pile(count)?, 1.0, 1.0) };
        let thresholds =
            TierThresholds::from_impostor_table(&rows, "bean", 0.05, 2.0, 1.1).map_err(|e| e.to_string())?;
        let base = SplitSettings::new(r, outer, thresholds);
        let bounds = stacking.bounds();
        let [wide, _, foreground] = Shot::fig15(bounds.min, bounds.max);
        let grains = u32::try_from(count).map_err(|_| format!("{count} grains do not fit a u32 index"))?;
        let buffer = GrainSplitter::upload_grains(&gpu.device, stacking.centre_scale())
            .map_err(|e| format!("{count} grains: {e}"))?;
        println!(
            "  {count} {scene} (r/R = {:.2}): generated and uploaded in {:.1} s",
            r / outer,
            started.elapsed().as_secs_f64()
        );
        for shot in [wide, foreground] {
            let camera = shot.camera(size).map_err(|e| e.to_string())?;
            for &kind in kinds {
                for (culling, order) in CULLINGS {
                    let settings = SplitSettings {
                        hiz_culling: culling != "cone",
                        temporal_occluders: culling == "two-phase",
                        ..base
                    };
                    let options = SplitterOptions { capacity: grains, size, occluder_map: kind, order };
                    let splitter = GrainSplitter::new(&gpu.device, settings, options).map_err(|e| e.to_string())?;
                    let bindings = splitter.bind(&gpu.device, &buffer).map_err(|e| e.to_string())?;
                    let frames = BenchFrames { warm_up: WARM_UP, timed };
                    let result =
                        time_frames(gpu, &splitter, &bindings, &camera, grains, frames).map_err(|e| e.to_string())?;
                    let c = result.counters;
                    let timing = match result.source {
                        gpu_harness::TimingSource::Timestamps => "timestamps",
                        gpu_harness::TimingSource::WallClock => "wall clock",
                    };
                    println!(
                        "    {} {kind:?} {culling} {order:?}: map {:.3} ms, split {:.3} ms, total {:.3} ms ({timing}); lists {:?}, culled frustum {} cone {} Hi-Z {}",
                        shot.name,
                        result.map_ms,
                        result.split_ms,
                        result.total_ms,
                        c.count,
                        c.culled[0],
                        c.culled[1],
                        c.culled[2]
                    );
                    let fraction = |n: u32| f64::from(n) / count as f64;
                    writeln!(
                    csv,
                    "{adapter},{timing},{scene},{count},{},{},{},{kind:?},{order:?},{},{:.4},{:.4},{:.4},{culling},{},{},{},{},{},{},{},{:.5},{:.5},{:.5}",
                    shot.name,
                    size.0,
                    size.1,
                    result.frames,
                    result.map_ms,
                    result.split_ms,
                    result.total_ms,
                    c.count[0],
                    c.count[1],
                    c.count[2],
                    c.count[3],
                    c.culled[0],
                    c.culled[1],
                    c.culled[2],
                    fraction(c.culled[0]),
                    fraction(c.culled[1]),
                    fraction(c.culled[2]),
                )
                .map_err(|e| e.to_string())?;
                }
            }
        }
    }
    Ok(csv)
}
