//! Surfaces displaced along their normal by 3D fBm ([`Displaced`]), coloured by the
//! displacement (Fig. 11: deep = red, high = yellow).

use glam::Vec3;
use svo_brick::{ATTRIBUTE_CHANNELS, SurfaceSource};

use crate::analytic::Sphere;
use crate::error::{SceneError, check};
use crate::noise::Fbm;
use crate::plate::Plane;

mod sealed {
    use glam::Vec3;

    use crate::error::SceneError;
    use crate::noise::Fbm;

    /// What [`Displaced`](super::Displaced) needs of its base (see its documentation).
    pub trait Sealed {
        /// `e(p)` and `∇e(p)`.
        fn field(&self, fbm: &Fbm, p: Vec3) -> (f32, Vec3);
        /// `K`, the bound of `|∇e|`.
        fn lipschitz_bound(&self, fbm: &Fbm) -> Result<f32, SceneError>;
        /// The foot of `p` on the base surface.
        fn foot(&self, p: Vec3) -> Vec3;
    }
}

/// A base surface that [`Displaced`] can displace: [`Sphere`] or [`Plane`] (sealed). The
/// base's own attribute is not used.
pub trait DisplacementBase: sealed::Sealed {}

impl DisplacementBase for Sphere {}
impl DisplacementBase for Plane {}

impl sealed::Sealed for Sphere {
    fn field(&self, fbm: &Fbm, p: Vec3) -> (f32, Vec3) {
        let (r, local) = (self.radius(), p - self.centre());
        let rho = local.length();
        if rho == 0.0 {
            return (-r, Vec3::ZERO);
        }
        let radial = local / rho;
        let (d, dd) = fbm.value_and_gradient(self.centre() + radial * r);
        let tangential = dd - radial * radial.dot(dd);
        let rho0 = r - fbm.amplitude_bound();
        if rho >= rho0 {
            (rho - r - d, radial - tangential * (r / rho))
        } else {
            (rho - r - d * (rho / rho0), radial * (1.0 - d / rho0) - tangential * (r / rho0))
        }
    }

    fn lipschitz_bound(&self, fbm: &Fbm) -> Result<f32, SceneError> {
        let (a, r) = (fbm.amplitude_bound(), self.radius());
        if a >= r {
            return Err(SceneError::DisplacementTooLarge { amplitude_bound: a, radius: r });
        }
        let rho0 = r - a;
        Ok((1.0 + a / rho0).hypot(r * fbm.gradient_bound() / rho0))
    }

    fn foot(&self, p: Vec3) -> Vec3 {
        let local = p - self.centre();
        let radial = local.try_normalize().unwrap_or(Vec3::Z);
        self.centre() + radial * self.radius()
    }
}

impl sealed::Sealed for Plane {
    fn field(&self, fbm: &Fbm, p: Vec3) -> (f32, Vec3) {
        let n = self.normal();
        let a = n.dot(p - self.point());
        let (d, dd) = fbm.value_and_gradient(p - n * a);
        (a - d, n - (dd - n * n.dot(dd)))
    }

    fn lipschitz_bound(&self, fbm: &Fbm) -> Result<f32, SceneError> {
        Ok(1f32.hypot(fbm.gradient_bound()))
    }

    fn foot(&self, p: Vec3) -> Vec3 {
        p - self.normal() * self.normal().dot(p - self.point())
    }
}

/// Colours correlated with the displacement `h`: `lerp(deep, high, σ(steepness · h / A))`
/// with `σ` the logistic sigmoid and `A` the fBm's first amplitude.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeightColours {
    deep: [f32; ATTRIBUTE_CHANNELS],
    high: [f32; ATTRIBUTE_CHANNELS],
    steepness: f32,
}

