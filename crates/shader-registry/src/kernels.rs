//! The differential-test kernels of `shaders/test-kernels/`: entry points that run a
//! module's functions over buffers of cases, for the CPU = GPU tests in `tests/` and the
//! GPU timings of the experiments. Each kernel composes after its module (and that
//! module's dependencies) and the generated declarations of its input and output structs
//! ([`kernel_io`](crate::kernel_io)).

use gpu_layout::{StructDecl, WgslModule};
use wgsl_gen::{ComposedShader, GenerateError, generate_declarations};

use crate::kernel_io;

/// A test kernel file and what it composes with.
#[derive(Clone, Copy, Debug)]
pub struct TestKernel {
    /// The file's stem.
    pub name: &'static str,
    /// Path relative to the workspace root.
    pub path: &'static str,
    /// Contents, embedded at build time.
    pub source: &'static str,
    /// The module whose functions it runs.
    pub module: &'static WgslModule,
    /// The kernel's own input and output structs (declared in [`kernel_io`]).
    pub structs: &'static [StructDecl],
}

macro_rules! test_kernel {
    ($name:literal, $module:expr, $structs:expr) => {
        TestKernel {
            name: $name,
            path: concat!("shaders/test-kernels/", $name, ".wgsl"),
            source: include_str!(concat!("../../../shaders/test-kernels/", $name, ".wgsl")),
            module: $module,
            structs: $structs,
        }
    };
}

static KERNELS: &[TestKernel] = &[
    test_kernel!("octahedral_map_differential", &octahedral_map::WGSL, kernel_io::octahedral_map::STRUCTS),
    test_kernel!("impostor_sampling_differential", &octahedral_map::WGSL, kernel_io::octahedral_map::STRUCTS),
    test_kernel!("occlusion_cone_differential", &occlusion_cone::WGSL, &[]),
    test_kernel!("quadric_fit_differential", &quadric_fit::WGSL, kernel_io::quadric_fit::STRUCTS),
    test_kernel!("ddm_compress_differential", &ddm_compress::WGSL, &[]),
    test_kernel!("ddm_plain_pairs_differential", &ddm_compress::WGSL, &[]),
    test_kernel!("abuffer_mask_differential", &abuffer_mask::WGSL, &[]),
    test_kernel!("smith_micro_differential", &smith_micro::WGSL, kernel_io::smith_micro::STRUCTS),
    test_kernel!("smith_micro_corrected_differential", &smith_micro::WGSL, kernel_io::smith_micro::STRUCTS),
    test_kernel!("smith_micro_correlated_differential", &smith_micro::WGSL, kernel_io::smith_micro::STRUCTS),
    test_kernel!("smith_micro_cubic_differential", &smith_micro::WGSL, kernel_io::smith_micro::STRUCTS),
    test_kernel!("ddm_tracer_compute", &ddm_tracer::WGSL, kernel_io::ddm_tracer::STRUCTS),
    test_kernel!("svo_brick_differential", &svo_brick::WGSL, &[]),
    test_kernel!("svo_tracer_differential", &svo_tracer::WGSL, &[]),
];

/// Every test kernel.
pub fn test_kernels() -> &'static [TestKernel] {
    KERNELS
}

/// The test kernel whose file stem is `name`.
pub fn test_kernel(name: &str) -> Option<&'static TestKernel> {
    KERNELS.iter().find(|k| k.name == name)
}

/// The composed source of the test kernel `name` ([`TestKernel::shader`]); the error names
/// the kernel.
pub fn test_kernel_source(name: &str) -> Result<String, String> {
    let kernel = test_kernel(name).ok_or_else(|| format!("no test kernel `{name}` in shaders/test-kernels"))?;
    kernel.shader().map(|shader| shader.source().to_owned()).map_err(|e| format!("test kernel `{name}`: {e}"))
}

impl TestKernel {
    /// The generated declarations of [`structs`](Self::structs).
    pub fn generate_declarations(&self) -> Result<String, GenerateError> {
        generate_declarations(&format!("the test kernel {}", self.name), self.structs, &[])
    }

    /// The kernel composed after its module and its own generated declarations.
    pub fn shader(&self) -> Result<ComposedShader, GenerateError> {
        let declarations = self.generate_declarations()?;
        let module = crate::module(self.module.name)
            .map_or_else(|| ComposedShader::of_module(self.module), crate::CrateModule::shader);
        Ok(module
            .with_part(format!("{} (generated kernel structs)", self.path), &declarations)
            .with_part(self.path, self.source))
    }
}
