//! A tile that does not repeat (`periodic_xy: false` through the maps, the patches, the
//! tracer and the ground truth): a plane sloping from z = 1 at x = 0 to z = 4 at x = 12
//! (its opposite borders differ by 3 voxels, so repeating it would put a wall at the seam)
//! and a sphere beside the x = 12 border. Rays from above and beside the tile, through
//! every wall, must find exactly the single tile's mesh: no seam, no wrapped copy.
//!
//! The exact triangles (`PatchSurface::Triangles`) are the mesh's own triangles in `f32`
//! voxel-local coordinates, so their hits differ from the `f64` ground truth by rounding
//! only: one `f32` operation on values below 64 rounds by at most `64 ε / 2`, a trace
//! accumulates one such error per step, and the slab entry, the change to voxel-local
//! coordinates and the plane solve add at most 16 more ([`rounding_slack`]).

use ddm_compress::{DirectionCones, DistanceMapSettings, MapKind, Triangle, compute_distance_maps};
use ddm_tracer::{
    CompressedMaps, DistanceSource, MeshRaycaster, Method, PatchSettings, PatchSurface, Stepping, TraceOutcome,
    TraceSettings, VoxelPatches, trace,
};
use glam::{DVec3, UVec3, Vec2, Vec3};

/// A tracer over one scene, as the cases compare it.
type TraceRay<'a> = dyn Fn(Vec3, Vec3) -> TraceOutcome + 'a;

const DIMS: UVec3 = UVec3::new(12, 12, 6);

/// Rounding of one `f32` operation on values below 64, counted as a whole ulp.
const F32_STEP_ERROR: f64 = 64.0 * f32::EPSILON as f64;

/// How far a hit of `steps` steps on an exact triangle may lie from the exact one by
/// rounding alone (see the module documentation).
fn rounding_slack(steps: u32) -> f64 {
    f64::from(steps + 16) * F32_STEP_ERROR
}

/// The sloped plane z = 1 + x / 4 over the tile (outward normal up) and a sphere of radius
/// 1.3 centred at (10.3, 6, 4.4), which reaches x = 11.6 and sinks into the plane.
fn single_tile() -> Vec<Triangle> {
    let [a, b, c, d] =
        [Vec3::new(0.0, 0.0, 1.0), Vec3::new(12.0, 0.0, 4.0), Vec3::new(12.0, 12.0, 4.0), Vec3::new(0.0, 12.0, 1.0)];
    let mut triangles = vec![Triangle([a, b, c]), Triangle([a, c, d])];
    triangles.extend(mesostructure::sphere(Vec3::new(10.3, 6.0, 4.4), 1.3, 16));
    triangles
}

/// Random downward rays (xorshift, fixed seed) from above the slab over a square reaching
/// 3 voxels past the tile on each side, elevations in [−85°, −8°]: they enter through the
/// top and the side walls, and the shallow ones leave through the side walls.
fn rays(count: usize, seed: u64) -> Vec<(Vec3, Vec3)> {
    let mut state = seed;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    (0..count)
        .map(|_| {
            let origin = Vec3::new(next() * 18.0 - 3.0, next() * 18.0 - 3.0, DIMS.z as f32 + 0.5);
            let azimuth = next() * std::f32::consts::TAU;
            let elevation = -(8.0 + 77.0 * next()).to_radians();
            (origin, Vec3::new(elevation.cos() * azimuth.cos(), elevation.cos() * azimuth.sin(), elevation.sin()))
        })
        .collect()
}

/// Rays whose hit or miss differs from the mesh's, and the largest distance of the others'
/// hit points from the mesh's as a fraction of [`rounding_slack`].
fn disagreements(mesh: &MeshRaycaster, trace_ray: impl Fn(Vec3, Vec3) -> TraceOutcome) -> (usize, f64, usize) {
    let (mut wrong, mut worst, mut hits) = (0, 0.0_f64, 0);
    for (origin, direction) in rays(4000, 0x51_7e) {
        let out = trace_ray(origin, direction);
        assert!(!out.exhausted, "ray {origin} {direction} ran out of steps");
        let truth = mesh.first_hit(origin.as_dvec3(), direction.as_dvec3().normalize(), f64::MAX);
        match (out.hit, truth) {
            (Some(hit), Some(truth)) => {
                hits += 1;
                worst = worst.max((hit.point.as_dvec3() - truth.point).length() / rounding_slack(out.steps));
            }
            (None, None) => {}
            _ => wrong += 1,
        }
    }
    (wrong, worst, hits)
}

