//! The tracer's models against the ground truth along a dolly (the paper's Fig. 8): image
//! error (RMSE, SSIM, ꟻLIP), the surface's mean colour and its drift across the zoom (the
//! paper's coherence claim), the silhouette's coverage error (Fig. 4's over-accumulation),
//! the work and the time per frame.
//!
//! # What is measured
//!
//! For each view of the [`Dolly`] the ground truth ([`crate::truth`]) is rendered once and
//! every model of [`DollySettings::models`] is rendered by the CPU tracer
//! ([`crate::cpu::render`]); each pair is compared by [`compare`]:
//!
//! - `rmse`: over every channel of every pixel of the linear radiance;
//! - `ssim`, `flip`: of the 8-bit sRGB images at [`DollySettings::exposure`]
//!   (`image-metrics`: SSIM as scikit-image computes it, NVIDIA's ꟻLIP at 67 px/°);
//! - the surface's mean colour [`Frame::surface_mean`] (the radiance of the covered part,
//!   whatever its size on screen), its relative error `‖m − m_truth‖ / ‖m_truth‖`, and the
//!   **drift**: per channel, the ratio `m_c / m_truth,c` at this view minus the ratio at the
//!   first view, the largest channel's absolute value — how much the model's colour bias
//!   changes along the zoom (zero for a perfectly coherent model, even a biased one);
//! - the silhouette ([`silhouette_error`]): over the pixels whose true coverage is in
//!   `(0.02, 0.98)`, the mean signed coverage error (positive: over-accumulation, Fig. 4),
//!   the mean absolute error, and the mean positive part (the over-accumulation alone);
//! - elements per pixel and the tracer's wall time (all cores), the truth's wall time, and
//!   optionally the voxel truth's RMSE against the truth (the voxelisation error floor).

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use abuffer_mask::MaskTable;
use glam::Vec3;
use svo_brick::{PackedTree, SurfaceSource};
use svo_tracer::{Camera, Model, TraceSettings};

use crate::cpu;
use crate::error::{RenderError, check};
use crate::frame::Frame;
use crate::scenes::Scene;
use crate::truth::{TruthSettings, packed_domain, render_source_truth, render_voxel_truth};

/// The lowest true coverage of a silhouette pixel.
pub const SILHOUETTE_MIN: f32 = 0.02;
/// The highest true coverage of a silhouette pixel.
pub const SILHOUETTE_MAX: f32 = 0.98;

/// A camera path towards a point, its distances decreasing geometrically (Fig. 8's zoom).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dolly {
    /// The point looked at and approached.
    pub target: Vec3,
    /// The unit direction from the target towards the eyes.
    pub direction: Vec3,
    /// The image's up vector (not parallel to `direction`).
    pub up: Vec3,
    /// The first view's distance from the target.
    pub far: f32,
    /// Octaves of zoom: the last view is `2^octaves` times closer.
    pub octaves: f32,
    /// The number of views (≥ 1), distances `far · 2^(−octaves · i / (views − 1))`.
    pub views: u32,
    /// The vertical field of view (radians).
    pub fov_y: f32,
    /// Pixels across (≥ 11, SSIM's window).
    pub width: u32,
    /// Pixels down (≥ 11).
    pub height: u32,
}

impl Dolly {
    /// A dolly towards the scene's [`target`](Scene::target) along its outward normal,
    /// field of view 0.5 rad, `y` up (or `z` when the normal is vertical).
    pub fn towards(scene: &Scene, far: f32, octaves: f32, views: u32, width: u32, height: u32) -> Self {
        let up = if scene.outward.y.abs() > 0.9 { Vec3::Z } else { Vec3::Y };
        Self { target: scene.target, direction: scene.outward, up, far, octaves, views, fov_y: 0.5, width, height }
    }

    /// `Err(Setting)` naming the first field out of range.
    pub fn validate(&self) -> Result<(), RenderError> {
        check(self.far > 0.0 && self.far.is_finite(), "Dolly::far", f64::from(self.far), "finite and positive")?;
        let octaves = self.octaves;
        check((0.0..=20.0).contains(&octaves), "Dolly::octaves", f64::from(octaves), "in [0, 20]")?;
        check(self.views >= 1, "Dolly::views", f64::from(self.views), "at least 1")?;
        check(self.width >= 11, "Dolly::width", f64::from(self.width), "at least 11 (SSIM's window)")?;
        check(self.height >= 11, "Dolly::height", f64::from(self.height), "at least 11 (SSIM's window)")
    }

