//! Small wgpu helpers shared by the passes: the error type, error scopes, shader module
//! composition, texture creation and readback.

use std::fmt;

/// Why a GPU pass could not run.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum GpuError {
    /// The request itself is invalid (empty target, zero supersampling, …).
    InvalidRequest(String),
    /// The request exceeds a limit of the adapter.
    TooLarge {
        /// What is too large.
        what: String,
        /// The requested amount.
        requested: u64,
        /// The adapter's limit.
        limit: u64,
    },
    /// wgpu reported a validation or out-of-memory error.
    Wgpu(String),
    /// Mapping a buffer for readback failed.
    Readback(String),
}

impl fmt::Display for GpuError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::InvalidRequest(message) => write!(f, "invalid GPU request: {message}"),
            Self::TooLarge { what, requested, limit } => {
                write!(f, "{what}: {requested} exceeds the adapter's limit {limit}")
            }
            Self::Wgpu(message) => write!(f, "wgpu error: {message}"),
            Self::Readback(message) => write!(f, "GPU readback failed: {message}"),
        }
    }
}

impl std::error::Error for GpuError {}

/// Runs `work` inside validation and out-of-memory error scopes, so that wgpu errors become
/// [`GpuError::Wgpu`] instead of wgpu's default panic; the scopes are serialized with every
/// other user of [`gpu_harness::error_scoped`]. `work` must not call `scoped`.
pub(crate) fn scoped<T>(device: &wgpu::Device, work: impl FnOnce() -> T) -> Result<T, GpuError> {
    gpu_harness::error_scoped(device, work).map_err(|e| match e {
        gpu_harness::HarnessError::Wgpu(message) => GpuError::Wgpu(message),
        other => GpuError::Wgpu(other.to_string()),
    })
}

/// Blocks until the device's queue is idle.
pub(crate) fn wait(device: &wgpu::Device) -> Result<(), GpuError> {
    device.poll(wgpu::PollType::wait_indefinitely()).map(|_| ()).map_err(|e| GpuError::Readback(e.to_string()))
}

/// The WGSL source of a pipeline shader of this crate, composed after the generated
/// declarations.
pub(crate) fn compose(parts: &[&str]) -> String {
    let mut source = String::from(crate::scene::GENERATED_WGSL);
    for part in parts {
        source.push('\n');
        source.push_str(part);
    }
    source
}

/// Checks that a 2-D texture of `width × height × layers` fits the adapter.
pub(crate) fn check_texture_size(
    device: &wgpu::Device,
    what: &str,
    (width, height, layers): (u32, u32, u32),
) -> Result<(), GpuError> {
    if width == 0 || height == 0 || layers == 0 {
        return Err(GpuError::InvalidRequest(format!("{what}: empty size {width}×{height}×{layers}")));
    }
    let limits = device.limits();
    let side = width.max(height);
    if side > limits.max_texture_dimension_2d {
        return Err(GpuError::TooLarge {
            what: format!("{what}: side in texels"),
            requested: u64::from(side),
            limit: u64::from(limits.max_texture_dimension_2d),
        });
    }
    if layers > limits.max_texture_array_layers {
        return Err(GpuError::TooLarge {
            what: format!("{what}: array layers"),
            requested: u64::from(layers),
            limit: u64::from(limits.max_texture_array_layers),
        });
    }
    Ok(())
}

/// Copies `buffer` (with `COPY_SRC`) into a staging buffer, maps it and returns its first
/// `size` bytes. Waits for all submitted work.
pub(crate) fn read_buffer(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    buffer: &wgpu::Buffer,
    size: u64,
) -> Result<Vec<u8>, GpuError> {
    let staging = scoped(device, || {
        let staging = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("grain-impostor readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(buffer, 0, &staging, 0, size);
        queue.submit([encoder.finish()]);
        staging
    })?;
    map_and_read(device, &staging)
}

fn map_and_read(device: &wgpu::Device, staging: &wgpu::Buffer) -> Result<Vec<u8>, GpuError> {
    let (sender, receiver) = std::sync::mpsc::channel();
    let slice = staging.slice(..);
    slice.map_async(wgpu::MapMode::Read, move |result| {
        // A closed channel only means the caller gave up waiting.
        let _ = sender.send(result);
    });
    wait(device)?;
    receiver.recv().map_err(|e| GpuError::Readback(e.to_string()))?.map_err(|e| GpuError::Readback(e.to_string()))?;
    let bytes = slice.get_mapped_range().map_err(|e| GpuError::Readback(e.to_string()))?.to_vec();
    staging.unmap();
    Ok(bytes)
}

/// Reads mip level 0, layer 0 of a 2-D texture with `COPY_SRC` usage, `bytes_per_texel`
/// bytes per texel, as tightly packed rows (top to bottom).
pub(crate) fn read_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    texture: &wgpu::Texture,
    bytes_per_texel: u32,
) -> Result<Vec<u8>, GpuError> {
    let (width, height) = (texture.width(), texture.height());
    let row_bytes = width * bytes_per_texel;
    let padded_row_bytes = row_bytes.next_multiple_of(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT);
    let size = u64::from(padded_row_bytes) * u64::from(height);
    let staging = scoped(device, || {
        let staging = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("grain-impostor texture readback"),
            size,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.copy_texture_to_buffer(
            texture.as_image_copy(),
            wgpu::TexelCopyBufferInfo {
                buffer: &staging,
                layout: wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(padded_row_bytes),
                    rows_per_image: Some(height),
                },
            },
            wgpu::Extent3d { width, height, depth_or_array_layers: 1 },
        );
        queue.submit([encoder.finish()]);
        staging
    })?;
    let padded = map_and_read(device, &staging)?;
    let mut bytes = Vec::with_capacity((row_bytes * height) as usize);
    for row in padded.chunks_exact(padded_row_bytes as usize) {
        bytes.extend_from_slice(&row[..row_bytes as usize]);
    }
    Ok(bytes)
}

/// A bind group layout entry for a texture read with `textureLoad` only (any float format,
/// filterable or not).
pub(crate) fn loaded_texture_entry(binding: u32, dimension: wgpu::TextureViewDimension) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: false },
            view_dimension: dimension,
            multisampled: false,
        },
        count: None,
    }
}

/// A bind group layout entry for a write-only 2-D storage texture of `format`.
pub fn storage_texture_entry(binding: u32, format: wgpu::TextureFormat) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::StorageTexture {
            access: wgpu::StorageTextureAccess::WriteOnly,
            format,
            view_dimension: wgpu::TextureViewDimension::D2,
        },
        count: None,
    }
}

/// A bind group layout entry for a uniform buffer, optionally with a dynamic offset.
pub(crate) fn uniform_entry(
    binding: u32,
    visibility: wgpu::ShaderStages,
    dynamic: bool,
    size: u64,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: dynamic,
            min_binding_size: wgpu::BufferSize::new(size),
        },
        count: None,
    }
}
