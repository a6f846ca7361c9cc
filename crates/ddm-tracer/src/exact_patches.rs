//! Exact triangle patches, and the per-voxel choice between a voxel's fitted quadric and
//! its exact triangles under an error budget (beyond the paper).
//!
//! §3.1 replaces the mesostructure inside a zero-distance voxel by quadric patches. On
//! the meshes the tracer is measured against (faceted spheres and tori, and the sharp
//! edges and corners of height fields such as mazes and bricks) one quadric per voxel
//! cannot follow the mesh to 10⁻³ voxel, and the C⁰ construction of steps b–c cuts the
//! corners of voxels that hold two sheets (`cargo xtask ddm-trace` measures both). The
//! mesh itself is exact: a voxel can keep the triangles that cross it, each stored as a
//! plane patch ([`crate::patch::TracePatch`]) *bounded* by its triangle
//! ([`crate::patch::BOUNDED_PATCH`]), and the tracer's Algorithm 3.2 then returns the
//! mesh's own first hit inside the voxel. Two triangles of a voxel that form a convex
//! planar quadrilateral (a mesh's quad, split in two) share one 4-corner patch
//! ([`MERGE_TOLERANCE`]). Triangles still cost one 128-byte patch each (or pair) where a
//! quadric costs one per voxel, so [`crate::PatchSurface::Adaptive`] keeps the fitted
//! quadric wherever it is good enough:
//!
//! - [`representation_error`] traces probe segments through the voxel with both
//!   representations (the tracer's own [`patch_hit`]): [`PROBE_POINTS_PER_AXIS`]³ points
//!   inside the voxel, each crossed by the [`probe_directions`], down- and upward (view
//!   and shadow rays);
//! - a segment where both hit contributes the distance between the two hits; a segment
//!   where only one hits at `t` contributes the distance from `t` to the other
//!   representation's first hit on `[t − UNMATCHED_ERROR, t + UNMATCHED_ERROR]` (the
//!   other may place it just outside the voxel; both lists hold whole surfaces, which
//!   extend past the voxel), or [`UNMATCHED_ERROR`] when there is none there. A quadric
//!   sheet lying on a voxel face where the mesh has no surface (the fit of a wall top
//!   whose side lies on the face is the pair of planes) is caught this way: the tracer
//!   accepts hits up to the segment's end;
//! - the error is the largest contribution.
//!
//! The probes sample the voxel; they are not a proof: a quadric may still stray between
//! them, which the tracer measurements against the mesh show.

use alloc::vec::Vec;

use ddm_compress::Triangle;
use ddm_compress::geometry::{Aabb, triangle_overlaps_box};
use glam::{DVec3, Vec3, Vec4};
use quadric_fit::{GpuQuadric, Quadric};

use crate::patch::{BOUNDED_PATCH, TracePatch, patch_hit};
use crate::voxel::{NUDGE, voxel_exit};

/// Probe points per axis of a voxel in [`representation_error`] (at `(i + ½)/n`).
pub const PROBE_POINTS_PER_AXIS: u32 = 3;

/// The error (voxels) of a probe hit that the other representation does not match
/// within this distance; also the reach of that search.
pub const UNMATCHED_ERROR: f32 = 0.5;

/// Angles from the vertical, in degrees, of the [`probe_directions`] (each at 8
/// azimuths except 0°, down and up).
pub const PROBE_ANGLES_DEG: [f32; 5] = [0.0, 30.0, 55.0, 75.0, 85.0];

/// The probe directions: [`PROBE_ANGLES_DEG`] from straight down and from straight up,
/// at 8 azimuths (one direction for 0°), 66 in all.
pub fn probe_directions() -> Vec<Vec3> {
    let mut directions = Vec::new();
    for sign in [-1.0_f32, 1.0] {
        for angle in PROBE_ANGLES_DEG {
            let theta = angle.to_radians();
            let azimuths = if angle == 0.0 { 1 } else { 8 };
            for a in 0..azimuths {
                // Odd multiples of 22.5°: no probe runs along a voxel wall.
                let phi = (a as f32 + 0.5) * core::f32::consts::TAU / 8.0;
                let (s, c) = (libm::sinf(theta), libm::cosf(theta));
                directions.push(Vec3::new(s * libm::cosf(phi), s * libm::sinf(phi), sign * c));
            }
        }
    }
    directions
}

/// The bounded plane patch of `triangle` (grid coordinates) relative to the voxel corner
/// `origin`: the triangle's plane (computed in `f64`, then moved to the voxel's frame)
/// and its three corners as the polygon. `None` for a degenerate (zero-area or
/// non-finite) triangle.
pub fn triangle_patch(triangle: &[Vec3; 3], origin: DVec3) -> Option<TracePatch> {
    let corners = triangle.map(|v| v.as_dvec3() - origin);
    bounded_patch(&corners, triangle_normal(&corners)?)
}

