//! Watertightness without the maps: along random segments between voxels that hold no
//! surface, the number of crossings with the union of all patches, as the tracer
//! intersects them ([`ddm_tracer::patch`]'s rules, in `f32`), is odd exactly when the two
//! ends lie on different sides of the mesh. A crack between two voxels' patches lets a
//! segment through it cross once too few.
//!
//! **A regression pin, not yet the goal of 0.** Of 10⁵ segments per tile, the parity is
//! wrong on (12 × 12 × 6 / 24 × 24 × 12) maze 4 / 1, bricks 0 / 0, beads 2 / 4, ball 0 / 0,
//! chain mail 6 / 6 (pinned; a change that makes one worse fails, one that improves it
//! should lower the pin). **None of them is a crack**, which the test asserts: each such
//! segment is traced again with its ends moved by [`PERTURBATIONS`] random offsets of up
//! to 0.007 voxel, and at least one copy has the right parity (through a crack wider than
//! that, every copy would be wrong). They are counting ambiguities of `f32` crossings: a
//! crossing within rounding of a voxel wall, where the segment also grazes a crease, and
//! neighbouring triangles of a fan both accepting one crossing in their tolerance bands.
//! The fans around the feature vertices of crease voxels (`patches::crease`) added such
//! borders: maze 2 / 0 → 4 / 1 and beads 1 → 2 at 12 × 12 × 6. Faults of earlier
//! constructions found by this test and removed:
//! bilinear pieces of a fan (the paper's fan of quads) accept ghost hits of their quadrics
//! inside each other's polygons (24 % of the beads' segments wrong); fans around a corner
//! of a non-convex polygon fold over (polygons of more than four points, and voxels with
//! several polygons, are now fans of triangles around the polygon's mean point); grid
//! corners lying exactly on a floor put whole patches in voxel faces (at 24 × 24 × 12,
//! maze 7169 and beads 10 198 segments wrong) until the grid decisions were taken at
//! slightly moved grid points ([`ddm_tracer::solid::SAMPLE_OFFSET`]); and feature vertices
//! clamped onto a voxel's face made fans lying in the face (maze 2 → 15) until a vertex
//! nearer a face than `FEATURE_MARGIN` was refused.
//!
//! The ends are points in the middle of voxels whose eight corners lie on one side, and
//! whose centre and end point lie on that side too ([`MeshSides`]): such a voxel has no
//! patch, and the end's side is the same for the patches (which separate the corners by
//! their sides) and for the mesh. Segments run in any direction and cross the tile's
//! borders.

use ddm_compress::{DistanceMapSettings, MapKind, compute_distance_maps};
use ddm_tracer::patch::{inside_polygon, polygon_margin, quadric_of};
use ddm_tracer::solid::MeshSides;
use ddm_tracer::voxel::{NUDGE, voxel_entry, voxel_exit};
use ddm_tracer::{MeshRaycaster, PatchSettings, PatchSurface, TracePatch, VoxelPatches};
use glam::{IVec3, UVec3, Vec2, Vec3};
use mesostructure::Mesostructure;
use quadric_fit::first_hit;
use quadric_fit::watertight::SignedGrid;

/// The grids and watertight subdivisions: the tiles' features are 1–3 voxels wide at the
/// first, at the second their floors and heights fall on grid corners and faces, and the
/// third builds the first's surface on cells of half a voxel (chain mail's tubes, 0.9–1.2
/// voxel thick, then cross cell edges).
const GRIDS: [(UVec3, u32); 3] = [(UVec3::new(12, 12, 6), 1), (UVec3::new(24, 24, 12), 1), (UVec3::new(12, 12, 6), 2)];

/// Segments per mesostructure.
const SEGMENTS: usize = 100_000;

/// Two hits on neighbouring patches of a voxel (sharing an edge of their polygons) this
/// close along the segment (voxels) are one crossing when one of them lies only in the
/// polygon test's tolerance band ([`ddm_tracer::patch::POLYGON_TOLERANCE`] outside its polygon): the patches
/// overlap there so that no crack opens between them. Two hits strictly inside their
/// polygons are two crossings.
const OVERLAP: f32 = 1e-2;

