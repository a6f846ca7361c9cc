//! Structs and constants shared with the WGSL twin, `shaders/octahedral_map.wgsl`.
//!
//! Their WGSL declarations are generated into `shaders/generated/octahedral_map.wgsl` by
//! `cargo xtask codegen`; a test checks that the WGSL layout equals this one.

use glam::{UVec2, UVec4, Vec2};
use gpu_layout::{GpuConst, gpu_const, gpu_struct};

use crate::direction::FALLBACK_DIRECTION;
use crate::views::MAX_SUBDIVISIONS;

gpu_struct! {
    /// The four views nearest to a direction and their interpolation coefficients
    /// (Listing 1 of the paper).
    pub struct ViewSample {
        /// `(i0, i1, i2, i3)`: the views at `(⌊u⌋,⌊v⌋)`, `(⌈u⌉,⌊v⌋)`, `(⌊u⌋,⌈v⌉)`,
        /// `(⌈u⌉,⌈v⌉)` of the direction's hemisphere.
        pub indices: UVec4,
        /// `α = fract(u, v)`: `α.x` interpolates `(i0, i2) → (i1, i3)`, `α.y`
        /// interpolates `(i0, i1) → (i2, i3)`.
        pub alpha: Vec2,
        /// Explicit padding to WGSL's 16-byte struct alignment; always zero.
        pub padding: Vec2,
    }
}

impl ViewSample {
    /// The bilinear weights of `indices`, summing to 1:
    /// `((1-αx)(1-αy), αx(1-αy), (1-αx)αy, αx αy)`.
    pub fn weights(&self) -> [f32; 4] {
        let Vec2 { x, y } = self.alpha;
        [(1.0 - x) * (1.0 - y), x * (1.0 - y), (1.0 - x) * y, x * y]
    }
}

gpu_struct! {
    /// Uniforms of a pass that samples an octahedral impostor.
    pub struct OctahedralUniforms {
        /// `n`, the number of views along an edge of a hemisphere's square.
        pub subdivisions: u32,
        /// `N = 2n²`.
        pub view_count: u32,
        /// Explicit padding to 16 bytes (uniform buffers); always zero.
        pub padding: UVec2,
    }
}

impl OctahedralUniforms {
    /// The uniforms of `views`.
    pub fn new(views: crate::OctahedralViews) -> Self {
        Self { subdivisions: views.subdivisions(), view_count: views.view_count(), padding: UVec2::ZERO }
    }
}

/// Constants of this crate that the WGSL twin uses, for `cargo xtask codegen`.
pub const WGSL_CONSTANTS: &[GpuConst] = &[
    gpu_const!(MAX_SUBDIVISIONS: u32 as "OCTAHEDRAL_MAX_SUBDIVISIONS"),
    gpu_const!(FALLBACK_DIRECTION: Vec3 as "OCTAHEDRAL_FALLBACK_DIRECTION"),
];

/// Per-item layout assertions that do not need naga.
#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn structs_have_the_expected_sizes() {
        assert_eq!(size_of::<ViewSample>(), 32);
        assert_eq!(size_of::<OctahedralUniforms>(), 16);
        let _ = UVec4::ZERO;
    }
}
