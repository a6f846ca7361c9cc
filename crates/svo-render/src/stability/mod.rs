//! Stability where the paper's hypotheses fail: *sweeps* that relax one hypothesis of
//! Heitz & Neyret §5.1 step by step and measure every model of the tracer against the
//! supersampled truth of the unfiltered surface (eq. 2, [`crate::truth`]).
//!
//! # The sweeps ([`Sweep`]; scenes and views in [`cases`])
//!
//! - [`Sweep::ThinPlate`] (H7, "no thin parts"): a disk-shaped `svo_scenes::Plate` whose
//!   thickness goes from several finest voxels to well below one, seen face-on and
//!   edge-on. Below a voxel the filtered distance `h̄` (a box mean of the distance at coarse
//!   levels, the vertex value at the finest) no longer changes sign across the plate.
//! - [`Sweep::Curvature`] (H6, "the macro-surface is locally planar"): spheres whose
//!   radius goes from many voxels down to one, and cubes of the same half-side seen at a
//!   corner and at an edge (a quarter-plane, not the half-plane of §5.4's masks).
//! - [`Sweep::NonGaussian`] (H3, "the micro-geometry is a Gaussian surface"): a height map
//!   of a Gaussian random field against `microsurface-truth`'s cellular and ridged
//!   surfaces of the same RMS height, the height growing relative to the voxel; coloured by
//!   height, so that eq. 17's visible colour depends on the masking of Smith's model
//!   (eqs. 4–6), which assumes Gaussian heights and slopes; and each surface again with
//!   Fig. 12's specular material lit from the mirror direction, whose highlight the lobe
//!   `σn² + σnp²` of §5.5 spreads as if the slopes were Gaussian.
//! - [`Sweep::Grazing`]: a plane with Gaussian bumps seen from 0° to ~85° off its normal, where
//!   Smith's `Λ(v)` (eq. 6) and the elements' footprint both stretch.
//!
//! # What a row measures
//!
//! For each step and view the octree (4³ bricks, [`StabilitySettings::levels`] levels,
//! `Paper20` layout) is built from the step's source, the truth is rendered once, and each
//! model of [`StabilitySettings::models`] is rendered with the *same* camera, light,
//! material and background, then compared by [`crate::accuracy::compare`]: RMSE of the
//! linear radiance, SSIM and ꟻLIP of the 8-bit images, the surface's mean colour error,
//! the silhouette's coverage bias; plus the coverage error over *every* pixel (a vanishing
//! plate has no silhouette pixels, its interior goes), the elements per pixel and the
//! tracer's time. [`StabilityTable::to_csv`] writes them, [`write_folder`] writes one CSV
//! per sweep and the whole table.

pub mod cases;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use abuffer_mask::MaskTable;
use glam::Vec3;
use svo_brick::{BrickSize, BrickTree, BuildOptions, PackedTree, VoxelLayout};
use svo_tracer::{Model, TraceSettings};

use crate::accuracy::{Comparison, compare};
use crate::cpu;
use crate::error::{RenderError, check};
use crate::frame::Frame;
use crate::truth::{TruthSettings, render_source_truth};
use cases::{Case, DOMAIN, View, finest_voxel};

/// A sweep: which hypothesis it relaxes and along which parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Sweep {
    /// H7: plate thickness in finest voxels.
    ThinPlate,
    /// H6: curvature radius (or box half-side) in finest voxels.
    Curvature,
    /// H3: RMS height of Gaussian and non-Gaussian micro-surfaces in finest voxels.
    NonGaussian,
    /// Grazing views: the angle between the view and the normal, in degrees.
    Grazing,
}

impl Sweep {
    /// Every sweep.
    pub const ALL: [Sweep; 4] = [Sweep::ThinPlate, Sweep::Curvature, Sweep::NonGaussian, Sweep::Grazing];

