//! Algorithm 1: one cone through the octree, element by element, its coverage combined as
//! an A-buffer mask (§5.3–5.4), with the paper's baselines as modes of the same loop.
//!
//! # Cone elements
//!
//! Element `d` is a cylinder centred at `z_d` on the axis, of radius `r_d = w(z_d)/2` and
//! half-length `l_d = max(r_d, κ S₀)` (`S₀` the finest voxel): the paper's "length equals
//! diameter" takes thousands of elements per voxel when the cone is thinner than a voxel,
//! so the half-length is floored (`GigaVoxels` floors its step at ~0.66 voxel: `κ = 0.33`).
//! Elements are contiguous, `z_{d+1} = z_d + 2 l_d`, from the cone's entry into the domain
//! to its exit. The level of detail is `λ = log₂(w / S₀)` (clamped by the sampler).
//!
//! # Per element ([`Model::Masks`], Algorithm 1)
//!
//! The sample's plane `(h̄, n̄)`, with `n̄` in the footprint's frame (turned by π where a lens
//! cone has crossed its axis), gives `(θ, v)` (`abuffer_mask::HalfPlane`), the table gives
//! the mask `1_A`, and `L += L_d popcount(1_A ∖ α)/N`, `α ∪= 1_A`; the cone stops when `α` is
//! full. The baselines:
//!
//! - [`Model::AlphaBlend`]: the same octree and elements, but the element's opacity is the
//!   exact covered fraction of its footprint, composited front to back (eq. 12, the volume
//!   model of `GigaVoxels`, Fig. 10b);
//! - [`Model::Nearest`]: the nearest voxel of the nearest level, opaque where `h̄ ≤ 0`
//!   (Fig. 10a, Carmack's SVO);
//! - [`Model::SeparateFiltering`]: masks, but shading with `a_s = 0` and the lobe `σnp`
//!   only (Fig. 11–12's naive filtering).
//!
//! # Where an element is shaded (beyond the paper)
//!
//! Algorithm 1 shades an element with the sample at its centre `p_d`. Where the cone is
//! wider than a finest voxel (`λ ≥ 1`) that sample is a prefiltered mean over the element's
//! footprint, centred there, and the centre shades, as in the paper. Where it is thinner
//! (`λ ≤ 0`, magnified), the finest level holds the surface's own attributes (no variance,
//! §5.2), but the element's half-length is floored at `κ S₀ ≫ r_d`, and an element that adds
//! coverage has `|h̄| ≤ l_d + 2 r_d`: its centre can lie a third of a voxel off the surface,
//! where the trilinear colour and normal blend vertex samples the pixel never sees. So it
//! is shaded by the octree sampled at the point `x` of its plane `(h̄, n̂)` (§5.4) that the
//! cone's axis `d` sees: the axis meets the plane at `t = −h̄ / (n̂·d)` from `p_d`; `t` is
//! kept within the element (`|t| ≤ l_d`), and `x = p_d + t d − (h̄ + t n̂·d) n̂` is that
//! point of the axis projected onto the plane. (The foot of the centre, `p_d − h̄ n̂`, is
//! off by `|h̄| tan φ` along the surface at a view angle `φ`: half a voxel at 60°, many
//! pixels of a magnified view.) The plane is the distance's tangent at `p_d`, and a curved
//! surface departs from it by the curvature times the square of the distance, so `x` is
//! refined by [`SHADING_POINT_REFINEMENTS`] (2) Newton steps along the axis: each samples
//! the octree at the last point and moves to where the axis meets that sample's plane, the
//! axis parameter kept within the element (`|t| ≤ l_d`) throughout, so that the point never
//! leaves the element it shades (steps free to wander moved silhouette and grazing pixels
//! to surfaces beyond it: ꟻLIP at 85° 0.063 → 0.088 in `svo-render`'s grazing sweep, 0.078
//! kept within). On a plane of linear colour the first point is exact. Between the two
//! regimes, `0 < λ < 1`, the point moves linearly from `x` towards `p_d` in `λ`, so that a
//! zoom sees no jump. Coverage is still the centre's plane. Where the point leaves the
//! domain or falls in an empty node, the centre's sample shades; [`Model::Nearest`] always
//! shades the voxel it hits (Fig. 10a). The light direction and the shadow cone start from
//! the shading point projected onto the last plane sampled (for `λ ≥ 1` the foot of the
//! centre, as before), as the truth's start from its hit (`tests/shading_point.rs`: a
//! magnified plane of linear colour is shaded as at each axis's hit; at the centre or the
//! foot it fails).
//!
//! Why not `x` at every level: where a feature is thinner than the level's voxels (H7),
//! the mean normal at its surface cancels (a plate's two faces), while the sample in front
//! of it, at the centre, still carries the facing side's; shading at `x` there darkened a
//! 3-voxel plate seen from afar by 0.25 → 0.30 RMSE (`svo-render`'s thin-plate sweep).
//!
//! Measured on `cargo xtask svo --quick` (the bumpy sphere against its supersampled
//! source), the masks' ꟻLIP at 1, 0.26 and 0.064 pixels per voxel goes from 0.031, 0.118,
//! 0.148 (shaded at centres) to 0.024, 0.091, 0.111 at `x`, and 0.022, 0.082, 0.084 with the
//! steps, against 0.026, 0.080, 0.059 for the finest voxels traced with one ray per pixel.
//! Where the paper's hypotheses fail it is not always better (`svo-stability --quick`): a
//! sphere of radius 2 voxels seen magnified 0.071 → 0.077, grazing views at 85° 0.063 →
//! 0.078, while 0° goes 0.110 → 0.098 (`docs/failure-modes.md` §2.4).
//!
//! # Empty-space skip (beyond the paper)
//!
//! An element whose sample has `h̄ > l_d + 2 r_d` covers nothing (the half-plane misses the
//! footprint). The last sample proves a lower bound of the source's distance at its point
//! (the sample minus [`error_bound`]'s interpolation error, or the sample itself in an
//! empty node), and the distance is 1-Lipschitz, so later elements are skipped while that
//! bound, less their own error bound and the distance travelled, stays above `l + 2r`; and
//! elements inside an empty node (at levels it answers for) are skipped to its exit. A
//! skipped element still advances `z` by `2 l`, so the elements that are sampled, and the
//! image, are the same bits with and without the skip (a test checks it).
//!
//! # Shadows
//!
//! With a light, each of the first [`TraceSettings::shadow_cones`] elements that add
//! coverage casts a shadow cone towards the light's centre, starting at the element's width
//! and widening linearly to the light's diameter at the light; it is traced like a pixel
//! cone with its own mask, and `V̄(l) = 1 −` its coverage. Later elements reuse the last
//! visibility.
//!
//! **Where a shadow cone starts** ([`light_visibility`]). The elements that fill the rest of
//! a pixel's mask lie deeper in the surface (`h̄ < 0`): a cone started at the element's
//! centre, or a fixed offset from it, begins inside the surface's own reach and shadows its
//! own surface (7–18 % too dark on a lit sphere with 4 cones). So the cone starts from the
//! element's surface point `x` on its plane `(h̄, n̂)` (its shading point projected onto the
//! plane, see "Where an element is shaded"; §5.4, H6), lifted along `n̂` by just what keeps its own first element off that plane.
//! Element `e` of the shadow cone (centre `c`, radius `r_e`, half-length `l_e`, footprint
//! `[−1, 1]²`) covers nothing when its sample has `h̄(c) > l_e |n_z| + √2 r_e ‖n_xy‖` (the
//! mask test `v ≤ −√2`, `abuffer_mask::HalfPlane`), and by Cauchy–Schwarz
//! (`n_z² + ‖n_xy‖² ≤ 1`) that holds whatever its sampled normal when
//! `h̄(c) > ρ_e = √(l_e² + 2 r_e²)`, the element's circumradius. The first element's centre
//! lies at `t₁ = l(0)` along the axis `d` from the start `x + δ n̂`, at the height
//! `δ + t₁ (n̂·d)` above the plane, so
//!
//! ```text
//! δ = ρ₁ − t₁ (n̂·d)
//! ```
//!
//! puts its circumsphere on the plane — for the source's distance. The octree's distance is
//! not the source's: at the finest level it interpolates vertex samples trilinearly, so
//! between them it departs from the distance (and from the plane `(h̄, n̂)` sampled at `p_d`)
//! by up to `(√3/2) S₀` (the trilinear weights' `Σ w_k |c_k − p| ≤ (√3/2) S₀` for a
//! 1-Lipschitz distance). With the start exactly on the circumsphere, any such deficit
//! covers part of the first elements' masks: on the magnified bumpy sphere one shadow cone
//! darkened the frame by 26 % (4 cones: 42 %) where the truth is lit, in contour bands of the
//! elements' depth. So the start is lifted by `(√3/2) S₀` more (`SHADOW_LIFT_VOXELS`):
//!
//! ```text
//! δ = ρ₁ − t₁ (n̂·d) + (√3/2) S₀
//! ```
//!
//! which costs the contact shadows of occluders closer than that to the surface — below the
//! finest voxel, where the octree represents no occluder anyway (H7). On a convex body the
//! sampled `h̄(c)` is at least the height of `c` above the tangent plane at `x` (the body
//! lies below that plane, and the box
//! means and multilinear interpolation of a convex distance are at least the distance,
//! Jensen), so the first element covers nothing; a later element at `t` rises by
//! `t (n̂·d)` while its circumradius grows by at most `√3 |R − r| t / D` (`R` the light's
//! radius, `r` the start radius, `D` the light's distance), so no element covers anything
//! as long as `n̂·l ≥ √3 |R − r| / D`: an unshadowed convex surface keeps `V̄ = 1` except in
//! that band above its terminator, where the light's disk itself starts to set (`n̂·l <
//! R/D`). A real occluder farther along the cone is seen as before; the microsurface's own
//! occlusion below the element's scale is not the shadow cone's (H1: it is local, in
//! `L_d`).

