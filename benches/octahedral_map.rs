//! CPU cost of the octahedral view lookup (Listing 1), in ns per direction.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3;
use octahedral_map::OctahedralViews;
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

const DIRECTIONS: usize = 4096;

fn directions() -> Vec<Vec3> {
    let mut rng = SmallRng::seed_from_u64(1);
    (0..DIRECTIONS)
        .map(|_| Vec3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0)))
        .collect()
}

fn view_lookup(c: &mut Criterion) {
    let directions = directions();
    let mut group = c.benchmark_group("octahedral_map");
    group.throughput(Throughput::Elements(DIRECTIONS as u64));
    for n in [8_u32, 10, 64] {
        let views = OctahedralViews::new(n).unwrap();
        group.bench_function(format!("sample/n={n}"), |b| {
            b.iter(|| {
                let mut checksum = 0_u32;
                for d in &directions {
                    checksum = checksum.wrapping_add(views.sample(black_box(*d)).indices.x);
                }
                checksum
            });
        });
    }
    let views = OctahedralViews::new(8).unwrap();
    group.bench_function("view_direction/n=8", |b| {
        b.iter(|| {
            let mut sum = Vec3::ZERO;
            for index in 0..DIRECTIONS as u32 {
                sum += views.view_direction(black_box(index % views.view_count())).unwrap_or(Vec3::ZERO);
            }
            sum
        });
    });
    group.bench_function("nearest_view/n=8", |b| {
        b.iter(|| {
            let mut checksum = 0_u32;
            for d in &directions {
                checksum = checksum.wrapping_add(views.nearest_view(black_box(*d)));
            }
            checksum
        });
    });
    group.finish();
}

criterion_group!(benches, view_lookup);
criterion_main!(benches);
