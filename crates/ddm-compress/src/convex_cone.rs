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
//! convex; [`ConvexCone`] is a convex cone holding it: the product `wedge × z-interval`
//! (exactly the cone for the downward `m × 1` cones with `m ≥ 2`), cut by half-spaces
//! when the band of elevations does not reach from a pole to the horizon:
//! - a band that stops short of the pole (the band `[−45°, 0°]` of a DDM `m × 2`), in a
//!   wedge narrower than `π`: the *chord plane* through the band's outer elevation at
//!   the wedge's two boundary azimuths. The band lies on one side of it (the arc between
//!   the two rays bulges away from the pole);
//! - a band that stops short of the horizon (`[−90°, −45°]`): the directions beyond its
//!   inner elevation `φ` form a convex circular cone, which lies inside each of its
//!   tangent half-spaces; those at the wedge's two boundary azimuths and its centre.
//!
//! Without the cuts the band `[−45°, 0°]` would be bounded as if it held the straight-down
//! direction, and its map would store the plain downward distance (the DDM 4×2 measured
//! no better than the 4×1). Since `A ∩ C ⊆ A ∩ K` for `C ⊆ K`, a bound for `K` holds for
//! `C`.
//!
//! The projection onto the cut cone, `K = {x : nᵢ · x ≤ 0}` for up to seven normals, is
//! the orthogonal projection onto the span of the face of `K` that holds it: a face's
//! plane (accepted when the point lands in `K`: the optimality conditions then hold), or
//! else the edge (the line where two faces meet, whose rays in `K` are found once per
//! cone) whose point in `K` lies nearest `w`, or the apex. A plane's point has the form
//! `w − λ nᵢ` with `λ ≥ 0`, never shorter than the projection (Moreau), so rounding there
//! can only weaken a bound; the edges' membership is decided with a slack, so that
//! rounding keeps the true edge among the candidates.

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

/// How far outside the faces (relative to `|d|`, about an angle in radians) a witness's
/// direction may lie ([`ConvexCone::contains_nearly`]). Integer geometry meets a cone
/// often only on its boundary: from a voxel inside a maze wall, the steep band `[−90°,
/// −45°]` reaches the wall's foot exactly along `−45°` and nowhere else, and the rounding
/// of the band's tangent planes puts that direction a hair outside, so that no witness
/// exists and every pair is split down to the tolerance's size. The search then computes
/// the distance over the cone widened by this angle, which is still at most the cone's
/// (a value stays a lower bound), and its lower bounds hold there, since they hold for
/// every direction within [`PROJECTION_SLACK`], ten times this, of the cone.
pub(crate) const WITNESS_SLACK: f32 = 1e-6;

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
    /// Outward normals `n` of the half-spaces `n · x ≤ 0` whose intersection is the cone
    /// (the first `face_count`), computed once: the wedge's two walls, the `z` sign
    /// constraint, then from `first_cut` on the cuts of the product (see the module
    /// documentation): the chord plane of a band of elevations of one sign that stops
    /// short of the pole, in a wedge narrower than `π`, then the tangent planes of the
    /// band's inner elevation (nearer the horizon) when it is not the horizon.
    faces: [Vec3; 3 + MAX_CUTS],
    /// Where the cuts start in `faces`.
    first_cut: usize,
    /// How many of `faces` are used.
    face_count: usize,
    /// The cone's edges: unit directions `r` along the line where two faces meet, with
    /// whether `r` (and `−r`) lies in the cone, for the edges where one of them does (see
    /// [`ConvexCone::project_onto_cut`]); the first `edge_count` are used.
    edges: [(Vec3, bool, bool); MAX_EDGES],
    edge_count: usize,
}

/// At most this many edges: one per pair of faces.
const MAX_EDGES: usize = (3 + MAX_CUTS) * (2 + MAX_CUTS) / 2;

/// How far outside a face (relative to `|w|`) a candidate of
/// [`ConvexCone::project_onto_cut`] may lie and still count as in the cone: rounding of
/// the small solve, far below the bound's [`PROJECTION_SLACK`].
const FEASIBLE_SLACK: f32 = 1e-6;