    /// The distance of view `i` from the target.
    pub fn distance(&self, view: u32) -> f32 {
        if self.views <= 1 {
            return self.far;
        }
        self.far * (-self.octaves * view as f32 / (self.views - 1) as f32).exp2()
    }

    /// The camera of view `i`.
    pub fn camera(&self, view: u32) -> Result<Camera, RenderError> {
        let eye = self.target + self.direction.normalize_or_zero() * self.distance(view);
        Camera::look_at(eye, self.target, self.up, self.fov_y, self.width, self.height)
            .map_err(|source| RenderError::Camera { view, source })
    }
}

/// Everything [`dolly_accuracy`] needs besides the surface and its octree.
#[derive(Clone, Debug, PartialEq)]
pub struct DollySettings {
    /// The views.
    pub dolly: Dolly,
    /// The tracer's settings (its `model` is replaced by each of [`models`](Self::models));
    /// its light, material and background shade the truth too.
    pub trace: TraceSettings,
    /// The ground truth's sampling. Shadows must be on in both or in neither
    /// (`shadow_rays_per_axis > 0` iff `trace.shadow_cones > 0`).
    pub truth: TruthSettings,
    /// The models compared (each gets one row per view).
    pub models: Vec<Model>,
    /// The exposure of the 8-bit images SSIM and ꟻLIP compare.
    pub exposure: f32,
    /// Also render the voxel truth at each view and report its RMSE against the truth.
    pub voxel_truth: bool,
}

impl DollySettings {
    /// Every model, exposure 1, no voxel truth.
    pub fn new(dolly: Dolly, trace: TraceSettings, truth: TruthSettings) -> Self {
        Self { dolly, trace, truth, models: Model::ALL.to_vec(), exposure: 1.0, voxel_truth: false }
    }
}

/// The silhouette's coverage error of a frame against the truth.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SilhouetteError {
    /// Pixels whose true coverage is in `(SILHOUETTE_MIN, SILHOUETTE_MAX)`.
    pub pixels: u32,
    /// The mean signed coverage error over them (positive: too much coverage).
    pub bias: f64,
    /// The mean absolute coverage error.
    pub mean_abs: f64,
    /// The mean of the positive part of the error (over-accumulation alone, Fig. 4).
    pub over_accumulation: f64,
}

/// [`SilhouetteError`] of `coverage` against `truth` (pixel for pixel; zeros without
/// silhouette pixels).
pub fn silhouette_error(coverage: &[f32], truth: &[f32]) -> SilhouetteError {
    let mut out = SilhouetteError::default();
    for (&c, &t) in coverage.iter().zip(truth) {
        if t > SILHOUETTE_MIN && t < SILHOUETTE_MAX {
            let e = f64::from(c - t);
            out.pixels += 1;
            out.bias += e;
            out.mean_abs += e.abs();
            out.over_accumulation += e.max(0.0);
        }
    }
    if out.pixels > 0 {
        let n = f64::from(out.pixels);
        out.bias /= n;
        out.mean_abs /= n;
        out.over_accumulation /= n;
    }
    out
}

/// A frame against the truth (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Comparison {
    /// RMSE of the linear radiance.
    pub rmse: f64,
    /// Mean SSIM of the 8-bit images.
    pub ssim: f64,
    /// Mean ꟻLIP of the 8-bit images.
    pub flip: f64,
    /// The frame's surface mean colour.
    pub mean: Vec3,
    /// The truth's surface mean colour.
    pub truth_mean: Vec3,
    /// `‖mean − truth_mean‖ / ‖truth_mean‖` (the absolute difference's norm where the truth
    /// is black).
    pub colour_error: f64,
    /// The silhouette's coverage error.
    pub silhouette: SilhouetteError,
}

