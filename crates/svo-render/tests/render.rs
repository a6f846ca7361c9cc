//! The ground truth against exact coverage, the tracer against the truth, the dolly table,
//! and the voxel truth's convergence to the truth.

use std::sync::OnceLock;

use abuffer_mask::MaskTable;
use glam::Vec3;
use svo_brick::{BrickSize, PackedTree, VoxelLayout};
use svo_render::accuracy::{Dolly, DollySettings, compare, dolly_accuracy};
use svo_render::truth::{TruthSettings, render_source_truth, render_voxel_truth};
use svo_render::{Frame, cpu, scenes};
use svo_tracer::{Camera, Light, Model, TraceSettings};

const RADIUS: f32 = 0.6;
const BACKGROUND: Vec3 = Vec3::new(0.1, 0.12, 0.15);

/// A light beside the camera (the views look along +z from z < 0).
fn settings() -> TraceSettings {
    TraceSettings {
        light: Light { position: Vec3::new(-3.0, 4.0, -6.0), radius: 0.5, radiance: 3.0 },
        background: BACKGROUND,
        ..TraceSettings::default()
    }
}

fn table() -> &'static MaskTable<4> {
    static TABLE: OnceLock<MaskTable<4>> = OnceLock::new();
    TABLE.get_or_init(|| MaskTable::<4>::paper().unwrap())
}

/// The bumpy sphere of the dolly and the convergence test.
fn bumpy() -> scenes::Scene {
    scenes::bumpy_sphere(0.55, 0.03, 18.0).unwrap()
}

/// Its octree with 4³ bricks and `levels` levels (3, 4, 5: 16, 32, 64 voxels across).
fn bumpy_tree(levels: u32) -> &'static PackedTree {
    static TREES: OnceLock<[PackedTree; 3]> = OnceLock::new();
    let trees = TREES.get_or_init(|| {
        [3, 4, 5].map(|l| PackedTree::new(&bumpy().build(BrickSize::Four, l).unwrap(), VoxelLayout::Paper20))
    });
    &trees[(levels - 3) as usize]
}

/// The exact fraction of pixel `(x, y)`'s footprint (the cone's `(u, v) ∈ (−½, ½)²`) whose
/// rays hit the sphere of `RADIUS` at the origin: for each `u` (4096-point midpoint rule) the
/// rays in the plane of `u` that hit form one interval of `v`, the roots of the quadratic
/// discriminant `(e·d)² − |d|² (|e|² − R²) = 0` with `d = p + w v` (`e` the eye, `p ⟂ w`).
fn exact_coverage(camera: &Camera, x: u32, y: u32) -> f64 {
    let cone = camera.pixel_cone(x, y);
    let e: glam::DVec3 = cone.origin.as_dvec3();
    let spread = f64::from(cone.spread);
    let (a, r, w) = (cone.direction.as_dvec3(), cone.right.as_dvec3() * spread, cone.up.as_dvec3() * spread);
    let k = e.length_squared() - f64::from(RADIUS).powi(2);
    assert!(k > 0.0);
    let n = 4096;
    let mut area = 0.0;
    for i in 0..n {
        let u = (f64::from(i) + 0.5) / f64::from(n) - 0.5;
        let p = a + r * u;
        let (ep, ew) = (e.dot(p), e.dot(w));
        let qa = ew * ew - w.length_squared() * k;
        let qb = 2.0 * ep * ew;
        let qc = ep * ep - p.length_squared() * k;
        assert!(qa < 0.0, "the sphere subtends less than a half-space");
        let disc = qb * qb - 4.0 * qa * qc;
        if disc <= 0.0 {
            continue;
        }
        let (v1, v2) = ((-qb + disc.sqrt()) / (2.0 * qa), (-qb - disc.sqrt()) / (2.0 * qa));
        let (lo, hi) = (v1.min(v2).max(-0.5), v1.max(v2).min(0.5));
        if hi > lo {
            assert!(e.dot(p + w * (0.5 * (lo + hi))) < 0.0, "the hits lie in front of the eye");
            area += hi - lo;
        }
    }
    area / f64::from(n)
}

fn sphere_camera(size: u32) -> Camera {
    Camera::look_at(Vec3::new(0.0, 0.0, -3.0), Vec3::ZERO, Vec3::Y, 0.5, size, size).unwrap()
}

