//! Conservativeness of the directional and plain distance maps, compressed or not: no
//! stored value exceeds a sampled upper estimate of the true one, and sphere tracing with
//! them never steps past the first true intersection.

use ddm_compress::testing::{reference_distance_maps, sampled_distance};
use ddm_compress::{
    CompressedMap, DirectionCones, DistanceMapSettings, DistanceMaps, MapKind, Triangle, compute_distance_maps,
};
use glam::{UVec3, Vec3};

const DIMS: UVec3 = UVec3::new(6, 6, 4);

/// A bumpy floor (a pyramid on a plane) and a slanted plate: faces in many directions.
fn mesostructure() -> Vec<Triangle> {
    let (p, q, r, s) =
        (Vec3::new(0.0, 0.0, 0.5), Vec3::new(6.0, 0.0, 0.5), Vec3::new(6.0, 6.0, 0.5), Vec3::new(0.0, 6.0, 0.5));
    let apex = Vec3::new(2.0, 2.0, 2.6);
    let base = [Vec3::new(1.0, 1.0, 0.5), Vec3::new(3.0, 1.0, 0.5), Vec3::new(3.0, 3.0, 0.5), Vec3::new(1.0, 3.0, 0.5)];
    let mut triangles = vec![Triangle([p, q, r]), Triangle([p, r, s])];
    for i in 0..4 {
        triangles.push(Triangle([base[i], base[(i + 1) % 4], apex]));
    }
    triangles.push(Triangle([Vec3::new(3.5, 4.0, 1.5), Vec3::new(5.5, 4.2, 3.2), Vec3::new(4.0, 5.5, 2.0)]));
    triangles
}

fn maps(kind: MapKind) -> DistanceMaps {
    let settings = DistanceMapSettings { tolerance: 0.05, periodic_xy: false };
    compute_distance_maps(DIMS, &mesostructure(), kind, settings).unwrap()
}

fn voxel_index(v: UVec3) -> usize {
    (v.x + DIMS.x * (v.y + DIMS.y * v.z)) as usize
}

/// Mean and largest `sampled - stored` over the voxel-cones with a finite sampled value,
/// asserting that no stored value exceeds the sampled one.
fn gaps(maps: &DistanceMaps, triangles: &[Triangle], label: &str) -> (f32, f32) {
    let (mut checked, mut considered, mut total_gap, mut largest_gap) = (0, 0, 0.0_f64, 0.0_f32);
    let dims = maps.dims;
    for z in 0..dims.z {
        for y in 0..dims.y {
            for x in 0..dims.x {
                let v = UVec3::new(x, y, z);
                let index = (x + dims.x * (y + dims.y * z)) as usize;
                for (c, map) in maps.values.iter().enumerate() {
                    let cone = maps.kind.cones().and_then(|cones| cones.cone(c as u32));
                    let sampled = sampled_distance(v, triangles, cone.as_ref(), 32);
                    let stored = map[index];
                    considered += 1;
                    // The slack is the rounding of the sampled `f32` distance (~10
                    // operations on coordinates below 8, each within ulp(8) / 2 = 4.8e-7):
                    // 1e-4 covers it with room.
                    assert!(
                        stored <= sampled + 1e-4,
                        "{label}: voxel {v} cone {c}: stored {stored} > sampled {sampled}"
                    );
                    if sampled.is_finite() {
                        checked += 1;
                        total_gap += f64::from(sampled - stored);
                        largest_gap = largest_gap.max(sampled - stored);
                    }
                }
            }
        }
    }
    println!("{label}: {checked} of {considered} voxel-cones see the surface (a finite sampled value)");
    // Skipped: voxel-cones through which no sampled pair reaches a triangle. The floor
    // spans the whole tile, and every downward cone (elevations down to −90°) of every
    // voxel meets it right below: those all count. Upward cones see only the plate and the
    // pyramid's faces above some voxels.
    let downward = match maps.kind.cones() {
        Some(cones) => {
            (0..cones.count()).filter(|&c| cones.cone(c).is_some_and(|cone| cone.elevation_max <= 0.0)).count()
        }
        None => 1,
    };
    let must_see = downward * (dims.x * dims.y * dims.z) as usize;
    assert!(
        checked >= must_see,
        "{label}: only {checked} of {considered} voxel-cones see the surface ({must_see} must)"
    );
    ((total_gap / checked as f64) as f32, largest_gap)
}

#[test]
fn stored_values_never_exceed_sampled_distances() {
    let triangles = mesostructure();
    let settings = DistanceMapSettings { tolerance: 0.05, periodic_xy: false };
    let kinds = [
        MapKind::Directional(DirectionCones::full(4, 2).unwrap()),
        MapKind::Directional(DirectionCones::downward(8, 1).unwrap()),
        MapKind::Plain,
    ];
    for kind in kinds {
        let fast = compute_distance_maps(DIMS, &triangles, kind, settings).unwrap();
        let reference = reference_distance_maps(DIMS, &triangles, kind, settings).unwrap();
        let (fast_mean, fast_max) = gaps(&fast, &triangles, "search");
        let (reference_mean, reference_max) = gaps(&reference, &triangles, "reference");
        println!(
            "{kind:?}: mean / max (sampled - stored): search {fast_mean:.3} / {fast_max:.3}, reference {reference_mean:.3} / {reference_max:.3} voxel"
        );
        // The search is at least as tight as the previous computation on average (the
        // claim, without slack: the sums are `f64`).
        assert!(fast_mean <= reference_mean, "search {fast_mean} looser than reference {reference_mean}");
    }
}

