//! The outputs of the per-pixel pass.

use crate::error::DdmRenderError;

/// What a [`DdmTarget`] writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TargetKind {
    /// A storage buffer of [`BaseRenderPixel`](ddm_tracer::tangent_space::BaseRenderPixel)s.
    Pixels,
    /// A [`COLOR_TARGET_FORMAT`](crate::COLOR_TARGET_FORMAT) storage texture.
    Color,
    /// A [`COLOR_TARGET_FORMAT`](crate::COLOR_TARGET_FORMAT) and a [`DEPTH_TARGET_FORMAT`](crate::DEPTH_TARGET_FORMAT) storage texture, depth-tested.
    ColorDepth,
}

/// The output of the per-pixel pass: its bind group, built once by
/// [`DdmRenderer::pixel_target`](crate::DdmRenderer::pixel_target) or [`DdmRenderer::color_target`](crate::DdmRenderer::color_target) for a G-buffer size.
#[derive(Clone, Debug)]
pub struct DdmTarget {
    pub(super) bind_group: wgpu::BindGroup,
    pub(super) kind: TargetKind,
    pub(super) width: u32,
    pub(super) height: u32,
    /// The colour and depth views a [`TargetKind::ColorDepth`] target clears.
    pub(super) clear_views: Option<(wgpu::TextureView, wgpu::TextureView)>,
}

impl DdmTarget {
    /// Records a render pass that clears a [`TargetKind::ColorDepth`] target's textures to
    /// zero (nothing drawn): once per frame, before the first object's
    /// [`DdmRenderer::encode`](crate::DdmRenderer::encode). Errors for another kind of target.
    pub fn encode_clear(&self, encoder: &mut wgpu::CommandEncoder) -> Result<(), DdmRenderError> {
        let Some((color, depth)) = &self.clear_views else {
            return Err(DdmRenderError::InvalidTarget {
                what: "the target to clear",
                problem: "only a colour and depth target is cleared by the renderer".into(),
            });
        };
        let attachment = |view| {
            Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                    store: wgpu::StoreOp::Store,
                },
            })
        };
        drop(encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("ddm-render clear colour and depth"),
            color_attachments: &[attachment(color), attachment(depth)],
            ..Default::default()
        }));
        Ok(())
    }

    /// What the target receives.
    pub fn kind(&self) -> TargetKind {
        self.kind
    }

    /// `(width, height)` in pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }
}
