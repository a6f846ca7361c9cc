//! CPU cost of Smith's Λ (eq. 6) and of the mean visible attribute ā(v, l) (eq. 17), in
//! ns per evaluation; and eq. 17 with a per-material Λ correction (table and cubic, both
//! validated once when built, never per evaluation) beside eq. 17 itself.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::Vec3;
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use smith_micro::{HeightCorrelatedAttribute, SlopeDeviation};

const COUNT: usize = 4096;

/// Directions on the upper hemisphere, biased to nothing in particular.
fn upper_directions(seed: u64) -> Vec<Vec3> {
    let mut rng = SmallRng::seed_from_u64(seed);
    (0..COUNT)
        .map(|_| Vec3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(0.0..1.0)))
        .collect()
}

fn smith(c: &mut Criterion) {
    let views = upper_directions(1);
    let lights = upper_directions(2);
    let mut rng = SmallRng::seed_from_u64(3);
    let nus: Vec<f32> = (0..COUNT).map(|_| rng.random_range(0.0..4.0)).collect();
    let slopes = SlopeDeviation::new(0.3, 0.6).expect("valid slopes");
    let attribute = HeightCorrelatedAttribute::new(0.5, 0.3).expect("valid attribute");
    let mut group = c.benchmark_group("smith_micro");
    group.throughput(Throughput::Elements(COUNT as u64));
    group.bench_function("lambda_from_nu", |b| {
        b.iter(|| nus.iter().map(|&nu| smith_micro::smith_lambda_from_nu(black_box(nu)).unwrap_or(0.0)).sum::<f32>());
    });
    group.bench_function("lambda_direction", |b| {
        b.iter(|| {
            views.iter().map(|&v| smith_micro::smith_lambda_direction(black_box(v), slopes).unwrap_or(0.0)).sum::<f32>()
        });
    });
    group.bench_function("visible_mean_attribute_for_directions", |b| {
        b.iter(|| {
            views
                .iter()
                .zip(&lights)
                .map(|(&v, &l)| {
                    smith_micro::visible_mean_attribute_for_directions(attribute, black_box(v), black_box(l), slopes)
                        .unwrap_or(0.0)
                })
                .sum::<f32>()
        });
    });
    let lambdas: Vec<(f32, f32)> =
        (0..COUNT).map(|_| (rng.random_range(0.0..12.0), rng.random_range(0.0..3.0))).collect();
    let correction = smith_micro::LambdaCorrection::from_knots([1.5, 1.4, 1.3, 1.25, 1.2, 1.15, 1.1, 1.0])
        .expect("knots in the accepted range");
    group.bench_function("visible_mean_attribute", |b| {
        b.iter(|| {
            lambdas
                .iter()
                .map(|&(v, l)| {
                    smith_micro::visible_mean_attribute(attribute, black_box(v), black_box(l)).unwrap_or(0.0)
                })
                .sum::<f32>()
        });
    });
    group.bench_function("corrected_visible_mean_attribute", |b| {
        b.iter(|| {
            lambdas
                .iter()
                .map(|&(v, l)| {
                    smith_micro::corrected_visible_mean_attribute(attribute, black_box(v), black_box(l), &correction)
                        .unwrap_or(0.0)
                })
                .sum::<f32>()
        });
    });
    let cubic = smith_micro::CubicLambdaCorrection::fit_to_table(&correction).expect("the cubic stays in range");
    group.bench_function("cubic_corrected_visible_mean_attribute", |b| {
        b.iter(|| {
            lambdas
                .iter()
                .map(|&(v, l)| {
                    smith_micro::cubic_corrected_visible_mean_attribute(attribute, black_box(v), black_box(l), &cubic)
                        .unwrap_or(0.0)
                })
                .sum::<f32>()
        });
    });
    group.finish();
}

criterion_group!(benches, smith);
criterion_main!(benches);
