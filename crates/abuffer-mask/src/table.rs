//! The precomputed mask table of §5.4, parametrised by `(θ, v)`, and its lookup.
//!
//! # Cells
//!
//! The table has `T` cells along `θ` and `V` along `v` (256 × 256 by default, as in §6).
//! Cell `(i, j)` holds the mask of the half-plane at its centre
//!
//! ```text
//! θ_i = (i + ½) 2π / T,        v_j = (j + ½ − V/2) Δv,   Δv = 2√2 / (V − 1),
//! ```
//!
//! so the end cells' centres are exactly `v = ∓√2`: cell `j = 0` is empty and cell
//! `j = V − 1` full (samples lie strictly inside the footprint). The table covers
//! `v ∈ [−V_max, V_max)` with `V_max = V Δv / 2`; smaller / larger `v` clamp to the end cells.
//!
//! # Lookup ("nearest mode", bit-identical on CPU and GPU)
//!
//! ```text
//! i = floor(θ × theta_scale)  mod T,       theta_scale = T / 2π        (as f32)
//! j = clamp(floor(v × v_scale) + V/2, 0, V − 1),   v_scale = 1 / Δv     (as f32)
//! cell = i V + j
//! ```
//!
//! Each index uses one multiplication (correctly rounded in IEEE 754 and in WGSL) followed
//! by `floor` and integer arithmetic, with the scales precomputed as `f32` on the CPU and
//! passed to the GPU: no add follows a multiply, so fused multiply-add contraction cannot
//! change the result, and no division, transcendental or reassociable sum is involved.
//! The products are clamped to `±2²⁴` before the integer conversion, and non-finite `θ`, `v`
//! are classified by bit tests before any float operation (NaN `θ` → `i = 0`; NaN `v` →
//! `j = 0`; `±∞` `v` → the end cells; `±∞` `θ` → `i = 0`).
//!
//! # GPU layout
//!
//! [`MaskTable::words`] is a flat `u32` buffer: the mask of cell `c = i V + j` occupies
//! words `c W .. c W + W` (`W = N / 32`), word `w` holding samples `32w .. 32w + 32` (bit `k`
//! = sample `32w + k`). Its size is `T V W` words (1 MiB for 256 × 256 × 128 samples).
//! [`MaskTableUniforms`] carries `T`, `V`, `W`, `N` and the three scales.
//!
//! # Complementary half-planes
//!
//! Cells `(i, j)` and `((i + T/2) mod T, V − 1 − j)` are the half-plane and its complement
//! (`θ + π`, `−v`). The builder computes the cells with `i < T/2` and stores the complement
//! for the others, so that they partition the samples exactly (a sample exactly on the line
//! belongs to the half-plane of the cell with `i < T/2`).

use alloc::vec::Vec;
use core::f64::consts::{SQRT_2, TAU};

use glam::Vec2;
use gpu_layout::f32_bits::{ABS_MASK, INFINITY_BITS};
use gpu_layout::gpu_struct;

use crate::mask::Mask;
use crate::samples::SamplePattern;

/// The paper's table resolution (§6): 256 × 256.
pub const DEFAULT_TABLE_SIZE: u32 = 256;

/// The largest supported resolution along `θ` or `v`.
pub const MAX_TABLE_SIZE: u32 = 4096;

/// `2²⁴`: products are clamped to `±2²⁴` before the integer conversion.
pub(crate) const INDEX_CLAMP: f32 = 16_777_216.0;

gpu_struct! {
    /// Describes a [`MaskTable`] to a shader (§5.4): its resolution, the
    /// lookup scales (precomputed in `f32` on the CPU so that both sides use the same bits)
    /// and the mask size.
    pub struct MaskTableUniforms {
        /// `T`, cells along `θ`.
        pub theta_count: u32,
        /// `V`, cells along `v`.
        pub v_count: u32,
        /// `W = N / 32`, `u32` words per mask.
        pub words_per_mask: u32,
        /// `N`, samples per mask.
        pub sample_count: u32,
        /// `T / 2π` as `f32` ([`TableLayout::theta_scale`](crate::TableLayout::theta_scale)).
        pub theta_scale: f32,
        /// `(V − 1) / 2√2` as `f32` ([`TableLayout::v_scale`](crate::TableLayout::v_scale)).
        pub v_scale: f32,
        /// `1 / N`, exact (a power of two): coverage is `popcount × coverage_scale`.
        pub coverage_scale: f32,
        /// Explicit padding to 16 bytes; always zero.
        pub padding: u32,
    }
}

/// The `(θ, v)` resolution of a mask table and its lookup (no allocation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TableLayout {
    theta_count: u32,
    v_count: u32,
    theta_scale: f32,
    v_scale: f32,
}

