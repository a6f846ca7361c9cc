//! Exploration: `cargo xtask fig9`'s fit and sweeps for one surface, with per-angle errors.
//! `light_eval SURFACE [SIZE] [RAYS]` (SURFACE: gauss, fbm, band, cell, ridged).

use glam::DVec3;
use microsurface_truth::comparison::{AngleComparison, Sweep, compare_models, max_error};
use microsurface_truth::{
    HeightField, LambdaCorrection, Spectrum, fit_visibility_correction, generate_cellular, generate_gaussian,
    generate_ridged,
};

fn field(name: &str, size: usize, offset: u64) -> HeightField {
    match name {
        "gauss" => generate_gaussian(size, Spectrum::Gaussian { wavelength: 16.0 }, 0.5, 1 + offset),
        "fbm" => generate_gaussian(
            size,
            Spectrum::PowerLaw { min_wavelength: 8.0, max_wavelength: size as f64 / 4.0, exponent: 3.0 },
            0.5,
            2 + offset,
        ),
        "band" => generate_gaussian(size, Spectrum::BandPass { wavelength: 24.0, width: 0.1 }, 0.5, 3 + offset),
        "cell" => generate_cellular(size, size / 8, 0.5, 4 + offset),
        _ => generate_ridged(size, 16.0, 0.5, 5 + offset),
    }
    .unwrap()
}

const ANGLES: [f64; 18] =
    [0.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 45.0, 50.0, 55.0, 60.0, 65.0, 70.0, 75.0, 80.0, 85.0];

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let name = args.get(1).map_or("cell", |s| s.as_str()).to_owned();
    let size: usize = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(1024);
    let rays: usize = args.get(3).and_then(|s| s.parse().ok()).unwrap_or(200_000);
    let surface = field(&name, size, 0);
    let gaussian = !matches!(name.as_str(), "cell" | "ridged");
    let fitting: Vec<HeightField> =
        if gaussian { vec![field(&name, size, 1000), field(&name, size, 2000)] } else { vec![surface.clone()] };
    let model = fit_visibility_correction(&fitting, rays / 4, 31).unwrap();
    println!(
        "view {:?}\nlight {:?}\nrho {:?}",
        model.view().knots(),
        model.light().knots(),
        model.correlation_coefficients()
    );
    let identity = LambdaCorrection::IDENTITY;
    let mut sweeps: Vec<(String, Option<DVec3>)> = vec![("view".into(), None)];
    for az in [90.0_f64, 0.0, 180.0] {
        let (t, p) = (60_f64.to_radians(), az.to_radians());
        sweeps.push((format!("light{az}"), Some(DVec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos()))));
    }
    for (k, (label, light)) in sweeps.iter().enumerate() {
        let sweep = Sweep {
            angles_deg: &ANGLES,
            view_azimuth: 0.0,
            light: *light,
            rays: if light.is_some() { rays / 2 } else { rays },
            seed: if light.is_some() { 22 + k as u64 } else { 17 },
        };
        let rows = compare_models(&surface, &sweep, &identity, &model).unwrap();
        let e17 = max_error(&rows, 0.0, 85.0, AngleComparison::eq17_error);
        let ec = max_error(&rows, 0.0, 85.0, AngleComparison::correlated_error);
        let per: Vec<String> = rows
            .iter()
            .map(|r| {
                format!("{:.0}:{:.2}/{:.2}", r.view_angle_deg, 100.0 * r.eq17_error(), 100.0 * r.correlated_error())
            })
            .collect();
        println!("{name} {label}: eq17 {:.2}% corrected {:.2}%\n   {}", 100.0 * e17, 100.0 * ec, per.join(" "));
    }
}
