//! The sparse octree of `n³` bricks (§5.2, after `GigaVoxels` \[CNLE09\]; Fig. 10d) and its
//! construction from a [`SurfaceSource`].
//!
//! # Units and levels
//!
//! The octree covers the cube `domain.origin + [0, domain.size)³`. Inside, lengths are in
//! *finest voxels* (`voxel_size = domain.size / (n 2^(levels − 1))` world units). Level 0
//! is the finest; level `L` has voxels of `S_L = 2^L` finest voxels; the root is a single
//! brick at level `levels − 1`.
//!
//! # Voxels at vertices: bricks of `(n + 1)³`
//!
//! A level-`L` voxel `v` stands at the lattice point `v S_L` and describes the cube of side
//! `S_L` centred there. A node at level `L` covers `n S_L` finest voxels, `n³` cells, and its
//! brick stores the `(n + 1)³` voxels at the cells' corners, so that trilinear
//! interpolation anywhere in the node reads one brick. Neighbouring bricks share their
//! face voxels. This is the role of `GigaVoxels`' one-voxel border (8³ cells stored as 10³
//! with centred samples) at `(n + 1)³ / (n + 2)³ = 73 %` of its memory for `n = 8`.
//!
//! # Which nodes get a brick
//!
//! A cone element at level of detail `λ ∈ [L, L + 1)` has radius `r` and half-length `l`
//! below `S_L`; its footprint square reaches `l |n_z| + √2 r ρ ≤ √(l² + 2r²) < √3 S_L`
//! along any plane normal (`n_z² + ρ² = 1`), so its mask is empty wherever the surface is
//! farther than `√3 S_L`. A node gets a brick iff the surface may come within
//! [`EMPTY_DISTANCE`]` = 2` of its level's voxels of it: iff one of its `n³` cells `c` has
//! `|d(c)| ≤ (√3/2) S_L + 2 S_L` (a 1-Lipschitz distance misses nothing; the node's centre
//! is tested first, with the node's half-diagonal). Everywhere in a node without a brick
//! the distance is thus above `2 S_L`, the value its samples return. (The filtered `h̄` of
//! a coarse level blurs the surface by up to `√3 S_L`; that blur is not kept beyond the
//! elements' reach.) A brick node above level 0 has eight children;
//! a node without a brick has none and is [`EMPTY`](OctreeNode::EMPTY) (outside) or
//! [`FULL`](OctreeNode::FULL) (inside).
//!
//! # Every voxel is a function of its position
//!
//! A voxel's value depends only on its level and integer position: `h̄`, `n̄` are means
//! over fixed quadrature points of its cube, its statistics come from the surface samples
//! in its cube, and dilation looks up the same global tables. So the face voxels that
//! neighbouring bricks share are the same bits in both, and where a neighbour has no brick
//! they are what the source gives there: brick borders interpolate without seams.
//!
//! # `h̄` and `n̄`: a box filter
//!
//! `h̄` at level `L` is the mean of the signed distance over the voxel's cube, `n̄` the
//! mean of its gradient, both by the midpoint rule on `q³` sub-cubes, `q = min(2^L,
//! quadrature)` (at level 0 the source at the vertex itself). Since the same fixed offsets
//! serve every voxel, `n̄` is exactly the gradient of the filtered `h̄` (a mean of shifted
//! copies of the field), and the filtered `h̄` is 1-Lipschitz like the source.

use alloc::vec::Vec;

use glam::{IVec3, UVec3, Vec3};
use gpu_layout::gpu_struct;

use crate::descriptor::Voxel;
use crate::prefilter::{HeightVariance, SurfaceStatistics, surface_statistics};
use crate::surface::{Cell, SurfaceSample, SurfaceSource};

/// The side `n` of the bricks.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum BrickSize {
    /// 4³ voxels.
    Four,
    /// 8³ voxels (`GigaVoxels`' and the paper's choice; the default).
    #[default]
    Eight,
    /// 16³ voxels.
    Sixteen,
}

impl BrickSize {
    /// `n`.
    pub const fn side(self) -> u32 {
        match self {
            BrickSize::Four => 4,
            BrickSize::Eight => 8,
            BrickSize::Sixteen => 16,
        }
    }

