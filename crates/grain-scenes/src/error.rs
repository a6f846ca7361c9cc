//! Why a stacking could not be made or posed: the one error type of the crate.

use std::fmt;

/// Why a stacking could not be made, or a frame of its animation written.
#[derive(Clone, Debug, PartialEq)]
pub enum SceneError {
    /// A field of a specification is out of its range (NaN, negative, too large, or
    /// incompatible with another field).
    InvalidField {
        /// The field, as written in Rust (`"scale_jitter"`, `"region.aspect.x"`, …).
        field: &'static str,
        /// Its value (counts converted to `f64`).
        value: f64,
        /// What the field must satisfy.
        reason: &'static str,
    },
    /// A stacking size could not be parsed (see [`crate::StackingSize`]).
    InvalidSize {
        /// The string as given.
        text: String,
    },
    /// The stacking needs more memory than is available.
    TooLarge {
        /// Bytes the stacking's arrays need.
        requested_bytes: u64,
        /// Bytes available (`MemAvailable` of `/proc/meminfo`, or the explicit limit).
        available_bytes: u64,
    },
    /// The allocator refused the stacking's arrays.
    AllocationFailed {
        /// Bytes that were requested.
        requested_bytes: u64,
    },
    /// A caller-provided slice does not have one element per grain.
    LengthMismatch {
        /// The slice's parameter name.
        slice: &'static str,
        /// The number of grains.
        expected: usize,
        /// The slice's length.
        actual: usize,
    },
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneError::InvalidField { field, value, reason } => {
                write!(f, "invalid `{field}` = {value}: {reason}")
            }
            SceneError::InvalidSize { text } => {
                write!(f, "invalid stacking size {text:?}: expected one of \"20k\", \"200k\", \"1.6M\", \"20M\"")
            }
            SceneError::TooLarge { requested_bytes, available_bytes } => write!(
                f,
                "the stacking needs {requested_bytes} bytes, which exceeds this machine's available memory ({available_bytes} bytes)"
            ),
            SceneError::AllocationFailed { requested_bytes } => {
                write!(f, "the allocator refused {requested_bytes} bytes for the stacking's arrays")
            }
            SceneError::LengthMismatch { slice, expected, actual } => {
                write!(f, "`{slice}` has {actual} elements, but the stacking has {expected} grains")
            }
        }
    }
}

impl std::error::Error for SceneError {}

/// Shorthand for [`SceneError::InvalidField`].
pub(crate) fn invalid(field: &'static str, value: f64, reason: &'static str) -> SceneError {
    SceneError::InvalidField { field, value, reason }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_the_field_and_the_machine() {
        let e = invalid("scale_jitter", 1.5, "must lie in [0, 1)");
        assert!(e.to_string().contains("scale_jitter"), "{e}");
        let e = SceneError::TooLarge { requested_bytes: 10, available_bytes: 5 };
        assert!(e.to_string().contains("exceeds this machine's available memory"), "{e}");
        let e = SceneError::InvalidSize { text: "3q".into() };
        assert!(e.to_string().contains("\"3q\""), "{e}");
        let e = SceneError::LengthMismatch { slice: "rotation", expected: 3, actual: 2 };
        assert!(e.to_string().contains("rotation"), "{e}");
    }
}
