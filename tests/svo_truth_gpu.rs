//! `svo_render::GpuVoxelTruth`, the voxel truth on the GPU, against the CPU's
//! (`svo_render::truth::render_voxel_truth`): the same rays and jitter, traced in `f32` from
//! each ray's entry into the domain where the CPU traces in `f64`.
//!
//! A pixel may differ beyond float tolerance only where the CPU's own result is sensitive to
//! where a hit is accepted: f32 moves a hit by a few ulps of the domain (~10⁻⁷), far less than
//! the tolerance `ε` (10⁻⁴ finest voxel, 3·10⁻⁶ here), and its rays by a few ulps, so every
//! pixel that differs must be one whose CPU truth already changes when `ε` is halved or
//! doubled or the eye moves by 8 ulps (grazing rays, hits on the edge of a bump). The test
//! prints how many pixels are close, how many differ, and how many are sensitive.

use glam::Vec3;
use integration_tests::{gpu, svo_bumps_over_floor};
use svo_brick::VoxelLayout;
use svo_render::gpu_truth::MIN_RELATIVE_EPSILON;
use svo_render::renderer::pack_for;
use svo_render::timing::time_voxel_truth;
use svo_render::truth::{TruthSettings, render_voxel_truth};
use svo_render::{Frame, GpuVoxelTruth, RenderError};
use svo_tracer::{Camera, Lens, TraceSettings};

const WIDTH: u32 = 32;
const HEIGHT: u32 = 24;

fn camera(eye: Vec3) -> Camera {
    Camera::look_at(eye, Vec3::ZERO, Vec3::Y, 0.7, WIDTH, HEIGHT).unwrap()
}

/// The camera with its eye moved by 8 `f32` ulps of its largest coordinate, each way along
/// its right and up axes: rays as far from the camera's as the GPU's `f32` rays may be.
fn nudged(camera: &Camera) -> Vec<Camera> {
    let eye = camera.position();
    let ulp = 8.0 * f32::EPSILON * eye.abs().max_element();
    let target = eye + camera.forward();
    let lens = camera.lens();
    let (width, height) = camera.size();
    let fov = 2.0 * (0.5 * camera.pixel_size() * height as f32).atan();
    [camera.right(), -camera.right(), camera.up(), -camera.up()]
        .map(|axis| {
            let moved =
                Camera::look_at(eye + axis * ulp, target + axis * ulp, camera.up(), fov, width, height).unwrap();
            lens.map_or(moved, |lens| moved.with_lens(lens).unwrap())
        })
        .to_vec()
}

/// Whether pixel `k` of `a` and `b` agree within float tolerance.
fn close(a: &Frame, b: &Frame, k: usize) -> bool {
    let dr = (a.radiance[k] - b.radiance[k]).abs().max_element();
    dr <= 1e-4 * (1.0 + b.radiance[k].abs().max_element()) && (a.coverage[k] - b.coverage[k]).abs() <= 1e-6
}

