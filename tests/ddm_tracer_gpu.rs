//! CPU = GPU differential test of `shaders/ddm_tracer.wgsl` (the compute tracer of
//! Algorithms 3.1–3.3) against `ddm-tracer`'s CPU reference: plain distance map and DDM
//! 4×1 sphere tracing, DDM + quadric (C⁰ patches, and the adaptive quadric / exact
//! triangle patches) and relief mapping, on a maze and a ball, reading compressed maps;
//! lone bounded triangle patches; and a tile that does not repeat, with rays from beside
//! it.
//!
//! Compared per ray: hit or miss, the cone, the step count, the hit point and normal.
//! Single precision on both sides; the GPU may contract `a + b * c` into fused
//! multiply-adds and round `atan2` and `normalize` differently, so a ray whose step lands
//! within rounding of a voxel wall can take one step more or less, and a hit point can
//! move by a few ulps. No count of such rays is allowed in advance; each differing ray
//! must be explained, ray by ray:
//!
//! - a different cone only for a direction within [`ATAN2_ERROR`] of a cone boundary (it
//!   belongs to both cones; both maps are safe for it);
//! - a different hit/miss, step count or exhaustion only for a ray whose CPU outcome
//!   changes the same way when its origin or direction moves by [`PERTURBATION_ULPS`]
//!   ulp (the rounding of a few operations: the ray is within rounding of a decision);
//! - a different hit point or normal only within 4 times the spread of those perturbed
//!   CPU traces (a noise estimate, printed), plus the rounding floor of a trace
//!   ([`point_floor`], [`NORMAL_FLOOR`]).
//!
//! On lavapipe every ray agrees bit for bit except the relief-mapping normals (WGSL's
//! `normalize` against glam's: within 4.9e-7, under [`NORMAL_FLOOR`]) and the 64 special
//! rays at azimuth 270° (a 4-cone boundary), which the GPU assigns to the other cone.

use ddm_compress::{DirectionCones, DistanceMapSettings, DistanceMaps, MapKind, Triangle, compute_distance_maps};
use ddm_tracer::{
    CompressedMaps, HeightMap, MeshRaycaster, Method, PatchSettings, PatchSurface, Stepping, TraceOutcome,
    TraceSettings, VoxelPatches, relief_trace, trace,
};
use ddm_tracer::{GpuScene, GpuSceneError, TraceResult};
use glam::{UVec3, Vec2, Vec3};
use integration_tests::gpu;
use mesostructure::Mesostructure;
use shader_registry::kernel_io::ddm_tracer::TraceRay;

const DIMS: UVec3 = UVec3::new(12, 12, 6);

/// WGSL's accuracy bound of `atan2` (4096 ulp of the result, WGSL §"Floating point
/// accuracy"), in radians for results up to π: how far the GPU's azimuth may lie from
/// the CPU's, hence how close to a cone boundary a direction must be for the two to pick
/// different cones.
const ATAN2_ERROR: f32 = 4096.0 * std::f32::consts::PI * f32::EPSILON;

/// How far (in ulp of each coordinate) the perturbed CPU traces move a ray's origin and
/// direction: the order of the rounding of the few operations FMA contraction may change.
const PERTURBATION_ULPS: u32 = 4;

/// The rounding of one `f32` operation on the tracer's values (coordinates below 64: a
/// ray crosses the 6.5-voxel slab at ≥ 5° elevation, `t ≤ 6.5 / sin 5° < 75`, and the
/// origins lie within 12 voxels), counted as a whole ulp of 128.
const F32_STEP_ERROR: f32 = 128.0 * f32::EPSILON;

/// The rounding floor of a hit point after `steps` steps: one [`F32_STEP_ERROR`] per
/// step, and 4 for the slab entry and the hit.
fn point_floor(steps: u32) -> f32 {
    (steps + 4) as f32 * F32_STEP_ERROR
}

/// The rounding floor of a unit normal: WGSL's `inverseSqrt` within 2 ulp, the dot
/// product and the scaling a few ulp more, per component of a unit vector: 16 ε.
const NORMAL_FLOOR: f32 = 16.0 * f32::EPSILON;

