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

use ddm_compress::{
    Aabb, DistanceMapSettings, MapKind, PlainGpuScene, Triangle, box_triangle_distance, compute_distance_maps,
};
use glam::{UVec3, Vec3};
use integration_tests::gpu;
use mesostructure::Mesostructure;

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
