//! *Model no more than a scene needs*, for grains: the measured table that
//! [`model_select`] chooses an impostor atlas from — `(n, p)`, sampling mode and layout —
//! per grain, for an image-error budget, and the check of its choices on views the table
//! never saw.
//!
//! **The table** ([`table_rows`]): each grain of the comparison scene of
//! [`crate::accuracy`] (one copy per view direction, the mesh supersampled
//! [`crate::accuracy::REFERENCE_SUPERSAMPLING`]² times as the truth, the same deferred shading), at each
//! calibration size on screen, every atlas configuration of the settings; per
//! configuration the mean ꟻLIP and 1 − SSIM (`image-metrics`: NVIDIA's ꟻLIP and the
//! standard Gaussian SSIM) of its image against the mesh's, and its cost: the atlas's GPU
//! memory with full mips, in MiB — what an atlas costs a renderer for every grain of the
//! type, whatever the number of grains (its time per pixel depends on the mode and is
//! measured by `cargo xtask bench-gpu stackings`, not here). The condition of a row is
//! the grain's diameter on screen in pixels, and its errors are the **worst** over the
//! calibration diameters up to it: ꟻLIP does not grow with the diameter here — small
//! grains alias against the supersampled mesh (the nut's best configuration: 0.077 at
//! 16 px, 0.065 at 32, 0.062 at 64), while large ones show the atlas's resolution — so a
//! row at `D` bounds every measured size up to `D`, and the table grows with the condition
//! by construction, as [`model_select::Table::select`] assumes. Grains larger than the
//! largest calibration size have no row (the selector says so).
//!
//! **The check** ([`held_out_views`], then [`model_select::Table::check_held_out`]): the
//! same grains seen from other directions (the table's Fibonacci set rotated by
//! [`SelectionSettings::held_out_rotation_deg`] about an oblique axis) at a size between
//! the calibration ones, every configuration rendered again.

use glam::{Quat, Vec3};
use grain_mesh::GrainMesh;
use image::RgbaImage;
use model_select::Measurement;
use octahedral_map::sampling::{SamplingMode, ViewLayout};

use crate::accuracy::{
    AccuracySweep, ComparisonScene, SweepError, fibonacci_directions, sampling_mode_name, view_layout_name,
};
use crate::atlas_gpu::AtlasTextures;
use crate::bake::{BakeSettings, Baker, Progress};

/// [`Measurement::condition`]'s unit.
pub const CONDITION_UNIT: &str = "grain diameter on screen (pixels)";
/// [`Measurement::cost`]'s unit.
pub const COST_UNIT: &str = "atlas GPU memory with full mips (MiB)";
/// The committed table, relative to the workspace root (`cargo xtask select-tables`).
pub const TABLE_FILE: &str = "crates/grain-impostor/tables/grain_selection.csv";
/// The table's name.
pub const TABLE_NAME: &str = "grain-atlases";
/// The sources that produce the table, relative to the workspace root: its
/// [`model_select::fingerprint`] stamps the table, and a test fails when they change
/// without the table being measured again.
pub const TABLE_SOURCES: [&str; 4] =
    ["crates/grain-impostor/src", "crates/grain-mesh/src", "crates/octahedral-map/src", "crates/image-metrics/src"];

/// A configuration's name in tables: `n8 p64 mixed compact`.
pub fn representation_name(subdivisions: u32, texels: u32, mode: SamplingMode, layout: ViewLayout) -> String {
    format!("n{subdivisions} p{texels} {} {}", sampling_mode_name(mode), view_layout_name(layout))
}

/// What the table and its check measure.
#[derive(Clone, Debug, PartialEq)]
pub struct SelectionSettings {
    /// The values of `n`.
    pub subdivisions: Vec<u32>,
    /// The values of `p`.
    pub texels: Vec<u32>,
    /// The sampling modes.
    pub modes: Vec<SamplingMode>,
    /// The layouts.
    pub layouts: Vec<ViewLayout>,
    /// View directions (grains in the comparison grid).
    pub view_count: u32,
    /// The calibration diameters on screen, pixels, increasing.
    pub diameters: Vec<f32>,
    /// The held-out diameter, pixels.
    pub held_out_diameter: f32,
    /// The rotation of the held-out view directions, degrees.
    pub held_out_rotation_deg: f32,
}

