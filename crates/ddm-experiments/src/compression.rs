//! The equivalent of Mehra & Kumar's Table 3: the plain distance map and the downward DDMs
//! 2×1, 4×1 and 8×1 of each mesostructure, each cone's map compressed with blocks of 2, 4
//! and 8 (§4, Algorithm A.1); the compression efficiency is uncompressed size / (lookup
//! grid + atlas) ([`CompressedMap::compression_efficiency`]), averaged over a map's cones.

use ddm_compress::{CompressedMap, DistanceMapSettings, Triangle};
use glam::UVec3;

use crate::ExperimentError;
use crate::maps::{COMPRESSION_MAPS, TableMap, compute_named};

/// Settings of the compression table.
#[derive(Clone, Debug, PartialEq)]
pub struct CompressionSettings {
    /// Voxels of the tile.
    pub dims: UVec3,
    /// How the maps are computed.
    pub map_settings: DistanceMapSettings,
    /// The maps, in table order.
    pub maps: Vec<TableMap>,
    /// Block sides of the compression, in table order (1 to 64).
    pub blocks: Vec<u32>,
}

impl CompressionSettings {
    /// The paper's table: a 64 × 64 × 16 tile, tolerance 0.25 voxel, periodic in x and y,
    /// [`COMPRESSION_MAPS`], blocks of 2, 4 and 8.
    pub fn paper() -> Self {
        Self {
            dims: UVec3::new(64, 64, 16),
            map_settings: DistanceMapSettings { tolerance: 0.25, periodic_xy: true },
            maps: COMPRESSION_MAPS.to_vec(),
            blocks: vec![2, 4, 8],
        }
    }

    /// [`CompressionSettings::paper`] on an 8 × 8 × 4 tile: seconds instead of minutes.
    pub fn quick() -> Self {
        Self { dims: UVec3::new(8, 8, 4), ..Self::paper() }
    }

    /// Checks the fields that [`map_compression`] does not meet as a scene error.
    pub fn validate(&self) -> Result<(), ExperimentError> {
        if self.dims.cmpeq(UVec3::ZERO).any() {
            return Err(ExperimentError::settings("dims", format!("every size must be positive, not {}", self.dims)));
        }
        if let Some(&block) = self.blocks.iter().find(|&&b| b == 0 || b > 64) {
            return Err(ExperimentError::settings("blocks", format!("a block side must be 1 to 64, not {block}")));
        }
        if self.maps.is_empty() || self.blocks.is_empty() {
            return Err(ExperimentError::settings("maps/blocks", "the table needs a map and a block size"));
        }
        Ok(())
    }
}

/// One map of one mesostructure in the table.
#[derive(Clone, Debug, PartialEq)]
pub struct MapCompression {
    /// The mesostructure.
    pub mesostructure: String,
    /// Its triangles.
    pub triangles: usize,
    /// The map's name.
    pub map: &'static str,
    /// Its cones (1 for the plain map).
    pub cones: usize,
    /// Wall-clock seconds of computing the map (all its cones).
    pub seconds: f64,
    /// `(block, mean efficiency over the cones)` in the order of the settings' blocks.
    pub efficiencies: Vec<(u32, f64)>,
}

/// The table's rows of the mesh `triangles` named `name`: one per map of `settings`.
pub fn map_compression(
    name: &str,
    triangles: &[Triangle],
    settings: &CompressionSettings,
) -> Result<Vec<MapCompression>, ExperimentError> {
    settings.validate()?;
    let mut rows = Vec::with_capacity(settings.maps.len());
    for &table_map in &settings.maps {
        let named = compute_named(name, settings.dims, triangles, table_map, settings.map_settings)?;
        let maps = &named.maps;
        let mut efficiencies = Vec::with_capacity(settings.blocks.len());
        for &block in &settings.blocks {
            // Every cone's map is compressed on its own; report their mean.
            let mut sum = 0.0;
            for values in &maps.values {
                let compressed =
                    CompressedMap::compress(values, &maps.surface, settings.dims, block).map_err(|error| {
                        ExperimentError::scene(
                            name,
                            format!("{}: cannot compress with block {block}: {error}", table_map.name),
                        )
                    })?;
                sum += compressed.compression_efficiency();
            }
            efficiencies.push((block, sum / maps.values.len() as f64));
        }
        rows.push(MapCompression {
            mesostructure: name.to_owned(),
            triangles: triangles.len(),
            map: table_map.name,
            cones: maps.values.len(),
            seconds: named.seconds,
            efficiencies,
        });
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A floor at z = 1.25 on 8 × 8 × 4 voxels crosses exactly the voxel layer z = 1, the
    /// same in every map: blocks of 2 keep the 16 blocks of the lowest block layer in the
    /// atlas (16 × 8 values) beside a 4 × 4 × 2 grid, blocks of 4 all 4 blocks (4 × 64)
    /// beside 4 entries, the block of 8 one 512-value block beside 1 entry.
    #[test]
    fn a_floor_compresses_as_counted_by_hand() {
        let settings = CompressionSettings::quick();
        let floor = mesostructure::plane(settings.dims, 1.25);
        let rows = map_compression("floor", &floor, &settings).unwrap();
        let voxels = 256.0;
        let expected = [(2, voxels / (32.0 + 128.0)), (4, voxels / (4.0 + 256.0)), (8, voxels / (1.0 + 512.0))];
        let names: Vec<_> = rows.iter().map(|r| (r.map, r.cones)).collect();
        assert_eq!(names, [("DM", 1), ("DDM 2x1", 2), ("DDM 4x1", 4), ("DDM 8x1", 8)]);
        for row in &rows {
            assert_eq!((row.mesostructure.as_str(), row.triangles), ("floor", floor.len()));
            assert!(row.seconds >= 0.0);
            for (&(block, efficiency), &(expected_block, expected_efficiency)) in row.efficiencies.iter().zip(&expected)
            {
                assert_eq!(block, expected_block);
                assert!((efficiency - expected_efficiency).abs() < 1e-12, "{} block {block}: {efficiency}", row.map);
            }
        }
    }

    #[test]
    fn bad_settings_name_their_field() {
        let floor = mesostructure::plane(UVec3::new(8, 8, 4), 1.25);
        for (settings, field) in [
            (CompressionSettings { blocks: vec![2, 0], ..CompressionSettings::quick() }, "blocks"),
            (CompressionSettings { blocks: vec![65], ..CompressionSettings::quick() }, "blocks"),
            (CompressionSettings { dims: UVec3::new(8, 0, 4), ..CompressionSettings::quick() }, "dims"),
            (CompressionSettings { maps: Vec::new(), ..CompressionSettings::quick() }, "maps"),
        ] {
            let error = map_compression("floor", &floor, &settings).unwrap_err();
            assert!(matches!(error, ExperimentError::InvalidSettings { .. }), "{error}");
            assert!(error.to_string().contains(field), "{error}");
        }
    }
}