    /// `log2 n`.
    pub const fn log2(self) -> u32 {
        self.side().trailing_zeros()
    }

    /// `n + 1`, the stored side: the node's `n` cells have `n + 1` vertices per axis.
    pub const fn stored_side(self) -> u32 {
        self.side() + 1
    }

    /// `(n + 1)³`, values stored per brick.
    pub const fn stored_voxels(self) -> usize {
        let s = self.stored_side() as usize;
        s * s * s
    }
}

/// A node without a brick is at least this many of its level's voxels from the surface
/// (more than a cone element's reach, `√3`), and its samples return this distance (with
/// the sign of the side).
pub const EMPTY_DISTANCE: f32 = 2.0;

/// The most levels an octree may have (finest resolution `n 2^(MAX_LEVELS − 1)` ≤ 2¹⁸).
pub const MAX_LEVELS: u32 = 15;

gpu_struct! {
    /// A node of the octree's node pool (2 × `u32`, as GigaVoxels' node tiles).
    pub struct OctreeNode {
        /// Index of the first of the eight children (`0`: none; the root is never a child).
        pub child: u32,
        /// The brick's index, or [`OctreeNode::EMPTY`] / [`OctreeNode::FULL`].
        pub brick: u32,
    }
}

impl OctreeNode {
    /// No brick, outside the surface.
    pub const EMPTY: u32 = u32::MAX;
    /// No brick, inside the surface.
    pub const FULL: u32 = u32::MAX - 1;
}

/// The cube an octree covers (world units).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Domain {
    /// The lowest corner.
    pub origin: Vec3,
    /// The side.
    pub size: f32,
}

/// How an octree is built.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BuildOptions {
    /// The bricks' side `n`.
    pub brick_size: BrickSize,
    /// The number of levels (1 ..= [`MAX_LEVELS`]); the finest resolution is
    /// `n 2^(levels − 1)` voxels across.
    pub levels: u32,
    /// Surface samples per finest voxel along each axis (the sampling step is
    /// `voxel_size / samples_per_voxel`; 1 ..= 16).
    pub samples_per_voxel: u32,
    /// The midpoint rule's sub-cubes per axis for `h̄` and `n̄` (1 ..= 16; see the module
    /// documentation).
    pub quadrature: u32,
    /// What `σh²` measures.
    pub height_variance: HeightVariance,
    /// The build fails rather than create more bricks.
    pub max_bricks: u32,
}

impl Default for BuildOptions {
    fn default() -> Self {
        Self {
            brick_size: BrickSize::Eight,
            levels: 4,
            samples_per_voxel: 2,
            quadrature: 4,
            height_variance: HeightVariance::SurfaceHeights,
            max_bricks: 1 << 20,
        }
    }
}

/// Why an octree could not be built.
#[derive(Clone, Debug, PartialEq)]
pub enum BuildError {
    /// An option is out of range: its name and value.
    Option(&'static str, u32),
    /// The domain's size is not finite and positive, or its origin not finite.
    Domain(Domain),
    /// The source's distance is NaN or infinite at this point (world units).
    Distance(Vec3),
    /// More bricks than `max_bricks` would be needed.
    TooManyBricks(u32),
}

impl core::fmt::Display for BuildError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            BuildError::Option(name, value) => write!(f, "build option `{name}` = {value} is out of range"),
            BuildError::Domain(d) => write!(f, "domain origin {} size {} is not a finite cube", d.origin, d.size),
            BuildError::Distance(p) => write!(f, "the source's distance at {p} is not finite"),
            BuildError::TooManyBricks(max) => write!(f, "the octree needs more than max_bricks = {max} bricks"),
        }
    }
}

impl core::error::Error for BuildError {}

/// A pre-filtered sparse voxel octree with unpacked voxels (see the module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct BrickTree {
    origin: Vec3,
    voxel_size: f32,
    brick_size: BrickSize,
    levels: u32,
    nodes: Vec<OctreeNode>,
    brick_levels: Vec<u32>,
    brick_origins: Vec<UVec3>,
    voxels: Vec<Voxel>,
}

/// A voxel's key at its level: its integer position biased by 1 (dilation looks one voxel
/// outside the domain) and packed in 21 bits per axis.
fn key(v: IVec3) -> u64 {
    let b = (v + 1).as_uvec3();
    u64::from(b.x) | u64::from(b.y) << 21 | u64::from(b.z) << 42
}

