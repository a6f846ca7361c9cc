//! The empty-space skip changes the work, never the image: every pixel's radiance and
//! coverage are the same bits with and without it, for every model, with depth of field
//! and with shadows.

use abuffer_mask::MaskTable;
use glam::Vec3;
use svo_brick::{BrickSize, BrickTree, BuildOptions, Domain, PackedTree, SdfSurface, VoxelLayout};
use svo_tracer::{Camera, Lens, Model, TraceSettings, trace_cone};

#[test]
fn skipping_empty_space_leaves_every_pixel_unchanged() {
    let bumps = |p: Vec3| 0.02 * (17.0 * p.x).sin() * (13.0 * p.y).sin() * (11.0 * p.z).sin();
    let shape = SdfSurface::new(
        move |p: Vec3| ((p - Vec3::new(0.1, 0.0, 0.0)).length() - 0.45 - bumps(p)).min(p.y + 0.55) / 1.6,
        |p: Vec3| [0.5 + 0.4 * p.z, 0.6, 0.3 + 0.3 * p.x],
        1e-4,
    )
    .unwrap();
    let options = BuildOptions { brick_size: BrickSize::Eight, levels: 4, ..BuildOptions::default() };
    let tree = BrickTree::build(&shape, Domain { origin: Vec3::splat(-1.0), size: 2.0 }, options).unwrap();
    let table = MaskTable::<4>::paper().unwrap();
    let camera = Camera::look_at(Vec3::new(0.4, 0.5, -2.6), Vec3::ZERO, Vec3::Y, 0.7, 24, 24).unwrap();
    let lens = camera.with_lens(Lens { aperture: 0.08, focus: 2.4 }).unwrap();
    let mut compared = 0;
    for layout in [VoxelLayout::Paper20, VoxelLayout::Compact16] {
        let packed = PackedTree::new(&tree, layout);
        for (model, camera, shadows) in
            Model::ALL.map(|m| (m, camera, 0)).into_iter().chain([(Model::Masks, lens, 0), (Model::Masks, camera, 2)])
        {
            let (mut with, mut without) = (0_u64, 0_u64);
            for y in 0..24 {
                for x in 0..24 {
                    let cone = camera.pixel_cone(x, y);
                    let on = TraceSettings { model, shadow_cones: shadows, ..TraceSettings::default() };
                    let off = TraceSettings { empty_space_skip: false, ..on };
                    let (a, b) = (trace_cone(&packed, &table, &cone, &on), trace_cone(&packed, &table, &cone, &off));
                    assert_eq!(
                        a.radiance.to_array().map(f32::to_bits),
                        b.radiance.to_array().map(f32::to_bits),
                        "{model:?} ({x}, {y})"
                    );
                    assert_eq!(a.coverage.to_bits(), b.coverage.to_bits());
                    (with, without) = (with + u64::from(a.elements), without + u64::from(b.elements));
                    compared += 1;
                }
            }
            println!(
                "{layout:?} {model:?} (shadows {shadows}, lens {}): elements per pixel {:.1} with the skip, {:.1} without",
                camera.pixel_cone(0, 0).lens.is_some(),
                with as f64 / 576.0,
                without as f64 / 576.0
            );
            assert!(with <= without);
        }
    }
    assert_eq!(compared, 2 * 6 * 576);
}

#[test]
fn thin_cones_skip_most_of_the_empty_space() {
    let sphere = SdfSurface::new(|p: Vec3| p.length() - 0.3, |_| [0.7; 3], 1e-4).unwrap();
    let options = BuildOptions { brick_size: BrickSize::Eight, levels: 5, ..BuildOptions::default() };
    let tree = BrickTree::build(&sphere, Domain { origin: Vec3::splat(-1.0), size: 2.0 }, options).unwrap();
    let packed = PackedTree::new(&tree, VoxelLayout::Compact16);
    let table = MaskTable::<4>::paper().unwrap();
    // A 512² view: pixels a fifth of a finest voxel wide at the sphere.
    let camera = Camera::look_at(Vec3::new(0.0, 0.0, -2.5), Vec3::ZERO, Vec3::Y, 0.5, 512, 512).unwrap();
    let (mut with, mut without, mut pixels) = (0_u64, 0_u64, 0_u32);
    for y in (0..512).step_by(37) {
        for x in (0..512).step_by(41) {
            let cone = camera.pixel_cone(x, y);
            let on = TraceSettings::default();
            let off = TraceSettings { empty_space_skip: false, ..on };
            let (a, b) = (trace_cone(&packed, &table, &cone, &on), trace_cone(&packed, &table, &cone, &off));
            assert_eq!(a.radiance.to_array().map(f32::to_bits), b.radiance.to_array().map(f32::to_bits));
            (with, without, pixels) = (with + u64::from(a.elements), without + u64::from(b.elements), pixels + 1);
        }
    }
    println!(
        "512² sphere, {pixels} pixels: {:.1} elements per pixel with the skip, {:.1} without",
        with as f64 / f64::from(pixels),
        without as f64 / f64::from(pixels)
    );
    // Pins the measured saving (a regression check, not a bound): at least 3× fewer samples.
    assert!(3 * with <= without, "{with} vs {without}");
}
