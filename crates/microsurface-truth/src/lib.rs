//! Ground truth for the view- and light-dependent mean attribute of a rough surface
//! (Heitz & Neyret 2012, §5.5 and Fig. 9), by exact ray casting of periodic height fields.
//!
//! A height field is a periodic grid of heights, interpolated piecewise linearly (two
//! triangles per cell), so that ray intersection is exact and the slopes whose statistics
//! Smith's model uses are exactly the surface's slopes. Orthographic rays with uniformly
//! distributed entry points sample the projected surface uniformly; averaging the
//! attribute at the first hit (and, with a light, only over hits whose shadow ray escapes)
//! gives the pixel's mean attribute that eq. 17 models.
//!
//! This is a std crate beside the algorithm crates; [`comparison`] measures `smith-micro`'s
//! eq. 17 (and plain MIP-mapping) against the ground truth, as Fig. 9 of the paper does;
//! [`fit_lambda_correction`] fits `smith-micro`'s per-material [`smith_micro::LambdaCorrection`]
//! to the ground truth of a view-only sweep, and [`fit_visibility_correction`] the
//! corrected model with separate view and light tables and a light–view correlation term
//! ([`smith_micro::VisibilityCorrection`]) on several realizations at once.
//! [`standard_surfaces`] are the five surfaces those experiments measure; [`selection`]
//! measures the table from which `model-select` picks the cheapest Smith model within an
//! image-error budget.
//!
//! ```
//! use microsurface_truth::{Spectrum, SurfaceStatistics, VisibleAverage, generate_gaussian};
//!
//! let field = generate_gaussian(64, Spectrum::Gaussian { wavelength: 16.0 }, 0.4, 7).unwrap();
//! let stats = SurfaceStatistics::measure(&field);
//! assert!((stats.slope_sigma.x - 0.4).abs() < 0.1);
//! // Mean height of what a camera 60° off the normal sees: above the mean height.
//! let truth = VisibleAverage::new(&field, 4_000, 1);
//! let view = glam::DVec3::new(60_f64.to_radians().sin(), 0.0, 60_f64.to_radians().cos());
//! let seen = truth.mean_attribute(view, None, |h| h - stats.mean_height).unwrap();
//! assert!(seen.mean > 0.0);
//! ```

pub mod comparison;
mod correction_fit;
mod experiment;
mod generate;
mod heightfield;
mod max_pyramid;
mod raycast;
pub mod selection;
mod statistics;
mod surfaces;
mod visibility_fit;

pub use correction_fit::{
    FIT_ANGLES_DEG, FIT_AZIMUTHS_DEG, FitError, FitSample, fit_lambda_correction, fit_to_samples,
};
pub use experiment::{AttributeEstimate, VisibleAverage};
pub use generate::{Spectrum, generate_cellular, generate_gaussian, generate_ridged};
pub use heightfield::{HeightField, HeightFieldError};
pub use raycast::{first_hit, is_lit};
/// The corrected visibility model's per-material factor on Λ, as fitted here.
pub use smith_micro::LambdaCorrection;
/// The corrected visibility model with the light–view correlation term, as fitted here.
pub use smith_micro::VisibilityCorrection;
/// Re-exported: the cubic form of the correction and the deviation up to which it replaces the table.
pub use smith_micro::{CUBIC_DEVIATION_BUDGET, CubicLambdaCorrection};
pub use statistics::SurfaceStatistics;
pub use surfaces::{FITTING_SEED_OFFSETS, SLOPE_SIGMA, Surface, realizations, standard_surfaces};
pub use visibility_fit::{
    CORRELATION_LIGHTS_DEG, CORRELATION_VIEW_ANGLES_DEG, PairSample, SHRINKAGE_STEPS, VisibilitySamples,
    collect_samples, fit_correlation, fit_samples, fit_visibility_correction,
};
