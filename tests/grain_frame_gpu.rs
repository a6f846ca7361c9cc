//! The multiscale renderer's frame (`grain-renderer`): meshes, impostors and points in one
//! frame, culling and early-Z that change no pixel, dynamic updates, the dolly against the
//! supersampled all-mesh render, several grain types, errors, the point tier, and interpenetrating grains.

use glam::{Quat, Vec3, Vec4};
use grain_impostor::mesh_gbuffer::{GbufferImage, GpuMesh, MeshGbufferPass, ScreenGbuffer};
use grain_impostor::scene::GrainInstance;
use grain_renderer::{ImpostorTier, TierSettings, VisibilityKind};
use grain_splitter::{OccluderMapKind, TierThresholds};
use integration_tests::gpu;

mod grain_scene;

use grain_scene::*;

/// The renderer's frame: the mesh tier for the near grains, impostors for the rest, shaded.
/// Culling (frustum, cone, Hi-Z, two-phase over two frames) and the software early-Z change
/// no pixel of the G-buffer or of the shaded image; the mesh tier alone (every grain a mesh)
/// covers the pixels `grain-impostor`'s mesh pass covers, with the same surface up to rounding.
#[test]
fn culling_and_early_z_change_no_pixel_of_a_frame_and_the_mesh_tier_is_the_mesh_pass() {
    use grain_impostor::scene::ShadingUniforms;
    use grain_renderer::{RendererOptions, StackingCamera, StackingRenderer};
    let gpu = gpu();
    let scene = scene(7, grain_mesh::Ball::default().mesh().unwrap());
    let camera = StackingCamera::perspective(scene.eye, scene.target, 0.7, SIZE, (0.05, 500.0)).unwrap();
    let lighting =
        ShadingUniforms::new(Vec3::new(0.3, 1.0, 0.5), Vec3::splat(2.5), Vec3::splat(0.2), Vec3::new(0.1, 0.1, 0.15))
            .unwrap();
    // Diameters here span about 10 to 30 pixels: meshes above 18.
    let render_with = |mesh_above: f32, culling: bool, early_z: bool, samples: u32| {
        let options = RendererOptions {
            size: SIZE,
            capacity: scene.grains.len() as u32,
            mesh_above,
            point_below: grain_renderer::renderer::NO_POINT_TIER,
            band: 1.0,
            occluder_map: OccluderMapKind::Auto,
            visibility: VisibilityKind::Auto,
            culling,
            samples,
        };
        let renderer = StackingRenderer::new(&gpu.device, &gpu.queue, &scene.mesh, &scene.atlas, options).unwrap();
        let bindings = renderer.upload(&gpu.device, &scene.grains).unwrap();
        let settings = TierSettings { early_z, ..TierSettings::default() };
        // Two frames: the second has the first's history (two-phase culling, hysteresis).
        for _ in 0..2 {
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            renderer.encode(&gpu.queue, &mut encoder, &bindings, &camera, &lighting, settings).unwrap();
            gpu.queue.submit([encoder.finish()]);
        }
        let counters: grain_splitter::SplitCounters =
            bytemuck::pod_read_unaligned(&gpu.read_buffer(renderer.splitter().counters(), 64).unwrap());
        let image = grain_impostor::shading::read_image(&gpu.device, &gpu.queue, renderer.image()).unwrap();
        (renderer.gbuffer().read(&gpu.device, &gpu.queue).unwrap(), image, counters)
    };
    let render = |mesh_above: f32, culling: bool, early_z: bool| render_with(mesh_above, culling, early_z, 1);
    // With 2 × 2 visibility samples per pixel too: every sample is a full visibility test.
    let (plain, plain_image, _) = render_with(18.0, false, false, 2);
    let (culled, culled_image, counters) = render_with(18.0, true, true, 2);
    assert!(counters.culled[1] + counters.culled[2] > 0, "grains are culled");
    assert!(culled == plain && culled_image == plain_image, "2×2 samples: culling or early-Z changed the frame");
    let (plain, plain_image, plain_counters) = render(18.0, false, false);
    println!("no culling, no early-Z: lists {:?}", plain_counters.count);
    assert!(plain_counters.count[0] > 0 && plain_counters.count[1] + plain_counters.count[2] > 0, "both tiers draw");
    let (culled, culled_image, counters) = render(18.0, true, true);
    println!(
        "culling and early-Z: lists {:?}, culled (frustum, cone, Hi-Z) {:?}",
        counters.count,
        &counters.culled[..3]
    );
    assert!(counters.culled[1] + counters.culled[2] > 0, "grains are culled");
    assert!(culled == plain, "culling or early-Z changed the G-buffer");
    assert!(culled_image == plain_image, "culling or early-Z changed the shaded image");
    // Every grain a mesh: the mesh tier against the mesh pass (one sample per pixel).
    let (meshes, _, counters) = render(1e-3, false, false);
    assert_eq!(counters.count[0] as usize, scene.grains.len());
    let placed = scene.mesh_placed(1);
    let target = ScreenGbuffer::new(&gpu.device, SIZE).unwrap();
    let pass = MeshGbufferPass::new(&gpu.device).unwrap();
    let gpu_mesh = GpuMesh::upload(&gpu.device, &scene.mesh).unwrap();
    pass.render(&gpu.device, &gpu.queue, &gpu_mesh, &scene.camera(), &placed, 1, &target).unwrap();
    let reference = target.read(&gpu.device, &gpu.queue).unwrap();
    let both = |i: usize| meshes.normal_coverage[i].w > 0.0 && reference.normal_coverage[i].w > 0.0;
    let n = reference.depth.len();
    let coverage_differs =
        (0..n).filter(|&i| (meshes.normal_coverage[i].w > 0.0) != (reference.normal_coverage[i].w > 0.0)).count();
    let depth_error = (0..n)
        .filter(|&i| both(i))
        .map(|i| (meshes.depth[i] - reference.depth[i]).abs() / reference.depth[i])
        .fold(0.0f32, f32::max);
    let normal_error = (0..n)
        .filter(|&i| both(i))
        .map(|i| (meshes.normal_coverage[i] - reference.normal_coverage[i]).truncate().length())
        .fold(0.0f32, f32::max);
    let differing = (0..n).filter(|&i| meshes.depth[i] != reference.depth[i]).count();
    println!(
        "mesh tier against the mesh pass: {differing} of {n} depths differ; coverage differs at {coverage_differs} pixels; max relative depth error {depth_error:.2e}, max normal error {normal_error:.2e}"
    );
    assert!(covered(&reference) * 4 > n);
    // The tier moves the vertex by the mesh's centre before placing it, the mesh pass moves the
    // instance: the same point with other roundings. Coverage agrees; depths differ by a few
    // roundings of world positions no larger than the depths here (64 ulp of the depth bound them); normals
    // by at most one step of the f16 G-buffer per component (√3 · 2⁻¹⁰).
    assert_eq!(coverage_differs, 0);
    assert!(depth_error <= 64.0 * f32::EPSILON, "depth error {depth_error}");
    assert!(normal_error <= 3f32.sqrt() / 1024.0, "normal error {normal_error}");
}

