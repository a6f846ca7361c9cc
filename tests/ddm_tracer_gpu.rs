//! CPU = GPU differential test of `shaders/ddm_tracer.wgsl` (the compute tracer of
//! Algorithms 3.1–3.3) against `ddm-tracer`'s CPU reference: plain distance map and DDM
//! 4×1 sphere tracing, DDM + quadric (C⁰ patches, and the adaptive quadric / exact
//! triangle patches) and relief mapping, on a maze and a ball, reading compressed maps;
//! and lone bounded triangle patches.
//!
//! Compared per ray: hit or miss, the cone, the step count, the hit point and normal.
//! Single precision on both sides; the GPU may contract `a + b * c` into fused
//! multiply-adds, so a ray whose step lands within rounding of a voxel wall can take one
//! step more or less, and a hit point can move by a few ulps.

use ddm_compress::{DirectionCones, DistanceMapSettings, MapKind, compute_distance_maps};
use ddm_tracer::{
    CompressedMaps, HeightMap, MeshRaycaster, Method, PatchSettings, PatchSurface, Stepping, TraceOutcome,
    TraceSettings, VoxelPatches, relief_trace, trace,
};
use ddm_tracer::{GpuScene, TraceResult};
use glam::{UVec3, Vec2, Vec3};
use integration_tests::gpu;
use mesostructure::Mesostructure;
use shader_registry::kernel_io::ddm_tracer::TraceRay;

const DIMS: UVec3 = UVec3::new(12, 12, 6);

fn kernel_source() -> String {
    shader_registry::test_kernel_source("ddm_tracer_compute").unwrap_or_else(|e| panic!("{e}"))
}

/// Random downward rays from above the slab, plus special ones: straight down, along
/// the cone boundaries (azimuth multiples of 90°), grazing, upward (misses), through
/// voxel corners.
fn rays(count: usize, seed: u64) -> Vec<(Vec3, Vec3)> {
    let mut state = seed;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    let top = DIMS.z as f32 + 0.5;
    let mut rays: Vec<(Vec3, Vec3)> = (0..count)
        .map(|_| {
            let origin = Vec3::new(next() * DIMS.x as f32, next() * DIMS.y as f32, top);
            let azimuth = next() * std::f32::consts::TAU;
            let elevation = -(5.0 + 85.0 * next()).to_radians();
            let d = Vec3::new(elevation.cos() * azimuth.cos(), elevation.cos() * azimuth.sin(), elevation.sin());
            (origin, d * (0.5 + 2.0 * next()))
        })
        .collect();
    for k in 0..64 {
        let origin = Vec3::new(k as f32 * 0.37, k as f32 * 0.21, top);
        rays.push((origin, Vec3::NEG_Z));
        rays.push((Vec3::new(k as f32, 3.0, top), Vec3::new(1.0, 0.0, -1.0)));
        rays.push((Vec3::new(2.0, k as f32, top), Vec3::new(0.0, -1.0, -0.3)));
        rays.push((Vec3::new(k as f32 * 0.5, 1.0, 3.0), Vec3::new(0.3, 0.2, 1.0)));
        rays.push((Vec3::new(k as f32 * 0.25, 5.0, top), Vec3::new(1.0, 1.0, -0.01)));
    }
    rays
}

struct Mismatches {
    rays: usize,
    hit_miss: usize,
    cone: usize,
    steps: usize,
    worst_point: f32,
    worst_normal: f32,
    boundary: usize,
    /// Rays on a cone boundary that CPU and GPU assigned to different cones.
    split: usize,
}

fn compare(maps: &CompressedMaps, patches: Option<&VoxelPatches>, settings: TraceSettings, seed: u64) -> Mismatches {
    let scene = GpuScene::new(maps, patches, settings).unwrap_or_else(|e| panic!("{e}"));
    compare_scene(&scene, maps.kind, |o, d| trace(maps, patches, o, d, settings), seed)
}

