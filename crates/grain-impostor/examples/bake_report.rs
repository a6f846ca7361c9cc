//! Bakes grains and reports: bake times, atlas memory for a range of `(n, p)`, and the
//! accuracy cost of the packed 8-byte layout.
//!
//! ```text
//! cargo run --release -p grain-impostor --example bake_report [-- --quick] [--save DIR]
//! ```
//!
//! `--quick` skips the n = 12 timing. Times are wall-clock seconds on whatever adapter
//! `gpu_harness::Gpu::new()` picks (lavapipe on machines without a GPU), including the
//! CPU mip chains and the readback.

use std::time::Instant;

use grain_impostor::atlas::AtlasMemory;
use grain_impostor::bake::{BakeSettings, Baker};
use grain_impostor::packed::{ErrorStats, packed_accuracy};
use grain_mesh::{Ball, CoffeeBean, GrainMesh, HexNut, SandGrain};
use octahedral_map::OctahedralViews;

fn mib(bytes: u64) -> f64 {
    bytes as f64 / (1024.0 * 1024.0)
}

fn stats(s: ErrorStats) -> String {
    format!("{:.5} / {:.5}", s.rmse, s.max)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let quick = args.iter().any(|a| a == "--quick");
    let save_dir = args.iter().position(|a| a == "--save").and_then(|i| args.get(i + 1)).map(std::path::PathBuf::from);
    let gpu = gpu_harness::Gpu::new()?;
    println!("adapter: {}", gpu.describe());

    println!("\n## Atlas memory (16 B/texel, full mip chains; file = GPU bytes + 64-byte header)\n");
    println!("| n | N | p | level 0 MiB | all levels MiB (GPU) | file bytes |");
    println!("| --- | --- | --- | --- | --- | --- |");
    for n in [4, 6, 8, 10, 12] {
        let views = OctahedralViews::new(n).ok_or("bad n")?;
        for p in [32, 64, 128] {
            let memory = AtlasMemory::of(views, p);
            println!(
                "| {n} | {} | {p} | {:.3} | {:.3} | {} |",
                views.view_count(),
                mib(memory.bytes_per_level[0]),
                mib(memory.gpu_bytes),
                memory.file_bytes()
            );
        }
    }

    let baker = Baker::new(&gpu.device)?;
    let grains: Vec<(&str, GrainMesh)> = vec![
        ("ball", Ball::default().mesh()?),
        ("bean", CoffeeBean::default().mesh()?),
        ("rock", SandGrain::default().mesh()?),
        ("nut", HexNut::default().mesh()?),
    ];

    println!("\n## Bake times (2 × 2 supersampling)\n");
    let sizes: &[(u32, u32)] = if quick { &[(8, 128)] } else { &[(8, 128), (12, 128)] };
    for &(n, p) in sizes {
        for (name, mesh) in grains.iter().filter(|(name, _)| *name == "ball" || *name == "rock") {
            let settings = BakeSettings::new(n, p);
            let start = Instant::now();
            let (atlas, timings) = baker.bake_timed(&gpu.device, &gpu.queue, mesh, &settings)?;
            let seconds = start.elapsed().as_secs_f64();
            println!(
                "{name} ({} triangles): n = {n}, p = {p}: {seconds:.2} s (views {:.2} s, mips {:.2} s; {} views per submission)",
                mesh.triangles().len(),
                timings.views_seconds,
                timings.mips_seconds,
                Baker::batch_views(&gpu.device, &settings)
            );
            if let Some(dir) = &save_dir {
                std::fs::create_dir_all(dir)?;
                grain_impostor::atlas_file::save_atlas(&atlas, dir.join(format!("{name}_n{n}_p{p}.atlas")))?;
            }
        }
    }

    println!("\n## Packed 8-byte layout vs the standard atlas (n = 8, p = 64), RMSE / max over covered texels\n");
    println!("| grain | level | texels | normal ° | albedo | roughness | metallic | depth (R) | alpha |");
    println!("| --- | --- | --- | --- | --- | --- | --- | --- | --- |");
    for (name, mesh) in &grains {
        let atlas = baker.bake(&gpu.device, &gpu.queue, mesh, &BakeSettings::new(8, 64))?;
        for level in [0, 3] {
            let a = packed_accuracy(&atlas, level).ok_or("missing level")?;
            println!(
                "| {name} | {level} | {} | {} | {} | {} | {} | {} | {} |",
                a.texels,
                stats(a.normal_degrees),
                stats(a.albedo),
                stats(a.roughness),
                stats(a.metallic),
                stats(a.depth),
                stats(a.alpha)
            );
        }
    }
    Ok(())
}
