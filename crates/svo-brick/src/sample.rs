//! Sampling a packed octree (§5.2–5.3): trilinear within a level, linear across levels
//! (quadrilinear), decoded before interpolation; and the nearest voxel as a baseline
//! (Fig. 10a).
//!
//! # The same bits on the CPU and in WGSL
//!
//! Hardware filtering is low-precision and `f32` textures are not filterable without a
//! feature, so interpolation is manual, from storage buffers, and written so that any
//! conforming WGSL implementation computes the same bits as this code:
//!
//! - The query point goes to finest-voxel units once, `q = (p − origin) × (1 / voxel_size)`
//!   (a subtraction and a product, nothing after); every later product is by a power of
//!   two or is exact.
//! - Interpolation fractions are quantised to `2⁻¹¹` (`t = ⌊f 2048⌋ / 2048`: at most 11
//!   significant bits), the positional resolution 1/2048 of a voxel.
//! - Every interpolation is [`lerp`]: `d = b − a` is split into its top 12 significant bits
//!   `d_hi` (a bit mask) and the exact rest `d_lo = d − d_hi`; then
//!   `(a + d_hi t) + d_lo t`. Both products are exact (≤ 23 bits), so a compiler that fuses
//!   a multiply and an add into an `fma` (which WGSL allows) cannot change the result.
//! - Decoding is exact ([`crate::layout`]); the scales that are not powers of two, and the
//!   renormalisation of `n̄` (`sqrt` and division, not correctly rounded in WGSL), come after
//!   the raw sample, which is what the differential test compares bit for bit.
//!
//! # Empty space
//!
//! Where the descent to level `L` ends at a node without a brick, level `L` contributes the
//! voxel `h̄ = ±2 S_L'` ([`EMPTY_DISTANCE`](crate::EMPTY_DISTANCE); `L'` the node's level,
//! `+` outside, `−` inside: a lower bound of the distance there, by the brick placement
//! rule), with every other field zero.

use alloc::vec::Vec;

use glam::{UVec3, UVec4, Vec3, Vec4};
use gpu_layout::gpu_struct;

use crate::descriptor::{ATTRIBUTE_CHANNELS, Voxel};
use crate::layout::{RawVoxel, VoxelLayout, level_inverse_scale, level_scale};
use crate::octree::{BrickTree, EMPTY_DISTANCE, OctreeNode};

/// Interpolation fractions are multiples of `1 / FRACTION_STEPS`.
pub const FRACTION_STEPS: f32 = 2048.0;

/// The mask that keeps the sign, the exponent and the top 11 explicit mantissa bits.
pub const SPLIT_MASK: u32 = 0xffff_f000;

gpu_struct! {
    /// Describes a [`PackedTree`] to a shader.
    pub struct OctreeUniforms {
        /// `(origin, 1 / voxel_size)`: the domain's lowest corner (world) and the inverse of
        /// the finest voxel's side.
        pub origin_inverse_size: Vec4,
        /// `(voxel_size, 0, 0, 0)`.
        pub voxel_size: Vec4,
        /// `(levels, log2 n, layout index, words per voxel)`.
        pub shape: UVec4,
        /// `(node count, brick count, finest resolution, 0)`.
        pub counts: UVec4,
        /// `(words per finest-level voxel, the first finest-level brick, words per brick
        /// binding, 0)`: bricks before the first finest one take `shape.w` words per voxel,
        /// the rest the finest level's (the build places bricks breadth-first, so the finest
        /// level's come last); the pool's word `k` lives in binding `k / words per binding`
        /// (see [`PackedTree::brick_bindings`]).
        pub pools: UVec4,
    }
}

/// The brick pool is split over at most this many storage bindings.
pub const MAX_BRICK_BINDINGS: usize = 4;

