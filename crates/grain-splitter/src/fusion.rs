//! Occluder fusion: a conservative depth bound per pixel and its max pyramid (a "max Hi-Z"),
//! CPU reference in `f64`. Beyond the paper (§8 culls a grain only when the inner ball of the
//! single occluder at its centre's pixel hides it); here the occluders of every pixel a
//! grain covers vote together.
//!
//! # The bound per pixel
//!
//! Eye at the origin of view space. Pixel `p = (x, y)` covers the square
//! `[x, x+1] × [y, y+1]`; its rays are the conic hull of its four corner rays (the square
//! maps to a convex quadrilateral in a plane not through the eye, and the rays through it
//! are the non-negative combinations of the corners' rays). Let `B(g₀, r₀)` be the inner
//! ball of the pixel's occluder (from the occluder map), `|g₀| > r₀`. The rays meeting it
//! form the circular cone of axis `g₀/|g₀|` and half-angle `α`, `sin α = r₀/|g₀|`; more
//! generally `{d : ∠(d, g₀) ≤ β}` is a convex cone for every `β < π/2`. So if the four
//! corner rays are within `α` of the axis, every ray of the footprint is, and its largest
//! angle `β_max` is reached at a corner (the sublevel cone `β ≤ β_max` holds the corners,
//! hence their conic hull). A ray at angle `β ≤ α` enters the ball at
//! `t_e(β) = |g₀| cos β − √(r₀² − |g₀|² sin² β)`, whose derivative
//! `|g₀| sin β (|g₀| cos β / √(r₀² − |g₀|² sin² β) − 1)` is `≥ 0` (as `|g₀| ≥ r₀`): every
//! ray through the pixel meets the occluder by the distance `D(p) = t_e(β_max)`, the largest
//! of the corners' entries. Otherwise (a corner misses the ball, no occluder, eye inside the
//! ball) `D(p) = +∞`. `t_e` is evaluated as `(|g₀|² − r₀²)/(c + √(r₀² − |d × g₀|²))`,
//! `c = d·g₀` (no cancellation), the footprint is widened by [`FOOTPRINT_MARGIN_PX`] and
//! `D` raised by the relative [`DEPTH_MARGIN`], so rounding (and the `f32` rasteriser's
//! sub-pixel disagreements) cannot make it too small.
//!
//! # The grain test
//!
//! A grain's outer ball `B(g₁, R₁)` strictly in front of the eye (`|g₁| > R₁` and view depth
//! `> R₁`) projects inside a screen rectangle, [`projected_bounds`]: for the screen's `x`,
//! `ndc_x = a·v / (−v_z)` is a ratio of linear forms, and its extremes over the ball are where
//! the plane `(a − s n)·v = 0` through the eye (`n = −z`) is tangent to the ball,
//! `((a − s n)·g₁)² = R₁² |a − s n|²`, a quadratic in `s` whose two roots bound `ndc_x`
//! exactly (Mara & `McGuire` 2013's per-axis tangents, for any perspective matrix). Clamped to
//! the screen (rays off screen draw nothing; an empty rectangle is frustum culling's
//! business: not hidden). [`DepthPyramid::hides`] reads the level where the rectangle spans at
//! most 2 × 2 texels and takes the largest `D` there; the grain is hidden iff
//! `|g₁| − R₁ > D_max`: any point `y` of the ball on a ray through a pixel `p` of the
//! rectangle has `|y| ≥ |g₁| − R₁ > D(p)`, which is at least that ray's entry into the
//! pixel's occluder (a solid ball), so `y` is behind it. [`check_fusion`] verifies this by
//! casting rays.
//!
//! # Orthographic cameras
//!
//! No fusion: the rays are parallel, so the bound would be a depth along the view axis, not
//! a distance from an eye, with its own footprint argument; out of scope. The pyramid is then
//! all `+∞` and [`DepthPyramid::hides`] false. So is it for perspective matrices whose `x`/`y`
//! rows translate (the pixel rays would miss the eye).

use glam::{DVec3, Vec3, Vec4};

