//! Conservative directional distance maps (§3.1) and the plain distance map baseline.
//!
//! `DDM(V, cone) = min { |m − v| : m ∈ M, v ∈ V, m − v ∈ cone }`: a ray leaving any point of
//! voxel `V` in a direction of the cone can advance that far without missing the
//! mesostructure `M`. The values computed here are lower bounds of it (conservative, as
//! the paper requires): the plain map's within `tolerance` of the exact box-to-mesh
//! distance (its own search, the private `plain` module, never below the voxel centre's
//! distance less half the voxel's diagonal); within about twice the `tolerance` for the
//! directional cones that are convex (every band of elevations from a pole to the
//! horizon, such as the DDM `m × 1`); a band short of the pole or the horizon (the DDM
//! `m × n`, `n ≥ 2`) is bounded through a convex cone that holds it: its values are within
//! about `2 tolerance` of the distance along that convex cone's directions, itself at most
//! the band's (see `convex_cone` and `search` in the source). Voxels that `M`
//! crosses store exactly 0 for every cone.

use alloc::vec::Vec;
use core::fmt;

use glam::{UVec3, Vec3};

use crate::bvh::TriangleBvh;
use crate::cones::{Cone, DirectionCones};
use crate::geometry::{Aabb, Triangle};
use crate::plain::{Child, PlainHierarchy};
use crate::search::{AxisDenominators, CONES_PER_SEARCH, TriangleAxes, VoxelSearch};

/// Which distance maps are computed: the plain distance map, or one directional distance
/// map per cone.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MapKind {
    /// The plain (undirected) distance map: a single map, for every direction.
    Plain,
    /// One directional distance map per cone of the cones (the paper's DDM m×n).
    Directional(DirectionCones),
}

impl MapKind {
    /// The number of maps: 1 for [`MapKind::Plain`], the number of cones otherwise.
    pub fn map_count(&self) -> u32 {
        match self {
            Self::Plain => 1,
            Self::Directional(cones) => cones.count(),
        }
    }

    /// The cones of a directional map; `None` for the plain map.
    pub fn cones(&self) -> Option<DirectionCones> {
        match self {
            Self::Plain => None,
            Self::Directional(cones) => Some(*cones),
        }
    }

    /// The cone that map `index` measures: `Some(None)` for the plain map's only map (every
    /// direction), `Some(Some(cone))` for a directional map, `None` past the last map.
    fn cone_of_map(&self, index: u32) -> Option<Option<Cone>> {
        match self {
            Self::Plain => (index == 0).then_some(None),
            Self::Directional(cones) => cones.cone(index).map(Some),
        }
    }

    /// Every map's cone in map order (`None`: every direction, the plain map).
    pub(crate) fn cone_list(&self) -> Vec<Option<Cone>> {
        (0..self.map_count()).map_while(|i| self.cone_of_map(i)).collect()
    }
}

impl From<DirectionCones> for MapKind {
    fn from(cones: DirectionCones) -> Self {
        Self::Directional(cones)
    }
}

/// The most voxels [`compute_distance_maps`] accepts: 2²⁴.
pub const MAX_VOXELS: u64 = 1 << 24;

/// The most values (voxels × maps) [`compute_distance_maps`] accepts: 2²⁸ (1 GiB of
/// `f32`).
pub const MAX_VALUES: u64 = 1 << 28;

/// Why [`compute_distance_maps`] refused its inputs. The checks run in the order of the
/// variants; the first that fails is returned.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DistanceMapError {
    /// A side of the grid is zero.
    EmptyGrid {
        /// The grid size given.
        dims: UVec3,
    },
    /// The grid has more than `limit` ([`MAX_VOXELS`]) voxels.
    TooManyVoxels {
        /// The grid size given.
        dims: UVec3,
        /// The largest number of voxels accepted.
        limit: u64,
    },
    /// Voxels × maps exceeds `limit` ([`MAX_VALUES`]).
    TooManyValues {
        /// Voxels of the grid.
        voxels: u64,
        /// Maps requested ([`MapKind::map_count`]).
        maps: u32,
        /// The largest number of values accepted.
        limit: u64,
    },
    /// The tolerance is zero, negative or not finite.
    InvalidTolerance {
        /// The tolerance given.
        tolerance: f32,
    },
    /// A vertex of triangle `index` (in the slice given) is NaN or infinite.
    NonFiniteTriangle {
        /// The triangle's index.
        index: usize,
    },
}

