//! Why a render, a measurement or a file could not be made: the one error type of the crate.

use std::fmt;
use std::path::PathBuf;

use svo_brick::BuildError;
use svo_tracer::CameraError;

/// Why a render, a measurement or a file could not be made. Every fallible function of the
/// crate returns one of these instead of panicking.
#[derive(Debug)]
pub enum RenderError {
    /// A setting is out of range: the field's name, its value and what it must be.
    Setting {
        /// The field, as `Struct::field`.
        field: &'static str,
        /// Its value.
        value: f64,
        /// What it must be.
        expected: &'static str,
    },
    /// A camera of a dolly could not be made.
    Camera {
        /// The view's index along the dolly.
        view: u32,
        /// Why.
        source: CameraError,
    },
    /// An octree could not be built from a scene.
    Build {
        /// The scene's name.
        scene: &'static str,
        /// Why.
        source: BuildError,
    },
    /// A scene of `svo-scenes` could not be made (a sweep's parameter out of the scene's
    /// range).
    Scene {
        /// The scene's name.
        scene: &'static str,
        /// Why (names the scene's parameter).
        source: svo_scenes::SceneError,
    },
    /// A micro-surface of `microsurface-truth` could not be generated.
    HeightField {
        /// The surface's name.
        surface: &'static str,
        /// Why.
        source: microsurface_truth::HeightFieldError,
    },
    /// An image metric could not be computed.
    Metric {
        /// The metric (`"SSIM"`, `"FLIP"`) and the image it compared.
        what: String,
        /// Why.
        source: image_metrics::MetricError,
    },
    /// A frame's pixels do not fill its size (an internal inconsistency, reported rather than
    /// panicking).
    FrameSize {
        /// The frame's `(width, height)`.
        size: (u32, u32),
        /// The number of pixels it holds.
        pixels: usize,
    },
    /// Two frames compared with each other differ in size.
    SizeMismatch {
        /// The reference's `(width, height)`.
        reference: (u32, u32),
        /// The test frame's `(width, height)`.
        test: (u32, u32),
    },
    /// A PNG could not be written.
    Png {
        /// The file.
        path: PathBuf,
        /// Why.
        source: image::ImageError,
    },
    /// The GPU failed or refused: what was being done and wgpu's or the harness's message.
    Gpu {
        /// What was being done (`"uploading the octree"`, …).
        what: &'static str,
        /// The message.
        message: String,
    },
    /// A scene could not be made from its file.
    SceneFile {
        /// The file.
        path: PathBuf,
        /// Why.
        source: svo_scenes::SceneError,
    },
    /// No scene has this name.
    UnknownScene {
        /// The name asked for.
        name: String,
        /// The names there are, comma-separated.
        known: String,
    },
    /// The octree does not fit the adapter's storage bindings.
    Pools(svo_brick::PoolError),
    /// A file could not be written.
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
}

impl fmt::Display for RenderError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RenderError::Setting { field, value, expected } => {
                write!(f, "setting `{field}` = {value} is out of range: it must be {expected}")
            }
            RenderError::Camera { view, source } => write!(f, "the camera of view {view}: {source}"),
            RenderError::Build { scene, source } => write!(f, "building the octree of scene `{scene}`: {source}"),
            RenderError::Scene { scene, source } => write!(f, "making the scene `{scene}`: {source}"),
            RenderError::HeightField { surface, source } => {
                write!(f, "generating the micro-surface `{surface}`: {source}")
            }
            RenderError::Metric { what, source } => write!(f, "{what}: {source}"),
            RenderError::FrameSize { size: (w, h), pixels } => {
                write!(f, "a {w}×{h} frame holds {pixels} pixels")
            }
            RenderError::SizeMismatch { reference: (rw, rh), test: (tw, th) } => {
                write!(f, "the reference frame is {rw}×{rh} px but the test frame is {tw}×{th} px")
            }
            RenderError::Png { path, source } => write!(f, "writing the PNG `{}`: {source}", path.display()),
            RenderError::Io { path, source } => write!(f, "writing `{}`: {source}", path.display()),
            RenderError::Gpu { what, message } => write!(f, "{what} on the GPU: {message}"),
            RenderError::Pools(source) => write!(f, "the octree does not fit the adapter: {source}"),
            RenderError::SceneFile { path, source } => write!(f, "the scene `{}`: {source}", path.display()),
            RenderError::UnknownScene { name, known } => {
                write!(f, "no scene is named `{name}`; the scenes are {known}")
            }
        }
    }
}

impl std::error::Error for RenderError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            RenderError::Camera { source, .. } => Some(source),
            RenderError::Build { source, .. } => Some(source),
            RenderError::Scene { source, .. } => Some(source),
            RenderError::HeightField { source, .. } => Some(source),
            RenderError::Metric { source, .. } => Some(source),
            RenderError::Png { source, .. } => Some(source),
            RenderError::Io { source, .. } => Some(source),
            RenderError::Pools(source) => Some(source),
            RenderError::SceneFile { source, .. } => Some(source),
            RenderError::UnknownScene { .. }
            | RenderError::Gpu { .. }
            | RenderError::Setting { .. }
            | RenderError::FrameSize { .. }
            | RenderError::SizeMismatch { .. } => None,
        }
    }
}

/// `Err(Setting)` unless `ok`.
pub(crate) fn check(ok: bool, field: &'static str, value: f64, expected: &'static str) -> Result<(), RenderError> {
    if ok { Ok(()) } else { Err(RenderError::Setting { field, value, expected }) }
}

/// A [`RenderError::Gpu`] of `what` from any displayable error.
pub(crate) fn gpu_failed(what: &'static str) -> impl FnOnce(gpu_harness::HarnessError) -> RenderError {
    move |e| RenderError::Gpu { what, message: e.to_string() }
}
