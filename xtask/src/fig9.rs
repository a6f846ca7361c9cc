//! `cargo xtask fig9 [OUT_DIR] [--height-map PNG] [--quick] [--spectra]`: the ground-truth experiment
//! of Heitz & Neyret 2012, Fig. 9 — the mean attribute seen at each view angle, ray traced
//! on Gaussian and non-Gaussian height fields, against eq. 17 and MIP-mapping (CSV + PNG).
//! `--spectra` adds a sweep over spectra of the Λ correction eq. 17 would need;
//! `--height-map` adds a surface from a grayscale image (white = 16 cells high, period =
//! the image side).
//!
//! The corrected visibility model (`smith_micro::VisibilityCorrection`: view table, light
//! table, light–view correlation) of each Gaussian surface is fitted with
//! `fit_visibility_correction` on two independent realizations of its generator (other
//! seeds), then evaluated on the surface itself: the sweeps shown are never used for
//! fitting. Non-Gaussian surfaces are textures: their model is fitted on their own
//! height map, with other rays, azimuths and lights than the sweeps shown (as a
//! renderer's pre-computation would). Besides the Fig. 9 view sweep and the
//! view-and-light sweep (light 60°, azimuth 90° from the view), two more light sweeps
//! (azimuth 0° and 180°) show where the correlation term is weakest.

use std::path::{Path, PathBuf};

use microsurface_truth::comparison::{
    AngleComparison, EVERY_DEGREE, Sweep, compare, compare_models, light_at_60_deg, max_error, max_errors,
};
use microsurface_truth::selection::ATTRIBUTE_CHANNELS;
use microsurface_truth::{
    CUBIC_DEVIATION_BUDGET, CubicLambdaCorrection, HeightField, LambdaCorrection, SLOPE_SIGMA, Spectrum, Surface,
    SurfaceStatistics, VisibilityCorrection, fit_visibility_correction, generate_gaussian, standard_surfaces,
};
use plotters::prelude::*;

use crate::chart::{draw_legend, drawing_error, legend_stroke, render_png};
use crate::cli::Args;

const LIGHT_ANGLES: [f64; 18] =
    [0.0, 5.0, 10.0, 15.0, 20.0, 25.0, 30.0, 35.0, 40.0, 45.0, 50.0, 55.0, 60.0, 65.0, 70.0, 75.0, 80.0, 85.0];
/// The view-and-light sweeps: (CSV name, light azimuth relative to the view, degrees).
const LIGHT_SWEEPS: [(&str, f64); 3] =
    [("view_and_light", 90.0), ("view_and_light_same_azimuth", 0.0), ("view_and_light_opposite_azimuth", 180.0)];
/// The RGB curves' names and colours, for `microsurface_truth::selection::ATTRIBUTE_CHANNELS`
/// (`a_c(h) = base + amplitude · s(h)`).
const CHANNELS: [(&str, RGBColor); 3] =
    [("R", RGBColor(200, 30, 30)), ("G", RGBColor(30, 150, 30)), ("B", RGBColor(30, 60, 200))];

/// The generated surfaces (`microsurface_truth::standard_surfaces`), and a height map's.
fn surfaces(size: usize, height_map: Option<&Path>) -> Result<Vec<Surface>, String> {
    let mut list = standard_surfaces(size, 0).map_err(|e| e.to_string())?;
    if let Some(path) = height_map {
        let field = HeightField::from_image(path, 16.0).map_err(|e| e.to_string())?;
        let name = path.file_stem().map_or("height_map".into(), |s| s.to_string_lossy().into_owned());
        list.push(Surface { name, gaussian: false, field, fitting_fields: Vec::new() });
    }
    Ok(list)
}

