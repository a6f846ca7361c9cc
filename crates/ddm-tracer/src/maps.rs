//! Where the tracer reads distances: the raw maps or their compressed form (§4; the
//! tracer must not see a difference in its hits), and which cone a ray reads (§3.2,
//! `dir_cone(r, t)` of Algorithm 3.1).

use alloc::vec::Vec;
use core::f32::consts::{FRAC_PI_2, TAU};
use core::fmt;

use ddm_compress::{CellDistance, CompressError, CompressedMap, DistanceMaps, MapKind};
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
    /// The selector of the maps of `kind`: `azimuths = 0` for [`MapKind::Plain`], else the
    /// cones' counts and band.
    pub fn new(kind: MapKind) -> Self {
        match kind {
            MapKind::Plain => Self { azimuths: 0, elevations: 0, elevation_min: -FRAC_PI_2, elevation_max: FRAC_PI_2 },
            MapKind::Directional(cones) => Self {
                azimuths: cones.azimuths(),
                elevations: cones.elevations(),
                elevation_min: cones.elevation_min(),
                elevation_max: cones.elevation_max(),
            },
        }
    }

    /// The cone of the unit `direction` (as [`ddm_compress::DirectionCones::cone_of`], with `√(x² + y²)`
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
    /// Whether the tile repeats in x and y (rays wrap around it); otherwise nothing lies
    /// outside the slab `[0, L_x] × [0, L_y]` and a ray that leaves it misses
    /// ([`ddm_compress::DistanceMaps::periodic_xy`]).
    fn periodic_xy(&self) -> bool;
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
        ConeSelector::new(self.kind)
    }

    fn periodic_xy(&self) -> bool {
        self.periodic_xy
    }

    #[inline]
    fn cone_map(&self, cone: u32) -> Option<RawConeMap<'_>> {
        self.values.get(cone as usize).map(|values| RawConeMap { dims: self.dims, values })
    }
}

/// Why [`CompressedMaps::compress`] refused a [`DistanceMaps`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CompressMapsError {
    /// The maps' `values` do not hold one map per map of their kind
    /// ([`MapKind::map_count`]).
    MapCount {
        /// Maps of the kind.
        expected: u32,
        /// Maps in `values`.
        found: usize,
    },
    /// [`CompressedMap::compress`] refused map `map` (the cone's index).
    Map {
        /// The map's index in `values`.
        map: usize,
        /// Why it was refused.
        error: CompressError,
    },
}

impl fmt::Display for CompressMapsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::MapCount { expected, found } => {
                write!(f, "{found} distance maps where their kind has {expected}")
            }
            Self::Map { map, error } => write!(f, "map {map}: {error}"),
        }
    }
}

impl core::error::Error for CompressMapsError {
    fn source(&self) -> Option<&(dyn core::error::Error + 'static)> {
        match self {
            Self::MapCount { .. } => None,
            Self::Map { error, .. } => Some(error),
        }
    }
}

/// Every map of a [`DistanceMaps`] compressed with [`CompressedMap`] (§4).
#[derive(Clone, Debug, PartialEq)]
pub struct CompressedMaps {
    /// Grid size in voxels.
    pub dims: UVec3,
    /// Which maps these are: `maps` has [`MapKind::map_count`] entries.
    pub kind: MapKind,
    /// One compressed map per cone.
    pub maps: Vec<CompressedMap>,
    /// Whether the tile repeats in x and y (from [`DistanceMaps::periodic_xy`]).
    pub periodic_xy: bool,
}

