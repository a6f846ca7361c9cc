//! Adapter choice and device creation.

use crate::HarnessError;
use crate::kernel_cache::KernelCache;

/// The environment variable that forces the adapter choice: `hardware`, `software` or
/// `any` (the default: hardware if there is one, else software).
pub const ADAPTER_ENV: &str = "GPU_ADAPTER";

/// Which kind of adapter to use.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AdapterPreference {
    /// A GPU (discrete, integrated or virtual); fail if there is none.
    Hardware,
    /// A CPU implementation such as lavapipe; fail if there is none.
    Software,
    /// The best adapter there is, hardware first.
    Any,
}

impl AdapterPreference {
    /// Reads [`ADAPTER_ENV`]; unset or empty means [`AdapterPreference::Any`].
    pub fn from_env() -> Result<Self, HarnessError> {
        match std::env::var(ADAPTER_ENV) {
            Err(_) => Ok(Self::Any),
            Ok(value) => match value.trim().to_ascii_lowercase().as_str() {
                "" | "any" => Ok(Self::Any),
                "hardware" | "hw" | "gpu" => Ok(Self::Hardware),
                "software" | "sw" | "cpu" => Ok(Self::Software),
                _ => Err(HarnessError::BadPreference(value)),
            },
        }
    }

    fn accepts(self, device_type: wgpu::DeviceType) -> bool {
        let software = device_type == wgpu::DeviceType::Cpu;
        match self {
            Self::Hardware => !software,
            Self::Software => software,
            Self::Any => true,
        }
    }

    fn describe(self) -> &'static str {
        match self {
            Self::Hardware => "hardware",
            Self::Software => "software",
            Self::Any => "usable",
        }
    }
}

/// The features [`Gpu::new`] enables whenever the adapter has them.
pub const OPTIONAL_FEATURES: wgpu::Features = wgpu::Features::TIMESTAMP_QUERY
    .union(wgpu::Features::SHADER_INT64)
    .union(wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX);

/// Lower is better.
fn rank(device_type: wgpu::DeviceType) -> u8 {
    match device_type {
        wgpu::DeviceType::DiscreteGpu => 0,
        wgpu::DeviceType::IntegratedGpu => 1,
        wgpu::DeviceType::VirtualGpu => 2,
        wgpu::DeviceType::Other => 3,
        wgpu::DeviceType::Cpu => 4,
    }
}

fn describe_info(info: &wgpu::AdapterInfo) -> String {
    format!("{} ({:?}, {:?}, driver {} {})", info.name, info.backend, info.device_type, info.driver, info.driver_info)
}

/// A headless device and queue on the chosen adapter.
///
/// It keeps every compute kernel it compiles (see [`Gpu::compute_map`]), keyed by the WGSL
/// source, the entry point and the number of scene buffers, so that calling a kernel again
/// reuses its pipeline: a timed call after the first one times a warm pipeline.
#[derive(Debug)]
pub struct Gpu {
    /// The adapter.
    pub adapter: wgpu::Adapter,
    /// The device, created with all of the adapter's limits.
    pub device: wgpu::Device,
    /// The device's queue.
    pub queue: wgpu::Queue,
    info: wgpu::AdapterInfo,
    /// The compiled kernels of this device.
    pub(crate) kernels: KernelCache,
}

impl Gpu {
    /// A device on the adapter chosen by [`ADAPTER_ENV`] (hardware first by default).
    pub fn new() -> Result<Self, HarnessError> {
        Self::with_preference(AdapterPreference::from_env()?, wgpu::Features::empty())
    }

