//! `cargo xtask bench-gpu ddm [OUT_DIR] [--quick] [--frames N] [--resolution WxH] [--size WxHxD]
//! [--obj PATH | --height-map PNG] [--scale S | --fit-slab] [--height H]`: GPU time per frame of
//! `ddm-render`'s embeddable renderer (the base mesh's G-buffer raster pass and the per-pixel
//! trace, shading and shadow ray: [`ddm_render::time_frames`]) for every tile (the five
//! procedural ones, or the user's: [`crate::ddm_input`]), on both base meshes of `xtask
//! ddm-render` (the plane of 4 × 4 tiles and the torus, same cameras and lights), for every
//! method — sphere tracing with the plain DM and with the DDM 4×1; DDM 4×1 + the C⁰
//! quadrics, + the watertight patches, + the adaptive patches (with distance and with
//! voxel-exit stepping); relief mapping (32 + 8 steps) on height fields — with and without
//! shadow rays, and for three map layouts: `uncompressed` (one word per voxel,
//! `GpuScene::uncompressed`), `block4` (§4's compression, 4³ blocks) and `block4 f16` (the
//! same with the atlas in binary16 rounded down, `GpuScene::with_f16_atlas`). Table 3's
//! claim, compression "never more than 5 % slower", is the ratio of the first two, printed
//! per method, and the f16 atlas's ratio to the f32 one after it. Each scene's pipeline is
//! specialised for its method, stepping, tiling, block shift and atlas (pipeline constants).
//!
//! Writes `ddm.csv` into `OUT_DIR` (default `target/bench-gpu/ddm`): per row the adapter,
//! tile, base, method, layout, shadows, size, the median, 10 % and 90 % frame times, the
//! per-pixel pass alone (timestamps only), covered and hit pixels, the primary ray's mean
//! steps per covered pixel, ns per covered pixel, the scene's storage bytes, the frames and
//! how they were timed. Defaults: 1920×1080, tiles of 16 × 16 × 8 voxels, 100 timed frames
//! after 10 on a hardware adapter; 320×180 and 5 after 1 on a software one; `--quick` 96×54,
//! 12 × 12 × 6 voxels, 2 after 1 (a smoke run).

use std::fmt::Write as _;
use std::path::Path;

use ddm_compress::DistanceMaps;
use ddm_render::{
    DdmFrame, DdmRenderPipelines, DdmRenderer, GpuSceneBuffers, PixelReadback, RenderSettings, RendererTimes, wgpu,
};
use ddm_tracer::tangent_space::{PIXEL_HIT, PIXEL_UNCOVERED};
use ddm_tracer::{CompressedMaps, GpuScene, Method, Stepping, TraceSettings, VoxelPatches};
use glam::{UVec3, Vec3};
use gpu_harness::{Gpu, TimingSource};

use crate::cli::{Args, positive};
use crate::ddm_input::{self, TileSource};
use crate::ddm_render::{Base, MAX_STEPS, RELIEF_BINARY, RELIEF_LINEAR, TileMaps, base_meshes};

/// The compressed layout's block side (§4).
const BLOCK: u32 = 4;

/// The patches a method traces.
#[derive(Clone, Copy)]
enum Patches {
    None,
    C0,
    Watertight,
    Adaptive,
}

/// One method: its name, maps (`true` the DDM 4×1, else the plain DM), patches, tracer
/// settings and shadow tolerance (as `xtask ddm-render`'s).
struct MethodCase {
    name: &'static str,
    ddm: bool,
    patches: Patches,
    settings: TraceSettings,
    shadow_tolerance: f32,
}

fn methods() -> Vec<MethodCase> {
    let sphere = TraceSettings { method: Method::SphereTracing, max_steps: MAX_STEPS, stepping: Stepping::Distance };
    let quadric = TraceSettings { method: Method::Quadric, ..sphere };
    let exit = TraceSettings { stepping: Stepping::VoxelExit, ..quadric };
    let case =
        |name, ddm, patches, settings, shadow_tolerance| MethodCase { name, ddm, patches, settings, shadow_tolerance };
    vec![
        case("dm", false, Patches::None, sphere, 1.75),
        case("ddm4x1", true, Patches::None, sphere, 1.75),
        case("ddm4x1_quadric", true, Patches::C0, quadric, 0.02),
        case("ddm4x1_watertight", true, Patches::Watertight, quadric, 0.02),
        case("ddm4x1_adaptive", true, Patches::Adaptive, quadric, 0.02),
        case("ddm4x1_adaptive_exit", true, Patches::Adaptive, exit, 0.02),
    ]
}

