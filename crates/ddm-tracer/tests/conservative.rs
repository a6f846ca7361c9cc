//! Over many random viewing rays per mesostructure: sphere tracing with conservative maps
//! (plain, DDM, compressed; distance, block-cell and voxel-exit stepping) never steps past the first
//! true intersection; compression does not change the hits of
//! the full method (Algorithm 3.1); and the full method's hits are close to the truth.

use ddm_compress::{CompressedMap, DirectionCones, DistanceMapSettings, DistanceMaps, MapKind, compute_distance_maps};
use ddm_tracer::{
    CompressedMaps, ConeDistances, ConeSelector, DistanceSource, MeshRaycaster, Method, PatchSettings, PatchSurface,
    Stepping, TraceSettings, VoxelPatches, trace,
};
use glam::{UVec3, Vec2, Vec3};
use mesostructure::Mesostructure;

const DIMS: UVec3 = UVec3::new(12, 12, 6);

/// Random downward rays from above the slab (xorshift, fixed seed): elevation in
/// [-85°, -12°].
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
            let origin = Vec3::new(next() * DIMS.x as f32, next() * DIMS.y as f32, DIMS.z as f32 + 0.5);
            let azimuth = next() * std::f32::consts::TAU;
            let elevation = -(12.0 + 73.0 * next()).to_radians();
            let direction =
                Vec3::new(elevation.cos() * azimuth.cos(), elevation.cos() * azimuth.sin(), elevation.sin());
            (origin, direction)
        })
        .collect()
}

/// Compressed maps read voxel by voxel: every cell a single voxel, as before blocks
/// without surface became cells; to measure what the block cells save.
struct VoxelCells<'a>(&'a CompressedMaps);

/// One cone's map of [`VoxelCells`].
struct VoxelCellMap<'a>(&'a CompressedMap);

impl ConeDistances for VoxelCellMap<'_> {
    fn distance(&self, voxel: UVec3) -> f32 {
        self.0.access(voxel).unwrap_or(0.0)
    }
}

impl DistanceSource for VoxelCells<'_> {
    type ConeMap<'b>
        = VoxelCellMap<'b>
    where
        Self: 'b;

    fn dims(&self) -> UVec3 {
        self.0.dims
    }

    fn selector(&self) -> ConeSelector {
        self.0.selector()
    }

    fn cone_map(&self, cone: u32) -> Option<VoxelCellMap<'_>> {
        self.0.maps.get(cone as usize).map(VoxelCellMap)
    }
}

struct Scene {
    mesh: MeshRaycaster,
    plain: DistanceMaps,
    ddm: DistanceMaps,
    /// The C⁰ patches of §3.1 (steps a–c).
    patches: VoxelPatches,
    /// The fitted quadric of step a per voxel.
    fitted: VoxelPatches,
    /// The mesh's own triangles per voxel.
    triangles: VoxelPatches,
    /// Per voxel the fitted quadric if it is within 1e-3 voxel of the triangles, else them.
    adaptive: VoxelPatches,
}

fn scene(which: Mesostructure) -> Scene {
    let triangles = which.triangles(DIMS);
    let settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: true };
    let plain = compute_distance_maps(DIMS, &triangles, MapKind::Plain, settings).unwrap();
    let ddm4x1 = MapKind::Directional(DirectionCones::downward(4, 1).unwrap());
    let ddm = compute_distance_maps(DIMS, &triangles, ddm4x1, settings).unwrap();
    let patches = VoxelPatches::build(DIMS, &triangles, &ddm.surface, PatchSettings::default()).unwrap();
    let fitted = VoxelPatches::build(
        DIMS,
        &triangles,
        &ddm.surface,
        PatchSettings { surface: PatchSurface::FittedQuadric, ..PatchSettings::default() },
    )
    .unwrap();
    let with = |surface| PatchSettings { surface, ..PatchSettings::default() };
    let exact = VoxelPatches::build(DIMS, &triangles, &ddm.surface, with(PatchSurface::Triangles)).unwrap();
    let adaptive =
        VoxelPatches::build(DIMS, &triangles, &ddm.surface, with(PatchSurface::Adaptive { max_error: 1e-3 })).unwrap();
    let mesh = MeshRaycaster::new(&triangles, Vec2::new(DIMS.x as f32, DIMS.y as f32));
    Scene { mesh, plain, ddm, patches, fitted, triangles: exact, adaptive }
}

