//! The directional distance map tracer of Mehra & Kumar, *Accurate and Efficient
//! Rendering of Detail using Directional Distance Maps* (§3.2, Algorithms 3.1–3.3), its
//! baselines, and the exact ground truth it is measured against. The CPU reference of the
//! WGSL compute tracer `wgsl/ddm_tracer.wgsl`.
//!
//! ```
//! use ddm_compress::{DirectionCones, DistanceMapSettings, MapKind, compute_distance_maps};
//! use ddm_tracer::{Method, PatchSettings, Stepping, TraceSettings, VoxelPatches, trace};
//! use glam::{UVec3, Vec3};
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let dims = UVec3::new(8, 8, 4);
//! let floor = mesostructure::plane(dims, 1.25);
//! let settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: true };
//! let kind = MapKind::Directional(DirectionCones::downward(4, 1)?);
//! let maps = compute_distance_maps(dims, &floor, kind, settings)?;
//! let patches = VoxelPatches::build(dims, &floor, &maps.surface, PatchSettings::default())?;
//! let settings = TraceSettings { method: Method::Quadric, max_steps: 64, stepping: Stepping::Distance };
//! let out = trace(&maps, Some(&patches), Vec3::new(2.5, 3.5, 6.0), Vec3::new(0.3, 0.1, -1.0), settings);
//! assert!((out.hit.unwrap().point.z - 1.25).abs() < 1e-5);
//! # Ok(())
//! # }
//! ```
//!
//! # Modules
//!
//! - [`voxel`]: ray–voxel geometry (slab entry, voxel and cell entry and exit).
//! - [`maps`]: raw or compressed maps behind one trait, and the ray's cone.
//! - [`patch`]: one voxel patch (a quadric clipped to a polygon) and a ray's hit with a
//!   voxel's patches (Algorithm 3.2).
//! - [`patches`]: the per-voxel C⁰ quadric patches (§3.1) in tracer form.
//! - [`exact_patches`]: exact triangle patches and the per-voxel choice between a fitted
//!   quadric and them under an error budget (beyond the paper).
//! - [`trace`](mod@trace): Algorithm 3.1–3.3 and plain sphere tracing, with the paper's stepping,
//!   or (beyond the paper) block cells on compressed maps or voxel-exit stepping.
//! - [`relief`]: the relief mapping baseline on height fields.
//! - [`ground_truth`]: exact ray–triangle intersection of the periodic mesh (BVH).
//! - [`gpu_scene`]: the scene packed into the buffers of the WGSL twin.
//! - [`tangent_space`]: the per-pixel ray of a mesostructure mapped on a base mesh.
//!
//! # Features
//!
//! - `std` (default): enables `std` in the dependencies. The crate is `#![no_std]` with
//!   `alloc`; `cargo check -p ddm-tracer --no-default-features` builds it.
#![no_std]

extern crate alloc;

pub mod exact_patches;
pub mod gpu_scene;
pub mod ground_truth;
pub mod maps;
pub mod patch;
pub mod patches;
pub mod relief;
pub mod tangent_space;
pub mod trace;
pub mod voxel;
#[cfg(feature = "wgsl")]
mod wgsl;

pub use gpu_scene::{GpuScene, GpuSceneError, TraceConeMap, TraceResult, TraceUniforms};
pub use ground_truth::{MeshHit, MeshRaycaster};
pub use maps::{CompressMapsError, CompressedMaps, ConeDistances, ConeSelector, DistanceSource, RawConeMap};
pub use patch::TracePatch;
pub use patches::{MAX_PATCH_VOXELS, PatchError, PatchSettings, PatchSurface, VoxelPatches};
pub use relief::{HeightMap, HeightMapError, relief_trace};
pub use trace::{Method, Stepping, TraceHit, TraceOutcome, TraceSettings, trace};
#[cfg(feature = "wgsl")]
pub use wgsl::WGSL;
