//! Rendering pre-filtered sparse voxel octrees after Heitz & Neyret, *Representing
//! Appearance and Pre-filtering Subpixel Data in Sparse Voxel Octrees* (HPG 2012): images
//! through the cone tracer (`svo-tracer`), the supersampled ground truth of the unfiltered
//! surface (eq. 2) and of the octree's finest level, and their accuracy along a dolly
//! (Fig. 8); on the CPU, and on wgpu through [`GpuRenderer`], built once and encoded per
//! frame.
//!
//! ```
//! use abuffer_mask::MaskTable;
//! use glam::Vec3;
//! use svo_brick::{BrickSize, PackedTree, VoxelLayout};
//! use svo_render::{accuracy, cpu, scenes, truth};
//! use svo_tracer::{Camera, TraceSettings};
//!
//! let scene = scenes::sphere(0.6)?;
//! let tree = scene.build(BrickSize::Four, 3)?; // 16 voxels across
//! let packed = PackedTree::new(&tree, VoxelLayout::Paper20);
//! let table = MaskTable::<4>::paper().expect("the paper's table");
//! let camera = Camera::look_at(Vec3::new(0.0, 0.0, -3.0), Vec3::ZERO, Vec3::Y, 0.5, 16, 16)?;
//! let settings = TraceSettings::default();
//!
//! let frame = cpu::render(&packed, &table, &camera, &settings);
//! let voxel = scene.voxel_size(BrickSize::Four, 3);
//! let truth_settings = truth::TruthSettings::for_voxel(voxel, 2);
//! let reference = truth::render_source_truth(scene.source.as_ref(), scene.domain, &camera, &settings, &truth_settings)?;
//! let comparison = accuracy::compare(&frame, &reference, settings.background, 1.0)?;
//! assert!(comparison.ssim > 0.5 && comparison.rmse < 0.2);
//! let image = frame.to_rgba8(1.0); // save with frame.write_png(path, 1.0)
//! assert_eq!(image.dimensions(), (16, 16));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # What is where
//!
//! - [`frame`]: [`Frame`] (linear radiance, coverage and work per pixel), its 8-bit sRGB
//!   image and PNG.
//! - [`cpu`]: [`cpu::render`], every pixel's cone through [`svo_tracer::trace_cone`] on every
//!   core (deterministic).
//! - [`truth`]: the ground truth, stratified supersampling of the footprint and the lens,
//!   sphere tracing, the base BRDF with the local attribute, stratified shadow rays towards
//!   the area light; of the unfiltered source ([`truth::render_source_truth`]) or of the
//!   finest voxels ([`truth::render_voxel_truth`]).
//! - [`accuracy`]: [`accuracy::dolly_accuracy`], the table of every model at every view of
//!   a dolly against the truth (RMSE, SSIM, ꟻLIP, mean colour and drift, silhouette coverage,
//!   elements, time), and its CSV.
//! - [`stability`]: sweeps that relax the paper's hypotheses step by step (H7 thin plates,
//!   H6 curvature and box corners, H3 non-Gaussian micro-surfaces, grazing views) with
//!   every model against the truth at each step ([`stability::run`]), their CSV and
//!   [`stability::write_folder`]; scenes from `svo-scenes` and `microsurface-truth`.
//! - [`scenes`]: the analytic scenes (sphere, bumpy sphere coloured by height, bumpy plane,
//!   box) as `svo_brick::SdfSurface` closures.
//! - [`scene_input`]: the scenes a user names ([`scene_input::SceneInput`]): a named one, a
//!   closed OBJ, a PNG height map.
//! - [`parallel`]: the per-pixel thread pool of [`std::thread::scope`].
//! - [`renderer`]: [`GpuRenderer`], the cone tracer on wgpu: the pools, the mask table and
//!   the pipeline built once; per frame ([`FrameSettings`]) one compute pass of 8 × 8 tiles
//!   through `svo-tracer`'s WGSL twin into radiance, coverage and work buffers and an
//!   sRGB-encoded storage texture.
//! - [`gpu_truth`]: [`GpuVoxelTruth`], the voxel truth on wgpu (the same rays as
//!   [`truth::render_voxel_truth`], in `f32`), to time supersampling on the tracer's adapter.
//! - [`shader`]: the frame kernel's WGSL (generated declarations and composition).
//! - [`timing`]: frames timed by GPU timestamps (wall clock on software adapters), and the
//!   benchmark of every model along a dolly with and without shadows and depth of field.
//! - [`RenderError`]: every failure, naming the setting or file.

pub mod accuracy;
pub mod cpu;
mod error;
pub mod frame;
pub mod gpu_truth;
pub mod parallel;
pub mod renderer;
pub mod scene_input;
pub mod scenes;
pub mod shader;
pub mod stability;
pub mod timing;
pub mod truth;

pub use error::RenderError;
pub use frame::Frame;
pub use gpu_truth::GpuVoxelTruth;
pub use renderer::{FrameSettings, GpuRenderer};
