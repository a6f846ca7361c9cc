//! The commands that run cargo: the tests (`test`, `test-gpu`), the benchmarks (`bench`)
//! and the generated WGSL (`codegen`).

use std::path::PathBuf;

use crate::bench_record;
use crate::cli::Args;
use crate::workspace_root;

pub fn cargo(args: &[&str]) -> Result<(), String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    println!("$ cargo {}", args.join(" "));
    let status = std::process::Command::new(&cargo)
        .args(args)
        .current_dir(workspace_root())
        .status()
        .map_err(|e| format!("cannot run {cargo}: {e}"))?;
    if status.success() { Ok(()) } else { Err(format!("`cargo {}` failed ({status})", args.join(" "))) }
}

pub fn codegen() -> Result<(), String> {
    // The algorithm crates' declarations and `naga_oil` headers, in each crate's `wgsl/`.
    for (relative, written) in shader_registry::write_generated_files(&workspace_root())? {
        println!("{} {relative}", if written { "wrote    " } else { "unchanged" });
    }
    // Pipeline crates keep their generated declarations beside their own shaders.
    let pipelines = [
        (grain_impostor::scene::GENERATED_WGSL_PATH, grain_impostor::scene::generated_wgsl()),
        (grain_impostor::cloud::CLOUD_GENERATED_WGSL_PATH, grain_impostor::cloud::cloud_generated_wgsl()),
        (grain_splitter::shaders::GENERATED_WGSL_PATH, grain_splitter::shaders::generated_wgsl()),
        (grain_renderer::shaders::GENERATED_WGSL_PATH, grain_renderer::shaders::generated_wgsl()),
        (svo_render::shader::GENERATED_WGSL_PATH, svo_render::shader::generated_wgsl()),
    ];
    for (relative, text) in pipelines {
        write_if_changed(relative, &text.map_err(|e| format!("{relative}: {e}"))?)?;
    }
    Ok(())
}

/// Writes `text` to `relative` (from the workspace root) unless the file already holds it.
fn write_if_changed(relative: &str, text: &str) -> Result<(), String> {
    let path = workspace_root().join(relative);
    let unchanged = std::fs::read_to_string(&path).is_ok_and(|old| old == text);
    if !unchanged {
        std::fs::write(&path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    }
    println!("{} {relative}", if unchanged { "unchanged" } else { "wrote    " });
    Ok(())
}

pub fn test_gpu() -> Result<(), String> {
    match gpu_harness::Gpu::new() {
        Ok(gpu) => println!("GPU tests on adapter: {}", gpu.describe()),
        Err(e) => return Err(e.to_string()),
    }
    // `--workspace` keeps the same feature unification as `cargo test --workspace`, so
    // nothing is rebuilt; the glob selects the GPU test targets of `tests/`.
    cargo(&["test", "--workspace", "--features", "integration-tests/gpu", "--test", "*_gpu", "--", "--show-output"])?;
    // A renderer outside the workspace's pipelines takes octahedral-map alone and checks its
    // GPU results against the Rust (exits with an error naming the first difference). Built
    // with the workspace's features (`cargo run --package` would resolve its own and compile
    // wgpu a third time); `.ci/packages` builds the algorithm crates alone.
    cargo(&["build", "--workspace", "--bins"])?;
    let exe = std::env::current_exe().map_err(|e| format!("cannot locate xtask's binary: {e}"))?;
    let renderer = exe.with_file_name(format!("foreign-renderer{}", std::env::consts::EXE_SUFFIX));
    println!("$ {}", renderer.display());
    let status = std::process::Command::new(&renderer)
        .current_dir(workspace_root())
        .status()
        .map_err(|e| format!("cannot run {}: {e}", renderer.display()))?;
    if status.success() { Ok(()) } else { Err(format!("{} failed ({status})", renderer.display())) }
}

pub fn test(_: &Args<'_>) -> Result<(), String> {
    cargo(&["test", "--workspace"])?;
    test_gpu()
}

/// `cargo bench --package benches`, the arguments passed on to criterion; with `--save`
/// or `--compare` its figures recorded or compared ([`bench_record`]).
pub fn bench(args: &Args<'_>) -> Result<(), String> {
    let target = std::env::var_os("CARGO_TARGET_DIR").map_or_else(|| workspace_root().join("target"), PathBuf::from);
    let save = args.value("save").map(|name| bench_record::record_path(&target, name)).transpose()?;
    let compare = args.value("compare").map(|name| bench_record::record_path(&target, name)).transpose()?;
    let saved = match &compare {
        Some(path) => Some(bench_record::Record::read(path)?),
        None => None,
    };
    let started = std::time::SystemTime::now();
    let mut command = vec!["bench", "--package", "benches"];
    if !args.rest().is_empty() {
        command.push("--");
        command.extend(args.rest().iter().map(String::as_str));
    }
    cargo(&command)?;
    if save.is_none() && saved.is_none() {
        return Ok(());
    }
    let name = args.value("save").unwrap_or("unsaved");
    let mut record = bench_record::Record::measured(&target, name, started)?;
    if save.is_some() {
        // A second run, back to back: each benchmark's own run-to-run spread.
        println!("bench: the second run of `--save {name}` (each benchmark's run-to-run spread)");
        let second = std::time::SystemTime::now();
        cargo(&command)?;
        record = bench_record::Record::measured(&target, name, second)?.with_run_to_run(&record);
    }
    if let Some(path) = &save {
        record.write(path)?;
        println!("bench: wrote {} ({} figures)", path.display(), record.figures.len());
    }
    match saved {
        Some(saved) => bench_record::print_comparison(&saved, &record),
        None => Ok(()),
    }
}
