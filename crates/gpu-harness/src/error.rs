//! Errors of the harness.

use std::fmt;

/// Everything that can go wrong while setting up or using the GPU.
#[derive(Clone, Debug)]
pub enum HarnessError {
    /// No adapter matches the requested preference.
    NoAdapter {
        /// What was asked for.
        wanted: String,
        /// The adapters that exist, if any.
        available: Vec<String>,
    },
    /// The `GPU_ADAPTER` environment variable holds an unknown value.
    BadPreference(String),
    /// The adapter refused to create a device.
    RequestDevice(String),
    /// A request exceeds what the adapter can do.
    TooLarge {
        /// What was requested.
        what: String,
        /// The requested amount.
        requested: u64,
        /// The adapter's limit.
        limit: u64,
    },
    /// A request is malformed (for example a zero-sized element type).
    InvalidRequest(String),
    /// wgpu reported a validation or out-of-memory error.
    Wgpu(String),
    /// Waiting for the GPU or mapping a buffer failed.
    Readback(String),
}

impl fmt::Display for HarnessError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            HarnessError::NoAdapter { wanted, available } => {
                write!(f, "no {wanted} GPU adapter found")?;
                if available.is_empty() {
                    write!(f, " (no adapter at all)")?;
                } else {
                    write!(f, " (available: {})", available.join("; "))?;
                }
                write!(
                    f,
                    ". Without a GPU, install the software Vulkan driver: \
                     `apt-get update && apt-get install -y mesa-vulkan-drivers` (lavapipe)"
                )?;
                if !available.is_empty() {
                    write!(f, ", or set GPU_ADAPTER=any")?;
                }
                Ok(())
            }
            HarnessError::BadPreference(value) => {
                write!(f, "GPU_ADAPTER={value:?} is not one of `hardware`, `software`, `any`")
            }
            HarnessError::RequestDevice(e) => write!(f, "the adapter refused to create a device: {e}"),
            HarnessError::TooLarge { what, requested, limit } => {
                write!(f, "{what}: {requested} exceeds the adapter's limit of {limit}")
            }
            HarnessError::InvalidRequest(e) => write!(f, "invalid request: {e}"),
            HarnessError::Wgpu(e) => write!(f, "wgpu error: {e}"),
            HarnessError::Readback(e) => write!(f, "GPU readback failed: {e}"),
        }
    }
}

impl std::error::Error for HarnessError {}
