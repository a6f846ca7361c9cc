//! Conservative directional distance maps (§3.1) and the plain distance map baseline.
//!
//! `DDM(V, cone) = min { |m − v| : m ∈ M, v ∈ V, m − v ∈ cone }`: a ray leaving any point of
//! voxel `V` in a direction of the cone can advance that far without missing the
//! mesostructure `M`. The values computed here are lower bounds of it (conservative, as
//! the paper requires), within about twice the `tolerance` of the exact value for the
//! cones that are convex (the plain map, and every band of elevations from a pole to the
//! horizon, such as the DDM `m × 1`); a band short of the pole or the horizon (the DDM
//! `m × n`, `n ≥ 2`) is bounded through a convex cone that holds it, so its values are
//! lower bounds that can be looser (see `convex_cone` in the source). Voxels that `M`
//! crosses store exactly 0 for every cone.

use alloc::vec::Vec;

use glam::{UVec3, Vec3};

use crate::bvh::TriangleBvh;
use crate::cones::{Cone, DirectionCones, azimuth_elevation};
use crate::geometry::{Aabb, Triangle};
use crate::search::{CONES_PER_SEARCH, TriangleAxes, VoxelSearch};

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
/// Every value is a lower bound of the true (directional) distance, within about
/// `2 tolerance` of it for convex cones (see the module documentation); voxels that a triangle crosses store 0. All cones of a voxel are
/// searched together over a triangle hierarchy, refining box–triangle pairs only where a
/// cone's value depends on them (see the `search` module's documentation in the source);
/// with the `std` feature the rows of the grid are shared among the available threads.
///
/// Returns `None` for an empty grid, a grid of more than 2²⁴ voxels, a non-positive or
/// non-finite tolerance, or a non-finite triangle.
pub fn compute_distance_maps(
    dims: UVec3,
    triangles: &[Triangle],
    cones: Option<DirectionCones>,
    settings: DistanceMapSettings,
) -> Option<DistanceMaps> {
    let scene = Scene::new(dims, triangles, cones, settings)?;
    let rows = (dims.y * dims.z) as usize;
    let per_row = dims.x as usize * scene.cone_list.len();
    let mut values = alloc::vec![0.0_f32; rows * per_row];
    let mut surface = alloc::vec![false; rows * dims.x as usize];
    scene.compute_rows(&mut values, &mut surface);
    // `values` is voxel-major (all cones of a voxel together); the maps are cone-major.
    let cone_count = scene.cone_list.len();
    let maps = (0..cone_count).map(|c| values.iter().skip(c).step_by(cone_count).copied().collect()).collect();
    Some(DistanceMaps { dims, cones, values: maps, surface, max_distance: scene.max_distance })
}

/// The previous, slower computation, kept as a reference for tests and benchmarks: every
/// cone of every voxel on its own, each triangle bounded by
/// [`crate::geometry::directional_distance_bound`] (bounding spheres, subdivided to
/// `tolerance`). Its values are lower bounds as well, usually a little looser than
/// [`compute_distance_maps`]'s. Same inputs and `None` cases.
pub fn reference_distance_maps(
    dims: UVec3,
    triangles: &[Triangle],
    cones: Option<DirectionCones>,
    settings: DistanceMapSettings,
) -> Option<DistanceMaps> {
    let scene = Scene::new(dims, triangles, cones, settings)?;
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
    Some(DistanceMaps { dims, cones, values, surface, max_distance: scene.max_distance })
}

/// The validated inputs of a distance-map computation: the triangle hierarchy (with the
/// 8 neighbouring tiles' copies when periodic), the cone list and the cap.
struct Scene {
    dims: UVec3,
    bvh: TriangleBvh,
    /// The separating axes of each of the hierarchy's triangles, in its order.
    axes: Vec<TriangleAxes>,
    cone_list: Vec<Option<Cone>>,
    tolerance: f32,
    max_distance: f32,
}

impl Scene {
    fn new(
        dims: UVec3,
        triangles: &[Triangle],
        cones: Option<DirectionCones>,
        settings: DistanceMapSettings,
    ) -> Option<Self> {
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
        let cone_list: Vec<Option<Cone>> = match cones {
            Some(c) => (0..c.count()).map(|i| c.cone(i)).collect(),
            None => alloc::vec![None],
        };
        let bvh = TriangleBvh::new(all);
        let axes = bvh.triangles().iter().map(TriangleAxes::of).collect();
        Some(Self { dims, bvh, axes, cone_list, tolerance: settings.tolerance, max_distance: dims.as_vec3().length() })
    }

