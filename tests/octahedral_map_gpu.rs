//! CPU = GPU differential tests of `shaders/octahedral_map.wgsl` against the
//! `octahedral-map` crate.

use glam::{Vec3, Vec4};
use integration_tests::{gpu, random_unit_directions, special_directions};
use octahedral_map::{MAX_SUBDIVISIONS, OctahedralViews, ViewSample};
use shader_registry::kernel_io::octahedral_map::OctahedralUniforms;

const SUBDIVISIONS: [u32; 8] = [1, 2, 3, 8, 10, 12, 33, 256];

fn kernel_source() -> String {
    shader_registry::test_kernel_source("octahedral_map_differential").unwrap_or_else(|e| panic!("{e}"))
}

fn test_directions(n: u32) -> Vec<Vec3> {
    let views = OctahedralViews::new(n).unwrap();
    let mut directions = special_directions();
    // Exactly the stored view directions, and points on cell edges between them.
    for index in 0..views.view_count().min(20_000) {
        let d = views.view_direction(index).unwrap();
        directions.push(d);
        let next = views.view_direction((index + 1) % views.view_count()).unwrap();
        directions.push((d + next) * 0.5);
    }
    directions.extend(random_unit_directions(100_000, u64::from(n)));
    directions
}

fn uniforms(n: u32) -> Vec<u8> {
    let uniforms = OctahedralUniforms::new(OctahedralViews::new(n).unwrap());
    bytemuck::bytes_of(&uniforms).to_vec()
}

#[test]
fn view_samples_match_the_cpu_reference() {
    let source = kernel_source();
    for n in SUBDIVISIONS {
        let views = OctahedralViews::new(n).unwrap();
        let directions = test_directions(n);
        assert!(directions.len() >= 100_000);
        let inputs: Vec<Vec4> = directions.iter().map(|d| d.extend(0.0)).collect();
        let gpu_samples: Vec<ViewSample> = gpu().compute_map(&source, "view_samples", &uniforms(n), &inputs).unwrap();
        let gpu_weights: Vec<[f32; 4]> = gpu().compute_map(&source, "view_weights", &uniforms(n), &inputs).unwrap();
        let mut index_mismatches = Vec::new();
        let mut worst_weight_error = 0.0_f32;
        for ((d, gpu_sample), gpu_weight) in directions.iter().zip(&gpu_samples).zip(&gpu_weights) {
            let cpu = views.sample(*d);
            if cpu.indices != gpu_sample.indices {
                index_mismatches.push((*d, cpu.indices, gpu_sample.indices));
            }
            let alpha_error = (cpu.alpha - gpu_sample.alpha).abs().max_element();
            let weight_error =
                cpu.weights().iter().zip(gpu_weight).map(|(a, b)| (a - b).abs()).fold(alpha_error, f32::max);
            worst_weight_error = worst_weight_error.max(weight_error);
        }
        assert!(
            index_mismatches.is_empty(),
            "n={n}: {} of {} directions get other indices on the GPU, e.g. {:?}",
            index_mismatches.len(),
            directions.len(),
            &index_mismatches[..index_mismatches.len().min(5)]
        );
        // u = (2(x⁺ + y⁺) + |z|) / (2 |d|₁) · (n − 1): the sums are exact or within an ulp
        // (≤ 3 on either side, fused or not), WGSL's division within 2.5 ulp, the scaling
        // 1 ulp: ≤ 13 ulp of a value below 1 on both sides together, times `n − 1` into
        // `u`, hence `α = u − ⌊u⌋`; the weights' products of `1 − α` add 3 ulp of 1.
        // (Lavapipe rounds the division correctly: bit-identical.)
        let weight_bound = (13.0 * (n.max(2) - 1) as f32 + 3.0) * f32::EPSILON;
        assert!(worst_weight_error <= weight_bound, "n={n}: weights differ by {worst_weight_error} > {weight_bound:e}");
        println!("n={n}: {} directions, indices equal, max weight difference {worst_weight_error:e}", directions.len());
    }
}

#[test]
fn view_directions_match_the_cpu_reference() {
    let source = kernel_source();
    for n in SUBDIVISIONS.into_iter().chain([MAX_SUBDIVISIONS]) {
        let views = OctahedralViews::new(n).unwrap();
        let count = views.view_count();
        let mut indices: Vec<u32> = (0..count.min(50_000)).collect();
        indices.extend((0..100_000_u32).map(|i| i.wrapping_mul(2_654_435_761) % count));
        indices.extend([count - 1, count, count + 1, u32::MAX]);
        assert!(indices.len() >= 100_000);
        let gpu_directions: Vec<Vec4> = gpu().compute_map(&source, "view_directions", &uniforms(n), &indices).unwrap();
        for (index, gpu_direction) in indices.iter().zip(&gpu_directions) {
            let cpu = views.view_direction(*index).unwrap_or(Vec3::ZERO);
            let error = (cpu - gpu_direction.truncate()).abs().max_element();
            // `normalize` of an integer lattice point: the squared length within 1 ulp,
            // `inverseSqrt` 2 ulp (WGSL), the product 1 ulp: ≤ 4 ulp of a unit component
            // on either side, 8 ε < 1e-6 together.
            assert!(error <= 1e-6, "n={n} view {index}: CPU {cpu} GPU {gpu_direction}");
        }
    }
}
