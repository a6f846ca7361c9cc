//! Cone-aware lower bounds of directional distances, by convex duality.
//!
//! For a set `A` of offsets `m − v` (here a box–triangle pair: `A = T − B`) and a convex
//! cone `K`, every `p ∈ A ∩ K` and every vector `w` satisfy
//!
//! `|p| ≥ h_A(w) / |P_K(w)|` where `h_A(w) = min_{a ∈ A} w · a > 0`,
//!
//! `P_K` being the projection onto `K`. Proof (Moreau): `w = P_K(w) + r` with `r` in the
//! polar cone, so `r · p ≤ 0` and `w · p ≤ P_K(w) · p ≤ |P_K(w)| |p|`. When `P_K(w) = 0`,
//! `A ∩ K` is empty. The largest such bound over all `w` equals the minimum of `|p|`
//! over `A ∩ K` (strong duality), so a few well-chosen `w` give a bound close to the
//! exact directional distance without splitting the pair; a `w` inside `K` gives the
//! direction in which a real point pair (a witness) is looked for.
//!
//! A cone of [`Cone`] (an azimuth interval times an elevation interval) is not always
//! convex; [`ConvexCone`] is the convex product cone `wedge × z-interval` holding it
//! (exactly the cone for the downward `m × 1` cones with `m ≥ 2`). Since `A ∩ C ⊆ A ∩ K`
//! for `C ⊆ K`, a bound for `K` holds for `C`.

use glam::{Vec2, Vec3};

use crate::cones::Cone;
use crate::geometry::Triangle;

/// The sign constraint on `z` of a [`ConvexCone`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Vertical {
    /// `z ≤ 0` (the cone's elevations are all `≤ 0`).
    Down,
    /// `z ≥ 0`.
    Up,
    /// Any `z`.
    Any,
}

/// Relative slack added to `|P_K(w)|`: the wedge's boundary rays are computed from the
/// cone's azimuths with rounding, so the true cone can stick out of `K` by about `1e-6`
/// rad; `|p| ≥ h / (|P_K(w)| + δ)` still holds for such a `p` when `δ` exceeds that angle.
const PROJECTION_SLACK: f32 = 1e-5;

/// A convex cone `W × Z` holding a [`Cone`]: `W` the azimuth wedge (the whole plane when
/// wider than `π`), `Z` the sign of `z` when all elevations share it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ConvexCone {
    /// Unit boundary rays of the wedge, counter-clockwise from `start` to `end`, or `None`
    /// for the whole plane.
    wedge: Option<(Vec2, Vec2)>,
    vertical: Vertical,
    /// A unit direction well inside the cone (its centre).
    center: Vec3,
    /// Whether the convex cone is the cone itself (elevations `[-π/2, 0]`, `[0, π/2]` or
    /// `[-π/2, π/2]`), and the wedge's rays turned inwards by [`INNER_TURN`] (`None`: the
    /// whole plane) for [`ConvexCone::contains_within`].
    exact: bool,
    inner_wedge: Option<(Vec2, Vec2)>,
}

/// The angle by which [`ConvexCone::contains_within`] shrinks the wedge, in radians: far
/// more than the rounding of the cone's azimuths, so a direction it accepts is in the
/// cone as [`Cone::contains_at`] computes it.
const INNER_TURN: f32 = 2e-5;

impl ConvexCone {
    /// The convex cone holding `cone`.
    pub(crate) fn holding(cone: &Cone) -> Self {
        let width = cone.azimuth_max - cone.azimuth_min;
        let ray = |angle: f32| {
            let (s, c) = libm::sincosf(angle);
            Vec2::new(c, s)
        };
        let wedge = (width <= core::f32::consts::PI).then(|| (ray(cone.azimuth_min), ray(cone.azimuth_max)));
        let vertical = if cone.elevation_max <= 0.0 {
            Vertical::Down
        } else if cone.elevation_min >= 0.0 {
            Vertical::Up
        } else {
            Vertical::Any
        };
        let (azimuth, elevation) =
            ((cone.azimuth_min + cone.azimuth_max) * 0.5, (cone.elevation_min + cone.elevation_max) * 0.5);
        let horizontal = ray(azimuth) * libm::cosf(elevation);
        let center = Vec3::new(horizontal.x, horizontal.y, libm::sinf(elevation));
        let half_pi = core::f32::consts::FRAC_PI_2;
        let exact = (wedge.is_some() || width >= core::f32::consts::TAU)
            && matches!(
                (
                    cone.elevation_min == -half_pi,
                    cone.elevation_max == 0.0,
                    cone.elevation_min == 0.0,
                    cone.elevation_max == half_pi
                ),
                (true, true, _, _) | (_, _, true, true) | (true, _, _, true)
            );
        let inner_wedge = wedge.map(|_| (ray(cone.azimuth_min + INNER_TURN), ray(cone.azimuth_max - INNER_TURN)));
        Self { wedge, vertical, center, exact, inner_wedge }
    }

