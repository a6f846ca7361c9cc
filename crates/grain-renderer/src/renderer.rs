//! [`StackingRenderer`]: the splitter, the mesh tier, the impostor tier and deferred shading
//! of one grain type, built once and encoded per frame with no CPU readback (§3, Fig. 2:
//! ① split, ② meshes, ③ impostors, ④ points, drawn by the impostor tier's visibility buffer).

use glam::{Vec3, Vec4};
use grain_impostor::atlas::ImpostorAtlas;
use grain_impostor::atlas_gpu::AtlasTextures;
use grain_impostor::cloud::{AtlasBinding, GBufferBinding};
use grain_impostor::mesh_gbuffer::ScreenGbuffer;
use grain_impostor::scene::{CameraUniforms, GrainInstance, ShadingUniforms};
use grain_impostor::shading::{ShadingBindings, ShadingPass};
use grain_splitter::{
    GrainSplitter, ListOrder, OccluderMapKind, SplitBindings, SplitCamera, SplitCounters, SplitSettings,
    SplitterOptions, TierThresholds,
};
use octahedral_map::{ImpostorSampler, ImpostorSamplingUniforms, SamplingMode, ViewSelection};

use crate::error::RenderError;
use crate::impostor_tier::{ImpostorTier, TierBindings, TierFrame, TierSettings, VisibilityKind};
use crate::inputs::ListInputs;
use crate::mesh_tier::{MeshTier, MeshTierBindings};

/// The light of the pile renders (`cargo xtask bench-gpu stackings`, the point threshold):
/// from the upper right front, white, a dim ambient term, a dark grey background.
pub fn pile_lighting() -> ShadingUniforms {
    // A non-zero constant direction: `new` cannot fail; the fallback is never used.
    ShadingUniforms::new(Vec3::new(0.4, 1.0, 0.6), Vec3::splat(2.6), Vec3::splat(0.25), Vec3::splat(0.1)).unwrap_or(
        ShadingUniforms { light_direction: Vec4::Y, light_colour: Vec4::ONE, ambient: Vec4::ZERO, background: Vec4::W },
    )
}

/// A point threshold no grain on screen is below: no grain goes to the point list.
pub const NO_POINT_TIER: f32 = 1e-6;

/// What a renderer is built for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RendererOptions {
    /// Viewport in pixels.
    pub size: (u32, u32),
    /// The most grains a scene may hold.
    pub capacity: u32,
    /// Projected diameter (pixels) above which a grain is a mesh: the measured impostor
    /// table's (`TierThresholds::from_impostor_table`), never a distance.
    pub mesh_above: f32,
    /// Projected diameter (pixels) below which a grain is a point ([`NO_POINT_TIER`]: none
    /// are): measured by [`crate::point_threshold::measure`], never a distance.
    pub point_below: f32,
    /// Hysteresis band (≥ 1) around both thresholds.
    pub band: f32,
    /// The occluder map's atomics.
    pub occluder_map: OccluderMapKind,
    /// The visibility buffer's atomics.
    pub visibility: VisibilityKind,
    /// Frustum, cone, Hi-Z and two-phase culling (all conservative: off only to compare).
    pub culling: bool,
    /// Visibility samples per pixel side of the impostor and point tiers (1: a pixel is
    /// covered or not at its centre; 2: fractional silhouettes, 4× the atlas evaluations;
    /// `crate::impostor_tier`, "Silhouettes").
    pub samples: u32,
}

/// One frame's camera, as the splitter and the tiers see it (the same matrices).
#[derive(Clone, Copy, Debug)]
pub struct StackingCamera {
    /// The splitter's form.
    pub split: SplitCamera,
    /// The raster and compute passes' form.
    pub uniforms: CameraUniforms,
}

impl StackingCamera {
    /// A perspective camera at `eye` looking at `target`, vertical field of view
    /// `fov_y_radians`, `size` pixels, depth range `near_far`.
    pub fn perspective(
        eye: Vec3,
        target: Vec3,
        fov_y_radians: f32,
        size: (u32, u32),
        near_far: (f32, f32),
    ) -> Result<Self, RenderError> {
        let split = SplitCamera::perspective(eye, target, Vec3::Y, fov_y_radians, size, near_far)
            .map_err(|e| RenderError::InvalidInput(e.to_string()))?;
        let uniforms = CameraUniforms::perspective(eye, target, Vec3::Y, fov_y_radians, size, near_far)
            .ok_or_else(|| RenderError::InvalidInput(format!("no camera at {eye} looking at {target}")))?;
        Ok(Self { split, uniforms })
    }
}

