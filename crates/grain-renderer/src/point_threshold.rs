//! The point threshold, measured: the largest projected diameter at which drawing a pile's
//! grains as points costs no more than an SSIM budget over drawing them as impostors, both
//! against the ground truth — the mesh, 4 × 4 supersampled.
//!
//! At each diameter `d` (the camera's distance puts a grain of scale 1 at `d` pixels
//! across) the pile is rendered three times from the same camera: the meshes (4 × 4
//! supersampled, `grain-impostor`'s mesh pass), every grain an impostor, every grain a point.
//! The images are cropped to the mesh render's covered rectangle (grown by 4 pixels, at least
//! 16 × 16) so that the background does not dilute the score, and each model is compared with
//! the mesh by `grain_impostor::accuracy::compare_images`, the metric of the measured impostor
//! table that sets the mesh threshold. Culling is off (a point pixel averages the grains kept).
//!
//! The threshold is the largest `d` of the ascending list such that the point loss
//! `1 − SSIM` is at most the impostor loss plus the budget at `d` and at every smaller
//! diameter; `None` when not even at the smallest.

use glam::Vec3;
use grain_impostor::accuracy::{ImageError, compare_images};
use grain_impostor::atlas::ImpostorAtlas;
use grain_impostor::scene::GrainInstance;
use grain_splitter::OccluderMapKind;

use crate::error::RenderError;
use crate::impostor_tier::{TierSettings, VisibilityKind};
use crate::mesh_reference::MeshReference;
use crate::renderer::{NO_POINT_TIER, RendererOptions, StackingCamera, StackingRenderer};

/// The vertical field of view of the measurement.
pub const MEASURE_FOV_Y: f32 = 0.6;

/// One diameter of the measurement.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointRow {
    /// Projected diameter of a grain of scale 1, pixels.
    pub diameter: f32,
    /// The point render against the mesh.
    pub points: ImageError,
    /// The impostor render against the mesh.
    pub impostors: ImageError,
    /// Pixels compared (the cropped rectangle).
    pub pixels: u32,
}

/// The measurement: every row and the threshold it gives.
#[derive(Clone, Debug, PartialEq)]
pub struct PointThreshold {
    /// One row per diameter, ascending.
    pub rows: Vec<PointRow>,
    /// The largest diameter within the budget at and below it (module docs).
    pub threshold: Option<f32>,
    /// The SSIM loss budget.
    pub budget: f64,
}

/// The threshold the rows give for `budget` (module docs); rows ascending in diameter.
pub fn threshold_of(rows: &[PointRow], budget: f64) -> Option<f32> {
    rows.iter().take_while(|r| r.points.ssim >= r.impostors.ssim - budget).last().map(|r| r.diameter)
}

