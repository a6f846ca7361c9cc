//! The error type of the renderer.

/// Why a renderer could not be built or a frame encoded.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum RenderError {
    /// A setting is out of range (the field and why).
    InvalidSetting {
        /// The field.
        field: &'static str,
        /// What is wrong with its value.
        reason: String,
    },
    /// An input buffer, texture or camera does not fit (what and why).
    InvalidInput(String),
    /// The device lacks a feature the chosen option needs.
    MissingFeature(&'static str),
    /// A buffer would exceed the device's limit.
    TooLarge {
        /// What.
        what: &'static str,
        /// Bytes or items requested.
        requested: u64,
        /// The limit.
        limit: u64,
    },
    /// A shader failed naga validation (the message names the file and line).
    InvalidShader(String),
}

impl std::fmt::Display for RenderError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::InvalidSetting { field, reason } => write!(f, "grain renderer: {field}: {reason}"),
            Self::InvalidInput(message) => write!(f, "grain renderer: {message}"),
            Self::MissingFeature(feature) => write!(f, "grain renderer: the device lacks {feature}"),
            Self::TooLarge { what, requested, limit } => {
                write!(f, "grain renderer: {what}: {requested} exceeds the device's limit of {limit}")
            }
            Self::InvalidShader(message) => write!(f, "grain renderer: {message}"),
        }
    }
}

impl std::error::Error for RenderError {}
