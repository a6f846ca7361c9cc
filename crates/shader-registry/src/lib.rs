//! The project's WGSL modules and where each piece comes from.
//!
//! Every algorithm crate with a WGSL twin has one [`ShaderModule`] here:
//!
//! - its **generated** declarations, `shaders/generated/<name>.wgsl`, written by
//!   `cargo xtask codegen` from the crate's [`gpu_layout`] structs and constants;
//! - its **hand-written** library, `shaders/<name>.wgsl`, the WGSL twin of the crate's
//!   functions;
//! - its **kernels**, `shaders/kernels/*.wgsl`, entry points used by the GPU tests and
//!   benchmarks.
//!
//! The sources are embedded with `include_str!`, so binaries need no repository at run
//! time. The crate's tests parse and validate every composed module with naga, check that
//! the naga layout of each generated struct equals its Rust layout, and check that the
//! committed generated files are fresh.
//!
//! ```
//! let module = shader_registry::module("octahedral_map").unwrap();
//! let shader = module.with_kernel("octahedral_map_differential").unwrap();
//! assert!(shader.source().contains("fn octahedral_view_sample"));
//! ```

use gpu_layout::GpuConst;
use wgsl_gen::{ComposedShader, GenerateError, StructDecl, generate_declarations};

/// A WGSL source file of the repository.
#[derive(Clone, Copy, Debug)]
pub struct WgslFile {
    /// Path relative to the workspace root.
    pub path: &'static str,
    /// Contents, embedded at build time.
    pub source: &'static str,
}

/// One WGSL module: generated declarations, hand-written library and kernels.
#[derive(Clone, Copy, Debug)]
pub struct ShaderModule {
    /// Module name (the crate name with underscores).
    pub name: &'static str,
    /// The committed generated declarations.
    pub generated: WgslFile,
    /// The hand-written library.
    pub library: WgslFile,
    /// Kernels that compose with the library.
    pub kernels: &'static [WgslFile],
    /// The Rust structs that the generated file declares.
    pub structs: fn() -> Vec<StructDecl>,
    /// The Rust constants that the generated file declares.
    pub constants: &'static [GpuConst],
}

macro_rules! wgsl_file {
    ($path:literal) => {
        WgslFile { path: $path, source: include_str!(concat!("../../../", $path)) }
    };
}