use abuffer_mask::{HalfPlane, Mask, MaskTable};
use glam::Vec3;
use svo_brick::{EmptyRegion, FRACTION_STEPS, PackedTree, Voxel};

use crate::camera::Cone;
use crate::shading::{Filtering, Material, element_radiance, tangent_frame};

/// How a cone combines its elements.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Model {
    /// The paper's: A-buffer masks and correlated shading.
    Masks,
    /// α-blending of exact element opacities (eq. 12).
    AlphaBlend,
    /// Nearest voxel, 0/1 occupancy.
    Nearest,
    /// Masks with separately filtered colour and normals.
    SeparateFiltering,
}

impl Model {
    /// Every model.
    pub const ALL: [Model; 4] = [Model::Masks, Model::AlphaBlend, Model::Nearest, Model::SeparateFiltering];

    /// A short name for tables.
    pub const fn name(self) -> &'static str {
        match self {
            Model::Masks => "masks",
            Model::AlphaBlend => "alpha-blend",
            Model::Nearest => "nearest",
            Model::SeparateFiltering => "separate",
        }
    }

    fn filtering(self) -> Filtering {
        if self == Model::SeparateFiltering { Filtering::Separate } else { Filtering::Correlated }
    }
}

/// A spherical light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    /// The centre.
    pub position: Vec3,
    /// The radius (the shadow cones widen to its diameter).
    pub radius: f32,
    /// `Ē`, the radiance it delivers (no fall-off).
    pub radiance: f32,
}

