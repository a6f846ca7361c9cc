//! The few analytic scenes the renders and measurements need, as [`SdfSurface`] closures: a
//! sphere, a sphere with bumps coloured by their height (the displaced sphere of Fig. 8 and
//! the height-correlated colour of Fig. 11), a plane with bumps, and a box.
//!
//! Each distance is an exact signed distance or a 1-Lipschitz bound of one with the same zero
//! set (what [`SurfaceSource`] requires): a displacement `h` is divided by the Lipschitz
//! constant `1 + max |∇h|` of `|p| − R − h(p)` (resp. `√(1 + max |∇h|²)` for a height field).
//! Scenes are boxed trait objects, so that the octree build is compiled once, here.

use glam::Vec3;
use svo_brick::{ATTRIBUTE_CHANNELS, BrickSize, BrickTree, BuildOptions, Domain, SdfSurface, SurfaceSource};

use crate::error::{RenderError, check};

/// The central-difference step of the scenes' gradients (world units): far below any finest
/// voxel the crate builds (a 2-unit domain at 2¹⁰ voxels across is 2·10⁻³).
pub const GRADIENT_STEP: f32 = 1e-4;

/// A surface to render: its source, the domain of its octree, and a point to dolly towards.
pub struct Scene {
    /// A short name for tables and files.
    pub name: &'static str,
    /// The surface.
    pub source: Box<dyn SurfaceSource + Send + Sync>,
    /// The cube its octree covers.
    pub domain: Domain,
    /// A point of the surface a dolly approaches ([`crate::accuracy::Dolly::towards`]).
    pub target: Vec3,
    /// The outward unit normal at [`target`](Self::target): the dolly's direction.
    pub outward: Vec3,
}

impl core::fmt::Debug for Scene {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Scene")
            .field("name", &self.name)
            .field("domain", &self.domain)
            .field("target", &self.target)
            .field("outward", &self.outward)
            .finish_non_exhaustive()
    }
}

/// The domain of every scene: the cube `[−1, 1]³`.
pub const DOMAIN: Domain = Domain { origin: Vec3::splat(-1.0), size: 2.0 };

impl Scene {
    /// The octree of the scene with `levels` levels of `brick_size`³ bricks (the other
    /// options at their defaults).
    pub fn build(&self, brick_size: BrickSize, levels: u32) -> Result<BrickTree, RenderError> {
        let options = BuildOptions { brick_size, levels, ..BuildOptions::default() };
        BrickTree::build(self.source.as_ref(), self.domain, options)
            .map_err(|source| RenderError::Build { scene: self.name, source })
    }

    /// The finest voxel of an octree of `levels` levels of `brick_size`³ bricks over the
    /// scene's domain.
    pub fn voxel_size(&self, brick_size: BrickSize, levels: u32) -> f32 {
        let bricks = 1u64 << levels.saturating_sub(1).min(40);
        self.domain.size / (brick_size.side() as f32 * bricks as f32)
    }
}

fn boxed<D, A>(distance: D, attribute: A) -> Box<dyn SurfaceSource + Send + Sync>
where
    D: Fn(Vec3) -> f32 + Send + Sync + 'static,
    A: Fn(Vec3) -> [f32; ATTRIBUTE_CHANNELS] + Send + Sync + 'static,
{
    match SdfSurface::new(distance, attribute, GRADIENT_STEP) {
        Ok(surface) => Box::new(surface),
        // GRADIENT_STEP is finite and positive, so this is never taken; a surface that is
        // empty everywhere stands in rather than a panic.
        Err(_) => Box::new(Empty),
    }
}

/// No surface (the stand-in of an impossible constructor failure).
struct Empty;

impl SurfaceSource for Empty {
    fn distance(&self, _: Vec3) -> f32 {
        1e30
    }
    fn gradient(&self, _: Vec3) -> Vec3 {
        Vec3::ZERO
    }
    fn attribute(&self, _: Vec3) -> [f32; ATTRIBUTE_CHANNELS] {
        [0.0; ATTRIBUTE_CHANNELS]
    }
}

