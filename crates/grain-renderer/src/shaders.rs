//! The crate's WGSL: generated declarations ([`TierUniforms`], [`TierPass`],
//! [`MeshTierUniforms`] and the
//! constants of [`crate::tier_layout`] and of the splitter's lists it reads) and the
//! composed shaders of the tiers.

use gpu_layout::{GpuConst, gpu_const};
use grain_splitter::lists::{COUNTER_COUNT, COUNTER_OFFSET, ELEMENT_WORKGROUP, MAX_GROUPS_PER_DIMENSION};
use wgsl_gen::{ComposedShader, GenerateError, StructDecl, generate_declarations};

use crate::tier_layout::{MeshTierUniforms, TIER_CONSTANTS, TierPass, TierUniforms};

/// Path of the committed generated declarations, relative to the workspace root.
pub const GENERATED_WGSL_PATH: &str = "crates/grain-renderer/shaders/generated.wgsl";
/// The committed generated declarations.
pub const GENERATED_WGSL: &str = include_str!("../shaders/generated.wgsl");

const TIER_PATH: &str = "crates/grain-renderer/shaders/impostor_tier.wgsl";
const TIER: &str = include_str!("../shaders/impostor_tier.wgsl");
const POINT_TIER_PATH: &str = "crates/grain-renderer/shaders/point_tier.wgsl";
const POINT_TIER: &str = include_str!("../shaders/point_tier.wgsl");
const RASTER_PATH: &str = "crates/grain-renderer/shaders/impostor_raster.wgsl";
const RASTER: &str = include_str!("../shaders/impostor_raster.wgsl");
const MESH_TIER_PATH: &str = "crates/grain-renderer/shaders/mesh_tier.wgsl";
const MESH_TIER: &str = include_str!("../shaders/mesh_tier.wgsl");
const VISIBILITY_64_PATH: &str = "crates/grain-renderer/shaders/tier_visibility_64.wgsl";
const VISIBILITY_64: &str = include_str!("../shaders/tier_visibility_64.wgsl");
const VISIBILITY_32_PATH: &str = "crates/grain-renderer/shaders/tier_visibility_32.wgsl";
const VISIBILITY_32: &str = include_str!("../shaders/tier_visibility_32.wgsl");

/// The constants of the splitter's lists the tier reads (`grain_splitter::lists`).
const LIST_CONSTANTS: &[GpuConst] = &[
    gpu_const!(COUNTER_COUNT: u32),
    gpu_const!(COUNTER_OFFSET: u32),
    gpu_const!(ELEMENT_WORKGROUP: u32),
    gpu_const!(MAX_GROUPS_PER_DIMENSION: u32),
];

/// The structs of the crate, for WGSL generation.
pub fn struct_declarations() -> Vec<StructDecl> {
    vec![StructDecl::of::<TierUniforms>(), StructDecl::of::<TierPass>(), StructDecl::of::<MeshTierUniforms>()]
}

/// The declarations as the Rust source says they should be now (`cargo xtask codegen`
/// writes them to [`GENERATED_WGSL_PATH`]).
pub fn generated_wgsl() -> Result<String, GenerateError> {
    generate_declarations("grain_renderer", &struct_declarations(), &[TIER_CONSTANTS, LIST_CONSTANTS].concat())
}

/// The impostor tier with the 64-bit visibility buffer (needs `SHADER_INT64` and
/// `SHADER_INT64_ATOMIC_MIN_MAX`).
pub fn impostor_tier_64_shader() -> ComposedShader {
    grain_impostor::cloud::cloud_sampling_shader("grain_renderer_impostor_tier_64")
        .with_part(GENERATED_WGSL_PATH, GENERATED_WGSL)
        .with_part(VISIBILITY_64_PATH, VISIBILITY_64)
        .with_part(TIER_PATH, TIER)
        .with_part(POINT_TIER_PATH, POINT_TIER)
        .with_part(RASTER_PATH, RASTER)
}

/// The impostor tier with the two-pass 32-bit visibility buffer.
pub fn impostor_tier_32_shader() -> ComposedShader {
    grain_impostor::cloud::cloud_sampling_shader("grain_renderer_impostor_tier_32")
        .with_part(GENERATED_WGSL_PATH, GENERATED_WGSL)
        .with_part(VISIBILITY_32_PATH, VISIBILITY_32)
        .with_part(TIER_PATH, TIER)
        .with_part(POINT_TIER_PATH, POINT_TIER)
        .with_part(RASTER_PATH, RASTER)
}

/// The mesh tier: `grain-impostor`'s mesh raster (`mesh_gbuffer.wgsl`) with a vertex entry
/// point that reads the splitter's mesh list.
pub fn mesh_tier_shader() -> ComposedShader {
    ComposedShader::new("grain_renderer_mesh_tier")
        .with_part(grain_impostor::scene::GENERATED_WGSL_PATH, grain_impostor::scene::GENERATED_WGSL)
        .with_part("crates/grain-impostor/shaders/mesh_gbuffer.wgsl", grain_impostor::mesh_gbuffer::MESH_GBUFFER_WGSL)
        .with_part(GENERATED_WGSL_PATH, GENERATED_WGSL)
        .with_part(MESH_TIER_PATH, MESH_TIER)
}

/// The naga capabilities of the 64-bit visibility buffer.
pub fn int64_capabilities() -> naga::valid::Capabilities {
    naga::valid::Capabilities::SHADER_INT64 | naga::valid::Capabilities::SHADER_INT64_ATOMIC_MIN_MAX
}

#[cfg(test)]
mod tests {
    use super::*;
    use wgsl_gen::check_layout;

    #[test]
    fn committed_generated_wgsl_is_fresh_and_laid_out_like_rust() {
        let expected = generated_wgsl().unwrap();
        assert!(GENERATED_WGSL == expected, "stale {GENERATED_WGSL_PATH}; run `cargo xtask codegen`");
        let module = impostor_tier_32_shader().validate().unwrap_or_else(|e| panic!("{e}"));
        check_layout(&module.module, &struct_declarations()).unwrap();
    }

    #[test]
    fn both_visibility_buffers_validate_with_naga() {
        impostor_tier_32_shader().validate().unwrap_or_else(|e| panic!("{e}"));
        mesh_tier_shader().validate().unwrap_or_else(|e| panic!("{e}"));
        impostor_tier_64_shader().validate_with(int64_capabilities()).unwrap_or_else(|e| panic!("{e}"));
        assert!(impostor_tier_64_shader().validate().is_err(), "the 64-bit buffer needs the capabilities");
    }
}
