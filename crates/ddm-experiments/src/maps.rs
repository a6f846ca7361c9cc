//! The distance maps of the tables, by name: the plain distance map (DM) and the downward
//! DDMs m×n of §3.1 (`m` azimuth and `n` elevation intervals over viewing directions).

use std::time::Instant;

use ddm_compress::{DirectionCones, DistanceMapSettings, DistanceMaps, MapKind, Triangle, compute_distance_maps};
use glam::UVec3;

use crate::ExperimentError;

/// The shape of a table's map: the plain distance map or a downward DDM.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MapShape {
    /// The plain distance map (DM).
    Plain,
    /// The downward DDM `azimuths × elevations` (cones over `φ ∈ [-π/2, 0]`).
    Downward {
        /// Azimuth intervals `m`.
        azimuths: u32,
        /// Elevation intervals `n`.
        elevations: u32,
    },
}

/// One map of a table: its name and shape.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TableMap {
    /// The name in the tables (`DM`, `DDM 4x1`, …).
    pub name: &'static str,
    /// Plain, or a downward DDM with its cone counts.
    pub shape: MapShape,
}

impl TableMap {
    /// The plain distance map.
    pub const DM: Self = Self { name: "DM", shape: MapShape::Plain };

    /// The downward DDM `azimuths × elevations` named `name`.
    pub const fn ddm(name: &'static str, azimuths: u32, elevations: u32) -> Self {
        Self { name, shape: MapShape::Downward { azimuths, elevations } }
    }

    /// The [`MapKind`] of the map.
    ///
    /// # Errors
    ///
    /// [`ExperimentError::InvalidSettings`] naming the map and the cones' error
    /// ([`ddm_compress::ConeError`]) for invalid cone counts.
    pub fn map_kind(&self) -> Result<MapKind, ExperimentError> {
        match self.shape {
            MapShape::Plain => Ok(MapKind::Plain),
            MapShape::Downward { azimuths, elevations } => DirectionCones::downward(azimuths, elevations)
                .map(MapKind::Directional)
                .map_err(|error| ExperimentError::settings("cones", format!("{}: {error}", self.name))),
        }
    }
}

/// The maps of Tables 1/2 (`ddm-trace`): DM and the DDMs 2×1, 4×1, 8×1, 4×2.
pub const TRACE_MAPS: [TableMap; 5] = [
    TableMap::DM,
    TableMap::ddm("DDM 2x1", 2, 1),
    TableMap::ddm("DDM 4x1", 4, 1),
    TableMap::ddm("DDM 8x1", 8, 1),
    TableMap::ddm("DDM 4x2", 4, 2),
];

/// The maps of the compression table (`ddm-compression`): DM and the DDMs 2×1, 4×1, 8×1.
pub const COMPRESSION_MAPS: [TableMap; 4] =
    [TableMap::DM, TableMap::ddm("DDM 2x1", 2, 1), TableMap::ddm("DDM 4x1", 4, 1), TableMap::ddm("DDM 8x1", 8, 1)];

/// A computed map with its name and how long computing it took.
#[derive(Clone, Debug)]
pub struct NamedMaps {
    /// The map's name and shape.
    pub table_map: TableMap,
    /// Its values (one map per cone) and surface voxels.
    pub maps: DistanceMaps,
    /// Wall-clock seconds of [`compute_distance_maps`] (all cones).
    pub seconds: f64,
}

/// Computes the map `table_map` for `triangles` on a `dims` grid.
///
/// # Errors
///
/// [`ExperimentError::InvalidSettings`] for invalid cone counts (see
/// [`TableMap::map_kind`]); [`ExperimentError::Scene`] naming `scene`, the map and the
/// [`ddm_compress::DistanceMapError`] (an empty or too large grid, a bad tolerance or a
/// non-finite triangle).
pub fn compute_named(
    scene: &str,
    dims: UVec3,
    triangles: &[Triangle],
    table_map: TableMap,
    settings: DistanceMapSettings,
) -> Result<NamedMaps, ExperimentError> {
    let kind = table_map.map_kind()?;
    let start = Instant::now();
    let maps = compute_distance_maps(dims, triangles, kind, settings).map_err(|error| {
        ExperimentError::scene(scene, format!("cannot compute the {} maps: {error}", table_map.name))
    })?;
    Ok(NamedMaps { table_map, maps, seconds: start.elapsed().as_secs_f64() })
}

/// The map called `name` in `maps`.
pub fn find<'a>(maps: &'a [NamedMaps], name: &str) -> Option<&'a NamedMaps> {
    maps.iter().find(|m| m.table_map.name == name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn map_kinds_have_the_cone_counts_of_their_names() {
        for table_map in TRACE_MAPS.iter().chain(&COMPRESSION_MAPS) {
            let kind = table_map.map_kind().unwrap();
            match table_map.shape {
                MapShape::Plain => assert!(kind == MapKind::Plain && table_map.name == "DM"),
                MapShape::Downward { azimuths, elevations } => {
                    assert_eq!(table_map.name, format!("DDM {azimuths}x{elevations}"));
                    let cones = DirectionCones::downward(azimuths, elevations).unwrap();
                    assert_eq!(kind, MapKind::Directional(cones));
                }
            }
        }
    }

    #[test]
    fn zero_cones_are_an_error_naming_the_map_and_the_count() {
        for (table_map, why) in
            [(TableMap::ddm("DDM 0x1", 0, 1), "azimuth"), (TableMap::ddm("DDM 4x0", 4, 0), "elevation")]
        {
            let error = table_map.map_kind().unwrap_err();
            assert!(matches!(error, ExperimentError::InvalidSettings { field: "cones", .. }), "{error}");
            let text = error.to_string();
            assert!(text.contains(table_map.name) && text.contains(why), "{text}");
        }
    }

    #[test]
    fn an_invalid_scene_is_an_error_naming_the_scene_the_map_and_why() {
        let settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: true };
        let floor = mesostructure::plane(UVec3::new(4, 4, 2), 0.5);
        let error = compute_named("floor", UVec3::new(0, 4, 2), &floor, TableMap::DM, settings).unwrap_err();
        let text = error.to_string();
        assert!(text.contains("floor") && text.contains("DM") && text.contains("no voxel"), "{text}");
        let mut broken = floor.clone();
        broken[1].0[0].x = f32::NAN;
        let ddm = TableMap::ddm("DDM 4x1", 4, 1);
        let text = compute_named("floor", UVec3::new(4, 4, 2), &broken, ddm, settings).unwrap_err().to_string();
        assert!(text.contains("floor") && text.contains("DDM 4x1") && text.contains("triangle 1"), "{text}");
    }
}
