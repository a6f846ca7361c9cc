//! Periodic height fields, interpolated piecewise linearly.

use std::fmt;
use std::path::Path;

use crate::max_pyramid::{MaxPyramid, wrap};

/// A periodic `size × size` grid of heights in cell units. Vertex `(i, j)` is at
/// `(i, j, height(i, j))`; cell `(i, j)` is split along its diagonal from `(i, j)` to
/// `(i + 1, j + 1)` into two triangles.
#[derive(Clone, Debug, PartialEq)]
pub struct HeightField {
    size: usize,
    heights: Vec<f64>,
    pyramid: MaxPyramid,
    max_height: f64,
    min_height: f64,
}

/// Why a height field could not be made.
#[derive(Debug)]
pub enum HeightFieldError {
    /// The grid is smaller than 2 × 2 or the data does not have `size²` values.
    BadSize(String),
    /// A height is NaN or infinite.
    NotFinite,
    /// A height map image could not be read.
    Image {
        /// The file.
        path: String,
        /// What went wrong.
        message: String,
    },
}

impl fmt::Display for HeightFieldError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            HeightFieldError::BadSize(m) => write!(f, "bad height field size: {m}"),
            HeightFieldError::NotFinite => write!(f, "height field holds a NaN or infinite height"),
            HeightFieldError::Image { path, message } => write!(f, "cannot read height map {path}: {message}"),
        }
    }
}

impl std::error::Error for HeightFieldError {}

impl HeightField {
    /// A height field from row-major heights (`heights[j * size + i]` at `(i, j)`).
    pub fn new(size: usize, heights: Vec<f64>) -> Result<Self, HeightFieldError> {
        if size < 2 || heights.len() != size * size {
            return Err(HeightFieldError::BadSize(format!("{} values for a {size}×{size} grid", heights.len())));
        }
        if heights.iter().any(|h| !h.is_finite()) {
            return Err(HeightFieldError::NotFinite);
        }
        let height = |i: usize, j: usize| heights[(j % size) * size + i % size];
        let cell_max = (0..size * size)
            .map(|k| {
                let (i, j) = (k % size, k / size);
                height(i, j).max(height(i + 1, j)).max(height(i, j + 1)).max(height(i + 1, j + 1))
            })
            .collect();
        let max_height = heights.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let min_height = heights.iter().copied().fold(f64::INFINITY, f64::min);
        Ok(Self { size, pyramid: MaxPyramid::new(size, cell_max), heights, max_height, min_height })
    }

    /// A height field from a square grayscale PNG (or any format `image` reads with its
    /// enabled features), white = `height_range` cells high, black = 0. The image is
    /// treated as periodic.
    pub fn from_image(path: &Path, height_range: f64) -> Result<Self, HeightFieldError> {
        let error = |message: String| HeightFieldError::Image { path: path.display().to_string(), message };
        let image = image::open(path).map_err(|e| error(e.to_string()))?.into_luma16();
        let (w, h) = image.dimensions();
        if w != h {
            return Err(error(format!("the image is {w}×{h}; a square image is needed")));
        }
        let heights = image.pixels().map(|p| f64::from(p.0[0]) / 65535.0 * height_range).collect();
        Self::new(w as usize, heights)
    }

    /// Side of the grid in cells (the period).
    pub fn size(&self) -> usize {
        self.size
    }

    /// The height at vertex `(i, j)`, indices taken modulo the period.
    pub fn height(&self, i: i64, j: i64) -> f64 {
        self.heights[wrap(j, self.size) * self.size + wrap(i, self.size)]
    }

    /// The highest of the four corner heights of cell `(i, j)`.
    pub fn cell_max(&self, i: i64, j: i64) -> f64 {
        self.pyramid.block_max(0, i, j)
    }

    /// The highest corners of its cells, per block of `2^L × 2^L` cells.
    pub(crate) fn pyramid(&self) -> &MaxPyramid {
        &self.pyramid
    }

    /// All vertex heights, row-major.
    pub fn heights(&self) -> &[f64] {
        &self.heights
    }

    /// Highest vertex.
    pub fn max_height(&self) -> f64 {
        self.max_height
    }

    /// Lowest vertex.
    pub fn min_height(&self) -> f64 {
        self.min_height
    }

    /// The interpolated height at `(x, y)`.
    pub fn interpolate(&self, x: f64, y: f64) -> f64 {
        let (i, j) = (x.floor(), y.floor());
        let (u, v) = (x - i, y - j);
        let (i, j) = (i as i64, j as i64);
        let (h00, h10, h01, h11) =
            (self.height(i, j), self.height(i + 1, j), self.height(i, j + 1), self.height(i + 1, j + 1));
        if v <= u { h00 + (h10 - h00) * u + (h11 - h10) * v } else { h00 + (h11 - h01) * u + (h01 - h00) * v }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_bad_input() {
        assert!(matches!(HeightField::new(1, vec![0.0]), Err(HeightFieldError::BadSize(_))));
        assert!(matches!(HeightField::new(2, vec![0.0; 3]), Err(HeightFieldError::BadSize(_))));
        assert!(matches!(HeightField::new(2, vec![0.0, f64::NAN, 0.0, 0.0]), Err(HeightFieldError::NotFinite)));
        let missing = HeightField::from_image(Path::new("/nonexistent/height.png"), 1.0).unwrap_err();
        assert!(missing.to_string().contains("/nonexistent/height.png"));
    }

    #[test]
    fn interpolation_is_periodic_and_exact_at_vertices() {
        let field = HeightField::new(2, vec![0.0, 1.0, 2.0, 3.0]).unwrap();
        assert_eq!(field.interpolate(1.0, 1.0), 3.0);
        assert_eq!(field.interpolate(3.0, 1.0), 3.0);
        assert_eq!(field.interpolate(0.5, 0.0), 0.5);
        assert_eq!(field.cell_max(0, 0), 3.0);
    }
}