/// A dynamic scene where a few grains move uploads only those (`update_changed`: one write
/// pair per run of consecutive indices) and renders what a fresh upload of the moved scene
/// renders.
#[test]
fn updating_only_the_moved_grains_renders_the_moved_scene() {
    use grain_renderer::{RendererOptions, StackingCamera, StackingRenderer};
    let gpu = gpu();
    let scene = scene(5, grain_mesh::Ball::default().mesh().unwrap());
    let camera = StackingCamera::perspective(scene.eye, scene.target, 0.7, SIZE, (0.05, 500.0)).unwrap();
    let lighting = grain_renderer::renderer::pile_lighting();
    let options = RendererOptions {
        size: SIZE,
        capacity: scene.grains.len() as u32,
        mesh_above: 18.0,
        point_below: grain_renderer::renderer::NO_POINT_TIER,
        band: 1.0,
        occluder_map: OccluderMapKind::Auto,
        visibility: VisibilityKind::Auto,
        culling: false,
        samples: 1,
    };
    let renderer = StackingRenderer::new(&gpu.device, &gpu.queue, &scene.mesh, &scene.atlas, options).unwrap();
    let frame = |bindings: &grain_renderer::SceneBindings| {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        renderer.encode(&gpu.queue, &mut encoder, bindings, &camera, &lighting, TierSettings::default()).unwrap();
        gpu.queue.submit([encoder.finish()]);
        renderer.gbuffer().read(&gpu.device, &gpu.queue).unwrap()
    };
    let bindings = renderer.upload(&gpu.device, &scene.grains).unwrap();
    let before = frame(&bindings);
    // Grains 99 and 120..123 (on the faces the eye sees) move by half an outer radius and turn.
    let mut moved = scene.grains.clone();
    let mut changes = Vec::new();
    for i in [99u32, 120, 121, 122, 123] {
        let g = &mut moved[i as usize];
        g.centre_scale += Vec4::new(0.5, -0.3, 0.2, 0.0) * scene.atlas.outer_radius;
        g.rotation = (Quat::from_vec4(g.rotation) * Quat::from_rotation_y(0.7)).into();
        changes.push((i, *g));
    }
    assert_eq!(renderer.update_changed(&gpu.queue, &bindings, 0, &changes).unwrap(), 2, "two runs of indices");
    let updated = frame(&bindings);
    let fresh = frame(&renderer.upload(&gpu.device, &moved).unwrap());
    let differing = (0..before.depth.len()).filter(|&i| before.depth[i] != updated.depth[i]).count();
    println!("{differing} depths changed when 5 of {} grains moved", scene.grains.len());
    assert!(differing > 0, "the moved grains show");
    assert!(updated == fresh, "the updated scene renders as a fresh upload of it");
    // Out of order, or past the scene: errors naming the indices.
    let swapped = [changes[1], changes[0]];
    let error = renderer.update_changed(&gpu.queue, &bindings, 0, &swapped).unwrap_err().to_string();
    assert!(error.contains("increasing index order: 99 after 120"), "{error}");
    let past = [(scene.grains.len() as u32, moved[0])];
    let error = renderer.update_changed(&gpu.queue, &bindings, 0, &past).unwrap_err().to_string();
    assert!(error.contains("grain 125 for a scene of 125 grains"), "{error}");
    let error = renderer.update_range(&gpu.queue, &bindings, 0, 124, &moved[..2]).unwrap_err().to_string();
    assert!(error.contains("grains 124..126 for a scene of 125 grains"), "{error}");
}

