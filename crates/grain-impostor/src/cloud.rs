//! Rendering a cloud of impostor grains into the screen G-buffer, in compute passes
//! (Michel & Boubekeur 2020, §4.1 and §5; per-pixel work in compute, see
//! `docs/ARCHITECTURE.md`).
//!
//! One grain type = one atlas: every [`GrainInstance`](crate::scene::GrainInstance) of
//! the instance buffer is drawn with the same atlas textures (the layers of
//! [`ATLAS_LAYERS`](crate::scene::ATLAS_LAYERS), bound as raw `wgpu::TextureView`s so
//! that this module does not depend on the atlas type) and the same
//! [`ImpostorSamplingUniforms`] (layout, radii, sampling mode, view selection).
//!
//! # Passes (`crates/grain-impostor/shaders/cloud.wgsl`)
//!
//! 1. `clear_cloud`: per pixel, nearest depth and owner ← none.
//! 2. `splat_depth`: one workgroup per grain walks the screen bounding rectangle of the
//!    grain's outer sphere. A pixel is **covered** when the blended atlas coverage
//!    `Σ wᵢ αᵢ` of the four views (§5 sampling, explicit LOD) reaches
//!    [`CloudSettings::coverage_threshold`] (0.5 by default); its depth is that of the
//!    blended surface point read from the atlas depth layer (`Σ wᵢ αᵢ qᵢ / Σ wᵢ αᵢ`,
//!    `qᵢ = ViewFrame::point_at(uvᵢ, depthᵢ)`), moved onto the camera ray. `atomicMin`
//!    of the depth's bits keeps the nearest.
//! 3. `splat_owner`: the same walk; the grain whose depth bits equal the minimum writes
//!    its index (`atomicMin`: ties go to the smallest index). Both splats are one entry
//!    point (`splat_cloud`) run twice, [`CloudUniforms::owner_pass`] selecting the atomic,
//!    so that the depth compared is computed by the same compiled code as the one stored.
//! 4. `resolve_cloud`: per pixel, the owner's four views are read in every atlas layer
//!    (trilinear, LOD = log2 of texels per pixel), blended with the bilinear weights,
//!    un-premultiplied, the grain-local normal rotated to world space; writes
//!    normal + coverage (1 for covered pixels), albedo, material and depth.
//!
//! **Occlusion between grains uses the atlas depth** (the true surface, not the grain
//! centre): overlapping or interpenetrating grains resolve per pixel, which the paper's
//! raster pipeline avoids for early-Z's sake (§10, "Limitations"). Two 32-bit atomic
//! passes replace a 64-bit `depth << 32 | index` `atomicMin`: this needs no
//! `SHADER_INT64_ATOMIC_MIN_MAX` and puts no limit on the grain count, at the cost of
//! walking each grain twice.
//!
//! **Depth** written to the G-buffer: `dot(p − o, forward)`, the distance along the
//! camera's forward axis from `o` = the eye (perspective) or the centre of the near plane
//! (orthographic); background: coverage 0, depth `+∞`. Grains whose bounding cube
//! crosses the eye plane of a perspective camera are skipped.

use glam::Vec2;
use gpu_layout::{GpuConst, gpu_const, gpu_struct};
use octahedral_map::ImpostorSamplingUniforms;
use wgsl_gen::{ComposedShader, GenerateError, StructDecl, generate_declarations};

use crate::gpu_util::storage_texture_entry;
use crate::mesh_gbuffer::GBUFFER_FORMATS;
use crate::scene::{CameraUniforms, PIXEL_TILE};

gpu_struct! {
    /// Per-frame settings of the cloud passes.
    pub struct CloudUniforms {
        /// Number of grains in the instance buffer to draw.
        pub grain_count: u32,
        /// `p`, texels per side of each atlas view (for the level of detail).
        pub texels: u32,
        /// Number of array layers of the atlas textures; views at or beyond it read as
        /// transparent.
        pub layers: u32,
        /// Blended α at or above which a pixel is covered by a grain.
        pub coverage_threshold: f32,
        /// 0: the depth pass of `splat_cloud`; 1: its owner pass.
        pub owner_pass: u32,
    }
}

