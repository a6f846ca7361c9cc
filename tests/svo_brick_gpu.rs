//! CPU = GPU differential test of `svo-brick`'s WGSL twin: quadrilinear and nearest
//! samples of packed octrees, bit for bit (0 ulp), over 100 000+ queries (counted) per tree
//! and layout, including brick borders, level boundaries, empty and full nodes, the domain's
//! boundary and special values; and the finished (world-unit, normalised) samples within
//! the normalisation's rounding bound. The brick pool is split over two or three of the twin's four
//! brick bindings, as for a tree larger than the adapter's binding limit.

use glam::{UVec4, Vec3, Vec4};
use integration_tests::{SPECIAL_F32, gpu};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use svo_brick::{BrickSize, BrickTree, BuildOptions, Domain, PackedTree, RawVoxel, SdfSurface, VoxelLayout};

const RANDOM_QUERIES: usize = 90_000;

fn kernel_source() -> String {
    shader_registry::test_kernel_source("svo_brick_differential").unwrap_or_else(|e| panic!("{e}"))
}

/// A sphere coloured by height, displaced by a few sines so that the coarse levels carry
/// height and slope variances and colour correlations.
fn tree(brick_size: BrickSize, levels: u32) -> BrickTree {
    let bumps = |p: Vec3| 0.02 * (17.0 * p.x).sin() * (13.0 * p.y).sin() * (11.0 * p.z).sin();
    let surface = SdfSurface::new(
        move |p: Vec3| (p.length() - 0.6 - bumps(p)) / 1.5,
        |p: Vec3| [0.5 + 0.4 * (p.length() - 0.6) * 25.0, 0.3 + 0.2 * p.z, 0.7],
        1e-4,
    )
    .unwrap();
    let options = BuildOptions { brick_size, levels, ..BuildOptions::default() };
    BrickTree::build(&surface, Domain { origin: Vec3::new(-1.0, -0.9, -1.1), size: 2.1 }, options).unwrap()
}

/// Queries `(p, lod)` in world units.
fn queries(tree: &BrickTree, seed: u64) -> Vec<Vec4> {
    let mut rng = SmallRng::seed_from_u64(seed);
    let levels = tree.levels() as f32;
    let size = tree.voxel_size() * tree.resolution() as f32;
    let mut out = Vec::new();
    let lods = |rng: &mut SmallRng| -> f32 {
        match rng.random_range(0..4) {
            0 => rng.random_range(0..tree.levels()) as f32,
            1 => rng.random_range(0..tree.levels()) as f32 + f32::EPSILON * [-1.0, 1.0][rng.random_range(0..2)],
            2 => rng.random_range(0..tree.levels()) as f32 + rng.random_range(0..2048) as f32 / 2048.0,
            _ => rng.random_range(-0.5..levels),
        }
    };
    for _ in 0..RANDOM_QUERIES {
        let p = tree.origin() + Vec3::new(rng.random(), rng.random(), rng.random()) * size;
        out.push(p.extend(lods(&mut rng)));
    }
    // Brick borders: the faces of every node, on them and one f32 step to either side.
    let n = tree.brick_size().side();
    for (&level, &origin) in tree.brick_levels().iter().zip(tree.brick_origins()) {
        for _ in 0..8 {
            let axis = rng.random_range(0..3);
            let mut q = origin.as_vec3() + Vec3::new(rng.random(), rng.random(), rng.random()) * (n << level) as f32;
            q[axis] = (origin[axis] + rng.random_range(0..2) * (n << level)) as f32;
            let mut p = tree.world(q);
            p[axis] = [p[axis], p[axis].next_up(), p[axis].next_down()][rng.random_range(0..3)];
            out.push(p.extend(lods(&mut rng)));
        }
    }
    // Voxel centres and corners of every level (fractions exactly 0 and ½).
    for _ in 0..10_000 {
        let level = rng.random_range(0..tree.levels());
        let s = (1u32 << level) as f32;
        let cells = (tree.resolution() >> level) as f32;
        let v = Vec3::new(rng.random(), rng.random(), rng.random()) * cells;
        let q = (v.floor() + [0.0, 0.5][rng.random_range(0..2)]) * s;
        out.push(tree.world(q).extend(level as f32));
    }
    // The domain's boundary and special values.
    let corner = tree.origin();
    for &x in &SPECIAL_F32 {
        for &lod in &[0.0, 1.5, f32::NAN, f32::INFINITY, f32::NEG_INFINITY, -3.0, 1e9] {
            out.push(Vec4::new(x, 0.1, 0.2, lod));
            out.push(Vec4::new(0.3, x, -0.1, lod));
            out.push(corner.extend(lod));
            out.push((corner + size).extend(lod));
            out.push(Vec4::new(corner.x, (corner.y + size).next_down(), 0.0, lod));
        }
    }
    out
}

