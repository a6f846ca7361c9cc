//! A margin for what a table did not see: the upper prediction bound of one more
//! measurement of a row (another camera, another realization) from the ones it was
//! measured with.
//!
//! A row that holds the worst of `n` cameras is exceeded by an unseen camera with
//! probability 1 / (n + 1) when the cameras are exchangeable (the new one is the largest
//! of n + 1 with that probability): 20 % for four. [`prediction_bound`] asks for a stated
//! confidence instead.

use statrs::distribution::{ContinuousCDF, StudentsT};

use crate::SelectError;

/// The one-sided upper prediction bound, at `confidence`, of one more draw of the
/// quantity of which `samples` are draws, and never below the largest of them:
///
/// max(x̄ + t · s · √(1 + 1/n), max xᵢ),
///
/// with x̄ the samples' mean, s their standard deviation (n − 1 in the denominator) and t
/// Student's quantile at `confidence` with n − 1 degrees of freedom: the normal-theory
/// prediction interval for a single future observation (Hahn, Meeker & Escobar,
/// *Statistical Intervals*, 2nd ed. 2017, ch. 4). The floor at the largest sample keeps
/// what was measured: a bound is never more optimistic than the worst case seen.
///
/// Errors ([`SelectError::InvalidSamples`]): fewer than two samples (no spread to
/// estimate), a sample that is not finite, or `confidence` outside [0.5, 1).
///
/// ```
/// // Four cameras measured ꟻLIP 0.30, 0.31, 0.32 and 0.337.
/// let bound = model_select::prediction_bound(&[0.30, 0.31, 0.32, 0.337], 0.95)?;
/// assert!(bound > 0.337 && bound < 0.38, "{bound}");
/// # Ok::<(), model_select::SelectError>(())
/// ```
pub fn prediction_bound(samples: &[f64], confidence: f64) -> Result<f64, SelectError> {
    let invalid = |reason: String| SelectError::InvalidSamples { reason };
    if !(0.5..1.0).contains(&confidence) {
        return Err(invalid(format!("confidence {confidence} is not in [0.5, 1)")));
    }
    if samples.len() < 2 {
        return Err(invalid(format!("{} sample(s): a spread needs at least two", samples.len())));
    }
    if let Some(bad) = samples.iter().find(|x| !x.is_finite()) {
        return Err(invalid(format!("sample {bad} is not finite")));
    }
    let n = samples.len() as f64;
    let mean = samples.iter().sum::<f64>() / n;
    let deviation = (samples.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / (n - 1.0)).sqrt();
    let student = StudentsT::new(0.0, 1.0, n - 1.0)
        .map_err(|e| invalid(format!("Student's t with {} degrees of freedom: {e}", n - 1.0)))?;
    let t = student.inverse_cdf(confidence);
    let largest = samples.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    Ok((mean + t * deviation * (1.0 + 1.0 / n).sqrt()).max(largest))
}

#[cfg(test)]
mod tests {
    use super::prediction_bound;

    #[test]
    fn the_bound_matches_the_textbook_quantile() {
        // x̄ = 2.5, s = √(5/3), t(0.95, 3) = 2.353363 (any t table): 2.5 + 2.353363 · 1.290994
        // · √1.25 = 5.896788.
        let bound = prediction_bound(&[1.0, 2.0, 3.0, 4.0], 0.95).unwrap();
        assert!((bound - 5.896788).abs() < 1e-5, "{bound}");
        // Equal samples: no spread, the bound is the value.
        assert_eq!(prediction_bound(&[0.3; 4], 0.99).unwrap(), 0.3);
        // At 50 % the mean would do; the floor keeps the largest sample.
        assert_eq!(prediction_bound(&[0.0, 0.0, 0.0, 1.0], 0.5).unwrap(), 1.0);
    }

    /// Normal draws from a fixed-seed generator (xorshift, Box–Muller).
    fn normals(seed: u64, count: usize) -> Vec<f64> {
        let mut state = seed;
        let mut uniform = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        };
        (0..count)
            .map(|_| {
                let (u, v) = (uniform(), uniform());
                (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
            })
            .collect()
    }

    #[test]
    fn one_more_normal_draw_exceeds_the_bound_at_the_stated_rate() {
        // 20 000 trials of four draws and a fifth: the fifth exceeds the 90 % bound with
        // probability at most 0.1 (exactly 0.1 without the floor, which only lowers it).
        // Binomial noise: σ = √(0.1 · 0.9 / 20 000) = 0.0021; allow 4σ.
        let (trials, confidence) = (20_000, 0.9);
        let draws = normals(0x9e37_79b9_7f4a_7c15, trials * 5);
        let exceeded = draws.chunks_exact(5).filter(|d| d[4] > prediction_bound(&d[..4], confidence).unwrap()).count();
        let rate = exceeded as f64 / trials as f64;
        let sigma = (0.1f64 * 0.9 / trials as f64).sqrt();
        println!("exceeded in {exceeded} of {trials}: {rate:.4} (stated {:.2}, σ {sigma:.4})", 1.0 - confidence);
        assert!((rate - 0.1).abs() < 4.0 * sigma, "{rate}");
        // The worst of four alone is exceeded one time in five.
        let by_max = draws.chunks_exact(5).filter(|d| d[4] > d[..4].iter().copied().fold(f64::MIN, f64::max)).count();
        let rate = by_max as f64 / trials as f64;
        assert!((rate - 0.2).abs() < 4.0 * (0.2f64 * 0.8 / trials as f64).sqrt(), "{rate}");
    }

    #[test]
    fn bad_samples_and_confidences_are_named() {
        let message = |r: Result<f64, crate::SelectError>| r.unwrap_err().to_string();
        assert!(message(prediction_bound(&[1.0], 0.95)).contains("1 sample(s)"));
        assert!(message(prediction_bound(&[1.0, f64::NAN], 0.95)).contains("sample NaN is not finite"));
        assert!(message(prediction_bound(&[1.0, 2.0], 1.0)).contains("confidence 1 is not in [0.5, 1)"));
        assert!(message(prediction_bound(&[1.0, 2.0], 0.4)).contains("confidence 0.4"));
    }
}
