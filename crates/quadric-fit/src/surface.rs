//! The per-voxel C⁰ surface of §3.1 ("Quadratic Surface", steps a–c).
//!
//! Voxel `(i, j, k)` is the unit cube `[i, i+1] × [j, j+1] × [k, k+1]` in grid
//! coordinates, and its quadric `Q_V` (step a, eq. 1, fitted with
//! [`fit_quadric`](crate::fit_quadric) or exact) is given in the same coordinates.
//! [`build_surface`] then
//!
//! 1. intersects each `Q_V` with the voxel's 12 edges ([`edge_crossing`]) and collects,
//!    per grid edge `e`, the list `L(e)` of hit points from all voxels sharing `e` (§3.1 a);
//! 2. replaces every `L(e)` by its average, the representative point of `e` (§3.1 b);
//! 3. orders each voxel's representative points into closed polygons by traversing its
//!    faces: two points are neighbours when their edges bound a common face on which the
//!    voxel's quadric crosses exactly those two edges (§3.1 c);
//! 4. builds the patches of Appendix B through each polygon: 3 points give a triangle
//!    ([`triangle_quadric`]), 4 a bilinear patch ([`bilinear_quadric`]) in polygon order,
//!    more points a fan of bilinear patches closed by a triangle (§3.1 c, "more than one
//!    bilinear (or triangular) patches").
//!
//! Every patch meets a voxel face along the straight segment between two representative
//! points, and the voxel across that face uses the same two points, so the surface is C⁰
//! wherever both voxels' quadrics cross the same edges of the shared face — always when
//! they are fitted to one surface finely enough, and exactly when the quadrics are equal.
//! Where neighbours disagree (one quadric crosses an edge the other misses) the paper
//! suggests a finer grid; this module does not hide the mismatch, it simply builds each
//! voxel from its own crossings.
//!
//! # Which edges a quadric crosses
//!
//! Each voxel's quadric is evaluated once at the voxel's 8 corners, and an edge is crossed
//! when the values at its ends differ in sign, counting 0 as positive (as marching cubes
//! does). Along the edge `Q` is a quadratic `αt² + βt + γ`, so a sign change means exactly
//! one root in `[0, 1]`; it is found in closed form (with the linear case `α ≈ 0` handled
//! separately) and by bisection when rounding makes the closed form fail. Deciding
//! crossings from shared corner values makes every face hold 0, 2 or 4 crossed edges, so
//! every representative point has exactly two neighbours and the polygons are closed.
//!
//! An edge with **two roots** in `(0, 1)` has equal signs at its ends: the surface folds
//! back inside the edge. It is counted in [`VoxelSurface::double_hits`] and not used, as a
//! sign-based cell cannot represent the fold at this resolution.
//!
//! A face with **four** crossed edges is ambiguous (its corners alternate in sign). The
//! voxel's quadric decides it at the face centre: corners with the centre's sign are joined
//! through the centre, so each segment cuts off one corner of the other sign and joins the
//! two crossed edges at that corner (the "asymptotic decider" of marching cubes, with the
//! quadric in place of the bilinear interpolant).

use alloc::collections::BTreeMap;
use alloc::vec::Vec;

use glam::DVec3;

use crate::patch::{bilinear_quadric, triangle_quadric};
use crate::quadric::Quadric;

/// Integer coordinates of a voxel (its lowest corner), or of a grid point.
pub type GridPoint = (u32, u32, u32);

/// An edge of the voxel grid: from `corner` to `corner + e_axis` (§3.1, the edges `e` whose
/// hit lists `L(e)` are averaged).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct GridEdge {
    /// 0, 1 or 2 for x, y or z.
    pub axis: u8,
    /// The lower end of the edge.
    pub corner: GridPoint,
}

impl GridEdge {
    /// The point at parameter `t ∈ [0, 1]` along the edge.
    pub fn point(&self, t: f64) -> DVec3 {
        let mut p = grid_point(self.corner);
        p[usize::from(self.axis % 3)] += t;
        p
    }
}

/// A face of the voxel grid: the unit square at `corner` spanned by the two axes other
/// than `normal`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct GridFace {
    /// 0, 1 or 2: the axis the face is perpendicular to.
    pub normal: u8,
    /// The face's lowest corner.
    pub corner: GridPoint,
}

