//! `cargo xtask ddm-render [OUT_DIR] [--quick] [--size WxHxD] [--resolution WxH] [--obj PATH |
//! --height-map PNG] [--scale S | --fit-slab] [--height H]`: mesostructures mapped onto a base mesh and
//! rendered as Mehra & Kumar do (§3), with `ddm-render`: the coarse base mesh (a plane of
//! 4 × 4 tiles, and a torus) is rasterized into a G-buffer (texture coordinates, tangent
//! frame, world position), then a compute pass builds each covered pixel's ray in the
//! mesostructure's tangent space, traces it with the WGSL tracer, shades the hit (Lambert
//! and ambient, normal mapped back to world space with the frame) and casts a shadow ray
//! toward the light through the same maps (shadowed hits get ambient only). Pixels whose
//! ray reaches the slab's bottom without a hit show the base mesh's own colour
//! (blue-grey); pixels whose ray leaves the torus again before any hit (its silhouettes:
//! `ddm_render`'s second raster pass finds where) and pixels off the base mesh show the
//! background.
//!
//! Each mesostructure (maze, bricks, beads, ball, chain mail) is rendered with each method:
//! sphere tracing with the plain distance map (DM) and with the DDM 4×1 (both stop at the
//! first zero-distance voxel, shading its entry wall), DDM 4×1 + quadric (Algorithm 3.1
//! on the C⁰ patches), DDM 4×1 + adaptive (per voxel the fitted quadric where it stays
//! within 1e-3 voxel of the mesh's triangles, else the triangles: `ddm_tracer::exact_patches`;
//! also with voxel-exit stepping, `ddm4x1_adaptive_exit`: `ddm_tracer::Stepping::VoxelExit`)
//! and relief mapping on the height fields (32 linear + 8 binary steps, 2 texels per voxel).
//! The tiles are 16 × 16 × 8 voxels (12 × 12 × 6 with `--quick`, any grid with `--size`);
//! with `--obj` or `--height-map` the user's tile is rendered instead of the five
//! ([`crate::ddm_input`] says what the coordinates mean and what is checked).
//!
//! **The reference** (`<mesostructure>_<base>_reference.png`): the same pipeline tracing
//! the mesh's own triangles (DDM 4×1 + triangles, `PatchSurface::Triangles`, voxel-exit
//! stepping, up to [`REFERENCE_MAX_STEPS`] steps): the exact mesostructure under the same
//! base mesh, tangent frames, shading and shadows, so that the difference of a method's
//! image from it is the method's own (its geometry, its steps, its shadow rays). Each
//! method's image gets its ꟻLIP map against it (`…_<method>_flip.png`) and its mean ꟻLIP
//! and 1 − SSIM in the CSV.
//! Shadow rays accept hits up to a tolerance short of the shaded point: 1.75 voxel for
//! sphere tracing (its hits are voxel entry points, up to a voxel diagonal from where a
//! shadow ray enters the same voxel), 0.25 voxel for relief, 0.02 voxel for the patches.
//!
//! The torus's slab is `h = 0.4` world units thick for tiles about 1.3–1.9 world units
//! wide: the mesostructure is flattened about 1.4× against its voxel proportions, to keep
//! the rays' depth small against the tube's radius of curvature (the tangent frame is held
//! constant along each ray, the paper's approximation).
//!
//! Everything is built once with `ddm-render`'s embeddable renderer: the pipelines for the
//! run, each base mesh's G-buffer pass (mesh uploaded once), each scene's buffers (uploaded
//! once, shared by both bases), and per base × scene a `DdmRenderer` and its pixel target:
//! it renders every frame with `encode` (no rebuild, no readback), and the target is read
//! back once per image, after its frames, for the PNG and the counts.
//!
//! Writes to `OUT_DIR` (default `target/ddm-render`) `<mesostructure>_<base>_<method>.png`
//! and `ddm_render_times.csv`: per image the covered, hit, left-the-shell and shadowed pixels, those
//! whose primary ray stopped on the step cap, its ꟻLIP
//! and 1 − SSIM against the reference, mean and
//! max tracer steps per covered pixel (primary ray), the per-pixel pass's GPU time
//! (`gpu_ms`, fastest of 3 frames; timestamps where the adapter has them, else the
//! `trace_wall_ms` below), the wall time of one whole frame (`pass_call_wall_ms`: raster and
//! per-pixel passes, submission to completion, warm pipelines; fastest of 3), the frame's
//! fixed cost (`call_overhead_wall_ms`: the same submission with the raster pass only;
//! fastest of 3), their difference `trace_wall_ms` (the per-pixel work) and the base's
//! raster wall time (`raster_wall_ms`, measured once per base, fastest of 3). On lavapipe,
//! with both passes in one command buffer, `gpu_ms` follows `trace_wall_ms` within about a
//! millisecond (measured; when the per-pixel pass was a lone dispatch its timestamps stayed
//! at 0.01–0.07 ms whatever the work), and `trace_wall_ms` remains the time to trust
//! there; on a hardware adapter the timestamps are.

