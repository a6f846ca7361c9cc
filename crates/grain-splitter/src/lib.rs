//! Occlusion culling and tier splitting of dense grain stackings on the GPU, after Michel &
//! Boubekeur, *Real Time Multiscale Rendering of Dense Dynamic Stackings* (CGF 2020), §7
//! (Fig. 7, "Global atomic splitting") and §8 (the occluder map and Listing 2).
//!
//! Per frame, with no CPU round trip:
//!
//! 1. **Occluder map** ([`OccluderMapKind`]): every grain with a solid core splats a square of
//!    half-side `k·r_px` (§8: `k` ≈ 0.15–0.2, [`DEFAULT_SPLAT_FACTOR`]) at its projected
//!    centre, keeping per pixel the grain whose centre is nearest — one 64-bit `atomicMax`
//!    of `(~depth << 32) | ~index` where the adapter has 64-bit atomics, two 32-bit passes
//!    elsewhere (same result).
//! 2. **Decision** per grain: frustum test of its outer sphere (scaled), the conservative
//!    cone test of `occlusion-cone` against the occluder at its centre's pixel, beyond the
//!    paper a Hi-Z test against a max pyramid of conservative per-pixel depth bounds of the
//!    occluders ([`hiz`], occluder fusion), and the tier from its projected diameter with
//!    hysteresis ([`TierThresholds`]).
//! 3. **Lists**: counts, offsets, the element lists (meshes, occluder-candidate impostors,
//!    other impostors, points: see [`lists`]) and the indirect arguments of their
//!    draws and dispatches ([`ListIndirect`]) — `GrainViewer` reads its counters back to issue
//!    draws; here the next pass draws with `draw_indexed_indirect` from [`GrainSplitter::indirect`].
//!
//! ```no_run
//! use glam::{Vec3, Vec4};
//! use grain_splitter::{GrainSplitter, ListOrder, OccluderMapKind, SplitCamera, SplitSettings, SplitterOptions, TierThresholds};
//! use wgpu::util::DeviceExt;
//!
//! # fn frame(device: &wgpu::Device, queue: &wgpu::Queue) -> Result<(), grain_splitter::SplitError> {
//! let grains: Vec<Vec4> = (0..1000).map(|i| Vec4::new(i as f32 % 10.0, (i / 100) as f32, (i / 10 % 10) as f32, 0.5)).collect();
//! let buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
//!     label: Some("grains"),
//!     contents: bytemuck::cast_slice(&grains),
//!     usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
//! });
//! // Built once: r and R of the grain's mesh, tiers by projected diameter in pixels.
//! let settings = SplitSettings::new(0.8, 1.0, TierThresholds::new(2.0, 64.0, 1.1)?);
//! let options = SplitterOptions { capacity: 1000, size: (1280, 720), occluder_map: OccluderMapKind::Auto, order: ListOrder::Atomic };
//! let splitter = GrainSplitter::new(device, settings, options)?;
//! let bindings = splitter.bind(device, &buffer)?;
//! // Per frame.
//! let camera = SplitCamera::perspective(Vec3::new(5.0, 5.0, 30.0), Vec3::splat(5.0), Vec3::Y, 0.6, (1280, 720), (0.1, 100.0))?;
//! let mut encoder = device.create_command_encoder(&Default::default());
//! splitter.encode(queue, &mut encoder, &bindings, &camera, 1000, None)?;
//! // ... then draw the mesh list with
//! // pass.draw_indexed_indirect(splitter.indirect(), GrainSplitter::indirect_offset(grain_splitter::LIST_MESH));
//! queue.submit([encoder.finish()]);
//! # Ok(()) }
//! ```
//!
//! # Conservative
//!
//! Nothing visible is culled: the cone test is exact and rounded conservatively
//! (`occlusion-cone`, checked over 10⁷ configurations), the Hi-Z test's bounds are proven in
//! [`fusion`] and rounded conservatively in [`hiz`], and the frustum test keeps a rounding
//! margin ([`FRUSTUM_MARGIN`]). The GPU tests render a scene with every grain as a mesh, with
//! and without culling, and compare the pixels.
//!
//! # CPU reference
//!
//! [`reference`](mod@reference) evaluates the same decisions with the same `f32` operations (each shader
//! function names its Rust twin) and lists in ascending order; the GPU tests compare the
//! lists as sets, the counts and the indirect arguments. With [`ListOrder::Stable`] the GPU
//! lists are in that order too.
//!
//! # Modules
//!
//! - [`bench`](mod@bench): GPU timing of the passes (`cargo xtask bench-gpu culling`).
//! - [`camera`]: [`SplitCamera`] and the projections of a centre.
//! - [`tiers`]: [`Tier`], [`TierThresholds`] (measured mesh threshold, hysteresis).
//! - [`settings`]: [`SplitSettings`] and the shaders' uniform block.
//! - [`lists`]: list and culling codes, [`SplitCounters`], [`ListIndirect`], the state word.
//! - [`decision`]: the paper's per-grain decisions and the occluder map (`f32`, twins of the shaders).
//! - [`reference`](mod@reference): the CPU reference of a whole frame.
//! - [`fusion`]: occluder fusion, a conservative depth bound per pixel and its max pyramid (CPU, `f64`).
//! - [`hiz`]: the same on the GPU in `f32` (the pyramid passes and the splitter's Hi-Z test).
//! - [`temporal`]: two-phase culling, last frame's visible grains as this frame's occluders.
//! - [`shaders`]: the generated declarations and the composed shaders.
//! - [`splitter`]: [`GrainSplitter`], the GPU passes.
//! - [`sweep`]: the culling experiments of Fig. 15 (ratio `r/R`, splat factor) on the CPU
//!   reference.
//! - [`error`]: the error type, [`SplitError`].

pub mod bench;
pub mod camera;
pub mod decision;
pub mod error;
pub mod fusion;
pub mod hiz;
pub mod lists;
mod rays;
pub mod reference;
pub mod settings;
pub mod shaders;
pub mod splitter;
pub mod sweep;
pub mod temporal;
pub mod tiers;

pub use camera::{Projected, SplitCamera};
pub use error::SplitError;
pub use fusion::{DepthPyramid, FusionCheck, FusionCounts, check_fusion, fused_split_counts, occluder_bound};
pub use lists::{
    CULLED_CONE, CULLED_FRUSTUM, CULLED_HIZ, LIST_COUNT, LIST_IMPOSTOR_OCCLUDER, LIST_IMPOSTOR_REST, LIST_MESH,
    LIST_POINT, ListIndirect, SplitCounters,
};
pub use reference::{OccluderMap, SplitOutput};
pub use settings::{DEFAULT_SPLAT_FACTOR, FRUSTUM_MARGIN, SplitParams, SplitSettings};
pub use splitter::{GrainSplitter, ListOrder, OccluderMapKind, SplitBindings, SplitTimestamps, SplitterOptions};
pub use tiers::{Tier, TierThresholds};