/// The fraction of rays that must be compared in full: the special rays at azimuth 270°
/// (64 of 6320, 1 %) may fall into the other cone, random ones only within
/// [`ATAN2_ERROR`] of one of 4 boundaries (probability 8 · 9.8e-4 / 2π ≈ 0.13 %), and
/// rays within rounding of a decision are rarer still: 98 % leaves room for both.
const MIN_COMPARED: f64 = 0.98;

/// `x` moved by `ulps` ulp up (`up`) or down.
fn nudged(x: f32, ulps: u32, up: bool) -> f32 {
    (0..ulps).fold(x, |x, _| if up { x.next_up() } else { x.next_down() })
}

/// The ray with its origin, then its direction, moved by [`PERTURBATION_ULPS`] along
/// each axis, both ways.
fn perturbations(origin: Vec3, direction: Vec3) -> Vec<(Vec3, Vec3)> {
    let mut rays = Vec::new();
    for axis in 0..3 {
        for up in [false, true] {
            let mut o = origin;
            o[axis] = nudged(o[axis], PERTURBATION_ULPS, up);
            rays.push((o, direction));
            let mut d = direction;
            d[axis] = nudged(d[axis], PERTURBATION_ULPS, up);
            rays.push((origin, d));
        }
    }
    rays
}

fn kernel_source() -> String {
    shader_registry::test_kernel_source("ddm_tracer_compute").unwrap_or_else(|e| panic!("{e}"))
}

/// Random downward rays from above the slab, plus special ones: straight down, along
/// the cone boundaries (azimuth multiples of 90°), grazing, upward (misses), through
/// voxel corners.
fn rays(count: usize, seed: u64) -> Vec<(Vec3, Vec3)> {
    let mut state = seed;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    let top = DIMS.z as f32 + 0.5;
    let mut rays: Vec<(Vec3, Vec3)> = (0..count)
        .map(|_| {
            let origin = Vec3::new(next() * DIMS.x as f32, next() * DIMS.y as f32, top);
            let azimuth = next() * std::f32::consts::TAU;
            let elevation = -(5.0 + 85.0 * next()).to_radians();
            let d = Vec3::new(elevation.cos() * azimuth.cos(), elevation.cos() * azimuth.sin(), elevation.sin());
            (origin, d * (0.5 + 2.0 * next()))
        })
        .collect();
    for k in 0..64 {
        let origin = Vec3::new(k as f32 * 0.37, k as f32 * 0.21, top);
        rays.push((origin, Vec3::NEG_Z));
        rays.push((Vec3::new(k as f32, 3.0, top), Vec3::new(1.0, 0.0, -1.0)));
        rays.push((Vec3::new(2.0, k as f32, top), Vec3::new(0.0, -1.0, -0.3)));
        rays.push((Vec3::new(k as f32 * 0.5, 1.0, 3.0), Vec3::new(0.3, 0.2, 1.0)));
        rays.push((Vec3::new(k as f32 * 0.25, 5.0, top), Vec3::new(1.0, 1.0, -0.01)));
    }
    rays
}

struct Mismatches {
    rays: usize,
    /// Rays compared in full (same cone, same discrete outcome).
    compared: usize,
    /// Rays within [`ATAN2_ERROR`] of a cone boundary.
    boundary: usize,
    /// Rays on a cone boundary that CPU and GPU assigned to different cones.
    split: usize,
    /// Rays whose hit/miss or steps differ, each within rounding of a decision (its
    /// perturbed CPU traces differ the same way).
    near_decision: usize,
    /// Rays whose point or normal is not bit-identical.
    inexact: usize,
    worst_point: f32,
    worst_normal: f32,
    /// Largest point / normal difference as a fraction of the allowed one.
    worst_ratio: f32,
}

fn compare(maps: &CompressedMaps, patches: Option<&VoxelPatches>, settings: TraceSettings, seed: u64) -> Mismatches {
    let scene = GpuScene::new(maps, patches, settings).unwrap_or_else(|e| panic!("{e}"));
    compare_scene(&scene, maps.kind, |o, d| trace(maps, patches, o, d, settings), seed)
}

