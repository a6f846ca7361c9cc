//! Properties of built octrees: brick placement, the finest level's exactness, the
//! 1-Lipschitz `h̄` of every level, seamless brick borders, the negative control of the
//! volume variance, and sampling at voxel centres.

use glam::{IVec3, UVec3, Vec3};
use svo_brick::{
    BrickSize, BrickTree, BuildError, BuildOptions, Domain, HeightVariance, OctreeNode, PackedTree, SdfSurface,
    SurfaceSource, VoxelLayout,
};

const RADIUS: f32 = 0.61;

/// A sphere of radius 0.61 in the unit cube around the origin, coloured by height.
fn sphere() -> impl SurfaceSource {
    SdfSurface::new(|p: Vec3| p.length() - RADIUS, |p: Vec3| [0.5 + 0.5 * p.z / RADIUS, 0.2, 0.8], 1e-4).unwrap()
}

fn domain() -> Domain {
    Domain { origin: Vec3::splat(-1.0), size: 2.0 }
}

fn options(brick_size: BrickSize, levels: u32) -> BuildOptions {
    BuildOptions { brick_size, levels, ..BuildOptions::default() }
}

#[test]
fn bricks_cover_the_surface_and_nothing_far_from_it() {
    let tree = BrickTree::build(&sphere(), domain(), options(BrickSize::Eight, 4)).unwrap();
    assert_eq!(tree.resolution(), 64);
    let n = tree.brick_size().side();
    let mut per_level = [0_usize; 4];
    for (b, (&level, &origin)) in tree.brick_levels().iter().zip(tree.brick_origins()).enumerate() {
        per_level[level as usize] += 1;
        let size = (n << level) as f32 * tree.voxel_size();
        let centre = tree.world(origin.as_vec3()) + 0.5 * size;
        let d = centre.length() - RADIUS;
        // The placement rule, in world units.
        assert!(d.abs() <= 0.5 * 3_f32.sqrt() * size + 2.0 * size / n as f32 + 1e-6, "brick {b} at {centre}");
    }
    println!("bricks per level (finest first): {per_level:?}, nodes {}", tree.nodes().len());
    assert_eq!(per_level[3], 1);
    // Every finest voxel crossed by the sphere lies in a finest brick: sample points on it.
    let packed = PackedTree::new(&tree, VoxelLayout::Paper20);
    let mut checked = 0;
    for k in 0..2000 {
        let (a, b) = (k as f32 * 0.61803, k as f32 * 0.1234 + 0.5);
        let dir = Vec3::new(a.cos() * b.sin(), a.sin() * b.sin(), b.cos());
        let raw = packed.sample_raw(dir * RADIUS, 0.0).unwrap();
        assert!(raw.distance.abs() < 0.05, "{dir}: {raw:?}");
        checked += 1;
    }
    assert_eq!(checked, 2000);
    assert!(tree.nodes().iter().any(|n| n.brick == OctreeNode::FULL));
    assert!(tree.nodes().iter().any(|n| n.brick == OctreeNode::EMPTY));
}

#[test]
fn the_finest_level_is_the_source_itself() {
    let source = sphere();
    let tree = BrickTree::build(&source, domain(), options(BrickSize::Four, 4)).unwrap();
    let mut compared = 0;
    for (b, (&level, &origin)) in tree.brick_levels().iter().zip(tree.brick_origins()).enumerate() {
        if level != 0 {
            continue;
        }
        let side = tree.brick_size().stored_side();
        for (i, voxel) in tree.brick_voxels(b).iter().enumerate() {
            let index = UVec3::new(i as u32 % side, i as u32 / side % side, i as u32 / (side * side));
            let centre = tree.world(origin.as_vec3() + index.as_vec3());
            assert_eq!(voxel.distance, source.distance(centre) / tree.voxel_size());
            assert_eq!(voxel.normal, source.gradient(centre));
            assert_eq!((voxel.distance_variance, voxel.slope_variance, voxel.correlation), (0.0, 0.0, [0.0; 3]));
            compared += 1;
        }
    }
    assert!(compared > 10_000, "{compared}");
}

