//! The deferred shading pass: reads the screen G-buffer ([`crate::scene::GBUFFER_LAYERS`])
//! and writes a displayable image. The mesh ground truth and the impostor cloud both go
//! through it, so that their images differ only by their G-buffers.
//!
//! # Model (`shaders/shading.wgsl`)
//!
//! One directional light of irradiance `E` from the unit direction `l`, a uniform ambient
//! radiance `A`, and per pixel (normal `n`, view direction `v` toward the camera, albedo
//! `ρ`, roughness `r`, metallic `m`):
//!
//! ```text
//! L = [ (1 - m) ρ/π  +  F(v·h) D(n·h) G(l) G(v) / (4 (n·l)(n·v)) ] E max(n·l, 0)  +  A ρ
//! ```
//!
//! with the GGX distribution `D` of `α = r²` (Walter et al. 2007, eq. 33), the separable
//! Smith masking `G(x) = 2 (n·x) / ((n·x) + sqrt(α² + (1 - α²)(n·x)²))` (ibid., eq. 34),
//! and Schlick's Fresnel with `F0 = mix(0.04, ρ, m)`. Pixels blend with the background
//! colour by coverage: `coverage · L + (1 - coverage) · background`.
//!
//! The output is `Rgba8Unorm` holding **sRGB-encoded** values (the linear result clamped
//! to `[0, 1]` and encoded with the sRGB transfer function), ready to save as PNG.

use glam::{Vec3, Vec4};

use crate::gpu_util::{GpuError, compose, read_texture, scoped, storage_texture_entry, uniform_entry};
use crate::mesh_gbuffer::ScreenGbuffer;
use crate::scene::{CameraUniforms, PIXEL_TILE, ShadingUniforms};

/// The WGSL of the shading pass (composed after the generated declarations).
pub const SHADING_WGSL: &str = include_str!("../shaders/shading.wgsl");

/// The format of the shaded image: sRGB-encoded values in an `Rgba8Unorm` texture.
pub const SHADED_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

impl ShadingUniforms {
    /// A light from `toward_light` (normalized here; `None` when zero or not finite) with
    /// irradiance `light_colour`, ambient radiance `ambient` and `background` colour.
    pub fn new(toward_light: Vec3, light_colour: Vec3, ambient: Vec3, background: Vec3) -> Option<Self> {
        let direction = toward_light.try_normalize()?;
        Some(Self {
            light_direction: direction.extend(0.0),
            light_colour: light_colour.extend(0.0),
            ambient: ambient.extend(0.0),
            background: background.extend(1.0),
        })
    }
}

/// The compiled shading pipeline.
#[derive(Debug)]
pub struct ShadingPass {
    pipeline: wgpu::ComputePipeline,
    layout: wgpu::BindGroupLayout,
}

fn sampled_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    crate::gpu_util::loaded_texture_entry(binding, wgpu::TextureViewDimension::D2)
}

impl ShadingPass {
    /// Compiles the pipeline.
    pub fn new(device: &wgpu::Device) -> Result<Self, GpuError> {
        scoped(device, || {
            let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("deferred shading"),
                source: wgpu::ShaderSource::Wgsl(compose(&[SHADING_WGSL]).into()),
            });
            let compute = wgpu::ShaderStages::COMPUTE;
            let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("deferred shading"),
                entries: &[
                    uniform_entry(0, compute, false, size_of::<CameraUniforms>() as u64),
                    uniform_entry(1, compute, false, size_of::<ShadingUniforms>() as u64),
                    sampled_entry(2),
                    sampled_entry(3),
                    sampled_entry(4),
                    storage_texture_entry(5, SHADED_FORMAT),
                ],
            });
            let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("deferred shading"),
                bind_group_layouts: &[Some(&layout)],
                immediate_size: 0,
            });
            let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("deferred shading"),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some("shade"),
                compilation_options: Default::default(),
                cache: None,
            });
            ShadingPass { pipeline, layout }
        })
    }

    /// A texture of the G-buffer's size that [`shade`](Self::shade) can write and
    /// [`read_image`] can read.
    pub fn create_target(&self, device: &wgpu::Device, gbuffer: &ScreenGbuffer) -> Result<wgpu::Texture, GpuError> {
        scoped(device, || {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some("shaded image"),
                size: wgpu::Extent3d { width: gbuffer.width, height: gbuffer.height, depth_or_array_layers: 1 },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: SHADED_FORMAT,
                usage: wgpu::TextureUsages::STORAGE_BINDING
                    | wgpu::TextureUsages::TEXTURE_BINDING
                    | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            })
        })
    }

    /// Shades `gbuffer` (rendered with `camera`) under `lighting` into `target` (of the
    /// G-buffer's size, format [`SHADED_FORMAT`], storage usage).
    pub fn shade(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        camera: &CameraUniforms,
        lighting: &ShadingUniforms,
        gbuffer: &ScreenGbuffer,
        target: &wgpu::Texture,
    ) -> Result<(), GpuError> {
        let bindings = self.bind(device, gbuffer, target)?;
        scoped(device, || {
            let mut encoder = device.create_command_encoder(&Default::default());
            self.encode(queue, &mut encoder, &bindings, camera, lighting);
            queue.submit([encoder.finish()]);
        })
    }
}

