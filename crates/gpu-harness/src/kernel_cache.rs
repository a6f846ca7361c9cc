//! The compiled kernels a [`Gpu`](crate::Gpu) keeps for its lifetime, so that a timed
//! dispatch is a warm one.

use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, AtomicUsize};
use std::sync::{Arc, Mutex, PoisonError};

/// A compiled kernel and its explicit bind group layout (cheap to clone: wgpu handles).
#[derive(Clone, Debug)]
pub(crate) struct Kernel {
    pub(crate) pipeline: wgpu::ComputePipeline,
    pub(crate) layout: wgpu::BindGroupLayout,
    /// Whether the pipeline has been dispatched (warmed up) once; shared by the clones.
    pub(crate) warm: Arc<AtomicBool>,
}

impl Kernel {
    /// A kernel that has not been dispatched yet.
    pub(crate) fn new(pipeline: wgpu::ComputePipeline, layout: wgpu::BindGroupLayout) -> Self {
        Self { pipeline, layout, warm: Arc::new(AtomicBool::new(false)) }
    }
}

/// What decides a kernel's pipeline: the WGSL source, the entry point, the number of
/// scene buffers bound at `3..` (the bind group layout) and the pipeline-overridable
/// constants with their values' bits.
pub(crate) type KernelKey = (String, String, usize, Vec<(String, u64)>);

/// The kernels a [`Gpu`] has compiled, kept for its lifetime: pipelines are never
/// evicted (a process compiles a bounded set of kernels; each entry is a pipeline and its
/// source text). Behind a mutex because the device is shared between threads (tests).
#[derive(Default)]
pub(crate) struct KernelCache {
    pub(crate) kernels: Mutex<HashMap<KernelKey, Kernel>>,
    /// How many kernels were compiled (cache misses that succeeded), for the unit tests.
    pub(crate) compilations: AtomicUsize,
    /// How many warm-up dispatches ran (one per compiled kernel that was then dispatched).
    pub(crate) warm_ups: AtomicUsize,
}

impl std::fmt::Debug for KernelCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let kernels = self.kernels.lock().unwrap_or_else(PoisonError::into_inner).len();
        f.debug_struct("KernelCache").field("kernels", &kernels).finish()
    }
}