/// (a) Coverage of the truth of an analytic sphere against the exact pixel coverage.
///
/// The bound: a `k × k` stratified estimate (one ray in each stratum of area `1/k²`) of the
/// covered fraction errs only in the strata the silhouette crosses, each by at most `1/k²`.
/// A curve crosses at most `1 +` (its crossings of the `k − 1` inner grid lines of each
/// direction) strata. The silhouette of a sphere is an ellipse, which meets a line at most
/// twice, and meets the pixel's square in at most 4 arcs, so at most `4 + 4 (k − 1) = 4k`
/// strata: `|error| ≤ 4/k`. Where the silhouette is one arc monotone in both directions (all
/// but the pixels where its tangent turns through the horizontal or the vertical) it crosses
/// at most `2k − 1` strata: `|error| < 2/k`, the bound asserted for all pixels but those.
#[test]
fn the_truth_of_a_sphere_has_the_exact_pixel_coverage() {
    let scene = scenes::sphere(RADIUS).unwrap();
    let size = 32;
    let camera = sphere_camera(size);
    let exact: Vec<f64> = (0..size * size).map(|i| exact_coverage(&camera, i % size, i / size)).collect();
    for k in [4, 8] {
        let truth_settings = TruthSettings::for_voxel(2.0 / 64.0, k);
        let truth =
            render_source_truth(scene.source.as_ref(), scene.domain, &camera, &settings(), &truth_settings).unwrap();
        let (mut edge, mut worst, mut sum_abs, mut sum, mut beyond_monotone) = (0, 0.0_f64, 0.0, 0.0, 0);
        for (i, (&c, &e)) in truth.coverage.iter().zip(&exact).enumerate() {
            let error = f64::from(c) - e;
            if e <= 0.0 || e >= 1.0 {
                assert_eq!(f64::from(c), e, "pixel {i}: no silhouette, no error");
                continue;
            }
            edge += 1;
            worst = worst.max(error.abs());
            sum_abs += error.abs();
            sum += error;
            if error.abs() >= 2.0 / f64::from(k) {
                beyond_monotone += 1;
            }
        }
        let kf = f64::from(k);
        println!(
            "k = {k}: {edge} silhouette pixels, coverage error max {worst:.4} (bounds 4/k = {:.3}, 2/k = {:.3}), \
             mean |error| {:.4}, mean signed {:+.4}; {beyond_monotone} pixels beyond 2/k",
            4.0 / kf,
            2.0 / kf,
            sum_abs / f64::from(edge),
            sum / f64::from(edge),
        );
        assert!(edge >= 60, "{edge} silhouette pixels");
        assert!(worst <= 4.0 / kf, "max error {worst} above 4/k");
        assert_eq!(beyond_monotone, 0, "errors beyond 2/k");
        // Jittered strata are unbiased: the mean signed error is noise, well under 1/k².
        assert!((sum / f64::from(edge)).abs() <= 1.0 / (kf * kf), "bias {}", sum / f64::from(edge));
    }
}

/// The smooth sphere's octree: 4³ bricks, 5 levels, 64 voxels across.
fn sphere_tree() -> &'static PackedTree {
    static TREE: OnceLock<PackedTree> = OnceLock::new();
    TREE.get_or_init(|| {
        PackedTree::new(&scenes::sphere(RADIUS).unwrap().build(BrickSize::Four, 5).unwrap(), VoxelLayout::Paper20)
    })
}

