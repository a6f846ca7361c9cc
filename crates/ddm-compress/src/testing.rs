//! Test and benchmark references, **not part of the supported API**: compiled only with
//! the non-default `testing` feature (and in this crate's own tests). They may change or
//! go away without notice.
//!
//! - [`reference_distance_maps`]: the previous, slower computation of the distance maps,
//!   which tests and benchmarks compare [`compute_distance_maps`](crate::compute_distance_maps) with.
//! - [`sampled_distance`]: a brute-force sampled upper estimate of a directional
//!   distance, which no conservative map value may exceed.

use alloc::vec::Vec;

use glam::{UVec3, Vec3};

use crate::cones::{Cone, azimuth_elevation};
use crate::ddm::{DistanceMapError, DistanceMapSettings, DistanceMaps, MapKind, Scene};
use crate::geometry::{Aabb, Triangle};

/// The previous, slower computation, kept as a reference for tests and benchmarks: every
/// cone of every voxel on its own, each triangle bounded by
/// [`crate::geometry::directional_distance_bound`] (bounding spheres, subdivided to
/// `tolerance`). Its values are lower bounds as well, usually a little looser than
/// [`compute_distance_maps`](crate::compute_distance_maps)'s.
///
/// # Errors
///
/// The same [`DistanceMapError`]s as [`compute_distance_maps`](crate::compute_distance_maps), for the same inputs.
pub fn reference_distance_maps(
    dims: UVec3,
    triangles: &[Triangle],
    kind: MapKind,
    settings: DistanceMapSettings,
) -> Result<DistanceMaps, DistanceMapError> {
    let scene = Scene::new(dims, triangles, kind, settings)?;
    let voxels = dims.x as usize * dims.y as usize * dims.z as usize;
    let (mut overlap_stack, mut distance_stack) = (Vec::new(), Vec::new());
    let mut values = alloc::vec![alloc::vec![scene.max_distance; voxels]; scene.cone_list.len()];
    let mut surface = alloc::vec![false; voxels];
    for z in 0..dims.z {
        for y in 0..dims.y {
            for x in 0..dims.x {
                let index = (x + dims.x * (y + dims.y * z)) as usize;
                let voxel = Aabb::voxel(x, y, z);
                if scene.bvh.any_overlaps(&voxel, &mut overlap_stack) {
                    surface[index] = true;
                    for map in values.iter_mut() {
                        map[index] = 0.0;
                    }
                    continue;
                }
                for (map, cone) in values.iter_mut().zip(&scene.cone_list) {
                    map[index] = scene.bvh.min_directional_distance(
                        &voxel,
                        cone.as_ref(),
                        settings.tolerance,
                        scene.max_distance,
                        &mut distance_stack,
                    );
                }
            }
        }
    }
    Ok(DistanceMaps {
        dims,
        kind,
        values,
        surface,
        max_distance: scene.max_distance,
        periodic_xy: settings.periodic_xy,
    })
}

/// A brute-force upper estimate of the directional distance from `voxel` to `triangles`
/// in `cone` (`None`: every direction): the smallest `|m − v|` over `samples²` point pairs whose direction lies in
/// the cone. A conservative map must never exceed it.
pub fn sampled_distance(voxel: UVec3, triangles: &[Triangle], cone: Option<&Cone>, samples: u32) -> f32 {
    let mut best = f32::INFINITY;
    let n = samples.max(1);
    let box_point = |k: u32| {
        // A low-discrepancy point of the voxel (Halton bases 2, 3, 5).
        let halton = |mut i: u32, base: u32| {
            let (mut f, mut r) = (1.0_f32, 0.0_f32);
            while i > 0 {
                f /= base as f32;
                r += f * (i % base) as f32;
                i /= base;
            }
            r
        };
        voxel.as_vec3() + Vec3::new(halton(k + 1, 2), halton(k + 1, 3), halton(k + 1, 5))
    };
    for triangle in triangles {
        let [a, b, c] = triangle.0;
        for k in 0..n {
            let v = box_point(k);
            for s in 0..n {
                // A point of the triangle (square-root parametrization, van der Corput).
                let u = (s as f32 + 0.5) / n as f32;
                let w = ((s * 7 + k * 3) % n) as f32 / n as f32 + 0.5 / n as f32;
                let su = libm::sqrtf(u);
                let m = a * (1.0 - su) + b * (su * (1.0 - w)) + c * (su * w);
                let d = m - v;
                let inside = match cone {
                    Some(cone) => {
                        azimuth_elevation(d).is_some_and(|(azimuth, elevation)| cone.contains_at(azimuth, elevation))
                    }
                    None => true,
                };
                if inside {
                    best = best.min(d.length());
                }
            }
        }
    }
    best
}