    /// Its name in the CSV and the file names.
    pub const fn name(self) -> &'static str {
        match self {
            Sweep::ThinPlate => "h7-thin-plate",
            Sweep::Curvature => "h6-curvature",
            Sweep::NonGaussian => "h3-non-gaussian",
            Sweep::Grazing => "grazing",
        }
    }

    /// The relaxed parameter and its unit, as written in the CSV's `parameter_name` column.
    pub const fn parameter(self) -> &'static str {
        match self {
            Sweep::ThinPlate => "thickness_voxels",
            Sweep::Curvature => "radius_voxels",
            Sweep::NonGaussian => "rms_height_voxels",
            Sweep::Grazing => "view_angle_deg",
        }
    }

    /// Whether the hypothesis is relaxed as the parameter *grows* (heights, angles) rather
    /// than as it shrinks (thickness, radius).
    pub const fn relaxed_upwards(self) -> bool {
        matches!(self, Sweep::NonGaussian | Sweep::Grazing)
    }

    /// The sweep's cases for `settings` (the steps of its parameter, the views of each).
    pub fn cases(self, settings: &StabilitySettings) -> Result<Vec<Case>, RenderError> {
        match self {
            Sweep::ThinPlate => cases::thin_plates(settings),
            Sweep::Curvature => cases::curvature(settings),
            Sweep::NonGaussian => cases::non_gaussian(settings),
            Sweep::Grazing => cases::grazing(settings),
        }
    }

    /// The number of views of each step (rows per step are this times the models).
    pub const fn views_per_step(self) -> usize {
        match self {
            Sweep::ThinPlate => 3,
            Sweep::Curvature => 3,
            // A diffuse and a specular (mirror) view of each surface.
            Sweep::NonGaussian => 2 * cases::MicroSurface::ALL.len(),
            Sweep::Grazing => 1,
        }
    }

    /// The steps of its parameter in `settings`.
    pub fn steps(self, settings: &StabilitySettings) -> &[f32] {
        match self {
            Sweep::ThinPlate => &settings.plate_thickness,
            Sweep::Curvature => &settings.curvature_radius,
            Sweep::NonGaussian => &settings.rms_height,
            Sweep::Grazing => &settings.view_angle_deg,
        }
    }
}

/// The sizes and steps of the sweeps. Every length is in finest voxels `S₀`.
#[derive(Clone, Debug, PartialEq)]
pub struct StabilitySettings {
    /// Pixels across (≥ 11, SSIM's window).
    pub width: u32,
    /// Pixels down (≥ 11).
    pub height: u32,
    /// Octree levels (4³ bricks; 2 ..= 8): `4 · 2^(levels − 1)` finest voxels across `[−1, 1]`.
    pub levels: u32,
    /// The truth's `k × k` rays per pixel (1 ..= 64).
    pub truth_rays_per_axis: u32,
    /// The models compared (each gets one row per step and view).
    pub models: Vec<Model>,
    /// The exposure of the 8-bit images SSIM and ꟻLIP compare.
    pub exposure: f32,
    /// The seed of the random surfaces.
    pub seed: u64,
    /// H7: plate thicknesses (positive).
    pub plate_thickness: Vec<f32>,
    /// H7: the plate's mid-plane above the lattice plane `z = 0` (in `[0, 1]`).
    pub plate_offset: f32,
    /// H7's far view: a pixel's footprint at the plate (in `[1, 16]`), so that the cone
    /// reads the level `log₂` of it.
    pub far_pixel_voxels: f32,
    /// H3: a pixel's footprint at the height map's centre (in `[1, 16]`; more towards the
    /// top of the oblique view). Keep `width × height_pixel_voxels` well below the domain's
    /// `4 · 2^(levels − 1)` voxels, or the view shows mostly the plane's edge, cut by the
    /// domain (at 40 px, 64 voxels and 3 voxels per pixel, the plane covers 30 % of the
    /// image and its mean colour errs by 24 % even for flat surfaces).
    pub height_pixel_voxels: f32,
    /// H6: sphere radii and cube half-sides (positive, at most 0.6 of the domain's half-side).
    pub curvature_radius: Vec<f32>,
    /// H3: RMS heights (positive).
    pub rms_height: Vec<f32>,
    /// H3 and grazing: the micro-surfaces' feature size (the Gaussian field's correlation
    /// length), at least 1.
    pub feature_voxels: f32,
    /// Grazing: view angles from the normal (degrees, in `[0, 89]`).
    pub view_angle_deg: Vec<f32>,
    /// Grazing: the bumps' RMS height (positive).
    pub bump_amplitude: f32,
}

impl StabilitySettings {
    /// The reduced sweeps of the tests: 24 × 24 pixels, 64 voxels across, 3 × 3 rays per
    /// pixel, every model, three steps per sweep.
    pub fn quick() -> Self {
        Self {
            width: 24,
            height: 24,
            levels: 5,
            truth_rays_per_axis: 3,
            plate_thickness: vec![3.0, 1.0, 0.25],
            curvature_radius: vec![8.0, 2.0, 1.0],
            rms_height: vec![0.25, 1.0, 2.0],
            view_angle_deg: vec![0.0, 60.0, 85.0],
            ..Self::default()
        }
    }

