//! The plain distance map laid out for a build on the GPU: the search of
//! [`compute_distance_maps`](crate::compute_distance_maps) with [`MapKind::Plain`] (the private `plain` module: per voxel,
//! the triangle hierarchy visited nearest first, each box–triangle pair bounded by
//! alternating projections, the exact distance where they stall), run by a GPU kernel
//! over many voxels at once.
//!
//! [`PlainGpuScene`] validates the inputs as [`compute_distance_maps`](crate::compute_distance_maps) does, builds the same
//! hierarchy (with the neighbouring tiles' copies when periodic) and flattens it into the
//! storage buffers a kernel reads: [`PlainGpuNode`]s (both children's boxes per inner node,
//! as on the CPU) and [`PlainGpuTriangle`]s in leaf order, with [`PlainGpuUniforms`]. The
//! WGSL twin ([`crate::WGSL`], feature `wgsl`) has the per-pair functions
//! (`ddm_plain_pair_lower_bound`, `ddm_box_triangle_distance`, `ddm_triangle_overlaps_box`
//! and what they call); the traversal, which reads the buffers, belongs to the kernel that
//! binds them (`ddm-render`'s `PlainMapBuilder`). [`PlainGpuScene::distance_maps`] turns
//! what the kernel wrote back into [`DistanceMaps`].
//!
//! A kernel visits the triangles in another order than the CPU (which tries the previous
//! voxel's nearest triangle first along x), so its values may differ from the CPU's, each
//! within the tolerance of the exact box-to-mesh distance and never above it.

use alloc::vec::Vec;
use core::fmt;

use glam::{UVec3, UVec4, Vec3, Vec4};
use gpu_layout::gpu_struct;

use crate::ddm::{DistanceMapError, DistanceMapSettings, DistanceMaps, MapKind, Scene};
use crate::geometry::{Aabb, Triangle};
use crate::plain::{Child, PlainHierarchy};

/// The flag of a [`PlainGpuNode`] child word that makes it a leaf: the word is then
/// `PLAIN_GPU_LEAF | count << PLAIN_GPU_FIRST_BITS | first` (`count` triangles from
/// `first` in [`PlainGpuScene::triangles`]); without it, an index into
/// [`PlainGpuScene::nodes`].
pub const PLAIN_GPU_LEAF: u32 = 1 << 31;

/// The bits of a leaf word that hold its first triangle (see [`PLAIN_GPU_LEAF`]); a scene
/// holds fewer than `2^PLAIN_GPU_FIRST_BITS` triangles.
pub const PLAIN_GPU_FIRST_BITS: u32 = 24;

/// The entries of a kernel's traversal stack: a scene's hierarchy is at most
/// `PLAIN_GPU_STACK − 1` inner nodes deep, so that a nearest-first traversal never holds
/// more.
pub const PLAIN_GPU_STACK: u32 = 48;

gpu_struct! {
    /// An inner node of the plain map's hierarchy as the GPU reads it: both children's
    /// boxes (so that one visit reads one node) and their child words ([`PLAIN_GPU_LEAF`]).
    pub struct PlainGpuNode {
        /// The first child's box minimum (`w` unused, 0).
        pub first_min: Vec4,
        /// The first child's box maximum (`w` unused, 0).
        pub first_max: Vec4,
        /// The second child's box minimum (`w` unused, 0).
        pub second_min: Vec4,
        /// The second child's box maximum (`w` unused, 0).
        pub second_max: Vec4,
        /// `(first child, second child, 0, 0)`: the children's words.
        pub children: UVec4,
    }
}

gpu_struct! {
    /// A triangle of the plain map's hierarchy as the GPU reads it: its corners and box
    /// (`w` unused, 0).
    pub struct PlainGpuTriangle {
        /// The first corner.
        pub a: Vec4,
        /// The second corner.
        pub b: Vec4,
        /// The third corner.
        pub c: Vec4,
        /// The corners' minimum.
        pub min: Vec4,
        /// The corners' maximum.
        pub max: Vec4,
    }
}

