//! CPU = GPU differential tests of `shaders/abuffer_mask.wgsl` against the
//! `abuffer-mask` crate: table indices, popcounts and coverages bit for bit, for
//! N = 32, 64, 128 over 100 000+ queries including special values and cell boundaries.

use abuffer_mask::{HalfPlane, MaskTable, MaskTableUniforms, TableLayout};
use glam::{UVec4, Vec3, Vec4};
use integration_tests::{SPECIAL_F32, gpu};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

const RANDOM_QUERIES: usize = 100_000;

fn kernel_source() -> String {
    shader_registry::test_kernel_source("abuffer_mask_differential").unwrap_or_else(|e| panic!("{e}"))
}

/// The kernel's uniforms: the table's, then the index of the first query.
fn uniforms(table: MaskTableUniforms, query_offset: u32) -> Vec<u8> {
    let mut bytes = bytemuck::bytes_of(&table).to_vec();
    bytes.extend(bytemuck::bytes_of(&[query_offset, 0, 0, 0]));
    bytes
}

/// `θ` or `v` values that stress the lookup: specials, and every cell boundary of the
/// layout with its `f32` neighbours.
fn special_parameters(layout: TableLayout) -> Vec<f32> {
    let mut values = SPECIAL_F32.to_vec();
    values.extend([
        std::f32::consts::PI,
        -std::f32::consts::PI,
        std::f32::consts::TAU,
        std::f32::consts::SQRT_2,
        -std::f32::consts::SQRT_2,
        2.0,
        -2.0,
    ]);
    for scale in [layout.theta_scale(), layout.v_scale()] {
        for k in -300..300 {
            let boundary = k as f32 / scale;
            values.extend([boundary, boundary.next_up(), boundary.next_down()]);
        }
    }
    values
}

fn queries(layout: TableLayout, seed: u64) -> Vec<[f32; 4]> {
    let special = special_parameters(layout);
    let mut rng = SmallRng::seed_from_u64(seed);
    let mut queries: Vec<[f32; 4]> = Vec::new();
    for (i, &a) in special.iter().enumerate() {
        let b = special[(i * 7 + 3) % special.len()];
        queries.push([a, b, b, a]);
        queries.push([rng.random_range(-4.0..4.0), a, a, rng.random_range(-2.0..2.0)]);
    }
    for _ in 0..RANDOM_QUERIES {
        let mut parameter = |range: f32| rng.random_range(-range..range);
        queries.push([parameter(13.0), parameter(1.6), parameter(13.0), parameter(1.6)]);
    }
    queries
}

fn check_masks<const WORDS: usize>(source: &str) {
    let table = MaskTable::<WORDS>::paper().unwrap();
    let layout = table.layout();
    let mut words = table.words().to_vec();
    words.resize(words.len().next_multiple_of(4), 0);
    let mut input: Vec<UVec4> = words.chunks(4).map(|c| UVec4::new(c[0], c[1], c[2], c[3])).collect();
    let query_offset = input.len();
    let queries = queries(layout, WORDS as u64);
    input.extend(queries.iter().map(|q| UVec4::from_array(q.map(f32::to_bits))));
    let bytes = uniforms(table.uniforms(), query_offset as u32);
    let gpu_counts: Vec<UVec4> = gpu().compute_map(source, "mask_queries", &bytes, &input).unwrap();
    let gpu_coverages: Vec<UVec4> = gpu().compute_map(source, "mask_coverages", &bytes, &input).unwrap();
    let mut mismatches = Vec::new();
    for ((q, counts), coverages) in queries.iter().zip(&gpu_counts[query_offset..]).zip(&gpu_coverages[query_offset..])
    {
        let (cell_a, cell_b) = (layout.cell_index(q[0], q[1]), layout.cell_index(q[2], q[3]));
        let (a, b) = (table.cell_mask(cell_a), table.cell_mask(cell_b));
        let cpu_counts = UVec4::new(cell_a, cell_b, a.union(b).popcount(), a.difference(b).popcount());
        let cpu_coverages = UVec4::new(
            a.union(b).coverage().to_bits(),
            a.difference(b).coverage().to_bits(),
            a.intersection(b).coverage().to_bits(),
            a.intersection(b).popcount(),
        );
        if cpu_counts != *counts || cpu_coverages != *coverages {
            mismatches.push((*q, cpu_counts, *counts, cpu_coverages, *coverages));
        }
    }
    assert!(
        mismatches.is_empty(),
        "N={}: {} of {} queries differ, e.g. {:?}",
        32 * WORDS,
        mismatches.len(),
        queries.len(),
        &mismatches[..mismatches.len().min(5)]
    );
    println!(
        "N={:>3}: {} queries: cell indices, popcounts (∪, \\, ∩) and coverages bit-identical",
        32 * WORDS,
        queries.len()
    );
}