/// Everything a cone needs besides the octree.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TraceSettings {
    /// The model.
    pub model: Model,
    /// `κ`: the elements' half-length floor in finest voxels.
    pub min_half_length: f32,
    /// At most this many elements per cone (sampled or skipped, so that skipping never
    /// changes where a cone stops).
    pub max_elements: u32,
    /// Skip elements proven empty (see the module documentation); the image is the same
    /// bits either way.
    pub empty_space_skip: bool,
    /// Shadow cones per pixel cone (0: no shadows).
    pub shadow_cones: u32,
    /// The light.
    pub light: Light,
    /// The material.
    pub material: Material,
    /// The colour behind the geometry.
    pub background: Vec3,
}

impl Default for TraceSettings {
    fn default() -> Self {
        Self {
            model: Model::Masks,
            min_half_length: 0.33,
            max_elements: 4096,
            empty_space_skip: true,
            shadow_cones: 0,
            light: Light { position: Vec3::new(10.0, 20.0, 30.0), radius: 1.0, radiance: 3.0 },
            material: Material::default(),
            background: Vec3::ZERO,
        }
    }
}

/// What one cone returns.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ConeResult {
    /// The pixel's radiance, background included.
    pub radiance: Vec3,
    /// The covered fraction of the footprint.
    pub coverage: f32,
    /// Elements sampled (skipped ones not counted).
    pub elements: u32,
}