fn compare_scene(
    scene: &GpuScene,
    kind: MapKind,
    reference: impl Fn(Vec3, Vec3) -> TraceOutcome,
    seed: u64,
) -> Mismatches {
    let rays = rays(6000, seed);
    let inputs: Vec<TraceRay> = rays.iter().map(|&(o, d)| TraceRay::new(o, d)).collect();
    let uniforms = scene.uniforms(inputs.len() as u32);
    let (results, _): (Vec<TraceResult>, _) = gpu()
        .compute_map_with_storage(
            &kernel_source(),
            "trace_rays",
            bytemuck::bytes_of(&uniforms),
            &inputs,
            &scene.storage_bytes(),
        )
        .unwrap_or_else(|e| panic!("{e}"));
    let mut m = Mismatches {
        rays: rays.len(),
        hit_miss: 0,
        cone: 0,
        steps: 0,
        worst_point: 0.0,
        worst_normal: 0.0,
        boundary: 0,
        split: 0,
    };
    for (&(origin, direction), gpu) in rays.iter().zip(&results) {
        let cpu = reference(origin, direction);
        // A direction on a cone boundary belongs to both cones (both maps are safe for
        // it); CPU and GPU atan2 may round it to either side, and then read different
        // (equally valid) maps: such rays are counted, not compared.
        let sectors = kind.map_count() as f32;
        let turns = direction.y.atan2(direction.x) / std::f32::consts::TAU * sectors;
        let on_boundary = (turns - turns.round()).abs() < 1e-4;
        m.boundary += usize::from(on_boundary);
        if cpu.cone != gpu.counts.y {
            if on_boundary {
                m.split += 1;
            } else {
                m.cone += 1;
            }
            continue;
        }
        let gpu_hit = gpu.normal_hit.w == 1.0;
        if cpu.hit.is_some() != gpu_hit {
            m.hit_miss += 1;
            continue;
        }
        m.steps += usize::from(cpu.steps != gpu.counts.x || u32::from(cpu.exhausted) != gpu.counts.z);
        if let Some(hit) = cpu.hit {
            m.worst_point = m.worst_point.max((hit.point - gpu.point_t.truncate()).length());
            m.worst_normal = m.worst_normal.max((hit.normal - gpu.normal_hit.truncate()).length());
        }
    }
    m
}

