//! IEEE 754 binary16 conversions for the packed layouts: round-to-nearest-even on the way
//! in, exact on the way out (as WGSL's `unpack2x16float`), never a subnormal half. They
//! live in [`gpu_layout::binary16`], shared with the other crates that pack halves.

pub use gpu_layout::binary16::{HALF_MAX, HALF_MIN_POSITIVE, f32_to_half, half_to_f32};
