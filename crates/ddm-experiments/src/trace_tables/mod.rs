//! Mehra & Kumar's Tables 1–3, measured with `ddm_tracer` against the exact mesh.
//!
//! For each mesostructure on a plane tile, one perspective view ([`View`]) is traced per
//! pixel with each [`TraceMethod`]: sphere tracing with the plain distance map (DM) and
//! with the DDMs 2×1, 4×1, 8×1 and 4×2 (each stopping at the first zero voxel, as
//! Donnelly's sphere tracing does), DDM 4×1 + quadric (Algorithm 3.1 on the C⁰ patches of
//! §3.1), DDM 4×1 + fitted Q (the same on each voxel's fitted quadric of step a), DDM 4×1 +
//! triangles (the mesh's own triangles per voxel, exact: beyond the paper), DDM 4×1 +
//! adaptive (per voxel the fitted quadric where it stays within the error budget of the
//! triangles, else the triangles: see `ddm_tracer::exact_patches`), DM, DDM 4×1 and
//! DDM 4×1 + adaptive with voxel-exit stepping (`... exit`: `ddm_tracer::Stepping::VoxelExit`,
//! beyond the paper; every other method steps by the stored distance as Algorithm 3.1
//! does), and relief mapping (height fields only; height map at 2 texels per voxel, 32
//! linear + 8 binary steps). Every pixel is compared with the exact first hit of the
//! original mesh ([`trace_stats`]).
//!
//! The steps of one structure, each a function of [`TraceScene`]: [`TraceScene::build`]
//! (the view, its ground truth, maps, patches), [`TraceScene::patch_rows`] (patch memory),
//! [`TraceScene::budget_rows`] (the adaptive patches against their budget),
//! [`TraceScene::steps_rows`] (steps against the view angle) and
//! [`TraceScene::run_method`] (Tables 1/2 and, on compressed maps, Table 3).
//!
//! The settings ([`TraceTablesSettings`]), the methods ([`TraceMethod`], [`PatchKind`]) and
//! the rows of the CSV files live in private submodules, re-exported here.
//!
//! Known limits of the inputs, visible in the numbers: the spheres and tori are coarse
//! meshes, whose facets a smooth quadric cannot match to 1e-3 voxel.

use std::time::Instant;

use ddm_compress::{DistanceMaps, Triangle};
use ddm_tracer::GpuScene;
use ddm_tracer::{
    CompressedMaps, HeightMap, MeshRaycaster, PatchSettings, PatchSurface, Stepping, TraceOutcome, TraceSettings,
    VoxelPatches, relief_trace, trace,
};
use glam::{DVec3, UVec3, Vec2, Vec3};
use mesostructure::Mesostructure;

use crate::ExperimentError;
use crate::gpu::GpuTracer;
use crate::maps::{NamedMaps, TRACE_MAPS, compute_named, find};
use crate::reference::{ReferenceAccuracy, ReferenceSurface, reference_accuracy};
use crate::stats::{hit_differences, mean_steps, trace_stats};
use crate::steps::{StepsRow, steps_vs_angle};
use crate::timing::{CpuRun, interleaved_time_ratio, timed};
use crate::view::{Camera, View};

mod methods;
mod rows;
mod settings;

pub use methods::{MethodCase, PatchKind, TraceMethod};
pub use rows::{BudgetRow, CompressionRow, MethodResult, MethodRow, PatchRow, SteppingComparison};
pub use settings::TraceTablesSettings;

/// Linear steps of the relief mapping baseline.
pub const RELIEF_LINEAR: u32 = 32;
/// Binary refinement steps of the relief mapping baseline.
pub const RELIEF_BINARY: u32 = 8;
/// Height-map texels per voxel of the relief mapping baseline.
pub const RELIEF_TEXELS_PER_VOXEL: u32 = 2;
/// Error budgets (voxels) of the adaptive patches' sweep: memory and accuracy against it.
pub const BUDGETS: [f32; 6] = [0.3, 0.1, 0.03, 0.01, 3e-3, 1e-3];

/// The exact mesh's first hit of each ray of a view.
#[derive(Clone, Debug, PartialEq)]
pub struct GroundTruth {
    /// Hit points.
    pub points: Vec<Option<DVec3>>,
    /// Unit normals facing the ray.
    pub normals: Vec<Option<Vec3>>,
}

