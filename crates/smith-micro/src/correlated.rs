//! The corrected visibility model with a light–view correlation term, kept beside eq. 17:
//! `ā(v, l) = ā + a_s Λ'/(Λ' + 2)` with
//!
//! `Λ' = A + B − ρ(cos Δφ) min(A, B)`, `A = c_v(u_v) Λ(v)`, `B = c_l(u_l) Λ(l)`,
//! `ρ(c) = ρ₀ + ρ₁ c + ρ₂ c²` clamped to `[MIN_CORRELATION, MAX_CORRELATION] = [−2, 2]`,
//!
//! where `c_v` and `c_l` are two per-material [`LambdaCorrection`] tables (`u = Λ/(1+Λ)`)
//! and `Δφ` is the azimuth difference between the view and the light.
//!
//! # Derivation
//!
//! Eq. 17 weighs a point at height `h` by `p(h) V(v,h) V(l,h)` and integrates; with
//! `V(ω,h) = g(h)^Λ(ω)` the product is `g^(Λ(v)+Λ(l))`, i.e. eq. 17 is already the
//! attribute analogue of Heitz 2014's *height-correlated* masking–shadowing
//! `G₂ = 1/(1 + Λ(v) + Λ(l))` (both factors conditioned on the same height). What eq. 17
//! leaves out is measured by ray tracing (`microsurface-truth`, `cargo xtask fig9`):
//!
//! 1. Seen from `v`, points are weighted by their projected area, so the visible set at
//!    a height is enriched in facets turned toward `v` — and these are the ones whose
//!    surroundings drop away along `v` (Smith assumes the occlusion along the ray is
//!    independent of the slope at its origin). A fitted factor `c_v(u)` on `Λ(v)`
//!    absorbs this for view-only sweeps ([`crate::correction`]).
//! 2. The *lit* points of what the eye sees are not weighted by their projected area
//!    toward the light: at normal view, the lit set sits markedly higher than the set
//!    seen from the light direction (measured factor ≈ 2 at `Λ = 0.05` on Gaussian
//!    surfaces, against ≈ 1.45 for the view). Hence a second table `c_l`, fitted on
//!    sweeps of the light at normal view, where `Λ' = B` exactly.
//! 3. Visibility and lighting are correlated through the direction, as in Heitz 2014's
//!    *height-direction-correlated* form `G₂ = 1/(1 + max(Λv,Λl) + λ(φ) min(Λv,Λl))`,
//!    which is `A + B − (1 − λ) min(A, B)`: with `ρ = 1 − λ`, `ρ = 1` (same azimuth:
//!    what is seen is mostly lit) gives `max(A, B)`, `ρ = 0` the height-correlated sum.
//!    Ray tracing (Gaussian surfaces, 1024²) asks for `ρ ≈ 0.1–0.4` at `Δφ = 90°`, for
//!    `ρ ≤ 0` at 180° (facets turned toward the eye are turned away from a light behind
//!    it, so fewer of the low visible points are lit than independence predicts), and
//!    for `ρ ≥ 1` at `Δφ = 0` (the tops seen at grazing angles include facets turned away
//!    from a light on the same side, which are self-shadowed: visible-and-lit points sit
//!    *lower* than visible ones, `Λ' < max(A, B)`, which `ρ ≤ 1` cannot reach). A
//!    quadratic in `cos Δφ` (three coefficients per material) follows this on average;
//!    Ginneken's `λ(φ) = 4.41φ/(4.41φ + 1)` cannot (it keeps `ρ` in `[0, 1]`).
//! 4. Ginneken's shape has one thing right: the correlation is *peaked* at `Δφ = 0`. On a
//!    narrow band-pass spectrum with a grazing light (75–82°) and view, the ray-traced
//!    `ρ` is about 1 at `Δφ = 0`, 0.1–0.35 at 45° and 0.3–0.8 at 90–180° (a 512² grid of
//!    view angle × light angle × `Δφ`, `examples/light_grid.rs` in `microsurface-truth`),
//!    which no quadratic in `cos Δφ` follows. A fourth term `ρ₃ ((1 + c)/2)⁸` (1 at
//!    `Δφ = 0`, 0.28 at 45°, 0.004 at 90°) lowers the RMS error on that grid by 4–35 %
//!    (in-sample; band-pass 0.77 % → 0.50 %), but it was measured to change nothing on
//!    the sweeps of `cargo xtask fig9` (light at 60°; the fit's lights are at 55° and
//!    72°, where the peak is weak: fitted `ρ₃` = 0.07 on the band-pass surface), so it
//!    is not part of the model: it would cost about seven operations for no measured
//!    gain. A fit with grazing lights and such a sweep would be the place to revisit it.
//!
//! `ρ` is clamped to `[−2, 2]`: `ρ ≤ 2` is the bound that keeps `Λ' ≥ |A − B| ≥ 0`
//! (a visible-and-lit set can sit lower than either set alone, down to eq. 17's
//! `Λ = 0`, the mean); `ρ ≥ −2` keeps `Λ' ≤ A + B + 2 min(A, B)`. An earlier bound
//! `ρ ≤ 1` (`Λ' ≥ max(A, B)`) cut off what the ray-traced data ask for: `ρ ≈ 1–2` at the
//! same azimuth when the two Λs differ, and on the cellular texture `ρ ≈ 1–2.6` at
//! opposite azimuths (the tops of convex cells are seen and lit from both sides). With
//! that bound the fit compromised elsewhere and the cellular texture at `Δφ = 180°` came
//! out worse than eq. 17 (3.40 % against 2.17 %, `cargo xtask fig9`, 1024²).
//!
//! Measured by `cargo xtask fig9` (1024², 200 000 rays per view angle, 100 000 with a
//! light; Gaussian surfaces fitted on two other realizations, textures on their own map
//! with other rays and lights): max error 0–85° in % of the attribute range, eq. 17 →
//! corrected, view only / light at 60° and 90°, 0°, 180° from the view:
//!
//! | surface | view | light 90° | 0° | 180° |
//! |---|---|---|---|---|
//! | Gaussian ℓ = 16 | 2.19 → 0.16 | 2.15 → 0.30 | 1.59 → 0.66 | 3.85 → 0.63 |
//! | fBm | 3.73 → 0.17 | 4.00 → 0.33 | 3.92 → 0.38 | 1.83 → 1.27 |
//! | band-pass | 3.30 → 0.12 | 3.30 → 0.88 | 2.60 → 0.72 | 3.59 → 1.22 |
//! | cellular (texture) | 1.46 → 0.42 | 1.81 → 0.65 | 1.14 → 0.42 | 2.17 → 2.09 |
//! | ridged (texture) | 2.63 → 0.23 | 2.90 → 0.39 | 2.16 → 1.07 | 5.79 → 1.62 |
//!
//! The corrected model is better than eq. 17 on every surface and sweep (on the cellular
//! texture at 180° only just). Limits: the quadratic `ρ` is a compromise over the
//! azimuth differences, so the same- and opposite-azimuth sweeps keep up to 1.1 % and
//! 2.1 %; the band-pass spectrum keeps 0.88 % at `Δφ = 90°`, where its error peaks with
//! the view as high as the light (60–65°): its ray-traced `ρ` grows with `Λ(v)/Λ(l)`
//! (0–0.3 at similar elevations, 0.7–1 with the view 20–25° nearer grazing than the
//! light; 512² grid), which `ρ(cos Δφ)` does not see. A term `ρ₃ t (1 − c)`,
//! `t = (A − B)/(A + B)`, fitted on lights at 50° and 70° and evaluated at 60° (1024²,
//! `examples/light_grid.rs`), brings the band-pass error at 90° from 0.68 % to 0.49 %
//! there but its worst azimuth only from 1.54 % to 1.32 %; in the full fit and the fig9
//! sweeps (1024², 100 000 rays, `examples/light_eval.rs`) it moves the band-pass errors
//! at 90°/180° from 0.93/1.28 % to 0.83/0.95 % but makes the 90° sweep worse on the
//! Gaussian (0.41 → 0.46 %), fBm (0.24 → 0.33 %) and cellular (0.66 → 0.73 %) surfaces:
//! not the ≤ 0.5 % asked for, and not better everywhere, so it is not part of the model.
//! The fit
//! (`microsurface-truth`'s `fit_visibility_correction`) shrinks the model toward eq. 17
//! as far as held-out samples ask, eq. 17 itself included.
//!
//! Cost in WGSL over eq. 17, counted on naga's IR (`wgsl_gen::operation_count`, test
//! `smith_micro_cost` in `shader-registry`; arithmetic per component, indexed loads and
//! branches, callees inlined): eq. 17 61 operations, the corrected model
//! (`smith_correlated_visible_mean_attribute`) 114, 53 more than eq. 17 (two table
//! lookups with their `Λ/(1 + Λ)` divisions, about 16 each; `ρ` from `cos Δφ` with its
//! special cases; `min`, the combination and three flushes of subnormals). The model is
//! not validated on the GPU: a [`VisibilityCorrection`] is valid by construction (its
//! tables are [`LambdaCorrection`]s, its coefficients are checked by
//! [`VisibilityCorrection::new`], [`VisibilityCorrectionError`] naming the one it
//! rejects), and the GPU reads it as a [`GpuVisibilityCorrection`]
//! ([`VisibilityCorrection::to_gpu`]). Before the type guaranteed it, the WGSL twin
//! re-validated the 16 knots and 3 coefficients on every call (167 operations). The
//! view-only correction on the sum ([`crate::corrected_visible_mean_attribute`], one
//! table) costs 22 more than eq. 17. The caller supplies `cos Δφ` (102 operations from
//! two directions; [`correlated_visible_mean_attribute_for_directions`] computes it).
//!
//! | input | result |
//! |---|---|
//! | [`VisibilityCorrection::IDENTITY`], normal (not subnormal) Λs | eq. 17, bit for bit |
//! | `Λ(v) = 0` or `Λ(l) = 0` | `ā + a_s x(B)` or `ā + a_s x(A)`: `ρ` plays no role |
//! | a Λ `= +∞` or above `MAX_CORRECTED_LAMBDA` | `ā + a_s` |
//! | `cos Δφ` NaN | treated as 0; outside `[−1, 1]` clamped |
//! | a Λ negative or NaN | `None` |
//!
//! | coefficient `ρᵢ` given to [`VisibilityCorrection::new`] | result |
//! |---|---|
//! | all three at most [`MAX_CORRELATION_COEFFICIENT`] in magnitude | the model |
//! | `ρᵢ` NaN | [`VisibilityCorrectionError::CoefficientNotANumber`] |
//! | `|ρᵢ|` above `MAX_CORRELATION_COEFFICIENT` (±∞ included) | [`VisibilityCorrectionError::CoefficientTooLarge`] |

