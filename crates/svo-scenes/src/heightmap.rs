//! A periodic height map `z = H(x, y)` ([`HeightMapSurface`]), interpolated piecewise
//! linearly on triangles split along each cell's diagonal (as
//! `microsurface_truth::HeightField`), with exact surface samples at its grid vertices.

use std::path::Path;

use glam::{Vec2, Vec3};
use svo_brick::{ATTRIBUTE_CHANNELS, Cell, SurfaceSample, SurfaceSource};

use crate::attribute::Attribute;
use crate::error::{SceneError, check, positive};

/// The surface `z = H(x, y)` of a periodic `size × size` grid of heights.
///
/// Vertex `(i, j)` lies at `(i · texel, j · texel, H_ij)` and the grid repeats with period
/// `size · texel` in x and y. Cell `(i, j)` is split along its diagonal from `(i, j)` to
/// `(i + 1, j + 1)` into two triangles, on which `H` is linear.
///
/// **Distance.** `(z − H(x, y))/√(1 + G²)`, with `G` the largest slope `|∇H|` of the
/// triangles ([`max_slope`](Self::max_slope)): `H` is `G`-Lipschitz, so the gradient
/// `(−∂H/∂x, −∂H/∂y, 1)` of `z − H` has length at most `√(1 + G²)` and the distance is
/// 1-Lipschitz. The gradient is that of the triangle holding `(x, y)`.
///
/// **Samples.** [`surface_samples`](SurfaceSource::surface_samples) returns one sample per
/// grid vertex inside the cell, over every period: position `(x_i, y_j, H_ij)`, normal
/// `normalize(−dx, −dy, 1)` with `dx`, `dy` the *forward* differences divided by `texel`
/// (the slopes `microsurface_truth::SurfaceStatistics` measures), area
/// `texel² √(1 + dx² + dy²)`, so that `area · n_z = texel²` is the projected area. The
/// `spacing` argument is ignored: the grid sets the sampling. A non-finite cell gets no
/// samples.
#[derive(Clone, Debug)]
pub struct HeightMapSurface {
    size: usize,
    heights: Vec<f32>,
    texel: f32,
    max_slope: f32,
    lipschitz: f32,
    attribute: Attribute<f32>,
}

impl HeightMapSurface {
    /// A height map from row-major `heights` (`heights[j · size + i]` at vertex `(i, j)`),
    /// multiplied by `height_scale`; `texel` is the grid step in world units. `attribute`
    /// is a function of the height (world units) or a constant.
    pub fn new(
        size: usize,
        heights: Vec<f32>,
        texel: f32,
        height_scale: f32,
        attribute: Attribute<f32>,
    ) -> Result<Self, SceneError> {
        if size < 2 || heights.len() != size.saturating_mul(size) {
            return Err(SceneError::HeightCount { size, len: heights.len() });
        }
        if let Some((index, &value)) = heights.iter().enumerate().find(|(_, h)| !h.is_finite()) {
            return Err(SceneError::NonFiniteHeight { index, value });
        }
        let texel = positive("HeightMapSurface", "texel", texel)?;
        let height_scale = check(
            "HeightMapSurface",
            "height_scale",
            height_scale,
            height_scale.is_finite() && height_scale >= 0.0,
            "finite and non-negative",
        )?;
        let heights: Vec<f32> = heights.into_iter().map(|h| h * height_scale).collect();
        if let Some((index, &value)) = heights.iter().enumerate().find(|(_, h)| !h.is_finite()) {
            return Err(SceneError::NonFiniteHeight { index, value });
        }
        let mut surface = HeightMapSurface { size, heights, texel, max_slope: 0.0, lipschitz: 1.0, attribute };
        let n = size as i64;
        let mut max_squared = 0.0f32;
        for j in 0..n {
            for i in 0..n {
                let [lower, upper] = surface.cell_slopes(i, j);
                max_squared = max_squared.max(lower.length_squared()).max(upper.length_squared());
            }
        }
        surface.max_slope = max_squared.sqrt();
        surface.lipschitz = (1.0 + max_squared).sqrt();
        Ok(surface)
    }

    /// A height map from a square 8- or 16-bit grayscale PNG: black = 0, white = `height`
    /// world units, one pixel per vertex, `texel` world units apart, treated as periodic.
    /// Errors name the file.
    pub fn from_png(
        path: impl AsRef<Path>,
        texel: f32,
        height: f32,
        attribute: Attribute<f32>,
    ) -> Result<Self, SceneError> {
        let path = path.as_ref();
        let error = |message: String| SceneError::Image { path: path.to_path_buf(), message };
        let image = image::open(path).map_err(|e| error(e.to_string()))?;
        let (width, rows) = (image.width(), image.height());
        let values: Vec<f32> = match image {
            image::DynamicImage::ImageLuma8(pixels) => pixels.pixels().map(|p| f32::from(p.0[0]) / 255.0).collect(),
            image::DynamicImage::ImageLuma16(pixels) => pixels.pixels().map(|p| f32::from(p.0[0]) / 65535.0).collect(),
            other => {
                return Err(error(format!("{:?} pixels: an 8- or 16-bit grayscale image is needed", other.color())));
            }
        };
        if width != rows || width < 2 {
            return Err(error(format!("the image is {width}×{rows}; a square image of at least 2×2 is needed")));
        }
        HeightMapSurface::new(width as usize, values, texel, height, attribute)
    }

