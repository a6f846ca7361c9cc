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
//! # Using the WGSL twin
//!
//! With the `wgsl` feature, [`WGSL`] is the crate's WGSL twin: the generated
//! [`MaskTableUniforms`] and constants, and the table lookup (`abuffer_cell_index`,
//! `abuffer_mask_word_offset`), the mask operations (`abuffer_mask_union`, `_difference`,
//! `_intersection`, `_popcount`, `_coverage`) and the half-plane of a cone element
//! (`abuffer_half_plane`), each named after the Rust function it mirrors. A mask is a
//! `vec4<u32>` whatever `N`; the table is the flat `u32` buffer of [`MaskTable::words`],
//! described to the shader by [`MaskTable::uniforms`]:
//!
//! ```
//! # #[cfg(feature = "wgsl")] {
//! use abuffer_mask::MaskTable;
//!
//! let table = MaskTable::<4>::paper().unwrap();
//! let words: &[u32] = table.words(); // upload as a storage buffer
//! let uniforms = table.uniforms(); // upload as a uniform buffer (a `bytemuck::Pod` struct)
//! assert_eq!(words.len(), 256 * 256 * 4);
//! assert_eq!(uniforms.sample_count, 128);
//!
//! let mut source = String::new();
//! abuffer_mask::WGSL.write_source(&mut source).unwrap(); // no dependencies to compose first
//! source.push_str(
//!     "@group(0) @binding(0) var<uniform> table: MaskTableUniforms;
//!      @group(0) @binding(1) var<storage, read> masks: array<u32>;
//!      fn coverage_of(theta: f32, v: f32) -> f32 {
//!          let first = abuffer_mask_word_offset(abuffer_cell_index(theta, v, table), table);
//!          var mask = vec4<u32>(0u);
//!          for (var w = 0u; w < table.words_per_mask; w++) { mask[w] = masks[first + w]; }
//!          return abuffer_mask_coverage(mask, table);
//!      }",
//! );
//! # let module = naga::front::wgsl::parse_str(&source).unwrap_or_else(|e| panic!("{}", e.emit_to_string(&source)));
//! # naga::valid::Validator::new(naga::valid::ValidationFlags::all(), Default::default()).validate(&module).unwrap();
//! assert!(source.contains("fn abuffer_cell_index"));
//! # }
//! ```
//!
//! Or register `WGSL.naga_oil_source` with a `naga_oil` composer under the name
//! `abuffer_mask` and `#import abuffer_mask::{...}` what your shader uses.
//!
//! # Features
//!
//! - `std` (default): enables `std` in the dependencies. The crate is `#![no_std]`; the mask
//!   table uses `alloc`. `cargo check -p abuffer-mask --no-default-features` builds it
//!   without `std`.
//! - `wgsl`: [`WGSL`], the WGSL twin (its sources are embedded; no extra dependency).
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
