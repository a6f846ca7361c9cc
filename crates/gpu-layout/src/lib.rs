//! Describe GPU-facing data once, in Rust, so that its WGSL twin can be generated.
//!
//! An algorithm crate declares its GPU structs with [`gpu_struct!`] and lists its
//! constants with [`gpu_const!`]. The macro emits an ordinary `#[repr(C)]`,
//! [`bytemuck::Pod`] struct *and* a [`GpuStruct`] description of it: field names,
//! Rust byte offsets (`core::mem::offset_of!`) and WGSL types. The `wgsl-gen` crate turns
//! that description into WGSL declarations, and checks with naga that the WGSL layout of
//! every generated struct equals the Rust layout, field by field.
//!
//! This crate is `no_std` and has no dependency besides glam and bytemuck, so algorithm
//! crates can use it without pulling in a shader compiler.
//!
//! ```
//! use gpu_layout::{GpuStruct, WgslType, gpu_struct};
//! use glam::{UVec4, Vec2};
//!
//! gpu_struct! {
//!     /// Four indices and two weights.
//!     pub struct Sample {
//!         /// Indices.
//!         pub indices: UVec4,
//!         /// Weights.
//!         pub weights: Vec2,
//!         /// Explicit padding to the 16-byte WGSL struct alignment.
//!         pub padding: Vec2,
//!     }
//! }
//!
//! assert_eq!(Sample::WGSL_NAME, "Sample");
//! assert_eq!(Sample::FIELDS[1].offset, 16);
//! assert_eq!((Sample::FIELDS[0].ty)(), WgslType::Vector(4, gpu_layout::Scalar::U32));
//! ```
//!
//! # Why there is no `vec3`
//!
//! [`WgslTyped`] is deliberately not implemented for 3-component vectors: a WGSL
//! `vec3<f32>` is 12 bytes but 16-byte aligned in storage and uniform buffers, the classic
//! trap where Rust and WGSL silently disagree. Store a `Vec4` (or a `Vec3` plus an explicit
//! scalar) instead.
//!
//! # A crate's WGSL twin
//!
//! [`WgslModule`] is how an algorithm crate exports its WGSL twin (behind the crate's
//! `wgsl` feature): generated declarations, hand-written library, the modules to compose
//! first, and the same text as a `naga_oil` composable module.
//!
//! # Features
//!
//! - `std` (default): enables `std` in glam, and `alloc`.
//! - `alloc`: [`WgslModule::source`], the composed source as a `String`.
#![no_std]

#[cfg(feature = "alloc")]
extern crate alloc;

pub mod binary16;
pub mod f32_bits;
mod module;
mod wgsl_type;

pub use module::{StructDecl, WgslModule};
pub use wgsl_type::{Scalar, WgslType, WgslTyped};

/// One field of a [`GpuStruct`]: its name, Rust byte offset and WGSL type.
#[derive(Clone, Copy, Debug)]
pub struct GpuField {
    /// Field name, identical in Rust and WGSL.
    pub name: &'static str,
    /// Byte offset of the field in the Rust struct (`core::mem::offset_of!`).
    pub offset: usize,
    /// Byte size of the field's Rust type (`core::mem::size_of`).
    pub size: usize,
    /// The field's WGSL type (a function so that array element types can be nested).
    pub ty: fn() -> WgslType,
}

/// A `#[repr(C)]` struct that is shared with WGSL. Implemented by [`gpu_struct!`].
pub trait GpuStruct: bytemuck::Pod {
    /// The struct's name in WGSL (the Rust identifier).
    const WGSL_NAME: &'static str;
    /// The fields, in declaration order.
    const FIELDS: &'static [GpuField];
}

/// The value of a constant shared with WGSL.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GpuConstValue {
    /// A `u32` constant.
    U32(u32),
    /// An `i32` constant.
    I32(i32),
    /// An `f32` constant; emitted as an exact hexadecimal float literal.
    F32(f32),
    /// A `vec3<f32>` constant (a value, not a storage layout, so `vec3` is safe here).
    Vec3F32([f32; 3]),
}

/// A named constant shared with WGSL. Build it with [`gpu_const!`], or with
/// [`gpu_override!`] for a pipeline-overridable one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GpuConst {
    /// Constant name, identical in Rust and WGSL.
    pub name: &'static str,
    /// Its value, read from the Rust constant itself; the default of an overridable one.
    pub value: GpuConstValue,
    /// Whether WGSL declares it `override` (a pipeline-overridable constant that a pipeline
    /// sets at creation, `wgpu::PipelineCompilationOptions::constants`, keyed by
    /// [`name`](Self::name); the driver then compiles each setting as its own kernel)
    /// rather than `const`.
    pub overridable: bool,
}

impl GpuConst {
    /// The pipeline constant that sets this overridable constant to `value`:
    /// `(name, value)`, as `wgpu::PipelineCompilationOptions::constants` takes it.
    pub fn set(&self, value: f64) -> (&'static str, f64) {
        (self.name, value)
    }
}

