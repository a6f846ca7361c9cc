//! A bounding volume hierarchy over triangles that speeds up the distance maps without
//! changing them: the overlap test visits only triangles whose boxes touch the voxel, and
//! the per-voxel minimum visits nodes nearest first and skips those whose lower bound
//! cannot beat the current best.
//!
//! Each node stores the box of its triangles' vertices (for the overlap test), the box of
//! their centres and the largest of their bounding radii (for the distance lower bound).
//! The distance bound of [`directional_distance_bound`] starts from the bounding-sphere
//! bound `|c_T − c_B| − r_B − r_T`, and `|c_T − c_B|` is at least the distance from `c_B`
//! to the centres' box, so a node whose bound reaches `best` holds no triangle that could
//! lower it: the result equals the brute-force minimum over all triangles, value for value.

use alloc::vec::Vec;

use glam::Vec3;

use crate::cones::Cone;
use crate::geometry::{Aabb, Triangle, directional_distance_bound, triangle_overlaps_box};

/// Triangles per leaf at most.
const LEAF_SIZE: usize = 4;

/// The relative margin by which [`TriangleBvh::any_overlaps`] widens the box before its
/// node tests: it keeps them from rejecting what the exact test, computed relative to the
/// box centre, would accept after rounding.
pub(crate) const OVERLAP_BOX_MARGIN: f32 = 1e-4;

/// A node of [`TriangleBvh`].
#[derive(Clone, Copy, Debug)]
struct Node {
    /// Box of the vertices of the node's triangles.
    vertex_bounds: Aabb,
    /// Box of the centres of the node's triangles.
    center_bounds: Aabb,
    /// Largest bounding radius of the node's triangles (around their centres).
    max_radius: f32,
    /// Leaf: first entry in `order`; inner node: index of the second child (the first
    /// child follows the node).
    first_or_child: u32,
    /// Leaf: number of triangles; inner node: 0.
    count: u32,
}

/// A bounding volume hierarchy over a triangle list (median splits along the longest axis
/// of the centres' box).
#[derive(Clone, Debug)]
pub struct TriangleBvh {
    triangles: Vec<Triangle>,
    /// Triangle indices, grouped by leaf.
    order: Vec<u32>,
    nodes: Vec<Node>,
}

/// The smallest box holding `points`, or `None` when there are none.
fn bounds_of(points: impl Iterator<Item = Vec3>) -> Option<Aabb> {
    points.fold(None, |acc: Option<Aabb>, p| match acc {
        Some(b) => Some(Aabb { min: b.min.min(p), max: b.max.max(p) }),
        None => Some(Aabb { min: p, max: p }),
    })
}

/// Distance from `point` to `aabb` (0 inside).
fn point_box_distance(point: Vec3, aabb: &Aabb) -> f32 {
    (point - point.clamp(aabb.min, aabb.max)).length()
}

impl TriangleBvh {
    /// Builds the hierarchy over `triangles`.
    pub fn new(triangles: Vec<Triangle>) -> Self {
        let mut bvh = Self { order: (0..triangles.len() as u32).collect(), triangles, nodes: Vec::new() };
        if !bvh.triangles.is_empty() {
            let count = bvh.order.len();
            bvh.build(0, count);
        }
        bvh
    }

    /// The triangles, in their original order.
    pub fn triangles(&self) -> &[Triangle] {
        &self.triangles
    }

    /// Appends the subtree over `order[start..end]` (non-empty) and returns its index.
    fn build(&mut self, start: usize, end: usize) -> usize {
        let triangles = &self.triangles;
        let members = &mut self.order[start..end];
        let vertices = members.iter().flat_map(|&i| triangles[i as usize].0);
        let fallback = Aabb { min: Vec3::ZERO, max: Vec3::ZERO };
        let vertex_bounds = bounds_of(vertices).unwrap_or(fallback);
        let center_bounds = bounds_of(members.iter().map(|&i| triangles[i as usize].center())).unwrap_or(fallback);
        let max_radius = members.iter().map(|&i| triangles[i as usize].radius()).fold(0.0, f32::max);
        let index = self.nodes.len();
        let mut node = Node { vertex_bounds, center_bounds, max_radius, first_or_child: start as u32, count: 0 };
        if members.len() <= LEAF_SIZE {
            node.count = members.len() as u32;
            self.nodes.push(node);
            return index;
        }
        let size = center_bounds.max - center_bounds.min;
        let axis = if size.x >= size.y && size.x >= size.z {
            0
        } else if size.y >= size.z {
            1
        } else {
            2
        };
        let middle = members.len() / 2;
        members.select_nth_unstable_by(middle, |&a, &b| {
            triangles[a as usize].center()[axis].total_cmp(&triangles[b as usize].center()[axis])
        });
        self.nodes.push(node);
        self.build(start, start + middle);
        let second = self.build(start + middle, end);
        self.nodes[index].first_or_child = second as u32;
        index
    }