/// Why a tree does not fit the GPU's bindings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PoolError {
    /// The node pool alone exceeds one binding: its bytes and the limit.
    Nodes(u64, u64),
    /// The brick pool needs more than [`MAX_BRICK_BINDINGS`] bindings: its bytes and the
    /// limit per binding.
    Bricks(u64, u64),
}

impl core::fmt::Display for PoolError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            PoolError::Nodes(bytes, limit) => {
                write!(f, "the node pool's {bytes} bytes exceed the storage binding limit of {limit} bytes")
            }
            PoolError::Bricks(bytes, limit) => write!(
                f,
                "the brick pool's {bytes} bytes need more than {MAX_BRICK_BINDINGS} storage bindings of {limit} bytes"
            ),
        }
    }
}

impl core::error::Error for PoolError {}

/// A [`BrickTree`] in a GPU layout: the node pool and the brick pool as flat `u32`
/// buffers, sampled exactly as the WGSL twin samples them.
#[derive(Clone, Debug, PartialEq)]
pub struct PackedTree {
    layout: VoxelLayout,
    uniforms: OctreeUniforms,
    nodes: Vec<OctreeNode>,
    words: Vec<u32>,
}

/// A node without a brick ([`PackedTree::empty_region`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EmptyRegion {
    /// The node's lowest corner (world).
    pub min: Vec3,
    /// Its highest corner.
    pub max: Vec3,
    /// Its level: samples at this level and finer are constant inside.
    pub level: u32,
    /// Whether it is inside the surface (`FULL`).
    pub inside: bool,
}

/// What [`PackedTree::sample_raw`] returns: the blended raw voxel (finest-voxel units,
/// codes for the attributes, an unnormalised `n̄`).
pub type RawSample = RawVoxel;

/// `a + (b − a) t` for `t` a multiple of 2⁻¹¹ in `[0, 1)`, immune to `fma` contraction (see
/// the module documentation).
#[inline]
pub fn lerp(a: f32, b: f32, t: f32) -> f32 {
    let d = b - a;
    let hi = f32::from_bits(d.to_bits() & SPLIT_MASK);
    let lo = d - hi;
    (a + hi * t) + lo * t
}

fn lerp3(a: Vec3, b: Vec3, t: f32) -> Vec3 {
    Vec3::new(lerp(a.x, b.x, t), lerp(a.y, b.y, t), lerp(a.z, b.z, t))
}

fn lerp_channels(a: [f32; ATTRIBUTE_CHANNELS], b: [f32; ATTRIBUTE_CHANNELS], t: f32) -> [f32; ATTRIBUTE_CHANNELS] {
    core::array::from_fn(|c| lerp(a[c], b[c], t))
}

/// [`lerp`] of every field.
pub fn lerp_raw(a: &RawVoxel, b: &RawVoxel, t: f32) -> RawVoxel {
    RawVoxel {
        distance: lerp(a.distance, b.distance, t),
        distance_variance: lerp(a.distance_variance, b.distance_variance, t),
        normal: lerp3(a.normal, b.normal, t),
        slope_variance: lerp(a.slope_variance, b.slope_variance, t),
        attribute: lerp_channels(a.attribute, b.attribute, t),
        correlation: lerp_channels(a.correlation, b.correlation, t),
    }
}

/// `(⌊x⌋, t)` with `t = ⌊(x − ⌊x⌋) 2048⌋ / 2048`.
fn split_fraction(x: f32) -> (f32, f32) {
    let i = libm::floorf(x);
    (i, libm::floorf((x - i) * FRACTION_STEPS) * (1.0 / FRACTION_STEPS))
}

/// Where the descent to a level ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Found {
    /// The brick of the node at the requested level, and the node's origin.
    Brick(u32, UVec3),
    /// A node without a brick at this level: its level, `EMPTY` or `FULL`, and its origin.
    Empty(u32, u32, UVec3),
}

