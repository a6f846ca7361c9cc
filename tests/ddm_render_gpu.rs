//! The base-mesh pipeline of `ddm-render` (Mehra & Kumar §3) on the GPU, through its
//! embeddable renderer (`DdmRenderer`, built once, one `encode` per frame): the raster
//! G-buffer and the compute pass's tangent-space rays.
//!
//! - Plane tile: the base mesh is the top of the slab in the tracer's own coordinates, so
//!   every covered pixel's tangent-space ray must be the ray that `xtask ddm-trace`'s
//!   plane-tile path traces through that pixel (same camera): origin on the eye ray at
//!   the slab top, same direction, and the same hit. The compute pass's ray also equals
//!   the CPU reference `tangent_space_ray` applied to the G-buffer texel (CPU = GPU for
//!   `render_tangent_ray`; the texel is copied back from the same `Rgba32Float` textures
//!   that the compute pass reads with `textureLoad`, so both see the same bits), its hit
//!   equals the CPU tracer's, and its shadow flag equals `in_shadow` on the CPU (CPU = GPU
//!   for `render_in_shadow`). Two frames with different cameras go through one renderer
//!   and one target, and both are checked, for two settings of the tracer's pipeline
//!   constants: blocks of 1 with the paper's stepping, and 4³ blocks with a binary16 atlas
//!   and block-cell stepping (against the CPU over the same rounded values).
//! - Colour target: the `Rgba16Float` texture holds the pixel target's colours, rounded to
//!   half precision, and the coverage in alpha.
//! - Torus: the G-buffer frames at every covered pixel are orthonormal (after
//!   normalisation) and match `torus_base_mesh`'s analytic frame at the pixel's texture
//!   coordinates, and the positions lie on the torus.
//! - Interpenetration: two objects (maze and ball tiles on planes that cross each other's
//!   slab) drawn one after the other into one colour and depth target equal, per pixel,
//!   the nearer of their separate renders (inverse eye distances from `eye_distance`).
//! - Torus silhouettes: the second raster pass's exit distance is where the pixel's ray
//!   leaves the torus (the exit point on the torus, the stretch before it inside), and
//!   every covered pixel's class (hit, miss at the slab's bottom, left the shell) equals
//!   the CPU's `pixel_class` of the same texel with the CPU tracer; pixels that leave the
//!   shell exist and outline the torus.

use ddm_compress::{DirectionCones, DistanceMapSettings, MapKind, compute_distance_maps};
use ddm_render::{
    COLOR_TARGET_FORMAT, Camera, DEPTH_TARGET_FORMAT, DdmFrame, DdmRenderPipelines, DdmRenderer, GBuffer, GBufferPass,
    GpuSceneBuffers, PixelReadback, RenderSettings, plane_base_mesh, rasterize_gbuffer, read_gbuffer, read_texture,
};
use ddm_tracer::GpuScene;
use ddm_tracer::tangent_space::{
    BaseRenderPixel, NO_EXIT, PIXEL_HIT, PIXEL_LEFT_SHELL, PIXEL_MISS, PIXEL_UNCOVERED, TangentFrame, eye_distance,
    in_shadow, pixel_class, shell_exit, slab_bottom, tangent_space_ray,
};
use ddm_tracer::{CompressedMaps, Method, PatchSettings, Stepping, TraceSettings, VoxelPatches, trace, trace_within};
use glam::{UVec2, UVec3, Vec3, Vec4};
use grain_impostor::half::{f16_bits_to_f32, f32_to_f16_bits};
use integration_tests::gpu;
use mesostructure::Mesostructure;

const DIMS: UVec3 = UVec3::new(12, 12, 6);
/// Shadow rays: how far short of the shaded point (voxels) a hit must be.
const SHADOW_TOLERANCE: f32 = 0.02;
const TRACE_SETTINGS: TraceSettings =
    TraceSettings { method: Method::Quadric, max_steps: 256, stepping: Stepping::Distance };
/// The rounding of one `f32` operation on the pipeline's values (coordinates below 64
/// voxels: the eye is ~36 voxels from the tile), counted as a whole ulp of 64.
const F32_STEP_ERROR: f32 = 64.0 * f32::EPSILON;
/// CPU = GPU for `tangent_space_ray` on the same texel bits: about 10 operations, each
/// rounding differently on either side at most (FMA contraction): 10 [`F32_STEP_ERROR`].
const MIRROR_BOUND: f32 = 10.0 * F32_STEP_ERROR;
/// Regression pins (not property bounds): how far the rasterized G-buffer's ray lies
/// from the exact eye ray of the plane-tile path. Vulkan does not bound the precision of
/// attribute interpolation, so no property bounds them; measured on lavapipe: origin
/// 3.2e-4 voxel (interpolated world positions ~36 voxels long), hit vs the eye ray's hit
/// 3.0e-4 (ball) and 4.2e-4 voxel (maze: the origin's error, carried along), direction
/// 2.1e-6 rad.
const RASTER_ORIGIN_PIN: f32 = 5e-4;
const RASTER_DIRECTION_PIN: f32 = 1e-5;
const WIDTH: u32 = 80;
const HEIGHT: u32 = 60;

