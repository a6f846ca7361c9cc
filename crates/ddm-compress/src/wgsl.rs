//! The crate's WGSL twin (feature `wgsl`): the generated declarations of
//! [`CompressedMapUniforms`] and [`SURFACE_FLAG`], and the functions of
//! `wgsl/ddm_compress.wgsl`, the twins of the compressed map's access (Algorithm A.2).

use gpu_layout::{StructDecl, WgslModule, gpu_const};

use crate::compress::{CompressedMapUniforms, SURFACE_FLAG};

/// The WGSL twin of this crate: `ddm_grid_index`, `ddm_atlas_index`,
/// `ddm_entry_is_surface`, `ddm_entry_distance` (the compressed map's access, Algorithm
/// A.2); no dependencies.
pub const WGSL: WgslModule = WgslModule {
    name: "ddm_compress",
    declarations: include_str!("../wgsl/generated/ddm_compress.wgsl"),
    library: include_str!("../wgsl/ddm_compress.wgsl"),
    naga_oil_source: concat!(
        include_str!("../wgsl/generated/ddm_compress.naga_oil_header.wgsl"),
        include_str!("../wgsl/generated/ddm_compress.wgsl"),
        include_str!("../wgsl/ddm_compress.wgsl"),
    ),
    dependencies: &[],
    structs: &[StructDecl::of::<CompressedMapUniforms>()],
    constants: &[gpu_const!(SURFACE_FLAG: u32 as "DDM_SURFACE_FLAG")],
};