/// The first hits of `rays` on `mesh` (ray length up to 10⁴ voxels).
pub fn ground_truth(mesh: &MeshRaycaster, rays: &[(Vec3, Vec3)]) -> GroundTruth {
    let hits: Vec<_> = rays.iter().map(|&(o, d)| mesh.first_hit(o.as_dvec3(), d.as_dvec3(), 1e4)).collect();
    GroundTruth {
        points: hits.iter().map(|h| h.map(|h| h.point)).collect(),
        normals: hits.iter().map(|h| h.map(|h| h.normal.as_vec3())).collect(),
    }
}

/// The four patch constructions of one structure, and how long they took.
#[derive(Clone, Debug)]
pub struct PatchSets {
    /// [`PatchKind::C0`].
    pub c0: VoxelPatches,
    /// [`PatchKind::Fitted`].
    pub fitted: VoxelPatches,
    /// [`PatchKind::Triangles`].
    pub triangles: VoxelPatches,
    /// [`PatchKind::Adaptive`] at the settings' budget.
    pub adaptive: VoxelPatches,
    /// [`PatchKind::Watertight`].
    pub watertight: VoxelPatches,
    /// Seconds of building the C⁰ and fitted patches.
    pub c0_fitted_seconds: f64,
    /// Seconds of building the triangle and adaptive patches.
    pub triangles_adaptive_seconds: f64,
    /// Seconds of building the watertight patches.
    pub watertight_seconds: f64,
}

impl PatchSets {
    /// The patches of `kind`.
    pub fn get(&self, kind: PatchKind) -> &VoxelPatches {
        match kind {
            PatchKind::C0 => &self.c0,
            PatchKind::Fitted => &self.fitted,
            PatchKind::Triangles => &self.triangles,
            PatchKind::Adaptive => &self.adaptive,
            PatchKind::Watertight => &self.watertight,
        }
    }
}

/// Builds the patches of `surface` with `surface_kind` and its watertight subdivision
/// (errors name `scene` and `what`).
fn build_patches(
    scene: &str,
    what: &str,
    (dims, periodic_xy): (UVec3, bool),
    triangles: &[Triangle],
    surface: &[bool],
    (surface_kind, watertight_subdivision): (PatchSurface, u32),
) -> Result<VoxelPatches, ExperimentError> {
    let settings =
        PatchSettings { surface: surface_kind, periodic_xy, watertight_subdivision, ..PatchSettings::default() };
    VoxelPatches::build(dims, triangles, surface, settings)
        .map_err(|error| ExperimentError::scene(scene, format!("the {what} patch construction failed: {error}")))
}

/// One structure of the tables: its settings and view, its mesh, the truth of the view,
/// its maps and patches.
#[derive(Clone, Debug)]
pub struct TraceScene {
    /// The mesostructure's name.
    pub name: &'static str,
    /// The settings it was built with (every later step uses them).
    pub settings: TraceTablesSettings,
    /// The view of the settings ([`View::perspective`]; for a tile that stands alone,
    /// [`Camera::of_single_tile`]'s).
    pub view: View,
    /// Voxels of the tile.
    pub dims: UVec3,
    /// The tile's triangles.
    pub triangles: Vec<Triangle>,
    /// Whether the structure is a height field (relief mapping applies).
    pub height_field: bool,
    /// The mesh, repeated as the maps are (ground truth, relief height map).
    pub mesh: MeshRaycaster,
    /// The exact first hits of the view's rays.
    pub truth: GroundTruth,
    /// The maps of [`TRACE_MAPS`].
    pub maps: Vec<NamedMaps>,
    /// Seconds of computing all maps.
    pub maps_seconds: f64,
    /// The patches, on the plain map's surface voxels.
    pub patches: PatchSets,
    /// The tile's own surface, for the fair yardstick ([`crate::reference`](mod@crate::reference)); `None` for a
    /// tile given only as triangles.
    pub reference: Option<ReferenceSurface>,
}

impl TraceScene {
    /// The scene of `structure` (maze and bricks are height fields) at `settings.dims`.
    pub fn build(structure: Mesostructure, settings: &TraceTablesSettings) -> Result<Self, ExperimentError> {
        let height_field = matches!(structure, Mesostructure::Maze(_) | Mesostructure::Bricks);
        let mut scene =
            Self::from_triangles(structure.name(), structure.triangles(settings.dims), height_field, settings)?;
        scene.reference = Some(ReferenceSurface::of(structure, settings.dims));
        Ok(scene)
    }