impl GridFace {
    /// The centre of the face.
    pub fn centre(&self) -> DVec3 {
        let mut p = grid_point(self.corner) + DVec3::splat(0.5);
        p[usize::from(self.normal % 3)] -= 0.5;
        p
    }
}

/// How a quadric meets one edge (§3.1 a, the intersection of `Q_V` with the edges of `V`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EdgeCrossing {
    /// The values at the two ends have the same sign and no fold was found.
    None,
    /// The ends differ in sign: the single root, as a parameter in `[0, 1]`.
    One(f64),
    /// The ends have the same sign but the quadric crosses the edge twice, at these
    /// parameters in `(0, 1)`. Not used by [`build_surface`] (see the module docs).
    Two(f64, f64),
}

/// One triangle or bilinear patch of Appendix B, restricted to its polygon.
#[derive(Clone, Debug, PartialEq)]
pub struct Patch {
    /// The patch's corners in order: 3 for a triangle, 4 for a bilinear patch
    /// `P1, P2, P3, P4`. A tracer keeps only hits inside this polygon.
    pub polygon: Vec<DVec3>,
    /// The quadric through the patch ([`triangle_quadric`] or [`bilinear_quadric`]).
    pub quadric: Quadric,
}

/// One closed polygon of representative points in a voxel and its patches (§3.1 c).
#[derive(Clone, Debug, PartialEq)]
pub struct SurfaceLoop {
    /// The edges of the voxel the polygon passes through, in polygon order.
    pub edges: Vec<GridEdge>,
    /// The representative points of those edges (§3.1 b), in the same order; at least 3.
    pub points: Vec<DVec3>,
    /// The patches covering the polygon: one for 3 or 4 points, a fan for more (patch
    /// `m` of `n > 4` points is the quad `P0, P(2m+1), P(2m+2), P(2m+3)`, and an odd
    /// remainder the triangle `P0, P(n-2), P(n-1)`). Patches whose points are collinear
    /// or coincident describe no surface and are left out, so this may be shorter, or
    /// empty.
    pub patches: Vec<Patch>,
}

/// The surface inside one voxel.
#[derive(Clone, Debug, PartialEq)]
pub struct VoxelSurface {
    /// The polygons; usually one, more where separate sheets cross the voxel.
    pub loops: Vec<SurfaceLoop>,
    /// Edges the quadric crosses twice, ignored (see the module docs).
    pub double_hits: u8,
}

/// Why a voxel of the input has no [`VoxelSurface`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Skipped {
    /// The quadric changes sign across none of the voxel's edges (all corners on one side,
    /// or values that are not numbers).
    NoCrossing,
    /// The voxel touches coordinate `u32::MAX`, so its far corner is not a grid point.
    OutOfRange,
    /// The faces did not close the points into polygons. Cannot happen with crossings
    /// decided from corner signs; kept so that a failure is reported, not a panic.
    Open,
}

/// The C⁰ surface of a voxel grid (§3.1 a–c).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct C0Surface {
    /// The representative point of every crossed edge: the average of its list `L(e)`.
    pub edge_points: BTreeMap<GridEdge, DVec3>,
    /// The surface of each voxel that has one.
    pub voxels: BTreeMap<GridPoint, VoxelSurface>,
    /// The input voxels without a surface, and why.
    pub skipped: BTreeMap<GridPoint, Skipped>,
}

/// `|α|` below this fraction of `|β| + |γ|` makes the edge polynomial linear.
const LINEAR: f64 = 1e-12;

pub(crate) fn grid_point(p: GridPoint) -> DVec3 {
    DVec3::new(f64::from(p.0), f64::from(p.1), f64::from(p.2))
}

pub(crate) fn offset(p: GridPoint, d: [u32; 3]) -> GridPoint {
    (p.0 + d[0], p.1 + d[1], p.2 + d[2])
}

/// The edge of voxel `v` along `axis` whose offsets along the two other axes are taken
/// from `off` (entry `axis` is ignored). Local index `4·axis + u + 2w` with `u`, `w` the
/// offsets along `axis+1` and `axis+2` (mod 3).
fn local_edge(axis: usize, off: [u32; 3]) -> usize {
    4 * axis + off[(axis + 1) % 3] as usize + 2 * off[(axis + 2) % 3] as usize
}

