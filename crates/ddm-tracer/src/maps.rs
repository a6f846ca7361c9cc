//! Where the tracer reads distances: the raw maps or their compressed form (§4; the
//! tracer must not see a difference in its hits), and which cone a ray reads (§3.2,
//! `dir_cone(r, t)` of Algorithm 3.1).

use alloc::vec::Vec;
use core::f32::consts::{FRAC_PI_2, TAU};

use ddm_compress::{CellDistance, CompressedMap, DirectionCones, DistanceMaps};
use glam::{UVec3, Vec3};

/// The direction cones as the tracer (and its WGSL twin) selects them: `azimuths ×
/// elevations` cones over `[elevation_min, elevation_max]`, or a single map for every
/// direction (`azimuths = 0`: the plain distance map).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConeSelector {
    /// Azimuth intervals `m` (0 for the plain distance map).
    pub azimuths: u32,
    /// Elevation intervals `n`.
    pub elevations: u32,
    /// Lowest elevation of the band, radians.
    pub elevation_min: f32,
    /// Highest elevation of the band, radians.
    pub elevation_max: f32,
}

impl ConeSelector {
    /// The selector of `cones` (`None`: the plain map). The band and counts are read back
    /// from the cones themselves (cone 0 starts the band, the last cone ends it).
    pub fn new(cones: Option<DirectionCones>) -> Self {
        let Some(cones) = cones else {
            return Self { azimuths: 0, elevations: 0, elevation_min: -FRAC_PI_2, elevation_max: FRAC_PI_2 };
        };
        let first = cones.cone(0);
        let last = cones.cone(cones.count().saturating_sub(1));
        let (Some(first), Some(last)) = (first, last) else {
            return Self { azimuths: 0, elevations: 0, elevation_min: -FRAC_PI_2, elevation_max: FRAC_PI_2 };
        };
        let azimuths = (0..cones.count())
            .filter(|&i| cones.cone(i).map(|c| c.elevation_min) == Some(first.elevation_min))
            .count() as u32;
        Self {
            azimuths,
            elevations: cones.count() / azimuths.max(1),
            elevation_min: first.elevation_min,
            elevation_max: last.elevation_max,
        }
    }

    /// The cone of the unit `direction` (as [`DirectionCones::cone_of`], with `√(x² + y²)`
    /// in place of `hypot` so that WGSL computes the same), 0 for the plain map, `None`
    /// outside the band. WGSL twin: `trace_select_cone`.
    pub fn select(&self, direction: Vec3) -> Option<u32> {
        if self.azimuths == 0 {
            return Some(0);
        }
        let horizontal = libm::sqrtf(direction.x * direction.x + direction.y * direction.y);
        let elevation = libm::atan2f(direction.z, horizontal);
        let mut azimuth = libm::atan2f(direction.y, direction.x);
        if azimuth < 0.0 {
            azimuth += TAU;
        }
        if azimuth >= TAU {
            azimuth = 0.0;
        }
        if !(elevation >= self.elevation_min && elevation <= self.elevation_max) {
            return None;
        }
        let a = ((azimuth / TAU * self.azimuths as f32) as u32).min(self.azimuths - 1);
        let t = (elevation - self.elevation_min) / (self.elevation_max - self.elevation_min);
        let e = ((t * self.elevations as f32) as u32).min(self.elevations - 1);
        Some(a + self.azimuths * e)
    }
}

/// A source of conservative distances per cone and voxel.
///
/// A ray reads a single cone's map ([`DistanceSource::cone_map`], resolved once per ray);
/// [`DistanceSource::distance`] is the same read for a single voxel.
pub trait DistanceSource {
    /// One cone's distances.
    type ConeMap<'a>: ConeDistances
    where
        Self: 'a;
    /// Grid size in voxels.
    fn dims(&self) -> UVec3;
    /// How rays choose their map.
    fn selector(&self) -> ConeSelector;
    /// The map of cone `cone`, `None` for an index outside the maps.
    fn cone_map(&self, cone: u32) -> Option<Self::ConeMap<'_>>;
    /// The stored distance of `voxel` (inside the grid) in map `cone`; 0 (always safe) for
    /// indices outside the maps.
    fn distance(&self, cone: u32, voxel: UVec3) -> f32 {
        self.cone_map(cone).map_or(0.0, |map| map.distance(voxel))
    }
}

/// The conservative distances of one cone's map.
pub trait ConeDistances {
    /// The stored distance of `voxel`; 0 (always safe) outside the grid.
    fn distance(&self, voxel: UVec3) -> f32;

    /// The stored distance of `voxel` with the cell of voxels from every point of which
    /// it holds (see [`CompressedMap::access_cell`]); by default the voxel alone.
    fn cell_distance(&self, voxel: UVec3) -> CellDistance {
        CellDistance { distance: self.distance(voxel), origin: voxel, size: UVec3::ONE }
    }
}

