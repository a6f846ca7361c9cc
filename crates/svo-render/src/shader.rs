//! The GPU kernels' WGSL: the generated declarations of [`SvoFrameUniforms`],
//! [`GpuTruthSettings`] and [`TILE`], and the kernels `shaders/svo_render.wgsl` (the frame)
//! and `shaders/svo_truth.wgsl` (the voxel truth), composed after `svo-tracer`'s twin.

use glam::{UVec4, Vec4};
use gpu_layout::{gpu_const, gpu_struct};
use wgsl_gen::{ComposedShader, GenerateError, StructDecl, generate_declarations};

/// The side of the kernel's square workgroups: one invocation per pixel in
/// `TILE × TILE` tiles, so that the cones of a workgroup are neighbours and read the same
/// bricks.
pub const TILE: u32 = 8;

gpu_struct! {
    /// What the frame kernel needs beside the camera and the trace settings.
    pub struct SvoFrameUniforms {
        /// `(exposure, 0, 0, 0)`: the image stores the sRGB encoding of
        /// `exposure × radiance`, as [`crate::Frame::to_rgba8`] does.
        pub exposure: Vec4,
    }
}

gpu_struct! {
    /// [`crate::truth::TruthSettings`] for the voxel truth's kernel
    /// (`svo_render_voxel_truth`).
    pub struct GpuTruthSettings {
        /// `(k rays per axis, m lens samples per axis, s shadow rays per axis, max steps)`.
        pub counts: UVec4,
        /// `(ε, jitter (0 or 1), 0, 0)`.
        pub epsilon_jitter: Vec4,
    }
}

/// Path of the committed generated declarations, relative to the workspace root.
pub const GENERATED_WGSL_PATH: &str = "crates/svo-render/shaders/generated.wgsl";
/// The committed generated declarations.
pub const GENERATED_WGSL: &str = include_str!("../shaders/generated.wgsl");
const FRAME_PATH: &str = "crates/svo-render/shaders/svo_render.wgsl";
const FRAME: &str = include_str!("../shaders/svo_render.wgsl");
const TRUTH_PATH: &str = "crates/svo-render/shaders/svo_truth.wgsl";
const TRUTH: &str = include_str!("../shaders/svo_truth.wgsl");

/// The structs of the crate, for WGSL generation.
pub fn struct_declarations() -> Vec<StructDecl> {
    vec![StructDecl::of::<SvoFrameUniforms>(), StructDecl::of::<GpuTruthSettings>()]
}

/// The declarations as the Rust source says they should be now (`cargo xtask codegen`
/// writes them to [`GENERATED_WGSL_PATH`]).
pub fn generated_wgsl() -> Result<String, GenerateError> {
    generate_declarations("svo_render", &struct_declarations(), &[gpu_const!("SVO_RENDER_TILE": u32 = TILE)])
}

/// The frame kernel (`svo_render_frame`): `svo-tracer`'s twin (with `svo-brick`'s,
/// `abuffer-mask`'s and `smith-micro`'s), the declarations and `svo_render.wgsl`.
pub fn frame_shader() -> ComposedShader {
    ComposedShader::of_module(&svo_tracer::WGSL)
        .with_part(GENERATED_WGSL_PATH, GENERATED_WGSL)
        .with_part(FRAME_PATH, FRAME)
}

/// The voxel truth's kernel (`svo_render_voxel_truth`, [`crate::GpuVoxelTruth`]): `svo-tracer`'s
/// twin (with `svo-brick`'s), the declarations and `svo_truth.wgsl`.
pub fn truth_shader() -> ComposedShader {
    ComposedShader::of_module(&svo_tracer::WGSL)
        .with_part(GENERATED_WGSL_PATH, GENERATED_WGSL)
        .with_part(TRUTH_PATH, TRUTH)
}

#[cfg(test)]
mod tests {
    use super::*;
    use wgsl_gen::check_layout;

    #[test]
    fn committed_generated_wgsl_is_fresh_and_laid_out_like_rust() {
        let expected = generated_wgsl().unwrap();
        assert!(GENERATED_WGSL == expected, "stale {GENERATED_WGSL_PATH}; run `cargo xtask codegen`");
        for shader in [frame_shader(), truth_shader()] {
            let module = shader.validate().unwrap_or_else(|e| panic!("{e}"));
            check_layout(&module.module, &struct_declarations()).unwrap();
            let mut structs = struct_declarations();
            structs.extend(svo_tracer::WGSL.structs.iter().cloned());
            check_layout(&module.module, &structs).unwrap();
        }
    }
}
