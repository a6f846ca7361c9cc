//! Memory of `svo-brick` octrees of the displaced sphere (`benches::displaced`) at growing
//! resolutions, in both packed layouts: the goal is a 512³-equivalent displaced
//! sphere in at most 150 MB (the paper used 300 MB).
//!
//! `cargo run --release -p benches --example svo_memory -- [--max-levels N] [--normalisation sum|hypot]`
//!
//! Builds with 8³ bricks and levels 4, 5, …, `N` (finest resolution `8 × 2^(levels − 1)`:
//! 64³, 128³, 256³, 512³, 1024³ for `N` = 4 … 8; default 7, about 5 minutes and 2.7 GB
//! on one core), the builder's default options otherwise, and prints per resolution:
//! bricks; stored voxels (`bricks × 10³`, with the apron) and interior voxels
//! (`bricks × 8³`); the node pool and brick pool bytes of each layout
//! (`PackedTree::bytes()`, in MB = 10⁶ B); bytes per stored voxel and per interior voxel
//! (node and brick pool together); build seconds (the `BrickTree`, one thread) and pack
//! seconds (both layouts). Then the peak resident memory, the bricks per level, the growth
//! per level and the verdict on the goal: measured when 512³ was built, otherwise
//! extrapolated from the growth of the brick count between the last two rows and marked
//! as such. First it measures the steepest slope of the raw displaced distance, beside the
//! two normalisations (`--normalisation`: `sum` divides by `1 + L`, a true bound and the
//! default; `hypot` by `√(1 + L²)`, not a bound for this 3D noise, for comparison only).
//! Unknown arguments are an error (exit status 2).

use std::time::Instant;

use benches::displaced::{self, Normalisation};
use glam::Vec3;
use svo_brick::{BrickSize, BrickTree, BuildOptions, PackedTree, VoxelLayout};

/// The memory goal for the 512³-equivalent displaced sphere (bytes).
const GOAL_BYTES: f64 = 150e6;
/// The finest level count the goal is about (512³ with 8³ bricks).
const GOAL_LEVELS: u32 = 7;
/// The smallest tree built (64³).
const MIN_LEVELS: u32 = 4;

const USAGE: &str = "usage: svo_memory [--max-levels N (4..=8, default 7)] [--normalisation sum|hypot]";

/// The command line.
struct Args {
    max_levels: u32,
    normalisation: Normalisation,
}

fn parse_args() -> Result<Args, String> {
    let mut args = Args { max_levels: GOAL_LEVELS, normalisation: Normalisation::Sum };
    let mut words = std::env::args().skip(1);
    while let Some(word) = words.next() {
        let (flag, inline) = match word.split_once('=') {
            Some((flag, value)) => (flag.to_owned(), Some(value.to_owned())),
            None => (word.clone(), None),
        };
        let mut value = |name: &str| {
            inline.clone().or_else(|| words.next()).ok_or_else(|| format!("{name} needs a value\n{USAGE}"))
        };
        match flag.as_str() {
            "--max-levels" | "--max-level" => {
                let text = value("--max-levels")?;
                let n: u32 = text.parse().map_err(|e| format!("--max-levels {text}: {e}\n{USAGE}"))?;
                if !(MIN_LEVELS..=8).contains(&n) {
                    return Err(format!("--max-levels {n} is outside 4..=8\n{USAGE}"));
                }
                args.max_levels = n;
            }
            "--normalisation" => {
                args.normalisation = match value("--normalisation")?.as_str() {
                    "sum" => Normalisation::Sum,
                    "hypot" => Normalisation::Hypot,
                    other => return Err(format!("--normalisation {other}: expected `sum` or `hypot`\n{USAGE}")),
                };
            }
            "-h" | "--help" => {
                println!("{USAGE}");
                std::process::exit(0);
            }
            other => return Err(format!("unknown argument `{other}`\n{USAGE}")),
        }
    }
    Ok(args)
}

