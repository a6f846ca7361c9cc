//! Why a surface could not be made: the one error type of the crate, naming the parameter,
//! the file or the mesh at fault.

use std::fmt;
use std::path::PathBuf;

use grain_mesh::{EdgeReport, ObjError};

/// Why a surface could not be made.
#[derive(Debug)]
pub enum SceneError {
    /// A parameter is out of its range.
    InvalidParameter {
        /// What the parameter belongs to (`"Sphere"`, `"Fbm"`, …).
        owner: &'static str,
        /// The parameter's name.
        field: &'static str,
        /// Its value, as printed.
        value: String,
        /// What it must satisfy.
        requirement: &'static str,
    },
    /// The displacement of a displaced sphere can reach its centre: the bound of `|D|`
    /// (`amplitude · Σ gainᵏ`) is not below the radius.
    DisplacementTooLarge {
        /// The bound of the displacement's magnitude.
        amplitude_bound: f32,
        /// The base sphere's radius.
        radius: f32,
    },
    /// A height grid is smaller than 2 × 2 or does not hold `size²` values.
    HeightCount {
        /// The side of the grid.
        size: usize,
        /// How many heights were given.
        len: usize,
    },
    /// A height is NaN or infinite.
    NonFiniteHeight {
        /// Its row-major index.
        index: usize,
        /// Its value.
        value: f32,
    },
    /// A height map image could not be used.
    Image {
        /// The file.
        path: PathBuf,
        /// What went wrong with it.
        message: String,
    },
    /// An OBJ file could not be loaded (the error names the file).
    Obj(ObjError),
    /// A mesh is not closed and consistently oriented, so its inside is undefined.
    OpenMesh {
        /// The file it came from, if any.
        path: Option<PathBuf>,
        /// How its edges pair up.
        report: EdgeReport,
    },
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneError::InvalidParameter { owner, field, value, requirement } => {
                write!(f, "{owner}.{field} = {value}: must be {requirement}")
            }
            SceneError::DisplacementTooLarge { amplitude_bound, radius } => write!(
                f,
                "the displacement can reach {amplitude_bound}, not below the base sphere's radius {radius} \
                 (lower Fbm.amplitude or the gain)"
            ),
            SceneError::HeightCount { size, len } => {
                write!(f, "height map: {len} heights for a {size}×{size} grid (a grid of at least 2×2 is needed)")
            }
            SceneError::NonFiniteHeight { index, value } => {
                write!(f, "height map: height {index} is {value}, not finite")
            }
            SceneError::Image { path, message } => write!(f, "height map {}: {message}", path.display()),
            SceneError::Obj(error) => error.fmt(f),
            SceneError::OpenMesh { path, report } => {
                match path {
                    Some(path) => write!(f, "mesh {}", path.display())?,
                    None => write!(f, "mesh")?,
                }
                write!(
                    f,
                    " is not closed and oriented: {} boundary, {} non-manifold and {} inconsistently oriented \
                     edges, {} degenerate triangles",
                    report.boundary_edges,
                    report.non_manifold_edges,
                    report.inconsistently_oriented_edges,
                    report.degenerate_triangles
                )
            }
        }
    }
}

impl std::error::Error for SceneError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            SceneError::Obj(error) => Some(error),
            _ => None,
        }
    }
}

impl From<ObjError> for SceneError {
    fn from(error: ObjError) -> Self {
        SceneError::Obj(error)
    }
}

/// `Err(InvalidParameter)` unless `value` is finite and positive.
pub(crate) fn positive(owner: &'static str, field: &'static str, value: f32) -> Result<f32, SceneError> {
    check(owner, field, value, value.is_finite() && value > 0.0, "finite and positive")
}

/// `Err(InvalidParameter)` naming `requirement` unless `holds`.
pub(crate) fn check<T: fmt::Debug>(
    owner: &'static str,
    field: &'static str,
    value: T,
    holds: bool,
    requirement: &'static str,
) -> Result<T, SceneError> {
    if holds {
        Ok(value)
    } else {
        Err(SceneError::InvalidParameter { owner, field, value: format!("{value:?}"), requirement })
    }
}

/// `Err(InvalidParameter)` unless every component of `value` is finite.
pub(crate) fn finite(owner: &'static str, field: &'static str, value: glam::Vec3) -> Result<glam::Vec3, SceneError> {
    check(owner, field, value, value.is_finite(), "finite")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_the_field_and_the_requirement() {
        let error = positive("Sphere", "radius", -1.0).unwrap_err();
        assert_eq!(error.to_string(), "Sphere.radius = -1.0: must be finite and positive");
        let error = SceneError::OpenMesh {
            path: Some("/tmp/x.obj".into()),
            report: EdgeReport { boundary_edges: 3, ..EdgeReport::default() },
        };
        let message = error.to_string();
        assert!(message.contains("/tmp/x.obj") && message.contains("3 boundary"), "{message}");
    }
}
