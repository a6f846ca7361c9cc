//! The occlusion test of Listing 2, in single precision, conservative under rounding.
//!
//! # The test
//!
//! Camera space, eye at the origin. The occluder's inner ball `B(g₀, r)` hides the grain
//! whose outer ball is `B(g₁, R)` iff (see the crate documentation for the proof)
//!
//! `g₀ · d > 0` and `|g₀ × g₁|² < r² |d|²`, with `d = g₁ − k g₀`, `k = R / r`,
//!
//! that is, iff `g₁` lies in the cone of axis `g₀/|g₀|` and half-angle `α`
//! (`sin α = r/|g₀|`) whose apex is `a = k g₀` (Listing 2's `g0 * R / r`): the angle `β`
//! between the axis and `g₁ − a` has `cos β > 0` and `sin² β < sin² α`. Written with the
//! cross product `g₀ × d = g₀ × g₁` and unnormalised vectors, the test needs no square
//! root, no division but `k`, and no `normalize` (whose argument Listing 2 lets vanish at
//! `g₁ = a`).
//!
//! # Decisions
//!
//! - **No occluder** (a cleared occluder-map texel): [`is_occluded`] takes an
//!   [`Option`]; `None` never culls.
//! - **`R < r`** (a grain scaled smaller than its occluder): the proof needs `k ≥ 1`, so
//!   `k = max(R, r)/r`: the grain is tested as if its outer radius were `r`, which bounds
//!   it, so the test stays conservative.
//! - **Per-grain scale**: the caller passes scaled radii (`r·s₀` of the occluder, `R·s₁` of
//!   the grain).
//! - **`g₁ = a`, `g₁ = g₀`, the eye inside or on the occluder ball** (`|g₀| ≤ r`): not
//!   culled (`g₀ · d > 0` fails at `g₁ = a` and `g₁ = g₀`; the cone is undefined when the
//!   eye is inside the ball).
//! - **Orthographic cameras**: the eye is at infinity, the cone becomes the cylinder of
//!   radius `r` along the view direction and its erosion by `R ≥ r` is empty (or, for
//!   `R = r`, the axis line, a set of measure zero), so nothing is culled: [`is_occluded`]
//!   returns `false` for [`Projection::Orthographic`]. (With per-grain scales an occludee
//!   smaller than `r` could in principle be culled there; not culling is conservative.)
//!   This is also why a narrow field of view culls less (paper Fig. 15): its rays are
//!   nearly parallel.
//! - **Outside the domain** — a coordinate or radius NaN, infinite, or of magnitude above
//!   [`MAX_COORDINATE`], a radius not in [`MIN_RADIUS`]`..=`[`MAX_RADIUS`]: not culled.
//!   The bounds keep every intermediate (products of four coordinates) far from `f32`
//!   overflow, which the WGSL twin could not represent.
//!
//! # Rounding
//!
//! The exact test holds on the boundary with equality, so a computed `lhs < rhs` could
//! flip by rounding. With unit roundoff `ε = 2⁻²⁴`, `P = |g₀|²|g₁|²` and
//! `Q = |g₁| + k|g₀|`:
//!
//! - each cross-product component carries an error below `2ε (|a_j b_k| + |a_k b_j|)`, so
//!   `|Δ(g₀ × g₁)| ≤ 2√2 ε √P`, and the computed `lhs = |g₀ × g₁|²` is within
//!   `6ε √(lhs P) + 2ε lhs + O(ε²P)` of the exact one (the cancellation of a cross product
//!   of nearly parallel vectors: relative `ε/sin α` for a narrow cone, inherent in any
//!   formulation from these inputs);
//! - `d`'s components are within `2ε (|g₁ᵢ| + k|g₀ᵢ|)`, so `|Δd| ≤ 2εQ`, and the computed
//!   `rhs = r²|d|²` is within `4ε r²|d|Q + 4ε r²|d|² + O(ε²)`.
//!
//! Where the test culls, `lhs < rhs`, so `√(lhs P) ≤ r|d|√P`: both errors are below
//! `6ε r|d| (√P + rQ + r|d|)`. [`is_occluded_by`] therefore culls only when
//! `lhs + MARGIN·ρ (√P + r Q̂ + ρ) < rhs` with `ρ = √rhs`, `Q̂ = √(2 (|g₁|² + k²|g₀|²)) ≥ Q`
//! and [`MARGIN`]` = 2⁻¹⁹ = 32ε`, over five times the bounds' `6ε` coefficients (the square
//! roots only enter the margin, whose own rounding the slack covers; a fused
//! multiply–add on the GPU only lowers the errors). `k` is rounded up by
//! [`APEX_ROUNDING`]: a larger `k` moves the apex back along the axis, and the cone with
//! the farther apex lies inside the nearer one, so this too only culls less.

use glam::{Vec3, Vec4};
use gpu_layout::f32_bits::ABS_MASK;

