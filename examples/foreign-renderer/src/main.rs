//! A foreign renderer takes `octahedral-map` alone: it pastes the crate's WGSL twin
//! (`octahedral_map::WGSL`, feature `wgsl`) before its own compute kernel, builds the
//! pipeline with plain wgpu, runs Listing 1's view lookup for every direction of a test set
//! on the GPU and checks each result against the Rust [`OctahedralViews::sample`] — the
//! four view indices exactly, the interpolation coefficients bit for bit (the twin is
//! written to compute the same bits).
//!
//! `cargo run -p foreign-renderer [-- SUBDIVISIONS]` prints the adapter and the number of
//! directions compared, and exits with an error naming the first difference. It uses no
//! other crate of this workspace: no harness, no registry, no pipeline.

use std::process::ExitCode;

use glam::{Vec3, Vec4};
use octahedral_map::{OctahedralViews, ViewSample};
use wgpu::util::DeviceExt;

/// The renderer's own kernel: one direction per invocation, Listing 1 through the crate's
/// `octahedral_view_sample`.
const KERNEL: &str = r"
@group(0) @binding(0) var<uniform> subdivisions: vec4<u32>;
@group(0) @binding(1) var<storage, read> directions: array<vec4<f32>>;
@group(0) @binding(2) var<storage, read_write> samples: array<ViewSample>;

@compute @workgroup_size(64)
fn sample_views(@builtin(global_invocation_id) id: vec3<u32>) {
    if id.x < arrayLength(&directions) {
        samples[id.x] = octahedral_view_sample(directions[id.x].xyz, subdivisions.x);
    }
}
";

/// Directions over the sphere: a Fibonacci spiral, the six axes, the view directions
/// themselves and points exactly between neighbouring views (cell edges), plus the zero
/// vector, NaN and infinities (which the crate maps to defined results).
fn directions(views: OctahedralViews) -> Vec<Vec3> {
    let golden = std::f32::consts::PI * (3.0 - 5.0_f32.sqrt());
    let count = 20_000;
    let mut out: Vec<Vec3> = (0..count)
        .map(|i| {
            let z = 1.0 - 2.0 * (i as f32 + 0.5) / count as f32;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = golden * i as f32;
            Vec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect();
    out.extend([Vec3::X, Vec3::NEG_X, Vec3::Y, Vec3::NEG_Y, Vec3::Z, Vec3::NEG_Z]);
    for index in 0..views.view_count() {
        let Some(d) = views.view_direction(index) else { continue };
        out.push(d);
        if let Some(next) = views.view_direction((index + 1) % views.view_count()) {
            out.push(d + next);
        }
    }
    out.extend([Vec3::ZERO, Vec3::splat(f32::NAN), Vec3::new(f32::INFINITY, -1.0, 0.0), Vec3::splat(1e-40)]);
    out
}

/// Runs the kernel on the first adapter wgpu offers and returns its name and the samples.
fn gpu_samples(views: OctahedralViews, directions: &[Vec3]) -> Result<(String, Vec<ViewSample>), String> {
    let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
    let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions::default()))
        .map_err(|e| format!("no GPU adapter (install a Vulkan driver, e.g. mesa-vulkan-drivers): {e}"))?;
    let name = format!("{} ({:?})", adapter.get_info().name, adapter.get_info().backend);
    let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor::default()))
        .map_err(|e| format!("cannot create a device on {name}: {e}"))?;

    // The crate's WGSL twin (its dependencies first: octahedral-map has none), then ours.
    let mut source = String::new();
    octahedral_map::WGSL.write_source(&mut source).map_err(|e| e.to_string())?;
    source.push_str(KERNEL);
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("foreign renderer"),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("foreign renderer"),
        layout: None,
        module: &module,
        entry_point: Some("sample_views"),
        compilation_options: Default::default(),
        cache: None,
    });

    let inputs: Vec<Vec4> = directions.iter().map(|d| d.extend(0.0)).collect();
    let output_size = (directions.len() * size_of::<ViewSample>()) as u64;
    let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("subdivisions"),
        contents: bytemuck::cast_slice(&[views.subdivisions(), 0, 0, 0]),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let input = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("directions"),
        contents: bytemuck::cast_slice(&inputs),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let output = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("samples"),
        size: output_size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let staging = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("samples readback"),
        size: output_size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("foreign renderer"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry { binding: 0, resource: uniform.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 1, resource: input.as_entire_binding() },
            wgpu::BindGroupEntry { binding: 2, resource: output.as_entire_binding() },
        ],
    });

    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.dispatch_workgroups((directions.len() as u32).div_ceil(64), 1, 1);
    }
    encoder.copy_buffer_to_buffer(&output, 0, &staging, 0, output_size);
    queue.submit([encoder.finish()]);

    let (sender, receiver) = std::sync::mpsc::channel();
    staging.slice(..).map_async(wgpu::MapMode::Read, move |result| {
        // The receiver waits below; a failed send only means it is gone already.
        let _ = sender.send(result);
    });
    device.poll(wgpu::PollType::wait_indefinitely()).map_err(|e| format!("waiting for the GPU: {e}"))?;
    receiver.recv().map_err(|e| e.to_string())?.map_err(|e| format!("mapping the results: {e}"))?;
    let bytes = staging.slice(..).get_mapped_range().map_err(|e| e.to_string())?.to_vec();
    Ok((name, bytemuck::pod_collect_to_vec(&bytes)))
}

fn run() -> Result<(), String> {
    let subdivisions = match std::env::args().nth(1) {
        None => 8,
        Some(text) => text.parse().map_err(|_| format!("SUBDIVISIONS must be a positive integer, not `{text}`"))?,
    };
    let views = OctahedralViews::new(subdivisions)
        .ok_or_else(|| format!("SUBDIVISIONS = {subdivisions} is outside 1..={}", octahedral_map::MAX_SUBDIVISIONS))?;
    let directions = directions(views);
    let (adapter, gpu) = gpu_samples(views, &directions)?;
    println!("adapter: {adapter}");
    for (direction, gpu) in directions.iter().zip(&gpu) {
        let cpu = views.sample(*direction);
        let same = cpu.indices == gpu.indices
            && cpu.alpha.to_array().map(f32::to_bits) == gpu.alpha.to_array().map(f32::to_bits);
        if !same {
            return Err(format!("direction {direction}: CPU {cpu:?}, GPU {gpu:?}"));
        }
    }
    println!(
        "n = {subdivisions}: {} directions, CPU = GPU bit for bit (octahedral_map::WGSL + the renderer's own kernel)",
        gpu.len()
    );
    Ok(())
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("foreign-renderer: {message}");
            ExitCode::FAILURE
        }
    }
}
