//! The accuracy experiment of issue 3 (the paper's Fig. 13): impostor renders against the
//! mesh rendered with the same shading, over many view directions and two screen sizes.
//!
//! - [`view_set`]: the view directions and the grid scene that shows one grain from each of
//!   them in a single image.
//! - [`metrics`]: SSIM and RMSE between two renders.
//! - [`sweep`]: bakes, renders and measures every configuration.
//! - [`table`]: the measurements as CSV (written by `cargo xtask impostor-accuracy`).
//! - [`timing`]: the time of each impostor render's cloud pass (the cost axis of the
//!   error-against-time chart).

pub mod metrics;
pub mod sweep;
pub mod table;
pub mod timing;
pub mod view_set;

pub use metrics::{ImageError, MetricError, compare_images};
pub use sweep::{AccuracySweep, REFERENCE_SUPERSAMPLING, SweepError, SweepRow, SweepSettings};
pub use table::{
    rows_from_csv, rows_to_csv, sampling_mode_from_name, sampling_mode_name, view_layout_from_name, view_layout_name,
};
pub use timing::SweepTiming;
pub use view_set::{ComparisonScene, fibonacci_directions};
