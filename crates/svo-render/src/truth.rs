//! The ground truth: eq. 2 of the paper literally — the *unfiltered* surface supersampled
//! over each pixel's footprint (and lens), shaded with the base BRDF and the local attribute,
//! shadowed by rays towards the area light — and the "voxel truth", the same supersampling
//! of the octree's finest level, which separates prefiltering error from voxelisation error.
//!
//! # Rays
//!
//! Pixel `(x, y)`'s footprint is the cone's own frame: the ray through `(u, v) ∈ (−½, ½)²` has
//! the direction `d(u, v) = cone.direction + (cone.right u + cone.up v) cone.spread`, exactly
//! the footprint the tracer's masks cover. The square is cut into `k × k` strata
//! ([`TruthSettings::rays_per_axis`]) with one sample in each (at its centre, or jittered by a
//! hash of the pixel and the stratum: deterministic). With a thin lens of aperture `A` focused
//! at `f`, each pixel ray is also split over `m × m` strata of the lens disk
//! ([`TruthSettings::lens_samples_per_axis`], the square mapped to the disk by Shirley &
//! Chiu's concentric map): the ray leaves the lens point `o + (right a + up b) A/2` towards
//! the point in focus `o + d(u, v) f`, which lies on the plane at distance `f` along the cone's
//! axis where the cone's width `w(z) = z s + A |z − f|/f` is the pinhole's — the tracer's lens
//! model, with the lens disk in the cone's frame.
//!
//! # Intersection
//!
//! Each ray is sphere-traced against the geometry's distance ([`TruthGeometry`]) in `f64`
//! along the ray (an `f32` parameter stalls where its ulp exceeds the tolerance, ~8 units from
//! the origin): from `ε` past the entry into the domain cube (at the entry itself the point,
//! rounded to `f32`, may lie on a face where the octree has no sample: such a ray was lost
//! whole, as a miss), step by the distance `d` until
//! `|d| < ε` ([`TruthSettings::epsilon`], a hit), the ray leaves the domain (a miss), or
//! [`TruthSettings::max_steps`] evaluations are spent (a miss: a ray grazing the surface
//! closer than the steps could resolve). A negative distance after a positive one (an
//! overshoot — impossible for a 1-Lipschitz distance, possible for the finest level's
//! trilinear interpolation) brackets the surface, and bisection finds it; a negative distance
//! at the first point (the ray starts inside) is a hit there.
//!
//! # Shading
//!
//! At a hit `x` the shading is [`svo_tracer::element_radiance`] of the voxel
//! `{ normal: n(x), attribute: a(x), slope_variance: 0, correlation: 0 }` — the base BRDF with
//! the local attribute, `σn = 0` — seen along `−ray`, lit from the light's centre. With
//! shadows ([`TruthSettings::shadow_rays_per_axis`] `= s > 0`), the visibility is the fraction
//! of `s × s` rays from `x + 16 ε n` towards stratified points of the light's disk (the light
//! sphere's silhouette seen from `x`: the disk of its radius through its centre, normal to the
//! direction) that reach their point without a hit; where the light's centre is below the
//! horizon (`n · l ≤ 0`) the shading is zero anyway and no shadow ray is cast. The pixel's
//! radiance is the mean over its rays (the background for a miss) and its coverage the
//! fraction of rays that hit.

use glam::{DVec3, Vec3};
use svo_brick::{ATTRIBUTE_CHANNELS, Domain, PackedTree, SurfaceSource, Voxel};
use svo_tracer::{Camera, ConeResult, Filtering, TraceSettings, element_radiance};

use crate::error::{RenderError, check};
use crate::frame::Frame;
use crate::parallel::per_pixel;

/// How the ground truth samples each pixel (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TruthSettings {
    /// `k`: the footprint is cut into `k × k` strata, one ray each (1 ..= 64).
    pub rays_per_axis: u32,
    /// `m`: with a lens, each footprint stratum is traced through `m × m` lens strata
    /// (1 ..= 16; ignored without a lens).
    pub lens_samples_per_axis: u32,
    /// `s`: `s × s` shadow rays towards the light's disk per hit (0 ..= 16; 0: no shadows,
    /// the visibility is 1).
    pub shadow_rays_per_axis: u32,
    /// Jitter each sample inside its stratum (by a hash of the pixel and the sample: the same
    /// rays on every run); without it, stratum centres.
    pub jitter: bool,
    /// `ε`: a distance below it is a hit (world units, positive; about 10⁻⁴ of the finest
    /// voxel, see [`TruthSettings::for_voxel`]).
    pub epsilon: f32,
    /// The most distance evaluations per ray, bisection included (≥ 1).
    pub max_steps: u32,
}