/// (b) The tracer with masks against the truth of a smooth sphere, and masks against
/// α-blending on the silhouette's coverage.
#[test]
fn masks_match_the_truth_of_a_smooth_sphere() {
    let scene = scenes::sphere(RADIUS).unwrap();
    let packed = sphere_tree();
    let camera = sphere_camera(48);
    let truth_settings = TruthSettings::for_voxel(scene.voxel_size(BrickSize::Four, 5), 8);
    let truth =
        render_source_truth(scene.source.as_ref(), scene.domain, &camera, &settings(), &truth_settings).unwrap();
    let mut biases = Vec::new();
    for model in [Model::Masks, Model::AlphaBlend, Model::Nearest] {
        let frame = cpu::render(packed, table(), &camera, &TraceSettings { model, ..settings() });
        let c = compare(&frame, &truth, BACKGROUND, 1.0).unwrap();
        println!(
            "{}: SSIM {:.4}, FLIP {:.4}, RMSE {:.4}, colour error {:.4}; silhouette ({} px) coverage bias {:+.4}, \
             |error| {:.4}, over-accumulation {:.4}; {:.1} elements per pixel",
            model.name(),
            c.ssim,
            c.flip,
            c.rmse,
            c.colour_error,
            c.silhouette.pixels,
            c.silhouette.bias,
            c.silhouette.mean_abs,
            c.silhouette.over_accumulation,
            frame.mean_elements()
        );
        if model == Model::Masks {
            // Pins: measured SSIM 0.9994, ꟻLIP 0.010, colour error 0.24 % (debug and release
            // alike: every pixel is deterministic). 0.99 and 0.02 keep a margin for changes of
            // the tracer and still fail both baselines (α-blending 0.962 / 0.038, nearest
            // 0.942 / 0.047: their silhouettes are thick).
            assert!(c.ssim >= 0.99, "SSIM {}", c.ssim);
            assert!(c.flip <= 0.02, "FLIP {}", c.flip);
            assert!(c.colour_error <= 0.02, "colour error {}", c.colour_error);
        }
        biases.push(c.silhouette.bias);
    }
    // The goal (N = 128). The truth's own coverage (k = 8, jittered) is unbiased; its
    // noise on a mean over ~120 pixels is ~0.0013.
    assert!(biases[0].abs() <= 0.01, "masks' bias {}", biases[0]);
    assert!(
        biases[1] >= 0.1 && biases[1] > 5.0 * biases[0].abs(),
        "α-blending's bias {} vs masks' {}",
        biases[1],
        biases[0]
    );
}

fn finite(row: &svo_render::accuracy::AccuracyRow) -> bool {
    let c = &row.comparison;
    [
        c.rmse,
        c.ssim,
        c.flip,
        c.colour_error,
        row.drift,
        c.silhouette.bias,
        c.silhouette.mean_abs,
        row.elements_per_pixel,
        row.ms,
        row.truth_ms,
    ]
    .iter()
    .all(|v| v.is_finite())
        && c.mean.is_finite()
        && c.truth_mean.is_finite()
        && row.voxel_rmse.is_some_and(f64::is_finite)
        && row.distance.is_finite()
        && row.pixel_voxels.is_finite()
}

/// (c) The dolly's table: one row per model and view, every value finite.
#[test]
fn the_dolly_table_has_every_model_at_every_zoom() {
    let scene = bumpy();
    let packed = bumpy_tree(5);
    let views = 4;
    let dolly = Dolly::towards(&scene, 3.0, 4.0, views, 24, 24);
    let truth = TruthSettings::for_voxel(scene.voxel_size(BrickSize::Four, 5), 3);
    let settings = DollySettings { voxel_truth: true, ..DollySettings::new(dolly, settings(), truth) };
    let table = dolly_accuracy(scene.source.as_ref(), packed, table(), &settings).unwrap();
    print!("{}", table.to_csv());
    assert_eq!(table.rows.len(), (views as usize) * Model::ALL.len());
    for (i, row) in table.rows.iter().enumerate() {
        assert_eq!(row.view, i as u32 / 4);
        assert_eq!(row.model, Model::ALL[i % 4]);
        assert!(finite(row), "{row:?}");
    }
    for model in Model::ALL {
        println!("{}: max drift {:.4}", model.name(), table.max_drift(model));
    }
    let distances: Vec<f32> = table.of(Model::Masks).map(|r| r.distance).collect();
    assert!((distances[0] - 3.0).abs() < 1e-6 && (distances[3] - 3.0 / 16.0).abs() < 1e-6, "{distances:?}");
    let path = std::env::temp_dir().join(format!("svo-render-dolly-{}.csv", std::process::id()));
    svo_render::accuracy::write_csv(&table, &path).unwrap();
    assert_eq!(std::fs::read_to_string(&path).unwrap(), table.to_csv());
    let _ = std::fs::remove_file(&path);
}

/// The mean absolute coverage difference of two frames.
fn coverage_error(a: &Frame, b: &Frame) -> f64 {
    a.coverage.iter().zip(&b.coverage).map(|(x, y)| f64::from((x - y).abs())).sum::<f64>() / a.coverage.len() as f64
}

