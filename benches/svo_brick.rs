//! CPU cost of `svo-brick` on the displaced sphere (`benches::displaced`): the octree's
//! build (bricks per second), the surface statistics that prefilter the coarse levels
//! (surface samples per second), the thin-shell surface sampling the build feeds them with
//! (samples per second), and quadrilinear and nearest sampling of both packed layouts (ns
//! per query = time / 4096). Short settings (10 samples) so that the file runs in about a
//! minute.

use std::hint::black_box;
use std::time::Duration;

use benches::displaced::{self, Normalisation};
use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, Criterion, SamplingMode, Throughput, criterion_group, criterion_main};
use glam::Vec3;
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use svo_brick::{BrickSize, BrickTree, BuildOptions, Cell, PackedTree, SurfaceSample, SurfaceSource, VoxelLayout};

/// Queries per sampling iteration.
const QUERIES: usize = 4096;

/// The 64³ build: 8³ bricks, 4 levels, the builder's other defaults.
fn options_64() -> BuildOptions {
    BuildOptions { brick_size: BrickSize::Eight, levels: 4, ..BuildOptions::default() }
}

/// 10 samples, short warm-up and measurement.
fn short(group: &mut BenchmarkGroup<'_, WallTime>) {
    group.sample_size(10).warm_up_time(Duration::from_millis(500)).measurement_time(Duration::from_secs(2));
}

/// `BrickTree::build` of the displaced sphere at 64³ (all levels: placement, surface
/// samples, box filters, statistics, dilation, brick assembly), in bricks per second.
fn build(c: &mut Criterion) {
    let source = displaced::displaced_sphere(Normalisation::Sum);
    let bricks = BrickTree::build(&source, displaced::domain(), options_64()).expect("builds").brick_count();
    let mut group = c.benchmark_group("svo_brick/build");
    short(&mut group);
    group.sampling_mode(SamplingMode::Flat);
    group.throughput(Throughput::Elements(bricks as u64));
    group.bench_function("displaced_sphere_64", |b| {
        b.iter(|| BrickTree::build(&source, black_box(displaced::domain()), options_64()).expect("builds"));
    });
    group.finish();
}

/// A bumpy patch of `side²` surface samples, half a finest voxel apart, over the footprint
/// of a voxel of `side / 2` finest voxels centred at `(side / 4)³` (finest-voxel units):
/// heights `z = c + h(x, y)` of two crossed sine waves (±0.4 voxel), exact normals, areas
/// `¼ √(1 + |∇h|²)`, a colour that follows the height.
fn bumpy_patch(side: u32) -> (Vec<SurfaceSample>, Vec3) {
    let centre = Vec3::splat(side as f32 / 4.0);
    let height = |x: f32, y: f32| 0.25 * (1.3 * x + 0.2).sin() * (1.7 * y).sin() + 0.15 * (2.9 * x - 1.1 * y).cos();
    let slope = |x: f32, y: f32| {
        let dx = 0.25 * 1.3 * (1.3 * x + 0.2).cos() * (1.7 * y).sin() - 0.15 * 2.9 * (2.9 * x - 1.1 * y).sin();
        let dy = 0.25 * 1.7 * (1.3 * x + 0.2).sin() * (1.7 * y).cos() + 0.15 * 1.1 * (2.9 * x - 1.1 * y).sin();
        (dx, dy)
    };
    let samples = (0..side * side)
        .map(|k| {
            let (x, y) = ((k % side) as f32 * 0.5 + 0.25, (k / side) as f32 * 0.5 + 0.25);
            let (h, (dx, dy)) = (height(x, y), slope(x, y));
            let u = 0.5 + h;
            SurfaceSample {
                position: Vec3::new(x, y, centre.z + h),
                normal: Vec3::new(-dx, -dy, 1.0).normalize(),
                area: 0.25 * (1.0 + dx * dx + dy * dy).sqrt(),
                attribute: [u, 0.8 * u, 0.3 + 0.4 * u],
            }
        })
        .collect();
    (samples, centre)
}

