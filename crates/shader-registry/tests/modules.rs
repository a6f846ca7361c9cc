//! Every WGSL module of the repository is fresh, valid under naga, and laid out like Rust.

use std::path::{Path, PathBuf};

use shader_registry::modules;
use wgsl_gen::check_layout;

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

#[test]
fn committed_generated_files_are_fresh() {
    let mut stale = Vec::new();
    for module in modules() {
        let expected = module.generate().unwrap_or_else(|e| panic!("cannot generate {}: {e}", module.generated.path));
        let path = workspace_root().join(module.generated.path);
        let committed = std::fs::read_to_string(&path).unwrap_or_default();
        if committed != expected {
            stale.push(module.generated.path);
        }
    }
    assert!(stale.is_empty(), "stale generated WGSL: {}; run `cargo xtask codegen`", stale.join(", "));
}

#[test]
fn every_composed_module_passes_naga_validation() {
    for module in modules() {
        let mut shaders = vec![module.library_shader()];
        for kernel in module.kernels {
            let stem = kernel.path.rsplit('/').next().and_then(|f| f.strip_suffix(".wgsl")).unwrap();
            shaders.push(module.with_kernel(stem).unwrap());
        }
        for shader in shaders {
            if let Err(error) = shader.validate() {
                panic!("{error}");
            }
        }
    }
}

#[test]
fn generated_structs_have_the_rust_layout() {
    for module in modules() {
        let validated = module.library_shader().validate().unwrap_or_else(|e| panic!("{e}"));
        if let Err(mismatches) = check_layout(&validated.module, &(module.structs)()) {
            let list: Vec<String> = mismatches.iter().map(ToString::to_string).collect();
            panic!("{}: WGSL layout differs from Rust:\n{}", module.generated.path, list.join("\n"));
        }
    }
}

/// No WGSL file in `shaders/` escapes the checks above.
#[test]
fn every_wgsl_file_is_registered() {
    let mut registered: Vec<&str> = Vec::new();
    for module in modules() {
        registered.push(module.generated.path);
        registered.push(module.library.path);
        registered.extend(module.kernels.iter().map(|k| k.path));
    }
    let mut unregistered = Vec::new();
    let mut pending = vec![workspace_root().join("shaders")];
    while let Some(dir) = pending.pop() {
        for entry in std::fs::read_dir(&dir).unwrap().map(Result::unwrap) {
            let path = entry.path();
            if path.is_dir() {
                pending.push(path);
            } else if path.extension().is_some_and(|e| e == "wgsl") {
                let relative = path.strip_prefix(workspace_root()).unwrap().to_string_lossy().replace('\\', "/");
                if !registered.contains(&relative.as_str()) {
                    unregistered.push(relative);
                }
            }
        }
    }
    assert!(unregistered.is_empty(), "WGSL files not in shader-registry (so never validated): {unregistered:?}");
}