/// (d) The voxel truth (the finest level supersampled) converges to the truth as the finest
/// voxel shrinks, levels 3 → 4 → 5 (16, 32, 64 voxels across).
#[test]
fn the_voxel_truth_converges_to_the_truth() {
    let scene = bumpy();
    let camera = Camera::look_at(Vec3::new(0.3, 0.2, -2.2), Vec3::ZERO, Vec3::Y, 0.6, 32, 32).unwrap();
    let truth_settings = TruthSettings::for_voxel(scene.voxel_size(BrickSize::Four, 5), 4);
    let truth =
        render_source_truth(scene.source.as_ref(), scene.domain, &camera, &settings(), &truth_settings).unwrap();
    let mut errors = Vec::new();
    for levels in [3, 4, 5] {
        let voxel = render_voxel_truth(bumpy_tree(levels), &camera, &settings(), &truth_settings).unwrap();
        let (rmse, coverage) = (voxel.rmse(&truth).unwrap(), coverage_error(&voxel, &truth));
        println!(
            "levels {levels} (voxel {:.4}): voxel truth vs truth RMSE {rmse:.5}, mean |coverage error| {coverage:.5}",
            scene.voxel_size(BrickSize::Four, levels)
        );
        errors.push((rmse, coverage));
    }
    for pair in errors.windows(2) {
        assert!(pair[1].0 < pair[0].0, "RMSE {:?}", errors);
        assert!(pair[1].1 < pair[0].1, "coverage {:?}", errors);
    }
}

/// (e) Depth of field and shadows: the truth's lens blurs the silhouette over more pixels and
/// its shadow rays darken what the light does not see (a grazing light on the bumps), and
/// the tracer's lens cones and shadow cone agree with it on the smooth sphere.
///
/// Two defects measured here are fixed (measured and printed, not asserted beyond the pins):
/// - more shadow cones: the later elements (deeper in the surface) started their shadow
///   cones within the surface's reach and shadowed themselves, 7.4 % too dark with 4 cones
///   on the lit sphere. They now start from the element's foot on its plane, lifted by their
///   first element's circumradius (`svo_tracer::light_visibility`): 4 cones give 0.29 %,
///   the same image as 1 cone and as none (test (f) bounds every pixel);
/// - wide (defocused) cones on the bumps under a grazing light read coarse levels, where the
///   Lambert term of the mean normal, `(n̄·l)₊`, is below the truth's mean `⟨(n(x)·l)₊⟩`
///   (the clamp is convex): 19.1 % colour error. It is now the expected clamped cosine over
///   visible facets of the voxel's Gaussian lobe of micro-normals
///   (`svo_tracer::expected_clamped_cosine`): 15.8 % (7.5 % without the visible-area
///   weighting of the facets; on this curved, partly resolved surface the weighting
///   over-corrects, while on the flat far patch of Fig. 11 it is what brings the colour
///   within 1 % of the truth, `tests/appearance.rs`).
#[test]
fn lens_and_shadows_of_the_truth_agree_with_the_cones() {
    let pinhole = Camera::look_at(Vec3::new(0.0, 0.0, -2.4), Vec3::ZERO, Vec3::Y, 0.6, 32, 32).unwrap();
    let lens = pinhole.with_lens(svo_tracer::Lens { aperture: 0.4, focus: 3.5 }).unwrap();
    let grazing = Light { position: Vec3::new(-6.0, 0.5, 0.5), radius: 0.4, radiance: 3.0 };
    let trace = TraceSettings { shadow_cones: 1, ..settings() };
    let truth_settings =
        TruthSettings { shadow_rays_per_axis: 3, lens_samples_per_axis: 2, ..TruthSettings::for_voxel(2.0 / 64.0, 3) };
    let unshadowed = TruthSettings { shadow_rays_per_axis: 0, ..truth_settings };
    let edge = |f: &Frame| f.coverage.iter().filter(|&&c| c > 0.02 && c < 0.98).count();

    let bumps = bumpy();
    let (source, domain) = (bumps.source.as_ref(), bumps.domain);
    let grazing_trace = TraceSettings { light: grazing, ..trace };
    let sharp = render_source_truth(source, domain, &pinhole, &grazing_trace, &truth_settings).unwrap();
    let blurred = render_source_truth(source, domain, &lens, &grazing_trace, &truth_settings).unwrap();
    let lit = render_source_truth(source, domain, &pinhole, &grazing_trace, &unshadowed).unwrap();
    let (sharp_mean, lit_mean) = (sharp.surface_mean(BACKGROUND), lit.surface_mean(BACKGROUND));
    println!(
        "truth of the bumps, grazing light: {} silhouette pixels in focus, {} with the lens; surface mean {sharp_mean} \
         with shadows, {lit_mean} without ({:.1} % darker)",
        edge(&sharp),
        edge(&blurred),
        100.0 * (1.0 - sharp_mean.length() / lit_mean.length())
    );
    assert!(2 * edge(&blurred) >= 5 * edge(&sharp));
    assert!(sharp_mean.length() < 0.98 * lit_mean.length());
    let wide = cpu::render(bumpy_tree(5), table(), &lens, &grazing_trace);
    let c = compare(&wide, &blurred, BACKGROUND, 1.0).unwrap();
    println!(
        "masks, lens, bumps, grazing light: colour error {:.4}, SSIM {:.4} (mean {} against {})",
        c.colour_error, c.ssim, c.mean, c.truth_mean
    );

    let scene = scenes::sphere(RADIUS).unwrap();
    let (source, domain) = (scene.source.as_ref(), scene.domain);
    for (name, camera) in [("pinhole", &pinhole), ("lens", &lens)] {
        let reference = render_source_truth(source, domain, camera, &trace, &truth_settings).unwrap();
        let frame = cpu::render(sphere_tree(), table(), camera, &trace);
        let c = compare(&frame, &reference, BACKGROUND, 1.0).unwrap();
        println!(
            "masks with 1 shadow cone, smooth sphere, {name}: SSIM {:.4}, FLIP {:.4}, RMSE {:.4}, colour error {:.4}, \
             silhouette bias {:+.4} ({} px)",
            c.ssim, c.flip, c.rmse, c.colour_error, c.silhouette.bias, c.silhouette.pixels
        );
        // Pins below the measured values (pinhole SSIM 0.998 / colour error 0.3 %, lens 0.974
        // / 1.5 %).
        assert!(c.ssim >= 0.95 && c.colour_error <= 0.02, "{name}: {c:?}");
        if name == "pinhole" {
            let four = cpu::render(sphere_tree(), table(), camera, &TraceSettings { shadow_cones: 4, ..trace });
            let c4 = compare(&four, &reference, BACKGROUND, 1.0).unwrap();
            println!(
                "masks with 4 shadow cones, smooth sphere, pinhole: colour error {:.4} (mean {} against {})",
                c4.colour_error, c4.mean, c4.truth_mean
            );
        }
    }
}

