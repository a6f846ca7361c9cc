//! The error measure of a selection and its bound.

use core::fmt;

use crate::SelectError;

/// An image-error measure of a [`Measurement`](crate::Measurement) against its truth.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Metric {
    /// The mean ꟻLIP error (Andersson et al., HPG 2020), 0 for identical images, at most 1.
    Flip,
    /// One minus the mean SSIM (Wang et al. 2004, 11 × 11 Gaussian window, σ = 1.5, on
    /// luma): 0 for identical images.
    SsimLoss,
}

impl Metric {
    /// Both metrics.
    pub const ALL: [Metric; 2] = [Self::Flip, Self::SsimLoss];

    /// The name in tables and command lines: `flip`, `1-ssim`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Flip => "flip",
            Self::SsimLoss => "1-ssim",
        }
    }

    /// The metric called `name` ([`Metric::name`]).
    pub fn from_name(name: &str) -> Result<Self, SelectError> {
        Self::ALL.into_iter().find(|m| m.name() == name).ok_or_else(|| SelectError::InvalidBudget {
            reason: format!("unknown metric `{name}` (known: flip, 1-ssim)"),
        })
    }
}

impl fmt::Display for Metric {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Flip => "ꟻLIP",
            Self::SsimLoss => "1 − SSIM",
        })
    }
}

/// The largest image error a selection may accept, under one [`Metric`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Budget {
    metric: Metric,
    max: f64,
}

impl Budget {
    /// A budget of at most `max` under `metric`; an error unless `max` is finite and
    /// positive.
    pub fn new(metric: Metric, max: f64) -> Result<Self, SelectError> {
        if max.is_finite() && max > 0.0 {
            Ok(Self { metric, max })
        } else {
            Err(SelectError::InvalidBudget { reason: format!("{metric} budget {max} is not a positive number") })
        }
    }

    /// The metric.
    pub fn metric(self) -> Metric {
        self.metric
    }

    /// The bound.
    pub fn max(self) -> f64 {
        self.max
    }
}

impl fmt::Display for Budget {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} ≤ {}", self.metric, self.max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn budgets_must_be_positive_numbers() {
        for bad in [0.0, -0.1, f64::NAN, f64::INFINITY] {
            assert!(Budget::new(Metric::Flip, bad).is_err(), "{bad}");
        }
        let budget = Budget::new(Metric::SsimLoss, 0.02).unwrap();
        assert_eq!((budget.metric(), budget.max()), (Metric::SsimLoss, 0.02));
        assert_eq!(budget.to_string(), "1 − SSIM ≤ 0.02");
    }

    #[test]
    fn metric_names_round_trip_and_unknown_names_are_errors() {
        for metric in Metric::ALL {
            assert_eq!(Metric::from_name(metric.name()).unwrap(), metric);
        }
        let error = Metric::from_name("psnr").unwrap_err().to_string();
        assert!(error.contains("unknown metric `psnr`"), "{error}");
    }
}
