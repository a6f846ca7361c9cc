//! Shared helpers of the GPU integration tests: the device, and direction sets that
//! cover every special case of the algorithms' inputs.

use std::sync::OnceLock;

use glam::Vec3;
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

/// The process-wide GPU, created once; prints the adapter so that test logs name it.
///
/// # Panics
///
/// When no adapter exists (the message says to install `mesa-vulkan-drivers`): these
/// tests exist to run on a GPU.
pub fn gpu() -> &'static gpu_harness::Gpu {
    static GPU: OnceLock<gpu_harness::Gpu> = OnceLock::new();
    GPU.get_or_init(|| {
        let gpu = gpu_harness::Gpu::new().unwrap_or_else(|e| panic!("{e}"));
        println!("adapter: {}", gpu.describe());
        gpu
    })
}

/// `count` directions uniform on the sphere, from a fixed seed.
pub fn random_unit_directions(count: usize, seed: u64) -> Vec<Vec3> {
    let mut rng = SmallRng::seed_from_u64(seed);
    (0..count)
        .map(|_| {
            let z: f32 = rng.random_range(-1.0..=1.0);
            let phi: f32 = rng.random_range(0.0..std::f32::consts::TAU);
            let r = (1.0 - z * z).max(0.0).sqrt();
            Vec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect()
}

/// Scalars that stress any float input: signed zeros, NaNs, infinities, the smallest normal
/// and subnormal values of both signs, the extremes, and huge magnitudes.
pub const SPECIAL_F32: [f32; 14] = [
    0.0,
    -0.0,
    f32::NAN,
    -f32::NAN,
    f32::INFINITY,
    f32::NEG_INFINITY,
    f32::MIN_POSITIVE,
    -f32::MIN_POSITIVE,
    f32::from_bits(1),
    f32::from_bits(0x8000_0001),
    f32::MAX,
    f32::MIN,
    1e30,
    -3e20,
];

/// Directions that stress a direction → view mapping: zero, signed zeros, NaN, ±∞,
/// subnormals, huge and tiny magnitudes, axes, poles, the equator (z = ±0), diagonals,
/// and unnormalized copies of random directions.
pub fn special_directions() -> Vec<Vec3> {
    let mut values = SPECIAL_F32.to_vec();
    values.extend([1.0, -1.0, 0.5, -0.25, f32::from_bits(0x0040_0000), 1e-30, 3e30]);
    let mut directions = Vec::new();
    for &x in &values {
        for &y in &values {
            for &z in &values {
                directions.push(Vec3::new(x, y, z));
            }
        }
    }
    // The equator, with both signed zeros, at many azimuths.
    for i in 0..720 {
        let (s, c) = (i as f32 * 0.5).to_radians().sin_cos();
        directions.push(Vec3::new(c, s, 0.0));
        directions.push(Vec3::new(c, s, -0.0));
    }
    // Unnormalized directions of every magnitude.
    for (i, d) in random_unit_directions(2_000, 7).into_iter().enumerate() {
        let scale = 10.0_f32.powi(i as i32 % 76 - 38);
        directions.push(d * scale);
    }
    directions
}

/// The workspace README's Rust examples, run as doctests so that they stay true.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

/// The octree the SVO GPU tests trace (`svo_tracer_gpu`, `svo_render_gpu`): a sphere with
/// sine bumps over a floor, coloured by position, 4 levels of 8³ bricks over `[−1, 1]³`.
pub fn svo_bumps_over_floor() -> svo_brick::BrickTree {
    use svo_brick::{BrickSize, BrickTree, BuildOptions, Domain, SdfSurface};
    let bumps = |p: Vec3| 0.02 * (17.0 * p.x).sin() * (13.0 * p.y).sin() * (11.0 * p.z).sin();
    let shape = SdfSurface::new(
        move |p: Vec3| ((p - Vec3::new(0.1, 0.0, 0.0)).length() - 0.45 - bumps(p)).min(p.y + 0.55) / 1.6,
        |p: Vec3| [0.5 + 0.4 * p.z, 0.6, 0.3 + 0.3 * p.x],
        1e-4,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let options = BuildOptions { brick_size: BrickSize::Eight, levels: 4, ..BuildOptions::default() };
    BrickTree::build(&shape, Domain { origin: Vec3::splat(-1.0), size: 2.0 }, options).unwrap_or_else(|e| panic!("{e}"))
}
