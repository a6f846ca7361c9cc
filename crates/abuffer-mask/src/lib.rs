//! Sub-pixel coverage masks for cone tracing, after Heitz & Neyret, *Representing
//! Appearance and Pre-filtering Subpixel Data in Sparse Voxel Octrees* (HPG 2012), §5.3
//! (Algorithm 1), §5.4 and Fig. 4.
//!
//! Each cone element occludes a half-plane of the pixel footprint, given by an angle `θ`
//! and an offset `v` computed from the voxel's distance `h̄` and normal `n̄` (§5.4). A
//! precomputed table maps `(θ, v)` to a mask of `N` Poisson-disk samples; masks of the
//! successive elements along the cone combine by union and difference, so occlusions that
//! are correlated along the ray (silhouettes) are counted once, where α-blending
//! saturates (Fig. 4).
//!
//! ```
//! use abuffer_mask::{ConeAccumulator, HalfPlane, MaskTable, alpha_blended_opacity};
//! use glam::Vec3;
//!
//! let table = MaskTable::<4>::paper().unwrap(); // N = 128 samples, 256 × 256 cells
//! // A plane through the cone axis, normal along x: it covers the half ω_x ≤ 0.
//! let plane = HalfPlane::from_cone_element(0.0, Vec3::new(1.0, 0.0, 0.0), 1.0, 0.5);
//! let mask = table.lookup(plane.theta, plane.v);
//! assert!((mask.coverage() - 0.5).abs() <= 0.04);
//!
//! // Two fragments covering the same half (Fig. 4): masks give one half, α-blending 0.75.
//! let mut cone = ConeAccumulator::new();
//! cone.add(mask, 1.0);
//! cone.add(mask, 1.0);
//! assert_eq!(cone.opacity(), mask.coverage());
//! assert_eq!(alpha_blended_opacity([0.5, 0.5]), 0.75);
//! ```
//!
//! # Modules
//!
//! - [`samples`]: the deterministic Poisson-disk sample positions (`N ≤ 128`).
//! - [`mask`]: masks `[u32; N/32]`, union / difference / intersection / popcount /
//!   coverage, and Algorithm 1's accumulation ([`ConeAccumulator`]).
//! - [`half_plane`]: `(θ, v)` from `h̄, n̄, r_d, l_d` (§5.4, re-derived; the `n_x = n_y = 0`
//!   case defined), and the exact covered area.
//! - [`table`]: the `(θ, v)` mask table, its GPU layout and its bit-exact lookup.
//! - [`accuracy`]: coverage error of a table against the exact area.
//!
//! # Features
//!
//! - `std` (default): enables `std` in the dependencies. The crate is `#![no_std]`; the mask
//!   table uses `alloc`. `cargo check -p abuffer-mask --no-default-features` builds it
//!   without `std`.
#![no_std]

extern crate alloc;

pub mod accuracy;
pub mod half_plane;
pub mod mask;
pub mod samples;
pub mod table;
#[cfg(feature = "wgsl")]
mod wgsl;

pub use accuracy::{CoverageErrorStats, coverage_error};
pub use half_plane::{HalfPlane, V_SATURATION, exact_coverage};
pub use mask::{ConeAccumulator, Mask, Mask32, Mask64, Mask128, alpha_blended_opacity};
pub use samples::{MAX_SAMPLES, SamplePattern};
pub use table::{DEFAULT_TABLE_SIZE, MaskTable, MaskTableUniforms, TableLayout};
#[cfg(feature = "wgsl")]
pub use wgsl::WGSL;
