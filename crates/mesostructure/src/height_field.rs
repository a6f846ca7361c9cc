//! Height fields over a tile and the maze and brick generators.

use ddm_compress::Triangle;
use glam::{UVec3, Vec3};

/// Heights at the `(width + 1) × (height + 1)` grid corners of a tile of `width × height`
/// unit cells.
#[derive(Clone, Debug, PartialEq)]
pub struct HeightField {
    /// Cells along x.
    pub width: u32,
    /// Cells along y.
    pub height: u32,
    /// Corner heights, index `x + (width + 1) y`.
    pub heights: Vec<f32>,
}

impl HeightField {
    /// Samples `height_at(x, y)` at the corners.
    pub fn from_fn(width: u32, height: u32, height_at: impl Fn(f32, f32) -> f32) -> Self {
        let heights =
            (0..=height).flat_map(|y| (0..=width).map(move |x| (x, y))).map(|(x, y)| height_at(x as f32, y as f32));
        Self { width, height, heights: heights.collect() }
    }

    /// Height at corner `(x, y)`, or 0 outside the grid.
    pub fn corner(&self, x: u32, y: u32) -> f32 {
        self.heights.get((x + (self.width + 1) * y) as usize).copied().unwrap_or(0.0)
    }

    /// Two triangles per cell, `2 width height` in all ([`cell_triangles`](Self::cell_triangles)
    /// row by row).
    pub fn triangles(&self) -> Vec<Triangle> {
        let mut triangles = Vec::with_capacity(2 * (self.width * self.height) as usize);
        for y in 0..self.height {
            for x in 0..self.width {
                triangles.extend(self.cell_triangles(x, y));
            }
        }
        triangles
    }

    /// The two triangles of cell `(x, y)`, split along its diagonal from `(x, y)` to
    /// `(x + 1, y + 1)`, facing up (out of the solid under them).
    pub fn cell_triangles(&self, x: u32, y: u32) -> [Triangle; 2] {
        let p = |dx: u32, dy: u32| Vec3::new((x + dx) as f32, (y + dy) as f32, self.corner(x + dx, y + dy));
        [Triangle([p(0, 0), p(1, 0), p(1, 1)]), Triangle([p(0, 0), p(1, 1), p(0, 1)])]
    }
}

/// A xorshift64 generator (deterministic per seed; seed 0 is remapped).
struct Xorshift(u64);

impl Xorshift {
    fn next_below(&mut self, n: u32) -> u32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        ((self.0 >> 32) % u64::from(n.max(1))) as u32
    }
}

/// A perfect maze on a torus of `cells × cells` rooms (depth-first carving from `seed`),
/// as a `2 cells × 2 cells` block grid: `true` where a wall stands.
fn maze_walls(cells: u32, seed: u64) -> Vec<bool> {
    let n = 2 * cells;
    // Blocks (odd, odd) are rooms; (even, even) are pillars; the rest are walls between
    // neighbouring rooms, open or closed.
    let mut walls: Vec<bool> = (0..n * n).map(|i| !((i % n) % 2 == 1 && (i / n) % 2 == 1)).collect();
    let mut visited = vec![false; (cells * cells) as usize];
    let mut rng = Xorshift(seed.max(1).wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1);
    let mut stack = vec![(0_u32, 0_u32)];
    visited[0] = true;
    while let Some(&(cx, cy)) = stack.last() {
        let neighbours: Vec<(i32, i32)> = [(1, 0), (-1, 0), (0, 1), (0, -1)]
            .into_iter()
            .filter(|&(dx, dy)| {
                let (nx, ny) = ((cx as i32 + dx).rem_euclid(cells as i32), (cy as i32 + dy).rem_euclid(cells as i32));
                !visited[(nx as u32 + cells * ny as u32) as usize]
            })
            .collect();
        if neighbours.is_empty() {
            stack.pop();
            continue;
        }
        let (dx, dy) = neighbours[rng.next_below(neighbours.len() as u32) as usize];
        let (nx, ny) =
            ((cx as i32 + dx).rem_euclid(cells as i32) as u32, (cy as i32 + dy).rem_euclid(cells as i32) as u32);
        // The wall block between room (cx, cy) and its neighbour, on the torus.
        let wx = ((2 * cx + 1) as i32 + dx).rem_euclid(n as i32) as u32;
        let wy = ((2 * cy + 1) as i32 + dy).rem_euclid(n as i32) as u32;
        walls[(wx + n * wy) as usize] = false;
        visited[(nx + cells * ny) as usize] = true;
        stack.push((nx, ny));
    }
    walls
}

