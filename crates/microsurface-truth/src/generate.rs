//! Periodic height-field generators: Gaussian random surfaces of several spectra (sums of
//! random-phase sinusoids on the period's frequency lattice), and non-Gaussian ones
//! (cellular cobblestones, ridged noise) to push Smith's model past its hypothesis H3.

use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

use crate::heightfield::{HeightField, HeightFieldError};
use crate::statistics::SurfaceStatistics;

/// The power spectrum of a Gaussian random surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Spectrum {
    /// Gaussian autocorrelation `exp(-r²/ℓ²)` with correlation length `ℓ = wavelength`
    /// cells: a 2-D Gaussian spectrum.
    Gaussian {
        /// Correlation length ℓ in cells.
        wavelength: f64,
    },
    /// fBm-like power law `|k|^-β` between two wavelengths.
    PowerLaw {
        /// Shortest wavelength in cells.
        min_wavelength: f64,
        /// Longest wavelength in cells.
        max_wavelength: f64,
        /// Exponent β of the power spectral density (fBm with Hurst H: β = 2H + 2).
        exponent: f64,
    },
    /// A narrow ring of wavelengths around `wavelength` (relative width `width`).
    BandPass {
        /// Central wavelength in cells.
        wavelength: f64,
        /// Standard deviation of the wavenumber relative to the central one.
        width: f64,
    },
}

/// Sinusoids summed per field: enough for the central limit theorem to make the heights
/// and slopes Gaussian (the measured excess kurtosis is reported by the statistics).
const TERMS: usize = 600;

impl Spectrum {
    /// A wavenumber `|k|` (radians per cell) drawn with density ∝ `|k| · PSD(|k|)`.
    fn sample_wavenumber(&self, rng: &mut SmallRng) -> f64 {
        let tau = std::f64::consts::TAU;
        match *self {
            Spectrum::Gaussian { wavelength } => {
                // PSD ∝ exp(-k²ℓ²/4): k is the norm of a 2-D normal vector, σ = √2/ℓ.
                let sigma = std::f64::consts::SQRT_2 / wavelength;
                let a: f64 = rng.random();
                sigma * (-2.0 * (1.0 - a).ln()).sqrt() // Rayleigh: |2-D normal vector|
            }
            Spectrum::PowerLaw { min_wavelength, max_wavelength, exponent } => {
                let (k0, k1) = (tau / max_wavelength, tau / min_wavelength);
                // Density ∝ k^(1-β) on [k0, k1], by inverse CDF.
                let p = 2.0 - exponent;
                let u: f64 = rng.random();
                if p.abs() < 1e-9 {
                    k0 * (k1 / k0).powf(u)
                } else {
                    (k0.powf(p) + u * (k1.powf(p) - k0.powf(p))).powf(1.0 / p)
                }
            }
            Spectrum::BandPass { wavelength, width } => {
                let k = tau / wavelength;
                let (a, b): (f64, f64) = (rng.random(), rng.random());
                let normal = (-2.0 * (1.0 - a).ln()).sqrt() * (tau * b).cos();
                (k * (1.0 + width * normal)).abs()
            }
        }
    }
}

/// Sums `terms` sinusoids with integer frequency vectors `(a, b)` (cycles per period), so
/// the field is exactly periodic.
fn sum_of_sinusoids(size: usize, frequencies: &[(i64, i64, f64, f64)]) -> Vec<f64> {
    let n = size as f64;
    let tau = std::f64::consts::TAU;
    let mut heights = vec![0.0; size * size];
    let mut cos_x = vec![0.0; size];
    let mut sin_x = vec![0.0; size];
    for &(a, b, amplitude, phase) in frequencies {
        for (i, (c, s)) in cos_x.iter_mut().zip(sin_x.iter_mut()).enumerate() {
            let angle = tau * (a as f64) * (i as f64) / n;
            (*c, *s) = (angle.cos(), angle.sin());
        }
        for j in 0..size {
            let angle = tau * (b as f64) * (j as f64) / n + phase;
            let (cy, sy) = (angle.cos() * amplitude, angle.sin() * amplitude);
            let row = &mut heights[j * size..(j + 1) * size];
            for ((h, c), s) in row.iter_mut().zip(&cos_x).zip(&sin_x) {
                *h += c * cy - s * sy; // cos(x + y)
            }
        }
    }
    heights
}

/// Scales `heights` so that the RMS slope (root mean square of `σ_nx` and `σ_ny`) is
/// `slope_sigma`.
fn with_slope_sigma(size: usize, heights: Vec<f64>, slope_sigma: f64) -> Result<HeightField, HeightFieldError> {
    let field = HeightField::new(size, heights)?;
    let stats = SurfaceStatistics::measure(&field);
    let current = ((stats.slope_sigma.x.powi(2) + stats.slope_sigma.y.powi(2)) / 2.0).sqrt();
    if current == 0.0 {
        return Ok(field);
    }
    let scale = slope_sigma / current;
    HeightField::new(size, field.heights().iter().map(|h| h * scale).collect())
}

