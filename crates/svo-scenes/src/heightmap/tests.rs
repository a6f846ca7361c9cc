use std::path::PathBuf;

use microsurface_truth::{HeightField, Spectrum, SurfaceStatistics, generate_gaussian};

use super::*;
use crate::testing::{assert_gradient_matches, assert_lipschitz};

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("svo-scenes-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A Gaussian surface of 32 × 32 vertices (cell units) from `microsurface-truth`.
fn gaussian_grid() -> Vec<f32> {
    let field = generate_gaussian(32, Spectrum::Gaussian { wavelength: 4.0 }, 0.4, 3).unwrap();
    field.heights().iter().map(|&h| h as f32).collect()
}

#[test]
fn distances_and_interpolation_are_exact() {
    // 2 × 2 grid, texel 0.5: vertex heights 0, 1, 2, 3 (× 0.25).
    let surface = HeightMapSurface::new(2, vec![0.0, 1.0, 2.0, 3.0], 0.5, 0.25, Attribute::grey()).unwrap();
    assert_eq!(surface.height(3, -1), 0.75);
    assert_eq!(surface.interpolate(0.5, 0.5).0, 0.75);
    assert_eq!(surface.interpolate(1.5, 0.5).0, 0.75);
    assert_eq!(surface.interpolate(0.25, 0.0).0, 0.125);
    // The lower triangle of cell (0, 0): slopes (0.25, 0.5) / 0.5; the upper one's (0.25, 0.5).
    let (h, slope) = surface.interpolate(0.3, 0.1);
    assert!((h - (0.25 * 0.6 + 0.5 * 0.2)).abs() < 1e-6);
    assert_eq!(slope, Vec2::new(0.5, 1.0));
    // Wrapping: cell (1, 0) goes from height 0.25 back to 0 (slope −0.5), and so on.
    let g = surface.max_slope();
    assert!((g - 1.25f32.sqrt()).abs() < 1e-6, "{g}");
    let k = (1.0 + g * g).sqrt();
    assert!((surface.distance(Vec3::new(0.3, 0.1, 1.0)) - (1.0 - h) / k).abs() < 1e-6);
    assert!(surface.gradient(Vec3::new(0.3, 0.1, 1.0)).abs_diff_eq(Vec3::new(-0.5, -1.0, 1.0) / k, 1e-6));
}

#[test]
fn bad_grids_are_errors() {
    let error = HeightMapSurface::new(3, vec![0.0; 8], 1.0, 1.0, Attribute::grey()).unwrap_err();
    assert!(matches!(error, SceneError::HeightCount { size: 3, len: 8 }), "{error}");
    let error = HeightMapSurface::new(2, vec![0.0, f32::NAN, 0.0, 0.0], 1.0, 1.0, Attribute::grey()).unwrap_err();
    assert!(matches!(error, SceneError::NonFiniteHeight { index: 1, .. }), "{error}");
    let error = HeightMapSurface::new(2, vec![0.0; 4], 0.0, 1.0, Attribute::grey()).unwrap_err();
    assert!(error.to_string().contains("HeightMapSurface.texel"), "{error}");
    let error = HeightMapSurface::new(2, vec![1e30; 4], 1.0, 1e30, Attribute::grey()).unwrap_err();
    assert!(matches!(error, SceneError::NonFiniteHeight { index: 0, .. }), "{error}");
}

#[test]
fn height_maps_are_1_lipschitz_with_exact_gradients() {
    let surface = HeightMapSurface::new(32, gaussian_grid(), 0.25, 0.25, Attribute::grey()).unwrap();
    let (min, max) = (Vec3::new(-1.0, -2.0, -0.5), Vec3::new(9.0, 9.0, 0.5));
    assert_lipschitz(&surface, min, max, 10_000, 31);
    // Off the triangles' edges (diagonals and grid lines), where the slope jumps.
    let texel = surface.texel();
    let smooth = |p: Vec3| {
        let (u, v) = (p.x / texel, p.y / texel);
        let (fu, fv) = (u - u.floor(), v - v.floor());
        [fu, fv, 1.0 - fu, 1.0 - fv, (fu - fv).abs()].into_iter().all(|e| e > 0.02)
    };
    assert!(assert_gradient_matches(&surface, min, max, 2000, 1e-3, 1e-3, smooth) > 500);
}

#[test]
fn samples_over_one_period_have_the_statistics_of_the_grid() {
    let texel = 0.5;
    // Heights in world units are cell heights × texel: the same shape, scaled.
    let surface = HeightMapSurface::new(32, gaussian_grid(), texel, texel, Attribute::function(|h| [h; 3])).unwrap();
    let period = surface.period();
    let cell = Cell { min: Vec3::new(0.0, 0.0, -100.0), max: Vec3::new(period, period, 100.0) };
    let mut samples = Vec::new();
    surface.surface_samples(cell, 123.0, &mut samples);
    assert_eq!(samples.len(), 32 * 32);
    let projected = |s: &SurfaceSample| f64::from(s.area * s.normal.z);
    let total: f64 = samples.iter().map(projected).sum();
    assert!((total / f64::from(period * period) - 1.0).abs() < 1e-5);
    let mean = |f: &dyn Fn(&SurfaceSample) -> f64| samples.iter().map(|s| projected(s) * f(s)).sum::<f64>() / total;
    let height = mean(&|s| f64::from(s.position.z));
    let height_variance = mean(&|s| (f64::from(s.position.z) - height).powi(2));
    let slope = |s: &SurfaceSample| (f64::from(-s.normal.x / s.normal.z), f64::from(-s.normal.y / s.normal.z));
    let (mx, my) = (mean(&|s| slope(s).0), mean(&|s| slope(s).1));
    let (vx, vy) = (mean(&|s| (slope(s).0 - mx).powi(2)), mean(&|s| (slope(s).1 - my).powi(2)));
    // The same grid as a microsurface-truth height field, in cell units.
    let field = HeightField::new(32, surface.heights().iter().map(|&h| f64::from(h) / f64::from(texel)).collect());
    let statistics = SurfaceStatistics::measure(&field.unwrap());
    let relative = |a: f64, b: f64| ((a - b) / b).abs();
    let texel = f64::from(texel);
    assert!(relative(height_variance, (statistics.height_sigma * texel).powi(2)) < 1e-5);
    assert!(relative(vx, statistics.slope_sigma.x.powi(2)) < 1e-5, "{vx} {}", statistics.slope_sigma.x.powi(2));
    assert!(relative(vy, statistics.slope_sigma.y.powi(2)) < 1e-5, "{vy} {}", statistics.slope_sigma.y.powi(2));
    assert!(mx.abs() < 1e-5 && my.abs() < 1e-5);
    for s in &samples {
        assert_eq!(s.attribute, [s.position.z.clamp(0.0, 1.0); 3]);
        assert!(surface.distance(s.position).abs() < 1e-6);
    }
    // The next period over holds the same samples, shifted.
    let shifted =
        Cell { min: cell.min + Vec3::new(period, -period, 0.0), max: cell.max + Vec3::new(period, -period, 0.0) };
    let mut again = Vec::new();
    surface.surface_samples(shifted, 1.0, &mut again);
    assert_eq!(again.len(), samples.len());
    assert_eq!(again[33].position.z, samples[33].position.z);
    // A cell above the surface holds none.
    let above = Cell { min: Vec3::new(0.0, 0.0, 50.0), max: Vec3::new(period, period, 60.0) };
    surface.surface_samples(above, 1.0, &mut again);
    assert_eq!(again.len(), samples.len());
}

#[test]
fn png_height_maps_round_trip() {
    let dir = temp_dir("png");
    // 16-bit: heights k · 4096 / 65535.
    let path16 = dir.join("ramp16.png");
    let values: Vec<u16> = (0..16).map(|k| k * 4096).collect();
    image::ImageBuffer::<image::Luma<u16>, _>::from_raw(4, 4, values.clone()).unwrap().save(&path16).unwrap();
    let surface = HeightMapSurface::from_png(&path16, 0.5, 2.0, Attribute::grey()).unwrap();
    assert_eq!(surface.size(), 4);
    for (h, v) in surface.heights().iter().zip(&values) {
        assert!((h - f32::from(*v) / 65535.0 * 2.0).abs() < 1e-6);
    }
    // 8-bit.
    let path8 = dir.join("ramp8.png");
    image::GrayImage::from_raw(2, 2, vec![0, 51, 102, 255]).unwrap().save(&path8).unwrap();
    let surface = HeightMapSurface::from_png(&path8, 1.0, 1.0, Attribute::grey()).unwrap();
    assert_eq!(surface.heights(), &[0.0, 0.2, 0.4, 1.0]);
    // Not square, not grayscale, missing: errors naming the file.
    let wide = dir.join("wide.png");
    image::GrayImage::new(4, 2).save(&wide).unwrap();
    let colour = dir.join("colour.png");
    image::RgbImage::new(2, 2).save(&colour).unwrap();
    for path in [wide, colour, dir.join("missing.png")] {
        let error = HeightMapSurface::from_png(&path, 1.0, 1.0, Attribute::grey()).unwrap_err();
        assert!(error.to_string().contains(&path.display().to_string()), "{error}");
    }
    std::fs::remove_dir_all(dir).unwrap();
}