#[test]
fn a_single_tile_shows_no_seam_and_no_wrapped_geometry() {
    let triangles = single_tile();
    let ddm = MapKind::Directional(DirectionCones::downward(4, 1).unwrap());
    let exact = TraceSettings { method: Method::Quadric, max_steps: 512, stepping: Stepping::Distance };
    let alone = MeshRaycaster::new(&triangles, Vec2::ZERO);
    for periodic_xy in [false, true] {
        let map_settings = DistanceMapSettings { tolerance: 0.25, periodic_xy };
        let maps = compute_distance_maps(DIMS, &triangles, ddm, map_settings).unwrap();
        assert_eq!(maps.periodic_xy(), periodic_xy);
        let patch_settings = PatchSettings { surface: PatchSurface::Triangles, periodic_xy, ..Default::default() };
        let patches = VoxelPatches::build(DIMS, &triangles, &maps.surface, patch_settings).unwrap();
        let compressed = CompressedMaps::compress(&maps, 4).unwrap();
        let cases: [(&str, &TraceRay); 3] = [
            ("raw maps", &|o, d| trace(&maps, Some(&patches), o, d, exact)),
            ("compressed maps, block cells", &|o, d| {
                trace(&compressed, Some(&patches), o, d, TraceSettings { stepping: Stepping::BlockCells, ..exact })
            }),
            ("raw maps, voxel-exit stepping", &|o, d| {
                trace(&maps, Some(&patches), o, d, TraceSettings { stepping: Stepping::VoxelExit, ..exact })
            }),
        ];
        for (name, trace_ray) in cases {
            let (wrong, worst, hits) = disagreements(&alone, trace_ray);
            println!(
                "periodic {periodic_xy}, {name}: {wrong} of 4000 rays hit or miss unlike the single tile's mesh; \
                 {hits} hits, worst {worst:.3} of the rounding bound"
            );
            assert!(hits > 1000, "{name}: only {hits} hits compared");
            if periodic_xy {
                // The same tile repeated: rays across the border find the copies' wall at
                // the seam and the sphere's copy, which the single tile does not have.
                assert!(wrong > 100, "periodic {name}: {wrong}");
            } else {
                assert_eq!(wrong, 0, "{name}");
                assert!(worst <= 1.0, "{name}: a hit {worst} times the rounding bound off the mesh");
            }
        }
    }
}

#[test]
fn watertight_patches_of_a_single_tile_follow_its_mesh_to_the_borders() {
    // The watertight surface decides corner sides from the mesh alone (no copies); its
    // winding rays lean inward so that those from the tile's last row of corners still
    // meet the plane (leaning outward they left the mesh's extent: 132 of these rays
    // missed in the last row of voxels before).
    let triangles = single_tile();
    let ddm = MapKind::Directional(DirectionCones::downward(4, 1).unwrap());
    let map_settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: false };
    let maps = compute_distance_maps(DIMS, &triangles, ddm, map_settings).unwrap();
    let settings = PatchSettings { surface: PatchSurface::Watertight, periodic_xy: false, ..Default::default() };
    let patches = VoxelPatches::build(DIMS, &triangles, &maps.surface, settings).unwrap();
    assert!(!patches.periodic_xy);
    let quadric = TraceSettings { method: Method::Quadric, max_steps: 512, stepping: Stepping::Distance };
    let alone = MeshRaycaster::new(&triangles, Vec2::ZERO);
    let (mut wrong, mut compared) = (0, 0);
    for (origin, direction) in rays(4000, 0x3a_11) {
        let out = trace(&maps, Some(&patches), origin, direction, quadric);
        let truth = alone.first_hit(origin.as_dvec3(), direction.as_dvec3().normalize(), f64::MAX);
        compared += 1;
        // The watertight patches replace the sphere's 16-segment facets by the polygons
        // through its edge crossings, so a ray grazing the sphere within a voxel may hit
        // one and miss the other; only rays whose true hit lies on the plane, or that miss,
        // are held to the mesh's answer.
        let on_plane = |p: DVec3| (p.z - (1.0 + p.x / 4.0)).abs() < 1e-3;
        let sphere_involved =
            truth.is_some_and(|t| !on_plane(t.point)) || out.hit.is_some_and(|h| !on_plane(h.point.as_dvec3()));
        if !sphere_involved && out.hit.is_some() != truth.is_some() {
            wrong += 1;
        }
    }
    println!("watertight single tile: {wrong} of {compared} rays off the sphere hit or miss unlike the mesh");
    assert_eq!(compared, 4000);
    assert_eq!(wrong, 0);
}
