//! The I/O of `octahedral_map_differential` and `impostor_sampling_differential`.

use glam::{UVec2, Vec4};
use gpu_layout::{StructDecl, gpu_struct};
use octahedral_map::OctahedralViews;

gpu_struct! {
    /// The view layout a kernel evaluates.
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
    pub fn new(views: OctahedralViews) -> Self {
        Self { subdivisions: views.subdivisions(), view_count: views.view_count(), padding: UVec2::ZERO }
    }
}

gpu_struct! {
    /// One camera ray in world space and the grain it samples (the layout of
    /// `grain-impostor`'s `GrainInstance` follows the ray): the input of the differential
    /// test kernel of `octahedral_map::sample_impostor`.
    pub struct ImpostorRayQuery {
        /// World-space ray origin (`xyz`; `w` ignored).
        pub world_origin: Vec4,
        /// World-space ray direction (`xyz`; need not be unit; `w` ignored).
        pub world_direction: Vec4,
        /// Grain centre (`xyz`) and uniform scale (`w`).
        pub centre_scale: Vec4,
        /// Grain rotation, grain → world, as a quaternion `(x, y, z, w)` (normalized by the
        /// sampler).
        pub rotation: Vec4,
    }
}

/// The kernels' structs.
pub const STRUCTS: &[StructDecl] = &[StructDecl::of::<OctahedralUniforms>(), StructDecl::of::<ImpostorRayQuery>()];
