//! The crate's WGSL twin (feature `wgsl`): the generated declaration of [`GpuQuadric`] and
//! the functions of `wgsl/quadric_fit.wgsl`, each the twin of the [`intersect`](crate::intersect)
//! function named in its comment.

use gpu_layout::{StructDecl, WgslModule};

use crate::gpu_quadric::GpuQuadric;

/// The WGSL twin of this crate: `quadric_value`, `quadric_gradient`, `quadric_normal` and
/// `quadric_first_hit` (Algorithm 3.2) over the generated `GpuQuadric`; no dependencies.
pub const WGSL: WgslModule = WgslModule {
    name: "quadric_fit",
    declarations: include_str!("../wgsl/generated/quadric_fit.wgsl"),
    library: include_str!("../wgsl/quadric_fit.wgsl"),
    naga_oil_source: concat!(
        include_str!("../wgsl/generated/quadric_fit.naga_oil_header.wgsl"),
        include_str!("../wgsl/generated/quadric_fit.wgsl"),
        include_str!("../wgsl/quadric_fit.wgsl"),
    ),
    dependencies: &[],
    structs: &[StructDecl::of::<GpuQuadric>()],
    constants: &[],
};
