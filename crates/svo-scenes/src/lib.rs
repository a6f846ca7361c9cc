//! Surfaces to build pre-filtered voxel octrees from (Heitz & Neyret, *Representing
//! Appearance and Pre-filtering Subpixel Data in Sparse Voxel Octrees*, HPG 2012), with no
//! downloads: each implements [`svo_brick::SurfaceSource`] — a 1-Lipschitz signed distance
//! (negative inside), its gradient, an RGB attribute in `[0, 1]`, and surface samples.
//!
//! ```
//! use glam::Vec3;
//! use svo_brick::SurfaceSource;
//! use svo_scenes::{Attribute, Torus};
//!
//! // Exact distances and gradients.
//! let torus = Torus::new(Vec3::ZERO, 2.0, 0.5, Attribute::constant([0.9, 0.6, 0.2])?)?;
//! assert!((torus.distance(Vec3::new(3.0, 0.0, 0.0)) - 0.5).abs() < 1e-6);
//! assert!(torus.gradient(Vec3::new(0.0, 3.0, 0.0)).abs_diff_eq(Vec3::Y, 1e-6));
//! # Ok::<(), svo_scenes::SceneError>(())
//! ```

mod analytic;
mod attribute;
mod displaced;
mod error;
mod heightmap;
mod noise;
mod plate;
mod shell;
#[cfg(test)]
mod testing;

pub use analytic::{AxisBox, Sphere, Torus};
pub use attribute::Attribute;
pub use displaced::{Displaced, DisplacementBase, HeightColours};
pub use error::SceneError;
pub use heightmap::HeightMapSurface;
pub use noise::{Fbm, MAX_OCTAVES, NOISE_GRADIENT_BOUND};
pub use plate::{Plane, Plate};
