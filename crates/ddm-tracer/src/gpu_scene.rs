//! The tracer's scene on the GPU: the uniforms, the per-cone map table and the result of
//! the WGSL twin's `trace_ray`, laid out for WGSL, and the packing of maps, patches and a
//! relief height map into the flat storage buffers that `wgsl/ddm_tracer.wgsl` reads
//! (bindings 3–8).

use alloc::vec::Vec;
use core::fmt;

use glam::{UVec2, UVec3, UVec4, Vec4};
use gpu_layout::gpu_struct;

use ddm_compress::DistanceMaps;

use crate::maps::{CompressedMaps, ConeSelector};
use crate::patch::TracePatch;
use crate::patches::VoxelPatches;
use crate::pipeline_constants::{AtlasStorage, METHOD_RELIEF, TracePipelineConstants, method_code, stepping_code};
use crate::relief::HeightMap;
use crate::trace::TraceSettings;

gpu_struct! {
    /// The tracer's uniforms: what may change without a new pipeline. The method, the
    /// stepping and the tiling are pipeline constants ([`TracePipelineConstants`]).
    pub struct TraceUniforms {
        /// `(L_x, L_y, L_z, max_steps)`.
        pub dims_max_steps: UVec4,
        /// `(azimuths, elevations, 0, ray_count)`; `azimuths = 0` for the plain map.
        pub cones_rays: UVec4,
        /// `(elevation_min, elevation_max, 0, 0)` of the cone band, radians.
        pub elevation_band: Vec4,
        /// Relief mapping: `(linear_steps, binary_steps, texels_per_voxel, 0)`.
        pub relief: UVec4,
    }
}

gpu_struct! {
    /// Where one cone's compressed map lives in the shared grid and atlas buffers.
    pub struct TraceConeMap {
        /// `(dims.x, dims.y, dims.z, block)`.
        pub dims_block: UVec4,
        /// `(grid.x, grid.y, grid.z, atlas_base)`: lookup-grid size, first atlas word.
        pub grid_atlas_base: UVec4,
        /// `(grid_base, 0, 0, 0)`: first lookup-grid word.
        pub grid_base: UVec4,
    }
}

gpu_struct! {
    /// One traced ray (the output of the compute pass).
    pub struct TraceResult {
        /// Hit point in `xyz`, ray parameter in `w` (zero for a miss).
        pub point_t: Vec4,
        /// Unit normal in `xyz`; `w` 1 for a hit, 0 for a miss.
        pub normal_hit: Vec4,
        /// `(steps, cone, exhausted, voxel index)`.
        pub counts: UVec4,
    }
}

/// Why [`GpuScene::new`] or [`GpuScene::with_relief`] cannot pack a scene. The checks of
/// each run in the order of the variants; the first that fails is returned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum GpuSceneError {
    /// [`CompressedMaps::maps`] does not hold one map per map of its kind.
    MapCount {
        /// Maps of the kind ([`ddm_compress::MapKind::map_count`]).
        expected: u32,
        /// Maps present.
        found: usize,
    },
    /// Map `map`'s size differs from [`CompressedMaps::dims`].
    MapDims {
        /// The map's index.
        map: usize,
        /// The maps' grid size.
        expected: UVec3,
        /// The map's own size.
        found: UVec3,
    },
    /// An uncompressed map does not hold one value per voxel ([`GpuScene::uncompressed`]).
    MapValues {
        /// The map's index.
        map: usize,
        /// Voxels of the grid.
        expected: usize,
        /// Values present.
        found: usize,
    },
    /// A distance of an uncompressed map is negative or NaN ([`GpuScene::uncompressed`]).
    InvalidDistance {
        /// The map's index.
        map: usize,
        /// The voxel's index, `x + L_x (y + L_y z)`.
        voxel: usize,
    },
    /// The patches were built for a periodic tile and the maps for a single one, or the
    /// other way round ([`crate::PatchSettings::periodic_xy`]).
    PatchTiling {
        /// Whether the maps are periodic.
        maps_periodic: bool,
    },
    /// Relief mapping was asked of a tile that does not repeat (its height map wraps).
    ReliefNeedsPeriodicTile,
    /// An `f16` atlas was asked of a scene without an atlas ([`GpuScene::uncompressed`]
    /// keeps every distance in its lookup grid).
    NoAtlas,
    /// The patches were built for another grid than the maps'.
    PatchDims {
        /// The maps' grid size.
        expected: UVec3,
        /// The patches' grid size.
        found: UVec3,
    },
    /// An index into the named buffer would not fit in a `u32` (WGSL indices are `u32`).
    BufferOverflow {
        /// The buffer (`atlas`, `grid`, `patch offsets`, `relief heights`).
        buffer: &'static str,
    },
    /// The relief height map has no texel per voxel.
    ReliefTexelsPerVoxel,
    /// The relief height map does not cover the tile at its texels per voxel.
    ReliefTexels {
        /// `dims.xy × texels_per_voxel`.
        expected: UVec2,
        /// [`HeightMap::texels`]`.xy`.
        found: UVec2,
    },
    /// The relief height map does not hold one height per texel.
    ReliefHeights {
        /// Texels of the map.
        expected: usize,
        /// Heights present.
        found: usize,
    },
}

