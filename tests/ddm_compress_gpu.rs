//! CPU = GPU differential test of `shaders/ddm_compress.wgsl` (the compressed distance
//! map's access function) against `ddm-compress`: every voxel of several maps, bit for bit
//! (75 840 queries, counted), indexed with divisions and with shifts, from `f32` and binary16
//! atlases.

use ddm_compress::CompressedMapUniforms;
use ddm_compress::{CompressedMap, DirectionCones, DistanceMapSettings, MapKind, Triangle, compute_distance_maps};
use glam::{UVec3, UVec4, Vec4};
use integration_tests::gpu;
use mesostructure::HeightField;

fn kernel_source() -> String {
    shader_registry::test_kernel_source("ddm_compress_differential").unwrap_or_else(|e| panic!("{e}"))
}

/// A wavy height-field floor over an `n × n` tile.
fn floor(n: u32, height: f32) -> Vec<Triangle> {
    HeightField::from_fn(n, n, |x, y| height + 0.8 * ((x * 0.9).sin() + (y * 0.7).cos())).triangles()
}

/// How the kernel reads the map: its indexing and its atlas's storage.
#[derive(Clone, Copy, Debug)]
struct Reading {
    /// With shifts (`ddm_*_index_shifted`, power-of-two blocks) instead of divisions.
    shifted: bool,
    /// The atlas as binary16 pairs rounded down, against the CPU's `with_f16_atlas`.
    f16: bool,
}

fn check(map: &CompressedMap, reading: Reading) -> usize {
    let mut words: Vec<u32> = map.grid().to_vec();
    let atlas_base = words.len() as u32;
    if reading.f16 {
        words.extend(ddm_compress::pack_f16_pairs_at_most(map.atlas()));
    } else {
        words.extend(map.atlas().iter().map(|v| v.to_bits()));
    }
    words.resize(words.len().next_multiple_of(4), 0);
    let query_offset = 1 + words.len() / 4;
    let shift = if reading.shifted { map.block_shift().expect("a power-of-two block") + 1 } else { 0 };
    let mut input = vec![UVec4::new(query_offset as u32, shift, u32::from(reading.f16), 0)];
    input.extend(words.chunks(4).map(|c| UVec4::new(c[0], c[1], c[2], c[3])));
    let dims = map.dims();
    let mut queries = Vec::new();
    for z in 0..dims.z + 1 {
        for y in 0..dims.y + 1 {
            for x in 0..dims.x + 1 {
                queries.push(UVec3::new(x, y, z));
            }
        }
    }
    queries.extend([UVec3::new(u32::MAX, 0, 0), UVec3::splat(1 << 31)]);
    input.extend(queries.iter().map(|q| q.extend(0)));
    let uniforms = CompressedMapUniforms::new(map, atlas_base);
    let results: Vec<Vec4> =
        gpu().compute_map(&kernel_source(), "access", bytemuck::bytes_of(&uniforms), &input).unwrap();
    let reference = if reading.f16 { map.with_f16_atlas() } else { map.clone() };
    for (query, result) in queries.iter().zip(&results[query_offset..]) {
        match reference.access(*query) {
            Some(distance) => {
                assert_eq!(result.z, 1.0, "{query}: GPU says outside the map");
                assert_eq!(
                    result.x.to_bits(),
                    distance.to_bits(),
                    "{query} ({reading:?}): CPU {distance}, GPU {}",
                    result.x
                );
            }
            None => assert_eq!(result.z, 0.0, "{query}: GPU says inside the map"),
        }
    }
    queries.len()
}

#[test]
fn access_matches_the_cpu_reference() {
    let dims = UVec3::new(12, 12, 6);
    let settings = DistanceMapSettings { tolerance: 0.1, periodic_xy: true };
    let cones = DirectionCones::downward(4, 1).unwrap();
    let maps = compute_distance_maps(dims, &floor(12, 2.0), MapKind::Directional(cones), settings).unwrap();
    let (mut checked, mut readings) = (0, 0);
    for block in [1, 2, 3, 4, 5] {
        for values in &maps.values {
            let map = CompressedMap::compress(values, &maps.surface, dims, block).unwrap();
            for shifted in [false, true] {
                for f16 in [false, true] {
                    if shifted && map.block_shift().is_none() {
                        continue;
                    }
                    checked += check(&map, Reading { shifted, f16 });
                    readings += 1;
                }
            }
        }
    }
    println!(
        "{checked} voxel queries (inside and outside, blocks 1-5, 4 cones, divisions and shifts, f32 and f16 \
         atlases): GPU access equals CPU bit for bit"
    );
    // Exhaustive: every voxel of the 12 × 12 × 6 maps and the first ones past each face
    // (13 × 13 × 7), and two far outside, for 4 cones and 5 block sizes, each read with
    // divisions and (the 3 power-of-two blocks) shifts, from an f32 and an f16 atlas.
    assert_eq!(readings, 4 * (5 + 3) * 2);
    assert_eq!(checked, readings * (13 * 13 * 7 + 2));
}
