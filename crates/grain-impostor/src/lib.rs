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

pub mod cloud;
pub mod scene;
