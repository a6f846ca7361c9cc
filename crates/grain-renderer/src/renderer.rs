//! [`StackingRenderer`]: the splitter, the mesh tier, the impostor tier and deferred shading
//! of one or several grain types ([`GrainType`]), built once and encoded per frame with no
//! CPU readback (§3, Fig. 2: ① split, ② meshes, ③ impostors, ④ points, drawn by the impostor
//! tier's visibility buffer).

use glam::{Vec3, Vec4};
use grain_impostor::atlas::ImpostorAtlas;
use grain_impostor::mesh_gbuffer::ScreenGbuffer;
use grain_impostor::scene::{CameraUniforms, GrainInstance, ShadingUniforms};
use grain_impostor::shading::{ShadingBindings, ShadingPass};
use grain_splitter::{GrainSplitter, SplitCamera, SplitCounters};

use crate::error::RenderError;
use crate::grain_type::{GrainType, TypeBindings, TypeRenderer, gpu_error};
use crate::impostor_tier::{ImpostorTier, TierSettings};
use crate::mesh_tier::MeshLayer;
pub use crate::options::{NO_POINT_TIER, RendererOptions};

/// The light of the pile renders (`cargo xtask bench-gpu stackings`, the point threshold):
/// from the upper right front, white, a dim ambient term, a dark grey background.
pub fn pile_lighting() -> ShadingUniforms {
    // A non-zero constant direction: `new` cannot fail; the fallback is never used.
    ShadingUniforms::new(Vec3::new(0.4, 1.0, 0.6), Vec3::splat(2.6), Vec3::splat(0.25), Vec3::splat(0.1)).unwrap_or(
        ShadingUniforms { light_direction: Vec4::Y, light_colour: Vec4::ONE, ambient: Vec4::ZERO, background: Vec4::W },
    )
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
    /// The occluder map and occluder fusion's Hi-Z pyramid (`grain-splitter`).
    OccluderMap,
    /// Culling, tiers and lists (`grain-splitter`).
    Split,
    /// The mesh tier (clears the G-buffer).
    Meshes,
    /// The impostor and point tiers' visibility: the splats (or raster sprites) of the
    /// impostor lists and the points, and the points' accumulation.
    Impostors,
    /// The visibility buffer resolved into the G-buffer, composited over the meshes.
    Resolve,
    /// Deferred shading of the G-buffer.
    Shading,
}

impl Stage {
    /// Every stage, in the order a frame runs them.
    pub const ALL: [Stage; 6] =
        [Stage::OccluderMap, Stage::Split, Stage::Meshes, Stage::Impostors, Stage::Resolve, Stage::Shading];

    /// Its name in tables and CSV.
    pub fn name(self) -> &'static str {
        match self {
            Stage::OccluderMap => "occluder_map",
            Stage::Split => "split",
            Stage::Meshes => "meshes",
            Stage::Impostors => "impostors",
            Stage::Resolve => "resolve",
            Stage::Shading => "shading",
        }
    }
}

/// A scene's grains on the GPU, per grain type, and every bind group that reads them.
pub struct SceneBindings {
    types: Vec<TypeBindings>,
}

impl SceneBindings {
    /// Grains in the scene, all types together.
    pub fn count(&self) -> u32 {
        self.types.iter().map(|t| t.count).sum()
    }

    /// Grains of each type.
    pub fn counts(&self) -> Vec<u32> {
        self.types.iter().map(|t| t.count).collect()
    }
}

/// The renderer of one or several grain types (`crate::grain_type`) at one viewport size.
pub struct StackingRenderer {
    options: RendererOptions,
    types: Vec<TypeRenderer>,
    shading: ShadingPass,
    shading_bindings: ShadingBindings,
    gbuffer: ScreenGbuffer,
    image: wgpu::Texture,
}