/// Regression pin of how tight the maps are. The mean `sampled − stored` mixes the maps'
/// own looseness (at most `2 tolerance` per value for convex cones, see `ddm-compress`'s
/// unit tests against exact values) with the sampling's error (32² point pairs per
/// triangle miss the nearest pair by an amount no property bounds), so the threshold is a
/// measured value: mean gaps 0.288 (full 4×2), 0.300 (downward 8×1), 0.169 (plain map)
/// (before the cone-aware bounds and witnesses: 0.298, 0.312, 0.169; the reference
/// computation: 0.466, 0.525, 0.196), pinned at 0.32. The largest gap (3.3 voxel, the
/// same for both) is a sampling artefact of grazing directions and is not pinned.
#[test]
fn mean_gap_to_sampled_distances_regression_pin() {
    let triangles = mesostructure();
    let settings = DistanceMapSettings { tolerance: 0.05, periodic_xy: false };
    for kind in [
        MapKind::Directional(DirectionCones::full(4, 2).unwrap()),
        MapKind::Directional(DirectionCones::downward(8, 1).unwrap()),
        MapKind::Plain,
    ] {
        let maps = compute_distance_maps(DIMS, &triangles, kind, settings).unwrap();
        let (mean, _) = gaps(&maps, &triangles, "search");
        assert!(mean < 0.32, "{kind:?}: the maps got looser: mean gap {mean}");
    }
}

fn first_true_hit(triangles: &[Triangle], origin: Vec3, direction: Vec3) -> Option<f32> {
    // Möller–Trumbore, nearest positive t.
    triangles
        .iter()
        .filter_map(|t| {
            let [a, b, c] = t.0;
            let (e1, e2) = (b - a, c - a);
            let p = direction.cross(e2);
            let det = e1.dot(p);
            if det.abs() < 1e-9 {
                return None;
            }
            let s = origin - a;
            let u = s.dot(p) / det;
            let q = s.cross(e1);
            let v = direction.dot(q) / det;
            let t = e2.dot(q) / det;
            (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0).then_some(t)
        })
        .min_by(f32::total_cmp)
}

#[test]
fn sphere_tracing_never_steps_past_the_surface() {
    let triangles = mesostructure();
    let cones = DirectionCones::full(4, 2).unwrap();
    let directional = maps(MapKind::Directional(cones));
    let compressed: Vec<CompressedMap> = directional
        .values
        .iter()
        .map(|values| CompressedMap::compress(values, &directional.surface, DIMS, 2).unwrap())
        .collect();
    let plain = maps(MapKind::Plain);
    let (mut rays, mut floor_rays, mut worst_overshoot) = (0, 0, 0.0_f32);
    for k in 0..4000_u32 {
        let f = |m: u32| ((k.wrapping_mul(m) % 1000) as f32 + 0.5) / 1000.0;
        let origin = Vec3::new(f(7919) * 6.0, f(104_729) * 6.0, 3.0 + f(1_299_709));
        let direction = Vec3::new(f(15_485_863) - 0.5, f(32_452_843) - 0.5, -0.2 - f(49_979_687)).normalize();
        // Rays that reach the floor plane (z = 0.5) inside the tile: they must hit.
        let t_floor = (0.5 - origin.z) / direction.z;
        let on_floor = origin + t_floor * direction;
        let reaches_floor = on_floor.x > 0.0 && on_floor.x < 6.0 && on_floor.y > 0.0 && on_floor.y < 6.0;
        floor_rays += usize::from(reaches_floor);
        let Some(truth) = first_true_hit(&triangles, origin, direction) else {
            assert!(!reaches_floor, "ray {k} crosses the floor but hits nothing");
            continue;
        };
        rays += 1;
        for method in 0..3 {
            let mut t = 0.0_f32;
            for step in 0..200 {
                let p = origin + t * direction;
                if !(p.cmpge(Vec3::ZERO).all() && p.cmplt(DIMS.as_vec3()).all()) {
                    break;
                }
                let voxel = p.as_uvec3();
                let cone = cones.cone_of(direction).unwrap();
                let value = match method {
                    0 => directional.values[cone as usize][voxel_index(voxel)],
                    1 => compressed[cone as usize].access(voxel).unwrap(),
                    _ => plain.values[0][voxel_index(voxel)],
                };
                if value <= 0.0 {
                    break; // a surface voxel: the quadric / exact test takes over here
                }
                t += value;
                // Rounding alone: one ulp(16) (t and the coordinates stay below 16) per
                // step taken, and 8 for the f32 Möller–Trumbore truth.
                let slack = (step + 8) as f32 * 16.0 * f32::EPSILON;
                worst_overshoot = worst_overshoot.max((t - truth) / slack);
                assert!(t <= truth + slack, "method {method}, ray {k}: stepped to {t} past the hit at {truth}");
            }
        }
    }
    println!(
        "{rays} of 4000 rays hit ({floor_rays} cross the floor inside the tile), worst step past the hit {worst_overshoot:.3} \
         of the rounding slack"
    );
    // Every ray that crosses the floor inside the tile is compared (asserted above), and
    // the rays start above the tile, most of them steep enough to cross it there.
    assert!(rays >= floor_rays && floor_rays * 2 >= 4000, "only {rays} rays hit the mesostructure");
}
