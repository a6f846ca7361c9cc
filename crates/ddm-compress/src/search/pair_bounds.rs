//! Lower bounds of a box–triangle pair's distance along a convex cone's directions: the
//! separating axes of the pair (with the denominators that the triangle's own axes share
//! across boxes) and the duality bounds over them, refined by a pattern search.

use alloc::vec::Vec;

use glam::Vec3;

use crate::cones::Cone;
use crate::convex_cone::{ConvexCone, triangle_box_support};
use crate::geometry::{Aabb, Triangle};

/// The separating axes of a triangle that do not depend on the box (those of
/// [`crate::geometry::separation_lower_bound`] but the centres' axis: the coordinate
/// axes, the normal and the 9 edge–axis cross products), normalised, with the interval of
/// the triangle's vertices along each. Splitting the box keeps them, so they are computed
/// once per triangle piece.
#[derive(Clone, Copy)]
pub(crate) struct TriangleAxes {
    axes: [Vec3; 16],
    /// `(min, max)` of `axis · vertex`.
    extent: [(f32, f32); 16],
    count: usize,
    /// Largest vertex coordinate magnitude (for the rounding margin).
    magnitude: f32,
}

impl TriangleAxes {
    /// The axes of `triangle`.
    pub(crate) fn of(triangle: &Triangle) -> Self {
        let [a, b, c] = triangle.0;
        let edges = [b - a, c - b, a - c];
        let mut axes = Self {
            axes: [Vec3::ZERO; 16],
            extent: [(0.0, 0.0); 16],
            count: 0,
            magnitude: a.abs().max(b.abs()).max(c.abs()).max_element(),
        };
        let mut add = |axis: Vec3| {
            let length_squared = axis.length_squared();
            if length_squared.is_nan() || length_squared <= 1e-20 {
                return;
            }
            let axis = axis / libm::sqrtf(length_squared);
            let (pa, pb, pc) = (a.dot(axis), b.dot(axis), c.dot(axis));
            axes.axes[axes.count] = axis;
            axes.extent[axes.count] = (pa.min(pb).min(pc), pa.max(pb).max(pc));
            axes.count += 1;
        };
        add(Vec3::X);
        add(Vec3::Y);
        add(Vec3::Z);
        add(edges[0].cross(edges[1]));
        for edge in edges {
            add(edge.cross(Vec3::X));
            add(edge.cross(Vec3::Y));
            add(edge.cross(Vec3::Z));
        }
        axes
    }

    /// The axes of `self` with the extents of `triangle`, a translated copy of the
    /// triangle `self` belongs to (a periodic neighbour). Any unit axis bounds the
    /// distance along it, so these are as valid as the copy's own (which differ from them
    /// by rounding), and the copy shares the triangle's [`AxisDenominators`] exactly.
    pub(crate) fn translated(&self, triangle: &Triangle) -> Self {
        let [a, b, c] = triangle.0;
        let mut axes = Self { magnitude: a.abs().max(b.abs()).max(c.abs()).max_element(), ..*self };
        for (extent, axis) in axes.extent[..axes.count].iter_mut().zip(&self.axes) {
            let (pa, pb, pc) = (a.dot(*axis), b.dot(*axis), c.dot(*axis));
            *extent = (pa.min(pb).min(pc), pa.max(pb).max(pc));
        }
        axes
    }