    /// The scene of any tile mesh `triangles` named `name`.
    pub fn from_triangles(
        name: &'static str,
        triangles: Vec<Triangle>,
        height_field: bool,
        settings: &TraceTablesSettings,
    ) -> Result<Self, ExperimentError> {
        settings.validate()?;
        let dims = settings.dims;
        // The truth repeats the tile as the maps do, or sees it alone (then in the middle
        // of the view).
        let periodic = settings.map_settings.periodic_xy;
        let view = if periodic {
            View::perspective(dims, settings.width, settings.height)?
        } else {
            View::looking(Camera::of_single_tile(dims), settings.width, settings.height)?
        };
        let period = if periodic { Vec2::new(dims.x as f32, dims.y as f32) } else { Vec2::ZERO };
        let mesh = MeshRaycaster::new(&triangles, period);
        let truth = ground_truth(&mesh, &view.rays);
        let start = Instant::now();
        let maps = TRACE_MAPS
            .iter()
            .map(|&kind| compute_named(name, dims, &triangles, kind, settings.map_settings))
            .collect::<Result<Vec<_>, _>>()?;
        let maps_seconds = start.elapsed().as_secs_f64();
        let surface = &maps[0].maps.surface;
        let start = Instant::now();
        let budget = settings.adaptive_budget;
        let build = |kind: PatchKind| {
            let surface_kind = (kind.surface(budget), settings.watertight_subdivision);
            build_patches(name, kind.name(), (dims, periodic), &triangles, surface, surface_kind)
        };
        let c0 = build(PatchKind::C0)?;
        let fitted = build(PatchKind::Fitted)?;
        let c0_fitted_seconds = start.elapsed().as_secs_f64();
        let start = Instant::now();
        let exact = build(PatchKind::Triangles)?;
        let adaptive = build(PatchKind::Adaptive)?;
        let triangles_adaptive_seconds = start.elapsed().as_secs_f64();
        let start = Instant::now();
        let watertight = build(PatchKind::Watertight)?;
        let patches = PatchSets {
            c0,
            fitted,
            triangles: exact,
            adaptive,
            watertight,
            c0_fitted_seconds,
            triangles_adaptive_seconds,
            watertight_seconds: start.elapsed().as_secs_f64(),
        };
        let settings = settings.clone();
        Ok(Self {
            name,
            settings,
            view,
            dims,
            triangles,
            height_field,
            mesh,
            truth,
            maps,
            maps_seconds,
            patches,
            reference: None,
        })
    }

    /// The accuracy of `outcomes` (of the view's rays) against the tile's own surface.
    fn reference_accuracy(&self, outcomes: &[TraceOutcome]) -> Option<ReferenceAccuracy> {
        let surface = self.reference.as_ref()?;
        Some(reference_accuracy(surface, &self.view.rays, outcomes, self.dims.z as f32))
    }

    /// The map called `name`.
    fn map(&self, name: &str) -> Result<&DistanceMaps, ExperimentError> {
        find(&self.maps, name)
            .map(|m| &m.maps)
            .ok_or_else(|| ExperimentError::scene(self.name, format!("no {name} map")))
    }

    /// The memory of each patch construction, in [`PatchKind::ALL`] order.
    pub fn patch_rows(&self) -> Vec<PatchRow> {
        PatchKind::ALL
            .iter()
            .map(|&kind| {
                let set = self.patches.get(kind);
                PatchRow {
                    mesostructure: self.name,
                    patches: kind,
                    quadric_voxels: set.quadric_voxels,
                    triangle_voxels: set.triangle_voxels,
                    voxels_without_patch: set.voxels_without_patch,
                    patch_count: set.patches.len(),
                    bytes: set.byte_size(),
                }
            })
            .collect()
    }

    /// The adaptive patches at each of the settings' `budgets`, traced with the DDM 4×1
    /// over the view against the truth (one timed pass).
    pub fn budget_rows(&self) -> Result<Vec<BudgetRow>, ExperimentError> {
        let (settings, view) = (&self.settings, &self.view);
        let ddm = self.map("DDM 4x1")?;
        let surface = &self.map("DM")?.surface;
        let quadric = settings.quadric();
        let mut rows = Vec::with_capacity(settings.budgets.len());
        for &budget in &settings.budgets {
            let surface_kind = PatchSurface::Adaptive { max_error: budget };
            let tiling = (self.dims, settings.map_settings.periodic_xy);
            let set = build_patches(self.name, "adaptive", tiling, &self.triangles, surface, (surface_kind, 1))?;
            let start = Instant::now();
            let outcomes: Vec<TraceOutcome> =
                view.rays.iter().map(|&(o, d)| trace(ddm, Some(&set), o, d, quadric)).collect();
            let seconds_per_ray = start.elapsed().as_secs_f64() / view.rays.len() as f64;
            rows.push(BudgetRow {
                mesostructure: self.name,
                budget,
                quadric_voxels: set.quadric_voxels,
                triangle_voxels: set.triangle_voxels,
                bytes: set.byte_size(),
                stats: trace_stats(&outcomes, &self.truth.points),
                cpu_rays_per_second: 1.0 / seconds_per_ray,
            });
        }
        Ok(rows)
    }

