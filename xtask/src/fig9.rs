//! `cargo xtask fig9 [OUT_DIR] [--height-map PNG] [--quick] [--spectra]`: the ground-truth experiment
//! of Heitz & Neyret 2012, Fig. 9 — the mean attribute seen at each view angle, ray traced
//! on Gaussian and non-Gaussian height fields, against eq. 17 and MIP-mapping (CSV + PNG).
//! `--spectra` adds a sweep over spectra of the Λ correction eq. 17 would need;
//! `--height-map` adds a surface from a grayscale image (white = 16 cells high, period =
//! the image side).
//!
//! The corrected model (`smith_micro::LambdaCorrection`) of each generated surface is
//! fitted on an independent realization of its generator (another seed) with
//! `fit_lambda_correction`, then evaluated on the surface itself: the sweeps shown are
//! never used for fitting. A `--height-map` has no second realization and is not
//! corrected (its corrected columns equal eq. 17).

use std::path::{Path, PathBuf};

use glam::DVec3;
use microsurface_truth::comparison::{AngleComparison, Sweep, compare, compare_corrected, max_error, max_errors};
use microsurface_truth::{
    HeightField, LambdaCorrection, Spectrum, SurfaceStatistics, fit_lambda_correction, generate_cellular,
    generate_gaussian, generate_ridged,
};
use plotters::prelude::*;

use crate::chart::{draw_legend, drawing_error, legend_stroke, render_png};

/// RMS slope of every generated surface: Λ spans 0 … 20 over 0° … 89°.
const SLOPE_SIGMA: f64 = 0.5;
const ALL_ANGLES: [f64; 90] = {
    let mut a = [0.0; 90];
    let mut i = 0;
    while i < 90 {
        a[i] = i as f64;
        i += 1;
    }
    a
};
const LIGHT_ANGLES: [f64; 18] =
    [0.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 45.0, 50.0, 55.0, 60.0, 65.0, 70.0, 75.0, 80.0, 85.0];
/// The light of the view-and-light sweep: 60° from the normal, azimuth 90° from the view's.
fn light() -> DVec3 {
    let t = 60_f64.to_radians();
    DVec3::new(0.0, t.sin(), t.cos())
}
/// Channels `a_c(h) = base + amplitude · s(h)` of the RGB curves.
const CHANNELS: [(&str, RGBColor, f64, f64); 3] = [
    ("R", RGBColor(200, 30, 30), 0.55, 0.35),
    ("G", RGBColor(30, 150, 30), 0.45, -0.25),
    ("B", RGBColor(30, 60, 200), 0.35, 0.15),
];

struct Surface {
    name: String,
    gaussian: bool,
    field: HeightField,
    /// An independent realization of the same generator, to fit the correction on.
    fitting_field: Option<HeightField>,
}

/// Seed offset of the realization the correction is fitted on.
const FITTING_SEED_OFFSET: u64 = 1000;

fn surfaces(size: usize, height_map: Option<&Path>) -> Result<Vec<Surface>, String> {
    let mut list = Vec::new();
    for offset in [0, FITTING_SEED_OFFSET] {
        let realizations = realizations(size, offset)?;
        if offset == 0 {
            list = realizations;
        } else {
            for (surface, fitting) in list.iter_mut().zip(realizations) {
                surface.fitting_field = Some(fitting.field);
            }
        }
    }
    if let Some(path) = height_map {
        let field = HeightField::from_image(path, 16.0).map_err(|e| e.to_string())?;
        let name = path.file_stem().map_or("height_map".into(), |s| s.to_string_lossy().into_owned());
        list.push(Surface { name, gaussian: false, field, fitting_field: None });
    }
    Ok(list)
}

