//! Unit tests of the renderer on wgpu's noop backend (no adapter needed).

use ddm_tracer::GpuScene;
use glam::{Vec3, Vec4};

use super::*;
use crate::base_mesh::plane_base_mesh;
use crate::camera::Camera;
use ddm_tracer::{TraceConeMap, TracePatch, TracePipelineConstants, TraceUniforms};
use glam::{UVec2, UVec3};

/// A device on wgpu's noop backend with `limits`: wgpu validates every object and
/// command but runs nothing, so these tests need no adapter (the GPU tests in
/// `tests/ddm_render_gpu.rs` check what the passes compute).
fn noop_device(limits: wgpu::Limits) -> (wgpu::Device, wgpu::Queue) {
    let mut descriptor = wgpu::InstanceDescriptor::new_without_display_handle();
    descriptor.backends = wgpu::Backends::NOOP;
    descriptor.backend_options.noop =
        wgpu::NoopBackendOptions { limits: Some(limits.clone()), ..wgpu::NoopBackendOptions::enabled() };
    let instance = wgpu::Instance::new(descriptor);
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default()))
        .expect("the noop backend always has an adapter");
    let descriptor = wgpu::DeviceDescriptor {
        required_features: wgpu::Features::TIMESTAMP_QUERY,
        required_limits: limits,
        ..Default::default()
    };
    pollster::block_on(adapter.request_device(&descriptor)).expect("the noop adapter creates devices")
}

/// WebGPU's default limits with room for the G-buffer's 64 colour bytes per sample.
fn limits() -> wgpu::Limits {
    wgpu::Limits { max_color_attachment_bytes_per_sample: 64, ..wgpu::Limits::default() }
}

/// A scene that packs (nothing runs on the noop device, so its contents do not matter).
fn scene() -> GpuScene {
    use bytemuck::Zeroable;
    GpuScene {
        uniforms: TraceUniforms::zeroed(),
        pipeline_constants: TracePipelineConstants::default(),
        cone_maps: vec![TraceConeMap::zeroed()],
        grid: vec![0],
        atlas: vec![0],
        atlas_values: 0,
        patch_offsets: vec![0, 0],
        patches: vec![TracePatch::zeroed()],
        heights: vec![0.0],
    }
}

fn settings() -> RenderSettings {
    RenderSettings {
        slab: Vec3::new(8.0, 8.0, 1.0),
        light: Vec3::new(0.0, 0.6, 0.8),
        ambient: 0.2,
        shadow_tolerance: Some(0.02),
        miss_color: Some(Vec3::splat(0.3)),
        albedo: Vec3::new(0.9, 0.7, 0.2),
        normal_tint: 0.25,
    }
}

fn view(width: u32, height: u32) -> Camera {
    Camera {
        eye: Vec3::new(-4.0, -6.0, 14.0),
        target: Vec3::new(8.0, 8.0, 4.0),
        up: Vec3::Z,
        half_fov_y: 0.4,
        width,
        height,
    }
}

struct Setup {
    device: wgpu::Device,
    queue: wgpu::Queue,
    renderer: DdmRenderer,
}

fn setup(width: u32, height: u32) -> Setup {
    let (device, queue) = noop_device(limits());
    let pipelines = DdmRenderPipelines::new(&device).unwrap();
    let mesh = plane_base_mesh(UVec3::new(8, 8, 4), UVec2::new(2, 2)).unwrap();
    let gbuffer = GBufferPass::new(&device, pipelines.gbuffer(), &mesh, width, height).unwrap();
    let scene = GpuSceneBuffers::new(&device, &scene()).unwrap();
    let renderer = DdmRenderer::new(&device, &pipelines, &gbuffer, &scene).unwrap();
    Setup { device, queue, renderer }
}

fn texture(device: &wgpu::Device, width: u32, height: u32, format: wgpu::TextureFormat) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: None,
        size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::STORAGE_BINDING,
        view_formats: &[],
    })
}

/// A texture a colour and depth target accepts (storage and render attachment).
fn attachable(device: &wgpu::Device, width: u32, height: u32, format: wgpu::TextureFormat) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: None,
        size: wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage: wgpu::TextureUsages::STORAGE_BINDING | wgpu::TextureUsages::RENDER_ATTACHMENT,
        view_formats: &[],
    })
}

