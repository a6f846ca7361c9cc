//! Every WGSL module of the workspace is fresh, valid under naga (plainly composed and
//! through `naga_oil`), laid out like Rust, complete in its dependencies, and registered.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use gpu_layout::WgslModule;
use naga_oil::compose::{ComposableModuleDescriptor, Composer, NagaModuleDescriptor, ShaderLanguage};
use shader_registry::{modules, test_kernels};
use wgsl_gen::{check_layout, naga_oil_imports};

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The files a crate embeds are the files of the repository (the registry's paths are
/// right), and what it embeds is what the Rust source generates now.
#[test]
fn committed_generated_files_are_fresh() {
    let mut stale = Vec::new();
    for module in modules() {
        let declarations = module.generate_declarations().unwrap_or_else(|e| panic!("{}: {e}", module.name()));
        if module.module.declarations != declarations {
            stale.push(module.declarations_path());
        }
        if module.module.naga_oil_source
            != format!("{}{}{}", module.generate_naga_oil_header(), module.module.declarations, module.module.library)
        {
            stale.push(module.naga_oil_header_path());
        }
        let on_disk = |relative: &str| {
            std::fs::read_to_string(workspace_root().join(relative)).unwrap_or_else(|e| panic!("{relative}: {e}"))
        };
        assert_eq!(on_disk(&module.declarations_path()), module.module.declarations, "{}", module.name());
        let library: String =
            module.library_files.iter().map(|file| on_disk(&format!("{}/{file}", module.crate_dir))).collect();
        assert_eq!(library, module.module.library, "{}: library_files do not make up the library", module.name());
    }
    assert!(stale.is_empty(), "stale generated WGSL: {}; run `cargo xtask codegen`", stale.join(", "));
}

#[test]
fn every_module_and_test_kernel_passes_naga_validation() {
    for module in modules() {
        module.shader().validate().unwrap_or_else(|e| panic!("{e}"));
    }
    for kernel in test_kernels() {
        let shader = kernel.shader().unwrap_or_else(|e| panic!("{}: {e}", kernel.name));
        shader.validate().unwrap_or_else(|e| panic!("{e}"));
    }
}

#[test]
fn generated_structs_have_the_rust_layout() {
    for module in modules() {
        let validated = module.shader().validate().unwrap_or_else(|e| panic!("{e}"));
        if let Err(mismatches) = check_layout(&validated.module, module.module.structs) {
            let list: Vec<String> = mismatches.iter().map(ToString::to_string).collect();
            panic!("{}: WGSL layout differs from Rust:\n{}", module.declarations_path(), list.join("\n"));
        }
    }
    for kernel in test_kernels() {
        let validated = kernel.shader().unwrap().validate().unwrap_or_else(|e| panic!("{e}"));
        if let Err(mismatches) = check_layout(&validated.module, kernel.structs) {
            let list: Vec<String> = mismatches.iter().map(ToString::to_string).collect();
            panic!("{}: WGSL layout differs from Rust:\n{}", kernel.path, list.join("\n"));
        }
    }
}

/// A module's dependency list holds each dependency after its own dependencies, so that
/// pasting the parts in order defines every name before its use (validation above then
/// proves the list complete).
#[test]
fn dependencies_are_listed_in_composition_order() {
    for module in modules() {
        let names: Vec<&str> = module.module.dependency_names().collect();
        for (position, dependency) in module.module.dependencies.iter().enumerate() {
            for inner in dependency.dependency_names() {
                let found = names.iter().position(|n| *n == inner);
                assert!(
                    found.is_some_and(|p| p < position),
                    "{}: `{inner}` (used by `{}`) must come before it in the dependency list {names:?}",
                    module.name(),
                    dependency.name
                );
            }
        }
        assert!(!names.contains(&module.name()), "{} depends on itself", module.name());
    }
}

/// A composer with every module added as a `naga_oil` composable module, dependencies
/// first (as a Bevy application registers them).
fn naga_oil_composer() -> Composer {
    let mut composer = Composer::default();
    let mut added: Vec<&str> = Vec::new();
    let mut pending: Vec<&WgslModule> = modules().iter().map(|m| m.module).collect();
    while !pending.is_empty() {
        let before = pending.len();
        pending.retain(|module| {
            if !module.dependency_names().all(|d| added.contains(&d)) {
                return true;
            }
            composer
                .add_composable_module(ComposableModuleDescriptor {
                    source: module.naga_oil_source,
                    file_path: module.name,
                    language: ShaderLanguage::Wgsl,
                    as_name: None,
                    additional_imports: &[],
                    shader_defs: HashMap::new(),
                })
                .unwrap_or_else(|e| {
                    panic!("naga_oil rejects `{}`:\n{}", module.name, e.emit_to_string(&Composer::default()))
                });
            added.push(module.name);
            false
        });
        assert!(
            pending.len() < before,
            "a dependency cycle among {:?}",
            pending.iter().map(|m| m.name).collect::<Vec<_>>()
        );
    }
    composer
}

/// Every module composes as a `naga_oil` module, and every test kernel — written against
/// the plain composition — validates as a `naga_oil` shader that `#import`s what it uses
/// from its module and the module's dependencies.
#[test]
fn every_module_composes_through_naga_oil() {
    let mut composer = naga_oil_composer();
    let mut composed = 0;
    for kernel in test_kernels() {
        let declarations = kernel.generate_declarations().unwrap();
        let mut imported: Vec<&WgslModule> = kernel.module.dependencies.to_vec();
        imported.push(kernel.module);
        let own = format!("{declarations}\n{}", kernel.source);
        let source = format!("{}{own}", naga_oil_imports(&own, &imported));
        let module = composer
            .make_naga_module(NagaModuleDescriptor { source: &source, file_path: kernel.path, ..Default::default() })
            .unwrap_or_else(|e| panic!("naga_oil cannot compose {}:\n{}", kernel.path, e.emit_to_string(&composer)));
        let mut validator =
            naga::valid::Validator::new(naga::valid::ValidationFlags::all(), naga::valid::Capabilities::default());
        validator.validate(&module).unwrap_or_else(|e| panic!("{}: {e:?}", kernel.path));
        assert!(!module.entry_points.is_empty(), "{}", kernel.path);
        composed += 1;
    }
    assert_eq!(composed, test_kernels().len());
}

/// No WGSL file in `shaders/` (or the crate folders it links to) escapes the checks above,
/// except the pipeline crates' own shaders, which their crates compose and validate.
#[test]
fn every_wgsl_file_is_registered() {
    let mut registered: Vec<String> = Vec::new();
    for module in modules() {
        registered.push(module.declarations_path());
        registered.push(module.naga_oil_header_path());
        registered.extend(module.library_files.iter().map(|f| format!("{}/{f}", module.crate_dir)));
    }
    registered.extend(test_kernels().iter().map(|k| k.path.to_owned()));
    let pipeline_links = ["grain-impostor", "ddm-render", "svo-render"];
    let mut unregistered = Vec::new();
    let mut linked = Vec::new();
    for entry in std::fs::read_dir(workspace_root().join("shaders")).unwrap().map(Result::unwrap) {
        let name = entry.file_name().to_string_lossy().into_owned();
        if entry.file_type().unwrap().is_symlink() {
            linked.push(name.clone());
        }
        if pipeline_links.contains(&name.as_str()) {
            continue;
        }
        let mut pending = vec![entry.path()];
        while let Some(path) = pending.pop() {
            if path.is_dir() {
                pending.extend(std::fs::read_dir(&path).unwrap().map(|e| e.unwrap().path()));
            } else if path.extension().is_some_and(|e| e == "wgsl") {
                let canonical = path.canonicalize().unwrap();
                let root = workspace_root().canonicalize().unwrap();
                let relative = canonical.strip_prefix(&root).unwrap().to_string_lossy().replace('\\', "/");
                if !registered.contains(&relative) {
                    unregistered.push(relative);
                }
            }
        }
    }
    assert!(unregistered.is_empty(), "WGSL files not in shader-registry (so never validated): {unregistered:?}");
    // Every algorithm crate's folder is linked from `shaders/`, named after the crate.
    for module in modules() {
        let crate_name = module.crate_dir.rsplit('/').next().unwrap();
        assert!(
            linked.iter().any(|l| l == crate_name),
            "shaders/{crate_name} should link to {}/wgsl",
            module.crate_dir
        );
    }
}
