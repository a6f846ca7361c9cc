//! Exploration: ray-traced visible-and-lit samples on a grid of view angle, light angle
//! and azimuth difference, with the Λ' each needs, as CSV on stdout.
//! `cargo run --release -p microsurface-truth --example light_grid -- [SIZE] [RAYS] [SURFACE]`
//! (angles from the environment: `LIGHT_ANGLES=55,65 VIEW_ANGLES=30,60,80`).

use glam::DVec3;
use microsurface_truth::comparison::{attribute_s, slope_deviation};
use microsurface_truth::{
    HeightField, Spectrum, SurfaceStatistics, VisibleAverage, collect_samples, fit_samples, generate_cellular,
    generate_gaussian, generate_ridged,
};
use smith_micro::corrected_lambda;

fn direction(theta_deg: f64, phi_deg: f64) -> DVec3 {
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    DVec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let size: usize = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(512);
    let rays: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(20_000);
    let only: Option<String> = args.get(3).cloned();
    let surfaces: Vec<(&str, HeightField)> = vec![
        ("gauss", generate_gaussian(size, Spectrum::Gaussian { wavelength: 12.0 }, 0.5, 101).unwrap()),
        (
            "fbm",
            generate_gaussian(
                size,
                Spectrum::PowerLaw { min_wavelength: 6.0, max_wavelength: 96.0, exponent: 3.0 },
                0.5,
                101,
            )
            .unwrap(),
        ),
        ("band", generate_gaussian(size, Spectrum::BandPass { wavelength: 16.0, width: 0.1 }, 0.5, 101).unwrap()),
        ("cell", generate_cellular(size, size / 8, 0.5, 204).unwrap()),
        ("ridged", generate_ridged(size, 12.0, 0.5, 205).unwrap()),
    ];
    println!("surface,tv,tl,dphi,lv,ll,a,b,x,se,needed,rho");
    for (name, field) in &surfaces {
        if only.as_deref().is_some_and(|o| o != *name) {
            continue;
        }
        let samples = collect_samples(field, rays / 2, 7).unwrap();
        let model = fit_samples(&samples).unwrap();
        eprintln!(
            "{name}: view {:?} light {:?} rho {:?}",
            model.view().knots(),
            model.light().knots(),
            model.correlation_coefficients()
        );
        let stats = SurfaceStatistics::measure(field);
        let slopes = slope_deviation(&stats).unwrap();
        let mean = field.heights().iter().map(|&h| attribute_s(&stats, h)).sum::<f64>() / field.heights().len() as f64;
        let mut seed = 1000;
        let list = |key: &str, default: &[f64]| -> Vec<f64> {
            std::env::var(key).map_or(default.to_vec(), |v| v.split(',').filter_map(|x| x.parse().ok()).collect())
        };
        let light_angles = list("LIGHT_ANGLES", &[40.0, 55.0, 65.0, 75.0, 82.0]);
        let view_angles = list("VIEW_ANGLES", &[30.0, 50.0, 62.0, 70.0, 76.0, 80.0, 83.0, 85.0, 87.0]);
        for &tl in &light_angles {
            for &dphi in &[0.0, 45.0, 90.0, 135.0, 180.0] {
                for &tv in &view_angles {
                    seed += 1;
                    let az = 10.0 + seed as f64 * 37.0;
                    let v = direction(tv, az);
                    let l = direction(tl, az + dphi);
                    let lv = smith_micro::smith_lambda_direction(v.as_vec3(), slopes).unwrap();
                    let ll = smith_micro::smith_lambda_direction(l.as_vec3(), slopes).unwrap();
                    let a = f64::from(corrected_lambda(lv, &model.view()).unwrap());
                    let b = f64::from(corrected_lambda(ll, &model.light()).unwrap());
                    let Some(e) =
                        VisibleAverage::new(field, rays, seed).mean_attribute(v, Some(l), |h| attribute_s(&stats, h))
                    else {
                        continue;
                    };
                    let x = e.mean - mean;
                    let needed = 2.0 * x / (1.0 - x);
                    let rho = (a + b - needed) / a.min(b);
                    println!("{name},{tv},{tl},{dphi},{lv},{ll},{a},{b},{x},{},{needed},{rho}", e.standard_error);
                }
            }
        }
    }
}