/// The camera of `xtask ddm-trace`'s view: above and to the side of the tile.
fn plane_camera(width: u32, height: u32) -> Camera {
    let size = DIMS.as_vec3();
    let target = Vec3::new(size.x, size.y, 0.3 * size.z);
    let eye = target + Vec3::new(-0.9 * size.x, -1.3 * size.y, 1.1 * size.x.max(size.y));
    Camera { eye, target, up: Vec3::Z, half_fov_y: 25f32.to_radians(), width, height }
}

/// A second view of the same tile: the eye moved to the other side, lower and closer.
fn moved_camera(width: u32, height: u32) -> Camera {
    let size = DIMS.as_vec3();
    let target = Vec3::new(1.5 * size.x, 1.2 * size.y, 0.3 * size.z);
    let eye = target + Vec3::new(1.1 * size.x, -0.8 * size.y, 0.9 * size.x.max(size.y));
    Camera { eye, target, up: Vec3::Z, half_fov_y: 25f32.to_radians(), width, height }
}

fn settings() -> RenderSettings {
    RenderSettings {
        slab: Vec3::new(DIMS.x as f32, DIMS.y as f32, 1.0),
        light: Vec3::new(0.45, 0.3, 0.84).normalize(),
        ambient: 0.2,
        shadow_tolerance: Some(SHADOW_TOLERANCE),
        miss_color: Some(Vec3::new(0.2, 0.25, 0.35)),
        albedo: ddm_render::DEFAULT_ALBEDO,
        normal_tint: ddm_render::DEFAULT_NORMAL_TINT,
    }
}

/// How a [`PlaneScene`] stores its maps on the GPU, and how it steps through them.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Storage {
    /// Blocks of 1 voxel (every distance in the lookup grid), the paper's stepping.
    Block1,
    /// Blocks of 4³ with the atlas in binary16 rounded down, block-cell stepping: a second
    /// setting of the tracer's pipeline constants.
    Block4F16,
}

/// A structure's maps (the CPU reference: the values the GPU reads) and patches, the
/// tracer settings, and a renderer of it on 3 × 3 plane tiles.
struct PlaneScene {
    maps: CompressedMaps,
    patches: VoxelPatches,
    settings: TraceSettings,
    renderer: DdmRenderer,
}

impl PlaneScene {
    fn new(structure: Mesostructure, pipelines: &DdmRenderPipelines, storage: Storage) -> Self {
        let gpu = gpu();
        let triangles = structure.triangles(DIMS);
        let settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: true };
        let ddm4x1 = MapKind::Directional(DirectionCones::downward(4, 1).unwrap());
        let maps = compute_distance_maps(DIMS, &triangles, ddm4x1, settings).unwrap();
        let patches = VoxelPatches::build(DIMS, &triangles, &maps.surface, PatchSettings::default()).unwrap();
        let (maps, settings, scene) = match storage {
            Storage::Block1 => {
                let packed = CompressedMaps::compress(&maps, 1).unwrap();
                let scene = GpuScene::new(&packed, Some(&patches), TRACE_SETTINGS).unwrap();
                (packed, TRACE_SETTINGS, scene)
            }
            Storage::Block4F16 => {
                let packed = CompressedMaps::compress(&maps, 4).unwrap();
                let blocks = TraceSettings { stepping: Stepping::BlockCells, ..TRACE_SETTINGS };
                let scene = GpuScene::new(&packed, Some(&patches), blocks).and_then(GpuScene::with_f16_atlas).unwrap();
                (packed.with_f16_atlas(), blocks, scene)
            }
        };
        let mesh = plane_base_mesh(DIMS, UVec2::new(3, 3)).unwrap();
        let gbuffer = GBufferPass::new(&gpu.device, pipelines.gbuffer(), &mesh, WIDTH, HEIGHT).unwrap();
        let scene = GpuSceneBuffers::new(&gpu.device, &scene).unwrap();
        let renderer = DdmRenderer::new(&gpu.device, pipelines, &gbuffer, &scene).unwrap();
        Self { maps, patches, settings, renderer }
    }
}

