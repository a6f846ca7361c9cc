//! The quadric as the GPU stores it: single precision, laid out for WGSL (its declaration
//! is generated into the crate's WGSL twin, see [`WGSL`](crate::WGSL) with the `wgsl`
//! feature).

use glam::{Vec2, Vec4};
use gpu_layout::gpu_struct;

use crate::quadric::Quadric;

gpu_struct! {
    /// A quadric's ten coefficients in single precision, `[A, B, C, D]`, `[E, F, G, H]`,
    /// `[I, J]` (eq. 1), meant for voxel-local coordinates where they are well scaled.
    pub struct GpuQuadric {
        /// `(A, B, C, D)`: the `x²`, `y²`, `z²` and `xy` coefficients.
        pub abcd: Vec4,
        /// `(E, F, G, H)`: the `yz`, `zx`, `x` and `y` coefficients.
        pub efgh: Vec4,
        /// `(I, J)`: the `z` coefficient and the constant.
        pub ij: Vec2,
        /// Explicit padding to WGSL's 16-byte struct alignment; always zero.
        pub padding: Vec2,
    }
}

impl GpuQuadric {
    /// The single-precision form of `quadric` (rounded to nearest).
    pub fn from_quadric(quadric: &Quadric) -> Self {
        let c = quadric.coefficients().map(|x| x as f32);
        Self {
            abcd: Vec4::new(c[0], c[1], c[2], c[3]),
            efgh: Vec4::new(c[4], c[5], c[6], c[7]),
            ij: Vec2::new(c[8], c[9]),
            padding: Vec2::ZERO,
        }
    }

    /// `[A, B, C, D, E, F, G, H, I, J]`.
    pub fn coefficients(&self) -> [f32; 10] {
        let (a, e, i) = (self.abcd, self.efgh, self.ij);
        [a.x, a.y, a.z, a.w, e.x, e.y, e.z, e.w, i.x, i.y]
    }
}