use core::fmt;

use glam::{Vec3, Vec4};
use gpu_layout::gpu_struct;

use crate::attribute::{HeightCorrelatedAttribute, visible_fraction_of_finite};
use crate::correction::{LambdaCorrection, corrected_lambda};
use crate::erf::{flush_subnormal, is_infinite_bits, is_nan_bits};
use crate::masking::{SlopeDeviation, smith_lambda_direction};

/// Smallest `ρ` after clamping: `Λ' ≤ A + B + 2 min(A, B)`, finite.
pub const MIN_CORRELATION: f32 = -2.0;
/// Largest `ρ` after clamping: `Λ' ≥ A + B − 2 min(A, B) = |A − B| ≥ 0`.
pub const MAX_CORRELATION: f32 = 2.0;
/// Largest accepted magnitude of a `ρ` coefficient.
pub const MAX_CORRELATION_COEFFICIENT: f32 = 16.0;

/// A per-material corrected visibility model (see the module documentation): the view
/// table `c_v`, the light table `c_l` (each a [`LambdaCorrection`]: factors at `u = i/7`)
/// and the coefficients of `ρ(cos Δφ)`, each at most [`MAX_CORRELATION_COEFFICIENT`] in
/// magnitude. Built only by [`VisibilityCorrection::new`] and
/// [`VisibilityCorrection::IDENTITY`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VisibilityCorrection {
    view: LambdaCorrection,
    light: LambdaCorrection,
    correlation: [f32; 3],
}

