//! `cargo xtask culling-chart [DIR] [--grains N] [--quick]`: the paper's Fig. 15 on a pile of
//! balls from `grain-scenes` — the proportion of grains still rendered after occlusion
//! culling against the ratio `r/R` assumed (1 → 0), for three shots (wide, narrow field of
//! view, foreground), with occluder fusion and two-phase culling beside the paper's cone —
//! and §8's splat factor against the same measure. Computed by the
//! splitter's CPU reference (`grain_splitter::sweep`); writes CSV and PNG charts into `DIR`.

use std::path::Path;
use std::time::Instant;

use grain_scenes::{GrainRadii, Region, Stacking, StackingSpec};
use grain_splitter::sweep::{CullingPoint, Shot, ratio_sweep, splat_sweep};
use grain_splitter::{DEFAULT_SPLAT_FACTOR, SplitSettings, TierThresholds};
use plotters::prelude::*;

use crate::chart::{draw_legend, drawing_error, legend_stroke, render_png};
use crate::cli::{Args, positive};

/// Grains of the default pile (quick: 20 000).
const DEFAULT_GRAINS: usize = 200_000;
const SPLAT_FACTORS: [f32; 8] = [0.05, 0.1, 0.15, 0.2, 0.3, 0.5, 0.75, 1.0];
const COLOURS: [RGBColor; 3] = [RGBColor(200, 30, 30), RGBColor(30, 150, 30), RGBColor(30, 60, 200)];

/// The pile: balls (`r = R = 1`, so every ratio's culling is conservative), outer balls
/// disjoint (spacing 1.02 with a 1 % jitter), ±10 % scale, seed 15.
pub fn pile(grains: usize) -> Result<Stacking, String> {
    let radii = GrainRadii::new(1.0, 1.0).map_err(|e| e.to_string())?;
    let mut spec = StackingSpec::new(grains, radii);
    spec.seed = 15;
    spec.region = Region::Pile { slope: 0.6 };
    spec.scale_jitter = 0.1;
    spec.jitter = 0.01;
    spec.spacing = 1.03;
    Stacking::generate(&spec).map_err(|e| e.to_string())
}