impl fmt::Display for GpuSceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::MapCount { expected, found } => {
                write!(f, "GPU scene: {found} compressed maps where their kind has {expected}")
            }
            Self::MapDims { map, expected, found } => {
                write!(f, "GPU scene: map {map} is {found} voxels, the maps' grid {expected}")
            }
            Self::PatchTiling { maps_periodic } => {
                let (maps, patches) =
                    if *maps_periodic { ("periodic", "a single tile") } else { ("a single tile", "periodic") };
                write!(f, "GPU scene: the maps are {maps} but the patches were built {patches}")
            }
            Self::ReliefNeedsPeriodicTile => {
                write!(f, "GPU scene: relief mapping needs a periodic tile (its height map wraps)")
            }
            Self::NoAtlas => {
                write!(f, "GPU scene: an f16 atlas needs compressed maps (uncompressed ones have no atlas)")
            }
            Self::PatchDims { expected, found } => {
                write!(f, "GPU scene: the patches' grid {found} differs from the maps' grid {expected}")
            }
            Self::MapValues { map, expected, found } => {
                write!(f, "GPU scene: uncompressed map {map} holds {found} values for {expected} voxels")
            }
            Self::InvalidDistance { map, voxel } => {
                write!(f, "GPU scene: map {map} holds a negative or NaN distance at voxel {voxel}")
            }
            Self::BufferOverflow { buffer } => write!(f, "GPU scene: the {buffer} buffer outgrows u32 indices"),
            Self::ReliefTexelsPerVoxel => write!(f, "GPU scene: the relief height map has 0 texels per voxel"),
            Self::ReliefTexels { expected, found } => write!(
                f,
                "GPU scene: the relief height map has {}×{} texels, the tile needs {}×{}",
                found.x, found.y, expected.x, expected.y
            ),
            Self::ReliefHeights { expected, found } => {
                write!(f, "GPU scene: the relief height map has {found} heights for {expected} texels")
            }
        }
    }
}

impl core::error::Error for GpuSceneError {}

/// Everything the compute pass reads, as flat buffers (storage bindings 3–8 of
/// `shaders/ddm_tracer.wgsl`), and the constants its pipeline is specialised for.
#[derive(Clone, Debug, PartialEq)]
pub struct GpuScene {
    /// The uniforms (binding 0), `ray_count` filled by [`GpuScene::uniforms`].
    pub uniforms: TraceUniforms,
    /// The values of the WGSL twin's overridable constants for this scene: a pipeline that
    /// traces it is created with [`TracePipelineConstants::constants`].
    pub pipeline_constants: TracePipelineConstants,
    /// One entry per cone.
    pub cone_maps: Vec<TraceConeMap>,
    /// All lookup grids, one after the other.
    pub grid: Vec<u32>,
    /// All atlases, one after the other, as [`pipeline_constants`](Self::pipeline_constants)`.atlas`
    /// says: `f32` bits, or binary16 pairs. Map `k`'s values start at value (not word)
    /// `cone_maps[k].grid_atlas_base.w`.
    pub atlas: Vec<u32>,
    /// How many values [`atlas`](Self::atlas) holds (0 without compressed maps; the buffer
    /// then holds one placeholder word).
    pub atlas_values: usize,
    /// `VoxelPatches::offsets` (one zero entry per voxel plus one when there are none).
    pub patch_offsets: Vec<u32>,
    /// The patches (one zero patch when there are none: WGSL arrays are never empty).
    pub patches: Vec<TracePatch>,
    /// The relief height map, `HeightMap::heights` (one zero when there is none).
    pub heights: Vec<f32>,
}

