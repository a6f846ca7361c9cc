//! Height maps from PNG files and their adaptive triangulation: a Delaunay triangulation
//! (`spade`) that keeps only the samples needed to stay within a height tolerance.

use std::fmt;
use std::path::{Path, PathBuf};

use ddm_compress::Triangle;
use glam::Vec3;
use spade::handles::FixedFaceHandle;
use spade::{DelaunayTriangulation, HasPosition, InsertionError, Point2, PositionInTriangulation, Triangulation};

use crate::HeightField;

/// Why a height map could not be read.
#[derive(Debug)]
pub enum HeightMapError {
    /// The file could not be opened or read.
    Read {
        /// The file.
        path: PathBuf,
        /// The reader's message.
        message: String,
    },
    /// The file is not a valid PNG image.
    Decode {
        /// The file.
        path: PathBuf,
        /// The decoder's message.
        message: String,
    },
    /// The image has fewer than 2 × 2 pixels (no cell).
    TooSmall {
        /// The file.
        path: PathBuf,
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
    },
    /// The height scale is not positive and finite.
    BadScale(f32),
}

impl fmt::Display for HeightMapError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Read { path, message } => write!(f, "cannot read height map {}: {message}", path.display()),
            Self::Decode { path, message } => write!(f, "height map {} is not a valid PNG: {message}", path.display()),
            Self::TooSmall { path, width, height } => {
                write!(f, "height map {} has {width} × {height} pixels, at least 2 × 2 are needed", path.display())
            }
            Self::BadScale(scale) => write!(f, "height scale {scale} is not positive and finite"),
        }
    }
}

impl std::error::Error for HeightMapError {}

impl HeightField {
    /// Reads a PNG height map: pixel `(x, y)` (grey level, colour images converted to
    /// luminance, 8 or 16 bits) becomes the corner `(x, y)` at height `level · height_scale`
    /// with `level ∈ [0, 1]`; an `w × h` image gives `(w − 1) × (h − 1)` cells.
    pub fn from_png(path: &Path, height_scale: f32) -> Result<Self, HeightMapError> {
        if !(height_scale > 0.0 && height_scale.is_finite()) {
            return Err(HeightMapError::BadScale(height_scale));
        }
        let bytes =
            std::fs::read(path).map_err(|e| HeightMapError::Read { path: path.to_owned(), message: e.to_string() })?;
        let image = image::load_from_memory_with_format(&bytes, image::ImageFormat::Png)
            .map_err(|e| HeightMapError::Decode { path: path.to_owned(), message: e.to_string() })?
            .into_luma16();
        let (width, height) = image.dimensions();
        if width < 2 || height < 2 {
            return Err(HeightMapError::TooSmall { path: path.to_owned(), width, height });
        }
        let scale = height_scale / f32::from(u16::MAX);
        Ok(Self {
            width: width - 1,
            height: height - 1,
            heights: image.pixels().map(|p| f32::from(p.0[0]) * scale).collect(),
        })
    }

    /// An adaptive triangulation within `tolerance` of the corner heights: see
    /// [`AdaptiveMesh`]. `None` for a non-positive or non-finite tolerance or an empty field.
    pub fn adaptive_triangles(&self, tolerance: f32) -> Option<AdaptiveMesh> {
        if !(tolerance > 0.0 && tolerance.is_finite()) || self.width == 0 || self.height == 0 {
            return None;
        }
        adaptive(self, tolerance).ok()
    }
}

/// A height field triangulated adaptively (Garland & Heckbert's greedy insertion, in
/// rounds): the border samples are all kept, so opposite borders of a periodic height
/// map stay crack-free when tiles repeat; then, round after round, every triangle whose
/// worst sample is farther than the tolerance from it gets that sample inserted into the
/// Delaunay triangulation, until every sample is within the tolerance.
#[derive(Clone, Debug, PartialEq)]
pub struct AdaptiveMesh {
    /// The triangles, counter-clockwise seen from above, in the field's cell units.
    pub triangles: Vec<Triangle>,
    /// Samples kept as vertices.
    pub vertices: usize,
    /// Largest `|mesh height − sample height|` over all samples (≤ the tolerance).
    pub max_error: f32,
}

/// A triangulation vertex: a sample position and its height.
#[derive(Clone, Copy, Debug)]
struct Sample {
    position: Point2<f64>,
    height: f64,
}