    /// The axes along which the triangle and `aabb` are apart, each oriented from the box
    /// to the triangle with its gap `h ≤ h_A(w)`, and the largest gap (with the axis
    /// joining the centres): a lower bound of their distance.
    pub(super) fn apart_from(&self, triangle: &Triangle, aabb: &Aabb) -> SeparatingAxes {
        let center = aabb.center();
        let half = aabb.max - center;
        let scale = 1.0 + center.abs().max_element() + self.magnitude + half.max_element();
        let margin = 1e-6 * scale;
        let mut apart =
            SeparatingAxes { axes: [(Vec3::ZERO, 0.0); 17], slots: [CENTRE_SLOT; 17], count: 0, gap: 0.0, margin };
        let mut push = |axis: Vec3, low: f32, high: f32, slot: u8| {
            let s = axis.dot(center);
            let r = half.x * axis.x.abs() + half.y * axis.y.abs() + half.z * axis.z.abs();
            let (forward, backward) = (low - s - r - margin, s - r - high - margin);
            let (entry, slot) = if forward > 0.0 {
                ((axis, forward), slot)
            } else if backward > 0.0 {
                ((-axis, backward), slot | 1)
            } else {
                return;
            };
            apart.gap = apart.gap.max(entry.1);
            apart.axes[apart.count] = entry;
            apart.slots[apart.count] = slot;
            apart.count += 1;
        };
        for (j, (&axis, &(low, high))) in self.axes[..self.count].iter().zip(&self.extent).enumerate() {
            push(axis, low, high, 2 * j as u8);
        }
        let centers = triangle.center() - center;
        let length = centers.length();
        if length > 1e-12 && length.is_finite() {
            let axis = centers / length;
            let [a, b, c] = triangle.0;
            let (pa, pb, pc) = (a.dot(axis), b.dot(axis), c.dot(axis));
            push(axis, pa.min(pb).min(pc), pa.max(pb).max(pc), CENTRE_SLOT);
        }
        apart
    }
}

/// The slot of [`SeparatingAxes::slots`] that has no denominator in [`AxisDenominators`].
pub(super) const CENTRE_SLOT: u8 = u8::MAX;

/// Denominators per triangle and cone: two per axis of [`TriangleAxes`].
pub(super) const AXIS_SLOTS: usize = 32;

/// At most this many bytes of [`AxisDenominators`]; beyond, they are computed as needed.
pub(super) const MAX_DENOMINATOR_BYTES: usize = 128 << 20;

/// The denominators `|P_K(±a)| + slack` of [`ConvexCone::bound`] for each fixed axis `a`
/// of each triangle ([`TriangleAxes`]) and each cone of a search, computed once: the
/// axes do not depend on the box, so every pair of the triangle with a voxel (or a piece
/// of one) reuses them. The bound is the same number computed either way.
pub(crate) struct AxisDenominators {
    /// `values[(triangle · cones + cone) · AXIS_SLOTS + slot]`, `slot` as in
    /// [`SeparatingAxes::slots`]; empty when over [`MAX_DENOMINATOR_BYTES`].
    values: Vec<f32>,
    /// Cones per triangle.
    cones: usize,
    /// Distinct triangles: the hierarchy's triangle `i` is a translated copy (same axes)
    /// of triangle `i mod triangles`.
    triangles: usize,
}

impl AxisDenominators {
    /// The denominators of `cones` for the first `triangles` of `axes` (the later ones
    /// being translated copies of those).
    pub(crate) fn new(cones: &[Option<Cone>], axes: &[TriangleAxes], triangles: usize) -> Self {
        let triangles = triangles.min(axes.len());
        let size = triangles * cones.len() * AXIS_SLOTS;
        if size * size_of::<f32>() > MAX_DENOMINATOR_BYTES {
            return Self { values: Vec::new(), cones: cones.len(), triangles };
        }
        let convex: Vec<Option<ConvexCone>> = cones.iter().map(|c| c.as_ref().map(ConvexCone::holding)).collect();
        let mut values = Vec::with_capacity(size);
        for triangle_axes in &axes[..triangles] {
            for convex in &convex {
                let mut slots = [f32::NAN; AXIS_SLOTS];
                if let Some(convex) = convex {
                    for (j, &axis) in triangle_axes.axes[..triangle_axes.count].iter().enumerate() {
                        slots[2 * j] = convex.bound_denominator(axis);
                        slots[2 * j + 1] = convex.bound_denominator(-axis);
                    }
                }
                values.extend_from_slice(&slots);
            }
        }
        Self { values, cones: cones.len(), triangles }
    }

    /// The denominators of the hierarchy's triangle `index` for every cone, or `None`
    /// when they were not stored.
    pub(super) fn of(&self, index: usize) -> Option<&[f32]> {
        let base = index.checked_rem(self.triangles)?;
        let per_triangle = self.cones * AXIS_SLOTS;
        self.values.get(base * per_triangle..(base + 1) * per_triangle)
    }
}