/// The generated surfaces, with generator seeds shifted by `seed_offset`.
fn realizations(size: usize, seed_offset: u64) -> Result<Vec<Surface>, String> {
    let e = |e: microsurface_truth::HeightFieldError| e.to_string();
    let list = vec![
        Surface {
            name: "gaussian_correlation".into(),
            gaussian: true,
            fitting_field: None,
            field: generate_gaussian(size, Spectrum::Gaussian { wavelength: 16.0 }, SLOPE_SIGMA, 1 + seed_offset)
                .map_err(e)?,
        },
        Surface {
            name: "fbm_power_law".into(),
            gaussian: true,
            fitting_field: None,
            field: generate_gaussian(
                size,
                Spectrum::PowerLaw { min_wavelength: 8.0, max_wavelength: size as f64 / 4.0, exponent: 3.0 },
                SLOPE_SIGMA,
                2 + seed_offset,
            )
            .map_err(e)?,
        },
        Surface {
            name: "band_pass".into(),
            gaussian: true,
            fitting_field: None,
            field: generate_gaussian(
                size,
                Spectrum::BandPass { wavelength: 24.0, width: 0.1 },
                SLOPE_SIGMA,
                3 + seed_offset,
            )
            .map_err(e)?,
        },
        Surface {
            name: "cellular".into(),
            gaussian: false,
            fitting_field: None,
            field: generate_cellular(size, size / 8, SLOPE_SIGMA, 4 + seed_offset).map_err(e)?,
        },
        Surface {
            name: "ridged".into(),
            gaussian: false,
            fitting_field: None,
            field: generate_ridged(size, 16.0, SLOPE_SIGMA, 5 + seed_offset).map_err(e)?,
        },
    ];
    Ok(list)
}