#[test]
fn every_level_stays_one_lipschitz() {
    let tree = BrickTree::build(&sphere(), domain(), options(BrickSize::Eight, 4)).unwrap();
    let side = tree.brick_size().stored_side() as usize;
    let mut pairs = 0;
    for b in 0..tree.brick_count() {
        let level = tree.brick_levels()[b];
        let scale = (1u32 << level) as f32;
        let voxels = tree.brick_voxels(b);
        let at = |x: usize, y: usize, z: usize| voxels[(z * side + y) * side + x].distance;
        for z in 0..side {
            for y in 0..side {
                for x in 0..side - 1 {
                    for (a, c) in
                        [(at(x, y, z), at(x + 1, y, z)), (at(y, x, z), at(y, x + 1, z)), (at(y, z, x), at(y, z, x + 1))]
                    {
                        // Neighbours S_L apart differ by at most S_L, up to f32 rounding of the means.
                        assert!((a - c).abs() <= scale * (1.0 + 1e-5), "level {level}: {a} vs {c}");
                        pairs += 1;
                    }
                }
            }
        }
    }
    assert!(pairs > 100_000, "{pairs}");
}

#[test]
fn neighbouring_bricks_share_their_faces_bit_for_bit_and_interpolate_continuously() {
    let tree = BrickTree::build(&sphere(), domain(), options(BrickSize::Four, 4)).unwrap();
    let n = tree.brick_size().side();
    let side = tree.brick_size().stored_side() as usize;
    let bricks: std::collections::HashMap<(u32, UVec3), usize> =
        (0..tree.brick_count()).map(|b| ((tree.brick_levels()[b], tree.brick_origins()[b]), b)).collect();
    let (mut faces, mut voxels) = (0, 0);
    for (&(level, origin), &brick) in &bricks {
        for axis in 0..3 {
            let mut step = UVec3::ZERO;
            step[axis] = n << level;
            let Some(&neighbour) = bricks.get(&(level, origin + step)) else { continue };
            let (a, b) = (tree.brick_voxels(brick), tree.brick_voxels(neighbour));
            for j in 0..side {
                for i in 0..side {
                    let index = |k: usize| {
                        let mut v = [i, j, j];
                        v[axis] = k;
                        v[(axis + 1) % 3] = i;
                        v[(axis + 2) % 3] = j;
                        (v[2] * side + v[1]) * side + v[0]
                    };
                    assert_eq!(
                        format!("{:?}", a[index(side - 1)]),
                        format!("{:?}", b[index(0)]),
                        "level {level} at {origin}"
                    );
                    voxels += 1;
                }
            }
            faces += 1;
        }
    }
    assert!(faces > 100, "{faces} shared faces");
    println!("{faces} shared faces, {voxels} voxels equal in both bricks");
    // Continuity across faces: one f32 step to either side of a face, the samples differ
    // by the field's change over that step (≤ √3 per voxel for a trilinear field) and rounding.
    for layout in VoxelLayout::ALL {
        let packed = PackedTree::new(&tree, layout);
        let mut compared = 0;
        for (&(level, origin), _) in bricks.iter().filter(|((l, _), _)| *l < 2) {
            let q = origin.as_vec3() + Vec3::new(0.37, 0.71, 0.13) * (n << level) as f32;
            for axis in 0..3 {
                let mut p = tree.world(q);
                p[axis] = tree.world(origin.as_vec3())[axis];
                let (mut below, mut above) = (p, p);
                below[axis] = p[axis].next_down();
                above[axis] = p[axis].next_up();
                let (Some(a), Some(b)) =
                    (packed.sample_raw(below, level as f32), packed.sample_raw(above, level as f32))
                else {
                    continue;
                };
                if a.normal == Vec3::ZERO || b.normal == Vec3::ZERO {
                    continue; // an empty node's sample is only a bound
                }
                // Fractions are quantised to 2⁻¹¹ voxel: a step of the field's ≤ √3 slope.
                assert!(
                    (a.distance - b.distance).abs() <= (3_f32.sqrt() / 2048.0 + 1e-5) * (1u32 << level) as f32,
                    "{layout:?} {a:?} {b:?}"
                );
                compared += 1;
            }
        }
        assert!(compared > 100, "{compared}");
    }
}

