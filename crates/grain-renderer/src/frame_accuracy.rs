//! Whole-frame accuracy and popping of the multiscale render along a camera path (a dolly),
//! against the mesh reference ([`MeshReference`]: every grain a mesh, `4 × 4` supersampled).
//!
//! # Per frame
//!
//! The renderer draws the frames **in order** (its hysteresis and two-phase culling see the
//! previous frame, as in an animation). Each multiscale image `M_k` is compared with the
//! reference `R_k` by the field's metrics (`image-metrics`): the standard SSIM (Wang et al.
//! 2004, 11 × 11 Gaussian window, σ = 1.5, on luma) and the mean ꟻLIP error (Andersson et al.
//! 2020); and by the mean absolute error `E_k = mean |M_k − R_k|` over the sRGB channels in
//! `[0, 1]`, the unit of the popping measure.
//!
//! # Popping
//!
//! A pop is a change of the image that the scene does not make: the frame-to-frame change of
//! the multiscale render beyond that of the reference, `P_k = mean |M_k − M_(k−1)| −
//! mean |R_k − R_(k−1)|`. Per pixel, `|M_k − M_(k−1)| ≤ |M_k − R_k| + |R_k − R_(k−1)| +
//! |R_(k−1) − M_(k−1)|`, so `P_k ≤ E_k + E_(k−1)`: the bound is reached when the error of
//! frame `k` has nothing in common with that of frame `k − 1` — every pixel's error replaced
//! at once, a full pop. When the camera moves little between frames and no grain changes
//! tier, the two errors are nearly the same field and `P_k` is near 0. A frame **spikes**
//! when `P_k > (E_k + E_(k−1)) / 2`: more than half of a full pop ([`spikes`]).

use gpu_harness::Gpu;
use grain_impostor::scene::ShadingUniforms;
use image::RgbaImage;

use crate::error::RenderError;
use crate::impostor_tier::TierSettings;
use crate::mesh_reference::MeshReference;
use crate::renderer::{SceneBindings, StackingCamera, StackingRenderer};

/// One frame's figures.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameAccuracy {
    /// The caller's label of the frame (e.g. the projected diameter of a grain, pixels).
    pub label: f32,
    /// Grains per list of the splitter (mesh, impostor occluders, other impostors, points).
    pub lists: [u32; 4],
    /// Standard SSIM of the multiscale image against the reference (1 = identical).
    pub ssim: f64,
    /// Mean ꟻLIP error against the reference (0 = identical).
    pub flip: f64,
    /// `E_k`: the mean absolute error against the reference, sRGB channels in `[0, 1]`.
    pub error: f64,
    /// `mean |M_k − M_(k−1)|` (none for the first frame).
    pub change: Option<f64>,
    /// `mean |R_k − R_(k−1)|` (none for the first frame).
    pub reference_change: Option<f64>,
}

impl FrameAccuracy {
    /// `P_k`, the change beyond the reference's (module docs); none for the first frame.
    pub fn popping(&self) -> Option<f64> {
        Some(self.change? - self.reference_change?)
    }
}

/// One frame's images.
#[derive(Clone, Debug)]
pub struct FrameImages {
    /// The multiscale render.
    pub render: RgbaImage,
    /// The mesh reference.
    pub reference: RgbaImage,
    /// The ꟻLIP error map in nv-flip's magma colours.
    pub flip_map: image::RgbImage,
}

/// Mean absolute difference of the RGB channels of two images of one size, in `[0, 1]`.
pub fn mean_absolute_difference(a: &RgbaImage, b: &RgbaImage) -> f64 {
    let sum: u64 =
        a.pixels().zip(b.pixels()).map(|(p, q)| (0..3).map(|c| u64::from(p[c].abs_diff(q[c]))).sum::<u64>()).sum();
    sum as f64 / (3.0 * 255.0 * a.pixels().len().max(1) as f64)
}