/// `mix(a, b, t)` per channel.
fn mix(a: [f32; 3], b: [f32; 3], t: f32) -> [f32; 3] {
    [a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t, a[2] + (b[2] - a[2]) * t]
}

/// The colour of a groove (the lowest point of a bumpy surface).
pub const GROOVE: [f32; 3] = [0.75, 0.08, 0.05];
/// The colour of a crest (the highest point).
pub const CREST: [f32; 3] = [0.85, 0.8, 0.25];

/// A smooth sphere of `radius` (in `(0, 0.95]`) at the origin, its colour a gentle gradient
/// in `z` (`[0.8, 0.55 + 0.25 z/R, 0.3]`).
pub fn sphere(radius: f32) -> Result<Scene, RenderError> {
    check(radius > 0.0 && radius <= 0.95, "sphere::radius", f64::from(radius), "in (0, 0.95]")?;
    Ok(Scene {
        name: "sphere",
        source: boxed(move |p: Vec3| p.length() - radius, move |p: Vec3| [0.8, 0.55 + 0.25 * p.z / radius, 0.3]),
        domain: DOMAIN,
        target: Vec3::new(0.0, 0.0, -radius),
        outward: Vec3::NEG_Z,
    })
}

/// The bumps `b(p) = sin(f x) sin(f y) sin(f z) ∈ [−1, 1]`, `|∇b| ≤ √3 f`.
fn bumps(p: Vec3, frequency: f32) -> f32 {
    (frequency * p.x).sin() * (frequency * p.y).sin() * (frequency * p.z).sin()
}

/// A sphere of `radius` displaced by `amplitude · b(p)` with `b = sin(f x) sin(f y) sin(f z)`
/// (`f = frequency`), coloured by the height: [`GROOVE`] at `b = −1`, [`CREST`] at `b = 1`,
/// linearly between — the colour correlated with height of Fig. 11 (H5bis).
///
/// The distance `(|p| − R − A b(p)) / (1 + √3 A f)` is 1-Lipschitz. `R + A ≤ 0.95`.
pub fn bumpy_sphere(radius: f32, amplitude: f32, frequency: f32) -> Result<Scene, RenderError> {
    check(amplitude >= 0.0 && amplitude.is_finite(), "bumpy_sphere::amplitude", f64::from(amplitude), "≥ 0")?;
    check(frequency > 0.0 && frequency.is_finite(), "bumpy_sphere::frequency", f64::from(frequency), "> 0")?;
    check(
        radius > amplitude && radius + amplitude <= 0.95,
        "bumpy_sphere::radius",
        f64::from(radius),
        "above the amplitude, with radius + amplitude ≤ 0.95",
    )?;
    let lipschitz = 1.0 + 3f32.sqrt() * amplitude * frequency;
    let distance = move |p: Vec3| (p.length() - radius - amplitude * bumps(p, frequency)) / lipschitz;
    let attribute = move |p: Vec3| mix(GROOVE, CREST, 0.5 + 0.5 * bumps(p, frequency));
    let target = Vec3::new(0.0, 0.0, -(radius + amplitude * bumps(Vec3::new(0.0, 0.0, -radius), frequency)));
    Ok(Scene { name: "bumpy-sphere", source: boxed(distance, attribute), domain: DOMAIN, target, outward: Vec3::NEG_Z })
}