/// The unit normal of the voxel-local triangle `t` (right-handed order), `None` when
/// degenerate or not finite.
fn triangle_normal(t: &[DVec3; 3]) -> Option<DVec3> {
    let normal = (t[1] - t[0]).cross(t[2] - t[0]);
    let length = normal.length();
    (length.is_finite() && length > 0.0).then(|| normal / length)
}

/// The bounded patch of the convex, counter-clockwise (about `normal`) voxel-local polygon
/// `corners` (3 or 4): its plane through corner 0 and the polygon.
fn bounded_patch(corners: &[DVec3], normal: DVec3) -> Option<TracePatch> {
    if !(3..=4).contains(&corners.len()) {
        return None;
    }
    let plane = Quadric::plane(normal, -normal.dot(corners[0])).ok()?;
    let gpu = GpuQuadric::from_quadric(&plane);
    let corner = |i: usize| corners[i.min(corners.len() - 1)].as_vec3().extend(0.0);
    Some(TracePatch {
        abcd: gpu.abcd,
        efgh: gpu.efgh,
        ij_corners: Vec4::new(gpu.ij.x, gpu.ij.y, corners.len() as f32, BOUNDED_PATCH),
        normal: normal.as_vec3().extend(0.0),
        corners: [corner(0), corner(1), corner(2), corner(3)],
    })
}

/// How far (voxels) the far corner of a triangle may lie from its neighbour's plane for
/// the two to merge into one quadrilateral patch: the `f32` rounding of the vertices of a
/// planar quad (a sphere's or a torus's facet) is about 1e-6 voxel on tiles of a few dozen
/// voxels, 1000 times below the accuracy goal of 1e-3 voxel.
pub const MERGE_TOLERANCE: f64 = 1e-6;

/// The convex quadrilateral `[p, s, q, r]` of two voxel-local triangles that share an edge
/// (`a` has `p → q`, `b` has `q → p`, exactly equal corners), lie in one plane (`b`'s far
/// corner `s` within [`MERGE_TOLERANCE`] of `a`'s plane, normals on the same side) and
/// turn the same way at every corner; `None` otherwise.
fn merged_quad(a: &[DVec3; 3], b: &[DVec3; 3], normal: DVec3) -> Option<[DVec3; 4]> {
    if normal.dot(triangle_normal(b)?) < 0.99 {
        return None;
    }
    for i in 0..3 {
        let (p, q, r) = (a[i], a[(i + 1) % 3], a[(i + 2) % 3]);
        for j in 0..3 {
            if b[j] == q && b[(j + 1) % 3] == p {
                let s = b[(j + 2) % 3];
                if normal.dot(s - p).abs() > MERGE_TOLERANCE {
                    return None;
                }
                let quad = [p, s, q, r];
                let convex = (0..4).all(|k| {
                    let (u, v, w) = (quad[k], quad[(k + 1) % 4], quad[(k + 2) % 4]);
                    (v - u).cross(w - v).dot(normal) > 1e-12
                });
                return convex.then_some(quad);
            }
        }
    }
    None
}

/// The bounded patches of the `triangles` (grid coordinates) that touch the unit voxel
/// with lowest corner `corner`, grown by `2 NUDGE` (the tracer's segment in a voxel starts
/// [`NUDGE`] before its entry wall), relative to `corner`. Two touching triangles that
/// share an edge and form a convex planar quadrilateral (the two halves of a mesh's quad)
/// become one 4-corner patch: the same surface, half the patches.
pub fn voxel_triangle_patches<'a>(
    triangles: impl IntoIterator<Item = &'a [Vec3; 3]>,
    corner: Vec3,
    out: &mut Vec<TracePatch>,
) {
    let grown = Aabb { min: corner - Vec3::splat(2.0 * NUDGE), max: corner + Vec3::splat(1.0 + 2.0 * NUDGE) };
    let origin = corner.as_dvec3();
    let touching: Vec<([DVec3; 3], DVec3)> = triangles
        .into_iter()
        .filter(|t| triangle_overlaps_box(&Triangle(**t), &grown))
        .filter_map(|t| {
            let local = t.map(|v| v.as_dvec3() - origin);
            Some((local, triangle_normal(&local)?))
        })
        .collect();
    let mut used = alloc::vec![false; touching.len()];
    for i in 0..touching.len() {
        if used[i] {
            continue;
        }
        used[i] = true;
        let (a, normal) = &touching[i];
        let partner = (i + 1..touching.len())
            .filter(|&j| !used[j])
            .find_map(|j| merged_quad(a, &touching[j].0, *normal).map(|quad| (j, quad)));
        let patch = match partner {
            Some((j, quad)) => {
                used[j] = true;
                bounded_patch(&quad, *normal)
            }
            None => bounded_patch(a, *normal),
        };
        out.extend(patch);
    }
}