#[test]
fn colour_and_depth_targets_are_checked_cleared_and_encoded() {
    let s = setup(40, 24);
    let (device, queue, renderer) = (&s.device, &s.queue, &s.renderer);
    let color = attachable(device, 40, 24, COLOR_TARGET_FORMAT);
    let depth = attachable(device, 40, 24, DEPTH_TARGET_FORMAT);
    // Storage-only textures cannot be cleared; formats must be the two targets'.
    let storage_only = texture(device, 40, 24, DEPTH_TARGET_FORMAT);
    match renderer.color_depth_target(device, &color, &storage_only) {
        Err(DdmRenderError::InvalidTarget { what, problem }) => {
            assert!(what.contains("depth") && problem.contains("RENDER_ATTACHMENT"), "{what}: {problem}");
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(
        renderer.color_depth_target(device, &depth, &color),
        Err(DdmRenderError::InvalidTarget { what: "colour target texture", .. })
    ));
    assert!(matches!(
        renderer.color_depth_target(device, &color, &attachable(device, 40, 23, DEPTH_TARGET_FORMAT)),
        Err(DdmRenderError::SizeMismatch { what: "depth target texture", .. })
    ));
    let target = renderer.color_depth_target(device, &color, &depth).unwrap();
    assert_eq!(target.kind(), TargetKind::ColorDepth);
    let camera = view(40, 24);
    let recorded = error_scoped(device, || {
        let mut encoder = device.create_command_encoder(&Default::default());
        target.encode_clear(&mut encoder).unwrap();
        renderer.encode(queue, &mut encoder, &DdmFrame::new(&camera, settings()), &target).unwrap();
        queue.submit([encoder.finish()]);
    });
    assert!(recorded.is_ok(), "{recorded:?}");
    // Only a colour and depth target is cleared by the renderer.
    let colour_only = renderer.color_target(device, &texture(device, 40, 24, COLOR_TARGET_FORMAT)).unwrap();
    let mut encoder = device.create_command_encoder(&Default::default());
    assert!(matches!(colour_only.encode_clear(&mut encoder), Err(DdmRenderError::InvalidTarget { .. })));
}

fn storage_buffer(device: &wgpu::Device, size: u64, usage: wgpu::BufferUsages) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor { label: None, size, usage, mapped_at_creation: false })
}

#[test]
fn settings_become_the_frame_parameters_or_name_the_bad_field() {
    let eye = Vec3::new(1.0, 2.0, 3.0);
    let params = settings().params(eye).unwrap();
    assert_eq!(params.eye, eye.extend(0.0));
    assert_eq!(params.light, Vec3::new(0.0, 0.6, 0.8).extend(0.2));
    assert_eq!(params.slab, Vec3::new(8.0, 8.0, 1.0).extend(0.02));
    assert_eq!(params.miss_color, Vec3::splat(0.3).extend(1.0));
    assert_eq!(params.albedo, Vec3::new(0.9, 0.7, 0.2).extend(0.25));
    let no_base = RenderSettings { miss_color: None, ..settings() }.params(eye).unwrap();
    assert_eq!(no_base.miss_color, Vec4::ZERO, "no base surface: w 0");
    let unshadowed = RenderSettings { shadow_tolerance: None, ..settings() }.params(eye).unwrap();
    assert!(unshadowed.slab.w < 0.0, "no shadow rays: negative tolerance");
    let bad = [
        (RenderSettings { slab: Vec3::new(8.0, 0.0, 1.0), ..settings() }, "slab"),
        (RenderSettings { slab: Vec3::new(8.0, f32::NAN, 1.0), ..settings() }, "slab"),
        (RenderSettings { light: Vec3::ZERO, ..settings() }, "light"),
        (RenderSettings { light: Vec3::new(f32::INFINITY, 0.0, 1.0), ..settings() }, "light"),
        (RenderSettings { ambient: 1.5, ..settings() }, "ambient"),
        (RenderSettings { ambient: f32::NAN, ..settings() }, "ambient"),
        (RenderSettings { shadow_tolerance: Some(-0.1), ..settings() }, "shadow_tolerance"),
        (RenderSettings { miss_color: Some(Vec3::splat(f32::NAN)), ..settings() }, "miss_color"),
        (RenderSettings { albedo: Vec3::new(0.5, -0.1, 0.5), ..settings() }, "albedo"),
        (RenderSettings { albedo: Vec3::splat(f32::INFINITY), ..settings() }, "albedo"),
        (RenderSettings { normal_tint: 1.5, ..settings() }, "normal_tint"),
        (RenderSettings { normal_tint: f32::NAN, ..settings() }, "normal_tint"),
    ];
    for (settings, field) in bad {
        match settings.params(eye) {
            Err(DdmRenderError::InvalidSettings(message)) => assert!(message.starts_with(field), "{message}"),
            other => panic!("{field}: {other:?}"),
        }
    }
    assert!(matches!(settings().params(Vec3::NAN), Err(DdmRenderError::InvalidCamera(_))));
}

