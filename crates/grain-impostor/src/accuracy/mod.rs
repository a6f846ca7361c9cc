//! The accuracy experiment of issue 3 (the paper's Fig. 13): impostor renders against the
//! mesh rendered with the same shading, over many view directions and two screen sizes.
//!
//! - [`view_set`]: the view directions and the grid scene that shows one grain from each of
//!   them in a single image.
//! - [`metrics`]: SSIM and RMSE between two renders.

pub mod metrics;
pub mod view_set;

pub use metrics::{ImageError, MetricError, compare_images};
pub use view_set::{ComparisonScene, fibonacci_directions};
