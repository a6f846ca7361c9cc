//! Structs and constants shared with the WGSL twin, `shaders/abuffer_mask.wgsl`.
//!
//! Their WGSL declarations are generated into `shaders/generated/abuffer_mask.wgsl` by
//! `cargo xtask codegen`; a test checks that the WGSL layout equals this one.
//!
//! In WGSL every mask is a `vec4<u32>` whatever `N` (unused words are zero), so one set of
//! functions serves `N = 32, 64, 128`; the table itself is the flat `u32` buffer of
//! [`MaskTable::words`](crate::MaskTable::words).

use gpu_layout::{GpuConst, gpu_const, gpu_struct};

use crate::half_plane::V_SATURATION;
use crate::samples::MAX_SAMPLES;

gpu_struct! {
    /// Describes a [`MaskTable`](crate::MaskTable) to a shader (§5.4): its resolution, the
    /// lookup scales (precomputed in `f32` on the CPU so that both sides use the same bits)
    /// and the mask size.
    pub struct MaskTableUniforms {
        /// `T`, cells along `θ`.
        pub theta_count: u32,
        /// `V`, cells along `v`.
        pub v_count: u32,
        /// `W = N / 32`, `u32` words per mask.
        pub words_per_mask: u32,
        /// `N`, samples per mask.
        pub sample_count: u32,
        /// `T / 2π` as `f32` ([`TableLayout::theta_scale`](crate::TableLayout::theta_scale)).
        pub theta_scale: f32,
        /// `(V − 1) / 2√2` as `f32` ([`TableLayout::v_scale`](crate::TableLayout::v_scale)).
        pub v_scale: f32,
        /// `1 / N`, exact (a power of two): coverage is `popcount × coverage_scale`.
        pub coverage_scale: f32,
        /// Explicit padding to 16 bytes; always zero.
        pub padding: u32,
    }
}

/// `MAX_SAMPLES` as a `u32` for WGSL.
const MAX_SAMPLES_U32: u32 = MAX_SAMPLES as u32;

/// Constants of this crate that the WGSL twin uses, for `cargo xtask codegen`.
pub const WGSL_CONSTANTS: &[GpuConst] = &[
    gpu_const!(V_SATURATION: f32 as "ABUFFER_V_SATURATION"),
    gpu_const!(MAX_SAMPLES_U32: u32 as "ABUFFER_MAX_SAMPLES"),
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniforms_are_32_bytes() {
        assert_eq!(size_of::<MaskTableUniforms>(), 32);
    }
}
