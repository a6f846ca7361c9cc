//! The plain distance map built on the GPU (`ddm_render::PlainMapBuild`, the kernel
//! `crates/ddm-render/shaders/plain_map_build.wgsl` over `ddm-compress`'s per-pair WGSL
//! twin) against the CPU's `compute_distance_maps` with `MapKind::Plain`, on every
//! procedural tile, periodic and clamped.
//!
//! Both searches return, per voxel, a lower bound of the exact box-to-mesh distance within
//! the tolerance of it (the `plain` module's proof; the GPU runs the same per-pair bounds
//! without the CPU's seed, so it may visit the triangles in another order). Hence, per
//! voxel: the same surface flag, and values that differ by at most the tolerance (plus the
//! bounds' rounding margins, 1e-4 at these coordinates). On a sample of voxels the GPU's
//! value is also checked against the exact distance (the minimum of
//! `box_triangle_distance` over every triangle and periodic copy): at most it, and within
//! the tolerance of it.
//!
//! The per-pair functions of the twin (`shaders/ddm-compress/plain_map.wgsl`) are also
//! compared one by one with their Rust on random, integer-aligned (touching) and degenerate
//! box–triangle pairs (the kernel `shaders/test-kernels/ddm_plain_pairs_differential.wgsl`).

use ddm_compress::geometry::{closest_point_on_triangle, segment_distance_squared, triangle_overlaps_box};
use ddm_compress::{
    Aabb, DistanceMapSettings, MapKind, PlainGpuScene, PlainGpuTriangle, Triangle, box_triangle_distance,
    compute_distance_maps,
};
use glam::{UVec3, Vec3, Vec4};
use integration_tests::gpu;
use mesostructure::Mesostructure;
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

/// The bounds' rounding margins at coordinates below 100 (`plain::MARGIN` and
/// `geometry::BOX_TRIANGLE_MARGIN`, 2e-6 relative, times the scale), with room for the
/// GPU's own rounding of the same operations.
const ROUNDING: f32 = 1e-4;

/// The exact box-to-mesh distance of voxel `(x, y, z)`: every triangle and, when
/// periodic, its eight neighbouring copies.
fn exact_distance(triangles: &[Triangle], dims: UVec3, periodic: bool, voxel: UVec3, cap: f32) -> f32 {
    let aabb = Aabb::voxel(voxel.x, voxel.y, voxel.z);
    let shifts: Vec<Vec3> = if periodic {
        (-1..=1)
            .flat_map(|i| (-1..=1).map(move |j| Vec3::new(i as f32 * dims.x as f32, j as f32 * dims.y as f32, 0.0)))
            .collect()
    } else {
        vec![Vec3::ZERO]
    };
    let mut best = cap;
    for t in triangles {
        for shift in &shifts {
            best = best.min(box_triangle_distance(&aabb, &Triangle(t.0.map(|v| v + *shift))));
        }
    }
    best
}

#[test]
fn the_gpu_plain_map_equals_the_cpu_one_within_the_tolerance_on_every_tile() {
    let dims = UVec3::new(16, 16, 8);
    let mut compared = 0;
    let mut sampled = 0;
    let mut surface_voxels = 0;
    for structure in Mesostructure::ALL {
        let triangles = structure.triangles(dims);
        for (periodic_xy, tolerance) in [(true, 0.05), (false, 0.25)] {
            let settings = DistanceMapSettings { tolerance, periodic_xy };
            let cpu = compute_distance_maps(dims, &triangles, MapKind::Plain, settings).unwrap();
            let scene = PlainGpuScene::new(dims, &triangles, settings).unwrap();
            let gpu_maps = ddm_render::build_plain_map(gpu(), &scene).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(gpu_maps.max_distance, cpu.max_distance);
            assert_eq!(gpu_maps.periodic_xy, periodic_xy);
            let (mut largest, mut mean_gpu, mut mean_cpu) = (0.0_f32, 0.0_f64, 0.0_f64);
            for (index, (&g, &c)) in gpu_maps.values[0].iter().zip(&cpu.values[0]).enumerate() {
                let name = structure.name();
                assert_eq!(gpu_maps.surface[index], cpu.surface[index], "{name} periodic {periodic_xy} voxel {index}");
                assert!(
                    (g - c).abs() <= tolerance + ROUNDING,
                    "{name} periodic {periodic_xy} voxel {index}: GPU {g}, CPU {c}"
                );
                largest = largest.max((g - c).abs());
                mean_gpu += f64::from(g);
                mean_cpu += f64::from(c);
                surface_voxels += usize::from(cpu.surface[index]);
                compared += 1;
            }
            // Every 37th voxel against the exact distance.
            for index in (0..gpu_maps.values[0].len()).step_by(37) {
                let voxel = UVec3::new(
                    index as u32 % dims.x,
                    (index as u32 / dims.x) % dims.y,
                    index as u32 / (dims.x * dims.y),
                );
                let exact = exact_distance(&triangles, dims, periodic_xy, voxel, cpu.max_distance);
                let g = gpu_maps.values[0][index];
                assert!(g <= exact + ROUNDING, "{} voxel {voxel}: GPU {g} above the exact {exact}", structure.name());
                assert!(
                    g >= exact - tolerance - ROUNDING,
                    "{} voxel {voxel}: GPU {g} ≪ the exact {exact}",
                    structure.name()
                );
                sampled += 1;
            }
            let n = gpu_maps.values[0].len() as f64;
            println!(
                "{} periodic {periodic_xy} tolerance {tolerance}: largest |GPU − CPU| {largest:.4}, mean GPU {:.4}, mean CPU {:.4}",
                structure.name(),
                mean_gpu / n,
                mean_cpu / n
            );
        }
    }
    let voxels = (dims.x * dims.y * dims.z) as usize;
    assert_eq!(compared, 10 * voxels);
    assert_eq!(sampled, 10 * voxels.div_ceil(37));
    // The comparison covers both kinds of voxel.
    assert!(surface_voxels > 0 && surface_voxels < compared, "{surface_voxels} surface voxels");
}

