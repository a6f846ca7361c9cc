//! `cargo xtask select-tables [--only TABLE]` and
//! `cargo xtask select [OUT_DIR] [--only TABLE] [--budget METRIC:MAX]...`: *model no more
//! than a scene needs* (`model_select`), for the DDM tracing methods
//! (`ddm_experiments::selection`, table `ddm`) and the Smith appearance models
//! (`microsurface_truth::selection`, table `smith`) and the grains' impostor atlases
//! (`grain_impostor::selection`, table `grains`: `(n, p)`, sampling mode and layout, the
//! cost the atlas's GPU memory) and the grains' tiers (`grain_renderer::tier_selection`,
//! table `tiers`: a pile all points or all impostors by projected diameter, the cost its
//! frame time; `stackings` reads its point thresholds from it).
//!
//! `select-tables` measures the tables the selector reads — per object (mesostructure,
//! surface) and representation (method, model), at each calibration condition (the
//! view's magnification, its largest view angle): ꟻLIP and 1 − SSIM of its image against
//! the truth's, CPU ns per ray or per pixel — and writes them, stamped with the commit,
//! the processor and the fingerprint of the sources that produce them, to
//! `crates/ddm-experiments/tables/ddm_selection.csv`,
//! `crates/microsurface-truth/tables/smith_selection.csv`,
//! `crates/grain-impostor/tables/grain_selection.csv` and
//! `crates/grain-renderer/tables/tier_selection.csv` (committed; a test fails when those
//! sources change and a table is not measured again).
//!
//! `select` reads the tables (an error when one is stale), and for each budget and
//! object lets the selector choose the cheapest representation within budget at the
//! held-out view's condition, then measures every representation on the held-out view
//! (another camera; for the Smith models also another realization of each Gaussian
//! surface): the choice's measured error there, whether it is within budget, and which
//! representations the table called cheaper met the budget there too. Writes to
//! `OUT_DIR` (default `target/select`) `selection.csv`, per object the truth's image, each
//! chosen representation's image and ꟻLIP map, and `<object>_selection.png`: ꟻLIP against
//! the table's cost of every candidate at the condition chosen at, its Pareto front, the
//! budgets and the choices.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use ddm_experiments::selection::SelectionSettings;
use ddm_experiments::trace_tables::TraceScene;
use grain_renderer::point_threshold::{self, MeasureView, PointMeasurement};
use grain_renderer::tier_selection::{self, TierTableSettings};
use grain_splitter::sweep::Shot;
use image::RgbaImage;
use mesostructure::Mesostructure;
use model_select::{Budget, HeldOutCheck, Measurement, Metric, Stamp, Table, fingerprint, pareto_front};
use plotters::prelude::*;

use crate::chart::{draw_legend, drawing_error, legend_stroke, render_png};
use crate::cli::Args;

/// One selector: its table and how its held-out views are measured.
pub struct Selector {
    /// Its name for `--only`.
    pub name: &'static str,
    /// The table's name.
    table_name: &'static str,
    /// The committed table, relative to the workspace root.
    pub table_file: &'static str,
    /// The sources that produce it.
    sources: &'static [&'static str],
    /// [`Measurement::condition`]'s unit, and a short label of it for charts.
    condition_unit: (&'static str, &'static str),
    /// [`Measurement::cost`]'s unit.
    cost_unit: &'static str,
    /// What a table row holds, for the chart's legend.
    row_note: &'static str,
    /// The three budgets when `--budget` is not given.
    default_budgets: [(Metric, f64); 3],
    /// Measures the table's rows; returns them with the adapter that measured them.
    measure: fn() -> Result<MeasuredTable, String>,
    /// Measures the held-out views.
    held_out: fn() -> Result<Vec<HeldOutView>, String>,
}

/// A table's rows and the adapter that measured them.
type MeasuredTable = (Vec<Measurement>, String);

/// One object seen from the held-out view: the truth's image and every representation's.
pub struct HeldOutView {
    /// The object (as in the table).
    object: String,
    /// The truth's image.
    truth: RgbaImage,
    /// Every representation: its measurement, its image and its file-name part.
    representations: Vec<(Measurement, RgbaImage, String)>,
}

