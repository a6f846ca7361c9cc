//! Project automation, in matklad's `cargo xtask` pattern (`.cargo/config.toml` aliases
//! `cargo xtask` to `cargo run --package xtask --`).
//!
//! - `cargo xtask test`: `cargo test --workspace`, then `test-gpu`.
//! - `cargo xtask test-gpu`: the GPU integration tests in `tests/` on the adapter chosen
//!   by `GPU_ADAPTER` (printed first).
//! - `cargo xtask bench [ARGS]`: the criterion benchmarks in `benches/`.
//! - `cargo xtask codegen`: rewrite the generated WGSL (each algorithm crate's
//!   `wgsl/generated/`, the pipeline crates' generated declarations) from the Rust
//!   declarations.
//! - `cargo xtask fig9 [OUT_DIR] [--height-map PNG] [--quick]`: the ray-traced ground truth
//!   of Heitz & Neyret's Fig. 9 against eq. 17 and MIP-mapping (default `target/fig9`).
//! - `cargo xtask showcase [OUT_DIR]`: the report of what exists so far (default
//!   `target/showcase`): the octahedral layout's angular error, the A-buffer masks'
//!   coverage error, and Fig. 9 at quick settings.
//! - `cargo xtask abuffer-chart [OUT_DIR]`: coverage error of the A-buffer mask tables
//!   against N (default `target/showcase`).
//! - `cargo xtask impostor-accuracy [OUT_DIR] [--quick] [--obj PATH]...`: SSIM/RMSE of octahedral impostors
//!   against the mesh for four grains, every `(n, p)`, three sampling modes, two screen sizes
//!   (Michel & Boubekeur's Fig. 13; default `target/impostor-accuracy`).
//! - `cargo xtask impostor-cloud [OUT_DIR] [--obj PATH | --grain NAME] [--n N] [--p P] [--mode M]
//!   [--grains COUNT]`: bakes any grain and renders a pile of it as an impostor cloud beside the
//!   mesh (default `target/impostor-cloud`).
//! - `cargo xtask ddm-compression [OUT_DIR] [--quick]`: compression efficiency of the
//!   distance maps and DDMs of four mesostructures (Mehra & Kumar's Table 3; default
//!   `target/ddm-compression`).
//! - `cargo xtask ddm-trace [OUT_DIR] [--quick] [--size WxHxD]`: Mehra & Kumar's Tables 1–3 measured with
//!   the DDM tracer on CPU and GPU against the exact mesh (default `target/ddm-trace`).
//! - `cargo xtask ddm-render [OUT_DIR] [--quick]`: the mesostructures mapped on a plane tile
//!   and a torus through a raster G-buffer and a compute trace (default `target/ddm-render`).

mod abuffer_chart;
mod chart;
mod ddm_compression;
mod ddm_render;
mod ddm_steps;
mod ddm_trace;
mod fig9;
mod impostor_accuracy;
mod impostor_cloud;
mod showcase;

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn cargo(args: &[&str]) -> Result<(), String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    println!("$ cargo {}", args.join(" "));
    let status = Command::new(&cargo)
        .args(args)
        .current_dir(workspace_root())
        .status()
        .map_err(|e| format!("cannot run {cargo}: {e}"))?;
    if status.success() { Ok(()) } else { Err(format!("`cargo {}` failed ({status})", args.join(" "))) }
}