fn write_csv(path: &Path, rows: &[(String, &str, AngleComparison, CubicLambdaCorrection)]) -> Result<(), String> {
    let mut csv = String::from(
        "surface,sweep,view_angle_deg,lambda,truth_s,truth_standard_error,eq17_s,mip_s,eq17_error,mip_error,\
         corrected_s,corrected_error,cubic_s,cubic_error\n",
    );
    for (surface, sweep, r, cubic) in rows {
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
            r.correlated,
            r.correlated_error(),
            r.cubic_corrected(cubic).unwrap_or(f64::NAN),
            r.cubic_error(cubic),
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
        for ((name, color), (base, amplitude)) in CHANNELS.into_iter().zip(ATTRIBUTE_CHANNELS) {
            let channel = |s: f64| base + amplitude * s;
            let truth: Vec<(f64, f64)> = rows.iter().map(|r| (r.view_angle_deg, channel(r.truth))).collect();
            let eq17: Vec<(f64, f64)> = rows.iter().map(|r| (r.view_angle_deg, channel(r.eq17))).collect();
            let mip: Vec<(f64, f64)> = rows.iter().map(|r| (r.view_angle_deg, channel(r.mip))).collect();
            let corrected: Vec<(f64, f64)> = rows.iter().map(|r| (r.view_angle_deg, channel(r.correlated))).collect();
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
                .label(format!("{name}: corrected model (fitted view/light tables, correlation)"))
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

/// Prints a fitted model: its two tables and `ρ` coefficients.
fn print_model(name: &str, realizations: usize, model: &VisibilityCorrection) {
    let table = |knots: [f32; 8]| knots.iter().map(|k| format!("{k:.3}")).collect::<Vec<_>>().join(" ");
    let source = if realizations == 0 { "own map".to_owned() } else { format!("{realizations} other realizations") };
    println!("  {name:<22} ({source})");
    println!("    view  {}", table(model.view().knots()));
    println!("    light {}", table(model.light().knots()));
    let [r0, r1, r2] = model.correlation_coefficients();
    println!("    ρ     {r0:.3} {r1:.3} {r2:.3}");
}

fn percent(x: f64) -> String {
    format!("{:.2}%", 100.0 * x)
}

/// The command's settings: `[OUT_DIR] [--height-map PNG] [--quick] [--spectra]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// Where the files go.
    pub out: PathBuf,
    /// A grayscale image added as a surface.
    pub height_map: Option<PathBuf>,
    /// 512² fields and fewer rays instead of 1024².
    pub quick: bool,
    /// Adds the sweep over spectra.
    pub spectra: bool,
}

impl Options {
    /// The options of `args`.
    pub fn from_args(args: &Args<'_>) -> Self {
        Self {
            out: args.out_dir(),
            height_map: args.value("height-map").map(PathBuf::from),
            quick: args.flag("quick"),
            spectra: args.flag("spectra"),
        }
    }
}

/// Runs the experiment and writes `fig9.csv` and one PNG per surface and sweep into the
/// output folder.
pub fn run(args: &Args<'_>) -> Result<(), String> {
    let Options { out, height_map, quick, spectra } = Options::from_args(args);
    std::fs::create_dir_all(&out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let (size, rays) = if quick { (512, 40_000) } else { (1024, 200_000) };
    println!("Fig. 9 ground truth: {size}² periodic fields, {rays} rays per view angle, RMS slope {SLOPE_SIGMA}");
    println!("errors are fractions of the attribute range; max over view angles in each range\n");
    println!(
        "{:<22} {:>6} {:>7} {:>7} | {:>9} {:>9} {:>9} {:>9} | {:>9} {:>9} {:>9} {:>9} | {:>9}",
        "surface",
        "σ_h",
        "skew",
        "kurt",
        "eq17 view",
        "light 90°",
        "0°",
        "180°",
        "corr view",
        "light 90°",
        "0°",
        "180°",
        "MIP 0-85"
    );
    println!("{:>58}(max error 0-85°; eq. 17, then the corrected model; light at 60°, azimuth from the view)", "");
    let mut csv_rows = Vec::new();
    let mut models = Vec::new();
    // Rays per direction pair of the fit, on each fitting realization.
    let fit_rays = rays / 4;
    for surface in surfaces(size, height_map.as_deref())? {
        let stats = SurfaceStatistics::measure(&surface.field);
        let degenerate = || format!("{}: degenerate surface", surface.name);
        // Gaussian surfaces: fitted on other realizations only. Textures: on their own map,
        // with rays, azimuths and lights other than those of the sweeps below.
        let model = fit_visibility_correction(surface.fitting(), fit_rays, 31)
            .map_err(|e| format!("{}: cannot fit the visibility model: {e}", surface.name))?;
        models.push((surface.name.clone(), surface.fitting_fields.len(), model));
        // The view table as a cubic (`smith_micro::cubic_correction`), on the sum of the Λs.
        let cubic = CubicLambdaCorrection::fit_to_table(&model.view())
            .map_err(|e| format!("{}: no cubic through the view table: {e}", surface.name))?;
        let identity = LambdaCorrection::IDENTITY;
        let view_sweep = Sweep { angles_deg: &EVERY_DEGREE, view_azimuth: 0.0, light: None, rays, seed: 17 };
        let view = compare_models(&surface.field, &view_sweep, &identity, &model).ok_or_else(degenerate)?;
        let mut lit = Vec::new();
        for (k, &(_, azimuth)) in LIGHT_SWEEPS.iter().enumerate() {
            let sweep = Sweep {
                angles_deg: &LIGHT_ANGLES,
                view_azimuth: 0.0,
                light: Some(light_at_60_deg(azimuth)),
                rays: rays / 2,
                seed: 23 + k as u64,
            };
            lit.push(compare_models(&surface.field, &sweep, &identity, &model).ok_or_else(degenerate)?);
        }
        let (_, mip) = max_errors(&view, 0.0, 85.0);
        let eq17 = |rows: &[AngleComparison]| percent(max_error(rows, 0.0, 85.0, AngleComparison::eq17_error));
        let corrected =
            |rows: &[AngleComparison]| percent(max_error(rows, 0.0, 85.0, AngleComparison::correlated_error));
        println!(
            "{:<22} {:>6.2} {:>7.3} {:>7.3} | {:>9} {:>9} {:>9} {:>9} | {:>9} {:>9} {:>9} {:>9} | {:>9}{}",
            surface.name,
            stats.height_sigma,
            stats.height_skewness,
            stats.height_excess_kurtosis,
            eq17(&view),
            eq17(&lit[0]),
            eq17(&lit[1]),
            eq17(&lit[2]),
            corrected(&view),
            corrected(&lit[0]),
            corrected(&lit[1]),
            corrected(&lit[2]),
            percent(mip),
            if surface.gaussian { "" } else { "  (non-Gaussian)" }
        );
        draw(
            &out.join(format!("fig9_{}_view.png", surface.name)),
            &format!("{}: view only (Fig. 9)", surface.name),
            &view,
        )?;
        for ((sweep, azimuth), rows) in LIGHT_SWEEPS.iter().zip(&lit) {
            let file = sweep.replacen("view_and_light", "light", 1);
            draw(
                &out.join(format!("fig9_{}_{file}.png", surface.name)),
                &format!("{}: view and light (light at 60°, azimuth {azimuth}° from the view)", surface.name),
                rows,
            )?;
        }
        let deviation = cubic.deviation_from(&model.view());
        println!(
            "{:<22} cubic view table: view only {}, {} from the table: {}",
            "",
            percent(max_error(&view, 0.0, 85.0, |row| row.cubic_error(&cubic))),
            percent(f64::from(deviation)),
            if deviation <= CUBIC_DEVIATION_BUDGET { "kept" } else { "the table is kept" }
        );
        csv_rows.extend(view.into_iter().map(|r| (surface.name.clone(), "view", r, cubic)));
        for ((sweep, _), rows) in LIGHT_SWEEPS.iter().zip(lit) {
            csv_rows.extend(rows.into_iter().map(|r| (surface.name.clone(), *sweep, r, cubic)));
        }
    }
    write_csv(&out.join("fig9.csv"), &csv_rows)?;
    println!("\nfitted models: view and light tables c(u), u = Λ/(1+Λ) = 0, 1/7, …, 1; ρ(c) = ρ0 + ρ1 c + ρ2 c²:");
    for (name, realizations, model) in models {
        print_model(&name, realizations, &model);
    }
    if spectra {
        spectral_sweep(size / 2, rays / 3)?;
    }
    println!("\nwrote {}", out.display());
    Ok(())
}