/// The multiscale renderer along a dolly from 200-pixel to 2-pixel grains, frame by frame
/// against every grain as a mesh 4 × 4 supersampled (standard SSIM and ꟻLIP), and two slow
/// dollies across the tier thresholds (meshes ↔ impostors, impostors ↔ points) where no frame
/// may spike (`frame_accuracy::spikes`: more than half of a full pop).
#[test]
fn the_multiscale_dolly_is_measured_per_frame_and_no_tier_switch_spikes() {
    use grain_renderer::frame_accuracy::{measure_frames, spikes};
    use grain_renderer::mesh_reference::MeshReference;
    use grain_renderer::{RendererOptions, StackingCamera, StackingRenderer};
    let gpu = gpu();
    // The atlas the measured impostor table's threshold is for (n = 8, p = 64, as `cargo
    // xtask stackings` bakes).
    let scene = scene_with_atlas(10, grain_mesh::CoffeeBean::default().mesh().unwrap(), (8, 64));
    let rows = grain_impostor::choice::measured_accuracy().unwrap();
    // The mesh threshold of the measured impostor table (SSIM loss ≤ 0.05); the point
    // threshold `cargo xtask stackings` measures on its bean pile (2 px), taken as a setting.
    let thresholds = TierThresholds::from_impostor_table(&rows, "bean", 0.05, 2.0, 1.1).unwrap();
    let options = RendererOptions {
        size: SIZE,
        capacity: scene.grains.len() as u32,
        mesh_above: thresholds.mesh_above(),
        point_below: thresholds.point_below(),
        band: 1.1,
        occluder_map: OccluderMapKind::Auto,
        visibility: VisibilityKind::Auto,
        culling: true,
        samples: 1,
    };
    let lighting = grain_renderer::renderer::pile_lighting();
    let truth = MeshReference::new(&gpu.device, &scene.mesh, &scene.grains, SIZE).unwrap();
    let focal = 0.5 * SIZE.1 as f32 / (0.5f32 * 0.7).tan();
    let direction = (scene.eye - scene.target).normalize();
    // A camera at which a grain of scale 1 at the target is `diameter` pixels across.
    let camera = |diameter: f32| {
        let distance = focal * 2.0 * scene.atlas.outer_radius / diameter;
        let eye = scene.target + direction * distance;
        (StackingCamera::perspective(eye, scene.target, 0.7, SIZE, (1e-3 * distance, 500.0)).unwrap(), diameter)
    };
    let run_with = |diameters: Vec<f32>, samples: u32| {
        let options = RendererOptions { samples, ..options };
        let renderer = StackingRenderer::new(&gpu.device, &gpu.queue, &scene.mesh, &scene.atlas, options).unwrap();
        let bindings = renderer.upload(&gpu.device, &scene.grains).unwrap();
        let cameras: Vec<_> = diameters.into_iter().map(camera).collect();
        let settings = TierSettings::default();
        measure_frames(gpu, &renderer, &bindings, &truth, &cameras, &lighting, settings, |_, _, _| Ok(())).unwrap()
    };
    let run = |diameters: Vec<f32>| run_with(diameters, 1);
    let diameters: Vec<f32> = (0..7).map(|k| 200.0 * 0.01f32.powf(k as f32 / 6.0)).collect();
    let dolly_2x2 = run_with(diameters.clone(), 2);
    println!("meshes above {:.1} px, points below {:.1} px", thresholds.mesh_above(), thresholds.point_below());
    let dolly = run(diameters);
    for (f, g) in dolly.iter().zip(&dolly_2x2) {
        println!(
            "  {:6.1} px: lists {:?}, SSIM {:.4}, FLIP {:.4}, mean error {:.4}; 2×2 samples: SSIM {:.4}, FLIP {:.4}, mean error {:.4}",
            f.label, f.lists, f.ssim, f.flip, f.error, g.ssim, g.flip, g.error
        );
    }
    // Every tier is drawn somewhere along the dolly.
    for list in [0, 3] {
        assert!(dolly.iter().any(|f| f.lists[list] > 0), "list {list} is drawn on the dolly");
    }
    assert!(dolly.iter().any(|f| f.lists[1] + f.lists[2] > 0), "impostors are drawn on the dolly");
    // Pins against regressions (measured on lavapipe 2026-12-02, not bounds from a property):
    // whole-frame SSIM ≥ 0.8 and mean ꟻLIP ≤ 0.2 at every frame.
    for f in dolly.iter().chain(&dolly_2x2) {
        assert!(f.ssim >= 0.8 && f.flip <= 0.2, "{:.1} px: SSIM {:.4}, FLIP {:.4}", f.label, f.ssim, f.flip);
    }
    let mut switched = 0;
    for (name, threshold) in [("meshes ↔ impostors", thresholds.mesh_above()), ("impostors ↔ points", 2.0)] {
        // 10 frames from 25 % above the threshold to 25 % below, 2.5 % apart.
        let frames = run((0..10).map(|k| threshold * 1.25 * 0.6f32.powf(k as f32 / 9.0)).collect());
        for f in &frames {
            println!(
                "  {name} {:6.2} px: lists {:?}, mean error {:.4}, popping {:?}",
                f.label,
                f.lists,
                f.error,
                f.popping()
            );
        }
        assert_ne!(frames[0].lists, frames[9].lists, "{name}: grains change tier across the threshold");
        assert!(spikes(&frames).is_empty(), "{name}: frames {:?} spike", spikes(&frames));
        switched += 1;
    }
    assert_eq!(switched, 2);
}