/// How far (voxels) the hits of `candidate` stray from those of `exact` on the probe
/// segments of a unit voxel (see the module documentation); both are voxel-local patch
/// lists as the tracer reads them. `directions` are unit vectors ([`probe_directions`]).
pub fn representation_error(candidate: &[TracePatch], exact: &[TracePatch], directions: &[Vec3]) -> f32 {
    let n = PROBE_POINTS_PER_AXIS;
    let mut worst = 0.0_f32;
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let inside = (Vec3::new(i as f32, j as f32, k as f32) + 0.5) / n as f32;
                for &d in directions {
                    // The segment through `inside`, from the voxel's entry wall.
                    let entry = inside - d * voxel_exit(inside, -d);
                    let t_exit = voxel_exit(entry, d);
                    let a = patch_hit(candidate, entry, d, t_exit).map(|h| h.0);
                    let b = patch_hit(exact, entry, d, t_exit).map(|h| h.0);
                    let error = match (a, b) {
                        (Some(a), Some(b)) => (a - b).abs(),
                        (Some(t), None) => unmatched_error(exact, entry, d, t),
                        (None, Some(t)) => unmatched_error(candidate, entry, d, t),
                        (None, None) => 0.0,
                    };
                    worst = worst.max(error);
                }
            }
        }
    }
    worst
}