fn cpu_words(sample: Option<RawVoxel>) -> [UVec4; 4] {
    let v = sample.unwrap_or_default();
    [
        UVec4::new(
            v.distance.to_bits(),
            v.distance_variance.to_bits(),
            v.slope_variance.to_bits(),
            u32::from(sample.is_some()),
        ),
        v.normal
            .to_array()
            .map(f32::to_bits)
            .into_iter()
            .chain([0])
            .collect::<Vec<_>>()
            .try_into()
            .map(UVec4::from_array)
            .unwrap(),
        UVec4::new(v.attribute[0].to_bits(), v.attribute[1].to_bits(), v.attribute[2].to_bits(), 0),
        UVec4::new(v.correlation[0].to_bits(), v.correlation[1].to_bits(), v.correlation[2].to_bits(), 0),
    ]
}

/// The GPU returns zeros for the fields of a point outside the domain.
fn masked(words: [UVec4; 4]) -> [UVec4; 4] {
    if words[0].w == 0 { [UVec4::ZERO; 4] } else { words }
}

#[test]
fn packed_octrees_sample_bit_identically_on_cpu_and_gpu() {
    let source = kernel_source();
    for (brick_size, levels) in [(BrickSize::Four, 4), (BrickSize::Eight, 3)] {
        let tree = tree(brick_size, levels);
        let queries = queries(&tree, u64::from(levels));
        assert!(queries.len() >= 100_000, "{} queries", queries.len());
        for layout in VoxelLayout::ALL {
            // The brick pool split over two or three bindings, as a tree past the adapter's
            // binding limit would be (the CPU reads one buffer).
            let brick_words = (brick_size.stored_voxels() * layout.words()) as u64;
            let words = PackedTree::new(&tree, layout).words().len() as u64;
            let limit = 4 * words.div_ceil(3).div_ceil(brick_words) * brick_words;
            let packed = PackedTree::with_binding_limit(&tree, layout, limit).unwrap();
            let bindings = packed.brick_bindings();
            assert!(bindings.iter().filter(|b| b.len() > 1).count() >= 2);
            let uniforms = bytemuck::bytes_of(&packed.uniforms()).to_vec();
            let mut storage: Vec<&[u8]> = vec![bytemuck::cast_slice(packed.nodes())];
            storage.extend(bindings.iter().map(|b| bytemuck::cast_slice::<u32, u8>(b)));
            let uploaded = gpu().upload_storage(&storage).unwrap();
            let run = |entry: &str| -> Vec<[UVec4; 4]> {
                gpu().compute_map_with_uploaded_storage(&source, entry, &uniforms, &queries, &uploaded).unwrap().0
            };
            let (quadrilinear, nearest, finished) = (run("quadrilinear"), run("nearest"), run("finished"));
            let (mut mismatches, mut inside, mut normal_error) = (Vec::new(), 0, 0.0_f32);
            for (k, q) in queries.iter().enumerate() {
                let (p, lod) = (q.truncate(), q.w);
                let cpu = masked(cpu_words(packed.sample_raw(p, lod)));
                let nearest_raw = masked(cpu_words(packed.sample_nearest_raw(p, lod)));
                if cpu != quadrilinear[k] || nearest_raw != nearest[k] {
                    mismatches.push((*q, cpu, quadrilinear[k], nearest_raw, nearest[k]));
                }
                if let Some(sample) = packed.sample(p, lod) {
                    inside += 1;
                    let gpu = finished[k];
                    let g = |w: u32| f32::from_bits(w);
                    assert_eq!(gpu[0].x, sample.distance.to_bits());
                    assert_eq!(gpu[0].y, sample.distance_variance.to_bits());
                    assert_eq!([gpu[2].x, gpu[2].y, gpu[2].z], sample.attribute.map(f32::to_bits));
                    assert_eq!([gpu[3].x, gpu[3].y, gpu[3].z], sample.correlation.map(f32::to_bits));
                    let n = Vec3::new(g(gpu[1].x), g(gpu[1].y), g(gpu[1].z));
                    let error = (n - sample.normal).abs().max_element();
                    // The normalisations differ by ≤ 10 f32 roundings of a unit vector: the
                    // dot product (fused or not), 1/√ (CPU) against inverseSqrt (2 ulp).
                    assert!(error <= 10.0 * f32::EPSILON, "{q}: {n} vs {}", sample.normal);
                    normal_error = normal_error.max(error);
                }
            }
            assert!(
                mismatches.is_empty(),
                "{brick_size:?} {layout:?}: {} of {} queries differ, e.g. {:?}",
                mismatches.len(),
                queries.len(),
                &mismatches[..mismatches.len().min(3)]
            );
            assert!(inside > 90_000, "{inside}");
            println!(
                "{brick_size:?} {layout:?}: {} queries ({inside} inside the domain), quadrilinear and nearest bit-identical; finished normals within {normal_error:e}",
                queries.len()
            );
        }
    }
}