    /// Mean steps against the view angle of every map ([`steps_vs_angle`]).
    pub fn steps_rows(&self) -> Result<Vec<StepsRow>, ExperimentError> {
        steps_vs_angle(self.name, self.dims, &self.maps, &self.settings.steps)
    }

    /// Traces the view with `method` on the CPU (and on `gpu`, when given): its Tables 1/2
    /// row and, for a map-based method, its Table 3 row. `None` for relief mapping on a
    /// structure that is no height field or a tile that stands alone.
    pub fn run_method(
        &self,
        method: TraceMethod,
        gpu: Option<&GpuTracer<'_>>,
    ) -> Result<Option<MethodResult>, ExperimentError> {
        match method.case(&self.settings) {
            Some(case) => self.run_case(method, case, gpu).map(Some),
            None if self.relief_applies() => self.run_relief(gpu).map(Some),
            None => Ok(None),
        }
    }

    /// Traces `view` with `method` on the CPU, once for the outcomes and then `passes`
    /// timed passes (one thread, the fastest kept): the method on another view than the
    /// tables' (its truth from [`ground_truth`] on [`TraceScene::mesh`]). `None` for relief
    /// mapping on a structure that is no height field or a tile that stands alone.
    pub fn trace_view(
        &self,
        method: TraceMethod,
        view: &View,
        passes: usize,
    ) -> Result<Option<CpuRun>, ExperimentError> {
        match method.case(&self.settings) {
            Some(case) => self.case_run(case, view, passes).map(Some),
            None if self.relief_applies() => Ok(Some(self.relief_run(&self.relief_height_map()?, view, passes))),
            None => Ok(None),
        }
    }

    /// [`TraceScene::trace_view`] of a map-based method.
    fn case_run(&self, case: MethodCase, view: &View, passes: usize) -> Result<CpuRun, ExperimentError> {
        let raw = self.map(case.map)?;
        let patches = case.patches.map(|kind| self.patches.get(kind));
        Ok(timed(&view.rays, passes, |o, d| trace(raw, patches, o, d, case.settings)))
    }

    /// Whether relief mapping runs: on a height field that repeats (its height map wraps,
    /// so not on a tile that stands alone).
    fn relief_applies(&self) -> bool {
        self.height_field && self.settings.map_settings.periodic_xy
    }

    /// The relief mapping baseline's height map of the mesh.
    fn relief_height_map(&self) -> Result<HeightMap, ExperimentError> {
        HeightMap::from_mesh(&self.mesh, self.dims, RELIEF_TEXELS_PER_VOXEL)
            .map_err(|e| ExperimentError::scene(self.name, format!("the relief height map: {e}")))
    }

    /// [`TraceScene::trace_view`] of relief mapping.
    fn relief_run(&self, height_map: &HeightMap, view: &View, passes: usize) -> CpuRun {
        let size_z = self.dims.z as f32;
        timed(&view.rays, passes, |o, d| relief_trace(height_map, size_z, o, d, RELIEF_LINEAR, RELIEF_BINARY))
    }