impl Default for TruthSettings {
    fn default() -> Self {
        Self {
            rays_per_axis: 8,
            lens_samples_per_axis: 2,
            shadow_rays_per_axis: 0,
            jitter: true,
            epsilon: 1e-6,
            max_steps: 1024,
        }
    }
}

impl TruthSettings {
    /// The defaults with `k = rays_per_axis` and `ε = 10⁻⁴ × voxel` (the finest voxel of the
    /// octree the truth is compared with).
    pub fn for_voxel(voxel: f32, rays_per_axis: u32) -> Self {
        Self { rays_per_axis, epsilon: 1e-4 * voxel, ..Self::default() }
    }

    /// `Err(Setting)` naming the first field out of range.
    pub fn validate(&self) -> Result<(), RenderError> {
        let k = self.rays_per_axis;
        check((1..=64).contains(&k), "TruthSettings::rays_per_axis", f64::from(k), "in 1 ..= 64")?;
        let m = self.lens_samples_per_axis;
        check((1..=16).contains(&m), "TruthSettings::lens_samples_per_axis", f64::from(m), "in 1 ..= 16")?;
        let s = self.shadow_rays_per_axis;
        check(s <= 16, "TruthSettings::shadow_rays_per_axis", f64::from(s), "in 0 ..= 16")?;
        let e = self.epsilon;
        check(e > 0.0 && e.is_finite(), "TruthSettings::epsilon", f64::from(e), "finite and positive")?;
        check(self.max_steps >= 1, "TruthSettings::max_steps", f64::from(self.max_steps), "at least 1")
    }
}

/// A surface the ground truth can intersect and shade.
pub trait TruthGeometry: Sync {
    /// The cube outside which there is no surface.
    fn domain(&self) -> Domain;

    /// A signed distance to the surface at `p` (negative inside; a 1-Lipschitz bound, or
    /// close to one), `None` where it is unknown (a miss).
    fn distance(&self, p: Vec3) -> Option<f32>;

    /// The unit normal `n(x)` and the attribute `a(x)` at the surface point `x`.
    fn surface(&self, x: Vec3) -> (Vec3, [f32; ATTRIBUTE_CHANNELS]);
}

/// The unfiltered source surface in its domain: eq. 2's ground truth.
#[derive(Clone, Copy, Debug)]
pub struct SourceGeometry<'a, S: ?Sized> {
    /// The surface.
    pub source: &'a S,
    /// The cube of its octree (rays stop at its faces, as the tracer's cones do).
    pub domain: Domain,
}

impl<S: SurfaceSource + Sync + ?Sized> TruthGeometry for SourceGeometry<'_, S> {
    fn domain(&self) -> Domain {
        self.domain
    }

    fn distance(&self, p: Vec3) -> Option<f32> {
        let d = self.source.distance(p);
        d.is_finite().then_some(d)
    }

    fn surface(&self, x: Vec3) -> (Vec3, [f32; ATTRIBUTE_CHANNELS]) {
        (self.source.gradient(x).normalize_or_zero(), self.source.attribute(x))
    }
}

/// The finest level of an octree, read with [`PackedTree::sample`] at level of detail 0 (trilinear in
/// the finest voxels; the constant bound of empty nodes): the voxel truth.
#[derive(Clone, Copy, Debug)]
pub struct VoxelGeometry<'a> {
    /// The octree.
    pub packed: &'a PackedTree,
}

/// The cube an octree covers (world units).
pub fn packed_domain(packed: &PackedTree) -> Domain {
    let u = packed.uniforms();
    Domain { origin: u.origin_inverse_size.truncate(), size: u.voxel_size.x * u.counts.z as f32 }
}

impl TruthGeometry for VoxelGeometry<'_> {
    fn domain(&self) -> Domain {
        packed_domain(self.packed)
    }

    fn distance(&self, p: Vec3) -> Option<f32> {
        self.packed.sample(p, 0.0).map(|v| v.distance).filter(|d| d.is_finite())
    }

    fn surface(&self, x: Vec3) -> (Vec3, [f32; ATTRIBUTE_CHANNELS]) {
        self.packed.sample(x, 0.0).map_or((Vec3::ZERO, [0.0; ATTRIBUTE_CHANNELS]), |v| (v.normal, v.attribute))
    }
}

/// A 32-bit integer hash (Wellons' `lowbias32`).
fn hash(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^ (x >> 16)
}

