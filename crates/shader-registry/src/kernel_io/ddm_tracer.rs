//! The I/O of `ddm_tracer_compute`: one ray per invocation, traced by `trace_ray` into a
//! `ddm_tracer::TraceResult`.

use glam::{Vec3, Vec4};
use gpu_layout::{StructDecl, gpu_struct};

gpu_struct! {
    /// One ray (the input of the compute pass).
    pub struct TraceRay {
        /// Origin in `xyz`, `w` zero.
        pub origin: Vec4,
        /// Direction in `xyz` (any length), `w` zero.
        pub direction: Vec4,
    }
}

impl TraceRay {
    /// The ray `origin + t direction`.
    pub fn new(origin: Vec3, direction: Vec3) -> Self {
        Self { origin: origin.extend(0.0), direction: direction.extend(0.0) }
    }
}

/// The kernel's structs.
pub const STRUCTS: &[StructDecl] = &[StructDecl::of::<TraceRay>()];