/// The bind group and uniform buffers of one G-buffer and target, for a frame loop
/// ([`ShadingPass::bind`], [`ShadingPass::encode`]).
#[derive(Debug)]
pub struct ShadingBindings {
    camera: wgpu::Buffer,
    lighting: wgpu::Buffer,
    bind_group: wgpu::BindGroup,
    size: (u32, u32),
}

impl ShadingPass {
    /// Binds `gbuffer` and `target` (as for [`shade`](Self::shade)) once, with uniform
    /// buffers that [`encode`](Self::encode) rewrites each frame.
    pub fn bind(
        &self,
        device: &wgpu::Device,
        gbuffer: &ScreenGbuffer,
        target: &wgpu::Texture,
    ) -> Result<ShadingBindings, GpuError> {
        if (target.width(), target.height()) != (gbuffer.width, gbuffer.height) {
            return Err(GpuError::InvalidRequest(format!(
                "shading target {}×{} differs from the G-buffer {}×{}",
                target.width(),
                target.height(),
                gbuffer.width,
                gbuffer.height
            )));
        }
        scoped(device, || {
            let uniform = |size: usize| {
                device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("deferred shading uniforms"),
                    size: size as u64,
                    usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                })
            };
            let camera = uniform(size_of::<CameraUniforms>());
            let lighting = uniform(size_of::<ShadingUniforms>());
            let target_view = target.create_view(&Default::default());
            let view = |view| wgpu::BindingResource::TextureView(view);
            let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("deferred shading"),
                layout: &self.layout,
                entries: &[
                    wgpu::BindGroupEntry { binding: 0, resource: camera.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 1, resource: lighting.as_entire_binding() },
                    wgpu::BindGroupEntry { binding: 2, resource: view(&gbuffer.views[0]) },
                    wgpu::BindGroupEntry { binding: 3, resource: view(&gbuffer.views[1]) },
                    wgpu::BindGroupEntry { binding: 4, resource: view(&gbuffer.views[2]) },
                    wgpu::BindGroupEntry { binding: 5, resource: view(&target_view) },
                ],
            });
            ShadingBindings { camera, lighting, bind_group, size: (gbuffer.width, gbuffer.height) }
        })
    }

    /// Writes `camera` and `lighting` through `queue` and records the shading of the bound
    /// G-buffer into the bound target (one compute pass, no submission).
    pub fn encode(
        &self,
        queue: &wgpu::Queue,
        encoder: &mut wgpu::CommandEncoder,
        bindings: &ShadingBindings,
        camera: &CameraUniforms,
        lighting: &ShadingUniforms,
    ) {
        queue.write_buffer(&bindings.camera, 0, bytemuck::bytes_of(camera));
        queue.write_buffer(&bindings.lighting, 0, bytemuck::bytes_of(lighting));
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("deferred shading"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&self.pipeline);
        pass.set_bind_group(0, &bindings.bind_group, &[]);
        pass.dispatch_workgroups(bindings.size.0.div_ceil(PIXEL_TILE), bindings.size.1.div_ceil(PIXEL_TILE), 1);
    }
}

/// Reads a shaded image ([`SHADED_FORMAT`]) back as an `RgbaImage` (sRGB-encoded).
pub fn read_image(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    target: &wgpu::Texture,
) -> Result<image::RgbaImage, GpuError> {
    let bytes = read_texture(device, queue, target, 4)?;
    image::RgbaImage::from_raw(target.width(), target.height(), bytes)
        .ok_or_else(|| GpuError::Readback("shaded image has the wrong size".into()))
}

