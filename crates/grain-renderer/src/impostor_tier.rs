//! The impostor tier (Michel & Boubekeur 2020, §4–5 and §9) in compute: the splitter's two
//! impostor lists splatted into a **visibility buffer**, then one resolve pass that samples
//! the winning grain's atlas into the screen G-buffer.
//!
//! # Visibility
//!
//! A pixel is covered by a grain when the blended atlas coverage reaches the threshold, at
//! the depth of the blended surface point (`grain_impostor::cloud`'s sampling, shared WGSL):
//!
//! - with `SHADER_INT64_ATOMIC_MIN_MAX` ([`VisibilityKind::Atomic64`]): one 64-bit
//!   `atomicMin` of `(depth bits << 32) | grain` per covered pixel (nearest, then smallest
//!   index);
//! - otherwise ([`VisibilityKind::TwoPass32`]): every list splatted twice **by the same
//!   pipeline** — nearest depth bits, then the grains whose depth bits equal it claim the
//!   pixel. The owner pass of `grain_impostor::cloud` recomputes the depth in a second entry
//!   point; a compiler free to contract `a·b + c` differently there could leave holes. Here a
//!   uniform selects the atomic, so both passes run one compiled function. Same images as the
//!   64-bit path (a test).
//!
//! With [`TierSettings::composite`] the buffer starts from the mesh tier's depth (`TIER_MESH`
//! pixels): an impostor wins a pixel only where it is nearer than the mesh, and the resolve
//! writes only the impostors' pixels.
//!
//! # Work by footprint
//!
//! Grains whose screen rectangle holds at most [`TIER_SMALL_PIXELS`] pixels (about 8 px across)
//! are splatted by one invocation each, 64 per workgroup, through the splitter's own dispatch
//! arguments; larger ones by one 8 × 8 workgroup each, through arguments this tier writes on the
//! GPU (`tier_arguments`). One workgroup per grain, as the impostor cloud does, idles most lanes
//! on the few-pixel grains dense stackings are made of.
//!
//! # Double draw and software early-Z (§9)
//!
//! The occluder candidates are splatted first, the other impostors second. With
//! [`TierSettings::early_z`] a pixel is skipped **before any atlas read** when the depth already
//! stored there is nearer than the grain's nearest possible depth (its centre's depth minus
//! `√2·R·s`, rounded down: the resolved point lies on the pixel ray within `√2·R·s` of the
//! centre). A skipped pixel could not have won, so the images are identical with and without
//! it (a test); [`ImpostorTier::stats`] counts evaluated and skipped pixels per list.
//!
//! # Silhouettes
//!
//! A pixel covered or not at its centre aliases along every silhouette, where the mesh
//! reference (4 × 4 supersampled) has fractional coverage and mixed colours. With
//! [`ImpostorTier::with_samples`] the visibility buffer holds `s × s` samples per pixel, each
//! tested at its own position (the atlas still filtered at the pixel's level of detail); the
//! resolve reduces them as the reference's supersampling does — coverage the covered
//! fraction, attributes the means over the covered samples — so silhouettes get fractional
//! coverage and mixed attributes. Every sample is a full visibility test, so culling and the
//! early-Z (per sample) still change nothing, and `s = 1` is the single-sample tier exactly.
//! In composite mode a pixel where the mesh tier won at least half of the samples keeps the
//! mesh's values (they cannot be read back there); otherwise its samples count as covered.
//! The cost is `s²` atlas evaluations per covered pixel in the splats and the resolve.
//!
//! # Points (Fig. 2 ④)
//!
//! The point list's grains enter the same visibility buffer as small discs — the pixels whose
//! centre lies within the grain's projected outer radius (at most
//! [`TIER_POINT_MAX_RADIUS`](crate::tier_layout::TIER_POINT_MAX_RADIUS)), and always the
//! centre's pixel — at their centre's depth less the atlas' inner radius, their owner tagged
//! with [`TIER_POINT_BIT`].
//! Every point grain within its diameter `2·R·s` of the depth that won its pixel then adds
//! its 1×1-mip colour, normal and roughness (the 4 views of §5 blended, un-premultiplied) to
//! [`TIER_POINT_SUMS`] fixed-point sums (WGSL has no float atomics; [`TIER_POINT_SCALE`]),
//! and the resolve writes their average: a pixel of many sub-pixel grains shows their mean
//! rather than whichever is nearest. The average is over the grains the splitter kept, so
//! culling can change a point pixel (a culled grain behind the front one no longer counts),
//! which it cannot for meshes and impostors.

