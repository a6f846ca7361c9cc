//! One grain type of a [`StackingRenderer`](crate::StackingRenderer): its splitter, mesh
//! tier, impostor tier (with the point tier) and atlas, built once; and the GPU buffers and
//! bind groups of its grains in a scene.
//!
//! A scene may mix grain types, as the paper's beaches mix grains (one atlas per type). Each
//! type is split and culled on its own (its occluder map and Hi-Z see only its grains, which
//! stays conservative); the frame draws every type's meshes into one G-buffer over one depth
//! buffer, then each type's impostor tier in turn, composited over the G-buffer's depth — the
//! meshes of all types and the impostors and points of the types before it — so the nearest
//! surface of any type wins each pixel.

use glam::Vec4;
use grain_impostor::atlas::ImpostorAtlas;
use grain_impostor::atlas_gpu::AtlasTextures;
use grain_impostor::cloud::{AtlasBinding, GBufferBinding};
use grain_impostor::mesh_gbuffer::ScreenGbuffer;
use grain_impostor::scene::{CameraUniforms, GrainInstance};
use grain_splitter::{
    GrainSplitter, ListOrder, SplitBindings, SplitCamera, SplitSettings, SplitterOptions, TierThresholds,
};
use octahedral_map::{ImpostorSampler, ImpostorSamplingUniforms, SamplingMode, ViewSelection};

use crate::error::RenderError;
use crate::impostor_tier::{ImpostorTier, TierBindings, TierFrame, TierSettings};
use crate::inputs::ListInputs;
use crate::mesh_tier::{MeshLayer, MeshTier, MeshTierBindings};
use crate::options::RendererOptions;

/// A grain type of a scene: its mesh, its atlas and its thresholds.
#[derive(Clone, Copy, Debug)]
pub struct GrainType<'a> {
    /// The mesh (the mesh tier; its bounds give the splitter's `r` and `R`).
    pub mesh: &'a grain_mesh::GrainMesh,
    /// The impostor atlas baked from it.
    pub atlas: &'a ImpostorAtlas,
    /// Projected diameter (pixels) above which a grain of this type is a mesh (its measured
    /// impostor table's).
    pub mesh_above: f32,
    /// Projected diameter (pixels) below which a grain of this type is a point.
    pub point_below: f32,
}

/// The passes of one grain type.
pub struct TypeRenderer {
    splitter: GrainSplitter,
    mesh_tier: MeshTier,
    impostor_tier: ImpostorTier,
    atlas: AtlasTextures,
    atlas_texels: u32,
    atlas_layers: u32,
    sampling: ImpostorSamplingUniforms,
}

/// One grain type's grains on the GPU and every bind group that reads them.
pub(crate) struct TypeBindings {
    pub(crate) centres: wgpu::Buffer,
    pub(crate) instances: wgpu::Buffer,
    pub(crate) count: u32,
    split: SplitBindings,
    mesh: MeshTierBindings,
    impostor: TierBindings,
}

pub(crate) fn gpu_error(e: impl std::fmt::Display) -> RenderError {
    RenderError::InvalidInput(e.to_string())
}

impl TypeRenderer {
    /// Builds the splitter for the mesh's `r` and `R` and the type's thresholds, the mesh
    /// tier, and the impostor tier sampling the atlas (mixed sampling, views chosen per
    /// grain).
    pub(crate) fn new(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        grain: &GrainType<'_>,
        options: &RendererOptions,
    ) -> Result<Self, RenderError> {
        let (mesh, atlas) = (grain.mesh, grain.atlas);
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
            TierThresholds::new(grain.point_below, grain.mesh_above, options.band).map_err(|e| match e {
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
            splitter,
            mesh_tier,
            impostor_tier,
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

    /// Uploads `grains` (1 to `capacity`) and binds them to this type's passes and `gbuffer`.
    pub(crate) fn upload(
        &self,
        device: &wgpu::Device,
        grains: &[GrainInstance],
        capacity: u32,
        gbuffer: &ScreenGbuffer,
    ) -> Result<TypeBindings, RenderError> {
        let count = u32::try_from(grains.len())
            .ok()
            .filter(|&n| n > 0 && n <= capacity)
            .ok_or_else(|| RenderError::InvalidInput(format!("{} grains: need 1 to {capacity}", grains.len())))?;
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
        let g = gbuffer;
        let gbuffer = GBufferBinding {
            normal_coverage: &g.views[0],
            albedo: &g.views[1],
            material: &g.views[2],
            depth: &g.views[3],
        };
        let impostor = self.impostor_tier.bind(device, &lists, &self.atlas_binding(), &gbuffer)?;
        Ok(TypeBindings { centres, instances, count, split, mesh, impostor })
    }

    /// Records this type's occluder map (and Hi-Z pyramid).
    pub(crate) fn encode_occluder_map(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        bindings: &TypeBindings,
        camera: &SplitCamera,
    ) -> Result<(), RenderError> {
        self.splitter
            .encode_occluder_map(queue, encoder, &bindings.split, camera, bindings.count, None)
            .map_err(gpu_error)
    }

    /// Records the split of this type's grains (after its occluder map).
    pub(crate) fn encode_split(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        bindings: &TypeBindings,
    ) -> Result<(), RenderError> {
        self.splitter.encode_split(encoder, &bindings.split, bindings.count, None).map_err(gpu_error)
    }

    /// Records this type's mesh tier as `layer` of the frame.
    pub(crate) fn encode_meshes(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        bindings: &TypeBindings,
        camera: &CameraUniforms,
        gbuffer: &ScreenGbuffer,
        layer: MeshLayer<'_>,
    ) -> Result<(), RenderError> {
        self.mesh_tier.encode_layer(queue, encoder, &bindings.mesh, camera, gbuffer, layer)
    }

    /// Records this type's impostor and point tiers' visibility (composited over the
    /// G-buffer's depth).
    pub(crate) fn encode_impostors(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        bindings: &TypeBindings,
        camera: &CameraUniforms,
        settings: TierSettings,
    ) -> Result<(), RenderError> {
        let frame = TierFrame {
            camera,
            sampling: self.sampling,
            instance_count: bindings.count,
            settings: TierSettings { composite: true, ..settings },
        };
        self.impostor_tier.encode_visibility(queue, encoder, &bindings.impostor, &frame, &self.atlas_binding())
    }

    /// Records the resolve of this type's visibility buffer into the G-buffer.
    pub(crate) fn encode_resolve(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        bindings: &TypeBindings,
    ) -> Result<(), RenderError> {
        self.impostor_tier.encode_resolve(encoder, &bindings.impostor);
        Ok(())
    }

    /// The splitter (its counters, lists and settings).
    pub fn splitter(&self) -> &GrainSplitter {
        &self.splitter
    }

    /// The impostor tier (its counters).
    pub fn impostor_tier(&self) -> &ImpostorTier {
        &self.impostor_tier
    }

    /// The mesh tier.
    pub fn mesh_tier(&self) -> &MeshTier {
        &self.mesh_tier
    }
}
