//! The directional distance map tracer of Mehra & Kumar, *Accurate and Efficient
//! Rendering of Detail using Directional Distance Maps* (§3.2, Algorithms 3.1–3.3), its
//! baselines, and the exact ground truth it is measured against. The CPU reference of the
//! WGSL compute tracer `wgsl/ddm_tracer.wgsl`.
//!
//! ```
//! use ddm_compress::{DirectionCones, DistanceMapSettings, MapKind, Triangle, compute_distance_maps};
//! use ddm_tracer::{Method, PatchSettings, Stepping, TraceSettings, VoxelPatches, trace};
//! use glam::{UVec3, Vec3};
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! // A tile of 8 × 8 × 4 voxels whose mesostructure is a floor at z = 1.25.
//! let dims = UVec3::new(8, 8, 4);
//! let corner = |x: f32, y: f32| Vec3::new(x, y, 1.25);
//! let floor = [
//!     Triangle([corner(0.0, 0.0), corner(8.0, 0.0), corner(8.0, 8.0)]),
//!     Triangle([corner(0.0, 0.0), corner(8.0, 8.0), corner(0.0, 8.0)]),
//! ];
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
//! - [`solid`]: the side of the tile's mesh at each grid corner and the mesh's crossing of
//!   each grid edge, the shared decisions of the watertight patches.
//! - [`ground_truth`]: exact ray–triangle intersection of the periodic mesh (BVH).
//! - [`gpu_scene`]: the scene packed into the buffers of the WGSL twin, with an `f32` or
//!   (rounded down, still conservative) binary16 atlas.
//! - [`pipeline_constants`]: what a pipeline tracing a scene is specialised for (the
//!   method, the stepping, the tiling, the block shift, the atlas's storage), as the WGSL
//!   twin's `override`s.
//! - [`tangent_space`]: the per-pixel ray of a mesostructure mapped on a base mesh.
//!
//! # Using the WGSL twin
//!
//! With the `wgsl` feature, [`WGSL`] is the tracer in WGSL: `trace_ray(uniforms, origin,
//! direction) -> TraceResult` (Algorithms 3.1–3.3 and relief mapping, one ray, the same
//! steps as [`trace()`]) and the tangent-space functions of a base mesh's pixel
//! (`render_tangent_frame`, `render_tangent_ray`, `render_in_shadow`, mirroring
//! [`tangent_space`]). It declares the scene's storage buffers at `@group(0)`, bindings
//! 3–8; [`GpuScene`] packs maps, patches and a relief height map into exactly those
//! buffers ([`GpuScene::storage_bytes`], in binding order) and the uniforms
//! ([`GpuScene::uniforms`]); a pipeline that traces the scene sets the twin's overridable
//! constants to [`GpuScene::pipeline_constants`] (`wgpu::PipelineCompilationOptions::constants`
//! takes [`TracePipelineConstants::constants`]; unset, they default to quadric patches,
//! distance stepping, a periodic tile, divisions and an `f32` atlas). It calls
//! `quadric-fit`'s and `ddm-compress`'s twins, which
//! [`WGSL`]'s `dependencies` lists and `write_source` writes first:
//!
//! ```
//! # #[cfg(feature = "wgsl")] {
//! let mut source = String::new();
//! ddm_tracer::WGSL.write_source(&mut source).unwrap(); // quadric_fit, ddm_compress, then ddm_tracer
//! source.push_str(
//!     "@group(0) @binding(0) var<uniform> uniforms: TraceUniforms;
//!      @group(0) @binding(1) var<storage, read> rays: array<vec4<f32>>; // origin, direction
//!      @group(0) @binding(2) var<storage, read_write> hits: array<TraceResult>;
//!      @compute @workgroup_size(64)
//!      fn main(@builtin(global_invocation_id) id: vec3<u32>) {
//!          if 2u * id.x + 1u < arrayLength(&rays) {
//!              hits[id.x] = trace_ray(uniforms, rays[2u * id.x].xyz, rays[2u * id.x + 1u].xyz);
//!          }
//!      }",
//! );
//! # let module = naga::front::wgsl::parse_str(&source).unwrap_or_else(|e| panic!("{}", e.emit_to_string(&source)));
//! # naga::valid::Validator::new(naga::valid::ValidationFlags::all(), Default::default()).validate(&module).unwrap();
//! assert_eq!(ddm_tracer::WGSL.dependency_names().collect::<Vec<_>>(), ["quadric_fit", "ddm_compress"]);
//! # }
//! ```
//!
//! With `naga_oil`, register `quadric_fit::WGSL.naga_oil_source`, then
//! `ddm_compress::WGSL.naga_oil_source`, then this crate's, and `#import
//! ddm_tracer::{trace_ray, TraceUniforms, TraceResult}`. `ddm-render` (in this workspace)
//! is a complete renderer built on it.
//!
//! # Features
//!
//! - `std` (default): enables `std` in the dependencies. The crate is `#![no_std]` with
//!   `alloc`; `cargo check -p ddm-tracer --no-default-features` builds it.
//! - `wgsl`: [`WGSL`], the WGSL twin (its sources are embedded; enables `quadric-fit`'s and
//!   `ddm-compress`'s twins, which it composes after).
#![no_std]

extern crate alloc;

pub mod exact_patches;
pub mod gpu_scene;
pub mod ground_truth;
pub mod maps;
pub mod patch;
pub mod patches;
pub mod pipeline_constants;
pub mod relief;
pub mod solid;
pub mod tangent_space;
pub mod trace;
pub mod voxel;
#[cfg(feature = "wgsl")]
mod wgsl;

pub use gpu_scene::{GpuScene, GpuSceneError, TraceConeMap, TraceResult, TraceUniforms};
pub use ground_truth::{MeshCrossing, MeshHit, MeshRaycaster};
pub use maps::{CompressMapsError, CompressedMaps, ConeDistances, ConeSelector, DistanceSource, RawConeMap};
pub use patch::TracePatch;
pub use patches::{
    MAX_PATCH_VOXELS, MAX_WATERTIGHT_SUBDIVISION, PatchError, PatchSettings, PatchSurface, VoxelPatches,
};
pub use pipeline_constants::{AtlasStorage, TracePipelineConstants};
pub use relief::{HeightMap, HeightMapError, relief_trace};
pub use trace::{Method, NO_LIMIT, Stepping, TraceHit, TraceOutcome, TraceSettings, trace, trace_within};
#[cfg(feature = "wgsl")]
pub use wgsl::WGSL;