impl GpuScene {
    /// Packs `maps` and `patches` for `settings`.
    ///
    /// # Errors
    ///
    /// [`GpuSceneError::MapCount`] or [`GpuSceneError::MapDims`] for maps that disagree
    /// with their kind or grid, [`GpuSceneError::PatchTiling`] when the patches were built
    /// for another tiling ([`crate::PatchSettings::periodic_xy`]) than the maps',
    /// [`GpuSceneError::PatchDims`] when the patches' grid differs
    /// from the maps', [`GpuSceneError::BufferOverflow`] when a buffer index would overflow
    /// `u32`.
    pub fn new(
        maps: &CompressedMaps,
        patches: Option<&VoxelPatches>,
        settings: TraceSettings,
    ) -> Result<Self, GpuSceneError> {
        let dims: UVec3 = maps.dims;
        let expected = maps.kind.map_count();
        if maps.maps.len() as u64 != u64::from(expected) {
            return Err(GpuSceneError::MapCount { expected, found: maps.maps.len() });
        }
        if let Some((map, found)) = maps.maps.iter().map(|m| m.dims()).enumerate().find(|&(_, d)| d != dims) {
            return Err(GpuSceneError::MapDims { map, expected: dims, found });
        }
        let selector = ConeSelector::new(maps.kind);
        let mut cone_maps = Vec::with_capacity(maps.maps.len());
        let (mut grid, mut atlas) = (Vec::new(), Vec::new());
        let overflow = |buffer| GpuSceneError::BufferOverflow { buffer };
        for map in &maps.maps {
            let g = ddm_compress::compress::grid_dims(map.dims(), map.block());
            cone_maps.push(TraceConeMap {
                dims_block: map.dims().extend(map.block()),
                grid_atlas_base: g.extend(u32::try_from(atlas.len()).map_err(|_| overflow("atlas"))?),
                grid_base: UVec4::new(u32::try_from(grid.len()).map_err(|_| overflow("grid"))?, 0, 0, 0),
            });
            grid.extend_from_slice(map.grid());
            atlas.extend(map.atlas().iter().map(|v| v.to_bits()));
        }
        // Shifts where every map shares one power-of-two block side.
        let block_shift = maps.maps.first().and_then(|m| m.block_shift());
        let block_shift = block_shift.filter(|&shift| maps.maps.iter().all(|m| m.block_shift() == Some(shift)));
        let mut scene = Self::with_maps(dims, maps.periodic_xy, selector, cone_maps, grid, atlas, patches, settings)?;
        scene.pipeline_constants.block_shift = block_shift;
        Ok(scene)
    }

