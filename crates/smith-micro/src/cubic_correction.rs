//! The per-material correction of Smith's Λ as a cubic: `Λ' = c(u) Λ` with
//! `u = Λ/(1 + Λ)` and `c(u) = c₀ + u (c₁ + u (c₂ + u c₃))`, and the corrected mean
//! visible attribute `ā(v, l) = ā + a_s Λ'/(Λ' + 2)` on the sum `Λ = Λ(v) + Λ(l)`, as
//! [`crate::corrected_visible_mean_attribute`] with its eight-knot table.
//!
//! The table of [`crate::LambdaCorrection`] costs a dynamically indexed lookup on the
//! GPU (22 operations over eq. 17 on naga's IR); the cubic costs 16: the division
//! `Λ/(1 + Λ)`, three multiply–adds and the product (9), and the bound on Λ and the flush
//! of a subnormal product that keep the GPU equal to the CPU (counted by the test
//! `smith_micro_cost` in `shader-registry`; eq. 17 is 61, one Smith Λ 186). [`CubicLambdaCorrection::fit_to_table`] takes the
//! least-squares cubic through a fitted table's knots; on the ray-traced sweeps of
//! `microsurface-truth` (test `corrected_thresholds`, view only, 512²) it is as accurate
//! as the table: max error 0–85° Gaussian ℓ = 12 0.409 → 0.343 %, fBm 0.389 → 0.304 %,
//! band-pass 0.227 → 0.228 %, cellular 0.338 → 0.337 %, ridged 0.276 → 0.370 %
//! (table → cubic; eq. 17: 2.400, 0.480, 3.286, 0.392, 3.052 %). A linear or quadratic
//! `c(u)` through the same knots was measured too coarse (up to 0.69 % on the Gaussian
//! surfaces, 2.2 % on the ridged texture). A cubic cannot follow a table that jumps near
//! grazing: the cellular texture's table at 1024² (`cargo xtask fig9`) ends 1.16 → 1.57 →
//! 3.5, and its cubic's error is 1.94 % where the table's is 0.42 % and eq. 17's 1.46 %.
//! [`CubicLambdaCorrection::fit_within`] therefore keeps the cubic only where it stays
//! within [`CUBIC_DEVIATION_BUDGET`] of the table, the table elsewhere. At 1024²
//! (`cargo xtask fig9`, 200 000 rays per angle) the cubic is kept on the three Gaussian
//! surfaces, with view-only max errors 0.14, 0.18 and 0.15 % (tables 0.16, 0.17, 0.12 %).
//!
//! | input | [`cubic_corrected_visible_mean_attribute`] |
//! |---|---|
//! | `Λ = 0` (normal incidence, flat) | `ā` |
//! | `Λ = +∞`, or above [`MAX_CORRECTED_LAMBDA`](crate::correction::MAX_CORRECTED_LAMBDA) | `ā + a_s` |
//! | `Λ` subnormal, or `c Λ` subnormal | `ā` (flushed, as the GPU does) |
//! | a Λ negative or NaN | `None` |
//! | a coefficient NaN or ±∞, or `c(u)` outside `[MIN_CORRECTION_FACTOR, MAX_CORRECTION_FACTOR]` somewhere on `[0, 1]` | `None` |
//! | `|ā|` or `|a_s|` above `2⁶⁴` or NaN | `None` |
//! | [`CubicLambdaCorrection::IDENTITY`] | eq. 17, same bits |

use glam::Vec4;
use gpu_layout::gpu_struct;

use crate::attribute::HeightCorrelatedAttribute;
use crate::correction::{
    CORRECTION_KNOTS, LambdaCorrection, MAX_CORRECTION_FACTOR, MIN_CORRECTION_FACTOR,
    visible_mean_attribute_of_corrected_sum,
};

/// The deviation from the table ([`CubicLambdaCorrection::deviation_from`]) up to which the
/// cubic replaces it: 0.25 % of the attribute range, half of the 0.5 % error budget the
/// corrected model is held to (the tables measure 0.12–0.42 % on the sweeps of
/// `cargo xtask fig9`). The Gaussian surfaces' tables stay inside it (measured 0.04–0.05 %
/// at 1024² by `cargo xtask fig9`, 0.10–0.22 % at 512² by the test `corrected_thresholds`);
/// the textures' do not (cellular 2.24 %, ridged 0.63 % at 1024²).
pub const CUBIC_DEVIATION_BUDGET: f32 = 0.0025;

