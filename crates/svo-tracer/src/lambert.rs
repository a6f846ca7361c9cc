//! The Lambert term of a voxel: the expected clamped cosine `⟨(m·l)₊⟩` over the visible part
//! of its Gaussian distribution of micro-normals, in place of the clamped cosine of the mean
//! normal `(n̄·l)₊`.
//!
//! # Why
//!
//! Eq. 13 writes the element's radiance with the mean cosine of the light over the
//! element's microsurface. The clamp `x ↦ max(0, x)` is convex, so the mean of the clamped
//! cosines is at least the clamped cosine of the mean (Jensen): under a grazing light a
//! coarse voxel of bumps has facets turned towards the light that are lit far more than
//! `n̄·l` says, and `(n̄·l)₊` renders it too dark (19 % colour error on the bumpy sphere of
//! `svo-render`'s tests, as wide lens cones read coarse levels). And at a grazing view the
//! facets turned towards the eye fill more of the footprint, which eq. 14 weights by their
//! projected area `v·n(x)`: their cosine to the light counts more.
//!
//! # The closed form (H3, H4, §5.2, §5.5, eq. 14)
//!
//! §5.2 and §5.5 describe the micro-normals as a Gaussian lobe `N(n̄, σn²)` of slopes
//! (H3: a Gaussian surface). In `n̄`'s frame the slopes are `s = (s₁, s₂) ~ N(0, σ² I)`
//! (`σ² = σn²`, isotropic, per macroscopic area) and the micro-normal is
//! `m = m̃/|m̃|`, `m̃ = (−s₁, −s₂, 1)`. A facet's projected area towards `v` per macroscopic
//! area is `m̃·v` exactly (its micro-area `|m̃|` times its cosine `m·v`), so weighting the
//! facets as eq. 14 does — projected area, times Smith's visibilities, which depend on the
//! height only (H4) and cancel between numerator and denominator — the element's Lambert
//! term is
//!
//! ```text
//! C = E_s[(N_v)₊ (N_l)₊ / |m̃|] / E_s[(N_v)₊],   N_d = m̃·d = d_z − s·d_⊥
//! ```
//!
//! (`(N_v)₊`: facets turned away from the eye are not seen). Both `N_v` and `N_l` are linear
//! in the slopes, hence exactly jointly Gaussian: means `μ_d = d_z`, deviations
//! `τ_d = σ |d_⊥|`, covariance `c = σ² v_⊥·l_⊥`, correlation `ρ = c/(τ_v τ_l)`. Then:
//!
//! - `E[N₊] = μ Φ(k) + τ φ(k)`, `k = μ/τ` (the rectified mean; `Φ`, `φ` the standard normal
//!   distribution and density, `Φ(k) = ½ erfc(−k/√2)` through `smith_micro::erfc`, the same
//!   approximation on the CPU and the GPU). For the view it is Smith's `v_z (1 + Λ(v))`.
//! - `E[(N_v)₊ (N_l)₊]`: by Price's theorem `∂E[X₊Y₊]/∂c = P(X > 0, Y > 0) = Φ₂(a, b; r)`
//!   (`a = k_v`, `b = k_l`), integrated from the independent value `E[X₊] E[Y₊]` at `c = 0`
//!   with the tetrachoric series `Φ₂(a, b; r) = Φ(a)Φ(b) + φ(a)φ(b) Σ_{j≥1} r^j/j!
//!   He_{j−1}(a) He_{j−1}(b)` (Hermite polynomials), kept to `j = 4`:
//!   `E[X₊Y₊] ≈ E[X₊]E[Y₊] + τ_v τ_l (ρ Φ(a)Φ(b) + φ(a)φ(b) (ρ²/2 + ρ³ ab/6 +
//!   ρ⁴ (a² − 1)(b² − 1)/24 + ρ⁵ (a³ − 3a)(b³ − 3b)/120))`, clamped at 0.
//! - The normalisation `1/|m̃| = 1/√(1 + |s|²)` is replaced by `1/√E[1 + |s|²] =
//!   1/√(1 + 2σ²)`. Both are `1 − σ² + O(σ⁴)` under a frontal view and light
//!   (`E[(1 + |s|²)^{−½}] = 1 − σ² + O(σ⁴)` for `|s|²/σ²` a χ² of two degrees).
//!
//! ```text
//! C ≈ E[(N_v)₊ (N_l)₊] / (E[(N_v)₊] √(1 + 2σ²))
//! ```
//!
//! Special cases, each exact where the derivation is: `σ = 0` (the finest level, the ground
//! truth's unfiltered surface and [`Filtering::Separate`]) returns `max(n̄·l, 0)` itself, bit
//! for bit; a view along `n̄` (`τ_v = 0`) gives `E[(N_l)₊]/√(1 + 2σ²)` (every facet is seen
//! alike) and so does a light along `n̄` (`τ_l = 0`: `N_l` is the constant `l_z`); beyond
//! `|k| ≥ √2` [`RECTIFIED_CUTOFF`] a Gaussian lies on one side of 0 to f32 precision
//! (`erfc(10) < 3·10⁻⁴⁵`): its rectified mean is `max(μ, 0)` and its density terms vanish; a
//! view whose rectified mean vanishes (far below the mean horizon) falls back on the
//! view-independent form.
//!
//! What it leaves out: the local shadowing of the lit facets by their neighbours (Smith's
//! `1/(1 + Λ(l))`), which eq. 13 does not put in the diffuse term either (eq. 14's `ā(v, l)`
//! is a mean over the lit and visible area, not the lit fraction).
//!
//! [`Filtering::Separate`]: crate::Filtering::Separate