/// Renders `cameras` in order with `renderer` (scene `scene`, tier `settings`) and with
/// `truth` on `gpu`, and measures every frame (module docs); `on_frame` receives each frame's figures
/// and images as they are made (to write them), `labels[k]` labels frame `k`.
#[allow(clippy::too_many_arguments)]
pub fn measure_frames(
    gpu: &Gpu,
    renderer: &StackingRenderer,
    scene: &SceneBindings,
    truth: &MeshReference,
    cameras: &[(StackingCamera, f32)],
    lighting: &ShadingUniforms,
    settings: TierSettings,
    mut on_frame: impl FnMut(usize, &FrameAccuracy, &FrameImages) -> Result<(), RenderError>,
) -> Result<Vec<FrameAccuracy>, RenderError> {
    let (device, queue) = (&gpu.device, &gpu.queue);
    let metric = |e: image_metrics::MetricError| RenderError::InvalidInput(e.to_string());
    let mut frames = Vec::with_capacity(cameras.len());
    let mut previous: Option<(RgbaImage, RgbaImage)> = None;
    for (k, (camera, label)) in cameras.iter().enumerate() {
        let mut encoder = device.create_command_encoder(&Default::default());
        renderer.encode(queue, &mut encoder, scene, camera, lighting, settings)?;
        queue.submit([encoder.finish()]);
        let render = grain_impostor::shading::read_image(device, queue, renderer.image())
            .map_err(|e| RenderError::InvalidInput(e.to_string()))?;
        let counters = renderer.read_counters(gpu)?;
        let (reference, _) = truth.render(device, queue, camera, lighting)?;
        let ssim = image_metrics::ssim(&reference, &render).map_err(metric)?;
        let flip = image_metrics::flip(&reference, &render).map_err(metric)?;
        let (change, reference_change) = match &previous {
            Some((m, r)) => (Some(mean_absolute_difference(&render, m)), Some(mean_absolute_difference(&reference, r))),
            None => (None, None),
        };
        let frame = FrameAccuracy {
            label: *label,
            lists: counters.count,
            ssim: ssim.mean,
            flip: flip.mean,
            error: mean_absolute_difference(&render, &reference),
            change,
            reference_change,
        };
        let images = FrameImages { render, reference, flip_map: image_metrics::flip_magma(&flip.map) };
        on_frame(k, &frame, &images)?;
        frames.push(frame);
        previous = Some((images.render, images.reference));
    }
    Ok(frames)
}

/// The frames whose popping exceeds half of a full pop, `P_k > (E_k + E_(k−1)) / 2`
/// (module docs).
pub fn spikes(frames: &[FrameAccuracy]) -> Vec<usize> {
    (1..frames.len())
        .filter(|&k| frames[k].popping().is_some_and(|p| p > 0.5 * (frames[k].error + frames[k - 1].error)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(error: f64, change: f64, reference_change: f64) -> FrameAccuracy {
        FrameAccuracy {
            label: 0.0,
            lists: [0; 4],
            ssim: 1.0,
            flip: 0.0,
            error,
            change: Some(change),
            reference_change: Some(reference_change),
        }
    }

    #[test]
    fn a_spike_is_more_than_half_of_a_full_pop() {
        let first = FrameAccuracy { change: None, reference_change: None, ..frame(0.02, 0.0, 0.0) };
        // Frame 1 changes 0.01 beyond the reference (≤ half of 0.02 + 0.02); frame 2 0.03.
        let frames = [first, frame(0.02, 0.05, 0.04), frame(0.02, 0.08, 0.05)];
        assert_eq!(frames[0].popping(), None);
        assert_eq!(spikes(&frames), vec![2]);
    }

    #[test]
    fn the_mean_absolute_difference_is_in_unit_range() {
        let black = RgbaImage::from_pixel(4, 4, image::Rgba([0, 0, 0, 255]));
        let white = RgbaImage::from_pixel(4, 4, image::Rgba([255, 255, 255, 0]));
        assert_eq!(mean_absolute_difference(&black, &white), 1.0);
        assert_eq!(mean_absolute_difference(&black, &black), 0.0);
    }
}