/// One built resolution.
struct Row {
    levels: u32,
    bricks: usize,
    nodes: usize,
    /// Bricks per level, the finest first.
    per_level: Vec<usize>,
    /// `PackedTree::bytes()` per layout (`VoxelLayout::ALL` order).
    bytes: [usize; 3],
}

/// The peak resident memory of this process (`VmHWM`, Linux), in MB.
fn peak_resident_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1e3)
}

/// The largest `|∇(|p| − R − A fbm(p))|` (central differences of step `1e-3`) over 10⁵
/// points of the shell `R ± 0.1` (golden-angle directions): how close the Lipschitz
/// bound the distance is divided by comes to the field's actual slope.
fn measured_max_gradient() -> f32 {
    let h = 1e-3;
    (0..100_000)
        .map(|k| {
            let z = 1.0 - 2.0 * (k as f32 + 0.5) / 1e5;
            let phi = k as f32 * 2.399_963;
            let r = (1.0 - z * z).sqrt();
            let radius = displaced::DISPLACED_RADIUS - 0.1 + 0.2 * ((k * 7919) % 1000) as f32 / 1000.0;
            let p = Vec3::new(r * phi.cos(), r * phi.sin(), z) * radius;
            let d = |e: Vec3| (displaced::raw_distance(p + e * h) - displaced::raw_distance(p - e * h)) / (2.0 * h);
            Vec3::new(d(Vec3::X), d(Vec3::Y), d(Vec3::Z)).length()
        })
        .fold(0.0, f32::max)
}

fn mb(bytes: f64) -> f64 {
    bytes / 1e6
}

fn main() {
    if let Err(message) = run() {
        eprintln!("svo_memory: {message}");
        std::process::exit(2);
    }
}

