//! The accuracy sweep: for each grain, atlas size `(n, p)`, sampling mode and screen size,
//! the impostor render of a [`ComparisonScene`] against the mesh render of the same scene,
//! both through the same deferred shading.

use std::fmt;

use glam::{Quat, Vec3, Vec4};
use grain_mesh::GrainMesh;
use image::RgbaImage;
use octahedral_map::sampling::{ImpostorSampler, SamplingMode, ViewLayout, ViewSelection};
use wgpu::util::DeviceExt;

use super::metrics::{ImageError, MetricError, compare_images};
use super::timing::{SweepTiming, fastest_ms};
use super::view_set::{ComparisonScene, fibonacci_directions};
use crate::atlas::ImpostorAtlas;
use crate::atlas_gpu::AtlasTextures;
use crate::bake::{BakeError, BakeSettings, Baker, Progress};
use crate::cloud::{AtlasBinding, CloudError, CloudFrame, CloudSettings, GBufferBinding, ImpostorCloudPass};
use crate::gpu_util::GpuError;
use crate::mesh_gbuffer::{GpuMesh, MeshGbufferPass, ScreenGbuffer};
use crate::scene::{GrainInstance, ShadingUniforms};
use crate::shading::{ShadingPass, read_image};

/// Supersampling of the mesh reference render (per axis).
pub const REFERENCE_SUPERSAMPLING: u32 = 4;

/// The light of every comparison: from the upper right front, white, with a dim ambient
/// term, on a dark grey background.
pub fn comparison_lighting() -> ShadingUniforms {
    // The direction is a non-zero constant, so `new` cannot fail; the fallback is never used.
    ShadingUniforms::new(Vec3::new(0.5, 0.7, 1.0), Vec3::splat(2.5), Vec3::splat(0.12), Vec3::splat(0.04)).unwrap_or(
        ShadingUniforms { light_direction: Vec4::Z, light_colour: Vec4::ONE, ambient: Vec4::ZERO, background: Vec4::W },
    )
}

/// What to measure.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepSettings {
    /// The values of `n` (views per edge).
    pub subdivisions: Vec<u32>,
    /// The values of `p` (texels per view side).
    pub texels: Vec<u32>,
    /// The sampling modes.
    pub modes: Vec<SamplingMode>,
    /// The atlas layouts: all `2n²` views, and/or each distinct view once.
    pub layouts: Vec<ViewLayout>,
    /// How many view directions (grains in the comparison grid).
    pub view_count: u32,
    /// On-screen diameters of the grains' outer spheres, in pixels.
    pub apparent_diameters: Vec<f32>,
    /// Whether each impostor render's cloud pass is timed, and how ([`SweepRow::cloud_ms`]);
    /// `None`: untimed.
    pub timing: Option<SweepTiming>,
}

impl SweepSettings {
    /// The full sweep: `n ∈ {4, 6, 8, 10, 12}`, `p ∈ {32, 64, 128}`, every sampling
    /// mode, both layouts, 64 views, grains 32 and 64 pixels wide; untimed.
    pub fn full() -> Self {
        Self {
            subdivisions: vec![4, 6, 8, 10, 12],
            texels: vec![32, 64, 128],
            modes: SamplingMode::ALL.to_vec(),
            layouts: vec![ViewLayout::Listing1, ViewLayout::Compact],
            view_count: 64,
            apparent_diameters: vec![32.0, 64.0],
            timing: None,
        }
    }
}

/// One measurement.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepRow {
    /// The grain's name.
    pub grain: String,
    /// `n`.
    pub subdivisions: u32,
    /// `p`.
    pub texels: u32,
    /// The sampling mode.
    pub mode: SamplingMode,
    /// The atlas layout.
    pub layout: ViewLayout,
    /// On-screen diameter of the outer sphere in pixels.
    pub apparent_diameter: f32,
    /// SSIM and RMSE against the mesh.
    pub error: ImageError,
    /// GPU bytes of the atlas in `layout` (full mips).
    pub atlas_bytes: u64,
    /// The fastest timed cloud pass drawing the comparison scene, milliseconds
    /// ([`SweepSettings::timing`]; `None` when untimed).
    pub cloud_ms: Option<f64>,
}

/// Why the sweep stopped.
#[derive(Clone, Debug, PartialEq)]
pub enum SweepError {
    /// The settings or a grain cannot be measured (the message says why).
    Invalid(String),
    /// GPU work failed.
    Gpu(GpuError),
    /// Baking failed.
    Bake(BakeError),
    /// The cloud pass failed.
    Cloud(CloudError),
    /// Comparing images failed.
    Metric(MetricError),
}

