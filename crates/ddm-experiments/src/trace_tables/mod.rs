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
//! Known limits of the inputs, visible in the numbers: the spheres and tori are coarse
//! meshes, whose facets a smooth quadric cannot match to 1e-3 voxel.

use std::time::Instant;

use ddm_compress::{DistanceMapSettings, DistanceMaps, Triangle};
use ddm_tracer::GpuScene;
use ddm_tracer::{
    CompressedMaps, HeightMap, MeshRaycaster, Method, PatchSettings, PatchSurface, Stepping, TraceOutcome,
    TraceSettings, VoxelPatches, relief_trace, trace,
};
use glam::{DVec3, UVec3, Vec2, Vec3};
use mesostructure::Mesostructure;

use crate::ExperimentError;
use crate::gpu::{GpuRun, GpuTracer};
use crate::maps::{NamedMaps, TRACE_MAPS, compute_named, find};
use crate::reference::{ReferenceAccuracy, ReferenceSurface, reference_accuracy};
use crate::stats::{HitDifferences, TraceStats, hit_differences, mean_steps, trace_stats};
use crate::steps::{StepsRow, StepsSettings, steps_vs_angle};
use crate::timing::{CpuRun, RATIO_ROUNDS, interleaved_time_ratio, timed};
use crate::view::{Camera, View};

/// Linear steps of the relief mapping baseline.
pub const RELIEF_LINEAR: u32 = 32;
/// Binary refinement steps of the relief mapping baseline.
pub const RELIEF_BINARY: u32 = 8;
/// Height-map texels per voxel of the relief mapping baseline.
pub const RELIEF_TEXELS_PER_VOXEL: u32 = 2;
/// Error budgets (voxels) of the adaptive patches' sweep: memory and accuracy against it.
pub const BUDGETS: [f32; 6] = [0.3, 0.1, 0.03, 0.01, 3e-3, 1e-3];

/// Settings of the tables.
#[derive(Clone, Debug, PartialEq)]
pub struct TraceTablesSettings {
    /// Voxels of the tile.
    pub dims: UVec3,
    /// Pixels per row of the view.
    pub width: u32,
    /// Rows of the view.
    pub height: u32,
    /// How the maps are computed.
    pub map_settings: DistanceMapSettings,
    /// Map reads before a ray gives up.
    pub max_steps: u32,
    /// Block side of Table 3's compressed maps.
    pub compression_block: u32,
    /// Error budget (voxels) of the `adaptive` patches: the accuracy goal.
    pub adaptive_budget: f32,
    /// Error budgets (voxels) of [`TraceScene::budget_rows`].
    pub budgets: Vec<f32>,
    /// Timed CPU passes per method; its time is the fastest.
    pub timed_passes: usize,
    /// Rounds of the interleaved raw / compressed time ratio (its median).
    pub ratio_rounds: usize,
    /// The steps-against-angle sweep.
    pub steps: StepsSettings,
}

impl TraceTablesSettings {
    /// The tables as `cargo xtask ddm-trace` measures them: 24 × 24 × 8 voxel tiles,
    /// 192 × 144 rays, tolerance 0.25 voxel, 512 steps, blocks of 4, budget 1e-3 voxel,
    /// fastest of 5 passes, median of [`RATIO_ROUNDS`] rounds.
    pub fn full() -> Self {
        Self {
            dims: UVec3::new(24, 24, 8),
            width: 192,
            height: 144,
            map_settings: DistanceMapSettings { tolerance: 0.25, periodic_xy: true },
            max_steps: 512,
            compression_block: 4,
            adaptive_budget: 1e-3,
            budgets: BUDGETS.to_vec(),
            timed_passes: 5,
            ratio_rounds: RATIO_ROUNDS,
            steps: StepsSettings::default(),
        }
    }

    /// [`TraceTablesSettings::full`] on 12 × 12 × 6 voxel tiles and 96 × 72 rays.
    pub fn quick() -> Self {
        Self { dims: UVec3::new(12, 12, 6), width: 96, height: 72, ..Self::full() }
    }

