//! Interleaved A/B timing of tracing on raw against compressed DDMs (issue 4's "time
//! within 5 %"): `cargo run --release -p benches --example ddm_compression_overhead
//! [ROUNDS [MESOSTRUCTURE [WxHxD]]]` (default 31 rounds, the maze, 16 × 16 × 8).
//!
//! Criterion times one benchmark after the other, so a drift of the machine's speed
//! between them (seen at ±15 % on a shared VM) shows up as a difference. Here each round
//! times one pass of the 4096 rays of `benches/ddm_tracer.rs` (DDM 4×1)
//! on the raw maps and one on the compressed maps (blocks of 4), in alternating order, and
//! the median of the per-round ratios compressed / raw is printed per patch kind.

use std::hint::black_box;
use std::time::Instant;

use ddm_compress::{DirectionCones, DistanceMapSettings, MapKind, compute_distance_maps};
use ddm_tracer::{
    CompressedMaps, DistanceSource, Method, PatchSettings, PatchSurface, Stepping, TraceSettings, VoxelPatches, trace,
};
use glam::{UVec3, Vec3};
use mesostructure::Mesostructure;

/// Seconds for one pass of `rays` (best of 3 repetitions, to skip interruptions).
fn pass<S: DistanceSource>(source: &S, patches: &VoxelPatches, rays: &[(Vec3, Vec3)], settings: TraceSettings) -> f64 {
    (0..3)
        .map(|_| {
            let start = Instant::now();
            let hits =
                rays.iter().filter(|&&(o, d)| trace(source, Some(patches), black_box(o), d, settings).hit.is_some());
            black_box(hits.count());
            start.elapsed().as_secs_f64()
        })
        .fold(f64::INFINITY, f64::min)
}

fn main() -> Result<(), String> {
    let usage = "usage: ddm_compression_overhead [ROUNDS [MESOSTRUCTURE [WxHxD]]]";
    let args: Vec<String> = std::env::args().skip(1).collect();
    let rounds: usize = match args.first() {
        Some(text) => text.parse().map_err(|e| format!("{usage}: {e}"))?,
        None => 31,
    };
    let structure = match args.get(1) {
        Some(name) => *Mesostructure::ALL
            .iter()
            .find(|m| m.name() == name)
            .ok_or_else(|| format!("{usage}: no mesostructure {name}"))?,
        None => Mesostructure::Maze(1),
    };
    let dims = match args.get(2) {
        Some(text) => {
            let size: Vec<u32> =
                text.split('x').map(str::parse).collect::<Result<_, _>>().map_err(|e| format!("{usage}: {e}"))?;
            let [x, y, z] = size[..] else { return Err(usage.into()) };
            UVec3::new(x, y, z)
        }
        None => UVec3::new(16, 16, 8),
    };
    let triangles = structure.triangles(dims);
    let settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: true };
    let structure_name = structure.name();
    let ddm4x1 = MapKind::Directional(DirectionCones::downward(4, 1).map_err(|e| e.to_string())?);
    let ddm = compute_distance_maps(dims, &triangles, ddm4x1, settings)
        .map_err(|e| format!("{structure_name}: the DDM 4x1 maps: {e}"))?;
    let compressed = CompressedMaps::compress(&ddm, 4)
        .map_err(|e| format!("{structure_name}: compressing the DDM 4x1 maps: {e}"))?;
    let rays = benches::tracer_rays(dims);
    for (name, surface, stepping) in [
        ("sphere tracing (no patches)", PatchSurface::C0, Stepping::Distance),
        ("sphere tracing, block cells", PatchSurface::C0, Stepping::BlockCells),
        ("sphere tracing, voxel exit", PatchSurface::C0, Stepping::VoxelExit),
        ("C0 quadric", PatchSurface::C0, Stepping::Distance),
        ("C0 quadric, block cells", PatchSurface::C0, Stepping::BlockCells),
        ("adaptive 1e-3", PatchSurface::Adaptive { max_error: 1e-3 }, Stepping::Distance),
        ("adaptive 1e-3, block cells", PatchSurface::Adaptive { max_error: 1e-3 }, Stepping::BlockCells),
        ("adaptive 1e-3, voxel exit", PatchSurface::Adaptive { max_error: 1e-3 }, Stepping::VoxelExit),
    ] {
        let patches =
            VoxelPatches::build(dims, &triangles, &ddm.surface, PatchSettings { surface, ..Default::default() })
                .map_err(|e| format!("{structure_name}: the {name} patches: {e}"))?;
        let method = if name.starts_with("sphere") { Method::SphereTracing } else { Method::Quadric };
        let trace_settings = TraceSettings { method, max_steps: 512, stepping };
        let mut ratios = Vec::with_capacity(rounds);
        let (mut raw_total, mut compressed_total) = (0.0, 0.0);
        for round in 0..rounds {
            let (raw, packed) = if round % 2 == 0 {
                let raw = pass(&ddm, &patches, &rays, trace_settings);
                (raw, pass(&compressed, &patches, &rays, trace_settings))
            } else {
                let packed = pass(&compressed, &patches, &rays, trace_settings);
                (pass(&ddm, &patches, &rays, trace_settings), packed)
            };
            ratios.push(packed / raw);
            raw_total += raw;
            compressed_total += packed;
        }
        let steps =
            |source: &dyn Fn(Vec3, Vec3) -> u32| rays.iter().map(|&(o, d)| f64::from(source(o, d))).sum::<f64>();
        let raw_steps = steps(&|o, d| trace(&ddm, Some(&patches), o, d, trace_settings).steps);
        let compressed_steps = steps(&|o, d| trace(&compressed, Some(&patches), o, d, trace_settings).steps);
        ratios.sort_by(f64::total_cmp);
        let median = ratios[rounds / 2];
        let (low, high) = (ratios[rounds / 4], ratios[3 * rounds / 4]);
        println!(
            "{name:28} raw {:7.0} k rays/s, compressed {:7.0} k rays/s; time ratio compressed/raw: median {median:.3} (quartiles {low:.3}–{high:.3}), {rounds} rounds; mean steps raw {:.2}, compressed {:.2}",
            rays.len() as f64 * rounds as f64 / raw_total / 1e3,
            rays.len() as f64 * rounds as f64 / compressed_total / 1e3,
            raw_steps / rays.len() as f64,
            compressed_steps / rays.len() as f64,
        );
    }
    Ok(())
}