impl SelectionSettings {
    /// The committed table's settings: `n ∈ {4, 6, 8, 12}`, `p ∈ {32, 64}`, every mode,
    /// both layouts, 64 directions, grains 16, 32 and 64 pixels wide; held out: 24
    /// pixels, the directions rotated by 31°.
    pub fn standard() -> Self {
        Self {
            subdivisions: vec![4, 6, 8, 12],
            texels: vec![32, 64],
            modes: SamplingMode::ALL.to_vec(),
            layouts: vec![ViewLayout::Listing1, ViewLayout::Compact],
            view_count: 64,
            diameters: vec![16.0, 32.0, 64.0],
            held_out_diameter: 24.0,
            held_out_rotation_deg: 31.0,
        }
    }

    /// An error naming the first field out of range.
    pub fn validate(&self) -> Result<(), SweepError> {
        let invalid =
            |field: &str, reason: &str| Err(SweepError::Invalid(format!("selection settings: {field}: {reason}")));
        if self.subdivisions.is_empty() || self.texels.is_empty() || self.modes.is_empty() || self.layouts.is_empty() {
            return invalid("subdivisions, texels, modes, layouts", "each needs at least one value");
        }
        if self.view_count == 0 {
            return invalid("view_count", "at least one view");
        }
        if self.diameters.is_empty() || self.diameters.windows(2).any(|w| w[1] <= w[0]) {
            return invalid("diameters", "at least one, increasing");
        }
        if !(self.diameters.iter().chain([&self.held_out_diameter]).all(|d| d.is_finite() && *d >= 2.0)) {
            return invalid("diameters", "each at least 2 pixels");
        }
        if !self.held_out_rotation_deg.is_finite() || self.held_out_rotation_deg.abs() < 1.0 {
            return invalid("held_out_rotation_deg", "at least 1° (else the held-out views are the table's)");
        }
        Ok(())
    }

    /// The held-out view directions: the table's, rotated.
    pub fn held_out_directions(&self) -> Vec<Vec3> {
        let rotation =
            Quat::from_axis_angle(Vec3::new(1.0, 2.0, 3.0).normalize(), self.held_out_rotation_deg.to_radians());
        fibonacci_directions(self.view_count).into_iter().map(|d| rotation * d).collect()
    }
}

/// One grain seen at one size: the mesh's image and every configuration's.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewMeasurements {
    /// The mesh's image (the truth).
    pub truth: RgbaImage,
    /// Per configuration its image and measurement.
    pub configurations: Vec<(Measurement, RgbaImage)>,
}

fn metric(e: image_metrics::MetricError) -> SweepError {
    SweepError::Invalid(format!("image metrics: {e}"))
}

/// Every configuration of `settings` for `mesh` in each of `scenes` (one
/// [`ViewMeasurements`] per scene, in order).
#[allow(clippy::too_many_arguments)]
fn measure(
    sweep: &AccuracySweep,
    baker: &Baker,
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    name: &str,
    mesh: &GrainMesh,
    scenes: &[ComparisonScene],
    settings: &SelectionSettings,
) -> Result<Vec<ViewMeasurements>, SweepError> {
    let mut views: Vec<ViewMeasurements> = scenes
        .iter()
        .map(|s| Ok(ViewMeasurements { truth: sweep.reference(device, queue, mesh, s)?, configurations: Vec::new() }))
        .collect::<Result<_, SweepError>>()?;
    for &n in &settings.subdivisions {
        for &p in &settings.texels {
            let bake = BakeSettings { progress: Progress::Hidden, ..BakeSettings::new(n, p) };
            let paper_atlas = baker.bake(device, queue, mesh, &bake)?;
            for &layout in &settings.layouts {
                let atlas = match layout {
                    ViewLayout::Listing1 => paper_atlas.clone(),
                    ViewLayout::Compact => paper_atlas.to_compact(),
                };
                let textures = AtlasTextures::upload(device, queue, &atlas)?;
                let mebibytes = atlas.memory().gpu_bytes as f64 / f64::from(1 << 20);
                for (scene, view) in scenes.iter().zip(&mut views) {
                    for &mode in &settings.modes {
                        let image = sweep.impostor(device, queue, &atlas, &textures, scene, mode)?;
                        let flip = image_metrics::flip(&view.truth, &image).map_err(metric)?.mean;
                        let ssim = image_metrics::ssim(&view.truth, &image).map_err(metric)?.mean;
                        let measurement = Measurement {
                            object: name.to_owned(),
                            representation: representation_name(n, p, mode, layout),
                            condition: f64::from(scene.apparent_diameter),
                            flip,
                            ssim_loss: (1.0 - ssim).max(0.0),
                            cost: mebibytes,
                        };
                        view.configurations.push((measurement, image));
                    }
                }
            }
        }
    }
    Ok(views)
}

