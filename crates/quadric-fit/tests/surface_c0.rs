//! The per-voxel C⁰ construction of §3.1 (steps a–c) on a sphere and a tilted plane:
//! neighbouring patches meet along identical face segments, representative points lie on
//! the true surface, and every patch passes through its polygon's points. Random inputs
//! never panic.

use std::collections::{BTreeMap, BTreeSet};

use glam::DVec3;
use proptest::prelude::*;
use quadric_fit::surface::{EdgeCrossing, GridEdge, GridPoint, Skipped, edge_crossing};
use quadric_fit::{C0Surface, Quadric, build_surface, fit_quadric};

const GRID: u32 = 9;

fn corner(v: GridPoint) -> DVec3 {
    DVec3::new(f64::from(v.0), f64::from(v.1), f64::from(v.2))
}

/// Voxels of the grid whose corners are not all on one side of `signed`.
fn crossed_voxels(signed: impl Fn(DVec3) -> f64) -> Vec<GridPoint> {
    let mut out = Vec::new();
    for i in 0..GRID {
        for j in 0..GRID {
            for k in 0..GRID {
                let o = corner((i, j, k));
                let signs: BTreeSet<bool> = (0..8)
                    .map(|c| signed(o + DVec3::new(f64::from(c & 1), f64::from((c >> 1) & 1), f64::from(c >> 2))) < 0.0)
                    .collect();
                if signs.len() == 2 {
                    out.push((i, j, k));
                }
            }
        }
    }
    out
}

/// Faces shared by two of `voxels` whose four corners are not all on one side of
/// `signed`: the faces the surface crosses, which `check_c0` must find segments on.
fn crossed_shared_faces(voxels: &[GridPoint], signed: impl Fn(DVec3) -> f64) -> usize {
    let set: BTreeSet<GridPoint> = voxels.iter().copied().collect();
    let mut count = 0;
    for &v in voxels {
        for normal in 0..3 {
            let mut w = [v.0, v.1, v.2];
            w[normal] += 1;
            if !set.contains(&(w[0], w[1], w[2])) {
                continue;
            }
            let o = corner((w[0], w[1], w[2]));
            let (a, b) = ((normal + 1) % 3, (normal + 2) % 3);
            let signs: BTreeSet<bool> = (0..4)
                .map(|c| {
                    let mut p = o;
                    p[a] += f64::from(c & 1);
                    p[b] += f64::from(c >> 1);
                    signed(p) < 0.0
                })
                .collect();
            count += usize::from(signs.len() == 2);
        }
    }
    count
}

/// Step a: fit each voxel's quadric to points of the true surface in the voxel and its
/// half-voxel neighbourhood (a 7³ lattice projected onto the surface).
fn fitted(voxels: &[GridPoint], project: impl Fn(DVec3) -> DVec3) -> BTreeMap<GridPoint, Quadric> {
    let mut quadrics = BTreeMap::new();
    for &v in voxels {
        let lo = corner(v) - DVec3::splat(0.5);
        let mut points = Vec::new();
        for a in 0..7 {
            for b in 0..7 {
                for c in 0..7 {
                    let p = project(lo + DVec3::new(f64::from(a), f64::from(b), f64::from(c)) / 3.0);
                    if p.cmpge(lo).all() && p.cmple(lo + DVec3::splat(2.0)).all() {
                        points.push(p);
                    }
                }
            }
        }
        let fit = fit_quadric(&points).expect("enough surface points near a crossed voxel");
        quadrics.insert(v, fit.quadric);
    }
    quadrics
}

/// Whether `edge` lies on the face `x_normal = plane`.
fn on_face(edge: &GridEdge, normal: usize, plane: u32) -> bool {
    let c = [edge.corner.0, edge.corner.1, edge.corner.2];
    usize::from(edge.axis) != normal && c[normal] == plane
}

/// The segments (pairs of consecutive polygon edges) of `voxel` on face `x_normal = plane`.
fn face_segments(surface: &C0Surface, voxel: GridPoint, normal: usize, plane: u32) -> BTreeSet<(GridEdge, GridEdge)> {
    let mut out = BTreeSet::new();
    for l in &surface.voxels[&voxel].loops {
        let n = l.edges.len();
        for i in 0..n {
            let (a, b) = (l.edges[i], l.edges[(i + 1) % n]);
            if on_face(&a, normal, plane) && on_face(&b, normal, plane) {
                out.insert((a.min(b), a.max(b)));
            }
        }
    }
    out
}