impl CompressedMaps {
    /// Compresses each map of `maps` in blocks of `block` voxels.
    ///
    /// # Errors
    ///
    /// [`CompressMapsError::MapCount`] when `maps.values` does not hold one map per map of
    /// `maps.kind`, else [`CompressMapsError::Map`] with the first map that
    /// [`CompressedMap::compress`] refuses and why.
    pub fn compress(maps: &DistanceMaps, block: u32) -> Result<Self, CompressMapsError> {
        let expected = maps.kind.map_count();
        if maps.values.len() as u64 != u64::from(expected) {
            return Err(CompressMapsError::MapCount { expected, found: maps.values.len() });
        }
        let compressed = maps
            .values
            .iter()
            .enumerate()
            .map(|(map, values)| {
                CompressedMap::compress(values, &maps.surface, maps.dims, block)
                    .map_err(|error| CompressMapsError::Map { map, error })
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self { dims: maps.dims, kind: maps.kind, maps: compressed, periodic_xy: maps.periodic_xy })
    }

    /// These maps with every atlas value rounded down to binary16
    /// ([`CompressedMap::with_f16_atlas`]): the CPU reference of a
    /// [`GpuScene::with_f16_atlas`](crate::GpuScene::with_f16_atlas), still conservative.
    pub fn with_f16_atlas(&self) -> Self {
        let maps = self.maps.iter().map(CompressedMap::with_f16_atlas).collect();
        Self { dims: self.dims, kind: self.kind, maps, periodic_xy: self.periodic_xy }
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
        ConeSelector::new(self.kind)
    }

    fn periodic_xy(&self) -> bool {
        self.periodic_xy
    }

    #[inline]
    fn cone_map(&self, cone: u32) -> Option<&CompressedMap> {
        self.maps.get(cone as usize)
    }
}

#[cfg(test)]
mod tests {
    use alloc::string::ToString;

    use ddm_compress::DirectionCones;

    use super::*;

    #[test]
    fn selection_agrees_with_the_cones_away_from_boundaries() {
        for cones in [DirectionCones::downward(4, 1), DirectionCones::downward(8, 1), DirectionCones::full(3, 2)] {
            let cones = cones.unwrap();
            let selector = ConeSelector::new(MapKind::Directional(cones));
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
        let plain = ConeSelector::new(MapKind::Plain);
        assert_eq!(plain.select(Vec3::Z), Some(0));
        let down = ConeSelector::new(MapKind::Directional(DirectionCones::downward(4, 1).unwrap()));
        assert_eq!(down.select(Vec3::new(0.0, 0.6, 0.8)), None);
    }

    #[test]
    fn the_selector_band_is_the_cones_band() {
        // The band as the cones themselves bound it: cone 0 starts it, the last cone ends it.
        for cones in [DirectionCones::downward(4, 2), DirectionCones::full(3, 3), DirectionCones::new(5, 3, -1.0, 0.3)]
        {
            let cones = cones.unwrap();
            let selector = ConeSelector::new(MapKind::Directional(cones));
            let (first, last) = (cones.cone(0).unwrap(), cones.cone(cones.count() - 1).unwrap());
            assert_eq!((selector.elevation_min, selector.elevation_max), (first.elevation_min, last.elevation_max));
            assert_eq!((selector.azimuths, selector.elevations), (cones.azimuths(), cones.elevations()));
        }
    }

    #[test]
    fn compressing_maps_names_the_map_and_the_reason() {
        let dims = UVec3::new(2, 2, 1);
        let cones = DirectionCones::downward(2, 1).unwrap();
        let mut maps = DistanceMaps {
            dims,
            kind: MapKind::Directional(cones),
            values: alloc::vec![alloc::vec![1.0; 4], alloc::vec![2.0; 4]],
            surface: alloc::vec![false; 4],
            max_distance: 3.0,
            periodic_xy: true,
        };
        let compressed = CompressedMaps::compress(&maps, 2).unwrap();
        assert_eq!((compressed.kind, compressed.maps.len()), (maps.kind, 2));
        assert_eq!(
            CompressedMaps::compress(&maps, 0),
            Err(CompressMapsError::Map { map: 0, error: CompressError::InvalidBlock { block: 0 } })
        );
        maps.values[1][3] = -1.0;
        let error = CompressedMaps::compress(&maps, 2).unwrap_err();
        assert_eq!(
            error,
            CompressMapsError::Map { map: 1, error: CompressError::InvalidValue { index: 3, value: -1.0 } }
        );
        assert!(error.to_string().starts_with("map 1: "), "{error}");
        maps.kind = MapKind::Plain;
        assert_eq!(CompressedMaps::compress(&maps, 2), Err(CompressMapsError::MapCount { expected: 1, found: 2 }));
    }
}
