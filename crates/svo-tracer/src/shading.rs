//! The radiance of a cone element, `L_d` (§5.5, eq. 13 and 17).
//!
//! In the frame of the element's mean normal `n̂`, with the view `v` (towards the eye) and
//! the light `l`, per colour channel `c`:
//!
//! ```text
//! L_d,c = Ē V̄(l) ( k_d/π ā_c(v, l) ⟨(m·l)₊⟩ + k_s ρ_s(v, l) )
//! ```
//!
//! - `ā_c(v, l) = ā + a_s (2 (Λv + Λl + 1)/(Λv + Λl + 2) − 1)` (eq. 17, through
//!   `smith_micro::visible_mean_attribute`) with Smith's `Λ` (eq. 6) of the voxel's slopes
//!   `σn`; a direction at or below the mean horizon has `Λ = ∞` (fully masked: the visible
//!   attribute tends to the top of the microsurface, `ā + a_s`).
//! - `ρ_s`: eq. 13's microfacet lobe with the convolved slopes `σn² + σnp²` (§5.5),
//!   `smith_micro::shade` of a white attribute.
//! - `⟨(m·l)₊⟩`: eq. 13's mean cosine, the expected clamped cosine over the visible
//!   facets (weighted by their projected area, as eq. 14 weights the attribute) of the
//!   voxel's Gaussian lobe of micro-normals `N(n̄, σn²)` (§5.2, §5.5;
//!   [`expected_clamped_cosine`], derived in its module), which is `(n̂·l)₊` at the finest
//!   level (`σn = 0`) and for [`Filtering::Separate`] (the naive filtering of Fig. 11–12
//!   keeps the Lambert term of the mean normal).
//! - `V̄(l)`: the shadow cone's visibility (1 without shadows).
//!
//! The Lambert term weighted by `ā(v, l)` is the design notes' addition: eq. 13 alone is a
//! specular lobe, and the paper's figures show diffuse colour.

use glam::Vec3;
use smith_micro::{FilteredSurface, HeightCorrelatedAttribute, SlopeDeviation, shade, smith_lambda_direction};
use svo_brick::{ATTRIBUTE_CHANNELS, Voxel};

use crate::lambert::expected_clamped_cosine;

/// The base material of the surface (the finest level's BRDF).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// `k_d`, the weight of the Lambert term.
    pub diffuse: f32,
    /// `k_s`, the weight of the microfacet lobe.
    pub specular: f32,
    /// `σnp`, the microfacet slopes of the base BRDF (§5.5).
    pub brdf_slope: f32,
}

impl Default for Material {
    fn default() -> Self {
        Self { diffuse: 1.0, specular: 0.0, brdf_slope: 0.2 }
    }
}

/// How the micro-descriptors are used (the paper's model or the naive one of Fig. 11–12).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Filtering {
    /// `ā(v, l)` with `a_s`, the lobe `σn² + σnp²` (the paper).
    Correlated,
    /// Separate filtering: `ā` alone (`a_s = 0`), masking and lobe without `σn` (`σnp`
    /// only).
    Separate,
}

/// `(t₁, t₂)` completing the unit `n` to an orthonormal frame (Duff et al. 2017).
pub(crate) fn tangent_frame(n: Vec3) -> (Vec3, Vec3) {
    let sign = if n.z >= 0.0 { 1.0 } else { -1.0 };
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x), Vec3::new(b, sign + n.y * n.y * a, -n.y))
}

fn lambda(direction: Vec3, slopes: SlopeDeviation) -> f32 {
    if direction.z <= 0.0 {
        return f32::INFINITY;
    }
    smith_lambda_direction(direction, slopes).unwrap_or(f32::INFINITY)
}

/// `L_d` of the element `voxel` (world units, unit normal) seen along `view` (unit,
/// towards the eye) and lit from `light` (unit, towards the light) with radiance `radiance`
/// and far visibility `visibility` (see the module documentation). A voxel without a
/// normal reflects nothing.
pub fn element_radiance(
    voxel: &Voxel,
    view: Vec3,
    light: Vec3,
    material: &Material,
    filtering: Filtering,
    radiance: f32,
    visibility: f32,
) -> Vec3 {
    let n = voxel.normal;
    if n.length_squared() < 0.5 {
        return Vec3::ZERO;
    }
    let (t1, t2) = tangent_frame(n);
    let frame = |d: Vec3| Vec3::new(d.dot(t1), d.dot(t2), d.dot(n));
    let (v, l) = (frame(view), frame(light));
    let sigma = match filtering {
        Filtering::Correlated => {
            libm::sqrtf(voxel.slope_variance.max(0.0)).min(smith_micro::masking::MAX_SLOPE_DEVIATION)
        }
        Filtering::Separate => 0.0,
    };
    // σ is clamped into the constructor's range, so this never returns.
    let Ok(slopes) = SlopeDeviation::isotropic(sigma) else { return Vec3::ZERO };
    let (lambda_v, lambda_l) = (lambda(v, slopes), lambda(l, slopes));
    // σ = 0 for Filtering::Separate: `(n̂·l)₊`, bit for bit.
    let lit = expected_clamped_cosine(v, l, sigma);
    let mut out = [0.0_f32; ATTRIBUTE_CHANNELS];
    for (c, value) in out.iter_mut().enumerate() {
        let correlation = if filtering == Filtering::Correlated { voxel.correlation[c] } else { 0.0 };
        let attribute = HeightCorrelatedAttribute::new(voxel.attribute[c], correlation)
            .ok()
            .and_then(|a| smith_micro::visible_mean_attribute(a, lambda_v, lambda_l))
            .unwrap_or(voxel.attribute[c]);
        *value = material.diffuse * core::f32::consts::FRAC_1_PI * attribute * lit;
    }
    let mut specular = 0.0;
    if material.specular > 0.0 {
        let brdf = SlopeDeviation::isotropic(material.brdf_slope).ok();
        let white = HeightCorrelatedAttribute::new(1.0, 0.0).ok();
        if let (Some(brdf_slopes), Some(attribute)) = (brdf, white) {
            let surface = FilteredSurface { slopes, brdf_slopes, attribute };
            specular = material.specular * shade(v, l, surface, 1.0).unwrap_or(0.0);
        }
    }
    (Vec3::from_array(out) + specular) * (radiance * visibility)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn voxel(correlation: f32) -> Voxel {
        Voxel {
            normal: Vec3::Z,
            slope_variance: 0.09,
            attribute: [0.5; 3],
            correlation: [correlation; 3],
            ..Voxel::default()
        }
    }

    #[test]
    fn grazing_views_see_the_top_of_a_correlated_surface() {
        let material = Material::default();
        let light = Vec3::Z;
        let normal_view = element_radiance(&voxel(0.3), Vec3::Z, light, &material, Filtering::Correlated, 1.0, 1.0);
        let grazing = Vec3::new(0.99, 0.0, 0.14).normalize();
        let grazing_view = element_radiance(&voxel(0.3), grazing, light, &material, Filtering::Correlated, 1.0, 1.0);
        let separate = element_radiance(&voxel(0.3), grazing, light, &material, Filtering::Separate, 1.0, 1.0);
        // Eq. 17: higher points (positive a_s) are seen more at grazing angles.
        assert!(grazing_view.x > normal_view.x);
        assert!((separate.x - 0.5 / core::f32::consts::PI).abs() < 1e-6);
        assert_eq!(
            element_radiance(&Voxel::default(), Vec3::Z, light, &material, Filtering::Correlated, 1.0, 1.0),
            Vec3::ZERO
        );
    }
}