#[test]
fn gpu_tracer_equals_the_cpu_reference() {
    println!("adapter: {}", gpu().describe());
    let settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: true };
    for (index, which) in [Mesostructure::Maze(1), Mesostructure::Ball].into_iter().enumerate() {
        let triangles = which.triangles(DIMS);
        let plain = compute_distance_maps(DIMS, &triangles, MapKind::Plain, settings).unwrap();
        let ddm4x1 = MapKind::Directional(DirectionCones::downward(4, 1).unwrap());
        let ddm = compute_distance_maps(DIMS, &triangles, ddm4x1, settings).unwrap();
        let patches = VoxelPatches::build(DIMS, &triangles, &ddm.surface, PatchSettings::default()).unwrap();
        // Exact triangles (bounded patches) where the fitted quadric misses 1e-3 voxel.
        let adaptive_settings =
            PatchSettings { surface: PatchSurface::Adaptive { max_error: 1e-3 }, ..Default::default() };
        let adaptive = VoxelPatches::build(DIMS, &triangles, &ddm.surface, adaptive_settings).unwrap();
        assert!(adaptive.quadric_voxels > 0 && adaptive.triangle_voxels > 0, "{}", which.name());
        let sphere = TraceSettings { method: Method::SphereTracing, max_steps: 256, stepping: Stepping::Distance };
        let quadric = TraceSettings { method: Method::Quadric, max_steps: 256, stepping: Stepping::Distance };
        let cases = [
            ("plain DM", CompressedMaps::compress(&plain, 2).unwrap(), None, sphere),
            ("DDM 4x1", CompressedMaps::compress(&ddm, 2).unwrap(), None, sphere),
            ("DDM 4x1 + quadric", CompressedMaps::compress(&ddm, 4).unwrap(), Some(&patches), quadric),
            ("DDM 4x1 + adaptive 1e-3", CompressedMaps::compress(&ddm, 4).unwrap(), Some(&adaptive), quadric),
            (
                "plain DM, voxel-exit stepping",
                CompressedMaps::compress(&plain, 2).unwrap(),
                None,
                TraceSettings { stepping: Stepping::VoxelExit, ..sphere },
            ),
            (
                "DDM 4x1, block cells",
                CompressedMaps::compress(&ddm, 4).unwrap(),
                None,
                TraceSettings { stepping: Stepping::BlockCells, ..sphere },
            ),
            (
                "DDM 4x1 + quadric, block cells",
                CompressedMaps::compress(&ddm, 4).unwrap(),
                Some(&patches),
                TraceSettings { stepping: Stepping::BlockCells, ..quadric },
            ),
            (
                "DDM 4x1 + adaptive 1e-3, voxel-exit stepping",
                CompressedMaps::compress(&ddm, 4).unwrap(),
                Some(&adaptive),
                TraceSettings { stepping: Stepping::VoxelExit, ..quadric },
            ),
            (
                "DDM 4x1 + quadric, 16 steps",
                CompressedMaps::compress(&ddm, 1).unwrap(),
                Some(&patches),
                TraceSettings { max_steps: 16, ..quadric },
            ),
        ];
        for (name, maps, patches, trace_settings) in cases {
            let m = compare(&maps, patches, trace_settings, 0x5eed + index as u64);
            println!(
                "{} {name}: {} rays ({} on cone boundaries, {} of them in different cones), hit/miss differ {}, cone differs {}, steps differ {}, worst point {:e}, worst normal {:e}",
                which.name(),
                m.rays,
                m.boundary,
                m.split,
                m.hit_miss,
                m.cone,
                m.steps,
                m.worst_point,
                m.worst_normal
            );
            // Measured on lavapipe: every count 0 and every difference exactly 0 (no
            // contraction). The bounds leave room for an adapter that fuses: a handful of
            // rays (≤ 0.1 %) taking another step, points within 1e-4 voxel.
            assert_eq!(m.hit_miss, 0, "{} {name}", which.name());
            // Only the 64 special rays at azimuth exactly 270° (a 4-cone boundary) split.
            assert!(m.split <= 64, "{} {name}: {}", which.name(), m.split);
            assert!(m.cone <= 2 && m.steps <= 6, "{} {name}", which.name());
            assert!(m.worst_point <= 1e-4 && m.worst_normal <= 1e-3, "{} {name}", which.name());
        }
        // Relief mapping of the same tile's height map (2 texels per voxel, 32 + 8 steps).
        let mesh = MeshRaycaster::new(&triangles, Vec2::new(DIMS.x as f32, DIMS.y as f32));
        let height_map = HeightMap::from_mesh(&mesh, DIMS, 2).unwrap_or_else(|e| panic!("{e}"));
        let maps = CompressedMaps::compress(&plain, 2).unwrap();
        let scene = GpuScene::new(
            &maps,
            None,
            TraceSettings { method: Method::SphereTracing, max_steps: 1, stepping: Stepping::Distance },
        )
        .and_then(|s| s.with_relief(&height_map, 32, 8))
        .unwrap_or_else(|e| panic!("the relief scene does not pack: {e}"));
        let size_z = DIMS.z as f32;
        let m = compare_scene(
            &scene,
            MapKind::Plain,
            |o, d| relief_trace(&height_map, size_z, o, d, 32, 8),
            0x7e1e + index as u64,
        );
        println!(
            "{} relief: {} rays, hit/miss differ {}, steps differ {}, worst point {:e}, worst normal {:e}",
            which.name(),
            m.rays,
            m.hit_miss,
            m.steps,
            m.worst_point,
            m.worst_normal
        );
        // Measured on lavapipe: 0 hit/miss and step differences, points equal, normals
        // within 4.6e-7 (WGSL's normalize() against glam's).
        assert_eq!(m.hit_miss, 0, "{} relief", which.name());
        assert!(m.steps <= 6, "{} relief", which.name());
        assert!(m.worst_point <= 1e-4 && m.worst_normal <= 1e-5, "{} relief", which.name());
    }
}