gpu_struct! {
    /// What a plain map build kernel needs besides the hierarchy.
    pub struct PlainGpuUniforms {
        /// `(dims.x, dims.y, dims.z, root)`: the grid size and the root's child word (a
        /// leaf of no triangle when the scene has none).
        pub dims_root: UVec4,
        /// The root's box minimum and, in `w`, the tolerance.
        pub root_min_tolerance: Vec4,
        /// The root's box maximum and, in `w`, the cap (the grid's diagonal).
        pub root_max_cap: Vec4,
        /// `(magnitude, 0, 0, 0)`: the largest vertex coordinate magnitude, which sets the
        /// rounding margins.
        pub magnitude: Vec4,
    }
}

/// Why a [`PlainGpuScene`] could not be built or its output read.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PlainGpuError {
    /// The inputs are refused as [`compute_distance_maps`](crate::compute_distance_maps) refuses them.
    Inputs(DistanceMapError),
    /// More triangles (with the periodic copies) than a leaf word can address.
    TooManyTriangles {
        /// Triangles in the hierarchy.
        count: usize,
        /// The most accepted, `2^PLAIN_GPU_FIRST_BITS − 1`.
        limit: usize,
    },
    /// The hierarchy is deeper than a kernel's stack holds ([`PLAIN_GPU_STACK`]).
    TooDeep {
        /// Inner-node levels of the hierarchy.
        depth: u32,
        /// The most accepted.
        limit: u32,
    },
    /// A buffer read back has the wrong number of entries.
    OutputLength {
        /// Which buffer (`values`, `surface`).
        buffer: &'static str,
        /// Entries expected: one per voxel.
        expected: usize,
        /// Entries given.
        found: usize,
    },
}

impl fmt::Display for PlainGpuError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Inputs(error) => write!(f, "plain map on the GPU: {error}"),
            Self::TooManyTriangles { count, limit } => {
                write!(f, "plain map on the GPU: {count} triangles (periodic copies included), more than {limit}")
            }
            Self::TooDeep { depth, limit } => {
                write!(f, "plain map on the GPU: the hierarchy is {depth} levels deep, more than the stack's {limit}")
            }
            Self::OutputLength { buffer, expected, found } => {
                write!(f, "plain map on the GPU: `{buffer}` has {found} entries, not one per voxel ({expected})")
            }
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for PlainGpuError {}

impl From<DistanceMapError> for PlainGpuError {
    fn from(error: DistanceMapError) -> Self {
        Self::Inputs(error)
    }
}

/// The inputs of a plain distance map built on the GPU: the flattened hierarchy and its
/// uniforms (see the module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct PlainGpuScene {
    dims: UVec3,
    periodic_xy: bool,
    max_distance: f32,
    nodes: Vec<PlainGpuNode>,
    triangles: Vec<PlainGpuTriangle>,
    uniforms: PlainGpuUniforms,
}

/// A point as a `Vec4` with `w = 0`.
fn point(v: Vec3) -> Vec4 {
    v.extend(0.0)
}

/// The word of `child` (see [`PLAIN_GPU_LEAF`]).
fn child_word(child: Child) -> u32 {
    match child {
        Child::Node(index) => index,
        Child::Leaf { first, count } => PLAIN_GPU_LEAF | count << PLAIN_GPU_FIRST_BITS | first,
    }
}

/// Inner-node levels below `child` (0 for a leaf).
fn depth(hierarchy: &PlainHierarchy, child: Child) -> u32 {
    // An explicit stack: the hierarchy may be deep enough to refuse.
    let mut deepest = 0;
    let mut stack = Vec::from([(child, 0_u32)]);
    while let Some((child, level)) = stack.pop() {
        if let Child::Node(index) = child {
            let level = level + 1;
            deepest = deepest.max(level);
            stack.extend(hierarchy.nodes[index as usize].children.map(|c| (c, level)));
        }
    }
    deepest
}

