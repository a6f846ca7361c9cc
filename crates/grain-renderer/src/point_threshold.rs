//! The point tier against the impostor tier, measured: at each projected diameter, the
//! image error and the GPU time of a pile drawn wholly as points and wholly as impostors,
//! both against the ground truth — the mesh, 4 × 4 supersampled. The rows feed the
//! committed tier table ([`crate::tier_selection`]) from which the point threshold is read.
//!
//! At each diameter `d` (the camera's distance puts a grain of scale 1 at `d` pixels
//! across) the pile is rendered three times from the same camera: the meshes (4 × 4
//! supersampled, `grain-impostor`'s mesh pass), every grain an impostor, every grain a point.
//! The images are cropped to the mesh render's covered rectangle (grown by 4 pixels, at least
//! 16 × 16) so that the background does not dilute the score, and each tier is compared with
//! the mesh by the field's metrics (`image-metrics`: mean ꟻLIP and the standard Gaussian
//! SSIM), and its coverage with the meshes' over the whole image ([`CoverageDifference`]: the
//! holes it opens, the pixels it adds). Each tier's time is the fastest of `frames` frames ([`crate::bench::time_frame`]:
//! GPU timestamps on a GPU, wall clock on a software adapter). Culling is off (a point pixel
//! averages the grains kept).

use glam::Vec3;
use gpu_harness::{Gpu, TimingSource};
use grain_impostor::atlas::ImpostorAtlas;
use grain_impostor::mesh_gbuffer::GbufferImage;
use grain_impostor::scene::GrainInstance;
use grain_splitter::OccluderMapKind;
use image::RgbaImage;

use crate::error::RenderError;
use crate::impostor_tier::{TierSettings, VisibilityKind};
use crate::mesh_reference::MeshReference;
use crate::renderer::{NO_POINT_TIER, RendererOptions, StackingCamera, StackingRenderer};

/// The vertical field of view of the measurement.
pub const MEASURE_FOV_Y: f32 = 0.6;

/// One tier's render at one diameter.
#[derive(Clone, Debug, PartialEq)]
pub struct TierRender {
    /// Mean ꟻLIP of the cropped image against the mesh's.
    pub flip: f64,
    /// One minus the mean (standard, Gaussian) SSIM of the cropped image against the mesh's.
    pub ssim_loss: f64,
    /// The tier's coverage against the meshes' over the whole image.
    pub coverage: CoverageDifference,
    /// The fastest frame, milliseconds.
    pub ms: f64,
    /// The cropped image.
    pub image: RgbaImage,
}

/// Where a tier's coverage differs from the meshes' (their 4 × 4 supersampled coverage):
/// the holes a tier opens and the pixels it adds, counted over the whole image. Silhouette
/// pixels, which the meshes cover in part, are in neither count.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CoverageDifference {
    /// Pixels whose every sample a mesh covers.
    pub mesh_covered: usize,
    /// Of those, the pixels the tier leaves empty (holes).
    pub uncovered: usize,
    /// Pixels no mesh sample covers that the tier covers.
    pub spurious: usize,
}

impl CoverageDifference {
    /// The counts for a tier's coverage `tier` (per pixel: covered or not) against the meshes'
    /// coverage fractions `mesh` (0 to 1 per pixel, the same pixels).
    pub fn of(mesh: impl IntoIterator<Item = f32>, tier: impl IntoIterator<Item = bool>) -> Self {
        let mut counts = Self::default();
        for (fraction, covered) in mesh.into_iter().zip(tier) {
            if fraction >= 1.0 {
                counts.mesh_covered += 1;
                counts.uncovered += usize::from(!covered);
            } else if fraction <= 0.0 {
                counts.spurious += usize::from(covered);
            }
        }
        counts
    }
}

/// One diameter of the measurement.
#[derive(Clone, Debug, PartialEq)]
pub struct PointRow {
    /// Projected diameter of a grain of scale 1, pixels.
    pub diameter: f32,
    /// Every grain a point.
    pub points: TierRender,
    /// Every grain an impostor.
    pub impostors: TierRender,
    /// The mesh's image (the truth), cropped.
    pub reference: RgbaImage,
}

impl PointRow {
    /// Pixels compared (the cropped rectangle).
    pub fn pixels(&self) -> u32 {
        self.reference.width() * self.reference.height()
    }
}

/// The measurement: one row per diameter, ascending, and how its times were taken.
#[derive(Clone, Debug, PartialEq)]
pub struct PointMeasurement {
    /// One row per diameter, ascending.
    pub rows: Vec<PointRow>,
    /// The clock of [`TierRender::ms`].
    pub timing: TimingSource,
}

