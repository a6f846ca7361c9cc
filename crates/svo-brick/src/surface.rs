//! What an octree is built from: a signed distance field, the attributes of its surface,
//! and samples of that surface for the statistics of the coarser levels.

use alloc::vec::Vec;

use glam::Vec3;

use crate::descriptor::ATTRIBUTE_CHANNELS;

/// A point of the surface that the coarse levels' statistics are measured on.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SurfaceSample {
    /// The point, on the surface.
    pub position: Vec3,
    /// The unit surface normal there (pointing outside).
    pub normal: Vec3,
    /// The surface area the sample stands for (world units²).
    pub area: f32,
    /// The attribute there.
    pub attribute: [f32; ATTRIBUTE_CHANNELS],
}

/// An axis-aligned box, `min ≤ p < max`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cell {
    /// The lowest corner.
    pub min: Vec3,
    /// The highest corner.
    pub max: Vec3,
}

impl Cell {
    /// Whether `p` lies in the half-open box.
    pub fn contains(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmplt(self.max).all()
    }
}

/// A surface with attributes, as the builder reads it (world units).
///
/// The distance must be a signed distance (negative inside) or a 1-Lipschitz bound of one
/// with the same zero set: the builder's brick placement and the prefiltered `h̄` rely on
/// `|distance(p) − distance(q)| ≤ |p − q|`.
pub trait SurfaceSource {
    /// The signed distance at `p`, negative inside.
    fn distance(&self, p: Vec3) -> f32;

    /// The gradient of [`distance`](Self::distance) at `p` (the outward normal on the
    /// surface).
    fn gradient(&self, p: Vec3) -> Vec3;

    /// The attribute of the surface at the surface point `x`.
    fn attribute(&self, x: Vec3) -> [f32; ATTRIBUTE_CHANNELS];

    /// Appends samples of the surface inside `cell` at about one per `spacing²` of area.
    ///
    /// The default is the thin-shell estimator: every point `p` of the grid of step
    /// `spacing` (cell-centred) with `|d(p)| < spacing / 2` is projected onto the surface,
    /// `x = p − d(p) ∇d / |∇d|²` (repeated up to [`PROJECTION_STEPS`] times for a distance
    /// that is only a bound), and stands for `spacing² |∇d(p)|` of area. By the coarea
    /// formula the shell `|d| < spacing / 2`, `spacing / |∇d|` thick, holds
    /// `area / (spacing² |∇d|)` grid points on average, so the total area is unbiased for an
    /// exact signed distance and for a 1-Lipschitz bound of one alike; each sample's weight
    /// is exact for a surface parallel to a grid plane. Height fields and meshes override
    /// it with exact samples.
    fn surface_samples(&self, cell: Cell, spacing: f32, out: &mut Vec<SurfaceSample>) {
        thin_shell_samples(self, cell, spacing, out);
    }
}

/// Newton steps of the thin-shell sampler's projection onto the surface, at most.
pub const PROJECTION_STEPS: usize = 4;

/// The default [`SurfaceSource::surface_samples`]: the thin-shell estimator.
pub fn thin_shell_samples<S: SurfaceSource + ?Sized>(
    source: &S,
    cell: Cell,
    spacing: f32,
    out: &mut Vec<SurfaceSample>,
) {
    if !spacing.is_finite() || spacing <= 0.0 {
        return;
    }
    let extent = (cell.max - cell.min) / spacing;
    let counts = [extent.x, extent.y, extent.z].map(|e| libm::ceilf(e).max(0.0) as u32);
    let area = spacing * spacing;
    for k in 0..counts[2] {
        for j in 0..counts[1] {
            for i in 0..counts[0] {
                let p = cell.min + (Vec3::new(i as f32, j as f32, k as f32) + 0.5) * spacing;
                if !cell.contains(p) {
                    continue;
                }
                let d = source.distance(p);
                if d.is_nan() || libm::fabsf(d) >= 0.5 * spacing {
                    continue;
                }
                let g = source.gradient(p);
                let g2 = g.length_squared();
                if !g2.is_finite() || g2 <= 0.0 {
                    continue;
                }
                // Newton steps x ← x − d ∇d / |∇d|²: one lands on the surface for an exact
                // signed distance; a 1-Lipschitz bound of one may need a few.
                let (mut x, mut gx, mut dx) = (p, g, d);
                for _ in 0..PROJECTION_STEPS {
                    let step = gx * (dx / gx.length_squared());
                    if !step.is_finite() {
                        break;
                    }
                    x -= step;
                    (dx, gx) = (source.distance(x), source.gradient(x));
                    if libm::fabsf(dx) <= 1e-6 * spacing {
                        break;
                    }
                }
                // The shell |d| < spacing / 2 is spacing / |∇d| thick: a distance that is only a
                // 1-Lipschitz bound (|∇d| < 1) has a thicker shell, hence the |∇d| weight.
                let length = libm::sqrtf(g2);
                out.push(SurfaceSample {
                    position: x,
                    normal: gx.try_normalize().unwrap_or(g / length),
                    area: area * length,
                    attribute: source.attribute(x),
                });
            }
        }
    }
}

