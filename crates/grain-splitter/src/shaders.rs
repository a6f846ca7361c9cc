//! The crate's WGSL: generated declarations (from [`crate::SplitCamera`],
//! [`crate::SplitParams`], [`crate::hiz::HizParams`] and the constants of `lists`, `settings`
//! and `hiz`), and the composed shaders of the passes.

use gpu_layout::GpuConst;
use wgsl_gen::{ComposedShader, GenerateError, StructDecl, generate_declarations};

use crate::camera::SplitCamera;
use crate::hiz::{HIZ_CONSTANTS, HizParams};
use crate::lists::LIST_CONSTANTS;
use crate::settings::{SETTINGS_CONSTANTS, SplitParams};

/// Path of the committed generated declarations, relative to the workspace root.
pub const GENERATED_WGSL_PATH: &str = "crates/grain-splitter/shaders/generated.wgsl";
/// The committed generated declarations.
pub const GENERATED_WGSL: &str = include_str!("../shaders/generated.wgsl");

const PROJECTION_PATH: &str = "crates/grain-splitter/shaders/projection.wgsl";
const PROJECTION: &str = include_str!("../shaders/projection.wgsl");
const MAP_64_PATH: &str = "crates/grain-splitter/shaders/occluder_map_64.wgsl";
const MAP_64: &str = include_str!("../shaders/occluder_map_64.wgsl");
const MAP_32_PATH: &str = "crates/grain-splitter/shaders/occluder_map_32.wgsl";
const MAP_32: &str = include_str!("../shaders/occluder_map_32.wgsl");
const HIZ_COMMON_PATH: &str = "crates/grain-splitter/shaders/hiz_common.wgsl";
const HIZ_COMMON: &str = include_str!("../shaders/hiz_common.wgsl");
const HIZ_PATH: &str = "crates/grain-splitter/shaders/hiz.wgsl";
const HIZ: &str = include_str!("../shaders/hiz.wgsl");
const HIZ_TEST_PATH: &str = "crates/grain-splitter/shaders/hiz_test.wgsl";
const HIZ_TEST: &str = include_str!("../shaders/hiz_test.wgsl");
const SPLIT_PATH: &str = "crates/grain-splitter/shaders/split.wgsl";
const SPLIT: &str = include_str!("../shaders/split.wgsl");

/// The structs of the crate, for WGSL generation.
pub fn struct_declarations() -> Vec<StructDecl> {
    vec![StructDecl::of::<SplitCamera>(), StructDecl::of::<SplitParams>(), StructDecl::of::<HizParams>()]
}

/// The constants of the crate, for WGSL generation.
pub fn constants() -> Vec<GpuConst> {
    [LIST_CONSTANTS, SETTINGS_CONSTANTS, HIZ_CONSTANTS].concat()
}

/// The declarations as the Rust source says they should be now (`cargo xtask codegen`
/// writes them to [`GENERATED_WGSL_PATH`]).
pub fn generated_wgsl() -> Result<String, GenerateError> {
    generate_declarations("grain_splitter", &struct_declarations(), &constants())
}

fn with_projection(name: &str) -> ComposedShader {
    ComposedShader::new(name).with_part(GENERATED_WGSL_PATH, GENERATED_WGSL).with_part(PROJECTION_PATH, PROJECTION)
}

/// The 64-bit occluder map pass (needs `SHADER_INT64` and `SHADER_INT64_ATOMIC_MIN_MAX`).
pub fn occluder_map_64_shader() -> ComposedShader {
    with_projection("grain_splitter_occluder_map_64").with_part(MAP_64_PATH, MAP_64)
}

/// The two-pass 32-bit occluder map.
pub fn occluder_map_32_shader() -> ComposedShader {
    with_projection("grain_splitter_occluder_map_32").with_part(MAP_32_PATH, MAP_32)
}

/// The pyramid of occluder fusion (per-pixel bounds, then one reduction per level).
pub fn hiz_shader() -> ComposedShader {
    with_projection("grain_splitter_hiz").with_part(HIZ_COMMON_PATH, HIZ_COMMON).with_part(HIZ_PATH, HIZ)
}

/// The splitter's passes, after `occlusion-cone`'s WGSL twin, with the Hi-Z test.
pub fn split_shader() -> ComposedShader {
    ComposedShader::of_module(&occlusion_cone::WGSL)
        .with_part(GENERATED_WGSL_PATH, GENERATED_WGSL)
        .with_part(PROJECTION_PATH, PROJECTION)
        .with_part(SPLIT_PATH, SPLIT)
        .with_part(HIZ_COMMON_PATH, HIZ_COMMON)
        .with_part(HIZ_TEST_PATH, HIZ_TEST)
}

/// The naga capabilities the 64-bit map needs.
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
        let module = split_shader().validate().unwrap_or_else(|e| panic!("{e}"));
        check_layout(&module.module, &struct_declarations()).unwrap();
    }

    #[test]
    fn every_shader_validates_with_naga() {
        occluder_map_32_shader().validate().unwrap_or_else(|e| panic!("{e}"));
        hiz_shader().validate().unwrap_or_else(|e| panic!("{e}"));
        occluder_map_64_shader().validate_with(int64_capabilities()).unwrap_or_else(|e| panic!("{e}"));
        // Without the capabilities the 64-bit map is rejected, so the fallback is needed.
        assert!(occluder_map_64_shader().validate().is_err());
    }
}