/// `[z_enter, z_exit]` of the ray `origin + z direction` in the box `[lo, hi]`, `None` if it
/// misses (slab test).
pub fn box_interval(origin: Vec3, direction: Vec3, lo: Vec3, hi: Vec3) -> Option<(f32, f32)> {
    let inverse = direction.recip();
    let (a, b) = ((lo - origin) * inverse, (hi - origin) * inverse);
    let (near, far) = (a.min(b), a.max(b));
    let enter = near.max_element().max(0.0);
    let exit = far.min_element();
    (enter <= exit && exit.is_finite()).then_some((enter, exit))
}

/// The footprint's frame and width along one cone (a pixel's, or a shadow cone).
struct ConeGeometry<'a> {
    origin: Vec3,
    direction: Vec3,
    right: Vec3,
    up: Vec3,
    width: &'a dyn Fn(f32) -> f32,
    crossed: &'a dyn Fn(f32) -> bool,
}

/// The coverage state of one cone.
enum Coverage<const W: usize> {
    Mask(Mask<W>),
    Alpha(f32),
}

impl<const W: usize> Coverage<W> {
    fn fraction(&self) -> f32 {
        match self {
            Coverage::Mask(mask) => mask.coverage(),
            Coverage::Alpha(alpha) => *alpha,
        }
    }
}

/// The octree's domain in world units.
fn domain(tree: &PackedTree) -> (Vec3, Vec3) {
    let u = tree.uniforms();
    let lo = u.origin_inverse_size.truncate();
    (lo, lo + u.voxel_size.x * u.counts.z as f32)
}

/// The margin a shadow cone adds to its start, in finest voxels: `√3/2`, the most the
/// finest level's trilinear distance departs from the distance between its vertex samples
/// (see the module documentation, "Where a shadow cone starts").
pub(crate) const SHADOW_LIFT_VOXELS: f32 = 0.866_025_4;

/// Newton steps that refine a magnified element's shading point along its axis, each from
/// the octree's sample at the last point (see the module documentation, "Where an element
/// is shaded").
pub(crate) const SHADING_POINT_REFINEMENTS: u32 = 2;

/// The factor of [`error_bound`]: `√3` and the layouts' quantisation and rounding.
pub(crate) const ERROR_BOUND_FACTOR: f32 = 1.74;

/// `lod` within the levels `[0, top]`, NaN as 0, as the sampler clamps it (its WGSL is
/// svo-brick's `svo_clamped_lod`).
fn clamped_lod(lod: f32, top: u32) -> f32 {
    if lod.is_nan() { 0.0 } else { lod.clamp(0.0, top as f32) }
}

/// The coarsest level a quadrilinear sample at `lod` reads: `⌊lod⌋ + 1`, as it blends
/// `⌊lod⌋` towards the next level, unless the blend's weight (the sampler's fraction, in
/// steps of 2⁻¹¹) is zero and `⌊lod⌋` alone is read — as for every magnified cone
/// (`lod ≤ 0`).
fn coarsest_read_level(lod: f32, top: u32) -> u32 {
    let lod = clamped_lod(lod, top);
    let level = libm::floorf(lod);
    let blended = libm::floorf((lod - level) * FRACTION_STEPS) > 0.0;
    (level as u32 + u32::from(blended)).min(top)
}

/// The finest level a sample at `lod` depends on through a level it reads: the coarsest
/// level quadrilinear sampling reads ([`coarsest_read_level`]; for a magnified cone the
/// finest level, whose empty nodes then count for the empty-space skip), or the nearest
/// level for [`Model::Nearest`].
fn sampled_level(lod: f32, top: u32, model: Model) -> u32 {
    if model == Model::Nearest {
        return (libm::floorf(clamped_lod(lod, top) + 0.5) as u32).min(top);
    }
    coarsest_read_level(lod, top)
}