impl fmt::Display for SweepError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Invalid(message) => write!(f, "accuracy sweep: {message}"),
            Self::Gpu(e) => write!(f, "accuracy sweep: {e}"),
            Self::Bake(e) => write!(f, "accuracy sweep: {e}"),
            Self::Cloud(e) => write!(f, "accuracy sweep: {e}"),
            Self::Metric(e) => write!(f, "accuracy sweep: {e}"),
        }
    }
}

impl std::error::Error for SweepError {}

impl From<GpuError> for SweepError {
    fn from(e: GpuError) -> Self {
        Self::Gpu(e)
    }
}
impl From<BakeError> for SweepError {
    fn from(e: BakeError) -> Self {
        Self::Bake(e)
    }
}
impl From<CloudError> for SweepError {
    fn from(e: CloudError) -> Self {
        Self::Cloud(e)
    }
}
impl From<MetricError> for SweepError {
    fn from(e: MetricError) -> Self {
        Self::Metric(e)
    }
}

/// The compiled passes of the experiment.
#[derive(Debug)]
pub struct AccuracySweep {
    baker: Baker,
    mesh_pass: MeshGbufferPass,
    cloud_pass: ImpostorCloudPass,
    shading: ShadingPass,
    lighting: ShadingUniforms,
}

impl AccuracySweep {
    /// Compiles every pass.
    pub fn new(device: &wgpu::Device) -> Result<Self, SweepError> {
        Ok(Self {
            baker: Baker::new(device)?,
            mesh_pass: MeshGbufferPass::new(device)?,
            cloud_pass: ImpostorCloudPass::new(device)?,
            shading: ShadingPass::new(device)?,
            lighting: comparison_lighting(),
        })
    }

    /// The scene of one measurement for `mesh` at `apparent_diameter` pixels.
    pub fn scene(mesh: &GrainMesh, view_count: u32, apparent_diameter: f32) -> Result<ComparisonScene, SweepError> {
        ComparisonScene::new(&fibonacci_directions(view_count), mesh.bounds().outer_radius, apparent_diameter)
            .ok_or_else(|| SweepError::Invalid(format!("no scene for {view_count} views at {apparent_diameter} px")))
    }

    fn shade(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        scene: &ComparisonScene,
        gbuffer: &ScreenGbuffer,
    ) -> Result<RgbaImage, SweepError> {
        let target = self.shading.create_target(device, gbuffer)?;
        self.shading.shade(device, queue, &scene.camera, &self.lighting, gbuffer, &target)?;
        Ok(read_image(device, queue, &target)?)
    }

    /// The mesh rendered into `scene` (the ground truth), with
    /// [`REFERENCE_SUPERSAMPLING`]² samples per pixel.
    pub fn reference(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        mesh: &GrainMesh,
        scene: &ComparisonScene,
    ) -> Result<RgbaImage, SweepError> {
        let gpu_mesh = GpuMesh::upload(device, mesh)?;
        // The scene places each grain's centre (the atlas origin); the mesh is modelled around
        // `bounds.centre`, so shift it by the rotated, scaled centre.
        let centre = mesh.bounds().centre;
        let instances: Vec<GrainInstance> = scene
            .instances
            .iter()
            .map(|grain| {
                let rotation = Quat::from_vec4(grain.rotation);
                let scale = grain.centre_scale.w;
                GrainInstance::new(grain.centre_scale.truncate() - rotation * (scale * centre), scale, rotation)
            })
            .collect();
        let gbuffer = ScreenGbuffer::new(device, scene.size)?;
        self.mesh_pass.render(
            device,
            queue,
            &gpu_mesh,
            &scene.camera,
            &instances,
            REFERENCE_SUPERSAMPLING,
            &gbuffer,
        )?;
        self.shade(device, queue, scene, &gbuffer)
    }

    /// The impostor of `atlas` (uploaded as `textures`) rendered into `scene` with `mode`.
    pub fn impostor(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        atlas: &ImpostorAtlas,
        textures: &AtlasTextures,
        scene: &ComparisonScene,
        mode: SamplingMode,
    ) -> Result<RgbaImage, SweepError> {
        Ok(self.impostor_timed(device, queue, atlas, textures, scene, mode, None)?.0)
    }