#[test]
fn an_empty_scene_builds_the_cap_everywhere_and_a_grid_not_a_multiple_of_the_tile_is_covered() {
    // 5 × 3 × 7: every workgroup side (4) overhangs; no voxel may stay unwritten.
    let dims = UVec3::new(5, 3, 7);
    let settings = DistanceMapSettings { tolerance: 0.05, periodic_xy: false };
    let scene = PlainGpuScene::new(dims, &[], settings).unwrap();
    let maps = ddm_render::build_plain_map(gpu(), &scene).unwrap_or_else(|e| panic!("{e}"));
    assert!(maps.values[0].iter().all(|&v| v == maps.max_distance), "{:?}", maps.values[0]);
    assert!(maps.surface.iter().all(|&s| !s));
    // One triangle: the voxels it crosses flagged, as on the CPU.
    let triangle = Triangle([Vec3::new(0.5, 0.5, 3.5), Vec3::new(4.5, 0.5, 3.5), Vec3::new(0.5, 2.5, 3.5)]);
    let scene = PlainGpuScene::new(dims, &[triangle], settings).unwrap();
    let maps = ddm_render::build_plain_map(gpu(), &scene).unwrap_or_else(|e| panic!("{e}"));
    let cpu = compute_distance_maps(dims, &[triangle], MapKind::Plain, settings).unwrap();
    assert_eq!(maps.surface, cpu.surface);
    for (index, (&g, &c)) in maps.values[0].iter().zip(&cpu.values[0]).enumerate() {
        assert!((g - c).abs() <= 0.05 + ROUNDING, "voxel {index}: GPU {g}, CPU {c}");
    }
    assert_eq!(maps.values[0].len(), 105);
}

/// Random pairs (boxes of sides 0.25–2 and triangles spread around them), pairs of a unit
/// voxel and an integer triangle (which often touch exactly, as the maze's walls do), and
/// degenerate triangles (a repeated corner, three collinear corners).
fn pairs() -> Vec<(Aabb, Triangle, f32)> {
    let mut rng = SmallRng::seed_from_u64(0x5eed_91a7_3c2d_0e14);
    let mut pairs = Vec::new();
    let tolerances = [0.01, 0.05, 0.25];
    for k in 0..3000 {
        let min = Vec3::new(rng.random_range(-3.0..3.0), rng.random_range(-3.0..3.0), rng.random_range(-3.0..3.0));
        let size = Vec3::new(rng.random_range(0.25..2.0), rng.random_range(0.25..2.0), rng.random_range(0.25..2.0));
        let anchor =
            min + Vec3::new(rng.random_range(-3.0..5.0), rng.random_range(-3.0..5.0), rng.random_range(-3.0..5.0));
        let mut vertex = || {
            anchor + Vec3::new(rng.random_range(-1.5..1.5), rng.random_range(-1.5..1.5), rng.random_range(-1.5..1.5))
        };
        let triangle = Triangle([vertex(), vertex(), vertex()]);
        pairs.push((Aabb { min, max: min + size }, triangle, tolerances[k % 3]));
    }
    for k in 0..1000 {
        let mut corner = || {
            Vec3::new(rng.random_range(-2..4) as f32, rng.random_range(-2..4) as f32, rng.random_range(-2..4) as f32)
        };
        let triangle = Triangle([corner(), corner(), corner()]);
        pairs.push((Aabb::voxel(0, 0, 0), triangle, tolerances[k % 3]));
    }
    for k in 0..300 {
        let a = Vec3::new(rng.random_range(-2.0..3.0), rng.random_range(-2.0..3.0), rng.random_range(-2.0..3.0));
        let b = Vec3::new(rng.random_range(-2.0..3.0), rng.random_range(-2.0..3.0), rng.random_range(-2.0..3.0));
        let triangle = if k % 2 == 0 { Triangle([a, a, b]) } else { Triangle([a, (a + b) * 0.5, b]) };
        pairs.push((Aabb::voxel(0, 0, 0), triangle, tolerances[k % 3]));
    }
    pairs
}

