//! Conservative directional distance maps and their lossless compression, after Mehra &
//! Kumar, *Accurate and Efficient Rendering of Detail using Directional Distance Maps*
//! (§3.1, §4, Appendix A).
//!
//! A directional distance map (DDM) stores, per voxel and per cone of directions, how far
//! a ray leaving the voxel in that cone can travel without missing the mesostructure.
//! Sphere tracing with it advances faster than with the plain distance map near
//! silhouettes, because surfaces behind the ray no longer limit its steps.
//!
//! ```
//! use ddm_compress::{CompressedMap, DirectionCones, DistanceMapSettings, MapKind, Triangle, compute_distance_maps};
//! use glam::{UVec3, Vec3};
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//!
//! // A floor at z = 1 in a 4 × 4 × 4 grid.
//! let floor = [
//!     Triangle([Vec3::new(0.0, 0.0, 1.0), Vec3::new(4.0, 0.0, 1.0), Vec3::new(4.0, 4.0, 1.0)]),
//!     Triangle([Vec3::new(0.0, 0.0, 1.0), Vec3::new(4.0, 4.0, 1.0), Vec3::new(0.0, 4.0, 1.0)]),
//! ];
//! let cones = DirectionCones::full(4, 2)?;
//! let maps = compute_distance_maps(UVec3::splat(4), &floor, MapKind::Directional(cones), DistanceMapSettings::default())?;
//! // From voxel (1, 1, 3) (z ∈ [3, 4]) the floor is 2 below, but only for downward rays.
//! let voxel = 1 + 4 * (1 + 4 * 3);
//! let down = cones.cone_of(Vec3::new(0.3, 0.2, -1.0)).unwrap() as usize;
//! let up = cones.cone_of(Vec3::new(0.3, 0.2, 1.0)).unwrap() as usize;
//! assert!(maps.values[down][voxel] <= 2.0 && maps.values[down][voxel] > 1.8);
//! assert_eq!(maps.values[up][voxel], maps.max_distance);
//! // Lossless where it matters: blocks crossed by the floor are stored whole.
//! let compressed = CompressedMap::compress(&maps.values[down], &maps.surface, maps.dims, 2)?;
//! assert_eq!(compressed.access(UVec3::new(1, 1, 1)), Some(0.0));
//! # Ok(())
//! # }
//! ```
//!
//! Invalid inputs are errors that say what is wrong, never a silently different map:
//!
//! ```
//! use ddm_compress::{ConeError, DirectionCones, DistanceMapError, DistanceMapSettings, MapKind, compute_distance_maps};
//! use glam::UVec3;
//!
//! assert_eq!(DirectionCones::downward(0, 1), Err(ConeError::ZeroAzimuths));
//! let settings = DistanceMapSettings { tolerance: 0.0, periodic_xy: true };
//! let error = compute_distance_maps(UVec3::splat(4), &[], MapKind::Plain, settings).unwrap_err();
//! assert_eq!(error, DistanceMapError::InvalidTolerance { tolerance: 0.0 });
//! ```
//!
//! # Modules
//!
//! - [`cones`]: the `m × n` direction cones over azimuth and elevation.
//! - [`geometry`]: boxes, triangles, overlap, the exact box–triangle distance
//!   ([`box_triangle_distance`]) and the conservative directional distance bound.
//! - [`bvh`]: the triangle hierarchy that makes [`compute_distance_maps`] fast.
//! - [`ddm`]: directional and plain distance maps of a triangle mesh ([`MapKind`] says
//!   which; [`DistanceMapError`] why inputs are refused; the per-voxel
//!   search over all cones at once lives in the private `search` module, its cone-aware
//!   duality bounds in the private `convex_cone` module, the plain map's box–mesh
//!   distance by alternating projections in the private `plain` module).
//! - [`plain_gpu`]: the plain map's hierarchy laid out for a build on the GPU
//!   ([`PlainGpuScene`]; the kernel and its pipeline are `ddm-render`'s).
//! - [`compress`]: the lookup grid and atlas (Algorithm A.1) and access (Algorithm A.2);
//!   [`CompressError`] says why a map cannot be compressed.
//! - [`f16_storage`]: distances as binary16 rounded down (still conservative), half the
//!   bytes, two per word as a GPU reads them.
//! - [`serialize`]: a versioned binary form that rejects corrupt data.
//!
//! # Using the WGSL twin
//!
//! With the `wgsl` feature, [`WGSL`] is the compressed map's access in WGSL (Algorithm
//! A.2): `ddm_grid_index`, `ddm_entry_is_surface`, `ddm_entry_distance`,
//! `ddm_atlas_index` and `ddm_voxel_in_map` over the generated [`CompressedMapUniforms`];
//! `ddm_grid_index_shifted` and `ddm_atlas_index_shifted` for power-of-two blocks
//! ([`CompressedMap::block_shift`]), and `ddm_f16_pair_value` for an atlas packed by
//! [`pack_f16_pairs_at_most`].
//! It also holds the plain map's per-pair bounds for a build on the GPU
//! (`ddm_plain_pair_lower_bound`, `ddm_box_triangle_distance`, `ddm_triangle_overlaps_box`,
//! `ddm_box_gap_squared`) over the generated [`PlainGpuNode`], [`PlainGpuTriangle`] and
//! [`PlainGpuUniforms`] ([`plain_gpu`]).
//! A shader binds a map's [`CompressedMap::grid`] and [`CompressedMap::atlas`] as storage
//! buffers and its [`CompressedMapUniforms::new`] as uniforms:
//!
//! ```
//! # #[cfg(feature = "wgsl")] {
//! let mut source = String::new();
//! ddm_compress::WGSL.write_source(&mut source).unwrap(); // no dependencies to compose first
//! source.push_str(
//!     "@group(0) @binding(0) var<uniform> map: CompressedMapUniforms;
//!      @group(0) @binding(1) var<storage, read> grid: array<u32>;
//!      @group(0) @binding(2) var<storage, read> atlas: array<f32>;
//!      fn distance_at(voxel: vec3<u32>) -> f32 {
//!          let entry = grid[ddm_grid_index(voxel, map)];
//!          if ddm_entry_is_surface(entry) {
//!              return atlas[map.grid_atlas_base.w + ddm_atlas_index(entry, voxel, map.dims_block.w)];
//!          }
//!          return ddm_entry_distance(entry);
//!      }",
//! );
//! # let module = naga::front::wgsl::parse_str(&source).unwrap_or_else(|e| panic!("{}", e.emit_to_string(&source)));
//! # naga::valid::Validator::new(naga::valid::ValidationFlags::all(), Default::default()).validate(&module).unwrap();
//! assert!(source.contains("fn ddm_grid_index"));
//! # }
//! ```
//!
//! Or register `WGSL.naga_oil_source` with a `naga_oil` composer under the name
//! `ddm_compress` and `#import ddm_compress::{...}`.
//!
//! # Features
//!
//! - `std` (default): enables `std` in the dependencies. The crate is `#![no_std]` with
//!   `alloc`; `cargo check -p ddm-compress --no-default-features` builds it.
//! - `wgsl`: [`WGSL`], the WGSL twin (its sources are embedded; no extra dependency).
//! - `testing`: test and benchmark references, not part of the supported API (the
//!   `testing` module: `reference_distance_maps`, the previous computation, and
//!   `sampled_distance`, a brute-force upper estimate of a directional distance). Enabled
//!   by this crate's tests and the workspace's tests and benchmarks only.
#![no_std]

