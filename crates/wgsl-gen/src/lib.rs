//! Rust is the single source of truth for GPU data: this crate turns the
//! [`gpu_layout`] descriptions of structs and constants into WGSL, composes generated and
//! hand-written WGSL into modules, validates them with naga, and proves that naga's layout
//! of every generated struct equals the Rust layout.
//!
//! ```
//! use gpu_layout::{GpuStruct, gpu_const, gpu_struct};
//! use wgsl_gen::{ComposedShader, StructDecl, check_layout, generate_declarations};
//!
//! gpu_struct! {
//!     /// A particle.
//!     pub struct Particle {
//!         /// Position and radius.
//!         pub position_radius: glam::Vec4,
//!         /// Identifier.
//!         pub id: u32,
//!         /// Explicit padding.
//!         pub padding: [u32; 3],
//!     }
//! }
//! const RADIUS_SCALE: f32 = 0.1;
//!
//! let structs = [StructDecl::of::<Particle>()];
//! let wgsl = generate_declarations("example", &structs, &[gpu_const!(RADIUS_SCALE: f32)]).unwrap();
//! assert!(wgsl.contains("struct Particle {"));
//!
//! let shader = ComposedShader::new("example")
//!     .with_part("generated.wgsl", &wgsl)
//!     .with_part("user.wgsl", "fn scaled(p: Particle) -> f32 { return p.position_radius.w * RADIUS_SCALE; }");
//! let module = shader.validate().unwrap();
//! check_layout(&module.module, &structs).unwrap();
//! ```

mod compose;
mod cost;
mod generate;
mod layout_check;
mod naga_oil;

pub use compose::{ComposedShader, ShaderError, ValidatedModule};
pub use cost::{OperationCount, operation_count};
pub use generate::{GenerateError, generate_declarations, wgsl_float_literal, wgsl_type_name};
pub use gpu_layout::StructDecl;
pub use layout_check::{LayoutMismatch, check_layout};
pub use naga_oil::{naga_oil_header, naga_oil_imports, top_level_items};