fn codegen() -> Result<(), String> {
    // The algorithm crates' declarations and `naga_oil` headers, in each crate's `wgsl/`.
    for (relative, written) in shader_registry::write_generated_files(&workspace_root())? {
        println!("{} {relative}", if written { "wrote    " } else { "unchanged" });
    }
    // Pipeline crates keep their generated declarations beside their own shaders.
    let pipelines = [
        (grain_impostor::scene::GENERATED_WGSL_PATH, grain_impostor::scene::generated_wgsl()),
        (grain_impostor::cloud::CLOUD_GENERATED_WGSL_PATH, grain_impostor::cloud::cloud_generated_wgsl()),
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

fn test_gpu() -> Result<(), String> {
    match gpu_harness::Gpu::new() {
        Ok(gpu) => println!("GPU tests on adapter: {}", gpu.describe()),
        Err(e) => return Err(e.to_string()),
    }
    // `--workspace` keeps the same feature unification as `cargo test --workspace`, so
    // nothing is rebuilt; the glob selects the GPU test targets of `tests/`.
    cargo(&["test", "--workspace", "--features", "integration-tests/gpu", "--test", "*_gpu", "--", "--show-output"])
}

fn run(args: &[String]) -> Result<(), String> {
    let mut rest: Vec<&str> = args.iter().skip(1).map(String::as_str).collect();
    if rest.first() == Some(&"--") {
        rest.remove(0);
    }
    match args.first().map(String::as_str) {
        Some("test") => {
            cargo(&["test", "--workspace"])?;
            test_gpu()
        }
        Some("test-gpu") => test_gpu(),
        Some("bench") => {
            let mut command = vec!["bench", "--package", "benches"];
            if !rest.is_empty() {
                command.push("--");
                command.extend(rest);
            }
            cargo(&command)
        }
        Some("codegen") => codegen(),
        Some("fig9") => fig9::run(&rest, workspace_root().join("target/fig9")),
        Some("showcase") => {
            let out = rest.first().map_or_else(|| workspace_root().join("target/showcase"), PathBuf::from);
            // Everything that can be shown so far, at quick settings: the octahedral layout,
            // impostor accuracy (Fig. 12-13), the A-buffer masks' coverage error, Fig. 9 and
            // the DDM tracer's tables and its renders on a plane and a torus.
            showcase::run(&out)?;
            let out_text = out.to_string_lossy().into_owned();
            impostor_accuracy::run(&[out_text.as_str(), "--quick"], out.clone())?;
            ddm_trace::run(&[out_text.as_str(), "--quick"], out.clone())?;
            ddm_render::run(&[out_text.as_str(), "--quick"], out.clone())?;
            abuffer_chart::run(&out)?;
            fig9::run(&["--quick"], out)
        }
        Some("abuffer-chart") => {
            let out = rest.first().map_or_else(|| workspace_root().join("target/showcase"), PathBuf::from);
            abuffer_chart::run(&out)
        }
        Some("impostor-accuracy") => {
            impostor_accuracy::run(&rest, workspace_root().join("target/impostor-accuracy"))
        }
        Some("impostor-cloud") => impostor_cloud::run(&rest, workspace_root().join("target/impostor-cloud")),
        Some("ddm-compression") => ddm_compression::run(&rest, workspace_root().join("target/ddm-compression")),
        Some("ddm-trace") => ddm_trace::run(&rest, workspace_root().join("target/ddm-trace")),
        Some("ddm-render") => ddm_render::run(&rest, workspace_root().join("target/ddm-render")),
        _ => Err(
            "usage: cargo xtask <test | test-gpu | bench [CRITERION ARGS] | codegen | showcase [OUT_DIR] | fig9 [OUT_DIR] [--height-map PNG] [--quick] [--spectra] | abuffer-chart [OUT_DIR] | ddm-compression [OUT_DIR] [--quick] [--size WxHxD] | ddm-trace [OUT_DIR] [--quick] [--size WxHxD] | ddm-render [OUT_DIR] [--quick] | impostor-accuracy [OUT_DIR] [--quick] [--obj PATH]... | impostor-cloud [OUT_DIR] [--obj PATH | --grain NAME] [--n N] [--p P] [--mode MODE] [--grains COUNT]>"
                .into(),
        ),
    }
}

/// Mesa's Vulkan drivers complain on every device creation when `XDG_RUNTIME_DIR` is not
/// a usable directory. Without it, re-run this xtask with one under `target/`.
fn rerun_with_runtime_dir(args: &[String]) -> Option<ExitCode> {
    if std::env::var_os("XDG_RUNTIME_DIR").is_some_and(|dir| Path::new(&dir).is_dir()) {
        return None;
    }
    let dir = workspace_root().join("target/xdg-runtime");
    std::fs::create_dir_all(&dir).ok()?;
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o700)).ok()?;
    }
    let status = Command::new(std::env::current_exe().ok()?).args(args).env("XDG_RUNTIME_DIR", &dir).status().ok()?;
    Some(status.code().map_or(ExitCode::FAILURE, |code| ExitCode::from(code as u8)))
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if let Some(code) = rerun_with_runtime_dir(&args) {
        return code;
    }
    match run(&args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("xtask: {message}");
            ExitCode::FAILURE
        }
    }
}
