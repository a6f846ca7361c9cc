//! Conservative directional distance maps (§3.1) and the plain distance map baseline.
//!
//! `DDM(V, cone) = min { |m − v| : m ∈ M, v ∈ V, m − v ∈ cone }`: a ray leaving any point of
//! voxel `V` in a direction of the cone can advance that far without missing the
//! mesostructure `M`. The values computed here are lower bounds of it (conservative, as
//! the paper requires), within about twice the `tolerance` of the exact value; voxels that
//! `M` crosses store exactly 0 for every cone.

use alloc::vec::Vec;

use glam::{UVec3, Vec3};

use crate::bvh::TriangleBvh;
use crate::cones::DirectionCones;
use crate::geometry::{Aabb, Triangle};

/// Distance maps over a grid of unit voxels: one map per direction cone (a single map for
/// the plain, undirected distance map).
#[derive(Clone, Debug, PartialEq)]
pub struct DistanceMaps {
    /// Grid size in voxels.
    pub dims: UVec3,
    /// The cones, or `None` for the plain distance map.
    pub cones: Option<DirectionCones>,
    /// `values[cone][voxel]`, voxel index `x + dims.x (y + dims.y z)`.
    pub values: Vec<Vec<f32>>,
    /// Whether each voxel contains part of the mesostructure.
    pub surface: Vec<bool>,
    /// The cap stored where no surface point lies in a cone: the grid's diagonal.
    pub max_distance: f32,
}

/// Settings of [`compute_distance_maps`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DistanceMapSettings {
    /// Accuracy of the lower bounds, in voxels (0.05 gives values within about 0.1 voxel
    /// of the exact distance).
    pub tolerance: f32,
    /// Whether the mesostructure tiles the plane periodically in x and y (its neighbours'
    /// triangles then count too).
    pub periodic_xy: bool,
}

impl Default for DistanceMapSettings {
    fn default() -> Self {
        Self { tolerance: 0.05, periodic_xy: true }
    }
}

/// Computes the distance maps of `triangles` (in voxel coordinates) on a `dims` grid:
/// one per cone of `cones`, or the plain distance map for `None`.
///
/// Returns `None` for an empty grid, a grid of more than 2²⁴ voxels, a non-positive or
/// non-finite tolerance, or a non-finite triangle.
pub fn compute_distance_maps(
    dims: UVec3,
    triangles: &[Triangle],
    cones: Option<DirectionCones>,
    settings: DistanceMapSettings,
) -> Option<DistanceMaps> {
    let voxels = dims.x as usize * dims.y as usize * dims.z as usize;
    if voxels == 0 || voxels > 1 << 24 || !(settings.tolerance > 0.0 && settings.tolerance.is_finite()) {
        return None;
    }
    if triangles.iter().any(|t| !t.is_finite()) {
        return None;
    }
    let mut all = Vec::with_capacity(triangles.len() * if settings.periodic_xy { 9 } else { 1 });
    let offsets: &[(f32, f32)] = if settings.periodic_xy {
        &[
            (0.0, 0.0),
            (-1.0, 0.0),
            (1.0, 0.0),
            (0.0, -1.0),
            (0.0, 1.0),
            (-1.0, -1.0),
            (-1.0, 1.0),
            (1.0, -1.0),
            (1.0, 1.0),
        ]
    } else {
        &[(0.0, 0.0)]
    };
    for &(ox, oy) in offsets {
        let shift = Vec3::new(ox * dims.x as f32, oy * dims.y as f32, 0.0);
        all.extend(triangles.iter().map(|t| Triangle(t.0.map(|v| v + shift))));
    }
    let max_distance = dims.as_vec3().length();
    let cone_list: Vec<Option<crate::cones::Cone>> = match cones {
        Some(c) => (0..c.count()).map(|i| c.cone(i)).collect(),
        None => alloc::vec![None],
    };
    let bvh = TriangleBvh::new(all);
    let (mut overlap_stack, mut distance_stack) = (Vec::new(), Vec::new());
    let mut values = alloc::vec![alloc::vec![max_distance; voxels]; cone_list.len()];
    let mut surface = alloc::vec![false; voxels];
    for z in 0..dims.z {
        for y in 0..dims.y {
            for x in 0..dims.x {
                let index = (x + dims.x * (y + dims.y * z)) as usize;
                let voxel = Aabb::voxel(x, y, z);
                if bvh.any_overlaps(&voxel, &mut overlap_stack) {
                    surface[index] = true;
                    for map in values.iter_mut() {
                        map[index] = 0.0;
                    }
                    continue;
                }
                for (map, cone) in values.iter_mut().zip(&cone_list) {
                    map[index] = bvh.min_directional_distance(
                        &voxel,
                        cone.as_ref(),
                        settings.tolerance,
                        max_distance,
                        &mut distance_stack,
                    );
                }
            }
        }
    }
    Some(DistanceMaps { dims, cones, values, surface, max_distance })
}

