//! Height and slope statistics of a height field (the quantities eq. 5 and eq. 6 use).

use glam::DVec2;

use crate::heightfield::HeightField;

/// Statistics measured on a height field's samples.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceStatistics {
    /// Mean vertex height.
    pub mean_height: f64,
    /// Standard deviation `σ_h` of vertex heights.
    pub height_sigma: f64,
    /// Standard deviations `(σ_nx, σ_ny)` of the slopes along x and y: the slopes of the
    /// piecewise-linear surface are exactly the forward differences of the grid.
    pub slope_sigma: DVec2,
    /// Mean of the slopes along x and y (zero for a periodic field, up to rounding).
    pub mean_slope: DVec2,
    /// Standard deviations of the second derivatives `∂²h/∂x²`, `∂²h/∂y²` (central second
    /// differences): the fourth spectral moments along x and y.
    pub curvature_sigma: DVec2,
    /// Excess kurtosis of the heights (0 for a Gaussian): how non-Gaussian the surface is.
    pub height_excess_kurtosis: f64,
    /// Skewness of the heights (0 for a Gaussian).
    pub height_skewness: f64,
}

impl SurfaceStatistics {
    /// Measures `field`.
    pub fn measure(field: &HeightField) -> Self {
        let n = field.size() as i64;
        let count = (n * n) as f64;
        let heights = field.heights();
        let mean_height = heights.iter().sum::<f64>() / count;
        let moment = |k: i32| heights.iter().map(|h| (h - mean_height).powi(k)).sum::<f64>() / count;
        let variance = moment(2);
        let (mut sx, mut sy, mut sxx, mut syy) = (0.0, 0.0, 0.0, 0.0);
        let (mut kxx, mut kyy) = (0.0, 0.0);
        for j in 0..n {
            for i in 0..n {
                let h = field.height(i, j);
                let dx = field.height(i + 1, j) - h;
                let dy = field.height(i, j + 1) - h;
                (sx, sy, sxx, syy) = (sx + dx, sy + dy, sxx + dx * dx, syy + dy * dy);
                let cx = field.height(i + 1, j) - 2.0 * h + field.height(i - 1, j);
                let cy = field.height(i, j + 1) - 2.0 * h + field.height(i, j - 1);
                (kxx, kyy) = (kxx + cx * cx, kyy + cy * cy);
            }
        }
        let curvature_sigma = DVec2::new((kxx / count).sqrt(), (kyy / count).sqrt());
        let mean_slope = DVec2::new(sx / count, sy / count);
        let slope_sigma = DVec2::new(
            (sxx / count - mean_slope.x * mean_slope.x).max(0.0).sqrt(),
            (syy / count - mean_slope.y * mean_slope.y).max(0.0).sqrt(),
        );
        let (skewness, kurtosis) = if variance > 0.0 {
            (moment(3) / variance.powf(1.5), moment(4) / (variance * variance) - 3.0)
        } else {
            (0.0, 0.0)
        };
        Self {
            mean_height,
            height_sigma: variance.sqrt(),
            slope_sigma,
            mean_slope,
            curvature_sigma,
            height_excess_kurtosis: kurtosis,
            height_skewness: skewness,
        }
    }

    /// Rice's spectral-width parameter along x, `α = m0 m4 / m2² = σ_h² σ_κx² / σ_nx⁴ ≥ 1`:
    /// near 1 for a narrow band of wavelengths, 3 for a Gaussian spectrum, large for
    /// broadband (fBm-like) surfaces. `None` for a flat field.
    pub fn spectral_width_x(&self) -> Option<f64> {
        let m2 = self.slope_sigma.x.powi(2);
        (m2 > 0.0).then(|| self.height_sigma.powi(2) * self.curvature_sigma.x.powi(2) / (m2 * m2))
    }

    /// The slope standard deviation in the azimuth of `direction` (its xy projection):
    /// `σ_n(v)² = σ_nx² cos²φ + σ_ny² sin²φ` (slopes along x and y uncorrelated, as for the
    /// generators of this crate). For a direction along the normal, the mean of both.
    pub fn projected_slope_sigma(&self, direction: glam::DVec3) -> f64 {
        let horizontal = direction.truncate();
        let length = horizontal.length();
        if length == 0.0 {
            return ((self.slope_sigma.x.powi(2) + self.slope_sigma.y.powi(2)) / 2.0).sqrt();
        }
        let (c, s) = (horizontal.x / length, horizontal.y / length);
        (self.slope_sigma.x.powi(2) * c * c + self.slope_sigma.y.powi(2) * s * s).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tilted_sawtooth_has_the_slopes_it_was_built_with() {
        // Heights alternate 0, 1 along x: forward differences ±1, zero along y.
        let heights = (0..16).map(|k| f64::from((k % 4) % 2)).collect();
        let field = HeightField::new(4, heights).unwrap();
        let stats = SurfaceStatistics::measure(&field);
        assert!((stats.slope_sigma.x - 1.0).abs() < 1e-12);
        assert_eq!(stats.slope_sigma.y, 0.0);
        assert!((stats.height_sigma - 0.5).abs() < 1e-12);
        assert!((stats.projected_slope_sigma(glam::DVec3::new(1.0, 1.0, 1.0)) - 0.5_f64.sqrt()).abs() < 1e-12);
    }
}