/// Largest magnitude of a camera-space coordinate the test accepts, `2²⁰`.
pub const MAX_COORDINATE: f32 = 1_048_576.0;
/// Smallest radius the test accepts, `2⁻²⁰`.
pub const MIN_RADIUS: f32 = 1.0 / 1_048_576.0;
/// Largest radius the test accepts, `2²⁰`.
pub const MAX_RADIUS: f32 = 1_048_576.0;
/// The rounding margin's coefficient, `2⁻¹⁹ = 32ε` (see the module documentation).
pub const MARGIN: f32 = 1.0 / 524_288.0;
/// The factor that rounds `k = R/r` up, `1 + 2⁻²⁰`, above the division's half-ulp error.
pub const APEX_ROUNDING: f32 = 1.0 + 1.0 / 1_048_576.0;
/// `|g₀|² > r² · EYE_CLEARANCE`: the eye must be clearly outside the occluder's inner ball,
/// `1 + 2⁻¹⁶`.
pub const EYE_CLEARANCE: f32 = 1.0 + 1.0 / 65_536.0;

/// The camera's projection: the cone exists only for a perspective camera.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Projection {
    /// A perspective camera; camera-space coordinates with the eye at the origin.
    Perspective,
    /// An orthographic camera: nothing is culled (see the module documentation).
    Orthographic,
}

/// A ball in camera space: the occluder's inner sphere or a grain's outer sphere (radii
/// already multiplied by the grain's scale). Plain data: [`is_occluded`] checks every
/// value, as the WGSL twin does with the raw texels it reads.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// The centre, camera space (eye at the origin).
    pub centre: Vec3,
    /// The radius.
    pub radius: f32,
}

impl Sphere {
    /// `(centre, radius)` as one vector, the layout of an occluder-map texel.
    pub fn to_vec4(self) -> Vec4 {
        self.centre.extend(self.radius)
    }

    /// The ball of `(x, y, z, radius)`.
    pub fn from_vec4(v: Vec4) -> Self {
        Self { centre: v.truncate(), radius: v.w }
    }
}

/// `|x| ≤ limit`, tested on the bits (false for NaN and ±∞), as the WGSL twin does.
fn within(x: f32, limit: f32) -> bool {
    x.to_bits() & ABS_MASK <= limit.to_bits()
}

/// Whether `sphere` is inside the test's domain (module documentation, "Outside the
/// domain"). WGSL twin: `occlusion_in_domain`.
pub fn in_domain(sphere: Sphere) -> bool {
    let radius_bits = sphere.radius.to_bits();
    sphere.centre.to_array().iter().all(|&c| within(c, MAX_COORDINATE))
        && radius_bits >= MIN_RADIUS.to_bits()
        && radius_bits <= MAX_RADIUS.to_bits()
}

/// `a · b`, summed in this order (the WGSL twin sums the same way).
fn dot(a: Vec3, b: Vec3) -> f32 {
    a.x * b.x + a.y * b.y + a.z * b.z
}

/// `a × b`, component by component (as the WGSL twin).
fn cross(a: Vec3, b: Vec3) -> Vec3 {
    Vec3::new(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x)
}

/// Whether the grain whose outer ball is `grain` is certainly hidden behind the inner ball
/// `occluder` (Listing 2, derived again; see the module documentation for every case).
/// Never `true` for a grain that any ray from the eye can see: the rounding margin makes
/// the `f32` test cull a subset of what the exact test culls.
///
/// WGSL twin: `occlusion_is_occluded` (perspective; the caller skips it for orthographic
/// cameras and empty texels).
///
/// ```
/// use glam::Vec3;
/// use occlusion_cone::{Projection, Sphere, is_occluded};
///
/// let occluder = Sphere { centre: Vec3::new(0.0, 0.0, -10.0), radius: 1.0 };
/// let behind = Sphere { centre: Vec3::new(0.0, 0.1, -14.0), radius: 1.2 };
/// let beside = Sphere { centre: Vec3::new(2.0, 0.0, -14.0), radius: 1.2 };
/// assert!(is_occluded(Projection::Perspective, Some(occluder), behind));
/// assert!(!is_occluded(Projection::Perspective, Some(occluder), beside));
/// assert!(!is_occluded(Projection::Orthographic, Some(occluder), behind));
/// assert!(!is_occluded(Projection::Perspective, None, behind));
/// ```
pub fn is_occluded(projection: Projection, occluder: Option<Sphere>, grain: Sphere) -> bool {
    match (projection, occluder) {
        (Projection::Perspective, Some(occluder)) => is_occluded_by(occluder, grain),
        _ => false,
    }
}