use std::fmt::Write as _;
use std::path::PathBuf;

use ddm_compress::{DirectionCones, DistanceMapSettings, DistanceMaps, MapKind, compute_distance_maps};
use ddm_render::{
    Camera, DdmFrame, DdmRenderPipelines, DdmRenderer, GBufferPass, GpuSceneBuffers, PassTimestamps, PixelReadback,
    RenderSettings, pixels_to_image, plane_base_mesh, wgpu,
};
use ddm_tracer::GpuScene;
use ddm_tracer::tangent_space::{PIXEL_HIT, PIXEL_LEFT_SHELL, PIXEL_UNCOVERED};
use ddm_tracer::{
    CompressedMaps, HeightMap, MeshRaycaster, Method, PatchSettings, PatchSurface, Stepping, TraceSettings,
    VoxelPatches,
};
use glam::{UVec2, UVec3, Vec2, Vec3};
use gpu_harness::Gpu;
use grain_impostor::half::f16_bits_to_f32;

use crate::ddm_input::{self, Tile, TileSource};

pub(crate) const MAX_STEPS: u32 = 256;
/// The reference's step cap (16× the methods'): the pixels that still stop on it are
/// counted (`capped_pixels`; on the torus, rays that run nearly parallel to the slab
/// through the periodic tiles, drawn as misses by every method).
const REFERENCE_MAX_STEPS: u32 = 4096;
/// The reference scene's name.
const REFERENCE: &str = "reference";
pub(crate) const RELIEF_LINEAR: u32 = 32;
pub(crate) const RELIEF_BINARY: u32 = 8;
const BACKGROUND: [u8; 3] = [18, 20, 30];
/// Frames per image; the fastest is reported.
const FRAMES: usize = 3;

/// One base mesh with its G-buffer pass, camera, light and slab.
pub(crate) struct Base {
    pub name: &'static str,
    pub gbuffer: GBufferPass,
    pub camera: Camera,
    pub light: Vec3,
    /// `(L_x, L_y, L_z / h)`.
    pub slab: Vec3,
    /// Wall time of its raster pass alone (fastest of [`FRAMES`]).
    pub raster_seconds: f64,
}

/// Timestamps of both passes of a frame (queries 0–1 raster, 2–3 per-pixel pass), where
/// the adapter has them.
struct FrameTimer {
    queries: wgpu::QuerySet,
    resolve: wgpu::Buffer,
}

impl FrameTimer {
    fn new(gpu: &Gpu) -> Option<Self> {
        gpu.has_timestamps().then(|| Self {
            queries: gpu.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("ddm-render frame timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: 4,
            }),
            resolve: gpu.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("ddm-render frame timestamps"),
                size: 32,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
        })
    }

    /// Seconds of the per-pixel pass of the last resolved frame.
    fn trace_seconds(&self, gpu: &Gpu) -> Result<f64, String> {
        let bytes = gpu.read_buffer(&self.resolve, 32).map_err(|e| e.to_string())?;
        let ticks: [u64; 4] = bytemuck::pod_read_unaligned(&bytes);
        Ok(ticks[3].saturating_sub(ticks[2]) as f64 * f64::from(gpu.queue.get_timestamp_period()) * 1e-9)
    }
}