    /// Checks the fields that no later step meets as a scene error.
    pub fn validate(&self) -> Result<(), ExperimentError> {
        let positive = |x: f32| x.is_finite() && x > 0.0;
        if self.dims.cmpeq(UVec3::ZERO).any() {
            return Err(ExperimentError::settings("dims", format!("every size must be positive, not {}", self.dims)));
        }
        if self.width == 0 || self.height == 0 {
            return Err(ExperimentError::settings(
                "width/height",
                format!("empty view {}x{}", self.width, self.height),
            ));
        }
        if self.max_steps == 0 {
            return Err(ExperimentError::settings("max_steps", "must be positive"));
        }
        if !(1..=64).contains(&self.compression_block) {
            return Err(ExperimentError::settings(
                "compression_block",
                format!("must be 1 to 64, not {}", self.compression_block),
            ));
        }
        if !positive(self.adaptive_budget) {
            return Err(ExperimentError::settings(
                "adaptive_budget",
                format!("{} is not positive", self.adaptive_budget),
            ));
        }
        if let Some(budget) = self.budgets.iter().find(|&&b| !positive(b)) {
            return Err(ExperimentError::settings("budgets", format!("{budget} is not positive")));
        }
        if self.timed_passes == 0 || self.ratio_rounds == 0 {
            return Err(ExperimentError::settings("timed_passes/ratio_rounds", "must be positive"));
        }
        self.steps.validate()
    }

    fn sphere(&self) -> TraceSettings {
        TraceSettings { method: Method::SphereTracing, max_steps: self.max_steps, stepping: Stepping::Distance }
    }

    fn quadric(&self) -> TraceSettings {
        TraceSettings { method: Method::Quadric, max_steps: self.max_steps, stepping: Stepping::Distance }
    }
}

/// A patch construction of the tables.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PatchKind {
    /// The paper's C⁰ patches (§3.1 steps b–c).
    C0,
    /// Each voxel's fitted quadric (step a).
    Fitted,
    /// The mesh's own triangles per voxel (exact).
    Triangles,
    /// The fitted quadric or the triangles under the error budget.
    Adaptive,
    /// The watertight C⁰ patches from decisions shared by neighbours (beyond the paper).
    Watertight,
}

impl PatchKind {
    /// The five, in table order.
    pub const ALL: [PatchKind; 5] = [Self::C0, Self::Fitted, Self::Triangles, Self::Adaptive, Self::Watertight];

    /// The construction of `ddm_tracer` it is (`adaptive_budget`: the adaptive patches'
    /// error budget, voxels).
    pub fn surface(self, adaptive_budget: f32) -> PatchSurface {
        match self {
            Self::C0 => PatchSurface::C0,
            Self::Fitted => PatchSurface::FittedQuadric,
            Self::Triangles => PatchSurface::Triangles,
            Self::Adaptive => PatchSurface::Adaptive { max_error: adaptive_budget },
            Self::Watertight => PatchSurface::Watertight,
        }
    }

    /// The name in `ddm_trace_patches.csv`.
    pub fn name(self) -> &'static str {
        match self {
            Self::C0 => "C0",
            Self::Fitted => "fitted",
            Self::Triangles => "triangles",
            Self::Adaptive => "adaptive",
            Self::Watertight => "watertight",
        }
    }
}

/// A method of Tables 1–3.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TraceMethod {
    /// Sphere tracing with the plain distance map.
    Dm,
    /// Sphere tracing with the DDM 2×1.
    Ddm2x1,
    /// Sphere tracing with the DDM 4×1.
    Ddm4x1,
    /// Sphere tracing with the DDM 8×1.
    Ddm8x1,
    /// Sphere tracing with the DDM 4×2.
    Ddm4x2,
    /// DDM 4×1 + the C⁰ quadric patches (Algorithm 3.1).
    Ddm4x1Quadric,
    /// DDM 4×1 + each voxel's fitted quadric.
    Ddm4x1Fitted,
    /// DDM 4×1 + the mesh's triangles (exact).
    Ddm4x1Triangles,
    /// DDM 4×1 + the adaptive patches.
    Ddm4x1Adaptive,
    /// DDM 4×1 + the watertight C⁰ patches.
    Ddm4x1Watertight,
    /// The plain distance map with voxel-exit stepping.
    DmExit,
    /// The DDM 4×1 with voxel-exit stepping.
    Ddm4x1Exit,
    /// DDM 4×1 + the adaptive patches with voxel-exit stepping.
    Ddm4x1AdaptiveExit,
    /// Relief mapping (height fields only).
    Relief,
}