use glam::{UVec4, Vec4};
use grain_impostor::cloud::{AtlasBinding, CloudUniforms, GBufferBinding};
use grain_impostor::gpu_util::storage_texture_entry;
use grain_impostor::scene::{CameraUniforms, PIXEL_TILE};
use grain_splitter::lists::{
    INDIRECT_DISPATCH, INDIRECT_WORDS, LIST_IMPOSTOR_OCCLUDER, LIST_IMPOSTOR_REST, LIST_POINT,
};
use octahedral_map::ImpostorSamplingUniforms;

use crate::error::RenderError;
use crate::impostor_raster::{RasterPath, raster_depth_scale};
use crate::inputs::ListInputs;
use crate::shaders::{impostor_tier_32_shader, impostor_tier_64_shader, int64_capabilities};
use crate::tier_layout::{TIER_ARGUMENT_WORDS, TIER_DRAW_ARGUMENTS, TIER_MAX_SAMPLES};
pub use crate::tier_layout::{
    TIER_COMPOSITE, TIER_DEPTH_SLACK, TIER_MESH, TIER_NONE, TIER_POINT_BIT, TIER_POINT_SCALE, TIER_POINT_SUMS,
    TIER_REACH, TIER_SMALL_PIXELS, TIER_STATS, TierPass, TierUniforms,
};

/// How the visibility buffer is built.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum VisibilityKind {
    /// 64-bit where the device has `SHADER_INT64_ATOMIC_MIN_MAX`, else 32-bit.
    Auto,
    /// One 64-bit `atomicMin` of `(depth << 32) | grain` per covered pixel.
    Atomic64,
    /// Depth, then owner, with 32-bit atomics (each list splatted twice).
    TwoPass32,
}

/// How the impostor lists reach the visibility buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ImpostorPath {
    /// Compute splats (one invocation per small grain, a workgroup per large one) with the
    /// software early-Z.
    #[default]
    Compute,
    /// Sprites with a hardware depth test ([`crate::impostor_raster`]), merged into the
    /// visibility buffer.
    Raster,
}

/// Per-frame settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TierSettings {
    /// Blended atlas α at or above which a pixel is covered.
    pub coverage_threshold: f32,
    /// Skip pixels the grain cannot win before reading the atlas (§9's double draw in compute).
    pub early_z: bool,
    /// Start from the G-buffer's depth (the mesh tier's) and write only the impostors' pixels;
    /// otherwise every pixel is written (background where no impostor covers it).
    pub composite: bool,
    /// Compute splats or raster sprites (the point list is splatted in compute either way).
    pub path: ImpostorPath,
}

impl Default for TierSettings {
    fn default() -> Self {
        Self { coverage_threshold: 0.5, early_z: true, composite: true, path: ImpostorPath::Compute }
    }
}

/// One frame's inputs.
#[derive(Clone, Copy, Debug)]
pub struct TierFrame<'a> {
    /// The camera (viewport = the tier's size).
    pub camera: &'a CameraUniforms,
    /// The atlas' sampling configuration (`octahedral_map::ImpostorSampler::uniforms`).
    pub sampling: ImpostorSamplingUniforms,
    /// Grains in the instance buffer (indices at or above are ignored).
    pub instance_count: u32,
    /// Settings.
    pub settings: TierSettings,
}

/// The bind groups of one set of inputs, atlas and G-buffer.
pub struct TierBindings {
    splat: wgpu::BindGroup,
    clear: wgpu::BindGroup,
    resolve: wgpu::BindGroup,
    arguments: wgpu::BindGroup,
    indirect: wgpu::Buffer,
}

struct Pipelines {
    arguments: wgpu::ComputePipeline,
    clear: wgpu::ComputePipeline,
    small: wgpu::ComputePipeline,
    large: wgpu::ComputePipeline,
    point_splat: wgpu::ComputePipeline,
    point_accumulate: wgpu::ComputePipeline,
    resolve: wgpu::ComputePipeline,
}

