//! View directions on a subdivided octahedron, after Michel & Boubekeur, *Real Time
//! Multiscale Rendering of Dense Dynamic Stackings* (CGF 2020), §4.2 and Listing 1.
//!
//! An impostor stores `N = 2n²` precomputed orthographic views of a grain. The view
//! directions are the points of an `n × n` grid laid over each hemisphere of the L1 unit
//! sphere (the octahedron `|x| + |y| + |z| = 1`), so that finding the four views nearest to
//! any direction, and their bilinear weights, costs a handful of arithmetic operations.
//!
//! ```
//! use glam::Vec3;
//! use octahedral_map::OctahedralViews;
//!
//! let views = OctahedralViews::new(8).unwrap(); // the paper's n = 8: 128 views
//! assert_eq!(views.view_count(), 128);
//!
//! let sample = views.sample(Vec3::new(0.3, -0.2, 0.9));
//! let weights = sample.weights();
//! assert!((weights.iter().sum::<f32>() - 1.0).abs() < 1e-6);
//! for index in sample.indices.to_array() {
//!     let direction = views.view_direction(index).unwrap();
//!     assert!((direction.length() - 1.0).abs() < 1e-6);
//! }
//!
//! // Eq. 4: a view rendered at p = 128 texels is valid within ±0.45°.
//! let half_angle = octahedral_map::validity_half_angle(128).unwrap();
//! assert!((half_angle.to_degrees() - 0.4476).abs() < 1e-3);
//! ```
//!
//! # Modules
//!
//! - [`direction`]: the canonical form of an arbitrary input vector (zero, NaN, ∞,
//!   subnormal and huge inputs all get a defined result).
//! - [`views`]: the view layout: index ↔ direction, and the four nearest views of a
//!   direction with their weights (Listing 1).
//! - [`validity`]: the validity half-angle of a view (eq. 4) and the smallest `n` whose
//!   neighbour spacing fits it (§6, Fig. 6).
//! - [`view_frame`]: the orthographic camera of each view and the mapping between
//!   points of a grain and texels (the conventions the baker and samplers share).
//! - [`compact`]: a layout storing each distinct view once (no duplicated equator).
//! - [`sampling`]: planar, spherical and mixed sampling of a quasi-spherical impostor
//!   (§5): the four views, their weights and the texture coordinates to read in each.
//!
//! # Features
//!
//! - `std` (default): enables `std` in the dependencies. The crate is `#![no_std]` and
//!   needs no allocator; `cargo check -p octahedral-map --no-default-features` builds it
//!   without `std`.
#![no_std]

pub mod compact;
pub mod direction;
pub mod sampling;
pub mod validity;
pub mod view_frame;
pub mod views;
#[cfg(feature = "wgsl")]
mod wgsl;

pub use compact::CompactViews;
pub use direction::{FALLBACK_DIRECTION, canonical_direction};
pub use sampling::{
    GrainRay, ImpostorSample, ImpostorSampler, ImpostorSamplingUniforms, SamplingMode, ViewLayout, ViewSelection,
    sample_impostor,
};
pub use validity::{max_neighbour_angle, min_subdivisions_for_texels, validity_half_angle};
pub use view_frame::ViewFrame;
pub use views::{MAX_SUBDIVISIONS, OctahedralViews, ViewSample};
#[cfg(feature = "wgsl")]
pub use wgsl::WGSL;