gpu_struct! {
    /// A per-material factor `c(u) = c₀ + u (c₁ + u (c₂ + u c₃))` on Smith's Λ (eq. 6),
    /// `u = Λ/(1 + Λ) ∈ [0, 1]`, valid when `c` stays in
    /// `[MIN_CORRECTION_FACTOR, MAX_CORRECTION_FACTOR]` over `[0, 1]`. See the module's
    /// table for what each input gives.
    pub struct CubicLambdaCorrection {
        /// `(c₀, c₁, c₂, c₃)`.
        pub coefficients: Vec4,
    }
}

impl CubicLambdaCorrection {
    /// No correction: `c = 1`, and the corrected attribute equals eq. 17.
    pub const IDENTITY: Self = Self { coefficients: Vec4::new(1.0, 0.0, 0.0, 0.0) };

    /// The correction with coefficients `(c₀, c₁, c₂, c₃)`, or `None` when one is not
    /// finite or `c(u)` leaves `[MIN_CORRECTION_FACTOR, MAX_CORRECTION_FACTOR]` on `[0, 1]`.
    pub fn from_coefficients(coefficients: [f32; 4]) -> Option<Self> {
        let correction = Self { coefficients: Vec4::from_array(coefficients) };
        correction.is_valid().then_some(correction)
    }

    /// The least-squares cubic through the knots of `table` (at `u = i/7`), or `None` when
    /// the table is invalid or the cubic leaves the accepted range.
    pub fn fit_to_table(table: &LambdaCorrection) -> Option<Self> {
        if !table.is_valid() {
            return None;
        }
        // Normal equations of the 8 × 4 Vandermonde system, in f64.
        let mut normal = [[0.0_f64; 4]; 4];
        let mut rhs = [0.0_f64; 4];
        for (i, &knot) in table.knots().iter().enumerate() {
            let u = i as f64 / (CORRECTION_KNOTS - 1) as f64;
            let powers = [1.0, u, u * u, u * u * u];
            for row in 0..4 {
                rhs[row] += powers[row] * f64::from(knot);
                for column in 0..4 {
                    normal[row][column] += powers[row] * powers[column];
                }
            }
        }
        let solution = solve4(normal, rhs)?;
        Self::from_coefficients(solution.map(|c| c as f32))
    }

    /// The cubic through the knots of `table` ([`CubicLambdaCorrection::fit_to_table`])
    /// when it stays within `budget` of the table ([`CubicLambdaCorrection::deviation_from`],
    /// a fraction of the attribute range), else `None`: the cheaper correction where it
    /// adds at most `budget` to the table's error, the table elsewhere.
    pub fn fit_within(table: &LambdaCorrection, budget: f32) -> Option<Self> {
        let cubic = Self::fit_to_table(table)?;
        (cubic.deviation_from(table) <= budget).then_some(cubic)
    }

    /// The largest difference between the visible fraction `x(Λ') = Λ'/(Λ' + 2)` of eq. 17
    /// corrected by this cubic and by `table`, halved: the difference of the two corrected
    /// attributes as a fraction of the attribute range `[ā − a_s, ā + a_s]`, over
    /// `Λ = u/(1 − u)` at 1024 steps of `u` in `[0, 1)` (at `u = 1` both give `x = 1`), the
    /// factors as the corrections evaluate them; NaN for an invalid table or cubic.
    pub fn deviation_from(&self, table: &LambdaCorrection) -> f32 {
        if !(self.is_valid() && table.is_valid()) {
            return f32::NAN;
        }
        let fraction = |corrected: f64| corrected / (corrected + 2.0);
        let mut largest = 0.0_f64;
        for step in 0..1024 {
            let u = step as f32 / 1024.0;
            let lambda = f64::from(u / (1.0 - u));
            let (by_cubic, by_table) = (f64::from(self.factor(u)), f64::from(table.factor(u)));
            largest = largest.max((fraction(by_cubic * lambda) - fraction(by_table * lambda)).abs() / 2.0);
        }
        largest as f32
    }