/// One cone's map of a [`DistanceMaps`]: its values, `x + dims.x (y + dims.y z)`.
#[derive(Clone, Copy, Debug)]
pub struct RawConeMap<'a> {
    dims: UVec3,
    values: &'a [f32],
}

impl ConeDistances for RawConeMap<'_> {
    #[inline]
    fn distance(&self, voxel: UVec3) -> f32 {
        if !voxel.cmplt(self.dims).all() {
            return 0.0;
        }
        let index = (voxel.x + self.dims.x * (voxel.y + self.dims.y * voxel.z)) as usize;
        self.values.get(index).copied().unwrap_or(0.0)
    }
}

impl ConeDistances for &CompressedMap {
    #[inline]
    fn distance(&self, voxel: UVec3) -> f32 {
        self.access(voxel).unwrap_or(0.0)
    }

    /// A block without surface is one cell: the block's minimum holds for all its voxels.
    #[inline]
    fn cell_distance(&self, voxel: UVec3) -> CellDistance {
        self.access_cell(voxel).unwrap_or(CellDistance { distance: 0.0, origin: voxel, size: UVec3::ONE })
    }
}

impl DistanceSource for DistanceMaps {
    type ConeMap<'a> = RawConeMap<'a>;

    fn dims(&self) -> UVec3 {
        self.dims
    }

    fn selector(&self) -> ConeSelector {
        ConeSelector::new(self.cones)
    }

    #[inline]
    fn cone_map(&self, cone: u32) -> Option<RawConeMap<'_>> {
        self.values.get(cone as usize).map(|values| RawConeMap { dims: self.dims, values })
    }
}

/// Every map of a [`DistanceMaps`] compressed with [`CompressedMap`] (§4).
#[derive(Clone, Debug, PartialEq)]
pub struct CompressedMaps {
    /// Grid size in voxels.
    pub dims: UVec3,
    /// The cones of the maps.
    pub cones: Option<DirectionCones>,
    /// One compressed map per cone.
    pub maps: Vec<CompressedMap>,
}

impl CompressedMaps {
    /// Compresses each map of `maps` in blocks of `block` voxels; `None` where
    /// [`CompressedMap::compress`] refuses.
    pub fn compress(maps: &DistanceMaps, block: u32) -> Option<Self> {
        let compressed = maps
            .values
            .iter()
            .map(|values| CompressedMap::compress(values, &maps.surface, maps.dims, block))
            .collect::<Option<Vec<_>>>()?;
        Some(Self { dims: maps.dims, cones: maps.cones, maps: compressed })
    }

    /// Bytes of the uncompressed maps over bytes of the lookup grids plus atlases.
    pub fn compression_efficiency(&self) -> f64 {
        let stored: usize = self.maps.iter().map(|m| m.grid().len() + m.atlas().len()).sum();
        let voxels = f64::from(self.dims.x) * f64::from(self.dims.y) * f64::from(self.dims.z);
        voxels * self.maps.len() as f64 / stored.max(1) as f64
    }
}

impl DistanceSource for CompressedMaps {
    type ConeMap<'a> = &'a CompressedMap;

    fn dims(&self) -> UVec3 {
        self.dims
    }

    fn selector(&self) -> ConeSelector {
        ConeSelector::new(self.cones)
    }

    #[inline]
    fn cone_map(&self, cone: u32) -> Option<&CompressedMap> {
        self.maps.get(cone as usize)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn selection_agrees_with_the_cones_away_from_boundaries() {
        for cones in [DirectionCones::downward(4, 1), DirectionCones::downward(8, 1), DirectionCones::full(3, 2)] {
            let cones = cones.unwrap();
            let selector = ConeSelector::new(Some(cones));
            assert_eq!(selector.azimuths * selector.elevations, cones.count());
            let mut mismatches = 0;
            for k in 0..2000 {
                let a = k as f32 * 0.618_034 * TAU;
                let e = -0.05 - (k as f32 * 0.414_213_5).fract() * 1.4;
                let d = Vec3::new(libm::cosf(e) * libm::cosf(a), libm::cosf(e) * libm::sinf(a), libm::sinf(e));
                if selector.select(d) != cones.cone_of(d) {
                    mismatches += 1;
                }
            }
            assert_eq!(mismatches, 0);
        }
        let plain = ConeSelector::new(None);
        assert_eq!(plain.select(Vec3::Z), Some(0));
        let down = ConeSelector::new(DirectionCones::downward(4, 1));
        assert_eq!(down.select(Vec3::new(0.0, 0.6, 0.8)), None);
    }
}