    /// Packs uncompressed `maps` and `patches` for `settings`: per cone a lookup grid of one
    /// word per voxel holding the voxel's own distance (the layout of a [`CompressedMaps`]
    /// with block 1 and no voxel flagged as surface, so that the WGSL twin reads every
    /// sample with one load and never the atlas). The tracer sees exactly the distances
    /// of `maps`: it traces as [`trace()`](crate::trace()) over the [`DistanceMaps`] themselves.
    ///
    /// # Errors
    ///
    /// [`GpuSceneError::MapCount`] when `maps.values` does not hold one map per map of its
    /// kind, [`GpuSceneError::MapValues`] when a map does not hold one value per voxel,
    /// [`GpuSceneError::InvalidDistance`] for a negative or NaN distance (whose bits would
    /// read as the surface flag or as no distance), and the errors of [`GpuScene::new`]
    /// for the patches and buffer sizes.
    pub fn uncompressed(
        maps: &DistanceMaps,
        patches: Option<&VoxelPatches>,
        settings: TraceSettings,
    ) -> Result<Self, GpuSceneError> {
        let dims = maps.dims;
        let expected = maps.kind.map_count();
        if maps.values.len() as u64 != u64::from(expected) {
            return Err(GpuSceneError::MapCount { expected, found: maps.values.len() });
        }
        let overflow = |buffer| GpuSceneError::BufferOverflow { buffer };
        let voxels = dims.x.checked_mul(dims.y).and_then(|n| n.checked_mul(dims.z)).ok_or(overflow("grid"))?;
        let mut cone_maps = Vec::with_capacity(maps.values.len());
        let mut grid = Vec::with_capacity(maps.values.len() * voxels as usize);
        for (map, values) in maps.values.iter().enumerate() {
            if values.len() as u64 != u64::from(voxels) {
                return Err(GpuSceneError::MapValues { map, expected: voxels as usize, found: values.len() });
            }
            if let Some(voxel) = values.iter().position(|v| v.is_nan() || *v < 0.0) {
                return Err(GpuSceneError::InvalidDistance { map, voxel });
            }
            cone_maps.push(TraceConeMap {
                dims_block: dims.extend(1),
                grid_atlas_base: dims.extend(0),
                grid_base: UVec4::new(u32::try_from(grid.len()).map_err(|_| overflow("grid"))?, 0, 0, 0),
            });
            // + 0.0 turns -0.0 into +0.0, whose sign bit (the surface flag) is clear.
            grid.extend(values.iter().map(|v| (v + 0.0).to_bits()));
        }
        let mut scene = Self::with_maps(
            dims,
            maps.periodic_xy,
            ConeSelector::new(maps.kind),
            cone_maps,
            grid,
            Vec::new(),
            patches,
            settings,
        )?;
        // Blocks of one voxel: the shift 0 indexes the grid by the voxel itself.
        scene.pipeline_constants.block_shift = Some(0);
        Ok(scene)
    }

    /// The scene of packed maps: the patches, the uniforms, the placeholders of empty buffers.
    #[expect(clippy::too_many_arguments, reason = "the private packing step of both constructors")]
    fn with_maps(
        dims: UVec3,
        periodic: bool,
        selector: ConeSelector,
        cone_maps: Vec<TraceConeMap>,
        grid: Vec<u32>,
        mut atlas: Vec<u32>,
        patches: Option<&VoxelPatches>,
        settings: TraceSettings,
    ) -> Result<Self, GpuSceneError> {
        let overflow = |buffer| GpuSceneError::BufferOverflow { buffer };
        let atlas_values = atlas.len();
        if atlas.is_empty() {
            atlas.push(0);
        }
        let voxels = dims.x.checked_mul(dims.y).and_then(|n| n.checked_mul(dims.z)).ok_or(overflow("patch offsets"))?;
        if let Some(p) = patches
            && p.periodic_xy != periodic
        {
            return Err(GpuSceneError::PatchTiling { maps_periodic: periodic });
        }
        let (patch_offsets, mut patch_list) = match patches {
            Some(p) if p.dims == dims => (p.offsets.clone(), p.patches.clone()),
            Some(p) => return Err(GpuSceneError::PatchDims { expected: dims, found: p.dims }),
            None => (alloc::vec![0; voxels as usize + 1], Vec::new()),
        };
        if patch_list.is_empty() {
            patch_list.push(bytemuck::Zeroable::zeroed());
        }
        let uniforms = TraceUniforms {
            dims_max_steps: dims.extend(settings.max_steps),
            cones_rays: UVec4::new(selector.azimuths, selector.elevations, 0, 0),
            elevation_band: Vec4::new(selector.elevation_min, selector.elevation_max, 0.0, 0.0),
            relief: UVec4::ZERO,
        };
        let pipeline_constants = TracePipelineConstants {
            method: method_code(settings.method),
            stepping: stepping_code(settings.stepping),
            periodic,
            block_shift: None,
            atlas: AtlasStorage::F32,
        };
        Ok(Self {
            uniforms,
            pipeline_constants,
            cone_maps,
            grid,
            atlas,
            atlas_values,
            patch_offsets,
            patches: patch_list,
            heights: alloc::vec![0.0],
        })
    }

