//! How well interpolated variances describe the surface in a sample's footprint: the
//! measurement behind [`PackedTree::sample_moment_corrected`].
//!
//! Two truths at a point `q` and level `L`, both the builder's surface statistics
//! ([`surface_statistics`]) of the source's own surface samples:
//!
//! - **box**: the samples in the cube of side `S_L` centred at `q`, about that cube's
//!   box-filtered plane — what a voxel centred at `q` would store;
//! - **mixture**: the samples of the eight trilinear corner voxels' cubes, each weighted by
//!   its trilinear weight, about the trilinearly interpolated plane — the footprint that
//!   trilinear interpolation actually averages over.
//!
//! Plain interpolation of stored variances estimates the within-voxel part only, so it
//! underestimates the mixture; the moment-corrected form adds the between-voxel part.

use alloc::vec::Vec;

use glam::{IVec3, Vec3};

use crate::octree::BrickTree;
use crate::prefilter::surface_statistics;
use crate::sample::PackedTree;
use crate::surface::{Cell, SurfaceSample, SurfaceSource};

/// Signed and absolute errors of an estimate of `σh` (relative to the truth).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DeviationError {
    /// Mean of `(σ̂ − σ) / σ`.
    pub mean_relative: f64,
    /// Mean of `|σ̂ − σ| / σ`.
    pub mean_absolute_relative: f64,
}

/// The errors of plain and moment-corrected interpolation of `σh` at one level, against
/// both truths (see the module documentation).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct InterpolationError {
    /// Points compared (those whose footprints hold surface with `σh > 0`).
    pub points: usize,
    /// Plain interpolation ([`PackedTree::sample`]) against the box truth.
    pub plain_box: DeviationError,
    /// Moment-corrected against the box truth.
    pub corrected_box: DeviationError,
    /// Plain interpolation against the mixture truth.
    pub plain_mixture: DeviationError,
    /// Moment-corrected against the mixture truth.
    pub corrected_mixture: DeviationError,
}

struct Measure<'a, S: ?Sized> {
    source: &'a S,
    tree: &'a BrickTree,
    samples_per_voxel: u32,
    quadrature: u32,
}

impl<S: SurfaceSource + ?Sized> Measure<'_, S> {
    /// The source's samples in the cube `[min, min + side)` (finest-voxel units), each area
    /// scaled by `weight`, appended to `out`.
    fn samples(&self, min: Vec3, side: f32, weight: f32, out: &mut Vec<SurfaceSample>) {
        let size = self.tree.voxel_size();
        let cell = Cell { min: self.tree.world(min), max: self.tree.world(min + side) };
        let mut world = Vec::new();
        self.source.surface_samples(cell, size / self.samples_per_voxel as f32, &mut world);
        out.extend(world.iter().map(|s| SurfaceSample {
            position: (s.position - self.tree.origin()) / size,
            area: weight * s.area / (size * size),
            ..*s
        }));
    }

    /// The box filter (midpoint rule, as the build) of the cube `[min, min + side)`.
    fn box_mean(&self, min: Vec3, side: f32, level: u32) -> (f32, Vec3) {
        let q = (1u32 << level.min(4)).min(self.quadrature);
        let step = side / q as f32;
        let (mut d, mut g) = (0.0_f32, Vec3::ZERO);
        for k in 0..q * q * q {
            let offset = Vec3::new((k % q) as f32, (k / q % q) as f32, (k / (q * q)) as f32);
            let x = self.tree.world(min + (offset + 0.5) * step);
            d += self.source.distance(x) / self.tree.voxel_size();
            g += self.source.gradient(x);
        }
        let count = (q * q * q) as f32;
        (d / count, g / count)
    }
}

fn accumulate(sums: &mut (f64, f64), estimate: f64, truth: f64) {
    let relative = (estimate - truth) / truth;
    sums.0 += relative;
    sums.1 += relative.abs();
}

/// Measures `σh` of `packed` (built from `source` as `tree`) at `level` against both truths
/// at `points` (world units), with surface samples `samples_per_voxel` per finest voxel and
/// the box filter's midpoint rule on `quadrature³` points (as the build's options).
pub fn moment_correction_error<S: SurfaceSource + ?Sized>(
    source: &S,
    tree: &BrickTree,
    packed: &PackedTree,
    points: &[Vec3],
    level: u32,
    samples_per_voxel: u32,
    quadrature: u32,
) -> InterpolationError {
    let measure = Measure { source, tree, samples_per_voxel, quadrature };
    let scale = (1u32 << level) as f32;
    let unit = f64::from(tree.voxel_size());
    let mut result = InterpolationError::default();
    let mut sums = [(0.0, 0.0); 4];
    let mut samples = Vec::new();
    for &p in points {
        let q = (p - tree.origin()) / tree.voxel_size();
        // Box truth.
        samples.clear();
        measure.samples(q - 0.5 * scale, scale, 1.0, &mut samples);
        let (d, g) = measure.box_mean(q - 0.5 * scale, scale, level);
        let Some(box_truth) = surface_statistics(&samples, q, d, g) else { continue };
        // Mixture truth: the eight corner cubes around q with trilinear weights.
        let local = q / scale;
        let base = local.floor();
        let t = local - base;
        samples.clear();
        let (mut d_mix, mut g_mix) = (0.0_f32, Vec3::ZERO);
        for k in 0..8 {
            let offset = IVec3::new(k & 1, (k >> 1) & 1, k >> 2);
            let w = (0..3).map(|a| if offset[a] == 1 { t[a] } else { 1.0 - t[a] }).product::<f32>();
            let min = (base + offset.as_vec3() - 0.5) * scale;
            measure.samples(min, scale, w, &mut samples);
            let (d, g) = measure.box_mean(min, scale, level);
            d_mix += w * d;
            g_mix += w * g;
        }
        let Some(mixture_truth) = surface_statistics(&samples, q, d_mix, g_mix) else { continue };
        let (Some(plain), Some(corrected)) =
            (packed.sample(p, level as f32), packed.sample_moment_corrected(p, level as f32))
        else {
            continue;
        };
        let truths = [box_truth, mixture_truth].map(|s| libm::sqrt(f64::from(s.height_variance)));
        if truths.iter().any(|&s| s <= 1e-6) {
            continue;
        }
        let estimates = [plain, corrected].map(|s| libm::sqrt(f64::from(s.distance_variance)) / unit);
        accumulate(&mut sums[0], estimates[0], truths[0]);
        accumulate(&mut sums[1], estimates[1], truths[0]);
        accumulate(&mut sums[2], estimates[0], truths[1]);
        accumulate(&mut sums[3], estimates[1], truths[1]);
        result.points += 1;
    }
    let n = result.points.max(1) as f64;
    let error = |s: (f64, f64)| DeviationError { mean_relative: s.0 / n, mean_absolute_relative: s.1 / n };
    result.plain_box = error(sums[0]);
    result.corrected_box = error(sums[1]);
    result.plain_mixture = error(sums[2]);
    result.corrected_mixture = error(sums[3]);
    result
}