#[test]
fn plane_tile_pixels_trace_the_plane_tile_rays() {
    // A non-height-field and a height field with walls and a floor, in two settings of
    // the tracer's pipeline constants; renderers of one setting share its pipelines.
    let pipelines = DdmRenderPipelines::new(&gpu().device).unwrap();
    let cases = [Mesostructure::Ball, Mesostructure::Maze(1)]
        .into_iter()
        .flat_map(|structure| [(structure, Storage::Block1), (structure, Storage::Block4F16)]);
    for (structure, storage) in cases {
        let gpu = gpu();
        let scene = PlaneScene::new(structure, &pipelines, storage);
        let structure_name = format!("{} {storage:?}", structure.name());
        let readback = PixelReadback::new(gpu, &scene.renderer).unwrap();
        // Two frames through the same renderer and target: only the camera and parameter
        // uniforms change between them.
        let mut frames: Vec<Vec<BaseRenderPixel>> = Vec::new();
        for (name, camera) in [("first", plane_camera(WIDTH, HEIGHT)), ("moved", moved_camera(WIDTH, HEIGHT))] {
            let started = std::time::Instant::now();
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            scene
                .renderer
                .encode(&gpu.queue, &mut encoder, &DdmFrame::new(&camera, settings()), readback.target())
                .unwrap();
            gpu.queue.submit([encoder.finish()]);
            gpu.wait().unwrap();
            let wall = started.elapsed().as_secs_f64() * 1e3;
            let pixels = readback.read(gpu).unwrap();
            let gbuffer = read_gbuffer(gpu, scene.renderer.gbuffer()).unwrap();
            check_frame(
                &format!("{structure_name} ({name} camera, frame {wall:.1} ms)"),
                &scene,
                &camera,
                &gbuffer,
                &pixels,
            );
            frames.push(pixels);
        }
        let moved = frames[0].iter().zip(&frames[1]).filter(|(a, b)| a.ray_origin != b.ray_origin).count();
        assert!(moved > 2000, "{structure_name}: the second frame repeats the first ({moved} rays differ)");
    }
    assert_eq!(pipelines.specialized_count(), 2, "one set of per-pixel pipelines per setting");
}

/// Checks one frame's pixels against the CPU: ray construction, hits and shadows.
fn check_frame(name: &str, scene: &PlaneScene, camera: &Camera, gbuffer: &GBuffer, pixels: &[BaseRenderPixel]) {
    let (maps, patches) = (&scene.maps, Some(&scene.patches));
    let settings = settings();
    let (slab, light) = (settings.slab, settings.light);
    let size_z = DIMS.z as f32;
    assert_eq!((gbuffer.width, gbuffer.height), (camera.width, camera.height));
    assert_eq!(pixels.len(), gbuffer.texels.len());
    let (mut covered, mut hits) = (0, 0);
    let (mut worst_origin, mut worst_direction, mut worst_mirror, mut worst_hit, mut worst_eye_hit) =
        (0.0_f32, 0.0_f32, 0.0_f32, 0.0_f32, 0.0_f32);
    let (mut hit_miss_differ, mut shadow_differ, mut shadowed) = (0, 0, 0);
    for y in 0..camera.height {
        for x in 0..camera.width {
            let i = (x + y * camera.width) as usize;
            let (texel, pixel) = (&gbuffer.texels[i], &pixels[i]);
            let Some((origin, direction)) = tangent_space_ray(texel, camera.eye, slab, size_z) else {
                assert_eq!(pixel.color.w, PIXEL_UNCOVERED, "{name}: pixel {x},{y}");
                continue;
            };
            covered += 1;
            // CPU = GPU for the ray construction.
            let gpu_origin = pixel.ray_origin.truncate();
            let gpu_direction = pixel.ray_direction.truncate();
            worst_mirror = worst_mirror
                .max((gpu_origin - origin).length())
                .max((gpu_direction - direction).length() / direction.length());
            // The ray of the plane-tile path through this pixel.
            let eye_direction = camera.pixel_direction(x, y);
            let entry = camera.eye + eye_direction * ((size_z - camera.eye.z) / eye_direction.z);
            worst_origin = worst_origin.max((gpu_origin - entry).length());
            // |a × b| = sin of the angle (acos near 1 has no resolution in f32).
            worst_direction = worst_direction.max(gpu_direction.normalize().cross(eye_direction).length());
            // The GPU hit against the CPU tracer on the same ray, and on the eye ray.
            let cpu = trace(maps, patches, origin, direction, scene.settings);
            let from_eye = trace(maps, patches, camera.eye, eye_direction, scene.settings);
            let gpu_hit = pixel.color.w == PIXEL_HIT;
            hits += usize::from(gpu_hit);
            match (cpu.hit, from_eye.hit, gpu_hit) {
                (Some(c), Some(e), true) => {
                    // CPU = GPU tracer on the same ray: within the rounding floor of its
                    // steps (see `tests/ddm_tracer_gpu.rs`: one step error per step, 4 for
                    // the entry and the hit).
                    let hit_error = (c.point - pixel.hit.truncate()).length();
                    let hit_bound = (cpu.steps + 4) as f32 * 2.0 * F32_STEP_ERROR;
                    assert!(hit_error <= hit_bound, "{name}: pixel {x},{y}: hit differs by {hit_error} > {hit_bound}");
                    worst_hit = worst_hit.max(hit_error / hit_bound);
                    worst_eye_hit = worst_eye_hit.max((e.point - pixel.hit.truncate()).length());
                    // CPU = GPU for the shadow ray (cast where the hit faces the light).
                    let frame = TangentFrame::new(texel, slab).unwrap();
                    let lit_side = frame.normal_to_world(c.normal).dot(light) > 0.0;
                    let tangent_light = frame.to_tangent(light);
                    let expected =
                        lit_side && in_shadow(maps, patches, c.point, tangent_light, SHADOW_TOLERANCE, scene.settings);
                    let gpu_shadowed = pixel.ray_direction.w == 1.0;
                    shadowed += usize::from(gpu_shadowed);
                    shadow_differ += usize::from(expected != gpu_shadowed);
                }
                (None, None, false) => {}
                _ => hit_miss_differ += 1,
            }
        }
    }
    println!(
        "{name}: covered {covered}, hits {hits}, hit/miss differ {hit_miss_differ}, shadowed {shadowed}, \
         shadow differs {shadow_differ}; worst: mirror {worst_mirror:e}, \
         origin {worst_origin:e} voxel, direction {worst_direction:e} rad, hit vs CPU {worst_hit:.3} of its bound, \
         hit vs eye ray {worst_eye_hit:e} voxel"
    );
    assert!(covered > 2000 && hits > covered / 2, "{name}: covered {covered}, hits {hits}");
    // Measured on lavapipe: 0 pixels differ; mirror 0 (bit-equal); hit vs CPU on the same
    // ray 0; the maze's 157 misses (quadric holes) are the CPU tracer's too. Hit/miss and
    // shadow flags are compared exactly: the rays are the same bits on both sides, and the
    // tracer twin differs only within rounding of a decision (none measured here).
    assert_eq!(hit_miss_differ, 0, "{name}");
    assert!(shadowed > 0, "{name}: no shadow to compare");
    assert_eq!(shadow_differ, 0, "{name}");
    assert!(worst_mirror <= MIRROR_BOUND, "{name}: {worst_mirror}");
    assert!(worst_origin < RASTER_ORIGIN_PIN, "{name}: {worst_origin} (regression pin)");
    assert!(worst_direction < RASTER_DIRECTION_PIN, "{name}: {worst_direction} (regression pin)");
    assert!(worst_eye_hit < RASTER_ORIGIN_PIN, "{name}: {worst_eye_hit} (regression pin)");
}