/// A scene of two grain types (beans and balls, interleaved) renders, pixel for pixel, the
/// nearer of the two one-type renders: each type is split, culled and drawn on its own, the
/// meshes of both share one depth test, and each impostor tier composites over what is there.
#[test]
fn two_grain_types_in_one_scene_keep_the_nearer_surface_of_each_pixel() {
    use grain_renderer::{GrainType, RendererOptions, StackingCamera, StackingRenderer};
    let gpu = gpu();
    let beans = scene(5, grain_mesh::CoffeeBean::default().mesh().unwrap());
    let mut balls = scene(5, grain_mesh::Ball::default().mesh().unwrap());
    // Smaller balls between the beans: half a bean spacing along each axis, 0.4 of their size.
    let shift = Vec3::splat(0.8 * beans.atlas.outer_radius);
    for g in &mut balls.grains {
        g.centre_scale = (g.centre_scale.truncate() + shift).extend(0.4 * g.centre_scale.w);
    }
    // Far enough that most grains are impostors (below 18 px).
    let eye = beans.target + (beans.eye - beans.target) * 1.6;
    let camera = StackingCamera::perspective(eye, beans.target, 0.7, SIZE, (0.05, 500.0)).unwrap();
    let lighting = grain_renderer::renderer::pile_lighting();
    let options = RendererOptions {
        size: SIZE,
        capacity: 125,
        mesh_above: 18.0,
        point_below: grain_renderer::renderer::NO_POINT_TIER,
        band: 1.0,
        occluder_map: OccluderMapKind::Auto,
        visibility: VisibilityKind::Auto,
        culling: true,
        samples: 1,
    };
    let render = |types: &[&Scene]| {
        let kinds: Vec<GrainType<'_>> = types
            .iter()
            .map(|s| GrainType { mesh: &s.mesh, atlas: &s.atlas, mesh_above: 18.0, point_below: 1e-6 })
            .collect();
        let renderer = StackingRenderer::with_types(&gpu.device, &gpu.queue, &kinds, options).unwrap();
        let grains: Vec<&[GrainInstance]> = types.iter().map(|s| s.grains.as_slice()).collect();
        let bindings = renderer.upload_types(&gpu.device, &grains).unwrap();
        for _ in 0..2 {
            let mut encoder = gpu.device.create_command_encoder(&Default::default());
            renderer.encode(&gpu.queue, &mut encoder, &bindings, &camera, &lighting, TierSettings::default()).unwrap();
            gpu.queue.submit([encoder.finish()]);
        }
        let counters = renderer.read_counters(gpu).unwrap();
        (renderer.gbuffer().read(&gpu.device, &gpu.queue).unwrap(), counters)
    };
    let (only_beans, bean_counters) = render(&[&beans]);
    let (only_balls, ball_counters) = render(&[&balls]);
    let (both, counters) = render(&[&beans, &balls]);
    for list in 0..4 {
        assert_eq!(counters.count[list], bean_counters.count[list] + ball_counters.count[list], "list {list}");
    }
    assert!(counters.count[0] > 0 && counters.count[1] + counters.count[2] > 0, "meshes and impostors drawn");
    let texel = |g: &GbufferImage, i: usize| (g.normal_coverage[i], g.albedo[i], g.material[i], g.depth[i]);
    let (mut from_beans, mut from_balls, mut ties) = (0, 0, 0);
    for i in 0..both.depth.len() {
        let (a, b) = (only_beans.depth[i], only_balls.depth[i]);
        if a == b && a.is_finite() {
            ties += 1;
            continue;
        }
        let expected = if a <= b { texel(&only_beans, i) } else { texel(&only_balls, i) };
        assert_eq!(texel(&both, i), expected, "pixel {i}: depths {a} (beans) and {b} (balls)");
        if a < b {
            from_beans += 1;
        } else if b < a {
            from_balls += 1;
        }
    }
    println!(
        "lists {:?} (beans {:?}, balls {:?}); {from_beans} pixels show beans, {from_balls} balls, {ties} exact ties",
        counters.count, bean_counters.count, ball_counters.count
    );
    assert!(from_beans > 500 && from_balls > 500, "both types are seen");
    assert!(ties * 1000 <= both.depth.len(), "{ties} exact ties");
}