#[test]
fn the_volume_variance_counts_a_flat_planes_ramp_as_roughness() {
    let plane = SdfSurface::new(|p: Vec3| p.z - 0.013, |_| [0.3; 3], 1e-4).unwrap();
    for (model, expect_rough) in [(HeightVariance::SurfaceHeights, false), (HeightVariance::DistanceVolume, true)] {
        let options = BuildOptions { height_variance: model, ..options(BrickSize::Four, 3) };
        let tree = BrickTree::build(&plane, domain(), options).unwrap();
        let mut checked = 0;
        for b in 0..tree.brick_count() {
            let level = tree.brick_levels()[b];
            if level == 0 {
                continue;
            }
            let s = (1u32 << level) as f32;
            for voxel in tree.brick_voxels(b) {
                if expect_rough {
                    // The midpoint rule's variance of a ramp of slope 1 over q points: (S² − (S/q)²)/12.
                    let q = (1u32 << level).min(4) as f32;
                    let ramp = (s * s - (s / q) * (s / q)) / 12.0;
                    assert!((voxel.distance_variance - ramp).abs() <= 1e-3 * ramp, "{voxel:?} vs {ramp}");
                } else {
                    assert!(voxel.distance_variance <= 1e-6 * s * s, "{voxel:?}");
                }
                checked += 1;
            }
        }
        assert!(checked > 1000);
    }
}

#[test]
fn sampling_a_voxel_centre_returns_that_voxel() {
    let tree = BrickTree::build(&sphere(), domain(), options(BrickSize::Eight, 3)).unwrap();
    for layout in VoxelLayout::ALL {
        let packed = PackedTree::new(&tree, layout);
        let side = tree.brick_size().stored_side();
        let mut compared = 0;
        for b in 0..tree.brick_count() {
            let (level, origin) = (tree.brick_levels()[b], tree.brick_origins()[b]);
            let scale = (1u32 << level) as f32;
            for (i, voxel) in tree.brick_voxels(b).iter().enumerate().step_by(7) {
                let index = IVec3::new(
                    (i as u32 % side) as i32,
                    (i as u32 / side % side) as i32,
                    (i as u32 / (side * side)) as i32,
                );
                if index.max_element() > side as i32 - 2 {
                    continue; // the far faces' points belong to the next node
                }
                let q = origin.as_vec3() + index.as_vec3() * scale;
                let sample = packed.sample(tree.world(q), level as f32).unwrap();
                let expected = layout.round_trip(voxel, level).scaled(tree.voxel_size());
                assert_eq!(sample.distance, expected.distance, "level {level} origin {origin} index {index}");
                assert_eq!(sample.attribute, expected.attribute);
                assert!((sample.normal - expected.normal).length() < 1e-6);
                compared += 1;
            }
        }
        assert!(compared > 500, "{compared}");
    }
}

#[test]
fn bad_options_are_errors_naming_the_option() {
    let error =
        BrickTree::build(&sphere(), domain(), BuildOptions { levels: 0, ..BuildOptions::default() }).unwrap_err();
    assert_eq!(error, BuildError::Option("levels", 0));
    assert!(error.to_string().contains("`levels`"));
    let error =
        BrickTree::build(&sphere(), Domain { origin: Vec3::ZERO, size: -1.0 }, BuildOptions::default()).unwrap_err();
    assert!(matches!(error, BuildError::Domain(_)));
    let limited = BuildOptions { max_bricks: 3, ..BuildOptions::default() };
    assert_eq!(BrickTree::build(&sphere(), domain(), limited).unwrap_err(), BuildError::TooManyBricks(3));
    let nan = SdfSurface::new(|_: Vec3| f32::NAN, |_| [0.0; 3], 1e-3).unwrap();
    assert!(matches!(BrickTree::build(&nan, domain(), BuildOptions::default()), Err(BuildError::Distance(_))));
}

#[test]
fn pools_split_over_bindings_or_fail_naming_the_limit() {
    let tree = BrickTree::build(&sphere(), domain(), options(BrickSize::Four, 3)).unwrap();
    let brick_bytes = (4 * BrickSize::Four.stored_voxels() * VoxelLayout::Compact16.words()) as u64;
    let bricks = tree.brick_count() as u64;
    let split =
        PackedTree::with_binding_limit(&tree, VoxelLayout::Compact16, brick_bytes * bricks.div_ceil(4)).unwrap();
    let bindings = split.brick_bindings();
    assert_eq!(bindings.iter().map(|b| b.len()).sum::<usize>(), split.words().len());
    assert!(bindings.iter().all(|b| (b.len() as u64 * 4) <= brick_bytes * bricks.div_ceil(4)));
    let whole = PackedTree::new(&tree, VoxelLayout::Compact16);
    assert_eq!(whole.brick_bindings()[0].len(), whole.words().len());
    assert_eq!(whole.brick_bindings()[1], &[0]);
    let error = PackedTree::with_binding_limit(&tree, VoxelLayout::Compact16, brick_bytes * (bricks / 5)).unwrap_err();
    assert!(matches!(error, svo_brick::PoolError::Bricks(..)));
    assert!(error.to_string().contains("storage bindings"), "{error}");
    let error = PackedTree::with_binding_limit(&tree, VoxelLayout::Compact16, 8).unwrap_err();
    assert!(matches!(error, svo_brick::PoolError::Nodes(..)));
}