/// [`compare`] with the GPU reading an atlas of binary16 pairs ([`GpuScene::with_f16_atlas`])
/// against the CPU tracer over the same values ([`CompressedMaps::with_f16_atlas`]).
fn compare_f16(
    maps: &CompressedMaps,
    patches: Option<&VoxelPatches>,
    settings: TraceSettings,
    seed: u64,
) -> Mismatches {
    let scene = GpuScene::new(maps, patches, settings).and_then(GpuScene::with_f16_atlas);
    let scene = scene.unwrap_or_else(|e| panic!("{e}"));
    let rounded = maps.with_f16_atlas();
    compare_scene(&scene, maps.kind, |o, d| trace(&rounded, patches, o, d, settings), seed)
}

/// [`compare`] for [`GpuScene::uncompressed`]: the GPU reading one grid word per voxel
/// against the CPU tracer over the uncompressed maps themselves.
fn compare_uncompressed(
    maps: &DistanceMaps,
    patches: Option<&VoxelPatches>,
    settings: TraceSettings,
    seed: u64,
) -> Mismatches {
    let scene = GpuScene::uncompressed(maps, patches, settings).unwrap_or_else(|e| panic!("{e}"));
    compare_scene(&scene, maps.kind, |o, d| trace(maps, patches, o, d, settings), seed)
}

fn compare_scene(
    scene: &GpuScene,
    kind: MapKind,
    reference: impl Fn(Vec3, Vec3) -> TraceOutcome,
    seed: u64,
) -> Mismatches {
    compare_rays(scene, kind, reference, &rays(6000, seed))
}

/// [`compare_scene`] over the given rays.
fn compare_rays(
    scene: &GpuScene,
    kind: MapKind,
    reference: impl Fn(Vec3, Vec3) -> TraceOutcome,
    rays: &[(Vec3, Vec3)],
) -> Mismatches {
    let inputs: Vec<TraceRay> = rays.iter().map(|&(o, d)| TraceRay::new(o, d)).collect();
    let uniforms = scene.uniforms(inputs.len() as u32);
    let storage = gpu().upload_storage(&scene.storage_bytes()).unwrap_or_else(|e| panic!("{e}"));
    // The pipeline specialised for the scene (method, stepping, tiling, block shift, atlas).
    let (results, _): (Vec<TraceResult>, _) = gpu()
        .compute_map_specialized(
            &kernel_source(),
            "trace_rays",
            &scene.pipeline_constants.constants(),
            bytemuck::bytes_of(&uniforms),
            &inputs,
            &storage,
        )
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(results.len(), rays.len());
    let mut m = Mismatches {
        rays: rays.len(),
        compared: 0,
        boundary: 0,
        split: 0,
        near_decision: 0,
        inexact: 0,
        worst_point: 0.0,
        worst_normal: 0.0,
        worst_ratio: 0.0,
    };
    for (&(origin, direction), gpu) in rays.iter().zip(&results) {
        let cpu = reference(origin, direction);
        // A direction on a cone boundary belongs to both cones (both maps are safe for
        // it); CPU and GPU atan2 may round it to either side, and then read different
        // (equally valid) maps: such rays are counted, not compared.
        let sectors = kind.map_count() as f32;
        let azimuth = direction.y.atan2(direction.x);
        let sector_width = std::f32::consts::TAU / sectors;
        let from_boundary = (azimuth / sector_width - (azimuth / sector_width).round()).abs() * sector_width;
        let on_boundary = from_boundary <= ATAN2_ERROR;
        m.boundary += usize::from(on_boundary);
        let context = || format!("ray {origin} {direction}: CPU {cpu:?}, GPU {gpu:?}");
        if cpu.cone != gpu.counts.y {
            assert!(on_boundary, "cone differs {from_boundary:e} rad from a boundary: {}", context());
            m.split += 1;
            continue;
        }
        let gpu_hit = gpu.normal_hit.w == 1.0;
        let perturbed =
            || perturbations(origin, direction).into_iter().map(|(o, d)| reference(o, d)).collect::<Vec<_>>();
        let discrete_differs =
            cpu.hit.is_some() != gpu_hit || cpu.steps != gpu.counts.x || u32::from(cpu.exhausted) != gpu.counts.z;
        if discrete_differs {
            // Allowed only where the CPU's own outcome changes the same way under a
            // perturbation of the ray by rounding.
            let near = perturbed().iter().any(|p| {
                (cpu.hit.is_some() != gpu_hit && p.hit.is_some() == gpu_hit)
                    || (cpu.steps != gpu.counts.x && p.steps != cpu.steps)
                    || (u32::from(cpu.exhausted) != gpu.counts.z && p.exhausted != cpu.exhausted)
            });
            assert!(near, "well-conditioned ray differs: {}", context());
            m.near_decision += 1;
            continue;
        }
        m.compared += 1;
        let Some(hit) = cpu.hit else { continue };
        let (point, normal) = (gpu.point_t.truncate(), gpu.normal_hit.truncate());
        if hit.point == point && hit.normal == normal {
            continue;
        }
        m.inexact += 1;
        // The spread of the CPU's own hit under perturbations of the ray by rounding.
        let (mut point_spread, mut normal_spread) = (0.0_f32, 0.0_f32);
        for p in perturbed() {
            if let Some(other) = p.hit
                && p.steps == cpu.steps
                && other.voxel == hit.voxel
            {
                point_spread = point_spread.max((other.point - hit.point).length());
                normal_spread = normal_spread.max((other.normal - hit.normal).length());
            }
        }
        let (point_error, normal_error) = ((hit.point - point).length(), (hit.normal - normal).length());
        let point_allowed = 4.0 * point_spread + point_floor(cpu.steps);
        let normal_allowed = 4.0 * normal_spread + NORMAL_FLOOR;
        assert!(
            point_error <= point_allowed && normal_error <= normal_allowed,
            "point differs by {point_error:e} (allowed {point_allowed:e}), normal by {normal_error:e} (allowed \
             {normal_allowed:e}): {}",
            context()
        );
        m.worst_point = m.worst_point.max(point_error);
        m.worst_normal = m.worst_normal.max(normal_error);
        m.worst_ratio = m.worst_ratio.max(point_error / point_allowed).max(normal_error / normal_allowed);
    }
    m
}