/// The grains' default budgets (mean ꟻLIP of the comparison image).
const GRAIN_BUDGETS: [(Metric, f64); 3] = [(Metric::Flip, 0.2), (Metric::Flip, 0.1), (Metric::Flip, 0.05)];

/// The tiers' default budgets (mean ꟻLIP of the cropped pile against its meshes 4 × 4
/// supersampled), spanning the table: both tiers measure 0.055 to 0.14 between 1 and 4 px.
const TIER_BUDGETS: [(Metric, f64); 3] = [(Metric::Flip, 0.15), (Metric::Flip, 0.1), (Metric::Flip, 0.09)];

/// Every selector, in page order.
pub const SELECTORS: [Selector; 4] = [
    Selector {
        name: "ddm",
        table_name: ddm_experiments::selection::TABLE_NAME,
        table_file: ddm_experiments::selection::TABLE_FILE,
        sources: &ddm_experiments::selection::TABLE_SOURCES,
        condition_unit: (ddm_experiments::selection::CONDITION_UNIT, "px/voxel"),
        cost_unit: ddm_experiments::selection::COST_UNIT,
        row_note: "95 % prediction bound of 4 cameras",
        default_budgets: [(Metric::Flip, 0.35), (Metric::Flip, 0.1), (Metric::Flip, 0.03)],
        measure: ddm_table,
        held_out: ddm_held_out,
    },
    Selector {
        name: "smith",
        table_name: microsurface_truth::selection::TABLE_NAME,
        table_file: microsurface_truth::selection::TABLE_FILE,
        sources: &microsurface_truth::selection::TABLE_SOURCES,
        condition_unit: (microsurface_truth::selection::CONDITION_UNIT, "° largest view angle"),
        cost_unit: microsurface_truth::selection::COST_UNIT,
        row_note: "worst band camera below the angle",
        default_budgets: [(Metric::Flip, 0.2), (Metric::Flip, 0.1), (Metric::Flip, 0.06)],
        measure: smith_table,
        held_out: smith_held_out,
    },
    Selector {
        name: "grains",
        table_name: grain_impostor::selection::TABLE_NAME,
        table_file: grain_impostor::selection::TABLE_FILE,
        sources: &grain_impostor::selection::TABLE_SOURCES,
        condition_unit: (grain_impostor::selection::CONDITION_UNIT, "px wide"),
        cost_unit: grain_impostor::selection::COST_UNIT,
        row_note: "64 view directions, worst size up to it",
        default_budgets: GRAIN_BUDGETS,
        measure: grains_table,
        held_out: grains_held_out,
    },
    Selector {
        name: "tiers",
        table_name: tier_selection::TABLE_NAME,
        table_file: tier_selection::TABLE_FILE,
        sources: &tier_selection::TABLE_SOURCES,
        condition_unit: (tier_selection::CONDITION_UNIT, "px wide"),
        cost_unit: tier_selection::COST_UNIT,
        row_note: "a pile of 2000 from the wide shot, worst size up to it",
        default_budgets: TIER_BUDGETS,
        measure: tiers_table,
        held_out: tiers_held_out,
    },
];

/// The selector `--only NAME` names.
pub fn selector(name: &str) -> Option<&'static Selector> {
    SELECTORS.iter().find(|s| s.name == name)
}

fn ddm_scenes(settings: &SelectionSettings) -> Result<Vec<TraceScene>, String> {
    Mesostructure::ALL.iter().map(|&s| TraceScene::build(s, &settings.tables).map_err(|e| e.to_string())).collect()
}

fn ddm_table() -> Result<MeasuredTable, String> {
    let settings = SelectionSettings::standard();
    let rows = ddm_experiments::selection::table_rows(&ddm_scenes(&settings)?, &settings).map_err(|e| e.to_string())?;
    Ok((rows, processor()))
}

fn ddm_held_out() -> Result<Vec<HeldOutView>, String> {
    use ddm_experiments::selection::{held_out_camera, measure_view};
    let settings = SelectionSettings::standard();
    let mut views = Vec::new();
    for scene in ddm_scenes(&settings)? {
        let camera = held_out_camera(scene.dims);
        // One pass: the held-out check uses the table's costs, not the held-out view's.
        let view = measure_view(&scene, camera, settings.held_out_rows, 1).map_err(|e| e.to_string())?;
        views.push(HeldOutView {
            object: scene.name.to_owned(),
            truth: view.truth,
            representations: view
                .methods
                .into_iter()
                .map(|m| (m.measurement, m.image, crate::ddm_trace::image_name(m.method)))
                .collect(),
        });
    }
    Ok(views)
}

