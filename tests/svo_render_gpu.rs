//! `svo_render::GpuRenderer`, the cone tracer built once and encoded per frame: its frames
//! against the CPU reference (`svo_render::cpu::render`), frame after frame with changing
//! cameras and models without rebuilding, its display image against the frame's own sRGB
//! encoding, its errors, and its frame timing.
//!
//! The renderer runs `svo-tracer`'s twin, so its pixels differ from the CPU's only where the
//! twin's do (`svo_tracer_gpu.rs`): `atan2`, `log2`, `sqrt` and divisions are not correctly
//! rounded in WGSL, and an element whose `(θ, v)` lies within that rounding of a mask-table
//! cell boundary takes the neighbouring cell's mask. The same criteria apply: nearly every
//! pixel equal within float tolerance, coverage within a few of the 128 mask samples.

use abuffer_mask::MaskTable;
use glam::Vec3;
use integration_tests::{gpu, svo_bumps_over_floor};
use svo_brick::VoxelLayout;
use svo_render::renderer::pack_for;
use svo_render::timing::time_frames;
use svo_render::{FrameSettings, GpuRenderer, RenderError, cpu};
use svo_tracer::{Camera, Lens, Model, TraceSettings};

const WIDTH: u32 = 40;
const HEIGHT: u32 = 28;

fn camera(eye: Vec3) -> Camera {
    Camera::look_at(eye, Vec3::ZERO, Vec3::Y, 0.7, WIDTH, HEIGHT).unwrap()
}

/// (pixels equal within 1e-4 relative, worst radiance difference, worst coverage difference).
fn differences(gpu: &svo_render::Frame, cpu: &svo_render::Frame) -> (usize, f32, f32) {
    let (mut close, mut worst_radiance, mut worst_coverage) = (0, 0.0_f32, 0.0_f32);
    for k in 0..cpu.pixels() {
        let dr = (gpu.radiance[k] - cpu.radiance[k]).abs().max_element();
        let dc = (gpu.coverage[k] - cpu.coverage[k]).abs();
        if dr <= 1e-4 * (1.0 + cpu.radiance[k].abs().max_element()) && dc <= 1e-6 {
            close += 1;
        }
        worst_radiance = worst_radiance.max(dr);
        worst_coverage = worst_coverage.max(dc);
    }
    (close, worst_radiance, worst_coverage)
}

#[test]
fn frames_match_the_cpu_reference_frame_after_frame() {
    let gpu = gpu();
    let tree = svo_bumps_over_floor();
    let table = MaskTable::<4>::paper().unwrap();
    let packed = pack_for(&gpu.device, &tree, VoxelLayout::Compact16Fine8).unwrap();
    // Built once: every frame below is one encode and one submission.
    let renderer = GpuRenderer::new(&gpu.device, &packed, &table, (WIDTH, HEIGHT)).unwrap();
    let near = camera(Vec3::new(0.4, 0.5, -2.6));
    let far = camera(Vec3::new(-1.5, 1.2, -5.0));
    let lens = near.with_lens(Lens { aperture: 0.08, focus: 2.4 }).unwrap();
    let frames = Model::ALL.map(|model| (model, near, 0)).into_iter().chain([
        (Model::Masks, far, 0),
        (Model::Masks, lens, 0),
        (Model::Masks, near, 1),
        (Model::AlphaBlend, far, 0),
    ]);
    let mut compared = 0;
    for (model, camera, shadow_cones) in frames {
        let settings = TraceSettings { model, shadow_cones, ..TraceSettings::default() };
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        let frame = FrameSettings { camera: &camera, settings: &settings, exposure: 1.0 };
        renderer.encode(&gpu.queue, &mut encoder, frame).unwrap();
        gpu.queue.submit([encoder.finish()]);
        let on_gpu = renderer.read_frame(gpu).unwrap();
        let on_cpu = cpu::render(&packed, &table, &camera, &settings);
        let (close, worst_radiance, worst_coverage) = differences(&on_gpu, &on_cpu);
        let elements_equal = (0..on_cpu.pixels()).filter(|&k| on_gpu.elements[k] == on_cpu.elements[k]).count();
        let total = on_cpu.pixels();
        println!(
            "{} (shadows {shadow_cones}, lens {}, eye {}): {close} of {total} pixels equal within 1e-4, \
             {elements_equal} with equal element counts; worst radiance {worst_radiance:.2e}, coverage {worst_coverage:.2e}",
            model.name(),
            camera.lens().is_some(),
            camera.position()
        );
        assert!(close * 100 >= total * 97, "{model:?}: only {close} of {total} pixels equal");
        assert!(worst_coverage <= 16.0 / 128.0, "{model:?}: coverage differs by {worst_coverage}");
        assert!(on_cpu.coverage.iter().any(|&c| c > 0.5), "the view must see the surface");
        compared += 1;
    }
    assert_eq!(compared, Model::ALL.len() + 4);
}

