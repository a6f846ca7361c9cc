//! Unit tests of the trace tables on small tiles.

use super::*;
use crate::stats::HitDifferences;
use crate::steps::StepsSettings;
use ddm_tracer::Method;

/// Tiny settings: an 8 × 8 × 4 tile, a 6 × 4 view, one timed pass, 3 ratio rounds.
fn tiny() -> TraceTablesSettings {
    TraceTablesSettings {
        dims: UVec3::new(8, 8, 4),
        width: 6,
        height: 4,
        budgets: vec![0.1, 1e-3],
        timed_passes: 1,
        ratio_rounds: 3,
        steps: StepsSettings { angles_deg: vec![0.0, 60.0], grid: 2, azimuths: 2, max_steps: 256 },
        ..TraceTablesSettings::full()
    }
}

fn floor_scene(settings: &TraceTablesSettings) -> TraceScene {
    let floor = mesostructure::plane(settings.dims, 1.25);
    TraceScene::from_triangles("floor", floor, true, settings).unwrap()
}

#[test]
fn every_method_has_a_distinct_name_and_map_methods_name_their_map() {
    let settings = tiny();
    for (i, a) in TraceMethod::ALL.iter().enumerate() {
        assert!(TraceMethod::ALL[i + 1..].iter().all(|b| a.name() != b.name()));
        if let Some(case) = a.case(&settings) {
            assert!(TRACE_MAPS.iter().any(|m| m.name == case.map), "{}", a.name());
            assert!(a.name().starts_with(case.map));
            assert_eq!(case.patches.is_some(), case.settings.method == Method::Quadric);
            assert_eq!(a.name().ends_with(" exit"), case.settings.stepping == Stepping::VoxelExit);
            assert_eq!(case.settings.max_steps, settings.max_steps);
        } else {
            assert_eq!(*a, TraceMethod::Relief);
        }
    }
}

/// On a flat floor every method hits every pixel the mesh covers: the patch methods at
/// the mesh's point, sphere tracing where the ray enters the floor's voxel layer,
/// relief mapping within its last bisection interval; the compressed maps change no
/// hit (the compression is lossless where it matters).
#[test]
fn a_floor_is_traced_exactly_by_the_exact_methods_and_compression_loses_nothing() {
    let settings = tiny();
    let scene = floor_scene(&settings);
    let view = &scene.view;
    let covered = scene.truth.points.iter().filter(|p| p.is_some()).count();
    assert!(covered > 0);
    let relief_bound = view
        .rays
        .iter()
        .map(|(_, d)| f64::from(settings.dims.z) / f64::from(d.z.abs()) / f64::from(RELIEF_LINEAR))
        .fold(0.0, f64::max)
        / f64::from(1_u32 << (RELIEF_BINARY + 1))
        + 1e-5;
    let layer_bound = view.rays.iter().map(|(_, d)| 0.75 / f64::from(d.z.abs())).fold(0.0, f64::max) + 1e-5;
    for method in TraceMethod::ALL {
        let result = scene.run_method(method, None).unwrap().unwrap();
        let s = result.row.stats;
        let name = method.name();
        assert_eq!((s.truth_hits, s.holes, s.false_hits, s.exhausted), (covered, 0, 0, 0), "{name}");
        assert_eq!(result.normals.len(), view.rays.len());
        assert!(result.row.gpu.is_none());
        let bound = match method.case(&settings) {
            // Patches and triangles represent a plane exactly.
            Some(MethodCase { patches: Some(_), .. }) => 1e-4,
            // Sphere tracing stops where the ray enters the floor's voxel layer
            // `1 ≤ z ≤ 2`: at most `(2 - 1.25) / |d.z|` before the floor.
            Some(MethodCase { patches: None, .. }) => layer_bound,
            // Relief: half the last bisection interval of the linear step
            // `size_z / |d.z| / linear` (the height map of a plane is exact).
            None => relief_bound,
        };
        assert!(s.max_error <= bound, "{name}: {} > {bound}", s.max_error);
        match result.compression {
            Some(row) => {
                assert_eq!((row.mesostructure, row.method, row.block), ("floor", method, 4));
                assert_eq!(row.compressed.differences, HitDifferences::default(), "{name}");
                assert!(row.compressed.cpu_time_ratio > 0.0 && row.gpu_time_ratio.is_none());
                let distance_stepping = method.case(&settings).unwrap().settings.stepping == Stepping::Distance;
                assert_eq!(row.block_cells.is_some(), distance_stepping, "{name}");
                if let Some(cells) = row.block_cells {
                    assert_eq!(cells.differences, HitDifferences::default(), "{name}");
                    // Crossing a block without surface in one step never takes more steps.
                    assert!(cells.mean_steps <= row.compressed.mean_steps, "{name}");
                }
            }
            None => assert_eq!(method, TraceMethod::Relief),
        }
    }
}