/// Where the pile is seen from and how it is rendered.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeasureView {
    /// The pile's centre (the camera's target).
    pub target: Vec3,
    /// Toward the eye, from the target; not zero.
    pub direction: Vec3,
    /// The image, pixels.
    pub size: (u32, u32),
    /// Frames timed per tier and diameter (the fastest is kept); at least 1.
    pub frames: u32,
}

/// Measures the pile `grains` of `mesh` (atlas `atlas`) seen as `view` says at each of
/// `diameters` (ascending, positive).
pub fn measure(
    gpu: &Gpu,
    mesh: &grain_mesh::GrainMesh,
    atlas: &ImpostorAtlas,
    grains: &[GrainInstance],
    view: MeasureView,
    diameters: &[f32],
) -> Result<PointMeasurement, RenderError> {
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
    if view.frames == 0 {
        return Err(RenderError::InvalidSetting { field: "frames", reason: "at least one frame is timed".into() });
    }
    let (device, queue, size) = (&gpu.device, &gpu.queue, view.size);
    let error = |e: &dyn std::fmt::Display| RenderError::InvalidInput(e.to_string());
    let direction = view
        .direction
        .try_normalize()
        .ok_or_else(|| RenderError::InvalidInput(format!("view direction {}: must not be zero", view.direction)))?;
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
    let mut timing = TimingSource::WallClock;
    for &diameter in diameters {
        let distance = focal * 2.0 * atlas.outer_radius / diameter;
        let camera = StackingCamera::perspective(
            view.target + direction * distance,
            view.target,
            MEASURE_FOV_Y,
            size,
            (1e-3 * distance, 4.0 * distance),
        )?;
        let mut render = |renderer: &StackingRenderer, scene| -> Result<(RgbaImage, f64, GbufferImage), RenderError> {
            let mut fastest = f64::INFINITY;
            for _ in 0..view.frames {
                let times =
                    crate::bench::time_frame(gpu, renderer, scene, &camera, &lighting, TierSettings::default())?;
                (fastest, timing) = (fastest.min(times.total()), times.source);
            }
            let image = grain_impostor::shading::read_image(device, queue, renderer.image()).map_err(|e| error(&e))?;
            let gbuffer = renderer.gbuffer().read(device, queue).map_err(|e| error(&e))?;
            Ok((image, fastest, gbuffer))
        };
        let (impostor_image, impostor_ms, impostor_gbuffer) = render(&impostors, &impostor_scene)?;
        let (point_image, point_ms, point_gbuffer) = render(&points, &point_scene)?;
        let (reference, coverage) = truth.render(device, queue, &camera, &lighting)?;
        let coverage_of = |tier: &GbufferImage| {
            CoverageDifference::of(
                coverage.normal_coverage.iter().map(|n| n.w),
                tier.normal_coverage.iter().map(|n| n.w > 0.0),
            )
        };
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
        let crop = |image: &RgbaImage| image::imageops::crop_imm(image, x0, y0, x1 - x0 + 1, y1 - y0 + 1).to_image();
        let reference = crop(&reference);
        let tier = |image: &RgbaImage, ms: f64, coverage: CoverageDifference| -> Result<TierRender, RenderError> {
            let image = crop(image);
            let flip = image_metrics::flip(&reference, &image).map_err(|e| error(&e))?.mean;
            let ssim_loss = 1.0 - image_metrics::ssim(&reference, &image).map_err(|e| error(&e))?.mean;
            Ok(TierRender { flip, ssim_loss, coverage, ms, image })
        };
        let points = tier(&point_image, point_ms, coverage_of(&point_gbuffer))?;
        let impostors = tier(&impostor_image, impostor_ms, coverage_of(&impostor_gbuffer))?;
        rows.push(PointRow { diameter, points, impostors, reference });
    }
    Ok(PointMeasurement { rows, timing })
}

#[cfg(test)]
mod tests {
    use super::CoverageDifference;

    #[test]
    fn coverage_counts_holes_and_additions_but_not_silhouettes() {
        // Wholly covered: kept, hole; empty: added, kept empty; silhouette (0.5): in neither count.
        let mesh = [1.0, 1.0, 0.0, 0.0, 0.5, 0.5];
        let tier = [true, false, true, false, true, false];
        let counts = CoverageDifference::of(mesh, tier);
        assert_eq!(counts, CoverageDifference { mesh_covered: 2, uncovered: 1, spurious: 1 });
        assert_eq!(CoverageDifference::of([], []), CoverageDifference::default());
    }
}