/// The CPU twin of the shader's sRGB encoding of one linear channel (clamped to `[0, 1]`).
pub fn linear_to_srgb(linear: f32) -> f32 {
    let c = linear.clamp(0.0, 1.0);
    if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 }
}

/// The CPU twin of the shader's model (see the module documentation) for one surface
/// point, in linear RGB, before coverage blending.
pub fn shade_surface(
    lighting: &ShadingUniforms,
    normal: Vec3,
    toward_viewer: Vec3,
    albedo: Vec3,
    roughness: f32,
    metallic: f32,
) -> Vec3 {
    let l = lighting.light_direction.truncate();
    let n_dot_l = normal.dot(l);
    let n_dot_v = normal.dot(toward_viewer).max(1e-4);
    let ambient = lighting.ambient.truncate() * albedo;
    if n_dot_l <= 0.0 {
        return ambient;
    }
    let h = (l + toward_viewer).normalize();
    let alpha = (roughness * roughness).max(1e-3);
    let f0 = Vec3::splat(0.04).lerp(albedo, metallic);
    let fresnel = f0 + (Vec3::ONE - f0) * (1.0 - h.dot(toward_viewer).max(0.0)).powi(5);
    let a2 = alpha * alpha;
    let n_dot_h = normal.dot(h).max(0.0);
    let d = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
    let distribution = a2 / (std::f32::consts::PI * d * d);
    let g1 = |x: f32| 2.0 * x / (x + (a2 + (1.0 - a2) * x * x).sqrt());
    let specular = fresnel * distribution * g1(n_dot_l) * g1(n_dot_v) / (4.0 * n_dot_l * n_dot_v);
    let diffuse = (1.0 - metallic) * albedo / std::f32::consts::PI;
    (diffuse + specular) * lighting.light_colour.truncate() * n_dot_l + ambient
}

/// Unused-channel helper: the background of `lighting` as an sRGB-encoded pixel.
pub fn background_pixel(lighting: &ShadingUniforms) -> [u8; 4] {
    let b: Vec4 = lighting.background;
    let encode = |c: f32| (linear_to_srgb(c) * 255.0).round() as u8;
    [encode(b.x), encode(b.y), encode(b.z), 255]
}

#[cfg(test)]
mod tests {
    use super::*;
    use wgsl_gen::ComposedShader;

    #[test]
    fn shading_shader_validates() {
        let shader = ComposedShader::new("shading")
            .with_part(crate::scene::GENERATED_WGSL_PATH, crate::scene::GENERATED_WGSL)
            .with_part("crates/grain-impostor/shaders/shading.wgsl", SHADING_WGSL);
        shader.validate().unwrap_or_else(|e| panic!("{e}"));
    }

    #[test]
    fn lambert_dominates_a_rough_surface_and_the_back_gets_only_ambient() {
        let lighting = ShadingUniforms::new(Vec3::Z, Vec3::splat(3.0), Vec3::splat(0.1), Vec3::ZERO).unwrap();
        let albedo = Vec3::splat(0.5);
        let lit = shade_surface(&lighting, Vec3::Z, Vec3::Z, albedo, 1.0, 0.0);
        let lambert = albedo / std::f32::consts::PI * 3.0 + 0.1 * albedo;
        // With α = 1 the GGX lobe is 1/π and F = 0.04: the specular adds 3 · 0.04 / (4π).
        let specular = 3.0 * 0.04 / (4.0 * std::f32::consts::PI);
        assert!((lit - lambert - Vec3::splat(specular)).abs().max_element() < 1e-5, "{lit}");
        assert_eq!(shade_surface(&lighting, Vec3::NEG_Z, Vec3::Z, albedo, 0.5, 0.0), 0.1 * albedo);
        assert!(ShadingUniforms::new(Vec3::ZERO, Vec3::ONE, Vec3::ZERO, Vec3::ZERO).is_none());
    }

    #[test]
    fn srgb_encoding_matches_the_standard_breakpoints() {
        assert_eq!(linear_to_srgb(0.0), 0.0);
        assert!((linear_to_srgb(1.0) - 1.0).abs() < 1e-6);
        assert!((linear_to_srgb(0.5) - 0.735_357).abs() < 1e-5);
        assert_eq!(linear_to_srgb(2.0), linear_to_srgb(1.0));
    }
}