/// Each segment with the wrong parity is traced again with its ends moved by these many
/// random offsets of up to `√3` [`PERTURBATION`] (the far end's with its components cycled,
/// so that no point of the segment stays where it was).
const PERTURBATIONS: usize = 12;

/// The size (voxels) of those offsets: far above `f32` rounding and the polygon test's
/// tolerance, far below a feature.
const PERTURBATION: f32 = 4e-3;

/// After a root at `t`, the second root of a quadric is searched from `t` + this.
const NEXT_ROOT: f32 = 1e-6;

struct Xorshift(u64);

impl Xorshift {
    fn next(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }

    fn below(&mut self, n: u32) -> u32 {
        ((self.next() * n as f32) as u32).min(n - 1)
    }
}

/// Every crossing of the voxel-local segment `local + t direction`, `t ∈ [0, t_exit)`, with
/// `patches`: both roots of each quadric, accepted as [`ddm_tracer::patch::patch_hit`]
/// accepts a hit (inside the polygon where the voxel has several patches or the patch is
/// bounded), counted once where neighbouring patches overlap (see [`OVERLAP`]).
///
/// The tracer looks [`NUDGE`] before the entry wall too (so that a floor on the wall is
/// not lost to rounding); counting crossings, that would count a crossing on a wall in
/// both voxels, and a patch's plane continued past a crease on the wall, so the count
/// starts at the wall.
fn voxel_crossings(patches: &[TracePatch], local: Vec3, direction: Vec3, t_exit: f32, out: &mut Vec<f32>) {
    // (t, patch, strictly inside its polygon).
    let mut hits: Vec<(f32, usize, bool)> = Vec::new();
    for (index, patch) in patches.iter().enumerate() {
        let quadric = quadric_of(patch);
        let clipped = patches.len() > 1 || patch.ij_corners.w == ddm_tracer::patch::BOUNDED_PATCH;
        let mut from = 0.0;
        // A quadric meets a line at most twice.
        for _ in 0..2 {
            let Some(t) = first_hit(&quadric, local, direction, from, t_exit) else { break };
            let at = local + direction * t;
            if t < t_exit && (!clipped || inside_polygon(patch, at)) {
                hits.push((t, index, !clipped || polygon_margin(patch, at) >= 0.0));
            }
            from = t + NEXT_ROOT;
        }
    }
    hits.sort_by(|a, b| a.0.total_cmp(&b.0));
    let adjacent = |a: usize, b: usize| {
        let shared = patches[a].corners.iter().filter(|c| patches[b].corners.contains(c)).count();
        a != b && shared >= 2
    };
    let mut kept: Vec<(f32, usize, bool)> = Vec::new();
    for hit in hits {
        let same = kept.iter().any(|k| (k.0 - hit.0).abs() <= OVERLAP && adjacent(k.1, hit.1) && !(k.2 && hit.2));
        if !same {
            kept.push(hit);
        }
    }
    out.extend(kept.iter().map(|k| k.0));
}

/// The crossings of the segment from `a` to `b` with the patches, in the tracer's voxel
/// walk (a voxel's patches are intersected from where the segment enters it).
fn segment_crossings(patches: &VoxelPatches, a: Vec3, b: Vec3) -> usize {
    let length = (b - a).length();
    let d = (b - a) / length;
    let dims = patches.dims.as_ivec3();
    let mut count = 0;
    let mut local_ts = Vec::new();
    let mut t = 0.0_f32;
    while t < length {
        let probe = a + d * (t + NUDGE);
        let v = probe.floor().as_ivec3();
        let corner = v.as_vec3();
        let start_local = a - corner;
        let t_in = voxel_entry(start_local, d);
        let entry = start_local + d * t_in;
        let t_exit = voxel_exit(entry, d);
        let wrapped = IVec3::new(v.x.rem_euclid(dims.x), v.y.rem_euclid(dims.y), v.z).as_uvec3();
        local_ts.clear();
        voxel_crossings(patches.of_voxel(wrapped), entry, d, t_exit, &mut local_ts);
        count += local_ts.iter().filter(|&&th| t_in + th < length).count();
        t = t.max(t_in + t_exit);
    }
    count
}

