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
//! # Using the WGSL twin
//!
//! With the `wgsl` feature, [`WGSL`] is the crate's WGSL twin: the generated declarations
//! ([`ViewSample`], [`ImpostorSamplingUniforms`], [`ImpostorSample`], the limits and bit
//! masks) and the functions, each named after the Rust function it mirrors
//! (`octahedral_view_sample` is [`OctahedralViews::sample`], `impostor_sample` is
//! [`sample_impostor`], …) and computing the same bits. Paste it before your own WGSL:
//!
//! ```
//! # #[cfg(feature = "wgsl")] {
//! let mut source = String::new();
//! octahedral_map::WGSL.write_source(&mut source).unwrap(); // no dependencies to compose first
//! source.push_str(
//!     "@group(0) @binding(0) var<storage, read> directions: array<vec4<f32>>;
//!      @group(0) @binding(1) var<storage, read_write> samples: array<ViewSample>;
//!      @compute @workgroup_size(64)
//!      fn main(@builtin(global_invocation_id) id: vec3<u32>) {
//!          samples[id.x] = octahedral_view_sample(directions[id.x].xyz, 8u);
//!      }",
//! );
//! # let module = naga::front::wgsl::parse_str(&source).unwrap_or_else(|e| panic!("{}", e.emit_to_string(&source)));
//! # naga::valid::Validator::new(naga::valid::ValidationFlags::all(), Default::default()).validate(&module).unwrap();
//! // `source` is one WGSL module, ready for `wgpu::Device::create_shader_module`.
//! assert!(source.contains("fn octahedral_view_sample(direction: vec3<f32>, subdivisions: u32) -> ViewSample"));
//! # }
//! ```
//!
//! Or register `WGSL.naga_oil_source` with a `naga_oil` composer (as Bevy does) under the
//! name `octahedral_map` and write `#import octahedral_map::{octahedral_view_sample,
//! ViewSample}` in your shader. The workspace's `examples/foreign-renderer` builds a wgpu
//! compute pipeline from it and checks the GPU against the Rust bit for bit.
//!
//! # Features
//!
//! - `std` (default): enables `std` in the dependencies. The crate is `#![no_std]` and
//!   needs no allocator; `cargo check -p octahedral-map --no-default-features` builds it
//!   without `std`.
//! - `wgsl`: [`WGSL`], the WGSL twin (its sources are embedded; no extra dependency).
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
