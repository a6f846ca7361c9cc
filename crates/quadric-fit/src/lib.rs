//! Quadric surfaces for directional distance maps, after Mehra & Kumar, *Accurate and
//! Efficient Rendering of Detail using Directional Distance Maps* (eq. 1–2, §3.1,
//! Algorithm 3.2, Appendix B).
//!
//! Inside a voxel that the mesostructure crosses, the surface is stored as a quadric
//! `Ax² + By² + Cz² + Dxy + Eyz + Fzx + Gx + Hy + Iz + J = 0` (eq. 1), either fitted to
//! surface samples by least squares (eq. 2) or built exactly from a triangle or bilinear
//! patch through the voxel's edge points (Appendix B). The tracer intersects rays with it
//! analytically (Algorithm 3.2).
//!
//! ```
//! use glam::{DVec3, Vec3};
//! use quadric_fit::{GpuQuadric, bilinear_quadric, first_hit};
//!
//! // A twisted quad across the unit voxel.
//! let quadric = bilinear_quadric(
//!     DVec3::new(0.0, 0.0, 0.2),
//!     DVec3::new(1.0, 0.0, 0.6),
//!     DVec3::new(1.0, 1.0, 0.3),
//!     DVec3::new(0.0, 1.0, 0.7),
//! )
//! .unwrap();
//! let gpu = GpuQuadric::from_quadric(&quadric);
//! let t = first_hit(&gpu, Vec3::new(0.5, 0.5, 1.0), Vec3::NEG_Z, 0.0, 1.0).unwrap();
//! // The patch's centre is at z = (0.2 + 0.6 + 0.3 + 0.7) / 4 = 0.45.
//! assert!((t - 0.55).abs() < 1e-5);
//! ```
//!
//! # Modules
//!
//! - [`quadric`]: the quadric of eq. 1 in double precision: value, gradient, frames.
//! - [`fit`]: least-squares fit (eq. 2) in a normalized frame, with a plane fallback;
//!   [`FitError`] says why points determine no surface.
//! - [`patch`]: triangle and bilinear patches as quadrics (Appendix B).
//! - [`intersect`]: single-precision ray intersection and normal, the WGSL twin's reference.
//! - [`eigen`]: symmetric eigen-decomposition (Jacobi) without `std`.
//! - [`gpu_quadric`]: the single-precision GPU layout of a quadric.
//! - [`surface`]: the per-voxel C⁰ construction of §3.1 (steps a–c): edge hits, averaged
//!   representative points, face-ordered polygons and their triangle/bilinear patches.
//! - [`watertight`]: the same polygons and patches from corner signs, edge points and face
//!   decisions taken once for the grid, so that neighbours never disagree (beyond the paper).
//! - [`feature`]: the feature vertex of a crease or corner voxel (dual contouring's QEF),
//!   around which [`watertight`]'s polygon is fanned where it cuts a sharp edge off.
//!
//! # Using the WGSL twin
//!
//! With the `wgsl` feature, [`WGSL`] is the crate's WGSL twin: the generated
//! [`GpuQuadric`] and `quadric_value`, `quadric_gradient`, `quadric_normal` and
//! `quadric_first_hit(q, origin, direction, t_min, t_max) -> vec2(t, hit)` (Algorithm 3.2),
//! the twins of [`intersect`]'s functions. Upload quadrics as
//! `bytemuck::cast_slice(&[GpuQuadric::from_quadric(&q)])` and paste the twin before your
//! WGSL:
//!
//! ```
//! # #[cfg(feature = "wgsl")] {
//! let mut source = String::new();
//! quadric_fit::WGSL.write_source(&mut source).unwrap(); // no dependencies to compose first
//! source.push_str(
//!     "@group(0) @binding(0) var<storage, read> quadrics: array<GpuQuadric>;
//!      @group(0) @binding(1) var<storage, read_write> depth: array<f32>;
//!      @compute @workgroup_size(64)
//!      fn main(@builtin(global_invocation_id) id: vec3<u32>) {
//!          // Straight down through the voxel's centre, from its top face.
//!          let hit = quadric_first_hit(quadrics[id.x], vec3<f32>(0.5, 0.5, 1.0), vec3<f32>(0.0, 0.0, -1.0), 0.0, 1.0);
//!          depth[id.x] = select(-1.0, hit.x, hit.y > 0.5);
//!      }",
//! );
//! # let module = naga::front::wgsl::parse_str(&source).unwrap_or_else(|e| panic!("{}", e.emit_to_string(&source)));
//! # naga::valid::Validator::new(naga::valid::ValidationFlags::all(), Default::default()).validate(&module).unwrap();
//! assert!(source.contains("fn quadric_first_hit"));
//! # }
//! ```
//!
//! Or register `WGSL.naga_oil_source` with a `naga_oil` composer under the name
//! `quadric_fit` and `#import quadric_fit::{quadric_first_hit, GpuQuadric}`.
//!
//! # Features
//!
//! - `std` (default): enables `std` in the dependencies. The crate is `#![no_std]`; only
//!   [`surface`] and [`watertight`] allocate (through `alloc`); `cargo check -p quadric-fit --no-default-features` builds it.
//! - `wgsl`: [`WGSL`], the WGSL twin (its sources are embedded; no extra dependency).
#![no_std]

extern crate alloc;

pub mod eigen;
pub mod feature;
pub mod fit;
pub mod gpu_quadric;
pub mod intersect;
pub mod patch;
pub mod quadric;
pub mod surface;
pub mod watertight;
#[cfg(feature = "wgsl")]
mod wgsl;

pub use feature::{FeatureVertex, TangentPlane, feature_vertex};
pub use fit::{FitError, FitKind, QuadricFit, fit_plane, fit_quadric};
pub use gpu_quadric::GpuQuadric;
pub use intersect::{first_hit, normal};
pub use patch::{bilinear_quadric, triangle_quadric};
pub use quadric::{Quadric, QuadricError};
pub use surface::{C0Surface, build_surface};
pub use watertight::{SignedGrid, build_watertight};
#[cfg(feature = "wgsl")]
pub use wgsl::WGSL;