/// A [`SurfaceSource`] from two closures: a signed distance (whose gradient is taken by
/// central differences of step `gradient_step`) and an attribute.
#[derive(Clone, Copy)]
pub struct SdfSurface<D, A> {
    distance: D,
    attribute: A,
    gradient_step: f32,
}

/// Why an [`SdfSurface`] could not be made.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SurfaceError {
    /// The gradient step is not finite and positive.
    GradientStep(f32),
}

impl core::fmt::Display for SurfaceError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            SurfaceError::GradientStep(step) => write!(f, "gradient step {step} is not finite and positive"),
        }
    }
}

impl core::error::Error for SurfaceError {}

impl<D, A> core::fmt::Debug for SdfSurface<D, A> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("SdfSurface").field("gradient_step", &self.gradient_step).finish_non_exhaustive()
    }
}

impl<D, A> SdfSurface<D, A>
where
    D: Fn(Vec3) -> f32,
    A: Fn(Vec3) -> [f32; ATTRIBUTE_CHANNELS],
{
    /// A surface from a signed distance, an attribute, and the step of the central
    /// differences that give the gradient (world units; a small fraction of the finest
    /// voxel).
    pub fn new(distance: D, attribute: A, gradient_step: f32) -> Result<Self, SurfaceError> {
        if !gradient_step.is_finite() || gradient_step <= 0.0 {
            return Err(SurfaceError::GradientStep(gradient_step));
        }
        Ok(Self { distance, attribute, gradient_step })
    }
}

impl<D, A> SurfaceSource for SdfSurface<D, A>
where
    D: Fn(Vec3) -> f32,
    A: Fn(Vec3) -> [f32; ATTRIBUTE_CHANNELS],
{
    fn distance(&self, p: Vec3) -> f32 {
        (self.distance)(p)
    }

    fn gradient(&self, p: Vec3) -> Vec3 {
        let h = self.gradient_step;
        let d = |e: Vec3| ((self.distance)(p + e * h) - (self.distance)(p - e * h)) / (2.0 * h);
        Vec3::new(d(Vec3::X), d(Vec3::Y), d(Vec3::Z))
    }

    fn attribute(&self, x: Vec3) -> [f32; ATTRIBUTE_CHANNELS] {
        (self.attribute)(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sphere(radius: f32) -> impl SurfaceSource {
        SdfSurface::new(move |p: Vec3| p.length() - radius, |_| [0.5; 3], 1e-3).unwrap()
    }

    #[test]
    fn thin_shell_samples_lie_on_the_surface_and_add_up_to_its_area() {
        let radius = 10.0;
        let source = sphere(radius);
        let mut samples = Vec::new();
        let cell = Cell { min: Vec3::splat(-12.0), max: Vec3::splat(12.0) };
        source.surface_samples(cell, 0.25, &mut samples);
        let area: f32 = samples.iter().map(|s| s.area).sum();
        let exact = 4.0 * core::f32::consts::PI * radius * radius;
        // The estimator is unbiased; with ~20 000 samples its relative noise is well under 1 %.
        assert!((area / exact - 1.0).abs() < 0.01, "{area} vs {exact}");
        for s in &samples {
            assert!((s.position.length() - radius).abs() < 1e-3);
            assert!((s.normal - s.position / radius).length() < 1e-2);
        }
    }

    #[test]
    fn a_distance_bound_below_the_true_distance_gets_the_same_area() {
        // Half the distance: a 1-Lipschitz bound with |∇d| = ½ and a shell twice as thick.
        let radius = 10.0;
        let half = SdfSurface::new(move |p: Vec3| 0.5 * (p.length() - radius), |_| [0.5; 3], 1e-3).unwrap();
        let mut samples = Vec::new();
        half.surface_samples(Cell { min: Vec3::splat(-12.0), max: Vec3::splat(12.0) }, 0.25, &mut samples);
        let area: f32 = samples.iter().map(|s| s.area).sum();
        let exact = 4.0 * core::f32::consts::PI * radius * radius;
        assert!((area / exact - 1.0).abs() < 0.01, "{area} vs {exact}");
    }

    #[test]
    fn a_bad_gradient_step_is_an_error() {
        let error = SdfSurface::new(|p: Vec3| p.x, |_: Vec3| [0.0; 3], 0.0).unwrap_err();
        assert_eq!(error, SurfaceError::GradientStep(0.0));
        assert!(alloc::format!("{error}").contains("gradient step"));
    }
}
