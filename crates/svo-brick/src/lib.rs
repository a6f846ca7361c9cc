//! Pre-filtered sparse voxel octrees after Heitz & Neyret, *Representing Appearance and
//! Pre-filtering Subpixel Data in Sparse Voxel Octrees* (HPG 2012), §5.2 and §6.
//!
//! (Crate documentation in progress.)
#![no_std]

extern crate alloc;
#[cfg(all(test, feature = "std"))]
extern crate std;

mod descriptor;
mod surface;

pub use descriptor::{ATTRIBUTE_CHANNELS, Voxel};
pub use surface::{Cell, SdfSurface, SurfaceError, SurfaceSample, SurfaceSource, thin_shell_samples};
