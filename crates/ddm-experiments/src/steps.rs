//! Sphere-tracing steps against the view angle (part of Tables 1/2): where the directional
//! distance maps save steps over the plain distance map.
//!
//! Mehra & Kumar credit the DDMs with "faster convergence near the mesostructure
//! boundary" (§3, Table 1). How much they save depends on the view: a ray seen from
//! straight above reaches the surface in a few steps with either map, while a grazing ray
//! crawls along the walls and tops beside it with the plain map, whose distances count
//! surfaces in every direction. Each angle from the vertical in
//! [`StepsSettings::angles_deg`] is traced with parallel rays from a
//! [`StepsSettings::grid`]² lattice over the tile at [`StepsSettings::azimuths`] azimuths
//! (odd multiples of 22.5° for 8, inside the cones of every map), each map stopping at its
//! first zero voxel (the sphere tracing of Tables 1/2), and the mean steps per ray are
//! recorded; the plain map and the DDM 4×1 also with voxel-exit stepping
//! (`ddm_tracer::Stepping::VoxelExit`, beyond the paper: rows `DM exit`, `DDM 4x1 exit`).

use ddm_tracer::{Method, Stepping, TraceSettings, trace};
use glam::{UVec3, Vec3};

use crate::ExperimentError;
use crate::maps::NamedMaps;
use crate::timing::Ray;

/// View angles from the vertical of the tables, degrees.
pub const ANGLES_DEG: [f32; 10] = [0.0, 15.0, 30.0, 45.0, 55.0, 65.0, 70.0, 75.0, 80.0, 85.0];
/// The maps also traced with [`Stepping::VoxelExit`], and their rows' names.
pub const EXIT_NAMES: [(&str, &str); 2] = [("DM", "DM exit"), ("DDM 4x1", "DDM 4x1 exit")];

/// Settings of [`steps_vs_angle`].
#[derive(Clone, Debug, PartialEq)]
pub struct StepsSettings {
    /// View angles from the vertical, degrees (0 to below 90).
    pub angles_deg: Vec<f32>,
    /// Ray origins per tile axis.
    pub grid: u32,
    /// Azimuths per angle.
    pub azimuths: u32,
    /// Map reads before a ray gives up.
    pub max_steps: u32,
}

impl Default for StepsSettings {
    /// The tables' sweep: [`ANGLES_DEG`], a 24² lattice, 8 azimuths, 512 steps.
    fn default() -> Self {
        Self { angles_deg: ANGLES_DEG.to_vec(), grid: 24, azimuths: 8, max_steps: 512 }
    }
}

impl StepsSettings {
    /// Checks every field.
    pub fn validate(&self) -> Result<(), ExperimentError> {
        if let Some(angle) = self.angles_deg.iter().find(|a| !(0.0..90.0).contains(*a)) {
            return Err(ExperimentError::settings("angles_deg", format!("{angle}° is not in [0°, 90°)")));
        }
        if self.angles_deg.is_empty() || self.grid == 0 || self.azimuths == 0 || self.max_steps == 0 {
            return Err(ExperimentError::settings("angles_deg/grid/azimuths/max_steps", "every one must be non-empty"));
        }
        Ok(())
    }

    /// The parallel rays of `angle_deg` over a tile of `dims`: for each azimuth, a lattice
    /// of origins half a voxel above the slab.
    pub fn rays(&self, dims: UVec3, angle_deg: f32) -> Vec<Ray> {
        let theta = angle_deg.to_radians();
        let grid = self.grid;
        let mut rays = Vec::with_capacity((self.azimuths * grid * grid) as usize);
        for a in 0..self.azimuths {
            let phi = (a as f32 + 0.5) * std::f32::consts::TAU / self.azimuths as f32;
            let direction = Vec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), -theta.cos());
            for j in 0..grid {
                for i in 0..grid {
                    let origin = Vec3::new(
                        (i as f32 + 0.37) * dims.x as f32 / grid as f32,
                        (j as f32 + 0.61) * dims.y as f32 / grid as f32,
                        dims.z as f32 + 0.5,
                    );
                    rays.push((origin, direction));
                }
            }
        }
        rays
    }
}

/// Mean steps of one map at one angle.
#[derive(Clone, Debug, PartialEq)]
pub struct StepsRow {
    /// The mesostructure.
    pub mesostructure: &'static str,
    /// The map (and stepping): a map's name, or an exit row of [`EXIT_NAMES`].
    pub map: &'static str,
    /// The view angle from the vertical, degrees.
    pub angle_deg: f32,
    /// Mean map reads per ray.
    pub mean_steps: f64,
    /// Rays that ran out of steps.
    pub exhausted: usize,
    /// Rays traced.
    pub rays: usize,
    /// `mean_steps` over the `DM` row's at the same angle (NaN without a `DM` map).
    pub steps_over_dm: f64,
}

