//! CPU cost of the octahedral view lookup (Listing 1), in ns per direction: the crate's
//! [`OctahedralViews::sample`] beside a direct transcription of the paper's Listing 1
//! ([`paper_listing_1`], which has no defined result for zero, NaN or infinite inputs).

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::{UVec2, UVec4, Vec2, Vec3};
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

/// Listing 1 of Michel & Boubekeur 2020 (`DirectionToViewIndices`), transcribed line by
/// line from GLSL: `d / dot(1, |d|)`, `uv = ((1, -1) d.y + d.x + 1)(n - 1) / 2`, the four
/// indices from `floor(uv)` and `ceil(uv)`, `n²` added for `d.z > 0`, `α = fract(uv)`
/// (GLSL's `x - floor(x)`). `floor` and `ceil` are `std`'s. Undefined (NaN `uv`, arbitrary
/// indices) for the zero vector and for NaN or infinite components.
fn paper_listing_1(d: Vec3, n: u32) -> (UVec4, Vec2) {
    let d = d / Vec3::ONE.dot(d.abs());
    let uv = (Vec2::new(1.0, -1.0) * d.y + d.x + 1.0) * (n - 1) as f32 / 2.0;
    let floor = Vec2::new(uv.x.floor(), uv.y.floor());
    let fuv = floor.as_uvec2() * UVec2::new(n, 1);
    let cuv = Vec2::new(uv.x.ceil(), uv.y.ceil()).as_uvec2() * UVec2::new(n, 1);
    let mut i = UVec4::new(fuv.x + fuv.y, cuv.x + fuv.y, fuv.x + cuv.y, cuv.x + cuv.y);
    if d.z > 0.0 {
        i += n * n;
    }
    (i, uv - floor)
}

/// Folds every output of a lookup into the checksum, so that none of it is optimised away.
fn fold(checksum: u32, indices: UVec4, alpha: Vec2) -> u32 {
    let bits = indices.x ^ indices.y.rotate_left(8) ^ indices.z.rotate_left(16) ^ indices.w.rotate_left(24);
    checksum.wrapping_add(bits ^ alpha.x.to_bits() ^ alpha.y.to_bits().rotate_left(1))
}

fn view_lookup(c: &mut Criterion) {
    let directions = directions();
    let mut group = c.benchmark_group("octahedral_map");
    group.throughput(Throughput::Elements(DIRECTIONS as u64));
    for n in [8_u32, 12, 64] {
        let views = OctahedralViews::new(n).unwrap();
        // The same indices on these directions (random, none special), so both sides
        // below do the same work.
        for d in &directions {
            assert_eq!(views.sample(*d).indices, paper_listing_1(*d, n).0, "n={n} d={d}");
        }
        group.bench_function(format!("sample/n={n}"), |b| {
            b.iter(|| {
                let mut checksum = 0_u32;
                for d in &directions {
                    let sample = black_box(views).sample(black_box(*d));
                    checksum = fold(checksum, sample.indices, sample.alpha);
                }
                checksum
            });
        });
        group.bench_function(format!("paper/n={n}"), |b| {
            b.iter(|| {
                let mut checksum = 0_u32;
                for d in &directions {
                    let (indices, alpha) = paper_listing_1(black_box(*d), black_box(n));
                    checksum = fold(checksum, indices, alpha);
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