/// The impostor tier for one viewport size, built once; [`ImpostorTier::encode`] records a
/// frame.
pub struct ImpostorTier {
    size: (u32, u32),
    samples: u32,
    kind: VisibilityKind,
    layout: wgpu::BindGroupLayout,
    clear_layout: wgpu::BindGroupLayout,
    resolve_layout: wgpu::BindGroupLayout,
    arguments_layout: wgpu::BindGroupLayout,
    pipelines: Pipelines,
    camera: wgpu::Buffer,
    sampling: wgpu::Buffer,
    cloud: wgpu::Buffer,
    tier: wgpu::Buffer,
    passes: wgpu::Buffer,
    pass_stride: u32,
    visibility: wgpu::Buffer,
    owner: wgpu::Buffer,
    stats: wgpu::Buffer,
    arguments: wgpu::Buffer,
    point_sums: wgpu::Buffer,
    raster: RasterPath,
}

/// The stages of the raster path's sprites and of every compute pass.
const ALL_STAGES: wgpu::ShaderStages = wgpu::ShaderStages::COMPUTE.union(wgpu::ShaderStages::VERTEX_FRAGMENT);

fn buffer_entry(binding: u32, ty: wgpu::BufferBindingType, dynamic: bool) -> wgpu::BindGroupLayoutEntry {
    // Read-only inputs are shared with the sprites; of the writable buffers only the counters
    // are (fragment shaders may write storage, vertex shaders may not).
    let visibility = match (ty, binding) {
        (WRITE, TIER_STATS_BINDING) => wgpu::ShaderStages::COMPUTE | wgpu::ShaderStages::FRAGMENT,
        (WRITE, _) => wgpu::ShaderStages::COMPUTE,
        _ => ALL_STAGES,
    };
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: dynamic,
            min_binding_size: if dynamic { wgpu::BufferSize::new(16) } else { None },
        },
        count: None,
    }
}

fn texture_entry(
    binding: u32,
    sample_type: wgpu::TextureSampleType,
    dimension: wgpu::TextureViewDimension,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: ALL_STAGES,
        ty: wgpu::BindingType::Texture { sample_type, view_dimension: dimension, multisampled: false },
        count: None,
    }
}

const UNIFORM: wgpu::BufferBindingType = wgpu::BufferBindingType::Uniform;
const READ: wgpu::BufferBindingType = wgpu::BufferBindingType::Storage { read_only: true };
const WRITE: wgpu::BufferBindingType = wgpu::BufferBindingType::Storage { read_only: false };
/// The binding of the counters (`stats` in the WGSL).
const TIER_STATS_BINDING: u32 = 10;

/// The number of [`TierPass`] entries: three lists (two impostor lists, the point list) ×
/// two passes.
const PASS_ENTRIES: u32 = 6;

impl ImpostorTier {
    /// Whether `device` can build the 64-bit visibility buffer.
    pub fn supports_atomic64(device: &wgpu::Device) -> bool {
        device.features().contains(wgpu::Features::SHADER_INT64 | wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX)
    }

    /// Validates the shader with naga, builds the pipelines and the buffers for a
    /// `size` viewport, one visibility sample per pixel.
    pub fn new(device: &wgpu::Device, size: (u32, u32), visibility: VisibilityKind) -> Result<Self, RenderError> {
        Self::with_samples(device, size, visibility, 1)
    }