/// Describes a Rust `const` for WGSL generation: `gpu_const!(NAME: u32)`, or
/// `gpu_const!(NAME: u32 as "WGSL_NAME")` to give it a (prefixed) WGSL name, since WGSL has
/// a single global namespace.
///
/// The type must be `u32`, `i32`, `f32` or `Vec3` (glam) and must match the constant's Rust type (a
/// mismatch does not compile).
///
/// ```
/// const LIMIT: u32 = 7;
/// let c = gpu_layout::gpu_const!(LIMIT: u32);
/// assert_eq!(c.name, "LIMIT");
/// assert_eq!(c.value, gpu_layout::GpuConstValue::U32(7));
/// let c = gpu_layout::gpu_const!(LIMIT: u32 as "MY_LIMIT");
/// assert_eq!(c.name, "MY_LIMIT");
/// ```
///
/// A value that has no Rust constant of its own (a bit mask, `f32::MAX`, `TAU`) is named
/// directly: `gpu_const!("WGSL_NAME": f32 = f32::MAX)`.
///
/// ```
/// let c = gpu_layout::gpu_const!("MY_ABS_MASK": u32 = !(1_u32 << 31));
/// assert_eq!(c.value, gpu_layout::GpuConstValue::U32(0x7fff_ffff));
/// ```
#[macro_export]
macro_rules! gpu_const {
    ($wgsl:literal : u32 = $value:expr) => {
        $crate::GpuConst { name: $wgsl, value: $crate::GpuConstValue::U32($value), overridable: false }
    };
    ($wgsl:literal : i32 = $value:expr) => {
        $crate::GpuConst { name: $wgsl, value: $crate::GpuConstValue::I32($value), overridable: false }
    };
    ($wgsl:literal : f32 = $value:expr) => {
        $crate::GpuConst { name: $wgsl, value: $crate::GpuConstValue::F32($value), overridable: false }
    };
    ($name:ident : $ty:ident as $wgsl:literal) => {
        $crate::GpuConst { name: $wgsl, ..$crate::gpu_const!($name: $ty) }
    };
    ($name:ident : u32) => {
        $crate::GpuConst { name: stringify!($name), value: $crate::GpuConstValue::U32($name), overridable: false }
    };
    ($name:ident : i32) => {
        $crate::GpuConst { name: stringify!($name), value: $crate::GpuConstValue::I32($name), overridable: false }
    };
    ($name:ident : f32) => {
        $crate::GpuConst { name: stringify!($name), value: $crate::GpuConstValue::F32($name), overridable: false }
    };
    ($name:ident : Vec3) => {
        $crate::GpuConst {
            name: stringify!($name),
            value: $crate::GpuConstValue::Vec3F32([$name.x, $name.y, $name.z]),
            overridable: false,
        }
    };
}

/// Describes a pipeline-overridable WGSL constant (`override NAME: T = default;`), with the
/// forms of [`gpu_const!`]: the default is a Rust constant or a value, and the WGSL name is
/// the one a pipeline sets ([`GpuConst::set`]). The type must be `u32`, `i32` or `f32`
/// (WGSL overrides are scalars).
///
/// A kernel branching on an overridable constant is specialised when its pipeline is
/// created: each setting compiles to its own code, without the branch.
///
/// ```
/// const DEFAULT_MODE: u32 = 1;
/// const MODE: gpu_layout::GpuConst = gpu_layout::gpu_override!(DEFAULT_MODE: u32 as "MY_MODE");
/// assert!(MODE.overridable);
/// assert_eq!((MODE.name, MODE.value), ("MY_MODE", gpu_layout::GpuConstValue::U32(1)));
/// assert_eq!(MODE.set(2.0), ("MY_MODE", 2.0));
/// ```
#[macro_export]
macro_rules! gpu_override {
    ($($constant:tt)*) => {
        $crate::GpuConst { overridable: true, ..$crate::gpu_const!($($constant)*) }
    };
}

/// Declares a `#[repr(C)]`, `Pod` struct and its [`GpuStruct`] description.
///
/// Field types must implement [`WgslTyped`] (scalars, glam 2- and 4-vectors, arrays of
/// them). The struct derives `Clone, Copy, Debug, PartialEq, Pod, Zeroable`; `Pod` rejects
/// implicit padding at compile time, so every padding byte is an explicit field. The
/// caller's crate must depend on `bytemuck` (with its `derive` feature).
#[macro_export]
macro_rules! gpu_struct {
    (
        $(#[$attr:meta])*
        $vis:vis struct $name:ident {
            $( $(#[$field_attr:meta])* $field_vis:vis $field:ident : $ty:ty ),* $(,)?
        }
    ) => {
        $(#[$attr])*
        #[repr(C)]
        #[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
        $vis struct $name {
            $( $(#[$field_attr])* $field_vis $field: $ty ),*
        }

        impl $crate::GpuStruct for $name {
            const WGSL_NAME: &'static str = stringify!($name);
            const FIELDS: &'static [$crate::GpuField] = &[
                $( $crate::GpuField {
                    name: stringify!($field),
                    offset: ::core::mem::offset_of!($name, $field),
                    size: ::core::mem::size_of::<$ty>(),
                    ty: <$ty as $crate::WgslTyped>::wgsl_type,
                } ),*
            ];
        }
    };
}
