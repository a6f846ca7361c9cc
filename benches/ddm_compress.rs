//! CPU cost of the compressed distance map's access (Algorithm A.2) and of computing a
//! small conservative directional distance map (§3.1).

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use ddm_compress::{CompressedMap, DirectionCones, DistanceMapSettings, Triangle, compute_distance_maps};
use glam::UVec3;
use mesostructure::HeightField;

/// A wavy height-field floor over an `n × n` tile.
fn wavy_floor(n: u32) -> Vec<Triangle> {
    HeightField::from_fn(n, n, |x, y| 2.0 + 0.8 * ((x * 0.9).sin() + (y * 0.7).cos())).triangles()
}

fn ddm(c: &mut Criterion) {
    let dims = UVec3::new(8, 8, 6);
    let cones = DirectionCones::downward(4, 1);
    let settings = DistanceMapSettings { tolerance: 0.1, periodic_xy: true };
    let triangles = wavy_floor(8);
    let mut group = c.benchmark_group("ddm_compress");
    group.sample_size(10);
    group.throughput(Throughput::Elements(u64::from(dims.x * dims.y * dims.z)));
    group.bench_function("compute_distance_maps/8x8x6/4x1_cones", |b| {
        b.iter(|| compute_distance_maps(black_box(dims), &triangles, cones, settings));
    });
    group.finish();

    let maps = compute_distance_maps(dims, &triangles, cones, settings).expect("valid scene");
    let map = CompressedMap::compress(&maps.values[0], &maps.surface, dims, 2).expect("valid map");
    let voxels: Vec<UVec3> = (0..4096_u32).map(|i| UVec3::new(i % 8, (i / 8) % 8, (i / 64) % 6)).collect();
    let mut group = c.benchmark_group("ddm_compress");
    group.throughput(Throughput::Elements(voxels.len() as u64));
    group.bench_function("compressed_access", |b| {
        b.iter(|| voxels.iter().map(|&v| map.access(black_box(v)).unwrap_or(0.0)).sum::<f32>());
    });
    group.finish();
}

criterion_group!(benches, ddm);
criterion_main!(benches);