/// (f) Shadow cones on a lit convex surface shadow nothing, whatever their number, and a
/// real occluder still darkens.
///
/// The bound: a shadow cone starts where its first element's circumsphere rests on the
/// element's plane, and on a convex body (whose sampled distance is at least its distance
/// to the tangent plane, see `svo_tracer::light_visibility`) no later element covers
/// anything while `n̂·l ≥ τ* = √3 R/D` (`R` the light's radius, `D ≥ |light| − radius` its
/// distance). So `V̄ = 1` exactly for those elements, and only the elements with
/// `n̂·l < τ*` may lose radiance, at most their whole `L_d ≤ Ē k_d/π a_max C(τ*, σ)` with
/// `C ≤ τ* + σ/√(2π)` the expected clamped cosine (its rectified Gaussian part is at most
/// `μ₊ + τ φ(0)`), `σ²` the largest slope variance the cones read: no pixel may differ by
/// more than `B = Ē k_d/π a_max (τ* + σ_max/√(2π))`.
#[test]
fn shadow_cones_leave_a_lit_convex_surface_lit_and_an_occluder_darkens() {
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, -2.4), Vec3::ZERO, Vec3::Y, 0.6, 32, 32).unwrap();
    let lit = settings();
    let light = lit.light;
    let tau = 3f32.sqrt() * light.radius / (light.position.length() - RADIUS);
    // The widest pinhole cone at the sphere (eye distance ≤ 3) reads levels ⌊λ⌋ and ⌊λ⌋ + 1.
    let spread = camera.pixel_cone(0, 0).spread;
    let lod = (3.0 * spread / (2.0 / 64.0)).log2().max(0.0).floor();
    let mut sigma_max = 0.0_f32;
    for i in 0..400 {
        let t = i as f32 * 0.618_034;
        let p = Vec3::new((t * 1.3).sin(), (t * 0.7).cos(), (t * 2.1).sin()).normalize() * RADIUS;
        for level in [lod, lod + 1.0] {
            sigma_max = sigma_max.max(sphere_tree().sample(p, level).unwrap().slope_variance.max(0.0).sqrt());
        }
    }
    let a_max = 0.8; // the sphere's brightest channel (red)
    let bound = light.radiance
        * lit.material.diffuse
        * std::f32::consts::FRAC_1_PI
        * a_max
        * (tau + sigma_max / (2.0 * std::f32::consts::PI).sqrt());
    let unshadowed = cpu::render(sphere_tree(), table(), &camera, &lit);
    let mean = unshadowed.surface_mean(BACKGROUND).element_sum();
    for k in [1, 2, 4] {
        let frame = cpu::render(sphere_tree(), table(), &camera, &TraceSettings { shadow_cones: k, ..lit });
        let differences: Vec<f32> =
            frame.radiance.iter().zip(&unshadowed.radiance).map(|(a, b)| (*a - *b).abs().max_element()).collect();
        let worst = differences.iter().copied().fold(0.0, f32::max);
        let changed = differences.iter().filter(|&&d| d > 0.0).count();
        let darker = 1.0 - frame.surface_mean(BACKGROUND).element_sum() / mean;
        println!(
            "K = {k} shadow cones, lit sphere: {changed} pixels differ from no shadows, by at most {worst:.2e} (bound \
             B = {bound:.4}: τ* = {tau:.4}, σ_max = {sigma_max:.4}); surface mean {:.3} % darker",
            100.0 * darker
        );
        assert!(worst <= bound, "K = {k}: a pixel differs by {worst}, above {bound}");
    }

    // A ball above a floor, lit from above: the floor under the ball is in its umbra.
    let floor_and_ball = svo_brick::SdfSurface::new(
        |p: Vec3| ((p - Vec3::new(0.0, 0.1, 0.0)).length() - 0.3).min(p.y + 0.4),
        |_| [0.7, 0.7, 0.7],
        1e-4,
    )
    .unwrap();
    let domain = scenes::DOMAIN;
    let options = svo_brick::BuildOptions { brick_size: BrickSize::Four, levels: 4, ..Default::default() };
    let tree =
        PackedTree::new(&svo_brick::BrickTree::build(&floor_and_ball, domain, options).unwrap(), VoxelLayout::Paper20);
    let above = TraceSettings {
        light: Light { position: Vec3::new(0.0, 6.0, 0.5), radius: 0.3, radiance: 3.0 },
        shadow_cones: 1,
        ..settings()
    };
    let view = Camera::look_at(Vec3::new(0.0, 1.2, -2.0), Vec3::new(0.0, -0.4, 0.0), Vec3::Y, 0.7, 24, 24).unwrap();
    let truth_settings = TruthSettings { shadow_rays_per_axis: 3, ..TruthSettings::for_voxel(2.0 / 32.0, 3) };
    let truth = render_source_truth(&floor_and_ball, domain, &view, &above, &truth_settings).unwrap();
    let truth_lit = render_source_truth(
        &floor_and_ball,
        domain,
        &view,
        &above,
        &TruthSettings { shadow_rays_per_axis: 0, ..truth_settings },
    )
    .unwrap();
    let umbra: Vec<usize> = (0..truth.radiance.len())
        .filter(|&i| {
            truth.coverage[i] == 1.0 && truth.radiance[i].element_sum() < 0.3 * truth_lit.radiance[i].element_sum()
        })
        .collect();
    let shadowed = cpu::render(&tree, table(), &view, &above);
    let unlit = cpu::render(&tree, table(), &view, &TraceSettings { shadow_cones: 0, ..above });
    let sum = |f: &Frame| umbra.iter().map(|&i| f.radiance[i].element_sum()).sum::<f32>();
    let (ratio, truth_ratio) = (sum(&shadowed) / sum(&unlit), sum(&truth) / sum(&truth_lit));
    println!(
        "ball over a floor: {} umbra pixels (the truth keeps {:.3} of their light); one shadow cone keeps {ratio:.3}",
        umbra.len(),
        truth_ratio
    );
    // The truth's umbra keeps < 0.3 of its light by construction; the cones must remove at
    // least half of the light there.
    assert!(umbra.len() >= 10, "{} umbra pixels", umbra.len());
    assert!(ratio <= 0.5, "the shadow cones keep {ratio} of the umbra's light");
}

