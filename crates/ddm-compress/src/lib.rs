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
//! use ddm_compress::{DirectionCones, DistanceMapSettings, Triangle, compute_distance_maps, CompressedMap};
//! use glam::{UVec3, Vec3};
//!
//! // A floor at z = 1 in a 4 × 4 × 4 grid.
//! let floor = [
//!     Triangle([Vec3::new(0.0, 0.0, 1.0), Vec3::new(4.0, 0.0, 1.0), Vec3::new(4.0, 4.0, 1.0)]),
//!     Triangle([Vec3::new(0.0, 0.0, 1.0), Vec3::new(4.0, 4.0, 1.0), Vec3::new(0.0, 4.0, 1.0)]),
//! ];
//! let cones = DirectionCones::full(4, 2).unwrap();
//! let maps = compute_distance_maps(UVec3::splat(4), &floor, Some(cones), DistanceMapSettings::default()).unwrap();
//! // From voxel (1, 1, 3) (z ∈ [3, 4]) the floor is 2 below, but only for downward rays.
//! let voxel = 1 + 4 * (1 + 4 * 3);
//! let down = cones.cone_of(Vec3::new(0.3, 0.2, -1.0)).unwrap() as usize;
//! let up = cones.cone_of(Vec3::new(0.3, 0.2, 1.0)).unwrap() as usize;
//! assert!(maps.values[down][voxel] <= 2.0 && maps.values[down][voxel] > 1.8);
//! assert_eq!(maps.values[up][voxel], maps.max_distance);
//! // Lossless where it matters: blocks crossed by the floor are stored whole.
//! let compressed = CompressedMap::compress(&maps.values[down], &maps.surface, maps.dims, 2).unwrap();
//! assert_eq!(compressed.access(UVec3::new(1, 1, 1)), Some(0.0));
//! ```
//!
//! # Modules
//!
//! - [`cones`]: the `m × n` direction cones over azimuth and elevation.
//! - [`geometry`]: boxes, triangles, overlap and the conservative directional distance
//!   bound.
//! - [`bvh`]: the triangle hierarchy that makes [`compute_distance_maps`] fast.
//! - [`ddm`]: directional and plain distance maps of a triangle mesh (the per-voxel
//!   search over all cones at once lives in the private `search` module, its cone-aware
//!   duality bounds in the private `convex_cone` module).
//! - [`compress`]: the lookup grid and atlas (Algorithm A.1) and access (Algorithm A.2).
//! - [`serialize`]: a versioned binary form that rejects corrupt data.
//!
//! # Features
//!
//! - `std` (default): enables `std` in the dependencies. The crate is `#![no_std]` with
//!   `alloc`; `cargo check -p ddm-compress --no-default-features` builds it.
#![no_std]

extern crate alloc;
#[cfg(feature = "std")]
extern crate std;

pub mod bvh;
pub mod compress;
pub mod cones;
mod convex_cone;
pub mod ddm;
pub mod geometry;
mod search;
pub mod serialize;
#[cfg(test)]
mod test_random;
#[cfg(feature = "wgsl")]
mod wgsl;

pub use bvh::TriangleBvh;
pub use compress::{CellDistance, CompressedMap, CompressedMapUniforms, SURFACE_FLAG};
pub use cones::{Cone, ConeRelation, DirectionCones, DirectionRange};
pub use ddm::{DistanceMapSettings, DistanceMaps, compute_distance_maps, reference_distance_maps, sampled_distance};
pub use geometry::{Aabb, Triangle};
pub use serialize::DecodeError;
#[cfg(feature = "wgsl")]
pub use wgsl::WGSL;