    /// Computes row `row` (`y + dims.y z`): `values` gets every cone of each voxel in
    /// turn, `surface` whether each voxel is crossed.
    fn compute_row(&self, row: usize, values: &mut [f32], surface: &mut [bool], scratch: &mut Scratch) {
        let (y, z) = (row as u32 % self.dims.y, row as u32 / self.dims.y);
        let cone_count = self.cone_list.len();
        for x in 0..self.dims.x {
            let voxel = Aabb::voxel(x, y, z);
            let out = &mut values[x as usize * cone_count..(x as usize + 1) * cone_count];
            if self.bvh.any_overlaps(&voxel, &mut scratch.overlap) {
                surface[x as usize] = true;
                out.fill(0.0);
                continue;
            }
            for (k, (chunk, out)) in
                self.cone_list.chunks(CONES_PER_SEARCH).zip(out.chunks_mut(CONES_PER_SEARCH)).enumerate()
            {
                let mut search = VoxelSearch::new(chunk, self.tolerance, self.max_distance);
                // The previous voxel's witnesses usually bound this one's values closely.
                let seeds = scratch.seeds.get_mut(k);
                if let Some(seeds) = &seeds {
                    search.seed(&voxel, seeds);
                }
                search.run(&self.bvh, &self.axes, &voxel, &mut scratch.nodes);
                for (c, value) in out.iter_mut().enumerate() {
                    *value = search.value(c);
                }
                match seeds {
                    Some(seeds) => {
                        seeds.clear();
                        seeds.extend(search.witness_points());
                    }
                    None => scratch.seeds.push(search.witness_points().collect()),
                }
            }
        }
    }

    /// Computes every row, on all available threads with the `std` feature.
    fn compute_rows(&self, values: &mut [f32], surface: &mut [bool]) {
        let per_row = self.dims.x as usize * self.cone_list.len();
        let row_surface = self.dims.x as usize;
        #[cfg(feature = "std")]
        {
            let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
            let rows = surface.len() / row_surface;
            if threads > 1 && rows > 1 {
                // Rows interleaved over the threads: neighbouring rows cost about the same.
                let threads = threads.min(rows);
                let mut slots: Vec<Vec<RowSlices<'_>>> = (0..threads).map(|_| Vec::new()).collect();
                for (row, (v, s)) in values.chunks_mut(per_row).zip(surface.chunks_mut(row_surface)).enumerate() {
                    slots[row % threads].push((row, v, s));
                }
                std::thread::scope(|scope| {
                    for slot in slots {
                        scope.spawn(move || {
                            let mut scratch = Scratch::default();
                            for (row, v, s) in slot {
                                self.compute_row(row, v, s, &mut scratch);
                            }
                        });
                    }
                });
                return;
            }
        }
        let mut scratch = Scratch::default();
        for (row, (v, s)) in values.chunks_mut(per_row).zip(surface.chunks_mut(row_surface)).enumerate() {
            self.compute_row(row, v, s, &mut scratch);
        }
    }
}

/// A row's index, its values (all cones of each voxel) and its surface flags.
#[cfg(feature = "std")]
type RowSlices<'a> = (usize, &'a mut [f32], &'a mut [bool]);

/// Reused traversal stacks.
#[derive(Default)]
struct Scratch {
    overlap: Vec<u32>,
    nodes: Vec<(u32, f32, u32)>,
    /// Per group of cones, the mesh points of the previous voxel's witnesses.
    seeds: Vec<Vec<Vec3>>,
}