/// `E(λ)`: how far a sample at `lod` may lie from the source's distance (world units). At
/// level `L` a stored `h̄_k` is a mean of the distance over its cube, within `(√3/2) S_L` of
/// the distance at its centre `c_k` (the distance is 1-Lipschitz); the trilinear weights
/// keep `Σ w_k |c_k − p| ≤ √(Σ w_k |c_k − p|²) = √(Σ_axes t(1 − t)) S_L ≤ (√3/2) S_L`
/// (Cauchy–Schwarz), so the interpolation is within `√3 S_L`, and the level blend within
/// that of the coarsest level it reads ([`coarsest_read_level`]: `S_{⌊λ⌋+1}`, or `S_⌊λ⌋`
/// where the blend's weight is zero). The nearest voxel's centre is within `(√3/2) S_L` of
/// the point: `√3 S_L` too, at the level `round(λ)`, never coarser than that. 1.74 adds the
/// layouts' quantisation (`2⁻¹¹ S_L`) and rounding.
fn error_bound(lod: f32, top: u32, voxel: f32) -> f32 {
    ERROR_BOUND_FACTOR * (1u32 << coarsest_read_level(lod, top)) as f32 * voxel
}

/// Where an element lies on its cone: what shading it needs besides its sample.
#[derive(Clone, Copy)]
struct Placement {
    /// Its centre's distance along the axis.
    z: f32,
    /// Its level of detail `λ`.
    lod: f32,
    /// Its half-length `l_d`.
    half_length: f32,
}

/// Marches `cone`, calling `shade(voxel, placement, new coverage)` for every element that
/// adds coverage; returns the final coverage and the number of elements.
fn march<const W: usize>(
    tree: &PackedTree,
    table: &MaskTable<W>,
    cone: &ConeGeometry<'_>,
    start: f32,
    settings: &TraceSettings,
    mut shade: impl FnMut(&Voxel, Placement, f32),
) -> (f32, u32) {
    let (lo, hi) = domain(tree);
    let Some((enter, exit)) = box_interval(cone.origin, cone.direction, lo, hi) else { return (0.0, 0) };
    let voxel = tree.uniforms().voxel_size.x;
    let floor = settings.min_half_length * voxel;
    let half_length = |z: f32| (0.5 * (cone.width)(z)).max(floor);
    let mut coverage =
        if settings.model == Model::AlphaBlend { Coverage::Alpha(0.0) } else { Coverage::Mask(Mask::<W>::EMPTY) };
    let mut z = enter.max(start) + half_length(enter.max(start));
    let (mut elements, mut steps) = (0, 0);
    // What the last sample proves: a lower bound of the source's distance at its point, and
    // the empty node it lay in.
    let mut proof: Option<(f32, f32)> = None;
    let mut region: Option<EmptyRegion> = None;
    let top = tree.uniforms().shape.x - 1;
    while z - half_length(z) < exit && steps < settings.max_elements {
        steps += 1;
        let width = (cone.width)(z);
        let (r, l) = (0.5 * width, half_length(z));
        let lod = libm::log2f((width / voxel).max(f32::MIN_POSITIVE));
        let p = cone.origin + cone.direction * z;
        let finest_sampled = sampled_level(lod, top, settings.model);
        if settings.empty_space_skip {
            let in_region =
                region.is_some_and(|g| g.level >= finest_sampled && p.cmpge(g.min).all() && p.cmplt(g.max).all());
            let far = proof.is_some_and(|(z0, lower)| lower - (z - z0) - error_bound(lod, top, voxel) > l + 2.0 * r);
            if in_region || far {
                z += 2.0 * l;
                continue;
            }
        }
        let sample = if settings.model == Model::Nearest { tree.sample_nearest(p, lod) } else { tree.sample(p, lod) };
        elements += 1;
        let Some(sample) = sample else { break };
        if settings.empty_space_skip {
            region = None;
            if sample.normal == Vec3::ZERO && sample.distance > 0.0 {
                region = tree.empty_region(p, finest_sampled).filter(|g| !g.inside);
            }
            // Outside an empty node the distance is at least the sample (the placement
            // rule); a brick sample is within error_bound of it.
            let lower = if region.is_some() { sample.distance } else { sample.distance - error_bound(lod, top, voxel) };
            proof = Some((z, lower));
        }
        match &mut coverage {
            Coverage::Mask(alpha) => {
                let mask = if settings.model == Model::Nearest {
                    if sample.distance <= 0.0 { Mask::FULL } else { Mask::EMPTY }
                } else {
                    let n = sample.normal;
                    let sign = if (cone.crossed)(z) { -1.0 } else { 1.0 };
                    let local = Vec3::new(sign * n.dot(cone.right), sign * n.dot(cone.up), n.dot(cone.direction));
                    let plane = HalfPlane::from_cone_element(sample.distance, local, r, l);
                    table.lookup(plane.theta, plane.v)
                };
                let added = mask.difference(*alpha).popcount();
                if added > 0 {
                    shade(
                        &sample,
                        Placement { z, lod, half_length: l },
                        added as f32 * (1.0 / Mask::<W>::SAMPLES as f32),
                    );
                    *alpha = alpha.union(mask);
                    if alpha.popcount() as usize >= Mask::<W>::SAMPLES {
                        break;
                    }
                }
            }
            Coverage::Alpha(alpha) => {
                let n = sample.normal;
                let local = Vec3::new(n.dot(cone.right), n.dot(cone.up), n.dot(cone.direction));
                let plane = HalfPlane::from_cone_element(sample.distance, local, r, l);
                let opacity = plane.exact_coverage() as f32;
                if opacity > 0.0 {
                    let added = (1.0 - *alpha) * opacity;
                    shade(&sample, Placement { z, lod, half_length: l }, added);
                    *alpha += added;
                    if *alpha >= 1.0 - 1.0 / 1024.0 {
                        break;
                    }
                }
            }
        }
        z += 2.0 * l;
    }
    (coverage.fraction(), elements)
}

