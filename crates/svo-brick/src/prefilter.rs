//! The statistics of a coarse voxel (§5.2, "Pre-computation"): `σh²`, `σn²`, `ā` and `a_s`
//! as *surface* statistics of the finest surface samples in the voxel's footprint.
//!
//! The text computes them "with the usual statistic formulas … as an integral in the
//! deepest level over the corresponding neighbourhood", without saying over what measure.
//! Smith's model (eqs. 4–6, H3) describes a surface by the distribution of its heights and
//! slopes *over the macroscopic plane*, so the measure here is projected area: sample `i`
//! (area `Aᵢ`, normal `nᵢ`) weighs `wᵢ = Aᵢ |nᵢ · n̂|` with `n̂ = n̄ / |n̄|`.
//!
//! - Micro-heights: the signed distance of `xᵢ` above the voxel's plane,
//!   `hᵢ = (h̄ + n̄ · (xᵢ − c)) / |n̄|`; `σh²` is their weighted variance.
//! - Slopes: `nᵢ` in an orthonormal frame `(t₁, t₂, n̂)` has the height-field slopes
//!   `(−nᵢ·t₁, −nᵢ·t₂) / (nᵢ·n̂)`; `σn²` is the mean of the two weighted variances (the
//!   isotropic case). Samples facing away from `n̂` (`nᵢ·n̂ ≤ 1/64`, slopes beyond 64) count
//!   for the heights and attributes but not for the slopes.
//! - `ā = Σ wᵢ aᵢ / Σ wᵢ` and `a_s = Σ wᵢ s(hᵢ − h̄ᵢ)(aᵢ − ā) / Σ wᵢ s²(hᵢ − h̄ᵢ)` with
//!   `s = 2g − 1`, `g` from eq. 5 at this voxel's `σh` (H5bis; `h̄ᵢ` the weighted mean of the
//!   `hᵢ`, so that `s` is centred); `a_s = 0` where `σh = 0`. A deviation below `10⁻⁶`
//!   finest voxels is the rounding of a flat surface and counts as 0.
//!
//! The literal alternative, the variance of the signed distance over the voxel's volume
//! ([`HeightVariance::DistanceVolume`]), counts the distance ramp across the cell as
//! roughness (`S²/12` for a flat plane along an axis); it is kept as a negative control.

use glam::{DVec3, Vec3};

use crate::descriptor::ATTRIBUTE_CHANNELS;
use crate::surface::SurfaceSample;

/// Which quantity `σh²` measures.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum HeightVariance {
    /// The variance of the micro-heights of the surface about the voxel's plane (the
    /// default; see the module documentation).
    #[default]
    SurfaceHeights,
    /// The variance of the signed distance over the voxel's volume: the literal reading of
    /// "the variance of the distance field", wrong for a flat surface (a negative control).
    DistanceVolume,
}

/// A voxel's surface statistics.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SurfaceStatistics {
    /// `σh²`.
    pub height_variance: f32,
    /// `σn²` (isotropic).
    pub slope_variance: f32,
    /// `ā`.
    pub attribute: [f32; ATTRIBUTE_CHANNELS],
    /// `a_s`.
    pub correlation: [f32; ATTRIBUTE_CHANNELS],
    /// `Σ wᵢ`, the projected area the statistics are over.
    pub weight: f32,
}

/// `(t₁, t₂)` completing the unit `n` to an orthonormal frame (Duff et al. 2017).
pub(crate) fn tangent_frame(n: DVec3) -> (DVec3, DVec3) {
    let sign = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (DVec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x), DVec3::new(b, sign + n.y * n.y * a, -n.y))
}