/// A deterministic number in `[0, 1)` for `(pixel, sample, dimension)`.
fn random(pixel: u32, sample: u32, dimension: u32) -> f64 {
    let h = hash(pixel ^ hash(sample.wrapping_mul(0x9e37_79b9) ^ hash(dimension.wrapping_add(0x632b_e5ab))));
    f64::from(h >> 8) / f64::from(1u32 << 24)
}

/// Shirley & Chiu's concentric map of `[0, 1)²` onto the unit disk (area-preserving, so
/// strata of the square are strata of the disk).
fn concentric(a: f64, b: f64) -> (f64, f64) {
    let (x, y) = (2.0 * a - 1.0, 2.0 * b - 1.0);
    if x == 0.0 && y == 0.0 {
        return (0.0, 0.0);
    }
    let quarter = std::f64::consts::FRAC_PI_4;
    let (r, phi) = if x.abs() > y.abs() { (x, quarter * y / x) } else { (y, 2.0 * quarter - quarter * x / y) };
    (r * phi.cos(), r * phi.sin())
}

/// `[t_enter, t_exit]` of the ray in the cube, `None` if it misses.
fn cube_interval(origin: DVec3, direction: DVec3, domain: Domain) -> Option<(f64, f64)> {
    let lo = domain.origin.as_dvec3();
    let hi = lo + f64::from(domain.size);
    let inverse = direction.recip();
    let (a, b) = ((lo - origin) * inverse, (hi - origin) * inverse);
    let enter = a.min(b).max_element().max(0.0);
    let exit = a.max(b).min_element();
    (enter <= exit && exit.is_finite()).then_some((enter, exit))
}

/// Sphere-traces the ray up to `limit` (see the module documentation): the hit's parameter,
/// if any, and the distance evaluations spent.
fn intersect<G: TruthGeometry + ?Sized>(
    geometry: &G,
    origin: DVec3,
    direction: DVec3,
    limit: f64,
    settings: &TruthSettings,
) -> (Option<f64>, u32) {
    let Some((enter, exit)) = cube_interval(origin, direction, geometry.domain()) else { return (None, 0) };
    let exit = exit.min(limit);
    let epsilon = settings.epsilon;
    let at = |t: f64| geometry.distance((origin + direction * t).as_vec3());
    // From ε inside the domain: at its entry the point may round (to f32) onto or beyond a
    // face, where the octree has no sample and the ray would be lost.
    let (mut t, mut previous, mut evaluations) = (enter + f64::from(epsilon), None::<f64>, 0_u32);
    while evaluations < settings.max_steps {
        if t > exit {
            return (None, evaluations);
        }
        evaluations += 1;
        let Some(d) = at(t) else { return (None, evaluations) };
        if d.abs() < epsilon {
            return (Some(t), evaluations);
        }
        if d < 0.0 {
            let Some(outside) = previous else { return (Some(t), evaluations) };
            // The surface lies in (outside, t): bisect.
            let (mut a, mut b) = (outside, t);
            while evaluations < settings.max_steps {
                let m = 0.5 * (a + b);
                evaluations += 1;
                match at(m) {
                    Some(dm) if dm.abs() < epsilon => return (Some(m), evaluations),
                    Some(dm) if dm > 0.0 => a = m,
                    Some(_) => b = m,
                    None => break,
                }
                if b - a <= f64::from(epsilon) * 1e-3 {
                    break;
                }
            }
            return (Some(0.5 * (a + b)), evaluations);
        }
        previous = Some(t);
        t += f64::from(d);
    }
    (None, evaluations)
}

/// A unit frame `(t₁, t₂)` orthogonal to the unit `w`.
fn frame_of(w: DVec3) -> (DVec3, DVec3) {
    let helper = if w.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
    let t1 = w.cross(helper).normalize();
    (t1, w.cross(t1))
}

/// The fraction of the `s × s` shadow rays from `x` (normal `n`) towards the light's disk that
/// reach it, and the evaluations spent.
fn light_visibility<G: TruthGeometry + ?Sized>(
    geometry: &G,
    x: DVec3,
    n: DVec3,
    trace: &TraceSettings,
    settings: &TruthSettings,
    seed: (u32, u32),
) -> (f32, u32) {
    let s = settings.shadow_rays_per_axis;
    let centre = trace.light.position.as_dvec3();
    let origin = x + n * (16.0 * f64::from(settings.epsilon));
    let Some(w) = (centre - origin).try_normalize() else { return (1.0, 0) };
    let (t1, t2) = frame_of(w);
    let radius = f64::from(trace.light.radius.max(0.0));
    let (mut free, mut evaluations) = (0_u32, 0_u32);
    for j in 0..s {
        for i in 0..s {
            let sample = seed.1.wrapping_mul(257).wrapping_add(j * s + i);
            let (ja, jb) =
                if settings.jitter { (random(seed.0, sample, 5), random(seed.0, sample, 6)) } else { (0.5, 0.5) };
            let (a, b) = concentric((f64::from(i) + ja) / f64::from(s), (f64::from(j) + jb) / f64::from(s));
            let target = centre + (t1 * a + t2 * b) * radius;
            let to = target - origin;
            let length = to.length();
            let Some(direction) = to.try_normalize() else {
                free += 1;
                continue;
            };
            let (hit, spent) = intersect(geometry, origin, direction, length, settings);
            evaluations += spent;
            free += u32::from(hit.is_none());
        }
    }
    (free as f32 / (s * s).max(1) as f32, evaluations)
}