/// Small floating triangles, one inside each of every other voxel of two layers: each
/// such voxel keeps one bounded patch, so rays that cross its plane beside the triangle
/// test that the GPU clips a lone bounded patch to its polygon as the CPU does.
#[test]
fn lone_triangle_patches_are_clipped_on_the_gpu_as_on_the_cpu() {
    let mut triangles = Vec::new();
    for z in [1u32, 3] {
        for y in 0..DIMS.y {
            for x in (y % 2..DIMS.x).step_by(2) {
                let c = Vec3::new(x as f32 + 0.2, y as f32 + 0.25, z as f32 + 0.4);
                let tilt = 0.05 * (x % 3) as f32;
                triangles.push(ddm_compress::Triangle([
                    c,
                    c + Vec3::new(0.5, 0.1, tilt),
                    c + Vec3::new(0.1, 0.45, -tilt),
                ]));
            }
        }
    }
    let settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: true };
    let maps = compute_distance_maps(DIMS, &triangles, MapKind::Plain, settings).unwrap();
    let exact = PatchSettings { surface: PatchSurface::Triangles, ..Default::default() };
    let patches = VoxelPatches::build(DIMS, &triangles, &maps.surface, exact).unwrap();
    assert_eq!(patches.patches.len(), triangles.len(), "one bounded patch per voxel");
    let quadric = TraceSettings { method: Method::Quadric, max_steps: 256, stepping: Stepping::Distance };
    let maps = CompressedMaps::compress(&maps, 2).unwrap();
    let m = compare(&maps, Some(&patches), quadric, 0x10e);
    let rays = rays(6000, 0x10e);
    let hits = rays.iter().filter(|&&(o, d)| trace(&maps, Some(&patches), o, d, quadric).hit.is_some()).count();
    println!(
        "floating triangles: {} rays ({hits} hit on the CPU), hit/miss differ {}, steps differ {}, worst point {:e}",
        m.rays, m.hit_miss, m.steps, m.worst_point
    );
    // Measured on lavapipe: 612 of 6320 rays hit, 0 hit/miss and step differences,
    // points equal. With the WGSL clipping of lone bounded patches removed (checked
    // once), 3679 rays differ: the GPU then hits the triangles' planes beside them.
    assert!(hits > 500 && hits < m.rays - 500, "{hits}");
    assert_eq!(m.hit_miss, 0);
    assert!(m.steps <= 6 && m.worst_point <= 1e-4);
}

#[test]
fn scene_buffers_are_checked_against_the_adapter() {
    let kernel = kernel_source();
    let uniforms = [0_u8; 48];
    let rays = [TraceRay::new(Vec3::ZERO, Vec3::NEG_Z)];
    // An empty storage buffer is a request error, not a wgpu panic.
    let empty: [&[u8]; 5] = [&[0; 48], &[0; 4], &[], &[0; 8], &[0; 128]];
    let result =
        gpu().compute_map_with_storage::<TraceRay, TraceResult>(&kernel, "trace_rays", &uniforms, &rays, &empty);
    assert!(matches!(result, Err(gpu_harness::HarnessError::InvalidRequest(_))), "{result:?}");
    // More storage bindings than the adapter allows per stage.
    let limit = gpu().limits().max_storage_buffers_per_shader_stage as usize;
    let many: Vec<&[u8]> = vec![&[0_u8; 16][..]; limit];
    let result =
        gpu().compute_map_with_storage::<TraceRay, TraceResult>(&kernel, "trace_rays", &uniforms, &rays, &many);
    assert!(matches!(result, Err(gpu_harness::HarnessError::TooLarge { .. })), "{result:?}");
}