/// Why [`VisibilityCorrection::new`] rejected its coefficients: the first invalid one, by
/// index (`ρ₀, ρ₁, ρ₂`). The tables cannot be invalid: they are [`LambdaCorrection`]s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum VisibilityCorrectionError {
    /// `ρ_index` is NaN.
    CoefficientNotANumber {
        /// The coefficient's index.
        index: usize,
    },
    /// `|ρ_index|` is above [`MAX_CORRELATION_COEFFICIENT`] (±∞ included).
    CoefficientTooLarge {
        /// The coefficient's index.
        index: usize,
        /// Its value.
        value: f32,
    },
}

impl fmt::Display for VisibilityCorrectionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            VisibilityCorrectionError::CoefficientNotANumber { index } => {
                write!(f, "correlation coefficient ρ{index} is NaN")
            }
            VisibilityCorrectionError::CoefficientTooLarge { index, value } => write!(
                f,
                "correlation coefficient ρ{index} is {value}, above {MAX_CORRELATION_COEFFICIENT} in magnitude"
            ),
        }
    }
}

impl core::error::Error for VisibilityCorrectionError {}

gpu_struct! {
    /// A [`VisibilityCorrection`] as the GPU reads it ([`VisibilityCorrection::to_gpu`]),
    /// the model argument of the WGSL twins, which assume it came from a validated model
    /// and do not re-check it. Its fields are private: safe Rust gets one only from
    /// [`VisibilityCorrection::to_gpu`] (reinterpreting other bytes with `bytemuck` voids
    /// that guarantee).
    pub struct GpuVisibilityCorrection {
        /// `c_v` at knots 0 … 3.
        view_low: Vec4,
        /// `c_v` at knots 4 … 7.
        view_high: Vec4,
        /// `c_l` at knots 0 … 3.
        light_low: Vec4,
        /// `c_l` at knots 4 … 7.
        light_high: Vec4,
        /// `(ρ₀, ρ₁, ρ₂, 0)`: `ρ(c) = ρ₀ + ρ₁ c + ρ₂ c²`, `c = cos Δφ`.
        correlation: Vec4,
    }
}