use crate::camera::SplitCamera;
use crate::decision::{NO_OCCLUDER, OccluderMap, decide};
use crate::lists::{CULLED_CONE, CULLED_FRUSTUM};
use crate::rays::{Rays, entry};
use crate::settings::SplitSettings;

pub use crate::rays::{DEPTH_MARGIN, FOOTPRINT_MARGIN_PX};

/// The conservative rectangle, in pixels `[x_min, x_max, y_min, y_max]` (unclamped, `y` down),
/// of the projection of the ball `B(centre_view, radius)` (view space); `None` for an
/// orthographic camera or a ball that is not strictly in front of the eye.
pub fn projected_bounds(camera: &SplitCamera, centre_view: DVec3, radius: f64) -> Option<[f64; 4]> {
    Rays::new(camera)?.bounds(centre_view, radius)
}

/// `D(p)` of pixel `(x, y)` for an occluder ball of centre `centre` (world space) and
/// radius `radius`: every ray through the pixel's footprint (widened by
/// [`FOOTPRINT_MARGIN_PX`]) meets the ball within this distance of the eye; `+∞` when a
/// corner ray misses it, the eye is inside it or the camera is orthographic (module docs).
pub fn occluder_bound(camera: &SplitCamera, (x, y): (u32, u32), centre: Vec3, radius: f64) -> f64 {
    Rays::new(camera).map_or(f64::INFINITY, |rays| rays.pixel_bound((x, y), rays.view(centre.as_dvec3()), radius))
}

/// A pyramid's first level being built: per pixel the smallest bound offered and the grain
/// whose inner ball it bounds (for the ray check).
pub(crate) struct BaseBounds {
    pub(crate) bound: Vec<f64>,
    pub(crate) owner: Vec<u32>,
}

impl BaseBounds {
    pub(crate) fn empty(pixels: usize) -> Self {
        Self { bound: vec![f64::INFINITY; pixels], owner: vec![NO_OCCLUDER; pixels] }
    }

    /// Keeps `bound` (of grain `owner`) at pixel `i` if it is smaller.
    pub(crate) fn offer(&mut self, i: usize, bound: f64, owner: u32) {
        if bound < self.bound[i] {
            self.bound[i] = bound;
            self.owner[i] = owner;
        }
    }
}

/// Level 0 of the map's pyramid: `D(p)` of each pixel's occluder (`+∞` where there is none,
/// or where fusion does not apply).
pub(crate) fn map_bounds(
    camera: &SplitCamera,
    settings: &SplitSettings,
    grains: &[Vec4],
    map: &OccluderMap,
) -> BaseBounds {
    let (width, height) = camera.size();
    let mut base = BaseBounds::empty(width as usize * height as usize);
    let radius = f64::from(settings.occluder_radius);
    if let Some(rays) = Rays::new(camera).filter(|_| (map.width, map.height) == (width, height) && radius > 0.0) {
        for y in 0..height {
            for x in 0..width {
                let Some(id) = map.get((x, y)) else { continue };
                let Some(&grain) = grains.get(id as usize) else { continue };
                let g0 = rays.view(grain.truncate().as_dvec3());
                base.offer((y * width + x) as usize, rays.pixel_bound((x, y), g0, radius * f64::from(grain.w)), id);
            }
        }
    }
    base
}

/// The per-pixel bounds `D(p)` (level 0) and their max pyramid.
#[derive(Clone, Debug, PartialEq)]
pub struct DepthPyramid {
    levels: Vec<(u32, u32, Vec<f64>)>,
    /// Per level-0 pixel, the grain its bound comes from ([`NO_OCCLUDER`]: none).
    owners: Vec<u32>,
}

impl DepthPyramid {
    /// The pyramid of `map` (the occluder map of `grains` for `camera`). All `+∞` (no fusion)
    /// for an orthographic camera, settings with no solid core, or a map whose size is not the
    /// camera's; texels whose id is not a grain are empty.
    pub fn build(camera: &SplitCamera, settings: &SplitSettings, grains: &[Vec4], map: &OccluderMap) -> Self {
        let (width, height) = camera.size();
        Self::from_base(width, height, map_bounds(camera, settings, grains, map))
    }

