//! `cargo xtask ddm-compression [OUT_DIR] [--quick] [--size WxHxD] [--obj PATH | --height-map PNG]
//! [--scale S | --fit-slab] [--height H]`: the equivalent of
//! Mehra & Kumar's Table 3, measured by `ddm_experiments::compression`: for each
//! mesostructure (maze, bricks, beads, ball, chain mail) on a 64 × 64 × 16 tile (the paper's
//! resolution; 8 × 8 × 4 with `--quick`, any grid with `--size`), the plain distance map and
//! the downward DDMs 2×1, 4×1 and 8×1 compressed with blocks of 2, 4 and 8. Prints a table
//! and writes `ddm_compression.csv`. With `--obj` or `--height-map`, the user's tile
//! instead of the five ([`crate::ddm_input`] says what the coordinates mean and what is
//! checked).

use std::fmt::Write as _;
use std::path::PathBuf;

use ddm_experiments::compression::{CompressionSettings, MapCompression, map_compression};

use crate::cli::{Args, grid_size};
use crate::ddm_input::{self, TileSource};

/// The command's settings.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// Where the CSV goes.
    pub out: PathBuf,
    /// The table's settings.
    pub settings: CompressionSettings,
    /// The user's tile, else the procedural ones.
    pub tile: Option<TileSource>,
}

impl Options {
    /// `[OUT_DIR] [--quick] [--size WxHxD]` and the tile flags of [`crate::ddm_input`].
    pub fn from_args(args: &Args<'_>) -> Result<Self, String> {
        let mut settings = if args.flag("quick") { CompressionSettings::quick() } else { CompressionSettings::paper() };
        if let Some(dims) = args.parse_value("size", grid_size)? {
            settings.dims = dims;
        }
        Ok(Self { out: args.out_dir(), settings, tile: TileSource::from_args(args)? })
    }
}

/// Runs the experiment.
pub fn run(args: &Args<'_>) -> Result<(), String> {
    let Options { out, mut settings, tile } = Options::from_args(args)?;
    let dims = settings.dims;
    let periodic = ddm_input::periodic_from_args(args, tile.as_ref())?;
    settings.map_settings.periodic_xy = periodic;
    let tiles = ddm_input::tiles(tile.as_ref(), dims, periodic)?;
    std::fs::create_dir_all(&out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    println!(
        "DDM compression (Table 3): {}x{}x{} voxels, tolerance {} voxel, {}; {}",
        dims.x,
        dims.y,
        dims.z,
        settings.map_settings.tolerance,
        if periodic { "periodic in x and y" } else { "a single tile (--clamp)" },
        ddm_input::describe(tile.as_ref())
    );
    println!("efficiency = uncompressed / (lookup + atlas); time = computing the map (all its cones)\n");
    let blocks: String = settings.blocks.iter().map(|b| format!(" {:>9}", format!("block {b}"))).collect();
    println!("{:<9} {:>9} {:>8} {:>9}{blocks}", "mesh", "triangles", "map", "time s");
    let mut csv = String::from("mesostructure,triangles,map,cones,block,efficiency,seconds\n");
    for tile in &tiles {
        for row in map_compression(tile.name, &tile.triangles, &settings).map_err(|e| e.to_string())? {
            print_row(&row);
            write_rows(&mut csv, &row)?;
        }
    }
    let path = out.join("ddm_compression.csv");
    std::fs::write(&path, csv).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    println!("\nwrote {}", path.display());
    Ok(())
}

/// One line of the printed table: a map's time and its efficiency per block.
fn print_row(row: &MapCompression) {
    let efficiencies: String = row.efficiencies.iter().map(|(_, e)| format!(" {e:>9.2}")).collect();
    println!("{:<9} {:>9} {:>8} {:>9.2}{efficiencies}", row.mesostructure, row.triangles, row.map, row.seconds);
}

/// The CSV rows of a map: one per block.
fn write_rows(csv: &mut String, row: &MapCompression) -> Result<(), String> {
    for (block, efficiency) in &row.efficiencies {
        writeln!(
            csv,
            "{},{},{},{},{block},{efficiency:.4},{:.3}",
            row.mesostructure, row.triangles, row.map, row.cones, row.seconds
        )
        .map_err(|e| e.to_string())?;
    }
    Ok(())
}