/// A Gaussian random surface of `size × size` cells with the given spectrum, isotropic,
/// scaled to RMS slope `slope_sigma`; deterministic for a `seed`. Errors for `size < 8`
/// (no room for a wavelength of 4 cells) or parameters that produce non-finite heights.
pub fn generate_gaussian(
    size: usize,
    spectrum: Spectrum,
    slope_sigma: f64,
    seed: u64,
) -> Result<HeightField, HeightFieldError> {
    if size < 8 {
        return Err(HeightFieldError::BadSize(format!("{size} cells: at least 8 are needed")));
    }
    let mut rng = SmallRng::seed_from_u64(seed);
    let tau = std::f64::consts::TAU;
    let nyquist = (size / 2) as i64;
    let mut frequencies = Vec::with_capacity(TERMS);
    let mut attempts = 0;
    while frequencies.len() < TERMS {
        attempts += 1;
        if attempts > 1000 * TERMS {
            return Err(HeightFieldError::BadSize(format!(
                "{spectrum:?} has no wavelength between 4 and {size} cells"
            )));
        }
        let k = spectrum.sample_wavenumber(&mut rng);
        if !k.is_finite() {
            continue;
        }
        let direction: f64 = rng.random_range(0.0..tau);
        // Cycles per period along x and y, rounded to the lattice.
        let cycles = k * size as f64 / tau;
        let (a, b) = ((cycles * direction.cos()).round() as i64, (cycles * direction.sin()).round() as i64);
        if (a, b) == (0, 0) || a.abs() > nyquist / 2 || b.abs() > nyquist / 2 {
            continue;
        }
        frequencies.push((a, b, 1.0, rng.random_range(0.0..tau)));
    }
    with_slope_sigma(size, sum_of_sinusoids(size, &frequencies), slope_sigma)
}

/// Cellular "cobblestones": `F2 - F1` of periodic Worley noise with `cells` feature
/// points (stones bulge, grooves between them), scaled to RMS slope `slope_sigma`.
pub fn generate_cellular(
    size: usize,
    cells: usize,
    slope_sigma: f64,
    seed: u64,
) -> Result<HeightField, HeightFieldError> {
    let size = size.max(2);
    let mut rng = SmallRng::seed_from_u64(seed);
    let n = size as f64;
    let points: Vec<(f64, f64)> =
        (0..cells.max(2)).map(|_| (rng.random_range(0.0..n), rng.random_range(0.0..n))).collect();
    let wrap = |d: f64| {
        let d = d.abs() % n;
        d.min(n - d)
    };
    let mut heights = Vec::with_capacity(size * size);
    for j in 0..size {
        for i in 0..size {
            let (mut f1, mut f2) = (f64::INFINITY, f64::INFINITY);
            for &(px, py) in &points {
                let d = wrap(i as f64 - px).hypot(wrap(j as f64 - py));
                if d < f1 {
                    (f1, f2) = (d, f1);
                } else if d < f2 {
                    f2 = d;
                }
            }
            heights.push(f2 - f1);
        }
    }
    with_slope_sigma(size, heights, slope_sigma)
}

/// Ridged noise: `-|g|` of a Gaussian band-limited field `g` (sharp crests, rounded
/// valleys), scaled to RMS slope `slope_sigma`.
pub fn generate_ridged(
    size: usize,
    wavelength: f64,
    slope_sigma: f64,
    seed: u64,
) -> Result<HeightField, HeightFieldError> {
    let base = generate_gaussian(size, Spectrum::Gaussian { wavelength }, 1.0, seed)?;
    let heights = base.heights().iter().map(|h| -h.abs()).collect();
    with_slope_sigma(base.size(), heights, slope_sigma)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gaussian_fields_are_gaussian_and_have_the_requested_slope() {
        for spectrum in [
            Spectrum::Gaussian { wavelength: 6.0 },
            Spectrum::PowerLaw { min_wavelength: 5.0, max_wavelength: 32.0, exponent: 3.0 },
            Spectrum::BandPass { wavelength: 8.0, width: 0.1 },
        ] {
            // The period must hold many correlation lengths for the heights to be Gaussian.
            let field = generate_gaussian(256, spectrum, 0.5, 3).unwrap();
            let stats = SurfaceStatistics::measure(&field);
            let slope = ((stats.slope_sigma.x.powi(2) + stats.slope_sigma.y.powi(2)) / 2.0).sqrt();
            assert!((slope - 0.5).abs() < 1e-9, "{spectrum:?}: {slope}");
            assert!(stats.height_excess_kurtosis.abs() < 0.3, "{spectrum:?}: {stats:?}");
            assert!(stats.height_skewness.abs() < 0.2, "{spectrum:?}: {stats:?}");
            assert!(stats.mean_slope.length() < 1e-9);
        }
        let spectrum = Spectrum::Gaussian { wavelength: 8.0 };
        assert_eq!(generate_gaussian(64, spectrum, 0.3, 9).unwrap(), generate_gaussian(64, spectrum, 0.3, 9).unwrap());
        assert!(generate_gaussian(4, spectrum, 0.3, 9).is_err());
        assert!(generate_gaussian(64, Spectrum::BandPass { wavelength: 1.0, width: 0.0 }, 0.3, 9).is_err());
    }

    #[test]
    fn non_gaussian_fields_are_measurably_non_gaussian() {
        let ridged = SurfaceStatistics::measure(&generate_ridged(128, 16.0, 0.5, 4).unwrap());
        assert!(ridged.height_skewness < -0.5, "{ridged:?}");
        let cellular = SurfaceStatistics::measure(&generate_cellular(128, 24, 0.5, 4).unwrap());
        assert!(cellular.height_skewness.abs() > 0.2 || cellular.height_excess_kurtosis.abs() > 0.3, "{cellular:?}");
    }
}