/// A floor that stands alone (`periodic_xy: false`): the truth sees no copy of it, and
/// the methods that represent a plane exactly follow it pixel for pixel, missing where the
/// ray passes beside the tile — no wrapped geometry in the maps, the patches or the tracer.
#[test]
fn a_tile_that_stands_alone_is_traced_without_its_copies() {
    let periodic = tiny();
    let mut alone = TraceTablesSettings { width: 24, height: 16, ..tiny() };
    alone.map_settings.periodic_xy = false;
    let scene = floor_scene(&alone);
    assert_eq!(scene.view, View::looking(Camera::of_single_tile(alone.dims), 24, 16).unwrap());
    let size = alone.dims.as_dvec3();
    let hits: Vec<DVec3> = scene.truth.points.iter().flatten().copied().collect();
    assert!(hits.iter().all(|p| (0.0..=size.x).contains(&p.x) && (0.0..=size.y).contains(&p.y)));
    let misses = scene.truth.points.len() - hits.len();
    assert!(!hits.is_empty() && misses > 0, "{} hits, {misses} misses", hits.len());
    // The same view of the repeating floor hits every pixel: those misses are its copies.
    let repeated = TraceTablesSettings { width: 24, height: 16, ..periodic };
    let wide = TraceScene::from_triangles("floor", mesostructure::plane(alone.dims, 1.25), true, &repeated).unwrap();
    let wide_truth = ground_truth(&wide.mesh, &scene.view.rays);
    assert_eq!(wide_truth.points.iter().flatten().count(), scene.truth.points.len());
    let mut compared = 0;
    for method in TraceMethod::ALL {
        let Some(result) = scene.run_method(method, None).unwrap() else {
            assert_eq!(method, TraceMethod::Relief, "relief mapping's height map wraps: left out");
            continue;
        };
        if method.case(&alone).is_some_and(|case| case.patches.is_some()) {
            let s = result.row.stats;
            assert_eq!((s.truth_hits, s.holes, s.false_hits), (hits.len(), 0, 0), "{}", method.name());
            assert!(s.max_error <= 1e-4, "{}: {}", method.name(), s.max_error);
            compared += 1;
        }
    }
    assert!(compared >= 5, "{compared} patch methods compared");
}

#[test]
fn relief_runs_on_height_fields_only() {
    let settings = tiny();
    let floor = mesostructure::plane(settings.dims, 1.25);
    let scene = TraceScene::from_triangles("floor", floor, false, &settings).unwrap();
    assert!(scene.run_method(TraceMethod::Relief, None).unwrap().is_none());
}

/// A floor is flat: the fitted quadric meets every budget, so every budget keeps all
/// surface voxels as quadrics and hits the floor exactly; the rows follow the budgets.
#[test]
fn patch_and_budget_rows_of_a_floor() {
    let settings = tiny();
    let scene = floor_scene(&settings);
    assert_eq!(scene.view, View::perspective(settings.dims, settings.width, settings.height).unwrap());
    let surface_voxels = scene.maps[0].maps.surface.iter().filter(|&&s| s).count() as u32;
    let patches = scene.patch_rows();
    let kinds: Vec<_> = patches.iter().map(|r| r.patches.name()).collect();
    assert_eq!(kinds, ["C0", "fitted", "triangles", "adaptive", "watertight"]);
    let triangles = &patches[2];
    assert_eq!((triangles.triangle_voxels, triangles.quadric_voxels), (surface_voxels, 0));
    let adaptive = &patches[3];
    assert_eq!((adaptive.quadric_voxels, adaptive.triangle_voxels), (surface_voxels, 0));
    let budgets = scene.budget_rows().unwrap();
    let listed: Vec<f32> = budgets.iter().map(|r| r.budget).collect();
    assert_eq!(listed, settings.budgets);
    for row in &budgets {
        assert_eq!((row.quadric_voxels, row.triangle_voxels, row.bytes), (surface_voxels, 0, adaptive.bytes));
        assert_eq!((row.stats.holes, row.stats.false_hits), (0, 0));
        assert!(row.stats.max_error < 1e-3 && row.cpu_rays_per_second > 0.0);
    }
    let steps = scene.steps_rows().unwrap();
    assert_eq!(steps.len(), settings.steps.angles_deg.len() * (TRACE_MAPS.len() + 2));
}

#[test]
fn bad_settings_name_their_field() {
    let floor = mesostructure::plane(UVec3::new(8, 8, 4), 1.25);
    for (settings, field) in [
        (TraceTablesSettings { compression_block: 0, ..tiny() }, "compression_block"),
        (TraceTablesSettings { budgets: vec![0.1, -1.0], ..tiny() }, "budgets"),
        (TraceTablesSettings { adaptive_budget: f32::NAN, ..tiny() }, "adaptive_budget"),
        (TraceTablesSettings { width: 0, ..tiny() }, "width"),
        (TraceTablesSettings { timed_passes: 0, ..tiny() }, "timed_passes"),
        (TraceTablesSettings { dims: UVec3::new(8, 8, 0), ..tiny() }, "dims"),
    ] {
        let error = TraceScene::from_triangles("floor", floor.clone(), true, &settings).unwrap_err();
        assert!(error.to_string().contains(field), "{error}");
    }
}