#[test]
fn sphere_tracing_never_steps_past_the_first_true_hit() {
    let sphere = TraceSettings { method: Method::SphereTracing, max_steps: 1024, stepping: Stepping::Distance };
    let exit = TraceSettings { stepping: Stepping::VoxelExit, ..sphere };
    let blocks = TraceSettings { stepping: Stepping::BlockCells, ..sphere };
    for which in Mesostructure::ALL {
        let s = scene(which);
        let compressed = CompressedMaps::compress(&s.ddm, 4).unwrap();
        let voxel_cells = VoxelCells(&compressed);
        // Two elevation bands: bounded through cut convex cones (`ddm-compress`'s
        // `convex_cone`).
        let settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: true };
        let ddm4x2 = MapKind::Directional(DirectionCones::downward(4, 2).unwrap());
        let banded = compute_distance_maps(DIMS, &which.triangles(DIMS), ddm4x2, settings).unwrap();
        let mut banded_steps = 0_u64;
        let mut true_hits = 0;
        let mut steps = [0_u64; 2];
        let mut compressed_steps = [0_u64; 2];
        // Distance stepping on compressed maps: the paper's rule, then block cells.
        let mut distance_steps = [0_u64; 2];
        for (origin, direction) in rays(1500, 0x9e37_79b9_7f4a_7c15) {
            let d = direction.normalize();
            let truth = s.mesh.first_hit(origin.as_dvec3(), d.as_dvec3(), 1e3);
            let runs = [
                trace(&s.plain, None, origin, direction, sphere),
                trace(&s.ddm, None, origin, direction, sphere),
                trace(&s.plain, None, origin, direction, exit),
                trace(&s.ddm, None, origin, direction, exit),
                trace(&compressed, None, origin, direction, exit),
                trace(&voxel_cells, None, origin, direction, exit),
                trace(&compressed, None, origin, direction, sphere),
                trace(&compressed, None, origin, direction, blocks),
                trace(&banded, None, origin, direction, sphere),
            ];
            banded_steps += u64::from(runs[8].steps);
            // On raw maps block cells are the paper's rule, step for step.
            assert_eq!(trace(&s.ddm, None, origin, direction, blocks), runs[1], "{}", which.name());
            distance_steps[0] += u64::from(runs[6].steps);
            distance_steps[1] += u64::from(runs[7].steps);
            steps[0] += u64::from(runs[1].steps);
            steps[1] += u64::from(runs[3].steps);
            compressed_steps[0] += u64::from(runs[5].steps);
            compressed_steps[1] += u64::from(runs[4].steps);
            for out in runs {
                assert!(!out.exhausted, "{} {origin} {direction}", which.name());
                if let Some(truth) = truth {
                    let hit =
                        out.hit.unwrap_or_else(|| panic!("{}: missed a true hit {origin} {direction}", which.name()));
                    // The entry of the first zero voxel lies before the true hit (the
                    // slack is the f32 rounding of a point ~20 voxels along the ray).
                    assert!(
                        f64::from(hit.t) <= truth.t + 1e-4,
                        "{}: stepped to {} past the true hit {} ({origin} {direction})",
                        which.name(),
                        hit.t,
                        truth.t
                    );
                }
            }
            true_hits += usize::from(truth.is_some());
        }
        assert!(true_hits > 1000, "{}: {true_hits}", which.name());
        // Voxel-exit stepping reads the map fewer times (measured: see the output).
        println!("{}: DDM 4x1 steps, distance stepping {}, voxel-exit stepping {}", which.name(), steps[0], steps[1]);
        assert!(steps[1] < steps[0], "{}: {steps:?}", which.name());
        // Splitting the cones' elevations saves steps (measured at 12x12x6: DDM 4x1 -> 4x2
        // maze 7461 -> 6865, bricks 5383 -> 5013, beads 5999 -> 5610, ball 15886 -> 13919,
        // chain mail 4461 -> 3948).
        println!("{}: DDM 4x2 steps {banded_steps}", which.name());
        assert!(banded_steps < steps[0], "{}: {banded_steps} {steps:?}", which.name());
        // On compressed maps, crossing a block without surface in one step saves steps
        // wherever such blocks lie on the rays' way (measured: see the output).
        println!(
            "{}: compressed DDM 4x1 with voxel-exit stepping, voxel cells {}, block cells {} steps",
            which.name(),
            compressed_steps[0],
            compressed_steps[1]
        );
        // Measured at 12x12x6, blocks of 4: the maze, bricks and beads cross every block
        // (equal counts), the ball 6691 -> 6149, chain mail 3037 -> 2834.
        assert!(compressed_steps[1] <= compressed_steps[0], "{}: {compressed_steps:?}", which.name());
        if matches!(which, Mesostructure::Ball | Mesostructure::ChainMail) {
            assert!(compressed_steps[1] < compressed_steps[0], "{}: {compressed_steps:?}", which.name());
        }
        // With the paper's rule the blocks' smaller values cost steps (§4); block cells
        // win them back (measured: see the output).
        println!(
            "{}: compressed DDM 4x1, distance stepping {}, with block cells {} (raw {})",
            which.name(),
            distance_steps[0],
            distance_steps[1],
            steps[0]
        );
        // Measured at 12x12x6, blocks of 4: the ball 16956 -> 15583 (raw 15886), chain mail
        // 4709 -> 4163 (raw 4461); the other three have surface in every block.
        assert!(distance_steps[1] <= distance_steps[0], "{}: {distance_steps:?}", which.name());
        if matches!(which, Mesostructure::Ball | Mesostructure::ChainMail) {
            assert!(distance_steps[1] < steps[0], "{}: {distance_steps:?} raw {}", which.name(), steps[0]);
        }
    }
}