    pub(crate) fn from_base(width: u32, height: u32, BaseBounds { bound: base, owner: owners }: BaseBounds) -> Self {
        let mut levels = vec![(width, height, base)];
        while let Some((w, h, texels)) = levels.last().filter(|(w, h, _)| *w > 1 || *h > 1) {
            let (nw, nh) = (w.div_ceil(2), h.div_ceil(2));
            let mut next = vec![0.0f64; nw as usize * nh as usize];
            for y in 0..*h {
                for x in 0..*w {
                    let slot = &mut next[((y / 2) * nw + x / 2) as usize];
                    *slot = slot.max(texels[(y * w + x) as usize]);
                }
            }
            levels.push((nw, nh, next));
        }
        Self { levels, owners }
    }

    /// The number of levels (level 0 is the screen, the last is 1 × 1).
    pub fn levels(&self) -> usize {
        self.levels.len()
    }

    /// Level `k`: `(width, height, texels)` row-major; `None` past the last level.
    pub fn level(&self, k: usize) -> Option<(u32, u32, &[f64])> {
        self.levels.get(k).map(|(w, h, t)| (*w, *h, t.as_slice()))
    }

    /// The grain whose inner ball bounds pixel `(x, y)` of level 0.
    pub fn owner(&self, (x, y): (u32, u32)) -> Option<u32> {
        let (w, h, _) = self.level(0)?;
        if x >= w || y >= h {
            return None;
        }
        self.owners.get((y * w + x) as usize).copied().filter(|&id| id != NO_OCCLUDER)
    }

    /// How many pixels have a finite bound.
    pub fn finite_pixels(&self) -> usize {
        self.levels.first().map_or(0, |(_, _, t)| t.iter().filter(|d| d.is_finite()).count())
    }

    fn checked(&self, camera: &SplitCamera, centre_view: DVec3, radius: f64) -> Option<([u32; 4], f64)> {
        let rays = Rays::new(camera)?;
        let (w, h, _) = self.level(0)?;
        if camera.size() != (w, h) {
            return None;
        }
        let near = centre_view.length() - radius;
        Some((rays.rect(centre_view, radius)?, near))
    }

    /// Whether the outer ball `B(centre_view, outer_radius)` (view space) is hidden by the
    /// fused occluders, reading at most 2 × 2 texels of the level where its rectangle fits
    /// (module docs). False when the ball reaches the eye or the near side, is off screen,
    /// or the camera is orthographic or not the pyramid's.
    pub fn hides(&self, camera: &SplitCamera, centre_view: DVec3, outer_radius: f64) -> bool {
        let Some(([x0, x1, y0, y1], near)) = self.checked(camera, centre_view, outer_radius) else { return false };
        let k = (0..self.levels.len())
            .find(|&k| (x1 >> k) - (x0 >> k) <= 1 && (y1 >> k) - (y0 >> k) <= 1)
            .unwrap_or(self.levels.len() - 1);
        let Some((w, _, texels)) = self.level(k) else { return false };
        let mut bound = 0.0f64;
        for y in (y0 >> k)..=(y1 >> k) {
            for x in (x0 >> k)..=(x1 >> k) {
                bound = bound.max(texels.get((y * w + x) as usize).copied().unwrap_or(f64::INFINITY));
            }
        }
        near > bound
    }

    /// [`DepthPyramid::hides`] for a grain `(centre, scale)` in world space (view transform
    /// in `f64`) whose outer radius at scale 1 is `outer_radius`.
    pub fn hides_grain(&self, camera: &SplitCamera, grain: Vec4, outer_radius: f32) -> bool {
        let Some(rays) = Rays::new(camera) else { return false };
        let radius = f64::from(outer_radius) * f64::from(grain.w);
        self.hides(camera, rays.view(grain.truncate().as_dvec3()), radius)
    }

    /// As [`DepthPyramid::hides`], scanning every level-0 pixel of the rectangle (tighter,
    /// slower: for measurements).
    pub fn hides_exact_rect(&self, camera: &SplitCamera, centre_view: DVec3, outer_radius: f64) -> bool {
        let Some(([x0, x1, y0, y1], near)) = self.checked(camera, centre_view, outer_radius) else { return false };
        let Some((w, _, texels)) = self.level(0) else { return false };
        (y0..=y1).all(|y| (x0..=x1).all(|x| texels.get((y * w + x) as usize).is_some_and(|&d| near > d)))
    }
}