/// The largest `|Q|/|∇Q|`, over the patches of `voxel` that have `p` and `q` as
/// consecutive corners, at 11 points of the segment `pq`; `None` if no patch has it.
fn segment_on_patch(surface: &C0Surface, voxel: GridPoint, p: DVec3, q: DVec3) -> Option<f64> {
    let mut worst = None;
    for l in &surface.voxels[&voxel].loops {
        for patch in &l.patches {
            let n = patch.polygon.len();
            let has = (0..n).any(|i| {
                let (a, b) = (patch.polygon[i], patch.polygon[(i + 1) % n]);
                (a == p && b == q) || (a == q && b == p)
            });
            if has {
                let d = (0..=10)
                    .map(|s| patch.quadric.distance_estimate(p.lerp(q, f64::from(s) / 10.0)).unwrap_or(f64::INFINITY))
                    .fold(0.0, f64::max);
                worst = Some(worst.map_or(d, |w: f64| w.max(d)));
            }
        }
    }
    worst
}

/// Checks (i) and (iii); returns (shared faces checked, max segment distance, max point
/// distance to its own patch, number of 3-, 4- and >4-point polygons).
fn check_c0(surface: &C0Surface) -> (usize, f64, f64, [usize; 3]) {
    let (mut faces, mut seg_max, mut point_max, mut sizes) = (0, 0.0_f64, 0.0_f64, [0; 3]);
    for (&v, vs) in &surface.voxels {
        for l in &vs.loops {
            assert!(l.points.len() >= 3);
            sizes[(l.points.len() - 3).min(2)] += 1;
            assert!(!l.patches.is_empty(), "{v:?}: no patch for {:?}", l.points);
            if l.points.len() <= 4 {
                assert_eq!(l.patches.len(), 1);
                assert_eq!(l.patches[0].polygon, l.points);
            }
            for patch in &l.patches {
                for &p in &patch.polygon {
                    point_max = point_max.max(patch.quadric.distance_estimate(p).unwrap_or(f64::INFINITY));
                }
            }
        }
        for normal in 0..3 {
            let mut w = [v.0, v.1, v.2];
            w[normal] += 1;
            let w = (w[0], w[1], w[2]);
            if !surface.voxels.contains_key(&w) {
                continue;
            }
            let plane = [v.0, v.1, v.2][normal] + 1;
            let (mine, theirs) = (face_segments(surface, v, normal, plane), face_segments(surface, w, normal, plane));
            assert_eq!(mine, theirs, "face between {v:?} and {w:?}");
            for (a, b) in &mine {
                let (p, q) = (surface.edge_points[a], surface.edge_points[b]);
                for voxel in [v, w] {
                    let d = segment_on_patch(surface, voxel, p, q).expect("a patch bounded by the face segment");
                    seg_max = seg_max.max(d);
                }
            }
            faces += usize::from(!mine.is_empty());
        }
    }
    (faces, seg_max, point_max, sizes)
}

fn sphere() -> (DVec3, f64) {
    (DVec3::new(4.37, 4.21, 3.93), 2.71)
}

#[test]
fn sphere_from_fitted_quadrics_is_c0() {
    let (c, r) = sphere();
    let voxels = crossed_voxels(|p| p.distance(c) - r);
    let surface = build_surface(&fitted(&voxels, |p| c + (p - c).normalize() * r));
    assert_eq!(surface.voxels.len(), voxels.len(), "skipped: {:?}", surface.skipped);
    let (faces, seg_max, point_max, sizes) = check_c0(&surface);
    let rep_max = surface.edge_points.values().map(|p| (p.distance(c) - r).abs()).fold(0.0, f64::max);
    println!(
        "sphere: {} voxels, {} edges, {faces} shared faces, polygons 3/4/>4 = {sizes:?}, \
         max segment distance {seg_max:.2e}, max patch-point distance {point_max:.2e}, \
         max representative-point distance to the sphere {rep_max:.2e}",
        surface.voxels.len(),
        surface.edge_points.len()
    );
    // Every face the sphere crosses between two crossed voxels is checked.
    assert_eq!(faces, crossed_shared_faces(&voxels, |p| p.distance(c) - r));
    assert!(sizes[0] > 0 && sizes[1] > 0, "{sizes:?}");
    // The patches pass through their polygons' points by construction, and a sphere is a
    // quadric, so the fit reproduces it: what remains is `f64` rounding (~1e-15 relative
    // per operation; the fit's normal equations lose a few digits to their condition),
    // far below 1e-9 (segments, points) and 1e-6 (the fit).
    assert!(seg_max < 1e-9, "{seg_max}");
    assert!(point_max < 1e-9, "{point_max}");
    assert!(rep_max < 1e-6, "{rep_max}");
}