    /// [`Self::impostor`], and with `timing` the fastest of its timed cloud passes (the
    /// passes that draw the G-buffer, without the shading), milliseconds.
    #[allow(clippy::too_many_arguments)]
    pub fn impostor_timed(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        atlas: &ImpostorAtlas,
        textures: &AtlasTextures,
        scene: &ComparisonScene,
        mode: SamplingMode,
        timing: Option<SweepTiming>,
    ) -> Result<(RgbaImage, Option<f64>), SweepError> {
        let sampler = ImpostorSampler::new(
            atlas.views,
            atlas.outer_radius,
            atlas.inner_radius,
            mode,
            atlas.layout,
            ViewSelection::PerGrainFromEye,
        )
        .ok_or_else(|| {
            SweepError::Invalid(format!(
                "no sampler for radii r = {}, R = {} (needs 0 < r ≤ R)",
                atlas.inner_radius, atlas.outer_radius
            ))
        })?;
        let instances = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("comparison grains"),
            contents: bytemuck::cast_slice(&scene.instances),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let gbuffer = ScreenGbuffer::new(device, scene.size)?;
        let frame = CloudFrame {
            camera: &scene.camera,
            sampling: sampler.uniforms(),
            instances: &instances,
            grain_count: scene.instances.len() as u32,
            settings: CloudSettings::default(),
        };
        let binding = AtlasBinding {
            normal_alpha: &textures.views[0],
            albedo_alpha: &textures.views[1],
            material_alpha: &textures.views[2],
            depth_alpha: &textures.views[3],
            sampler: &textures.sampler,
            texels: atlas.texels,
            layers: atlas.layer_count(),
        };
        let [normal_coverage, albedo, material, depth] = &gbuffer.views;
        let targets = GBufferBinding { normal_coverage, albedo, material, depth };
        let cloud_ms = match timing {
            Some(timing) => Some(fastest_ms(device, queue, timing, |encoder, timestamps| {
                self.cloud_pass.encode(device, encoder, &frame, &binding, &targets, timestamps)
            })?),
            None => None,
        };
        let mut encoder =
            device.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some("impostor cloud") });
        self.cloud_pass.encode(device, &mut encoder, &frame, &binding, &targets, None)?;
        queue.submit([encoder.finish()]);
        Ok((self.shade(device, queue, scene, &gbuffer)?, cloud_ms))
    }

    /// Runs the sweep over `grains`, calling `on_row` after each measurement (for progress
    /// output) and returning every row.
    pub fn run(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        grains: &[(String, GrainMesh)],
        settings: &SweepSettings,
        mut on_row: impl FnMut(&SweepRow),
    ) -> Result<Vec<SweepRow>, SweepError> {
        let mut rows = Vec::new();
        for (name, mesh) in grains {
            let scenes = settings
                .apparent_diameters
                .iter()
                .map(|&d| Self::scene(mesh, settings.view_count, d))
                .collect::<Result<Vec<_>, _>>()?;
            let references =
                scenes.iter().map(|s| self.reference(device, queue, mesh, s)).collect::<Result<Vec<_>, _>>()?;
            for &n in &settings.subdivisions {
                for &p in &settings.texels {
                    let bake = BakeSettings { progress: Progress::Hidden, ..BakeSettings::new(n, p) };
                    let paper_atlas = self.baker.bake(device, queue, mesh, &bake)?;
                    for &layout in &settings.layouts {
                        let atlas = match layout {
                            ViewLayout::Listing1 => paper_atlas.clone(),
                            ViewLayout::Compact => paper_atlas.to_compact(),
                        };
                        let textures = AtlasTextures::upload(device, queue, &atlas)?;
                        for (scene, reference) in scenes.iter().zip(&references) {
                            for &mode in &settings.modes {
                                let (render, cloud_ms) = self.impostor_timed(
                                    device,
                                    queue,
                                    &atlas,
                                    &textures,
                                    scene,
                                    mode,
                                    settings.timing,
                                )?;
                                let row = SweepRow {
                                    grain: name.clone(),
                                    subdivisions: n,
                                    texels: p,
                                    mode,
                                    layout,
                                    apparent_diameter: scene.apparent_diameter,
                                    error: compare_images(reference, &render)?,
                                    atlas_bytes: atlas.memory().gpu_bytes,
                                    cloud_ms,
                                };
                                on_row(&row);
                                rows.push(row);
                            }
                        }
                    }
                }
            }
        }
        Ok(rows)
    }
}