/// The axes along which a box–triangle pair is apart ([`TriangleAxes::apart_from`]).
pub(super) struct SeparatingAxes {
    /// `(unit axis w, h ≤ h_A(w))`, oriented from the box to the triangle.
    axes: [(Vec3, f32); 17],
    /// Where each axis' denominator lies in [`AxisDenominators`]: `2 j` for the
    /// triangle's axis `j`, `2 j + 1` for its opposite, [`CENTRE_SLOT`] for the axis
    /// joining the centres (which depends on the box).
    slots: [u8; 17],
    count: usize,
    pub(super) gap: f32,
    /// Rounding margin subtracted from every gap.
    pub(super) margin: f32,
}

/// A lower bound of the distance from `aabb` to `triangle` along directions of `convex`
/// ([`ConvexCone::bound`] over the separating axes `apart` of the pair, with the
/// denominators of the triangle's own axes from `denominators` when given, the projection of
/// the centres' offset onto the cone and its polar part), and the best axis other than the
/// polar one (the projected offset when no separating axis gives a positive bound; `None`
/// when that is zero too): where a witness is likely.
pub(super) fn cone_bound(
    convex: &ConvexCone,
    triangle: &Triangle,
    aabb: &Aabb,
    apart: &SeparatingAxes,
    denominators: Option<&[f32]>,
) -> (f32, Option<Vec3>) {
    let (center, half) = (aabb.center(), (aabb.max - aabb.min) * 0.5);
    let (mut g, mut best_axis) = (0.0_f32, None);
    for (&(axis, h), &slot) in apart.axes[..apart.count].iter().zip(&apart.slots) {
        let bound = match denominators.and_then(|d| d.get(usize::from(slot))) {
            Some(&denominator) => ConvexCone::bound_over(h, denominator),
            None => convex.bound(axis, h),
        };
        if bound > g {
            (g, best_axis) = (bound, Some(axis));
        }
    }
    let offset = triangle.center() - center;
    let q = convex.project(offset);
    let length = q.length();
    if length > 1e-6 {
        // A unit direction of the cone: no projection needed.
        let q = q / length;
        let bound = ConvexCone::bound_within(triangle_box_support(triangle, center, half, q) - apart.margin);
        if bound > g {
            (g, best_axis) = (bound, Some(q));
        } else {
            best_axis = best_axis.or(Some(q));
        }
    }
    // The offset's part polar to the cone separates the pair's offsets from the cone
    // when `h_A` is positive along it.
    let polar = offset - q;
    let polar_length = polar.length();
    if polar_length > 1e-6 * (1.0 + length) {
        let w = polar / polar_length;
        g = g.max(convex.bound(w, triangle_box_support(triangle, center, half, w) - apart.margin));
    }
    (g, best_axis)
}

/// The largest [`ConvexCone::bound`] of the pair (`aabb`, `triangle`) found by a pattern
/// search over unit `w` around `start` (whose bound is `start_bound`), and its `w`; the
/// search stops as soon as a bound reaches `enough` (where the caller needs no more).
/// Every `w` gives a valid lower bound, so the search only has to be good, not exact.
pub(super) fn improve_bound(
    convex: &ConvexCone,
    triangle: &Triangle,
    aabb: &Aabb,
    margin: f32,
    start: Vec3,
    start_bound: f32,
    enough: f32,
) -> (f32, Vec3) {
    let (center, half) = (aabb.center(), (aabb.max - aabb.min) * 0.5);
    let value = |w: Vec3| convex.bound(w, triangle_box_support(triangle, center, half, w) - margin);
    let (mut w, mut best) = (start, start_bound.max(value(start)));
    for step in [0.2_f32, 0.05, 0.0125] {
        for _ in 0..2 {
            let helper = if w.z.abs() < 0.9 { Vec3::Z } else { Vec3::X };
            let u = w.cross(helper).normalize_or_zero();
            let v = w.cross(u);
            let mut improved = false;
            for direction in [u, -u, v, -v] {
                let candidate = (w + direction * step).normalize_or_zero();
                let bound = value(candidate);
                if bound > best {
                    (best, w, improved) = (bound, candidate, true);
                    if best >= enough {
                        return (best, w);
                    }
                }
            }
            if !improved {
                break;
            }
        }
    }
    (best, w)
}