/// The axis parameter and point of the plane through `anchor` of normal `n` (unit), on
/// which `anchor` has the sampled height `height`, that the axis `p + t direction` sees,
/// from the axis parameter `t` of the last point: the axis meets that plane at
/// `t' = t − h(t)/(n·d)`, `t'` is kept within the element (`[−l, l]`, `l = half_length`),
/// and the axis point there is projected onto the plane, so that a plane seen edge-on (or
/// crossed outside the element) gives the foot of the element's nearest axis point.
fn axis_step(
    p: Vec3,
    direction: Vec3,
    t: f32,
    (anchor, n, height): (Vec3, Vec3, f32),
    half_length: f32,
) -> (f32, Vec3) {
    let slope = n.dot(direction);
    let above = |a: Vec3| height + n.dot(a - anchor);
    let next = if slope != 0.0 { (t - above(p + direction * t) / slope).clamp(-half_length, half_length) } else { t };
    let next = if next.is_nan() { t } else { next };
    let a = p + direction * next;
    (next, a - n * above(a))
}

/// Where an element centred at `p` on the axis `direction`, of sample `voxel`, level of
/// detail `lod` and half-length `half_length`, is shaded, and that point projected onto
/// the plane last sampled, where its light direction and shadow cone start (see the module
/// documentation, "Where an element is shaded"). For `lod ≤ 0`: the point of its plane
/// `(h̄, n̂)` that the axis sees ([`axis_step`]), then `refine` ×
/// [`SHADING_POINT_REFINEMENTS`] Newton steps, each from the octree's sample at the last
/// point, the axis parameter kept within the element throughout; for `lod ≥ 1` the centre
/// `p` (projected: its foot `p − h̄ n̂`); linearly between.
fn shading_points(
    tree: &PackedTree,
    p: Vec3,
    direction: Vec3,
    voxel: &Voxel,
    lod: f32,
    half_length: f32,
    refine: bool,
) -> (Vec3, Vec3) {
    let mut plane = (p, voxel.normal, voxel.distance);
    let (mut t, mut x) = axis_step(p, direction, 0.0, plane, half_length);
    if refine && lod < 1.0 {
        for _ in 0..SHADING_POINT_REFINEMENTS {
            let Some(there) = tree.sample(x, lod).filter(|v| v.normal != Vec3::ZERO) else { break };
            plane = (x, there.normal, there.distance);
            (t, x) = axis_step(p, direction, t, plane, half_length);
        }
    }
    let sampled = p + (x - p) * (1.0 - lod).clamp(0.0, 1.0);
    let (anchor, n, height) = plane;
    (sampled, sampled - n * (height + n.dot(sampled - anchor)))
}

/// The attributes that shade an element: the octree sampled at its shading point `point`
/// ([`shading_points`]), at the element's `lod` (see the module
/// documentation, "Where an element is shaded"); the element's own sample `voxel` for
/// [`Model::Nearest`] (Fig. 10a shades the voxel it hits), and where the surface point
/// lies outside the domain or in an empty node (no normal).
fn surface_voxel(tree: &PackedTree, voxel: &Voxel, point: Vec3, lod: f32, model: Model) -> Voxel {
    if model == Model::Nearest {
        return *voxel;
    }
    match tree.sample(point, lod) {
        Some(there) if there.normal != Vec3::ZERO => there,
        _ => *voxel,
    }
}

