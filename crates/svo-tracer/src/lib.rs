//! Cone tracing of pre-filtered sparse voxel octrees after Heitz & Neyret, *Representing
//! Appearance and Pre-filtering Subpixel Data in Sparse Voxel Octrees* (HPG 2012), §4,
//! §5.3–5.5 and Algorithm 1: the CPU reference and its WGSL twin.
//!
//! Each pixel is one cone (§4.1, widened by a thin lens for depth of field). The cone is cut
//! into cone elements whose footprint the octree's quadrilinear sample `(h̄, n̄)` covers as a
//! half-plane; its A-buffer mask (`abuffer-mask`) is combined with the masks of the elements
//! in front, so that occlusion correlated along the cone — a silhouette — is counted once
//! where α-blending saturates (Fig. 4); each element's radiance is eq. 13 with the visible
//! attribute of eq. 17 (`smith-micro`). Shadow cones give the light's visibility, and empty
//! space is skipped without changing a bit of the image.
//!
//! ```
//! use abuffer_mask::MaskTable;
//! use glam::Vec3;
//! use svo_brick::{BrickSize, BrickTree, BuildOptions, Domain, PackedTree, SdfSurface, VoxelLayout};
//! use svo_tracer::{Camera, Model, TraceSettings, trace_cone};
//!
//! let sphere = SdfSurface::new(|p: Vec3| p.length() - 0.5, |_| [0.8, 0.6, 0.2], 1e-4).unwrap();
//! let options = BuildOptions { brick_size: BrickSize::Four, levels: 3, ..BuildOptions::default() };
//! let tree = BrickTree::build(&sphere, Domain { origin: Vec3::splat(-1.0), size: 2.0 }, options).unwrap();
//! let packed = PackedTree::new(&tree, VoxelLayout::Compact16);
//! let table = MaskTable::<4>::paper().unwrap(); // 128 samples per mask
//!
//! let camera = Camera::look_at(Vec3::new(0.0, 0.0, -3.0), Vec3::ZERO, Vec3::Y, 0.6, 16, 16).unwrap();
//! let settings = TraceSettings::default(); // the paper's model, no shadows
//! let centre = trace_cone(&packed, &table, &camera.pixel_cone(8, 8), &settings);
//! assert_eq!(centre.coverage, 1.0); // the sphere covers the middle pixel
//! let corner = trace_cone(&packed, &table, &camera.pixel_cone(0, 0), &settings);
//! assert_eq!(corner.coverage, 0.0);
//! let blended = TraceSettings { model: Model::AlphaBlend, ..settings };
//! assert!(trace_cone(&packed, &table, &camera.pixel_cone(8, 8), &blended).coverage > 0.99);
//! ```
//!
//! # What is where
//!
//! - [`Camera`], [`Lens`], [`Cone`]: pixel cones, their width `w(z) = z s + A |z − f| / f`,
//!   and the π turn of the footprint past the focal plane (the paper is silent; see
//!   [`Cone::crossed`]).
//! - [`trace_cone`]: Algorithm 1 and its baselines as modes of the same loop ([`Model`]:
//!   masks, α-blending of eq. 12, the nearest voxel with 0/1 occupancy, separate
//!   filtering), shadow cones ([`light_visibility`]) and the empty-space skip.
//! - [`element_radiance`]: `L_d` (eq. 13 with eq. 17, plus a Lambert term), whose mean
//!   cosine is [`expected_clamped_cosine`] over the voxel's lobe of micro-normals.
//! - [`GpuCamera`], [`GpuTraceSettings`]: the GPU forms.
//!
//! # Using the WGSL twin
//!
//! With the `wgsl` feature, [`WGSL`] composes after `svo_brick`, `abuffer_mask` and
//! `smith_micro` (`WGSL.write_source` writes them first) and provides `svo_pixel_cone` and
//! `svo_trace_cone`, each function named after the Rust it mirrors; `tests/svo_tracer_gpu.rs`
//! compares whole cones with this crate. Bind the octree at 3–7 (`svo_brick`) and the mask
//! table's words at 8:
//!
//! ```
//! # #[cfg(feature = "wgsl")] {
//! let mut source = String::new();
//! svo_tracer::WGSL.write_source(&mut source).unwrap();
//! source.push_str(
//!     "struct Frame { tree: OctreeUniforms, table: MaskTableUniforms, camera: GpuCamera, settings: GpuTraceSettings }
//!      @group(0) @binding(0) var<uniform> frame: Frame;
//!      @group(0) @binding(1) var<storage, read_write> image: array<vec4<f32>>;
//!      @compute @workgroup_size(8, 8)
//!      fn render(@builtin(global_invocation_id) id: vec3<u32>) {
//!          if id.x >= frame.camera.size.x || id.y >= frame.camera.size.y { return; }
//!          let r = svo_trace_cone(frame.tree, frame.table, svo_pixel_cone(frame.camera, id.x, id.y), frame.settings);
//!          image[id.y * frame.camera.size.x + id.x] = vec4<f32>(r.radiance, r.coverage);
//!      }",
//! );
//! # let module = naga::front::wgsl::parse_str(&source).unwrap_or_else(|e| panic!("{}", e.emit_to_string(&source)));
//! # naga::valid::Validator::new(naga::valid::ValidationFlags::all(), Default::default()).validate(&module).unwrap();
//! assert!(source.contains("fn svo_trace_cone"));
//! # }
//! ```
//!
//! # Features
//!
//! - `std` (default): enables `std` in the dependencies. The crate is `#![no_std]` and
//!   needs no allocator; `cargo check -p svo-tracer --no-default-features` builds it
//!   without `std`.
//! - `wgsl`: [`WGSL`], the WGSL twin (its sources are embedded).
#![no_std]

#[cfg(feature = "std")]
extern crate std;

mod camera;
mod gpu;
mod lambert;
mod shading;
mod trace;
#[cfg(feature = "wgsl")]
mod wgsl;

pub use camera::{Camera, CameraError, Cone, Lens};
pub use gpu::{GpuCamera, GpuTraceSettings};
pub use lambert::{RECTIFIED_CUTOFF, expected_clamped_cosine};
pub use shading::{Filtering, Material, element_radiance};
pub use trace::{ConeResult, Light, Model, TraceSettings, box_interval, light_visibility, trace_cone};
#[cfg(feature = "wgsl")]
pub use wgsl::WGSL;