/// Bad input is an error naming what is wrong, and no buffer of the tier can be mapped (a
/// frame never waits on the CPU).
#[test]
fn errors_name_what_is_wrong_and_no_tier_buffer_is_mappable() {
    use grain_renderer::{RendererOptions, StackingRenderer};
    let gpu = gpu();
    let scene = scene(2, grain_mesh::Ball::default().mesh().unwrap());
    let tier = ImpostorTier::new(&gpu.device, SIZE, VisibilityKind::Auto).unwrap();
    for (name, buffer) in tier.buffers() {
        let usage = buffer.usage();
        assert!(!usage.intersects(wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::MAP_WRITE), "{name}: {usage:?}");
    }
    let e = ImpostorTier::new(&gpu.device, (0, 10), VisibilityKind::Auto).err().unwrap().to_string();
    assert!(e.contains("size"), "{e}");
    let e = ImpostorTier::with_samples(&gpu.device, SIZE, VisibilityKind::Auto, 5).err().unwrap().to_string();
    assert!(e.contains("samples") && e.contains("1 to 4"), "{e}");
    let options = RendererOptions {
        size: SIZE,
        capacity: 4,
        mesh_above: 30.0,
        point_below: grain_renderer::renderer::NO_POINT_TIER,
        band: 1.1,
        occluder_map: OccluderMapKind::Auto,
        visibility: VisibilityKind::Auto,
        culling: true,
        samples: 1,
    };
    let renderer = StackingRenderer::new(&gpu.device, &gpu.queue, &scene.mesh, &scene.atlas, options).unwrap();
    let e = renderer.upload(&gpu.device, &scene.grains).err().unwrap().to_string();
    assert!(e.contains("8 grains: need 1 to 4"), "{e}");
    let e = renderer.upload(&gpu.device, &[]).err().unwrap().to_string();
    assert!(e.contains("0 grains"), "{e}");
    let bad = RendererOptions { mesh_above: -1.0, ..options };
    let e = StackingRenderer::new(&gpu.device, &gpu.queue, &scene.mesh, &scene.atlas, bad).err().unwrap().to_string();
    assert!(e.contains("mesh_above"), "{e}");
    let bindings = renderer.upload(&gpu.device, &scene.grains[..4]).unwrap();
    let e = renderer.update(&gpu.queue, &bindings, &scene.grains).err().unwrap().to_string();
    assert!(e.contains("8 grains for a scene of 4"), "{e}");
    let small =
        grain_renderer::StackingCamera::perspective(scene.eye, scene.target, 0.7, (64, 64), (0.05, 500.0)).unwrap();
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    let lighting = grain_impostor::scene::ShadingUniforms::new(Vec3::Y, Vec3::ONE, Vec3::ZERO, Vec3::ZERO).unwrap();
    let e =
        renderer.encode(&gpu.queue, &mut encoder, &bindings, &small, &lighting, TierSettings::default()).err().unwrap();
    assert!(e.to_string().contains("size"), "{e}");
    let camera =
        grain_renderer::StackingCamera::perspective(scene.eye, scene.target, 0.7, SIZE, (0.05, 500.0)).unwrap();
    let bad_threshold = TierSettings { coverage_threshold: 0.0, ..TierSettings::default() };
    let e = renderer.encode(&gpu.queue, &mut encoder, &bindings, &camera, &lighting, bad_threshold).err().unwrap();
    assert!(e.to_string().contains("coverage_threshold"), "{e}");
}

