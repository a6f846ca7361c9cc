//! The Lambert term of a voxel: the expected clamped cosine `⟨(m·l)₊⟩` over its Gaussian
//! distribution of micro-normals, in place of the clamped cosine of the mean normal
//! `(n̄·l)₊`.
//!
//! # Why
//!
//! Eq. 13 writes the element's radiance with the mean cosine of the light over the
//! element's microsurface. The clamp `x ↦ max(0, x)` is convex, so the mean of the clamped
//! cosines is at least the clamped cosine of the mean (Jensen): under a grazing light a
//! coarse voxel of bumps has facets turned towards the light that are lit far more than
//! `n̄·l` says, and `(n̄·l)₊` renders it too dark (~25 % on the bumpy sphere of
//! `svo-render`'s tests, as wide lens cones read coarse levels).
//!
//! # The closed form (H3, §5.2, §5.5)
//!
//! §5.2 and §5.5 describe the micro-normals as a Gaussian lobe `N(n̄, σn²)` of slopes
//! (H3: a Gaussian surface). In `n̄`'s frame the slopes are `s = (s₁, s₂) ~ N(0, σ² I)`
//! (`σ² = σn²`, isotropic), the micro-normal is `m = (−s₁, −s₂, 1)/√(1 + |s|²)`, and, for a
//! unit light direction `l = (l_⊥, l_z)`:
//!
//! ```text
//! (m·l)₊ = (l_z − s·l_⊥)₊ / √(1 + |s|²)
//! ```
//!
//! Seen along the mean normal, a pixel averages its footprint uniformly in macroscopic area
//! (a facet's micro-area times its cosine to `n̄` is its macro-area), which is the slope
//! distribution's own measure, so the element's Lambert term is `C = E_s[(m·l)₊]`:
//!
//! - the numerator `N = l_z − s·l_⊥` is linear in the slopes, hence exactly Gaussian, of
//!   mean `μ = l_z = n̄·l` and deviation `τ = σ |l_⊥|`; its rectified mean is
//!   `E[N₊] = μ Φ(μ/τ) + τ φ(μ/τ)`, with `Φ`, `φ` the standard normal distribution and
//!   density, i.e. with `x = μ/(√2 τ)`:
//!   `E[N₊] = ½ μ erfc(−x) + τ e^{−x²}/√(2π)` (erfc: `smith_micro::erfc`, the same
//!   approximation on the CPU and the GPU);
//! - the normalisation `1/√(1 + |s|²)` is replaced by `1/√E[1 + |s|²] = 1/√(1 + 2σ²)`. Both
//!   are `1 − σ² + O(σ⁴)` under a frontal light (`E[(1 + |s|²)^{−½}] = 1 − σ² + O(σ⁴)` for
//!   `|s|²/σ²` a χ² of two degrees), so the form is exact to first order in `σ²` there and
//!   exact for `σ = 0`.
//!
//! ```text
//! C(μ, τ, σ) = (½ μ erfc(−μ/(√2 τ)) + τ e^{−μ²/(2τ²)}/√(2π)) / √(1 + 2σ²)
//! ```
//!
//! It is `≥ max(μ, 0)/√(1 + 2σ²)` (Jensen) and tends to it as `τ → 0`. For `σ = 0` (the
//! finest level, the ground truth's unfiltered surface and [`Filtering::Separate`]) the
//! function returns `max(n̄·l, 0)` itself, bit for bit; for `τ = 0` with `σ > 0` (a light
//! along `n̄`) it returns `max(μ, 0)/√(1 + 2σ²)`; beyond `|x| ≥`
//! [`RECTIFIED_CUTOFF`] the Gaussian lies on one side of 0 to f32 precision
//! (`erfc(10) < 3·10⁻⁴⁵`) and `E[N₊] = max(μ, 0)`.
//!
//! What it leaves out: the local shadowing of the lit facets by their neighbours (Smith's
//! `1/(1 + Λ(l))`), which eq. 13 does not put in the diffuse term either, and the weighting
//! of the facets by their cosine to an oblique view (their visible projected area); both
//! are second order on the scenes measured (see `svo-render`'s tests).
//!
//! [`Filtering::Separate`]: crate::Filtering::Separate

use glam::Vec3;

/// `|x| = |μ|/(√2 τ)` from which the rectified Gaussian mean is `max(μ, 0)` (its tail,
/// `erfc(|x|) < 3·10⁻⁴⁵` and `e^{−x²} < 4·10⁻⁴⁴`, is below f32's normal range):
/// `smith_micro`'s own `erfc` cut-off.
pub const RECTIFIED_CUTOFF: f32 = smith_micro::erf::ERFC_ZERO_FROM;

/// `1/√2`.
pub(crate) const FRAC_1_SQRT_2: f32 = core::f32::consts::FRAC_1_SQRT_2;

/// `1/√(2π)`.
pub(crate) const FRAC_1_SQRT_2PI: f32 = 0.398_942_3;

