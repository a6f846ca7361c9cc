//! Closest points on triangles with the feature (vertex, edge or face) they lie on, and a
//! bounding volume hierarchy over triangles for nearest-triangle and box queries.

use glam::DVec3;

/// The feature of a triangle `[a, b, c]` that a closest point lies on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Feature {
    /// Corner `k` (`a`, `b`, `c` for 0, 1, 2).
    Vertex(usize),
    /// Edge `k`, from corner `k` to corner `k + 1 mod 3`.
    Edge(usize),
    /// The interior.
    Face,
}

/// The point of triangle `[a, b, c]` nearest to `p` and its feature: Ericson's
/// *Real-Time Collision Detection* §5.1.5, as `grain_mesh::bounds::closest_point_on_triangle`,
/// with the Voronoi region it ends in.
pub(crate) fn closest_feature(p: DVec3, [a, b, c]: [DVec3; 3]) -> (DVec3, Feature) {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let d1 = ab.dot(ap);
    let d2 = ac.dot(ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return (a, Feature::Vertex(0));
    }
    let bp = p - b;
    let d3 = ab.dot(bp);
    let d4 = ac.dot(bp);
    if d3 >= 0.0 && d4 <= d3 {
        return (b, Feature::Vertex(1));
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return (a + ab * (d1 / (d1 - d3)), Feature::Edge(0));
    }
    let cp = p - c;
    let d5 = ab.dot(cp);
    let d6 = ac.dot(cp);
    if d6 >= 0.0 && d5 <= d6 {
        return (c, Feature::Vertex(2));
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return (a + ac * (d2 / (d2 - d6)), Feature::Edge(2));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))), Feature::Edge(1));
    }
    let denominator = va + vb + vc;
    if denominator == 0.0 {
        // Collinear corners that the tests above did not settle: the nearest corner.
        let k = (0..3).min_by(|&i, &j| p.distance([a, b, c][i]).total_cmp(&p.distance([a, b, c][j]))).unwrap_or(0);
        return ([a, b, c][k], Feature::Vertex(k));
    }
    (a + ab * (vb / denominator) + ac * (vc / denominator), Feature::Face)
}

/// Triangles per leaf at most.
const LEAF_SIZE: usize = 4;

/// Deepest traversal stack: a median split of `n` triangles is `⌈log₂ n⌉ + 1` levels deep,
/// and the stack holds at most one node per level plus one.
const STACK: usize = 96;

#[derive(Clone, Copy, Debug)]
struct Node {
    min: DVec3,
    max: DVec3,
    /// A leaf's first index into `order`, or an inner node's left child (the right child
    /// follows it).
    first: u32,
    /// A leaf's triangle count; 0 for an inner node.
    count: u32,
}

impl Node {
    fn distance_squared(&self, p: DVec3) -> f64 {
        let outside = (self.min - p).max(p - self.max).max(DVec3::ZERO);
        outside.length_squared()
    }
}

/// A bounding volume hierarchy over triangles: binary, split at the median centroid along
/// the longest axis of the centroids' box.
#[derive(Clone, Debug)]
pub(crate) struct Bvh {
    nodes: Vec<Node>,
    order: Vec<u32>,
}

impl Bvh {
    pub(crate) fn new(triangles: &[[DVec3; 3]]) -> Bvh {
        let bounds: Vec<(DVec3, DVec3)> =
            triangles.iter().map(|[a, b, c]| (a.min(*b).min(*c), a.max(*b).max(*c))).collect();
        let centroids: Vec<DVec3> = triangles.iter().map(|[a, b, c]| (*a + *b + *c) / 3.0).collect();
        let mut order: Vec<u32> = (0..triangles.len() as u32).collect();
        let empty = Node { min: DVec3::INFINITY, max: DVec3::NEG_INFINITY, first: 0, count: 0 };
        let mut nodes = vec![empty];
        let mut pending = vec![(0usize, 0usize, triangles.len())];
        while let Some((index, start, end)) = pending.pop() {
            let slice = &mut order[start..end];
            let (mut min, mut max) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
            let (mut centre_min, mut centre_max) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
            for &t in slice.iter() {
                min = min.min(bounds[t as usize].0);
                max = max.max(bounds[t as usize].1);
                centre_min = centre_min.min(centroids[t as usize]);
                centre_max = centre_max.max(centroids[t as usize]);
            }
            if slice.len() <= LEAF_SIZE {
                nodes[index] = Node { min, max, first: start as u32, count: slice.len() as u32 };
                continue;
            }
            let spread = centre_max - centre_min;
            let axis = if spread.x >= spread.y && spread.x >= spread.z {
                0
            } else if spread.y >= spread.z {
                1
            } else {
                2
            };
            let half = slice.len() / 2;
            slice.select_nth_unstable_by(half, |&s, &t| {
                centroids[s as usize][axis].total_cmp(&centroids[t as usize][axis])
            });
            let left = nodes.len();
            nodes.extend([empty, empty]);
            nodes[index] = Node { min, max, first: left as u32, count: 0 };
            pending.push((left, start, start + half));
            pending.push((left + 1, start + half, end));
        }
        Bvh { nodes, order }
    }