/// How a map-based method traces: its map, patches and settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MethodCase {
    /// The map's name in [`TRACE_MAPS`].
    pub map: &'static str,
    /// The patches, for [`Method::Quadric`].
    pub patches: Option<PatchKind>,
    /// Method and stepping (`max_steps` from the settings).
    pub settings: TraceSettings,
}

impl TraceMethod {
    /// All methods, in table order.
    pub const ALL: [TraceMethod; 14] = [
        Self::Dm,
        Self::Ddm2x1,
        Self::Ddm4x1,
        Self::Ddm8x1,
        Self::Ddm4x2,
        Self::Ddm4x1Quadric,
        Self::Ddm4x1Fitted,
        Self::Ddm4x1Triangles,
        Self::Ddm4x1Adaptive,
        Self::Ddm4x1Watertight,
        Self::DmExit,
        Self::Ddm4x1Exit,
        Self::Ddm4x1AdaptiveExit,
        Self::Relief,
    ];

    /// The name in the tables.
    pub fn name(self) -> &'static str {
        match self {
            Self::Dm => "DM",
            Self::Ddm2x1 => "DDM 2x1",
            Self::Ddm4x1 => "DDM 4x1",
            Self::Ddm8x1 => "DDM 8x1",
            Self::Ddm4x2 => "DDM 4x2",
            Self::Ddm4x1Quadric => "DDM 4x1 + quadric",
            Self::Ddm4x1Fitted => "DDM 4x1 + fitted Q",
            Self::Ddm4x1Triangles => "DDM 4x1 + triangles",
            Self::Ddm4x1Adaptive => "DDM 4x1 + adaptive",
            Self::Ddm4x1Watertight => "DDM 4x1 + watertight",
            Self::DmExit => "DM exit",
            Self::Ddm4x1Exit => "DDM 4x1 exit",
            Self::Ddm4x1AdaptiveExit => "DDM 4x1 + adaptive exit",
            Self::Relief => "relief 32+8",
        }
    }

    /// The map, patches and settings of a map-based method (`None` for relief mapping).
    pub fn case(self, settings: &TraceTablesSettings) -> Option<MethodCase> {
        let (sphere, quadric) = (settings.sphere(), settings.quadric());
        let exit = |s: TraceSettings| TraceSettings { stepping: Stepping::VoxelExit, ..s };
        let case = |map, patches, settings| Some(MethodCase { map, patches, settings });
        match self {
            Self::Dm | Self::Ddm2x1 | Self::Ddm4x1 | Self::Ddm8x1 | Self::Ddm4x2 => case(self.name(), None, sphere),
            Self::Ddm4x1Quadric => case("DDM 4x1", Some(PatchKind::C0), quadric),
            Self::Ddm4x1Fitted => case("DDM 4x1", Some(PatchKind::Fitted), quadric),
            Self::Ddm4x1Triangles => case("DDM 4x1", Some(PatchKind::Triangles), quadric),
            Self::Ddm4x1Adaptive => case("DDM 4x1", Some(PatchKind::Adaptive), quadric),
            Self::Ddm4x1Watertight => case("DDM 4x1", Some(PatchKind::Watertight), quadric),
            Self::DmExit => case("DM", None, exit(sphere)),
            Self::Ddm4x1Exit => case("DDM 4x1", None, exit(sphere)),
            Self::Ddm4x1AdaptiveExit => case("DDM 4x1", Some(PatchKind::Adaptive), exit(quadric)),
            Self::Relief => None,
        }
    }
}

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

/// Builds the patches of `surface` with `surface_kind` (errors name `scene` and `what`).
fn build_patches(
    scene: &str,
    what: &str,
    (dims, periodic_xy): (UVec3, bool),
    triangles: &[Triangle],
    surface: &[bool],
    surface_kind: PatchSurface,
) -> Result<VoxelPatches, ExperimentError> {
    let settings = PatchSettings { surface: surface_kind, periodic_xy, ..PatchSettings::default() };
    VoxelPatches::build(dims, triangles, surface, settings)
        .map_err(|error| ExperimentError::scene(scene, format!("the {what} patch construction failed: {error}")))
}

