//! One voxel patch as the tracer stores it: a quadric (eq. 1) clipped to the polygon of
//! §3.1 c, laid out for the GPU; the polygon test, and a ray's nearest hit among a voxel's
//! patches (Algorithm 3.2).

use glam::{Vec2, Vec3, Vec4};
use gpu_layout::gpu_struct;
use quadric_fit::{GpuQuadric, first_hit};

use crate::voxel::NUDGE;

/// `TracePatch::ij_corners.w` of a *bounded* patch: its hits count only inside its
/// polygon even when it is alone in its voxel (the exact triangles of
/// [`crate::exact_patches`]). Other patches store 0 there.
pub const BOUNDED_PATCH: f32 = 1.0;

/// Tolerance of the polygon test, in voxels: a hit this far outside a patch's polygon
/// still counts, so that neighbouring patches of a fan overlap instead of leaving a crack.
pub const POLYGON_TOLERANCE: f32 = 1e-4;

gpu_struct! {
    /// One quadric patch of a zero-distance voxel, voxel-local (see
    /// [`crate::patches`]).
    pub struct TracePatch {
        /// `(A, B, C, D)` of eq. 1.
        pub abcd: Vec4,
        /// `(E, F, G, H)`.
        pub efgh: Vec4,
        /// `(I, J, corners, bounded)`: the last coefficients, the polygon's corner count (3
        /// or 4) and [`BOUNDED_PATCH`] for a patch clipped to its polygon even when alone
        /// in its voxel (0 otherwise).
        pub ij_corners: Vec4,
        /// The polygon's unit Newell normal in `xyz`; `w` zero.
        pub normal: Vec4,
        /// The polygon's corners in order (`w` zero); a triangle repeats its last corner.
        pub corners: [Vec4; 4],
    }
}

/// Whether the voxel-local point `p` lies inside the patch's polygon seen along its Newell
/// normal, up to [`POLYGON_TOLERANCE`]: on the inner side of every edge (the polygons of
/// §3.1 c are convex in practice; a concave one loses hits near its reflex corner). WGSL
/// twin: `trace_inside_polygon`.
pub fn inside_polygon(patch: &TracePatch, p: Vec3) -> bool {
    let n = patch.normal.truncate();
    let corners = patch.corners.map(Vec4::truncate);
    let count = if patch.ij_corners.z > 3.5 { 4 } else { 3 };
    for i in 0..count {
        let a = corners[i];
        let b = corners[(i + 1) % count];
        let edge = b - a;
        let side = edge.cross(p - a).dot(n);
        let length = edge.length();
        if side < -POLYGON_TOLERANCE * length {
            return false;
        }
    }
    true
}

/// How far inside the patch's polygon the voxel-local point `p` lies, seen along its
/// Newell normal as [`inside_polygon`] sees it: the smallest signed distance to the lines
/// of its edges (positive inside), in voxels. [`inside_polygon`] accepts down to
/// `-POLYGON_TOLERANCE`; a hit with a negative margin lies in the band where neighbouring
/// patches overlap.
pub fn polygon_margin(patch: &TracePatch, p: Vec3) -> f32 {
    let n = patch.normal.truncate();
    let corners = patch.corners.map(Vec4::truncate);
    let count = if patch.ij_corners.z > 3.5 { 4 } else { 3 };
    let mut margin = f32::INFINITY;
    for i in 0..count {
        let a = corners[i];
        let edge = corners[(i + 1) % count] - a;
        let length = edge.length();
        if length > 0.0 {
            margin = margin.min(edge.cross(p - a).dot(n) / length);
        }
    }
    margin
}

/// The nearest hit of the ray `local + t direction`, `t ∈ [-NUDGE, t_exit]`, with
/// `patches` (voxel-local): `(t, patch index)`. With one unbounded patch any hit in the
/// segment counts; with several, or on a bounded patch ([`BOUNDED_PATCH`]:
/// an exact triangle), only hits inside the patch's polygon (Algorithm 3.2 over the
/// voxel's patches). The segment starts [`NUDGE`] before the voxel wall: a surface lying on
/// the wall (a floor at an integer height) is otherwise lost whenever the rounded entry
/// point lands a few ulps past it.
pub fn patch_hit(patches: &[TracePatch], local: Vec3, direction: Vec3, t_exit: f32) -> Option<(f32, usize)> {
    let mut best: Option<(f32, usize)> = None;
    for (index, patch) in patches.iter().enumerate() {
        let Some(t) = first_hit(&quadric_of(patch), local, direction, -NUDGE, t_exit) else { continue };
        let clipped = patches.len() > 1 || patch.ij_corners.w == BOUNDED_PATCH;
        if clipped && !inside_polygon(patch, local + direction * t) {
            continue;
        }
        if best.is_none_or(|b| t < b.0) {
            best = Some((t, index));
        }
    }
    best
}

/// The quadric of a patch.
pub fn quadric_of(patch: &TracePatch) -> GpuQuadric {
    GpuQuadric { abcd: patch.abcd, efgh: patch.efgh, ij: patch.ij_corners.truncate().truncate(), padding: Vec2::ZERO }
}
