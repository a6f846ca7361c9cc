//! The tracer's scene on the GPU: the uniforms, the per-cone map table and the result of
//! the WGSL twin's `trace_ray`, laid out for WGSL, and the packing of maps, patches and a
//! relief height map into the flat storage buffers that `wgsl/ddm_tracer.wgsl` reads
//! (bindings 3–8).

use alloc::vec::Vec;

use glam::{UVec3, UVec4, Vec4};
use gpu_layout::gpu_struct;

use crate::maps::{CompressedMaps, ConeSelector};
use crate::patch::TracePatch;
use crate::patches::VoxelPatches;
use crate::relief::HeightMap;
use crate::trace::{Method, Stepping, TraceSettings};

/// `TraceUniforms::cones_method.z` for [`crate::Method::SphereTracing`].
pub const METHOD_SPHERE_TRACING: u32 = 0;
/// `TraceUniforms::cones_method.z` for [`crate::Method::Quadric`].
pub const METHOD_QUADRIC: u32 = 1;
/// `TraceUniforms::cones_method.z` for relief mapping ([`crate::relief_trace`]).
pub const METHOD_RELIEF: u32 = 2;
/// `TraceUniforms::stepping.x` for [`crate::Stepping::Distance`].
pub const STEPPING_DISTANCE: u32 = 0;
/// `TraceUniforms::stepping.x` for [`crate::Stepping::VoxelExit`].
pub const STEPPING_VOXEL_EXIT: u32 = 1;
/// `TraceUniforms::stepping.x` for [`crate::Stepping::BlockCells`].
pub const STEPPING_BLOCK_CELLS: u32 = 2;

gpu_struct! {
    /// The tracer's uniforms.
    pub struct TraceUniforms {
        /// `(L_x, L_y, L_z, max_steps)`.
        pub dims_max_steps: UVec4,
        /// `(azimuths, elevations, method, ray_count)`; `azimuths = 0` for the plain map.
        pub cones_method: UVec4,
        /// `(elevation_min, elevation_max, 0, 0)` of the cone band, radians.
        pub elevation_band: Vec4,
        /// Relief mapping: `(linear_steps, binary_steps, texels_per_voxel, 0)`.
        pub relief: UVec4,
        /// `(stepping, 0, 0, 0)`: [`STEPPING_DISTANCE`], [`STEPPING_VOXEL_EXIT`] or [`STEPPING_BLOCK_CELLS`].
        pub stepping: UVec4,
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

/// The code of `method` in [`TraceUniforms::cones_method`]`.z`.
const fn method_code(method: Method) -> u32 {
    match method {
        Method::SphereTracing => METHOD_SPHERE_TRACING,
        Method::Quadric => METHOD_QUADRIC,
    }
}

/// The code of `stepping` in [`TraceUniforms::stepping`]`.x`.
const fn stepping_code(stepping: Stepping) -> u32 {
    match stepping {
        Stepping::Distance => STEPPING_DISTANCE,
        Stepping::VoxelExit => STEPPING_VOXEL_EXIT,
        Stepping::BlockCells => STEPPING_BLOCK_CELLS,
    }
}

/// Everything the compute pass reads, as flat buffers (storage bindings 3–8 of
/// `shaders/ddm_tracer.wgsl`).
#[derive(Clone, Debug, PartialEq)]
pub struct GpuScene {
    /// The uniforms (binding 0), `ray_count` filled by [`GpuScene::uniforms`].
    pub uniforms: TraceUniforms,
    /// One entry per cone.
    pub cone_maps: Vec<TraceConeMap>,
    /// All lookup grids, one after the other.
    pub grid: Vec<u32>,
    /// All atlases, one after the other.
    pub atlas: Vec<f32>,
    /// `VoxelPatches::offsets` (one zero entry per voxel plus one when there are none).
    pub patch_offsets: Vec<u32>,
    /// The patches (one zero patch when there are none: WGSL arrays are never empty).
    pub patches: Vec<TracePatch>,
    /// The relief height map, `HeightMap::heights` (one zero when there is none).
    pub heights: Vec<f32>,
}

impl GpuScene {
    /// Packs `maps` and `patches` for `settings`. `None` if the patch grid's size differs
    /// from the maps' or a buffer index would overflow `u32`.
    pub fn new(maps: &CompressedMaps, patches: Option<&VoxelPatches>, settings: TraceSettings) -> Option<Self> {
        let dims: UVec3 = maps.dims;
        let selector = ConeSelector::new(maps.cones);
        let mut cone_maps = Vec::with_capacity(maps.maps.len());
        let (mut grid, mut atlas) = (Vec::new(), Vec::new());
        for map in &maps.maps {
            let g = ddm_compress::compress::grid_dims(map.dims(), map.block());
            cone_maps.push(TraceConeMap {
                dims_block: map.dims().extend(map.block()),
                grid_atlas_base: g.extend(u32::try_from(atlas.len()).ok()?),
                grid_base: UVec4::new(u32::try_from(grid.len()).ok()?, 0, 0, 0),
            });
            grid.extend_from_slice(map.grid());
            atlas.extend_from_slice(map.atlas());
        }
        if atlas.is_empty() {
            atlas.push(0.0);
        }
        let voxels = (dims.x * dims.y * dims.z) as usize;
        let (patch_offsets, mut patch_list) = match patches {
            Some(p) if p.dims == dims => (p.offsets.clone(), p.patches.clone()),
            Some(_) => return None,
            None => (alloc::vec![0; voxels + 1], Vec::new()),
        };
        if patch_list.is_empty() {
            patch_list.push(bytemuck::Zeroable::zeroed());
        }
        let uniforms = TraceUniforms {
            dims_max_steps: dims.extend(settings.max_steps),
            cones_method: UVec4::new(selector.azimuths, selector.elevations, method_code(settings.method), 0),
            elevation_band: Vec4::new(selector.elevation_min, selector.elevation_max, 0.0, 0.0),
            relief: UVec4::ZERO,
            stepping: UVec4::new(stepping_code(settings.stepping), 0, 0, 0),
        };
        Some(Self { uniforms, cone_maps, grid, atlas, patch_offsets, patches: patch_list, heights: alloc::vec![0.0] })
    }

    /// The scene switched to relief mapping of `map` with `linear_steps` and `binary_steps`
    /// (the maps and patches stay bound but unused). `None` when the map does not cover
    /// the tile at a whole number of texels per voxel.
    pub fn with_relief(mut self, map: &HeightMap, linear_steps: u32, binary_steps: u32) -> Option<Self> {
        let dims = self.uniforms.dims_max_steps.truncate();
        let s = map.texels_per_voxel;
        if map.texels.x != dims.x * s
            || map.texels.y != dims.y * s
            || map.heights.len() != (map.texels.x * map.texels.y) as usize
        {
            return None;
        }
        self.uniforms.cones_method.z = METHOD_RELIEF;
        self.uniforms.relief = UVec4::new(linear_steps, binary_steps, s, 0);
        self.heights = map.heights.clone();
        Some(self)
    }

    /// The uniforms for `ray_count` rays.
    pub fn uniforms(&self, ray_count: u32) -> TraceUniforms {
        let mut u = self.uniforms;
        u.cones_method.w = ray_count;
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