/// The offsets (0 or 1 per axis) of the lower end of local edge `l`.
pub(crate) fn edge_offsets(l: usize) -> (usize, [u32; 3]) {
    let axis = l / 4;
    let mut off = [0; 3];
    off[(axis + 1) % 3] = (l & 1) as u32;
    off[(axis + 2) % 3] = ((l >> 1) & 1) as u32;
    (axis, off)
}

pub(crate) fn corner_index(off: [u32; 3]) -> usize {
    (off[0] + 2 * off[1] + 4 * off[2]) as usize
}

fn negative(value: f64) -> bool {
    value < 0.0
}

/// The root in `[0, 1]` of `αt² + βt + γ` given that it changes sign between
/// `f0 = γ` and `f1`; closed form, with bisection on `f` when rounding defeats it.
fn single_root(alpha: f64, beta: f64, gamma: f64, f: impl Fn(f64) -> f64) -> f64 {
    let closed = if alpha.abs() <= LINEAR * (beta.abs() + gamma.abs()) {
        -gamma / beta
    } else {
        // Stable formula; a sign change guarantees a non-negative discriminant.
        let disc = (beta * beta - 4.0 * alpha * gamma).max(0.0);
        let q = -0.5 * (beta + libm::copysign(libm::sqrt(disc), beta));
        let (r0, r1) = (q / alpha, gamma / q);
        let dist = |r: f64| if r.is_finite() { (r - r.clamp(0.0, 1.0)).abs() } else { f64::INFINITY };
        if dist(r0) <= dist(r1) { r0 } else { r1 }
    };
    if closed.is_finite() && (-1e-9..=1.0 + 1e-9).contains(&closed) {
        return closed.clamp(0.0, 1.0);
    }
    let (mut lo, mut hi) = (0.0, 1.0);
    let low_negative = negative(f(0.0));
    for _ in 0..64 {
        let mid = 0.5 * (lo + hi);
        if negative(f(mid)) == low_negative {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Where `quadric` meets `edge` (§3.1 a): the root of the quadratic `Q(corner + t e_axis)`
/// in `[0, 1]` when the values at the ends differ in sign (0 counts as positive), two roots
/// when the ends agree but the quadric dips across the edge, [`EdgeCrossing::None`]
/// otherwise (also for values that are not numbers). The result is always in `[0, 1]`.
pub fn edge_crossing(quadric: &Quadric, edge: GridEdge) -> EdgeCrossing {
    let axis = usize::from(edge.axis % 3);
    let start = grid_point(edge.corner);
    let mut end = start;
    end[axis] += 1.0;
    crossing_between(quadric, start, axis, quadric.value(start), quadric.value(end))
}

fn crossing_between(quadric: &Quadric, start: DVec3, axis: usize, f0: f64, f1: f64) -> EdgeCrossing {
    let alpha = quadric.coefficients()[axis];
    let beta = quadric.gradient(start)[axis];
    let gamma = f0;
    let f = |t: f64| {
        let mut p = start;
        p[axis] += t;
        quadric.value(p)
    };
    if f0.is_nan() || f1.is_nan() {
        return EdgeCrossing::None;
    }
    if negative(f0) != negative(f1) {
        return EdgeCrossing::One(single_root(alpha, beta, gamma, f));
    }
    // Same signs: two roots iff the vertex lies inside and has the other sign.
    if alpha == 0.0 || !alpha.is_finite() || !beta.is_finite() {
        return EdgeCrossing::None;
    }
    let vertex = -beta / (2.0 * alpha);
    if !(vertex > 0.0 && vertex < 1.0) || negative(f(vertex)) == negative(f0) {
        return EdgeCrossing::None;
    }
    let disc = libm::sqrt((beta * beta - 4.0 * alpha * gamma).max(0.0));
    let half = (disc / (2.0 * alpha)).abs();
    EdgeCrossing::Two((vertex - half).clamp(0.0, 1.0), (vertex + half).clamp(0.0, 1.0))
}

/// The crossings of one voxel: root parameter per local edge, and the corner values.
struct VoxelCrossings {
    t: [Option<f64>; 12],
    corners: [f64; 8],
    double_hits: u8,
}

fn voxel_crossings(voxel: GridPoint, quadric: &Quadric) -> VoxelCrossings {
    let origin = grid_point(voxel);
    let mut corners = [0.0; 8];
    for (c, value) in corners.iter_mut().enumerate() {
        let off = DVec3::new((c & 1) as f64, ((c >> 1) & 1) as f64, ((c >> 2) & 1) as f64);
        *value = quadric.value(origin + off);
    }
    let mut t = [None; 12];
    let mut double_hits = 0;
    for (l, slot) in t.iter_mut().enumerate() {
        let (axis, off) = edge_offsets(l);
        let mut far = off;
        far[axis] = 1;
        let start = origin + DVec3::new(f64::from(off[0]), f64::from(off[1]), f64::from(off[2]));
        let (f0, f1) = (corners[corner_index(off)], corners[corner_index(far)]);
        match crossing_between(quadric, start, axis, f0, f1) {
            EdgeCrossing::One(root) => *slot = Some(root),
            EdgeCrossing::Two(..) => double_hits += 1,
            EdgeCrossing::None => {}
        }
    }
    VoxelCrossings { t, corners, double_hits }
}

/// The neighbours (local edge indices) of each crossed local edge, two per edge when the
/// faces close, from the face traversal of §3.1 c. `corner_negative` are the corners'
/// sides, `crossed` the edges crossed, and `centre_negative(normal, side)` decides an
/// ambiguous face (four crossed edges) by the side of its centre: corners with the
/// centre's side are joined through the centre, so each segment cuts off one corner of
/// the other side.
pub(crate) fn face_links(
    corner_negative: &[bool; 8],
    crossed: &[bool; 12],
    mut centre_negative: impl FnMut(usize, u32) -> bool,
) -> [Vec<usize>; 12] {
    let mut links: [Vec<usize>; 12] = Default::default();
    let mut link = |a: usize, b: usize| {
        links[a].push(b);
        links[b].push(a);
    };
    for normal in 0..3 {
        let (p, q) = ((normal + 1) % 3, (normal + 2) % 3);
        for side in 0..2 {
            // The face's four edges: along p at offset w along q, along q at offset u along p.
            let mut face_off = [0; 3];
            face_off[normal] = side;
            let edge_at = |axis: usize, other: usize, value: u32| {
                let mut off = face_off;
                off[other] = value;
                local_edge(axis, off)
            };
            let edges = [edge_at(p, q, 0), edge_at(p, q, 1), edge_at(q, p, 0), edge_at(q, p, 1)];
            let face_crossed: Vec<usize> = edges.iter().copied().filter(|&l| crossed[l]).collect();
            match face_crossed.len() {
                2 => link(face_crossed[0], face_crossed[1]),
                4 => {
                    let centre = centre_negative(normal, side);
                    for (a, b) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                        let mut off = face_off;
                        off[p] = a;
                        off[q] = b;
                        if corner_negative[corner_index(off)] != centre {
                            // Cut off this corner: join its edge along p and its edge along q.
                            link(edge_at(p, q, b), edge_at(q, p, a));
                        }
                    }
                }
                _ => {}
            }
        }
    }
    links
}

/// Closed polygons through the crossed local edges, or `None` when a point does not have
/// exactly two neighbours.
pub(crate) fn trace_loops(links: &[Vec<usize>; 12], crossed: &[bool; 12]) -> Option<Vec<Vec<usize>>> {
    if (0..12).any(|l| crossed[l] && links[l].len() != 2) {
        return None;
    }
    let mut visited = [false; 12];
    let mut loops = Vec::new();
    for start in 0..12 {
        if !crossed[start] || visited[start] {
            continue;
        }
        let mut cycle = Vec::new();
        let (mut previous, mut current) = (usize::MAX, start);
        loop {
            if visited[current] {
                break;
            }
            visited[current] = true;
            cycle.push(current);
            let next = if links[current][0] != previous { links[current][0] } else { links[current][1] };
            previous = current;
            current = next;
        }
        if current != start || cycle.len() < 3 {
            return None;
        }
        loops.push(cycle);
    }
    Some(loops)
}

/// The polygons of `voxel` through the representative points of its local edge `cycles`
/// (a cycle whose edges lack a point is left out), with their patches.
pub(crate) fn surface_loops(
    voxel: GridPoint,
    cycles: &[Vec<usize>],
    edge_points: &BTreeMap<GridEdge, DVec3>,
) -> Vec<SurfaceLoop> {
    let mut loops = Vec::new();
    for cycle in cycles {
        let edges: Vec<GridEdge> = cycle
            .iter()
            .map(|&l| {
                let (axis, off) = edge_offsets(l);
                GridEdge { axis: axis as u8, corner: offset(voxel, off) }
            })
            .collect();
        let points: Vec<DVec3> = edges.iter().filter_map(|e| edge_points.get(e).copied()).collect();
        if points.len() != edges.len() {
            continue;
        }
        let patches = polygon_patches(&points);
        loops.push(SurfaceLoop { edges, points, patches });
    }
    loops
}

/// The patches through a polygon (§3.1 c, Appendix B): see [`SurfaceLoop::patches`].
pub fn polygon_patches(points: &[DVec3]) -> Vec<Patch> {
    let mut patches = Vec::new();
    let mut push = |polygon: Vec<DVec3>| {
        let quadric = match polygon.as_slice() {
            [a, b, c] => triangle_quadric(*a, *b, *c).ok(),
            [a, b, c, d] => bilinear_quadric(*a, *b, *c, *d).ok(),
            // Only triangles and quads are built below.
            _ => None,
        };
        // A degenerate (collinear) piece has no surface to add: the remaining pieces cover
        // the polygon.
        if let Some(quadric) = quadric {
            patches.push(Patch { polygon, quadric });
        }
    };
    let n = points.len();
    if n < 3 {
        return patches;
    }
    if n <= 4 {
        push(points.to_vec());
        return patches;
    }
    let mut k = 1;
    while k + 2 < n {
        push(alloc::vec![points[0], points[k], points[k + 1], points[k + 2]]);
        k += 2;
    }
    if k + 1 < n {
        push(alloc::vec![points[0], points[k], points[k + 1]]);
    }
    patches
}

/// The C⁰ surface of §3.1 (steps a–c) from one quadric per surface voxel, in grid
/// coordinates (voxel `(i, j, k)` is `[i, i+1] × [j, j+1] × [k, k+1]`). See the module
/// docs for the rules; voxels without a surface are listed in [`C0Surface::skipped`].
pub fn build_surface(quadrics: &BTreeMap<GridPoint, Quadric>) -> C0Surface {
    let mut surface = C0Surface::default();
    // Step a: hits per voxel, and the lists L(e) (kept as running sums).
    let mut lists: BTreeMap<GridEdge, (DVec3, u32)> = BTreeMap::new();
    let mut per_voxel = Vec::new();
    for (&voxel, quadric) in quadrics {
        if voxel.0 == u32::MAX || voxel.1 == u32::MAX || voxel.2 == u32::MAX {
            surface.skipped.insert(voxel, Skipped::OutOfRange);
            continue;
        }
        let crossings = voxel_crossings(voxel, quadric);
        if crossings.t.iter().all(Option::is_none) {
            surface.skipped.insert(voxel, Skipped::NoCrossing);
            continue;
        }
        for (l, t) in crossings.t.iter().enumerate() {
            if let Some(t) = *t {
                let (axis, off) = edge_offsets(l);
                let edge = GridEdge { axis: axis as u8, corner: offset(voxel, off) };
                let entry = lists.entry(edge).or_insert((DVec3::ZERO, 0));
                entry.0 += edge.point(t);
                entry.1 += 1;
            }
        }
        per_voxel.push((voxel, quadric, crossings));
    }
    // Step b: representative points.
    surface.edge_points = lists.into_iter().map(|(e, (sum, n))| (e, sum / f64::from(n))).collect();
    // Step c: polygons by face traversal, then patches.
    for (voxel, quadric, crossings) in per_voxel {
        let crossed = crossings.t.map(|t| t.is_some());
        let corner_negative = crossings.corners.map(negative);
        // An ambiguous face is decided at its centre with the voxel's own quadric.
        let links = face_links(&corner_negative, &crossed, |normal, side| {
            let mut centre = grid_point(voxel) + DVec3::splat(0.5);
            centre[normal] = grid_point(voxel)[normal] + f64::from(side);
            negative(quadric.value(centre))
        });
        let Some(cycles) = trace_loops(&links, &crossed) else {
            surface.skipped.insert(voxel, Skipped::Open);
            continue;
        };
        let loops = surface_loops(voxel, &cycles, &surface.edge_points);
        surface.voxels.insert(voxel, VoxelSurface { loops, double_hits: crossings.double_hits });
    }
    surface
}