/// The parallel render is every pixel's `trace_cone`, bit for bit, in row-major order.
/// (g) Magnified bumps: where the pixel is a fraction of the finest voxel, the shadow cones
/// start on the finest level's interpolated distance, which departs from the element's plane
/// by up to `(√3/2) S₀` between its vertex samples; started on the plane itself they covered
/// their own first elements (the frame 26 % darker with one cone, 42 % with four, in contour
/// bands, where the truth is lit). They may darken the frame no more than the truth's own
/// shadow rays darken it, plus three standard errors of the truth's mean visibility
/// (`s × s` rays per hit, each a Bernoulli of variance at most ¼, over `N` covered pixels:
/// `3 · ½ / √(s² N)`).
#[test]
fn shadow_cones_do_not_shadow_a_magnified_bumpy_surface_the_truth_sees_lit() {
    let scene = bumpy();
    let tree = PackedTree::new(&scene.build(BrickSize::Eight, 4).unwrap(), VoxelLayout::Compact16Fine8);
    let voxel = scene.voxel_size(BrickSize::Eight, 4);
    // A pixel of about an eighth of a finest voxel at the target, the light beside the view.
    let dolly = Dolly::towards(&scene, 0.25, 0.0, 1, 32, 32);
    let camera = dolly.camera(0).unwrap();
    let pixel = 2.0 * 0.25 * (0.5 * dolly.fov_y).tan() / 32.0;
    assert!(pixel < voxel / 4.0, "the view is magnified: pixel {pixel}, voxel {voxel}");
    let light_at = scene.target + (dolly.direction + 0.7 * dolly.up + 0.4 * Vec3::X).normalize() * 8.0;
    let lit = TraceSettings { light: Light { position: light_at, radius: 0.4, radiance: 3.0 }, ..settings() };
    let s = 3;
    let truth = TruthSettings { shadow_rays_per_axis: s, ..TruthSettings::for_voxel(voxel, 2) };
    let unshadowed_truth = TruthSettings { shadow_rays_per_axis: 0, ..truth };
    let (source, domain) = (scene.source.as_ref(), scene.domain);
    let truth_lit = render_source_truth(source, domain, &camera, &lit, &unshadowed_truth).unwrap();
    let truth_shadowed = render_source_truth(source, domain, &camera, &lit, &truth).unwrap();
    let covered = truth_lit.coverage.iter().filter(|&&c| c > 0.0).count();
    assert!(covered > 500, "{covered} covered pixels");
    let darker = |shadowed: &Frame, unshadowed: &Frame| {
        1.0 - shadowed.surface_mean(BACKGROUND).element_sum() / unshadowed.surface_mean(BACKGROUND).element_sum()
    };
    let truth_darker = darker(&truth_shadowed, &truth_lit);
    let noise = 3.0 * 0.5 / ((s * s) as f32 * covered as f32).sqrt();
    let unshadowed = cpu::render(&tree, table(), &camera, &lit);
    for k in [1, 4] {
        let frame = cpu::render(&tree, table(), &camera, &TraceSettings { shadow_cones: k, ..lit });
        let cones_darker = darker(&frame, &unshadowed);
        println!(
            "magnified bumps ({:.3} voxels per pixel), K = {k} shadow cones: {:.2} % darker than without; the truth's \
             shadow rays {:.2} % (± {:.2} %, {covered} px)",
            pixel / voxel,
            100.0 * cones_darker,
            100.0 * truth_darker,
            100.0 * noise
        );
        assert!(
            cones_darker <= truth_darker + noise,
            "K = {k}: {cones_darker} darker, the truth {truth_darker} ± {noise}"
        );
    }
}

#[test]
fn the_parallel_render_is_the_tracer_pixel_by_pixel() {
    let camera = Camera::look_at(Vec3::new(0.5, 0.3, -2.5), Vec3::ZERO, Vec3::Y, 0.6, 16, 12).unwrap();
    let trace = TraceSettings { shadow_cones: 1, ..settings() };
    let frame = cpu::render(sphere_tree(), table(), &camera, &trace);
    assert_eq!((frame.width, frame.height, frame.pixels()), (16, 12, 192));
    for y in 0..12 {
        for x in 0..16 {
            let r = svo_tracer::trace_cone(sphere_tree(), table(), &camera.pixel_cone(x, y), &trace);
            let i = (y * 16 + x) as usize;
            assert_eq!(frame.radiance[i].to_array().map(f32::to_bits), r.radiance.to_array().map(f32::to_bits));
            assert_eq!((frame.coverage[i].to_bits(), frame.elements[i]), (r.coverage.to_bits(), r.elements));
        }
    }
}
