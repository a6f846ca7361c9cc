//! The impostor tier of `grain-renderer` (the splitter's impostor lists through a compute
//! visibility buffer) against the impostor cloud of `grain-impostor`, which samples the same
//! atlas with the same WGSL functions: the G-buffers must be equal pixel for pixel, with and
//! without the software early-Z, with either visibility buffer, with culling on, and when
//! composited over a mesh render.

use grain_impostor::mesh_gbuffer::{GpuMesh, MeshGbufferPass, ScreenGbuffer};
use grain_renderer::{ImpostorPath, TierSettings, VisibilityKind};
use grain_splitter::TierThresholds;
use integration_tests::gpu;

mod grain_scene;

use grain_scene::*;

#[test]
fn the_tier_equals_the_impostor_cloud_with_and_without_early_z_and_culling() {
    // Beans (r/R = 0.22: nothing is culled), then balls (r/R ≈ 1: the cone and Hi-Z cull).
    let beans = scene(7, grain_mesh::CoffeeBean::default().mesh().unwrap());
    let balls = scene(7, grain_mesh::Ball::default().mesh().unwrap());
    let mut culled_balls = 0;
    let mut compared = 0;
    for (name, scene) in [("beans", &beans), ("balls", &balls)] {
        let reference = cloud_render(scene);
        let pixels = reference.depth.len();
        println!("{} {name}, {} of {pixels} pixels covered by the cloud", scene.grains.len(), covered(&reference));
        assert!(covered(&reference) * 4 > pixels, "the pile fills the view");
        let kinds = kinds();
        println!("visibility buffers compared: {kinds:?}");
        for &kind in &kinds {
            for (early_z, culling) in [(false, false), (true, false), (true, true)] {
                let target = ScreenGbuffer::new(&gpu().device, SIZE).unwrap();
                let settings = TierSettings { early_z, composite: false, ..TierSettings::default() };
                let (image, stats, culled) = tier_render(scene, kind, settings, culling, &target);
                let differing =
                    (0..pixels).filter(|&i| image.depth[i].to_bits() != reference.depth[i].to_bits()).count();
                println!(
                    "{name}, {kind:?}, early-Z {early_z}, culling {culling}: {differing} depths differ; evaluated pixels {:?}, early-Z skips {:?}, resolved {}; culled (frustum, cone, Hi-Z) {:?}",
                    &stats[..2],
                    &stats[2..4],
                    stats[4],
                    &culled[..3]
                );
                assert!(
                    image == reference,
                    "{name}, {kind:?}, early-Z {early_z}, culling {culling}: the G-buffer differs"
                );
                assert_eq!(stats[4] as usize, covered(&reference));
                if early_z {
                    assert!(stats[3] > 0, "the second list skips pixels before reading the atlas");
                } else {
                    assert_eq!(stats[2] + stats[3], 0);
                }
                if name == "balls" {
                    culled_balls += culled[1] + culled[2];
                }
                compared += 1;
            }
        }
    }
    assert_eq!(compared, 6 * kinds().len());
    assert!(culled_balls > 0, "culling is exercised on the balls");
}

/// Relative depth difference of two `f32` depths computed by differently compiled copies of
/// the same formula: a few ulp of rounding (`2⁻²⁴` each) in the ray, the texture blend and the
/// projection; 2⁻¹⁸ leaves 64 ulp.
const REROUNDING: f32 = 1.0 / 262_144.0;