/// Compression changes, accuracy: `(hit/miss or point differences raw vs compressed,
/// wrong hit/miss against the mesh, hits within 1e-3 voxel, rays both hit)`, both traced
/// with `stepping` (with voxel-exit or block-cell stepping the compressed maps cross blocks without
/// surface in one step).
fn quadric_counts(s: &Scene, patches: &VoxelPatches, stepping: Stepping) -> (usize, usize, usize, usize) {
    let quadric = TraceSettings { method: Method::Quadric, max_steps: 1024, stepping };
    let compressed = CompressedMaps::compress(&s.ddm, 4).unwrap();
    let (mut differ, mut wrong, mut close, mut hits) = (0, 0, 0, 0);
    for (origin, direction) in rays(1500, 0x1234_5678_9abc_def1) {
        let raw = trace(&s.ddm, Some(patches), origin, direction, quadric);
        let packed = trace(&compressed, Some(patches), origin, direction, quadric);
        match (raw.hit, packed.hit) {
            (Some(a), Some(b)) if (a.point - b.point).length() <= 1e-5 => {}
            (None, None) => {}
            _ => differ += 1,
        }
        let truth = s.mesh.first_hit(origin.as_dvec3(), direction.normalize().as_dvec3(), 1e3);
        match (raw.hit, truth) {
            (Some(a), Some(b)) => {
                hits += 1;
                close += usize::from((a.point.as_dvec3() - b.point).length() <= 1e-3);
            }
            (None, None) => {}
            _ => wrong += 1,
        }
    }
    (differ, wrong, close, hits)
}