impl BrickTree {
    /// Builds the octree of `source` over `domain` (see the module documentation).
    pub fn build<S: SurfaceSource + Sync + ?Sized>(
        source: &S,
        domain: Domain,
        options: BuildOptions,
    ) -> Result<Self, BuildError> {
        check_options(domain, &options)?;
        let n = options.brick_size.side();
        let levels = options.levels;
        let resolution = n << (levels - 1);
        let voxel_size = domain.size / resolution as f32;
        let mut tree = BrickTree {
            origin: domain.origin,
            voxel_size,
            brick_size: options.brick_size,
            levels,
            nodes: alloc::vec![OctreeNode { child: 0, brick: OctreeNode::EMPTY }],
            brick_levels: Vec::new(),
            brick_origins: Vec::new(),
            voxels: Vec::new(),
        };
        tree.place_bricks(source, options.max_bricks)?;
        let samples = tree.surface_samples(source, options.samples_per_voxel);
        let mut level_tables = Vec::with_capacity(levels as usize);
        for level in 0..levels {
            level_tables.push(LevelTable::build(&tree, source, &samples, level, &options));
        }
        let stored = options.brick_size.stored_side() as i32;
        tree.voxels.reserve(tree.brick_levels.len() * options.brick_size.stored_voxels());
        for (b, &level) in tree.brick_levels.iter().enumerate() {
            let table = &level_tables[level as usize];
            let first = (tree.brick_origins[b] >> level).as_ivec3();
            for z in 0..stored {
                for y in 0..stored {
                    for x in 0..stored {
                        tree.voxels.push(table.voxel(first + IVec3::new(x, y, z)));
                    }
                }
            }
        }
        Ok(tree)
    }

    /// Breadth-first: every node's brick or emptiness, children in tiles of eight.
    fn place_bricks<S: SurfaceSource + Sync + ?Sized>(
        &mut self,
        source: &S,
        max_bricks: u32,
    ) -> Result<(), BuildError> {
        let n = self.brick_size.side();
        let mut queue = alloc::collections::VecDeque::new();
        queue.push_back((0_usize, self.levels - 1, UVec3::ZERO));
        while let Some((index, level, min)) = queue.pop_front() {
            let size = n << level;
            let centre = self.world(min.as_vec3() + 0.5 * size as f32);
            let world_distance = source.distance(centre);
            if !world_distance.is_finite() {
                return Err(BuildError::Distance(centre));
            }
            let d = world_distance / self.voxel_size;
            let cell = (1u32 << level) as f32;
            let margin = EMPTY_DISTANCE * cell;
            let near = libm::fabsf(d) <= 0.5 * libm::sqrtf(3.0) * size as f32 + margin
                && (0..n * n * n).any(|k| {
                    let offset = Vec3::new((k % n) as f32, (k / n % n) as f32, (k / (n * n)) as f32);
                    let c = self.world(min.as_vec3() + (offset + 0.5) * cell);
                    let dc = source.distance(c) / self.voxel_size;
                    dc.is_nan() || libm::fabsf(dc) <= 0.5 * libm::sqrtf(3.0) * cell + margin
                });
            if !near {
                self.nodes[index].brick = if d > 0.0 { OctreeNode::EMPTY } else { OctreeNode::FULL };
                continue;
            }
            if self.brick_levels.len() as u32 >= max_bricks {
                return Err(BuildError::TooManyBricks(max_bricks));
            }
            self.nodes[index].brick = self.brick_levels.len() as u32;
            self.brick_levels.push(level);
            self.brick_origins.push(min);
            if level > 0 {
                let child = self.nodes.len();
                self.nodes[index].child = child as u32;
                let half = size / 2;
                for octant in 0..8_u32 {
                    self.nodes.push(OctreeNode { child: 0, brick: OctreeNode::EMPTY });
                    let offset = UVec3::new(octant & 1, (octant >> 1) & 1, octant >> 2) * half;
                    queue.push_back((child + octant as usize, level - 1, min + offset));
                }
            }
        }
        Ok(())
    }