#[test]
fn the_raster_path_draws_the_compute_paths_image_up_to_rounding_and_ties() {
    // The same lists through sprites with a hardware depth test and through the compute
    // splats. A pixel may differ only where the paths' winners are a near tie (both covered,
    // depths within REROUNDING), or where the blended coverage sits at the threshold within
    // rounding, a set of measure zero: at most 1 pixel in 10⁴ covered ones (printed).
    let balls = scene(7, grain_mesh::Ball::default().mesh().unwrap());
    let beans = scene(7, grain_mesh::CoffeeBean::default().mesh().unwrap());
    let mut compared = 0;
    for (name, scene) in [("beans", &beans), ("balls", &balls)] {
        for (kind, samples) in kinds().into_iter().flat_map(|kind| [(kind, 1), (kind, 2)]) {
            let render = |path| {
                let target = ScreenGbuffer::new(&gpu().device, SIZE).unwrap();
                let settings = TierSettings { composite: false, path, ..TierSettings::default() };
                let every_grain_an_impostor = TierThresholds::new(1e-3, 1e6, 1.0).unwrap();
                let (image, stats, culled, _) =
                    tier_render_sampled(scene, kind, settings, true, every_grain_an_impostor, samples, &target);
                (image, stats, culled)
            };
            let (compute, compute_stats, _) = render(ImpostorPath::Compute);
            let (raster, raster_stats, _) = render(ImpostorPath::Raster);
            let pixels = compute.depth.len();
            let (mut equal, mut near_ties, mut coverage_flips) = (0, 0, 0);
            for i in 0..pixels {
                let same = compute.depth[i].to_bits() == raster.depth[i].to_bits()
                    && compute.normal_coverage[i] == raster.normal_coverage[i]
                    && compute.albedo[i] == raster.albedo[i]
                    && compute.material[i] == raster.material[i];
                let (a, b) = (compute.normal_coverage[i].w > 0.0, raster.normal_coverage[i].w > 0.0);
                if same {
                    equal += 1;
                } else if a && b && compute.normal_coverage[i].w == raster.normal_coverage[i].w {
                    let (da, db) = (compute.depth[i], raster.depth[i]);
                    assert!(
                        (da - db).abs() <= REROUNDING * da.abs().max(db.abs()),
                        "{name}, {kind:?}, pixel {i}: winners at depths {da} and {db} are no near tie"
                    );
                    near_ties += 1;
                } else {
                    coverage_flips += 1;
                }
            }
            let covered_pixels = covered(&compute);
            // Coverage is the covered fraction of the pixel's samples.
            let samples_per_pixel = (samples * samples) as f32;
            let fractional = compute.normal_coverage.iter().filter(|n| n.w > 0.0 && n.w < 1.0).count();
            assert!(
                compute.normal_coverage.iter().all(|n| (n.w * samples_per_pixel).fract() == 0.0),
                "coverage in steps of 1/{samples_per_pixel}"
            );
            assert_eq!(fractional > 0, samples > 1, "{fractional} pixels of fractional coverage");
            println!(
                "{name}, {kind:?}, {samples}×{samples} samples: {equal} of {pixels} pixels equal, {near_ties} near ties, {coverage_flips} coverage flips; \
                 fragments shaded {:?} against compute evaluations {:?} (early-Z skips {:?})",
                &raster_stats[..2],
                &compute_stats[..2],
                &compute_stats[2..4]
            );
            assert!(covered_pixels * 4 > pixels, "the pile fills the view");
            assert!(
                coverage_flips * 10_000 <= covered_pixels,
                "{coverage_flips} coverage flips of {covered_pixels} covered pixels"
            );
            assert_eq!(raster_stats[4] as usize, covered(&raster), "the resolve counts the raster's pixels");
            assert_eq!(compute_stats[4] as usize, covered_pixels);
            assert!(raster_stats[0] + raster_stats[1] > 0, "the sprites' fragments are counted");
            compared += 1;
        }
    }
    assert_eq!(compared, 4 * kinds().len());
}

#[test]
fn composited_over_a_mesh_render_each_pixel_keeps_the_nearer_surface() {
    let gpu = gpu();
    let scene = scene(5, grain_mesh::CoffeeBean::default().mesh().unwrap());
    let camera = scene.camera();
    // Meshes: every third grain, placed by its centre as the atlas is (the mesh's bounds
    // centre moved onto the grain centre).
    let meshes = scene.mesh_placed(3);
    let gpu_mesh = GpuMesh::upload(&gpu.device, &scene.mesh).unwrap();
    let mesh_pass = MeshGbufferPass::new(&gpu.device).unwrap();
    let mesh_only = ScreenGbuffer::new(&gpu.device, SIZE).unwrap();
    mesh_pass.render(&gpu.device, &gpu.queue, &gpu_mesh, &camera, &meshes, 1, &mesh_only).unwrap();
    let mesh_image = mesh_only.read(&gpu.device, &gpu.queue).unwrap();
    let alone = ScreenGbuffer::new(&gpu.device, SIZE).unwrap();
    let kind = VisibilityKind::Auto;
    let separate = TierSettings { composite: false, ..TierSettings::default() };
    let (impostors, _, _) = tier_render(&scene, kind, separate, false, &alone);
    let (composite, _, _) = tier_render(&scene, kind, TierSettings::default(), false, &mesh_only);
    let (mut from_mesh, mut from_impostor) = (0, 0);
    for i in 0..composite.depth.len() {
        let (m, t) = (mesh_image.depth[i], impostors.depth[i]);
        let expected = if t <= m && impostors.normal_coverage[i].w > 0.0 { &impostors } else { &mesh_image };
        assert_eq!(composite.depth[i].to_bits(), expected.depth[i].to_bits(), "pixel {i}: depth");
        assert_eq!(composite.normal_coverage[i], expected.normal_coverage[i], "pixel {i}: normal");
        assert_eq!(composite.albedo[i], expected.albedo[i], "pixel {i}: albedo");
        if expected.normal_coverage[i].w > 0.0 {
            if std::ptr::eq(expected, &mesh_image) { from_mesh += 1 } else { from_impostor += 1 }
        }
    }
    println!("composite: {from_mesh} pixels from meshes, {from_impostor} from impostors");
    assert!(from_mesh > 100 && from_impostor > 100, "both tiers show");
}
