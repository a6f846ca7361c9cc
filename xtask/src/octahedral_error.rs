//! `cargo xtask octahedral-error [OUT_DIR]`: the angular error of the octahedral view layout
//! against `n`, with the eq. 4 validity angles (PNG + CSV).

use std::path::Path;

use octahedral_map::validity::angle_between;
use octahedral_map::{OctahedralViews, max_neighbour_angle, min_subdivisions_for_texels, validity_half_angle};
use plotters::prelude::*;

use crate::chart::{draw_legend, drawing_error, legend_stroke, render_png};

use glam::DVec3;

/// Directions sampled per `n` (a spherical Fibonacci lattice): 16 per view, within these
/// bounds.
const SAMPLES: (usize, usize) = (200_000, 4_000_000);
/// Worst samples refined by local search into the true local maxima of the error.
const REFINED: usize = 24;
const SUBDIVISIONS: [u32; 18] = [2, 3, 4, 6, 8, 10, 12, 16, 24, 32, 48, 64, 96, 128, 192, 256, 384, 512];
const TEXELS: [u32; 3] = [64, 128, 256];

/// Angular error statistics of one layout, in radians.
struct ErrorStats {
    n: u32,
    mean: f64,
    max: f64,
    neighbour: f64,
}

fn fibonacci_direction(i: usize, count: usize) -> DVec3 {
    let golden = (1.0 + 5.0_f64.sqrt()) / 2.0;
    let z = 1.0 - (2.0 * i as f64 + 1.0) / count as f64;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = std::f64::consts::TAU * (i as f64 / golden).fract();
    DVec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Angle between `d` and its nearest view.
fn error_at(views: OctahedralViews, d: DVec3) -> f64 {
    let nearest = views.nearest_view(d.as_vec3());
    views.view_direction_f64(nearest).map_or(std::f64::consts::PI, |v| angle_between(v, d.normalize()))
}

/// Pattern search for a local maximum of the angular error around `start`.
fn refine_max(views: OctahedralViews, start: DVec3, step: f64) -> f64 {
    let (mut d, mut best, mut step) = (start, error_at(views, start), step);
    while step > 1e-10 {
        let (t, b) = d.any_orthonormal_pair();
        let candidates = [t, -t, b, -b, t + b, t - b, -t + b, -t - b].map(|dir| (d + dir * step).normalize());
        match candidates.into_iter().map(|c| (error_at(views, c), c)).max_by(|a, b| a.0.total_cmp(&b.0)) {
            Some((e, c)) if e > best => (best, d) = (e, c),
            _ => step *= 0.5,
        }
    }
    best
}

fn measure(n: u32) -> ErrorStats {
    let views = OctahedralViews::new(n).expect("n is in range");
    let samples = (16 * views.view_count() as usize).clamp(SAMPLES.0, SAMPLES.1);
    let mut errors: Vec<(f64, DVec3)> =
        (0..samples).map(|i| fibonacci_direction(i, samples)).map(|d| (error_at(views, d), d)).collect();
    let mean = errors.iter().map(|e| e.0).sum::<f64>() / samples as f64;
    errors.sort_by(|a, b| b.0.total_cmp(&a.0));
    let spacing = (4.0 * std::f64::consts::PI / samples as f64).sqrt();
    let max = errors[..REFINED].iter().map(|&(_, d)| refine_max(views, d, spacing)).fold(errors[0].0, f64::max);
    ErrorStats { n, mean, max, neighbour: max_neighbour_angle(n).unwrap_or(f64::NAN) }
}

fn write_csv(path: &Path, stats: &[ErrorStats]) -> Result<(), String> {
    let mut csv = String::from("n,views,mean_error_deg,max_error_deg,max_neighbour_angle_deg\n");
    for s in stats {
        csv += &format!(
            "{},{},{:.6},{:.6},{:.6}\n",
            s.n,
            2 * s.n * s.n,
            s.mean.to_degrees(),
            s.max.to_degrees(),
            s.neighbour.to_degrees()
        );
    }
    std::fs::write(path, csv).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

fn draw_chart(path: &Path, stats: &[ErrorStats]) -> Result<(), String> {
    const SIZE: (u32, u32) = (1200, 800);
    render_png(path, SIZE, |root| {
        let e = drawing_error;
        let (n_min, n_max) = (f64::from(SUBDIVISIONS[0]), f64::from(SUBDIVISIONS[SUBDIVISIONS.len() - 1]));
        let mut chart = ChartBuilder::on(root)
            .caption("Octahedral views: angle to the nearest view vs n (N = 2n² views)", ("sans-serif", 28))
            .margin(20)
            .x_label_area_size(50)
            .y_label_area_size(70)
            .build_cartesian_2d((n_min..n_max).log_scale(), (0.05_f64..100.0).log_scale())
            .map_err(e)?;
        chart
            .configure_mesh()
            .x_desc("n (views per edge of a hemisphere's square, log scale)")
            .y_desc("angle (degrees, log scale)")
            .label_style(("sans-serif", 18))
            .draw()
            .map_err(e)?;
        let series = [
            (
                "max angle to nearest view",
                RED,
                stats.iter().map(|s| (f64::from(s.n), s.max.to_degrees())).collect::<Vec<_>>(),
            ),
            ("mean angle to nearest view", BLUE, stats.iter().map(|s| (f64::from(s.n), s.mean.to_degrees())).collect()),
            (
                "max neighbour spacing / 2",
                MAGENTA,
                stats.iter().map(|s| (f64::from(s.n), s.neighbour.to_degrees() / 2.0)).collect(),
            ),
        ];
        for (label, color, points) in series {
            chart
                .draw_series(LineSeries::new(points.clone(), color.stroke_width(3)))
                .map_err(e)?
                .label(label)
                .legend(legend_stroke(color, 3, 24));
            chart.draw_series(points.iter().map(|&p| Circle::new(p, 3, color.filled()))).map_err(e)?;
        }
        let greys = [RGBColor(40, 40, 40), RGBColor(100, 100, 100), RGBColor(160, 160, 160)];
        for (p, color) in TEXELS.into_iter().zip(greys) {
            let theta = validity_half_angle(p).unwrap_or(0.0).to_degrees();
            chart
                .draw_series(LineSeries::new([(n_min, theta), (n_max, theta)], color.stroke_width(2)))
                .map_err(e)?
                .label(format!("eq. 4 validity half-angle, p = {p} texels ({theta:.3}°)"))
                .legend(legend_stroke(color, 2, 24));
        }
        draw_legend(&mut chart, 18, SeriesLabelPosition::UpperRight)?;
        Ok(())
    })
}

/// Writes `octahedral_angular_error.png` and `.csv` into `out`.
pub fn run(out: &Path) -> Result<(), String> {
    std::fs::create_dir_all(out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    println!("Octahedral view layout: angle between a direction and its nearest view");
    println!(
        "(16 Fibonacci directions per view, {} to {}; max refined by local search from the {REFINED} worst: a lower bound)",
        SAMPLES.0, SAMPLES.1
    );
    println!("{:>4} {:>6} {:>10} {:>10} {:>14}", "n", "views", "mean (°)", "max (°)", "neighbour (°)");
    let stats: Vec<ErrorStats> = SUBDIVISIONS.into_iter().map(measure).collect();
    for s in &stats {
        println!(
            "{:>4} {:>6} {:>10.4} {:>10.4} {:>14.4}",
            s.n,
            2 * s.n * s.n,
            s.mean.to_degrees(),
            s.max.to_degrees(),
            s.neighbour.to_degrees()
        );
    }
    println!("\nValidity (eq. 4) and the n it asks for:");
    let n_max = SUBDIVISIONS[SUBDIVISIONS.len() - 1];
    for p in TEXELS {
        let theta = validity_half_angle(p).unwrap_or(0.0);
        let paper = min_subdivisions_for_texels(p, 4096).map_or("none ≤ 4096".into(), |n| n.to_string());
        let covering = stats
            .iter()
            .find(|s| s.max <= theta)
            .map_or(format!("> {n_max}"), |s| format!("about {} (first charted n)", s.n));
        println!(
            "  p = {p:>3}: half-angle {:.4}°; neighbour spacing ≤ 2θ (paper, §6) needs n = {paper}; \
             every direction within θ of a view needs n = {covering}",
            theta.to_degrees()
        );
    }
    let csv = out.join("octahedral_angular_error.csv");
    let png = out.join("octahedral_angular_error.png");
    write_csv(&csv, &stats)?;
    draw_chart(&png, &stats)?;
    println!("\nwrote {}\nwrote {}", png.display(), csv.display());
    Ok(())
}