/// The point tier: every grain a point (small balls far away). Every pixel holding a grain's
/// centre is covered (centres within 10⁻³ px of a pixel edge are left out and counted), every
/// covered pixel lies in some grain's disc (its projected outer radius, 1 % and 10⁻³ px of
/// rounding allowed), the uniform material comes back within the fixed point's and the 8-bit
/// G-buffer's rounding, and pixels holding several grains average them.
#[test]
fn the_point_tier_covers_the_centres_pixels_and_averages_their_grains() {
    let mut scene = scene(12, grain_mesh::Ball::default().mesh().unwrap());
    scene.eye = scene.target + (scene.eye - scene.target) * 3.0;
    let split_camera = scene.split_camera();
    let target = ScreenGbuffer::new(&gpu().device, SIZE).unwrap();
    let points = TierThresholds::new(1e5, 1e6, 1.0).unwrap();
    let settings = TierSettings { composite: false, ..TierSettings::default() };
    for kind in kinds() {
        let (image, stats, _, sums) = tier_render_with(&scene, kind, settings, false, points, &target);
        let mut centre_pixels = vec![false; image.depth.len()];
        let mut ambiguous = 0;
        let focal = split_camera.projection.x;
        let mut discs = Vec::new();
        for g in &scene.grains {
            let projected = split_camera.project(g.centre_scale.truncate());
            let Some(pixel) = projected.pixel else { continue };
            let radius = (scene.atlas.outer_radius * g.centre_scale.w * focal / projected.view_depth).min(4.0);
            discs.push((pixel, radius));
            if !(pixel.x >= 0.0 && pixel.y >= 0.0 && pixel.x < SIZE.0 as f32 && pixel.y < SIZE.1 as f32) {
                continue;
            }
            if projected.near_pixel_edge(SIZE, 64.0) {
                ambiguous += 1;
                continue;
            }
            centre_pixels[(pixel.y as u32 * SIZE.0 + pixel.x as u32) as usize] = true;
        }
        let covered: Vec<bool> = image.normal_coverage.iter().map(|n| n.w > 0.0).collect();
        let missing = (0..covered.len()).filter(|&i| centre_pixels[i] && !covered[i]).count();
        let extra = (0..covered.len()).filter(|&i| covered[i] && !centre_pixels[i]).count();
        let outside = (0..covered.len())
            .filter(|&i| covered[i] && !centre_pixels[i])
            .filter(|&i| {
                let p = glam::Vec2::new((i as u32 % SIZE.0) as f32 + 0.5, (i as u32 / SIZE.0) as f32 + 0.5);
                !discs.iter().any(|&(c, r)| {
                    let cell = c.floor() + 0.5;
                    p.distance(c) <= r * 1.01 + 1e-3 || p.distance(cell) < 1e-3
                })
            })
            .count();
        let weights: Vec<u32> =
            sums.iter().step_by(grain_renderer::impostor_tier::TIER_POINT_SUMS as usize).copied().collect();
        let covered_count = covered.iter().filter(|&&c| c).count();
        let several = weights.iter().filter(|&&w| w >= 2).count();
        let mean = weights.iter().map(|&w| f64::from(w)).sum::<f64>() / covered_count.max(1) as f64;
        println!(
            "{kind:?}: {} grains, {covered_count} pixels covered, {missing} centre pixels missing, {extra} covered by discs beyond the centres, {outside} outside every disc ({ambiguous} centres near an edge); {several} pixels average 2 or more grains (mean {mean:.2}); resolved points {}",
            scene.grains.len(),
            stats[5]
        );
        assert_eq!(missing, 0);
        assert_eq!(outside, 0, "covered pixels outside every grain's disc");
        assert_eq!(stats[5] as usize, covered_count);
        assert!(several > 0, "the scene has pixels of several grains");
        let albedo: Vec<f32> = (0..covered.len()).filter(|&i| covered[i]).map(|i| image.albedo[i].x).collect();
        let (lo, hi) = albedo.iter().fold((f32::MAX, f32::MIN), |(lo, hi), &a| (lo.min(a), hi.max(a)));
        // One material everywhere: the averages differ by the fixed point's rounding (1/1023 per
        // grain) and the 8-bit G-buffer's (1/255) at most, twice.
        assert!(hi - lo <= 2.0 * (1.0 / 1023.0 + 1.0 / 255.0), "albedo spread {lo}..{hi}");
    }
}

