//! How well a table's masks estimate the covered area: `|coverage(mask) − exact area|`
//! of half-plane ∩ footprint, the exact area from polygon clipping
//! ([`exact_coverage`]).

use core::f64::consts::TAU;

use crate::half_plane::exact_coverage;
use crate::table::MaskTable;

/// Coverage error statistics of one table (fractions of the footprint's area).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CoverageErrorStats {
    /// Samples per mask `N`.
    pub samples: usize,
    /// Max over the cell centres of `|popcount / N − exact area|`: the error of the
    /// sample pattern alone.
    pub max_at_centres: f64,
    /// Mean of the same over all cells.
    pub mean_at_centres: f64,
    /// Max over a regular `(θ, v)` grid `oversampling` times finer than the table (each
    /// point looked up in nearest mode): sample pattern plus table quantization.
    pub max_anywhere: f64,
    /// Mean of the same.
    pub mean_anywhere: f64,
}

/// Measures the coverage error of `table`: at every cell centre, and on a grid
/// `oversampling × oversampling` times finer than the table over `θ ∈ [0, 2π)`,
/// `v ∈ [−√2, √2]` (`oversampling` 0 is taken as 1).
pub fn coverage_error<const WORDS: usize>(table: &MaskTable<WORDS>, oversampling: u32) -> CoverageErrorStats {
    let layout = table.layout();
    let (t, v) = (layout.theta_count(), layout.v_count());
    let (mut max_c, mut sum_c) = (0.0_f64, 0.0_f64);
    for i in 0..t {
        for j in 0..v {
            let (theta, offset) = layout.cell_centre(i, j);
            let error = (f64::from(table.cell_mask(i * v + j).coverage()) - exact_coverage(theta, offset)).abs();
            max_c = max_c.max(error);
            sum_c += error;
        }
    }
    let s = oversampling.max(1);
    let (rows, columns) = (t * s, v * s);
    let (mut max_a, mut sum_a) = (0.0_f64, 0.0_f64);
    for a in 0..rows {
        let theta = (f64::from(a) + 0.5) * TAU / f64::from(rows);
        for b in 0..columns {
            let offset = core::f64::consts::SQRT_2 * (2.0 * (f64::from(b) + 0.5) / f64::from(columns) - 1.0);
            let mask = table.lookup(theta as f32, offset as f32);
            let error = (f64::from(mask.coverage()) - exact_coverage(theta, offset)).abs();
            max_a = max_a.max(error);
            sum_a += error;
        }
    }
    CoverageErrorStats {
        samples: 32 * WORDS,
        max_at_centres: max_c,
        mean_at_centres: sum_c / layout.cell_count() as f64,
        max_anywhere: max_a,
        mean_anywhere: sum_a / (f64::from(rows) * f64::from(columns)),
    }
}
