//! Why a metric could not be computed: the one error type of the crate.

use std::fmt;

/// Why a metric could not be computed from its inputs. Every metric checks its inputs
/// and returns one of these instead of panicking.
#[derive(Clone, Debug, PartialEq)]
pub enum MetricError {
    /// The reference and the test image (or luma plane) differ in size.
    SizeMismatch {
        /// The reference's `(width, height)`.
        reference: (u32, u32),
        /// The test's `(width, height)`.
        test: (u32, u32),
    },
    /// The images are smaller than the metric needs (SSIM: its 11 × 11 window; ꟻLIP: one
    /// pixel).
    TooSmall {
        /// The metric (`"SSIM"`, `"FLIP"`).
        metric: &'static str,
        /// The images' `(width, height)`.
        size: (u32, u32),
        /// The smallest width and height the metric accepts.
        min_side: u32,
    },
    /// A luma plane does not have `width × height` values.
    LengthMismatch {
        /// Which plane: `"reference"` or `"test"`.
        plane: &'static str,
        /// `width × height`.
        expected: usize,
        /// The slice's length.
        actual: usize,
    },
    /// A luma plane holds a NaN or an infinity.
    NonFinite {
        /// Which plane: `"reference"` or `"test"`.
        plane: &'static str,
        /// The first such value's `(x, y)`.
        at: (u32, u32),
        /// The value.
        value: f64,
    },
}

impl fmt::Display for MetricError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MetricError::SizeMismatch { reference: (rw, rh), test: (tw, th) } => {
                write!(
                    f,
                    "the reference is {rw}×{rh} px but the test image is {tw}×{th} px; they must be the same size"
                )
            }
            MetricError::TooSmall { metric, size: (w, h), min_side } => {
                write!(f, "{metric} needs images of at least {min_side}×{min_side} px, got {w}×{h} px")
            }
            MetricError::LengthMismatch { plane, expected, actual } => {
                write!(f, "the {plane} luma plane has {actual} values, but width × height is {expected}")
            }
            MetricError::NonFinite { plane, at: (x, y), value } => {
                write!(f, "the {plane} luma plane holds {value} at ({x}, {y}); every value must be finite")
            }
        }
    }
}

impl std::error::Error for MetricError {}

/// `Ok` when both sizes are equal and at least `min_side` in both directions.
pub(crate) fn check_sizes(
    metric: &'static str,
    reference: (u32, u32),
    test: (u32, u32),
    min_side: u32,
) -> Result<(), MetricError> {
    if reference != test {
        return Err(MetricError::SizeMismatch { reference, test });
    }
    if reference.0 < min_side || reference.1 < min_side {
        return Err(MetricError::TooSmall { metric, size: reference, min_side });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_what_is_wrong() {
        let mismatch = check_sizes("SSIM", (64, 48), (64, 47), 11).unwrap_err();
        assert_eq!(mismatch, MetricError::SizeMismatch { reference: (64, 48), test: (64, 47) });
        let text = mismatch.to_string();
        assert!(text.contains("64×48") && text.contains("64×47"), "{text}");

        let small = check_sizes("SSIM", (10, 48), (10, 48), 11).unwrap_err();
        assert_eq!(small, MetricError::TooSmall { metric: "SSIM", size: (10, 48), min_side: 11 });
        assert!(small.to_string().contains("at least 11×11"), "{small}");
        assert_eq!(check_sizes("SSIM", (11, 11), (11, 11), 11), Ok(()));

        let length = MetricError::LengthMismatch { plane: "test", expected: 121, actual: 120 };
        assert!(length.to_string().contains("test luma plane has 120 values"), "{length}");
        let nan = MetricError::NonFinite { plane: "reference", at: (3, 4), value: f64::NAN };
        assert!(nan.to_string().contains("NaN at (3, 4)"), "{nan}");
    }
}