fn smith_table() -> Result<MeasuredTable, String> {
    let rows = microsurface_truth::selection::table_rows(&microsurface_truth::selection::SelectionSettings::standard())
        .map_err(|e| e.to_string())?;
    Ok((rows, processor()))
}

/// The grains of the atlas table: the four procedural ones.
fn selection_grains() -> Result<Vec<(String, grain_mesh::GrainMesh)>, String> {
    crate::impostor_accuracy::grains(false, &[])
}

fn grains_table() -> Result<MeasuredTable, String> {
    let gpu = gpu_harness::Gpu::new().map_err(|e| e.to_string())?;
    let settings = grain_impostor::selection::SelectionSettings::standard();
    let rows = grain_impostor::selection::table_rows(&gpu.device, &gpu.queue, &selection_grains()?, &settings)
        .map_err(|e| e.to_string())?;
    // The cost is memory; the errors are of images rendered on this adapter.
    Ok((rows, format!("atlas memory; images rendered on {}", gpu.describe()).replace(',', ";")))
}

fn grains_held_out() -> Result<Vec<HeldOutView>, String> {
    let gpu = gpu_harness::Gpu::new().map_err(|e| e.to_string())?;
    let settings = grain_impostor::selection::SelectionSettings::standard();
    let views = grain_impostor::selection::held_out_views(&gpu.device, &gpu.queue, &selection_grains()?, &settings)
        .map_err(|e| e.to_string())?;
    Ok(views
        .into_iter()
        .filter_map(|view| {
            let object = view.configurations.first()?.0.object.clone();
            let representations = view
                .configurations
                .into_iter()
                .map(|(m, image)| {
                    let part = file_part(&m.representation);
                    (m, image, part)
                })
                .collect();
            Some(HeldOutView { object, truth: view.truth, representations })
        })
        .collect())
}

/// One grain's pile for the tier table: its atlas (n = 8, p = 64, as `stackings` bakes
/// it), the grains, and the pile's three shots (Fig. 15).
fn tier_pile(
    gpu: &gpu_harness::Gpu,
    mesh: &grain_mesh::GrainMesh,
    settings: &TierTableSettings,
) -> Result<(grain_impostor::atlas::ImpostorAtlas, Vec<grain_impostor::scene::GrainInstance>, [Shot; 3]), String> {
    let (stacking, grains) = crate::stackings::pile_instances(settings.grain_count, mesh)?;
    let region = stacking.bounds();
    let atlas = crate::stackings::bake_atlas(gpu, mesh)?;
    Ok((atlas, grains, Shot::fig15(region.min, region.max)))
}

/// Each procedural grain's pile seen from `shot` (0 the table's, 1 the held-out) at
/// `diameters`.
fn tier_measurements(
    shot: usize,
    diameters: impl Fn(&TierTableSettings) -> Vec<f32>,
) -> Result<(Vec<(String, PointMeasurement)>, String), String> {
    let gpu = gpu_harness::Gpu::new().map_err(|e| e.to_string())?;
    let settings = TierTableSettings::standard();
    settings.validate().map_err(|e| e.to_string())?;
    let mut measured = Vec::new();
    let mut timing = None;
    for (name, mesh) in selection_grains()? {
        let (atlas, grains, shots) = tier_pile(&gpu, &mesh, &settings)?;
        let view = MeasureView {
            target: shots[shot].target,
            direction: shots[shot].eye - shots[shot].target,
            size: settings.size,
            frames: settings.frames,
        };
        let m = point_threshold::measure(&gpu, &mesh, &atlas, &grains, view, &diameters(&settings))
            .map_err(|e| format!("{name}: {e}"))?;
        timing = Some(m.timing);
        measured.push((name, m));
    }
    let clock = match timing {
        Some(gpu_harness::TimingSource::Timestamps) => "GPU timestamps",
        _ => "wall clock",
    };
    Ok((measured, format!("{} ({clock})", gpu.describe()).replace(',', ";")))
}