/// Traces the rays of every angle with every map of `maps` (named as in the tables), and
/// the maps of [`EXIT_NAMES`] again with voxel-exit stepping; rows by angle, then map.
pub fn steps_vs_angle(
    mesostructure: &'static str,
    dims: UVec3,
    maps: &[NamedMaps],
    settings: &StepsSettings,
) -> Result<Vec<StepsRow>, ExperimentError> {
    settings.validate()?;
    if maps.is_empty() {
        return Err(ExperimentError::scene(mesostructure, "no maps to trace"));
    }
    let sphere =
        TraceSettings { method: Method::SphereTracing, max_steps: settings.max_steps, stepping: Stepping::Distance };
    let exit = TraceSettings { stepping: Stepping::VoxelExit, ..sphere };
    let mut rows = Vec::new();
    for &angle in &settings.angles_deg {
        let rays = settings.rays(dims, angle);
        let runs = maps.iter().map(|m| (m.table_map.name, m, sphere)).chain(maps.iter().filter_map(|m| {
            EXIT_NAMES.iter().find(|(of, _)| *of == m.table_map.name).map(|(_, exit_name)| (*exit_name, m, exit))
        }));
        let first = rows.len();
        for (name, map, trace_settings) in runs {
            let (mut steps, mut exhausted) = (0_u64, 0);
            for &(origin, direction) in &rays {
                let out = trace(&map.maps, None, origin, direction, trace_settings);
                steps += u64::from(out.steps);
                exhausted += usize::from(out.exhausted);
            }
            rows.push(StepsRow {
                mesostructure,
                map: name,
                angle_deg: angle,
                mean_steps: steps as f64 / rays.len() as f64,
                exhausted,
                rays: rays.len(),
                steps_over_dm: f64::NAN,
            });
        }
        let dm = rows[first..].iter().find(|r| r.map == "DM").map_or(f64::NAN, |r| r.mean_steps);
        for row in &mut rows[first..] {
            row.steps_over_dm = row.mean_steps / dm;
        }
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use ddm_compress::DistanceMapSettings;

    use super::*;
    use crate::maps::{TableMap, compute_named};

    const DIMS: UVec3 = UVec3::new(8, 8, 4);

    fn floor_maps(kinds: &[TableMap]) -> Vec<NamedMaps> {
        let floor = mesostructure::plane(DIMS, 1.25);
        let settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: true };
        kinds.iter().map(|&k| compute_named("floor", DIMS, &floor, k, settings).unwrap()).collect()
    }

    fn tiny() -> StepsSettings {
        StepsSettings { angles_deg: vec![0.0, 45.0, 80.0], grid: 3, azimuths: 4, max_steps: 256 }
    }

    #[test]
    fn rows_cover_every_angle_map_and_exit_row() {
        let maps = floor_maps(&[TableMap::DM, TableMap::ddm("DDM 2x1", 2, 1), TableMap::ddm("DDM 4x1", 4, 1)]);
        let settings = tiny();
        let rows = steps_vs_angle("floor", DIMS, &maps, &settings).unwrap();
        let names: Vec<_> = rows.iter().take(5).map(|r| r.map).collect();
        assert_eq!(names, ["DM", "DDM 2x1", "DDM 4x1", "DM exit", "DDM 4x1 exit"]);
        assert_eq!(rows.len(), 5 * settings.angles_deg.len());
        for (chunk, &angle) in rows.chunks(5).zip(&settings.angles_deg) {
            for row in chunk {
                assert_eq!((row.angle_deg, row.rays, row.mesostructure), (angle, 4 * 3 * 3, "floor"));
                // Every ray reaches the floor: no ray runs out of steps, each reads a voxel.
                assert_eq!(row.exhausted, 0);
                assert!(row.mean_steps >= 1.0, "{row:?}");
                assert_eq!(row.steps_over_dm, row.mean_steps / chunk[0].mean_steps);
            }
            assert_eq!(chunk[0].steps_over_dm, 1.0);
        }
    }

    #[test]
    fn vertical_rays_onto_a_floor_take_the_same_steps_at_every_origin() {
        // Straight down, every origin sees the same column of distances above the floor.
        let maps = floor_maps(&[TableMap::DM]);
        let settings = StepsSettings { angles_deg: vec![0.0], ..tiny() };
        let sphere = TraceSettings { method: Method::SphereTracing, max_steps: 256, stepping: Stepping::Distance };
        let steps: Vec<u32> =
            settings.rays(DIMS, 0.0).iter().map(|&(o, d)| trace(&maps[0].maps, None, o, d, sphere).steps).collect();
        assert!(steps.iter().all(|&s| s == steps[0]), "{steps:?}");
        let rows = steps_vs_angle("floor", DIMS, &maps, &settings).unwrap();
        assert_eq!(rows[0].mean_steps, f64::from(steps[0]));
    }

    #[test]
    fn without_a_dm_the_ratio_is_nan_and_bad_settings_are_errors() {
        let maps = floor_maps(&[TableMap::ddm("DDM 2x1", 2, 1)]);
        let rows = steps_vs_angle("floor", DIMS, &maps, &tiny()).unwrap();
        assert!(rows.iter().all(|r| r.steps_over_dm.is_nan()));
        let error = steps_vs_angle("floor", DIMS, &maps, &StepsSettings { angles_deg: vec![90.0], ..tiny() });
        assert!(error.unwrap_err().to_string().contains("angles_deg"));
        let error = steps_vs_angle("floor", DIMS, &[], &tiny()).unwrap_err();
        assert!(error.to_string().contains("floor"));
    }
}