    /// The total number of rows [`run`] returns for `sweeps`: steps × views × models.
    pub fn rows(&self, sweeps: &[Sweep]) -> usize {
        sweeps.iter().map(|s| s.steps(self).len() * s.views_per_step() * self.models.len()).sum()
    }

    /// `Err(Setting)` naming the first field out of range.
    pub fn validate(&self) -> Result<(), RenderError> {
        check(self.width >= 11, "StabilitySettings::width", f64::from(self.width), "at least 11 (SSIM's window)")?;
        check(self.height >= 11, "StabilitySettings::height", f64::from(self.height), "at least 11 (SSIM's window)")?;
        check((2..=8).contains(&self.levels), "StabilitySettings::levels", f64::from(self.levels), "in 2 ..= 8")?;
        let k = self.truth_rays_per_axis;
        check((1..=64).contains(&k), "StabilitySettings::truth_rays_per_axis", f64::from(k), "in 1 ..= 64")?;
        let exposure = self.exposure;
        let finite_positive = exposure > 0.0 && exposure.is_finite();
        check(finite_positive, "StabilitySettings::exposure", f64::from(exposure), "finite and positive")?;
        let n = self.models.len() as f64;
        check(!self.models.is_empty(), "StabilitySettings::models", n, "at least one model")?;
        let positive = |v: f32| v > 0.0 && v.is_finite();
        for (field, values) in [
            ("StabilitySettings::plate_thickness", &self.plate_thickness),
            ("StabilitySettings::rms_height", &self.rms_height),
        ] {
            for &v in values {
                check(positive(v), field, f64::from(v), "finite and positive")?;
            }
        }
        let largest = 0.6 / finest_voxel(self.levels);
        for &r in &self.curvature_radius {
            check(
                positive(r) && r <= largest,
                "StabilitySettings::curvature_radius",
                f64::from(r),
                "in (0, 0.6 / S₀]",
            )?;
        }
        for &a in &self.view_angle_deg {
            check((0.0..=89.0).contains(&a), "StabilitySettings::view_angle_deg", f64::from(a), "in [0, 89]")?;
        }
        let far = self.far_pixel_voxels;
        check((1.0..=16.0).contains(&far), "StabilitySettings::far_pixel_voxels", f64::from(far), "in [1, 16]")?;
        let h = self.height_pixel_voxels;
        check((1.0..=16.0).contains(&h), "StabilitySettings::height_pixel_voxels", f64::from(h), "in [1, 16]")?;
        let offset = self.plate_offset;
        check((0.0..=1.0).contains(&offset), "StabilitySettings::plate_offset", f64::from(offset), "in [0, 1]")?;
        let feature = self.feature_voxels;
        check(feature >= 1.0 && feature.is_finite(), "StabilitySettings::feature_voxels", f64::from(feature), "≥ 1")?;
        let bumps = self.bump_amplitude;
        check(positive(bumps), "StabilitySettings::bump_amplitude", f64::from(bumps), "finite and positive")
    }
}

impl Default for StabilitySettings {
    /// The full sweeps: 40 × 40 pixels, 64 voxels across, 4 × 4 rays per pixel, every
    /// model; six to seven steps per sweep.
    fn default() -> Self {
        Self {
            width: 40,
            height: 40,
            levels: 5,
            truth_rays_per_axis: 4,
            models: Model::ALL.to_vec(),
            exposure: 1.0,
            seed: 7,
            plate_thickness: vec![4.0, 2.0, 1.0, 0.5, 0.25, 0.125],
            plate_offset: 0.5,
            far_pixel_voxels: 3.0,
            height_pixel_voxels: 1.5,
            curvature_radius: vec![16.0, 8.0, 4.0, 2.0, 1.0],
            rms_height: vec![0.125, 0.25, 0.5, 1.0, 2.0],
            feature_voxels: 3.0,
            view_angle_deg: vec![0.0, 30.0, 50.0, 65.0, 75.0, 80.0, 85.0],
            bump_amplitude: 0.5,
        }
    }
}

