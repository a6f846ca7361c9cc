//! Project automation, in matklad's `cargo xtask` pattern (`.cargo/config.toml` aliases
//! `cargo xtask` to `cargo run --package xtask --`).
//!
//! Every command is declared once in [`COMMANDS`] (its flags, its `OUT_DIR` and what runs
//! it); `cargo xtask --help` lists their usage lines, `cargo xtask COMMAND --help` prints
//! one, and the README's command table shows the same lines (a test checks it). The
//! experiments themselves live in library crates (e.g. `ddm-experiments` for Mehra &
//! Kumar's Tables 1–3); the commands parse arguments, call them, write CSV/PNG files, draw
//! charts and print.

mod abuffer_chart;
mod bench_ddm;
mod bench_gpu;
mod bench_record;
mod bench_stackings;
mod cargo_tasks;
mod chart;
mod cli;
mod commands;
mod culling_chart;
mod ddm_build;
mod ddm_compression;
mod ddm_input;
mod ddm_render;
mod ddm_resolution;
mod ddm_steps;
mod ddm_trace;
mod fig9;
mod gpu_report;
mod impostor_accuracy;
mod impostor_cloud;
mod interpenetration;
mod occlusion_check;
mod octahedral_error;
mod report_check;
mod report_page;
mod select;
mod showcase;
mod stackings;
mod svo;
mod svo_stability;

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use cli::Parsed;
use commands::usage;
pub use commands::{COMMANDS, command};

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn run(words: &[String]) -> Result<(), String> {
    let Some((name, rest)) = words.split_first() else {
        return Err(format!("no command\n{}", usage()));
    };
    if matches!(name.as_str(), "--help" | "-h" | "help") {
        println!("{}", usage());
        return Ok(());
    }
    let command = command(name).ok_or_else(|| format!("unknown command `{name}`\n{}", usage()))?;
    match command.parse(rest)? {
        Parsed::Run(args) => (command.run)(&args),
        Parsed::Help(usage) => {
            println!("usage: {usage}");
            Ok(())
        }
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
    let status = std::process::Command::new(std::env::current_exe().ok()?)
        .args(args)
        .env("XDG_RUNTIME_DIR", &dir)
        .status()
        .ok()?;
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