impl HasPosition for Sample {
    type Scalar = f64;
    fn position(&self) -> Point2<f64> {
        self.position
    }
}

/// The mesh height at `point`, or `None` outside the triangulation.
fn interpolate(
    triangulation: &DelaunayTriangulation<Sample>,
    point: Point2<f64>,
) -> Option<(f64, Option<FixedFaceHandle<spade::handles::InnerTag>>)> {
    match triangulation.locate(point) {
        PositionInTriangulation::OnVertex(v) => Some((triangulation.vertex(v).data().height, None)),
        PositionInTriangulation::OnEdge(e) => {
            let [a, b] = triangulation.directed_edge(e).vertices().map(|v| *v.data());
            let (ab, ap) = (
                (b.position.x - a.position.x, b.position.y - a.position.y),
                (point.x - a.position.x, point.y - a.position.y),
            );
            let t = (ab.0 * ap.0 + ab.1 * ap.1) / (ab.0 * ab.0 + ab.1 * ab.1);
            Some((a.height + t * (b.height - a.height), None))
        }
        PositionInTriangulation::OnFace(f) => {
            let [a, b, c] = triangulation.face(f).vertices().map(|v| *v.data());
            let det = (b.position.x - a.position.x) * (c.position.y - a.position.y)
                - (c.position.x - a.position.x) * (b.position.y - a.position.y);
            let wb = ((point.x - a.position.x) * (c.position.y - a.position.y)
                - (c.position.x - a.position.x) * (point.y - a.position.y))
                / det;
            let wc = ((b.position.x - a.position.x) * (point.y - a.position.y)
                - (point.x - a.position.x) * (b.position.y - a.position.y))
                / det;
            Some((a.height + wb * (b.height - a.height) + wc * (c.height - a.height), Some(f)))
        }
        _ => None,
    }
}

fn adaptive(field: &HeightField, tolerance: f32) -> Result<AdaptiveMesh, InsertionError> {
    let (w, h) = (field.width, field.height);
    let sample = |x: u32, y: u32| Sample {
        position: Point2::new(f64::from(x), f64::from(y)),
        height: f64::from(field.corner(x, y)),
    };
    let mut triangulation = DelaunayTriangulation::<Sample>::new();
    let mut inserted = vec![false; ((w + 1) * (h + 1)) as usize];
    for y in 0..=h {
        for x in 0..=w {
            if x == 0 || y == 0 || x == w || y == h {
                triangulation.insert(sample(x, y))?;
                inserted[(x + (w + 1) * y) as usize] = true;
            }
        }
    }
    let tolerance = f64::from(tolerance);
    loop {
        // The worst sample of each face, or of each edge's neighbourhood for samples on
        // edges (inserted one per round).
        let mut worst: std::collections::HashMap<Option<FixedFaceHandle<spade::handles::InnerTag>>, (f64, u32, u32)> =
            std::collections::HashMap::new();
        for y in 1..h {
            for x in 1..w {
                if inserted[(x + (w + 1) * y) as usize] {
                    continue;
                }
                let s = sample(x, y);
                let Some((height, face)) = interpolate(&triangulation, s.position) else { continue };
                let error = (height - s.height).abs();
                if error > tolerance {
                    let entry = worst.entry(face).or_insert((0.0, x, y));
                    if error > entry.0 {
                        *entry = (error, x, y);
                    }
                }
            }
        }
        if worst.is_empty() {
            break;
        }
        for &(_, x, y) in worst.values() {
            triangulation.insert(sample(x, y))?;
            inserted[(x + (w + 1) * y) as usize] = true;
        }
    }
    let mut max_error = 0.0_f64;
    for y in 0..=h {
        for x in 0..=w {
            let s = sample(x, y);
            if let Some((height, _)) = interpolate(&triangulation, s.position) {
                max_error = max_error.max((height - s.height).abs());
            }
        }
    }
    let triangles = triangulation
        .inner_faces()
        .map(|face| {
            Triangle(face.vertices().map(|v| {
                let s = v.data();
                Vec3::new(s.position.x as f32, s.position.y as f32, s.height as f32)
            }))
        })
        .collect();
    Ok(AdaptiveMesh { triangles, vertices: triangulation.num_vertices(), max_error: max_error as f32 })
}
