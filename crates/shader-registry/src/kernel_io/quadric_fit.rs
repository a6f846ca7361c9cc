//! The I/O of `quadric_fit_differential`.

use glam::{Vec2, Vec3, Vec4};
use gpu_layout::{StructDecl, gpu_struct};
use quadric_fit::GpuQuadric;

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
    pub fn new(quadric: &GpuQuadric, origin: Vec3, direction: Vec3, t_min: f32, t_max: f32) -> Self {
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

/// The kernel's structs.
pub const STRUCTS: &[StructDecl] = &[StructDecl::of::<QuadricRayQuery>()];