    /// The surface samples of every finest brick's cell, in finest-voxel units.
    fn surface_samples<S: SurfaceSource + Sync + ?Sized>(&self, source: &S, per_voxel: u32) -> Vec<SurfaceSample> {
        let n = self.brick_size.side();
        let spacing = self.voxel_size / per_voxel as f32;
        let inverse_area = 1.0 / (self.voxel_size * self.voxel_size);
        let finest: Vec<UVec3> =
            self.brick_levels.iter().zip(&self.brick_origins).filter(|(l, _)| **l == 0).map(|(_, o)| *o).collect();
        let per_brick = map_in_parallel(&finest, |&min, world| {
            let cell = Cell { min: self.world(min.as_vec3()), max: self.world((min + n).as_vec3()) };
            world.clear();
            source.surface_samples(cell, spacing, world);
            let mut samples = Vec::new();
            for s in world.iter() {
                let position = (s.position - self.origin) / self.voxel_size;
                let local = position - min.as_vec3();
                if local.cmpge(Vec3::ZERO).all() && local.cmplt(Vec3::splat(n as f32)).all() && s.area > 0.0 {
                    samples.push(SurfaceSample { position, area: s.area * inverse_area, ..*s });
                }
            }
            samples
        });
        per_brick.concat()
    }

    /// World position of a point in finest-voxel units.
    pub fn world(&self, p: Vec3) -> Vec3 {
        self.origin + p * self.voxel_size
    }

    /// The lowest corner of the domain (world units).
    pub fn origin(&self) -> Vec3 {
        self.origin
    }

    /// The finest voxel's side (world units).
    pub fn voxel_size(&self) -> f32 {
        self.voxel_size
    }

    /// The bricks' side.
    pub fn brick_size(&self) -> BrickSize {
        self.brick_size
    }

    /// The number of levels.
    pub fn levels(&self) -> u32 {
        self.levels
    }

    /// The finest resolution, `n 2^(levels − 1)` voxels across.
    pub fn resolution(&self) -> u32 {
        self.brick_size.side() << (self.levels - 1)
    }

    /// The node pool (the root first).
    pub fn nodes(&self) -> &[OctreeNode] {
        &self.nodes
    }

    /// The number of bricks.
    pub fn brick_count(&self) -> usize {
        self.brick_levels.len()
    }

    /// Each brick's level.
    pub fn brick_levels(&self) -> &[u32] {
        &self.brick_levels
    }

    /// Each brick's node's lowest corner (finest-voxel units).
    pub fn brick_origins(&self) -> &[UVec3] {
        &self.brick_origins
    }

    /// Brick `brick`'s `(n + 1)³` voxels (finest-voxel units), x fastest; stored index
    /// `(x, y, z)` is the level-`L` voxel (vertex) `origin / S_L + (x, y, z)`, at
    /// `(origin / S_L + (x, y, z)) S_L`.
    pub fn brick_voxels(&self, brick: usize) -> &[Voxel] {
        let count = self.brick_size.stored_voxels();
        &self.voxels[brick * count..(brick + 1) * count]
    }
}

fn check_options(domain: Domain, options: &BuildOptions) -> Result<(), BuildError> {
    if !domain.size.is_finite() || domain.size <= 0.0 || !domain.origin.is_finite() {
        return Err(BuildError::Domain(domain));
    }
    let checks = [
        ("levels", options.levels, 1..=MAX_LEVELS),
        ("samples_per_voxel", options.samples_per_voxel, 1..=16),
        ("quadrature", options.quadrature, 1..=16),
        ("max_bricks", options.max_bricks, 1..=u32::MAX - 2),
    ];
    for (name, value, range) in checks {
        if !range.contains(&value) {
            return Err(BuildError::Option(name, value));
        }
    }
    Ok(())
}

/// One level's voxels: every voxel some brick stores (shared faces once), computed once.
struct LevelTable {
    keys: Vec<u64>,
    voxels: Vec<Voxel>,
}

/// The surface samples of one level, grouped by voxel.
struct SampleBins<'a> {
    samples: &'a [SurfaceSample],
    order: Vec<u32>,
    /// `(key, first, end)` into `order`, sorted by key.
    ranges: Vec<(u64, u32, u32)>,
}