#[test]
fn device_limits_decide_what_can_be_built() {
    // WebGPU's default 32 colour bytes per sample cannot hold four Rgba32Float targets.
    let (device, _) = noop_device(wgpu::Limits::default());
    match DdmRenderPipelines::new(&device) {
        Err(DdmRenderError::TooLarge { what, requested: 64, limit: 32 }) => {
            assert!(what.contains("max_color_attachment_bytes_per_sample"), "{what}");
        }
        other => panic!("{other:?}"),
    }
    let (device, _) = noop_device(wgpu::Limits { max_storage_buffers_per_shader_stage: 6, ..limits() });
    match DdmRenderPipelines::new(&device) {
        Err(DdmRenderError::TooLarge { what, requested: 7, limit: 6 }) => {
            assert!(what.contains("max_storage_buffers_per_shader_stage"), "{what}");
        }
        other => panic!("{other:?}"),
    }
    let (device, _) = noop_device(limits());
    let pipelines = DdmRenderPipelines::new(&device).unwrap();
    let mesh = plane_base_mesh(UVec3::new(8, 8, 4), UVec2::ONE).unwrap();
    let side = device.limits().max_texture_dimension_2d + 1;
    match GBufferPass::new(&device, pipelines.gbuffer(), &mesh, side, 4) {
        Err(DdmRenderError::TooLarge { what, .. }) => assert!(what.contains("max_texture_dimension_2d"), "{what}"),
        other => panic!("{other:?}"),
    }
    assert!(matches!(
        GBufferPass::new(&device, pipelines.gbuffer(), &mesh, 0, 4),
        Err(DdmRenderError::EmptySize { width: 0, height: 4 })
    ));
    let mut broken = mesh.clone();
    broken.indices.push([0, 1, 99]);
    assert!(matches!(
        GBufferPass::new(&device, pipelines.gbuffer(), &broken, 4, 4),
        Err(DdmRenderError::InvalidMesh(_))
    ));
    broken.indices.pop();
    broken.positions[0].x = f32::NAN;
    assert!(matches!(
        GBufferPass::new(&device, pipelines.gbuffer(), &broken, 4, 4),
        Err(DdmRenderError::InvalidMesh(_))
    ));
}

#[test]
fn targets_must_fit_the_renderer() {
    let s = setup(40, 24);
    let (device, renderer) = (&s.device, &s.renderer);
    let storage = wgpu::BufferUsages::STORAGE;
    assert_eq!(renderer.pixel_bytes(), 40 * 24 * 64);
    let small = storage_buffer(device, renderer.pixel_bytes() - 4, storage);
    assert!(matches!(renderer.pixel_target(device, &small), Err(DdmRenderError::InvalidTarget { .. })));
    let not_storage = storage_buffer(device, renderer.pixel_bytes(), wgpu::BufferUsages::COPY_SRC);
    assert!(matches!(renderer.pixel_target(device, &not_storage), Err(DdmRenderError::InvalidTarget { .. })));
    let target = renderer.pixel_target(device, &storage_buffer(device, renderer.pixel_bytes(), storage)).unwrap();
    assert_eq!((target.kind(), target.size()), (TargetKind::Pixels, (40, 24)));
    let rgba8 = texture(device, 40, 24, wgpu::TextureFormat::Rgba8Unorm);
    assert!(matches!(renderer.color_target(device, &rgba8), Err(DdmRenderError::InvalidTarget { .. })));
    let wrong_size = texture(device, 41, 24, COLOR_TARGET_FORMAT);
    assert!(matches!(
        renderer.color_target(device, &wrong_size),
        Err(DdmRenderError::SizeMismatch { expected: (40, 24), found: (41, 24), .. })
    ));
    let color = renderer.color_target(device, &texture(device, 40, 24, COLOR_TARGET_FORMAT)).unwrap();
    assert_eq!(color.kind(), TargetKind::Color);
}