/// What one frame culls with and without fusion (state 0: no hysteresis history).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FusionCounts {
    /// Grains in the scene.
    pub grains: u32,
    /// Culled by the frustum test.
    pub frustum: u32,
    /// Culled by the single-occluder cone test (Listing 2).
    pub cone: u32,
    /// Culled by fusion and not by the cone: what fusion adds.
    pub fusion_only: u32,
    /// Culled by both.
    pub both: u32,
    /// Drawn with the frustum and cone tests: `grains − frustum − cone`.
    pub visible_after_cone: u32,
    /// Drawn with fusion too: `visible_after_cone − fusion_only`.
    pub visible_after_fusion: u32,
}

impl FusionCounts {
    /// Every grain the pyramid hides among those in the frustum.
    pub fn fusion(&self) -> u32 {
        self.fusion_only + self.both
    }
}

/// The counts of [`FusionCounts`]: [`decide`] for the frustum and cone tests, and the
/// pyramid of `map` ([`DepthPyramid::hides`]) for the grains not frustum-culled; culled =
/// cone or fusion.
pub fn fused_split_counts(
    camera: &SplitCamera,
    settings: &SplitSettings,
    grains: &[Vec4],
    map: &OccluderMap,
) -> FusionCounts {
    let pyramid = DepthPyramid::build(camera, settings, grains, map);
    let mut counts = FusionCounts { grains: grains.len().min(u32::MAX as usize) as u32, ..Default::default() };
    for index in 0..counts.grains {
        let grain = grains[index as usize];
        let model = decide(camera, settings, grains, map, index, 0).model;
        if model == CULLED_FRUSTUM {
            counts.frustum += 1;
            continue;
        }
        let cone = model == CULLED_CONE;
        let fusion = pyramid.hides_grain(camera, grain, settings.outer_radius);
        counts.cone += u32::from(cone);
        counts.both += u32::from(cone && fusion);
        counts.fusion_only += u32::from(fusion && !cone);
    }
    counts.visible_after_cone = counts.grains - counts.frustum - counts.cone;
    counts.visible_after_fusion = counts.visible_after_cone - counts.fusion_only;
    counts
}

/// The outcome of [`check_fusion`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FusionCheck {
    /// Grains the pyramid culls, each checked.
    pub culled_checked: u32,
    /// Rays cast (landing on screen).
    pub rays: u64,
    /// Rays that reach a point of the culled grain's outer ball before any occluder: must be 0.
    pub violations: u64,
}

/// `SplitMix64` (Steele, Lea & Flood 2014).
struct SplitMix64(u64);

impl SplitMix64 {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `[-1, 1)`.
    fn signed(&mut self) -> f64 {
        (self.next() >> 11) as f64 * (2.0 / (1u64 << 53) as f64) - 1.0
    }

    /// Uniform in the unit ball (rejection).
    fn in_ball(&mut self) -> DVec3 {
        loop {
            let v = DVec3::new(self.signed(), self.signed(), self.signed());
            if v.length_squared() <= 1.0 {
                return v;
            }
        }
    }
}