use glam::Vec3;

/// `|x| = |μ|/(√2 τ)` from which a rectified Gaussian is one-sided, its mean `max(μ, 0)`
/// (its tail, `erfc(|x|) < 3·10⁻⁴⁵` and `e^{−x²} < 4·10⁻⁴⁴`, is below f32's normal range):
/// `smith_micro`'s own `erfc` cut-off.
pub const RECTIFIED_CUTOFF: f32 = smith_micro::erf::ERFC_ZERO_FROM;

/// `1/√2`.
pub(crate) const FRAC_1_SQRT_2: f32 = core::f32::consts::FRAC_1_SQRT_2;

/// `1/√(2π)`.
pub(crate) const FRAC_1_SQRT_2PI: f32 = 0.398_942_3;

/// The statistics of `N ~ N(μ, τ²)` clamped at 0: `E[N₊]`, and `Φ(k)`, `φ(k)`, `k = μ/τ`
/// (`φ = 0` and `k = 0` where the Gaussian is one-sided or degenerate, so that the series
/// terms vanish).
struct Rectified {
    mean: f32,
    cdf: f32,
    density: f32,
    ratio: f32,
}

/// [`Rectified`] of `N(mu, tau²)`.
fn rectified(mu: f32, tau: f32) -> Rectified {
    let one_sided = Rectified { mean: mu.max(0.0), cdf: if mu > 0.0 { 1.0 } else { 0.0 }, density: 0.0, ratio: 0.0 };
    if tau.is_nan() || tau <= 0.0 {
        return one_sided;
    }
    let x = mu / tau * FRAC_1_SQRT_2;
    if x.is_nan() || x.abs() >= RECTIFIED_CUTOFF {
        return one_sided;
    }
    // erfc of a finite |x| < 10 always has a value.
    let cdf = 0.5 * smith_micro::erfc(-x).unwrap_or(0.0);
    let density = libm::expf(-(x * x)) * FRAC_1_SQRT_2PI;
    let mean = (mu * cdf + tau * density).max(0.0);
    Rectified { mean, cdf, density, ratio: mu / tau }
}

