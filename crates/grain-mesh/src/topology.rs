//! How the triangles of a mesh fit together: closedness (every edge shared by exactly two
//! triangles) and consistent orientation (the two traverse it in opposite directions).
//!
//! Vertices at bit-identical positions are counted as one ("welded"), since meshes split
//! vertices along creases and texture seams to give them separate normals or texture
//! coordinates while the surface stays closed.

use std::collections::HashMap;

use glam::Vec3;

/// How the edges of a triangle mesh pair up, with vertices welded by position.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EdgeReport {
    /// Distinct undirected edges.
    pub edges: usize,
    /// Edges used by exactly one triangle: holes in the surface.
    pub boundary_edges: usize,
    /// Edges used by more than two triangles.
    pub non_manifold_edges: usize,
    /// Edges used by exactly two triangles that traverse it in the same direction, so that
    /// their orientations disagree.
    pub inconsistently_oriented_edges: usize,
    /// Triangles with two corners at the same position (they have no proper edges).
    pub degenerate_triangles: usize,
}

impl EdgeReport {
    /// Counts the edges of `triangles` over `positions`. Indices out of range are counted
    /// as degenerate triangles.
    pub fn of(positions: &[Vec3], triangles: &[[u32; 3]]) -> EdgeReport {
        let welded = weld_by_position(positions);
        // Undirected edge (low, high) → (traversals low → high, traversals high → low).
        let mut edges: HashMap<(u32, u32), (u32, u32)> = HashMap::new();
        let mut degenerate_triangles = 0;
        for corners in triangles {
            let Some(ids) = corners.iter().map(|&i| welded.get(i as usize).copied()).collect::<Option<Vec<u32>>>()
            else {
                degenerate_triangles += 1;
                continue;
            };
            if ids[0] == ids[1] || ids[1] == ids[2] || ids[2] == ids[0] {
                degenerate_triangles += 1;
                continue;
            }
            for k in 0..3 {
                let (from, to) = (ids[k], ids[(k + 1) % 3]);
                let counts = edges.entry((from.min(to), from.max(to))).or_default();
                if from < to {
                    counts.0 += 1;
                } else {
                    counts.1 += 1;
                }
            }
        }
        let mut report = EdgeReport { edges: edges.len(), degenerate_triangles, ..EdgeReport::default() };
        for &(forward, backward) in edges.values() {
            match forward + backward {
                1 => report.boundary_edges += 1,
                2 if forward != 1 => report.inconsistently_oriented_edges += 1,
                2 => {}
                _ => report.non_manifold_edges += 1,
            }
        }
        report
    }

    /// Whether the mesh is closed and consistently oriented: every edge is shared by
    /// exactly two triangles traversing it in opposite directions, and no triangle is
    /// degenerate. Only then does the divergence theorem give the enclosed volume.
    pub fn is_closed_and_oriented(&self) -> bool {
        self.edges > 0
            && self.boundary_edges == 0
            && self.non_manifold_edges == 0
            && self.inconsistently_oriented_edges == 0
            && self.degenerate_triangles == 0
    }
}

/// For each vertex, the index of the first vertex at the same position (`-0.0` and `0.0`
/// are the same position).
pub fn weld_by_position(positions: &[Vec3]) -> Vec<u32> {
    let mut first_at: HashMap<[u32; 3], u32> = HashMap::with_capacity(positions.len());
    positions
        .iter()
        .enumerate()
        .map(|(i, p)| {
            // Adding 0.0 turns -0.0 into 0.0 and leaves every other value unchanged.
            let key = (*p + Vec3::ZERO).to_array().map(f32::to_bits);
            *first_at.entry(key).or_insert(i as u32)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tetrahedron wound outward.
    fn tetrahedron() -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let positions = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
        (positions, vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    }

    #[test]
    fn tetrahedron_is_closed_and_oriented() {
        let (positions, triangles) = tetrahedron();
        let report = EdgeReport::of(&positions, &triangles);
        assert_eq!(report.edges, 6);
        assert!(report.is_closed_and_oriented(), "{report:?}");
    }

    #[test]
    fn flipped_triangle_is_found() {
        let (positions, mut triangles) = tetrahedron();
        triangles[3] = [1, 3, 2];
        let report = EdgeReport::of(&positions, &triangles);
        assert_eq!(report.inconsistently_oriented_edges, 3);
        assert!(!report.is_closed_and_oriented());
    }

    #[test]
    fn missing_triangle_leaves_boundary_edges() {
        let (positions, mut triangles) = tetrahedron();
        triangles.pop();
        let report = EdgeReport::of(&positions, &triangles);
        assert_eq!(report.boundary_edges, 3);
        assert!(!report.is_closed_and_oriented());
    }

    #[test]
    fn duplicated_vertices_are_welded() {
        let (mut positions, mut triangles) = tetrahedron();
        positions.push(Vec3::new(-0.0, 0.0, 0.0)); // vertex 4 = vertex 0
        triangles[0] = [4, 2, 1];
        assert!(EdgeReport::of(&positions, &triangles).is_closed_and_oriented());
        assert_eq!(weld_by_position(&positions)[4], 0);
    }

    #[test]
    fn duplicated_triangle_is_non_manifold() {
        let (positions, mut triangles) = tetrahedron();
        triangles.push([0, 2, 1]);
        triangles.push([0, 1, 2]);
        let report = EdgeReport::of(&positions, &triangles);
        assert_eq!(report.non_manifold_edges, 3);
    }
}
