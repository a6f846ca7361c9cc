//! The plain distance map against the bound a grid signed distance field gives (the
//! `mesh_to_sdf` crate's `generate_grid_sdf` at the voxel centres, less half the voxel
//! diagonal): never looser wherever that bound is one, on a closed tilted torus.

use benches::plain_map::{centre_sdf_bound, tilted_torus};
use ddm_compress::geometry::closest_point_on_triangle;
use ddm_compress::{DistanceMapSettings, MapKind, compute_distance_maps};
use glam::{UVec3, Vec3};

#[test]
fn plain_map_is_never_looser_than_the_centre_sdf_bound() {
    let dims = UVec3::splat(32);
    let triangles = tilted_torus(dims, 32, 16);
    let settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: false };
    let maps = compute_distance_maps(dims, &triangles, MapKind::Plain, settings).unwrap_or_else(|e| panic!("{e}"));
    let baseline = centre_sdf_bound(dims, &triangles);
    let half_diagonal = 0.75_f32.sqrt();
    let (mut compared, mut tighter, mut baseline_not_a_bound) = (0_u32, 0_u32, 0_u32);
    let (mut sum_ours, mut sum_baseline) = (0.0_f64, 0.0_f64);
    for (index, (&ours, &theirs)) in maps.values[0].iter().zip(&baseline).enumerate() {
        if maps.surface[index] {
            continue;
        }
        let index = index as u32;
        let centre = Vec3::new(
            (index % dims.x) as f32 + 0.5,
            ((index / dims.x) % dims.y) as f32 + 0.5,
            (index / (dims.x * dims.y)) as f32 + 0.5,
        );
        let centre_distance = triangles
            .iter()
            .map(|t| closest_point_on_triangle(centre, t).distance(centre))
            .fold(f32::INFINITY, f32::min);
        // The property: each pair's first bound is at least |c − q| − √3/2 (plain module).
        // The slack covers the rounding margins (coordinates below 64).
        assert!(ours >= centre_distance - half_diagonal - 1e-3, "voxel {index}: {ours} below the centre bound");
        // The baseline propagates nearest triangles over the grid: where its triangle is
        // not the nearest, its distance exceeds the true one and it bounds nothing.
        let valid = theirs <= (centre_distance - half_diagonal).max(0.0) + 1e-3;
        if valid {
            assert!(ours >= theirs - 1e-3, "voxel {index}: ours {ours} looser than the baseline {theirs}");
        } else {
            baseline_not_a_bound += 1;
        }
        tighter += u32::from(ours > theirs + 1e-3);
        sum_ours += f64::from(ours);
        sum_baseline += f64::from(theirs);
        compared += 1;
    }
    println!(
        "{compared} voxels off the surface: ours tighter in {tighter}; mean {:.4} (ours) vs {:.4} (centre SDF bound); \
         the baseline exceeds the true centre bound in {baseline_not_a_bound}",
        sum_ours / f64::from(compared),
        sum_baseline / f64::from(compared)
    );
    // Most of the 32³ voxels lie off the torus's surface.
    assert!(compared > 25_000, "{compared}");
}
