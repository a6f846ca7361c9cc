//! A headless wgpu device for tests, benchmarks and tools, with helpers to run a compute
//! kernel over a slice and read the result back, render offscreen into an
//! [`image::RgbaImage`], and time GPU work with timestamp queries.
//!
//! This crate is never a dependency of the algorithm crates: it serves the GPU tests,
//! the benchmarks and the pipelines beside them.
//!
//! ```no_run
//! let gpu = gpu_harness::Gpu::new()?; // honours GPU_ADAPTER=hardware|software|any
//! println!("running on {}", gpu.describe());
//! # Ok::<(), gpu_harness::HarnessError>(())
//! ```
//!
//! # Adapter choice
//!
//! [`Gpu::new`] prefers a hardware adapter (discrete, then integrated, then virtual) and
//! falls back to a software one (Mesa's lavapipe on Linux). The environment variable
//! [`ADAPTER_ENV`] (`GPU_ADAPTER`) forces the choice: `hardware`, `software` or `any`.
//! Without any adapter the error says to install `mesa-vulkan-drivers`.
//!
//! # Kernel convention
//!
//! [`Gpu::compute_map`] binds, in group 0, a uniform buffer at binding 0, the input
//! array at binding 1 (`var<storage, read>`) and the output array at binding 2
//! (`var<storage, read_write>`), and dispatches a 2-D grid of workgroups of
//! [`WORKGROUP_SIZE`] invocations. A kernel finds its element with
//! `id.x + id.y * num_workgroups.x * WORKGROUP_SIZE` and returns when that is past
//! `arrayLength` of its input. Inputs larger than the adapter's storage-binding limit are
//! split into chunks; each chunk is a separate dispatch over its own buffers.
//!
//! # Warm calls
//!
//! A [`Gpu`] compiles each kernel once: its pipeline is cached (for the device's
//! lifetime), keyed by the WGSL source, the entry point and the number of scene buffers,
//! and every later call with the same three reuses it, so call sites stay one line. Before
//! a pipeline's first timed dispatch, one untimed workgroup runs it into a scratch output
//! (whatever a driver defers to first use stays out of the timing), so every timed
//! dispatch ([`Gpu::compute_map_timed`] and all calls returning a [`GpuTiming`]) is one of
//! a warm pipeline, the first call's included. Scene buffers that several calls bind can
//! be uploaded once ([`Gpu::upload_storage`], then
//! [`Gpu::compute_map_with_uploaded_storage`]); [`Gpu::compute_map_with_storage`] uploads
//! them per call. Timings never include compilation, uploads or readback.

mod bound;
mod compute;
mod context;
mod error;
mod kernel_cache;
mod readback;
mod render;
mod timing;

pub use bound::UploadedStorage;
pub use compute::WORKGROUP_SIZE;
pub use context::{ADAPTER_ENV, AdapterPreference, Gpu, OPTIONAL_FEATURES, error_scoped};
pub use error::HarnessError;
pub use render::RENDER_FORMAT;
pub use timing::{FrameTimes, GpuTiming, TimingSource};