    fn run_case(
        &self,
        method: TraceMethod,
        case: MethodCase,
        gpu: Option<&GpuTracer<'_>>,
    ) -> Result<MethodResult, ExperimentError> {
        let (settings, view) = (&self.settings, &self.view);
        let raw = self.map(case.map)?;
        let patches = case.patches.map(|kind| self.patches.get(kind));
        let trace_settings = case.settings;
        let rays = &view.rays;
        let run = self.case_run(case, view, settings.timed_passes)?;
        let pack_error = |what: &str, error: &dyn std::fmt::Display| {
            ExperimentError::scene(self.name, format!("cannot {what} the {} maps: {error}", case.map))
        };
        let compressed =
            CompressedMaps::compress(raw, settings.compression_block).map_err(|e| pack_error("compress", &e))?;
        // The scene of the compute pass on `maps`, its errors naming the structure and map.
        let gpu_scene = |maps: &CompressedMaps| {
            GpuScene::new(maps, patches, trace_settings).map_err(|e| pack_error("build the GPU scene of", &e))
        };
        let gpu_on_raw = match gpu {
            Some(gpu) => {
                let raw_gpu = CompressedMaps::compress(raw, 1).map_err(|e| pack_error("pack", &e))?;
                Some(gpu.run_scene(&gpu_scene(&raw_gpu)?, rays, &run.outcomes)?)
            }
            None => None,
        };
        // The compressed maps traced with `stepping`: against the raw maps traced with the
        // method's own settings (outcomes and interleaved time ratio).
        let on_compressed = |stepping: Stepping| {
            let packed_settings = TraceSettings { stepping, ..trace_settings };
            let outcomes: Vec<TraceOutcome> =
                rays.iter().map(|&(o, d)| trace(&compressed, patches, o, d, packed_settings)).collect();
            let cpu_time_ratio = interleaved_time_ratio(
                rays,
                settings.ratio_rounds,
                |o, d| trace(raw, patches, o, d, trace_settings),
                |o, d| trace(&compressed, patches, o, d, packed_settings),
            );
            let comparison = SteppingComparison {
                mean_steps: mean_steps(&outcomes),
                differences: hit_differences(&run.outcomes, &outcomes),
                cpu_time_ratio,
            };
            (outcomes, comparison)
        };
        let (packed, packed_comparison) = on_compressed(trace_settings.stepping);
        let gpu_time_ratio = match (gpu, gpu_on_raw) {
            (Some(gpu), Some(on_raw)) => {
                Some(gpu.run_scene(&gpu_scene(&compressed)?, rays, &packed)?.seconds / on_raw.seconds)
            }
            _ => None,
        };
        // The paper's rule on raw maps against block cells on compressed maps (the same
        // rule on raw maps); voxel-exit methods cross blocks as cells already.
        let block_cells =
            (trace_settings.stepping == Stepping::Distance).then(|| on_compressed(Stepping::BlockCells).1);
        let compression = CompressionRow {
            mesostructure: self.name,
            method,
            block: settings.compression_block,
            efficiency: compressed.compression_efficiency(),
            raw_mean_steps: mean_steps(&run.outcomes),
            compressed: packed_comparison,
            gpu_time_ratio,
            block_cells,
        };
        Ok(MethodResult {
            row: MethodRow {
                mesostructure: self.name,
                method,
                stats: trace_stats(&run.outcomes, &self.truth.points),
                reference: self.reference_accuracy(&run.outcomes),
                cpu_rays_per_second: 1.0 / run.seconds_per_ray,
                gpu: gpu_on_raw,
            },
            compression: Some(compression),
            normals: run.outcomes.iter().map(|o| o.hit.map(|h| h.normal)).collect(),
        })
    }

    fn run_relief(&self, gpu: Option<&GpuTracer<'_>>) -> Result<MethodResult, ExperimentError> {
        let (settings, view) = (&self.settings, &self.view);
        let height_map = self.relief_height_map()?;
        let run = self.relief_run(&height_map, view, settings.timed_passes);
        let gpu_row = match gpu {
            Some(gpu) => {
                let plain = CompressedMaps::compress(self.map("DM")?, 1)
                    .map_err(|e| ExperimentError::scene(self.name, format!("cannot pack the DM maps: {e}")))?;
                let scene = GpuScene::new(&plain, None, settings.sphere())
                    .and_then(|s| s.with_relief(&height_map, RELIEF_LINEAR, RELIEF_BINARY))
                    .map_err(|e| ExperimentError::scene(self.name, format!("the relief scene does not pack: {e}")))?;
                Some(gpu.run_scene(&scene, &view.rays, &run.outcomes)?)
            }
            None => None,
        };
        Ok(MethodResult {
            row: MethodRow {
                mesostructure: self.name,
                method: TraceMethod::Relief,
                stats: trace_stats(&run.outcomes, &self.truth.points),
                reference: self.reference_accuracy(&run.outcomes),
                cpu_rays_per_second: 1.0 / run.seconds_per_ray,
                gpu: gpu_row,
            },
            compression: None,
            normals: run.outcomes.iter().map(|o| o.hit.map(|h| h.normal)).collect(),
        })
    }
}

#[cfg(test)]
mod tests;