    /// The scene with its atlas stored as binary16 pairs, each value rounded down
    /// ([`ddm_compress::pack_f16_pairs_at_most`]): half the atlas's bytes, still
    /// conservative. The CPU reference of the result traces
    /// [`CompressedMaps::with_f16_atlas`] (the same values, bit for bit). A scene already
    /// in `f16` is returned unchanged.
    ///
    /// # Errors
    ///
    /// [`GpuSceneError::NoAtlas`] for a scene of uncompressed maps, which has no atlas.
    pub fn with_f16_atlas(mut self) -> Result<Self, GpuSceneError> {
        if self.atlas_values == 0 {
            return Err(GpuSceneError::NoAtlas);
        }
        if self.pipeline_constants.atlas == AtlasStorage::F32 {
            let values: Vec<f32> = self.atlas.iter().map(|&w| f32::from_bits(w)).collect();
            self.atlas = ddm_compress::pack_f16_pairs_at_most(&values);
            self.pipeline_constants.atlas = AtlasStorage::F16;
        }
        Ok(self)
    }

    /// The scene switched to relief mapping of `map` with `linear_steps` and `binary_steps`
    /// (the maps and patches stay bound but unused).
    ///
    /// # Errors
    ///
    /// [`GpuSceneError::ReliefNeedsPeriodicTile`] for maps of a single tile;
    /// [`GpuSceneError::ReliefTexelsPerVoxel`], [`GpuSceneError::ReliefTexels`] or
    /// [`GpuSceneError::ReliefHeights`] when the map does not cover the tile at a whole,
    /// non-zero number of texels per voxel with one height per texel;
    /// [`GpuSceneError::BufferOverflow`] when the texel count would overflow `u32`.
    pub fn with_relief(mut self, map: &HeightMap, linear_steps: u32, binary_steps: u32) -> Result<Self, GpuSceneError> {
        if !self.pipeline_constants.periodic {
            return Err(GpuSceneError::ReliefNeedsPeriodicTile);
        }
        let dims = self.uniforms.dims_max_steps.truncate();
        let s = map.texels_per_voxel;
        if s == 0 {
            return Err(GpuSceneError::ReliefTexelsPerVoxel);
        }
        let (Some(x), Some(y)) = (dims.x.checked_mul(s), dims.y.checked_mul(s)) else {
            return Err(GpuSceneError::BufferOverflow { buffer: "relief heights" });
        };
        let (expected, found) = (UVec2::new(x, y), map.texels.truncate());
        if found != expected {
            return Err(GpuSceneError::ReliefTexels { expected, found });
        }
        let texels = found.x as usize * found.y as usize;
        if map.heights.len() != texels {
            return Err(GpuSceneError::ReliefHeights { expected: texels, found: map.heights.len() });
        }
        self.pipeline_constants.method = METHOD_RELIEF;
        self.uniforms.relief = UVec4::new(linear_steps, binary_steps, s, 0);
        self.heights = map.heights.clone();
        Ok(self)
    }

    /// The uniforms for `ray_count` rays.
    pub fn uniforms(&self, ray_count: u32) -> TraceUniforms {
        let mut u = self.uniforms;
        u.cones_rays.w = ray_count;
        u
    }

    /// Bytes of the storage buffers, in binding order 3 to 8.
    pub fn storage_bytes(&self) -> [&[u8]; 6] {
        [
            bytemuck::cast_slice(&self.cone_maps),
            bytemuck::cast_slice(&self.grid),
            bytemuck::cast_slice(&self.atlas),
            bytemuck::cast_slice(&self.patch_offsets),
            bytemuck::cast_slice(&self.patches),
            bytemuck::cast_slice(&self.heights),
        ]
    }
}

#[cfg(test)]
mod tests {
    use alloc::string::ToString;

    use ddm_compress::{DirectionCones, MapKind};
    use glam::Vec2;

    use super::*;
    use crate::ground_truth::MeshRaycaster;
    use crate::patches::PatchSettings;
    use crate::pipeline_constants::METHOD_QUADRIC;
    use crate::trace::{Method, Stepping};

