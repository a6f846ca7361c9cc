//! The impostor tier's **raster path** ([`ImpostorPath::Raster`](crate::ImpostorPath)): the
//! impostors as sprites with a hardware depth test — the paper's own form (§4, §9) and the
//! comparison for the compute path.
//!
//! Each element of an impostor list is one instance of a 6-vertex `draw_indirect` (arguments
//! written on the GPU by the tier's `tier_arguments`): the two triangles of the grain's screen
//! rectangle, whose pixel centres are exactly the pixels the compute splat visits. Each
//! fragment evaluates the same `cloud_hit` as the compute splat (the shared WGSL of
//! `grain_impostor::cloud`), discards what it does not cover, and writes the grain's index
//! into an `R32Uint` target and its view depth times [`raster_depth_scale`] as its depth
//! (`Depth32Float`, compare `Less`, cleared to 1). The scale is a power of two, so the scaled
//! depth is exact and orders like the view depth: the depth test picks the nearest hit as
//! the visibility buffer does. The occluder list is drawn first and the rest second (§9's
//! double draw; with the depth written by the fragment, the hardware tests it late, so the
//! second draw is not cheaper per fragment here — the compute path's software early-Z is).
//! A compute pass then offers every pixel's winner to the visibility buffer (which holds the
//! mesh tier's depth in composite mode), and the points and the resolve run as on the compute
//! path: both paths write the same G-buffer from the same winners.
//!
//! Where the two paths can differ: ties of equal depth go to the first drawn grain here and
//! to the smallest index in compute; a fragment and a compute invocation compiled apart may
//! round `cloud_hit` differently (an `f32` ulp in depth, or coverage at exactly the threshold);
//! and depths beyond the far plane clamp to 1 here. The GPU test bounds each.

use grain_impostor::scene::CameraUniforms;

use crate::error::RenderError;

/// The depth attachment's format.
pub const RASTER_DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// The owner target's format (a grain index, `TIER_NONE` where no impostor covers).
pub const RASTER_OWNER_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R32Uint;

/// `(s, 1/s)`: the power of two `s` that maps view depths up to the far plane of `camera`
/// into `[0, 1]` (`s = 2^-⌈log2 far⌉`, far measured along the view axis from the eye, or from
/// the near plane of an orthographic camera, as the G-buffer's depth is). Multiplying by
/// `s` is exact, so the depth test orders scaled depths exactly as the view depths.
pub fn raster_depth_scale(camera: &CameraUniforms) -> Result<(f32, f32), RenderError> {
    let inverse = camera.world_from_clip().as_dmat4();
    let unproject = |z: f64| inverse.project_point3(glam::DVec3::new(0.0, 0.0, z));
    let (near, far) = (unproject(0.0), unproject(1.0));
    let forward = (far - near).normalize();
    let origin = if camera.eye.w != 0.0 { camera.eye.truncate().as_dvec3() } else { near };
    let depth = (far - origin).dot(forward);
    if !(depth.is_finite() && depth > 0.0) {
        return Err(RenderError::InvalidInput(format!("the camera's far plane is at view depth {depth}")));
    }
    let exponent = depth.log2().ceil().clamp(-126.0, 126.0) as i32;
    let scale = 2f32.powi(-exponent);
    Ok((scale, 1.0 / scale))
}

/// The raster path's pipelines and targets for one viewport size, built once.
pub(crate) struct RasterPath {
    size: (u32, u32),
    sprites: wgpu::RenderPipeline,
    merge: wgpu::ComputePipeline,
    owner: wgpu::TextureView,
    depth: wgpu::TextureView,
    merge_bind_group: wgpu::BindGroup,
}