extern crate alloc;
#[cfg(feature = "std")]
extern crate std;

pub mod bvh;
pub mod compress;
pub mod cones;
mod convex_cone;
pub mod ddm;
pub mod f16_storage;
pub mod geometry;
mod plain;
pub mod plain_gpu;
mod search;
pub mod serialize;
#[cfg(test)]
mod test_random;
#[cfg(any(test, feature = "testing"))]
pub mod testing;
#[cfg(feature = "wgsl")]
mod wgsl;

pub use bvh::TriangleBvh;
pub use compress::{CellDistance, CompressError, CompressedMap, CompressedMapUniforms, MAX_BLOCK, SURFACE_FLAG};
pub use cones::{Cone, ConeError, ConeRelation, DirectionCones, DirectionRange, ElevationBound};
pub use ddm::{
    DistanceMapError, DistanceMapSettings, DistanceMaps, MAX_VALUES, MAX_VOXELS, MapKind, compute_distance_maps,
};
pub use f16_storage::pack_f16_pairs_at_most;
pub use geometry::{Aabb, Triangle, box_triangle_distance};
pub use plain_gpu::{
    PLAIN_GPU_FIRST_BITS, PLAIN_GPU_LEAF, PLAIN_GPU_STACK, PlainGpuError, PlainGpuNode, PlainGpuScene,
    PlainGpuTriangle, PlainGpuUniforms,
};
pub use serialize::DecodeError;
#[cfg(feature = "wgsl")]
pub use wgsl::WGSL;