/// A height-field maze filling a tile of `size` voxels: a perfect maze of 4 × 4 rooms that
/// tiles periodically, walls `0.75 size.z` high on a floor at `0.125 size.z`.
pub fn maze(size: UVec3, seed: u64) -> Vec<Triangle> {
    maze_height_field(size, seed).triangles()
}

/// The heights of [`maze`].
pub fn maze_height_field(size: UVec3, seed: u64) -> HeightField {
    let cells = 4;
    let walls = maze_walls(cells, seed);
    let blocks = 2 * cells;
    let (floor, top) = (0.125 * size.z as f32, 0.75 * size.z as f32);
    // Corners on the far edge (t = extent) wrap to block 0, like the near edge, so that the
    // tile repeats without a seam.
    let block_of = |t: f32, extent: u32| {
        let extent = extent.max(1) as f32;
        ((t.rem_euclid(extent) / extent * blocks as f32) as u32).min(blocks - 1)
    };
    HeightField::from_fn(size.x, size.y, |x, y| {
        let (bx, by) = (block_of(x, size.x), block_of(y, size.y));
        if walls[(bx + blocks * by) as usize] { top } else { floor }
    })
}

/// Rounded bricks filling a tile of `size` voxels: 2 rows of 2 bricks (the second row
/// shifted by half a brick), mortar at `0.2 size.z`, brick tops at `0.7 size.z`, edges
/// rounded over a quarter of the brick height.
pub fn bricks(size: UVec3) -> Vec<Triangle> {
    bricks_height_field(size).triangles()
}

/// The heights of [`bricks`].
pub fn bricks_height_field(size: UVec3) -> HeightField {
    let (rows, per_row) = (2.0_f32, 2.0_f32);
    let (sx, sy, sz) = (size.x as f32, size.y as f32, size.z as f32);
    let (mortar, top) = (0.2 * sz, 0.7 * sz);
    let (brick_x, brick_y) = (sx / per_row, sy / rows);
    let gap = 0.06 * brick_y.min(brick_x);
    let rounding = (0.25 * (top - mortar)).min(0.25 * brick_y).max(1e-3);
    HeightField::from_fn(size.x, size.y, |x, y| {
        let row = (y / brick_y).floor();
        let shift = if row as i64 % 2 == 1 { 0.5 * brick_x } else { 0.0 };
        let u = (x + shift).rem_euclid(brick_x);
        let v = y - row * brick_y;
        // Distance inside the brick from its nearest edge (negative in the mortar).
        let inside = (u - gap).min(brick_x - gap - u).min(v - gap).min(brick_y - gap - v);
        if inside <= 0.0 {
            mortar
        } else if inside >= rounding {
            top
        } else {
            let t = 1.0 - inside / rounding;
            mortar + (top - mortar) * (1.0 - t * t).max(0.0).sqrt()
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Tiles repeat without a seam: the far edge's corners equal the near edge's.
    fn assert_periodic(field: &HeightField, name: &str) {
        for y in 0..=field.height {
            assert_eq!(field.corner(0, y), field.corner(field.width, y), "{name}: seam at x, row {y}");
        }
        for x in 0..=field.width {
            assert_eq!(field.corner(x, 0), field.corner(x, field.height), "{name}: seam at y, column {x}");
        }
    }

    #[test]
    fn maze_and_bricks_tile_without_seams() {
        for size in [UVec3::new(12, 12, 6), UVec3::new(16, 16, 8), UVec3::new(24, 20, 8), UVec3::new(64, 64, 16)] {
            for seed in [1, 7, 42] {
                assert_periodic(&maze_height_field(size, seed), "maze");
            }
            assert_periodic(&bricks_height_field(size), "bricks");
        }
    }
}
