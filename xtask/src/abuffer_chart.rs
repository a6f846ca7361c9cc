//! `cargo xtask abuffer-chart [OUT_DIR]`: coverage error of the (θ, v) mask tables against
//! the number of samples N (Heitz & Neyret 2012, §5.4), as PNG + CSV.

use std::path::Path;

use abuffer_mask::{CoverageErrorStats, MaskTable, coverage_error};
use plotters::prelude::*;

use crate::chart::{draw_legend, drawing_error, legend_stroke, render_png};

/// A chart series: its label, colour and points.
type Series = (&'static str, RGBColor, Vec<(f64, f64)>);

/// Grid points per table cell (per axis) for the "anywhere" statistics.
const OVERSAMPLING: u32 = 2;

fn measure<const WORDS: usize>() -> Result<(CoverageErrorStats, f32), String> {
    let table = MaskTable::<WORDS>::paper().ok_or("unsupported mask size")?;
    Ok((coverage_error(&table, OVERSAMPLING), table.samples().min_distance()))
}

fn write_csv(path: &Path, stats: &[(CoverageErrorStats, f32)]) -> Result<(), String> {
    let mut csv = String::from(
        "samples,min_distance,max_error_at_centres,mean_error_at_centres,max_error_anywhere,mean_error_anywhere\n",
    );
    for (s, d) in stats {
        csv += &format!(
            "{},{d:.6},{:.6},{:.6},{:.6},{:.6}\n",
            s.samples, s.max_at_centres, s.mean_at_centres, s.max_anywhere, s.mean_anywhere
        );
    }
    std::fs::write(path, csv).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

fn draw_chart(path: &Path, stats: &[(CoverageErrorStats, f32)]) -> Result<(), String> {
    const SIZE: (u32, u32) = (1200, 800);
    render_png(path, SIZE, |root| {
        let e = drawing_error;
        let mut chart = ChartBuilder::on(root)
            .caption("A-buffer masks: |mask coverage − exact area| vs N (256 × 256 (θ, v) table)", ("sans-serif", 28))
            .margin(20)
            .x_label_area_size(50)
            .y_label_area_size(70)
            .build_cartesian_2d(
                (24.0_f64..160.0).log_scale().with_key_points(vec![32.0, 64.0, 128.0]),
                (0.001_f64..0.2).log_scale(),
            )
            .map_err(e)?;
        chart
            .configure_mesh()
            .x_label_formatter(&|n| format!("{n:.0}"))
            .x_desc("N (Poisson-disk samples per mask, log scale)")
            .y_desc("coverage error (fraction of the pixel, log scale)")
            .label_style(("sans-serif", 18))
            .draw()
            .map_err(e)?;
        let n = |s: &CoverageErrorStats| s.samples as f64;
        let series: [Series; 4] = [
            ("max, cell centres", RED, stats.iter().map(|(s, _)| (n(s), s.max_at_centres)).collect()),
            ("max, anywhere (with quantization)", MAGENTA, stats.iter().map(|(s, _)| (n(s), s.max_anywhere)).collect()),
            ("mean, cell centres", BLUE, stats.iter().map(|(s, _)| (n(s), s.mean_at_centres)).collect()),
            ("mean, anywhere (with quantization)", CYAN, stats.iter().map(|(s, _)| (n(s), s.mean_anywhere)).collect()),
        ];
        for (label, color, points) in series {
            chart
                .draw_series(LineSeries::new(points.clone(), color.stroke_width(3)))
                .map_err(e)?
                .label(label)
                .legend(legend_stroke(color, 3, 24));
            chart.draw_series(points.iter().map(|&p| Circle::new(p, 4, color.filled()))).map_err(e)?;
        }
        draw_legend(&mut chart, 18, SeriesLabelPosition::UpperRight)?;
        Ok(())
    })
}

/// Writes `abuffer_coverage_error.png` and `.csv` into `out`.
pub fn run(out: &Path) -> Result<(), String> {
    std::fs::create_dir_all(out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let stats = [measure::<1>()?, measure::<2>()?, measure::<4>()?];
    println!(
        "{:>4} {:>8} {:>12} {:>12} {:>12} {:>12}",
        "N", "min dist", "max centre", "mean centre", "max any", "mean any"
    );
    for (s, d) in &stats {
        println!(
            "{:>4} {d:>8.4} {:>12.5} {:>12.5} {:>12.5} {:>12.5}",
            s.samples, s.max_at_centres, s.mean_at_centres, s.max_anywhere, s.mean_anywhere
        );
    }
    let csv = out.join("abuffer_coverage_error.csv");
    let png = out.join("abuffer_coverage_error.png");
    write_csv(&csv, &stats)?;
    draw_chart(&png, &stats)?;
    println!("\nwrote {}\nwrote {}", png.display(), csv.display());
    Ok(())
}
