//! CPU rays per second of the DDM tracer (Algorithms 3.1–3.3) and its baselines on a
//! 16 × 16 × 8 maze tile: sphere tracing with the plain distance map and the DDM 4×1, DDM
//! 4×1 + quadric patches on raw and compressed maps, DDM 4×1 with exact triangle patches
//! and with adaptive patches (fitted quadric or triangles per voxel, budget 1e-3 voxel), both
//! also with voxel-exit stepping (adaptive also on compressed maps, where a block without
//! surface is one cell), relief
//! mapping, and the exact mesh ground truth. Throughput is in rays (one camera ray per
//! element).

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use ddm_compress::{DirectionCones, DistanceMapSettings, MapKind, compute_distance_maps};
use ddm_tracer::{
    CompressedMaps, HeightMap, MeshRaycaster, Method, PatchSettings, PatchSurface, Stepping, TraceSettings,
    VoxelPatches, relief_trace, trace,
};
use glam::{UVec3, Vec2};
use mesostructure::Mesostructure;

fn tracer(c: &mut Criterion) {
    let dims = UVec3::new(16, 16, 8);
    let triangles = Mesostructure::Maze(1).triangles(dims);
    let settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: true };
    let plain = compute_distance_maps(dims, &triangles, MapKind::Plain, settings).expect("valid scene");
    let ddm4x1 = MapKind::Directional(DirectionCones::downward(4, 1).expect("valid cones"));
    let ddm = compute_distance_maps(dims, &triangles, ddm4x1, settings).expect("valid scene");
    let compressed = CompressedMaps::compress(&ddm, 4).expect("compressible");
    let patches = VoxelPatches::build(dims, &triangles, &ddm.surface, PatchSettings::default()).expect("patches");
    let with = |surface| PatchSettings { surface, ..PatchSettings::default() };
    let exact = VoxelPatches::build(dims, &triangles, &ddm.surface, with(PatchSurface::Triangles)).expect("patches");
    let adaptive =
        VoxelPatches::build(dims, &triangles, &ddm.surface, with(PatchSurface::Adaptive { max_error: 1e-3 }))
            .expect("patches");
    let mesh = MeshRaycaster::new(&triangles, Vec2::new(dims.x as f32, dims.y as f32));
    let height_map = HeightMap::from_mesh(&mesh, dims, 2).expect("valid tile");
    let rays = benches::tracer_rays(dims);
    let sphere = TraceSettings { method: Method::SphereTracing, max_steps: 512, stepping: Stepping::Distance };
    let quadric = TraceSettings { method: Method::Quadric, max_steps: 512, stepping: Stepping::Distance };

    let mut group = c.benchmark_group("ddm_tracer/maze_16x16x8");
    group.throughput(Throughput::Elements(rays.len() as u64));
    group.bench_function("sphere_tracing/plain_dm", |b| {
        b.iter(|| rays.iter().filter(|&&(o, d)| trace(&plain, None, black_box(o), d, sphere).hit.is_some()).count());
    });
    group.bench_function("sphere_tracing/ddm_4x1", |b| {
        b.iter(|| rays.iter().filter(|&&(o, d)| trace(&ddm, None, black_box(o), d, sphere).hit.is_some()).count());
    });
    group.bench_function("quadric/ddm_4x1", |b| {
        b.iter(|| {
            rays.iter().filter(|&&(o, d)| trace(&ddm, Some(&patches), black_box(o), d, quadric).hit.is_some()).count()
        });
    });
    group.bench_function("quadric/ddm_4x1_compressed_block4", |b| {
        b.iter(|| {
            rays.iter()
                .filter(|&&(o, d)| trace(&compressed, Some(&patches), black_box(o), d, quadric).hit.is_some())
                .count()
        });
    });
    let blocks = TraceSettings { stepping: Stepping::BlockCells, ..quadric };
    group.bench_function("quadric/ddm_4x1_block_cells_compressed_block4", |b| {
        b.iter(|| {
            rays.iter()
                .filter(|&&(o, d)| trace(&compressed, Some(&patches), black_box(o), d, blocks).hit.is_some())
                .count()
        });
    });
    group.bench_function("triangles/ddm_4x1", |b| {
        b.iter(|| {
            rays.iter().filter(|&&(o, d)| trace(&ddm, Some(&exact), black_box(o), d, quadric).hit.is_some()).count()
        });
    });
    group.bench_function("adaptive_1e-3/ddm_4x1", |b| {
        b.iter(|| {
            rays.iter().filter(|&&(o, d)| trace(&ddm, Some(&adaptive), black_box(o), d, quadric).hit.is_some()).count()
        });
    });
    group.bench_function("adaptive_1e-3/ddm_4x1_compressed_block4", |b| {
        b.iter(|| {
            rays.iter()
                .filter(|&&(o, d)| trace(&compressed, Some(&adaptive), black_box(o), d, quadric).hit.is_some())
                .count()
        });
    });
    let exit = |settings| TraceSettings { stepping: Stepping::VoxelExit, ..settings };
    group.bench_function("sphere_tracing/ddm_4x1_voxel_exit", |b| {
        b.iter(|| {
            rays.iter().filter(|&&(o, d)| trace(&ddm, None, black_box(o), d, exit(sphere)).hit.is_some()).count()
        });
    });
    group.bench_function("adaptive_1e-3/ddm_4x1_voxel_exit", |b| {
        b.iter(|| {
            rays.iter()
                .filter(|&&(o, d)| trace(&ddm, Some(&adaptive), black_box(o), d, exit(quadric)).hit.is_some())
                .count()
        });
    });
    group.bench_function("adaptive_1e-3/ddm_4x1_voxel_exit_compressed_block4", |b| {
        b.iter(|| {
            rays.iter()
                .filter(|&&(o, d)| trace(&compressed, Some(&adaptive), black_box(o), d, exit(quadric)).hit.is_some())
                .count()
        });
    });
    group.bench_function("relief/32_linear_8_binary", |b| {
        b.iter(|| {
            rays.iter()
                .filter(|&&(o, d)| relief_trace(&height_map, dims.z as f32, black_box(o), d, 32, 8).hit.is_some())
                .count()
        });
    });
    group.bench_function("ground_truth/mesh_bvh", |b| {
        b.iter(|| {
            rays.iter().filter(|&&(o, d)| mesh.first_hit(black_box(o).as_dvec3(), d.as_dvec3(), 1e4).is_some()).count()
        });
    });
    group.finish();
}

criterion_group!(benches, tracer);
criterion_main!(benches);