/// [`is_occluded`] for a perspective camera and an occluder. WGSL twin:
/// `occlusion_is_occluded`.
pub fn is_occluded_by(occluder: Sphere, grain: Sphere) -> bool {
    if !(in_domain(occluder) && in_domain(grain)) {
        return false;
    }
    let (g0, r) = (occluder.centre, occluder.radius);
    let g1 = grain.centre;
    let r2 = r * r;
    let g0_2 = dot(g0, g0);
    // Every value is finite and bounded here (the domain check): no NaN reaches a
    // comparison.
    if g0_2 <= r2 * EYE_CLEARANCE {
        return false;
    }
    let k = grain.radius.max(r) / r * APEX_ROUNDING;
    let d = g1 - g0 * k;
    if dot(g0, d) <= 0.0 {
        return false;
    }
    let c = cross(g0, g1);
    let lhs = dot(c, c);
    let rhs = r2 * dot(d, d);
    let g1_2 = dot(g1, g1);
    let rho = libm::sqrtf(rhs);
    let reach = libm::sqrtf(2.0 * (g1_2 + k * k * g0_2));
    let margin = MARGIN * rho * (libm::sqrtf(g0_2 * g1_2) + r * reach + rho);
    lhs + margin < rhs
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sphere(x: f32, y: f32, z: f32, radius: f32) -> Sphere {
        Sphere { centre: Vec3::new(x, y, z), radius }
    }

    #[test]
    fn the_documented_cases() {
        let occluder = sphere(0.0, 0.0, -10.0, 1.0);
        // On the axis far behind: hidden; the apex and the occluder itself: not culled.
        assert!(is_occluded_by(occluder, sphere(0.0, 0.0, -30.0, 1.5)));
        assert!(!is_occluded_by(occluder, sphere(0.0, 0.0, -15.0, 1.5)), "the apex a = g0 R / r");
        assert!(!is_occluded_by(occluder, occluder), "g1 = g0");
        // In front of the occluder: visible.
        assert!(!is_occluded_by(occluder, sphere(0.0, 0.0, -5.0, 0.5)));
        // R < r is tested as R = r: a small grain just behind the occluder's apex region.
        assert!(is_occluded_by(occluder, sphere(0.0, 0.0, -12.0, 0.2)));
        assert!(is_occluded_by(occluder, sphere(0.0, 0.0, -10.5, 0.2)), "inside the occluder ball");
        assert!(!is_occluded_by(occluder, sphere(0.0, 0.0, -8.5, 0.2)), "in front of it");
        // The eye inside the occluder, non-finite and out-of-domain values.
        assert!(!is_occluded_by(sphere(0.0, 0.0, -0.5, 1.0), sphere(0.0, 0.0, -30.0, 1.0)));
        assert!(!is_occluded_by(occluder, sphere(f32::NAN, 0.0, -30.0, 1.0)));
        assert!(!is_occluded_by(occluder, sphere(0.0, 0.0, f32::NEG_INFINITY, 1.0)));
        assert!(!is_occluded_by(occluder, sphere(0.0, 0.0, -30.0, f32::INFINITY)));
        assert!(!is_occluded_by(occluder, sphere(0.0, 0.0, -30.0, 0.0)));
        assert!(!is_occluded_by(occluder, sphere(0.0, 0.0, -2.0 * MAX_COORDINATE, 1.0)));
        assert!(!is_occluded_by(sphere(0.0, 0.0, -10.0, -1.0), sphere(0.0, 0.0, -30.0, 1.0)));
        assert!(in_domain(sphere(MAX_COORDINATE, -MAX_COORDINATE, 0.0, MIN_RADIUS)));
        assert!(!in_domain(sphere(0.0, 0.0, 0.0, MIN_RADIUS / 2.0)));
    }

    #[test]
    fn the_cone_boundary_is_listing_2s() {
        // Occluder at distance 10, r = 1: sin α = 0.1. Grain R = 2: apex at distance 20.
        // At distance 20 + t behind the apex, the cone's radius is t tan α.
        let occluder = sphere(0.0, 0.0, -10.0, 1.0);
        let tan_alpha = 0.1 / (1.0_f32 - 0.01).sqrt();
        let t = 10.0;
        let edge = t * tan_alpha;
        assert!(is_occluded_by(occluder, sphere(edge * 0.99, 0.0, -30.0, 2.0)));
        assert!(!is_occluded_by(occluder, sphere(edge * 1.01, 0.0, -30.0, 2.0)));
    }

    #[test]
    fn margins_are_what_the_documentation_says() {
        assert_eq!(MARGIN, 32.0 * f32::EPSILON / 2.0);
        assert_eq!(APEX_ROUNDING, 1.0 + 8.0 * f32::EPSILON);
        assert_eq!(MAX_COORDINATE, 2.0_f32.powi(20));
        // Products of four coordinates stay far below f32::MAX.
        assert!(3.0 * MAX_COORDINATE.powi(2) * 3.0 * MAX_COORDINATE.powi(2) * 4.0 < f32::MAX / 1e6);
    }
}
