//! Baking an impostor: the `N = 2n²` orthographic views of a grain (§4.1 "Precomputation",
//! §4.2: "precomputed views are rendered using orthographic cameras"), each `p × p`
//! texels, rendered by the mesh G-buffer pass of [`crate::mesh_gbuffer`] with `s × s`
//! supersampling, reduced into the atlas layout, then given premultiplied-alpha mip
//! chains ([`crate::mips`]) and quantized into [`crate::scene::ATLAS_LAYERS`].
//!
//! View `i` uses the camera of [`view_camera`]: the grain's centre (its
//! [`grain_mesh::GrainBounds::centre`]) at the origin, looking along `-ω_i` with the
//! [`octahedral_map::ViewFrame`] of `ω_i`, extent `R` (the outer radius), depth range
//! `±R`. The GPU work is batched: many views per submission, one array layer and one
//! render pass per view, then one reduction dispatch for the whole batch.

use std::fmt;
use std::io::IsTerminal;

use glam::{Quat, Vec3};
use grain_mesh::GrainMesh;
use octahedral_map::{OctahedralViews, ViewFrame};

use crate::atlas::{AtlasImage, AtlasTexel, ImpostorAtlas};
use crate::gpu_util::GpuError;
use crate::mesh_gbuffer::{FineTargets, GpuMesh, MeshGbufferPass, fine_size};
use crate::scene::{CameraUniforms, GrainInstance};

/// The smallest supersampling factor the baker accepts (2 × 2 samples per texel).
pub const MIN_BAKE_SUPERSAMPLING: u32 = 2;

/// Bytes of the supersampled targets per fine texel: four G-buffer layers and the depth
/// buffer.
const FINE_BYTES_PER_TEXEL: u64 = 8 + 4 + 4 + 4 + 4;

/// The most memory the supersampled targets of one batch may take.
const BATCH_TARGET_BYTES: u64 = 256 << 20;

/// Whether to show the progress bar.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Progress {
    /// On stderr when stderr is a terminal.
    #[default]
    Auto,
    /// Never.
    Hidden,
}

/// What to bake.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct BakeSettings {
    /// `n`: views per edge of the octahedral layout (`N = 2n²` views).
    pub subdivisions: u32,
    /// `p`: texels per side of each view, a power of two.
    pub texels: u32,
    /// `s`: supersampling factor per axis, at least [`MIN_BAKE_SUPERSAMPLING`].
    pub supersampling: u32,
    /// The progress bar.
    pub progress: Progress,
}

impl BakeSettings {
    /// `n` views per edge, `p` texels, `2 × 2` supersampling, automatic progress bar.
    pub fn new(subdivisions: u32, texels: u32) -> Self {
        Self { subdivisions, texels, supersampling: MIN_BAKE_SUPERSAMPLING, progress: Progress::Auto }
    }
}

/// Why a bake failed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum BakeError {
    /// The settings are invalid (the message says which and why).
    InvalidSettings(String),
    /// The GPU work failed.
    Gpu(GpuError),
}

impl fmt::Display for BakeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::InvalidSettings(message) => write!(f, "invalid bake settings: {message}"),
            Self::Gpu(error) => write!(f, "bake failed on the GPU: {error}"),
        }
    }
}

impl std::error::Error for BakeError {}

impl From<GpuError> for BakeError {
    fn from(error: GpuError) -> Self {
        Self::Gpu(error)
    }
}

/// The orthographic camera of view `index` of `views` for a grain of outer radius
/// `extent` centred at the origin, rendering `texels × texels`; `None` for an index out
/// of range or a non-positive extent.
pub fn view_camera(views: OctahedralViews, index: u32, extent: f32, texels: u32) -> Option<CameraUniforms> {
    let frame = ViewFrame::from_direction(views.view_direction(index)?)?;
    CameraUniforms::orthographic(Vec3::ZERO, -frame.direction, frame.up, extent, extent, (texels, texels))
}

/// Where a bake's wall-clock time went.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BakeTimings {
    /// Rendering, reduction and readback of every view (GPU work and waiting for it).
    pub views_seconds: f64,
    /// Mip chains, dilation and quantization on the CPU.
    pub mips_seconds: f64,
}

/// The baker: the mesh G-buffer pipelines, compiled once.
#[derive(Debug)]
pub struct Baker {
    pass: MeshGbufferPass,
}

impl Baker {
    /// Compiles the pipelines.
    pub fn new(device: &wgpu::Device) -> Result<Self, GpuError> {
        Ok(Self { pass: MeshGbufferPass::new(device)? })
    }