impl PackedTree {
    /// Packs `tree` in `layout` for bindings of at most `max_binding_bytes` each (the
    /// adapter's `min(max_storage_buffer_binding_size, max_buffer_size)`): the brick pool
    /// is split into up to [`MAX_BRICK_BINDINGS`] bindings of whole bricks (a multiple of the
    /// largest brick's words, so that no brick straddles two bindings: the finest level's
    /// bricks are half as large in `Compact16Fine8`).
    pub fn with_binding_limit(
        tree: &BrickTree,
        layout: VoxelLayout,
        max_binding_bytes: u64,
    ) -> Result<Self, PoolError> {
        let mut packed = Self::new(tree, layout);
        let node_bytes = 8 * packed.nodes.len() as u64;
        if node_bytes > max_binding_bytes {
            return Err(PoolError::Nodes(node_bytes, max_binding_bytes));
        }
        let brick_words = (tree.brick_size().stored_voxels() * layout.words()) as u64;
        let per_binding =
            (max_binding_bytes / 4 / brick_words * brick_words).min(u64::from(u32::MAX) / brick_words * brick_words);
        let words = packed.words.len() as u64;
        if per_binding == 0 || words.div_ceil(per_binding) > MAX_BRICK_BINDINGS as u64 {
            return Err(PoolError::Bricks(4 * words, max_binding_bytes));
        }
        packed.uniforms.pools.z = per_binding as u32;
        Ok(packed)
    }

    /// Packs `tree` in `layout`, the brick pool in a single binding.
    pub fn new(tree: &BrickTree, layout: VoxelLayout) -> Self {
        let stored = tree.brick_size().stored_voxels();
        let mut words = Vec::with_capacity(tree.brick_count() * stored * layout.words());
        let mut first_fine = tree.brick_count() as u32;
        for (b, &level) in tree.brick_levels().iter().enumerate() {
            if level == 0 {
                first_fine = first_fine.min(b as u32);
            }
            let w = layout.words_at(level);
            for voxel in tree.brick_voxels(b) {
                words.extend_from_slice(&layout.encode(voxel, level)[..w]);
            }
        }
        let origin = tree.origin();
        let uniforms = OctreeUniforms {
            origin_inverse_size: origin.extend(1.0 / tree.voxel_size()),
            voxel_size: Vec4::new(tree.voxel_size(), 0.0, 0.0, 0.0),
            shape: UVec4::new(tree.levels(), tree.brick_size().log2(), layout.index(), layout.words() as u32),
            counts: UVec4::new(tree.nodes().len() as u32, tree.brick_count() as u32, tree.resolution(), 0),
            pools: UVec4::new(layout.words_at(0) as u32, first_fine, u32::MAX, 0),
        };
        Self { layout, uniforms, nodes: tree.nodes().to_vec(), words }
    }

    /// The first word of brick `brick` in the pool.
    fn brick_offset(&self, brick: u32) -> usize {
        let stored = ((1usize << self.brick_log2()) + 1).pow(3);
        let (coarse, fine) = (self.uniforms.shape.w as usize, self.uniforms.pools.x as usize);
        let first_fine = self.uniforms.pools.y;
        if brick < first_fine {
            brick as usize * stored * coarse
        } else {
            first_fine as usize * stored * coarse + (brick - first_fine) as usize * stored * fine
        }
    }

    /// The layout.
    pub fn layout(&self) -> VoxelLayout {
        self.layout
    }

    /// The uniforms of the WGSL twin.
    pub fn uniforms(&self) -> OctreeUniforms {
        self.uniforms
    }

    /// The node pool (upload as `array<OctreeNode>`, or as `u32` pairs).
    pub fn nodes(&self) -> &[OctreeNode] {
        &self.nodes
    }

    /// The brick pool: brick `b`'s `(n + 1)³` voxels, x fastest, each
    /// [`VoxelLayout::words_at`] its level words.
    pub fn words(&self) -> &[u32] {
        &self.words
    }