#[test]
fn sphere_patches_stay_close_to_the_sphere() {
    // Between the representative points the patches are bilinear, not spherical. The
    // polygon's centroid is an average of points of the sphere less than a voxel diagonal
    // (√3) apart, so it lies within the sagitta of such a chord, r - √(r² - 3/4).
    let (c, r) = sphere();
    let exact =
        Quadric::new([1.0, 1.0, 1.0, 0.0, 0.0, 0.0, -2.0 * c.x, -2.0 * c.y, -2.0 * c.z, c.length_squared() - r * r])
            .expect("sphere");
    let voxels = crossed_voxels(|p| p.distance(c) - r);
    let surface = build_surface(&voxels.iter().map(|&v| (v, exact)).collect());
    let mut worst = 0.0_f64;
    for vs in surface.voxels.values() {
        for l in &vs.loops {
            let centroid = l.points.iter().copied().sum::<DVec3>() / l.points.len() as f64;
            worst = worst.max((centroid.distance(c) - r).abs());
        }
    }
    let sagitta = r - (r * r - 0.75).sqrt();
    println!("sphere (exact quadric): max polygon-centroid distance to the sphere {worst:.3} (sagitta {sagitta:.3})");
    assert!(worst < sagitta, "{worst}");
    check_c0(&surface);
}

#[test]
fn tilted_plane_exact_and_fitted_is_c0() {
    let n = DVec3::new(0.3, 0.5, 0.81).normalize();
    let o = DVec3::new(4.1, 4.2, 4.3);
    let voxels = crossed_voxels(|p| n.dot(p - o));
    let exact = Quadric::plane(n, -n.dot(o)).expect("plane");
    for (label, quadrics) in
        [("exact", voxels.iter().map(|&v| (v, exact)).collect()), ("fitted", fitted(&voxels, |p| p - n * n.dot(p - o)))]
    {
        let surface = build_surface(&quadrics);
        assert_eq!(surface.voxels.len(), voxels.len(), "{label}: skipped {:?}", surface.skipped);
        let (faces, seg_max, point_max, sizes) = check_c0(&surface);
        let rep_max = surface.edge_points.values().map(|p| n.dot(*p - o).abs()).fold(0.0, f64::max);
        println!(
            "plane ({label}): {} voxels, {faces} shared faces, polygons 3/4/>4 = {sizes:?}, \
             max segment distance {seg_max:.2e}, max patch-point distance {point_max:.2e}, \
             max representative-point distance {rep_max:.2e}",
            surface.voxels.len()
        );
        // Every face the plane crosses between two crossed voxels is checked.
        assert_eq!(faces, crossed_shared_faces(&voxels, |p| n.dot(p - o)), "{label}");
        assert!(sizes[0] > 0 && sizes[1] > 0 && sizes[2] > 0, "{sizes:?}");
        // Exact by construction (and a plane is a quadric): `f64` rounding only.
        assert!(seg_max < 1e-9 && point_max < 1e-9 && rep_max < 1e-9, "{seg_max} {point_max} {rep_max}");
    }
}

