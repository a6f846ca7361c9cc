//! Why a pipeline, a pass, a target or a frame of `ddm-render` could not be built or
//! encoded.

use std::fmt;

use gpu_harness::HarnessError;

/// Why a `ddm-render` object could not be built, a frame encoded or read back. Every
/// variant names what is wrong (the limit, the field, the texture or buffer).
#[derive(Clone, Debug)]
pub enum DdmRenderError {
    /// A composed shader failed generation or naga validation (the message names the file
    /// and line).
    InvalidShader {
        /// Which shader (`ddm_render_raster`, `ddm_render_pixels`).
        shader: &'static str,
        /// naga's or the generator's message.
        message: String,
    },
    /// A request exceeds a limit of the device (`wgpu::Device::limits`).
    TooLarge {
        /// What is too large, and the `wgpu::Limits` field it is checked against.
        what: &'static str,
        /// The requested amount.
        requested: u64,
        /// The device's limit.
        limit: u64,
    },
    /// The G-buffer size has a zero side.
    EmptySize {
        /// Requested width in pixels.
        width: u32,
        /// Requested height in pixels.
        height: u32,
    },
    /// A storage buffer of the tracer's scene is empty (WGSL arrays never are).
    EmptySceneBuffer(&'static str),
    /// The base mesh cannot be rasterized (the message says why).
    InvalidMesh(&'static str),
    /// A camera field is not usable (named in the message).
    InvalidCamera(&'static str),
    /// A [`RenderSettings`](crate::RenderSettings) field is not usable (named in the message).
    InvalidSettings(&'static str),
    /// Two sizes that must be equal differ.
    SizeMismatch {
        /// What was compared with the G-buffer (the camera, a target).
        what: &'static str,
        /// The G-buffer's `(width, height)`.
        expected: (u32, u32),
        /// The other `(width, height)`.
        found: (u32, u32),
    },
    /// A texture or buffer given as a target lacks a property the pass needs.
    InvalidTarget {
        /// Which target.
        what: &'static str,
        /// What it lacks.
        problem: String,
    },
    /// A timestamp query set cannot take the pass's timestamps.
    InvalidTimestamps(String),
    /// wgpu reported an error, or a readback failed.
    Gpu(HarnessError),
    /// A plain distance map built on the GPU could not be laid out or read back (the
    /// error names the input or buffer).
    PlainMap(ddm_compress::PlainGpuError),
}

impl fmt::Display for DdmRenderError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::InvalidShader { shader, message } => write!(f, "ddm-render shader `{shader}`: {message}"),
            Self::TooLarge { what, requested, limit } => {
                write!(f, "ddm-render: {what}: {requested} exceeds the device's limit of {limit}")
            }
            Self::EmptySize { width, height } => write!(f, "ddm-render: the G-buffer size {width}×{height} is empty"),
            Self::EmptySceneBuffer(name) => write!(f, "ddm-render: the {name} is empty"),
            Self::InvalidMesh(why) => write!(f, "ddm-render: invalid base mesh: {why}"),
            Self::InvalidCamera(why) => write!(f, "ddm-render: invalid camera: {why}"),
            Self::InvalidSettings(why) => write!(f, "ddm-render: invalid render settings: {why}"),
            Self::SizeMismatch { what, expected, found } => write!(
                f,
                "ddm-render: {what} is {}×{} but the G-buffer is {}×{}",
                found.0, found.1, expected.0, expected.1
            ),
            Self::InvalidTarget { what, problem } => write!(f, "ddm-render: {what}: {problem}"),
            Self::InvalidTimestamps(why) => write!(f, "ddm-render: timestamps: {why}"),
            Self::Gpu(e) => write!(f, "ddm-render: {e}"),
            Self::PlainMap(e) => write!(f, "ddm-render: {e}"),
        }
    }
}

impl std::error::Error for DdmRenderError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Self::Gpu(e) => Some(e),
            Self::PlainMap(e) => Some(e),
            _ => None,
        }
    }
}

impl From<ddm_compress::PlainGpuError> for DdmRenderError {
    fn from(e: ddm_compress::PlainGpuError) -> Self {
        Self::PlainMap(e)
    }
}

impl From<HarnessError> for DdmRenderError {
    fn from(e: HarnessError) -> Self {
        Self::Gpu(e)
    }
}

/// `Err(TooLarge)` when `requested` exceeds `limit`.
pub(crate) fn check_limit(what: &'static str, requested: u64, limit: u64) -> Result<(), DdmRenderError> {
    if requested > limit { Err(DdmRenderError::TooLarge { what, requested, limit }) } else { Ok(()) }
}
