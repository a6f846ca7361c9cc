//! Octahedral impostors of grains on wgpu, after Michel & Boubekeur, *Real Time Multiscale
//! Rendering of Dense Dynamic Stackings* (CGF 2020), §4–6.
//!
//! This is a pipeline crate: it depends on the algorithm crates (`octahedral-map` owns the
//! view layout, the view frames and the sampling math) and on wgpu, never the reverse.
//!
//! # Shared conventions
//!
//! The passes of this crate meet in two data formats, declared here once:
//!
//! - the **screen G-buffer** ([`scene::GBUFFER_LAYERS`]), written by the mesh raster pass
//!   (ground truth) and by the impostor cloud pass, read by the deferred shading pass;
//! - the **atlas layers** ([`scene::ATLAS_LAYERS`]): `p × p × N` texture arrays with full,
//!   premultiplied-alpha mip chains, written by the baker and read by the samplers.
//!
//! Cameras and grains reach the GPU as [`scene::CameraUniforms`] and
//! [`scene::GrainInstance`], whose WGSL declarations are generated into
//! `crates/grain-impostor/shaders/generated.wgsl` (see [`scene::generated_wgsl`]; a test
//! checks that the committed file is fresh and laid out like Rust).
//!
//! View `i` of an atlas follows [`octahedral_map::ViewFrame`]: an orthographic camera
//! looking along `-ω_i`, covering the square `[-R, R]²` of the plane through the grain's
//! centre, `R` the grain's outer radius.
//!
//! # Modules
//!
//! - [`scene`]: the shared contract (cameras, instances, G-buffer and atlas formats).
//! - [`mesh_gbuffer`]: rasterizes a grain mesh into the screen G-buffer with `s × s`
//!   supersampling (ground truth, and the baker's renderer).
//! - [`bake`]: renders the `N = 2n²` views into an [`atlas::ImpostorAtlas`].
//! - [`atlas`]: the CPU atlas, its texel encodings and memory; [`mips`]: premultiplied,
//!   dilated mip chains; [`atlas_gpu`]: upload to texture arrays; [`atlas_file`]:
//!   save/load with checked errors; [`packed`]: the 8-byte packed layout and its cost.
//! - [`cloud`]: the impostor cloud pass (compute splats + resolve into the screen G-buffer,
//!   sampling with `octahedral_map::sampling`).
//! - [`choice`]: the atlas `(n, p)` and sampling mode for a screen size and an SSIM budget
//!   (eq. 4, and the cheapest measured configuration).
//! - [`selection`]: the table `model-select` chooses an atlas from (ꟻLIP and standard SSIM
//!   against the supersampled mesh, the atlas's memory as the cost) and its held-out check.
//! - [`shading`]: deferred shading of the G-buffer into a displayable image.
//! - [`accuracy`]: the view set, comparison scene and image metrics of the accuracy
//!   experiment (SSIM, RMSE against the mesh).
//! - [`gpu_util`], [`half`]: helpers.
//!
//! `cargo run --release -p grain-impostor --example bake_report` prints bake times, the
//! atlas memory for `n ∈ {4, …, 12}`, `p ∈ {32, 64, 128}`, and the accuracy cost of the
//! packed layout on the four procedural grains.

pub mod accuracy;
pub mod atlas;
pub mod atlas_file;
pub mod atlas_gpu;
pub mod atlas_image;
pub mod bake;
pub mod choice;
pub mod cloud;
pub mod gpu_util;
pub mod half;
pub mod mesh_gbuffer;
pub mod mips;
pub mod packed;
pub mod scene;
pub mod selection;
pub mod shading;