/// The radiance and evaluations of one ray (`None`: a miss).
fn shade_ray<G: TruthGeometry + ?Sized>(
    geometry: &G,
    origin: DVec3,
    direction: DVec3,
    trace: &TraceSettings,
    settings: &TruthSettings,
    seed: (u32, u32),
) -> (Option<Vec3>, u32) {
    let (hit, mut evaluations) = intersect(geometry, origin, direction, f64::INFINITY, settings);
    let Some(t) = hit else { return (None, evaluations) };
    let x = origin + direction * t;
    let (normal, attribute) = geometry.surface(x.as_vec3());
    let voxel = Voxel { normal, attribute, ..Voxel::default() };
    let light = (trace.light.position - x.as_vec3()).normalize_or_zero();
    let mut visibility = 1.0;
    if settings.shadow_rays_per_axis > 0 && normal.dot(light) > 0.0 {
        let (v, spent) = light_visibility(geometry, x, normal.as_dvec3(), trace, settings, seed);
        visibility = v;
        evaluations += spent;
    }
    let view = -direction.as_vec3();
    let radiance =
        element_radiance(&voxel, view, light, &trace.material, Filtering::Correlated, trace.light.radiance, visibility);
    (Some(radiance), evaluations)
}

/// The ground truth of pixel `(x, y)`: its radiance, coverage (the fraction of rays that
/// hit) and the distance evaluations of all its rays (in [`ConeResult::elements`]). The
/// light, material and background are `trace`'s; `settings` must be valid
/// ([`TruthSettings::validate`]), or zero-sized strata give a black, uncovered pixel.
pub fn truth_pixel<G: TruthGeometry + ?Sized>(
    geometry: &G,
    camera: &Camera,
    x: u32,
    y: u32,
    trace: &TraceSettings,
    settings: &TruthSettings,
) -> ConeResult {
    let cone = camera.pixel_cone(x, y);
    let pixel = y.wrapping_mul(camera.size().0).wrapping_add(x);
    let k = settings.rays_per_axis;
    let lens = cone.lens.filter(|l| l.aperture > 0.0);
    let m = if lens.is_some() { settings.lens_samples_per_axis } else { 1 };
    let (o, axis) = (cone.origin.as_dvec3(), cone.direction.as_dvec3());
    let (right, up, spread) = (cone.right.as_dvec3(), cone.up.as_dvec3(), f64::from(cone.spread));
    let (mut sum, mut hits, mut rays, mut evaluations) = (DVec3::ZERO, 0_u32, 0_u32, 0_u32);
    for j in 0..k {
        for i in 0..k {
            for lj in 0..m {
                for li in 0..m {
                    let sample = ((j * k + i) * m + lj) * m + li;
                    let jitter = |dimension| if settings.jitter { random(pixel, sample, dimension) } else { 0.5 };
                    let u = (f64::from(i) + jitter(0)) / f64::from(k) - 0.5;
                    // y down in the image, `up` up in the footprint: stratum rows top to bottom.
                    let v = 0.5 - (f64::from(j) + jitter(1)) / f64::from(k);
                    let d = axis + (right * u + up * v) * spread;
                    let (origin, direction) = match lens {
                        Some(lens) => {
                            let (a, b) = concentric(
                                (f64::from(li) + jitter(2)) / f64::from(m),
                                (f64::from(lj) + jitter(3)) / f64::from(m),
                            );
                            let start = o + (right * a + up * b) * (0.5 * f64::from(lens.aperture));
                            let focus = o + d * f64::from(lens.focus);
                            (start, (focus - start).normalize())
                        }
                        None => (o, d.normalize()),
                    };
                    let (radiance, spent) = shade_ray(geometry, origin, direction, trace, settings, (pixel, sample));
                    evaluations = evaluations.saturating_add(spent);
                    rays += 1;
                    match radiance {
                        Some(r) => {
                            sum += r.as_dvec3();
                            hits += 1;
                        }
                        None => sum += trace.background.as_dvec3(),
                    }
                }
            }
        }
    }
    let n = f64::from(rays.max(1));
    ConeResult { radiance: (sum / n).as_vec3(), coverage: (f64::from(hits) / n) as f32, elements: evaluations }
}