/// Compares `test` with `truth` (the same size, at least 11 × 11 for SSIM), their images at
/// `exposure`, the surface means without `background`.
pub fn compare(test: &Frame, truth: &Frame, background: Vec3, exposure: f32) -> Result<Comparison, RenderError> {
    test.same_size(truth)?;
    let rmse = test.rmse(truth)?;
    let (a, b) = (truth.to_rgba8(exposure), test.to_rgba8(exposure));
    let ssim = image_metrics::ssim(&a, &b).map_err(|source| RenderError::Metric { what: "SSIM".into(), source })?;
    let flip = image_metrics::flip(&a, &b).map_err(|source| RenderError::Metric { what: "FLIP".into(), source })?;
    let (mean, truth_mean) = (test.surface_mean(background), truth.surface_mean(background));
    let difference = f64::from((mean - truth_mean).length());
    let reference = f64::from(truth_mean.length());
    let colour_error = if reference > 0.0 { difference / reference } else { difference };
    Ok(Comparison {
        rmse,
        ssim: ssim.mean,
        flip: flip.mean,
        mean,
        truth_mean,
        colour_error,
        silhouette: silhouette_error(&test.coverage, &truth.coverage),
    })
}

/// One model at one view of the dolly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AccuracyRow {
    /// The model.
    pub model: Model,
    /// The view's index along the dolly.
    pub view: u32,
    /// The eye's distance from the target.
    pub distance: f32,
    /// A pixel's footprint at the target in finest voxels (`< 1`: magnification).
    pub pixel_voxels: f32,
    /// The frame against the truth.
    pub comparison: Comparison,
    /// The change of the colour ratio since the first view (see the module documentation).
    pub drift: f64,
    /// Cone elements sampled per pixel.
    pub elements_per_pixel: f64,
    /// The tracer's wall time for the frame (ms, all cores).
    pub ms: f64,
    /// The truth's wall time for the frame (ms, all cores; shared by the view's rows).
    pub truth_ms: f64,
    /// The voxel truth's RMSE against the truth, if rendered (shared by the view's rows).
    pub voxel_rmse: Option<f64>,
}

/// The rows of a dolly: for each view, one per model, in the order of
/// [`DollySettings::models`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AccuracyTable {
    /// The rows, view by view.
    pub rows: Vec<AccuracyRow>,
}

/// The CSV header of [`AccuracyTable::to_csv`].
pub const CSV_HEADER: &str = "model,view,distance,pixel_voxels,rmse,ssim,flip,mean_r,mean_g,mean_b,truth_r,truth_g,truth_b,colour_error,drift,silhouette_pixels,coverage_bias,coverage_abs,over_accumulation,elements_per_pixel,ms,truth_ms,voxel_rmse";

impl AccuracyTable {
    /// The rows of `model`, view by view.
    pub fn of(&self, model: Model) -> impl Iterator<Item = &AccuracyRow> {
        self.rows.iter().filter(move |r| r.model == model)
    }

    /// The largest absolute [`AccuracyRow::drift`] of `model` over the dolly.
    pub fn max_drift(&self, model: Model) -> f64 {
        self.of(model).map(|r| r.drift.abs()).fold(0.0, f64::max)
    }

    /// The table as CSV ([`CSV_HEADER`] and one line per row; an absent voxel RMSE is an
    /// empty field).
    pub fn to_csv(&self) -> String {
        let mut out = String::from(CSV_HEADER);
        out.push('\n');
        for r in &self.rows {
            let c = &r.comparison;
            let s = &c.silhouette;
            let voxel = r.voxel_rmse.map(|v| format!("{v:.6}")).unwrap_or_default();
            // Writing to a String cannot fail.
            let _ = writeln!(
                out,
                "{},{},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{},{:.6},{:.6},{:.6},{:.3},{:.3},{:.3},{voxel}",
                r.model.name(),
                r.view,
                r.distance,
                r.pixel_voxels,
                c.rmse,
                c.ssim,
                c.flip,
                c.mean.x,
                c.mean.y,
                c.mean.z,
                c.truth_mean.x,
                c.truth_mean.y,
                c.truth_mean.z,
                c.colour_error,
                r.drift,
                s.pixels,
                s.bias,
                s.mean_abs,
                s.over_accumulation,
                r.elements_per_pixel,
                r.ms,
                r.truth_ms,
            );
        }
        out
    }
}

/// Writes [`AccuracyTable::to_csv`] of `table` to `path` (its folder must exist).
pub fn write_csv(table: &AccuracyTable, path: &Path) -> Result<(), RenderError> {
    std::fs::write(path, table.to_csv()).map_err(|source| RenderError::Io { path: path.to_path_buf(), source })
}

