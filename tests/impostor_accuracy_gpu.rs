//! The impostor accuracy experiment (issue 3) on a reduced view set (16 directions,
//! grains 32 px wide, n = 8, p = 64): SSIM of impostor renders against the mesh.
//!
//! Two kinds of test. The properties and the paper's claims, asserted without margins:
//! the compact layout renders the same images as the paper's from 100 of 128 views;
//! mixed sampling beats planar and spherical sampling on the bean; the hex nut, which
//! breaks the quasi-spherical hypothesis, scores below the ball; timing the cloud pass (either
//! clock) leaves the impostor pixel for pixel as it was. And regression pins
//! (`*_regression_pin`): no property bounds an SSIM, so their thresholds are the values
//! measured on lavapipe (quoted in each pin's doc comment) less 0.005–0.01, which leaves
//! room for another adapter's rasterization and filtering but fails on a real loss of
//! accuracy. A change that moves a measured value should move its pin in the same
//! commit, saying why. The full sweep is `cargo xtask impostor-accuracy`.

use gpu_harness::TimingSource;
use grain_impostor::accuracy::{AccuracySweep, SweepRow, SweepSettings, SweepTiming};
use grain_impostor::atlas_gpu::AtlasTextures;
use grain_impostor::bake::{BakeSettings, Baker, Progress};
use grain_mesh::{Ball, CoffeeBean, GrainMesh, HexNut};
use integration_tests::gpu;
use octahedral_map::{SamplingMode, ViewLayout};

fn measure(name: &str, mesh: GrainMesh, modes: &[SamplingMode], layouts: &[ViewLayout]) -> Vec<SweepRow> {
    let gpu = gpu();
    let sweep = AccuracySweep::new(&gpu.device).unwrap();
    let settings = SweepSettings {
        subdivisions: vec![8],
        texels: vec![64],
        modes: modes.to_vec(),
        layouts: layouts.to_vec(),
        view_count: 16,
        apparent_diameters: vec![32.0],
        timing: Some(SweepTiming { passes: 1, clock: TimingSource::WallClock }),
    };
    let rows = sweep.run(&gpu.device, &gpu.queue, &[(name.to_owned(), mesh)], &settings, |_| {}).unwrap();
    for r in &rows {
        let ms = r.cloud_ms.expect("a timed sweep times every configuration");
        println!(
            "{name} n=8 p=64 {:?} {:?}: SSIM {:.4}, RMSE {:.4}, cloud {ms:.3} ms",
            r.mode, r.layout, r.error.ssim, r.error.rmse
        );
        assert!(ms.is_finite() && ms > 0.0, "{name} {:?}: cloud pass time {ms} ms", r.mode);
    }
    rows
}

fn ssim(rows: &[SweepRow], mode: SamplingMode) -> f64 {
    rows.iter().find(|r| r.mode == mode && r.layout == ViewLayout::Listing1).map(|r| r.error.ssim).unwrap()
}

/// Regression pin of the ball's SSIM. Measured on lavapipe: planar 0.9291, spherical
/// 0.9650, mixed 0.9355, mixed-smooth 0.9342 (paper and compact layouts alike).
#[test]
fn ball_ssim_regression_pin() {
    let rows = measure("ball", Ball::default().mesh().unwrap(), &SamplingMode::ALL, &[ViewLayout::Listing1]);
    assert!(ssim(&rows, SamplingMode::Mixed) >= 0.93);
    assert!(ssim(&rows, SamplingMode::Planar) >= 0.92);
    assert!(ssim(&rows, SamplingMode::Spherical) >= 0.96);
    assert!(ssim(&rows, SamplingMode::MixedSmooth) >= 0.93);
}

#[test]
fn the_compact_layout_renders_the_same_ball_images_from_fewer_views() {
    let rows = measure(
        "ball",
        Ball::default().mesh().unwrap(),
        &SamplingMode::ALL,
        &[ViewLayout::Listing1, ViewLayout::Compact],
    );
    // On a sphere the spherical proxy is (nearly) the surface itself: it wins.
    let spherical = ssim(&rows, SamplingMode::Spherical);
    for mode in [SamplingMode::Planar, SamplingMode::Mixed, SamplingMode::MixedSmooth] {
        assert!(spherical > ssim(&rows, mode), "{mode:?}");
    }
    // The compact layout stores each view once: it renders exactly the same images with
    // the 4n − 4 = 28 duplicated equator views of 2n² = 128 fewer (n = 8).
    for mode in SamplingMode::ALL {
        let of = |layout| rows.iter().find(|r| r.mode == mode && r.layout == layout).unwrap();
        let (paper, compact) = (of(ViewLayout::Listing1), of(ViewLayout::Compact));
        assert_eq!(paper.error, compact.error, "{mode:?}");
        assert_eq!(compact.atlas_bytes * 128, paper.atlas_bytes * 100);
    }
}

