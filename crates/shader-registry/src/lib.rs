//! The workspace's WGSL, gathered: every algorithm crate's exported twin (its `wgsl`
//! feature, a [`gpu_layout::WgslModule`]), where the twin's files live in the repository,
//! and the test kernels that prove each twin equal to its Rust.
//!
//! A crate owns its WGSL: the hand-written library and the generated declarations live in
//! `crates/<crate>/wgsl/` and are embedded by the crate itself, so its package is
//! self-contained; the repository's `shaders/<crate>` is a link to that folder, so that
//! `shaders/` stays the one place where all WGSL is read and edited. This crate adds what
//! only the workspace needs: the paths (for `cargo xtask codegen` and the freshness test),
//! and the differential-test kernels of `shaders/test-kernels/` with their input and
//! output structs ([`kernel_io`]), which are not part of any crate's API.
//!
//! The crate's tests parse and validate every module and kernel with naga, check naga's
//! layout of every generated struct against Rust's, that the committed generated files
//! are fresh, that each module lists its dependencies completely and in order, that each
//! module composes through `naga_oil` as well, and that no WGSL file in `shaders/` escapes
//! these checks.
//!
//! ```
//! let module = shader_registry::module("octahedral_map").unwrap();
//! assert!(module.shader().source().contains("fn octahedral_view_sample"));
//! let kernel = shader_registry::test_kernel("octahedral_map_differential").unwrap();
//! assert!(kernel.shader().unwrap().source().contains("@compute"));
//! ```

pub mod kernel_io;
mod kernels;

use gpu_layout::WgslModule;
use wgsl_gen::{ComposedShader, GenerateError, generate_declarations, naga_oil_header};

pub use kernels::{TestKernel, test_kernel, test_kernel_source, test_kernels};

/// An algorithm crate's WGSL twin and where its files are in the repository.
#[derive(Clone, Copy, Debug)]
pub struct CrateModule {
    /// The twin, as the crate exports it.
    pub module: &'static WgslModule,
    /// The crate's folder, relative to the workspace root.
    pub crate_dir: &'static str,
    /// The hand-written files whose concatenation is [`WgslModule::library`], relative to
    /// [`crate_dir`](Self::crate_dir).
    pub library_files: &'static [&'static str],
}

static MODULES: &[CrateModule] = &[
    CrateModule {
        module: &octahedral_map::WGSL,
        crate_dir: "crates/octahedral-map",
        library_files: &["wgsl/octahedral_map.wgsl"],
    },
    CrateModule {
        module: &occlusion_cone::WGSL,
        crate_dir: "crates/occlusion-cone",
        library_files: &["wgsl/occlusion_cone.wgsl"],
    },
    CrateModule {
        module: &quadric_fit::WGSL,
        crate_dir: "crates/quadric-fit",
        library_files: &["wgsl/quadric_fit.wgsl"],
    },
    CrateModule {
        module: &ddm_compress::WGSL,
        crate_dir: "crates/ddm-compress",
        library_files: &["wgsl/ddm_compress.wgsl", "wgsl/plain_map.wgsl"],
    },
    CrateModule {
        module: &abuffer_mask::WGSL,
        crate_dir: "crates/abuffer-mask",
        library_files: &["wgsl/abuffer_mask.wgsl"],
    },
    CrateModule {
        module: &smith_micro::WGSL,
        crate_dir: "crates/smith-micro",
        library_files: &["wgsl/smith_micro.wgsl"],
    },
    CrateModule { module: &svo_brick::WGSL, crate_dir: "crates/svo-brick", library_files: &["wgsl/svo_brick.wgsl"] },
    CrateModule { module: &svo_tracer::WGSL, crate_dir: "crates/svo-tracer", library_files: &["wgsl/svo_tracer.wgsl"] },
    CrateModule {
        module: &ddm_tracer::WGSL,
        crate_dir: "crates/ddm-tracer",
        library_files: &["wgsl/ddm_tracer.wgsl", "wgsl/tangent_space.wgsl"],
    },
];

/// Every algorithm crate's module.
pub fn modules() -> &'static [CrateModule] {
    MODULES
}

/// The module called `name` (the crate name with underscores).
pub fn module(name: &str) -> Option<&'static CrateModule> {
    MODULES.iter().find(|m| m.module.name == name)
}

/// Writes every generated file of the registered modules (declarations, `naga_oil`
/// headers) under `workspace_root` where its content differs; returns each path with
/// whether it was written (`cargo xtask codegen`). The new files take effect when the
/// crates are rebuilt, since each crate embeds its own.
pub fn write_generated_files(workspace_root: &std::path::Path) -> Result<Vec<(String, bool)>, String> {
    let mut written = Vec::new();
    for module in MODULES {
        let declarations =
            module.generate_declarations().map_err(|e| format!("{}: {e}", module.declarations_path()))?;
        // The header names what the module uses of its dependencies: generate it from the
        // declarations about to be written, not from the embedded (possibly stale) ones.
        let header = naga_oil_header(module.module, &declarations);
        let files = [(module.declarations_path(), declarations), (module.naga_oil_header_path(), header)];
        for (relative, text) in files {
            let path = workspace_root.join(&relative);
            let unchanged = std::fs::read_to_string(&path).is_ok_and(|old| old == text);
            if !unchanged {
                std::fs::write(&path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
            }
            written.push((relative, !unchanged));
        }
    }
    Ok(written)
}

impl CrateModule {
    /// The module's name.
    pub fn name(&self) -> &'static str {
        self.module.name
    }

    /// Path of the committed generated declarations, relative to the workspace root.
    pub fn declarations_path(&self) -> String {
        format!("{}/wgsl/generated/{}.wgsl", self.crate_dir, self.module.name)
    }

    /// Path of the committed `naga_oil` header, relative to the workspace root.
    pub fn naga_oil_header_path(&self) -> String {
        format!("{}/wgsl/generated/{}.naga_oil_header.wgsl", self.crate_dir, self.module.name)
    }

    /// The generated declarations as the Rust source says they should be now.
    pub fn generate_declarations(&self) -> Result<String, GenerateError> {
        generate_declarations(self.module.name, self.module.structs, self.module.constants)
    }

    /// The `naga_oil` header as the sources say it should be now.
    pub fn generate_naga_oil_header(&self) -> String {
        naga_oil_header(self.module, self.module.declarations)
    }

    /// The module composed with its dependencies ([`WgslModule::parts`]), each part
    /// labelled with its file.
    pub fn shader(&self) -> ComposedShader {
        let mut shader = ComposedShader::new(format!("{}.composed", self.module.name));
        for dependency in self.module.dependencies {
            shader = match module(dependency.name) {
                Some(registered) => registered.with_own_parts(shader),
                None => shader.with_module(dependency),
            };
        }
        self.with_own_parts(shader)
    }

    fn with_own_parts(&self, shader: ComposedShader) -> ComposedShader {
        let label = self.library_files.iter().map(|file| format!("{}/{file}", self.crate_dir)).collect::<Vec<_>>();
        shader
            .with_part(self.declarations_path(), self.module.declarations)
            .with_part(label.join(" + "), self.module.library)
    }
}