    /// How many views one submission renders for `settings` on `device`: bounded by the
    /// array-layer limit, the storage-buffer binding limit and a batch of at most 256 MiB of
    /// fine texels.
    pub fn batch_views(device: &wgpu::Device, settings: &BakeSettings) -> u32 {
        let limits = device.limits();
        let fine = u64::from(settings.texels * settings.supersampling);
        let by_memory = BATCH_TARGET_BYTES / (fine * fine * FINE_BYTES_PER_TEXEL).max(1);
        let output_per_view = u64::from(settings.texels).pow(2) * 64;
        let by_binding = limits.max_storage_buffer_binding_size.min(limits.max_buffer_size) / output_per_view.max(1);
        let views = u64::from(settings.subdivisions).pow(2) * 2;
        by_memory.min(by_binding).min(u64::from(limits.max_texture_array_layers)).min(views).max(1) as u32
    }

    /// Bakes `mesh` with `settings`.
    pub fn bake(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        mesh: &GrainMesh,
        settings: &BakeSettings,
    ) -> Result<ImpostorAtlas, BakeError> {
        self.bake_timed(device, queue, mesh, settings).map(|(atlas, _)| atlas)
    }

    /// [`bake`](Self::bake), also returning where the time went.
    pub fn bake_timed(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        mesh: &GrainMesh,
        settings: &BakeSettings,
    ) -> Result<(ImpostorAtlas, BakeTimings), BakeError> {
        let start = std::time::Instant::now();
        let invalid = |message: String| Err(BakeError::InvalidSettings(message));
        let Some(views) = OctahedralViews::new(settings.subdivisions) else {
            return invalid(format!("view subdivisions n = {}", settings.subdivisions));
        };
        let p = settings.texels;
        if !p.is_power_of_two() {
            return invalid(format!("texels per side p = {p} is not a power of two (needed for the mip chain)"));
        }
        if settings.supersampling < MIN_BAKE_SUPERSAMPLING {
            return invalid(format!("supersampling {} < {MIN_BAKE_SUPERSAMPLING}", settings.supersampling));
        }
        let bounds = mesh.bounds();
        let (outer_radius, inner_radius) = (bounds.outer_radius, bounds.inner_radius);
        let fine_side = fine_size(settings.supersampling, (p, p))?;
        let batch = Self::batch_views(device, settings);
        let fine = FineTargets::new(device, fine_side, batch)?;
        let gpu_mesh = GpuMesh::upload(device, mesh)?;
        let instance = GrainInstance::new(-bounds.centre, 1.0, Quat::IDENTITY);
        let view_count = views.view_count();
        let bar = match settings.progress {
            Progress::Auto if std::io::stderr().is_terminal() => indicatif::ProgressBar::new(u64::from(view_count)),
            _ => indicatif::ProgressBar::hidden(),
        };
        bar.set_message("baking views");
        let mut texels = Vec::with_capacity(view_count as usize * (p * p) as usize);
        let mut first = 0;
        while first < view_count {
            let count = batch.min(view_count - first);
            let cameras = (first..first + count)
                .map(|index| view_camera(views, index, outer_radius, p))
                .collect::<Option<Vec<_>>>()
                .ok_or_else(|| {
                    BakeError::InvalidSettings(format!("outer radius R = {outer_radius} gives no camera"))
                })?;
            let values = self.pass.render_atlas_views(
                device,
                queue,
                &gpu_mesh,
                &cameras,
                &instance,
                (settings.supersampling, p, outer_radius),
                &fine,
            )?;
            texels.extend(values.chunks_exact(4).map(|t| AtlasTexel {
                normal: t[0].truncate(),
                albedo: t[1].truncate(),
                roughness: t[2].x,
                metallic: t[2].y,
                depth: t[3].x,
                alpha: t[0].w,
            }));
            first += count;
            bar.set_position(u64::from(first));
        }
        let views_seconds = start.elapsed().as_secs_f64();
        bar.set_message("mip chains");
        let level0 = AtlasImage { side: p, views: view_count, texels };
        let atlas = ImpostorAtlas::from_level0(views, outer_radius, inner_radius, level0)
            .ok_or_else(|| BakeError::InvalidSettings(format!("radii r = {inner_radius}, R = {outer_radius}")));
        bar.finish_and_clear();
        let timings = BakeTimings { views_seconds, mips_seconds: start.elapsed().as_secs_f64() - views_seconds };
        Ok((atlas?, timings))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn view_cameras_exist_for_every_view_and_not_beyond() {
        let views = OctahedralViews::new(3).unwrap();
        for index in 0..views.view_count() {
            assert!(view_camera(views, index, 1.0, 32).is_some(), "view {index}");
        }
        assert!(view_camera(views, views.view_count(), 1.0, 32).is_none());
        assert!(view_camera(views, 0, 0.0, 32).is_none());
    }
}