    /// The triangle minimising `distance_squared(triangle)` and that value, visiting only
    /// the leaves whose boxes are nearer to `p` than the best so far (`distance_squared`
    /// must be at least the squared distance from `p` to the triangle's box).
    pub(crate) fn nearest(&self, p: DVec3, mut distance_squared: impl FnMut(u32) -> f64) -> Option<(u32, f64)> {
        let mut best: Option<(u32, f64)> = None;
        if self.order.is_empty() {
            return best;
        }
        let mut stack = [0u32; STACK];
        let mut len = 1;
        while len > 0 {
            len -= 1;
            let node = self.nodes[stack[len] as usize];
            let bound = best.map_or(f64::INFINITY, |(_, d)| d);
            if node.distance_squared(p) >= bound {
                continue;
            }
            if node.count > 0 {
                for &t in &self.order[node.first as usize..(node.first + node.count) as usize] {
                    let d = distance_squared(t);
                    if best.is_none_or(|(_, b)| d < b) {
                        best = Some((t, d));
                    }
                }
                continue;
            }
            let (left, right) = (node.first, node.first + 1);
            let (dl, dr) =
                (self.nodes[left as usize].distance_squared(p), self.nodes[right as usize].distance_squared(p));
            // The nearer child is popped first.
            let (near, far) = if dl <= dr { (left, right) } else { (right, left) };
            if len + 2 <= STACK {
                stack[len] = far;
                stack[len + 1] = near;
                len += 2;
            }
        }
        best
    }

    /// Calls `visit` with every triangle of the leaves whose boxes meet the closed box
    /// `[min, max]`: every triangle whose box meets it, and some others.
    pub(crate) fn overlapping(&self, min: DVec3, max: DVec3, mut visit: impl FnMut(u32)) {
        if self.order.is_empty() {
            return;
        }
        let mut stack = [0u32; STACK];
        let mut len = 1;
        while len > 0 {
            len -= 1;
            let node = self.nodes[stack[len] as usize];
            if node.max.cmplt(min).any() || node.min.cmpgt(max).any() {
                continue;
            }
            if node.count > 0 {
                self.order[node.first as usize..(node.first + node.count) as usize].iter().for_each(|&t| visit(t));
            } else if len + 2 <= STACK {
                stack[len] = node.first;
                stack[len + 1] = node.first + 1;
                len += 2;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::Rng;

    fn random_point(rng: &mut Rng, scale: f32) -> DVec3 {
        rng.vec3(glam::Vec3::splat(-scale), glam::Vec3::splat(scale)).as_dvec3()
    }

    #[test]
    fn closest_features_agree_with_grain_mesh() {
        let mut rng = Rng::new(41);
        let mut seen = [0usize; 7];
        for _ in 0..20_000 {
            let corners = [0; 3].map(|_| random_point(&mut rng, 1.0));
            let p = random_point(&mut rng, 2.0);
            let (x, feature) = closest_feature(p, corners);
            let [a, b, c] = corners;
            assert!(x.distance(grain_mesh::bounds::closest_point_on_triangle(p, a, b, c)) < 1e-12);
            // The point lies on its feature.
            let on_segment = |u: DVec3, v: DVec3| {
                let t = ((x - u).dot(v - u) / (v - u).length_squared()).clamp(0.0, 1.0);
                x.distance(u + (v - u) * t) < 1e-9
            };
            match feature {
                Feature::Vertex(k) => {
                    assert_eq!(x, corners[k]);
                    seen[k] += 1;
                }
                Feature::Edge(k) => {
                    assert!(on_segment(corners[k], corners[(k + 1) % 3]));
                    seen[3 + k] += 1;
                }
                Feature::Face => seen[6] += 1,
            }
        }
        assert!(seen.iter().all(|&n| n > 100), "{seen:?}");
    }

    #[test]
    fn nearest_and_overlapping_equal_brute_force() {
        let mut rng = Rng::new(42);
        let triangles: Vec<[DVec3; 3]> = (0..500)
            .map(|_| {
                let centre = random_point(&mut rng, 5.0);
                [0; 3].map(|_| centre + random_point(&mut rng, 0.3))
            })
            .collect();
        let bvh = Bvh::new(&triangles);
        let d2 = |p: DVec3, t: u32| p.distance_squared(closest_feature(p, triangles[t as usize]).0);
        for _ in 0..300 {
            let p = random_point(&mut rng, 7.0);
            let (t, d) = bvh.nearest(p, |t| d2(p, t)).unwrap();
            let brute = (0..500).map(|t| d2(p, t)).fold(f64::INFINITY, f64::min);
            assert_eq!(d, brute);
            assert_eq!(d2(p, t), d);
        }
        let (min, max) = (DVec3::new(-1.0, -2.0, 0.0), DVec3::new(2.0, 1.0, 3.0));
        let mut found = Vec::new();
        bvh.overlapping(min, max, |t| found.push(t));
        found.sort_unstable();
        let expected: Vec<u32> = (0..500u32)
            .filter(|&t| {
                let [a, b, c] = triangles[t as usize];
                a.min(b).min(c).cmple(max).all() && a.max(b).max(c).cmpge(min).all()
            })
            .collect();
        assert!(expected.iter().all(|t| found.binary_search(t).is_ok()));
        assert!(!expected.is_empty() && found.len() < 200, "{} of 500", found.len());
    }
}