/// Records a command buffer with `record`, submits it and waits: the wall time from
/// submission to completion.
fn submit_and_wait(
    gpu: &Gpu,
    record: impl FnOnce(&mut wgpu::CommandEncoder) -> Result<(), String>,
) -> Result<f64, String> {
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    record(&mut encoder)?;
    let commands = encoder.finish();
    let started = std::time::Instant::now();
    gpu.queue.submit([commands]);
    gpu.wait().map_err(|e| e.to_string())?;
    Ok(started.elapsed().as_secs_f64())
}

/// Runs the renders; `args` are `[OUT_DIR] [--quick] [--size WxHxD] [--resolution WxH]`
/// and the tile flags of [`crate::ddm_input`].
pub fn run(args: &crate::cli::Args<'_>) -> Result<(), String> {
    let (out, quick): (PathBuf, bool) = (args.out_dir(), args.flag("quick"));
    let (dims, default_size) =
        if quick { (UVec3::new(12, 12, 6), (160, 120)) } else { (UVec3::new(16, 16, 8), (640, 480)) };
    let dims = args.parse_value("size", crate::cli::grid_size)?.unwrap_or(dims);
    let (width, height) = args.parse_value("resolution", crate::cli::resolution)?.unwrap_or(default_size);
    if width > 4096 || height > 4096 {
        return Err(format!("--resolution {width}x{height}: at most 4096 pixels a side"));
    }
    let source = TileSource::from_args(args)?;
    let periodic = ddm_input::periodic_from_args(args, source.as_ref())?;
    let tiles = ddm_input::tiles(source.as_ref(), dims, periodic)?;
    std::fs::create_dir_all(&out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let gpu = Gpu::new().map_err(|e| e.to_string())?;
    println!(
        "DDM on a base mesh: {}x{}x{} voxels per tile, {width}x{height} pixels, {}, GPU: {}",
        dims.x,
        dims.y,
        dims.z,
        ddm_input::describe(source.as_ref()),
        gpu.describe()
    );
    if gpu.is_software() {
        println!("(GPU times are from lavapipe, a software Vulkan on the CPU, not a GPU)");
    }
    let started = std::time::Instant::now();
    let pipelines = DdmRenderPipelines::new(&gpu.device).map_err(|e| e.to_string())?;
    println!("pipelines: {:.1} ms (built once for the run)", started.elapsed().as_secs_f64() * 1e3);
    let bases = base_meshes(&gpu, &pipelines, dims, width, height)?;
    let timer = FrameTimer::new(&gpu);
    let mut csv = String::from(
        "mesostructure,base,method,covered_pixels,hit_pixels,left_shell_pixels,shadowed_pixels,capped_pixels,flip,one_minus_ssim,mean_steps,max_steps,gpu_ms,gpu_timing,pass_call_wall_ms,call_overhead_wall_ms,trace_wall_ms,raster_wall_ms\n",
    );
    println!(
        "{:<11} {:<6} {:<20} {:>8} {:>8} {:>8} {:>6} {:>7} {:>7} {:>5} {:>9} {:>9}",
        "structure",
        "base",
        "method",
        "covered",
        "hits",
        "shadow",
        "capped",
        "ꟻLIP",
        "steps",
        "max",
        "GPU ms",
        "trace ms"
    );
    let (mut first_frames, mut warm_frames, mut images) = (0.0, 0.0, 0);
    for tile in &tiles {
        let name = tile.name;
        // Every error names the mesostructure and the map or scene it is about.
        let failed = |what: &str, error: &dyn std::fmt::Display| format!("{name}: {what}: {error}");
        let maps = TileMaps::build(tile, dims, false)?;
        let sphere =
            TraceSettings { method: Method::SphereTracing, max_steps: MAX_STEPS, stepping: Stepping::Distance };
        let quadric = TraceSettings { method: Method::Quadric, max_steps: MAX_STEPS, stepping: Stepping::Distance };
        let plain_packed = CompressedMaps::compress(&maps.plain, 1).map_err(|e| failed("packing the DM maps", &e))?;
        let ddm_packed = CompressedMaps::compress(&maps.ddm, 1).map_err(|e| failed("packing the DDM 4x1 maps", &e))?;
        let scene = |method: &'static str, maps, patches, settings, tolerance| {
            GpuScene::new(maps, patches, settings)
                .map(|scene| (method, scene, tolerance))
                .map_err(|e| failed(&format!("the {method} scene"), &e))
        };
        let exit = TraceSettings { stepping: Stepping::VoxelExit, ..quadric };
        let reference_settings = TraceSettings { max_steps: REFERENCE_MAX_STEPS, ..exit };
        // The reference first: every method's image is compared with it.
        let mut scenes: Vec<(&'static str, GpuScene, f32)> = vec![
            scene(REFERENCE, &ddm_packed, Some(&maps.exact), reference_settings, 0.02)?,
            scene("dm", &plain_packed, None, sphere, 1.75)?,
            scene("ddm4x1", &ddm_packed, None, sphere, 1.75)?,
            scene("ddm4x1_quadric", &ddm_packed, Some(&maps.c0), quadric, 0.02)?,
            scene("ddm4x1_adaptive", &ddm_packed, Some(&maps.adaptive), quadric, 0.02)?,
            scene("ddm4x1_adaptive_exit", &ddm_packed, Some(&maps.adaptive), exit, 0.02)?,
        ];
        if let Some(height_map) = &maps.height_map {
            let scene = GpuScene::new(&plain_packed, None, sphere)
                .and_then(|s| s.with_relief(height_map, RELIEF_LINEAR, RELIEF_BINARY))
                .map_err(|e| failed("the relief scene", &e))?;
            scenes.push(("relief", scene, 0.25));
        }
        // Each scene uploaded once, for both bases.
        let uploaded: Vec<(&'static str, GpuSceneBuffers, f32)> = scenes
            .iter()
            .map(|(method, scene, tolerance)| {
                GpuSceneBuffers::new(&gpu.device, scene).map(|b| (*method, b, *tolerance)).map_err(|e| e.to_string())
            })
            .collect::<Result<_, _>>()?;
        for base in &bases {
            let mut reference: Option<image::RgbaImage> = None;
            for (method, scene, tolerance) in &uploaded {
                let renderer =
                    DdmRenderer::new(&gpu.device, &pipelines, &base.gbuffer, scene).map_err(|e| e.to_string())?;
                let readback = PixelReadback::new(&gpu, &renderer).map_err(|e| e.to_string())?;
                let frame = DdmFrame {
                    camera: &base.camera,
                    settings: RenderSettings {
                        slab: base.slab,
                        light: base.light,
                        ambient: 0.2,
                        shadow_tolerance: Some(*tolerance),
                        miss_color: Some(Vec3::new(0.22, 0.27, 0.36)),
                        albedo: ddm_render::DEFAULT_ALBEDO,
                        normal_tint: ddm_render::DEFAULT_NORMAL_TINT,
                    },
                    raster_timestamps: timer.as_ref().map(|t| PassTimestamps { query_set: &t.queries, first: 0 }),
                    trace_timestamps: timer.as_ref().map(|t| PassTimestamps { query_set: &t.queries, first: 2 }),
                };
                let (mut best_gpu, mut frame_wall, mut overhead) = (f64::INFINITY, f64::INFINITY, f64::INFINITY);
                for k in 0..FRAMES {
                    let wall = submit_and_wait(&gpu, |encoder| {
                        renderer.encode(&gpu.queue, encoder, &frame, readback.target()).map_err(|e| e.to_string())?;
                        if let Some(t) = &timer {
                            encoder.resolve_query_set(&t.queries, 0..4, &t.resolve, 0);
                        }
                        Ok(())
                    })?;
                    if k == 0 {
                        first_frames += wall;
                    } else {
                        warm_frames += wall / (FRAMES - 1) as f64;
                    }
                    frame_wall = frame_wall.min(wall);
                    if let Some(t) = &timer {
                        best_gpu = best_gpu.min(t.trace_seconds(&gpu)?);
                    }
                    // The frame without its per-pixel pass (the pixel target keeps the
                    // full frame's pixels).
                    let raster_only = submit_and_wait(&gpu, |encoder| {
                        renderer.gbuffer().encode(&gpu.queue, encoder, &base.camera, None).map_err(|e| e.to_string())
                    })?;
                    overhead = overhead.min(raster_only);
                }
                images += 1;
                let trace_wall = (frame_wall - overhead).max(0.0);
                let (gpu_seconds, timing_name) =
                    if timer.is_some() { (best_gpu, "timestamps") } else { (trace_wall, "wall clock") };
                let pixels = readback.read(&gpu).map_err(|e| e.to_string())?;
                let covered: Vec<_> = pixels.iter().filter(|p| p.color.w != PIXEL_UNCOVERED).collect();
                let hits = covered.iter().filter(|p| p.color.w == PIXEL_HIT).count();
                let left_shell = covered.iter().filter(|p| p.color.w == PIXEL_LEFT_SHELL).count();
                let shadowed = covered.iter().filter(|p| p.color.w == PIXEL_HIT && p.ray_direction.w == 1.0).count();
                let mean_steps =
                    covered.iter().map(|p| f64::from(p.ray_origin.w)).sum::<f64>() / covered.len().max(1) as f64;
                let max_steps = covered.iter().map(|p| p.ray_origin.w as u32).max().unwrap_or(0);
                let image = pixels_to_image(&pixels, width, height, BACKGROUND);
                let stem = format!("{name}_{}_{method}", base.name);
                let path = out.join(format!("{stem}.png"));
                image.save(&path).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
                let rgba = image::DynamicImage::ImageRgb8(image).to_rgba8();
                let cap = if *method == REFERENCE { REFERENCE_MAX_STEPS } else { MAX_STEPS };
                let capped = covered.iter().filter(|p| p.ray_origin.w as u32 >= cap).count();
                let (flip, ssim_loss) = match &reference {
                    None => {
                        reference = Some(rgba);
                        (0.0, 0.0)
                    }
                    Some(truth) => {
                        let flip = image_metrics::flip(truth, &rgba).map_err(|e| format!("{stem}: {e}"))?;
                        let flip_path = out.join(format!("{stem}_flip.png"));
                        image_metrics::flip_magma(&flip.map)
                            .save(&flip_path)
                            .map_err(|e| format!("cannot write {}: {e}", flip_path.display()))?;
                        let ssim = image_metrics::ssim(truth, &rgba).map_err(|e| format!("{stem}: {e}"))?.mean;
                        (flip.mean, (1.0 - ssim).max(0.0))
                    }
                };
                println!(
                    "{:<11} {:<6} {:<20} {:>8} {:>8} {:>8} {:>6} {:>7.4} {:>7.2} {:>5} {:>9.3} {:>9.1}",
                    name,
                    base.name,
                    method,
                    covered.len(),
                    hits,
                    shadowed,
                    capped,
                    flip,
                    mean_steps,
                    max_steps,
                    gpu_seconds * 1e3,
                    trace_wall * 1e3
                );
                writeln!(
                    csv,
                    "{},{},{method},{},{hits},{left_shell},{shadowed},{capped},{flip:.5},{ssim_loss:.5},{mean_steps:.3},{max_steps},{:.4},{timing_name},{:.2},{:.2},{:.2},{:.3}",
                    name,
                    base.name,
                    covered.len(),
                    gpu_seconds * 1e3,
                    frame_wall * 1e3,
                    overhead * 1e3,
                    trace_wall * 1e3,
                    base.raster_seconds * 1e3
                )
                .map_err(|e| e.to_string())?;
            }
        }
    }
    if let Some(maze) = tiles.iter().find(|t| t.name == "maze") {
        interpenetration(&gpu, &pipelines, &bases[0], maze, dims, &out)?;
    }
    let path = out.join("ddm_render_times.csv");
    std::fs::write(&path, csv).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    let images_f = f64::from(images.max(1));
    println!(
        "frames (raster + trace, wall clock): first of each renderer {:.1} ms, later ones {:.1} ms, mean over {images} images",
        first_frames / images_f * 1e3,
        warm_frames / images_f * 1e3
    );
    println!("wrote {} and the PNGs beside it", path.display());
    Ok(())
}

/// Frames of [`INTERPENETRATION_FRAMES`] in which a golden ball moves across the maze
/// (paper Fig. 1's scene): the ball is a tile that stands alone (`periodic_xy: false`, one
/// sphere filling the slab's height and no floor) on a plane of one tile a third of a slab
/// above the maze's plane, drawn without its base surface (`miss_color: None`), so that
/// only the ball shows; both DDM 4×1 + adaptive (voxel-exit stepping) objects drawn one
/// after the other into one colour and depth target (`DdmRenderer::color_depth_target`),
/// each pixel keeping the nearer, so that the maze's walls cut into the ball (each object
/// casts shadows on itself only). The ball's motion is its renderer's camera moved the
/// other way (eye distances, and so depths, are unchanged by the translation): nothing is
/// uploaded per frame. Writes `maze_ball_interpenetration_KK.png`.
fn interpenetration(
    gpu: &Gpu,
    pipelines: &DdmRenderPipelines,
    plane: &Base,
    maze: &Tile,
    dims: UVec3,
    out: &std::path::Path,
) -> Result<(), String> {
    let (width, height) = (plane.camera.width, plane.camera.height);
    let size = dims.as_vec3();
    let radius = 0.5 * size.min_element() - 0.1;
    let ball = Tile {
        name: "golden ball",
        triangles: mesostructure::sphere(0.5 * size, radius, 32),
        height_field: false,
        structure: None,
        periodic_xy: false,
    };
    let tiles = [maze, &ball];
    let ball_plane = plane_base_mesh(dims, UVec2::ONE).ok_or("empty plane")?;
    let ball_gbuffer = GBufferPass::new(&gpu.device, pipelines.gbuffer(), &ball_plane, width, height)
        .map_err(|e| format!("the ball's plane: {e}"))?;
    let exit = TraceSettings { method: Method::Quadric, max_steps: MAX_STEPS, stepping: Stepping::VoxelExit };
    let mut renderers = Vec::new();
    for (tile, gbuffer) in tiles.iter().zip([&plane.gbuffer, &ball_gbuffer]) {
        let maps = TileMaps::build(tile, dims, false)?;
        let packed = CompressedMaps::compress(&maps.ddm, 1).map_err(|e| format!("{}: {e}", tile.name))?;
        let scene = GpuScene::new(&packed, Some(&maps.adaptive), exit).map_err(|e| format!("{}: {e}", tile.name))?;
        let scene = GpuSceneBuffers::new(&gpu.device, &scene).map_err(|e| e.to_string())?;
        renderers.push(DdmRenderer::new(&gpu.device, pipelines, gbuffer, &scene).map_err(|e| e.to_string())?);
    }
    let texture = |format| {
        gpu.scoped(|| {
            gpu.device.create_texture(&wgpu::TextureDescriptor {
                label: Some("ddm-render interpenetration target"),
                size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::STORAGE_BINDING
                    | wgpu::TextureUsages::RENDER_ATTACHMENT
                    | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            })
        })
        .map_err(|e| e.to_string())
    };
    let (color, depth) = (texture(ddm_render::COLOR_TARGET_FORMAT)?, texture(ddm_render::DEPTH_TARGET_FORMAT)?);
    let targets = renderers
        .iter()
        .map(|r| r.color_depth_target(&gpu.device, &color, &depth).map_err(|e| e.to_string()))
        .collect::<Result<Vec<_>, _>>()?;
    let settings = RenderSettings {
        slab: plane.slab,
        light: plane.light,
        ambient: 0.2,
        shadow_tolerance: Some(0.02),
        miss_color: Some(Vec3::new(0.22, 0.27, 0.36)),
        albedo: ddm_render::DEFAULT_ALBEDO,
        normal_tint: ddm_render::DEFAULT_NORMAL_TINT,
    };
    for k in 0..INTERPENETRATION_FRAMES {
        // The ball's plane starts a quarter tile into the maze's and moves one tile along x,
        // a third of the slab up.
        let along = k as f32 / (INTERPENETRATION_FRAMES - 1) as f32;
        let offset = Vec3::new((0.25 + along) * size.x, 0.25 * size.y, size.z / 3.0);
        let ball_camera =
            Camera { eye: plane.camera.eye - offset, target: plane.camera.target - offset, ..plane.camera };
        // The ball golden, as the paper's Fig. 1 ball, and no base surface under it.
        let golden =
            RenderSettings { albedo: Vec3::new(1.0, 0.76, 0.3), normal_tint: 0.1, miss_color: None, ..settings };
        let frames = [DdmFrame::new(&plane.camera, settings), DdmFrame::new(&ball_camera, golden)];
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        targets[0].encode_clear(&mut encoder).map_err(|e| e.to_string())?;
        for ((renderer, target), frame) in renderers.iter().zip(&targets).zip(&frames) {
            renderer.encode(&gpu.queue, &mut encoder, frame, target).map_err(|e| e.to_string())?;
        }
        gpu.queue.submit([encoder.finish()]);
        let texels: Vec<[u16; 4]> =
            bytemuck::pod_collect_to_vec(&ddm_render::read_texture(gpu, &color).map_err(|e| e.to_string())?);
        let mut image = image::RgbImage::from_pixel(width, height, image::Rgb(BACKGROUND));
        for (out_pixel, texel) in image.pixels_mut().zip(&texels) {
            if f16_bits_to_f32(texel[3]) > 0.0 {
                let c = Vec3::new(f16_bits_to_f32(texel[0]), f16_bits_to_f32(texel[1]), f16_bits_to_f32(texel[2]));
                let c = c.clamp(Vec3::ZERO, Vec3::ONE).powf(1.0 / 2.2) * 255.0;
                *out_pixel = image::Rgb([c.x as u8, c.y as u8, c.z as u8]);
            }
        }
        let path = out.join(format!("maze_ball_interpenetration_{k:02}.png"));
        image.save(&path).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    }
    println!(
        "maze and a golden ball (a lone tile, radius {radius} voxels): {INTERPENETRATION_FRAMES} interpenetration \
         frames (one colour and depth target)"
    );
    Ok(())
}

/// Frames of [`interpenetration`].
const INTERPENETRATION_FRAMES: u32 = 4;

/// What the renders and the GPU benchmark trace on one tile: its plain map and DDM 4×1
/// (tolerance 0.25, periodic), the C⁰ patches, the adaptive patches (1e-3 voxel), the
/// mesh's triangles as patches (the reference), the watertight patches where asked, and
/// the relief height map (2 texels per voxel) of a height field.
pub(crate) struct TileMaps {
    pub plain: DistanceMaps,
    pub ddm: DistanceMaps,
    pub c0: VoxelPatches,
    pub adaptive: VoxelPatches,
    pub exact: VoxelPatches,
    pub watertight: Option<VoxelPatches>,
    pub height_map: Option<HeightMap>,
}

impl TileMaps {
    /// Builds them for `tile` at `dims`; errors name the tile and what failed.
    pub(crate) fn build(tile: &Tile, dims: UVec3, watertight: bool) -> Result<Self, String> {
        let (name, triangles) = (tile.name, &tile.triangles);
        let failed = |what: &str, error: &dyn std::fmt::Display| format!("{name}: {what}: {error}");
        let settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: tile.periodic_xy };
        let plain =
            compute_distance_maps(dims, triangles, MapKind::Plain, settings).map_err(|e| failed("the DM maps", &e))?;
        let ddm4x1 = MapKind::Directional(DirectionCones::downward(4, 1).map_err(|e| failed("the DDM 4x1 cones", &e))?);
        let ddm =
            compute_distance_maps(dims, triangles, ddm4x1, settings).map_err(|e| failed("the DDM 4x1 maps", &e))?;
        let patches = |what: &str, surface: Option<PatchSurface>| {
            let settings = PatchSettings {
                surface: surface.unwrap_or(PatchSettings::default().surface),
                periodic_xy: tile.periodic_xy,
                ..PatchSettings::default()
            };
            VoxelPatches::build(dims, triangles, &ddm.surface, settings).map_err(|e| failed(what, &e))
        };
        let c0 = patches("the C0 patches", None)?;
        let adaptive = patches("the adaptive patches", Some(PatchSurface::Adaptive { max_error: 1e-3 }))?;
        let exact = patches("the triangle patches", Some(PatchSurface::Triangles))?;
        let watertight =
            if watertight { Some(patches("the watertight patches", Some(PatchSurface::Watertight))?) } else { None };
        // Relief mapping's height map wraps: not for a tile that stands alone.
        let height_map = if tile.height_field && tile.periodic_xy {
            let mesh = MeshRaycaster::new(triangles, Vec2::new(dims.x as f32, dims.y as f32));
            Some(HeightMap::from_mesh(&mesh, dims, 2).map_err(|e| failed("the relief height map", &e))?)
        } else {
            None
        };
        Ok(Self { plain, ddm, c0, adaptive, exact, watertight, height_map })
    }
}