#[test]
fn the_moment_correction_restores_the_variance_trilinear_interpolation_misses() {
    let bumps = |p: Vec3| 0.03 * (23.0 * p.x).sin() * (19.0 * p.y).sin() * (29.0 * p.z).sin();
    let source = SdfSurface::new(move |p: Vec3| (p.length() - 0.6 - bumps(p)) / 2.0, |_| [0.5; 3], 1e-4).unwrap();
    let options = options(BrickSize::Eight, 4);
    let tree = BrickTree::build(&source, domain(), options).unwrap();
    let packed = PackedTree::new(&tree, VoxelLayout::Paper20);
    let points: Vec<Vec3> = (0..240)
        .map(|k| {
            let (a, b) = (k as f32 * 2.399_963, (1.0 - 2.0 * (k as f32 + 0.5) / 240.0).acos());
            Vec3::new(a.cos() * b.sin(), a.sin() * b.sin(), b.cos()) * (0.6 + bumps(Vec3::ZERO))
        })
        .collect();
    for level in 1..4 {
        let e = svo_brick::moment_correction_error(
            &source,
            &tree,
            &packed,
            &points,
            level,
            options.samples_per_voxel,
            options.quadrature,
        );
        let f = |d: svo_brick::DeviationError| format!("{:+.3} (|·| {:.3})", d.mean_relative, d.mean_absolute_relative);
        println!(
            "level {level}: {} points; σh relative error against the box: plain {}, corrected {}; against the mixture: plain {}, corrected {}",
            e.points,
            f(e.plain_box),
            f(e.corrected_box),
            f(e.plain_mixture),
            f(e.corrected_mixture)
        );
        assert!(e.points >= 180, "{} points compared", e.points);
        // The law of total variance: interpolated variances hold only the within-voxel part
        // of the trilinear footprint's variance, so plain interpolation underestimates it,
        // and the moment correction, which adds the between-voxel part, is closer.
        assert!(e.plain_mixture.mean_relative < 0.0, "{e:?}");
        assert!(e.corrected_mixture.mean_absolute_relative < e.plain_mixture.mean_absolute_relative, "{e:?}");
    }
}

#[test]
fn voxels_off_the_surface_take_the_attributes_of_their_nearest_surface() {
    // The sphere's attribute is a = 0.5 + 0.5 z / R (|∇a| = 0.5 / R on the surface). Every
    // voxel, with surface samples or dilated from the nearest voxel that has them (at most
    // 2 voxels from its projection), must hold a mean attribute of the surface within
    // 4√3 S_L of its closest surface point, so within 0.5 / R × 4√3 S_L of a there; a voxel
    // that kept an undefined (zero) attribute would fail.
    let tree = BrickTree::build(&sphere(), domain(), options(BrickSize::Eight, 4)).unwrap();
    let side = tree.brick_size().stored_side();
    let mut checked = 0;
    for b in 0..tree.brick_count() {
        let (level, origin) = (tree.brick_levels()[b], tree.brick_origins()[b]);
        let scale = (1u32 << level) as f32;
        for (i, voxel) in tree.brick_voxels(b).iter().enumerate() {
            let index = UVec3::new(i as u32 % side, i as u32 / side % side, i as u32 / (side * side));
            let centre = tree.world(origin.as_vec3() + index.as_vec3() * scale);
            if centre.length() < 1e-6 {
                continue; // the sphere's centre has no closest point
            }
            let closest = centre.normalize() * RADIUS;
            let expected = 0.5 + 0.5 * closest.z / RADIUS;
            let bound = 0.5 / RADIUS * 4.0 * 3_f32.sqrt() * scale * tree.voxel_size();
            assert!(
                (voxel.attribute[0] - expected).abs() <= bound,
                "level {level} at {centre}: {voxel:?} vs {expected} ± {bound}"
            );
            assert!((voxel.attribute[1] - 0.2).abs() < 1e-5 && (voxel.attribute[2] - 0.8).abs() < 1e-5, "{voxel:?}");
            checked += 1;
        }
    }
    // All but the few copies of the vertex at the sphere's centre.
    assert!(checked + 64 >= tree.brick_count() * BrickSize::Eight.stored_voxels(), "{checked}");
}