/// `miss_color: None` (an object standing alone on its base): every pixel that showed the
/// base surface under the slab shows what lies behind instead (class and colour as where a
/// ray leaves the shell), and every other pixel is the same bits.
#[test]
fn without_a_base_surface_misses_show_what_lies_behind() {
    let gpu = gpu();
    // The chain mail has no floor: rays between its rings reach the slab's bottom.
    let pipelines = DdmRenderPipelines::new(&gpu.device).unwrap();
    let scene = PlaneScene::new(Mesostructure::ChainMail, &pipelines, Storage::Block1);
    let camera = plane_camera(WIDTH, HEIGHT);
    let readback = PixelReadback::new(gpu, &scene.renderer).unwrap();
    let mut frames = Vec::new();
    for settings in [settings(), RenderSettings { miss_color: None, ..settings() }] {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        scene.renderer.encode(&gpu.queue, &mut encoder, &DdmFrame::new(&camera, settings), readback.target()).unwrap();
        gpu.queue.submit([encoder.finish()]);
        frames.push(readback.read(gpu).unwrap());
    }
    let (mut misses, mut others) = (0, 0);
    for (i, (with_base, without)) in frames[0].iter().zip(&frames[1]).enumerate() {
        if with_base.color.w == PIXEL_MISS {
            misses += 1;
            assert_eq!(without.color, Vec4::new(0.0, 0.0, 0.0, PIXEL_LEFT_SHELL), "pixel {i}");
            assert_eq!((without.ray_origin, without.ray_direction), (with_base.ray_origin, with_base.ray_direction));
        } else {
            others += 1;
            assert_eq!(without, with_base, "pixel {i}");
        }
    }
    println!("no base surface: {misses} misses now show what lies behind, {others} other pixels unchanged");
    assert!(misses > 500 && others > 500, "{misses} misses, {others} others");
}

