//! CPU = GPU test of `svo-tracer`'s WGSL twin: whole pixel cones (camera ray, Algorithm 1
//! with every model, depth of field, shadow cones and the empty-space skip) against the CPU
//! reference on a small octree. The twin follows the Rust operation for operation, but
//! `atan2`, `log2`, `sqrt` and divisions are not correctly rounded in WGSL, so an element
//! whose `(θ, v)` lies within that rounding of a mask-table cell boundary may take the
//! neighbouring cell's mask: such pixels differ by a few mask samples. The test requires
//! nearly every pixel equal within float tolerance and bounds the rest by those samples.

use abuffer_mask::MaskTable;
use glam::{UVec4, Vec3, Vec4};
use integration_tests::{gpu, svo_bumps_over_floor};
use svo_brick::{PackedTree, VoxelLayout};
use svo_tracer::{Camera, Lens, Model, TraceSettings, trace_cone};

const SIZE: u32 = 32;

#[test]
fn pixel_cones_match_the_cpu_reference() {
    let tree = svo_bumps_over_floor();
    let table = MaskTable::<4>::paper().unwrap();
    let camera = Camera::look_at(Vec3::new(0.4, 0.5, -2.6), Vec3::ZERO, Vec3::Y, 0.7, SIZE, SIZE).unwrap();
    let lens = camera.with_lens(Lens { aperture: 0.08, focus: 2.4 }).unwrap();
    let source = shader_registry::test_kernel_source("svo_tracer_differential").unwrap_or_else(|e| panic!("{e}"));
    let pixels: Vec<UVec4> = (0..SIZE * SIZE).map(|k| UVec4::new(k % SIZE, k / SIZE, 0, 0)).collect();
    let packed = PackedTree::new(&tree, VoxelLayout::Compact16Fine8);
    let mut storage: Vec<&[u8]> = vec![bytemuck::cast_slice(packed.nodes())];
    let bindings = packed.brick_bindings();
    storage.extend(bindings.iter().map(|b| bytemuck::cast_slice::<u32, u8>(b)));
    storage.push(bytemuck::cast_slice(table.words()));
    let uploaded = gpu().upload_storage(&storage).unwrap();
    let cases =
        Model::ALL.map(|m| (m, camera, 0)).into_iter().chain([(Model::Masks, lens, 0), (Model::Masks, camera, 2)]);
    let mut compared = 0;
    for (model, camera, shadows) in cases {
        let settings = TraceSettings { model, shadow_cones: shadows, ..TraceSettings::default() };
        let mut uniforms = bytemuck::bytes_of(&packed.uniforms()).to_vec();
        uniforms.extend(bytemuck::bytes_of(&table.uniforms()));
        uniforms.extend(bytemuck::bytes_of(&camera.to_gpu()));
        uniforms.extend(bytemuck::bytes_of(&settings.to_gpu()));
        let (results, _): (Vec<[Vec4; 2]>, _) =
            gpu().compute_map_with_uploaded_storage(&source, "trace_pixels", &uniforms, &pixels, &uploaded).unwrap();
        let (mut close, mut worst_radiance, mut worst_coverage, mut elements_equal) = (0, 0.0_f32, 0.0_f32, 0);
        for (pixel, result) in pixels.iter().zip(&results) {
            let cpu = trace_cone(&packed, &table, &camera.pixel_cone(pixel.x, pixel.y), &settings);
            let gpu_radiance = result[0].truncate();
            let dr = (gpu_radiance - cpu.radiance).abs().max_element();
            let dc = (result[0].w - cpu.coverage).abs();
            if dr <= 1e-4 * (1.0 + cpu.radiance.abs().max_element()) && dc <= 1e-6 {
                close += 1;
            }
            worst_radiance = worst_radiance.max(dr);
            worst_coverage = worst_coverage.max(dc);
            elements_equal += usize::from(result[1].x as u32 == cpu.elements);
            compared += 1;
        }
        let total = pixels.len();
        println!(
            "{} (shadows {shadows}, lens {}): {close} of {total} pixels equal within 1e-4, {elements_equal} with equal element counts; worst radiance {worst_radiance:.2e}, coverage {worst_coverage:.2e}",
            model.name(),
            camera.lens().is_some()
        );
        // A cell flip changes an element's mask by a few of its 128 samples; a few flips per
        // pixel at most.
        assert!(close * 100 >= total * 97, "{model:?}: only {close} of {total} pixels equal");
        assert!(worst_coverage <= 16.0 / 128.0, "{model:?}: coverage differs by {worst_coverage}");
    }
    assert_eq!(compared, 6 * (SIZE * SIZE) as usize);
}