/// The tier measurement runs on a small pile: one row per diameter, both tiers' losses in
/// range and measured on the same crop as the reference, a positive time per tier, and the
/// table rows it gives read back by the point threshold's rule.
#[test]
fn the_point_tier_is_measured_against_the_supersampled_mesh() {
    use grain_renderer::point_threshold::{MeasureView, measure};
    use grain_renderer::tier_selection::{IMPOSTORS, POINTS, measurements, point_threshold};
    use model_select::{Budget, Metric};
    let gpu = gpu();
    let scene = scene(6, grain_mesh::CoffeeBean::default().mesh().unwrap());
    let diameters = [1.0, 2.0, 4.0];
    let view = MeasureView { target: scene.target, direction: scene.eye - scene.target, size: SIZE, frames: 2 };
    let measured = measure(gpu, &scene.mesh, &scene.atlas, &scene.grains, view, &diameters).unwrap();
    for row in &measured.rows {
        println!(
            "{} px: ꟻLIP points {:.4}, impostors {:.4}; SSIM loss points {:.4}, impostors {:.4}; {:.3} ms and {:.3} ms ({:?}; {} px)",
            row.diameter,
            row.points.flip,
            row.impostors.flip,
            row.points.ssim_loss,
            row.impostors.ssim_loss,
            row.points.ms,
            row.impostors.ms,
            measured.timing,
            row.pixels()
        );
        for tier in [&row.points, &row.impostors] {
            assert!((0.0..=2.0).contains(&tier.ssim_loss), "{}", tier.ssim_loss);
            assert!((0.0..=1.0).contains(&tier.flip), "{}", tier.flip);
            assert!(tier.ms > 0.0 && tier.ms.is_finite(), "{}", tier.ms);
            assert_eq!(tier.image.dimensions(), row.reference.dimensions());
        }
        assert!(row.pixels() >= 256);
    }
    assert_eq!(measured.rows.iter().map(|r| r.diameter).collect::<Vec<_>>(), diameters);
    let rows = measurements("bean", &measured);
    assert_eq!(rows.len(), 2 * diameters.len());
    assert_eq!(rows.iter().filter(|r| r.representation == POINTS).count(), diameters.len());
    assert_eq!(rows.iter().filter(|r| r.representation == IMPOSTORS).count(), diameters.len());
    // Points wherever their ꟻLIP is within budget: the leading run of diameters (the
    // table's rows are the worst up to each, so a run within budget is one of raw rows).
    let budget = Budget::new(Metric::Flip, 0.1).unwrap();
    let threshold = point_threshold(&rows, "bean", budget).unwrap();
    let leading = measured.rows.iter().take_while(|r| r.points.flip <= 0.1).last().map(|r| r.diameter);
    assert_eq!(threshold, leading);
    println!("threshold: {threshold:?}");
    let backwards = MeasureView { direction: Vec3::Z, ..view };
    let e = measure(gpu, &scene.mesh, &scene.atlas, &scene.grains, backwards, &[2.0, 1.0]);
    assert!(e.err().unwrap().to_string().contains("diameters"));
}