/// Checks `pyramid` (of `grains` for `camera`) by brute force: for every grain it culls,
/// casts `rays_per_grain` rays from the eye through uniform random points of its outer ball
/// that land on screen, finds the pixel each crosses, and verifies in `f64` that the ray
/// enters the inner ball of the grain that bounds that pixel ([`DepthPyramid::owner`])
/// before its first point in the culled grain's outer ball. Nothing is checked for an
/// orthographic camera (nothing is culled).
pub fn check_fusion(
    camera: &SplitCamera,
    settings: &SplitSettings,
    grains: &[Vec4],
    pyramid: &DepthPyramid,
    rays_per_grain: u32,
    seed: u64,
) -> FusionCheck {
    let mut check = FusionCheck::default();
    let Some(rays) = Rays::new(camera) else { return check };
    let mut random = SplitMix64(seed);
    let inner = f64::from(settings.occluder_radius);
    for grain in grains {
        let g1 = rays.view(grain.truncate().as_dvec3());
        let radius = f64::from(settings.outer_radius) * f64::from(grain.w);
        if !pyramid.hides(camera, g1, radius) {
            continue;
        }
        check.culled_checked += 1;
        let mut cast = 0;
        for _ in 0..rays_per_grain.saturating_mul(8) {
            if cast == rays_per_grain {
                break;
            }
            let y = g1 + random.in_ball() * radius;
            let Some((px, py)) = rays.pixel(y) else { continue };
            if !(0.0..rays.width).contains(&px) || !(0.0..rays.height).contains(&py) {
                continue;
            }
            cast += 1;
            let d = y.normalize();
            let grain_entry = entry(d, g1, radius).unwrap_or(0.0);
            let occluder = pyramid.owner((px as u32, py as u32)).and_then(|id| grains.get(id as usize));
            let hidden = occluder.and_then(|o| entry(d, rays.view(o.truncate().as_dvec3()), inner * f64::from(o.w)));
            if !hidden.is_some_and(|t| t < grain_entry) {
                check.violations += 1;
            }
        }
        check.rays += u64::from(cast);
    }
    check
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::{NO_OCCLUDER, occluder_map};
    use crate::tiers::TierThresholds;
    use glam::Vec3;
    use occlusion_cone::{Exact, hidden_exact};

    fn settings(ratio: f32) -> SplitSettings {
        SplitSettings::new(ratio, 1.0, TierThresholds::new(2.0, 64.0, 1.1).unwrap())
    }

    /// `n³` grains on a jittered lattice of spacing 1, scales `scale ± 0.05`.
    fn lattice(n: u32, scale: f32, seed: u64) -> Vec<Vec4> {
        let mut random = SplitMix64(seed);
        let half = (n as f32 - 1.0) * 0.5;
        let mut grains = Vec::with_capacity((n * n * n) as usize);
        for i in 0..n {
            for j in 0..n {
                for k in 0..n {
                    let jitter =
                        Vec3::new(random.signed() as f32, random.signed() as f32, random.signed() as f32) * 0.12;
                    let centre = Vec3::new(i as f32, j as f32, k as f32) - half + jitter;
                    grains.push(centre.extend(scale + 0.05 * random.signed() as f32));
                }
            }
        }
        grains
    }

    fn camera(fov: f32, distance: f32) -> SplitCamera {
        let eye = Vec3::new(0.55, 0.4, 0.73).normalize() * distance;
        SplitCamera::perspective(eye, Vec3::ZERO, Vec3::Y, fov, (320, 240), (0.1, 500.0)).unwrap()
    }

    #[test]
    fn dense_lattice_fusion_is_conservative_and_counts_are_printed() {
        // Touching grains (R ≈ 0.55 spacing) and interpenetrating ones (0.85); the paper's
        // splat factor and a larger one.
        let mut checked = vec![];
        for scale in [0.55, 0.85] {
            let grains = lattice(22, scale, 7);
            for ratio in [0.9, 0.5] {
                for (fov, distance) in [(1.0, 42.0), (0.3, 90.0)] {
                    for splat_factor in [0.2, 0.5] {
                        let camera = camera(fov, distance);
                        let settings = SplitSettings { splat_factor, ..settings(ratio) };
                        let map = occluder_map(&camera, &settings, &grains);
                        let counts = fused_split_counts(&camera, &settings, &grains, &map);
                        let pyramid = DepthPyramid::build(&camera, &settings, &grains, &map);
                        let check = check_fusion(&camera, &settings, &grains, &pyramid, 16, 11);
                        let pyramid = DepthPyramid::build(&camera, &settings, &grains, &map);
                        let rays = Rays::new(&camera).unwrap();
                        let exact = grains
                            .iter()
                            .filter(|g| {
                                pyramid.hides_exact_rect(&camera, rays.view(g.truncate().as_dvec3()), f64::from(g.w))
                            })
                            .count();
                        println!(
                            "scale {scale} r/R {ratio} fov {fov} k {splat_factor}: grains {} frustum {} cone {} \
                             fusion {} (only {}, both {}) exact-rect {exact} visible {} -> {} | filled {} finite {} \
                             | checked {} rays {} violations {}",
                            counts.grains,
                            counts.frustum,
                            counts.cone,
                            counts.fusion(),
                            counts.fusion_only,
                            counts.both,
                            counts.visible_after_cone,
                            counts.visible_after_fusion,
                            map.filled(),
                            pyramid.finite_pixels(),
                            check.culled_checked,
                            check.rays,
                            check.violations,
                        );
                        assert_eq!(check.violations, 0);
                        assert_eq!(check.culled_checked == 0, check.rays == 0);
                        assert!(exact >= counts.fusion() as usize, "the exact rectangle culls at least the pyramid's");
                        assert_eq!(counts.frustum + counts.cone + counts.visible_after_cone, counts.grains);
                        checked.push(check.culled_checked);
                    }
                }
            }
        }
        println!("culled and checked per configuration: {checked:?}");
        assert!(checked[0] > 0, "touching grains, r/R 0.9, wide field, paper splats");
        assert!(checked.iter().filter(|&&c| c > 0).count() >= 4);
    }

    #[test]
    fn the_rectangle_contains_the_projected_ball() {
        let camera = camera(1.0, 30.0);
        let rays = Rays::new(&camera).unwrap();
        let mut random = SplitMix64(3);
        let mut tested = 0;
        for _ in 0..400 {
            let g = DVec3::new(random.signed() * 12.0, random.signed() * 9.0, -2.0 - 20.0 * (random.signed() + 1.0));
            let radius = 0.1 + 3.0 * (random.signed() + 1.0);
            let Some([x0, x1, y0, y1]) = rays.bounds(g, radius) else {
                assert!(-g.z - radius <= 0.0 || g.length() <= radius);
                continue;
            };
            tested += 1;
            for _ in 0..200 {
                let p = random.in_ball();
                // Half the samples on the sphere, where the extremes lie.
                let p = if p.length_squared() > 0.25 { p.normalize() } else { p };
                let (px, py) = rays.pixel(g + p * radius).unwrap();
                let slack = 1e-9 * (1.0 + px.abs() + py.abs());
                assert!(px >= x0 - slack && px <= x1 + slack && py >= y0 - slack && py <= y1 + slack);
            }
        }
        assert!(tested > 100, "{tested}");
    }

    #[test]
    fn empty_pixels_have_no_bound_and_covered_ones_a_finite_one() {
        let camera =
            SplitCamera::perspective(Vec3::new(0.0, 0.0, 20.0), Vec3::ZERO, Vec3::Y, 0.6, (64, 48), (0.1, 100.0))
                .unwrap();
        let settings = settings(0.8);
        let grains = [Vec4::new(0.0, 0.0, 0.0, 1.0)];
        let map = occluder_map(&camera, &settings, &grains);
        let pyramid = DepthPyramid::build(&camera, &settings, &grains, &map);
        let (w, h, d) = pyramid.level(0).unwrap();
        assert_eq!((w, h), (64, 48));
        for (i, &id) in map.ids.iter().enumerate() {
            if id == NO_OCCLUDER {
                assert_eq!(d[i], f64::INFINITY);
            } else {
                assert!(d[i] > 19.2 - 1e-9 && d[i] < 20.0, "{}", d[i]);
            }
        }
        assert!(pyramid.finite_pixels() > 0 && pyramid.finite_pixels() == map.filled());
        let (tw, th, top) = pyramid.level(pyramid.levels() - 1).unwrap();
        assert_eq!((tw, th, top), (1, 1, &[f64::INFINITY][..]));
        assert!(pyramid.level(pyramid.levels()).is_none());
        // Orthographic: no fusion.
        let projection = grain_impostor::scene::orthographic_rh(2.0, 0.5, 10.0);
        let ortho = SplitCamera::from_matrices(glam::Mat4::IDENTITY, projection, (32, 32)).unwrap();
        let flat = DepthPyramid::build(&ortho, &settings, &grains, &occluder_map(&ortho, &settings, &grains));
        assert_eq!(flat.finite_pixels(), 0);
        assert!(!flat.hides(&ortho, DVec3::new(0.0, 0.0, -5.0), 0.1));
    }

    #[test]
    fn two_occluders_side_by_side_hide_a_grain_behind_their_common_edge() {
        // Eye at the origin looking down −z, 64 × 64 pixels, 58.6 pixels per unit of x/z.
        let camera = SplitCamera::perspective(Vec3::ZERO, Vec3::NEG_Z, Vec3::Y, 1.0, (64, 64), (0.1, 100.0)).unwrap();
        let settings = SplitSettings { splat_factor: 0.6, ..settings(0.9) };
        // Inner radius 2.22 (13 pixels at depth 10), centres 6.5 pixels either side of the
        // centre, the right one nearer (it owns the shared texels); behind, a grain of 7 pixels.
        let grains =
            [Vec4::new(-1.11, 0.0, -10.0, 2.47), Vec4::new(1.10, 0.0, -9.9, 2.47), Vec4::new(0.0, 0.0, -30.0, 3.59)];
        let map = occluder_map(&camera, &settings, &grains);
        let out = crate::reference::split(&camera, &settings, &grains, &map, &[]).unwrap();
        assert_eq!(out.counters.culled, [0, 0, 1, 0], "the cone test culls nothing, the Hi-Z test one");
        let cone_only = SplitSettings { hiz_culling: false, ..settings };
        let out = crate::reference::split(&camera, &cone_only, &grains, &map, &[]).unwrap();
        assert_eq!(out.counters.culled, [0, 0, 0, 0]);
        // Neither occluder alone hides it, exactly.
        let grain = DVec3::new(0.0, 0.0, -30.0);
        for o in &grains[..2] {
            let exact = hidden_exact(o.truncate().as_dvec3(), 0.9 * f64::from(o.w), grain, 3.59);
            assert_ne!(exact, Exact::Hidden);
        }
        let pyramid = DepthPyramid::build(&camera, &settings, &grains, &map);
        assert!(pyramid.hides(&camera, grain, 3.59), "fused, they do");
        assert!(pyramid.hides_exact_rect(&camera, grain, 3.59));
        assert!(!pyramid.hides(&camera, DVec3::new(0.0, 0.0, -12.0), 3.59), "not when it reaches their depth");
        let counts = fused_split_counts(&camera, &settings, &grains, &map);
        assert_eq!((counts.cone, counts.fusion_only, counts.visible_after_fusion), (0, 1, 2));
        let check = check_fusion(&camera, &settings, &grains, &pyramid, 2000, 5);
        assert_eq!((check.culled_checked, check.violations), (1, 0));
        assert!(check.rays == 2000, "{}", check.rays);
    }

    #[test]
    fn bad_input_is_not_hidden() {
        let camera = camera(1.0, 30.0);
        let settings = settings(0.9);
        let grains = lattice(4, 0.55, 1);
        let map = occluder_map(&camera, &settings, &grains);
        let pyramid = DepthPyramid::build(&camera, &settings, &grains, &map);
        for (g, r) in [(DVec3::NAN, 1.0), (DVec3::new(0.0, 0.0, -5.0), f64::NAN), (DVec3::new(0.0, 0.0, 1.0), 0.5)] {
            assert!(!pyramid.hides(&camera, g, r) && !pyramid.hides_exact_rect(&camera, g, r));
        }
        assert!(!pyramid.hides(&camera, DVec3::new(0.0, 0.0, -1.0), 2.0), "reaches the eye");
        assert!(!pyramid.hides(&camera, DVec3::new(500.0, 0.0, -10.0), 0.5), "off screen");
        // A map of another size: no fusion, no panic.
        let small = OccluderMap { width: 2, height: 2, ids: vec![0; 4] };
        assert_eq!(DepthPyramid::build(&camera, &settings, &grains, &small).finite_pixels(), 0);
        let other = SplitCamera::perspective(Vec3::Z * 30.0, Vec3::ZERO, Vec3::Y, 1.0, (16, 16), (0.1, 100.0)).unwrap();
        assert!(!pyramid.hides(&other, DVec3::new(0.0, 0.0, -20.0), 0.5));
    }
}