/// At most this many cutting half-spaces: a chord plane and three tangent planes.
const MAX_CUTS: usize = 4;

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
        // The band's elevation farthest from the horizon, when it is not the pole.
        let outer = match vertical {
            Vertical::Down if cone.elevation_min > -half_pi => Some(cone.elevation_min),
            Vertical::Up if cone.elevation_max < half_pi => Some(cone.elevation_max),
            _ => None,
        };
        let chord = outer.filter(|_| width < core::f32::consts::PI).and_then(|elevation| {
            let direction = |azimuth: f32| {
                let (h, z) = (ray(azimuth) * libm::cosf(elevation), libm::sinf(elevation));
                Vec3::new(h.x, h.y, z)
            };
            let normal = direction(cone.azimuth_min).cross(direction(cone.azimuth_max)).normalize_or_zero();
            // Oriented so that the cone lies on the side `n · x ≤ 0`.
            let normal = if normal.dot(center) > 0.0 { -normal } else { normal };
            (normal != Vec3::ZERO).then_some(normal)
        });
        // The band's elevation nearer the horizon, when it is not the horizon: the
        // directions below `φ < 0` (above `φ > 0`) form a convex circular cone around the
        // pole, which holds the band and lies inside each of its tangent half-spaces
        // `z − tan φ (x cos a + y sin a) ≤ 0` (sign flipped for `φ > 0`), taken at the wedge's
        // two boundary azimuths and its centre.
        let inner = match vertical {
            Vertical::Down if cone.elevation_max < 0.0 => Some((cone.elevation_max, 1.0)),
            Vertical::Up if cone.elevation_min > 0.0 => Some((cone.elevation_min, -1.0)),
            _ => None,
        };
        let mut faces = [Vec3::ZERO; 3 + MAX_CUTS];
        let mut face_count = 0;
        // The wedge's walls and the `z` sign constraint come first.
        let first_cut = 2 * usize::from(wedge.is_some()) + usize::from(vertical != Vertical::Any);
        let mut push = |normal: Vec3| {
            faces[face_count] = normal;
            face_count += 1;
        };
        if let Some((start, end)) = wedge {
            // `start ⟂ xy ≥ 0` and `xy ⟂ end ≥ 0` as `n · x ≤ 0`.
            push(Vec3::new(start.y, -start.x, 0.0));
            push(Vec3::new(-end.y, end.x, 0.0));
        }
        match vertical {
            Vertical::Down => push(Vec3::Z),
            Vertical::Up => push(-Vec3::Z),
            Vertical::Any => {}
        }
        if let Some(normal) = chord {
            push(normal);
        }
        if let Some((elevation, sign)) = inner {
            let slope = libm::tanf(elevation);
            for azimuth in [cone.azimuth_min, azimuth, cone.azimuth_max] {
                let h = ray(azimuth) * -slope;
                push((Vec3::new(h.x, h.y, 1.0) * sign).normalize());
            }
        }
        let (edges, edge_count) = edges_of(&faces[..face_count]);
        Self { wedge, vertical, center, exact, inner_wedge, faces, first_cut, face_count, edges, edge_count }
    }

    /// The cuts of the product cone (see `faces`).
    fn cuts(&self) -> &[Vec3] {
        &self.faces[self.first_cut..self.face_count]
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

    /// Whether the direction `d` lies in the convex cone widened by [`WITNESS_SLACK`]
    /// (`n · d ≤ WITNESS_SLACK |d|` for every face normal `n`; finite `d` only).
    pub(crate) fn contains_nearly(&self, d: Vec3) -> bool {
        let slack = WITNESS_SLACK * d.length();
        d.is_finite() && self.faces[..self.face_count].iter().all(|n| n.dot(d) <= slack)
    }

    /// A unit direction inside the cone (its centre of azimuth and elevation).
    pub(crate) fn center(&self) -> Vec3 {
        self.center
    }

    /// The projection `P_K(w)` of `w` onto the cone.
    pub(crate) fn project(&self, w: Vec3) -> Vec3 {
        let product = self.project_onto_product(w);
        // The product's projection is the cut cone's when it lies in the cut cone.
        if self.cuts().iter().all(|n| n.dot(product) <= 0.0) { product } else { self.project_onto_cut(w) }
    }

    /// The projection onto `wedge × z-interval`, without the chord plane.
    fn project_onto_product(&self, w: Vec3) -> Vec3 {
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

    /// The projection onto the product cone cut by the half-spaces of `cuts`, `K = {x :
    /// nᵢ · x ≤ 0}` over all the faces (the wedge's two walls, the `z` sign constraint and
    /// the cuts): `w` itself when it lies in `K`. Otherwise the projection lies inside a face of `K` of
    /// dimension 2, 1 or 0, and is then the orthogonal projection of `w` onto that face's
    /// span: a face's plane `nᵢ⊥`, the line where two faces meet (an edge) or the apex.
    ///
    /// - On a face's plane: `p = w − (nᵢ · w) nᵢ` with `nᵢ · w > 0`; when `p` lies in `K` it
    ///   meets the optimality conditions (Karush–Kuhn–Tucker) and is the projection. It has
    ///   the form `w − λ nᵢ` with `λ ≥ 0`, which is never shorter than the projection
    ///   (Moreau), so a `p` that rounding lets through keeps the bound safe.
    /// - Otherwise on an edge `r` (or at the apex): every `t r` in `K` is a point of `K`, so
    ///   no nearer `w` than the projection, and for it `|w − t r|² = |w|² − t²` with
    ///   `t = w · r`; the projection is the edge point of largest `|t|` in `K` (which edges'
    ///   rays lie in `K` is computed once, [`edges_of`]), or the apex when none is.
    fn project_onto_cut(&self, w: Vec3) -> Vec3 {
        let normals = &self.faces[..self.face_count];
        let slack = FEASIBLE_SLACK * w.length();
        if normals.iter().all(|n| n.dot(w) <= 0.0) {
            return w;
        }
        for n in normals {
            let along = n.dot(w);
            if along > 0.0 {
                let p = w - *n * (along / n.length_squared());
                if normals.iter().all(|m| m.dot(p) <= slack) {
                    return p;
                }
            }
        }
        let mut best = (0.0, Vec3::ZERO);
        for &(r, forward, backward) in &self.edges[..self.edge_count] {
            let t = r.dot(w);
            if (t > 0.0 && forward || t < 0.0 && backward) && t * t > best.0 {
                best = (t * t, r * t);
            }
        }
        best.1
    }

    /// The projection as [`ConvexCone::project_onto_cut`] computed it before: `w − Σ λᵢ nᵢ`
    /// of least length over `λ ≥ 0` (the subtracted part is the projection onto the polar
    /// cone, generated by the `nᵢ`), over every active set of at most three normals.
    #[cfg(test)]
    fn project_onto_cut_exhaustively(&self, w: Vec3) -> Vec3 {
        let (normals, count) = (&self.faces[..self.face_count], self.face_count);
        let mut best = w;
        let mut consider = |polar: Option<Vec3>| {
            if let Some(polar) = polar {
                let candidate = w - polar;
                if candidate.length_squared() < best.length_squared() {
                    best = candidate;
                }
            }
        };
        for i in 0..count {
            consider(polar_part(w, &[normals[i]]));
            for j in i + 1..count {
                consider(polar_part(w, &[normals[i], normals[j]]));
                for k in j + 1..count {
                    consider(polar_part(w, &[normals[i], normals[j], normals[k]]));
                }
            }
        }
        best
    }

    /// The lower bound `h / |P_K(w)|` of `|p|` over `p ∈ A ∩ K`, for a unit `w` with
    /// `h ≤ h_A(w)`; 0 when `h ≤ 0`. Very large (not infinite) when `w` is polar to the
    /// cone.
    pub(crate) fn bound(&self, w: Vec3, h: f32) -> f32 {
        if h.is_nan() || h <= 0.0 {
            return 0.0;
        }
        h / self.bound_denominator(w)
    }

    /// The denominator `|P_K(w)| + δ` of [`ConvexCone::bound`] (see [`PROJECTION_SLACK`]).
    pub(crate) fn bound_denominator(&self, w: Vec3) -> f32 {
        self.project(w).length() + PROJECTION_SLACK
    }

    /// A lower bound, at most [`ConvexCone::bound`], for a unit `w` that the caller knows
    /// lies in the cone (a projection onto it, normalised), without projecting: `|P_K(w)|
    /// ≤ |w| = 1` for every unit `w` (a projection onto a convex cone does not lengthen),
    /// so `h / (1 + δ)` never exceeds `h / (|P_K(w)| + δ)`, and equals it when `w` is in
    /// the cone.
    pub(crate) fn bound_within(h: f32) -> f32 {
        Self::bound_over(h, 1.0 + PROJECTION_SLACK)
    }

    /// [`ConvexCone::bound`] from its denominator ([`ConvexCone::bound_denominator`]).
    pub(crate) fn bound_over(h: f32, denominator: f32) -> f32 {
        if h.is_nan() || h <= 0.0 {
            return 0.0;
        }
        h / denominator
    }
}

/// The edges of the cone `{x : nᵢ · x ≤ 0}` (see [`ConvexCone::edges`]): for each pair of
/// faces that are not parallel, the unit direction of their common line, kept when it or
/// its opposite lies in the cone (within [`FEASIBLE_SLACK`], so that rounding keeps a
/// true edge).
fn edges_of(normals: &[Vec3]) -> ([(Vec3, bool, bool); MAX_EDGES], usize) {
    let mut edges = [(Vec3::ZERO, false, false); MAX_EDGES];
    let mut count = 0;
    for (i, a) in normals.iter().enumerate() {
        for b in &normals[i + 1..] {
            let r = a.cross(*b);
            let length_squared = r.length_squared();
            if length_squared.is_nan() || length_squared <= 1e-12 || count == MAX_EDGES {
                continue;
            }
            let r = r / libm::sqrtf(length_squared);
            let forward = normals.iter().all(|n| n.dot(r) <= FEASIBLE_SLACK);
            let backward = normals.iter().all(|n| n.dot(r) >= -FEASIBLE_SLACK);
            if forward || backward {
                edges[count] = (r, forward, backward);
                count += 1;
            }
        }
    }
    (edges, count)
}

#[cfg(test)]
/// `Σ λᵢ nᵢ` for the `λ` that minimises `|w − Σ λᵢ nᵢ|` over the span of `normals` (one
/// to three), or `None` when a `λᵢ` is negative (another active set holds the projection)
/// or the normals are (nearly) dependent.
fn polar_part(w: Vec3, normals: &[Vec3]) -> Option<Vec3> {
    let lambdas: [f32; 3] = match *normals {
        [a] => [a.dot(w) / a.length_squared(), 0.0, 0.0],
        [a, b] => {
            let (aa, ab, bb) = (a.dot(a), a.dot(b), b.dot(b));
            let det = aa * bb - ab * ab;
            if det <= 1e-9 {
                return None;
            }
            let (wa, wb) = (a.dot(w), b.dot(w));
            [(bb * wa - ab * wb) / det, (aa * wb - ab * wa) / det, 0.0]
        }
        [a, b, c] => {
            let det = a.dot(b.cross(c));
            if det.abs() <= 1e-6 {
                return None;
            }
            [w.dot(b.cross(c)) / det, w.dot(c.cross(a)) / det, w.dot(a.cross(b)) / det]
        }
        _ => return None,
    };
    // NaN fails too.
    if !lambdas.iter().all(|&l| l >= 0.0) {
        return None;
    }
    Some(normals.iter().zip(lambdas).map(|(&n, l)| n * l).sum())
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

    /// The directions of `cone` on an `(n + 1)²` grid of azimuths and elevations, edges
    /// included.
    fn cone_directions(cone: &Cone, n: u32) -> impl Iterator<Item = Vec3> + '_ {
        (0..=n).flat_map(move |i| {
            (0..=n).map(move |j| {
                let t = cone.azimuth_min + (cone.azimuth_max - cone.azimuth_min) * i as f32 / n as f32;
                let f = cone.elevation_min + (cone.elevation_max - cone.elevation_min) * j as f32 / n as f32;
                Vec3::new(libm::cosf(f) * libm::cosf(t), libm::cosf(f) * libm::sinf(t), libm::sinf(f))
            })
        })
    }

    #[test]
    fn projections_lie_in_the_cone_and_are_nearest() {
        let mut next = uniform(0x51_7cc1_b727_220a);
        for cones in [
            DirectionCones::downward(8, 1).unwrap(),
            DirectionCones::downward(2, 1).unwrap(),
            DirectionCones::full(3, 3).unwrap(),
            DirectionCones::downward(4, 2).unwrap(),
            DirectionCones::downward(8, 3).unwrap(),
            DirectionCones::full(4, 4).unwrap(),
        ] {
            for index in 0..cones.count() {
                let cone = cones.cone(index).unwrap();
                let convex = ConvexCone::holding(&cone);
                let (a, e) = azimuth_elevation(convex.center()).unwrap();
                assert!(cone.contains_at(a, e), "centre of cone {index}");
                for _ in 0..500 {
                    let w = Vec3::new(next(), next(), next()) * 2.0 - 1.0;
                    let p = convex.project(w);
                    // Every direction of the cone is no nearer w than p (sampled; the nearest
                    // point of the ray through each direction).
                    let nearest = cone_directions(&cone, 16)
                        .map(|d| w.distance(d * w.dot(d).max(0.0)))
                        .fold(f32::INFINITY, f32::min);
                    assert!(w.distance(p) <= nearest + 1e-5, "cone {index}: {w} -> {p}, sampled {nearest}");
                }
            }
        }
    }

    #[test]
    fn faces_and_edges_give_the_projection_of_every_active_set() {
        let mut next = uniform(0x0dd_b1a5_e5ba_d5ee);
        let (mut compared, mut cut) = (0, 0);
        for cones in [
            DirectionCones::downward(4, 2).unwrap(),
            DirectionCones::full(6, 4).unwrap(),
            DirectionCones::downward(1, 3).unwrap(),
            DirectionCones::full(3, 3).unwrap(),
        ] {
            for index in 0..cones.count() {
                let convex = ConvexCone::holding(&cones.cone(index).unwrap());
                for _ in 0..2000 {
                    let w = Vec3::new(next(), next(), next()) * 2.0 - 1.0;
                    let (fast, exhaustive) = (convex.project_onto_cut(w), convex.project_onto_cut_exhaustively(w));
                    // Never shorter (the bound stays safe), as short up to rounding and in the
                    // cone. (Where two faces meet at a grazing angle, points differing by
                    // 1e-4 across the edge can have lengths equal to 1e-8.)
                    let (fast_length, exhaustive_length) = (fast.length(), exhaustive.length());
                    assert!(fast_length >= exhaustive_length - 1e-6, "cone {index}: {w} -> {fast} vs {exhaustive}");
                    assert!(fast_length <= exhaustive_length + 1e-5, "cone {index}: {w} -> {fast} vs {exhaustive}");
                    let outside =
                        convex.faces[..convex.face_count].iter().map(|n| n.dot(fast)).fold(f32::MIN, f32::max);
                    assert!(outside <= 1e-5, "cone {index}: {w} -> {fast}, outside by {outside}");
                    compared += 1;
                    cut += usize::from(!convex.cuts().iter().all(|n| n.dot(convex.project_onto_product(w)) <= 0.0));
                }
            }
        }
        std::println!("{compared} projections compared, {cut} of them outside the product's cuts");
        assert_eq!(compared, 2000 * (8 + 24 + 3 + 9));
    }

    #[test]
    fn the_cuts_hold_the_band_and_cut_off_the_pole() {
        for cones in [
            DirectionCones::downward(4, 2).unwrap(),
            DirectionCones::downward(8, 3).unwrap(),
            DirectionCones::full(6, 4).unwrap(),
        ] {
            for index in 0..cones.count() {
                let cone = cones.cone(index).unwrap();
                let convex = ConvexCone::holding(&cone);
                let half_pi = core::f32::consts::FRAC_PI_2;
                let (down, up) = (cone.elevation_max <= 0.0, cone.elevation_min >= 0.0);
                let chord = down && cone.elevation_min > -half_pi || up && cone.elevation_max < half_pi;
                let inner = down && cone.elevation_max < 0.0 || up && cone.elevation_min > 0.0;
                let expected = usize::from(chord) + 3 * usize::from(inner);
                assert_eq!(convex.cuts().len(), expected, "cone {cone:?}");
                // Every direction of the cone is on the inner side (sampled, edges included).
                for cut in convex.cuts() {
                    for d in cone_directions(&cone, 32) {
                        assert!(cut.dot(d) <= 1e-6, "cone {cone:?}: {d} outside by {}", cut.dot(d));
                    }
                }
            }
        }
        // The band [−45°, 0°] of a DDM 4×2: seen from a plane h below, its nearest point
        // in the cut cone is at √1.5 h (exact cone: √2 h; without the cut: h), so the
        // projection of straight down has length 1/√1.5.
        let cones = DirectionCones::downward(4, 2).unwrap();
        let convex = ConvexCone::holding(&cones.cone(4).unwrap());
        let length = convex.project(-Vec3::Z).length();
        assert!((length - 1.0 / 1.5_f32.sqrt()).abs() < 1e-5, "{length}");
        assert!((convex.bound(-Vec3::Z, 1.0) - 1.5_f32.sqrt()).abs() < 1e-3);
    }
}