/// The per-channel ratio of a colour to the truth's (1 where the truth's channel is black).
fn ratio(mean: Vec3, truth: Vec3) -> [f64; 3] {
    let (m, t) = (mean.to_array(), truth.to_array());
    [0, 1, 2].map(|c| if t[c].abs() > 1e-9 { f64::from(m[c] / t[c]) } else { 1.0 })
}

/// Milliseconds since `start`.
fn ms_since(start: Instant) -> f64 {
    start.elapsed().as_secs_f64() * 1e3
}

/// Renders the dolly with the tracer (every model of `settings.models`) and the ground truth
/// of `source` (the unfiltered surface `packed` was built from, in `packed`'s domain) and
/// compares them view by view (see the module documentation).
pub fn dolly_accuracy<S: SurfaceSource + Sync + ?Sized, const W: usize>(
    source: &S,
    packed: &PackedTree,
    table: &MaskTable<W>,
    settings: &DollySettings,
) -> Result<AccuracyTable, RenderError> {
    let render = |camera: &Camera, trace: &TraceSettings| Ok(cpu::render(packed, table, camera, trace));
    dolly_accuracy_with(source, packed, settings, render, |_, _| {})
}

/// [`dolly_accuracy`] with the tracer's frames from `render` (for instance a
/// [`crate::GpuRenderer`]'s), called once per view and model in the order of the rows; its
/// wall time is the row's [`ms`](AccuracyRow::ms). `truth` receives each view's index and
/// its ground truth.
pub fn dolly_accuracy_with<S: SurfaceSource + Sync + ?Sized>(
    source: &S,
    packed: &PackedTree,
    settings: &DollySettings,
    mut render: impl FnMut(&Camera, &TraceSettings) -> Result<Frame, RenderError>,
    mut truth_frame: impl FnMut(u32, &Frame),
) -> Result<AccuracyTable, RenderError> {
    settings.dolly.validate()?;
    settings.truth.validate()?;
    let shadows = (settings.trace.shadow_cones > 0, settings.truth.shadow_rays_per_axis > 0);
    check(
        shadows.0 == shadows.1,
        "TruthSettings::shadow_rays_per_axis",
        f64::from(settings.truth.shadow_rays_per_axis),
        "positive exactly when TraceSettings::shadow_cones is",
    )?;
    let exposure = settings.exposure;
    check(
        exposure > 0.0 && exposure.is_finite(),
        "DollySettings::exposure",
        f64::from(exposure),
        "finite and positive",
    )?;
    let domain = packed_domain(packed);
    let voxel = packed.uniforms().voxel_size.x;
    let mut rows = Vec::new();
    let mut first: Vec<Option<[f64; 3]>> = vec![None; settings.models.len()];
    for view in 0..settings.dolly.views {
        let camera = settings.dolly.camera(view)?;
        let start = Instant::now();
        let truth = render_source_truth(source, domain, &camera, &settings.trace, &settings.truth)?;
        let truth_ms = ms_since(start);
        truth_frame(view, &truth);
        let voxel_rmse = if settings.voxel_truth {
            Some(render_voxel_truth(packed, &camera, &settings.trace, &settings.truth)?.rmse(&truth)?)
        } else {
            None
        };
        let distance = settings.dolly.distance(view);
        let pixel_voxels = distance * camera.pixel_size() / voxel;
        for (index, &model) in settings.models.iter().enumerate() {
            let trace = TraceSettings { model, ..settings.trace };
            let start = Instant::now();
            let frame = render(&camera, &trace)?;
            let ms = ms_since(start);
            let comparison = compare(&frame, &truth, settings.trace.background, exposure)?;
            let now = ratio(comparison.mean, comparison.truth_mean);
            let reference = match first.get_mut(index) {
                Some(slot) => *slot.get_or_insert(now),
                None => now,
            };
            let drift =
                (0..3).map(|c| now[c] - reference[c]).fold(0.0_f64, |a, d| if d.abs() > a.abs() { d } else { a });
            rows.push(AccuracyRow {
                model,
                view,
                distance,
                pixel_voxels,
                comparison,
                drift,
                elements_per_pixel: frame.mean_elements(),
                ms,
                truth_ms,
                voxel_rmse,
            });
        }
    }
    Ok(AccuracyTable { rows })
}