impl TableLayout {
    /// `T × V` cells, or `None` unless `T` and `V` are even, at least 2 and at most
    /// [`MAX_TABLE_SIZE`] (even `V` puts `v = 0` on a cell boundary and the end cells'
    /// centres at `±√2`).
    pub fn new(theta_count: u32, v_count: u32) -> Option<Self> {
        let valid = theta_count >= 2
            && theta_count.is_multiple_of(2)
            && v_count >= 2
            && v_count.is_multiple_of(2)
            && theta_count <= MAX_TABLE_SIZE
            && v_count <= MAX_TABLE_SIZE;
        valid.then(|| Self {
            theta_count,
            v_count,
            theta_scale: (f64::from(theta_count) / TAU) as f32,
            v_scale: (1.0 / Self::v_step_f64(v_count)) as f32,
        })
    }

    /// The paper's 256 × 256 layout.
    pub fn paper() -> Self {
        Self {
            theta_count: DEFAULT_TABLE_SIZE,
            v_count: DEFAULT_TABLE_SIZE,
            theta_scale: (f64::from(DEFAULT_TABLE_SIZE) / TAU) as f32,
            v_scale: (1.0 / Self::v_step_f64(DEFAULT_TABLE_SIZE)) as f32,
        }
    }

    fn v_step_f64(v_count: u32) -> f64 {
        2.0 * SQRT_2 / f64::from(v_count - 1)
    }

    /// `T`, the cells along `θ`.
    pub fn theta_count(&self) -> u32 {
        self.theta_count
    }

    /// `V`, the cells along `v`.
    pub fn v_count(&self) -> u32 {
        self.v_count
    }

    /// `T V`, the number of cells.
    pub fn cell_count(&self) -> usize {
        self.theta_count as usize * self.v_count as usize
    }

    /// `T / 2π` rounded to `f32`, the factor of the `θ` lookup.
    pub fn theta_scale(&self) -> f32 {
        self.theta_scale
    }

    /// `1 / Δv = (V − 1) / 2√2` rounded to `f32`, the factor of the `v` lookup.
    pub fn v_scale(&self) -> f32 {
        self.v_scale
    }

    /// The cell row of `θ` (see the module docs).
    pub fn theta_index(&self, theta: f32) -> u32 {
        if theta.to_bits() & ABS_MASK >= INFINITY_BITS {
            return 0;
        }
        let t = (theta * self.theta_scale).clamp(-INDEX_CLAMP, INDEX_CLAMP);
        let i = libm::floorf(t) as i32;
        let count = self.theta_count as i32;
        ((i % count + count) % count) as u32
    }

    /// The cell column of `v` (see the module docs).
    pub fn v_index(&self, v: f32) -> u32 {
        let bits = v.to_bits();
        if bits & ABS_MASK > INFINITY_BITS {
            return 0;
        }
        // ±∞ times a positive finite scale stays ±∞ and clamps; no NaN can arise.
        let t = (v * self.v_scale).clamp(-INDEX_CLAMP, INDEX_CLAMP);
        let j = libm::floorf(t) as i32 + (self.v_count / 2) as i32;
        j.clamp(0, self.v_count as i32 - 1) as u32
    }

    /// The cell index `i V + j` of `(θ, v)`.
    pub fn cell_index(&self, theta: f32, v: f32) -> u32 {
        self.theta_index(theta) * self.v_count + self.v_index(v)
    }

    /// The centre `(θ_i, v_j)` of cell `(i, j)`, in `f64`.
    pub fn cell_centre(&self, i: u32, j: u32) -> (f64, f64) {
        let theta = (f64::from(i) + 0.5) * TAU / f64::from(self.theta_count);
        let v = (f64::from(j) + 0.5 - f64::from(self.v_count) / 2.0) * Self::v_step_f64(self.v_count);
        (theta, v)
    }

    /// The cell holding the complement of cell `(i, j)`: `((i + T/2) mod T, V − 1 − j)`.
    pub fn complementary_cell(&self, i: u32, j: u32) -> (u32, u32) {
        ((i + self.theta_count / 2) % self.theta_count, self.v_count - 1 - j)
    }
}

/// The mask table for `N = 32 × WORDS` samples (needs `alloc`).
#[derive(Clone, Debug, PartialEq)]
pub struct MaskTable<const WORDS: usize> {
    layout: TableLayout,
    samples: SamplePattern,
    words: Vec<u32>,
}