/// The depth and owner a pixel holds before any grain covers it (both atomics' initial
/// value, above every depth's bits and every grain index).
pub const NO_GRAIN: u32 = u32::MAX;

/// The constants of the cloud shader, generated with its uniforms.
const CLOUD_CONSTANTS: &[GpuConst] = &[gpu_const!(NO_GRAIN: u32 as "CLOUD_NONE")];

/// Settings of [`ImpostorCloudPass::encode`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CloudSettings {
    /// Blended atlas α at or above which a pixel counts as covered (0.5 by default).
    pub coverage_threshold: f32,
}

impl Default for CloudSettings {
    fn default() -> Self {
        Self { coverage_threshold: 0.5 }
    }
}

/// Path of the committed generated WGSL of this module, relative to the workspace root.
pub const CLOUD_GENERATED_WGSL_PATH: &str = "crates/grain-impostor/shaders/cloud_generated.wgsl";
/// The committed generated declarations of this module.
pub const CLOUD_GENERATED_WGSL: &str = include_str!("../shaders/cloud_generated.wgsl");
/// Path of the hand-written cloud shader.
pub const CLOUD_WGSL_PATH: &str = "crates/grain-impostor/shaders/cloud.wgsl";
/// The hand-written cloud shader.
pub const CLOUD_WGSL: &str = include_str!("../shaders/cloud.wgsl");
/// Path of the sampling functions shared with other impostor passes.
pub const CLOUD_SAMPLING_WGSL_PATH: &str = "crates/grain-impostor/shaders/cloud_sampling.wgsl";
/// The sampling functions (`cloud_hit`, `cloud_surface`, `cloud_grain_rectangle`, …): they
/// read `camera`, `sampling`, `cloud` and the atlas textures the including shader declares.
pub const CLOUD_SAMPLING_WGSL: &str = include_str!("../shaders/cloud_sampling.wgsl");

/// The structs of this module, for WGSL generation.
pub fn cloud_struct_declarations() -> Vec<StructDecl> {
    vec![StructDecl::of::<CloudUniforms>()]
}

/// The WGSL declarations of [`CloudUniforms`] as the Rust source says they should be now
/// (`cargo xtask codegen` writes them to [`CLOUD_GENERATED_WGSL_PATH`]).
pub fn cloud_generated_wgsl() -> Result<String, GenerateError> {
    generate_declarations("grain_impostor_cloud", &cloud_struct_declarations(), CLOUD_CONSTANTS)
}

/// `octahedral-map`'s WGSL twin ([`octahedral_map::WGSL`]), this crate's scene
/// declarations, the cloud declarations and the sampling functions
/// ([`CLOUD_SAMPLING_WGSL`]), named `name`: the start of every shader that samples impostor
/// atlases per pixel (it declares the bindings and entry points after).
pub fn cloud_sampling_shader(name: &str) -> ComposedShader {
    ComposedShader::new(name)
        .with_module(&octahedral_map::WGSL)
        .with_part(crate::scene::GENERATED_WGSL_PATH, crate::scene::GENERATED_WGSL)
        .with_part(CLOUD_GENERATED_WGSL_PATH, CLOUD_GENERATED_WGSL)
        .with_part(CLOUD_SAMPLING_WGSL_PATH, CLOUD_SAMPLING_WGSL)
}

/// The composed cloud shader: [`cloud_sampling_shader`] and `cloud.wgsl`.
pub fn cloud_shader() -> ComposedShader {
    cloud_sampling_shader("octahedral_map.composed").with_part(CLOUD_WGSL_PATH, CLOUD_WGSL)
}

/// Why the cloud pass could not be built or encoded.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CloudError {
    /// The composed shader failed naga validation (the message names the file and line).
    InvalidShader(String),
    /// The viewport needs more per-pixel scratch memory than one storage binding allows.
    ViewportTooLarge {
        /// Pixels requested.
        pixels: u64,
        /// The most pixels the adapter's storage-binding limit allows.
        limit: u64,
    },
    /// The grain count needs more workgroups than the dispatch limit allows.
    TooManyGrains {
        /// Grains requested.
        grains: u32,
        /// The most grains one dispatch can handle on this adapter.
        limit: u64,
    },
    /// The camera's viewport is empty or not an integer size.
    InvalidViewport,
}

