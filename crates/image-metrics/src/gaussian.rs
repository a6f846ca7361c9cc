//! The Gaussian filter of SSIM, as `scipy.ndimage.gaussian_filter(x, 1.5, truncate=3.5,
//! mode='reflect')` computes it (what scikit-image's `structural_similarity` calls with
//! `gaussian_weights=True`): a normalised 11-tap kernel, separable, rows' axis first, the
//! border extended by reflection about the edge (`d c b a | a b c d | d c b a`).
//!
//! The arithmetic follows scipy's and numpy's order of operations (kernel weights, their
//! pairwise sum, the symmetric correlation loop), so that the results agree with scipy to
//! within a few ulps rather than by chance.

/// SSIM's Gaussian standard deviation, in pixels (Wang et al. 2004, §III-C).
pub const SSIM_SIGMA: f64 = 1.5;

/// The window's half-width: scipy's `int(truncate · σ + 0.5)` with scikit-image's
/// `truncate = 3.5`, i.e. 5, an 11 × 11 window.
pub const SSIM_WINDOW_RADIUS: u32 = 5;

const RADIUS: usize = SSIM_WINDOW_RADIUS as usize;
const TAPS: usize = 2 * RADIUS + 1;

/// The kernel of scipy's `_gaussian_kernel1d(1.5, 0, 5)`: `exp(-0.5 / σ² · x²)` for
/// `x = -5..=5`, divided by its (numpy pairwise) sum.
pub(crate) fn kernel() -> [f64; TAPS] {
    let factor = -0.5 / (SSIM_SIGMA * SSIM_SIGMA);
    let mut phi = [0.0; TAPS];
    for (i, p) in phi.iter_mut().enumerate() {
        let x = i as f64 - RADIUS as f64;
        *p = (factor * (x * x)).exp();
    }
    let sum = pairwise_sum(&phi);
    phi.map(|p| p / sum)
}

/// numpy's pairwise summation (`pairwise_sum_DOUBLE`): below 8 values a plain loop; up
/// to 128, eight interleaved partial sums combined as a tree, then the remainder; above,
/// the two halves (split at a multiple of 8) recursively.
pub(crate) fn pairwise_sum(values: &[f64]) -> f64 {
    let n = values.len();
    if n < 8 {
        values.iter().fold(0.0, |sum, &v| sum + v)
    } else if n <= 128 {
        let mut r = [0.0; 8];
        r.copy_from_slice(&values[..8]);
        let blocks = n - n % 8;
        for block in values[8..blocks].chunks_exact(8) {
            for (r, &v) in r.iter_mut().zip(block) {
                *r += v;
            }
        }
        let mut sum = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]));
        for &v in &values[blocks..] {
            sum += v;
        }
        sum
    } else {
        let half = n / 2;
        let half = half - half % 8;
        pairwise_sum(&values[..half]) + pairwise_sum(&values[half..])
    }
}

/// scipy's `mode='reflect'`: index `i` of a line of `n` samples, reflected about the
/// edges (half-sample symmetric, period `2n`).
fn reflect(i: isize, n: usize) -> usize {
    let period = 2 * n as isize;
    let m = i.rem_euclid(period) as usize;
    if m < n { m } else { 2 * n - 1 - m }
}

/// Correlates one line with the symmetric kernel as scipy's `NI_Correlate1D` does:
/// `x[i]·w[0] + Σ_{j=5..1} (x[i−j] + x[i+j])·w[j]`, on a line extended by reflection.
fn correlate_line(line: &[f64], kernel: &[f64; TAPS], extended: &mut Vec<f64>, out: &mut [f64]) {
    let n = line.len();
    extended.clear();
    extended.extend((-(RADIUS as isize)..(n + RADIUS) as isize).map(|i| line[reflect(i, n)]));
    let centre = &kernel[RADIUS..];
    for (i, o) in out.iter_mut().enumerate() {
        let c = i + RADIUS;
        let mut sum = extended[c] * centre[0];
        for j in (1..=RADIUS).rev() {
            sum += (extended[c - j] + extended[c + j]) * centre[j];
        }
        *o = sum;
    }
}