#[test]
fn the_per_pair_functions_equal_their_rust() {
    let pairs = pairs();
    let queries: Vec<PlainGpuTriangle> = pairs
        .iter()
        .map(|(aabb, t, tolerance)| PlainGpuTriangle {
            a: t.0[0].extend(0.0),
            b: t.0[1].extend(0.0),
            c: t.0[2].extend(0.0),
            min: aabb.min.extend(*tolerance),
            max: aabb.max.extend(0.0),
        })
        .collect();
    let source = shader_registry::test_kernel_source("ddm_plain_pairs_differential").unwrap_or_else(|e| panic!("{e}"));
    let results: Vec<Vec4> = gpu().compute_map(&source, "pair_bounds", &[], &queries).unwrap();
    let points: Vec<Vec4> = gpu().compute_map(&source, "closest_points", &[], &queries).unwrap();
    let (mut compared, mut overlapping) = (0, 0);
    let (mut distance_gap, mut segment_gap, mut point_gap) = (0.0_f32, 0.0_f32, 0.0_f32);
    for (k, ((aabb, triangle, tolerance), (result, point))) in pairs.iter().zip(results.iter().zip(&points)).enumerate()
    {
        // Overlap: the same separating-axis test, decided the same way even where the
        // triangle touches the box exactly (integer pairs).
        let overlaps = triangle_overlaps_box(triangle, aabb);
        assert_eq!(result.x == 1.0, overlaps, "pair {k}: overlap, {triangle:?} {aabb:?}");
        overlapping += usize::from(overlaps);
        // The exact distance: the same minimum over the same candidates, rounded apart by
        // a few ulps of the coordinates (below 10): well within 1e-4.
        let exact = box_triangle_distance(aabb, triangle);
        assert!((result.y - exact).abs() <= 1e-4, "pair {k}: exact distance GPU {} CPU {exact}", result.y);
        distance_gap = distance_gap.max((result.y - exact).abs());
        // The pair bound: a lower bound of the exact distance within the tolerance of it
        // (plus the margins, 1e-4 here).
        assert!(result.z <= exact + 1e-4, "pair {k}: bound {} above the exact {exact}", result.z);
        assert!(result.z >= exact - tolerance - 1e-4, "pair {k}: bound {} ≪ the exact {exact}: {triangle:?}", result.z);
        // The segment distance (squared, up to about 200): relative rounding.
        let box_edge_end = Vec3::new(aabb.max.x, aabb.min.y, aabb.min.z);
        let segments = segment_distance_squared(triangle.0[0], triangle.0[1], aabb.min, box_edge_end);
        assert!(
            (result.w - segments).abs() <= 1e-5 * (1.0 + segments),
            "pair {k}: segments GPU {} CPU {segments}",
            result.w
        );
        segment_gap = segment_gap.max((result.w - segments).abs() / (1.0 + segments));
        // The closest point of the triangle to the box's centre.
        let nearest = closest_point_on_triangle((aabb.min + aabb.max) * 0.5, triangle);
        assert!(point.truncate().distance(nearest) <= 1e-4, "pair {k}: closest point GPU {point} CPU {nearest}");
        point_gap = point_gap.max(point.truncate().distance(nearest));
        compared += 1;
    }
    println!(
        "{compared} pairs ({overlapping} overlapping): largest |GPU − CPU| exact distance {distance_gap:e}, \
         segments (relative) {segment_gap:e}, closest point {point_gap:e}"
    );
    assert_eq!(compared, 4300);
    assert!(overlapping > 100 && overlapping < compared - 100, "{overlapping} overlapping pairs");
}