impl VisibilityCorrection {
    /// No correction: eq. 17 (both tables the identity, `ρ = 0`).
    pub const IDENTITY: Self =
        Self { view: LambdaCorrection::IDENTITY, light: LambdaCorrection::IDENTITY, correlation: [0.0; 3] };

    /// The model from its tables and `(ρ₀, ρ₁, ρ₂)`, or the first coefficient that is NaN
    /// or above [`MAX_CORRELATION_COEFFICIENT`] in magnitude, and why.
    pub fn new(
        view: LambdaCorrection,
        light: LambdaCorrection,
        correlation: [f32; 3],
    ) -> Result<Self, VisibilityCorrectionError> {
        for (index, &value) in correlation.iter().enumerate() {
            if is_nan_bits(value) {
                return Err(VisibilityCorrectionError::CoefficientNotANumber { index });
            }
            if value.abs() > MAX_CORRELATION_COEFFICIENT {
                return Err(VisibilityCorrectionError::CoefficientTooLarge { index, value });
            }
        }
        Ok(Self { view, light, correlation })
    }

    /// The view table `c_v`.
    pub fn view(&self) -> LambdaCorrection {
        self.view
    }

    /// The light table `c_l`.
    pub fn light(&self) -> LambdaCorrection {
        self.light
    }