#[test]
fn the_gpu_voxel_truth_traces_the_cpus_rays() {
    let gpu = gpu();
    let tree = svo_bumps_over_floor();
    let packed = pack_for(&gpu.device, &tree, VoxelLayout::Paper20).unwrap();
    let voxel = packed.uniforms().voxel_size.x;
    // Built once: every frame below is one encode and one submission.
    let truth = GpuVoxelTruth::new(&gpu.device, &packed, (WIDTH, HEIGHT)).unwrap();
    let near = camera(Vec3::new(0.4, 0.5, -2.6));
    let far = camera(Vec3::new(-1.5, 1.2, -5.0));
    let lens = near.with_lens(Lens { aperture: 0.08, focus: 2.4 }).unwrap();
    let base = TruthSettings::for_voxel(voxel, 3);
    let cases = [
        ("near", near, base),
        ("far, centred strata", far, TruthSettings { jitter: false, ..base }),
        ("lens", lens, TruthSettings { lens_samples_per_axis: 2, ..base }),
        ("shadows", near, TruthSettings { shadow_rays_per_axis: 2, ..base }),
    ];
    let trace = TraceSettings::default();
    let (mut compared, mut differing) = (0, 0);
    for (name, camera, settings) in cases {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        truth.encode(&gpu.queue, &mut encoder, &camera, &trace, &settings, None).unwrap();
        gpu.queue.submit([encoder.finish()]);
        let on_gpu = truth.read_frame(gpu).unwrap();
        let on_cpu = render_voxel_truth(&packed, &camera, &trace, &settings).unwrap();
        let mut perturbed: Vec<Frame> = [0.5, 2.0]
            .iter()
            .map(|f| {
                let settings = TruthSettings { epsilon: f * settings.epsilon, ..settings };
                render_voxel_truth(&packed, &camera, &trace, &settings).unwrap()
            })
            .collect();
        perturbed.extend(nudged(&camera).iter().map(|c| render_voxel_truth(&packed, c, &trace, &settings).unwrap()));
        let total = on_cpu.pixels();
        let mut same = 0;
        let mut sensitive = 0;
        let mut unexplained = Vec::new();
        for k in 0..total {
            let is_sensitive = perturbed.iter().any(|p| !close(p, &on_cpu, k));
            sensitive += usize::from(is_sensitive);
            if close(&on_gpu, &on_cpu, k) {
                same += 1;
            } else if !is_sensitive {
                unexplained.push((k, on_gpu.radiance[k], on_cpu.radiance[k], on_gpu.coverage[k], on_cpu.coverage[k]));
            }
        }
        let covered = (0..total).filter(|&k| on_cpu.coverage[k] > 0.0).count();
        println!(
            "{name}: {same} of {total} pixels within float tolerance ({covered} covered), {} differ, \
             {sensitive} sensitive to ε on the CPU, {} differ without being sensitive",
            total - same,
            unexplained.len()
        );
        assert!(
            unexplained.is_empty(),
            "{name}: pixels that differ although the CPU is not sensitive: {unexplained:?}"
        );
        assert!(covered * 8 >= total, "{name}: the view must see the surface ({covered} of {total} covered)");
        compared += total;
        differing += total - same;
    }
    assert_eq!(compared, 4 * (WIDTH * HEIGHT) as usize);
    println!("{differing} of {compared} pixels differ, all where the CPU is sensitive to ε");
}

#[test]
fn the_gpu_voxel_truth_is_timed_and_refuses_what_it_cannot_trace() {
    let gpu = gpu();
    let tree = svo_bumps_over_floor();
    let packed = pack_for(&gpu.device, &tree, VoxelLayout::Compact16Fine8).unwrap();
    let voxel = packed.uniforms().voxel_size.x;
    let truth = GpuVoxelTruth::new(&gpu.device, &packed, (WIDTH, HEIGHT)).unwrap();
    let trace = TraceSettings::default();
    let settings = TruthSettings::for_voxel(voxel, 2);
    let near = camera(Vec3::new(0.4, 0.5, -2.6));
    let times = time_voxel_truth(gpu, &truth, &near, &trace, &settings, 1, 3).unwrap();
    assert_eq!(times.ms.len(), 3);
    assert!(times.median() > 0.0, "{times:?}");
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    let small = Camera::look_at(Vec3::new(0.0, 0.0, -3.0), Vec3::ZERO, Vec3::Y, 0.7, 8, 8).unwrap();
    let error = truth.encode(&gpu.queue, &mut encoder, &small, &trace, &settings, None).unwrap_err();
    assert!(matches!(error, RenderError::Setting { field: "Camera::size", .. }), "{error}");
    assert_eq!(truth.min_epsilon(), MIN_RELATIVE_EPSILON * 2.0, "the domain is [-1, 1]³");
    let fine = TruthSettings { epsilon: 0.5 * truth.min_epsilon(), ..settings };
    let error = truth.encode(&gpu.queue, &mut encoder, &near, &trace, &fine, None).unwrap_err();
    assert!(matches!(error, RenderError::Setting { field: "TruthSettings::epsilon", .. }), "{error}");
    let none = TruthSettings { rays_per_axis: 0, ..settings };
    let error = truth.encode(&gpu.queue, &mut encoder, &near, &trace, &none, None).unwrap_err();
    assert!(matches!(error, RenderError::Setting { field: "TruthSettings::rays_per_axis", .. }), "{error}");
    let error = GpuVoxelTruth::new(&gpu.device, &packed, (0, 4)).unwrap_err();
    assert!(matches!(error, RenderError::Setting { field: "GpuVoxelTruth::size", .. }), "{error}");
}