    /// The box of node `index`'s triangles' vertices (node 0 is the root), or `None` past
    /// the end.
    pub(crate) fn node_bounds(&self, index: u32) -> Option<Aabb> {
        self.nodes.get(index as usize).map(|node| node.vertex_bounds)
    }

    /// The indices (into [`TriangleBvh::triangles`]) of node `index`'s triangles if it is
    /// a leaf.
    pub(crate) fn leaf_indices(&self, index: u32) -> Option<&[u32]> {
        let node = self.nodes.get(index as usize)?;
        (node.count > 0).then(|| {
            let first = node.first_or_child as usize;
            &self.order[first..first + node.count as usize]
        })
    }

    /// The two children of node `index` if it is an inner node.
    pub(crate) fn children(&self, index: u32) -> Option<[u32; 2]> {
        let node = self.nodes.get(index as usize)?;
        (node.count == 0).then_some([index + 1, node.first_or_child])
    }

    /// Whether any triangle intersects `aabb` ([`triangle_overlaps_box`]): the nodes whose
    /// boxes reach `aabb` widened by a relative margin of 1e-4 are searched.
    pub fn any_overlaps(&self, aabb: &Aabb, stack: &mut Vec<u32>) -> bool {
        let margin = OVERLAP_BOX_MARGIN * (1.0 + aabb.max.abs().max_element());
        let wide = Aabb { min: aabb.min - margin, max: aabb.max + margin };
        stack.clear();
        if !self.nodes.is_empty() {
            stack.push(0);
        }
        while let Some(index) = stack.pop() {
            let node = &self.nodes[index as usize];
            let b = &node.vertex_bounds;
            if b.min.cmpgt(wide.max).any() || b.max.cmplt(wide.min).any() {
                continue;
            }
            if node.count > 0 {
                let first = node.first_or_child as usize;
                let leaf = &self.order[first..first + node.count as usize];
                if leaf.iter().any(|&i| triangle_overlaps_box(&self.triangles[i as usize], aabb)) {
                    return true;
                }
            } else {
                stack.push(node.first_or_child);
                stack.push(index + 1);
            }
        }
        false
    }

    /// A lower bound of node `index`'s triangles' [`directional_distance_bound`] from a box
    /// with centre `center` and bounding radius `radius`.
    fn node_lower_bound(&self, index: u32, center: Vec3, radius: f32) -> f32 {
        let node = &self.nodes[index as usize];
        let distance = point_box_distance(center, &node.center_bounds);
        // The margin covers the rounding of the triangles' own sphere bounds.
        let margin = 1e-5 * (1.0 + distance + radius + node.max_radius);
        distance - radius - node.max_radius - margin
    }

    /// `best.min(d)` where `d` is the minimum of [`directional_distance_bound`] over all
    /// triangles: the same value as the brute-force loop, with nodes visited nearest first
    /// and pruned once their lower bound reaches the current best.
    pub fn min_directional_distance(
        &self,
        aabb: &Aabb,
        cone: Option<&Cone>,
        tolerance: f32,
        best: f32,
        stack: &mut Vec<(u32, f32)>,
    ) -> f32 {
        let (center, radius) = (aabb.center(), aabb.radius());
        let mut best = best;
        stack.clear();
        if !self.nodes.is_empty() {
            stack.push((0, self.node_lower_bound(0, center, radius)));
        }
        while let Some((index, lower)) = stack.pop() {
            if lower >= best {
                continue;
            }
            let node = &self.nodes[index as usize];
            if node.count > 0 {
                let first = node.first_or_child as usize;
                for &i in &self.order[first..first + node.count as usize] {
                    let triangle = &self.triangles[i as usize];
                    best = best.min(directional_distance_bound(aabb, triangle, cone, tolerance, best));
                }
            } else {
                let children = [index + 1, node.first_or_child];
                let [near, far] = children.map(|child| (child, self.node_lower_bound(child, center, radius)));
                let (near, far) = if near.1 <= far.1 { (near, far) } else { (far, near) };
                if far.1 < best {
                    stack.push(far);
                }
                if near.1 < best {
                    stack.push(near);
                }
            }
        }
        best
    }
}