/// One model at one step and view of a sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct StabilityRow {
    /// The sweep.
    pub sweep: Sweep,
    /// The view (see [`cases`]).
    pub variant: &'static str,
    /// The relaxed parameter's value ([`Sweep::parameter`]).
    pub parameter: f32,
    /// A pixel's footprint at the view's target in finest voxels: the cone reads the level
    /// `λ = log₂ max(1, pixel_voxels)` there.
    pub pixel_voxels: f32,
    /// For the length parameters, the parameter in voxels of the level the cone reads at
    /// the target (`parameter / max(1, pixel_voxels)`); the angle itself for
    /// [`Sweep::Grazing`].
    pub parameter_at_lod: f32,
    /// The model.
    pub model: Model,
    /// The frame against the truth.
    pub comparison: Comparison,
    /// The mean absolute coverage error over every pixel.
    pub coverage_error: f64,
    /// The mean signed coverage error over every pixel (negative: geometry lost).
    pub coverage_bias: f64,
    /// The truth's mean coverage over every pixel.
    pub truth_coverage: f64,
    /// Cone elements sampled per pixel.
    pub elements_per_pixel: f64,
    /// The tracer's wall time for the frame (ms, all cores).
    pub ms: f64,
    /// The truth's wall time for the frame (ms, all cores; shared by the view's rows).
    pub truth_ms: f64,
}

/// The rows of one or more sweeps, in order: sweep, step, view, model.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StabilityTable {
    /// The rows.
    pub rows: Vec<StabilityRow>,
}

/// The CSV header of [`StabilityTable::to_csv`].
pub const CSV_HEADER: &str = "sweep,variant,parameter_name,parameter,pixel_voxels,parameter_at_lod,model,rmse,ssim,flip,colour_error,silhouette_pixels,silhouette_bias,coverage_error,coverage_bias,truth_coverage,elements_per_pixel,ms,truth_ms";

impl StabilityTable {
    /// The rows of `sweep`, view `variant` and `model`, step by step.
    pub fn series<'a>(
        &'a self,
        sweep: Sweep,
        variant: &'a str,
        model: Model,
    ) -> impl Iterator<Item = &'a StabilityRow> + 'a {
        self.rows.iter().filter(move |r| r.sweep == sweep && r.variant == variant && r.model == model)
    }

    /// The views of `sweep` present in the table, in order of appearance.
    pub fn variants(&self, sweep: Sweep) -> Vec<&'static str> {
        let mut out: Vec<&'static str> = Vec::new();
        for r in self.rows.iter().filter(|r| r.sweep == sweep) {
            if !out.contains(&r.variant) {
                out.push(r.variant);
            }
        }
        out
    }

    /// The rows of `sweep` alone.
    pub fn of_sweep(&self, sweep: Sweep) -> StabilityTable {
        StabilityTable { rows: self.rows.iter().filter(|r| r.sweep == sweep).cloned().collect() }
    }

    /// The table as CSV ([`CSV_HEADER`] and one line per row).
    pub fn to_csv(&self) -> String {
        let mut out = String::from(CSV_HEADER);
        out.push('\n');
        for r in &self.rows {
            let c = &r.comparison;
            // Writing to a String cannot fail.
            let _ = writeln!(
                out,
                "{},{},{},{},{:.4},{:.4},{},{:.6},{:.6},{:.6},{:.6},{},{:.6},{:.6},{:.6},{:.6},{:.3},{:.3},{:.3}",
                r.sweep.name(),
                r.variant,
                r.sweep.parameter(),
                r.parameter,
                r.pixel_voxels,
                r.parameter_at_lod,
                r.model.name(),
                c.rmse,
                c.ssim,
                c.flip,
                c.colour_error,
                c.silhouette.pixels,
                c.silhouette.bias,
                r.coverage_error,
                r.coverage_bias,
                r.truth_coverage,
                r.elements_per_pixel,
                r.ms,
                r.truth_ms,
            );
        }
        out
    }
}

/// Milliseconds since `start`.
fn ms_since(start: Instant) -> f64 {
    start.elapsed().as_secs_f64() * 1e3
}

/// The mean absolute and mean signed coverage error of `frame` against `truth` over every
/// pixel, and the truth's mean coverage (the frames have the same size: [`compare`]
/// checked it).
fn coverage_errors(frame: &Frame, truth: &Frame) -> (f64, f64, f64) {
    let n = truth.coverage.len().max(1) as f64;
    let (mut abs, mut signed, mut total) = (0.0, 0.0, 0.0);
    for (&c, &t) in frame.coverage.iter().zip(&truth.coverage) {
        let e = f64::from(c - t);
        abs += e.abs();
        signed += e;
        total += f64::from(t);
    }
    (abs / n, signed / n, total / n)
}