/// A brute-force upper estimate of the directional distance from `voxel` to `triangles`
/// in `cone`: the smallest `|m − v|` over `samples²` point pairs whose direction lies in
/// the cone. A conservative map must never exceed it.
pub fn sampled_distance(voxel: UVec3, triangles: &[Triangle], cone: Option<&crate::cones::Cone>, samples: u32) -> f32 {
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
                    Some(cone) => cone.angle_lower_bound(d) == 0.0,
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{directional_distance_bound, triangle_overlaps_box};

    /// The maps by testing every voxel against every triangle, as before the hierarchy.
    fn brute_force(dims: UVec3, triangles: &[Triangle], cones: Option<DirectionCones>, tolerance: f32) -> DistanceMaps {
        let voxels = (dims.x * dims.y * dims.z) as usize;
        let max_distance = dims.as_vec3().length();
        let cone_list: Vec<Option<crate::cones::Cone>> = match cones {
            Some(c) => (0..c.count()).map(|i| c.cone(i)).collect(),
            None => alloc::vec![None],
        };
        let mut values = alloc::vec![alloc::vec![max_distance; voxels]; cone_list.len()];
        let mut surface = alloc::vec![false; voxels];
        for z in 0..dims.z {
            for y in 0..dims.y {
                for x in 0..dims.x {
                    let index = (x + dims.x * (y + dims.y * z)) as usize;
                    let voxel = Aabb::voxel(x, y, z);
                    if triangles.iter().any(|t| triangle_overlaps_box(t, &voxel)) {
                        surface[index] = true;
                        values.iter_mut().for_each(|map| map[index] = 0.0);
                        continue;
                    }
                    for (map, cone) in values.iter_mut().zip(&cone_list) {
                        let mut best = max_distance;
                        for triangle in triangles {
                            let bound = directional_distance_bound(&voxel, triangle, cone.as_ref(), tolerance, best);
                            best = best.min(bound);
                        }
                        map[index] = best;
                    }
                }
            }
        }
        DistanceMaps { dims, cones, values, surface, max_distance }
    }

    /// Small random triangles scattered in the grid (a xorshift generator, fixed seed).
    fn random_scene(seed: u64, count: usize, dims: UVec3) -> Vec<Triangle> {
        let mut state = seed;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 40) as f32 / (1u64 << 24) as f32
        };
        let size = dims.as_vec3();
        (0..count)
            .map(|_| {
                let anchor = Vec3::new(next(), next(), next()) * size;
                let mut vertex = || anchor + (Vec3::new(next(), next(), next()) - 0.5) * 3.0;
                Triangle([vertex(), vertex(), vertex()])
            })
            .collect()
    }

    #[test]
    fn hierarchy_gives_the_brute_force_values() {
        let dims = UVec3::new(7, 6, 5);
        for seed in [0x9e37_79b9_7f4a_7c15_u64, 0x1234_5678_9abc_def1] {
            let triangles = random_scene(seed, 40, dims);
            let settings = DistanceMapSettings { tolerance: 0.1, periodic_xy: false };
            for cones in [None, DirectionCones::downward(4, 1), DirectionCones::full(3, 2)] {
                let fast = compute_distance_maps(dims, &triangles, cones, settings).unwrap();
                let slow = brute_force(dims, &triangles, cones, settings.tolerance);
                assert_eq!(fast.surface, slow.surface);
                assert!(fast.surface.iter().any(|&s| s) && !fast.surface.iter().all(|&s| s));
                assert_eq!(fast.values, slow.values, "cones {cones:?}");
            }
        }
    }
}