/// The expected clamped cosine `⟨(m·l)₊⟩` of the light `light` over the facets visible along
/// `view` (both unit, in the frame of the mean normal `n̄ = +z`) of a surface of isotropic
/// slope deviation `sigma` (`σn`, `≥ 0`; see the module documentation for the derivation):
///
/// ```text
/// C ≈ E[(N_v)₊ (N_l)₊] / (E[(N_v)₊] √(1 + 2σ²)),   N_d = d_z − s·d_⊥,  s ~ N(0, σ² I)
/// ```
///
/// `sigma = 0` (or negative, or NaN) gives `max(l_z, 0)` exactly, the Lambert term of the
/// mean normal; the result is never negative or NaN for finite directions.
///
/// WGSL twin: `svo_expected_clamped_cosine`.
pub fn expected_clamped_cosine(view: Vec3, light: Vec3, sigma: f32) -> f32 {
    if sigma.is_nan() || sigma <= 0.0 {
        return light.z.max(0.0);
    }
    let normalisation = libm::sqrtf(1.0 + 2.0 * (sigma * sigma));
    let (view_across, light_across) =
        (libm::sqrtf(view.x * view.x + view.y * view.y), libm::sqrtf(light.x * light.x + light.y * light.y));
    let (tau_v, tau_l) = (sigma * view_across, sigma * light_across);
    let lit = rectified(light.z, tau_l);
    let seen = rectified(view.z, tau_v);
    if !(tau_v > 0.0 && tau_l > 0.0 && seen.mean > 0.0) {
        return lit.mean / normalisation;
    }
    let rho = ((view.x * light.x + view.y * light.y) / (view_across * light_across)).clamp(-1.0, 1.0);
    let (a, b) = (seen.ratio, lit.ratio);
    let (a2, b2) = (a * a, b * b);
    let hermite = 0.5
        + rho
            * (a * b * (1.0 / 6.0)
                + rho
                    * ((a2 - 1.0) * (b2 - 1.0) * (1.0 / 24.0)
                        + rho * (a * (a2 - 3.0)) * (b * (b2 - 3.0)) * (1.0 / 120.0)));
    let series = rho * (seen.cdf * lit.cdf) + (seen.density * lit.density) * (rho * rho) * hermite;
    let product = (seen.mean * lit.mean + (tau_v * tau_l) * series).max(0.0);
    product / (seen.mean * normalisation)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `E[(N_v)₊ (N_l)₊/|m̃|] / E[(N_v)₊]` over Gaussian slopes, by a midpoint rule on
    /// `[−7σ, 7σ]²` (the integrand is continuous; 400² cells).
    fn quadrature(view: Vec3, light: Vec3, sigma: f64) -> f64 {
        let (n, span) = (400, 7.0 * sigma);
        let h = 2.0 * span / f64::from(n);
        let (v, l) = (view.as_dvec3(), light.as_dvec3());
        let (mut sum, mut weight) = (0.0, 0.0);
        for i in 0..n {
            let s1 = -span + (f64::from(i) + 0.5) * h;
            for j in 0..n {
                let s2 = -span + (f64::from(j) + 0.5) * h;
                let p = (-(s1 * s1 + s2 * s2) / (2.0 * sigma * sigma)).exp();
                let seen = (v.z - s1 * v.x - s2 * v.y).max(0.0);
                let lit = (l.z - s1 * l.x - s2 * l.y).max(0.0) / (1.0 + s1 * s1 + s2 * s2).sqrt();
                sum += p * seen * lit;
                weight += p * seen;
            }
        }
        sum / weight
    }

    /// A unit direction at `elevation` above the plane, `azimuth` from +x (degrees).
    fn direction(elevation: f32, azimuth: f32) -> Vec3 {
        let (e, a) = (elevation.to_radians(), azimuth.to_radians());
        Vec3::new(e.cos() * a.cos(), e.cos() * a.sin(), e.sin())
    }

    #[test]
    fn no_roughness_is_the_clamped_cosine_of_the_mean_normal_bit_for_bit() {
        let view = direction(20.0, 180.0);
        for l in [direction(90.0, 0.0), direction(30.0, 0.0), direction(3.0, 40.0), direction(-20.0, 0.0)] {
            for sigma in [0.0, -1.0, f32::NAN] {
                assert_eq!(expected_clamped_cosine(view, l, sigma).to_bits(), l.z.max(0.0).to_bits(), "{l} {sigma}");
            }
        }
    }

    /// The closed form against the exact expectation. Its approximations are the
    /// normalisation by `√E[1 + |s|²]` and the truncated tetrachoric series. Bound: the facets
    /// that carry the expectation lie within ~2σ of the mean slope, where `1 + |s|²` differs
    /// from its mean `1 + 2σ²` by at most `6σ²`, so the normalisation errs by at most `3σ²`
    /// relatively; the series' remainder (`ρ⁶ φ(a)φ(b) He₄ He₄/720` and beyond) is below that
    /// for `|ρ| ≤ 1` on these inputs. Absolute below 0.02 (where the term itself vanishes).
    #[test]
    fn the_closed_form_is_the_expected_clamped_cosine_within_its_approximation() {
        let mut worst_naive = 0.0_f64;
        for sigma in [0.1_f32, 0.3, 0.5] {
            for view_elevation in [90.0, 15.0, 5.0] {
                for light_elevation in [45.0, 10.0, -5.0] {
                    for azimuth in [0.0, 90.0, 180.0] {
                        let (v, l) = (direction(view_elevation, 0.0), direction(light_elevation, azimuth));
                        let exact = quadrature(v, l, f64::from(sigma));
                        let ours = f64::from(expected_clamped_cosine(v, l, sigma));
                        let naive = f64::from(l.z.max(0.0));
                        let scale = exact.max(0.02);
                        worst_naive = worst_naive.max((naive - exact).abs() / scale);
                        assert!(
                            (ours - exact).abs() <= 3.0 * f64::from(sigma * sigma) * scale,
                            "σ {sigma}, view {view_elevation}°, light {light_elevation}° at {azimuth}°: {ours} vs {exact}"
                        );
                    }
                }
            }
        }
        // The naive form is far off somewhere (else the test would not tell them apart).
        std::println!("worst relative error of (n̄·l)₊: {worst_naive:.3}");
        assert!(worst_naive > 0.5, "{worst_naive}");
    }

    #[test]
    fn grazing_lights_and_views_see_more_than_the_mean_normal_says() {
        let (up, l) = (Vec3::Z, direction(5.0, 0.0));
        let rough = expected_clamped_cosine(up, l, 0.3);
        assert!(rough > 1.5 * l.z, "{rough} vs {}", l.z);
        // Below the mean horizon the facets turned towards the light are still lit.
        assert!(expected_clamped_cosine(up, direction(-5.0, 0.0), 0.3) > 0.0);
        // Facets turned towards a grazing eye face a light on the eye's side more.
        let (towards, away) = (direction(5.0, 0.0), direction(5.0, 180.0));
        let frontal = expected_clamped_cosine(up, direction(45.0, 0.0), 0.3);
        assert!(expected_clamped_cosine(towards, direction(45.0, 0.0), 0.3) > frontal);
        assert!(expected_clamped_cosine(away, direction(45.0, 0.0), 0.3) < frontal);
        // Huge ratios take the one-sided branches, without NaN.
        assert_eq!(expected_clamped_cosine(up, Vec3::new(1e-30, 0.0, 1.0), 1e-10), 1.0);
        assert_eq!(expected_clamped_cosine(up, Vec3::new(1.0, 0.0, -1e-3), 1e-8), 0.0);
        let tiny = expected_clamped_cosine(Vec3::new(1.0, 0.0, 1e-30), Vec3::new(1.0, 0.0, 1e-30), 1e-20);
        assert!(tiny.is_finite() && tiny >= 0.0, "{tiny}");
    }
}