    /// The brick pool as the WGSL twin binds it: [`MAX_BRICK_BINDINGS`] slices of whole
    /// bricks for bindings 4, 5, 6, 7 (the unused ones a single zero word, since a binding
    /// cannot be empty).
    pub fn brick_bindings(&self) -> [&[u32]; MAX_BRICK_BINDINGS] {
        const UNUSED: &[u32] = &[0];
        let chunk = (self.uniforms.pools.z as usize).max(1);
        let mut chunks = self.words.chunks(chunk);
        core::array::from_fn(|_| chunks.next().filter(|c| !c.is_empty()).unwrap_or(UNUSED))
    }

    /// Bytes of the node and brick pools.
    pub fn bytes(&self) -> usize {
        8 * self.nodes.len() + 4 * self.words.len()
    }

    fn levels(&self) -> u32 {
        self.uniforms.shape.x
    }

    fn brick_log2(&self) -> u32 {
        self.uniforms.shape.y
    }

    /// `p` (world) in finest-voxel units.
    pub fn tree_position(&self, p: Vec3) -> Vec3 {
        (p - self.uniforms.origin_inverse_size.truncate()) * self.uniforms.origin_inverse_size.w
    }

    /// The finest voxel holding `q` (finest-voxel units), `None` outside the domain.
    fn cell(&self, q: Vec3) -> Option<UVec3> {
        let resolution = self.uniforms.counts.z as f32;
        (q.cmpge(Vec3::ZERO).all() && q.cmplt(Vec3::splat(resolution)).all()).then(|| q.floor().as_uvec3())
    }

    /// Descends from the root towards the node of `level` holding the finest voxel `cell`.
    fn find(&self, cell: UVec3, level: u32) -> Found {
        let mut node_level = self.levels() - 1;
        let mut index = 0_usize;
        let mut origin = UVec3::ZERO;
        while node_level > level {
            let node = self.nodes[index];
            if node.child == 0 {
                return Found::Empty(node_level, node.brick, origin);
            }
            let half = 1u32 << (self.brick_log2() + node_level - 1);
            let bits = (cell - origin).cmpge(UVec3::splat(half));
            let octant = u32::from(bits.x) | u32::from(bits.y) << 1 | u32::from(bits.z) << 2;
            origin += UVec3::new(u32::from(bits.x), u32::from(bits.y), u32::from(bits.z)) * half;
            index = (node.child + octant) as usize;
            node_level -= 1;
        }
        let brick = self.nodes[index].brick;
        if brick >= OctreeNode::FULL { Found::Empty(node_level, brick, origin) } else { Found::Brick(brick, origin) }
    }

    /// Decodes stored voxel `index` of brick `brick` (of level `level`). (The WGSL twin reads
    /// its words from binding `word / words_per_binding`; here the pool is one buffer.)
    fn stored_voxel(&self, brick: u32, index: UVec3, level: u32) -> RawVoxel {
        let side = (1u32 << self.brick_log2()) + 1;
        let w = self.layout.words_at(level);
        let voxel = (index.z * side + index.y) * side + index.x;
        let first = self.brick_offset(brick) + voxel as usize * w;
        self.layout.decode_raw(&self.words[first..first + w], level)
    }

    fn empty_voxel(level: u32, brick: u32) -> RawVoxel {
        let bound = EMPTY_DISTANCE * level_scale(level);
        RawVoxel { distance: if brick == OctreeNode::FULL { -bound } else { bound }, ..RawVoxel::default() }
    }

    /// Trilinear interpolation at `level` of the point `q` (finest-voxel units) in the
    /// finest voxel `cell`.
    fn trilinear(&self, q: Vec3, cell: UVec3, level: u32) -> RawVoxel {
        let (brick, origin) = match self.find(cell, level) {
            Found::Brick(brick, origin) => (brick, origin),
            Found::Empty(level, brick, _) => return Self::empty_voxel(level, brick),
        };
        self.trilinear_in_brick(q, brick, origin, level)
    }

