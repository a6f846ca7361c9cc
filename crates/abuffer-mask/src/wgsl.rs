//! The crate's WGSL twin (feature `wgsl`): the generated declarations of
//! [`MaskTableUniforms`] and the constants below, and the functions of
//! `wgsl/abuffer_mask.wgsl`, each the twin of the Rust function named in its comment.
//!
//! In WGSL every mask is a `vec4<u32>` whatever `N` (unused words are zero), so one set of
//! functions serves `N = 32, 64, 128`; the table itself is the flat `u32` buffer of
//! [`MaskTable::words`](crate::MaskTable::words).

use gpu_layout::f32_bits::{ABS_MASK, INFINITY_BITS};
use gpu_layout::{StructDecl, WgslModule, gpu_const};

use crate::half_plane::V_SATURATION;
use crate::samples::MAX_SAMPLES;
use crate::table::{INDEX_CLAMP, MaskTableUniforms};

/// The WGSL twin of this crate: the table lookup (`abuffer_theta_index`, `abuffer_v_index`,
/// `abuffer_cell_index`, `abuffer_mask_word_offset`), the mask operations of Algorithm 1
/// (union, difference, intersection, popcount, coverage) and the half-plane of a cone
/// element (`abuffer_half_plane`, §5.4); no dependencies.
pub const WGSL: WgslModule = WgslModule {
    name: "abuffer_mask",
    declarations: include_str!("../wgsl/generated/abuffer_mask.wgsl"),
    library: include_str!("../wgsl/abuffer_mask.wgsl"),
    naga_oil_source: concat!(
        include_str!("../wgsl/generated/abuffer_mask.naga_oil_header.wgsl"),
        include_str!("../wgsl/generated/abuffer_mask.wgsl"),
        include_str!("../wgsl/abuffer_mask.wgsl"),
    ),
    dependencies: &[],
    structs: &[StructDecl::of::<MaskTableUniforms>()],
    constants: &[
        gpu_const!(V_SATURATION: f32 as "ABUFFER_V_SATURATION"),
        gpu_const!("ABUFFER_MAX_SAMPLES": u32 = MAX_SAMPLES as u32),
        gpu_const!(INDEX_CLAMP: f32 as "ABUFFER_INDEX_CLAMP"),
        gpu_const!(ABS_MASK: u32 as "ABUFFER_ABS_MASK"),
        gpu_const!(INFINITY_BITS: u32 as "ABUFFER_INFINITY_BITS"),
    ],
};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniforms_are_32_bytes() {
        assert_eq!(size_of::<MaskTableUniforms>(), 32);
    }
}
