//! CPU cost of impostor sampling (§5): grain-local ray from a world ray, the four views,
//! their weights and texture coordinates, per sampling mode, in ns per sample.

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::{Quat, Vec3};
use octahedral_map::{GrainRay, ImpostorSampler, OctahedralViews, SamplingMode, ViewLayout, ViewSelection};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

const RAYS: usize = 4096;

/// World rays from eyes 2–10 R away toward points within 1.2 R of a rotated, scaled grain.
fn rays() -> Vec<(Vec3, Vec3)> {
    let mut rng = SmallRng::seed_from_u64(1);
    let mut unit = || Vec3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
    (0..RAYS)
        .map(|_| {
            let eye = unit().normalize() * 6.0;
            let target = unit() * 0.7;
            (eye, target - eye)
        })
        .collect()
}

fn sampling(c: &mut Criterion) {
    let rays = rays();
    let (centre, scale, rotation) = (Vec3::new(0.1, -0.2, 0.3), 1.2, Quat::from_rotation_y(0.7));
    let mut group = c.benchmark_group("impostor_sampling");
    group.throughput(Throughput::Elements(RAYS as u64));
    let views = OctahedralViews::new(8).unwrap();
    for mode in SamplingMode::ALL {
        for layout in [ViewLayout::Listing1, ViewLayout::Compact] {
            let sampler = ImpostorSampler::new(views, 1.0, 0.6, mode, layout, ViewSelection::PerFragment).unwrap();
            group.bench_function(format!("{mode:?}/{layout:?}/n=8"), |b| {
                b.iter(|| {
                    let mut checksum = 0.0_f32;
                    for &(origin, direction) in &rays {
                        let ray =
                            GrainRay::from_world(black_box(origin), black_box(direction), centre, scale, rotation);
                        let sample = sampler.sample(&ray);
                        checksum += sample.texture_coordinates[0].x + sample.indices.x as f32;
                    }
                    checksum
                });
            });
        }
    }
    group.finish();
}

criterion_group!(benches, sampling);
criterion_main!(benches);