    const DIMS: UVec3 = UVec3::new(4, 4, 2);
    const SETTINGS: TraceSettings =
        TraceSettings { method: Method::Quadric, max_steps: 64, stepping: Stepping::Distance };

    /// A floor at z = 0.5: the lowest voxel layer is surface; two cones' maps.
    fn maps() -> CompressedMaps {
        let cones = DirectionCones::downward(2, 1).unwrap();
        let surface: Vec<bool> = (0..32).map(|i| i < 16).collect();
        let values = surface.iter().map(|&s| if s { 0.0 } else { 0.5 }).collect::<Vec<_>>();
        let maps = DistanceMaps {
            dims: DIMS,
            kind: MapKind::Directional(cones),
            values: alloc::vec![values.clone(), values],
            surface,
            max_distance: DIMS.as_vec3().length(),
            periodic_xy: true,
        };
        CompressedMaps::compress(&maps, 2).unwrap()
    }

    #[test]
    fn a_consistent_scene_packs_with_its_cones() {
        let scene = GpuScene::new(&maps(), None, SETTINGS).unwrap();
        assert_eq!(scene.cone_maps.len(), 2);
        assert_eq!(scene.uniforms.cones_rays.truncate(), UVec3::new(2, 1, 0));
        assert_eq!(scene.pipeline_constants.method, METHOD_QUADRIC);
        assert_eq!(scene.pipeline_constants.block_shift, Some(1), "blocks of 2");
        assert_eq!(scene.patch_offsets.len(), 33);
    }

    #[test]
    fn each_inconsistent_scene_has_its_error() {
        let mut fewer = maps();
        fewer.maps.pop();
        assert_eq!(GpuScene::new(&fewer, None, SETTINGS), Err(GpuSceneError::MapCount { expected: 2, found: 1 }));
        let mut other = maps();
        let small = DistanceMaps {
            dims: UVec3::new(2, 2, 2),
            kind: MapKind::Plain,
            values: alloc::vec![alloc::vec![1.0; 8]],
            surface: alloc::vec![false; 8],
            max_distance: 3.0,
            periodic_xy: true,
        };
        other.maps[1] = CompressedMaps::compress(&small, 2).unwrap().maps.remove(0);
        assert_eq!(
            GpuScene::new(&other, None, SETTINGS),
            Err(GpuSceneError::MapDims { map: 1, expected: DIMS, found: UVec3::new(2, 2, 2) })
        );
        let floor = mesostructure::plane(UVec3::new(4, 4, 3), 0.5);
        let surface: Vec<bool> = (0..48).map(|i| i < 16).collect();
        let patches = VoxelPatches::build(UVec3::new(4, 4, 3), &floor, &surface, PatchSettings::default()).unwrap();
        let error = GpuScene::new(&maps(), Some(&patches), SETTINGS).unwrap_err();
        assert_eq!(error, GpuSceneError::PatchDims { expected: DIMS, found: UVec3::new(4, 4, 3) });
        assert!(error.to_string().contains("[4, 4, 3]"), "{error}");
    }

    #[test]
    fn an_uncompressed_scene_holds_each_voxels_distance_in_its_grid() {
        let cones = DirectionCones::downward(2, 1).unwrap();
        let values: Vec<f32> = (0..32).map(|i| if i < 16 { -0.0 } else { 0.25 * i as f32 }).collect();
        let mut maps = DistanceMaps {
            dims: DIMS,
            kind: MapKind::Directional(cones),
            values: alloc::vec![values.clone(), values.iter().map(|v| v + 1.0).collect()],
            surface: (0..32).map(|i| i < 16).collect(),
            max_distance: DIMS.as_vec3().length(),
            periodic_xy: true,
        };
        let scene = GpuScene::uncompressed(&maps, None, SETTINGS).unwrap();
        assert_eq!(scene.grid.len(), 64);
        assert_eq!(scene.cone_maps[1].grid_base.x, 32);
        assert_eq!(scene.cone_maps[1].dims_block, DIMS.extend(1));
        // No word carries the surface flag: every read is the grid's, -0.0 stored as +0.0.
        assert!(scene.grid.iter().all(|w| w & ddm_compress::compress::SURFACE_FLAG == 0));
        for (cone, values) in maps.values.iter().enumerate() {
            for (voxel, v) in values.iter().enumerate() {
                assert_eq!(f32::from_bits(scene.grid[32 * cone + voxel]), *v);
            }
        }
        assert_eq!(scene.clone().with_f16_atlas(), Err(GpuSceneError::NoAtlas));
        maps.values[1][7] = f32::NAN;
        assert_eq!(
            GpuScene::uncompressed(&maps, None, SETTINGS),
            Err(GpuSceneError::InvalidDistance { map: 1, voxel: 7 })
        );
        maps.values[1].pop();
        assert_eq!(
            GpuScene::uncompressed(&maps, None, SETTINGS),
            Err(GpuSceneError::MapValues { map: 1, expected: 32, found: 31 })
        );
        maps.values.pop();
        assert_eq!(
            GpuScene::uncompressed(&maps, None, SETTINGS),
            Err(GpuSceneError::MapCount { expected: 2, found: 1 })
        );
    }