#[test]
fn mask_lookups_and_set_operations_match_the_cpu_bit_for_bit() {
    let source = kernel_source();
    check_masks::<1>(&source);
    check_masks::<2>(&source);
    check_masks::<4>(&source);
}

fn cone_elements() -> Vec<[Vec4; 2]> {
    let mut rng = SmallRng::seed_from_u64(11);
    let mut elements = Vec::new();
    let specials =
        [0.0_f32, -0.0, 1.0, -1.0, 0.5, f32::from_bits(5), f32::NAN, f32::INFINITY, f32::NEG_INFINITY, 1e-20];
    for &nx in &specials {
        for &ny in &specials {
            for &nz in &specials[..6] {
                for (h, r, l) in [(0.1, 1.0, 0.5), (-0.3, 0.5, 0.0), (0.0, 0.0, 1.0), (0.2, 1.0, -1.0), (2.0, 0.1, 0.1)]
                {
                    elements.push([Vec4::new(nx, ny, nz, h), Vec4::new(r, l, 0.0, 0.0)]);
                }
            }
        }
    }
    for i in 0..RANDOM_QUERIES {
        let z: f32 = rng.random_range(-1.0..=1.0);
        let phi: f32 = rng.random_range(0.0..std::f32::consts::TAU);
        let length: f32 = if i % 3 == 0 { rng.random_range(0.05..1.0) } else { 1.0 };
        let s = (1.0 - z * z).max(0.0).sqrt() * length;
        let normal = Vec3::new(s * phi.cos(), s * phi.sin(), z * length);
        let (h, r, l) = (rng.random_range(-1.0..1.0), rng.random_range(0.05..2.0), rng.random_range(0.0..0.5));
        elements.push([normal.extend(h), Vec4::new(r, l, 0.0, 0.0)]);
    }
    elements
}

#[test]
fn half_planes_match_the_cpu_within_tolerance_and_indices_match_off_boundaries() {
    let source = kernel_source();
    let table = MaskTable::<4>::paper().unwrap();
    let layout = table.layout();
    let elements = cone_elements();
    let bytes = uniforms(table.uniforms(), 0);
    let results: Vec<UVec4> = gpu().compute_map(&source, "half_planes", &bytes, &elements).unwrap();
    let (mut worst_theta, mut worst_v, mut equal, mut near_boundary_mismatches) = (0.0_f32, 0.0_f32, 0, 0);
    for (element, result) in elements.iter().zip(&results) {
        let [a, b] = *element;
        let cpu = HalfPlane::from_cone_element(a.w, a.truncate(), b.x, b.y);
        let (theta, v) = (f32::from_bits(result.x), f32::from_bits(result.y));
        worst_theta = worst_theta.max((cpu.theta - theta).abs());
        worst_v = worst_v.max((cpu.v - v).abs());
        if layout.cell_index(cpu.theta, cpu.v) == result.z {
            equal += 1;
            continue;
        }
        // Allowed only when the CPU value lies within 1e-3 of a cell of a boundary.
        let (t, s) = (cpu.theta * layout.theta_scale(), cpu.v * layout.v_scale());
        let near = (t - t.round()).abs() < 1e-3 || (s - s.round()).abs() < 1e-3;
        assert!(
            near,
            "{element:?}: CPU {cpu:?} cell {} GPU ({theta}, {v}) cell {}",
            layout.cell_index(cpu.theta, cpu.v),
            result.z
        );
        near_boundary_mismatches += 1;
    }
    assert!(worst_theta <= 1e-5 && worst_v <= 1e-5, "θ differs by {worst_theta}, v by {worst_v}");
    println!(
        "half planes: {} cone elements, max |Δθ| {worst_theta:e}, max |Δv| {worst_v:e}; cell indices equal for {equal}, \
         {near_boundary_mismatches} differ within 1e-3 cell of a boundary",
        elements.len()
    );
}