    /// `(ρ₀, ρ₁, ρ₂)`.
    pub fn correlation_coefficients(&self) -> [f32; 3] {
        self.correlation
    }

    /// The model as the GPU reads it: each table as [`LambdaCorrection::to_gpu`] lays it
    /// out, then `(ρ₀, ρ₁, ρ₂, 0)`.
    pub fn to_gpu(&self) -> GpuVisibilityCorrection {
        let (view, light) = (self.view.to_gpu(), self.light.to_gpu());
        let [r0, r1, r2] = self.correlation;
        GpuVisibilityCorrection {
            view_low: view.low,
            view_high: view.high,
            light_low: light.low,
            light_high: light.high,
            correlation: Vec4::new(r0, r1, r2, 0.0),
        }
    }

    /// `ρ(cos Δφ)`, clamped to `[MIN_CORRELATION, MAX_CORRELATION]` (`cos Δφ` clamped to
    /// `[−1, 1]`, NaN read as 0).
    ///
    /// WGSL twin: `smith_view_light_correlation`.
    pub fn correlation_at(&self, cos_azimuth_difference: f32) -> f32 {
        let c = if is_nan_bits(cos_azimuth_difference) { 0.0 } else { cos_azimuth_difference.clamp(-1.0, 1.0) };
        let [r0, r1, r2] = self.correlation;
        (r0 + c * (r1 + c * r2)).clamp(MIN_CORRELATION, MAX_CORRELATION)
    }
}

impl Default for VisibilityCorrection {
    fn default() -> Self {
        Self::IDENTITY
    }
}

/// The corrected and correlated `Λ' = A + B − ρ min(A, B)` (see the module
/// documentation): `None` for a negative or NaN Λ, `+∞` when `A` or `B` is.
///
/// WGSL twin: `smith_correlated_lambda`.
pub fn correlated_lambda(
    lambda_view: f32,
    lambda_light: f32,
    cos_azimuth_difference: f32,
    correction: &VisibilityCorrection,
) -> Option<f32> {
    let view = corrected_lambda(lambda_view, &correction.view)?;
    let light = corrected_lambda(lambda_light, &correction.light)?;
    if is_infinite_bits(view) || is_infinite_bits(light) {
        return Some(f32::INFINITY);
    }
    // Both ≤ 4·2⁶⁴ and ρ ∈ [−2, 2]: no overflow, and Λ' ≥ 0: rounding is monotonic and
    // 2 min(A, B) ≤ A + B is exact, so fl(A + B) ≥ fl(ρ min(A, B)) (also fused, on a GPU).
    let rho = correction.correlation_at(cos_azimuth_difference);
    Some(flush_subnormal((view + light) - rho * view.min(light)))
}

/// The corrected, correlated mean visible attribute `ā + a_s Λ'/(Λ' + 2)` (see the
/// module's table).
///
/// WGSL twin: `smith_correlated_visible_mean_attribute`.
pub fn correlated_visible_mean_attribute(
    attribute: HeightCorrelatedAttribute,
    lambda_view: f32,
    lambda_light: f32,
    cos_azimuth_difference: f32,
    correction: &VisibilityCorrection,
) -> Option<f32> {
    let lambda = correlated_lambda(lambda_view, lambda_light, cos_azimuth_difference, correction)?;
    // As eq. 17: 0 gives 0, ∞ gives 1, a normal Λ' keeps 2/Λ' finite.
    let visible_fraction = if is_infinite_bits(lambda) { 1.0 } else { visible_fraction_of_finite(lambda) };
    Some(attribute.at(visible_fraction))
}

