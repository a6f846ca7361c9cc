//! The maximum pyramid of a periodic height field: level 0 holds each cell's highest
//! corner, level `L` the highest of the `2^L × 2^L` cells of each block, so that a ray
//! above a block's maximum skips the whole block (Tevs, Ihrke & Seidel 2008, "Maximum
//! mipmaps for fast, accurate, and scalable dynamic height field rendering").

/// Per-level block maxima of a periodic `size × size` grid of cells.
///
/// A level exists only where `2^L` divides the size, so that a block covers the same
/// cells in every period; a size that is odd has level 0 alone.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct MaxPyramid {
    /// Every level in turn, each row-major over its `(size >> L)²` blocks.
    maxima: Vec<f64>,
    /// Where each level starts in `maxima`.
    starts: Vec<usize>,
    size: usize,
}

/// `i` modulo `n` in `0 … n`, with a mask where `n` is a power of two.
#[inline]
pub(crate) fn wrap(i: i64, n: usize) -> usize {
    if n.is_power_of_two() { (i as usize) & (n - 1) } else { i.rem_euclid(n as i64) as usize }
}

impl MaxPyramid {
    /// The pyramid over `cell_max` (row-major, `size²` values, each cell's highest corner).
    pub(crate) fn new(size: usize, cell_max: Vec<f64>) -> Self {
        let (mut maxima, mut starts) = (cell_max, vec![0]);
        let mut side = size;
        while side.is_multiple_of(2) && side >= 2 {
            let below = starts[starts.len() - 1];
            let half = side / 2;
            starts.push(maxima.len());
            for k in 0..half * half {
                let at = |i: usize, j: usize| maxima[below + j * side + i];
                let (i, j) = (2 * (k % half), 2 * (k / half));
                let highest = at(i, j).max(at(i + 1, j)).max(at(i, j + 1)).max(at(i + 1, j + 1));
                maxima.push(highest);
            }
            side = half;
        }
        Self { maxima, starts, size }
    }

    /// The coarsest level.
    pub(crate) fn top(&self) -> usize {
        self.starts.len() - 1
    }

    /// The highest corner over block `(i, j)` of `level` (block coordinates, periodic).
    #[inline]
    pub(crate) fn block_max(&self, level: usize, i: i64, j: i64) -> f64 {
        let side = self.size >> level;
        self.maxima[self.starts[level] + wrap(j, side) * side + wrap(i, side)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_block_is_the_highest_of_its_cells_in_every_period() {
        let size = 12; // levels 0, 1, 2: 12, 6 and 3 blocks a side
        let cells: Vec<f64> = (0..size * size).map(|k| f64::from((k * 7919 % 101) as u32)).collect();
        let pyramid = MaxPyramid::new(size, cells.clone());
        assert_eq!(pyramid.top(), 2);
        for level in 0..=pyramid.top() {
            let width = 1_i64 << level;
            for (bi, bj) in [(0, 0), (1, 2), (-1, -1), (7, -4)] {
                let expected = (0..width)
                    .flat_map(|dj| (0..width).map(move |di| (bi * width + di, bj * width + dj)))
                    .map(|(i, j)| cells[wrap(j, size) * size + wrap(i, size)])
                    .fold(f64::NEG_INFINITY, f64::max);
                assert_eq!(pyramid.block_max(level, bi, bj), expected, "level {level}, block ({bi}, {bj})");
            }
        }
    }

    #[test]
    fn wrapping_matches_the_euclidean_remainder() {
        for n in [1, 3, 8, 12] {
            for i in -30..30 {
                assert_eq!(wrap(i, n), i.rem_euclid(n as i64) as usize, "{i} mod {n}");
            }
        }
    }
}
