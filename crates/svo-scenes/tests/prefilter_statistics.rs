//! svo-brick's prefiltered statistics of a height field against microsurface-truth's: at
//! each level whose voxel footprint spans exactly one period of a periodic height field, a
//! voxel holding the surface must have the field's height and slope deviations (σh, σn), its
//! correlation `a_s` with the attribute, and its mean attribute ā. Goal (the issue): σh, σn
//! and `a_s` within 2 %, ā exact (to f32 rounding).

use glam::Vec3;
use microsurface_truth::{HeightField, Spectrum, SurfaceStatistics, generate_gaussian};
use svo_brick::{BrickSize, BrickTree, BuildOptions, Domain};
use svo_scenes::{Attribute, HeightMapSurface};

/// The colour of a height: red low, yellow high (Fig. 11), per channel.
fn colour(h: f32) -> [f32; 3] {
    let t = 0.5 + 0.5 * (2.0 * h).tanh();
    [0.9, 0.2 + 0.7 * t, 0.1]
}

#[test]
fn prefiltered_statistics_equal_the_height_fields_at_every_level() {
    for level in 1..=4_u32 {
        let period = 1usize << level;
        // Texel = finest voxel. A Gaussian spectrum of wavelength period / 2 where the
        // generator has room (≥ 8 cells), else hashed heights of deviation ~0.2.
        let field = if period >= 8 {
            generate_gaussian(period, Spectrum::Gaussian { wavelength: period as f64 / 2.0 }, 0.35, u64::from(level))
                .unwrap()
        } else {
            let hashed = (0..period * period).map(|k| {
                let x = ((k as u64 + 1).wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 40) as f64 / f64::from(1u32 << 24);
                0.35 * (x - 0.5)
            });
            HeightField::new(period, hashed.collect()).unwrap()
        };
        let stats = SurfaceStatistics::measure(&field);
        let mean = stats.mean_height;
        let heights: Vec<f32> = field.heights().iter().map(|h| (h - mean) as f32).collect();
        let surface = HeightMapSurface::new(period, heights.clone(), 1.0, 1.0, Attribute::function(colour)).unwrap();
        // Four periods across; the plane z = 0 on a lattice point of level L, the heights
        // inside that voxel layer's footprint (|h| < S_L / 2).
        let s = period as f32;
        assert!(heights.iter().all(|h| h.abs() < 0.45 * s), "level {level}: heights too large for one voxel layer");
        let options =
            BuildOptions { brick_size: BrickSize::Four, levels: level + 1, quadrature: 16, ..BuildOptions::default() };
        let tree = BrickTree::build(&surface, Domain { origin: Vec3::new(0.0, 0.0, -2.0 * s), size: 4.0 * s }, options)
            .unwrap();
        // The reference a_s and ā, from the field's own vertices (every voxel footprint holds
        // one period's vertices once, each of projected area 1).
        let sigma = stats.height_sigma as f32;
        let shape: Vec<f32> = heights.iter().map(|&h| 2.0 * smith_micro::height_cdf(h, sigma).unwrap() - 1.0).collect();
        let attributes: Vec<[f32; 3]> = heights.iter().map(|&h| colour(h)).collect();
        let mean_attribute: [f64; 3] =
            core::array::from_fn(|c| attributes.iter().map(|a| f64::from(a[c])).sum::<f64>() / attributes.len() as f64);
        let correlation: [f64; 3] = core::array::from_fn(|c| {
            let num: f64 =
                shape.iter().zip(&attributes).map(|(s, a)| f64::from(*s) * (f64::from(a[c]) - mean_attribute[c])).sum();
            num / shape.iter().map(|s| f64::from(*s).powi(2)).sum::<f64>()
        });
        let slope = ((stats.slope_sigma.x.powi(2) + stats.slope_sigma.y.powi(2)) / 2.0).sqrt();
        let side = tree.brick_size().stored_side();
        let (mut compared, mut worst) = (0, [0.0_f64; 4]);
        for b in 0..tree.brick_count() {
            if tree.brick_levels()[b] != level {
                continue;
            }
            let origin = tree.brick_origins()[b];
            for (i, voxel) in tree.brick_voxels(b).iter().enumerate() {
                let side = side as usize;
                let vertex = [i % side, i / side % side, i / (side * side)];
                let at = |axis: usize| origin[axis] as usize / period + vertex[axis];
                // The voxel layer that holds the surface, away from the domain's sides
                // (whose footprints stick out of the domain).
                if at(2) != 2 || !(1..4).contains(&at(0)) || !(1..4).contains(&at(1)) {
                    continue;
                }
                let errors = [
                    (f64::from(voxel.distance_variance).sqrt() - stats.height_sigma) / stats.height_sigma,
                    (f64::from(voxel.slope_variance).sqrt() - slope) / slope,
                    (f64::from(voxel.correlation[1]) - correlation[1]) / correlation[1],
                    f64::from(voxel.attribute[1]) - mean_attribute[1],
                ];
                for (w, e) in worst.iter_mut().zip(errors) {
                    *w = w.max(e.abs());
                }
                compared += 1;
            }
        }
        println!(
            "level {level} (period {period}): {compared} voxels; the field's σh {:.4}, σn {:.4}; worst relative errors σh {:.2e}, σn {:.2e}, a_s {:.2e}, ā absolute {:.2e}",
            stats.height_sigma, slope, worst[0], worst[1], worst[2], worst[3]
        );
        assert!(compared >= 4, "level {level}: {compared} voxels compared");
        assert!(worst[0] <= 0.02 && worst[1] <= 0.02 && worst[2] <= 0.02, "level {level}: {worst:?}");
        assert!(worst[3] <= 1e-5, "level {level}: ā off by {}", worst[3]);
    }
}