impl fmt::Display for DistanceMapError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::EmptyGrid { dims } => write!(f, "distance maps: the grid {dims} has no voxel"),
            Self::TooManyVoxels { dims, limit } => write!(
                f,
                "distance maps: the grid {dims} has {} voxels, more than the limit of {limit}",
                u128::from(dims.x) * u128::from(dims.y) * u128::from(dims.z)
            ),
            Self::TooManyValues { voxels, maps, limit } => {
                write!(f, "distance maps: {voxels} voxels × {maps} maps exceed the limit of {limit} values")
            }
            Self::InvalidTolerance { tolerance } => {
                write!(f, "distance maps: the tolerance {tolerance} is not a positive finite number")
            }
            Self::NonFiniteTriangle { index } => write!(f, "distance maps: triangle {index} has a non-finite vertex"),
        }
    }
}

impl core::error::Error for DistanceMapError {}

/// Distance maps over a grid of unit voxels: one map per direction cone (a single map for
/// the plain, undirected distance map).
#[derive(Clone, Debug, PartialEq)]
pub struct DistanceMaps {
    /// Grid size in voxels.
    pub dims: UVec3,
    /// Which maps these are: `values` has [`MapKind::map_count`] maps.
    pub kind: MapKind,
    /// `values[cone][voxel]`, voxel index `x + dims.x (y + dims.y z)`.
    pub values: Vec<Vec<f32>>,
    /// Whether each voxel contains part of the mesostructure.
    pub surface: Vec<bool>,
    /// The cap stored where no surface point lies in a cone: the grid's diagonal.
    pub max_distance: f32,
    /// Whether the maps were computed for a tile repeating in x and y
    /// ([`DistanceMapSettings::periodic_xy`]); otherwise nothing lies outside the tile's
    /// slab `[0, dims.x] × [0, dims.y]`, and a tracer must treat leaving it as a miss.
    pub periodic_xy: bool,
}

/// Settings of [`compute_distance_maps`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DistanceMapSettings {
    /// Accuracy of the lower bounds, in voxels: the plain map's values are within it of the
    /// exact distance, the convex cones' within about twice it (0.05 gives values within
    /// about 0.1 voxel).
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
/// one per cone for [`MapKind::Directional`], the plain distance map for
/// [`MapKind::Plain`].
///
/// Every value is a lower bound of the true (directional) distance: within `tolerance` of
/// it for the plain map, within about `2 tolerance` for convex cones (see the module
/// documentation); voxels that a triangle crosses store 0. All cones of a voxel are
/// searched together over a triangle hierarchy, refining box–triangle pairs only where a
/// cone's value depends on them (see the `search` module's documentation in the source);
/// the plain map bounds each box–triangle pair by alternating projections (the `plain`
/// module). With the `std` feature the rows of the grid are shared among the available
/// threads.
///
/// # Errors
///
/// A [`DistanceMapError`]: an empty grid, more than [`MAX_VOXELS`] voxels or
/// [`MAX_VALUES`] values, a non-positive or non-finite tolerance, or a non-finite triangle
/// (with its index).
pub fn compute_distance_maps(
    dims: UVec3,
    triangles: &[Triangle],
    kind: MapKind,
    settings: DistanceMapSettings,
) -> Result<DistanceMaps, DistanceMapError> {
    let scene = Scene::new(dims, triangles, kind, settings)?;
    let rows = (dims.y * dims.z) as usize;
    let per_row = dims.x as usize * scene.cone_list.len();
    let mut values = alloc::vec![0.0_f32; rows * per_row];
    let mut surface = alloc::vec![false; rows * dims.x as usize];
    scene.compute_rows(&mut values, &mut surface);
    // `values` is voxel-major (all cones of a voxel together); the maps are cone-major.
    let cone_count = scene.cone_list.len();
    let maps = (0..cone_count).map(|c| values.iter().skip(c).step_by(cone_count).copied().collect()).collect();
    Ok(DistanceMaps {
        dims,
        kind,
        values: maps,
        surface,
        max_distance: scene.max_distance,
        periodic_xy: settings.periodic_xy,
    })
}