/// The display image is the sRGB encoding of `exposure × radiance` of the same frame: WGSL's
/// `pow` is not correctly rounded, so a value may land on the neighbouring byte, never
/// further.
#[test]
fn the_image_is_the_frames_srgb_encoding() {
    let gpu = gpu();
    let tree = svo_bumps_over_floor();
    let table = MaskTable::<4>::paper().unwrap();
    let packed = pack_for(&gpu.device, &tree, VoxelLayout::Paper20).unwrap();
    let renderer = GpuRenderer::new(&gpu.device, &packed, &table, (WIDTH, HEIGHT)).unwrap();
    let camera = camera(Vec3::new(0.4, 0.5, -2.6));
    let settings = TraceSettings::default();
    let exposure = 1.7;
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    renderer
        .encode(&gpu.queue, &mut encoder, FrameSettings { camera: &camera, settings: &settings, exposure })
        .unwrap();
    gpu.queue.submit([encoder.finish()]);
    let image = renderer.read_image(gpu).unwrap();
    let expected = renderer.read_frame(gpu).unwrap().to_rgba8(exposure);
    let mut worst = 0;
    for (a, b) in image.pixels().zip(expected.pixels()) {
        for c in 0..4 {
            worst = worst.max(a.0[c].abs_diff(b.0[c]));
        }
    }
    println!("image against the frame's sRGB encoding: worst difference {worst} of 255");
    assert!(worst <= 1);
    assert_eq!(image.dimensions(), (WIDTH, HEIGHT));
}

#[test]
fn bad_frames_are_errors_naming_the_setting() {
    let gpu = gpu();
    let tree = svo_bumps_over_floor();
    let table = MaskTable::<4>::paper().unwrap();
    let packed = pack_for(&gpu.device, &tree, VoxelLayout::Compact16).unwrap();
    let error = GpuRenderer::new(&gpu.device, &packed, &table, (0, 8)).unwrap_err();
    assert!(error.to_string().contains("GpuRenderer::size"), "{error}");
    let renderer = GpuRenderer::new(&gpu.device, &packed, &table, (WIDTH, HEIGHT)).unwrap();
    let settings = TraceSettings::default();
    let small = Camera::look_at(Vec3::new(0.0, 0.0, -3.0), Vec3::ZERO, Vec3::Y, 0.7, 16, 16).unwrap();
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    let frame = FrameSettings { camera: &small, settings: &settings, exposure: 1.0 };
    let error = renderer.encode(&gpu.queue, &mut encoder, frame).unwrap_err();
    assert!(matches!(error, RenderError::Setting { field: "Camera::size", .. }), "{error}");
    let right = camera(Vec3::new(0.0, 0.0, -3.0));
    let frame = FrameSettings { camera: &right, settings: &settings, exposure: f32::NAN };
    let error = renderer.encode(&gpu.queue, &mut encoder, frame).unwrap_err();
    assert!(error.to_string().contains("exposure"), "{error}");
}

/// `time_frames` times as many frames as asked, by timestamps on a hardware adapter and by
/// wall clock on a software one; every time is positive and finite.
#[test]
fn frames_are_timed() {
    let gpu = gpu();
    let tree = svo_bumps_over_floor();
    let table = MaskTable::<4>::paper().unwrap();
    let packed = pack_for(&gpu.device, &tree, VoxelLayout::Compact16Fine8).unwrap();
    let renderer = GpuRenderer::new(&gpu.device, &packed, &table, (WIDTH, HEIGHT)).unwrap();
    let camera = camera(Vec3::new(0.4, 0.5, -2.6));
    let settings = TraceSettings::default();
    let frame = FrameSettings { camera: &camera, settings: &settings, exposure: 1.0 };
    let times = time_frames(gpu, &renderer, frame, 1, 5).unwrap();
    println!("{WIDTH}×{HEIGHT}: median {:.3} ms ({:?}) of {:?}", times.median(), times.source, times.ms);
    assert_eq!(times.ms.len(), 5);
    assert!(times.ms.iter().all(|&t| t > 0.0 && t.is_finite()), "{:?}", times.ms);
    let expected = if gpu.has_timestamps() && !gpu.is_software() {
        gpu_harness::TimingSource::Timestamps
    } else {
        gpu_harness::TimingSource::WallClock
    };
    assert_eq!(times.source, expected);
}
