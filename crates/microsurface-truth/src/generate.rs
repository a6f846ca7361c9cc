//! Periodic height-field generators: Gaussian random surfaces of several spectra (every
//! frequency of the period's lattice up to a quarter of the grid, each with an independent
//! complex Gaussian amplitude of variance ∝ the power spectral density: a stationary,
//! isotropic Gaussian random field sampled exactly), and non-Gaussian ones
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

impl Spectrum {
    /// The (unnormalized) 2-D power spectral density at wavenumber `|k|` (radians per
    /// cell); `lattice_step` is the spacing of the period's frequency lattice, the
    /// narrowest band-pass width that still holds lattice frequencies.
    fn power_density(&self, k: f64, lattice_step: f64) -> f64 {
        let tau = std::f64::consts::TAU;
        match *self {
            // Gaussian autocorrelation exp(-r²/ℓ²): PSD ∝ exp(-k²ℓ²/4).
            Spectrum::Gaussian { wavelength } => (-k * k * wavelength * wavelength / 4.0).exp(),
            Spectrum::PowerLaw { min_wavelength, max_wavelength, exponent } => {
                let (k0, k1) = (tau / max_wavelength, tau / min_wavelength);
                if (k0..=k1).contains(&k) { k.powf(-exponent) } else { 0.0 }
            }
            // |k| ~ N(k_c, (width k_c)²) radially: PSD ∝ exp(-(k - k_c)²/(2 s²)) / k.
            Spectrum::BandPass { wavelength, width } => {
                let center = tau / wavelength;
                let deviation = (width * center).abs().max(0.5 * lattice_step);
                (-(k - center).powi(2) / (2.0 * deviation * deviation)).exp() / k
            }
        }
    }
}

/// A standard normal deviate (Box–Muller).
fn standard_normal(rng: &mut SmallRng) -> f64 {
    let (a, b): (f64, f64) = (rng.random(), rng.random());
    (-2.0 * (1.0 - a).ln()).sqrt() * (std::f64::consts::TAU * b).cos()
}

/// `Re Σ_(a,b) C_ab exp(iτ(a x + b y)/N)` on the `size × size` grid for the complex
/// coefficients `coefficients[(a + limit) (2 limit + 1) + (b + limit)]`, `|a|, |b| ≤ limit`:
/// a separable inverse DFT (first over `b` for every row `y`, then over `a`), exact and
/// periodic.
fn inverse_dft(size: usize, limit: i64, coefficients: &[(f64, f64)]) -> Vec<f64> {
    let n = size as i64;
    let side = (2 * limit + 1) as usize;
    let twiddle: Vec<(f64, f64)> = (0..size)
        .map(|m| {
            let angle = std::f64::consts::TAU * m as f64 / size as f64;
            (angle.cos(), angle.sin())
        })
        .collect();
    // The twiddles exp(iτ f p / N) for p = 0, 1, …: the index f·p mod N, stepped.
    let rotations = |frequency: i64| {
        let stride = frequency.rem_euclid(n) as usize;
        (0..size).scan(0_usize, move |index, _| {
            let at = *index;
            *index = if *index + stride >= size { *index + stride - size } else { *index + stride };
            Some(at)
        })
    };
    // rows[a][y] = Σ_b C_ab exp(iτ b y / N)
    let mut rows = vec![(0.0, 0.0); side * size];
    for (ai, row) in rows.chunks_exact_mut(size).enumerate() {
        let column = &coefficients[ai * side..(ai + 1) * side];
        for (bi, &(re, im)) in column.iter().enumerate() {
            if re == 0.0 && im == 0.0 {
                continue;
            }
            let b = bi as i64 - limit;
            for (value, k) in row.iter_mut().zip(rotations(b)) {
                let (c, s) = twiddle[k];
                value.0 += re * c - im * s;
                value.1 += re * s + im * c;
            }
        }
    }
    let mut heights = vec![0.0; size * size];
    for (y, line) in heights.chunks_exact_mut(size).enumerate() {
        for (ai, row) in rows.chunks_exact(size).enumerate() {
            let (re, im) = row[y];
            if re == 0.0 && im == 0.0 {
                continue;
            }
            let a = ai as i64 - limit;
            for (h, k) in line.iter_mut().zip(rotations(a)) {
                let (c, s) = twiddle[k];
                *h += re * c - im * s;
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
    // Frequencies up to a quarter of the grid (wavelengths ≥ 4 cells), so that the
    // piecewise-linear surface resolves every one.
    let limit = (size / 4) as i64;
    let lattice_step = tau / size as f64;
    let side = (2 * limit + 1) as usize;
    let mut coefficients = vec![(0.0, 0.0); side * side];
    let mut total_power = 0.0;
    for a in -limit..=limit {
        for b in -limit..=limit {
            // Draw for every lattice point, so the field does not depend on which are zero.
            let (re, im) = (standard_normal(&mut rng), standard_normal(&mut rng));
            if (a, b) == (0, 0) {
                continue;
            }
            let k = lattice_step * (a as f64).hypot(b as f64);
            let power = spectrum.power_density(k, lattice_step);
            if !(power.is_finite() && power > 0.0) {
                continue;
            }
            total_power += power;
            let amplitude = power.sqrt();
            coefficients[(a + limit) as usize * side + (b + limit) as usize] = (amplitude * re, amplitude * im);
        }
    }
    if !(total_power > 0.0 && total_power.is_finite()) {
        return Err(HeightFieldError::BadSize(format!("{spectrum:?} has no wavelength between 4 and {size} cells")));
    }
    with_slope_sigma(size, inverse_dft(size, limit, &coefficients), slope_sigma)
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
