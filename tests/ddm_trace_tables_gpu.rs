//! The GPU column of `cargo xtask ddm-trace`: [`ddm_experiments::gpu::GpuTracer`] traces
//! each method's scene with the pipeline specialised for it (method, stepping, tiling,
//! block shift and atlas storage are the kernel's overridable constants). A plumbing
//! check: the ray-by-ray CPU = GPU comparison, with every difference explained, is
//! `ddm_tracer_gpu.rs`.
//!
//! Run with the kernel's default constants, every ray of a plain or DDM sphere-tracing
//! method differed (all 6 912 rays of each of the five tiles at 12 × 12 × 6, and all of a
//! tile that stands alone); with its own setting none did on lavapipe. A differing ray
//! here can only come from rounding within reach of a decision (a step landing on a voxel
//! wall, a direction on a cone boundary), which `ddm_tracer_gpu.rs` finds on fewer than
//! 1 % of its rays; the bound below allows that and no wrong setting.

use ddm_compress::{DistanceMapSettings, Triangle};
use ddm_experiments::gpu::GpuTracer;
use ddm_experiments::trace_tables::TraceScene;
use ddm_experiments::{TraceMethod, TraceTablesSettings};
use glam::Vec3;
use integration_tests::gpu;
use mesostructure::Mesostructure;

/// The 12 outward-facing triangles of the box `[lo, hi]`.
fn box_triangles(lo: Vec3, hi: Vec3) -> Vec<Triangle> {
    let corner = |i: usize| Vec3::select(glam::BVec3::new(i & 1 != 0, i & 2 != 0, i & 4 != 0), hi, lo);
    // Each face as a quad, counter-clockwise seen from outside.
    let faces = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
    faces
        .iter()
        .flat_map(|&[a, b, c, d]| {
            [Triangle([corner(a), corner(b), corner(c)]), Triangle([corner(a), corner(c), corner(d)])]
        })
        .collect()
}

/// A small view of each scene.
fn settings(periodic_xy: bool) -> TraceTablesSettings {
    TraceTablesSettings {
        width: 32,
        height: 24,
        map_settings: DistanceMapSettings { tolerance: 0.25, periodic_xy },
        timed_passes: 1,
        ratio_rounds: 1,
        ..TraceTablesSettings::quick()
    }
}

/// Every method of `scene` on the GPU: (method, differing rays, rays), at least 13 methods.
fn gpu_differences(scene: &TraceScene, rays: usize) -> Vec<(TraceMethod, usize)> {
    let tracer = GpuTracer::new(gpu(), 1).unwrap_or_else(|e| panic!("{e}"));
    let mut rows = Vec::new();
    for method in TraceMethod::ALL {
        let Some(result) = scene.run_method(method, Some(&tracer)).unwrap_or_else(|e| panic!("{method:?}: {e}")) else {
            continue;
        };
        let run = result.row.gpu.unwrap_or_else(|| panic!("{method:?}: no GPU run"));
        println!("{} {method:?}: {} of {rays} rays differ", scene.name, run.differs);
        rows.push((method, run.differs));
    }
    assert!(rows.len() >= 13, "{}: only {} methods traced", scene.name, rows.len());
    rows
}

#[test]
fn every_method_runs_its_own_pipeline_setting_on_repeating_and_lone_tiles() {
    let mut failures = Vec::new();
    let repeating = settings(true);
    let rays = (repeating.width * repeating.height) as usize;
    for structure in [Mesostructure::Maze(1), Mesostructure::Ball] {
        let scene = TraceScene::build(structure, &repeating).unwrap_or_else(|e| panic!("{e}"));
        failures.extend(gpu_differences(&scene, rays).into_iter().filter(|r| r.1 > rays / 100));
    }
    // A box standing alone (the tracer must not wrap it).
    let alone = settings(false);
    let triangles = box_triangles(Vec3::new(3.3, 4.2, 0.4), Vec3::new(8.6, 7.7, 4.4));
    let scene = TraceScene::from_triangles("pillar", triangles, false, &alone).unwrap_or_else(|e| panic!("{e}"));
    failures.extend(gpu_differences(&scene, rays).into_iter().filter(|r| r.1 > rays / 100));
    assert!(failures.is_empty(), "methods whose GPU run differs on more than 1 % of the rays: {failures:?}");
}