impl PlainGpuScene {
    /// Validates the inputs (as [`compute_distance_maps`](crate::compute_distance_maps) with [`MapKind::Plain`]) and lays
    /// out the hierarchy of `triangles` (in voxel coordinates) on a `dims` grid.
    ///
    /// # Errors
    ///
    /// [`PlainGpuError::Inputs`] with the [`DistanceMapError`] that
    /// [`compute_distance_maps`](crate::compute_distance_maps) would return; [`PlainGpuError::TooManyTriangles`] or
    /// [`PlainGpuError::TooDeep`] when the hierarchy does not fit the kernel's words or
    /// stack.
    pub fn new(dims: UVec3, triangles: &[Triangle], settings: DistanceMapSettings) -> Result<Self, PlainGpuError> {
        let scene = Scene::new(dims, triangles, MapKind::Plain, settings)?;
        let max_distance = scene.max_distance;
        // `Scene::new` builds the plain hierarchy for `MapKind::Plain`.
        let hierarchy = scene.plain.unwrap_or_else(|| PlainHierarchy::new(&scene.bvh));
        let limit = (1_usize << PLAIN_GPU_FIRST_BITS) - 1;
        if hierarchy.triangles.len() > limit {
            return Err(PlainGpuError::TooManyTriangles { count: hierarchy.triangles.len(), limit });
        }
        let (root_bounds, root) = match hierarchy.root {
            Some(root) => root,
            None => (Aabb { min: Vec3::ZERO, max: Vec3::ZERO }, Child::Leaf { first: 0, count: 0 }),
        };
        let levels = depth(&hierarchy, root);
        if levels >= PLAIN_GPU_STACK {
            return Err(PlainGpuError::TooDeep { depth: levels, limit: PLAIN_GPU_STACK - 1 });
        }
        let mut nodes: Vec<PlainGpuNode> = hierarchy
            .nodes
            .iter()
            .map(|node| PlainGpuNode {
                first_min: point(node.bounds[0].min),
                first_max: point(node.bounds[0].max),
                second_min: point(node.bounds[1].min),
                second_max: point(node.bounds[1].max),
                children: UVec4::new(child_word(node.children[0]), child_word(node.children[1]), 0, 0),
            })
            .collect();
        let mut gpu_triangles: Vec<PlainGpuTriangle> = hierarchy
            .triangles
            .iter()
            .zip(&hierarchy.triangle_bounds)
            .map(|(triangle, bounds)| PlainGpuTriangle {
                a: point(triangle.0[0]),
                b: point(triangle.0[1]),
                c: point(triangle.0[2]),
                min: point(bounds.min),
                max: point(bounds.max),
            })
            .collect();
        // WGSL storage arrays are never empty: an entry that no word reaches.
        if nodes.is_empty() {
            nodes.push(bytemuck::Zeroable::zeroed());
        }
        if gpu_triangles.is_empty() {
            gpu_triangles.push(bytemuck::Zeroable::zeroed());
        }
        let uniforms = PlainGpuUniforms {
            dims_root: dims.extend(child_word(root)),
            root_min_tolerance: root_bounds.min.extend(settings.tolerance),
            root_max_cap: root_bounds.max.extend(max_distance),
            magnitude: Vec4::new(hierarchy.magnitude, 0.0, 0.0, 0.0),
        };
        Ok(Self { dims, periodic_xy: settings.periodic_xy, max_distance, nodes, triangles: gpu_triangles, uniforms })
    }

    /// The grid size in voxels.
    pub fn dims(&self) -> UVec3 {
        self.dims
    }

    /// The number of voxels: one kernel thread, one value and one surface flag each (voxel
    /// `x + dims.x (y + dims.y z)`).
    pub fn voxel_count(&self) -> usize {
        (self.dims.x as usize) * (self.dims.y as usize) * (self.dims.z as usize)
    }

    /// The inner nodes (at least one entry: a scene without inner nodes has one that no
    /// word reaches).
    pub fn nodes(&self) -> &[PlainGpuNode] {
        &self.nodes
    }

    /// The triangles in leaf order, periodic copies included (at least one entry, as for
    /// [`PlainGpuScene::nodes`]).
    pub fn triangles(&self) -> &[PlainGpuTriangle] {
        &self.triangles
    }

    /// The kernel's uniforms.
    pub fn uniforms(&self) -> PlainGpuUniforms {
        self.uniforms
    }