impl std::fmt::Display for CloudError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::InvalidShader(message) => write!(f, "cloud shader ({CLOUD_WGSL_PATH}): {message}"),
            Self::ViewportTooLarge { pixels, limit } => {
                write!(f, "impostor cloud: {pixels} pixels exceed the adapter's {limit}-pixel scratch limit")
            }
            Self::TooManyGrains { grains, limit } => {
                write!(f, "impostor cloud: {grains} grains exceed the adapter's dispatch limit of {limit}")
            }
            Self::InvalidViewport => write!(f, "impostor cloud: the camera's viewport is empty"),
        }
    }
}

impl std::error::Error for CloudError {}

/// The atlas of one grain type, as raw views (layers of
/// [`ATLAS_LAYERS`](crate::scene::ATLAS_LAYERS), `D2Array`, premultiplied α, full mips).
#[derive(Clone, Copy, Debug)]
pub struct AtlasBinding<'a> {
    /// `normal_alpha` layer.
    pub normal_alpha: &'a wgpu::TextureView,
    /// `albedo_alpha` layer.
    pub albedo_alpha: &'a wgpu::TextureView,
    /// `material_alpha` layer.
    pub material_alpha: &'a wgpu::TextureView,
    /// `depth_alpha` layer.
    pub depth_alpha: &'a wgpu::TextureView,
    /// A filtering sampler (linear min/mag/mipmap, clamp to edge for trilinear reads).
    pub sampler: &'a wgpu::Sampler,
    /// `p`, texels per side of each view.
    pub texels: u32,
    /// Array layers of the atlas textures (`2n²`, or the compact count).
    pub layers: u32,
}

/// The G-buffer targets in [`GBUFFER_LAYERS`](crate::scene::GBUFFER_LAYERS) order; the
/// textures need `STORAGE_BINDING` (as those of [`ScreenGbuffer`](crate::mesh_gbuffer::ScreenGbuffer)).
#[derive(Clone, Copy, Debug)]
pub struct GBufferBinding<'a> {
    /// `normal_coverage` (`Rgba16Float`).
    pub normal_coverage: &'a wgpu::TextureView,
    /// `albedo` (`Rgba8Unorm`).
    pub albedo: &'a wgpu::TextureView,
    /// `material` (`Rgba8Unorm`).
    pub material: &'a wgpu::TextureView,
    /// `depth` (`R32Float`).
    pub depth: &'a wgpu::TextureView,
}

/// The compiled cloud passes.
#[derive(Debug)]
pub struct ImpostorCloudPass {
    layout: wgpu::BindGroupLayout,
    clear: wgpu::ComputePipeline,
    splat: wgpu::ComputePipeline,
    resolve: wgpu::ComputePipeline,
}

/// One frame's inputs: camera, sampling configuration and grains.
#[derive(Clone, Copy, Debug)]
pub struct CloudFrame<'a> {
    /// The camera; its viewport must equal the G-buffer size.
    pub camera: &'a CameraUniforms,
    /// Layout, radii (`R` must be the atlas bake extent), mode and view selection, from
    /// `octahedral_map::ImpostorSampler::uniforms`.
    pub sampling: ImpostorSamplingUniforms,
    /// Storage buffer of `GrainInstance`s.
    pub instances: &'a wgpu::Buffer,
    /// Number of grains to draw from `instances`.
    pub grain_count: u32,
    /// Coverage threshold and other settings.
    pub settings: CloudSettings,
}

fn texture_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: true },
            view_dimension: wgpu::TextureViewDimension::D2Array,
            multisampled: false,
        },
        count: None,
    }
}

fn buffer_entry(binding: u32, ty: wgpu::BufferBindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer { ty, has_dynamic_offset: false, min_binding_size: None },
        count: None,
    }
}

