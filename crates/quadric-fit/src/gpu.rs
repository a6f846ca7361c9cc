//! The quadric as the GPU stores it, and the structs and constants shared with the WGSL
//! twin `shaders/quadric_fit.wgsl` (generated into `shaders/generated/quadric_fit.wgsl`).

use glam::{Vec2, Vec4};
use gpu_layout::{GpuConst, gpu_struct};

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
        let c = quadric.coefficients.map(|x| x as f32);
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

gpu_struct! {
    /// One ray–quadric query, flattened for a storage buffer: the quadric's coefficients,
    /// the ray and its parameter range (the ray's segment inside the voxel).
    pub struct QuadricRayQuery {
        /// `(A, B, C, D)`.
        pub abcd: Vec4,
        /// `(E, F, G, H)`.
        pub efgh: Vec4,
        /// `(I, J, t_min, t_max)`.
        pub ij_t_range: Vec4,
        /// Ray origin in `xyz`; `w` unused (zero).
        pub origin: Vec4,
        /// Ray direction in `xyz`; `w` unused (zero).
        pub direction: Vec4,
    }
}

impl QuadricRayQuery {
    /// The query for `quadric` and the ray `origin + t direction`, `t ∈ [t_min, t_max]`.
    pub fn new(quadric: &GpuQuadric, origin: glam::Vec3, direction: glam::Vec3, t_min: f32, t_max: f32) -> Self {
        Self {
            abcd: quadric.abcd,
            efgh: quadric.efgh,
            ij_t_range: Vec4::new(quadric.ij.x, quadric.ij.y, t_min, t_max),
            origin: origin.extend(0.0),
            direction: direction.extend(0.0),
        }
    }

    /// The quadric of the query.
    pub fn quadric(&self) -> GpuQuadric {
        GpuQuadric { abcd: self.abcd, efgh: self.efgh, ij: self.ij_t_range.truncate().truncate(), padding: Vec2::ZERO }
    }
}

/// Constants of this crate that the WGSL twin uses (none yet), for `cargo xtask codegen`.
pub const WGSL_CONSTANTS: &[GpuConst] = &[];