/// The stages of a frame, in order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// Occluder map, culling, tiers, lists (`grain-splitter`).
    Split,
    /// The mesh tier (clears the G-buffer).
    Meshes,
    /// The impostor tier, composited over the meshes.
    Impostors,
    /// Deferred shading of the G-buffer.
    Shading,
}

impl Stage {
    /// Every stage, in the order a frame runs them.
    pub const ALL: [Stage; 4] = [Stage::Split, Stage::Meshes, Stage::Impostors, Stage::Shading];

    /// Its name in tables and CSV.
    pub fn name(self) -> &'static str {
        match self {
            Stage::Split => "split",
            Stage::Meshes => "meshes",
            Stage::Impostors => "impostors",
            Stage::Shading => "shading",
        }
    }
}

/// A scene's grains on the GPU and every bind group that reads them.
pub struct SceneBindings {
    centres: wgpu::Buffer,
    instances: wgpu::Buffer,
    count: u32,
    split: SplitBindings,
    mesh: MeshTierBindings,
    impostor: TierBindings,
}

impl SceneBindings {
    /// Grains in the scene.
    pub fn count(&self) -> u32 {
        self.count
    }
}

/// The renderer of one grain type (mesh and atlas) at one viewport size.
pub struct StackingRenderer {
    options: RendererOptions,
    splitter: GrainSplitter,
    mesh_tier: MeshTier,
    impostor_tier: ImpostorTier,
    shading: ShadingPass,
    shading_bindings: ShadingBindings,
    gbuffer: ScreenGbuffer,
    image: wgpu::Texture,
    atlas: AtlasTextures,
    atlas_texels: u32,
    atlas_layers: u32,
    sampling: ImpostorSamplingUniforms,
}

fn gpu_error(e: impl std::fmt::Display) -> RenderError {
    RenderError::InvalidInput(e.to_string())
}

