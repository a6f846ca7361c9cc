//! Pre-filtered sparse voxel octrees after Heitz & Neyret, *Representing Appearance and
//! Pre-filtering Subpixel Data in Sparse Voxel Octrees* (HPG 2012), §5.2 and §6.
//!
//! (Crate documentation in progress.)
#![no_std]

extern crate alloc;
#[cfg(all(test, feature = "std"))]
extern crate std;

mod accuracy;
mod descriptor;
mod half;
mod layout;
mod octree;
mod prefilter;
mod sample;
mod surface;
#[cfg(feature = "wgsl")]
mod wgsl;

pub use accuracy::{DeviationError, InterpolationError, moment_correction_error};
pub use descriptor::{ATTRIBUTE_CHANNELS, Voxel};
pub use half::{HALF_MAX, HALF_MIN_POSITIVE, f32_to_half, half_to_f32};
pub use layout::{COMPACT_DISTANCE_RANGE, COMPACT_DISTANCE_STEPS, MAX_VOXEL_WORDS, RawVoxel, VoxelLayout};
pub use octree::{BrickSize, BrickTree, BuildError, BuildOptions, Domain, MAX_LEVELS, OctreeNode};
pub use prefilter::{HeightVariance, SurfaceStatistics, surface_statistics};
pub use sample::{
    FRACTION_STEPS, MAX_BRICK_BINDINGS, OctreeUniforms, PackedTree, PoolError, RawSample, SPLIT_MASK, lerp, lerp_raw,
};
pub use surface::{Cell, SdfSurface, SurfaceError, SurfaceSample, SurfaceSource, thin_shell_samples};
#[cfg(feature = "wgsl")]
pub use wgsl::WGSL;