/// Sizes, frames and tiles of a run.
struct BenchSize {
    resolution: (u32, u32),
    dims: UVec3,
    warm_up: u32,
    frames: u32,
}

impl BenchSize {
    fn new(args: &Args<'_>, gpu: &Gpu) -> Result<Self, String> {
        let (resolution, dims, warm_up, frames) = if args.flag("quick") {
            ((96, 54), UVec3::new(12, 12, 6), 1, 2)
        } else if gpu.is_software() {
            ((320, 180), UVec3::new(16, 16, 8), 1, 5)
        } else {
            ((1920, 1080), UVec3::new(16, 16, 8), 10, 100)
        };
        Ok(Self {
            resolution: args.parse_value("resolution", crate::cli::resolution)?.unwrap_or(resolution),
            dims: args.parse_value("size", crate::cli::grid_size)?.unwrap_or(dims),
            warm_up,
            frames: args.parse_value("frames", positive::<u32>)?.unwrap_or(frames),
        })
    }
}

/// One measured configuration.
struct Row {
    tile: &'static str,
    base: &'static str,
    method: &'static str,
    layout: &'static str,
    shadows: bool,
    median_ms: f64,
    p10_ms: f64,
    p90_ms: f64,
    trace_median_ms: Option<f64>,
    covered: usize,
    hits: usize,
    mean_steps: f64,
    scene_bytes: usize,
    source: TimingSource,
}

/// The command.
pub fn run(args: &Args<'_>) -> Result<(), String> {
    let gpu = Gpu::new().map_err(|e| e.to_string())?;
    let size = BenchSize::new(args, &gpu)?;
    let (width, height) = size.resolution;
    let source = TileSource::from_args(args)?;
    let periodic = ddm_input::periodic_from_args(args, source.as_ref())?;
    let tiles = ddm_input::tiles(source.as_ref(), size.dims, periodic)?;
    let out = args.out_dir();
    std::fs::create_dir_all(&out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    println!(
        "bench-gpu ddm on {}: {width}×{height}, tiles of {}×{}×{} voxels ({}), {} timed frames after {}",
        gpu.describe(),
        size.dims.x,
        size.dims.y,
        size.dims.z,
        ddm_input::describe(source.as_ref()),
        size.frames,
        size.warm_up
    );
    let started = std::time::Instant::now();
    let pipelines = DdmRenderPipelines::new(&gpu.device).map_err(|e| e.to_string())?;
    let bases = base_meshes(&gpu, &pipelines, size.dims, width, height)?;
    let color = gpu
        .scoped(|| {
            gpu.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("bench-gpu ddm colour target"),
                size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: ddm_render::COLOR_TARGET_FORMAT,
                usage: wgpu::TextureUsages::STORAGE_BINDING,
                view_formats: &[],
            })
        })
        .map_err(|e| e.to_string())?;
    let mut rows = Vec::new();
    for tile in &tiles {
        let maps = TileMaps::build(tile, size.dims, true)?;
        let scenes = tile_scenes(tile.name, &maps)?;
        for base in &bases {
            for (method, layout, scene, tolerance) in &scenes {
                let uploaded = GpuSceneBuffers::new(&gpu.device, scene).map_err(|e| format!("{}: {e}", tile.name))?;
                let renderer = DdmRenderer::new(&gpu.device, &pipelines, &base.gbuffer, &uploaded)
                    .map_err(|e| format!("{}: {e}", tile.name))?;
                let target = renderer.color_target(&gpu.device, &color).map_err(|e| e.to_string())?;
                let readback = PixelReadback::new(&gpu, &renderer).map_err(|e| e.to_string())?;
                for shadows in [false, true] {
                    let settings = render_settings(base, shadows.then_some(*tolerance));
                    let frame = DdmFrame::new(&base.camera, settings);
                    let (times, work) = measure(&gpu, &renderer, &frame, &target, &readback, &size)
                        .map_err(|e| format!("{} on the {} with {method}: {e}", tile.name, base.name))?;
                    let row = Row {
                        tile: tile.name,
                        base: base.name,
                        method,
                        layout,
                        shadows,
                        median_ms: times.frame.median(),
                        p10_ms: times.frame.quantile(0.1),
                        p90_ms: times.frame.quantile(0.9),
                        trace_median_ms: times.trace.as_ref().map(|t| t.median()),
                        covered: work.covered,
                        hits: work.hits,
                        mean_steps: work.mean_steps,
                        scene_bytes: scene.storage_bytes().iter().map(|b| b.len()).sum(),
                        source: times.frame.source,
                    };
                    println!(
                        "  {:<11} {:<6} {:<21} {:<12} shadows {:<5} {:>9.4} ms (p10 {:.4}, p90 {:.4}), {:>7} covered, {:.1} steps",
                        row.tile,
                        row.base,
                        row.method,
                        row.layout,
                        row.shadows,
                        row.median_ms,
                        row.p10_ms,
                        row.p90_ms,
                        row.covered,
                        row.mean_steps
                    );
                    rows.push(row);
                }
            }
        }
    }
    print_layout_ratios(&rows, "block4", "uncompressed", "Table 3: \"never more than 5 % slower\"");
    print_layout_ratios(&rows, "block4 f16", "block4", "the atlas in binary16 against f32");
    let adapter = gpu.adapter_info().name.replace('"', "\"\"");
    let path = out.join("ddm.csv");
    write_csv(&path, &rows, &adapter, size.resolution, size.frames)?;
    println!(
        "bench-gpu ddm: {} rows in {:.1} s, wrote {}",
        rows.len(),
        started.elapsed().as_secs_f64(),
        path.display()
    );
    Ok(())
}