impl Mismatches {
    fn report(&self, label: &str) {
        println!(
            "{label}: {} rays, {} compared in full ({} within atan2's error of a cone boundary, {} of them in the \
             other cone; {} differ within rounding of a decision); {} points or normals not bit-identical, worst \
             point {:e}, normal {:e} ({:.3} of the allowed difference)",
            self.rays,
            self.compared,
            self.boundary,
            self.split,
            self.near_decision,
            self.inexact,
            self.worst_point,
            self.worst_normal,
            self.worst_ratio
        );
        assert!(
            self.compared as f64 >= MIN_COMPARED * self.rays as f64,
            "{label}: only {} of {} rays compared in full",
            self.compared,
            self.rays
        );
    }
}

#[test]
fn gpu_tracer_equals_the_cpu_reference() {
    println!("adapter: {}", gpu().describe());
    let settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: true };
    for (index, which) in [Mesostructure::Maze(1), Mesostructure::Ball].into_iter().enumerate() {
        let triangles = which.triangles(DIMS);
        let plain = compute_distance_maps(DIMS, &triangles, MapKind::Plain, settings).unwrap();
        let ddm4x1 = MapKind::Directional(DirectionCones::downward(4, 1).unwrap());
        let ddm = compute_distance_maps(DIMS, &triangles, ddm4x1, settings).unwrap();
        let patches = VoxelPatches::build(DIMS, &triangles, &ddm.surface, PatchSettings::default()).unwrap();
        // Exact triangles (bounded patches) where the fitted quadric misses 1e-3 voxel.
        let adaptive_settings =
            PatchSettings { surface: PatchSurface::Adaptive { max_error: 1e-3 }, ..Default::default() };
        let adaptive = VoxelPatches::build(DIMS, &triangles, &ddm.surface, adaptive_settings).unwrap();
        assert!(adaptive.quadric_voxels > 0 && adaptive.triangle_voxels > 0, "{}", which.name());
        let sphere = TraceSettings { method: Method::SphereTracing, max_steps: 256, stepping: Stepping::Distance };
        let quadric = TraceSettings { method: Method::Quadric, max_steps: 256, stepping: Stepping::Distance };
        let cases = [
            ("plain DM", CompressedMaps::compress(&plain, 2).unwrap(), None, sphere),
            ("DDM 4x1", CompressedMaps::compress(&ddm, 2).unwrap(), None, sphere),
            ("DDM 4x1 + quadric", CompressedMaps::compress(&ddm, 4).unwrap(), Some(&patches), quadric),
            ("DDM 4x1 + adaptive 1e-3", CompressedMaps::compress(&ddm, 4).unwrap(), Some(&adaptive), quadric),
            (
                "plain DM, voxel-exit stepping",
                CompressedMaps::compress(&plain, 2).unwrap(),
                None,
                TraceSettings { stepping: Stepping::VoxelExit, ..sphere },
            ),
            (
                "DDM 4x1, block cells",
                CompressedMaps::compress(&ddm, 4).unwrap(),
                None,
                TraceSettings { stepping: Stepping::BlockCells, ..sphere },
            ),
            (
                "DDM 4x1 + quadric, block cells",
                CompressedMaps::compress(&ddm, 4).unwrap(),
                Some(&patches),
                TraceSettings { stepping: Stepping::BlockCells, ..quadric },
            ),
            (
                "DDM 4x1 + adaptive 1e-3, voxel-exit stepping",
                CompressedMaps::compress(&ddm, 4).unwrap(),
                Some(&adaptive),
                TraceSettings { stepping: Stepping::VoxelExit, ..quadric },
            ),
            (
                "DDM 4x1 + quadric, 16 steps",
                CompressedMaps::compress(&ddm, 1).unwrap(),
                Some(&patches),
                TraceSettings { max_steps: 16, ..quadric },
            ),
        ];
        for (name, maps, patches, trace_settings) in cases {
            let m = compare(&maps, patches, trace_settings, 0x5eed + index as u64);
            m.report(&format!("{} {name}", which.name()));
        }
        // Blocks of 3 index the maps with divisions (TRACE_BLOCK_SHIFT unset); every case
        // above, with blocks of 1, 2 or 4, with shifts.
        let blocks_of_3 = CompressedMaps::compress(&ddm, 3).unwrap();
        assert_eq!(GpuScene::new(&blocks_of_3, None, quadric).unwrap().pipeline_constants.block_shift, None);
        let m = compare(&blocks_of_3, Some(&patches), quadric, 0x5eed + index as u64);
        m.report(&format!("{} DDM 4x1 + quadric, blocks of 3 (divisions)", which.name()));
        // The atlas in binary16, rounded down.
        let f16_cases = [
            ("DDM 4x1 + quadric, f16 atlas", CompressedMaps::compress(&ddm, 4).unwrap(), quadric),
            (
                "plain DM, block cells, f16 atlas",
                CompressedMaps::compress(&plain, 2).unwrap(),
                TraceSettings { stepping: Stepping::BlockCells, ..sphere },
            ),
        ];
        for (name, maps, trace_settings) in f16_cases {
            let patches = (trace_settings.method == Method::Quadric).then_some(&patches);
            let m = compare_f16(&maps, patches, trace_settings, 0x5eed + index as u64);
            m.report(&format!("{} {name}", which.name()));
        }
        let uncompressed = [
            (
                "plain DM, uncompressed, block cells",
                &plain,
                None,
                TraceSettings { stepping: Stepping::BlockCells, ..sphere },
            ),
            ("DDM 4x1 + quadric, uncompressed", &ddm, Some(&patches), quadric),
        ];
        for (name, maps, patches, trace_settings) in uncompressed {
            let m = compare_uncompressed(maps, patches, trace_settings, 0x5eed + index as u64);
            m.report(&format!("{} {name}", which.name()));
        }
        // Relief mapping of the same tile's height map (2 texels per voxel, 32 + 8 steps).
        let mesh = MeshRaycaster::new(&triangles, Vec2::new(DIMS.x as f32, DIMS.y as f32));
        let height_map = HeightMap::from_mesh(&mesh, DIMS, 2).unwrap_or_else(|e| panic!("{e}"));
        let maps = CompressedMaps::compress(&plain, 2).unwrap();
        let scene = GpuScene::new(
            &maps,
            None,
            TraceSettings { method: Method::SphereTracing, max_steps: 1, stepping: Stepping::Distance },
        )
        .and_then(|s| s.with_relief(&height_map, 32, 8))
        .unwrap_or_else(|e| panic!("the relief scene does not pack: {e}"));
        let size_z = DIMS.z as f32;
        let m = compare_scene(
            &scene,
            MapKind::Plain,
            |o, d| relief_trace(&height_map, size_z, o, d, 32, 8),
            0x7e1e + index as u64,
        );
        // Measured on lavapipe: points equal, normals within 4.9e-7 (WGSL's normalize()
        // against glam's), under `NORMAL_FLOOR`.
        m.report(&format!("{} relief", which.name()));
    }
}