/// One row of `ddm_trace_patches.csv`: the memory of one patch construction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PatchRow {
    /// The mesostructure.
    pub mesostructure: &'static str,
    /// The construction.
    pub patches: PatchKind,
    /// Voxels kept as quadrics.
    pub quadric_voxels: u32,
    /// Voxels kept as triangles.
    pub triangle_voxels: u32,
    /// Surface voxels without a patch.
    pub voxels_without_patch: u32,
    /// Patches.
    pub patch_count: usize,
    /// Bytes the tracer reads.
    pub bytes: usize,
}

/// One row of `ddm_adaptive_budget.csv`: the adaptive patches at one error budget, traced
/// with the DDM 4×1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BudgetRow {
    /// The mesostructure.
    pub mesostructure: &'static str,
    /// The error budget, voxels.
    pub budget: f32,
    /// Voxels kept as quadrics.
    pub quadric_voxels: u32,
    /// Voxels kept as triangles.
    pub triangle_voxels: u32,
    /// Bytes the tracer reads.
    pub bytes: usize,
    /// The outcomes against the truth.
    pub stats: TraceStats,
    /// CPU rays per second of one pass.
    pub cpu_rays_per_second: f64,
}

/// One row of `ddm_trace_methods.csv` (Tables 1/2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MethodRow {
    /// The mesostructure.
    pub mesostructure: &'static str,
    /// The method.
    pub method: TraceMethod,
    /// The outcomes against the truth.
    pub stats: TraceStats,
    /// The outcomes against the tile's own surface ([`crate::reference`](mod@crate::reference)), when the scene
    /// has one.
    pub reference: Option<ReferenceAccuracy>,
    /// CPU rays per second (one thread, fastest pass).
    pub cpu_rays_per_second: f64,
    /// The GPU pass on the raw maps, when a GPU was given.
    pub gpu: Option<GpuRun>,
}

/// The compressed maps traced with another stepping, against the raw maps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SteppingComparison {
    /// Mean steps on the compressed maps.
    pub mean_steps: f64,
    /// Differences from the raw maps' outcomes.
    pub differences: HitDifferences,
    /// CPU time ratio compressed / raw (interleaved median).
    pub cpu_time_ratio: f64,
}

/// One row of `ddm_trace_compression.csv` (Table 3): a method on raw and compressed maps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CompressionRow {
    /// The mesostructure.
    pub mesostructure: &'static str,
    /// The method.
    pub method: TraceMethod,
    /// Block side of the compression.
    pub block: u32,
    /// Compression efficiency of the method's maps.
    pub efficiency: f64,
    /// Mean steps on the raw maps.
    pub raw_mean_steps: f64,
    /// The compressed maps traced with the method's own stepping.
    pub compressed: SteppingComparison,
    /// GPU time ratio compressed / raw, when a GPU was given.
    pub gpu_time_ratio: Option<f64>,
    /// For methods that step by the stored distance, the compressed maps traced with
    /// block cells (`Stepping::BlockCells`, beyond the paper).
    pub block_cells: Option<SteppingComparison>,
}

/// What one method gives: its Tables 1/2 row, its Table 3 row (map-based methods) and the
/// hit normal of each pixel (for the images).
#[derive(Clone, Debug, PartialEq)]
pub struct MethodResult {
    /// Tables 1/2.
    pub row: MethodRow,
    /// Table 3 (`None` for relief mapping).
    pub compression: Option<CompressionRow>,
    /// The hit normal of each pixel, `None` for a miss.
    pub normals: Vec<Option<Vec3>>,
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
            build_patches(name, kind.name(), (dims, periodic), &triangles, surface, kind.surface(budget))
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
            let set = build_patches(self.name, "adaptive", tiling, &self.triangles, surface, surface_kind)?;
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
            // Relief mapping's height map wraps: not for a tile that stands alone.
            None if self.height_field && self.settings.map_settings.periodic_xy => self.run_relief(gpu).map(Some),
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
            None if self.height_field && self.settings.map_settings.periodic_xy => {
                Ok(Some(self.relief_run(&self.relief_height_map()?, view, passes)))
            }
            None => Ok(None),
        }
    }

    /// [`TraceScene::trace_view`] of a map-based method.
    fn case_run(&self, case: MethodCase, view: &View, passes: usize) -> Result<CpuRun, ExperimentError> {
        let raw = self.map(case.map)?;
        let patches = case.patches.map(|kind| self.patches.get(kind));
        Ok(timed(&view.rays, passes, |o, d| trace(raw, patches, o, d, case.settings)))
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