    /// The side of the grid in vertices.
    pub fn size(&self) -> usize {
        self.size
    }

    /// The grid step (world units).
    pub fn texel(&self) -> f32 {
        self.texel
    }

    /// The period `size · texel` in x and y.
    pub fn period(&self) -> f32 {
        self.size as f32 * self.texel
    }

    /// The vertex heights in world units, row-major.
    pub fn heights(&self) -> &[f32] {
        &self.heights
    }

    /// The height of vertex `(i, j)`, indices taken modulo the period.
    pub fn height(&self, i: i64, j: i64) -> f32 {
        let n = self.size as i64;
        self.heights[(j.rem_euclid(n) * n + i.rem_euclid(n)) as usize]
    }

    /// `G`, the largest slope `|∇H|` of the triangles.
    pub fn max_slope(&self) -> f32 {
        self.max_slope
    }

    /// `√(1 + G²)`: the distance is `z − H` divided by it.
    pub fn lipschitz_factor(&self) -> f32 {
        self.lipschitz
    }

    /// The gradients `∇H` of cell `(i, j)`'s lower (`v ≤ u`) and upper triangles.
    fn cell_slopes(&self, i: i64, j: i64) -> [Vec2; 2] {
        let (h00, h10) = (self.height(i, j), self.height(i + 1, j));
        let (h01, h11) = (self.height(i, j + 1), self.height(i + 1, j + 1));
        [Vec2::new(h10 - h00, h11 - h10) / self.texel, Vec2::new(h11 - h01, h01 - h00) / self.texel]
    }

    /// `H(x, y)` and `∇H` there (of the triangle holding `(x, y)`).
    pub fn interpolate(&self, x: f32, y: f32) -> (f32, Vec2) {
        let (u, v) = (x / self.texel, y / self.texel);
        let (fi, fj) = (u.floor(), v.floor());
        let (fu, fv) = (u - fi, v - fj);
        let (i, j) = (fi as i64, fj as i64);
        let h00 = self.height(i, j);
        let [lower, upper] = self.cell_slopes(i, j);
        let slope = if fv <= fu { lower } else { upper };
        (h00 + slope.x * fu * self.texel + slope.y * fv * self.texel, slope)
    }
}

impl SurfaceSource for HeightMapSurface {
    fn distance(&self, p: Vec3) -> f32 {
        (p.z - self.interpolate(p.x, p.y).0) / self.lipschitz
    }

    fn gradient(&self, p: Vec3) -> Vec3 {
        let (_, slope) = self.interpolate(p.x, p.y);
        Vec3::new(-slope.x, -slope.y, 1.0) / self.lipschitz
    }

    /// The attribute of the height `H(x.x, x.y)` under `x`.
    fn attribute(&self, x: Vec3) -> [f32; ATTRIBUTE_CHANNELS] {
        self.attribute.eval(self.interpolate(x.x, x.y).0)
    }

    /// One exact sample per grid vertex in `cell` (see [`HeightMapSurface`]); `spacing` is
    /// ignored.
    fn surface_samples(&self, cell: Cell, _spacing: f32, out: &mut Vec<SurfaceSample>) {
        if !(cell.min.is_finite() && cell.max.is_finite()) {
            return;
        }
        let range = |lo: f32, hi: f32| (lo / self.texel).floor() as i64..=(hi / self.texel).ceil() as i64;
        let area = self.texel * self.texel;
        for big_j in range(cell.min.y, cell.max.y) {
            for big_i in range(cell.min.x, cell.max.x) {
                let h = self.height(big_i, big_j);
                let position = Vec3::new(big_i as f32 * self.texel, big_j as f32 * self.texel, h);
                if !cell.contains(position) {
                    continue;
                }
                let dx = (self.height(big_i + 1, big_j) - h) / self.texel;
                let dy = (self.height(big_i, big_j + 1) - h) / self.texel;
                let stretch = (1.0 + dx * dx + dy * dy).sqrt();
                out.push(SurfaceSample {
                    position,
                    normal: Vec3::new(-dx, -dy, 1.0) / stretch,
                    area: area * stretch,
                    attribute: self.attribute.eval(h),
                });
            }
        }
    }
}

#[cfg(test)]
mod tests;