/// The statistics of `samples` (all in the voxel's footprint) for the voxel of centre
/// `centre`, distance `distance` and normal `normal` (finest-voxel units); `None` when the
/// samples have no projected area.
pub fn surface_statistics(
    samples: &[SurfaceSample],
    centre: Vec3,
    distance: f32,
    normal: Vec3,
) -> Option<SurfaceStatistics> {
    let length = f64::from(normal.length());
    let (n_hat, plane_scale) = if length > 1e-6 {
        (normal.as_dvec3() / length, 1.0 / length)
    } else {
        // A vanishing mean gradient (a medial point): the samples' mean normal instead.
        let mean = samples.iter().fold(DVec3::ZERO, |m, s| m + s.normal.as_dvec3() * f64::from(s.area));
        (mean.try_normalize()?, 1.0)
    };
    let (t1, t2) = tangent_frame(n_hat);
    let c = centre.as_dvec3();
    let h0 = f64::from(distance);
    let n_bar = if length > 1e-6 { normal.as_dvec3() } else { n_hat };
    let height = |s: &SurfaceSample| (h0 + n_bar.dot(s.position.as_dvec3() - c)) * plane_scale;
    let weight = |s: &SurfaceSample| f64::from(s.area) * s.normal.as_dvec3().dot(n_hat).abs();

    let (mut w_sum, mut h_sum, mut h2_sum) = (0.0, 0.0, 0.0);
    let mut a_sum = [0.0_f64; ATTRIBUTE_CHANNELS];
    let (mut ws, mut sx, mut sy, mut sxx, mut syy) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for s in samples {
        let w = weight(s);
        if w.is_nan() || w <= 0.0 {
            continue;
        }
        let h = height(s);
        w_sum += w;
        h_sum += w * h;
        h2_sum += w * h * h;
        for (sum, a) in a_sum.iter_mut().zip(s.attribute) {
            *sum += w * f64::from(a);
        }
        let n = s.normal.as_dvec3();
        let up = n.dot(n_hat);
        if up > 1.0 / 64.0 {
            let (x, y) = (-n.dot(t1) / up, -n.dot(t2) / up);
            ws += w;
            sx += w * x;
            sy += w * y;
            sxx += w * x * x;
            syy += w * y * y;
        }
    }
    if w_sum.is_nan() || w_sum <= 0.0 {
        return None;
    }
    let mean_height = h_sum / w_sum;
    // Below 10⁻⁶ finest voxels the deviation is rounding of a flat surface: zero.
    let height_variance = (h2_sum / w_sum - mean_height * mean_height).max(0.0);
    let height_variance = if height_variance < 1e-12 { 0.0 } else { height_variance };
    let slope_variance = if ws > 0.0 {
        let (mx, my) = (sx / ws, sy / ws);
        0.5 * ((sxx / ws - mx * mx).max(0.0) + (syy / ws - my * my).max(0.0))
    } else {
        0.0
    };
    let attribute = a_sum.map(|a| a / w_sum);
    let mut correlation = [0.0_f32; ATTRIBUTE_CHANNELS];
    let sigma = libm::sqrt(height_variance) as f32;
    if sigma > 0.0 {
        let (mut num, mut den) = ([0.0_f64; ATTRIBUTE_CHANNELS], 0.0_f64);
        for s in samples {
            let w = weight(s);
            if w.is_nan() || w <= 0.0 {
                continue;
            }
            let g = smith_micro::height_cdf((height(s) - mean_height) as f32, sigma).unwrap_or(0.5);
            let shape = 2.0 * f64::from(g) - 1.0;
            den += w * shape * shape;
            for c in 0..ATTRIBUTE_CHANNELS {
                num[c] += w * shape * (f64::from(s.attribute[c]) - attribute[c]);
            }
        }
        if den > 0.0 {
            correlation = num.map(|x| (x / den) as f32);
        }
    }
    Some(SurfaceStatistics {
        height_variance: height_variance as f32,
        slope_variance: slope_variance as f32,
        attribute: attribute.map(|a| a as f32),
        correlation,
        weight: w_sum as f32,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(position: Vec3, normal: Vec3, attribute: f32) -> SurfaceSample {
        SurfaceSample { position, normal: normal.normalize(), area: 1.0, attribute: [attribute; 3] }
    }

    #[test]
    fn a_flat_tilted_plane_has_no_roughness() {
        let n = Vec3::new(0.3, -0.2, 1.0).normalize();
        let samples: alloc::vec::Vec<_> = (0..64)
            .map(|k| {
                let (i, j) = ((k % 8) as f32 - 3.5, (k / 8) as f32 - 3.5);
                let (t1, t2) = tangent_frame(n.as_dvec3());
                let p = t1.as_vec3() * i * 0.5 + t2.as_vec3() * j * 0.5 + n * 0.25;
                sample(p, n, 0.4)
            })
            .collect();
        let stats = surface_statistics(&samples, Vec3::ZERO, -0.25, n).unwrap();
        assert!(stats.height_variance < 1e-10, "{stats:?}");
        assert!(stats.slope_variance < 1e-10);
        assert!((stats.attribute[0] - 0.4).abs() < 1e-6);
        assert_eq!(stats.correlation, [0.0; 3]);
    }

    #[test]
    fn a_two_level_surface_correlates_its_colour_with_height() {
        // Half the samples at +0.5 (colour 1), half at −0.5 (colour 0): σh = 0.5, and
        // a(h) = ā + a_s s(h) with s(±0.5) = ±(2 g(0.5) − 1) = ±erf(1/√2).
        let samples: alloc::vec::Vec<_> = (0..32)
            .map(|k| {
                let up = k % 2 == 0;
                sample(Vec3::new(k as f32 * 0.1, 0.0, if up { 0.5 } else { -0.5 }), Vec3::Z, if up { 1.0 } else { 0.0 })
            })
            .collect();
        let stats = surface_statistics(&samples, Vec3::ZERO, 0.0, Vec3::Z).unwrap();
        assert!((stats.height_variance - 0.25).abs() < 1e-6);
        let s = smith_micro::erf(core::f32::consts::FRAC_1_SQRT_2).unwrap();
        assert!((stats.correlation[0] - 0.5 / s).abs() < 1e-4, "{stats:?} vs {}", 0.5 / s);
        assert!((stats.attribute[1] - 0.5).abs() < 1e-6);
    }
}