#[test]
fn mixed_sampling_beats_planar_and_spherical_on_the_bean() {
    let rows = measure("bean", CoffeeBean::default().mesh().unwrap(), &SamplingMode::ALL, &[ViewLayout::Listing1]);
    // The paper's claim (§5): mixed sampling is better than either alone on a grain that
    // is neither planar nor spherical.
    let mixed = ssim(&rows, SamplingMode::Mixed);
    assert!(mixed > ssim(&rows, SamplingMode::Planar));
    assert!(mixed > ssim(&rows, SamplingMode::Spherical));
}

/// Regression pin of the bean's SSIM. Measured on lavapipe: planar 0.8936, spherical
/// 0.6917, mixed 0.9082, and the official code's continuous variant (smoothstep weight)
/// 0.9034: the paper's formula, jump at `d = ρ` included, scores higher here (pinned as
/// an observation, not a claim of the paper).
#[test]
fn bean_ssim_regression_pin() {
    let rows = measure("bean", CoffeeBean::default().mesh().unwrap(), &SamplingMode::ALL, &[ViewLayout::Listing1]);
    let mixed = ssim(&rows, SamplingMode::Mixed);
    assert!(mixed >= 0.90);
    assert!(ssim(&rows, SamplingMode::Planar) >= 0.885);
    assert!(ssim(&rows, SamplingMode::Spherical) >= 0.68);
    let smooth = ssim(&rows, SamplingMode::MixedSmooth);
    assert!(smooth >= 0.895 && smooth < mixed);
}

/// The hex nut breaks the quasi-spherical hypothesis: its mixed-sampling impostor scores
/// below the ball's at the same settings.
#[test]
fn the_hex_nut_breaks_the_quasi_spherical_hypothesis() {
    let rows = measure("nut", HexNut::default().mesh().unwrap(), &[SamplingMode::Mixed], &[ViewLayout::Listing1]);
    let nut = ssim(&rows, SamplingMode::Mixed);
    let ball = measure("ball", Ball::default().mesh().unwrap(), &[SamplingMode::Mixed], &[ViewLayout::Listing1]);
    let ball = ssim(&ball, SamplingMode::Mixed);
    assert!(nut < ball, "the nut ({nut}) should score below the ball's mixed-sampling SSIM ({ball})");
}

/// Regression pin of the hex nut's SSIM. Measured on lavapipe: mixed 0.8131 (bean 0.9082,
/// ball 0.9355 at the same settings).
#[test]
fn nut_ssim_regression_pin() {
    let rows = measure("nut", HexNut::default().mesh().unwrap(), &[SamplingMode::Mixed], &[ViewLayout::Listing1]);
    assert!(ssim(&rows, SamplingMode::Mixed) >= 0.80);
}

/// Timing leaves the images alone and reads both clocks: with the timestamps (where the
/// adapter has them; on lavapipe they do not bracket the work, so only a finite,
/// non-negative span is asserted) and the wall clock, the impostor is the untimed one,
/// pixel for pixel; no timed pass and timestamps on a device without them are errors.
#[test]
fn timing_the_cloud_pass_leaves_the_impostor_unchanged() {
    let gpu = gpu();
    let mesh = Ball::default().mesh().unwrap();
    let sweep = AccuracySweep::new(&gpu.device).unwrap();
    let scene = AccuracySweep::scene(&mesh, 4, 32.0).unwrap();
    let bake = BakeSettings { progress: Progress::Hidden, ..BakeSettings::new(4, 32) };
    let atlas = Baker::new(&gpu.device).unwrap().bake(&gpu.device, &gpu.queue, &mesh, &bake).unwrap();
    let textures = AtlasTextures::upload(&gpu.device, &gpu.queue, &atlas).unwrap();
    let render =
        |timing| sweep.impostor_timed(&gpu.device, &gpu.queue, &atlas, &textures, &scene, SamplingMode::Mixed, timing);
    let (untimed, none) = render(None).unwrap();
    assert_eq!(none, None);
    let mut clocks = vec![TimingSource::WallClock];
    if gpu.device.features().contains(wgpu::Features::TIMESTAMP_QUERY) {
        clocks.push(TimingSource::Timestamps);
    } else {
        let error = render(Some(SweepTiming { passes: 1, clock: TimingSource::Timestamps })).unwrap_err();
        assert!(error.to_string().contains("TIMESTAMP_QUERY"), "{error}");
    }
    println!("clocks compared: {}", clocks.len());
    for clock in clocks {
        let (image, ms) = render(Some(SweepTiming { passes: 2, clock })).unwrap();
        let ms = ms.unwrap();
        println!("{}: {ms:.4} ms", clock.name());
        assert!(ms.is_finite() && ms >= 0.0, "{}: {ms}", clock.name());
        assert!(image == untimed, "{}: the timed render differs", clock.name());
    }
    let error = render(Some(SweepTiming { passes: 0, clock: TimingSource::WallClock })).unwrap_err();
    assert!(error.to_string().contains("timing.passes"), "{error}");
}