/// `cos Δφ` between the azimuths of `view` and `light` (their xy projections), 1 when
/// either projection is zero (a direction along the normal, whose Λ is 0), 0 when either
/// is not finite.
///
/// WGSL twin: `smith_cos_azimuth_difference`.
pub fn cos_azimuth_difference(view: Vec3, light: Vec3) -> f32 {
    if !(view.x.is_finite() && view.y.is_finite() && light.x.is_finite() && light.y.is_finite()) {
        return 0.0;
    }
    // Subnormals flushed (as the GPU does), then each projection scaled by its largest
    // component: no overflow or underflow of the squares.
    let scaled = |x: f32, y: f32| {
        let (x, y) = (flush_subnormal(x), flush_subnormal(y));
        let largest = x.abs().max(y.abs());
        (largest > 0.0).then(|| (flush_subnormal(x / largest), flush_subnormal(y / largest)))
    };
    match (scaled(view.x, view.y), scaled(light.x, light.y)) {
        (Some((ax, ay)), Some((bx, by))) => {
            let dot = ax * bx + ay * by;
            let lengths = libm::sqrtf(ax * ax + ay * ay) * libm::sqrtf(bx * bx + by * by);
            flush_subnormal((dot / lengths).clamp(-1.0, 1.0))
        }
        _ => 1.0,
    }
}