/// The Gaussian-filtered `plane` (`width × height`, row-major): down the columns first
/// (numpy's axis 0), then along the rows, each pass stored in `f64`.
pub(crate) fn gaussian_filter(plane: &[f64], width: usize, height: usize) -> Vec<f64> {
    debug_assert_eq!(plane.len(), width * height);
    let kernel = kernel();
    let mut extended = Vec::with_capacity(width.max(height) + 2 * RADIUS);
    let mut column = vec![0.0; height];
    let mut filtered = vec![0.0; height];
    let mut vertical = vec![0.0; width * height];
    for x in 0..width {
        for (y, c) in column.iter_mut().enumerate() {
            *c = plane[y * width + x];
        }
        correlate_line(&column, &kernel, &mut extended, &mut filtered);
        for (y, &f) in filtered.iter().enumerate() {
            vertical[y * width + x] = f;
        }
    }
    let mut out = vec![0.0; width * height];
    for (row, out_row) in vertical.chunks_exact(width).zip(out.chunks_exact_mut(width)) {
        correlate_line(row, &kernel, &mut extended, out_row);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kernel_is_scipys() {
        // scipy.ndimage._filters._gaussian_kernel1d(1.5, 0, 5), printed with repr().
        let scipy = [
            0.00102838008447911,
            0.007598758135239185,
            0.03600077212843083,
            0.10936068950970002,
            0.2130055377112537,
            0.26601172486179436,
            0.2130055377112537,
            0.10936068950970002,
            0.03600077212843083,
            0.007598758135239185,
            0.00102838008447911,
        ];
        let ours = kernel();
        for (o, s) in ours.iter().zip(scipy) {
            assert!((o - s).abs() <= 2.0 * f64::EPSILON * s, "{o} vs {s}");
        }
        assert!((pairwise_sum(&ours) - 1.0).abs() <= 4.0 * f64::EPSILON);
    }

    #[test]
    fn pairwise_sum_is_numpys_order() {
        // Values chosen so that the order of summation changes the result.
        let values: Vec<f64> = (0..300).map(|i| if i % 3 == 0 { 1e16 } else { 1.0 + f64::from(i) * 1e-3 }).collect();
        // numpy.add.reduce(values), with repr(); Python's sequential sum() gives 1e18.
        assert_eq!(pairwise_sum(&values), 1.0000000000000003e18);
        assert_eq!(values.iter().fold(0.0, |s, v| s + v), 1e18);
        assert_eq!(pairwise_sum(&[1.0, 2.0, 3.0]), 6.0);
        assert_eq!(pairwise_sum(&[]), 0.0);
    }

    #[test]
    fn reflection_repeats_the_edge_sample() {
        let n = 4;
        let mapped: Vec<usize> = (-5..9).map(|i| reflect(i, n)).collect();
        assert_eq!(mapped, [3, 3, 2, 1, 0, 0, 1, 2, 3, 3, 2, 1, 0, 0]);
    }

    #[test]
    fn filter_keeps_constants_and_matches_scipy_at_the_border() {
        let (w, h) = (13, 12);
        let constant = gaussian_filter(&vec![7.25; w * h], w, h);
        assert!(constant.iter().all(|v| (v - 7.25).abs() <= 1e-14));
        // An impulse at a corner: reflection folds the kernel's tail back onto the image,
        // so the corner keeps (w0 + w1)², 0.22945753784297646 in scipy.
        let mut impulse = vec![0.0; w * h];
        impulse[0] = 1.0;
        let filtered = gaussian_filter(&impulse, w, h);
        let k = kernel();
        let corner = (k[5] + k[4]) * (k[5] + k[4]);
        assert!((filtered[0] - corner).abs() <= 1e-16, "{} vs {corner}", filtered[0]);
        assert!((filtered[0] - 0.22945753784297646).abs() <= 4.0 * f64::EPSILON);
        let total: f64 = filtered.iter().sum();
        assert!((total - 1.0).abs() <= 1e-14, "reflection conserves mass: {total}");
    }
}
