//! CPU cost of quadric fitting (eq. 2) and ray–quadric intersection (Algorithm 3.2).

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::{DVec3, Vec3};
use quadric_fit::{GpuQuadric, bilinear_quadric, first_hit, fit_quadric};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

const RAYS: usize = 4096;

fn intersection(c: &mut Criterion) {
    let mut rng = SmallRng::seed_from_u64(3);
    let quadric = bilinear_quadric(
        DVec3::new(0.0, 0.0, 0.2),
        DVec3::new(1.0, 0.0, 0.7),
        DVec3::new(1.0, 1.0, 0.3),
        DVec3::new(0.0, 1.0, 0.6),
    )
    .map(|q| GpuQuadric::from_quadric(&q))
    .expect("a twisted patch has a quadric");
    let rays: Vec<(Vec3, Vec3)> = (0..RAYS)
        .map(|_| {
            let origin = Vec3::new(rng.random(), rng.random(), 1.0);
            let direction = Vec3::new(rng.random_range(-0.5..0.5), rng.random_range(-0.5..0.5), -1.0).normalize();
            (origin, direction)
        })
        .collect();
    let mut group = c.benchmark_group("quadric_fit");
    group.throughput(Throughput::Elements(RAYS as u64));
    group.bench_function("first_hit", |b| {
        b.iter(|| {
            let mut sum = 0.0_f32;
            for (origin, direction) in &rays {
                sum += first_hit(&quadric, black_box(*origin), black_box(*direction), 0.0, 2.0).unwrap_or(0.0);
            }
            sum
        });
    });
    group.finish();

    let points: Vec<DVec3> = (0..64)
        .map(|i| {
            let (u, v) = (rng.random::<f64>(), rng.random::<f64>());
            DVec3::new(u, v, 0.3 + 0.2 * u * v + 0.01 * f64::from(i % 3))
        })
        .collect();
    let mut group = c.benchmark_group("quadric_fit");
    group.throughput(Throughput::Elements(1));
    group.bench_function("fit_quadric/64_points", |b| b.iter(|| fit_quadric(black_box(&points))));
    group.finish();
}

criterion_group!(benches, intersection);
criterion_main!(benches);