#[test]
fn the_watertight_patches_have_the_meshs_crossing_parity_up_to_a_pinned_few_segments() {
    let (mut failures, mut robust) = (Vec::new(), Vec::new());
    for ((dims, subdivision), which) in GRIDS.into_iter().flat_map(|d| Mesostructure::ALL.map(|m| (d, m))) {
        let triangles = which.triangles(dims);
        let settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: true };
        let maps = compute_distance_maps(dims, &triangles, MapKind::Plain, settings).unwrap();
        let surface = PatchSettings {
            surface: PatchSurface::Watertight,
            watertight_subdivision: subdivision,
            ..PatchSettings::default()
        };
        let patches = VoxelPatches::build(dims, &triangles, &maps.surface, surface).unwrap();
        let mesh = MeshRaycaster::new(&triangles, Vec2::new(dims.x as f32, dims.y as f32));
        let mut sides = MeshSides::new(&mesh, dims);
        // The voxels that can end a segment, with their side.
        let mut ends = Vec::new();
        for z in 0..dims.z {
            for y in 0..dims.y {
                for x in 0..dims.x {
                    let corners: Vec<bool> =
                        (0..8).map(|c| sides.inside((x + (c & 1), y + ((c >> 1) & 1), z + (c >> 2)))).collect();
                    let centre = glam::DVec3::new(f64::from(x), f64::from(y), f64::from(z)) + 0.5;
                    let no_patch = patches.of_voxel(UVec3::new(x, y, z)).is_empty();
                    if corners.iter().all(|&s| s == corners[0]) && sides.point_inside(centre) == corners[0] && no_patch
                    {
                        ends.push((UVec3::new(x, y, z), corners[0]));
                    }
                }
            }
        }
        let (inside_ends, outside_ends) = (ends.iter().filter(|e| e.1).count(), ends.iter().filter(|e| !e.1).count());
        // Chain mail's tubes are thinner than a voxel is wide: segments between two outside
        // ends still cross a tube twice, or once through a crack.
        let least_inside = if matches!(which, Mesostructure::ChainMail | Mesostructure::Ball) { 0 } else { 50 };
        assert!(
            inside_ends >= least_inside && outside_ends > 50,
            "{}: {inside_ends} inside, {outside_ends} outside",
            which.name()
        );
        let mut random = Xorshift(0x5eed_0000 + ends.len() as u64);
        let (mut mismatches, mut crossing_total, mut odd, mut skipped) = (0, 0, 0, 0);
        for _ in 0..SEGMENTS {
            let (va, sa) = ends[random.below(ends.len() as u32) as usize];
            let (vb, sb) = ends[random.below(ends.len() as u32) as usize];
            // The far end in this tile or a neighbouring copy.
            let shift = Vec3::new(
                (random.below(3) as f32 - 1.0) * dims.x as f32,
                (random.below(3) as f32 - 1.0) * dims.y as f32,
                0.0,
            );
            // Anywhere in the middle of the end voxels: segments between voxel centres
            // would run exactly through grid lines.
            let mut jitter = || Vec3::new(random.next(), random.next(), random.next()) * 0.6 + 0.2;
            let a = va.as_vec3() + jitter();
            let b = vb.as_vec3() + jitter() + shift;
            let on_their_sides =
                sides.point_inside(a.as_dvec3()) == sa && sides.point_inside((b - shift).as_dvec3()) == sb;
            if !on_their_sides || (b - a).length() < 0.5 {
                skipped += 1;
                continue;
            }
            let crossings = segment_crossings(&patches, a, b);
            crossing_total += crossings;
            odd += usize::from(sa != sb);
            if (crossings % 2 == 1) != (sa != sb) {
                mismatches += 1;
                // A crack keeps the parity wrong for segments near this one too; a counting
                // ambiguity (a crossing within rounding or the polygon tolerance of a patch's
                // border) does not.
                let mut offsets = Xorshift(0xface + mismatches as u64);
                let moved: Vec<usize> = (0..PERTURBATIONS)
                    .map(|_| {
                        let mut offset = || Vec3::new(offsets.next(), offsets.next(), offsets.next()) * 2.0 - 1.0;
                        let e = offset() * PERTURBATION;
                        // The far end moves by `e` with its components cycled: the segment
                        // moves by a non-zero offset at every point along it.
                        segment_crossings(&patches, a + e, b + Vec3::new(e.y, e.z, e.x))
                    })
                    .collect();
                if moved.iter().all(|c| (c % 2 == 1) != (sa != sb)) {
                    robust.push((which.name(), dims, subdivision, a, b));
                }
                if mismatches <= 5 {
                    println!("{}: {a} -> {b}: {crossings} crossings, sides {sa} {sb}", which.name());
                }
            }
        }
        println!(
            "{} at {dims} (subdivision {subdivision}): {} voxels with patches ({} off the surface voxels), {} patches; {SEGMENTS} segments ({skipped} skipped: an end \
             across a thin feature, or too short) between {} ends ({inside_ends} inside), {odd} with ends on different sides, {crossing_total} crossings; parity wrong on \
             {mismatches}; sides: {} points on the mesh, {} ambiguous, {} edges without a crossing",
            which.name(),
            patches.quadric_voxels,
            patches.patch_voxels_off_surface,
            patches.patches.len(),
            ends.len(),
            sides.points_on_surface,
            sides.ambiguous_points,
            sides.edges_without_crossing,
        );
        assert!(skipped < SEGMENTS / 100, "{}: {skipped} segments skipped", which.name());
        if least_inside > 0 {
            assert!(odd > SEGMENTS / 10, "{}: only {odd} segments join the two sides", which.name());
        }
        assert!(crossing_total > SEGMENTS / 4, "{}: only {crossing_total} crossings", which.name());
        assert_eq!(patches.patch_voxels_off_surface, 0, "{}", which.name());
        let case = GRIDS.iter().position(|&g| g == (dims, subdivision)).expect("a case of GRIDS");
        let pin = match which {
            Mesostructure::Maze(_) => [4, 1, 4][case],
            Mesostructure::Beads => [2, 4, 4][case],
            Mesostructure::Bricks => [0, 0, 1][case],
            Mesostructure::Ball => 0,
            Mesostructure::ChainMail => [6, 6, 17][case],
        };
        if mismatches > pin {
            failures.push((which.name(), dims, subdivision, mismatches, pin));
        }
    }
    assert!(failures.is_empty(), "segments with the wrong parity (tile, grid, subdivision, count, pin): {failures:?}");
    assert!(robust.is_empty(), "wrong parity on every perturbed copy too (a crack): {robust:?}");
}