#[test]
fn frames_encode_into_both_targets_and_bad_frames_are_errors() {
    let s = setup(40, 24);
    let (device, queue, renderer) = (&s.device, &s.queue, &s.renderer);
    let pixels = renderer
        .pixel_target(device, &storage_buffer(device, renderer.pixel_bytes(), wgpu::BufferUsages::STORAGE))
        .unwrap();
    let color = renderer.color_target(device, &texture(device, 40, 24, COLOR_TARGET_FORMAT)).unwrap();
    let queries =
        device.create_query_set(&wgpu::QuerySetDescriptor { label: None, ty: wgpu::QueryType::Timestamp, count: 4 });
    let camera = view(40, 24);
    let moved = Camera { eye: Vec3::new(20.0, -3.0, 9.0), ..camera };
    // Frames for both targets and two cameras, with timestamps, pass wgpu's validation.
    let recorded = error_scoped(device, || {
        for (camera, target) in [(&camera, &pixels), (&moved, &color)] {
            let frame = DdmFrame {
                raster_timestamps: Some(PassTimestamps { query_set: &queries, first: 0 }),
                trace_timestamps: Some(PassTimestamps { query_set: &queries, first: 2 }),
                ..DdmFrame::new(camera, settings())
            };
            let mut encoder = device.create_command_encoder(&Default::default());
            renderer.encode(queue, &mut encoder, &frame, target).unwrap();
            queue.submit([encoder.finish()]);
        }
    });
    assert!(recorded.is_ok(), "{recorded:?}");
    let mut encoder = device.create_command_encoder(&Default::default());
    let mut encode = |frame: &DdmFrame<'_>, target: &DdmTarget| renderer.encode(queue, &mut encoder, frame, target);
    let wrong_camera = view(40, 25);
    assert!(matches!(
        encode(&DdmFrame::new(&wrong_camera, settings()), &pixels),
        Err(DdmRenderError::SizeMismatch { expected: (40, 24), found: (40, 25), .. })
    ));
    let blind = Camera { target: camera.eye, ..camera };
    assert!(matches!(encode(&DdmFrame::new(&blind, settings()), &pixels), Err(DdmRenderError::InvalidCamera(_))));
    let flat = Camera { half_fov_y: 0.0, ..camera };
    assert!(matches!(encode(&DdmFrame::new(&flat, settings()), &pixels), Err(DdmRenderError::InvalidCamera(_))));
    let dark = RenderSettings { ambient: -1.0, ..settings() };
    assert!(matches!(encode(&DdmFrame::new(&camera, dark), &pixels), Err(DdmRenderError::InvalidSettings(_))));
    let late = DdmFrame {
        trace_timestamps: Some(PassTimestamps { query_set: &queries, first: 3 }),
        ..DdmFrame::new(&camera, settings())
    };
    assert!(matches!(encode(&late, &pixels), Err(DdmRenderError::InvalidTimestamps(_))));
    // A target of another renderer's size.
    let other = setup(8, 8);
    let other_target = other
        .renderer
        .pixel_target(
            &other.device,
            &storage_buffer(&other.device, other.renderer.pixel_bytes(), wgpu::BufferUsages::STORAGE),
        )
        .unwrap();
    assert!(matches!(
        encode(&DdmFrame::new(&camera, settings()), &other_target),
        Err(DdmRenderError::SizeMismatch { expected: (40, 24), found: (8, 8), .. })
    ));
    // Nothing was recorded by the failed frames: the encoder finishes empty and valid.
    let finished = error_scoped(device, || queue.submit([encoder.finish()]));
    assert!(finished.is_ok(), "{finished:?}");
}