fn write_csv(path: &Path, rows: &[(&str, f32, CullingPoint)]) -> Result<(), String> {
    let mut csv = String::from(
        "shot,fov_y_degrees,ratio,splat_factor,grains,in_frustum,cone_culled,rendered_fraction,map_filled_fraction,\
         fusion_extra,rendered_fraction_with_fusion,fusion_rays_checked,fusion_violations,\
         two_phase_extra,rendered_fraction_two_phase,two_phase_rays_checked,two_phase_violations\n",
    );
    for (shot, fov, p) in rows {
        csv += &format!(
            "{shot},{:.1},{:.3},{:.3},{},{},{},{:.6},{:.6},{},{:.6},{},{},{},{:.6},{},{}\n",
            fov.to_degrees(),
            p.ratio,
            p.splat_factor,
            p.grains,
            p.in_frustum,
            p.cone_culled,
            p.rendered_fraction(),
            f64::from(p.map_filled) / f64::from(p.map_pixels),
            p.fusion_extra,
            p.rendered_fraction_with_fusion(),
            p.fusion_rays,
            p.fusion_violations,
            p.two_phase_extra,
            p.rendered_fraction_two_phase(),
            p.two_phase_rays,
            p.two_phase_violations
        );
    }
    std::fs::write(path, csv).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// Label, colour, line width, points.
type Series = (String, RGBColor, u32, Vec<(f64, f64)>);

fn draw(path: &Path, caption: &str, x_desc: &str, x_range: (f64, f64), series: &[Series]) -> Result<(), String> {
    render_png(path, (1200, 800), |root| {
        let e = drawing_error;
        let (lo, hi) = x_range;
        let mut chart = ChartBuilder::on(root)
            .caption(caption, ("sans-serif", 26))
            .margin(20)
            .x_label_area_size(50)
            .y_label_area_size(70)
            .build_cartesian_2d(lo..hi, 0.0_f64..1.0)
            .map_err(e)?;
        chart
            .configure_mesh()
            .x_desc(x_desc)
            .y_desc("grains still rendered / grains in the frustum")
            .label_style(("sans-serif", 18))
            .draw()
            .map_err(e)?;
        for (label, colour, width, points) in series {
            let width = *width;
            chart
                .draw_series(LineSeries::new(points.clone(), colour.stroke_width(width)))
                .map_err(e)?
                .label(label.as_str())
                .legend(legend_stroke(*colour, width, 24));
            chart.draw_series(points.iter().map(|&p| Circle::new(p, 4, colour.filled()))).map_err(e)?;
        }
        draw_legend(&mut chart, 18, SeriesLabelPosition::LowerLeft)?;
        Ok(())
    })
}

pub fn run(args: &Args<'_>) -> Result<(), String> {
    let quick = args.flag("quick");
    let grains = args.parse_value("grains", positive::<usize>)?.unwrap_or(if quick { 20_000 } else { DEFAULT_GRAINS });
    let size = if quick { (480, 270) } else { (960, 540) };
    let out = args.out_dir();
    std::fs::create_dir_all(&out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let started = Instant::now();
    let stacking = pile(grains)?;
    let bounds = stacking.bounds();
    let centres = stacking.centre_scale();
    println!("culling-chart: a pile of {grains} balls, {}×{} pixels", size.0, size.1);
    // Tiers do not matter here: every grain is an impostor.
    let base = SplitSettings::new(1.0, 1.0, TierThresholds::new(1e-3, 1e6, 1.0).map_err(|e| e.to_string())?);
    let ratios: Vec<f32> = (0..=20).map(|i| 1.0 - i as f32 * 0.05).collect();
    let (mut ratio_rows, mut splat_rows) = (Vec::new(), Vec::new());
    let (mut ratio_series, mut splat_series) = (Vec::new(), Vec::new());
    for (shot, colour) in Shot::fig15(bounds.min, bounds.max).into_iter().zip(COLOURS) {
        let camera = shot.camera(size).map_err(|e| e.to_string())?;
        let points = ratio_sweep(&camera, &base, centres, &ratios).map_err(|e| e.to_string())?;
        let splats = splat_sweep(&camera, &base, centres, &SPLAT_FACTORS).map_err(|e| e.to_string())?;
        let label = format!("{} ({:.0}° field of view)", shot.name, shot.fov_y.to_degrees());
        println!("  {label}: {} of {grains} grains in the frustum", points[0].in_frustum);
        for p in &points {
            println!(
                "    r/R = {:.2}: {:.1} % rendered with the cone, {:.1} % with fusion too, {:.1} % two-phase ({} + {} rays checked, {} reach a culled grain)",
                p.ratio,
                100.0 * p.rendered_fraction(),
                100.0 * p.rendered_fraction_with_fusion(),
                100.0 * p.rendered_fraction_two_phase(),
                p.fusion_rays,
                p.two_phase_rays,
                p.fusion_violations + p.two_phase_violations
            );
        }
        let violations: u64 = points.iter().chain(&splats).map(|p| p.fusion_violations + p.two_phase_violations).sum();
        if violations > 0 {
            return Err(format!(
                "{}: {violations} rays reach a grain that fusion or two-phase culling culled: not conservative",
                shot.name
            ));
        }
        let curve = |points: &[CullingPoint], x: fn(&CullingPoint) -> f32, y: fn(&CullingPoint) -> f64| {
            points.iter().map(|p| (f64::from(x(p)), y(p))).collect::<Vec<_>>()
        };
        let ratio: fn(&CullingPoint) -> f32 = |p| p.ratio;
        let splat: fn(&CullingPoint) -> f32 = |p| p.splat_factor;
        let (cone, fused) = (CullingPoint::rendered_fraction, CullingPoint::rendered_fraction_with_fusion);
        let two_phase = CullingPoint::rendered_fraction_two_phase;
        for (series, points, x) in [(&mut ratio_series, &points, ratio), (&mut splat_series, &splats, splat)] {
            series.push((label.clone(), colour, 3, curve(points, x, cone)));
            series.push((format!("{label}, + occluder fusion"), colour, 1, curve(points, x, fused)));
            series.push((
                format!("{label}, + two-phase (last frame's visible grains)"),
                colour,
                2,
                curve(points, x, two_phase),
            ));
        }
        ratio_rows.extend(points.into_iter().map(|p| (shot.name, shot.fov_y, p)));
        splat_rows.extend(splats.into_iter().map(|p| (shot.name, shot.fov_y, p)));
    }
    write_csv(&out.join("culling_fig15.csv"), &ratio_rows)?;
    write_csv(&out.join("culling_splat.csv"), &splat_rows)?;
    draw(
        &out.join("culling_fig15.png"),
        &format!("Fig. 15: occlusion culling against r/R ({grains} balls, splat factor {DEFAULT_SPLAT_FACTOR})"),
        "r/R assumed for culling",
        (1.0, 0.0),
        &ratio_series,
    )?;
    draw(
        &out.join("culling_splat.png"),
        &format!("§8: occlusion culling against the occluder-map splat factor ({grains} balls, r/R = 1)"),
        "splat half-side / projected inner radius",
        (0.0, 1.0),
        &splat_series,
    )?;
    println!(
        "wrote culling_fig15.{{csv,png}} and culling_splat.{{csv,png}} into {} in {:.1} s",
        out.display(),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}
