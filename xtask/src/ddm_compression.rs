//! `cargo xtask ddm-compression [OUT_DIR] [--quick] [--size WxHxD]`: the equivalent of Mehra & Kumar's
//! Table 3. For each mesostructure (maze, bricks, beads, ball, chain mail) on a
//! 64 × 64 × 16 tile (the paper's resolution; 8 × 8 × 4 with `--quick`), the plain distance map and
//! the downward DDMs 2×1, 4×1 and 8×1 are computed and every map is compressed with
//! blocks of 2, 4 and 8; the compression efficiency is uncompressed size / (lookup grid +
//! atlas) ([`CompressedMap::compression_efficiency`]). Prints a table and writes
//! `ddm_compression.csv`.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use ddm_compress::{CompressedMap, DirectionCones, DistanceMapSettings, compute_distance_maps};
use glam::UVec3;
use mesostructure::Mesostructure;

/// Block sizes of the compression.
const BLOCKS: [u32; 3] = [2, 4, 8];

/// The maps of the table: name and cones (`None` for the plain distance map).
fn map_kinds() -> Vec<(&'static str, Option<DirectionCones>)> {
    vec![
        ("DM", None),
        ("DDM 2x1", DirectionCones::downward(2, 1)),
        ("DDM 4x1", DirectionCones::downward(4, 1)),
        ("DDM 8x1", DirectionCones::downward(8, 1)),
    ]
}

/// The grid size of a `--size WxHxD` argument (`text` is the word after `--size`).
pub fn parse_size(text: Option<&str>) -> Result<UVec3, String> {
    let text = text.ok_or("--size needs WxHxD")?;
    let parts: Vec<u32> =
        text.split('x').map(str::parse).collect::<Result<_, _>>().map_err(|e| format!("--size {text}: {e}"))?;
    match parts[..] {
        [x, y, z] if x > 0 && y > 0 && z > 0 => Ok(UVec3::new(x, y, z)),
        _ => Err(format!("--size {text}: expected three positive sizes WxHxD")),
    }
}

/// Runs the experiment; `args` are `[OUT_DIR] [--quick] [--size WxHxD]`.
pub fn run(args: &[&str], default_out: PathBuf) -> Result<(), String> {
    let mut out = default_out;
    let mut quick = false;
    let mut size = None;
    let mut args = args.iter();
    while let Some(&arg) = args.next() {
        match arg {
            "--quick" => quick = true,
            "--size" => size = Some(parse_size(args.next().copied())?),
            _ => out = PathBuf::from(arg),
        }
    }
    std::fs::create_dir_all(&out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let dims = size.unwrap_or(if quick { UVec3::new(8, 8, 4) } else { UVec3::new(64, 64, 16) });
    let settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: true };
    println!(
        "DDM compression (Table 3): {}x{}x{} voxels, tolerance {} voxel, periodic in x and y",
        dims.x, dims.y, dims.z, settings.tolerance
    );
    println!("efficiency = uncompressed / (lookup + atlas); time = computing the map (all its cones)\n");
    println!(
        "{:<9} {:>9} {:>8} {:>9} {:>9} {:>9} {:>9}",
        "mesh", "triangles", "map", "time s", "block 2", "block 4", "block 8"
    );
    let mut csv = String::from("mesostructure,triangles,map,cones,block,efficiency,seconds\n");
    for structure in Mesostructure::ALL {
        let triangles = structure.triangles(dims);
        for (map_name, cones) in map_kinds() {
            let start = Instant::now();
            let maps = compute_distance_maps(dims, &triangles, cones, settings)
                .ok_or_else(|| format!("{}: invalid scene for {map_name}", structure.name()))?;
            let seconds = start.elapsed().as_secs_f64();
            let mut efficiencies = Vec::new();
            for block in BLOCKS {
                // Every cone's map is compressed on its own; report their mean.
                let mut sum = 0.0;
                for values in &maps.values {
                    let compressed = CompressedMap::compress(values, &maps.surface, dims, block).ok_or_else(|| {
                        format!("{} {map_name}: cannot compress with block {block}", structure.name())
                    })?;
                    sum += compressed.compression_efficiency();
                }
                let efficiency = sum / maps.values.len() as f64;
                efficiencies.push(efficiency);
                let cone_count = maps.values.len();
                writeln!(
                    csv,
                    "{},{},{map_name},{cone_count},{block},{efficiency:.4},{seconds:.3}",
                    structure.name(),
                    triangles.len()
                )
                .map_err(|e| e.to_string())?;
            }
            println!(
                "{:<9} {:>9} {:>8} {:>9.2} {:>9.2} {:>9.2} {:>9.2}",
                structure.name(),
                triangles.len(),
                map_name,
                seconds,
                efficiencies[0],
                efficiencies[1],
                efficiencies[2]
            );
        }
    }
    let path = out.join("ddm_compression.csv");
    std::fs::write(&path, csv).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    println!("\nwrote {}", path.display());
    Ok(())
}
