//! Cone tracing of pre-filtered sparse voxel octrees after Heitz & Neyret, *Representing
//! Appearance and Pre-filtering Subpixel Data in Sparse Voxel Octrees* (HPG 2012), §4,
//! §5.3–5.5 and Algorithm 1: the CPU reference.
#![no_std]

#[cfg(feature = "std")]
extern crate std;

mod camera;
mod gpu;
mod shading;
mod trace;
#[cfg(feature = "wgsl")]
mod wgsl;

pub use camera::{Camera, CameraError, Cone, Lens};
pub use gpu::{GpuCamera, GpuTraceSettings};
pub use shading::{Filtering, Material, element_radiance};
pub use trace::{ConeResult, Light, Model, TraceSettings, box_interval, light_visibility, trace_cone};
#[cfg(feature = "wgsl")]
pub use wgsl::WGSL;