    /// Trilinear interpolation at `level` in brick `brick` whose node's origin is `origin`
    /// (`q` in the node).
    fn trilinear_in_brick(&self, q: Vec3, brick: u32, origin: UVec3, level: u32) -> RawVoxel {
        let inverse = level_inverse_scale(level);
        let local = q * inverse - (origin >> level).as_vec3();
        let n = (1u32 << self.brick_log2()) as f32;
        let (mut i0, mut t) = ([0_u32; 3], [0.0_f32; 3]);
        for axis in 0..3 {
            let (i, f) = split_fraction(local[axis]);
            i0[axis] = i.clamp(0.0, n - 1.0) as u32;
            t[axis] = f;
        }
        let base = UVec3::from_array(i0);
        let corner = |dx: u32, dy: u32, dz: u32| self.stored_voxel(brick, base + UVec3::new(dx, dy, dz), level);
        let x00 = lerp_raw(&corner(0, 0, 0), &corner(1, 0, 0), t[0]);
        let x10 = lerp_raw(&corner(0, 1, 0), &corner(1, 1, 0), t[0]);
        let x01 = lerp_raw(&corner(0, 0, 1), &corner(1, 0, 1), t[0]);
        let x11 = lerp_raw(&corner(0, 1, 1), &corner(1, 1, 1), t[0]);
        let y0 = lerp_raw(&x00, &x10, t[1]);
        let y1 = lerp_raw(&x01, &x11, t[1]);
        lerp_raw(&y0, &y1, t[2])
    }

    /// Trilinear interpolation at `level` with the moment correction.
    ///
    /// Trilinear weights make the sample's footprint the mixture of the eight corner voxels'
    /// footprints (weights `w_k`). By the law of total variance, the variance of that
    /// mixture's micro-heights about the interpolated plane `(h̄(q), ∇h̄(q))` is the
    /// interpolated variance `Σ w_k σ_k²` (all plain interpolation gives) plus what it
    /// misses: the spread of the corners' own planes about the interpolated one,
    ///
    /// - the offsets `Σ w_k (h̄_k − h̄(q) − ∇h̄ · (c_k − q))² / |∇h̄|²` (zero for a linear
    ///   field: a flat surface adds nothing),
    /// - the tilts `Σ w_k |n̂_k − n̂|² S_L² / 12` (a plane tilted by `δ` over a box of side
    ///   `S_L` has height variance `δ² S_L² / 12`),
    ///
    /// and `σn² += ½ Σ w_k |n̂_k − n̂|²` for the slopes. `∇h̄` is the gradient of the
    /// trilinear interpolant (`|n̄|` is not stored). CPU only; measured by
    /// [`moment_correction_error`](crate::moment_correction_error).
    fn trilinear_moment_corrected(&self, q: Vec3, cell: UVec3, level: u32) -> RawVoxel {
        let (brick, origin) = match self.find(cell, level) {
            Found::Brick(brick, origin) => (brick, origin),
            Found::Empty(level, brick, _) => return Self::empty_voxel(level, brick),
        };
        let plain = self.trilinear_in_brick(q, brick, origin, level);
        let corners = self.corners(q, brick, origin, level);
        let scale = level_scale(level);
        let (_, t) = self.stencil(q, origin, level);
        let mut gradient = Vec3::ZERO;
        for axis in 0..3 {
            let bit = 1 << axis;
            for k in (0..8).filter(|k| k & bit == 0) {
                // The edge's weight: the product of the other two axes' weights.
                let w: f32 =
                    (0..3).filter(|&a| a != axis).map(|a| if k >> a & 1 == 1 { t[a] } else { 1.0 - t[a] }).product();
                gradient[axis] += w * (corners[k | bit].1.distance - corners[k].1.distance) / scale;
            }
        }
        let slope = gradient.length();
        if slope.is_nan() || slope <= 0.0 {
            return plain;
        }
        let n_hat = gradient / slope;
        let (mut offsets, mut tilts) = (0.0_f32, 0.0_f32);
        for &(w, voxel, centre) in &corners {
            let linear = plain.distance + gradient.dot(centre - q);
            let offset = (voxel.distance - linear) / slope;
            offsets += w * offset * offset;
            tilts += w * (voxel.normal.normalize_or_zero() - n_hat).length_squared();
        }
        RawVoxel {
            distance_variance: plain.distance_variance + offsets + tilts * scale * scale / 12.0,
            slope_variance: plain.slope_variance + 0.5 * tilts,
            ..plain
        }
    }