#[test]
fn ambiguous_face_is_decided_at_its_centre() {
    // (x - ½)(y - ½) - ε: both z-faces have four crossings; the sheets cut off the corners
    // (0, 0) and (1, 1), where the product is positive, and the centre is negative.
    let q = Quadric::new([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -0.5, -0.5, 0.0, 0.25 - 0.01]).expect("saddle");
    let surface = build_surface(&BTreeMap::from([((0, 0, 0), q)]));
    let loops = &surface.voxels[&(0, 0, 0)].loops;
    assert_eq!(loops.len(), 2);
    for l in loops {
        assert_eq!(l.points.len(), 4);
        let near_origin = l.points.iter().all(|p| p.x + p.y < 1.0);
        let near_far = l.points.iter().all(|p| p.x + p.y > 1.0);
        assert!(near_origin ^ near_far, "{:?}", l.points);
        assert!(l.patches[0].quadric.is_plane());
    }
    // With the opposite constant the centre is positive and the other corners are cut.
    let q = Quadric::new([0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -0.5, -0.5, 0.0, 0.25 + 0.01]).expect("saddle");
    let surface = build_surface(&BTreeMap::from([((0, 0, 0), q)]));
    for l in &surface.voxels[&(0, 0, 0)].loops {
        assert!(l.points.iter().all(|p| p.x > p.y) || l.points.iter().all(|p| p.x < p.y), "{:?}", l.points);
    }
}

#[test]
fn edge_crossings_linear_double_and_none() {
    let x = GridEdge { axis: 0, corner: (2, 0, 0) };
    // Plane x = 2.25: linear along the edge.
    let plane = Quadric::plane(DVec3::X, -2.25).expect("plane");
    match edge_crossing(&plane, x) {
        EdgeCrossing::One(t) => assert!((t - 0.25).abs() < 1e-15, "{t}"),
        other => panic!("{other:?}"),
    }
    // (x - 2.5)² - 0.01: crosses twice, at 2.4 and 2.6.
    let dip = Quadric::new([1.0, 0.0, 0.0, 0.0, 0.0, 0.0, -5.0, 0.0, 0.0, 6.24]).expect("dip");
    match edge_crossing(&dip, x) {
        EdgeCrossing::Two(a, b) => assert!((a - 0.4).abs() < 1e-12 && (b - 0.6).abs() < 1e-12, "{a} {b}"),
        other => panic!("{other:?}"),
    }
    let surface = build_surface(&BTreeMap::from([((2, 0, 0), dip)]));
    assert_eq!(surface.skipped[&(2, 0, 0)], Skipped::NoCrossing);
    // A far away plane: no crossing. (Not-a-number coefficients cannot reach here:
    // `Quadric::new` rejects them.)
    let far = Quadric::plane(DVec3::X, 9.0).expect("plane");
    assert_eq!(edge_crossing(&far, x), EdgeCrossing::None);
    let surface = build_surface(&BTreeMap::from([((0, 0, 0), far), ((u32::MAX, 0, 0), plane)]));
    assert!(surface.voxels.is_empty());
    assert_eq!(surface.skipped[&(0, 0, 0)], Skipped::NoCrossing);
    assert_eq!(surface.skipped[&(u32::MAX, 0, 0)], Skipped::OutOfRange);
}

fn coefficient() -> impl Strategy<Value = f64> {
    prop_oneof![8 => -2.0_f64..2.0, 2 => Just(0.0), 1 => any::<f64>()]
}

fn any_quadric() -> impl Strategy<Value = Quadric> {
    proptest::array::uniform10(coefficient()).prop_filter_map("a valid quadric", |c| Quadric::new(c).ok())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(500))]

    #[test]
    fn random_grids_never_panic(cells in proptest::collection::btree_map((0u32..3, 0u32..3, 0u32..3), any_quadric(), 0..12)) {
        let surface = build_surface(&cells);
        prop_assert_eq!(surface.voxels.len() + surface.skipped.len(), cells.len());
        for (v, vs) in &surface.voxels {
            let lo = corner(*v);
            for l in &vs.loops {
                prop_assert!(l.points.len() >= 3 && l.points.len() == l.edges.len());
                for p in &l.points {
                    prop_assert!(p.is_finite() && p.cmpge(lo).all() && p.cmple(lo + DVec3::ONE).all(), "{:?}", p);
                }
                for patch in &l.patches {
                    prop_assert!(matches!(patch.polygon.len(), 3 | 4));
                    prop_assert!(patch.quadric.coefficients().iter().all(|c| c.is_finite()));
                }
            }
        }
    }
}