/// Small floating triangles, one inside each of every other voxel of two layers: each
/// such voxel keeps one bounded patch, so rays that cross its plane beside the triangle
/// test that the GPU clips a lone bounded patch to its polygon as the CPU does.
#[test]
fn lone_triangle_patches_are_clipped_on_the_gpu_as_on_the_cpu() {
    let mut triangles = Vec::new();
    for z in [1u32, 3] {
        for y in 0..DIMS.y {
            for x in (y % 2..DIMS.x).step_by(2) {
                let c = Vec3::new(x as f32 + 0.2, y as f32 + 0.25, z as f32 + 0.4);
                let tilt = 0.05 * (x % 3) as f32;
                triangles.push(Triangle([c, c + Vec3::new(0.5, 0.1, tilt), c + Vec3::new(0.1, 0.45, -tilt)]));
            }
        }
    }
    let settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: true };
    let maps = compute_distance_maps(DIMS, &triangles, MapKind::Plain, settings).unwrap();
    let exact = PatchSettings { surface: PatchSurface::Triangles, ..Default::default() };
    let patches = VoxelPatches::build(DIMS, &triangles, &maps.surface, exact).unwrap();
    assert_eq!(patches.patches.len(), triangles.len(), "one bounded patch per voxel");
    let quadric = TraceSettings { method: Method::Quadric, max_steps: 256, stepping: Stepping::Distance };
    let maps = CompressedMaps::compress(&maps, 2).unwrap();
    let m = compare(&maps, Some(&patches), quadric, 0x10e);
    let rays = rays(6000, 0x10e);
    let hits = rays.iter().filter(|&&(o, d)| trace(&maps, Some(&patches), o, d, quadric).hit.is_some()).count();
    println!("floating triangles: {} rays, {hits} hit on the CPU", m.rays);
    m.report("floating triangles");
    // Both outcomes must be tested: each layer's triangles (area ≈ 0.11 voxel², in half
    // of the voxels) cover ≈ 5.6 % of the tile seen from above, so at least 5 % of the
    // rays hit (one layer's share less a margin; two layers give ≈ 11 %) and at least
    // half miss. Measured on lavapipe: 612 of 6320 rays hit, every ray bit-identical.
    // With the WGSL clipping of lone bounded patches removed (checked once), 3679 rays
    // differ: the GPU then hits the triangles' planes beside them.
    assert!(hits * 20 >= m.rays && (m.rays - hits) * 2 >= m.rays, "{hits} of {} rays hit", m.rays);
}

