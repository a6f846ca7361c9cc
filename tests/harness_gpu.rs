//! Tests of the GPU harness itself: chunking, errors, offscreen rendering, timing.

use gpu_harness::{HarnessError, TimingSource};
use integration_tests::gpu;

const DOUBLE_KERNEL: &str = "
@group(0) @binding(0) var<uniform> factor: vec4<u32>;
@group(0) @binding(1) var<storage, read> input: array<u32>;
@group(0) @binding(2) var<storage, read_write> output: array<u32>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = id.x + id.y * groups.x * 64u;
    if index >= arrayLength(&input) {
        return;
    }
    output[index] = input[index] * factor.x + index;
}
";

#[test]
fn compute_map_covers_every_element_across_chunks() {
    let inputs: Vec<u32> = (0..200_003).collect();
    let factor = [3_u32, 0, 0, 0];
    let whole: Vec<u32> = gpu().compute_map(DOUBLE_KERNEL, "main", bytemuck::bytes_of(&factor), &inputs).unwrap();
    assert_eq!(whole, inputs.iter().map(|&x| x * 3 + x).collect::<Vec<_>>());
    let (chunked, _): (Vec<u32>, _) =
        gpu().compute_map_in_chunks(DOUBLE_KERNEL, "main", bytemuck::bytes_of(&factor), &inputs, 10_000).unwrap();
    // The kernel sees chunk-local indices, so the index term restarts at each chunk.
    let expected: Vec<u32> = inputs.iter().map(|&x| x * 3 + x % 10_000).collect();
    assert_eq!(chunked, expected);
    let empty: Vec<u32> = gpu().compute_map(DOUBLE_KERNEL, "main", &[], &[] as &[u32]).unwrap();
    assert!(empty.is_empty());
}

#[test]
fn impossible_requests_are_errors() {
    let huge_uniforms = vec![0_u8; gpu().limits().max_uniform_buffer_binding_size as usize + 16];
    let result = gpu().compute_map::<u32, u32>(DOUBLE_KERNEL, "main", &huge_uniforms, &[1]);
    assert!(matches!(result, Err(HarnessError::TooLarge { .. })), "{result:?}");
    let result = gpu().compute_map::<(), u32>(DOUBLE_KERNEL, "main", &[], &[()]);
    assert!(matches!(result, Err(HarnessError::InvalidRequest(_))), "{result:?}");
    let side = gpu().limits().max_texture_dimension_2d + 1;
    let result = gpu().render_to_image(GRADIENT, "vs", "fs", (side, 1), 3);
    assert!(matches!(result, Err(HarnessError::TooLarge { .. })), "{result:?}");
    let result = gpu().compute_map::<u32, u32>("fn broken(", "main", &[], &[1]);
    assert!(matches!(result, Err(HarnessError::Wgpu(_))), "{result:?}");
}

const GRADIENT: &str = "
@vertex
fn vs(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    return vec4<f32>(uv * 2.0 - 1.0, 0.0, 1.0);
}

@fragment
fn fs(@builtin(position) p: vec4<f32>) -> @location(0) vec4<f32> {
    return vec4<f32>(floor(p.x) / 255.0, floor(p.y) / 255.0, 0.5, 1.0);
}
";

#[test]
fn render_to_image_reads_back_unpadded_rows() {
    // 70 × 3 pixels: 280-byte rows are padded to 512 bytes in the readback buffer.
    let image = gpu().render_to_image(GRADIENT, "vs", "fs", (70, 3), 3).unwrap();
    assert_eq!(image.dimensions(), (70, 3));
    for (x, y, pixel) in image.enumerate_pixels() {
        assert_eq!(pixel.0, [x as u8, y as u8, 128, 255], "pixel ({x}, {y})");
    }
}

#[test]
fn timing_reports_its_source() {
    let inputs: Vec<u32> = (0..1_000_000).collect();
    let (_, timing) =
        gpu().compute_map_timed::<u32, u32>(DOUBLE_KERNEL, "main", bytemuck::bytes_of(&[1_u32; 4]), &inputs).unwrap();
    let expected = if gpu().has_timestamps() { TimingSource::Timestamps } else { TimingSource::WallClock };
    assert_eq!(timing.source, expected);
    assert!(timing.seconds > 0.0 && timing.seconds < 60.0, "{timing}");
    println!("1M-element kernel: {timing}");
}

const SCENE_KERNEL: &str = "
@group(0) @binding(0) var<uniform> factor: vec4<u32>;
@group(0) @binding(1) var<storage, read> input: array<u32>;
@group(0) @binding(2) var<storage, read_write> output: array<u32>;
@group(0) @binding(3) var<storage, read> offsets: array<u32>;

@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>, @builtin(num_workgroups) groups: vec3<u32>) {
    let index = id.x + id.y * groups.x * 64u;
    if index >= arrayLength(&input) {
        return;
    }
    output[index] = input[index] * factor.x + offsets[index % arrayLength(&offsets)];
}
";

#[test]
fn repeated_calls_reuse_the_kernel_and_bind_their_own_buffers() {
    // The harness caches the kernel after the first call (its unit tests count the
    // compilations); here every later call must still see its own uniforms, inputs and
    // storage buffers.
    let gpu = gpu();
    let offsets: Vec<u32> = (0..37).map(|k| k * 1000).collect();
    let uploaded = gpu.upload_storage(&[bytemuck::cast_slice(&offsets)]).unwrap();
    let expected = |inputs: &[u32], factor: u32| -> Vec<u32> {
        inputs.iter().enumerate().map(|(i, &x)| x * factor + offsets[i % offsets.len()]).collect()
    };
    let mut walls = Vec::new();
    for (call, (count, factor)) in
        [(300_000_usize, 3_u32), (300_000, 5), (1_000, 7), (300_000, 2)].into_iter().enumerate()
    {
        let inputs: Vec<u32> = (0..count as u32).map(|x| x ^ 0x55).collect();
        let uniforms = [factor, 0, 0, 0];
        let started = std::time::Instant::now();
        let (outputs, timing): (Vec<u32>, _) = gpu
            .compute_map_with_uploaded_storage(SCENE_KERNEL, "main", bytemuck::bytes_of(&uniforms), &inputs, &uploaded)
            .unwrap();
        walls.push((count, started.elapsed().as_secs_f64() * 1e3, timing));
        assert_eq!(outputs, expected(&inputs, factor), "call {call}");
        // Uploading per call gives the same outputs.
        let (per_call, _): (Vec<u32>, _) = gpu
            .compute_map_with_storage(
                SCENE_KERNEL,
                "main",
                bytemuck::bytes_of(&uniforms),
                &inputs,
                &[bytemuck::cast_slice(&offsets)],
            )
            .unwrap();
        assert_eq!(per_call, outputs, "call {call}");
    }
    for (call, (count, wall, timing)) in walls.iter().enumerate() {
        let kind = if call == 0 { "first (compiles the kernel)" } else { "warm" };
        println!("call {call}, {count} elements, {kind}: whole call {wall:.2} ms, dispatch {timing}");
    }
    let result = gpu.upload_storage(&[&[]]);
    assert!(matches!(result, Err(HarnessError::InvalidRequest(ref m)) if m.contains("storage buffer 3")), "{result:?}");
}
