//! Regression thresholds of the impostor accuracy experiment (issue 3): SSIM of impostor
//! renders against the mesh, on a reduced view set (16 directions, grains 32 px wide), for a
//! few configurations. Thresholds sit just below the values measured on lavapipe (quoted
//! beside each); the orderings are the paper's claims that our measurements confirm.
//! The full sweep is `cargo xtask impostor-accuracy`.

use grain_impostor::accuracy::{AccuracySweep, SweepRow, SweepSettings};
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
    };
    let rows = sweep.run(&gpu.device, &gpu.queue, &[(name.to_owned(), mesh)], &settings, |_| {}).unwrap();
    for r in &rows {
        println!("{name} n=8 p=64 {:?} {:?}: SSIM {:.4}, RMSE {:.4}", r.mode, r.layout, r.error.ssim, r.error.rmse);
    }
    rows
}

fn ssim(rows: &[SweepRow], mode: SamplingMode) -> f64 {
    rows.iter().find(|r| r.mode == mode && r.layout == ViewLayout::Listing1).map(|r| r.error.ssim).unwrap()
}

#[test]
fn ball_impostors_reach_their_measured_ssim() {
    let rows = measure(
        "ball",
        Ball::default().mesh().unwrap(),
        &SamplingMode::ALL,
        &[ViewLayout::Listing1, ViewLayout::Compact],
    );
    // Measured: planar 0.9291, spherical 0.9650, mixed 0.9355, mixed-smooth 0.9342.
    assert!(ssim(&rows, SamplingMode::Mixed) >= 0.93);
    assert!(ssim(&rows, SamplingMode::Planar) >= 0.92);
    // On a sphere the spherical proxy is (nearly) the surface itself: it wins.
    assert!(ssim(&rows, SamplingMode::Spherical) >= 0.96);
    // The compact layout stores each view once: it renders exactly the same images with
    // 28 of 128 views fewer (n = 8).
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
    // Measured: planar 0.8936, spherical 0.6917, mixed 0.9082.
    let mixed = ssim(&rows, SamplingMode::Mixed);
    assert!(mixed >= 0.90);
    assert!(mixed > ssim(&rows, SamplingMode::Planar) + 0.005);
    assert!(mixed > ssim(&rows, SamplingMode::Spherical) + 0.1);
    // The official code's continuous variant (smoothstep weight) measured 0.9034: the
    // paper's formula, jump at d = ρ included, scores higher here.
    let smooth = ssim(&rows, SamplingMode::MixedSmooth);
    assert!(smooth >= 0.895 && smooth < mixed);
}

#[test]
fn the_hex_nut_breaks_the_quasi_spherical_hypothesis() {
    let rows = measure("nut", HexNut::default().mesh().unwrap(), &[SamplingMode::Mixed], &[ViewLayout::Listing1]);
    let nut = ssim(&rows, SamplingMode::Mixed);
    // Measured: mixed 0.8131 (bean 0.9082, ball 0.9355 at the same settings).
    assert!(nut >= 0.80);
    assert!(nut < 0.93, "the nut should score below the ball's mixed-sampling SSIM");
}
