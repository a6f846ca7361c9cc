//! CPU cost of Algorithm 1's mask step (lines 8, 10, 11): the (θ, v) table lookup, then
//! difference + popcount against the accumulated mask, then union; in ns per cone element.

use std::hint::black_box;

use abuffer_mask::{ConeAccumulator, Mask, MaskTable};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

const ELEMENTS: usize = 4096;

fn half_planes() -> Vec<(f32, f32)> {
    let mut rng = SmallRng::seed_from_u64(1);
    (0..ELEMENTS).map(|_| (rng.random_range(-3.2..3.2), rng.random_range(-1.5..1.5))).collect()
}

fn bench_words<const WORDS: usize>(c: &mut Criterion, planes: &[(f32, f32)]) {
    let table = MaskTable::<WORDS>::paper().expect("1 ≤ WORDS ≤ 4");
    let mut group = c.benchmark_group("abuffer_mask");
    group.throughput(Throughput::Elements(ELEMENTS as u64));
    group.bench_function(format!("lookup+union+popcount/N={}", 32 * WORDS), |b| {
        b.iter(|| {
            // A cone of 8 elements per pixel: reset the accumulator every 8 lookups.
            let mut checksum = 0.0_f32;
            for pixel in planes.chunks(8) {
                let mut cone = ConeAccumulator::<WORDS>::new();
                for &(theta, v) in pixel {
                    cone.add(table.lookup(black_box(theta), black_box(v)), 1.0);
                }
                checksum += cone.radiance;
            }
            checksum
        });
    });
    group.bench_function(format!("lookup/N={}", 32 * WORDS), |b| {
        b.iter(|| {
            let mut union = Mask::<WORDS>::EMPTY;
            for &(theta, v) in planes {
                union = union.union(table.lookup(black_box(theta), black_box(v)));
            }
            union
        });
    });
    group.finish();
}

fn mask_step(c: &mut Criterion) {
    let planes = half_planes();
    bench_words::<1>(c, &planes);
    bench_words::<2>(c, &planes);
    bench_words::<4>(c, &planes);
}

criterion_group!(benches, mask_step);
criterion_main!(benches);