fn tiers_table() -> Result<MeasuredTable, String> {
    let (measured, adapter) = tier_measurements(0, |s| s.diameters.clone())?;
    let rows = measured.iter().flat_map(|(name, m)| tier_selection::measurements(name, m)).collect();
    Ok((rows, adapter))
}

fn tiers_held_out() -> Result<Vec<HeldOutView>, String> {
    let (measured, _) = tier_measurements(1, |s| vec![s.held_out_diameter])?;
    let mut views = Vec::new();
    for (name, m) in measured {
        let rows = tier_selection::measurements(&name, &m);
        for (row, [points, impostors]) in
            m.rows.into_iter().zip(rows.chunks_exact(2).map(|c| [c[0].clone(), c[1].clone()]))
        {
            views.push(HeldOutView {
                object: name.clone(),
                truth: row.reference,
                representations: vec![
                    (points, row.points.image, "points".into()),
                    (impostors, row.impostors.image, "impostors".into()),
                ],
            });
        }
    }
    Ok(views)
}

fn smith_held_out() -> Result<Vec<HeldOutView>, String> {
    // One timed pass: the held-out check uses the table's costs, not the held-out view's.
    let settings = microsurface_truth::selection::SelectionSettings {
        passes: 1,
        ..microsurface_truth::selection::SelectionSettings::standard()
    };
    let views = microsurface_truth::selection::held_out_rows(&settings).map_err(|e| e.to_string())?;
    Ok(views
        .into_iter()
        .filter_map(|view| {
            let object = view.models.first()?.measurement.object.clone();
            let representations =
                view.models.into_iter().map(|m| (m.measurement, m.image, file_part(m.model.name()))).collect();
            Some(HeldOutView { object, truth: view.truth, representations })
        })
        .collect())
}

/// The selectors `--only` names (all without it), or an error naming the flag.
fn selected(args: &Args<'_>) -> Result<Vec<&'static Selector>, String> {
    match args.value("only") {
        None => Ok(SELECTORS.iter().collect()),
        Some(name) => selector(name).map(|s| vec![s]).ok_or_else(|| {
            let names: Vec<&str> = SELECTORS.iter().map(|s| s.name).collect();
            format!("--only {name}: no such table (the tables: {})", names.join(", "))
        }),
    }
}

/// The processor's name (`/proc/cpuinfo`), the adapter of the tables' CPU costs.
fn processor() -> String {
    let name = std::fs::read_to_string("/proc/cpuinfo").ok().and_then(|text| {
        text.lines().find_map(|l| {
            l.strip_prefix("model name").and_then(|r| r.split_once(':')).map(|(_, n)| n.trim().to_owned())
        })
    });
    format!("CPU {} (one thread)", name.unwrap_or_else(|| std::env::consts::ARCH.to_owned())).replace(',', ";")
}

/// `select-tables`: measures and writes the committed tables.
pub fn tables(args: &Args<'_>) -> Result<(), String> {
    for selector in selected(args)? {
        let started = Instant::now();
        let root = crate::workspace_root();
        let sources = fingerprint(&root, selector.sources).map_err(|e| e.to_string())?;
        let (rows, adapter) = (selector.measure)()?;
        let stamp = Stamp {
            command: format!("cargo xtask select-tables --only {}", selector.name),
            commit: crate::showcase::commit(),
            adapter,
            sources,
        };
        let table = Table::new(selector.table_name, stamp, selector.condition_unit.0, selector.cost_unit, rows)
            .map_err(|e| e.to_string())?;
        let path = root.join(selector.table_file);
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
        }
        std::fs::write(&path, table.to_csv()).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        for object in table.objects() {
            let rows: Vec<_> = table.rows().iter().filter(|r| r.object == object).collect();
            let points: Vec<(f64, f64)> = rows.iter().map(|r| (r.cost, r.flip)).collect();
            let front: Vec<String> = pareto_front(&points)
                .into_iter()
                .map(|i| {
                    format!(
                        "{} @{:.1} (cost {:.2}, ꟻLIP {:.3})",
                        rows[i].representation, rows[i].condition, rows[i].cost, rows[i].flip
                    )
                })
                .collect();
            println!("{object}: front over every condition: {}", front.join("; "));
        }
        println!(
            "wrote {} ({} rows) in {:.0} s",
            selector.table_file,
            table.rows().len(),
            started.elapsed().as_secs_f64()
        );
    }
    Ok(())
}

