//! The thin-shell surface estimator for a distance that is only a 1-Lipschitz bound
//! (`|∇d| < 1`), as the displaced surfaces' is.
//!
//! `svo_brick::thin_shell_samples` gives every grid point of the shell `|d| < spacing / 2`
//! the area `spacing²`, which is unbiased when `|∇d| = 1`. For a bound with `|∇d| = g < 1`
//! the shell is `1/g` times thicker and that total area `1/g` times too large. By the
//! coarea formula, `∫_{|d| < s/2} |∇d| dV = ∫_{−s/2}^{s/2} area(d = t) dt ≈ s · area`, so
//! weighting each grid point by `spacing² · |∇d(p)|` is unbiased for any such `d`.

use glam::Vec3;
use svo_brick::{Cell, SurfaceSample, SurfaceSource};

/// Newton steps projecting a shell point onto the zero set at most.
const PROJECTION_STEPS: usize = 4;

/// Appends the thin-shell samples of `source` in `cell` (the grid of step `spacing`,
/// cell-centred, as `svo_brick::thin_shell_samples`), each weighted by
/// `spacing² · |∇d(p)|`, projected on the surface by Newton steps
/// `x ← x − d(x) ∇d(x)/|∇d(x)|²`, with the unit normal `∇d/|∇d|` at the projected point.
pub(crate) fn weighted_shell_samples<S: SurfaceSource + ?Sized>(
    source: &S,
    cell: Cell,
    spacing: f32,
    out: &mut Vec<SurfaceSample>,
) {
    if !(spacing > 0.0 && spacing.is_finite()) {
        return;
    }
    let extent = (cell.max - cell.min) / spacing;
    let counts = extent.to_array().map(|e| e.ceil().max(0.0) as u32);
    for k in 0..counts[2] {
        for j in 0..counts[1] {
            for i in 0..counts[0] {
                let p = cell.min + (Vec3::new(i as f32, j as f32, k as f32) + 0.5) * spacing;
                if !cell.contains(p) {
                    continue;
                }
                let d = source.distance(p);
                if d.abs() >= 0.5 * spacing || d.is_nan() {
                    continue;
                }
                let g = source.gradient(p);
                let g2 = g.length_squared();
                if !(g2 > 0.0 && g2.is_finite()) {
                    continue;
                }
                let (mut x, mut gx, mut dx) = (p, g, d);
                for _ in 0..PROJECTION_STEPS {
                    let step = gx * (dx / gx.length_squared());
                    if !step.is_finite() {
                        break;
                    }
                    x -= step;
                    (dx, gx) = (source.distance(x), source.gradient(x));
                    if dx.abs() <= 1e-6 * spacing {
                        break;
                    }
                }
                let normal = gx.try_normalize().unwrap_or(g / g2.sqrt());
                let area = spacing * spacing * g2.sqrt();
                out.push(SurfaceSample { position: x, normal, area, attribute: source.attribute(x) });
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use svo_brick::SdfSurface;

    use super::*;

    #[test]
    fn a_scaled_distance_gets_the_right_area() {
        // A sphere's distance divided by 3: a 1-Lipschitz bound with |∇d| = 1/3.
        let radius = 2.0;
        let source = SdfSurface::new(move |p: Vec3| (p.length() - radius) / 3.0, |_| [0.5; 3], 1e-3).unwrap();
        let mut samples = Vec::new();
        let cell = Cell { min: Vec3::splat(-2.5), max: Vec3::splat(2.5) };
        weighted_shell_samples(&source, cell, 0.05, &mut samples);
        let area: f32 = samples.iter().map(|s| s.area).sum();
        let exact = 4.0 * std::f32::consts::PI * radius * radius;
        assert!((area / exact - 1.0).abs() < 0.01, "{area} vs {exact}");
        for s in &samples {
            assert!((s.position.length() - radius).abs() < 1e-5);
            assert!(s.normal.abs_diff_eq(s.position / radius, 1e-3));
        }
        let mut none = Vec::new();
        weighted_shell_samples(&source, cell, f32::NAN, &mut none);
        assert!(none.is_empty());
    }
}
