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
//! A [`CubicLambdaCorrection`] is valid by construction: its coefficients are private,
//! and [`CubicLambdaCorrection::from_coefficients`], [`CubicLambdaCorrection::fit_to_table`]
//! and [`CubicLambdaCorrection::fit_within`] check once per material that `c(u)` stays in
//! `[MIN_CORRECTION_FACTOR, MAX_CORRECTION_FACTOR]` on `[0, 1]`, saying where it does not
//! ([`CubicCorrectionError`], [`CubicFitError`]); no evaluation re-checks it. The GPU
//! reads its [`GpuCubicLambdaCorrection`] ([`CubicLambdaCorrection::to_gpu`]).
//!
//! | input | [`cubic_corrected_visible_mean_attribute`] |
//! |---|---|
//! | `Λ = 0` (normal incidence, flat) | `ā` |
//! | `Λ = +∞`, or above [`MAX_CORRECTED_LAMBDA`](crate::correction::MAX_CORRECTED_LAMBDA) | `ā + a_s` |
//! | `Λ` subnormal, or `c Λ` subnormal | `ā` (flushed, as the GPU does) |
//! | a Λ negative or NaN | `None` |
//! | [`CubicLambdaCorrection::IDENTITY`] | eq. 17, same bits |
//!
//! | coefficients given to [`CubicLambdaCorrection::from_coefficients`] | result |
//! |---|---|
//! | finite, `c(u)` in `[MIN_CORRECTION_FACTOR, MAX_CORRECTION_FACTOR]` on `[0, 1]` | the correction |
//! | `cᵢ` NaN or ±∞ | [`CubicCorrectionError::CoefficientNotFinite`] |
//! | `c(u) < MIN_CORRECTION_FACTOR` at some `u ∈ [0, 1]` | [`CubicCorrectionError::FactorBelowMinimum`] (where) |
//! | `c(u) > MAX_CORRECTION_FACTOR` at some `u ∈ [0, 1]` | [`CubicCorrectionError::FactorAboveMaximum`] (where) |

use core::fmt;

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

/// A per-material factor `c(u) = c₀ + u (c₁ + u (c₂ + u c₃))` on Smith's Λ (eq. 6),
/// `u = Λ/(1 + Λ) ∈ [0, 1]`, with `c` in `[MIN_CORRECTION_FACTOR, MAX_CORRECTION_FACTOR]`
/// over `[0, 1]`: built only by [`CubicLambdaCorrection::from_coefficients`], the fits
/// [`CubicLambdaCorrection::fit_to_table`] and [`CubicLambdaCorrection::fit_within`],
/// and [`CubicLambdaCorrection::IDENTITY`]. See the module's table for what each input
/// gives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CubicLambdaCorrection {
    coefficients: [f32; 4],
}

/// Why a cubic was rejected by [`CubicLambdaCorrection::from_coefficients`] or
/// [`CubicLambdaCorrection::fit_to_table`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CubicCorrectionError {
    /// Coefficient `c_index` is NaN or ±∞ (the first such one).
    CoefficientNotFinite {
        /// The coefficient's index, `0 … 3`.
        index: usize,
    },
    /// `c(u) < MIN_CORRECTION_FACTOR` at `u` (the first of `0`, the interior extrema of
    /// `c` and `1` where `c` leaves the range; `c(u)` computed in f64).
    FactorBelowMinimum {
        /// Where, in `[0, 1]`.
        u: f64,
        /// `c(u)` there.
        factor: f64,
    },
    /// `c(u) > MAX_CORRECTION_FACTOR` at `u` (as for
    /// [`CubicCorrectionError::FactorBelowMinimum`]).
    FactorAboveMaximum {
        /// Where, in `[0, 1]`.
        u: f64,
        /// `c(u)` there.
        factor: f64,
    },
}

impl fmt::Display for CubicCorrectionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CubicCorrectionError::CoefficientNotFinite { index } => {
                write!(f, "cubic correction coefficient c{index} is not finite")
            }
            CubicCorrectionError::FactorBelowMinimum { u, factor } => {
                write!(f, "the cubic correction's factor is {factor} at u = {u}, below {MIN_CORRECTION_FACTOR}")
            }
            CubicCorrectionError::FactorAboveMaximum { u, factor } => {
                write!(f, "the cubic correction's factor is {factor} at u = {u}, above {MAX_CORRECTION_FACTOR}")
            }
        }
    }
}

impl core::error::Error for CubicCorrectionError {}