fn write_csv(path: &Path, rows: &[(String, &'static str, AngleComparison)]) -> Result<(), String> {
    let mut csv = String::from(
        "surface,sweep,view_angle_deg,lambda,truth_s,truth_standard_error,eq17_s,mip_s,eq17_error,mip_error,\
         corrected_s,corrected_error,corrected_per_direction_s,corrected_per_direction_error\n",
    );
    for (surface, sweep, r) in rows {
        csv += &format!(
            "{surface},{sweep},{},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6}\n",
            r.view_angle_deg,
            r.lambda,
            r.truth,
            r.truth_standard_error,
            r.eq17,
            r.mip,
            r.eq17_error(),
            r.mip_error(),
            r.corrected,
            r.corrected_error(),
            r.corrected_per_direction,
            r.corrected_per_direction_error()
        );
    }
    std::fs::write(path, csv).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

fn draw(path: &Path, title: &str, rows: &[AngleComparison]) -> Result<(), String> {
    render_png(path, (1200, 800), |root| {
        let mut chart = ChartBuilder::on(root)
            .caption(title, ("sans-serif", 26))
            .margin(20)
            .x_label_area_size(50)
            .y_label_area_size(70)
            .build_cartesian_2d(0.0_f64..90.0, 0.0_f64..1.0)
            .map_err(drawing_error)?;
        chart
            .configure_mesh()
            .x_desc("view angle from the mean normal (degrees)")
            .y_desc("mean attribute seen")
            .label_style(("sans-serif", 18))
            .draw()
            .map_err(drawing_error)?;
        for (name, color, base, amplitude) in CHANNELS {
            let channel = |s: f64| base + amplitude * s;
            let truth: Vec<(f64, f64)> = rows.iter().map(|r| (r.view_angle_deg, channel(r.truth))).collect();
            let eq17: Vec<(f64, f64)> = rows.iter().map(|r| (r.view_angle_deg, channel(r.eq17))).collect();
            let mip: Vec<(f64, f64)> = rows.iter().map(|r| (r.view_angle_deg, channel(r.mip))).collect();
            let corrected: Vec<(f64, f64)> = rows.iter().map(|r| (r.view_angle_deg, channel(r.corrected))).collect();
            chart
                .draw_series(LineSeries::new(truth, color.stroke_width(3)))
                .map_err(drawing_error)?
                .label(format!("{name}: ray-traced ground truth"))
                .legend(legend_stroke(color, 3, 24));
            chart
                .draw_series(DashedLineSeries::new(eq17, 10, 6, color.stroke_width(2)))
                .map_err(drawing_error)?
                .label(format!("{name}: eq. 17"))
                .legend(legend_stroke(color, 2, 8));
            chart
                .draw_series(DashedLineSeries::new(mip, 2, 6, color.mix(0.6).stroke_width(2)))
                .map_err(drawing_error)?
                .label(format!("{name}: MIP-mapping"))
                .legend(legend_stroke(color, 2, 3));
            chart
                .draw_series(corrected.iter().map(|&p| Circle::new(p, 3, color.filled())))
                .map_err(drawing_error)?
                .label(format!("{name}: eq. 17 with the fitted Λ correction"))
                .legend(move |(x, y)| Circle::new((x + 4, y), 3, color.filled()));
        }
        draw_legend(&mut chart, 16, SeriesLabelPosition::UpperLeft)
    })
}

/// View angles of the spectral sweep (where Λ matters and Monte-Carlo noise does not
/// dominate the inverted Λ).
const SWEEP_ANGLES: [f64; 8] = [65.0, 70.0, 75.0, 78.0, 81.0, 84.0, 86.0, 88.0];

/// For Gaussian surfaces of many spectra, the factor `Λ_needed / Λ` that would make eq. 17
/// match the ground truth (`Λ_needed = 2x/(1-x)`, `x = E[s] - ā`), printed against Rice's
/// spectral width `α`: whether a correction of Λ can depend on Λ (and `α`) alone.
fn spectral_sweep(size: usize, rays: usize) -> Result<(), String> {
    let spectra = [
        ("band-pass 24, width 0.05", Spectrum::BandPass { wavelength: 24.0, width: 0.05 }),
        ("band-pass 24, width 0.2", Spectrum::BandPass { wavelength: 24.0, width: 0.2 }),
        ("band-pass 24, width 0.35", Spectrum::BandPass { wavelength: 24.0, width: 0.35 }),
        ("Gaussian, ℓ = 16", Spectrum::Gaussian { wavelength: 16.0 }),
        ("Gaussian, ℓ = 8", Spectrum::Gaussian { wavelength: 8.0 }),
        ("power law β=3, 8-32", Spectrum::PowerLaw { min_wavelength: 8.0, max_wavelength: 32.0, exponent: 3.0 }),
        ("power law β=3, 8-128", Spectrum::PowerLaw { min_wavelength: 8.0, max_wavelength: 128.0, exponent: 3.0 }),
        ("power law β=4, 8-128", Spectrum::PowerLaw { min_wavelength: 8.0, max_wavelength: 128.0, exponent: 4.0 }),
        ("power law β=2.5, 6-128", Spectrum::PowerLaw { min_wavelength: 6.0, max_wavelength: 128.0, exponent: 2.5 }),
    ];
    println!("\nΛ_needed / Λ for eq. 17 to match the ground truth, per spectrum (columns: view angle, Λ):");
    for (name, spectrum) in spectra {
        let field = generate_gaussian(size, spectrum, SLOPE_SIGMA, 11).map_err(|e| e.to_string())?;
        let stats = SurfaceStatistics::measure(&field);
        let alpha = stats.spectral_width_x().unwrap_or(f64::NAN);
        let sweep = Sweep { angles_deg: &SWEEP_ANGLES, view_azimuth: 0.0, light: None, rays, seed: 5 };
        let rows = compare(&field, &sweep).ok_or(format!("{name}: degenerate surface"))?;
        let mut line = format!("  {name:<24} α = {alpha:5.2} |");
        for r in rows {
            let x = r.truth - r.mip;
            line += &format!(" {:.0}°/{:.2}: {:.3}", r.view_angle_deg, r.lambda, 2.0 * x / (1.0 - x) / r.lambda);
        }
        println!("{line}");
    }
    Ok(())
}

fn percent(x: f64) -> String {
    format!("{:.2}%", 100.0 * x)
}

/// Runs the experiment and writes `fig9.csv` and one PNG per surface and sweep into `out`.
pub fn run(args: &[&str], default_out: PathBuf) -> Result<(), String> {
    let mut out = default_out;
    let (mut height_map, mut quick, mut spectra) = (None, false, false);
    let mut iter = args.iter();
    while let Some(&arg) = iter.next() {
        match arg {
            "--height-map" => height_map = Some(PathBuf::from(iter.next().ok_or("--height-map needs a PNG path")?)),
            "--quick" => quick = true,
            "--spectra" => spectra = true,
            _ => out = PathBuf::from(arg),
        }
    }
    std::fs::create_dir_all(&out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let (size, rays) = if quick { (512, 40_000) } else { (1024, 200_000) };
    println!("Fig. 9 ground truth: {size}² periodic fields, {rays} rays per view angle, RMS slope {SLOPE_SIGMA}");
    println!("errors are fractions of the attribute range; max over view angles in each range\n");
    println!(
        "{:<22} {:>6} {:>7} {:>7} | {:>9} {:>9} {:>9} | {:>9} {:>11} | {:>9} {:>9} {:>9} {:>11}",
        "surface",
        "σ_h",
        "skew",
        "kurt",
        "eq17 0-70",
        "70-85",
        "85-89",
        "MIP 0-85",
        "light 0-85",
        "corr 0-70",
        "70-85",
        "85-89",
        "light 0-85"
    );
    let mut csv_rows = Vec::new();
    let mut knots = Vec::new();
    for surface in surfaces(size, height_map.as_deref())? {
        let stats = SurfaceStatistics::measure(&surface.field);
        let degenerate = || format!("{}: degenerate surface", surface.name);
        // Fitted on the other realization only: the sweeps below never enter the fit.
        let correction = match &surface.fitting_field {
            Some(fitting) => fit_lambda_correction(fitting, rays, 31).ok_or_else(degenerate)?,
            None => LambdaCorrection::IDENTITY,
        };
        knots.push((surface.name.clone(), surface.fitting_field.is_some(), correction.knots()));
        let view_sweep = Sweep { angles_deg: &ALL_ANGLES, view_azimuth: 0.0, light: None, rays, seed: 17 };
        let light_sweep =
            Sweep { angles_deg: &LIGHT_ANGLES, view_azimuth: 0.0, light: Some(light()), rays: rays / 2, seed: 23 };
        let view = compare_corrected(&surface.field, &view_sweep, &correction).ok_or_else(degenerate)?;
        let lit = compare_corrected(&surface.field, &light_sweep, &correction).ok_or_else(degenerate)?;
        let (low, _) = max_errors(&view, 0.0, 70.0);
        let (mid, _) = max_errors(&view, 70.0, 85.0);
        let (high, _) = max_errors(&view, 85.0, 89.0);
        let (_, mip) = max_errors(&view, 0.0, 85.0);
        let (light_error, _) = max_errors(&lit, 0.0, 85.0);
        let corrected = |rows: &[AngleComparison], low: f64, high: f64| {
            percent(max_error(rows, low, high, AngleComparison::corrected_error))
        };
        println!(
            "{:<22} {:>6.2} {:>7.3} {:>7.3} | {:>9} {:>9} {:>9} | {:>9} {:>11} | {:>9} {:>9} {:>9} {:>11}{}",
            surface.name,
            stats.height_sigma,
            stats.height_skewness,
            stats.height_excess_kurtosis,
            percent(low),
            percent(mid),
            percent(high),
            percent(mip),
            percent(light_error),
            corrected(&view, 0.0, 70.0),
            corrected(&view, 70.0, 85.0),
            corrected(&view, 85.0, 89.0),
            corrected(&lit, 0.0, 85.0),
            if surface.gaussian { "" } else { "  (non-Gaussian)" }
        );
        draw(
            &out.join(format!("fig9_{}_view.png", surface.name)),
            &format!("{}: view only (Fig. 9)", surface.name),
            &view,
        )?;
        draw(
            &out.join(format!("fig9_{}_light.png", surface.name)),
            &format!("{}: view and light (light at 60°, azimuth 90°)", surface.name),
            &lit,
        )?;
        csv_rows.extend(view.into_iter().map(|r| (surface.name.clone(), "view", r)));
        csv_rows.extend(lit.into_iter().map(|r| (surface.name.clone(), "view_and_light", r)));
    }
    write_csv(&out.join("fig9.csv"), &csv_rows)?;
    println!("\nfitted Λ correction c(u), u = Λ/(1+Λ) = 0, 1/7, …, 1 (fitted on another realization):");
    for (name, fitted, knots) in knots {
        let knots: Vec<String> = knots.iter().map(|k| format!("{k:.3}")).collect();
        println!("  {name:<22} {}{}", knots.join(" "), if fitted { "" } else { "  (not fitted: identity)" });
    }
    if spectra {
        spectral_sweep(size / 2, rays / 3)?;
    }
    println!("\nwrote {}", out.display());
    Ok(())
}