static MODULES: &[ShaderModule] = &[
    ShaderModule {
        name: "octahedral_map",
        generated: wgsl_file!("shaders/generated/octahedral_map.wgsl"),
        library: wgsl_file!("shaders/octahedral_map.wgsl"),
        kernels: &[
            wgsl_file!("shaders/kernels/octahedral_map_differential.wgsl"),
            wgsl_file!("shaders/kernels/impostor_sampling_differential.wgsl"),
        ],
        structs: || {
            vec![
                StructDecl::of::<octahedral_map::ViewSample>(),
                StructDecl::of::<octahedral_map::OctahedralUniforms>(),
                StructDecl::of::<octahedral_map::ImpostorSamplingUniforms>(),
                StructDecl::of::<octahedral_map::ImpostorRayQuery>(),
                StructDecl::of::<octahedral_map::ImpostorSample>(),
            ]
        },
        constants: octahedral_map::gpu::WGSL_CONSTANTS,
    },
    ShaderModule {
        name: "quadric_fit",
        generated: wgsl_file!("shaders/generated/quadric_fit.wgsl"),
        library: wgsl_file!("shaders/quadric_fit.wgsl"),
        kernels: &[wgsl_file!("shaders/kernels/quadric_fit_differential.wgsl")],
        structs: || {
            vec![StructDecl::of::<quadric_fit::GpuQuadric>(), StructDecl::of::<quadric_fit::gpu::QuadricRayQuery>()]
        },
        constants: quadric_fit::gpu::WGSL_CONSTANTS,
    },
    ShaderModule {
        name: "ddm_compress",
        generated: wgsl_file!("shaders/generated/ddm_compress.wgsl"),
        library: wgsl_file!("shaders/ddm_compress.wgsl"),
        kernels: &[wgsl_file!("shaders/kernels/ddm_compress_differential.wgsl")],
        structs: || vec![StructDecl::of::<ddm_compress::gpu::CompressedMapUniforms>()],
        constants: ddm_compress::gpu::WGSL_CONSTANTS,
    },
    ShaderModule {
        name: "abuffer_mask",
        generated: wgsl_file!("shaders/generated/abuffer_mask.wgsl"),
        library: wgsl_file!("shaders/abuffer_mask.wgsl"),
        kernels: &[wgsl_file!("shaders/kernels/abuffer_mask_differential.wgsl")],
        structs: || vec![StructDecl::of::<abuffer_mask::MaskTableUniforms>()],
        constants: abuffer_mask::gpu::WGSL_CONSTANTS,
    },
    ShaderModule {
        name: "smith_micro",
        generated: wgsl_file!("shaders/generated/smith_micro.wgsl"),
        library: wgsl_file!("shaders/smith_micro.wgsl"),
        kernels: &[
            wgsl_file!("shaders/kernels/smith_micro_differential.wgsl"),
            wgsl_file!("shaders/kernels/smith_micro_corrected_differential.wgsl"),
            wgsl_file!("shaders/kernels/smith_micro_correlated_differential.wgsl"),
            wgsl_file!("shaders/kernels/smith_micro_cubic_differential.wgsl"),
        ],
        structs: || {
            vec![
                StructDecl::of::<smith_micro::gpu::SmithCase>(),
                StructDecl::of::<smith_micro::gpu::SmithResults>(),
                StructDecl::of::<smith_micro::LambdaCorrection>(),
                StructDecl::of::<smith_micro::gpu::CorrectionCase>(),
                StructDecl::of::<smith_micro::gpu::CorrectionResults>(),
                StructDecl::of::<smith_micro::VisibilityCorrection>(),
                StructDecl::of::<smith_micro::gpu::CorrelatedCase>(),
                StructDecl::of::<smith_micro::gpu::CorrelatedResults>(),
                StructDecl::of::<smith_micro::CubicLambdaCorrection>(),
                StructDecl::of::<smith_micro::gpu::CubicCase>(),
                StructDecl::of::<smith_micro::gpu::CubicResults>(),
            ]
        },
        constants: smith_micro::gpu::WGSL_CONSTANTS,
    },
    ShaderModule {
        name: "ddm_tracer",
        generated: wgsl_file!("shaders/generated/ddm_tracer.wgsl"),
        library: wgsl_file!("shaders/ddm_tracer.wgsl"),
        kernels: &[wgsl_file!("shaders/kernels/ddm_tracer_compute.wgsl")],
        structs: || {
            vec![
                StructDecl::of::<ddm_tracer::gpu::TracePatch>(),
                StructDecl::of::<ddm_tracer::gpu::TraceUniforms>(),
                StructDecl::of::<ddm_tracer::gpu::TraceConeMap>(),
                StructDecl::of::<ddm_tracer::gpu::TraceRay>(),
                StructDecl::of::<ddm_tracer::gpu::TraceResult>(),
            ]
        },
        constants: ddm_tracer::gpu::WGSL_CONSTANTS,
    },
    ShaderModule {
        name: "ddm_render",
        generated: wgsl_file!("shaders/generated/ddm_render.wgsl"),
        library: wgsl_file!("shaders/ddm_render.wgsl"),
        kernels: &[],
        structs: || {
            vec![
                StructDecl::of::<ddm_tracer::tangent_space::BaseGBufferTexel>(),
                StructDecl::of::<ddm_tracer::tangent_space::BaseRenderParams>(),
                StructDecl::of::<ddm_tracer::tangent_space::BaseRenderPixel>(),
            ]
        },
        constants: ddm_tracer::tangent_space::WGSL_CONSTANTS,
    },
];

/// Modules whose library calls other modules' functions: the generated declarations and
/// library of each listed dependency are composed before the module's own, in order.
static DEPENDENCIES: &[(&str, &[&str])] =
    &[("ddm_tracer", &["quadric_fit", "ddm_compress"]), ("ddm_render", &["quadric_fit", "ddm_compress", "ddm_tracer"])];

/// The modules that `name`'s library builds on (see [`ShaderModule::library_shader`]).
pub fn dependencies(name: &str) -> &'static [&'static str] {
    DEPENDENCIES.iter().find(|(module, _)| *module == name).map_or(&[], |(_, deps)| deps)
}

/// All modules.
pub fn modules() -> &'static [ShaderModule] {
    MODULES
}

/// The module called `name`.
pub fn module(name: &str) -> Option<&'static ShaderModule> {
    MODULES.iter().find(|m| m.name == name)
}

impl ShaderModule {
    /// The generated declarations as the Rust source says they should be now.
    pub fn generate(&self) -> Result<String, GenerateError> {
        generate_declarations(self.name, &(self.structs)(), self.constants)
    }

    /// The committed generated declarations followed by the library, after those of the
    /// modules it depends on ([`dependencies`]).
    pub fn library_shader(&self) -> ComposedShader {
        let mut shader = ComposedShader::new(format!("{}.composed", self.name));
        for dependency in dependencies(self.name).iter().filter_map(|name| module(name)) {
            shader = shader
                .with_part(dependency.generated.path, dependency.generated.source)
                .with_part(dependency.library.path, dependency.library.source);
        }
        shader.with_part(self.generated.path, self.generated.source).with_part(self.library.path, self.library.source)
    }

    /// The library composed with the kernel file whose stem is `kernel`
    /// (`shaders/kernels/<kernel>.wgsl`).
    pub fn with_kernel(&self, kernel: &str) -> Option<ComposedShader> {
        let file = self.kernels.iter().find(|k| k.path.rsplit('/').next() == Some(&format!("{kernel}.wgsl")))?;
        Some(self.library_shader().with_part(file.path, file.source))
    }
}