impl ImpostorCloudPass {
    /// Validates the composed shader with naga and builds the pipelines.
    pub fn new(device: &wgpu::Device) -> Result<Self, CloudError> {
        let shader = cloud_shader();
        shader.validate().map_err(|e| CloudError::InvalidShader(e.to_string()))?;
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("impostor cloud"),
            source: wgpu::ShaderSource::Wgsl(shader.source().into()),
        });
        let uniform = wgpu::BufferBindingType::Uniform;
        let read_only = wgpu::BufferBindingType::Storage { read_only: true };
        let read_write = wgpu::BufferBindingType::Storage { read_only: false };
        let entries = [
            buffer_entry(0, uniform),
            buffer_entry(1, uniform),
            buffer_entry(2, uniform),
            buffer_entry(3, read_only),
            buffer_entry(4, read_write),
            buffer_entry(5, read_write),
            texture_entry(6),
            texture_entry(7),
            texture_entry(8),
            texture_entry(9),
            wgpu::BindGroupLayoutEntry {
                binding: 10,
                visibility: wgpu::ShaderStages::COMPUTE,
                ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                count: None,
            },
            storage_texture_entry(11, GBUFFER_FORMATS[0]),
            storage_texture_entry(12, GBUFFER_FORMATS[1]),
            storage_texture_entry(13, GBUFFER_FORMATS[2]),
            storage_texture_entry(14, GBUFFER_FORMATS[3]),
        ];
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("impostor cloud"),
            entries: &entries,
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("impostor cloud"),
            bind_group_layouts: &[Some(&layout)],
            immediate_size: 0,
        });
        let pipeline = |entry: &str| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(entry),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(entry),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        Ok(Self {
            clear: pipeline("clear_cloud"),
            splat: pipeline("splat_cloud"),
            resolve: pipeline("resolve_cloud"),
            layout,
        })
    }

    /// Records the four passes into `encoder`. `timestamps`, when given, receives 8
    /// timestamps (start and end of each pass) at indices `0..8` of the query set.
    pub fn encode(
        &self,
        device: &wgpu::Device,
        encoder: &mut wgpu::CommandEncoder,
        frame: &CloudFrame<'_>,
        atlas: &AtlasBinding<'_>,
        gbuffer: &GBufferBinding<'_>,
        timestamps: Option<&wgpu::QuerySet>,
    ) -> Result<(), CloudError> {
        use wgpu::util::DeviceExt;
        let viewport = Vec2::new(frame.camera.viewport.x, frame.camera.viewport.y);
        if !(viewport.x >= 1.0 && viewport.y >= 1.0) || viewport.fract() != Vec2::ZERO {
            return Err(CloudError::InvalidViewport);
        }
        let (width, height) = (viewport.x as u32, viewport.y as u32);
        let limits = device.limits();
        let pixels = u64::from(width) * u64::from(height);
        let max_pixels = limits.max_storage_buffer_binding_size.min(limits.max_buffer_size) / 4;
        if pixels > max_pixels {
            return Err(CloudError::ViewportTooLarge { pixels, limit: max_pixels });
        }
        let max_groups = u64::from(limits.max_compute_workgroups_per_dimension);
        if u64::from(frame.grain_count) > max_groups * max_groups {
            return Err(CloudError::TooManyGrains { grains: frame.grain_count, limit: max_groups * max_groups });
        }
        let cloud = |owner_pass| CloudUniforms {
            grain_count: frame.grain_count,
            texels: atlas.texels.max(1),
            layers: atlas.layers,
            coverage_threshold: frame.settings.coverage_threshold,
            owner_pass,
        };
        let uniform = |label: &str, bytes: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytes,
                usage: wgpu::BufferUsages::UNIFORM,
            })
        };
        let camera_buffer = uniform("cloud camera", bytemuck::bytes_of(frame.camera));
        let sampling_buffer = uniform("cloud sampling", bytemuck::bytes_of(&frame.sampling));
        let cloud_buffers = [0, 1].map(|pass| uniform("cloud settings", bytemuck::bytes_of(&cloud(pass))));
        let scratch = |label: &str| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: pixels * 4,
                usage: wgpu::BufferUsages::STORAGE,
                mapped_at_creation: false,
            })
        };
        let nearest = scratch("cloud nearest depth");
        let owner = scratch("cloud owner");
        let bind_group = |cloud_buffer: &wgpu::Buffer| {
            let entries = [
                wgpu::BindGroupEntry { binding: 0, resource: camera_buffer.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 1, resource: sampling_buffer.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 2, resource: cloud_buffer.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 3, resource: frame.instances.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 4, resource: nearest.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 5, resource: owner.as_entire_binding() },
                wgpu::BindGroupEntry { binding: 6, resource: wgpu::BindingResource::TextureView(atlas.normal_alpha) },
                wgpu::BindGroupEntry { binding: 7, resource: wgpu::BindingResource::TextureView(atlas.albedo_alpha) },
                wgpu::BindGroupEntry { binding: 8, resource: wgpu::BindingResource::TextureView(atlas.material_alpha) },
                wgpu::BindGroupEntry { binding: 9, resource: wgpu::BindingResource::TextureView(atlas.depth_alpha) },
                wgpu::BindGroupEntry { binding: 10, resource: wgpu::BindingResource::Sampler(atlas.sampler) },
                wgpu::BindGroupEntry {
                    binding: 11,
                    resource: wgpu::BindingResource::TextureView(gbuffer.normal_coverage),
                },
                wgpu::BindGroupEntry { binding: 12, resource: wgpu::BindingResource::TextureView(gbuffer.albedo) },
                wgpu::BindGroupEntry { binding: 13, resource: wgpu::BindingResource::TextureView(gbuffer.material) },
                wgpu::BindGroupEntry { binding: 14, resource: wgpu::BindingResource::TextureView(gbuffer.depth) },
            ];
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("impostor cloud"),
                layout: &self.layout,
                entries: &entries,
            })
        };
        let [depth_group, owner_group] = [bind_group(&cloud_buffers[0]), bind_group(&cloud_buffers[1])];
        let pixel_groups = (width.div_ceil(PIXEL_TILE), height.div_ceil(PIXEL_TILE));
        let grains = u64::from(frame.grain_count);
        let grain_groups = if grains <= max_groups {
            (grains as u32, 1)
        } else {
            (max_groups as u32, grains.div_ceil(max_groups) as u32)
        };
        let passes = [
            (&self.clear, pixel_groups, "clear_cloud", &depth_group),
            (&self.splat, grain_groups, "splat_depth", &depth_group),
            (&self.splat, grain_groups, "splat_owner", &owner_group),
            (&self.resolve, pixel_groups, "resolve_cloud", &depth_group),
        ];
        for (k, (pipeline, (x, y), label, bind_group)) in passes.into_iter().enumerate() {
            let writes = timestamps.map(|query_set| wgpu::ComputePassTimestampWrites {
                query_set,
                beginning_of_pass_write_index: Some(2 * k as u32),
                end_of_pass_write_index: Some(2 * k as u32 + 1),
            });
            let mut pass = encoder
                .begin_compute_pass(&wgpu::ComputePassDescriptor { label: Some(label), timestamp_writes: writes });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, bind_group, &[]);
            if x > 0 && y > 0 {
                pass.dispatch_workgroups(x, y, 1);
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use wgsl_gen::check_layout;

    #[test]
    fn committed_cloud_wgsl_is_fresh_valid_and_laid_out_like_rust() {
        let expected = cloud_generated_wgsl().unwrap();
        assert!(CLOUD_GENERATED_WGSL == expected, "stale {CLOUD_GENERATED_WGSL_PATH}; run `cargo xtask codegen`");
        let module = cloud_shader().validate().unwrap_or_else(|e| panic!("{e}"));
        check_layout(&module.module, &cloud_struct_declarations()).unwrap();
        check_layout(&module.module, &crate::scene::struct_declarations()).unwrap();
    }
}
