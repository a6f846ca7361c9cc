//! Why a splitter could not be built, bound or encoded.

use std::fmt;

/// Why a splitter could not be built, bound or encoded.
#[derive(Clone, Debug, PartialEq)]
pub enum SplitError {
    /// A camera argument is invalid (the field is named).
    InvalidCamera {
        /// The argument.
        field: &'static str,
        /// What is wrong with it.
        reason: String,
    },
    /// A setting is invalid (the field is named).
    InvalidSetting {
        /// The setting.
        field: &'static str,
        /// What is wrong with it.
        reason: String,
    },
    /// The request exceeds a limit of the adapter (or of the packing).
    TooLarge {
        /// What is too large.
        what: &'static str,
        /// The requested amount.
        requested: u64,
        /// The limit.
        limit: u64,
    },
    /// The adapter lacks a feature the request needs.
    MissingFeature(&'static str),
    /// A shader failed naga validation (the message names the file and line).
    InvalidShader(String),
    /// A buffer given to the splitter cannot serve (the message says why).
    InvalidBuffer(String),
    /// wgpu reported an error, or a readback failed.
    Wgpu(String),
}

impl fmt::Display for SplitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::InvalidCamera { field, reason } => write!(f, "grain splitter camera: `{field}` {reason}"),
            Self::InvalidSetting { field, reason } => {
                write!(f, "grain splitter setting `{field}` is invalid: {reason}")
            }
            Self::TooLarge { what, requested, limit } => {
                write!(f, "grain splitter: {what} {requested} exceeds the limit {limit}")
            }
            Self::MissingFeature(feature) => write!(f, "grain splitter: the adapter lacks {feature}"),
            Self::InvalidShader(message) => write!(f, "grain splitter shader: {message}"),
            Self::InvalidBuffer(message) => write!(f, "grain splitter: {message}"),
            Self::Wgpu(message) => write!(f, "grain splitter: wgpu error: {message}"),
        }
    }
}

impl std::error::Error for SplitError {}