/// Measures the threshold for the pile `grains` of `mesh` (atlas `atlas`) seen from
/// `direction` (toward the eye, from the pile's centre `target`) at `size` pixels, at each of
/// `diameters` (ascending, positive), within the SSIM loss `budget`.
#[allow(clippy::too_many_arguments)]
pub fn measure(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    mesh: &grain_mesh::GrainMesh,
    atlas: &ImpostorAtlas,
    grains: &[GrainInstance],
    (target, direction): (Vec3, Vec3),
    size: (u32, u32),
    diameters: &[f32],
    budget: f64,
) -> Result<PointThreshold, RenderError> {
    if diameters.is_empty()
        || diameters.iter().any(|d| !d.is_finite())
        || diameters.windows(2).any(|w| w[0] >= w[1])
        || diameters[0] <= 0.0
    {
        return Err(RenderError::InvalidSetting {
            field: "diameters",
            reason: format!("{diameters:?}: must be positive and ascending"),
        });
    }
    if !(budget.is_finite() && budget >= 0.0) {
        return Err(RenderError::InvalidSetting { field: "budget", reason: format!("{budget}: must be ≥ 0") });
    }
    let error = |e: &dyn std::fmt::Display| RenderError::InvalidInput(e.to_string());
    let direction = direction
        .try_normalize()
        .ok_or_else(|| RenderError::InvalidInput(format!("view direction {direction}: must not be zero")))?;
    let base = RendererOptions {
        size,
        capacity: grains.len() as u32,
        mesh_above: 1e6,
        point_below: NO_POINT_TIER,
        band: 1.0,
        occluder_map: OccluderMapKind::Auto,
        visibility: VisibilityKind::Auto,
        culling: false,
        samples: 1,
    };
    let impostors = StackingRenderer::new(device, queue, mesh, atlas, base)?;
    let points = StackingRenderer::new(device, queue, mesh, atlas, RendererOptions { point_below: 1e5, ..base })?;
    let impostor_scene = impostors.upload(device, grains)?;
    let truth = MeshReference::new(device, mesh, grains, size)?;
    let point_scene = points.upload(device, grains)?;
    let lighting = crate::renderer::pile_lighting();
    let focal = 0.5 * size.1 as f32 / (0.5 * MEASURE_FOV_Y).tan();
    let mut rows = Vec::with_capacity(diameters.len());
    for &diameter in diameters {
        let distance = focal * 2.0 * atlas.outer_radius / diameter;
        let camera = StackingCamera::perspective(
            target + direction * distance,
            target,
            MEASURE_FOV_Y,
            size,
            (1e-3 * distance, 4.0 * distance),
        )?;
        let render = |renderer: &StackingRenderer, scene| {
            let mut encoder = device.create_command_encoder(&Default::default());
            renderer.encode(queue, &mut encoder, scene, &camera, &lighting, TierSettings::default())?;
            queue.submit([encoder.finish()]);
            grain_impostor::shading::read_image(device, queue, renderer.image()).map_err(|e| error(&e))
        };
        let impostor_image = render(&impostors, &impostor_scene)?;
        let point_image = render(&points, &point_scene)?;
        let (reference, coverage) = truth.render(device, queue, &camera, &lighting)?;
        let covered = |i: usize| coverage.normal_coverage[i].w > 0.0;
        let (mut x0, mut y0, mut x1, mut y1) = (u32::MAX, u32::MAX, 0, 0);
        for y in 0..size.1 {
            for x in 0..size.0 {
                if covered((y * size.0 + x) as usize) {
                    (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
                }
            }
        }
        if x0 > x1 {
            return Err(RenderError::InvalidInput(format!("at {diameter} px the pile is off screen")));
        }
        let grow = |lo: u32, hi: u32, side: u32| {
            let (lo, hi) = (lo.saturating_sub(4), (hi + 4).min(side - 1));
            let short = 16u32.saturating_sub(hi - lo + 1);
            let lo = lo.saturating_sub(short / 2 + short % 2);
            (lo, (lo + (hi - lo + 1).max(16) - 1).min(side - 1))
        };
        let ((x0, x1), (y0, y1)) = (grow(x0, x1, size.0), grow(y0, y1, size.1));
        let crop =
            |image: &image::RgbaImage| image::imageops::crop_imm(image, x0, y0, x1 - x0 + 1, y1 - y0 + 1).to_image();
        let reference = crop(&reference);
        let points = compare_images(&reference, &crop(&point_image)).map_err(|e| error(&e))?;
        let impostors = compare_images(&reference, &crop(&impostor_image)).map_err(|e| error(&e))?;
        rows.push(PointRow { diameter, points, impostors, pixels: (x1 - x0 + 1) * (y1 - y0 + 1) });
    }
    let threshold = threshold_of(&rows, budget);
    Ok(PointThreshold { rows, threshold, budget })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(diameter: f32, ssim: f64) -> PointRow {
        let e = |ssim| ImageError { ssim, rmse: 0.0 };
        PointRow { diameter, points: e(ssim), impostors: e(1.0), pixels: 256 }
    }

    #[test]
    fn the_threshold_is_the_last_diameter_of_the_leading_run_within_budget() {
        let rows = [row(1.0, 0.99), row(2.0, 0.97), row(3.0, 0.9), row(4.0, 0.99)];
        assert_eq!(threshold_of(&rows, 0.05), Some(2.0));
        assert_eq!(threshold_of(&rows, 0.2), Some(4.0));
        assert_eq!(threshold_of(&rows, 0.001), None);
        assert_eq!(threshold_of(&[], 0.05), None);
    }
}
