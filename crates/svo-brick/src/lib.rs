//! Pre-filtered sparse voxel octrees after Heitz & Neyret, *Representing Appearance and
//! Pre-filtering Subpixel Data in Sparse Voxel Octrees* (HPG 2012), §5.2 and §6: the data
//! a cone tracer reads.
//!
//! Each voxel stores the macroscopic signed distance `h̄` and normal `n̄` of a surface and
//! Gaussian micro-descriptors of what is below the voxel's resolution: the variance `σh²` of
//! the micro-heights, the slope variance `σn²`, and per attribute channel the mean `ā` and
//! the correlation `a_s` with height (`a(h) = ā + a_s s(h)`, H5bis) — the inputs of eq. 17
//! (`smith-micro`) and of the §5.4 masks (`abuffer-mask`).
//!
//! ```
//! use glam::Vec3;
//! use svo_brick::{BrickSize, BrickTree, BuildOptions, Domain, PackedTree, SdfSurface, VoxelLayout};
//!
//! // A sphere of radius 0.6, red below and yellow above.
//! let sphere = SdfSurface::new(
//!     |p: Vec3| p.length() - 0.6,
//!     |p: Vec3| [1.0, 0.5 + 0.5 * p.z / 0.6, 0.0],
//!     1e-4,
//! )
//! .unwrap();
//! let options = BuildOptions { brick_size: BrickSize::Four, levels: 3, ..BuildOptions::default() };
//! let tree = BrickTree::build(&sphere, Domain { origin: Vec3::splat(-1.0), size: 2.0 }, options).unwrap();
//! assert_eq!(tree.resolution(), 16); // 4 · 2² voxels across at the finest level
//!
//! let packed = PackedTree::new(&tree, VoxelLayout::Compact16); // 16 bytes per voxel
//! let on_surface = packed.sample(Vec3::new(0.0, 0.0, 0.6), 0.0).unwrap();
//! assert!(on_surface.distance.abs() < 0.01);
//! assert!(on_surface.normal.z > 0.99);
//! // A coarser level of detail, between levels 1 and 2: the curvature became roughness.
//! let coarse = packed.sample(Vec3::new(0.0, 0.0, 0.6), 1.5).unwrap();
//! assert!(coarse.distance_variance > 0.0);
//! assert!(packed.sample(Vec3::splat(3.0), 0.0).is_none()); // outside the domain
//! ```
//!
//! # What is where
//!
//! - The descriptor: [`Voxel`]. Sources: [`SurfaceSource`] (a signed distance, its
//!   gradient, attributes and surface samples), [`SdfSurface`] from closures.
//! - The octree: [`BrickTree::build`] places bricks of `n³` cells (n = 4, 8, 16; `(n + 1)³`
//!   voxels at the corners, faces shared) where the surface is within reach, box-filters `h̄` and `n̄` bottom-up and
//!   measures the statistics of each coarse voxel from the surface samples in its
//!   footprint ([`surface_statistics`]; [`HeightVariance::DistanceVolume`] is the literal
//!   "variance of the distance" as a negative control); voxels without samples are dilated
//!   from the nearest that have them.
//! - The GPU forms: [`VoxelLayout::Paper20`] (the paper's precision, 20 bytes) and
//!   [`VoxelLayout::Compact16`] (16 bytes), each with a documented and tested round-trip
//!   bound; [`PackedTree`] holds the node and brick pools, split over up to four bindings
//!   sized from the adapter's limit ([`PackedTree::with_binding_limit`]).
//! - Sampling: [`PackedTree::sample`] (quadrilinear), [`PackedTree::sample_nearest`] (the
//!   nearest voxel, the blocky baseline of Fig. 10a), [`PackedTree::sample_moment_corrected`]
//!   (variances that include the corners' disagreement; CPU), each the same bits as the WGSL
//!   twin where the twin has it.
//! - [`moment_correction_error`]: what interpolated variances miss, measured.
//!
//! # Using the WGSL twin
//!
//! With the `wgsl` feature, [`WGSL`] declares the generated [`OctreeNode`] and
//! [`OctreeUniforms`] and the sampler (`svo_sample_raw`, `svo_sample_nearest_raw`,
//! `svo_finish`, and what they are made of), each function named after the Rust it mirrors
//! and proven bit-identical to it (`tests/svo_brick_gpu.rs`). The node pool is bound at
//! group 0 binding 3 and the brick pool at bindings 4–7:
//!
//! ```
//! # #[cfg(feature = "wgsl")] {
//! let mut source = String::new();
//! svo_brick::WGSL.write_source(&mut source).unwrap(); // no dependencies to compose first
//! source.push_str(
//!     "@group(0) @binding(0) var<uniform> tree: OctreeUniforms;
//!      fn distance_at(p: vec3<f32>, lod: f32) -> f32 {
//!          let s = svo_sample_raw(tree, p, lod);
//!          return select(1e30, svo_finish(tree, s.voxel).distance, s.inside);
//!      }",
//! );
//! # let module = naga::front::wgsl::parse_str(&source).unwrap_or_else(|e| panic!("{}", e.emit_to_string(&source)));
//! # naga::valid::Validator::new(naga::valid::ValidationFlags::all(), Default::default()).validate(&module).unwrap();
//! assert!(source.contains("fn svo_sample_raw"));
//! # }
//! ```
//!
//! Upload `bytemuck::bytes_of(&packed.uniforms())`, `packed.nodes()` and the four slices of
//! `packed.brick_bindings()`. Or register `WGSL.naga_oil_source` with a `naga_oil` composer
//! under the name `svo_brick`.
//!
//! # Features
//!
//! - `std` (default): enables `std` in the dependencies. The crate is `#![no_std]`; the
//!   octree uses `alloc`. `cargo check -p svo-brick --no-default-features` builds it
//!   without `std`.
//! - `wgsl`: [`WGSL`], the WGSL twin (its sources are embedded; no extra dependency).
#![no_std]

extern crate alloc;
#[cfg(feature = "std")]
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
pub use octree::{BrickSize, BrickTree, BuildError, BuildOptions, Domain, EMPTY_DISTANCE, MAX_LEVELS, OctreeNode};
pub use prefilter::{HeightVariance, SurfaceStatistics, surface_statistics};
pub use sample::{
    EmptyRegion, FRACTION_STEPS, MAX_BRICK_BINDINGS, OctreeUniforms, PackedTree, PoolError, RawSample, SPLIT_MASK,
    lerp, lerp_raw,
};
pub use surface::{Cell, PROJECTION_STEPS, SdfSurface, SurfaceError, SurfaceSample, SurfaceSource, thin_shell_samples};
#[cfg(feature = "wgsl")]
pub use wgsl::WGSL;