/// The plane `y = A sin(f x) sin(f z)` (`A = amplitude`, `f = frequency`) across the domain,
/// solid below, coloured by height like [`bumpy_sphere`].
///
/// The distance `(y − h(x, z)) / √(1 + 2 A² f²)` is 1-Lipschitz. `A ≤ 0.5`.
pub fn bumpy_plane(amplitude: f32, frequency: f32) -> Result<Scene, RenderError> {
    check((0.0..=0.5).contains(&amplitude), "bumpy_plane::amplitude", f64::from(amplitude), "in [0, 0.5]")?;
    check(frequency > 0.0 && frequency.is_finite(), "bumpy_plane::frequency", f64::from(frequency), "> 0")?;
    let lipschitz = (1.0 + 2.0 * amplitude * amplitude * frequency * frequency).sqrt();
    let height = move |p: Vec3| (frequency * p.x).sin() * (frequency * p.z).sin();
    let distance = move |p: Vec3| (p.y - amplitude * height(p)) / lipschitz;
    let attribute = move |p: Vec3| mix(GROOVE, CREST, 0.5 + 0.5 * height(p));
    Ok(Scene {
        name: "bumpy-plane",
        source: boxed(distance, attribute),
        domain: DOMAIN,
        target: Vec3::ZERO,
        outward: Vec3::Y,
    })
}

/// The axis-aligned box of half-sides `half` (each in `(0, 0.95]`) at the origin (its exact
/// signed distance), coloured by position (`0.5 + 0.4 p / half` per axis, a colour cube).
pub fn cuboid(half: Vec3) -> Result<Scene, RenderError> {
    let smallest = half.min_element();
    check(smallest > 0.0 && half.max_element() <= 0.95, "cuboid::half", f64::from(smallest), "each in (0, 0.95]")?;
    let distance = move |p: Vec3| {
        let q = p.abs() - half;
        q.max(Vec3::ZERO).length() + q.max_element().min(0.0)
    };
    let attribute = move |p: Vec3| (Vec3::splat(0.5) + 0.4 * p / half).clamp(Vec3::ZERO, Vec3::ONE).to_array();
    Ok(Scene {
        name: "box",
        source: boxed(distance, attribute),
        domain: DOMAIN,
        target: Vec3::new(0.0, 0.0, -half.z),
        outward: Vec3::NEG_Z,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn targets_lie_on_their_surfaces_and_bad_parameters_are_errors() {
        let scenes = [
            sphere(0.6).unwrap(),
            bumpy_sphere(0.6, 0.03, 20.0).unwrap(),
            bumpy_plane(0.05, 9.0).unwrap(),
            cuboid(Vec3::new(0.5, 0.4, 0.3)).unwrap(),
        ];
        for scene in &scenes {
            let d = scene.source.distance(scene.target);
            assert!(d.abs() < 1e-5, "{}: {d}", scene.name);
            let g = scene.source.gradient(scene.target + scene.outward * 0.01).normalize();
            assert!(g.dot(scene.outward) > 0.8, "{}: {g}", scene.name);
        }
        assert!(matches!(sphere(1.5), Err(RenderError::Setting { field: "sphere::radius", .. })));
        assert!(matches!(bumpy_sphere(0.6, 0.5, 3.0), Err(RenderError::Setting { field: "bumpy_sphere::radius", .. })));
        assert!(matches!(cuboid(Vec3::new(0.5, 0.0, 0.5)), Err(RenderError::Setting { field: "cuboid::half", .. })));
        assert!((scenes[0].voxel_size(BrickSize::Eight, 3) - 2.0 / 32.0).abs() < 1e-9);
    }

    #[test]
    fn the_displaced_distance_is_one_lipschitz() {
        let scene = bumpy_sphere(0.6, 0.05, 25.0).unwrap();
        let mut worst = 0.0_f32;
        for i in 0..2000 {
            let t = i as f32 * 0.618_034;
            let p = Vec3::new((t * 1.3).sin(), (t * 0.7).cos(), (t * 2.1).sin()) * 0.8;
            let q = p + Vec3::new(t.cos(), t.sin(), (3.0 * t).cos()) * 0.01;
            let ratio = (scene.source.distance(p) - scene.source.distance(q)).abs() / (p - q).length();
            worst = worst.max(ratio);
        }
        assert!(worst <= 1.0 + 1e-3, "{worst}");
    }
}