/// The plane tile (4 × 4 tiles seen by `xtask ddm-trace`'s camera) and the torus, each
/// uploaded once into a G-buffer pass, with the raster pass's wall time.
pub(crate) fn base_meshes(
    gpu: &Gpu,
    pipelines: &DdmRenderPipelines,
    dims: UVec3,
    width: u32,
    height: u32,
) -> Result<Vec<Base>, String> {
    let size = dims.as_vec3();
    let target = Vec3::new(size.x, size.y, 0.3 * size.z);
    let plane_camera = Camera {
        eye: target + Vec3::new(-0.9 * size.x, -1.3 * size.y, 1.1 * size.x.max(size.y)),
        target,
        up: Vec3::Z,
        half_fov_y: 25f32.to_radians(),
        width,
        height,
    };
    let plane = plane_base_mesh(dims, UVec2::new(4, 4)).ok_or("empty plane")?;
    let torus = mesostructure::torus_base_mesh(3.0, 1.2, 96, 48, UVec2::new(16, 6)).ok_or("invalid torus")?;
    let torus_camera = Camera {
        eye: Vec3::new(0.0, -7.5, 5.5),
        target: Vec3::new(0.0, 0.0, -0.3),
        up: Vec3::Z,
        half_fov_y: 28f32.to_radians(),
        width,
        height,
    };
    let thickness = 0.4;
    let mut bases = Vec::new();
    for (name, mesh, camera, light, slab) in [
        ("plane", plane, plane_camera, Vec3::new(0.45, 0.3, 0.84), Vec3::new(size.x, size.y, 1.0)),
        ("torus", torus, torus_camera, Vec3::new(-0.35, -0.55, 0.75), Vec3::new(size.x, size.y, size.z / thickness)),
    ] {
        let gbuffer = GBufferPass::new(&gpu.device, pipelines.gbuffer(), &mesh, width, height)
            .map_err(|e| format!("{name}: {e}"))?;
        let mut raster_seconds = f64::INFINITY;
        for _ in 0..FRAMES {
            let wall = submit_and_wait(gpu, |encoder| {
                gbuffer.encode(&gpu.queue, encoder, &camera, None).map_err(|e| format!("{name}: {e}"))
            })?;
            raster_seconds = raster_seconds.min(wall);
        }
        println!("{name}: G-buffer raster {:.2} ms (wall clock, fastest of {FRAMES})", raster_seconds * 1e3);
        bases.push(Base { name, gbuffer, camera, light: light.normalize(), slab, raster_seconds });
    }
    Ok(bases)
}