/// Interpenetrating grains (`cargo xtask interpenetration`, `docs/failure-modes.md` §1.5): a
/// pile of beans packed from the spacing at which their outer balls are disjoint to half of
/// it (the bean's inner balls, r/R 0.22, still disjoint), every grain an impostor (`n` 8,
/// `p` 64) at 8 px, against the meshes 4 × 4 supersampled, whose depth test resolves every
/// intersection. No NaN at either end; the impostors' per-pixel depth keeps ꟻLIP, and no hole
/// opens as the grains interpenetrate.
///
/// Regression pins, not error bounds: the ꟻLIP bound, 0.06, is 0.016 above the largest
/// measured on lavapipe (0.042 → 0.044 from disjoint to tight, 300 beans at 160 × 90), and
/// the holes (pixels every mesh sample covers that the impostors leave empty) and added
/// pixels are pinned at 0.5 % of the covered pixels (measured: 2 holes of 4139, none of 1513).
#[test]
fn interpenetrating_beans_regression_pin() {
    use grain_impostor::bake::{BakeSettings, Baker, Progress};
    use grain_renderer::point_threshold::{self, MeasureView};
    use grain_scenes::{GrainRadii, Region, Stacking, StackingSpec};
    let gpu = gpu();
    let mesh = grain_mesh::CoffeeBean::default().mesh().unwrap();
    let settings = BakeSettings { progress: Progress::Hidden, ..BakeSettings::new(8, 64) };
    let atlas = Baker::new(&gpu.device).unwrap().bake(&gpu.device, &gpu.queue, &mesh, &settings).unwrap();
    let bounds = mesh.bounds();
    let radii = GrainRadii::new(bounds.occluder_radius(), bounds.outer_radius).unwrap();
    let disjoint = StackingSpec::disjoint_spacing(0.05);
    for spacing in [disjoint, 0.5 * disjoint] {
        let mut spec = StackingSpec::new(300, radii);
        (spec.seed, spec.region, spec.scale_jitter, spec.jitter, spec.spacing) =
            (9, Region::Pile { slope: 0.6 }, 0.1, 0.05, spacing);
        let stacking = Stacking::generate(&spec).unwrap();
        assert_eq!(spec.outer_balls_disjoint(), spacing == disjoint);
        let grains: Vec<GrainInstance> = stacking
            .centre_scale()
            .iter()
            .zip(stacking.rotation())
            .map(|(c, q)| GrainInstance::new(c.truncate(), c.w, Quat::from_vec4(*q)))
            .collect();
        let region = stacking.bounds();
        let [wide, ..] = grain_splitter::sweep::Shot::fig15(region.min, region.max);
        let view = MeasureView { target: wide.target, direction: wide.eye - wide.target, size: (160, 90), frames: 1 };
        let measured = point_threshold::measure(gpu, &mesh, &atlas, &grains, view, &[8.0]).unwrap();
        let tier = &measured.rows[0].impostors;
        let coverage = tier.coverage;
        println!(
            "spacing {spacing:.3}: ꟻLIP {:.4}, 1 − SSIM {:.4}, holes {} and added {} of {} covered pixels",
            tier.flip, tier.ssim_loss, coverage.uncovered, coverage.spurious, coverage.mesh_covered
        );
        assert!(tier.flip.is_finite() && tier.ssim_loss.is_finite(), "spacing {spacing}: not finite");
        assert!(tier.flip <= 0.06, "spacing {spacing}: ꟻLIP {}", tier.flip);
        assert!(coverage.mesh_covered > 1000, "spacing {spacing}: the pile covers {} pixels", coverage.mesh_covered);
        let allowed = coverage.mesh_covered / 200;
        assert!(coverage.uncovered <= allowed, "spacing {spacing}: {} holes", coverage.uncovered);
        assert!(coverage.spurious <= allowed, "spacing {spacing}: {} added pixels", coverage.spurious);
    }
}
