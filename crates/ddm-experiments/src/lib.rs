//! Mehra & Kumar, *Accurate and Efficient Rendering of Detail using Directional Distance
//! Maps*: the experiments behind Tables 1–3, as functions that take settings and return
//! typed rows, so that they are tested like the algorithm crates and `cargo xtask
//! ddm-trace` / `ddm-compression` only parse arguments, write files and draw charts.
//!
//! - [`trace_tables`]: Tables 1–3 measured with `ddm_tracer` against the exact mesh — per
//!   mesostructure, one perspective view traced with every [`TraceMethod`] (steps, hit
//!   error, holes, CPU rays/s, GPU time), the same methods on compressed maps (Table 3),
//!   the patches' memory, the adaptive patches against their error budget, and the steps
//!   against the view angle ([`steps`]).
//! - [`compression`]: Table 3's compression efficiency of the plain distance map and the
//!   DDMs with blocks of 2, 4 and 8.
//! - [`stats`]: outcomes against the ground truth, and two tracings against each other.
//! - [`reference`](mod@reference): each tile's own surface (analytic spheres and tori, the height field's
//!   triangles) and a method's geometric, normal and leak errors against it.
//! - [`resolution`]: each patch construction's error against that surface as the tile is
//!   sampled by finer grids (12 to 96 voxels across).
//! - [`timing`]: fastest-of-N CPU timing and the interleaved time ratio (median of
//!   alternating pairs of passes, so that a drift of the machine's speed cancels).
//! - [`view`]: the camera rays of the tables' view (and of any other camera).
//! - [`shading`]: a view shaded from its hit normals (the images the metrics compare).
//! - [`selection`]: the measured table that `model_select` picks the cheapest method
//!   within an image-error budget from, and the check of its choices on a held-out view.
//! - [`maps`]: the maps of the tables (plain DM, DDM m×n) by name.
//! - [`gpu`]: the WGSL tracer's compute pass, timed, and its differences from the CPU's.
//!
//! ```
//! use ddm_experiments::compression::{CompressionSettings, map_compression};
//! use glam::UVec3;
//!
//! let settings = CompressionSettings { dims: UVec3::new(8, 8, 4), ..CompressionSettings::paper() };
//! let floor = mesostructure::plane(settings.dims, 1.25);
//! let rows = map_compression("floor", &floor, &settings).unwrap();
//! assert_eq!(rows.len(), 4); // DM, DDM 2x1, 4x1, 8x1
//! ```

use std::fmt;

pub mod compression;
pub mod gpu;
pub mod maps;
pub mod reference;
pub mod resolution;
pub mod selection;
pub mod shading;
pub mod stats;
pub mod steps;
pub mod timing;
pub mod trace_tables;
pub mod view;

pub use trace_tables::{TraceMethod, TraceTablesSettings};

/// Why an experiment did not run to its end.
#[derive(Clone, Debug, PartialEq)]
pub enum ExperimentError {
    /// A field of the settings is out of range.
    InvalidSettings {
        /// The field, as named in the settings struct.
        field: &'static str,
        /// What is wrong with it.
        reason: String,
    },
    /// A scene's maps, patches or compressed maps could not be built.
    Scene {
        /// The mesostructure (or scene) name.
        scene: String,
        /// What failed.
        what: String,
    },
    /// The GPU pass failed (the message is the harness's or the registry's).
    Gpu(String),
    /// An image metric or a selection failed.
    Selection(String),
}

impl ExperimentError {
    /// An [`ExperimentError::InvalidSettings`].
    pub(crate) fn settings(field: &'static str, reason: impl Into<String>) -> Self {
        Self::InvalidSettings { field, reason: reason.into() }
    }

    /// An [`ExperimentError::Scene`].
    pub(crate) fn scene(scene: &str, what: impl Into<String>) -> Self {
        Self::Scene { scene: scene.to_owned(), what: what.into() }
    }
}

impl fmt::Display for ExperimentError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::InvalidSettings { field, reason } => write!(f, "invalid settings: {field}: {reason}"),
            Self::Scene { scene, what } => write!(f, "{scene}: {what}"),
            Self::Gpu(message) => write!(f, "GPU pass: {message}"),
            Self::Selection(message) => write!(f, "selection: {message}"),
        }
    }
}

impl std::error::Error for ExperimentError {}