/// Every method's scene in both layouts (relief once, in its own layout `height map`).
fn tile_scenes(name: &str, maps: &TileMaps) -> Result<Vec<(&'static str, &'static str, GpuScene, f32)>, String> {
    let failed = |what: &str, error: &dyn std::fmt::Display| format!("{name}: {what}: {error}");
    let packed = |maps: &DistanceMaps| CompressedMaps::compress(maps, BLOCK).map_err(|e| failed("compressing", &e));
    let (plain_packed, ddm_packed) = (packed(&maps.plain)?, packed(&maps.ddm)?);
    let mut scenes = Vec::new();
    for case in methods() {
        let patches: Option<&VoxelPatches> = match case.patches {
            Patches::None => None,
            Patches::C0 => Some(&maps.c0),
            Patches::Watertight => maps.watertight.as_ref(),
            Patches::Adaptive => Some(&maps.adaptive),
        };
        let (raw, compressed) = if case.ddm { (&maps.ddm, &ddm_packed) } else { (&maps.plain, &plain_packed) };
        let uncompressed = GpuScene::uncompressed(raw, patches, case.settings)
            .map_err(|e| failed(&format!("the uncompressed {} scene", case.name), &e))?;
        let block = GpuScene::new(compressed, patches, case.settings)
            .map_err(|e| failed(&format!("the compressed {} scene", case.name), &e))?;
        let half = block.clone().with_f16_atlas().map_err(|e| failed(&format!("the f16 {} scene", case.name), &e))?;
        scenes.push((case.name, "uncompressed", uncompressed, case.shadow_tolerance));
        scenes.push((case.name, "block4", block, case.shadow_tolerance));
        scenes.push((case.name, "block4 f16", half, case.shadow_tolerance));
    }
    if let Some(height_map) = &maps.height_map {
        let sphere =
            TraceSettings { method: Method::SphereTracing, max_steps: MAX_STEPS, stepping: Stepping::Distance };
        let scene = GpuScene::new(&plain_packed, None, sphere)
            .and_then(|s| s.with_relief(height_map, RELIEF_LINEAR, RELIEF_BINARY))
            .map_err(|e| failed("the relief scene", &e))?;
        scenes.push(("relief", "height map", scene, 0.25));
    }
    Ok(scenes)
}