#[test]
fn color_target_holds_the_pixel_colours_in_half_precision() {
    let gpu = gpu();
    let pipelines = DdmRenderPipelines::new(&gpu.device).unwrap();
    let scene = PlaneScene::new(Mesostructure::Ball, &pipelines, Storage::Block1);
    let camera = plane_camera(WIDTH, HEIGHT);
    let frame = DdmFrame::new(&camera, settings());
    let readback = PixelReadback::new(gpu, &scene.renderer).unwrap();
    let texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
        label: Some("colour target"),
        size: wgpu::Extent3d { width: WIDTH, height: HEIGHT, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: COLOR_TARGET_FORMAT,
        usage: wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::COPY_SRC,
        view_formats: &[],
    });
    let color = scene.renderer.color_target(&gpu.device, &texture).unwrap();
    // Two frames of the same view, one per target, in one submission each.
    for target in [readback.target(), &color] {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        scene.renderer.encode(&gpu.queue, &mut encoder, &frame, target).unwrap();
        gpu.queue.submit([encoder.finish()]);
    }
    let pixels = readback.read(gpu).unwrap();
    let texels: Vec<[u16; 4]> = bytemuck::pod_collect_to_vec(&read_texture(gpu, &texture).unwrap());
    assert_eq!(texels.len(), pixels.len());
    let (mut covered, mut rounded_away) = (0, 0);
    for (i, (texel, pixel)) in texels.iter().zip(&pixels).enumerate() {
        if pixel.color.w == PIXEL_UNCOVERED {
            assert_eq!(*texel, [0; 4], "uncovered pixel {i}");
            continue;
        }
        covered += 1;
        assert_eq!(f16_bits_to_f32(texel[3]), 1.0, "coverage of pixel {i}");
        // Vulkan lets a storage write round f32 to f16 either to nearest or toward zero:
        // the stored half is one of the two halves around the colour (adjacent patterns).
        for (c, (&stored, value)) in texel.iter().zip(pixel.color.to_array()).take(3).enumerate() {
            let nearest = f32_to_f16_bits(value);
            assert!(
                nearest.abs_diff(stored) <= 1,
                "pixel {i} channel {c}: {value} stored as {}",
                f16_bits_to_f32(stored)
            );
            let error = (f16_bits_to_f32(stored) - value).abs();
            // Within one half-precision ulp: 2⁻¹⁰ relative, 2⁻²⁴ among the subnormal halves.
            let ulp = (value.abs() * 2f32.powi(-10)).max(2f32.powi(-24));
            assert!(error <= ulp, "pixel {i} channel {c}: error {error}");
            rounded_away += usize::from(nearest != stored);
        }
    }
    println!("colour target: {covered} covered pixels, {rounded_away} channels not rounded to nearest");
    assert!(covered > 2000, "{covered}");
}

#[test]
fn torus_gbuffer_frames_are_orthonormal_and_analytic() {
    let gpu = gpu();
    let (major, minor, repeats) = (3.0_f32, 1.2_f32, UVec2::new(8, 2));
    let mesh = mesostructure::torus_base_mesh(major, minor, 96, 48, repeats).unwrap();
    let camera = Camera {
        eye: Vec3::new(0.0, -7.5, 5.5),
        target: Vec3::new(0.0, 0.0, -0.3),
        up: Vec3::Z,
        half_fov_y: 28f32.to_radians(),
        width: 96,
        height: 72,
    };
    let gbuffer = rasterize_gbuffer(gpu, &mesh, &camera).unwrap();
    let tau = std::f32::consts::TAU;
    let (mut covered, mut worst_orthogonal, mut worst_frame, mut worst_position, mut worst_scale) =
        (0, 0.0_f32, 0.0_f32, 0.0_f32, 0.0_f32);
    for texel in gbuffer.texels.iter().filter(|t| t.position_coverage.w > 0.0) {
        covered += 1;
        let t = texel.tangent_u.truncate().normalize();
        let b = texel.bitangent_v.truncate().normalize();
        let n = texel.normal_depth.truncate().normalize();
        worst_orthogonal = worst_orthogonal.max(t.dot(b).abs()).max(t.dot(n).abs()).max(b.dot(n).abs());
        let theta = tau * texel.tangent_u.w / repeats.x as f32;
        let phi = tau * texel.bitangent_v.w / repeats.y as f32;
        let (st, ct, sp, cp) = (theta.sin(), theta.cos(), phi.sin(), phi.cos());
        let t_exact = Vec3::new(-st, ct, 0.0);
        let b_exact = Vec3::new(-sp * ct, -sp * st, cp);
        let n_exact = Vec3::new(cp * ct, cp * st, sp);
        worst_frame = worst_frame.max((t - t_exact).length()).max((b - b_exact).length()).max((n - n_exact).length());
        let p_exact = Vec3::new((major + minor * cp) * ct, (major + minor * cp) * st, minor * sp);
        worst_position = worst_position.max((texel.position_coverage.truncate() - p_exact).length());
        let scale_u = tau * (major + minor * cp) / repeats.x as f32;
        worst_scale = worst_scale.max((texel.tangent_u.truncate().length() / scale_u - 1.0).abs());
    }
    println!(
        "covered {covered}; worst |dot| {worst_orthogonal:e}, frame {worst_frame:e}, position {worst_position:e}, \
         |dP/du| relative {worst_scale:e}"
    );
    assert!(covered > 1500, "{covered}");
    // The mesh has 96 × 48 quads: vertex steps Δθ = 2π/96 around the ring, Δφ = 2π/48
    // around the tube. Frames: each vector interpolates its vertices' unit vectors
    // linearly, and the exact ones turn at rate ≤ 1 per radian of θ and φ, so linear
    // interpolation errs by ≤ (Δθ² + Δφ²) / 8 (second-order term; normalising only moves
    // it toward the sphere), and two such vectors are orthogonal within twice that.
    // Positions: flat quads against the torus, the sagittas r (1 − cos(Δφ/2)) +
    // (R + r)(1 − cos(Δθ/2)). Plus f32 rounding of coordinates below 8 (16 ulp).
    // Measured on lavapipe: |dot| 2.24e-3, frame 2.12e-3, position 4.78e-3.
    let (d_theta, d_phi) = (tau / 96.0, tau / 48.0);
    let frame_bound = (d_theta * d_theta + d_phi * d_phi) / 8.0 + 16.0 * f32::EPSILON;
    let sagitta = minor * (1.0 - (d_phi / 2.0).cos()) + (major + minor) * (1.0 - (d_theta / 2.0).cos());
    let position_bound = sagitta + 16.0 * 8.0 * f32::EPSILON;
    assert!(worst_frame <= frame_bound, "{worst_frame} > {frame_bound}");
    assert!(worst_orthogonal <= 2.0 * frame_bound, "{worst_orthogonal} > {}", 2.0 * frame_bound);
    assert!(worst_position <= position_bound, "{worst_position} > {position_bound}");
    // Regression pin: |∂P/∂u| relative, measured 2.66e-3 (chords of the one-ring fit; the
    // chord estimate Δφ²/6 = 2.9e-3 of ddm-render's base_mesh does not bound it there).
    assert!(worst_scale < 4e-3, "{worst_scale} (regression pin)");
}

