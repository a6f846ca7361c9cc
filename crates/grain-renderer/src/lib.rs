//! The multiscale renderer of dense grain stackings, after Michel & Boubekeur, *Real Time
//! Multiscale Rendering of Dense Dynamic Stackings* (CGF 2020), §3 (Fig. 2), §4–5 and §9:
//! the tiers `grain-splitter` sorts grains into, drawn in one frame with no CPU round trip.
//!
//! [`StackingRenderer`] records a frame — split, mesh tier, impostor and point tiers,
//! deferred shading — into one command encoder.
//!
//! The **mesh tier** ([`MeshTier`]) draws the splitter's mesh list with one
//! `draw_indexed_indirect`. The **impostor tier** ([`ImpostorTier`]): the splitter's impostor
//! lists splatted in compute into a visibility buffer (one 64-bit `atomicMin` of
//! `(depth << 32) | grain` per covered pixel where the adapter has 64-bit atomics, a robust
//! two-pass 32-bit fallback elsewhere), occluder candidates first and the rest with a software
//! early-Z (§9's double draw), work per grain by footprint, then one resolve into the screen
//! G-buffer of `grain-impostor` — composited over the mesh tier's depth. The same lists can
//! be drawn as sprites with a hardware depth test instead ([`ImpostorPath::Raster`]), the
//! paper's form and the comparison, into the same visibility buffer.
//!
//! # Modules
//!
//! - [`renderer`]: [`StackingRenderer`], every pass of a frame built once.
//! - [`grain_type`]: one grain type's passes ([`GrainType`]); a scene may mix several.
//! - [`options`]: what a renderer is built for, [`RendererOptions`].
//! - [`bench`](mod@bench): a frame timed stage by stage.
//! - [`point_threshold`]: the point tier against the impostor tier, measured (error and time).
//! - [`tier_selection`]: the committed tier table and the point threshold read from it.
//! - [`frame_accuracy`]: whole-frame SSIM and ꟻLIP along a camera path, and popping.
//! - [`mesh_reference`]: the ground truth, every grain a mesh 4 × 4 supersampled.
//! - [`mesh_tier`]: [`MeshTier`], the mesh list in one indirect draw.
//! - [`impostor_tier`]: [`ImpostorTier`], its settings and counters.
//! - [`impostor_raster`]: the impostor tier's raster path.
//! - [`inputs`]: [`ListInputs`], the grains and the splitter's lists the tiers read.
//! - [`tier_layout`]: the tier's uniform blocks and constants (generated into WGSL).
//! - [`shaders`]: the generated declarations and the composed shaders.
//! - [`error`]: the error type, [`RenderError`].

pub mod bench;
pub mod error;
pub mod frame_accuracy;
pub mod grain_type;
pub mod impostor_raster;
pub mod impostor_tier;
pub mod inputs;
pub mod mesh_reference;
pub mod mesh_tier;
pub mod options;
pub mod point_threshold;
pub mod renderer;
pub mod shaders;
pub mod tier_layout;
pub mod tier_selection;

pub use error::RenderError;
pub use grain_type::{GrainType, TypeRenderer};
pub use impostor_tier::{
    ImpostorPath, ImpostorTier, TierBindings, TierFrame, TierPass, TierSettings, TierUniforms, VisibilityKind,
};
pub use inputs::ListInputs;
pub use mesh_tier::{MeshTier, MeshTierBindings};
pub use renderer::{RendererOptions, SceneBindings, StackingCamera, StackingRenderer, Stage};