/// [`correlated_visible_mean_attribute`] for a view and a light direction in the
/// mean-normal frame over slopes `slopes`: `None` when a direction is below the
/// horizon, zero or not finite.
pub fn correlated_visible_mean_attribute_for_directions(
    attribute: HeightCorrelatedAttribute,
    view: Vec3,
    light: Vec3,
    slopes: SlopeDeviation,
    correction: &VisibilityCorrection,
) -> Option<f32> {
    let lambda_view = smith_lambda_direction(view, slopes)?;
    let lambda_light = smith_lambda_direction(light, slopes)?;
    let cos = cos_azimuth_difference(view, light);
    correlated_visible_mean_attribute(attribute, lambda_view, lambda_light, cos, correction)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attribute::visible_mean_attribute;

    fn model(rho: [f32; 3]) -> VisibilityCorrection {
        let view = LambdaCorrection::from_knots([1.5, 1.4, 1.3, 1.25, 1.2, 1.15, 1.1, 1.0]).unwrap();
        let light = LambdaCorrection::from_knots([2.2, 2.0, 1.6, 1.4, 1.3, 1.2, 1.1, 1.0]).unwrap();
        VisibilityCorrection::new(view, light, rho).unwrap()
    }

    #[test]
    fn identity_is_eq17_bit_for_bit() {
        let attribute = HeightCorrelatedAttribute::new(0.4, 0.3).unwrap();
        let mut lambdas: std::vec::Vec<f32> = (0..300).map(|i| 1e-4 * 1.06_f32.powi(i)).collect();
        lambdas.extend([0.0, f32::MIN_POSITIVE, 1e19, 3e30, f32::MAX, f32::INFINITY]);
        for &view in &lambdas {
            for &light in lambdas.iter().step_by(7) {
                for cos in [-1.0, 0.0, 0.7, 1.0] {
                    let eq17 = visible_mean_attribute(attribute, view, light).map(f32::to_bits);
                    let model =
                        correlated_visible_mean_attribute(attribute, view, light, cos, &VisibilityCorrection::IDENTITY);
                    assert_eq!(model.map(f32::to_bits), eq17, "Λ = {view} + {light}");
                }
            }
        }
    }

    #[test]
    fn correlation_interpolates_between_max_and_sum() {
        let full = model([1.0, 0.0, 0.0]);
        let none = model([0.0, 0.0, 0.0]);
        let (a, b) = (corrected_lambda(0.3, &full.view()).unwrap(), corrected_lambda(0.2, &full.light()).unwrap());
        assert_eq!(correlated_lambda(0.3, 0.2, 0.3, &full), Some(a.max(b)));
        assert_eq!(correlated_lambda(0.3, 0.2, 0.3, &none), Some(a + b));
        // ρ = 0.5 + 0.25 c + 0.25 c²: 1 at c = 1, 0.5 at c = 0, 0.5 at c = −1.
        let quadratic = model([0.5, 0.25, 0.25]);
        assert_eq!(quadratic.correlation_at(1.0), 1.0);
        assert_eq!(quadratic.correlation_at(0.0), 0.5);
        assert_eq!(quadratic.correlation_at(-1.0), 0.5);
        assert_eq!(quadratic.correlation_at(f32::NAN), 0.5);
        assert_eq!(quadratic.correlation_at(5.0), 1.0);
        // Clamped to [−2, 2].
        assert_eq!(model([-9.0, 0.0, 0.0]).correlation_at(0.0), MIN_CORRELATION);
        assert_eq!(model([9.0, 0.0, 0.0]).correlation_at(0.0), MAX_CORRELATION);
        // A negative ρ sees higher points than the sum.
        let anti = model([-0.9, 0.0, 0.0]);
        let attribute = HeightCorrelatedAttribute::new(0.0, 1.0).unwrap();
        let sum = correlated_visible_mean_attribute(attribute, 0.3, 0.2, -1.0, &none).unwrap();
        assert!(correlated_visible_mean_attribute(attribute, 0.3, 0.2, -1.0, &anti).unwrap() > sum);
    }

    #[test]
    fn the_largest_correlation_keeps_lambda_non_negative() {
        let anti = model([16.0, 0.0, 0.0]);
        assert_eq!(anti.correlation_at(0.3), 2.0);
        let (view, light) = (anti.view(), anti.light());
        for i in 0..400 {
            let lambda_view = 1e-4 * 1.05_f32.powi(i);
            for j in (0..400).step_by(3) {
                let lambda_light = 1e-4 * 1.05_f32.powi(j);
                let (a, b) =
                    (corrected_lambda(lambda_view, &view).unwrap(), corrected_lambda(lambda_light, &light).unwrap());
                let lambda = correlated_lambda(lambda_view, lambda_light, 0.3, &anti).unwrap();
                // ρ = 2: Λ' = |A − B| up to the rounding of A + B.
                assert!(lambda >= 0.0 && (lambda - (a - b).abs()).abs() <= 1e-6 * (a + b), "{a} {b}: {lambda}");
            }
        }
    }

    #[test]
    fn one_direction_at_the_normal_uses_the_other_table_alone() {
        let m = model([0.7, 0.2, -0.1]);
        for lambda in [0.01_f32, 0.3, 2.0, 40.0] {
            let light_only = correlated_lambda(0.0, lambda, -0.4, &m).unwrap();
            assert_eq!(light_only, corrected_lambda(lambda, &m.light()).unwrap());
            let view_only = correlated_lambda(lambda, 0.0, 0.9, &m).unwrap();
            assert_eq!(view_only, corrected_lambda(lambda, &m.view()).unwrap());
        }
    }

    #[test]
    fn special_inputs_have_defined_results() {
        let m = model([0.3, 0.9, -0.9]);
        let attribute = HeightCorrelatedAttribute::new(0.5, -0.2).unwrap();
        assert_eq!(correlated_visible_mean_attribute(attribute, 0.0, 0.0, 0.0, &m), Some(0.5));
        assert_eq!(correlated_visible_mean_attribute(attribute, f32::INFINITY, 0.1, 0.0, &m), Some(0.3));
        assert_eq!(correlated_visible_mean_attribute(attribute, 0.1, f32::MAX, 0.0, &m), Some(0.3));
        assert_eq!(correlated_visible_mean_attribute(attribute, -1.0, 0.1, 0.0, &m), None);
        assert_eq!(correlated_visible_mean_attribute(attribute, 0.1, f32::NAN, 0.0, &m), None);
        // Every accepted input gives a finite value between ā and ā + a_s.
        let extreme = VisibilityCorrection::new(
            LambdaCorrection::from_knots([4.0; 8]).unwrap(),
            LambdaCorrection::from_knots([4.0; 8]).unwrap(),
            [-16.0, 0.0, 0.0],
        )
        .unwrap();
        for view in [0.0_f32, 1e-40, 1e-3, 1.0, 1e19, f32::MAX] {
            for light in [0.0_f32, 1e-40, 0.5, 1e19, f32::MAX] {
                for cos in [-1.0_f32, 0.0, 1.0, f32::NAN, f32::INFINITY] {
                    let value = correlated_visible_mean_attribute(attribute, view, light, cos, &extreme).unwrap();
                    assert!(value.is_finite() && (0.3..=0.5).contains(&value), "{view} {light} {cos}: {value}");
                }
            }
        }
    }

    #[test]
    fn invalid_coefficients_are_rejected_by_index_value_and_reason() {
        use VisibilityCorrectionError::{CoefficientNotANumber, CoefficientTooLarge};
        let m = model([0.3, 0.9, -0.9]);
        for index in 0..3 {
            let with = |value: f32| {
                let mut rho = [0.0; 3];
                rho[index] = value;
                VisibilityCorrection::new(m.view(), m.light(), rho)
            };
            assert_eq!(with(f32::NAN), Err(CoefficientNotANumber { index }));
            for value in [16.000_002, -16.000_002, 17.0, f32::INFINITY, f32::NEG_INFINITY, f32::MAX] {
                assert_eq!(with(value), Err(CoefficientTooLarge { index, value }), "{value}");
            }
            for value in [MAX_CORRELATION_COEFFICIENT, -MAX_CORRELATION_COEFFICIENT, -1e-40, 0.0] {
                assert_eq!(with(value).map(|model| model.correlation_coefficients()[index]), Ok(value));
            }
        }
        // The first invalid coefficient is reported; the tables come through unchanged.
        assert_eq!(
            VisibilityCorrection::new(m.view(), m.light(), [0.0, 20.0, f32::NAN]),
            Err(CoefficientTooLarge { index: 1, value: 20.0 })
        );
        assert_eq!((m.view(), m.light()), (model([0.0; 3]).view(), model([0.0; 3]).light()));
        assert_eq!(VisibilityCorrection::default(), VisibilityCorrection::IDENTITY);
    }

    #[test]
    fn the_gpu_form_holds_both_tables_then_the_coefficients() {
        let m = model([0.3, 0.9, -0.9]);
        let floats: [f32; 20] = bytemuck::cast(m.to_gpu());
        assert_eq!(floats[..8], m.view().knots());
        assert_eq!(floats[8..16], m.light().knots());
        assert_eq!(floats[16..], [0.3, 0.9, -0.9, 0.0]);
    }

    #[test]
    fn azimuth_difference_of_directions() {
        let cos = |a: Vec3, b: Vec3| cos_azimuth_difference(a, b);
        assert_eq!(cos(Vec3::new(1.0, 0.0, 1.0), Vec3::new(3.0, 0.0, 0.2)), 1.0);
        assert_eq!(cos(Vec3::new(1.0, 0.0, 1.0), Vec3::new(-3.0, 0.0, 0.2)), -1.0);
        assert!(cos(Vec3::new(1.0, 0.0, 1.0), Vec3::new(0.0, 2.0, 0.2)).abs() < 1e-7);
        assert!((cos(Vec3::new(1.0, 1.0, 1.0), Vec3::new(0.0, 2.0, 0.2)) - 0.5_f32.sqrt()).abs() < 1e-6);
        assert_eq!(cos(Vec3::Z, Vec3::new(0.0, 2.0, 0.2)), 1.0);
        assert_eq!(cos(Vec3::new(1e-30, 1e-30, 1.0), Vec3::new(3e30, -3e30, 1.0)).to_bits(), 0.0_f32.to_bits());
        assert_eq!(cos(Vec3::new(f32::NAN, 0.0, 1.0), Vec3::Z), 0.0);
        let slopes = SlopeDeviation::new(0.5, 0.5).unwrap();
        let attribute = HeightCorrelatedAttribute::new(0.0, 1.0).unwrap();
        let below = Vec3::new(0.0, 1.0, -0.1);
        assert_eq!(
            correlated_visible_mean_attribute_for_directions(attribute, Vec3::Z, below, slopes, &model([0.0; 3])),
            None
        );
    }
}