/// Points of the patches, snapped together: each point (tile coordinates) goes to the lattice
/// of 10⁻⁵ voxel, reduced into the tile in x and y, and takes the key of a point already met
/// within one lattice step (in any of the 27 neighbouring cells). The copies of one corner
/// that two voxels store differ by `f32` rounding (under 10⁻⁶ voxel); distinct corners lie
/// at least [`ddm_tracer::solid::EDGE_MARGIN`] / subdivision (5 · 10⁻⁵) apart.
struct Snapped {
    period: (i64, i64),
    keys: std::collections::HashMap<(i64, i64, i64), (i64, i64, i64)>,
}

impl Snapped {
    fn key(&mut self, p: glam::DVec3) -> (i64, i64, i64) {
        let reduce = |k: (i64, i64, i64)| (k.0.rem_euclid(self.period.0), k.1.rem_euclid(self.period.1), k.2);
        let q = p * 1e5;
        let k = reduce((q.x.round() as i64, q.y.round() as i64, q.z.round() as i64));
        for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    if let Some(&found) = self.keys.get(&reduce((k.0 + dx, k.1 + dy, k.2 + dz))) {
                        return found;
                    }
                }
            }
        }
        self.keys.insert(k, k);
        k
    }
}

/// With subdivision every patch is a bounded triangle, so watertightness can be checked
/// exactly, without rays: over all voxels' lists (corners snapped by [`Snapped`]), every
/// edge of a triangle is an edge of exactly one other triangle (a closed surface), and
/// every voxel whose interior (10⁻³ voxel in) a triangle's box enters lists the triangle
/// (the tracer meets it wherever it is). A degenerate triangle left out would show as
/// edges of one triangle.
#[test]
fn the_subdivided_watertight_triangles_close_and_every_voxel_they_cross_lists_them() {
    type Key = (i64, i64, i64);
    let dims = UVec3::new(12, 12, 6);
    for which in Mesostructure::ALL {
        let triangles = which.triangles(dims);
        let settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: true };
        let maps = compute_distance_maps(dims, &triangles, MapKind::Plain, settings).unwrap();
        let settings =
            PatchSettings { surface: PatchSurface::Watertight, watertight_subdivision: 2, ..PatchSettings::default() };
        let patches = VoxelPatches::build(dims, &triangles, &maps.surface, settings).unwrap();
        let mut snapped =
            Snapped { period: (i64::from(dims.x) * 100_000, i64::from(dims.y) * 100_000), keys: Default::default() };
        // Each voxel's triangles, as sorted snapped corners, and their bounding boxes.
        let mut lists: std::collections::BTreeMap<[u32; 3], std::collections::BTreeSet<[Key; 3]>> = Default::default();
        let mut boxes = Vec::new();
        for z in 0..dims.z {
            for y in 0..dims.y {
                for x in 0..dims.x {
                    let voxel = UVec3::new(x, y, z);
                    for patch in patches.of_voxel(voxel) {
                        assert_eq!(patch.ij_corners.w, ddm_tracer::patch::BOUNDED_PATCH);
                        let points = [0, 1, 2].map(|i| patch.corners[i].truncate().as_dvec3() + voxel.as_dvec3());
                        let mut corners = points.map(|p| snapped.key(p));
                        corners.sort_unstable();
                        lists.entry(voxel.to_array()).or_default().insert(corners);
                        let (lo, hi) =
                            (points[0].min(points[1]).min(points[2]), points[0].max(points[1]).max(points[2]));
                        boxes.push((voxel, corners, lo, hi));
                    }
                }
            }
        }
        let all: std::collections::BTreeSet<[Key; 3]> = lists.values().flatten().copied().collect();
        let mut edges: std::collections::BTreeMap<[Key; 2], u32> = Default::default();
        for t in &all {
            for (i, j) in [(0, 1), (1, 2), (0, 2)] {
                *edges.entry([t[i], t[j]]).or_default() += 1;
            }
        }
        let open: Vec<_> = edges.iter().filter(|&(_, &n)| n != 2).take(5).collect();
        assert!(all.len() > 1000, "{}: {} triangles", which.name(), all.len());
        assert!(open.is_empty(), "{}: edges not of exactly two triangles: {open:?}", which.name());
        let mut elsewhere = 0;
        for (voxel, corners, lo, hi) in &boxes {
            let (lo, hi) = ((*lo + 1e-3).floor().as_ivec3(), (*hi - 1e-3).floor().as_ivec3());
            for vz in lo.z.max(0)..=hi.z.min(dims.z as i32 - 1) {
                for vy in lo.y..=hi.y {
                    for vx in lo.x..=hi.x {
                        let wrapped =
                            [vx.rem_euclid(dims.x as i32) as u32, vy.rem_euclid(dims.y as i32) as u32, vz as u32];
                        if wrapped != voxel.to_array() {
                            elsewhere += 1;
                        }
                        assert!(
                            lists.get(&wrapped).is_some_and(|l| l.contains(corners)),
                            "{}: a triangle of voxel {voxel} crosses voxel {wrapped:?}, which does not list it",
                            which.name()
                        );
                    }
                }
            }
        }
        println!(
            "{}: {} triangles, {} edges each of two triangles; {elsewhere} crossings of a triangle into another voxel, each listed",
            which.name(),
            all.len(),
            edges.len()
        );
    }
}