    /// The eight corners of the trilinear stencil at `q`: `(w_k, voxel, centre)` (centres in
    /// finest-voxel units).
    fn corners(&self, q: Vec3, brick: u32, origin: UVec3, level: u32) -> [(f32, RawVoxel, Vec3); 8] {
        let (base, t) = self.stencil(q, origin, level);
        let scale = level_scale(level);
        core::array::from_fn(|k| {
            let offset = UVec3::new(k as u32 & 1, (k as u32 >> 1) & 1, k as u32 >> 2);
            let weight = (0..3).map(|a| if offset[a] == 1 { t[a] } else { 1.0 - t[a] }).product::<f32>();
            // Stored index i is the level-L voxel origin / S_L + i, at that lattice point.
            let centre = ((origin >> level).as_vec3() + (base + offset).as_vec3()) * scale;
            (weight, self.stored_voxel(brick, base + offset, level), centre)
        })
    }

    /// The stencil's first stored index and fractions at `q`.
    fn stencil(&self, q: Vec3, origin: UVec3, level: u32) -> (UVec3, Vec3) {
        let local = q * level_inverse_scale(level) - (origin >> level).as_vec3();
        let n = (1u32 << self.brick_log2()) as f32;
        let (mut base, mut t) = (UVec3::ZERO, Vec3::ZERO);
        for axis in 0..3 {
            let (i, f) = split_fraction(local[axis]);
            base[axis] = i.clamp(0.0, n - 1.0) as u32;
            t[axis] = f;
        }
        (base, t)
    }

    /// The two levels a quadrilinear sample at `lod` blends and the quantised weight of the
    /// coarser (`lod` clamped to `[0, levels − 1]`, NaN → 0; at the top level, the same
    /// level twice with weight 0).
    fn blended_levels(&self, lod: f32) -> (u32, u32, f32) {
        let top = (self.levels() - 1) as f32;
        let lod = if lod.is_nan() { 0.0 } else { lod.clamp(0.0, top) };
        let (level, t) = split_fraction(lod);
        let fine = level as u32;
        let coarse = (fine + 1).min(self.levels() - 1);
        (fine, coarse, if coarse == fine { 0.0 } else { t })
    }

    /// The quadrilinear sample with the moment-corrected variances (see
    /// `trilinear_moment_corrected`), world units; CPU only.
    pub fn sample_moment_corrected(&self, p: Vec3, lod: f32) -> Option<Voxel> {
        let q = self.tree_position(p);
        let cell = self.cell(q)?;
        let (fine, coarse, t) = self.blended_levels(lod);
        let a = self.trilinear_moment_corrected(q, cell, fine);
        let b = self.trilinear_moment_corrected(q, cell, coarse);
        Some(self.finish(lerp_raw(&a, &b, t)))
    }

    /// The quadrilinear raw sample at `p` (world) and level of detail `lod` (in levels,
    /// `log2(w / voxel_size)` for a cone of width `w`; clamped to `[0, levels − 1]`, NaN →
    /// 0): trilinear at `⌊lod⌋` and `⌊lod⌋ + 1`, blended by the quantised fraction.
    /// `None` outside the domain.
    pub fn sample_raw(&self, p: Vec3, lod: f32) -> Option<RawSample> {
        let q = self.tree_position(p);
        let cell = self.cell(q)?;
        let (fine, coarse, t) = self.blended_levels(lod);
        let a = self.trilinear(q, cell, fine);
        let b = self.trilinear(q, cell, coarse);
        Some(lerp_raw(&a, &b, t))
    }