impl HeightColours {
    /// Colours from `deep` to `high` (channels in `[0, 1]`); `steepness` finite and
    /// non-negative (0: a uniform mid colour).
    pub fn new(
        deep: [f32; ATTRIBUTE_CHANNELS],
        high: [f32; ATTRIBUTE_CHANNELS],
        steepness: f32,
    ) -> Result<Self, SceneError> {
        let in_range = |c: &[f32; ATTRIBUTE_CHANNELS]| c.iter().all(|x| (0.0..=1.0).contains(x));
        let deep = check("HeightColours", "deep", deep, in_range(&deep), "in [0, 1]")?;
        let high = check("HeightColours", "high", high, in_range(&high), "in [0, 1]")?;
        let valid = steepness.is_finite() && steepness >= 0.0;
        let steepness = check("HeightColours", "steepness", steepness, valid, "finite and non-negative")?;
        Ok(HeightColours { deep, high, steepness })
    }

    /// The colour at displacement `h` for the first amplitude `amplitude`.
    pub fn at(&self, h: f32, amplitude: f32) -> [f32; ATTRIBUTE_CHANNELS] {
        let t = 1.0 / (1.0 + (-self.steepness * h / amplitude).exp());
        let t = if t >= 0.0 { t.min(1.0) } else { 0.5 };
        std::array::from_fn(|c| self.deep[c] + (self.high[c] - self.deep[c]) * t)
    }
}

impl Default for HeightColours {
    /// Fig. 11's: deep red, high yellow, steepness 4.
    fn default() -> Self {
        HeightColours { deep: [0.8, 0.1, 0.05], high: [0.95, 0.85, 0.1], steepness: 4.0 }
    }
}

/// A [`Sphere`] or [`Plane`] displaced along its normal by [`Fbm`], coloured by
/// [`HeightColours`].
///
/// # The surface
///
/// The fBm `D` is evaluated on the base surface, at the foot `x(p)` of `p` (its radial
/// projection on a sphere, its orthogonal projection on a plane), so the displaced surface
/// is exactly `{x + D(x) n(x)}`: every base point moves along its normal by `D(x)`. The
/// noise is 3D, so the sphere has no seam or pole.
///
/// # A 1-Lipschitz distance
///
/// The distance is `e(p)/K` with `e` a function whose zero set is the displaced surface and
/// `K` a proven bound of `|∇e|`, with `A = `[`Fbm::amplitude_bound`] `≥ |D|` and
/// `L = `[`Fbm::gradient_bound`] `≥ |∇D|`:
///
/// - **Plane** (unit normal `n`, height `a = n·(p − p₀)`): `e = a − D(p − a n)`. The foot
///   moves only in the plane, so `∇e = n − P∇D` with `P` the projection on the plane:
///   `|∇e|² = 1 + |P∇D|² ≤ 1 + L²`, `K = √(1 + L²)`.
/// - **Sphere** (centre `c`, radius `r`, `ρ = |p − c|`, `r̂ = (p − c)/ρ`, foot
///   `c + r r̂`): the foot's Jacobian is `(r/ρ)(I − r̂r̂ᵀ)`, so `D(foot)` has the tangential
///   gradient `(r/ρ) P∇D`, unbounded as `ρ → 0`. Hence `e = ρ − r − w(ρ) D(foot)` with
///   `w = min(1, ρ/ρ₀)` and `ρ₀ = r − A > 0` (required: [`SceneError::DisplacementTooLarge`]
///   otherwise). For `ρ ≥ ρ₀`, `∇e = r̂ − (r/ρ) P∇D`, so `|∇e|² ≤ 1 + (rL/ρ₀)²`. For
///   `ρ < ρ₀`, `∇e = (1 − D/ρ₀) r̂ − (r/ρ₀) P∇D`, so `|∇e|² ≤ (1 + A/ρ₀)² + (rL/ρ₀)²`, which
///   is `K²`. The taper does not move the zero set: the surface lies at `ρ = r + D ≥ ρ₀`,
///   where `w = 1`, and below `ρ₀`, `e ≤ ρ₀ − r + A ρ/ρ₀ < 0`.
///
/// A 1-Lipschitz function vanishing on the surface is at most the distance to it in
/// magnitude, so `|e/K|` never overestimates the distance (the contract's "bound of a signed
/// distance"). Its gradient has length `|∇e|/K ≤ 1` (`√(1 + |P∇D|²)/K` on a displaced
/// plane), so consumers wanting a local distance should divide by `|∇d|`. (Evaluating `D`
/// at `p` itself instead of the foot would need `K = 1 + L`: `∇D` would no longer be
/// orthogonal to the base's normal.)
#[derive(Clone, Debug)]
pub struct Displaced<S> {
    base: S,
    fbm: Fbm,
    colours: HeightColours,
    lipschitz: f32,
}

