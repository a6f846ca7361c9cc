//! Grains as input for dense stackings, after Michel & Boubekeur, *Real Time Multiscale
//! Rendering of Dense Dynamic Stackings* (CGF 2020): triangle meshes from OBJ files or
//! made in code, with the centre, inner radius `r` and outer radius `R` of the paper's
//! quasi-spherical hypothesis (§1: the surface lies between two spheres of radii `r` and
//! `R` about the grain's centre; §8 culls with the inner sphere, §10 names a threaded nut
//! as the shape that breaks the hypothesis).
//!
//! ```
//! use grain_mesh::{CentreKind, CoffeeBean, HexNut};
//!
//! let bean = CoffeeBean::default().mesh().unwrap();
//! let bounds = bean.bounds();
//! assert_eq!(bounds.centre_kind, CentreKind::VolumeCentroid);
//! assert!(bounds.inner_radius <= bounds.outer_radius);
//! assert!(bounds.centre_inside_solid());
//!
//! // The nut's centre is in its hole: r is the hole's radius, but no material fills the
//! // inner sphere, so it cannot occlude anything.
//! let nut = HexNut::default().mesh().unwrap();
//! assert!(!nut.bounds().centre_inside_solid());
//! assert_eq!(nut.bounds().occluder_radius(), 0.0);
//! ```
//!
//! # Modules
//!
//! - [`mesh`]: [`GrainMesh`], a validated mesh with unit per-vertex normals (from the file
//!   or area-weighted) and optional per-vertex [`VertexMaterial`] (albedo, roughness).
//! - [`obj`]: loading OBJ files with `tobj`, and a minimal OBJ writer.
//! - [`procedural`]: [`Ball`], [`CoffeeBean`], [`SandGrain`] (seeded rock) and [`HexNut`].
//! - [`bounds`]: the centre (volume centroid of closed meshes, surface centroid otherwise),
//!   `r`, `R`, `r/R`, and whether the inner ball is solid.
//! - [`error`]: [`MeshError`], why a mesh could not be made.
//! - [`material`]: [`VertexMaterial`], the per-vertex material of procedural grains.
//! - [`topology`]: closedness and orientation of the triangles, by welded position.
//!
//! Bad input — an unreadable file, no triangles, a NaN vertex, a mesh with `r = R = 0` —
//! is an error naming the file and the problem, never a panic.

pub mod bounds;
pub mod error;
pub mod material;
pub mod mesh;
pub mod obj;
pub mod procedural;
pub mod topology;

pub use bounds::{CentreKind, GrainBounds};
pub use error::MeshError;
pub use material::VertexMaterial;
pub use mesh::{GrainMesh, area_weighted_normals};
pub use obj::{ObjError, ObjProblem, load_obj, parse_obj, write_obj, write_obj_to};
pub use procedural::{Ball, CoffeeBean, HexNut, SandGrain};
pub use topology::EdgeReport;
