//! One-shot timing of `compute_distance_maps` per mesostructure (no criterion repetitions):
//! `cargo run --release -p benches --example ddm_timing -- WxHxD M [MESH | reference]`
//! computes the downward DDM `M×1` (`M = 0`: the plain distance map) of every
//! mesostructure (or only `MESH`) with tolerance 0.25, periodic in x and y, and prints the
//! time and the sum of all values (higher is tighter: every value is a lower bound);
//! `reference` also times `reference_distance_maps`.

use std::time::Instant;

use ddm_compress::testing::reference_distance_maps;
use ddm_compress::{DirectionCones, DistanceMapSettings, MapKind, compute_distance_maps};
use glam::UVec3;
use mesostructure::Mesostructure;

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().collect();
    let usage = "usage: ddm_timing WxHxD M [MESH | reference]";
    let size: Vec<u32> = args
        .get(1)
        .ok_or(usage)?
        .split('x')
        .map(str::parse)
        .collect::<Result<_, _>>()
        .map_err(|e| format!("{usage}: {e}"))?;
    let [x, y, z] = size[..] else { return Err(usage.into()) };
    let dims = UVec3::new(x, y, z);
    let azimuths: u32 = args.get(2).ok_or(usage)?.parse().map_err(|e| format!("{usage}: {e}"))?;
    let kind = if azimuths == 0 {
        MapKind::Plain
    } else {
        MapKind::Directional(DirectionCones::downward(azimuths, 1).map_err(|e| format!("{usage}: {e}"))?)
    };
    let only = args.get(3).map(String::as_str);
    let settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: true };
    for structure in Mesostructure::ALL {
        if only.is_some_and(|name| name != structure.name() && name != "reference") {
            continue;
        }
        let triangles = structure.triangles(dims);
        let start = Instant::now();
        let name = structure.name();
        let maps = compute_distance_maps(dims, &triangles, kind, settings).map_err(|e| format!("{name}: {e}"))?;
        let seconds = start.elapsed().as_secs_f64();
        let sum: f64 = maps.values.iter().flatten().map(|&v| f64::from(v)).sum();
        print!("{name:<9} triangles {:>6} {seconds:>8.3} s  sum {sum:.3}", triangles.len());
        if only == Some("reference") {
            let start = Instant::now();
            let reference = reference_distance_maps(dims, &triangles, kind, settings)
                .map_err(|e| format!("{name}: reference: {e}"))?;
            let sum: f64 = reference.values.iter().flatten().map(|&v| f64::from(v)).sum();
            print!("   reference {:.3} s  sum {sum:.3}", start.elapsed().as_secs_f64());
        }
        println!();
    }
    Ok(())
}