    /// Whether every coefficient is finite and `c(u)` lies in
    /// `[MIN_CORRECTION_FACTOR, MAX_CORRECTION_FACTOR]` for every `u ∈ [0, 1]` (checked at
    /// the ends and at the roots of `c′` inside, in f64).
    pub fn is_valid(&self) -> bool {
        if !self.coefficients.is_finite() {
            return false;
        }
        let [c0, c1, c2, c3] = self.coefficients.to_array().map(f64::from);
        let value = |u: f64| c0 + u * (c1 + u * (c2 + u * c3));
        let in_range =
            |u: f64| (f64::from(MIN_CORRECTION_FACTOR)..=f64::from(MAX_CORRECTION_FACTOR)).contains(&value(u));
        if !(in_range(0.0) && in_range(1.0)) {
            return false;
        }
        // c′(u) = c₁ + 2 c₂ u + 3 c₃ u².
        let (a, b, c) = (3.0 * c3, 2.0 * c2, c1);
        let mut roots = [f64::NAN; 2];
        if a == 0.0 {
            if b != 0.0 {
                roots[0] = -c / b;
            }
        } else {
            let discriminant = b * b - 4.0 * a * c;
            if discriminant >= 0.0 {
                let root = libm::sqrt(discriminant);
                roots = [(-b - root) / (2.0 * a), (-b + root) / (2.0 * a)];
            }
        }
        roots.iter().filter(|&&u| u > 0.0 && u < 1.0).all(|&u| in_range(u))
    }

    /// The factor `c(u)` (Horner's scheme). Does not check validity.
    ///
    /// WGSL twin: `smith_cubic_correction_factor`.
    pub fn factor(&self, u: f32) -> f32 {
        let [c0, c1, c2, c3] = self.coefficients.to_array();
        c0 + u * (c1 + u * (c2 + u * c3))
    }
}

impl Default for CubicLambdaCorrection {
    fn default() -> Self {
        Self::IDENTITY
    }
}

/// A [`CubicLambdaCorrection`] that [`CubicLambdaCorrection::is_valid`] accepted, checked
/// once (per material) so that each evaluation skips the check, as the WGSL twin does.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CheckedCubicCorrection(CubicLambdaCorrection);

impl CheckedCubicCorrection {
    /// The checked correction, or `None` when `correction` is invalid.
    pub fn new(correction: CubicLambdaCorrection) -> Option<Self> {
        correction.is_valid().then_some(Self(correction))
    }

    /// The correction.
    pub fn correction(&self) -> CubicLambdaCorrection {
        self.0
    }

    /// [`cubic_corrected_visible_mean_attribute`] without re-checking the correction.
    ///
    /// WGSL twin: `smith_corrected_visible_mean_attribute_of_valid_cubic`.
    pub fn visible_mean_attribute(
        &self,
        attribute: HeightCorrelatedAttribute,
        lambda_view: f32,
        lambda_light: f32,
    ) -> Option<f32> {
        visible_mean_attribute_of_corrected_sum(attribute, lambda_view, lambda_light, |u| self.0.factor(u))
    }
}

/// Solves the 4 × 4 system by Gaussian elimination with partial pivoting; `None` when it
/// is (nearly) singular.
fn solve4(mut matrix: [[f64; 4]; 4], mut rhs: [f64; 4]) -> Option<[f64; 4]> {
    for column in 0..4 {
        let pivot = (column..4).max_by(|&a, &b| matrix[a][column].abs().total_cmp(&matrix[b][column].abs()))?;
        if matrix[pivot][column].abs() < 1e-12 {
            return None;
        }
        matrix.swap(column, pivot);
        rhs.swap(column, pivot);
        let pivot_row = matrix[column];
        for row in column + 1..4 {
            let factor = matrix[row][column] / pivot_row[column];
            for (value, &above) in matrix[row][column..].iter_mut().zip(&pivot_row[column..]) {
                *value -= factor * above;
            }
            rhs[row] -= factor * rhs[column];
        }
    }
    let mut solution = [0.0; 4];
    for row in (0..4).rev() {
        let known: f64 = (row + 1..4).map(|k| matrix[row][k] * solution[k]).sum();
        solution[row] = (rhs[row] - known) / matrix[row][row];
    }
    solution.iter().all(|s| s.is_finite()).then_some(solution)
}