    /// Whether the unit direction `d` lies in the cone (closed: a direction along `z` is
    /// in every cone whose elevations reach it), or `None` when the convex cone is not
    /// the cone itself. Directions within [`INNER_TURN`] of the wedge's boundary count as
    /// outside.
    pub(crate) fn contains_within(&self, d: Vec3) -> Option<bool> {
        if !self.exact {
            return None;
        }
        let vertical = match self.vertical {
            Vertical::Down => d.z <= 0.0,
            Vertical::Up => d.z >= 0.0,
            Vertical::Any => true,
        };
        let xy = d.truncate();
        let horizontal = match self.inner_wedge {
            None => true,
            Some((start, end)) => start.perp_dot(xy) >= 0.0 && xy.perp_dot(end) >= 0.0,
        };
        Some(vertical && horizontal && d.is_finite())
    }

    /// A unit direction inside the cone (its centre of azimuth and elevation).
    pub(crate) fn center(&self) -> Vec3 {
        self.center
    }

    /// The projection `P_K(w)` of `w` onto the cone.
    pub(crate) fn project(&self, w: Vec3) -> Vec3 {
        let xy = w.truncate();
        let xy = match self.wedge {
            None => xy,
            Some((start, end)) => {
                let after_start = start.perp_dot(xy) >= 0.0;
                let before_end = xy.perp_dot(end) >= 0.0;
                // For a wedge of width `π` the two tests are the same half-plane test.
                if after_start && before_end {
                    xy
                } else {
                    let (a, b) = (start.dot(xy).max(0.0), end.dot(xy).max(0.0));
                    if a >= b { start * a } else { end * b }
                }
            }
        };
        let z = match self.vertical {
            Vertical::Down => w.z.min(0.0),
            Vertical::Up => w.z.max(0.0),
            Vertical::Any => w.z,
        };
        Vec3::new(xy.x, xy.y, z)
    }

    /// The lower bound `h / |P_K(w)|` of `|p|` over `p ∈ A ∩ K`, for a unit `w` with
    /// `h ≤ h_A(w)`; 0 when `h ≤ 0`. Very large (not infinite) when `w` is polar to the
    /// cone.
    pub(crate) fn bound(&self, w: Vec3, h: f32) -> f32 {
        if h.is_nan() || h <= 0.0 {
            return 0.0;
        }
        h / (self.project(w).length() + PROJECTION_SLACK)
    }
}

/// `h_A(w) = min w · (m − v)` over `m ∈ triangle` and `v` in the box of centre `center`
/// and half-size `half` (exact up to rounding; callers subtract a margin).
pub(crate) fn triangle_box_support(triangle: &Triangle, center: Vec3, half: Vec3, w: Vec3) -> f32 {
    let [a, b, c] = triangle.0.map(|v| v - center);
    w.dot(a).min(w.dot(b)).min(w.dot(c)) - (half.x * w.x.abs() + half.y * w.y.abs() + half.z * w.z.abs())
}

/// `h_A(w) = min w · a` over the box `a ∈ [min, max]`.
pub(crate) fn box_support(min: Vec3, max: Vec3, w: Vec3) -> f32 {
    let pick = |wi: f32, lo: f32, hi: f32| if wi >= 0.0 { wi * lo } else { wi * hi };
    pick(w.x, min.x, max.x) + pick(w.y, min.y, max.y) + pick(w.z, min.z, max.z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cones::{DirectionCones, azimuth_elevation};
    use crate::test_random::uniform;

    #[test]
    fn projections_lie_in_the_cone_and_are_nearest() {
        let mut next = uniform(0x51_7cc1_b727_220a);
        for cones in [
            DirectionCones::downward(8, 1).unwrap(),
            DirectionCones::downward(2, 1).unwrap(),
            DirectionCones::full(3, 3).unwrap(),
        ] {
            for index in 0..cones.count() {
                let cone = cones.cone(index).unwrap();
                let convex = ConvexCone::holding(&cone);
                let (a, e) = azimuth_elevation(convex.center()).unwrap();
                assert!(cone.contains_at(a, e), "centre of cone {index}");
                for _ in 0..500 {
                    let w = Vec3::new(next(), next(), next()) * 2.0 - 1.0;
                    let p = convex.project(w);
                    // Every direction of the cone is no nearer w than p (sampled).
                    let mut nearest = f32::INFINITY;
                    for i in 0..=16 {
                        for j in 0..=16 {
                            let t = cone.azimuth_min + (cone.azimuth_max - cone.azimuth_min) * i as f32 / 16.0;
                            let f = cone.elevation_min + (cone.elevation_max - cone.elevation_min) * j as f32 / 16.0;
                            let d =
                                Vec3::new(libm::cosf(f) * libm::cosf(t), libm::cosf(f) * libm::sinf(t), libm::sinf(f));
                            // The nearest point of the ray through d.
                            nearest = nearest.min(w.distance(d * w.dot(d).max(0.0)));
                        }
                    }
                    assert!(w.distance(p) <= nearest + 1e-5, "cone {index}: {w} -> {p}, sampled {nearest}");
                }
            }
        }
    }
}