impl<'a> SampleBins<'a> {
    fn new(samples: &'a [SurfaceSample], level: u32) -> Self {
        let scale = 1.0 / (1u32 << level) as f32;
        // A vertex's footprint is the cube of side S_L centred on it.
        let voxel_of = |s: &SurfaceSample| key((s.position * scale + 0.5).floor().as_ivec3());
        let mut keyed: Vec<(u64, u32)> = samples.iter().enumerate().map(|(i, s)| (voxel_of(s), i as u32)).collect();
        keyed.sort_unstable();
        let mut ranges: Vec<(u64, u32, u32)> = Vec::new();
        for (i, &(k, _)) in keyed.iter().enumerate() {
            match ranges.last_mut() {
                Some(last) if last.0 == k => last.2 = i as u32 + 1,
                _ => ranges.push((k, i as u32, i as u32 + 1)),
            }
        }
        Self { samples, order: keyed.into_iter().map(|(_, i)| i).collect(), ranges }
    }

    fn samples_in(&self, k: u64, out: &mut Vec<SurfaceSample>) -> bool {
        out.clear();
        let Ok(r) = self.ranges.binary_search_by_key(&k, |r| r.0) else { return false };
        let (_, first, end) = self.ranges[r];
        out.extend(self.order[first as usize..end as usize].iter().map(|&i| self.samples[i as usize]));
        true
    }
}

/// Everything one voxel's computation needs.
struct VoxelContext<'a, S: ?Sized> {
    tree: &'a BrickTree,
    source: &'a S,
    bins: Option<SampleBins<'a>>,
    level: u32,
    options: &'a BuildOptions,
}

impl<S: SurfaceSource + Sync + ?Sized> VoxelContext<'_, S> {
    fn scale(&self) -> f32 {
        (1u32 << self.level) as f32
    }

    fn centre(&self, v: IVec3) -> Vec3 {
        v.as_vec3() * self.scale()
    }

    /// `h̄`, `n̄` and the volume variance of the distance by the midpoint rule.
    fn box_mean(&self, v: IVec3) -> (f32, Vec3, f32) {
        let q = (1u32 << self.level.min(4)).min(self.options.quadrature);
        let step = self.scale() / q as f32;
        let min = (v.as_vec3() - 0.5) * self.scale();
        let (mut d_sum, mut d2_sum, mut g_sum) = (0.0_f64, 0.0_f64, glam::DVec3::ZERO);
        for k in 0..q {
            for j in 0..q {
                for i in 0..q {
                    let p = self.tree.world(min + (Vec3::new(i as f32, j as f32, k as f32) + 0.5) * step);
                    let d = f64::from(self.source.distance(p) / self.tree.voxel_size);
                    d_sum += d;
                    d2_sum += d * d;
                    g_sum += self.source.gradient(p).as_dvec3();
                }
            }
        }
        let count = f64::from(q * q * q);
        let mean = d_sum / count;
        ((mean) as f32, (g_sum / count).as_vec3(), (d2_sum / count - mean * mean).max(0.0) as f32)
    }

    /// The statistics of voxel `v` from its own samples.
    fn own_statistics(
        &self,
        v: IVec3,
        distance: f32,
        normal: Vec3,
        scratch: &mut Vec<SurfaceSample>,
    ) -> Option<SurfaceStatistics> {
        let bins = self.bins.as_ref()?;
        if !bins.samples_in(key(v), scratch) {
            return None;
        }
        surface_statistics(scratch, self.centre(v), distance, normal)
    }

    fn voxel(&self, v: IVec3, scratch: &mut Vec<SurfaceSample>) -> Voxel {
        let (distance, normal, volume_variance) = self.box_mean(v);
        let centre = self.centre(v);
        // The closest surface point by one projection step along the filtered gradient.
        let g2 = normal.length_squared();
        let projected = if g2 > 0.0 { centre - normal * (distance / g2) } else { centre };
        let mut voxel = Voxel { distance, normal, ..Voxel::default() };
        if self.level == 0 {
            voxel.attribute = self.source.attribute(self.tree.world(projected));
            return voxel;
        }
        let stats = self.own_statistics(v, distance, normal, scratch).or_else(|| self.dilated(projected, scratch));
        match stats {
            Some(stats) => {
                voxel.distance_variance = stats.height_variance;
                voxel.slope_variance = stats.slope_variance;
                voxel.attribute = stats.attribute;
                voxel.correlation = stats.correlation;
            }
            None => voxel.attribute = self.source.attribute(self.tree.world(projected)),
        }
        if self.options.height_variance == HeightVariance::DistanceVolume {
            voxel.distance_variance = volume_variance;
        }
        voxel
    }

    /// Dilation: the statistics of the voxel with samples nearest to `projected` (the
    /// voxel's closest surface point), searched in growing shells of up to 2 voxels.
    fn dilated(&self, projected: Vec3, scratch: &mut Vec<SurfaceSample>) -> Option<SurfaceStatistics> {
        let home = (projected / self.scale() + 0.5).floor().as_ivec3();
        for radius in 0..=2 {
            let mut best: Option<(f32, IVec3)> = None;
            for z in -radius..=radius {
                for y in -radius..=radius {
                    for x in -radius..=radius {
                        let offset = IVec3::new(x, y, z);
                        if offset.abs().max_element() != radius {
                            continue;
                        }
                        let v = home + offset;
                        let has =
                            self.bins.as_ref().is_some_and(|b| b.ranges.binary_search_by_key(&key(v), |r| r.0).is_ok());
                        if has {
                            let d = (self.centre(v) - projected).length_squared();
                            if best.is_none_or(|(bd, _)| d < bd) {
                                best = Some((d, v));
                            }
                        }
                    }
                }
            }
            if let Some((_, v)) = best {
                let (distance, normal, _) = self.box_mean(v);
                return self.own_statistics(v, distance, normal, scratch);
            }
        }
        None
    }
}