    #[test]
    fn an_f16_atlas_holds_the_rounded_values_of_the_cpu_reference_in_half_the_words() {
        let mut compressed = maps();
        // Distances that binary16 cannot hold exactly.
        for map in &mut compressed.maps {
            let values: Vec<f32> = (0..32).map(|i| if i < 16 { 0.1 + 0.01 * i as f32 } else { 0.5 }).collect();
            let surface: Vec<bool> = (0..32).map(|i| i < 16).collect();
            *map = ddm_compress::CompressedMap::compress(&values, &surface, DIMS, 2).unwrap();
        }
        let scene = GpuScene::new(&compressed, None, SETTINGS).unwrap();
        let half = scene.clone().with_f16_atlas().unwrap();
        assert_eq!(half.pipeline_constants.atlas, AtlasStorage::F16);
        assert_eq!((half.atlas_values, half.atlas.len()), (scene.atlas_values, scene.atlas.len().div_ceil(2)));
        let reference = compressed.with_f16_atlas();
        let values = reference.maps.iter().flat_map(|m| m.atlas().iter().copied());
        let mut lowered = 0;
        for (k, (value, original)) in values.zip(&scene.atlas).enumerate() {
            let word = half.atlas[k / 2];
            let bits = if k % 2 == 0 { word & 0xffff } else { word >> 16 } as u16;
            assert_eq!(gpu_layout::binary16::half_to_f32(bits), value, "value {k}");
            assert!(value <= f32::from_bits(*original));
            lowered += usize::from(value < f32::from_bits(*original));
        }
        assert!(lowered > 0);
        assert_eq!(half.clone().with_f16_atlas(), Ok(half), "already f16");
    }

    #[test]
    fn each_unusable_relief_map_has_its_error() {
        let scene = GpuScene::new(&maps(), None, SETTINGS).unwrap();
        let floor = mesostructure::plane(DIMS, 0.5);
        let map = HeightMap::from_mesh(&MeshRaycaster::new(&floor, Vec2::new(4.0, 4.0)), DIMS, 2).unwrap();
        let relief = scene.clone().with_relief(&map, 32, 8).unwrap();
        assert_eq!((relief.pipeline_constants.method, relief.heights.len()), (METHOD_RELIEF, 64));
        let zero = HeightMap { texels_per_voxel: 0, ..map.clone() };
        assert_eq!(scene.clone().with_relief(&zero, 32, 8), Err(GpuSceneError::ReliefTexelsPerVoxel));
        let coarse = HeightMap { texels_per_voxel: 1, ..map.clone() };
        assert_eq!(
            scene.clone().with_relief(&coarse, 32, 8),
            Err(GpuSceneError::ReliefTexels { expected: UVec2::new(4, 4), found: UVec2::new(8, 8) })
        );
        let huge = HeightMap { texels_per_voxel: u32::MAX, ..map.clone() };
        assert_eq!(
            scene.clone().with_relief(&huge, 32, 8),
            Err(GpuSceneError::BufferOverflow { buffer: "relief heights" })
        );
        let mut short = map;
        short.heights.pop();
        assert_eq!(scene.with_relief(&short, 32, 8), Err(GpuSceneError::ReliefHeights { expected: 64, found: 63 }));
    }
}