/// A brute-force upper estimate of the directional distance from `voxel` to `triangles`
/// in `cone`: the smallest `|m − v|` over `samples²` point pairs whose direction lies in
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{directional_distance_bound, triangle_overlaps_box};

    /// The maps by testing every voxel against every triangle, as before the hierarchy.
    fn brute_force(dims: UVec3, triangles: &[Triangle], cones: Option<DirectionCones>, tolerance: f32) -> DistanceMaps {
        let voxels = (dims.x * dims.y * dims.z) as usize;
        let max_distance = dims.as_vec3().length();
        let cone_list: Vec<Option<Cone>> = match cones {
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
        let mut next = crate::test_random::uniform(seed);
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
    fn reference_hierarchy_gives_the_brute_force_values() {
        let dims = UVec3::new(7, 6, 5);
        for seed in [0x9e37_79b9_7f4a_7c15_u64, 0x1234_5678_9abc_def1] {
            let triangles = random_scene(seed, 40, dims);
            let settings = DistanceMapSettings { tolerance: 0.1, periodic_xy: false };
            for cones in [None, DirectionCones::downward(4, 1), DirectionCones::full(3, 2)] {
                let fast = reference_distance_maps(dims, &triangles, cones, settings).unwrap();
                let slow = brute_force(dims, &triangles, cones, settings.tolerance);
                assert_eq!(fast.surface, slow.surface);
                assert!(fast.surface.iter().any(|&s| s) && !fast.surface.iter().all(|&s| s));
                assert_eq!(fast.values, slow.values, "cones {cones:?}");
            }
        }
    }

    /// The largest difference between the hierarchy's search and the search over every
    /// triangle, for the convex cones (`[0]`) and the cut ones (`[1]`), asserting on the
    /// way that both stay below a sampled upper estimate of the true value; and the
    /// voxel-cones compared and considered.
    fn search_differences() -> ([f32; 2], usize, usize, usize) {
        // The order in which pairs are met changes the upper bounds found on the way, so
        // the two searches may finalise different pairs: both stay below the true value
        // (below a sampled upper estimate of it).
        let dims = UVec3::new(7, 6, 5);
        let (mut largest_difference, mut compared, mut considered, mut untouched) = ([0.0_f32; 2], 0, 0, 0);
        for seed in [0x9e37_79b9_7f4a_7c15_u64, 0x1234_5678_9abc_def1] {
            let triangles = random_scene(seed, 40, dims);
            // Voxels that no triangle's bounding box reaches cannot be surface voxels.
            let untouched_here = (0..dims.x * dims.y * dims.z)
                .filter(|&i| {
                    let v =
                        Vec3::new((i % dims.x) as f32, ((i / dims.x) % dims.y) as f32, (i / (dims.x * dims.y)) as f32);
                    triangles.iter().all(|t| {
                        let [a, b, c] = t.0;
                        let (lo, hi) = (a.min(b).min(c), a.max(b).max(c));
                        hi.cmplt(v).any() || lo.cmpgt(v + Vec3::ONE).any()
                    })
                })
                .count();
            let settings = DistanceMapSettings { tolerance: TOLERANCE, periodic_xy: false };
            // `downward(4, 2)` and `downward(8, 3)` have bands short of the pole and the
            // horizon, whose convex cones are cut (see `convex_cone`).
            for (group, cones) in [
                (0, None),
                (0, DirectionCones::downward(4, 1)),
                (0, DirectionCones::full(3, 2)),
                (1, DirectionCones::downward(4, 2)),
                (1, DirectionCones::downward(8, 3)),
            ] {
                untouched += untouched_here;
                let fast = compute_distance_maps(dims, &triangles, cones, settings).unwrap();
                let reference = reference_distance_maps(dims, &triangles, cones, settings).unwrap();
                assert_eq!(fast.surface, reference.surface);
                let cone_list: Vec<Option<Cone>> = match cones {
                    Some(c) => (0..c.count()).map(|i| c.cone(i)).collect(),
                    None => alloc::vec![None],
                };
                for z in 0..dims.z {
                    for y in 0..dims.y {
                        for x in 0..dims.x {
                            let index = (x + dims.x * (y + dims.y * z)) as usize;
                            considered += 1;
                            // Surface voxels store 0 in both (compared by `surface` above).
                            if fast.surface[index] {
                                continue;
                            }
                            compared += 1;
                            let mut search = VoxelSearch::new(&cone_list, settings.tolerance, fast.max_distance);
                            search.run_over_every_triangle(&triangles, &Aabb::voxel(x, y, z));
                            for (c, map) in fast.values.iter().enumerate() {
                                let (hierarchy, every) = (map[index], search.value(c));
                                let sampled =
                                    sampled_distance(UVec3::new(x, y, z), &triangles, cone_list[c].as_ref(), 6);
                                // The slack: the sampled f32 distance's rounding (~10
                                // operations on coordinates below 8).
                                assert!(
                                    hierarchy <= sampled + 1e-4 && every <= sampled + 1e-4,
                                    "voxel {index} cone {c}"
                                );
                                largest_difference[group] = largest_difference[group].max((hierarchy - every).abs());
                            }
                        }
                    }
                }
            }
        }
        (largest_difference, compared, considered, untouched)
    }

    /// The search tolerance of [`search_differences`].
    const TOLERANCE: f32 = 0.1;

    #[test]
    fn search_over_the_hierarchy_agrees_with_the_search_over_every_triangle() {
        let (largest, compared, considered, untouched) = search_differences();
        #[cfg(feature = "std")]
        std::println!(
            "largest differences {largest:?}, {compared} of {considered} voxels off the surface ({untouched} beyond \
             every triangle's bounding box)"
        );
        // Compared: at least the voxels beyond every triangle's bounding box.
        assert!(untouched > 0 && compared >= untouched, "{compared} voxels compared, {untouched} untouched");
        // For convex cones both values lie within about `2 tolerance` below the true value
        // (module documentation), hence within `2 tolerance` of each other; the cut cones
        // have no such guarantee (their values can be looser), only the bound checked
        // above.
        assert!(largest[0] <= 2.0 * TOLERANCE, "{largest:?}");
    }

    /// Regression pin of how close the two searches are, well inside the guarantee:
    /// measured 0.061 voxel for the convex cones (the hierarchy's search is also seeded
    /// with the previous voxel's witnesses, the other is not), 0.099 for the cut ones,
    /// whose pairs are more often finalised by size (their bounds cannot reach the
    /// witnesses' lengths); pinned at 0.075 and 0.11.
    #[test]
    fn search_difference_regression_pin() {
        let (largest, _, _, _) = search_differences();
        assert!(largest[0] <= 0.075 && largest[1] <= 0.11, "{largest:?}");
    }
}