impl<const WORDS: usize> MaskTable<WORDS> {
    /// Builds the table of `layout` for the Poisson-disk pattern of `32 × WORDS` samples
    /// (see the module docs); `None` when `WORDS` is 0 or above 4.
    pub fn new(layout: TableLayout) -> Option<Self> {
        let samples = SamplePattern::poisson_disk(32 * WORDS)?;
        let omegas: Vec<Vec2> = (0..samples.len()).filter_map(|k| samples.footprint_point(k)).collect();
        let (t, v) = (layout.theta_count, layout.v_count);
        let mut words = alloc::vec![0_u32; layout.cell_count() * WORDS];
        for i in 0..t / 2 {
            for j in 0..v {
                let (theta, offset) = layout.cell_centre(i, j);
                let normal = glam::DVec2::new(libm::cos(theta), libm::sin(theta));
                let mask = Mask::<WORDS>::from_fn(|k| omegas[k].as_dvec2().dot(normal) <= offset);
                let (ci, cj) = layout.complementary_cell(i, j);
                for (cell, mask) in [(i * v + j, mask), (ci * v + cj, mask.complement())] {
                    let start = cell as usize * WORDS;
                    words[start..start + WORDS].copy_from_slice(&mask.words);
                }
            }
        }
        Some(Self { layout, samples, words })
    }

    /// The 256 × 256 table of the paper.
    pub fn paper() -> Option<Self> {
        Self::new(TableLayout::paper())
    }

    /// The table's `(θ, v)` layout.
    pub fn layout(&self) -> TableLayout {
        self.layout
    }

    /// The sample pattern whose bits the masks hold.
    pub fn samples(&self) -> &SamplePattern {
        &self.samples
    }

    /// The flat `u32` buffer to upload (layout in the module docs).
    pub fn words(&self) -> &[u32] {
        &self.words
    }

    /// The mask of cell `cell = i V + j` (the empty mask for a cell out of range).
    pub fn cell_mask(&self, cell: u32) -> Mask<WORDS> {
        let start = cell as usize * WORDS;
        let mut mask = Mask::EMPTY;
        if let Some(words) = self.words.get(start..start + WORDS) {
            mask.words.copy_from_slice(words);
        }
        mask
    }

    /// The mask of the half-plane `(θ, v)`: a nearest-cell lookup (Algorithm 1, line 8).
    pub fn lookup(&self, theta: f32, v: f32) -> Mask<WORDS> {
        self.cell_mask(self.layout.cell_index(theta, v))
    }

    /// The uniforms that describe this table to the WGSL twin.
    pub fn uniforms(&self) -> MaskTableUniforms {
        MaskTableUniforms {
            theta_count: self.layout.theta_count,
            v_count: self.layout.v_count,
            words_per_mask: WORDS as u32,
            sample_count: (32 * WORDS) as u32,
            theta_scale: self.layout.theta_scale,
            v_scale: self.layout.v_scale,
            coverage_scale: 1.0 / (32 * WORDS) as f32,
            padding: 0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f32::consts::PI;

    #[test]
    fn layouts_are_validated() {
        assert!(TableLayout::new(255, 256).is_none());
        assert!(TableLayout::new(0, 256).is_none());
        assert!(TableLayout::new(256, 1).is_none());
        assert!(TableLayout::new(256, 255).is_none());
        assert!(TableLayout::new(8192, 256).is_none());
        assert_eq!(TableLayout::new(256, 256), Some(TableLayout::paper()));
    }

    #[test]
    fn lookup_finds_the_cell_whose_centre_is_nearest() {
        let layout = TableLayout::new(64, 32).unwrap();
        for i in 0..64 {
            for j in 0..32 {
                let (theta, v) = layout.cell_centre(i, j);
                assert_eq!(layout.cell_index(theta as f32, v as f32), i * 32 + j);
                assert_eq!(layout.cell_index((theta - TAU) as f32, v as f32), i * 32 + j);
            }
        }
        assert_eq!(layout.v_index(-5.0), 0);
        assert_eq!(layout.v_index(5.0), 31);
        assert_eq!(layout.v_index(f32::INFINITY), 31);
        assert_eq!(layout.v_index(f32::NEG_INFINITY), 0);
        assert_eq!(layout.v_index(f32::NAN), 0);
        assert_eq!(layout.theta_index(f32::NAN), 0);
        assert_eq!(layout.theta_index(1e30), layout.theta_index(1e30));
        assert!(layout.theta_index(-PI) < 64);
    }

    #[test]
    fn end_cells_are_empty_and_full() {
        let table = MaskTable::<4>::paper().unwrap();
        for i in 0..256 {
            assert_eq!(table.cell_mask(i * 256), Mask::EMPTY);
            assert_eq!(table.cell_mask(i * 256 + 255), Mask::FULL);
        }
        assert_eq!(table.lookup(0.0, -2.0), Mask::EMPTY);
        assert_eq!(table.lookup(1.0, 2.0), Mask::FULL);
        assert_eq!(table.words().len(), 256 * 256 * 4);
    }
}