    /// [`ImpostorTier::new`] with `samples × samples` visibility samples per pixel (1 to
    /// [`TIER_MAX_SAMPLES`]; module docs, "Silhouettes").
    pub fn with_samples(
        device: &wgpu::Device,
        size: (u32, u32),
        visibility: VisibilityKind,
        samples: u32,
    ) -> Result<Self, RenderError> {
        let (width, height) = size;
        if width == 0 || height == 0 {
            return Err(RenderError::InvalidSetting { field: "size", reason: format!("{size:?}: must not be empty") });
        }
        if !(1..=TIER_MAX_SAMPLES).contains(&samples) {
            return Err(RenderError::InvalidSetting {
                field: "samples",
                reason: format!("{samples}: must be 1 to {TIER_MAX_SAMPLES} per pixel side"),
            });
        }
        let has_64 = Self::supports_atomic64(device);
        let kind = match visibility {
            VisibilityKind::Auto if has_64 => VisibilityKind::Atomic64,
            VisibilityKind::Auto => VisibilityKind::TwoPass32,
            VisibilityKind::Atomic64 if !has_64 => {
                return Err(RenderError::MissingFeature("SHADER_INT64_ATOMIC_MIN_MAX (the 64-bit visibility buffer)"));
            }
            other => other,
        };
        let limits = device.limits();
        let storage_limit = limits.max_storage_buffer_binding_size.min(limits.max_buffer_size);
        let pixels = u64::from(width) * u64::from(height);
        let sample_count = pixels * u64::from(samples * samples);
        let word = if kind == VisibilityKind::Atomic64 { 8 } else { 4 };
        if sample_count * word > storage_limit {
            return Err(RenderError::TooLarge {
                what: "visibility buffer bytes",
                requested: sample_count * word,
                limit: storage_limit,
            });
        }
        let sum_bytes = pixels * u64::from(TIER_POINT_SUMS) * 4;
        if sum_bytes > storage_limit {
            return Err(RenderError::TooLarge {
                what: "point tier sum bytes",
                requested: sum_bytes,
                limit: storage_limit,
            });
        }
        let shader =
            if kind == VisibilityKind::Atomic64 { impostor_tier_64_shader() } else { impostor_tier_32_shader() };
        let capabilities =
            if kind == VisibilityKind::Atomic64 { int64_capabilities() } else { naga::valid::Capabilities::default() };
        shader.validate_with(capabilities).map_err(|e| RenderError::InvalidShader(e.to_string()))?;
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some(shader.name()),
            source: wgpu::ShaderSource::Wgsl(shader.source().to_owned().into()),
        });
        let float = wgpu::TextureSampleType::Float { filterable: true };
        let array = wgpu::TextureViewDimension::D2Array;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("impostor tier"),
            entries: &[
                buffer_entry(0, UNIFORM, false),
                buffer_entry(1, UNIFORM, false),
                buffer_entry(2, UNIFORM, false),
                buffer_entry(3, UNIFORM, false),
                buffer_entry(4, UNIFORM, true),
                buffer_entry(5, READ, false),
                buffer_entry(6, READ, false),
                buffer_entry(7, READ, false),
                buffer_entry(8, WRITE, false),
                buffer_entry(9, WRITE, false),
                buffer_entry(TIER_STATS_BINDING, WRITE, false),
                texture_entry(11, float, array),
                texture_entry(12, float, array),
                texture_entry(13, float, array),
                texture_entry(14, float, array),
                wgpu::BindGroupLayoutEntry {
                    binding: 15,
                    visibility: ALL_STAGES,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
                buffer_entry(16, WRITE, false),
            ],
        });
        let arguments_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("impostor tier: arguments"),
            entries: &[buffer_entry(5, WRITE, false)],
        });
        let clear_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("impostor tier: mesh depth"),
            entries: &[texture_entry(
                0,
                wgpu::TextureSampleType::Float { filterable: false },
                wgpu::TextureViewDimension::D2,
            )],
        });
        let formats = grain_impostor::mesh_gbuffer::GBUFFER_FORMATS;
        let resolve_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("impostor tier: G-buffer"),
            entries: &[
                storage_texture_entry(1, formats[0]),
                storage_texture_entry(2, formats[1]),
                storage_texture_entry(3, formats[2]),
                storage_texture_entry(4, formats[3]),
            ],
        });
        let pipeline = |groups: &[&wgpu::BindGroupLayout], entry: &str| {
            let groups: Vec<Option<&wgpu::BindGroupLayout>> = groups.iter().map(|g| Some(*g)).collect();
            let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(entry),
                bind_group_layouts: &groups,
                immediate_size: 0,
            });
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let pipelines = Pipelines {
            arguments: pipeline(&[&layout, &arguments_layout], "tier_arguments"),
            clear: pipeline(&[&layout, &clear_layout], "tier_clear"),
            small: pipeline(&[&layout], "tier_splat_small"),
            large: pipeline(&[&layout], "tier_splat_large"),
            point_splat: pipeline(&[&layout], "tier_point_splat"),
            point_accumulate: pipeline(&[&layout], "tier_point_accumulate"),
            resolve: pipeline(&[&layout, &resolve_layout], "tier_resolve"),
        };
        let buffer = |label: &str, size: u64, usage: wgpu::BufferUsages| {
            device.create_buffer(&wgpu::BufferDescriptor { label: Some(label), size, usage, mapped_at_creation: false })
        };
        let uniform = wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST;
        let storage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC;
        let pass_stride = limits.min_uniform_buffer_offset_alignment.max(16);
        let owner_bytes = if kind == VisibilityKind::TwoPass32 { sample_count * 4 } else { 16 };
        let raster = RasterPath::new(device, &module, &layout, size, samples);
        Ok(Self {
            size,
            samples,
            kind,
            layout,
            clear_layout,
            resolve_layout,
            arguments_layout,
            pipelines,
            camera: buffer("tier camera", size_of::<CameraUniforms>() as u64, uniform),
            sampling: buffer("tier sampling", size_of::<ImpostorSamplingUniforms>() as u64, uniform),
            cloud: buffer("tier cloud settings", size_of::<CloudUniforms>() as u64, uniform),
            tier: buffer("tier settings", size_of::<TierUniforms>() as u64, uniform),
            passes: buffer("tier passes", u64::from(PASS_ENTRIES * pass_stride), uniform),
            pass_stride,
            visibility: buffer("tier visibility", sample_count * word, storage),
            owner: buffer("tier owners", owner_bytes, storage),
            stats: buffer("tier stats", u64::from(TIER_STATS) * 4, storage),
            arguments: buffer(
                "tier arguments",
                u64::from(TIER_ARGUMENT_WORDS) * 4,
                storage | wgpu::BufferUsages::INDIRECT,
            ),
            point_sums: buffer("point tier sums", sum_bytes, storage),
            raster,
        })
    }

    /// Visibility samples per pixel side.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// The visibility buffer kind (never `Auto`).
    pub fn kind(&self) -> VisibilityKind {
        self.kind
    }

    /// The point tier's per-pixel sums of the last frame ([`TIER_POINT_SUMS`] `u32`s per
    /// pixel, row-major; the first is the number of grains averaged).
    pub fn point_sums(&self) -> &wgpu::Buffer {
        &self.point_sums
    }

    /// The counters of the last frame ([`TIER_STATS`] `u32`s, see there).
    pub fn stats(&self) -> &wgpu::Buffer {
        &self.stats
    }

    /// The bind groups of `inputs`, `atlas` and `gbuffer` (whose textures need
    /// `STORAGE_BINDING` and, for the depth, `TEXTURE_BINDING`).
    pub fn bind(
        &self,
        device: &wgpu::Device,
        inputs: &ListInputs<'_>,
        atlas: &AtlasBinding<'_>,
        gbuffer: &GBufferBinding<'_>,
    ) -> Result<TierBindings, RenderError> {
        if !inputs.indirect.usage().contains(wgpu::BufferUsages::INDIRECT) {
            return Err(RenderError::InvalidInput("the splitter's indirect buffer needs INDIRECT usage".into()));
        }
        fn whole(binding: u32, buffer: &wgpu::Buffer) -> wgpu::BindGroupEntry<'_> {
            wgpu::BindGroupEntry { binding, resource: buffer.as_entire_binding() }
        }
        fn view(binding: u32, view: &wgpu::TextureView) -> wgpu::BindGroupEntry<'_> {
            wgpu::BindGroupEntry { binding, resource: wgpu::BindingResource::TextureView(view) }
        }
        let splat = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("impostor tier"),
            layout: &self.layout,
            entries: &[
                whole(0, &self.camera),
                whole(1, &self.sampling),
                whole(2, &self.cloud),
                whole(3, &self.tier),
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                        buffer: &self.passes,
                        offset: 0,
                        size: wgpu::BufferSize::new(16),
                    }),
                },
                whole(5, inputs.instances),
                whole(6, inputs.elements),
                whole(7, inputs.counters),
                whole(8, &self.visibility),
                whole(9, &self.owner),
                whole(10, &self.stats),
                view(11, atlas.normal_alpha),
                view(12, atlas.albedo_alpha),
                view(13, atlas.material_alpha),
                view(14, atlas.depth_alpha),
                wgpu::BindGroupEntry { binding: 15, resource: wgpu::BindingResource::Sampler(atlas.sampler) },
                whole(16, &self.point_sums),
            ],
        });
        let arguments = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("impostor tier: arguments"),
            layout: &self.arguments_layout,
            entries: &[whole(5, &self.arguments)],
        });
        let clear = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("impostor tier: mesh depth"),
            layout: &self.clear_layout,
            entries: &[view(0, gbuffer.depth)],
        });
        let resolve = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("impostor tier: G-buffer"),
            layout: &self.resolve_layout,
            entries: &[
                view(1, gbuffer.normal_coverage),
                view(2, gbuffer.albedo),
                view(3, gbuffer.material),
                view(4, gbuffer.depth),
            ],
        });
        Ok(TierBindings { splat, clear, resolve, arguments, indirect: inputs.indirect.clone() })
    }

    /// Writes the frame's uniforms through `queue` and records the tier:
    /// [`ImpostorTier::encode_visibility`], then [`ImpostorTier::encode_resolve`]. Reads the
    /// splitter's lists of the same submission; nothing is read back.
    pub fn encode(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        bindings: &TierBindings,
        frame: &TierFrame<'_>,
        atlas: &AtlasBinding<'_>,
    ) -> Result<(), RenderError> {
        self.encode_visibility(queue, encoder, bindings, frame, atlas)?;
        self.encode_resolve(encoder, bindings);
        Ok(())
    }

    /// Writes the frame's uniforms through `queue` and records the visibility buffer:
    /// arguments, clear, the splats (or sprites) of [`LIST_IMPOSTOR_OCCLUDER`] and
    /// [`LIST_IMPOSTOR_REST`], those of [`LIST_POINT`], and the points' accumulation.
    pub fn encode_visibility(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        bindings: &TierBindings,
        frame: &TierFrame<'_>,
        atlas: &AtlasBinding<'_>,
    ) -> Result<(), RenderError> {
        let viewport = (frame.camera.viewport.x, frame.camera.viewport.y);
        if viewport != (self.size.0 as f32, self.size.1 as f32) {
            return Err(RenderError::InvalidInput(format!(
                "the camera's viewport {viewport:?} differs from the tier's size {:?}",
                self.size
            )));
        }
        let settings = frame.settings;
        if frame.instance_count >= TIER_POINT_BIT {
            return Err(RenderError::TooLarge {
                what: "grains (indices must stay below the point bit)",
                requested: u64::from(frame.instance_count),
                limit: u64::from(TIER_POINT_BIT) - 1,
            });
        }
        if !(settings.coverage_threshold > 0.0 && settings.coverage_threshold <= 1.0) {
            return Err(RenderError::InvalidSetting {
                field: "coverage_threshold",
                reason: format!("{}: must be in (0, 1]", settings.coverage_threshold),
            });
        }
        let lists = [LIST_IMPOSTOR_OCCLUDER, LIST_IMPOSTOR_REST, LIST_POINT];
        queue.write_buffer(&self.camera, 0, bytemuck::bytes_of(frame.camera));
        queue.write_buffer(&self.sampling, 0, bytemuck::bytes_of(&frame.sampling));
        let cloud = CloudUniforms {
            grain_count: frame.instance_count,
            texels: atlas.texels.max(1),
            layers: atlas.layers,
            coverage_threshold: settings.coverage_threshold,
            owner_pass: 0,
        };
        queue.write_buffer(&self.cloud, 0, bytemuck::bytes_of(&cloud));
        let flags = if settings.composite { TIER_COMPOSITE } else { 0 };
        let (depth_scale, inverse_scale) = raster_depth_scale(frame.camera)?;
        let tier = TierUniforms {
            counts: UVec4::new(frame.instance_count, flags, self.samples, 0),
            lists: UVec4::new(lists[0], lists[1], lists[2], 0),
            raster: Vec4::new(depth_scale, inverse_scale, 0.0, 0.0),
        };
        queue.write_buffer(&self.tier, 0, bytemuck::bytes_of(&tier));
        let mut passes = vec![0u8; (PASS_ENTRIES * self.pass_stride) as usize];
        for (k, &list) in lists.iter().enumerate() {
            for owner_pass in 0..2 {
                let entry = TierPass { list, early_z: u32::from(settings.early_z), owner_pass, slot: k as u32 };
                let at = ((2 * k as u32 + owner_pass) * self.pass_stride) as usize;
                passes[at..at + 16].copy_from_slice(bytemuck::bytes_of(&entry));
            }
        }
        queue.write_buffer(&self.passes, 0, &passes);
        encoder.clear_buffer(&self.stats, 0, None);
        encoder.clear_buffer(&self.point_sums, 0, None);

        let pixel_groups = (self.size.0.div_ceil(PIXEL_TILE), self.size.1.div_ceil(PIXEL_TILE));
        let raster = settings.path == ImpostorPath::Raster;
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("impostor tier"),
                timestamp_writes: None,
            });
            pass.set_bind_group(0, &bindings.splat, &[0]);
            pass.set_pipeline(&self.pipelines.arguments);
            pass.set_bind_group(1, &bindings.arguments, &[]);
            pass.dispatch_workgroups(1, 1, 1);
            pass.set_pipeline(&self.pipelines.clear);
            pass.set_bind_group(1, &bindings.clear, &[]);
            pass.dispatch_workgroups(pixel_groups.0, pixel_groups.1, 1);
        }
        if raster {
            let draws = [0, 1].map(|k: u64| u64::from(TIER_DRAW_ARGUMENTS) * 4 + 16 * k);
            self.raster.encode_draws(encoder, &bindings.splat, &self.arguments, [0, 2 * self.pass_stride], draws);
        }
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("impostor tier: visibility"),
            timestamp_writes: None,
        });
        let owner_passes: &[u32] = if self.kind == VisibilityKind::TwoPass32 { &[0, 1] } else { &[0] };
        for &owner_pass in owner_passes {
            if raster {
                pass.set_bind_group(0, &bindings.splat, &[owner_pass * self.pass_stride]);
                self.raster.encode_merge(&mut pass, PIXEL_TILE);
            }
            for (k, &list) in lists.iter().enumerate() {
                if raster && list != LIST_POINT {
                    continue;
                }
                let offset = (2 * k as u32 + owner_pass) * self.pass_stride;
                pass.set_bind_group(0, &bindings.splat, &[offset]);
                let splitter_arguments = u64::from(list * INDIRECT_WORDS + INDIRECT_DISPATCH) * 4;
                if list == LIST_POINT {
                    pass.set_pipeline(&self.pipelines.point_splat);
                    pass.dispatch_workgroups_indirect(&bindings.indirect, splitter_arguments);
                    continue;
                }
                pass.set_pipeline(&self.pipelines.small);
                pass.dispatch_workgroups_indirect(&bindings.indirect, splitter_arguments);
                pass.set_pipeline(&self.pipelines.large);
                pass.dispatch_workgroups_indirect(&self.arguments, 12 * k as u64);
            }
        }
        // Every point grain in the layer that won its pixel adds to the pixel's sums.
        pass.set_bind_group(0, &bindings.splat, &[4 * self.pass_stride]);
        pass.set_pipeline(&self.pipelines.point_accumulate);
        let point_arguments = u64::from(LIST_POINT * INDIRECT_WORDS + INDIRECT_DISPATCH) * 4;
        pass.dispatch_workgroups_indirect(&bindings.indirect, point_arguments);
        Ok(())
    }

    /// Records the resolve of the visibility buffer [`ImpostorTier::encode_visibility`] made
    /// into the G-buffer (one compute pass, the uniforms of that frame).
    pub fn encode_resolve(&self, encoder: &mut wgpu::CommandEncoder, bindings: &TierBindings) {
        let pixel_groups = (self.size.0.div_ceil(PIXEL_TILE), self.size.1.div_ceil(PIXEL_TILE));
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("impostor tier: resolve"),
            timestamp_writes: None,
        });
        pass.set_bind_group(0, &bindings.splat, &[0]);
        pass.set_pipeline(&self.pipelines.resolve);
        pass.set_bind_group(1, &bindings.resolve, &[]);
        pass.dispatch_workgroups(pixel_groups.0, pixel_groups.1, 1);
    }

    /// Every buffer the tier owns, named. None can be mapped.
    pub fn buffers(&self) -> Vec<(&'static str, &wgpu::Buffer)> {
        vec![
            ("camera", &self.camera),
            ("sampling", &self.sampling),
            ("cloud settings", &self.cloud),
            ("tier settings", &self.tier),
            ("passes", &self.passes),
            ("visibility", &self.visibility),
            ("owners", &self.owner),
            ("stats", &self.stats),
            ("arguments", &self.arguments),
            ("point sums", &self.point_sums),
        ]
    }
}