/// A budget `METRIC:MAX` (`flip:0.05`, `1-ssim:0.02`).
fn budget(text: &str) -> Result<Budget, String> {
    let (metric, max) = text.split_once(':').ok_or_else(|| format!("--budget {text}: expected METRIC:MAX"))?;
    let metric = Metric::from_name(metric).map_err(|e| format!("--budget {text}: {e}"))?;
    let max: f64 = max.parse().map_err(|_| format!("--budget {text}: `{max}` is not a number"))?;
    Budget::new(metric, max).map_err(|e| format!("--budget {text}: {e}"))
}

/// `selector`'s committed table, or an error when it is missing or stale.
pub fn fresh_table(selector: &Selector) -> Result<Table, String> {
    let root = crate::workspace_root();
    let table = Table::read(&root.join(selector.table_file)).map_err(|e| e.to_string())?;
    let sources = fingerprint(&root, selector.sources).map_err(|e| e.to_string())?;
    if !table.is_fresh(&sources) {
        return Err(format!(
            "{} is stale: measured from sources {} (commit {}), they are now {sources}; \
             run `cargo xtask select-tables --only {}`",
            selector.table_file,
            table.stamp().sources,
            table.stamp().commit,
            selector.name
        ));
    }
    Ok(table)
}

/// A file-name part: lowercase letters and digits, `_` for the rest.
fn file_part(text: &str) -> String {
    let mut name = String::new();
    for c in text.chars() {
        if c.is_ascii_alphanumeric() {
            name.push(c.to_ascii_lowercase());
        } else if !name.ends_with('_') {
            name.push('_');
        }
    }
    name.trim_matches('_').to_owned()
}