impl<S: DisplacementBase> Displaced<S> {
    /// `base` displaced by `fbm`. A sphere needs `fbm.amplitude_bound() < radius`.
    pub fn new(base: S, fbm: Fbm, colours: HeightColours) -> Result<Self, SceneError> {
        let lipschitz = base.lipschitz_bound(&fbm)?;
        Ok(Displaced { base, fbm, colours, lipschitz })
    }

    /// The base surface.
    pub fn base(&self) -> &S {
        &self.base
    }

    /// The displacement.
    pub fn fbm(&self) -> &Fbm {
        &self.fbm
    }

    /// `K`: the distance is the displaced field divided by `K ≥ 1`.
    pub fn lipschitz_factor(&self) -> f32 {
        self.lipschitz
    }

    /// The displacement `D` at the foot of `p` on the base surface.
    pub fn displacement(&self, p: Vec3) -> f32 {
        self.fbm.value(self.base.foot(p))
    }
}

impl<S: DisplacementBase> SurfaceSource for Displaced<S> {
    fn distance(&self, p: Vec3) -> f32 {
        self.base.field(&self.fbm, p).0 / self.lipschitz
    }

    /// Exact (the fBm's analytic derivative through the foot); zero at a sphere's centre.
    fn gradient(&self, p: Vec3) -> Vec3 {
        self.base.field(&self.fbm, p).1 / self.lipschitz
    }

