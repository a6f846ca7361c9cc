//! CPU = GPU differential test of `occlusion-cone`'s WGSL twin (`occlusion_is_occluded`)
//! against `occlusion_cone::is_occluded_by`: 200 000 random configurations concentrated on
//! the occlusion cone's boundary, and every special input (no occluder radius, NaN, ±∞,
//! values outside the domain, the grain at the apex or at the occluder's centre, the eye
//! inside the occluder).
//!
//! Both sides evaluate the same operations in the same order, except the three square
//! roots of the rounding margin (WGSL's `sqrt` is not correctly rounded) and any
//! multiply–add the GPU may fuse. So a decision may differ only where the CPU's own
//! decision changes when the grain's centre and radius are scaled by `1 ± 2⁻²⁰` — a
//! perturbation some sixteen times the ulp, far above those rounding differences; every
//! other decision must be equal. The test counts and prints both.

use glam::{Vec3, Vec4};
use integration_tests::gpu;
use occlusion_cone::{MAX_COORDINATE, Sphere, is_occluded_by};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

/// A unit vector at `angle` from `axis`, uniform around it.
fn around(rng: &mut SmallRng, axis: Vec3, angle: f32) -> Vec3 {
    let e1 = axis.any_orthonormal_vector();
    let e2 = axis.cross(e1);
    let phi = rng.random_range(0.0..std::f32::consts::TAU);
    axis * angle.cos() + (e1 * phi.cos() + e2 * phi.sin()) * angle.sin()
}

fn random_pair(rng: &mut SmallRng) -> (Sphere, Sphere) {
    let r = 10_f32.powf(rng.random_range(-2.0..1.0));
    let big_r = r * rng.random_range(0.5..3.0);
    let tilt = rng.random_range(0.0..1.0);
    let u = around(rng, Vec3::NEG_Z, tilt);
    let distance = r * (1.0 + 10_f32.powf(rng.random_range(-3.0..3.0)));
    let g0 = u * distance;
    let alpha = (r / distance).asin();
    let apex = g0 * (big_r.max(r) / r);
    let beta = alpha * (1.0 + rng.random_range(-0.05..0.05));
    let grain = apex + around(rng, u, beta.max(0.0)) * big_r * 10_f32.powf(rng.random_range(-2.0..3.0));
    (Sphere { centre: g0, radius: r }, Sphere { centre: grain, radius: big_r })
}

fn special_pairs() -> Vec<(Sphere, Sphere)> {
    let occluder = Sphere { centre: Vec3::new(0.0, 0.0, -10.0), radius: 1.0 };
    let grain = |x: f32, y: f32, z: f32, radius: f32| Sphere { centre: Vec3::new(x, y, z), radius };
    let mut pairs = vec![
        (occluder, grain(0.0, 0.0, -30.0, 1.5)),
        (occluder, grain(0.0, 0.0, -15.0, 1.5)),
        (occluder, occluder),
        (occluder, grain(0.0, 0.0, -12.0, 0.2)),
        (Sphere { centre: Vec3::new(0.0, 0.0, -0.5), radius: 1.0 }, grain(0.0, 0.0, -30.0, 1.0)),
        (occluder, grain(0.0, 0.0, -2.0 * MAX_COORDINATE, 1.0)),
        (occluder, grain(0.0, 0.0, -30.0, 0.0)),
        (occluder, grain(0.0, 0.0, -30.0, -1.0)),
    ];
    for special in integration_tests::SPECIAL_F32 {
        pairs.push((occluder, grain(special, 0.0, -30.0, 1.0)));
        pairs.push((occluder, grain(0.0, 0.0, -30.0, special)));
        pairs.push((Sphere { centre: Vec3::new(0.0, special, -10.0), radius: 1.0 }, grain(0.0, 0.0, -30.0, 1.0)));
        pairs.push((Sphere { centre: Vec3::new(0.0, 0.0, -10.0), radius: special }, grain(0.0, 0.0, -30.0, 1.0)));
    }
    pairs
}

/// Whether the CPU's decision changes when the grain is scaled by `1 ± 2⁻²⁰`.
fn near_threshold(occluder: Sphere, grain: Sphere) -> bool {
    let decision = is_occluded_by(occluder, grain);
    [1.0 - 1.0 / 1_048_576.0, 1.0 + 1.0 / 1_048_576.0].iter().any(|&s| {
        is_occluded_by(occluder, Sphere { centre: grain.centre * s, radius: grain.radius * s }) != decision
            || is_occluded_by(occluder, Sphere { centre: grain.centre, radius: grain.radius * s }) != decision
    })
}

#[test]
fn occlusion_decisions_match_the_cpu_reference() {
    let mut rng = SmallRng::seed_from_u64(0x0cc1);
    let mut pairs: Vec<(Sphere, Sphere)> = (0..200_000).map(|_| random_pair(&mut rng)).collect();
    pairs.extend(special_pairs());
    let inputs: Vec<Mat2x4> = pairs.iter().map(|(o, g)| Mat2x4(o.to_vec4(), g.to_vec4())).collect();
    let source = shader_registry::test_kernel_source("occlusion_cone_differential").unwrap_or_else(|e| panic!("{e}"));
    let culled: Vec<u32> = gpu().compute_map(&source, "occlusion_decisions", &[0_u8; 16], &inputs).unwrap();
    assert_eq!(culled.len(), pairs.len());
    let (mut compared, mut near, mut differ_near, mut culled_count) = (0, 0, 0, 0);
    for ((occluder, grain), gpu_culled) in pairs.iter().zip(&culled) {
        let cpu = is_occluded_by(*occluder, *grain);
        culled_count += usize::from(cpu);
        if near_threshold(*occluder, *grain) {
            near += 1;
            differ_near += usize::from(cpu != (*gpu_culled == 1));
            continue;
        }
        compared += 1;
        assert_eq!(cpu, *gpu_culled == 1, "occluder {occluder:?}, grain {grain:?}");
    }
    println!(
        "{} pairs: {compared} compared exactly, {near} within the perturbation of the threshold ({differ_near} of them differ), {culled_count} culled by the CPU",
        pairs.len()
    );
    // Near-threshold cases are rare by construction (the angles spread over ±5 % of α),
    // and both outcomes occur often.
    assert!(compared >= pairs.len() * 99 / 100, "{compared} of {}", pairs.len());
    assert!(culled_count > 10_000 && culled_count < pairs.len() - 10_000, "{culled_count}");
}

/// Two `vec4`s, the kernel's input (`mat2x4<f32>`).
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
struct Mat2x4(Vec4, Vec4);

const _: () = assert!(size_of::<Mat2x4>() == 32);