/// Why [`CubicLambdaCorrection::fit_within`] keeps the table instead of a cubic.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CubicFitError {
    /// The least-squares cubic leaves the accepted range ([`CubicLambdaCorrection::fit_to_table`]).
    Invalid(CubicCorrectionError),
    /// The cubic deviates from the table by more than the budget (or the budget is NaN).
    OverBudget {
        /// [`CubicLambdaCorrection::deviation_from`] the table.
        deviation: f32,
        /// The budget asked for.
        budget: f32,
    },
}

impl fmt::Display for CubicFitError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CubicFitError::Invalid(error) => error.fmt(f),
            CubicFitError::OverBudget { deviation, budget } => {
                write!(f, "the cubic deviates {deviation} from the table, over the budget {budget}")
            }
        }
    }
}

impl core::error::Error for CubicFitError {}

impl From<CubicCorrectionError> for CubicFitError {
    fn from(error: CubicCorrectionError) -> Self {
        CubicFitError::Invalid(error)
    }
}

gpu_struct! {
    /// A [`CubicLambdaCorrection`] as the GPU reads it ([`CubicLambdaCorrection::to_gpu`]),
    /// the correction argument of the WGSL twins, which assume it came from a validated
    /// correction and do not re-check it. Its field is private: safe Rust gets one only
    /// from [`CubicLambdaCorrection::to_gpu`] (reinterpreting other bytes with `bytemuck`
    /// voids that guarantee).
    pub struct GpuCubicLambdaCorrection {
        /// `(c₀, c₁, c₂, c₃)`.
        coefficients: Vec4,
    }
}

impl CubicLambdaCorrection {
    /// No correction: `c = 1`, and the corrected attribute equals eq. 17.
    pub const IDENTITY: Self = Self { coefficients: [1.0, 0.0, 0.0, 0.0] };

    /// The correction with coefficients `(c₀, c₁, c₂, c₃)`, or why not: a coefficient not
    /// finite, or where `c(u)` leaves `[MIN_CORRECTION_FACTOR, MAX_CORRECTION_FACTOR]` on
    /// `[0, 1]` (checked at the ends and at the roots of `c′` inside, in f64).
    pub fn from_coefficients(coefficients: [f32; 4]) -> Result<Self, CubicCorrectionError> {
        if let Some(index) = coefficients.iter().position(|c| !c.is_finite()) {
            return Err(CubicCorrectionError::CoefficientNotFinite { index });
        }
        let [c0, c1, c2, c3] = coefficients.map(f64::from);
        let value = |u: f64| c0 + u * (c1 + u * (c2 + u * c3));
        // c′(u) = c₁ + 2 c₂ u + 3 c₃ u²: its roots inside (0, 1), in increasing order.
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
                let (r0, r1) = ((-b - root) / (2.0 * a), (-b + root) / (2.0 * a));
                roots = [r0.min(r1), r0.max(r1)];
            }
        }
        let inside = roots.into_iter().filter(|&u| u > 0.0 && u < 1.0);
        for u in core::iter::once(0.0).chain(inside).chain(core::iter::once(1.0)) {
            let factor = value(u);
            if factor < f64::from(MIN_CORRECTION_FACTOR) {
                return Err(CubicCorrectionError::FactorBelowMinimum { u, factor });
            }
            if factor > f64::from(MAX_CORRECTION_FACTOR) {
                return Err(CubicCorrectionError::FactorAboveMaximum { u, factor });
            }
        }
        Ok(Self { coefficients })
    }

    /// The least-squares cubic through the knots of `table` (at `u = i/7`), or why it
    /// leaves the accepted range ([`CubicLambdaCorrection::from_coefficients`]).
    pub fn fit_to_table(table: &LambdaCorrection) -> Result<Self, CubicCorrectionError> {
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
        // The matrix depends on the knots' positions only, and is regular: its solution
        // is finite for finite knots (a non-finite one would be reported below).
        Self::from_coefficients(solve4(normal, rhs).map(|c| c as f32))
    }

    /// The cubic through the knots of `table` ([`CubicLambdaCorrection::fit_to_table`])
    /// when it stays within `budget` of the table ([`CubicLambdaCorrection::deviation_from`],
    /// a fraction of the attribute range), else why not: the cheaper correction where it
    /// adds at most `budget` to the table's error, the table elsewhere.
    pub fn fit_within(table: &LambdaCorrection, budget: f32) -> Result<Self, CubicFitError> {
        let cubic = Self::fit_to_table(table)?;
        let deviation = cubic.deviation_from(table);
        if deviation <= budget { Ok(cubic) } else { Err(CubicFitError::OverBudget { deviation, budget }) }
    }

    /// The largest difference between the visible fraction `x(Λ') = Λ'/(Λ' + 2)` of eq. 17
    /// corrected by this cubic and by `table`, halved: the difference of the two corrected
    /// attributes as a fraction of the attribute range `[ā − a_s, ā + a_s]`, over
    /// `Λ = u/(1 − u)` at 1024 steps of `u` in `[0, 1)` (at `u = 1` both give `x = 1`), the
    /// factors as the corrections evaluate them. Finite: both corrections are valid.
    pub fn deviation_from(&self, table: &LambdaCorrection) -> f32 {
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

    /// `(c₀, c₁, c₂, c₃)`.
    pub fn coefficients(&self) -> [f32; 4] {
        self.coefficients
    }

    /// The correction as the GPU reads it.
    pub fn to_gpu(&self) -> GpuCubicLambdaCorrection {
        GpuCubicLambdaCorrection { coefficients: Vec4::from_array(self.coefficients) }
    }

    /// The factor `c(u)` (Horner's scheme).
    ///
    /// WGSL twin: `smith_cubic_correction_factor`.
    pub fn factor(&self, u: f32) -> f32 {
        let [c0, c1, c2, c3] = self.coefficients;
        c0 + u * (c1 + u * (c2 + u * c3))
    }
}