    /// A device on the best adapter accepted by `preference`, with `features` (which the
    /// adapter must support) plus timestamp queries when the adapter has them.
    pub fn with_preference(preference: AdapterPreference, features: wgpu::Features) -> Result<Self, HarnessError> {
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapters = pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()));
        let available: Vec<String> = adapters.iter().map(|a| describe_info(&a.get_info())).collect();
        let adapter = adapters
            .into_iter()
            // wgpu's noop backend (enabled by `WGPU_NOOP_BACKEND=1` where compiled in) runs
            // nothing: never an adapter to test or measure on.
            .filter(|a| a.get_info().backend != wgpu::Backend::Noop)
            .filter(|a| preference.accepts(a.get_info().device_type))
            .filter(|a| a.features().contains(features))
            .min_by_key(|a| rank(a.get_info().device_type))
            .ok_or_else(|| HarnessError::NoAdapter { wanted: preference.describe().to_owned(), available })?;
        Self::on_adapter(adapter, features)
    }

    /// A device on `adapter` with `features` plus, when the adapter has them,
    /// [`OPTIONAL_FEATURES`]: timestamp queries and 64-bit integers with atomic min/max (the
    /// grain splitter's 64-bit occluder map).
    pub(crate) fn on_adapter(adapter: wgpu::Adapter, features: wgpu::Features) -> Result<Self, HarnessError> {
        let optional = OPTIONAL_FEATURES & adapter.features();
        let descriptor = wgpu::DeviceDescriptor {
            label: Some("gpu-harness"),
            required_features: features | optional,
            required_limits: adapter.limits(),
            ..Default::default()
        };
        let (device, queue) = pollster::block_on(adapter.request_device(&descriptor))
            .map_err(|e| HarnessError::RequestDevice(e.to_string()))?;
        let info = adapter.get_info();
        Ok(Self { adapter, device, queue, info, kernels: KernelCache::default() })
    }

    /// The adapter's information.
    pub fn adapter_info(&self) -> &wgpu::AdapterInfo {
        &self.info
    }

    /// One line naming the adapter, its backend, type and driver.
    pub fn describe(&self) -> String {
        describe_info(&self.info)
    }

    /// Whether the adapter is a software implementation.
    pub fn is_software(&self) -> bool {
        self.info.device_type == wgpu::DeviceType::Cpu
    }

    /// The device's limits (the adapter's own).
    pub fn limits(&self) -> wgpu::Limits {
        self.device.limits()
    }

    /// Whether GPU timestamp queries are available.
    pub fn has_timestamps(&self) -> bool {
        self.device.features().contains(wgpu::Features::TIMESTAMP_QUERY)
    }

    /// Runs `work` inside a validation and out-of-memory error scope, turning wgpu's
    /// errors into [`HarnessError::Wgpu`] instead of its default panic (see
    /// [`error_scoped`]).
    pub fn scoped<T>(&self, work: impl FnOnce() -> T) -> Result<T, HarnessError> {
        error_scoped(&self.device, work)
    }

    /// Blocks until the queue is idle.
    pub fn wait(&self) -> Result<(), HarnessError> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| HarnessError::Readback(e.to_string()))
    }
}

/// Serializes the error scopes of [`error_scoped`]: they form one stack per device, shared by
/// every thread that uses it (tests run on several threads), so pushes and pops of two
/// threads must not interleave. Never held across nested calls.
static SCOPE_LOCK: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// Runs `work` inside validation and out-of-memory error scopes on `device`, so that wgpu
/// errors become [`HarnessError::Wgpu`] instead of wgpu's default panic. One process-wide
/// lock serializes the scopes of every caller (this crate, the pipeline crates); `work` must
/// not call `error_scoped` itself.
pub fn error_scoped<T>(device: &wgpu::Device, work: impl FnOnce() -> T) -> Result<T, HarnessError> {
    // A panic while holding the lock leaves no scope pushed, so a poisoned lock is safe.
    let _guard = SCOPE_LOCK.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    let validation = device.push_error_scope(wgpu::ErrorFilter::Validation);
    let memory = device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
    let value = work();
    let memory_error = pollster::block_on(memory.pop());
    let validation_error = pollster::block_on(validation.pop());
    match validation_error.or(memory_error) {
        Some(e) => Err(HarnessError::Wgpu(e.to_string())),
        None => Ok(value),
    }
}