#[test]
fn scene_buffers_are_checked_against_the_adapter() {
    let kernel = kernel_source();
    let uniforms = [0_u8; 48];
    let rays = [TraceRay::new(Vec3::ZERO, Vec3::NEG_Z)];
    // An empty storage buffer is a request error, not a wgpu panic.
    let empty: [&[u8]; 5] = [&[0; 48], &[0; 4], &[], &[0; 8], &[0; 128]];
    let result =
        gpu().compute_map_with_storage::<TraceRay, TraceResult>(&kernel, "trace_rays", &uniforms, &rays, &empty);
    assert!(matches!(result, Err(gpu_harness::HarnessError::InvalidRequest(_))), "{result:?}");
    // More storage bindings than the adapter allows per stage.
    let limit = gpu().limits().max_storage_buffers_per_shader_stage as usize;
    let many: Vec<&[u8]> = vec![&[0_u8; 16][..]; limit];
    let result =
        gpu().compute_map_with_storage::<TraceRay, TraceResult>(&kernel, "trace_rays", &uniforms, &rays, &many);
    assert!(matches!(result, Err(gpu_harness::HarnessError::TooLarge { .. })), "{result:?}");
}

/// A tile that does not repeat (`periodic_xy: false` in maps, patches and GPU scene): a
/// plane sloping from z = 1 at x = 0 to z = 4 at x = 12 and a sphere beside the x = 12
/// border, traced from above a square reaching 3 voxels past the tile on each side, so
/// that rays enter through the side walls (`trace_tile_entry`) and leave through them.
#[test]
fn a_single_tile_traces_on_the_gpu_as_on_the_cpu() {
    let [a, b, c, d] =
        [Vec3::new(0.0, 0.0, 1.0), Vec3::new(12.0, 0.0, 4.0), Vec3::new(12.0, 12.0, 4.0), Vec3::new(0.0, 12.0, 1.0)];
    let mut triangles = vec![Triangle([a, b, c]), Triangle([a, c, d])];
    triangles.extend(mesostructure::sphere(Vec3::new(10.3, 6.0, 4.4), 1.3, 16));
    let settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: false };
    let ddm4x1 = MapKind::Directional(DirectionCones::downward(4, 1).unwrap());
    let ddm = compute_distance_maps(DIMS, &triangles, ddm4x1, settings).unwrap();
    let plain = compute_distance_maps(DIMS, &triangles, MapKind::Plain, settings).unwrap();
    let patch_settings = PatchSettings { surface: PatchSurface::Triangles, periodic_xy: false, ..Default::default() };
    let patches = VoxelPatches::build(DIMS, &triangles, &ddm.surface, patch_settings).unwrap();
    // Patches built for the repeating tile do not go with these maps.
    let periodic_patches = VoxelPatches::build(DIMS, &triangles, &ddm.surface, PatchSettings::default()).unwrap();
    let quadric = TraceSettings { method: Method::Quadric, max_steps: 256, stepping: Stepping::Distance };
    let error = GpuScene::uncompressed(&ddm, Some(&periodic_patches), quadric).unwrap_err();
    assert_eq!(error, GpuSceneError::PatchTiling { maps_periodic: false });
    let mut state = 0x5119_u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    let rays: Vec<(Vec3, Vec3)> = (0..6000)
        .map(|_| {
            let origin = Vec3::new(next() * 18.0 - 3.0, next() * 18.0 - 3.0, DIMS.z as f32 + 0.5);
            let azimuth = next() * std::f32::consts::TAU;
            let elevation = -(5.0 + 85.0 * next()).to_radians();
            (origin, Vec3::new(elevation.cos() * azimuth.cos(), elevation.cos() * azimuth.sin(), elevation.sin()))
        })
        .collect();
    let sphere = TraceSettings { method: Method::SphereTracing, ..quadric };
    let block_cells = TraceSettings { stepping: Stepping::BlockCells, ..quadric };
    let compressed = CompressedMaps::compress(&ddm, 4).unwrap();
    let scene = GpuScene::new(&compressed, Some(&patches), block_cells).unwrap_or_else(|e| panic!("{e}"));
    let m = compare_rays(&scene, ddm.kind, |o, d| trace(&compressed, Some(&patches), o, d, block_cells), &rays);
    m.report("single tile, DDM 4x1 + triangles, block cells");
    let scene = GpuScene::uncompressed(&plain, None, sphere).unwrap_or_else(|e| panic!("{e}"));
    let m = compare_rays(&scene, MapKind::Plain, |o, d| trace(&plain, None, o, d, sphere), &rays);
    m.report("single tile, plain DM, uncompressed");
    // The same scene refuses relief mapping (its height map would wrap).
    let mesh = MeshRaycaster::new(&triangles, Vec2::ZERO);
    let height_map = HeightMap::from_mesh(&mesh, DIMS, 2).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.with_relief(&height_map, 8, 4).unwrap_err(), GpuSceneError::ReliefNeedsPeriodicTile);
}