/// The rows of one view of `case`: the truth once, then every model.
fn measure_view<const W: usize>(
    case: &Case,
    view: &View,
    packed: &PackedTree,
    table: &MaskTable<W>,
    settings: &StabilitySettings,
) -> Result<Vec<StabilityRow>, RenderError> {
    let voxel = finest_voxel(settings.levels);
    let trace = TraceSettings {
        light: view.light,
        material: view.material,
        background: BACKGROUND,
        ..TraceSettings::default()
    };
    let truth_settings = TruthSettings::for_voxel(voxel, settings.truth_rays_per_axis);
    let start = Instant::now();
    let truth = render_source_truth(case.source.as_ref(), DOMAIN, &view.camera, &trace, &truth_settings)?;
    let truth_ms = ms_since(start);
    let pixel_voxels = view.pixel_voxels(voxel);
    let parameter_at_lod =
        if case.sweep == Sweep::Grazing { case.parameter } else { case.parameter / pixel_voxels.max(1.0) };
    let mut rows = Vec::with_capacity(settings.models.len());
    for &model in &settings.models {
        let start = Instant::now();
        let frame = cpu::render(packed, table, &view.camera, &TraceSettings { model, ..trace });
        let ms = ms_since(start);
        let comparison = compare(&frame, &truth, trace.background, settings.exposure)?;
        let (coverage_error, coverage_bias, truth_coverage) = coverage_errors(&frame, &truth);
        rows.push(StabilityRow {
            sweep: case.sweep,
            variant: view.variant,
            parameter: case.parameter,
            pixel_voxels,
            parameter_at_lod,
            model,
            comparison,
            coverage_error,
            coverage_bias,
            truth_coverage,
            elements_per_pixel: frame.mean_elements(),
            ms,
            truth_ms,
        });
    }
    Ok(rows)
}

/// The background of every view (dark blue-grey, distinct from every surface colour).
pub const BACKGROUND: Vec3 = Vec3::new(0.1, 0.12, 0.15);

/// Runs `sweeps` (see the module documentation): for each step, the octree of its source,
/// and for each view the truth and every model. Returns [`StabilitySettings::rows`] rows.
pub fn run<const W: usize>(
    sweeps: &[Sweep],
    settings: &StabilitySettings,
    table: &MaskTable<W>,
) -> Result<StabilityTable, RenderError> {
    settings.validate()?;
    let options = BuildOptions { brick_size: BrickSize::Four, levels: settings.levels, ..BuildOptions::default() };
    let mut rows = Vec::with_capacity(settings.rows(sweeps));
    for &sweep in sweeps {
        for case in sweep.cases(settings)? {
            let tree = BrickTree::build(case.source.as_ref(), DOMAIN, options)
                .map_err(|source| RenderError::Build { scene: sweep.name(), source })?;
            let packed = PackedTree::new(&tree, VoxelLayout::Paper20);
            for view in &case.views {
                rows.extend(measure_view(&case, view, &packed, table, settings)?);
            }
        }
    }
    Ok(StabilityTable { rows })
}

/// Writes `table` into the folder `dir` (created if missing): `stability.csv` with every
/// row and `<sweep>.csv` for each sweep present ([`Sweep::name`]). Returns the files
/// written.
pub fn write_folder(table: &StabilityTable, dir: &Path) -> Result<Vec<PathBuf>, RenderError> {
    std::fs::create_dir_all(dir).map_err(|source| RenderError::Io { path: dir.to_path_buf(), source })?;
    let mut files = Vec::new();
    let mut write = |name: String, text: String| -> Result<(), RenderError> {
        let path = dir.join(name);
        std::fs::write(&path, text).map_err(|source| RenderError::Io { path: path.clone(), source })?;
        files.push(path);
        Ok(())
    };
    write("stability.csv".into(), table.to_csv())?;
    for sweep in Sweep::ALL {
        let rows = table.of_sweep(sweep);
        if !rows.rows.is_empty() {
            write(format!("{}.csv", sweep.name()), rows.to_csv())?;
        }
    }
    Ok(files)
}