/// Eq. 17 with the sum corrected by the cubic: `ā + a_s Λ'/(Λ' + 2)`, `Λ' = c(u) Λ`,
/// `Λ = Λ(v) + Λ(l)` (see the module's table). With [`CubicLambdaCorrection::IDENTITY`]
/// this is [`crate::visible_mean_attribute`], bit for bit.
///
/// WGSL twin: `smith_corrected_visible_mean_attribute_of_valid_cubic` (for a correction
/// that [`CubicLambdaCorrection::is_valid`] accepted).
pub fn cubic_corrected_visible_mean_attribute(
    attribute: HeightCorrelatedAttribute,
    lambda_view: f32,
    lambda_light: f32,
    correction: &CubicLambdaCorrection,
) -> Option<f32> {
    if !correction.is_valid() {
        return None;
    }
    visible_mean_attribute_of_corrected_sum(attribute, lambda_view, lambda_light, |u| correction.factor(u))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::correction::corrected_visible_mean_attribute;
    use crate::correction::tests::{SPECIAL, assert_eq17_bit_for_bit};

    #[test]
    fn identity_is_eq17_bit_for_bit() {
        assert_eq17_bit_for_bit(|attribute, view, light| {
            cubic_corrected_visible_mean_attribute(attribute, view, light, &CubicLambdaCorrection::IDENTITY)
        });
    }

    #[test]
    fn a_cubic_table_is_fitted_exactly_and_agrees_with_the_table() {
        // Knots sampled from a cubic: the fit recovers it, and the two corrections agree
        // to the table's interpolation error.
        let cubic = |u: f32| 1.4 - 0.9 * u + 0.8 * u * u - 0.5 * u * u * u;
        let knots: [f32; CORRECTION_KNOTS] = core::array::from_fn(|i| cubic(i as f32 / 7.0));
        let table = LambdaCorrection::from_knots(knots).unwrap();
        let fitted = CubicLambdaCorrection::fit_to_table(&table).unwrap();
        let expected = Vec4::new(1.4, -0.9, 0.8, -0.5);
        assert!((fitted.coefficients - expected).abs().max_element() < 1e-4, "{:?}", fitted.coefficients);
        let attribute = HeightCorrelatedAttribute { mean: 0.2, height_correlation: 0.7 };
        for lambda in [0.01_f32, 0.3, 1.0, 4.0, 40.0] {
            let by_table = corrected_visible_mean_attribute(attribute, lambda, 0.0, &table).unwrap();
            let by_cubic = cubic_corrected_visible_mean_attribute(attribute, lambda, 0.0, &fitted).unwrap();
            assert!((by_table - by_cubic).abs() < 2e-3, "Λ = {lambda}: {by_table} {by_cubic}");
        }
        // The identity table gives the identity cubic.
        let identity = CubicLambdaCorrection::fit_to_table(&LambdaCorrection::IDENTITY).unwrap();
        assert!((identity.coefficients - CubicLambdaCorrection::IDENTITY.coefficients).abs().max_element() < 1e-6);
    }

    #[test]
    fn the_cubic_is_kept_only_within_its_budget() {
        // A smooth table: its cubic deviates little. A table that jumps at grazing (as a
        // cellular texture's fitted table does, 1.16 → 3.5 over the last knot) cannot be
        // followed by a cubic.
        let smooth = LambdaCorrection::from_knots([1.45, 1.33, 1.26, 1.22, 1.20, 1.13, 1.09, 0.93]).unwrap();
        let jump = LambdaCorrection::from_knots([1.09, 1.25, 1.21, 1.15, 1.14, 1.16, 1.57, 3.5]).unwrap();
        let smooth_deviation = CubicLambdaCorrection::fit_to_table(&smooth).unwrap().deviation_from(&smooth);
        let jump_deviation = CubicLambdaCorrection::fit_to_table(&jump).unwrap().deviation_from(&jump);
        // Measured 0.0021 and 0.022 (fractions of the attribute range).
        assert!(smooth_deviation < 2.5e-3 && jump_deviation > 1e-2, "{smooth_deviation} {jump_deviation}");
        assert!(CubicLambdaCorrection::fit_within(&smooth, 2.5e-3).is_some());
        assert!(CubicLambdaCorrection::fit_within(&jump, 2.5e-3).is_none());
        // The identity's cubic is exact.
        let identity = LambdaCorrection::IDENTITY;
        assert!(CubicLambdaCorrection::fit_to_table(&identity).unwrap().deviation_from(&identity) < 1e-7);
    }

    #[test]
    fn the_checked_correction_gives_the_same_bits() {
        let cubic = CubicLambdaCorrection::from_coefficients([1.4, -0.9, 0.8, -0.5]).unwrap();
        let checked = CheckedCubicCorrection::new(cubic).unwrap();
        assert_eq!(checked.correction(), cubic);
        let attribute = HeightCorrelatedAttribute { mean: 0.5, height_correlation: -0.2 };
        for &view in &SPECIAL {
            for &light in &SPECIAL {
                let expected = cubic_corrected_visible_mean_attribute(attribute, view, light, &cubic);
                let value = checked.visible_mean_attribute(attribute, view, light);
                assert_eq!(value.map(f32::to_bits), expected.map(f32::to_bits), "Λ = {view} + {light}");
            }
        }
        let invalid = CubicLambdaCorrection { coefficients: Vec4::new(1.0, -4.0, 4.0, 0.0) };
        assert_eq!(CheckedCubicCorrection::new(invalid), None);
    }

    #[test]
    fn coefficients_that_leave_the_range_are_rejected() {
        assert!(CubicLambdaCorrection::from_coefficients([1.0, 0.0, 0.0, 0.0]).is_some());
        // Ends in range, but c(1/2) = 1 − 4 · 0.25 + ... dips below 0.25 inside.
        let dip = [1.0, -4.0, 4.0, 0.0];
        assert!(CubicLambdaCorrection::from_coefficients(dip).is_none());
        for bad in
            [[f32::NAN, 0.0, 0.0, 0.0], [1.0, f32::INFINITY, 0.0, 0.0], [0.2, 0.0, 0.0, 0.0], [4.0, 0.5, 0.0, 0.0]]
        {
            assert!(CubicLambdaCorrection::from_coefficients(bad).is_none(), "{bad:?}");
        }
        let attribute = HeightCorrelatedAttribute { mean: 0.5, height_correlation: -0.2 };
        let invalid = CubicLambdaCorrection { coefficients: Vec4::new(1.0, -4.0, 4.0, 0.0) };
        assert_eq!(cubic_corrected_visible_mean_attribute(attribute, 1.0, 0.0, &invalid), None);
        let table = LambdaCorrection { low: Vec4::splat(f32::NAN), high: Vec4::ONE };
        assert_eq!(CubicLambdaCorrection::fit_to_table(&table), None);
    }

    #[test]
    fn special_inputs_have_defined_results() {
        let correction = CubicLambdaCorrection::from_coefficients([1.4, -0.9, 0.8, -0.5]).unwrap();
        let attribute = HeightCorrelatedAttribute { mean: 0.5, height_correlation: -0.2 };
        let value = |view: f32, light: f32| cubic_corrected_visible_mean_attribute(attribute, view, light, &correction);
        assert_eq!(value(f32::MAX, f32::MAX), Some(0.3));
        assert_eq!(value(f32::INFINITY, 0.0), Some(0.3));
        assert_eq!(value(0.0, 0.0), Some(0.5));
        assert_eq!(value(1e-40, 0.0), Some(0.5));
        assert_eq!(value(0.0, f32::NAN), None);
        assert_eq!(value(-1.0, 0.0), None);
        // Every accepted input gives a finite result between ā + a_s and ā.
        for &view in &SPECIAL[..14] {
            for &light in &SPECIAL[..14] {
                let result = value(view, light).unwrap();
                assert!(result.is_finite() && (0.3..=0.5).contains(&result), "Λ = {view} + {light}: {result}");
            }
        }
    }
}