    fn attribute(&self, x: Vec3) -> [f32; ATTRIBUTE_CHANNELS] {
        self.colours.at(self.displacement(x), self.fbm.amplitude())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attribute::Attribute;
    use crate::testing::{Rng, assert_gradient_matches, assert_lipschitz};
    use svo_brick::Cell;

    fn sphere() -> Displaced<Sphere> {
        let base = Sphere::new(Vec3::new(0.1, -0.2, 0.0), 1.0, Attribute::grey()).unwrap();
        Displaced::new(base, Fbm::new(5, 4, 0.5, 0.05, 0.5).unwrap(), HeightColours::default()).unwrap()
    }

    fn plane() -> Displaced<Plane> {
        let base = Plane::new(Vec3::ZERO, Vec3::new(0.2, 0.1, 1.0), Attribute::grey()).unwrap();
        Displaced::new(base, Fbm::new(6, 3, 0.6, 0.1, 0.8).unwrap(), HeightColours::default()).unwrap()
    }

    #[test]
    fn the_zero_set_is_the_base_moved_along_its_normal() {
        let s = sphere();
        let mut rng = Rng::new(21);
        for _ in 0..1000 {
            let u = rng.unit();
            let foot = s.base().centre() + u;
            let x = foot + u * s.fbm().value(foot);
            assert!(s.distance(x).abs() < 1e-6, "{}", s.distance(x));
            assert!(s.distance(foot + u * 0.3) > 0.0 && s.distance(foot - u * 0.3) < 0.0);
            assert!((s.displacement(x) - s.fbm().value(foot)).abs() < 1e-6);
        }
        assert!(s.distance(s.base().centre()) < 0.0);
        let p = plane();
        let n = p.base().normal();
        for _ in 0..1000 {
            let foot = rng.vec3(Vec3::splat(-3.0), Vec3::splat(3.0));
            let foot = foot - n * n.dot(foot);
            let x = foot + n * p.fbm().value(foot);
            assert!(p.distance(x).abs() < 1e-6);
            assert!(p.distance(x + n * 0.5) > 0.0 && p.distance(x - n * 0.5) < 0.0);
        }
    }

    #[test]
    fn displaced_distances_are_1_lipschitz() {
        let s = sphere();
        assert!(assert_lipschitz(&s, Vec3::splat(-1.5), Vec3::splat(1.5), 10_000, 22) < 1.0);
        // Close to the surface, where the displacement's gradient matters most.
        assert_lipschitz(&s, Vec3::new(0.8, -0.2, -0.2), Vec3::new(1.2, 0.2, 0.2), 10_000, 23);
        // Inside the taper's radius ρ₀ = 0.906…
        assert_lipschitz(&s, Vec3::splat(-0.6), Vec3::splat(0.6), 10_000, 24);
        let p = plane();
        assert_lipschitz(&p, Vec3::splat(-2.0), Vec3::splat(2.0), 10_000, 25);
        assert_lipschitz(&p, Vec3::new(-0.5, -0.5, -0.2), Vec3::new(0.5, 0.5, 0.2), 10_000, 26);
    }

    #[test]
    fn displaced_gradients_equal_finite_differences() {
        let s = sphere();
        let c = s.base().centre();
        let rho0 = 1.0 - s.fbm().amplitude_bound();
        // Off the centre and off the taper's sphere ρ = ρ₀ (where ∇e jumps).
        let smooth = |p: Vec3| p.distance(c) > 0.1 && (p.distance(c) - rho0).abs() > 0.01;
        assert!(assert_gradient_matches(&s, Vec3::splat(-1.5), Vec3::splat(1.5), 500, 1e-3, 3e-3, smooth) > 450);
        let p = plane();
        assert!(assert_gradient_matches(&p, Vec3::splat(-2.0), Vec3::splat(2.0), 500, 1e-3, 3e-3, |_| true) == 500);
    }

    #[test]
    fn shell_samples_lie_on_the_surface_and_add_up_to_its_area() {
        let base = Plane::new(Vec3::ZERO, Vec3::Z, Attribute::grey()).unwrap();
        let p = Displaced::new(base, Fbm::new(6, 3, 0.6, 0.1, 0.8).unwrap(), HeightColours::default()).unwrap();
        let side = 2.0;
        let mut samples = Vec::new();
        let cell = Cell { min: Vec3::new(0.0, 0.0, -0.25), max: Vec3::new(side, side, 0.25) };
        p.surface_samples(cell, 0.02, &mut samples);
        let area: f64 = samples.iter().map(|s| f64::from(s.area)).sum();
        // The graph's area ∫∫ √(1 + |∇D|²) by the midpoint rule.
        let n = 400;
        let h = side / n as f32;
        let mut exact = 0.0f64;
        for j in 0..n {
            for i in 0..n {
                let (_, g) = p.fbm().value_and_gradient(Vec3::new((i as f32 + 0.5) * h, (j as f32 + 0.5) * h, 0.0));
                exact += f64::from((1.0 + g.x * g.x + g.y * g.y).sqrt() * h * h);
            }
        }
        assert!(exact > 4.2, "{exact}");
        assert!((area / exact - 1.0).abs() < 0.01, "{area} vs {exact}");
        for s in &samples {
            assert!(p.distance(s.position).abs() < 1e-5);
            assert!((s.normal - p.gradient(s.position).normalize()).length() < 1e-5);
        }
    }

    #[test]
    fn colours_follow_the_height_and_big_displacements_are_errors() {
        let s = sphere();
        let colours = HeightColours::default();
        let amplitude = s.fbm().amplitude();
        assert_eq!(colours.at(0.0, amplitude), [0.875, 0.475, 0.075]);
        let deep = colours.at(-10.0 * amplitude, amplitude);
        let high = colours.at(10.0 * amplitude, amplitude);
        assert!(deep[1] < 0.11 && high[1] > 0.84, "{deep:?} {high:?}");
        let x = s.base().centre() + Vec3::X;
        assert_eq!(s.attribute(x), colours.at(s.displacement(x), amplitude));
        let base = Sphere::new(Vec3::ZERO, 0.09, Attribute::grey()).unwrap();
        let error = Displaced::new(base, *s.fbm(), colours).unwrap_err();
        assert!(matches!(error, SceneError::DisplacementTooLarge { .. }), "{error}");
        assert!(HeightColours::new([0.0; 3], [2.0, 0.0, 0.0], 1.0).unwrap_err().to_string().contains("high"));
    }
}