    /// The distance map from what a kernel wrote: per voxel, its value and whether a
    /// triangle crosses it (non-zero).
    ///
    /// # Errors
    ///
    /// [`PlainGpuError::OutputLength`] when a slice does not hold one entry per voxel.
    pub fn distance_maps(&self, values: &[f32], surface: &[u32]) -> Result<DistanceMaps, PlainGpuError> {
        let expected = self.voxel_count();
        for (buffer, found) in [("values", values.len()), ("surface", surface.len())] {
            if found != expected {
                return Err(PlainGpuError::OutputLength { buffer, expected, found });
            }
        }
        Ok(DistanceMaps {
            dims: self.dims,
            kind: MapKind::Plain,
            values: alloc::vec![values.to_vec()],
            surface: surface.iter().map(|&s| s != 0).collect(),
            max_distance: self.max_distance,
            periodic_xy: self.periodic_xy,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::compute_distance_maps;

    /// A floor at `z = 1.5` over a `4 × 4` tile and a small tent above it.
    fn scene_triangles() -> Vec<Triangle> {
        let floor = |x: f32, y: f32| Vec3::new(x, y, 1.5);
        let mut triangles = Vec::from([
            Triangle([floor(0.0, 0.0), floor(4.0, 0.0), floor(4.0, 4.0)]),
            Triangle([floor(0.0, 0.0), floor(4.0, 4.0), floor(0.0, 4.0)]),
        ]);
        triangles.push(Triangle([Vec3::new(1.0, 1.0, 2.0), Vec3::new(3.0, 1.0, 2.0), Vec3::new(2.0, 3.0, 4.5)]));
        triangles
    }

    #[test]
    fn the_layout_reaches_every_triangle_once_and_words_decode() {
        let settings = DistanceMapSettings { tolerance: 0.05, periodic_xy: true };
        let scene = PlainGpuScene::new(UVec3::new(4, 4, 6), &scene_triangles(), settings).unwrap();
        // Walk the words as a kernel does: every triangle (9 copies of 3) reached once.
        let mut reached = alloc::vec![0_u32; scene.triangles().len()];
        let mut stack = Vec::from([scene.uniforms().dims_root.w]);
        while let Some(word) = stack.pop() {
            if word & PLAIN_GPU_LEAF != 0 {
                let count = (word & !PLAIN_GPU_LEAF) >> PLAIN_GPU_FIRST_BITS;
                let first = word & ((1 << PLAIN_GPU_FIRST_BITS) - 1);
                for t in first..first + count {
                    reached[t as usize] += 1;
                }
            } else {
                let node = scene.nodes()[word as usize];
                stack.extend([node.children.x, node.children.y]);
            }
        }
        assert_eq!(reached.len(), 27);
        assert!(reached.iter().all(|&r| r == 1), "{reached:?}");
        // Every triangle lies in its box.
        for t in scene.triangles() {
            for v in [t.a, t.b, t.c] {
                assert!(v.cmpge(t.min).all() && v.cmple(t.max).all());
            }
        }
    }

    #[test]
    fn an_empty_scene_has_one_unreached_entry_per_buffer_and_gives_the_cap() {
        let settings = DistanceMapSettings { tolerance: 0.05, periodic_xy: false };
        let scene = PlainGpuScene::new(UVec3::new(2, 3, 4), &[], settings).unwrap();
        assert_eq!((scene.nodes().len(), scene.triangles().len()), (1, 1));
        let root = scene.uniforms().dims_root.w;
        assert_eq!(root, PLAIN_GPU_LEAF, "a leaf of no triangle");
        let cpu = compute_distance_maps(UVec3::new(2, 3, 4), &[], MapKind::Plain, settings).unwrap();
        assert_eq!(scene.uniforms().root_max_cap.w, cpu.max_distance);
    }

    #[test]
    fn refused_inputs_and_outputs_name_what_is_wrong() {
        let settings = DistanceMapSettings { tolerance: -1.0, periodic_xy: false };
        let error = PlainGpuScene::new(UVec3::ONE, &scene_triangles(), settings).unwrap_err();
        assert_eq!(error, PlainGpuError::Inputs(DistanceMapError::InvalidTolerance { tolerance: -1.0 }));
        let settings = DistanceMapSettings { tolerance: 0.1, periodic_xy: false };
        let scene = PlainGpuScene::new(UVec3::new(2, 2, 2), &scene_triangles(), settings).unwrap();
        let error = scene.distance_maps(&[0.0; 8], &[0; 7]).unwrap_err();
        assert_eq!(error, PlainGpuError::OutputLength { buffer: "surface", expected: 8, found: 7 });
        assert!(alloc::format!("{error}").contains("`surface` has 7 entries"));
        let maps = scene.distance_maps(&[0.5; 8], &[0, 1, 0, 0, 0, 0, 0, 0]).unwrap();
        assert_eq!(maps.surface.iter().filter(|&&s| s).count(), 1);
        assert_eq!((maps.kind, maps.values[0][3]), (MapKind::Plain, 0.5));
    }
}