/// The validated inputs of a distance-map computation: the triangle hierarchy (with the
/// 8 neighbouring tiles' copies when periodic), the cone list and the cap.
pub(crate) struct Scene {
    dims: UVec3,
    pub(crate) bvh: TriangleBvh,
    /// The separating axes of each of the hierarchy's triangles, in its order.
    axes: Vec<TriangleAxes>,
    /// Per group of [`CONES_PER_SEARCH`] cones, the bound denominators of the axes.
    denominators: Vec<AxisDenominators>,
    /// The plain map's hierarchy (for [`MapKind::Plain`] only).
    pub(crate) plain: Option<PlainHierarchy>,
    /// Each map's cone (`None`: every direction).
    pub(crate) cone_list: Vec<Option<Cone>>,
    tolerance: f32,
    pub(crate) max_distance: f32,
}

impl Scene {
    /// Checks the inputs (in the order of [`DistanceMapError`]'s variants) and builds the
    /// hierarchy.
    pub(crate) fn new(
        dims: UVec3,
        triangles: &[Triangle],
        kind: MapKind,
        settings: DistanceMapSettings,
    ) -> Result<Self, DistanceMapError> {
        if dims.cmpeq(UVec3::ZERO).any() {
            return Err(DistanceMapError::EmptyGrid { dims });
        }
        let voxels = u128::from(dims.x) * u128::from(dims.y) * u128::from(dims.z);
        if voxels > u128::from(MAX_VOXELS) {
            return Err(DistanceMapError::TooManyVoxels { dims, limit: MAX_VOXELS });
        }
        let voxels = voxels as u64; // at most MAX_VOXELS
        let maps = kind.map_count();
        if voxels * u64::from(maps) > MAX_VALUES {
            return Err(DistanceMapError::TooManyValues { voxels, maps, limit: MAX_VALUES });
        }
        if !(settings.tolerance > 0.0 && settings.tolerance.is_finite()) {
            return Err(DistanceMapError::InvalidTolerance { tolerance: settings.tolerance });
        }
        if let Some(index) = triangles.iter().position(|t| !t.is_finite()) {
            return Err(DistanceMapError::NonFiniteTriangle { index });
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
        let cone_list = kind.cone_list();
        let bvh = TriangleBvh::new(all);
        let plain = matches!(kind, MapKind::Plain).then(|| PlainHierarchy::new(&bvh));
        // The plain map searches its own hierarchy, which needs no separating axes.
        // The periodic copies (after the first `triangles.len()`) take their originals' axes.
        let axes: Vec<TriangleAxes> = if plain.is_some() {
            Vec::new()
        } else {
            let originals: Vec<TriangleAxes> = triangles.iter().map(TriangleAxes::of).collect();
            bvh.triangles()
                .iter()
                .zip(originals.iter().cycle())
                .map(|(triangle, original)| original.translated(triangle))
                .collect()
        };
        let denominators = if plain.is_some() {
            Vec::new()
        } else {
            cone_list
                .chunks(CONES_PER_SEARCH)
                .map(|chunk| AxisDenominators::new(chunk, &axes, triangles.len()))
                .collect()
        };
        Ok(Self {
            dims,
            bvh,
            axes,
            denominators,
            plain,
            cone_list,
            tolerance: settings.tolerance,
            max_distance: dims.as_vec3().length(),
        })
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
            if let Some(plain) = &self.plain {
                let found = plain.voxel_distance(
                    &voxel,
                    self.tolerance,
                    self.max_distance,
                    scratch.nearest,
                    &mut scratch.distance_nodes,
                );
                out[0] = found.value;
                scratch.nearest = found.nearest.or(scratch.nearest);
                continue;
            }
            let chunks = self.cone_list.chunks(CONES_PER_SEARCH).zip(out.chunks_mut(CONES_PER_SEARCH));
            // One entry of `denominators` per chunk (built so in `new`).
            for (k, ((chunk, out), denominators)) in chunks.zip(&self.denominators).enumerate() {
                let mut search = VoxelSearch::new(chunk, self.tolerance, self.max_distance);
                // The previous voxel's witnesses usually bound this one's values closely.
                let seeds = scratch.seeds.get_mut(k);
                if let Some(seeds) = &seeds {
                    search.seed(&voxel, seeds);
                }
                search.run(&self.bvh, &self.axes, denominators, &voxel, &mut scratch.nodes);
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
    /// The plain map: the triangle nearest the previous voxel, tried first.
    nearest: Option<u32>,
    /// The plain map's traversal stack.
    distance_nodes: Vec<(Child, f32)>,
}

#[cfg(test)]
mod tests {
    use alloc::format;
    use alloc::string::ToString;

    use super::*;
    use crate::geometry::{directional_distance_bound, triangle_overlaps_box};
    use crate::testing::{reference_distance_maps, sampled_distance};

    /// The maps by testing every voxel against every triangle, as before the hierarchy.
    fn brute_force(dims: UVec3, triangles: &[Triangle], kind: MapKind, tolerance: f32) -> DistanceMaps {
        let voxels = (dims.x * dims.y * dims.z) as usize;
        let max_distance = dims.as_vec3().length();
        let cone_list = kind.cone_list();
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
        DistanceMaps { dims, kind, values, surface, max_distance, periodic_xy: false }
    }

    /// The downward DDM `azimuths × elevations`.
    fn downward(azimuths: u32, elevations: u32) -> MapKind {
        MapKind::Directional(DirectionCones::downward(azimuths, elevations).unwrap())
    }

    #[test]
    fn map_kinds_count_their_maps_and_list_their_cones() {
        assert_eq!(MapKind::Plain.map_count(), 1);
        assert_eq!(MapKind::Plain.cones(), None);
        assert_eq!(MapKind::Plain.cone_list(), [None]);
        let cones = DirectionCones::downward(4, 2).unwrap();
        let kind = MapKind::from(cones);
        assert_eq!((kind.map_count(), kind.cones()), (8, Some(cones)));
        let list = kind.cone_list();
        assert_eq!(list.len(), 8);
        assert!(list.iter().enumerate().all(|(i, c)| *c == cones.cone(i as u32)));
    }

    #[test]
    fn each_invalid_input_has_its_error() {
        use DistanceMapError::*;
        let settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: true };
        let floor = [Triangle([Vec3::ZERO, Vec3::X, Vec3::Y])];
        let plain = |dims: UVec3| compute_distance_maps(dims, &floor, MapKind::Plain, settings);
        let flat = UVec3::new(4, 0, 4);
        assert_eq!(plain(flat), Err(EmptyGrid { dims: flat }));
        let big = UVec3::new(1 << 12, 1 << 12, 2);
        assert_eq!(plain(big), Err(TooManyVoxels { dims: big, limit: MAX_VOXELS }));
        let huge = UVec3::splat(u32::MAX);
        assert_eq!(plain(huge), Err(TooManyVoxels { dims: huge, limit: MAX_VOXELS }));
        assert!(plain(huge).unwrap_err().to_string().contains(&format!("{}", u128::from(u32::MAX).pow(3))));
        // 2²⁴ voxels are accepted; 16 maps of them reach the value limit exactly, 17 exceed it.
        let most = UVec3::new(1 << 12, 1 << 12, 1);
        let cones = DirectionCones::downward(17, 1).unwrap();
        assert_eq!(
            compute_distance_maps(most, &floor, MapKind::Directional(cones), settings),
            Err(TooManyValues { voxels: MAX_VOXELS, maps: 17, limit: MAX_VALUES })
        );
        let cones = DirectionCones::downward(u32::MAX, 1).unwrap();
        assert_eq!(
            compute_distance_maps(UVec3::ONE, &floor, cones.into(), settings),
            Err(TooManyValues { voxels: 1, maps: u32::MAX, limit: MAX_VALUES })
        );
        for tolerance in [0.0, -0.5, f32::INFINITY] {
            let settings = DistanceMapSettings { tolerance, ..settings };
            let result = compute_distance_maps(UVec3::splat(2), &floor, MapKind::Plain, settings);
            assert_eq!(result, Err(InvalidTolerance { tolerance }));
        }
        let settings_nan = DistanceMapSettings { tolerance: f32::NAN, ..settings };
        assert!(matches!(
            compute_distance_maps(UVec3::splat(2), &floor, MapKind::Plain, settings_nan),
            Err(InvalidTolerance { tolerance }) if tolerance.is_nan()
        ));
        let mut broken = alloc::vec![floor[0]; 3];
        broken[2].0[1].y = f32::NAN;
        let result = compute_distance_maps(UVec3::splat(2), &broken, MapKind::Plain, settings);
        assert_eq!(result, Err(NonFiniteTriangle { index: 2 }));
        let message = result.unwrap_err().to_string();
        assert!(message.contains("triangle 2"), "{message}");
        // The reference refuses the same inputs with the same errors.
        assert_eq!(
            reference_distance_maps(UVec3::splat(2), &broken, MapKind::Plain, settings),
            Err(NonFiniteTriangle { index: 2 })
        );
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
            for kind in [MapKind::Plain, downward(4, 1), MapKind::Directional(DirectionCones::full(3, 2).unwrap())] {
                let fast = reference_distance_maps(dims, &triangles, kind, settings).unwrap();
                let slow = brute_force(dims, &triangles, kind, settings.tolerance);
                assert_eq!(fast.surface, slow.surface);
                assert!(fast.surface.iter().any(|&s| s) && !fast.surface.iter().all(|&s| s));
                assert_eq!(fast.values, slow.values, "{kind:?}");
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
            for (group, kind) in [
                (0, downward(4, 1)),
                (0, MapKind::Directional(DirectionCones::full(3, 2).unwrap())),
                (1, downward(4, 2)),
                (1, downward(8, 3)),
            ] {
                untouched += untouched_here;
                let fast = compute_distance_maps(dims, &triangles, kind, settings).unwrap();
                let reference = reference_distance_maps(dims, &triangles, kind, settings).unwrap();
                assert_eq!(fast.surface, reference.surface);
                assert_eq!((fast.kind, reference.kind), (kind, kind));
                assert_eq!(fast.values.len(), kind.map_count() as usize);
                let cone_list = kind.cone_list();
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

    #[test]
    fn plain_map_is_within_tolerance_below_the_exact_distance_and_above_the_centre_bound() {
        let dims = UVec3::new(7, 6, 5);
        let (mut compared, mut tighter_than_centre) = (0, 0);
        for seed in [0x9e37_79b9_7f4a_7c15_u64, 0x1234_5678_9abc_def1] {
            let triangles = random_scene(seed, 12, dims);
            for tolerance in [0.02, 0.25] {
                let settings = DistanceMapSettings { tolerance, periodic_xy: false };
                let maps = compute_distance_maps(dims, &triangles, MapKind::Plain, settings).unwrap();
                let reference = reference_distance_maps(dims, &triangles, MapKind::Plain, settings).unwrap();
                assert_eq!(maps.surface, reference.surface);
                for (index, (&value, &surface)) in maps.values[0].iter().zip(&maps.surface).enumerate() {
                    if surface {
                        assert_eq!(value, 0.0);
                        continue;
                    }
                    let index = index as u32;
                    let voxel = Aabb::voxel(index % dims.x, (index / dims.x) % dims.y, index / (dims.x * dims.y));
                    let exact = triangles
                        .iter()
                        .map(|t| crate::geometry::box_triangle_distance(&voxel, t))
                        .fold(maps.max_distance, f32::min);
                    let centre = voxel.center();
                    let centre_distance = triangles
                        .iter()
                        .map(|t| crate::geometry::closest_point_on_triangle(centre, t).distance(centre))
                        .fold(f32::INFINITY, f32::min);
                    // The slack: both sides' rounding margins (coordinates below 10).
                    assert!(value <= exact + 1e-4, "voxel {index}: {value} above the exact {exact}");
                    assert!(value >= exact - tolerance - 1e-4, "voxel {index}: {value} ≪ exact {exact}");
                    let centre_bound = centre_distance - 0.75_f32.sqrt();
                    assert!(
                        value >= centre_bound - 1e-4,
                        "voxel {index}: {value} below the centre bound {centre_bound}"
                    );
                    tighter_than_centre += usize::from(value > centre_bound + 1e-4);
                    compared += 1;
                }
            }
        }
        #[cfg(feature = "std")]
        std::println!("{compared} voxels compared, {tighter_than_centre} strictly tighter than the centre bound");
        // 2 scenes × 2 tolerances × 210 voxels, less the surface voxels: every voxel off
        // the surface is compared; at least a quarter of them lie off the 12 triangles.
        assert!(compared >= 210, "{compared}");
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
        // Both values lie within about `2 tolerance` below the true value for convex cones,
        // below the distance along the convex cone holding a cut one (module
        // documentation), hence within `2 tolerance` of each other.
        assert!(largest[0] <= 2.0 * TOLERANCE && largest[1] <= 2.0 * TOLERANCE, "{largest:?}");
    }

    /// Regression pin of how close the two searches are, well inside the guarantee:
    /// measured 0.054 voxel for the convex cones (the hierarchy's search is also seeded
    /// with the previous voxel's witnesses and casts rays against the whole mesh, the
    /// other does neither; 0.061 before the mesh rays), 0.099 for the cut ones (the same
    /// before their witnesses were taken in the convex cone); pinned at 0.075 and 0.11.
    #[test]
    fn search_difference_regression_pin() {
        let (largest, _, _, _) = search_differences();
        assert!(largest[0] <= 0.075 && largest[1] <= 0.11, "{largest:?}");
    }
}