/// `select`: the choices of three budgets checked on the held-out views.
pub fn run(args: &Args<'_>) -> Result<(), String> {
    let started = Instant::now();
    let out = args.out_dir();
    std::fs::create_dir_all(&out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let given: Vec<Budget> = args.values("budget").iter().map(|t| budget(t)).collect::<Result<_, _>>()?;
    let selectors = selected(args)?;
    let mut csv = String::from(
        "table,metric,budget,object,held_out_condition,chosen_at_condition,choice,table_error,table_cost,\
         held_out_error,within_budget,cheaper_within_budget_on_held_out,candidates,within_budget_in_table,note\n",
    );
    // Choices made, those within budget held out, and budgets the table could not meet.
    let (mut made, mut met, mut unmet) = (0, 0, 0);
    for selector in selectors {
        let budgets: Vec<Budget> = if given.is_empty() {
            selector
                .default_budgets
                .iter()
                .map(|&(m, max)| Budget::new(m, max))
                .collect::<Result<_, _>>()
                .map_err(|e| e.to_string())?
        } else {
            given.clone()
        };
        let table = fresh_table(selector)?;
        println!(
            "select {}: table {} (commit {}, {})",
            selector.name,
            selector.table_file,
            table.stamp().commit,
            table.stamp().adapter
        );
        for view in (selector.held_out)()? {
            let name = file_part(&view.object);
            save(&out.join(format!("{name}_truth.png")), &view.truth)?;
            let measurements: Vec<Measurement> = view.representations.iter().map(|(m, _, _)| m.clone()).collect();
            let condition = measurements.first().map_or(0.0, |m| m.condition);
            let mut choices = Vec::new();
            for &budget in &budgets {
                match table.check_held_out(&measurements, budget) {
                    Ok(choice) => {
                        made += 1;
                        met += usize::from(choice.within_budget);
                        write_choice(&mut csv, selector, &choice, condition);
                        write_images(&out, &name, &view, &choice)?;
                        choices.push(choice);
                    }
                    Err(e) => {
                        unmet += 1;
                        println!("  {}: {budget}: {e}", view.object);
                        let _ = writeln!(
                            csv,
                            "{},{},{},{},{condition:.3},,,,,,false,,,0,\"{}\"",
                            selector.name,
                            budget.metric().name(),
                            budget.max(),
                            view.object,
                            e.to_string().replace('"', "'")
                        );
                    }
                }
            }
            chart(&out.join(format!("{name}_selection.png")), selector, &table, &view, &choices, &budgets)?;
        }
    }
    let path = out.join("selection.csv");
    std::fs::write(&path, csv).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    println!(
        "{met} of {made} choices within budget on the held-out views ({unmet} budgets met by no measured \
         representation); wrote {} in {:.0} s",
        path.display(),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

fn save(path: &Path, image: &RgbaImage) -> Result<(), String> {
    image::DynamicImage::ImageRgba8(image.clone())
        .to_rgb8()
        .save(path)
        .map_err(|e| format!("cannot write {}: {e}", path.display()))
}

fn write_choice(csv: &mut String, selector: &Selector, c: &HeldOutCheck, condition: f64) {
    let metric = c.budget.metric();
    println!(
        "  {:<22} {}: {} (table {:.4} at {:.2} {}, cost {:.1}) → held-out {:.4} {}{}",
        c.object,
        c.budget,
        c.chosen.representation,
        c.chosen.error(metric),
        c.chosen.condition,
        selector.condition_unit.1,
        c.chosen.cost,
        c.measured.error(metric),
        if c.within_budget { "within budget" } else { "OVER BUDGET" },
        if c.cheaper_within_budget.is_empty() {
            String::new()
        } else {
            format!("; cheaper and within budget there: {}", c.cheaper_within_budget.join(", "))
        }
    );
    let _ = writeln!(
        csv,
        "{},{},{},{},{condition:.3},{:.3},{},{:.5},{:.2},{:.5},{},{},{},{},",
        selector.name,
        metric.name(),
        c.budget.max(),
        c.object,
        c.chosen.condition,
        c.chosen.representation,
        c.chosen.error(metric),
        c.chosen.cost,
        c.measured.error(metric),
        c.within_budget,
        c.cheaper_within_budget.join(" / "),
        c.candidates.0,
        c.candidates.1
    );
}

/// The chosen representation's held-out image and its ꟻLIP map.
fn write_images(out: &Path, name: &str, view: &HeldOutView, choice: &HeldOutCheck) -> Result<(), String> {
    let Some((_, image, part)) =
        view.representations.iter().find(|(m, _, _)| m.representation == choice.chosen.representation)
    else {
        return Err(format!("{name}: {} has no image", choice.chosen.representation));
    };
    let stem = format!("{name}_{part}");
    save(&out.join(format!("{stem}.png")), image)?;
    let flip = image_metrics::flip(&view.truth, image).map_err(|e| format!("{stem}: {e}"))?;
    image_metrics::flip_magma(&flip.map)
        .save(out.join(format!("{stem}_flip.png")))
        .map_err(|e| format!("cannot write {stem}_flip.png: {e}"))
}

const TABLE_GREY: RGBColor = RGBColor(120, 120, 120);
const HELD_OUT_BLUE: RGBColor = RGBColor(0, 114, 178);
const BUDGET_COLOURS: [RGBColor; 3] = [RGBColor(0, 158, 115), RGBColor(230, 159, 0), RGBColor(213, 94, 0)];

/// ꟻLIP against the table's cost of every candidate at the magnification the choices
/// were made at, with the front, the held-out errors, the budgets and the choices.
fn chart(
    path: &Path,
    selector: &Selector,
    table: &Table,
    view: &HeldOutView,
    choices: &[HeldOutCheck],
    budgets: &[Budget],
) -> Result<(), String> {
    let object = view.object.as_str();
    let condition = choices.first().map_or_else(
        || table.rows().iter().filter(|r| r.object == object).map(|r| r.condition).fold(0.0, f64::max),
        |c| c.chosen.condition,
    );
    let rows: Vec<_> = table.rows().iter().filter(|r| r.object == object && r.condition == condition).collect();
    let cost_of = |name: &str| rows.iter().find(|r| r.representation == name).map(|r| r.cost);
    let table_points: Vec<(f64, f64)> = rows.iter().map(|r| (r.cost, r.flip)).collect();
    let held: Vec<(f64, f64, &str)> = view
        .representations
        .iter()
        .filter_map(|(m, _, _)| cost_of(&m.representation).map(|c| (c, m.flip, m.representation.as_str())))
        .collect();
    let (mut x_lo, mut x_hi, mut y_hi) = (f64::INFINITY, 0.0_f64, 0.0_f64);
    for (x, y) in table_points.iter().copied().chain(held.iter().map(|&(x, y, _)| (x, y))) {
        (x_lo, x_hi, y_hi) = (x_lo.min(x), x_hi.max(x), y_hi.max(y));
    }
    for b in budgets.iter().filter(|b| b.metric() == Metric::Flip) {
        y_hi = y_hi.max(b.max());
    }
    if !x_lo.is_finite() || x_lo <= 0.0 {
        return Err(format!("{object}: no positive costs to chart"));
    }
    let adapter = table.stamp().adapter.clone();
    render_png(path, (960, 600), |root| {
        let e = drawing_error;
        let caption = format!(
            "{object}: FLIP against cost, table at {condition:.1} {}, held-out view",
            selector.condition_unit.1
        );
        let mut chart = ChartBuilder::on(root)
            .caption(caption, ("sans-serif", 20))
            .margin(12)
            .x_label_area_size(44)
            .y_label_area_size(60)
            .build_cartesian_2d((x_lo / 1.3..x_hi * 1.3).log_scale(), 0.0..y_hi * 1.1)
            .map_err(e)?;
        chart
            .configure_mesh()
            .x_desc(format!("cost: {}, {adapter}", selector.cost_unit))
            .y_desc("mean FLIP against the truth's image")
            .x_labels(8)
            .label_style(("sans-serif", 14))
            .draw()
            .map_err(e)?;
        chart
            .draw_series(table_points.iter().map(|&p| Circle::new(p, 4, TABLE_GREY.filled())))
            .map_err(e)?
            .label(format!("each representation in the table ({})", selector.row_note))
            .legend(|(x, y)| Circle::new((x + 12, y), 4, TABLE_GREY.filled()));
        let front: Vec<(f64, f64)> = pareto_front(&table_points).into_iter().map(|i| table_points[i]).collect();
        chart
            .draw_series(LineSeries::new(front, BLACK.stroke_width(2)))
            .map_err(e)?
            .label("the table's Pareto front")
            .legend(legend_stroke(BLACK, 2, 24));
        chart
            .draw_series(held.iter().map(|&(x, y, _)| Cross::new((x, y), 5, HELD_OUT_BLUE.stroke_width(2))))
            .map_err(e)?
            .label("each representation on the held-out view (same cost)")
            .legend(|(x, y)| Cross::new((x + 12, y), 5, HELD_OUT_BLUE.stroke_width(2)));
        // Names where they stay legible (the grain atlases are 32 points: the legend names
        // the choices).
        let labelled = if held.len() <= 16 { &held[..] } else { &[] };
        chart
            .draw_series(labelled.iter().map(|&(x, y, name)| {
                Text::new(name.to_owned(), (x * 1.04, y), ("sans-serif", 11).into_font().color(&TABLE_GREY))
            }))
            .map_err(e)?;
        for (k, b) in budgets.iter().enumerate().filter(|(_, b)| b.metric() == Metric::Flip) {
            let colour = BUDGET_COLOURS[k % BUDGET_COLOURS.len()];
            // The bundled font has no ꟻ.
            let budget = b.to_string().replace('ꟻ', "F");
            let label = match choices.iter().find(|c| c.budget == *b) {
                Some(c) => format!("{budget}: {} ({:.3} held out)", c.chosen.representation, c.measured.flip),
                None => format!("{budget}: nothing within budget"),
            };
            chart
                .draw_series(LineSeries::new([(x_lo / 1.3, b.max()), (x_hi * 1.3, b.max())], colour.stroke_width(1)))
                .map_err(e)?
                .label(label)
                .legend(legend_stroke(colour, 3, 24));
            if let Some(c) = choices.iter().find(|c| c.budget == *b) {
                chart
                    .draw_series([Circle::new((c.chosen.cost, c.measured.flip), 9, colour.stroke_width(3))])
                    .map_err(e)?;
            }
        }
        draw_legend(&mut chart, 14, SeriesLabelPosition::UpperRight)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn budgets_parse_and_bad_ones_name_the_flag() {
        assert_eq!(budget("flip:0.05").unwrap(), Budget::new(Metric::Flip, 0.05).unwrap());
        assert_eq!(budget("1-ssim:0.2").unwrap(), Budget::new(Metric::SsimLoss, 0.2).unwrap());
        for (text, expected) in [
            ("flip", "expected METRIC:MAX"),
            ("psnr:3", "unknown metric `psnr`"),
            ("flip:x", "`x` is not a number"),
            ("flip:-1", "is not a positive number"),
        ] {
            let error = budget(text).unwrap_err();
            assert!(error.starts_with(&format!("--budget {text}: ")) && error.contains(expected), "{error}");
        }
    }

    #[test]
    fn file_parts_are_plain() {
        assert_eq!(file_part("chain mail"), "chain_mail");
        assert_eq!(file_part("DDM 4x1 + adaptive"), "ddm_4x1_adaptive");
    }

    #[test]
    fn the_committed_tables_are_fresh_and_complete() {
        // Fails when a source that produces a table changed since it was measured: run
        // `cargo xtask select-tables --only NAME` and commit the table.
        let [ddm, smith, grains, tiers] = &SELECTORS;
        let table = fresh_table(ddm).unwrap_or_else(|e| panic!("{e}"));
        let settings = SelectionSettings::standard();
        let objects: Vec<&str> = Mesostructure::ALL.iter().map(|m| m.name()).collect();
        assert_eq!(table.objects(), objects);
        // Every method at every calibration magnification: relief too on the height fields.
        let methods = ddm_experiments::TraceMethod::ALL.len();
        let expected: usize = Mesostructure::ALL
            .iter()
            .map(|m| if matches!(m, Mesostructure::Maze(_) | Mesostructure::Bricks) { methods } else { methods - 1 })
            .sum::<usize>()
            * settings.calibration_rows.len();
        assert_eq!(table.rows().len(), expected);

        let table = fresh_table(smith).unwrap_or_else(|e| panic!("{e}"));
        let settings = microsurface_truth::selection::SelectionSettings::standard();
        let surfaces = microsurface_truth::realizations(64, 0).unwrap();
        let objects: Vec<&str> = surfaces.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(table.objects(), objects);
        let models = microsurface_truth::selection::SmithModel::ALL.len();
        assert_eq!(table.rows().len(), objects.len() * models * settings.band_tops_deg.len());

        let table = fresh_table(grains).unwrap_or_else(|e| panic!("{e}"));
        let settings = grain_impostor::selection::SelectionSettings::standard();
        assert_eq!(table.objects(), ["ball", "bean", "rock", "nut"]);
        let configurations =
            settings.subdivisions.len() * settings.texels.len() * settings.modes.len() * settings.layouts.len();
        assert_eq!(table.rows().len(), 4 * configurations * settings.diameters.len());

        let table = fresh_table(tiers).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(table.objects(), ["ball", "bean", "rock", "nut"]);
        // Two tiers at every calibration diameter.
        assert_eq!(table.rows().len(), 4 * 2 * TierTableSettings::standard().diameters.len());
    }

    #[test]
    fn only_names_a_table() {
        let command = crate::command("select").unwrap();
        let words = |w: &[&str]| w.iter().map(|s| s.to_string()).collect::<Vec<_>>();
        let crate::cli::Parsed::Run(args) = command.parse(&words(&["--only", "smith"])).unwrap() else { panic!() };
        assert_eq!(selected(&args).unwrap().iter().map(|s| s.name).collect::<Vec<_>>(), ["smith"]);
        let crate::cli::Parsed::Run(args) = command.parse(&words(&["--only", "grain"])).unwrap() else { panic!() };
        let error = selected(&args).err().unwrap();
        assert_eq!(error, "--only grain: no such table (the tables: ddm, smith, grains, tiers)");
        let crate::cli::Parsed::Run(args) = command.parse(&[]).unwrap() else { panic!() };
        assert_eq!(selected(&args).unwrap().len(), 4);
    }
}