/// The ground truth of every pixel of `camera` on every core (see the module
/// documentation), with `trace`'s light, material and background.
pub fn render_truth<G: TruthGeometry + ?Sized>(
    geometry: &G,
    camera: &Camera,
    trace: &TraceSettings,
    settings: &TruthSettings,
) -> Result<Frame, RenderError> {
    settings.validate()?;
    let (width, height) = camera.size();
    let pixels = per_pixel(width, height, |x, y| {
        let r = truth_pixel(geometry, camera, x, y, trace, settings);
        (r.radiance, r.coverage, r.elements)
    });
    Frame::from_pixels(width, height, pixels)
}

/// [`render_truth`] of the unfiltered `source` in `domain`: eq. 2's ground truth.
pub fn render_source_truth<S: SurfaceSource + Sync + ?Sized>(
    source: &S,
    domain: Domain,
    camera: &Camera,
    trace: &TraceSettings,
    settings: &TruthSettings,
) -> Result<Frame, RenderError> {
    render_truth(&SourceGeometry { source, domain }, camera, trace, settings)
}

/// [`render_truth`] of the octree's finest level: the voxel truth.
pub fn render_voxel_truth(
    packed: &PackedTree,
    camera: &Camera,
    trace: &TraceSettings,
    settings: &TruthSettings,
) -> Result<Frame, RenderError> {
    render_truth(&VoxelGeometry { packed }, camera, trace, settings)
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Ball;

    impl TruthGeometry for Ball {
        fn domain(&self) -> Domain {
            Domain { origin: Vec3::splat(-1.0), size: 2.0 }
        }
        fn distance(&self, p: Vec3) -> Option<f32> {
            Some(p.length() - 0.5)
        }
        fn surface(&self, x: Vec3) -> (Vec3, [f32; 3]) {
            (x.normalize(), [1.0; 3])
        }
    }

    #[test]
    fn sphere_tracing_finds_the_exact_hit_and_misses_outside() {
        let settings = TruthSettings { epsilon: 1e-7, ..TruthSettings::default() };
        let (t, evaluations) = intersect(&Ball, DVec3::new(0.0, 0.0, -3.0), DVec3::Z, f64::INFINITY, &settings);
        assert!((t.unwrap() - 2.5).abs() < 1e-6, "{t:?}");
        assert!(evaluations < 10);
        let (t, _) = intersect(&Ball, DVec3::new(0.0, 0.6, -3.0), DVec3::Z, f64::INFINITY, &settings);
        assert!(t.is_none());
        let (t, _) = intersect(&Ball, DVec3::new(0.0, 0.0, -3.0), DVec3::Z, 2.0, &settings);
        assert!(t.is_none(), "beyond the limit");
        // Far from the origin an f32 parameter would stall; f64 does not.
        let (t, _) = intersect(&Ball, DVec3::new(0.0, 0.0, -1000.0), DVec3::Z, f64::INFINITY, &settings);
        assert!((t.unwrap() - 999.5).abs() < 1e-5);
    }

    #[test]
    fn the_concentric_map_fills_the_disk() {
        for (a, b) in [(0.0, 0.0), (0.99, 0.5), (0.5, 0.01), (0.3, 0.8)] {
            let (x, y) = concentric(a, b);
            assert!(x * x + y * y <= 1.0 + 1e-12);
        }
        let (x, y) = concentric(1.0, 0.5);
        assert!((x - 1.0).abs() < 1e-12 && y.abs() < 1e-12);
        assert!(random(3, 4, 5) < 1.0 && random(3, 4, 5) != random(3, 4, 6));
    }

    #[test]
    fn bad_settings_name_their_field() {
        let bad = TruthSettings { rays_per_axis: 0, ..TruthSettings::default() };
        assert!(matches!(bad.validate(), Err(RenderError::Setting { field: "TruthSettings::rays_per_axis", .. })));
        let bad = TruthSettings { epsilon: -1.0, ..TruthSettings::default() };
        assert!(matches!(bad.validate(), Err(RenderError::Setting { field: "TruthSettings::epsilon", .. })));
        assert!(TruthSettings::for_voxel(0.01, 4).validate().is_ok());
    }
}
