//! The distance maps of the tables, by name: the plain distance map (DM) and the downward
//! DDMs m×n of §3.1 (`m` azimuth and `n` elevation intervals over viewing directions).

use std::time::Instant;

use ddm_compress::{DirectionCones, DistanceMapSettings, DistanceMaps, Triangle, compute_distance_maps};
use glam::UVec3;

use crate::ExperimentError;

/// One map of a table: its name and, for a DDM, its cone counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MapKind {
    /// The name in the tables (`DM`, `DDM 4x1`, …).
    pub name: &'static str,
    /// `(azimuths, elevations)` of a downward DDM, `None` for the plain distance map.
    pub cones: Option<(u32, u32)>,
}

impl MapKind {
    /// The plain distance map.
    pub const DM: Self = Self { name: "DM", cones: None };

    /// The downward DDM `azimuths × elevations` named `name`.
    pub const fn ddm(name: &'static str, azimuths: u32, elevations: u32) -> Self {
        Self { name, cones: Some((azimuths, elevations)) }
    }

    /// The cones of the map (`None` for the plain distance map); an error for zero counts.
    pub fn direction_cones(&self) -> Result<Option<DirectionCones>, ExperimentError> {
        match self.cones {
            None => Ok(None),
            Some((azimuths, elevations)) => DirectionCones::downward(azimuths, elevations).map(Some).ok_or_else(|| {
                ExperimentError::settings("cones", format!("{}: no cones {azimuths}x{elevations}", self.name))
            }),
        }
    }
}

/// The maps of Tables 1/2 (`ddm-trace`): DM and the DDMs 2×1, 4×1, 8×1, 4×2.
pub const TRACE_MAPS: [MapKind; 5] = [
    MapKind::DM,
    MapKind::ddm("DDM 2x1", 2, 1),
    MapKind::ddm("DDM 4x1", 4, 1),
    MapKind::ddm("DDM 8x1", 8, 1),
    MapKind::ddm("DDM 4x2", 4, 2),
];

/// The maps of the compression table (`ddm-compression`): DM and the DDMs 2×1, 4×1, 8×1.
pub const COMPRESSION_MAPS: [MapKind; 4] =
    [MapKind::DM, MapKind::ddm("DDM 2x1", 2, 1), MapKind::ddm("DDM 4x1", 4, 1), MapKind::ddm("DDM 8x1", 8, 1)];

/// A computed map with its name and how long computing it took.
#[derive(Clone, Debug)]
pub struct NamedMaps {
    /// The map's kind.
    pub kind: MapKind,
    /// Its values (one map per cone) and surface voxels.
    pub maps: DistanceMaps,
    /// Wall-clock seconds of [`compute_distance_maps`] (all cones).
    pub seconds: f64,
}

/// Computes the map of `kind` for `triangles` on a `dims` grid; `scene` names the scene in
/// the error (an empty or too large grid, a bad tolerance or a non-finite triangle).
pub fn compute_named(
    scene: &str,
    dims: UVec3,
    triangles: &[Triangle],
    kind: MapKind,
    settings: DistanceMapSettings,
) -> Result<NamedMaps, ExperimentError> {
    let cones = kind.direction_cones()?;
    let start = Instant::now();
    let maps = compute_distance_maps(dims, triangles, cones, settings).ok_or_else(|| {
        ExperimentError::scene(
            scene,
            format!(
                "cannot compute the {} maps (empty or too large grid, bad tolerance or a non-finite triangle)",
                kind.name
            ),
        )
    })?;
    Ok(NamedMaps { kind, maps, seconds: start.elapsed().as_secs_f64() })
}

/// The map called `name` in `maps`.
pub fn find<'a>(maps: &'a [NamedMaps], name: &str) -> Option<&'a NamedMaps> {
    maps.iter().find(|m| m.kind.name == name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn map_kinds_have_the_cone_counts_of_their_names() {
        for kind in TRACE_MAPS.iter().chain(&COMPRESSION_MAPS) {
            let cones = kind.direction_cones().unwrap();
            match kind.cones {
                None => assert!(cones.is_none() && kind.name == "DM"),
                Some((a, e)) => {
                    assert_eq!(kind.name, format!("DDM {a}x{e}"));
                    assert_eq!(cones.unwrap().count(), a * e);
                }
            }
        }
    }

    #[test]
    fn zero_cones_are_an_error_naming_the_map() {
        let error = MapKind::ddm("DDM 0x1", 0, 1).direction_cones().unwrap_err();
        assert!(error.to_string().contains("DDM 0x1"), "{error}");
    }

    #[test]
    fn an_empty_grid_is_an_error_naming_the_scene_and_map() {
        let settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: true };
        let floor = mesostructure::plane(UVec3::new(4, 4, 2), 0.5);
        let error = compute_named("floor", UVec3::new(0, 4, 2), &floor, MapKind::DM, settings).unwrap_err();
        let text = error.to_string();
        assert!(text.contains("floor") && text.contains("DM"), "{text}");
    }
}