impl Default for CubicLambdaCorrection {
    fn default() -> Self {
        Self::IDENTITY
    }
}

/// Solves the 4 × 4 system by Gaussian elimination with partial pivoting (a singular
/// matrix gives non-finite values, which the caller rejects).
fn solve4(mut matrix: [[f64; 4]; 4], mut rhs: [f64; 4]) -> [f64; 4] {
    for column in 0..4 {
        let pivot =
            (column..4).max_by(|&a, &b| matrix[a][column].abs().total_cmp(&matrix[b][column].abs())).unwrap_or(column);
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
    solution
}

/// Eq. 17 with the sum corrected by the cubic: `ā + a_s Λ'/(Λ' + 2)`, `Λ' = c(u) Λ`,
/// `Λ = Λ(v) + Λ(l)` (see the module's table). With [`CubicLambdaCorrection::IDENTITY`]
/// this is [`crate::visible_mean_attribute`], bit for bit.
///
/// WGSL twin: `smith_cubic_corrected_visible_mean_attribute`.
pub fn cubic_corrected_visible_mean_attribute(
    attribute: HeightCorrelatedAttribute,
    lambda_view: f32,
    lambda_light: f32,
    correction: &CubicLambdaCorrection,
) -> Option<f32> {
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
        assert_eq!(CubicLambdaCorrection::default(), CubicLambdaCorrection::IDENTITY);
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
        let coefficients = Vec4::from_array(fitted.coefficients());
        assert!((coefficients - expected).abs().max_element() < 1e-4, "{coefficients:?}");
        let attribute = HeightCorrelatedAttribute::new(0.2, 0.7).unwrap();
        for lambda in [0.01_f32, 0.3, 1.0, 4.0, 40.0] {
            let by_table = corrected_visible_mean_attribute(attribute, lambda, 0.0, &table).unwrap();
            let by_cubic = cubic_corrected_visible_mean_attribute(attribute, lambda, 0.0, &fitted).unwrap();
            assert!((by_table - by_cubic).abs() < 2e-3, "Λ = {lambda}: {by_table} {by_cubic}");
        }
        // The identity table gives the identity cubic.
        let identity = CubicLambdaCorrection::fit_to_table(&LambdaCorrection::IDENTITY).unwrap();
        let difference = Vec4::from_array(identity.coefficients()) - Vec4::new(1.0, 0.0, 0.0, 0.0);
        assert!(difference.abs().max_element() < 1e-6);
    }

    #[test]
    fn the_cubic_is_kept_only_within_its_budget() {
        // A smooth table: its cubic deviates little. A table that jumps at grazing (as a
        // cellular texture's fitted table does, 1.16 → 3.5 over the last knot) cannot be
        // followed by a cubic.
        let smooth = LambdaCorrection::from_knots([1.45, 1.33, 1.26, 1.22, 1.20, 1.13, 1.09, 0.93]).unwrap();
        let jump = LambdaCorrection::from_knots([1.09, 1.25, 1.21, 1.15, 1.14, 1.16, 1.57, 3.5]).unwrap();
        let smooth_deviation = CubicLambdaCorrection::fit_to_table(&smooth).unwrap().deviation_from(&smooth);
        let jump_cubic = CubicLambdaCorrection::fit_to_table(&jump).unwrap();
        let jump_deviation = jump_cubic.deviation_from(&jump);
        // Measured 0.0021 and 0.022 (fractions of the attribute range).
        assert!(smooth_deviation < 2.5e-3 && jump_deviation > 1e-2, "{smooth_deviation} {jump_deviation}");
        assert!(CubicLambdaCorrection::fit_within(&smooth, 2.5e-3).is_ok());
        assert_eq!(
            CubicLambdaCorrection::fit_within(&jump, 2.5e-3),
            Err(CubicFitError::OverBudget { deviation: jump_deviation, budget: 2.5e-3 })
        );
        assert!(matches!(
            CubicLambdaCorrection::fit_within(&smooth, f32::NAN),
            Err(CubicFitError::OverBudget { budget, .. }) if budget.is_nan()
        ));
        // The identity's cubic is exact.
        let identity = LambdaCorrection::IDENTITY;
        assert!(CubicLambdaCorrection::fit_to_table(&identity).unwrap().deviation_from(&identity) < 1e-7);
    }

    #[test]
    fn a_valid_table_whose_cubic_leaves_the_range_is_reported() {
        // Seven knots at the lower bound and a jump to the upper one at grazing: the
        // least-squares cubic undershoots the bound between the knots.
        let table = LambdaCorrection::from_knots([0.25, 0.25, 0.25, 0.25, 0.25, 0.25, 0.25, 4.0]).unwrap();
        let error = CubicLambdaCorrection::fit_to_table(&table).unwrap_err();
        let CubicCorrectionError::FactorBelowMinimum { u, factor } = error else { panic!("{error:?}") };
        assert!((0.0..=1.0).contains(&u) && factor < f64::from(MIN_CORRECTION_FACTOR), "{error:?}");
        assert_eq!(CubicLambdaCorrection::fit_within(&table, 1.0), Err(CubicFitError::Invalid(error)));
    }

    #[test]
    fn coefficients_that_leave_the_range_are_rejected_and_say_where() {
        use CubicCorrectionError::{CoefficientNotFinite, FactorAboveMaximum, FactorBelowMinimum};
        assert_eq!(CubicLambdaCorrection::from_coefficients([1.0, 0.0, 0.0, 0.0]), Ok(CubicLambdaCorrection::IDENTITY));
        // Ends in range, but c(1/2) = 1 − 4/2 + 4/4 = 0 dips below 0.25 inside: c′ = 0 at 1/2.
        assert_eq!(
            CubicLambdaCorrection::from_coefficients([1.0, -4.0, 4.0, 0.0]),
            Err(FactorBelowMinimum { u: 0.5, factor: 0.0 })
        );
        // Ends in range, but c(1/2) = 1 + 14/2 − 14/4 = 4.5 peaks above 4 inside.
        assert_eq!(
            CubicLambdaCorrection::from_coefficients([1.0, 14.0, -14.0, 0.0]),
            Err(FactorAboveMaximum { u: 0.5, factor: 4.5 })
        );
        assert_eq!(
            CubicLambdaCorrection::from_coefficients([0.2, 0.0, 0.0, 0.0]),
            Err(FactorBelowMinimum { u: 0.0, factor: f64::from(0.2_f32) })
        );
        assert_eq!(
            CubicLambdaCorrection::from_coefficients([4.0, 0.5, 0.0, 0.0]),
            Err(FactorAboveMaximum { u: 1.0, factor: 4.5 })
        );
        for (index, bad) in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY, -f32::NAN].into_iter().enumerate() {
            let mut coefficients = [1.0, 0.0, 0.0, 0.0];
            coefficients[index] = bad;
            assert_eq!(
                CubicLambdaCorrection::from_coefficients(coefficients),
                Err(CoefficientNotFinite { index }),
                "{bad}"
            );
        }
        // An accepted cubic may touch the bounds: c = 0.25 + 15 u (1 − u) is 4 at u = 1/2.
        let touching = CubicLambdaCorrection::from_coefficients([0.25, 15.0, -15.0, 0.0]).unwrap();
        assert_eq!(touching.factor(0.5), 4.0);
        assert_eq!(touching.coefficients(), [0.25, 15.0, -15.0, 0.0]);
        let floats: [f32; 4] = bytemuck::cast(touching.to_gpu());
        assert_eq!(floats, touching.coefficients());
    }

    #[test]
    fn special_inputs_have_defined_results() {
        let correction = CubicLambdaCorrection::from_coefficients([1.4, -0.9, 0.8, -0.5]).unwrap();
        let attribute = HeightCorrelatedAttribute::new(0.5, -0.2).unwrap();
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