/// `surface_statistics` (σh², σn², ā, `a_s` of one coarse voxel) over 64 samples (a level-2
/// voxel at 2 samples per finest voxel) and 256 samples (level 3), in samples per second:
/// the prefiltering step the build repeats for every coarse voxel.
fn prefilter(c: &mut Criterion) {
    let mut group = c.benchmark_group("svo_brick/prefilter");
    short(&mut group);
    for side in [8_u32, 16] {
        let (samples, centre) = bumpy_patch(side);
        let mean = samples.iter().map(|s| s.position.z - centre.z).sum::<f32>() / samples.len() as f32;
        group.throughput(Throughput::Elements(samples.len() as u64));
        group.bench_function(format!("surface_statistics_{}", samples.len()), |b| {
            b.iter(|| svo_brick::surface_statistics(black_box(&samples), centre, -mean, Vec3::Z).expect("has area"));
        });
    }
    group.finish();
}

/// The thin-shell surface samples of the finest bricks of the 64³ build that hold the most
/// surface, at the build's spacing (half a finest voxel), in surface samples per second.
fn surface_sampling(c: &mut Criterion) {
    let source = displaced::displaced_sphere(Normalisation::Sum);
    let tree = BrickTree::build(&source, displaced::domain(), options_64()).expect("builds");
    let n = tree.brick_size().side();
    let spacing = tree.voxel_size() / options_64().samples_per_voxel as f32;
    let cells: Vec<Cell> = tree
        .brick_levels()
        .iter()
        .zip(tree.brick_origins())
        .filter(|&(&level, _)| level == 0)
        .map(|(_, &o)| Cell { min: tree.world(o.as_vec3()), max: tree.world((o + n).as_vec3()) })
        .step_by(16)
        .collect();
    let mut out = Vec::new();
    let count: usize = cells
        .iter()
        .map(|&cell| {
            out.clear();
            source.surface_samples(cell, spacing, &mut out);
            out.len()
        })
        .sum();
    let mut group = c.benchmark_group("svo_brick/surface_samples");
    short(&mut group);
    group.throughput(Throughput::Elements(count as u64));
    group.bench_function(format!("thin_shell_{}_bricks_64", cells.len()), |b| {
        b.iter(|| {
            cells
                .iter()
                .map(|&cell| {
                    out.clear();
                    source.surface_samples(black_box(cell), spacing, &mut out);
                    out.len()
                })
                .sum::<usize>()
        });
    });
    group.finish();
}

/// 4096 fixed points within ±0.08 of the undisplaced sphere (the displacement reaches
/// ±0.075) in uniform random directions, each with a uniform random lod in `[0, 3]`.
fn queries() -> Vec<(Vec3, f32)> {
    let mut rng = SmallRng::seed_from_u64(16);
    (0..QUERIES)
        .map(|_| {
            let z: f32 = rng.random_range(-1.0..1.0);
            let phi: f32 = rng.random_range(0.0..std::f32::consts::TAU);
            let r = (1.0 - z * z).sqrt();
            let radius = displaced::DISPLACED_RADIUS + rng.random_range(-0.08..0.08);
            (Vec3::new(r * phi.cos(), r * phi.sin(), z) * radius, rng.random_range(0.0..3.0))
        })
        .collect()
}

/// `PackedTree::sample` (quadrilinear) and `sample_nearest` of the 64³ tree in both
/// layouts, per 4096 queries (ns per query = time / 4096).
fn sample(c: &mut Criterion) {
    let source = displaced::displaced_sphere(Normalisation::Sum);
    let tree = BrickTree::build(&source, displaced::domain(), options_64()).expect("builds");
    let queries = queries();
    let mut group = c.benchmark_group("svo_brick/sample_64");
    short(&mut group);
    group.throughput(Throughput::Elements(QUERIES as u64));
    for layout in VoxelLayout::ALL {
        let packed = PackedTree::new(&tree, layout);
        group.bench_function(format!("quadrilinear/{}", layout.name()), |b| {
            b.iter(|| {
                queries
                    .iter()
                    .map(|&(p, lod)| packed.sample(black_box(p), lod).map_or(0.0, |v| v.distance))
                    .sum::<f32>()
            });
        });
        group.bench_function(format!("nearest/{}", layout.name()), |b| {
            b.iter(|| {
                queries
                    .iter()
                    .map(|&(p, lod)| packed.sample_nearest(black_box(p), lod).map_or(0.0, |v| v.distance))
                    .sum::<f32>()
            });
        });
    }
    group.finish();
}

criterion_group!(benches, build, prefilter, surface_sampling, sample);
criterion_main!(benches);