/// `items.map(f)`, each call with a scratch buffer; with `std`, on every available core
/// (each voxel is a function of its position, so the result does not depend on the
/// threads).
fn map_in_parallel<T: Sync, R: Send>(items: &[T], f: impl Fn(&T, &mut Vec<SurfaceSample>) -> R + Sync) -> Vec<R> {
    #[cfg(feature = "std")]
    {
        let threads =
            std::thread::available_parallelism().map_or(1, core::num::NonZero::get).min(items.len() / 512 + 1);
        if threads > 1 {
            let chunk = items.len().div_ceil(threads);
            return std::thread::scope(|scope| {
                let workers: Vec<_> = items
                    .chunks(chunk)
                    .map(|part| {
                        let f = &f;
                        scope.spawn(move || {
                            let mut scratch = Vec::new();
                            part.iter().map(|x| f(x, &mut scratch)).collect::<Vec<R>>()
                        })
                    })
                    .collect();
                let mut out = Vec::with_capacity(items.len());
                for worker in workers {
                    out.extend(worker.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic)));
                }
                out
            });
        }
    }
    let mut scratch = Vec::new();
    items.iter().map(|x| f(x, &mut scratch)).collect()
}

impl LevelTable {
    fn build<S: SurfaceSource + Sync + ?Sized>(
        tree: &BrickTree,
        source: &S,
        samples: &[SurfaceSample],
        level: u32,
        options: &BuildOptions,
    ) -> Self {
        let stored = tree.brick_size.stored_side() as i32;
        let mut positions: Vec<IVec3> = Vec::new();
        for (b, &l) in tree.brick_levels.iter().enumerate() {
            if l != level {
                continue;
            }
            let first = (tree.brick_origins[b] >> level).as_ivec3();
            for z in 0..stored {
                for y in 0..stored {
                    for x in 0..stored {
                        positions.push(first + IVec3::new(x, y, z));
                    }
                }
            }
        }
        positions.sort_unstable_by_key(|&v| key(v));
        positions.dedup();
        let context =
            VoxelContext { tree, source, bins: (level > 0).then(|| SampleBins::new(samples, level)), level, options };
        let voxels = map_in_parallel(&positions, |&v, scratch| context.voxel(v, scratch));
        Self { keys: positions.iter().map(|&v| key(v)).collect(), voxels }
    }

    fn voxel(&self, v: IVec3) -> Voxel {
        // Every stored voxel was collected when the table was built.
        self.keys.binary_search(&key(v)).map_or(Voxel::default(), |i| self.voxels[i])
    }
}