/// The visibility of the light from the surface point `surface` (world) of an element of
/// unit normal `normal` (zero: none), for a shadow cone of starting width `width`: `1 −` the
/// coverage of the cone from `surface + δ normal` towards the light's centre (see the module
/// documentation: `δ = ρ₁ − t₁ (n̂·d) + (√3/2) S₀` keeps the cone's first element off the
/// element's own plane, with the finest level's interpolation error to spare). The cone's axis is the direction `d` from `surface` to the light's centre, and
/// it reaches the light's diameter at the light's distance from `surface`. A surface point
/// at the light's centre (or not finite) sees all of it: `1`.
pub fn light_visibility<const W: usize>(
    tree: &PackedTree,
    table: &MaskTable<W>,
    surface: Vec3,
    normal: Vec3,
    width: f32,
    settings: &TraceSettings,
) -> f32 {
    let to_light = settings.light.position - surface;
    let distance = to_light.length();
    if distance.is_nan() || distance <= 0.0 {
        return 1.0;
    }
    let direction = to_light / distance;
    let (right, up) = tangent_frame(direction);
    let diameter = 2.0 * settings.light.radius;
    let widen = |t: f32| width + (diameter - width) * (t / distance).clamp(0.0, 1.0);
    // The first element of the march (it starts at t = 0 inside the domain): its centre t₁,
    // radius r₁ and half-length l₁, as `march` computes them.
    let floor = settings.min_half_length * tree.uniforms().voxel_size.x;
    let first = (0.5 * widen(0.0)).max(floor);
    let (r1, l1) = (0.5 * widen(first), (0.5 * widen(first)).max(floor));
    let reach = libm::sqrtf(l1 * l1 + 2.0 * (r1 * r1));
    let voxel = tree.uniforms().voxel_size.x;
    let lift = reach - first * normal.dot(direction) + SHADOW_LIFT_VOXELS * voxel;
    let origin = surface + normal * lift;
    let never = |_: f32| false;
    let geometry = ConeGeometry { origin, direction, right, up, width: &widen, crossed: &never };
    let shadow_settings = TraceSettings { shadow_cones: 0, ..*settings };
    let (coverage, _) = march(tree, table, &geometry, 0.0, &shadow_settings, |_, _, _| {});
    1.0 - coverage
}

/// Traces one pixel cone (Algorithm 1, see the module documentation).
pub fn trace_cone<const W: usize>(
    tree: &PackedTree,
    table: &MaskTable<W>,
    cone: &Cone,
    settings: &TraceSettings,
) -> ConeResult {
    let width = |z: f32| cone.width(z);
    let crossed = |z: f32| cone.crossed(z);
    let geometry = ConeGeometry {
        origin: cone.origin,
        direction: cone.direction,
        right: cone.right,
        up: cone.up,
        width: &width,
        crossed: &crossed,
    };
    let view = -cone.direction;
    let (mut radiance, mut shadows, mut visibility) = (Vec3::ZERO, 0, 1.0);
    let (coverage, elements) = march(tree, table, &geometry, 0.0, settings, |voxel, at, added| {
        let z = at.z;
        let p = cone.point(z);
        let refine = settings.model != Model::Nearest;
        let (sampled, surface) = shading_points(tree, p, cone.direction, voxel, at.lod, at.half_length, refine);
        let shading = surface_voxel(tree, voxel, sampled, at.lod, settings.model);
        let light = (settings.light.position - surface).normalize_or_zero();
        if shadows < settings.shadow_cones {
            let r = 0.5 * cone.width(z);
            visibility = light_visibility(tree, table, surface, voxel.normal, 2.0 * r, settings);
            shadows += 1;
        }
        let l_d = element_radiance(
            &shading,
            view,
            light,
            &settings.material,
            settings.model.filtering(),
            settings.light.radiance,
            visibility,
        );
        radiance += l_d * added;
    });
    ConeResult { radiance: radiance + settings.background * (1.0 - coverage), coverage, elements }
}