impl StackingRenderer {
    /// Builds every pipeline and buffer for one grain type, `mesh` and its `atlas` with the
    /// thresholds of `options`: the splitter for the mesh's `r` and `R`, the mesh tier, the
    /// impostor tier (mixed sampling, views chosen per grain), the G-buffer and the shaded
    /// image.
    pub fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        mesh: &grain_mesh::GrainMesh,
        atlas: &ImpostorAtlas,
        options: RendererOptions,
    ) -> Result<Self, RenderError> {
        let grain = GrainType { mesh, atlas, mesh_above: options.mesh_above, point_below: options.point_below };
        Self::with_types(device, queue, &[grain], options)
    }

    /// [`StackingRenderer::new`] for a scene mixing `types` (at least one; each with its own
    /// thresholds, which replace those of `options`; `options.capacity` grains of each).
    pub fn with_types(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        types: &[GrainType<'_>],
        options: RendererOptions,
    ) -> Result<Self, RenderError> {
        if types.is_empty() {
            return Err(RenderError::InvalidSetting { field: "types", reason: "no grain type".into() });
        }
        let types = types
            .iter()
            .map(|grain| TypeRenderer::new(device, queue, grain, &options))
            .collect::<Result<Vec<_>, _>>()?;
        let shading = ShadingPass::new(device).map_err(gpu_error)?;
        let gbuffer = ScreenGbuffer::new(device, options.size).map_err(gpu_error)?;
        let image = shading.create_target(device, &gbuffer).map_err(gpu_error)?;
        let shading_bindings = shading.bind(device, &gbuffer, &image).map_err(gpu_error)?;
        Ok(Self { options, types, shading, shading_bindings, gbuffer, image })
    }

    /// Uploads `grains` (at most the capacity) of a one-type renderer and binds them to
    /// every pass.
    pub fn upload(&self, device: &wgpu::Device, grains: &[GrainInstance]) -> Result<SceneBindings, RenderError> {
        self.upload_types(device, &[grains])
    }

    /// Uploads the grains of each type (`grains[k]` of type `k`: one slice per type, each of
    /// 1 to the capacity) and binds them to every pass.
    pub fn upload_types(
        &self,
        device: &wgpu::Device,
        grains: &[&[GrainInstance]],
    ) -> Result<SceneBindings, RenderError> {
        if grains.len() != self.types.len() {
            return Err(RenderError::InvalidInput(format!(
                "grains of {} types for a renderer of {}",
                grains.len(),
                self.types.len()
            )));
        }
        let types = self
            .types
            .iter()
            .zip(grains)
            .map(|(t, grains)| t.upload(device, grains, self.options.capacity, &self.gbuffer))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(SceneBindings { types })
    }

    /// Rewrites every grain of a one-type `scene` (dynamic scenes where all grains move
    /// each frame); `grains` holds as many as the scene.
    pub fn update(
        &self,
        queue: &wgpu::Queue,
        scene: &SceneBindings,
        grains: &[GrainInstance],
    ) -> Result<(), RenderError> {
        let [only] = scene.types.as_slice() else {
            return Err(RenderError::InvalidInput(format!(
                "a scene of {} grain types: update each with update_range",
                scene.types.len()
            )));
        };
        if grains.len() != only.count as usize {
            return Err(RenderError::InvalidInput(format!("{} grains for a scene of {}", grains.len(), only.count)));
        }
        self.update_range(queue, scene, 0, 0, grains)
    }

    /// Rewrites grains `first .. first + grains.len()` of type `grain_type` of `scene` and
    /// nothing else (two buffer writes: the splitter's centres and the instances).
    pub fn update_range(
        &self,
        queue: &wgpu::Queue,
        scene: &SceneBindings,
        grain_type: usize,
        first: u32,
        grains: &[GrainInstance],
    ) -> Result<(), RenderError> {
        let bindings = scene.types.get(grain_type).ok_or_else(|| {
            RenderError::InvalidInput(format!("grain type {grain_type} of a scene of {}", scene.types.len()))
        })?;
        let end = u64::from(first) + grains.len() as u64;
        if end > u64::from(bindings.count) {
            return Err(RenderError::InvalidInput(format!(
                "grains {first}..{end} for a scene of {} grains",
                bindings.count
            )));
        }
        let centres: Vec<Vec4> = grains.iter().map(|g| g.centre_scale).collect();
        let at = u64::from(first);
        queue.write_buffer(&bindings.centres, at * size_of::<Vec4>() as u64, bytemuck::cast_slice(&centres));
        queue.write_buffer(&bindings.instances, at * size_of::<GrainInstance>() as u64, bytemuck::cast_slice(grains));
        Ok(())
    }

    /// Rewrites only the grains of type `grain_type` that changed: `changes` lists `(index,
    /// new state)` in increasing index order; each run of consecutive indices is one
    /// [`update_range`] (so a frame where few grains move uploads only those). Returns the
    /// number of runs.
    ///
    /// [`update_range`]: StackingRenderer::update_range
    pub fn update_changed(
        &self,
        queue: &wgpu::Queue,
        scene: &SceneBindings,
        grain_type: usize,
        changes: &[(u32, GrainInstance)],
    ) -> Result<usize, RenderError> {
        if let Some(w) = changes.windows(2).find(|w| w[1].0 <= w[0].0) {
            return Err(RenderError::InvalidInput(format!(
                "changed grains must be listed in increasing index order: {} after {}",
                w[1].0, w[0].0
            )));
        }
        let count = scene.types.get(grain_type).map_or(0, |t| t.count);
        if let Some(&(last, _)) = changes.last().filter(|(i, _)| *i >= count) {
            return Err(RenderError::InvalidInput(format!("grain {last} for a scene of {count} grains")));
        }
        let mut runs = 0;
        let mut start = 0;
        while start < changes.len() {
            let mut end = start + 1;
            while end < changes.len() && changes[end].0 == changes[end - 1].0 + 1 {
                end += 1;
            }
            let grains: Vec<GrainInstance> = changes[start..end].iter().map(|(_, g)| *g).collect();
            self.update_range(queue, scene, grain_type, changes[start].0, &grains)?;
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

    /// Records one stage of a frame, for every grain type (for timing stages apart;
    /// [`StackingRenderer::encode`] records them all, in [`Stage::ALL`]'s order, which each
    /// stage needs): the meshes of every type over one depth buffer, then each type's
    /// impostor tier over the G-buffer (`crate::grain_type`). With several types, each
    /// type's visibility needs the previous types' resolved pixels, so [`Stage::Impostors`]
    /// also records the resolves of all types but the last (and is timed with them).
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
        if scene.types.len() != self.types.len() {
            return Err(RenderError::InvalidInput(format!(
                "a scene of {} grain types for a renderer of {}",
                scene.types.len(),
                self.types.len()
            )));
        }
        let mut pairs = self.types.iter().zip(&scene.types);
        match stage {
            Stage::OccluderMap => pairs.try_for_each(|(t, b)| t.encode_occluder_map(queue, encoder, b, &camera.split)),
            Stage::Split => pairs.try_for_each(|(t, b)| t.encode_split(encoder, b)),
            Stage::Meshes => pairs.enumerate().try_for_each(|(k, (t, b))| {
                let layer = if k == 0 { MeshLayer::First } else { MeshLayer::Over(self.types[0].mesh_tier()) };
                t.encode_meshes(queue, encoder, b, &camera.uniforms, &self.gbuffer, layer)
            }),
            // Each type's visibility starts from the G-buffer's depth, the previous types'
            // resolved pixels included: every resolve but the last type's runs in this stage.
            Stage::Impostors => pairs.enumerate().try_for_each(|(k, (t, b))| {
                if k > 0 {
                    self.types[k - 1].encode_resolve(encoder, &scene.types[k - 1])?;
                }
                t.encode_impostors(queue, encoder, b, &camera.uniforms, settings)
            }),
            Stage::Resolve => match (self.types.last(), scene.types.last()) {
                (Some(t), Some(b)) => t.encode_resolve(encoder, b),
                _ => Ok(()),
            },
            Stage::Shading => {
                self.shading.encode(queue, encoder, &self.shading_bindings, &camera.uniforms, lighting);
                Ok(())
            }
        }
    }

    /// Reads back the splitters' counters of the last submitted frame (waits for the GPU:
    /// for measurements between frames, never inside one): `count` and `culled` summed over
    /// the grain types, `offset` and `cursor` the first type's.
    pub fn read_counters(&self, gpu: &gpu_harness::Gpu) -> Result<SplitCounters, RenderError> {
        let mut total = SplitCounters::default();
        for (k, t) in self.types.iter().enumerate() {
            let bytes =
                gpu.read_buffer(t.splitter().counters(), size_of::<SplitCounters>() as u64).map_err(gpu_error)?;
            let c: SplitCounters = bytemuck::pod_read_unaligned(&bytes);
            if k == 0 {
                (total.offset, total.cursor) = (c.offset, c.cursor);
            }
            for i in 0..4 {
                total.count[i] += c.count[i];
                total.culled[i] += c.culled[i];
            }
        }
        Ok(total)
    }

    /// The passes of each grain type.
    pub fn types(&self) -> &[TypeRenderer] {
        &self.types
    }

    /// The first grain type's splitter (its counters, lists and settings).
    pub fn splitter(&self) -> &GrainSplitter {
        self.types[0].splitter()
    }

    /// The first grain type's impostor tier (its counters).
    pub fn impostor_tier(&self) -> &ImpostorTier {
        self.types[0].impostor_tier()
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