    /// The quadrilinear sample at `p` and `lod` (see [`sample_raw`](Self::sample_raw)) in
    /// world units, `n̄` normalised.
    pub fn sample(&self, p: Vec3, lod: f32) -> Option<Voxel> {
        self.sample_raw(p, lod).map(|raw| self.finish(raw))
    }

    /// The nearest voxel of the nearest level (`round(lod)`), the baseline of Fig. 10a,
    /// in world units.
    pub fn sample_nearest(&self, p: Vec3, lod: f32) -> Option<Voxel> {
        self.sample_nearest_raw(p, lod).map(|raw| self.finish(raw))
    }

    /// [`sample_nearest`](Self::sample_nearest) before [`finish`](Self::finish).
    pub fn sample_nearest_raw(&self, p: Vec3, lod: f32) -> Option<RawSample> {
        let q = self.tree_position(p);
        let cell = self.cell(q)?;
        let top = (self.levels() - 1) as f32;
        let level = libm::floorf(if lod.is_nan() { 0.0 } else { lod.clamp(0.0, top) } + 0.5) as u32;
        let raw = match self.find(cell, level) {
            Found::Empty(level, brick, _) => Self::empty_voxel(level, brick),
            Found::Brick(brick, origin) => {
                // The nearest lattice point: ⌊q / S_L + ½⌋ (an exact product, then one add).
                let nearest = (q * level_inverse_scale(level) + 0.5).floor().as_uvec3();
                self.stored_voxel(brick, nearest - (origin >> level), level)
            }
        };
        Some(raw)
    }

    /// The node without a brick that the descent towards `level` ends in at `p` (world), if
    /// any: the cube where every sample at levels `≤ level` is that node's constant voxel.
    /// A tracer skips it to its exit (`None`: a brick, or outside the domain).
    pub fn empty_region(&self, p: Vec3, level: u32) -> Option<EmptyRegion> {
        let cell = self.cell(self.tree_position(p))?;
        let Found::Empty(node_level, flag, origin) = self.find(cell, level.min(self.levels() - 1)) else { return None };
        let size = self.uniforms.voxel_size.x;
        let side = ((1u32 << self.brick_log2()) << node_level) as f32 * size;
        let min = self.uniforms.origin_inverse_size.truncate() + origin.as_vec3() * size;
        Some(EmptyRegion { min, max: min + side, level: node_level, inside: flag == OctreeNode::FULL })
    }

    /// A raw sample in world units, `n̄` normalised.
    pub fn finish(&self, raw: RawSample) -> Voxel {
        raw.finish().scaled(self.uniforms.voxel_size.x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lerp_is_exact_where_it_can_be_and_never_leaves_its_ends() {
        assert_eq!(lerp(1.0, 3.0, 0.5), 2.0);
        assert_eq!(lerp(-7.25, 9.5, 0.0), -7.25);
        let mut state = 1_u32;
        for _ in 0..100_000 {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            let a = (state >> 8) as f32 * 1e-3 - 5000.0;
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            let b = (state >> 8) as f32 * 1e-4;
            let t = (state & 2047) as f32 / FRACTION_STEPS;
            let r = lerp(a, b, t);
            assert!(r >= a.min(b) && r <= a.max(b), "{a} {b} {t} → {r}");
            // The split is exact, so the result is a + (b − a) t with two roundings at most.
            let exact = f64::from(a) + (f64::from(b) - f64::from(a)) * f64::from(t);
            let bound = 2.0 * f64::from(f32::EPSILON) * (f64::from(a.abs()) + f64::from(b.abs()));
            assert!((f64::from(r) - exact).abs() <= bound);
        }
    }
}