#[test]
fn compression_is_transparent_and_the_quadric_hits_are_accurate() {
    for which in Mesostructure::ALL {
        let s = scene(which);
        let (differ, wrong, close, hits) = quadric_counts(&s, &s.patches, Stepping::Distance);
        let (f_differ, f_wrong, f_close, f_hits) = quadric_counts(&s, &s.fitted, Stepping::Distance);
        println!(
            "{}: C0 patches: compressed differs {differ}, wrong hit/miss {wrong}, within 1e-3 voxel {close}/{hits}; \
             fitted quadrics: compressed differs {f_differ}, wrong {f_wrong}, within {f_close}/{f_hits}",
            which.name()
        );
        // The tracer intersects a voxel's patches from where the ray enters the voxel, so
        // a hit depends only on the ray and the voxel, not on the steps before it: raw and
        // compressed maps give bit-identical hits whenever they visit the same zero
        // voxels. They may not: a step that is safe for the mesh may jump over a zero
        // voxel whose quadric bulges past the mesh, and the other stepping lands in it.
        // Measured: 0 differences everywhere except chain mail with fitted quadrics (3 of
        // 1500; tori a few voxels thick at this size). Before the entry-point rule: 2 on
        // the ball (C0 and fitted) and 1–2 on chain mail. The goal (identical
        // classification, hits within 1e-5 voxel) is met by the C0 patches here, and by
        // the exact triangles and the adaptive patches on every mesostructure (next test).
        let allowed_fitted = if which == Mesostructure::ChainMail { 3 } else { 0 };
        assert_eq!(differ, 0, "{}", which.name());
        assert!(f_differ <= allowed_fitted, "{}: {f_differ}", which.name());
        // Regression guards at this tiny size (12 × 12 × 6: maze blocks 1.5 voxels wide,
        // the ball's radius 2.1 voxels), measured out of 1500 rays (wrong hit/miss, hits
        // within 1e-3 voxel of the mesh):
        // C0 patches: maze 55, 1173/1445; bricks 91, 895/1409; beads 145, 197/1355; ball 0, 1246/1500.
        // Fitted: maze 0, 1333/1500; bricks 38, 1227/1462; beads 1, 320/1499; ball 0, 1239/1500.
        // Chain mail: C0 275, 5/954; fitted 177, 36/1055 (too thin for 12 × 12 × 6).
        // The full measurement is `cargo xtask ddm-trace`.
        let (c0_wrong, fitted_wrong) = match which {
            Mesostructure::Maze(_) => (60, 3),
            Mesostructure::Bricks => (100, 45),
            Mesostructure::Beads => (160, 3),
            Mesostructure::ChainMail => (300, 200),
            _ => (2, 2),
        };
        assert!(wrong <= c0_wrong && f_wrong <= fitted_wrong, "{}: {wrong} / {f_wrong}", which.name());
        if which == Mesostructure::Ball {
            assert!(close * 100 >= hits * 80 && f_close * 100 >= f_hits * 80, "{}", which.name());
        }
    }
}

#[test]
fn exact_triangles_and_the_adaptive_choice_meet_the_accuracy_goal() {
    for which in Mesostructure::ALL {
        let s = scene(which);
        for (name, patches, stepping) in [
            ("triangles", &s.triangles, Stepping::Distance),
            ("adaptive 1e-3", &s.adaptive, Stepping::Distance),
            ("adaptive 1e-3, voxel exit", &s.adaptive, Stepping::VoxelExit),
            ("adaptive 1e-3, block cells", &s.adaptive, Stepping::BlockCells),
        ] {
            let (differ, wrong, close, hits) = quadric_counts(&s, patches, stepping);
            println!(
                "{} {name}: {} quadric voxels, {} triangle voxels, {} patches ({} bytes); compressed differs \
                 {differ}, wrong hit/miss {wrong}, within 1e-3 voxel {close}/{hits}",
                which.name(),
                patches.quadric_voxels,
                patches.triangle_voxels,
                patches.patches.len(),
                patches.byte_size()
            );
            // The goals: compression changes no hit (classification, points within
            // 1e-5 voxel), no hole or false hit, 99.9 % of the hits within 1e-3 voxel.
            assert_eq!(differ, 0, "{} {name}", which.name());
            assert_eq!(wrong, 0, "{} {name}", which.name());
            assert!(close * 1000 >= hits * 999, "{} {name}: {close}/{hits}", which.name());
        }
        // The adaptive choice keeps a quadric somewhere and is never larger than the
        // triangles.
        assert!(s.adaptive.byte_size() <= s.triangles.byte_size(), "{}", which.name());
    }
}
