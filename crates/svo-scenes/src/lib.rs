//! Surfaces to build pre-filtered voxel octrees from (Heitz & Neyret, *Representing
//! Appearance and Pre-filtering Subpixel Data in Sparse Voxel Octrees*, HPG 2012), with no
//! downloads: each implements [`svo_brick::SurfaceSource`] — a 1-Lipschitz signed distance
//! (negative inside), its gradient, an RGB attribute in `[0, 1]`, and surface samples.
//!
//! ```
//! use glam::Vec3;
//! use svo_brick::{Cell, SurfaceSource};
//! use svo_scenes::{Attribute, Displaced, Fbm, HeightColours, Sphere, Torus};
//!
//! // Exact distances and gradients.
//! let torus = Torus::new(Vec3::ZERO, 2.0, 0.5, Attribute::constant([0.9, 0.6, 0.2])?)?;
//! assert!((torus.distance(Vec3::new(3.0, 0.0, 0.0)) - 0.5).abs() < 1e-6);
//! assert!(torus.gradient(Vec3::new(0.0, 3.0, 0.0)).abs_diff_eq(Vec3::Y, 1e-6));
//!
//! // Fig. 11's sphere: displaced along its normal by 3D fBm, deep = red, high = yellow.
//! let sphere = Sphere::new(Vec3::ZERO, 1.0, Attribute::grey())?;
//! let fbm = Fbm::new(7, 5, 0.5, 0.04, 0.4)?;
//! let displaced = Displaced::new(sphere, fbm, HeightColours::default())?;
//! let x = Vec3::X * (1.0 + fbm.value(Vec3::X)); // a point of the displaced surface
//! assert!(displaced.distance(x).abs() < 1e-6);
//! assert!(displaced.distance(Vec3::ZERO) < 0.0);
//!
//! // Samples of the surface in a cell, for the coarse levels' statistics.
//! let mut samples = Vec::new();
//! let cell = Cell { min: Vec3::new(0.5, -0.25, -0.25), max: Vec3::new(1.5, 0.25, 0.25) };
//! displaced.surface_samples(cell, 0.02, &mut samples);
//! assert!(!samples.is_empty());
//! # Ok::<(), svo_scenes::SceneError>(())
//! ```
//!
//! # Sources
//!
//! - [`Sphere`], [`Torus`] (axis z), [`AxisBox`]: exact analytic signed distances and
//!   gradients; [`Plate`], a thin slab, infinite or a disk with sharp rims (H7's thin
//!   parts); [`Plane`], a half-space.
//! - [`Displaced`]: a [`Sphere`] or [`Plane`] displaced along its normal by [`Fbm`] (3D
//!   value noise implemented here, seeded, with an exact derivative and a proven gradient
//!   bound), coloured by [`HeightColours`]; the distance is divided by a proven Lipschitz
//!   bound, derived in [`Displaced`]'s documentation.
//! - [`HeightMapSurface`]: a periodic height grid (or a grayscale PNG), piecewise linear,
//!   with exact samples at its vertices.
//! - [`MeshSurface`]: a closed OBJ or [`grain_mesh::GrainMesh`], signed by angle-weighted
//!   pseudo-normals, with a BVH and stratified triangle samples.
//!
//! Analytic sources keep the trait's default thin-shell
//! [`surface_samples`](svo_brick::SurfaceSource::surface_samples) (exact distances, so
//! unbiased); displaced surfaces weight it by `|∇d|` (their distance is a bound, see
//! [`Displaced`]); height maps and meshes override it with exact samples.
//!
//! Attributes are an [`Attribute`]: a constant colour, or a closure (of the position, or
//! of the height for height maps). Bad input is an error ([`SceneError`]) naming the
//! parameter, the file or the mesh, never a panic.

mod analytic;
mod attribute;
mod bvh;
mod displaced;
mod error;
mod heightmap;
mod mesh;
mod noise;
mod plate;
#[cfg(test)]
mod testing;

pub use analytic::{AxisBox, Sphere, Torus};
pub use attribute::Attribute;
pub use displaced::{Displaced, DisplacementBase, HeightColours};
pub use error::SceneError;
pub use heightmap::HeightMapSurface;
pub use mesh::{MAX_TRIANGLE_SUBDIVISION, MeshSurface};
pub use noise::{Fbm, MAX_OCTAVES, NOISE_GRADIENT_BOUND};
pub use plate::{Plane, Plate};