/// The expected clamped cosine `⟨(m·l)₊⟩` of the light `light` (unit, in the frame of the
/// mean normal `n̄ = +z`) over micro-normals of isotropic slope deviation `sigma` (`σn`,
/// `≥ 0`) about `n̄` (see the module documentation for the derivation):
///
/// ```text
/// C = (½ μ erfc(−μ/(√2 τ)) + τ e^{−μ²/(2τ²)}/√(2π)) / √(1 + 2σ²),   μ = l_z, τ = σ |l_⊥|
/// ```
///
/// `sigma = 0` (or negative, or NaN) gives `max(l_z, 0)` exactly, the Lambert term of the
/// mean normal; the result is never negative or NaN for a finite `light`.
///
/// WGSL twin: `svo_expected_clamped_cosine`.
pub fn expected_clamped_cosine(light: Vec3, sigma: f32) -> f32 {
    let mu = light.z;
    // `!(σ > 0)` also catches NaN.
    if !(sigma > 0.0) {
        return mu.max(0.0);
    }
    let normalisation = libm::sqrtf(1.0 + 2.0 * (sigma * sigma));
    let tau = sigma * libm::sqrtf(light.x * light.x + light.y * light.y);
    let clamped = mu.max(0.0);
    if !(tau > 0.0) {
        return clamped / normalisation;
    }
    let x = mu / tau * FRAC_1_SQRT_2;
    if !(x.abs() < RECTIFIED_CUTOFF) {
        return clamped / normalisation;
    }
    // erfc of a finite |x| < 10 always has a value.
    let tail = smith_micro::erfc(-x).unwrap_or(0.0);
    let density = libm::expf(-(x * x)) * FRAC_1_SQRT_2PI;
    let rectified = (0.5 * mu * tail + tau * density).max(0.0);
    rectified / normalisation
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `E[(m·l)₊]` over Gaussian slopes, by a midpoint rule on `[−8σ, 8σ]²` (the integrand
    /// is smooth where `m·l ≠ 0` and continuous everywhere; 800² cells).
    fn quadrature(light: Vec3, sigma: f64) -> f64 {
        let (n, span) = (800, 8.0 * sigma);
        let h = 2.0 * span / f64::from(n);
        let (lx, ly, lz) = (f64::from(light.x), f64::from(light.y), f64::from(light.z));
        let (mut sum, mut weight) = (0.0, 0.0);
        for i in 0..n {
            let s1 = -span + (f64::from(i) + 0.5) * h;
            for j in 0..n {
                let s2 = -span + (f64::from(j) + 0.5) * h;
                let p = (-(s1 * s1 + s2 * s2) / (2.0 * sigma * sigma)).exp();
                let cosine = (lz - s1 * lx - s2 * ly) / (1.0 + s1 * s1 + s2 * s2).sqrt();
                sum += p * cosine.max(0.0);
                weight += p;
            }
        }
        sum / weight
    }

    fn light(elevation_degrees: f32) -> Vec3 {
        let e = elevation_degrees.to_radians();
        Vec3::new(e.cos(), 0.0, e.sin())
    }

    #[test]
    fn no_roughness_is_the_clamped_cosine_of_the_mean_normal_bit_for_bit() {
        for l in [light(90.0), light(30.0), light(3.0), light(-20.0), Vec3::new(0.3, -0.4, 0.866).normalize()] {
            for sigma in [0.0, -1.0, f32::NAN] {
                assert_eq!(expected_clamped_cosine(l, sigma).to_bits(), l.z.max(0.0).to_bits(), "{l} {sigma}");
            }
        }
    }

    /// The closed form against the exact expectation. Its two approximations are the
    /// normalisation by `√E[1 + |s|²]` (first order in `σ²`) only; the numerator is exact.
    /// Bounds: under a frontal light the error is the normalisation's, `O(σ⁴)` (measured
    /// 0.7 % at σ = 0.3); at grazing angles the facets turned towards the light are
    /// steeper than average, so their true normalisation is smaller than the RMS one and
    /// the form is too bright by at most the relative spread of `√(1 + |s|²)`, `≤ σ²`.
    #[test]
    fn the_closed_form_is_the_expected_clamped_cosine_within_its_approximation() {
        for sigma in [0.05_f32, 0.15, 0.3] {
            for elevation in [90.0, 45.0, 20.0, 10.0, 3.0, -3.0] {
                let l = light(elevation);
                let exact = quadrature(l, f64::from(sigma));
                let ours = f64::from(expected_clamped_cosine(l, sigma));
                let naive = f64::from(l.z.max(0.0));
                let bound = f64::from(sigma * sigma) * exact.max(0.02);
                std::println!(
                    "σ = {sigma}, elevation {elevation}°: exact {exact:.5}, closed form {ours:.5}, (n̄·l)₊ {naive:.5}"
                );
                assert!((ours - exact).abs() <= bound, "σ {sigma}, {elevation}°: {ours} vs {exact}");
            }
        }
    }

    #[test]
    fn grazing_lights_light_more_than_the_mean_normal_says() {
        let l = light(5.0);
        let rough = expected_clamped_cosine(l, 0.3);
        assert!(rough > 1.5 * l.z, "{rough} vs {}", l.z);
        // Below the mean horizon the facets turned towards the light are still lit.
        assert!(expected_clamped_cosine(light(-5.0), 0.3) > 0.0);
        // Huge ratios take the one-sided branch, without NaN.
        assert_eq!(expected_clamped_cosine(Vec3::new(1e-30, 0.0, 1.0), 1e-10), 1.0);
        assert_eq!(expected_clamped_cosine(Vec3::new(1.0, 0.0, -1e-3), 1e-8), 0.0);
    }
}