fn run() -> Result<(), String> {
    let args = parse_args()?;
    let source = displaced::displaced_sphere(args.normalisation);
    let brick_size = BrickSize::Eight;
    let n = brick_size.side() as usize;
    let stored_per_brick = brick_size.stored_voxels();
    let interior_per_brick = n * n * n;
    let defaults = BuildOptions::default();
    println!(
        "displaced sphere: R {} A {} fBm {} octaves f0 {}, distance / {:.3} ({:?}); 8³ bricks, {} samples per voxel, quadrature {}, {:?}",
        displaced::DISPLACED_RADIUS,
        displaced::DISPLACED_AMPLITUDE,
        displaced::OCTAVES,
        displaced::BASE_FREQUENCY,
        args.normalisation.divisor(),
        args.normalisation,
        defaults.samples_per_voxel,
        defaults.quadrature,
        defaults.height_variance,
    );
    println!(
        "max |∇ raw distance| measured over 10⁵ shell points: {:.3} (bounds: 1 + L = {:.3}, √(1 + L²) = {:.3})",
        measured_max_gradient(),
        Normalisation::Sum.divisor(),
        Normalisation::Hypot.divisor(),
    );
    println!(
        "{:>5} {:>7} {:>11} {:>11} {:>9} | {:>10} {:>10} {:>7} {:>7} | {:>10} {:>7} {:>7} | {:>10} {:>7} | {:>8} {:>7}",
        "res",
        "bricks",
        "stored vox",
        "interior",
        "nodes MB",
        "p20 brk MB",
        "p20 tot MB",
        "B/sto",
        "B/int",
        "c16 brk MB",
        "B/sto",
        "B/int",
        "f8 tot MB",
        "B/int",
        "build s",
        "pack s",
    );
    let mut rows: Vec<Row> = Vec::new();
    for levels in MIN_LEVELS..=args.max_levels {
        let options = BuildOptions { brick_size, levels, max_bricks: u32::MAX - 2, ..defaults };
        let start = Instant::now();
        let tree =
            BrickTree::build(&source, displaced::domain(), options).map_err(|e| format!("levels {levels}: {e}"))?;
        let build_seconds = start.elapsed().as_secs_f64();
        let start = Instant::now();
        let packed = VoxelLayout::ALL.map(|layout| PackedTree::new(&tree, layout));
        let pack_seconds = start.elapsed().as_secs_f64();
        let bricks = tree.brick_count();
        let nodes = tree.nodes().len();
        let node_bytes = 8 * nodes;
        let bytes = packed.each_ref().map(PackedTree::bytes);
        let (stored, interior) = (bricks * stored_per_brick, bricks * interior_per_brick);
        let per = |total: usize, voxels: usize| total as f64 / voxels as f64;
        println!(
            "{:>4}³ {bricks:>7} {stored:>11} {interior:>11} {:>9.3} | {:>10.2} {:>10.2} {:>7.2} {:>7.2} | {:>10.2} {:>7.2} {:>7.2} | {:>10.2} {:>7.2} | {build_seconds:>8.2} {pack_seconds:>7.2}",
            tree.resolution(),
            mb(node_bytes as f64),
            mb((bytes[0] - node_bytes) as f64),
            mb(bytes[0] as f64),
            per(bytes[0], stored),
            per(bytes[0], interior),
            mb((bytes[1] - node_bytes) as f64),
            per(bytes[1], stored),
            per(bytes[1], interior),
            mb(bytes[2] as f64),
            per(bytes[2], interior),
        );
        let mut per_level = vec![0; levels as usize];
        for &level in tree.brick_levels() {
            per_level[level as usize] += 1;
        }
        rows.push(Row { levels, bricks, nodes, per_level, bytes });
    }
    println!(
        "(p20 = Paper20, c16 = Compact16, f8 = Compact16Fine8; tot = node pool + brick pool; B/sto, B/int: total bytes per stored / interior voxel)"
    );
    if let Some(peak) = peak_resident_mb() {
        println!("peak resident memory of this process: {peak:.0} MB");
    }
    for row in &rows {
        let finest = row.per_level[0] as f64 / row.bricks as f64;
        println!(
            "{}³ bricks per level, finest first: {:?} ({:.1} % finest)",
            brick_size.side() << (row.levels - 1),
            row.per_level,
            100.0 * finest
        );
    }
    for (a, b) in rows.iter().zip(rows.iter().skip(1)) {
        println!(
            "growth {}³ → {}³: bricks ×{:.3}, nodes ×{:.3}",
            brick_size.side() << (a.levels - 1),
            brick_size.side() << (b.levels - 1),
            b.bricks as f64 / a.bricks as f64,
            b.nodes as f64 / a.nodes as f64,
        );
    }
    let last = rows.last().ok_or("nothing built")?;
    if last.levels >= GOAL_LEVELS {
        let row = rows.iter().find(|r| r.levels == GOAL_LEVELS).ok_or("no 512³ row")?;
        for (layout, &bytes) in VoxelLayout::ALL.iter().zip(&row.bytes) {
            let verdict = if bytes as f64 <= GOAL_BYTES { "meets" } else { "misses" };
            println!("512³ measured, {}: {:.1} MB, {verdict} the goal ≤ 150 MB", layout.name(), mb(bytes as f64));
        }
    } else if rows.len() >= 2 {
        // Bricks ∝ area ∝ res² in the limit; the measured ratio of the last two rows is used.
        let previous = &rows[rows.len() - 2];
        let growth = last.bricks as f64 / previous.bricks as f64;
        let steps = (GOAL_LEVELS - last.levels) as i32;
        let bricks = last.bricks as f64 * growth.powi(steps);
        let node_bytes = 8.0 * last.nodes as f64 * (last.nodes as f64 / previous.nodes as f64).powi(steps);
        println!(
            "512³ EXTRAPOLATED (not built) from the growth ×{growth:.3} per level between the last two rows: ~{bricks:.0} bricks"
        );
        for layout in VoxelLayout::ALL {
            let bytes = bricks * (stored_per_brick * layout.bytes()) as f64 + node_bytes;
            let verdict = if bytes <= GOAL_BYTES { "would meet" } else { "would miss" };
            println!("  {}: ~{:.0} MB, {verdict} the goal ≤ 150 MB", layout.name(), mb(bytes));
        }
    } else {
        println!("one resolution only: nothing to extrapolate to 512³");
    }
    Ok(())
}