/// Signed distance to the exact torus of centre radius `major`, tube radius `minor`.
fn torus_sdf(p: Vec3, major: f32, minor: f32) -> f32 {
    glam::Vec2::new(p.truncate().length() - major, p.z).length() - minor
}

#[test]
fn torus_silhouettes_show_what_lies_behind() {
    let gpu = gpu();
    let (major, minor, repeats) = (3.0_f32, 1.2_f32, UVec2::new(16, 6));
    let mesh = mesostructure::torus_base_mesh(major, minor, 96, 48, repeats).unwrap();
    let (width, height) = (96, 72);
    let camera = Camera {
        eye: Vec3::new(0.0, -7.5, 5.5),
        target: Vec3::new(0.0, 0.0, -0.3),
        up: Vec3::Z,
        half_fov_y: 28f32.to_radians(),
        width,
        height,
    };
    // The mesostructure 0.4 world units deep under the torus (as `xtask ddm-render`).
    let slab = Vec3::new(DIMS.x as f32, DIMS.y as f32, DIMS.z as f32 / 0.4);
    let render_settings = RenderSettings { slab, shadow_tolerance: None, ..settings() };
    let pipelines = DdmRenderPipelines::new(&gpu.device).unwrap();
    let gbuffer_pass = GBufferPass::new(&gpu.device, pipelines.gbuffer(), &mesh, width, height).unwrap();
    let tau = std::f32::consts::TAU;
    let (d_theta, d_phi) = (tau / 96.0, tau / 48.0);
    // As in `torus_gbuffer_frames_are_orthonormal_and_analytic`: flat quads lie within
    // their sagittas of the torus, plus f32 rounding of coordinates below 16 (eye
    // distances ~12: 16 ulp of 16).
    let sagitta = minor * (1.0 - (d_phi / 2.0).cos()) + (major + minor) * (1.0 - (d_theta / 2.0).cos());
    let surface_bound = sagitta + 16.0 * 16.0 * f32::EPSILON;
    for structure in [Mesostructure::Maze(1), Mesostructure::Ball] {
        let triangles = structure.triangles(DIMS);
        let map_settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: true };
        let ddm4x1 = MapKind::Directional(DirectionCones::downward(4, 1).unwrap());
        let maps = compute_distance_maps(DIMS, &triangles, ddm4x1, map_settings).unwrap();
        let patches = VoxelPatches::build(DIMS, &triangles, &maps.surface, PatchSettings::default()).unwrap();
        let scene =
            GpuScene::new(&CompressedMaps::compress(&maps, 1).unwrap(), Some(&patches), TRACE_SETTINGS).unwrap();
        let scene = GpuSceneBuffers::new(&gpu.device, &scene).unwrap();
        let renderer = DdmRenderer::new(&gpu.device, &pipelines, &gbuffer_pass, &scene).unwrap();
        let readback = PixelReadback::new(gpu, &renderer).unwrap();
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        renderer.encode(&gpu.queue, &mut encoder, &DdmFrame::new(&camera, render_settings), readback.target()).unwrap();
        gpu.queue.submit([encoder.finish()]);
        let pixels = readback.read(gpu).unwrap();
        let gbuffer = read_gbuffer(gpu, renderer.gbuffer()).unwrap();
        let name = structure.name();
        let (mut covered, mut with_exit, mut compared, mut near_decision) = (0, 0, 0, 0);
        let (mut steps_differ, mut steps_saved) = (0, 0);
        let (mut worst_exit, mut worst_inside) = (0.0_f32, f32::NEG_INFINITY);
        let mut counts = [0usize; 4];
        for (i, (texel, pixel)) in gbuffer.texels.iter().zip(&pixels).enumerate() {
            let Some((origin, direction)) = tangent_space_ray(texel, camera.eye, slab, DIMS.z as f32) else {
                assert_eq!(pixel.color.w, PIXEL_UNCOVERED, "{name}: pixel {i}");
                continue;
            };
            covered += 1;
            counts[pixel.color.w as usize] += 1;
            let (front, exit) = (texel.normal_depth.w, gbuffer.exit_distances[i]);
            if exit > 0.0 {
                with_exit += 1;
                // The exit point is on the torus, and the stretch before it is inside.
                let ray = (texel.position_coverage.truncate() - camera.eye).normalize();
                worst_exit = worst_exit.max(torus_sdf(camera.eye + ray * exit, major, minor).abs());
                for k in 1..16 {
                    let d = front + (exit - front) * k as f32 / 16.0;
                    worst_inside = worst_inside.max(torus_sdf(camera.eye + ray * d, major, minor));
                }
            }
            // CPU = GPU for the class: the same texel bits, the CPU tracer on the CPU's ray.
            let cpu = trace(&maps, Some(&patches), origin, direction, TRACE_SETTINGS);
            let shell = shell_exit(front, exit, direction);
            let bottom = slab_bottom(direction, DIMS.z as f32);
            let expected = pixel_class(cpu.hit.map(|h| h.t), shell, bottom);
            // A class decided within rounding of the ray's parameters (1e-4 voxel on rays
            // of ≤ ~100 voxels) may fall either way: counted, not compared.
            let margin = 1e-4_f32;
            let close = |a: f32, b: f32| a != NO_EXIT && b != NO_EXIT && (a - b).abs() <= margin;
            if cpu.hit.is_some_and(|h| close(h.t, shell)) || close(shell, bottom) {
                near_decision += 1;
                continue;
            }
            compared += 1;
            // The GPU's trace stops at the shell exit: its steps are the CPU's `trace_within`'s.
            let within = trace_within(&maps, Some(&patches), origin, direction, TRACE_SETTINGS, shell);
            steps_differ += usize::from(pixel.ray_origin.w as u32 != within.steps);
            steps_saved += (cpu.steps - within.steps) as usize;
            assert_eq!(
                pixel.color.w, expected,
                "{name}: pixel {i}: GPU class {} where the CPU's is {expected} (hit {:?}, shell exit {shell}, \
                 bottom {bottom})",
                pixel.color.w, cpu.hit
            );
        }
        println!(
            "{name}: covered {covered} (hit {}, miss {}, left the shell {}), {with_exit} with a second surface; \
             classes compared {compared}, {near_decision} within rounding of a decision; exit point off the torus \
             {worst_exit:e}, stretch before it outside by at most {worst_inside:e} (bound {surface_bound:e}); \
             steps saved by stopping at the exit {steps_saved}, steps differing from the CPU's {steps_differ}",
            counts[PIXEL_HIT as usize], counts[PIXEL_MISS as usize], counts[PIXEL_LEFT_SHELL as usize]
        );
        assert!(covered > 2000, "{name}: covered {covered}");
        assert_eq!(steps_differ, 0, "{name}: GPU steps differ from trace_within's");
        assert!(f64::from(compared) >= 0.99 * f64::from(covered), "{name}: compared {compared} of {covered}");
        assert!(worst_exit <= surface_bound, "{name}: exit point {worst_exit} off the torus > {surface_bound}");
        assert!(worst_inside <= surface_bound, "{name}: the stretch leaves the torus by {worst_inside}");
        // The silhouettes: a ray leaves the shell wherever it grazes the torus (its exit
        // within the slab's depth); the camera sees the whole outline and the hole.
        assert!(
            counts[PIXEL_LEFT_SHELL as usize] > 50,
            "{name}: only {} pixels leave the shell",
            counts[PIXEL_LEFT_SHELL as usize]
        );
    }
}