/// The distance from `t` to the first hit of `patches` on the ray `entry + s direction`,
/// `s ∈ [t − UNMATCHED_ERROR, t + UNMATCHED_ERROR]`, capped at [`UNMATCHED_ERROR`].
fn unmatched_error(patches: &[TracePatch], entry: Vec3, direction: Vec3, t: f32) -> f32 {
    let from = entry + direction * (t - UNMATCHED_ERROR);
    patch_hit(patches, from, direction, 2.0 * UNMATCHED_ERROR)
        .map_or(UNMATCHED_ERROR, |(s, _)| (s - UNMATCHED_ERROR).abs().min(UNMATCHED_ERROR))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad(z: f32) -> [[Vec3; 3]; 2] {
        let (a, b, c, d) =
            (Vec3::new(-1.0, -1.0, z), Vec3::new(3.0, -1.0, z), Vec3::new(3.0, 3.0, z), Vec3::new(-1.0, 3.0, z));
        [[a, b, c], [a, c, d]]
    }

    #[test]
    fn a_triangle_patch_is_hit_only_inside_its_triangle() {
        let corner = DVec3::new(4.0, 5.0, 1.0);
        let triangle = [Vec3::new(4.0, 5.0, 1.5), Vec3::new(5.0, 5.0, 1.5), Vec3::new(4.0, 6.0, 1.5)];
        let patch = triangle_patch(&triangle, corner).unwrap();
        let down = Vec3::NEG_Z;
        // Inside the triangle (x + y < 1 locally) the plane z = 0.5 is hit; outside not.
        let hit = patch_hit(&[patch], Vec3::new(0.2, 0.3, 1.0), down, 1.0).unwrap();
        assert!((hit.0 - 0.5).abs() < 1e-6);
        assert_eq!(patch_hit(&[patch], Vec3::new(0.7, 0.6, 1.0), down, 1.0), None);
        // Degenerate triangles give no patch.
        assert_eq!(triangle_patch(&[Vec3::ZERO, Vec3::X, Vec3::X * 2.0], corner), None);
        assert_eq!(triangle_patch(&[Vec3::ZERO, Vec3::X, Vec3::NAN], corner), None);
    }

    #[test]
    fn triangles_are_kept_by_the_voxels_they_touch() {
        let mut out = Vec::new();
        // A floor on the voxel wall z = 2 belongs to the voxels below and above it.
        // The two triangles of the quad become one 4-corner patch.
        voxel_triangle_patches(&quad(2.0), Vec3::new(0.0, 0.0, 1.0), &mut out);
        assert_eq!(out.len(), 1);
        assert_eq!(out[0].ij_corners.z, 4.0);
        out.clear();
        voxel_triangle_patches(&quad(2.0), Vec3::new(0.0, 0.0, 2.0), &mut out);
        assert_eq!(out.len(), 1);
        out.clear();
        voxel_triangle_patches(&quad(2.0), Vec3::new(0.0, 0.0, 3.0), &mut out);
        assert!(out.is_empty());
    }

    #[test]
    fn only_coplanar_convex_pairs_sharing_an_edge_are_merged() {
        let corner = Vec3::ZERO;
        let (a, b, c, d) =
            (Vec3::new(0.0, 0.0, 0.5), Vec3::new(1.0, 0.0, 0.5), Vec3::new(1.0, 1.0, 0.5), Vec3::new(0.0, 1.0, 0.5));
        let mut out = Vec::new();
        // Folded along the shared diagonal: two patches.
        voxel_triangle_patches(&[[a, b, c], [a, c, d + Vec3::Z * 0.2]], corner, &mut out);
        assert_eq!(out.len(), 2);
        // A concave union (the fourth corner pulled inside): two patches.
        out.clear();
        voxel_triangle_patches(&[[a, b, c], [a, c, Vec3::new(0.7, 0.6, 0.5)]], corner, &mut out);
        assert_eq!(out.len(), 2);
        // Opposite orientations (the second triangle flipped): two patches.
        out.clear();
        voxel_triangle_patches(&[[a, b, c], [a, d, c]], corner, &mut out);
        assert_eq!(out.len(), 2);
        // The merged quad is hit exactly where either triangle is, and only there.
        out.clear();
        voxel_triangle_patches(&[[a, b, c], [a, c, d]], corner, &mut out);
        assert_eq!(out.len(), 1);
        let mut separate = Vec::new();
        for t in [[a, b, c], [a, c, d]] {
            separate.extend(triangle_patch(&t, DVec3::ZERO));
        }
        assert!(representation_error(&out, &separate, &probe_directions()) < 1e-6);
    }

    #[test]
    fn the_error_of_a_representation_is_measured_on_probe_segments() {
        let directions = probe_directions();
        assert_eq!(directions.len(), 66);
        assert!(directions.iter().all(|d| (d.length() - 1.0).abs() < 1e-6));
        let corner = Vec3::new(0.0, 0.0, 0.0);
        let mut floor = Vec::new();
        voxel_triangle_patches(&quad(0.4), corner, &mut floor);
        // The plane itself, unbounded: the same hits.
        let plane = |z: f64| {
            let gpu = GpuQuadric::from_quadric(&Quadric::plane(DVec3::Z, -z).unwrap());
            TracePatch {
                abcd: gpu.abcd,
                efgh: gpu.efgh,
                ij_corners: Vec4::new(gpu.ij.x, gpu.ij.y, 0.0, 0.0),
                ..bytemuck::Zeroable::zeroed()
            }
        };
        assert!(representation_error(&[plane(0.4)], &floor, &directions) < 1e-5);
        // A plane 0.01 higher: vertical probes see 0.01, grazing ones up to 0.01 / cos 85°.
        let error = representation_error(&[plane(0.41)], &floor, &directions);
        assert!(error > 0.01 && error < 0.12, "{error}");
        // No surface at all where the floor is: unmatched hits.
        assert_eq!(representation_error(&[], &floor, &directions), UNMATCHED_ERROR);
        // A wall top whose side lies on the voxel face x = 1 (the mesh: the top z = 0.4
        // for x ≤ 1 and the side x = 1 below it), against the pair of planes
        // (x − 1)(z − 0.4) = 0, whose sheet x = 1 above the top lies on the face.
        let top = [Vec3::new(-1.0, -1.0, 0.4), Vec3::new(1.0, -1.0, 0.4), Vec3::new(1.0, 3.0, 0.4)];
        let top2 = [Vec3::new(-1.0, -1.0, 0.4), Vec3::new(1.0, 3.0, 0.4), Vec3::new(-1.0, 3.0, 0.4)];
        let side = [Vec3::new(1.0, -1.0, 0.4), Vec3::new(1.0, -1.0, -2.0), Vec3::new(1.0, 3.0, -2.0)];
        let side2 = [Vec3::new(1.0, -1.0, 0.4), Vec3::new(1.0, 3.0, -2.0), Vec3::new(1.0, 3.0, 0.4)];
        let mut wall = Vec::new();
        voxel_triangle_patches(&[top, top2, side, side2], corner, &mut wall);
        // `side` lies below z = -0.2 over the voxel: the top's quad and `side2` touch it.
        assert_eq!(wall.len(), 2);
        let pair = Quadric::new([0.0, 0.0, 0.0, 0.0, 0.0, 1.0, -0.4, 0.0, -1.0, 0.4]).unwrap();
        let gpu = GpuQuadric::from_quadric(&pair);
        let pair = TracePatch {
            abcd: gpu.abcd,
            efgh: gpu.efgh,
            ij_corners: Vec4::new(gpu.ij.x, gpu.ij.y, 0.0, 0.0),
            ..bytemuck::Zeroable::zeroed()
        };
        assert!(representation_error(&[pair], &wall, &directions) >= UNMATCHED_ERROR);
    }
}