/// The table's rows: every grain at every calibration diameter, every configuration.
pub fn table_rows(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    grains: &[(String, GrainMesh)],
    settings: &SelectionSettings,
) -> Result<Vec<Measurement>, SweepError> {
    settings.validate()?;
    let (sweep, baker) = (AccuracySweep::new(device)?, Baker::new(device)?);
    let mut rows = Vec::new();
    for (name, mesh) in grains {
        let scenes = settings
            .diameters
            .iter()
            .map(|&d| AccuracySweep::scene(mesh, settings.view_count, d))
            .collect::<Result<Vec<_>, _>>()?;
        let views = measure(&sweep, &baker, device, queue, name, mesh, &scenes, settings)?;
        let measured: Vec<Vec<Measurement>> =
            views.into_iter().map(|v| v.configurations.into_iter().map(|(m, _)| m).collect()).collect();
        rows.extend(worst_up_to_each_condition(&measured));
    }
    Ok(rows)
}

/// Per condition (`measured[k]`: every configuration at the `k`-th calibration diameter,
/// in the same order), each configuration's worst errors over the conditions up to it.
fn worst_up_to_each_condition(measured: &[Vec<Measurement>]) -> Vec<Measurement> {
    let mut rows = Vec::new();
    for (k, at) in measured.iter().enumerate() {
        for (c, row) in at.iter().enumerate() {
            let below = || measured[..=k].iter().filter_map(|m| m.get(c));
            rows.push(Measurement {
                flip: below().map(|m| m.flip).fold(0.0, f64::max),
                ssim_loss: below().map(|m| m.ssim_loss).fold(0.0, f64::max),
                ..row.clone()
            });
        }
    }
    rows
}

/// Every grain seen from the held-out directions at the held-out diameter, every
/// configuration rendered.
pub fn held_out_views(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    grains: &[(String, GrainMesh)],
    settings: &SelectionSettings,
) -> Result<Vec<ViewMeasurements>, SweepError> {
    settings.validate()?;
    let (sweep, baker) = (AccuracySweep::new(device)?, Baker::new(device)?);
    let directions = settings.held_out_directions();
    let mut views = Vec::new();
    for (name, mesh) in grains {
        let scene = ComparisonScene::new(&directions, mesh.bounds().outer_radius, settings.held_out_diameter)
            .ok_or_else(|| SweepError::Invalid(format!("{name}: no held-out scene")))?;
        views.extend(measure(&sweep, &baker, device, queue, name, mesh, std::slice::from_ref(&scene), settings)?);
    }
    Ok(views)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_row_is_the_worst_up_to_its_condition() {
        let m = |condition: f64, flip: f64| Measurement {
            object: "nut".into(),
            representation: "a".into(),
            condition,
            flip,
            ssim_loss: flip / 2.0,
            cost: 1.0,
        };
        let rows = worst_up_to_each_condition(&[vec![m(16.0, 0.3)], vec![m(32.0, 0.1)], vec![m(64.0, 0.4)]]);
        let flips: Vec<f64> = rows.iter().map(|r| r.flip).collect();
        assert_eq!(flips, [0.3, 0.3, 0.4]);
        assert_eq!(rows.iter().map(|r| r.condition).collect::<Vec<_>>(), [16.0, 32.0, 64.0]);
        assert_eq!(rows[1].ssim_loss, 0.15);
    }

    #[test]
    fn names_are_plain_and_settings_name_their_bad_field() {
        assert_eq!(representation_name(8, 64, SamplingMode::Mixed, ViewLayout::Compact), "n8 p64 mixed compact");
        let settings = SelectionSettings::standard();
        settings.validate().unwrap();
        let (low, high) = (settings.diameters[0], settings.diameters[settings.diameters.len() - 1]);
        assert!(low < settings.held_out_diameter && settings.held_out_diameter < high);
        assert!(!settings.diameters.contains(&settings.held_out_diameter));
        // The held-out directions are unit and none is a table direction.
        let table = fibonacci_directions(settings.view_count);
        for d in settings.held_out_directions() {
            assert!((d.length() - 1.0).abs() < 1e-5);
            assert!(table.iter().all(|t| t.dot(d) < 0.9999), "{d}");
        }
        let bad = SelectionSettings { diameters: vec![32.0, 16.0], ..SelectionSettings::standard() };
        assert!(bad.validate().unwrap_err().to_string().contains("diameters"));
        let bad = SelectionSettings { held_out_rotation_deg: 0.0, ..SelectionSettings::standard() };
        assert!(bad.validate().unwrap_err().to_string().contains("held_out_rotation_deg"));
    }
}