impl StackingRenderer {
    /// Builds every pipeline and buffer: the splitter for `mesh`'s `r` and
    /// `R`, the mesh tier, the impostor tier sampling `atlas` (mixed sampling, views chosen
    /// per grain), the G-buffer and the shaded image.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        mesh: &grain_mesh::GrainMesh,
        atlas: &ImpostorAtlas,
        options: RendererOptions,
    ) -> Result<Self, RenderError> {
        let limits = device.limits();
        let storage_limit = limits.max_storage_buffer_binding_size.min(limits.max_buffer_size);
        let instance_bytes = u64::from(options.capacity) * size_of::<GrainInstance>() as u64;
        if instance_bytes > storage_limit {
            return Err(RenderError::TooLarge {
                what: "grain instance bytes (capacity × instance size)",
                requested: instance_bytes,
                limit: storage_limit,
            });
        }
        let mesh_tier = MeshTier::new(device, options.size, mesh)?;
        let thresholds =
            TierThresholds::new(options.point_below, options.mesh_above, options.band).map_err(|e| match e {
                grain_splitter::SplitError::InvalidSetting { field, reason } => RenderError::InvalidSetting {
                    field: match field {
                        "band" => "band",
                        "point_below" => "point_below",
                        _ => "mesh_above",
                    },
                    reason,
                },
                other => gpu_error(other),
            })?;
        let bounds = mesh.bounds();
        let c = options.culling;
        let settings = SplitSettings {
            mesh_index_count: mesh_tier.index_count(),
            frustum_culling: c,
            cone_culling: c,
            hiz_culling: c,
            temporal_occluders: c,
            ..SplitSettings::new(bounds.occluder_radius(), atlas.outer_radius, thresholds)
        };
        let splitter = GrainSplitter::new(
            device,
            settings,
            SplitterOptions {
                capacity: options.capacity,
                size: options.size,
                occluder_map: options.occluder_map,
                order: ListOrder::Atomic,
            },
        )
        .map_err(gpu_error)?;
        let impostor_tier = ImpostorTier::with_samples(device, options.size, options.visibility, options.samples)?;
        let shading = ShadingPass::new(device).map_err(gpu_error)?;
        let gbuffer = ScreenGbuffer::new(device, options.size).map_err(gpu_error)?;
        let image = shading.create_target(device, &gbuffer).map_err(gpu_error)?;
        let shading_bindings = shading.bind(device, &gbuffer, &image).map_err(gpu_error)?;
        let sampler = ImpostorSampler::new(
            atlas.views,
            atlas.outer_radius,
            atlas.inner_radius,
            SamplingMode::Mixed,
            atlas.layout,
            ViewSelection::PerGrainFromEye,
        )
        .ok_or_else(|| {
            RenderError::InvalidInput(format!(
                "atlas radii r = {}, R = {}: a sampler needs 0 < r ≤ R",
                atlas.inner_radius, atlas.outer_radius
            ))
        })?;
        Ok(Self {
            options,
            splitter,
            mesh_tier,
            impostor_tier,
            shading,
            shading_bindings,
            gbuffer,
            image,
            atlas: AtlasTextures::upload(device, queue, atlas).map_err(gpu_error)?,
            atlas_texels: atlas.texels,
            atlas_layers: atlas.layer_count(),
            sampling: sampler.uniforms(),
        })
    }

    fn atlas_binding(&self) -> AtlasBinding<'_> {
        AtlasBinding {
            normal_alpha: &self.atlas.views[0],
            albedo_alpha: &self.atlas.views[1],
            material_alpha: &self.atlas.views[2],
            depth_alpha: &self.atlas.views[3],
            sampler: &self.atlas.sampler,
            texels: self.atlas_texels,
            layers: self.atlas_layers,
        }
    }

    /// Uploads `grains` (at most the capacity) and binds them to every pass.
    pub fn upload(&self, device: &wgpu::Device, grains: &[GrainInstance]) -> Result<SceneBindings, RenderError> {
        let count =
            u32::try_from(grains.len()).ok().filter(|&n| n > 0 && n <= self.options.capacity).ok_or_else(|| {
                RenderError::InvalidInput(format!("{} grains: need 1 to {}", grains.len(), self.options.capacity))
            })?;
        use wgpu::util::DeviceExt;
        let centres: Vec<Vec4> = grains.iter().map(|g| g.centre_scale).collect();
        let centres = GrainSplitter::upload_grains(device, &centres).map_err(gpu_error)?;
        let instances = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("grain instances"),
            contents: bytemuck::cast_slice(grains),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
        });
        let split = self.splitter.bind(device, &centres).map_err(gpu_error)?;
        let lists = ListInputs {
            instances: &instances,
            elements: self.splitter.elements(),
            counters: self.splitter.counters(),
            indirect: self.splitter.indirect(),
        };
        let mesh = self.mesh_tier.bind(device, &lists)?;
        let g = &self.gbuffer;
        let gbuffer = GBufferBinding {
            normal_coverage: &g.views[0],
            albedo: &g.views[1],
            material: &g.views[2],
            depth: &g.views[3],
        };
        let impostor = self.impostor_tier.bind(device, &lists, &self.atlas_binding(), &gbuffer)?;
        Ok(SceneBindings { centres, instances, count, split, mesh, impostor })
    }

    /// Rewrites every grain of `scene` (dynamic scenes where all grains move each frame);
    /// `grains` holds as many as the scene.
    pub fn update(
        &self,
        queue: &wgpu::Queue,
        scene: &SceneBindings,
        grains: &[GrainInstance],
    ) -> Result<(), RenderError> {
        if grains.len() != scene.count as usize {
            return Err(RenderError::InvalidInput(format!("{} grains for a scene of {}", grains.len(), scene.count)));
        }
        self.update_range(queue, scene, 0, grains)
    }

    /// Rewrites grains `first .. first + grains.len()` of `scene` and nothing else (two buffer
    /// writes: the splitter's centres and the instances).
    pub fn update_range(
        &self,
        queue: &wgpu::Queue,
        scene: &SceneBindings,
        first: u32,
        grains: &[GrainInstance],
    ) -> Result<(), RenderError> {
        let end = u64::from(first) + grains.len() as u64;
        if end > u64::from(scene.count) {
            return Err(RenderError::InvalidInput(format!(
                "grains {first}..{end} for a scene of {} grains",
                scene.count
            )));
        }
        let centres: Vec<Vec4> = grains.iter().map(|g| g.centre_scale).collect();
        let at = u64::from(first);
        queue.write_buffer(&scene.centres, at * size_of::<Vec4>() as u64, bytemuck::cast_slice(&centres));
        queue.write_buffer(&scene.instances, at * size_of::<GrainInstance>() as u64, bytemuck::cast_slice(grains));
        Ok(())
    }

    /// Rewrites only the grains that changed: `changes` lists `(index, new state)` in
    /// increasing index order; each run of consecutive indices is one [`update_range`]
    /// (so a frame where few grains move uploads only those). Returns the number of runs.
    ///
    /// [`update_range`]: StackingRenderer::update_range
    pub fn update_changed(
        &self,
        queue: &wgpu::Queue,
        scene: &SceneBindings,
        changes: &[(u32, GrainInstance)],
    ) -> Result<usize, RenderError> {
        if let Some(w) = changes.windows(2).find(|w| w[1].0 <= w[0].0) {
            return Err(RenderError::InvalidInput(format!(
                "changed grains must be listed in increasing index order: {} after {}",
                w[1].0, w[0].0
            )));
        }
        if let Some(&(last, _)) = changes.last().filter(|(i, _)| *i >= scene.count) {
            return Err(RenderError::InvalidInput(format!("grain {last} for a scene of {} grains", scene.count)));
        }
        let mut runs = 0;
        let mut start = 0;
        while start < changes.len() {
            let mut end = start + 1;
            while end < changes.len() && changes[end].0 == changes[end - 1].0 + 1 {
                end += 1;
            }
            let grains: Vec<GrainInstance> = changes[start..end].iter().map(|(_, g)| *g).collect();
            self.update_range(queue, scene, changes[start].0, &grains)?;
            runs += 1;
            start = end;
        }
        Ok(runs)
    }

    /// Records one frame: every [`Stage`] in order — split, mesh tier, impostor tier
    /// (composited), deferred shading into [`StackingRenderer::image`]. Uniforms are written
    /// through `queue` (one frame per submission); nothing is read back.
    pub fn encode(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        scene: &SceneBindings,
        camera: &StackingCamera,
        lighting: &ShadingUniforms,
        settings: TierSettings,
    ) -> Result<(), RenderError> {
        for stage in Stage::ALL {
            self.encode_stage(queue, encoder, scene, camera, lighting, settings, stage)?;
        }
        Ok(())
    }

    /// Records one stage of a frame (for timing stages apart; [`StackingRenderer::encode`]
    /// records them all, in [`Stage::ALL`]'s order, which each stage needs).
    #[allow(clippy::too_many_arguments)]
    pub fn encode_stage(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        scene: &SceneBindings,
        camera: &StackingCamera,
        lighting: &ShadingUniforms,
        settings: TierSettings,
        stage: Stage,
    ) -> Result<(), RenderError> {
        match stage {
            Stage::Split => {
                self.splitter.encode(queue, encoder, &scene.split, &camera.split, scene.count, None).map_err(gpu_error)
            }
            Stage::Meshes => self.mesh_tier.encode(queue, encoder, &scene.mesh, &camera.uniforms, &self.gbuffer),
            Stage::Impostors => {
                let frame = TierFrame {
                    camera: &camera.uniforms,
                    sampling: self.sampling,
                    instance_count: scene.count,
                    settings: TierSettings { composite: true, ..settings },
                };
                self.impostor_tier.encode(queue, encoder, &scene.impostor, &frame, &self.atlas_binding())
            }
            Stage::Shading => {
                self.shading.encode(queue, encoder, &self.shading_bindings, &camera.uniforms, lighting);
                Ok(())
            }
        }
    }

    /// Reads back the splitter's counters of the last submitted frame (waits for the GPU:
    /// for measurements between frames, never inside one).
    pub fn read_counters(&self, gpu: &gpu_harness::Gpu) -> Result<SplitCounters, RenderError> {
        let bytes = gpu.read_buffer(self.splitter.counters(), size_of::<SplitCounters>() as u64).map_err(gpu_error)?;
        Ok(bytemuck::pod_read_unaligned(&bytes))
    }

    /// The splitter (its counters, lists and settings).
    pub fn splitter(&self) -> &GrainSplitter {
        &self.splitter
    }

    /// The impostor tier (its counters).
    pub fn impostor_tier(&self) -> &ImpostorTier {
        &self.impostor_tier
    }

    /// The G-buffer of the last frame.
    pub fn gbuffer(&self) -> &ScreenGbuffer {
        &self.gbuffer
    }

    /// The shaded image of the last frame (`Rgba8Unorm`, sRGB-encoded values).
    pub fn image(&self) -> &wgpu::Texture {
        &self.image
    }

    /// The options.
    pub fn options(&self) -> &RendererOptions {
        &self.options
    }
}