/// `xtask ddm-render`'s shading of `base`, with shadow rays at `shadow_tolerance` or none.
fn render_settings(base: &Base, shadow_tolerance: Option<f32>) -> RenderSettings {
    RenderSettings {
        slab: base.slab,
        light: base.light,
        ambient: 0.2,
        shadow_tolerance,
        miss_color: Some(Vec3::new(0.22, 0.27, 0.36)),
        albedo: ddm_render::DEFAULT_ALBEDO,
        normal_tint: ddm_render::DEFAULT_NORMAL_TINT,
    }
}

/// The work of a frame: covered and hit pixels, the primary ray's mean steps per covered pixel.
struct Work {
    covered: usize,
    hits: usize,
    mean_steps: f64,
}

/// Times the frame, then renders it once more into the pixel target for its work.
fn measure(
    gpu: &Gpu,
    renderer: &DdmRenderer,
    frame: &DdmFrame<'_>,
    target: &ddm_render::DdmTarget,
    readback: &PixelReadback,
    size: &BenchSize,
) -> Result<(RendererTimes, Work), String> {
    let times =
        ddm_render::time_frames(gpu, renderer, frame, target, size.warm_up, size.frames).map_err(|e| e.to_string())?;
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    renderer.encode(&gpu.queue, &mut encoder, frame, readback.target()).map_err(|e| e.to_string())?;
    gpu.queue.submit([encoder.finish()]);
    let pixels = readback.read(gpu).map_err(|e| e.to_string())?;
    let covered: Vec<_> = pixels.iter().filter(|p| p.color.w != PIXEL_UNCOVERED).collect();
    let hits = covered.iter().filter(|p| p.color.w == PIXEL_HIT).count();
    let mean_steps = covered.iter().map(|p| f64::from(p.ray_origin.w)).sum::<f64>() / covered.len().max(1) as f64;
    Ok((times, Work { covered: covered.len(), hits, mean_steps }))
}

/// Per tile, base, method and shadows, the median frame time of `layout` over the
/// `baseline` layout's (Table 3's comparison for `block4` over `uncompressed`).
fn print_layout_ratios(rows: &[Row], layout: &str, baseline: &str, what: &str) {
    println!("{layout} / {baseline} median frame time ({what}):");
    let mut worst: Option<(f64, String)> = None;
    for row in rows.iter().filter(|r| r.layout == layout) {
        let Some(raw) = rows.iter().find(|r| {
            r.layout == baseline
                && (r.tile, r.base, r.method, r.shadows) == (row.tile, row.base, row.method, row.shadows)
        }) else {
            continue;
        };
        let ratio = row.median_ms / raw.median_ms;
        let label = format!("{} {} {} shadows {}", row.tile, row.base, row.method, row.shadows);
        println!("  {label:<55} {ratio:.3}");
        if worst.as_ref().is_none_or(|(w, _)| ratio > *w) {
            worst = Some((ratio, label));
        }
    }
    if let Some((ratio, label)) = worst {
        println!("  worst: {ratio:.3} ({label})");
    }
}

fn write_csv(path: &Path, rows: &[Row], adapter: &str, size: (u32, u32), frames: u32) -> Result<(), String> {
    let mut csv = String::from(
        "adapter,tile,base,method,layout,shadows,width,height,median_ms,p10_ms,p90_ms,trace_median_ms,covered_pixels,\
         hit_pixels,mean_steps,ns_per_covered_pixel,scene_bytes,frames,timing\n",
    );
    for r in rows {
        let trace = r.trace_median_ms.map_or(String::new(), |ms| format!("{ms:.5}"));
        let ns_per_pixel = if r.covered > 0 { r.median_ms * 1e6 / r.covered as f64 } else { f64::INFINITY };
        let timing = match r.source {
            TimingSource::Timestamps => "timestamps",
            TimingSource::WallClock => "wall-clock",
        };
        let _ = writeln!(
            csv,
            "\"{adapter}\",{},{},{},{},{},{},{},{:.5},{:.5},{:.5},{trace},{},{},{:.3},{ns_per_pixel:.3},{},{frames},{timing}",
            r.tile,
            r.base,
            r.method,
            r.layout,
            r.shadows,
            size.0,
            size.1,
            r.median_ms,
            r.p10_ms,
            r.p90_ms,
            r.covered,
            r.hits,
            r.mean_steps,
            r.scene_bytes
        );
    }
    std::fs::write(path, csv).map_err(|e| format!("cannot write {}: {e}", path.display()))
}