/// The inverse eye distance of what each pixel of a separate render shows (0 where the
/// object is not seen), from the pixel target and the G-buffer's front distances.
fn inverse_distances(pixels: &[BaseRenderPixel], gbuffer: &GBuffer) -> Vec<f32> {
    pixels
        .iter()
        .zip(&gbuffer.texels)
        .map(|(pixel, texel)| {
            let d = pixel.ray_direction.truncate();
            let t = match pixel.color.w {
                w if w == PIXEL_HIT => pixel.hit.w,
                w if w == PIXEL_MISS => slab_bottom(d, DIMS.z as f32),
                _ => return 0.0,
            };
            1.0 / eye_distance(texel.normal_depth.w, d, t)
        })
        .collect()
}

#[test]
fn two_objects_interpenetrate_by_depth() {
    let gpu = gpu();
    let pipelines = DdmRenderPipelines::new(&gpu.device).unwrap();
    let camera = plane_camera(WIDTH, HEIGHT);
    // The maze on the plane tile; the ball tile on the same plane moved by half a tile
    // across and half the slab up, so that each object's relief reaches into the other's.
    let plane = plane_base_mesh(DIMS, UVec2::new(3, 3)).unwrap();
    let mut moved = plane.clone();
    let size = DIMS.as_vec3();
    for p in &mut moved.positions {
        *p += Vec3::new(0.5 * size.x, 0.5 * size.y, 0.5 * size.z);
    }
    let renderers: Vec<DdmRenderer> = [(Mesostructure::Maze(1), &plane), (Mesostructure::Ball, &moved)]
        .into_iter()
        .map(|(structure, mesh)| {
            let triangles = structure.triangles(DIMS);
            let map_settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: true };
            let ddm4x1 = MapKind::Directional(DirectionCones::downward(4, 1).unwrap());
            let maps = compute_distance_maps(DIMS, &triangles, ddm4x1, map_settings).unwrap();
            let patches = VoxelPatches::build(DIMS, &triangles, &maps.surface, PatchSettings::default()).unwrap();
            let scene =
                GpuScene::new(&CompressedMaps::compress(&maps, 1).unwrap(), Some(&patches), TRACE_SETTINGS).unwrap();
            let scene = GpuSceneBuffers::new(&gpu.device, &scene).unwrap();
            let gbuffer = GBufferPass::new(&gpu.device, pipelines.gbuffer(), mesh, WIDTH, HEIGHT).unwrap();
            DdmRenderer::new(&gpu.device, &pipelines, &gbuffer, &scene).unwrap()
        })
        .collect();
    let frame = DdmFrame::new(&camera, settings());
    // Each object alone: its pixels and its inverse eye distances.
    let mut alone = Vec::new();
    for renderer in &renderers {
        let readback = PixelReadback::new(gpu, renderer).unwrap();
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        renderer.encode(&gpu.queue, &mut encoder, &frame, readback.target()).unwrap();
        gpu.queue.submit([encoder.finish()]);
        let pixels = readback.read(gpu).unwrap();
        let inverse = inverse_distances(&pixels, &read_gbuffer(gpu, renderer.gbuffer()).unwrap());
        alone.push((pixels, inverse));
    }
    // Both into one colour and depth target, in one submission.
    let texture = |format| {
        gpu.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("interpenetration target"),
            size: wgpu::Extent3d { width: WIDTH, height: HEIGHT, depth_or_array_layers: 1 },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format,
            usage: wgpu::TextureUsages::STORAGE_BINDING
                | wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        })
    };
    let (color, depth) = (texture(COLOR_TARGET_FORMAT), texture(DEPTH_TARGET_FORMAT));
    let targets: Vec<_> =
        renderers.iter().map(|r| r.color_depth_target(&gpu.device, &color, &depth).unwrap()).collect();
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    targets[0].encode_clear(&mut encoder).unwrap();
    for (renderer, target) in renderers.iter().zip(&targets) {
        renderer.encode(&gpu.queue, &mut encoder, &frame, target).unwrap();
    }
    gpu.queue.submit([encoder.finish()]);
    let colors: Vec<[u16; 4]> = bytemuck::pod_collect_to_vec(&read_texture(gpu, &color).unwrap());
    let depths: Vec<f32> = bytemuck::pod_collect_to_vec(&read_texture(gpu, &depth).unwrap());
    // The CPU's inverse distance repeats the GPU's few operations on the same values: equal
    // within 8 f32 roundings (relative); objects nearer than that to each other are a tie.
    let tolerance = 8.0 * f32::EPSILON;
    let (mut wins, mut ties, mut empty) = ([0usize; 2], 0, 0);
    for i in 0..colors.len() {
        let (a, b) = (alone[0].1[i], alone[1].1[i]);
        let nearest = a.max(b);
        if nearest == 0.0 {
            assert_eq!((colors[i], depths[i]), ([0; 4], 0.0), "pixel {i}: nothing seen, something drawn");
            empty += 1;
            continue;
        }
        assert!((depths[i] - nearest).abs() <= tolerance * nearest, "pixel {i}: depth {} for {a} and {b}", depths[i]);
        if (a - b).abs() <= tolerance * nearest {
            ties += 1;
            continue;
        }
        let winner = usize::from(b > a);
        wins[winner] += 1;
        let expected = alone[winner].0[i].color;
        assert_eq!(f16_bits_to_f32(colors[i][3]), 1.0, "pixel {i}: alpha");
        for (c, (&stored, value)) in colors[i].iter().zip(expected.to_array()).take(3).enumerate() {
            // Rounded to either half around the colour (see the colour target's test).
            assert!(f32_to_f16_bits(value).abs_diff(stored) <= 1, "pixel {i} channel {c}: {value} stored {stored}");
        }
    }
    println!(
        "interpenetration: the maze nearer at {} pixels, the ball at {}, {ties} ties, {empty} pixels with neither",
        wins[0], wins[1]
    );
    // Each object in front of the other somewhere: the two reliefs interpenetrate.
    assert!(wins[0] > 200 && wins[1] > 200, "{wins:?}");
    assert!(ties <= colors.len() / 100, "{ties} ties");
}