impl RasterPath {
    /// Builds the sprite pipeline (group 0: the tier's `layout`) and the merge pipeline
    /// (group 1: the raster targets, `samples × samples` texels per pixel) from the tier's
    /// shader `module`.
    pub(crate) fn new(
        device: &wgpu::Device,
        module: &wgpu::ShaderModule,
        layout: &wgpu::BindGroupLayout,
        size: (u32, u32),
        samples: u32,
    ) -> Self {
        let texture = |label: &str, format: wgpu::TextureFormat| {
            device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: wgpu::Extent3d {
                        width: size.0 * samples,
                        height: size.1 * samples,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: 1,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
                    view_formats: &[],
                })
                .create_view(&wgpu::TextureViewDescriptor::default())
        };
        let owner = texture("impostor raster owners", RASTER_OWNER_FORMAT);
        let depth = texture("impostor raster depth", RASTER_DEPTH_FORMAT);
        let targets_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("impostor raster targets"),
            entries: &[target_entry(0, wgpu::TextureSampleType::Uint), target_entry(1, wgpu::TextureSampleType::Depth)],
        });
        let sprites_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("impostor raster sprites"),
            bind_group_layouts: &[Some(layout)],
            immediate_size: 0,
        });
        let sprites = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("impostor raster sprites"),
            layout: Some(&sprites_layout),
            vertex: wgpu::VertexState {
                module,
                entry_point: Some("tier_raster_vertex"),
                compilation_options: Default::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: Some(wgpu::DepthStencilState {
                format: RASTER_DEPTH_FORMAT,
                depth_write_enabled: Some(true),
                depth_compare: Some(wgpu::CompareFunction::Less),
                stencil: Default::default(),
                bias: Default::default(),
            }),
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module,
                entry_point: Some("tier_raster_fragment"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState::from(RASTER_OWNER_FORMAT))],
            }),
            multiview_mask: None,
            cache: None,
        });
        let merge_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("impostor raster merge"),
            bind_group_layouts: &[Some(layout), Some(&targets_layout)],
            immediate_size: 0,
        });
        let merge = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some("impostor raster merge"),
            layout: Some(&merge_layout),
            module,
            entry_point: Some("tier_raster_merge"),
            compilation_options: Default::default(),
            cache: None,
        });
        let merge_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("impostor raster targets"),
            layout: &targets_layout,
            entries: &[
                wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&owner) },
                wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::TextureView(&depth) },
            ],
        });
        Self { size, sprites, merge, owner, depth, merge_bind_group }
    }

    /// Records the render pass: the impostor lists' sprites in order, each with its
    /// [`TierPass`](crate::TierPass) entry at `pass_offsets[k]` of `bind_group`, from the
    /// draw arguments at byte `draw_offsets[k]` of `arguments`.
    pub(crate) fn encode_draws(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        bind_group: &wgpu::BindGroup,
        arguments: &wgpu::Buffer,
        pass_offsets: [u32; 2],
        draw_offsets: [u64; 2],
    ) {
        let none = wgpu::Color { r: f64::from(u32::MAX), g: 0.0, b: 0.0, a: 0.0 };
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("impostor raster sprites"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &self.owner,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations { load: wgpu::LoadOp::Clear(none), store: wgpu::StoreOp::Store },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &self.depth,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Store }),
                stencil_ops: None,
            }),
            ..Default::default()
        });
        pass.set_pipeline(&self.sprites);
        for (offset, draw) in pass_offsets.into_iter().zip(draw_offsets) {
            pass.set_bind_group(0, bind_group, &[offset]);
            pass.draw_indirect(arguments, draw);
        }
    }

    /// Records the merge of the raster winners into the visibility buffer (group 0 must be
    /// bound with the pass entry of the owner pass to run).
    pub(crate) fn encode_merge(&self, pass: &mut wgpu::ComputePass<'_>, tile: u32) {
        pass.set_pipeline(&self.merge);
        pass.set_bind_group(1, &self.merge_bind_group, &[]);
        pass.dispatch_workgroups(self.size.0.div_ceil(tile), self.size.1.div_ceil(tile), 1);
    }
}

fn target_entry(binding: u32, sample_type: wgpu::TextureSampleType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Texture {
            sample_type,
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn depth_scale_is_a_power_of_two_covering_the_far_plane() {
        for far in [0.75f32, 1.0, 3.0, 100.0, 1000.0] {
            let camera =
                CameraUniforms::perspective(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 0.8, (64, 48), (0.1, far))
                    .unwrap();
            let (scale, inverse) = raster_depth_scale(&camera).unwrap();
            assert_eq!(scale.to_bits() & 0x007f_ffff, 0, "{scale} is a power of two");
            assert_eq!(scale * inverse, 1.0);
            // The far plane maps into [0, 1], and no smaller power of two would do.
            assert!(far * scale <= 1.0 + 1e-6 && far * scale > 0.5 - 1e-6, "far {far}: scale {scale}");
        }
    }
}
