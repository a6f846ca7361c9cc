//! Sampling a quasi-spherical impostor (§4.1 and §5 of the paper): which four views to
//! blend for a camera ray, with which weights, and which texel to read in each.
//!
//! # What is computed
//!
//! For a camera ray in the grain's local frame ([`GrainRay`]; built from a world ray and
//! the grain's centre, uniform scale and rotation by [`GrainRay::from_world`]):
//!
//! 1. the four views nearest (Listing 1) to the direction toward the camera, chosen
//!    **per grain** (from the grain centre toward the eye, the paper's choice, §4.2:
//!    "we compute the sampled directions at the extent of a whole grain") or **per
//!    fragment** (`−ray direction`, what `GrainViewer`'s `IntersectRaySphericalGBillboard`
//!    does); see [`ViewSelection`];
//! 2. for each view `i` (direction `ω_i`, frame [`ViewFrame`]), the texture coordinates
//!    of the texel to read, by [`SamplingMode`]:
//!    - **planar** `P`: the ray meets the view plane (through the centre, ⟂ `ω_i`);
//!    - **spherical** `S`: the ray meets the proxy sphere of radius `ρ = (r + R) / 2`, and
//!      that point is projected along `ω_i` onto the plane;
//!    - **mixed** `M = (d/R)·P + (1 − d/R)·S` (§5), `d` the distance from the centre to
//!      the ray's line. Texture coordinates are affine in the point, so the blend is done
//!      on coordinates.
//!
//! ```
//! use glam::{Quat, Vec3};
//! use octahedral_map::{GrainRay, ImpostorSampler, OctahedralViews, SamplingMode, ViewLayout, ViewSelection};
//!
//! let views = OctahedralViews::new(8).unwrap();
//! // R = 1.2 (also the half-size of each view's square), r = 0.8.
//! let sampler =
//!     ImpostorSampler::new(views, 1.2, 0.8, SamplingMode::Mixed, ViewLayout::Compact, ViewSelection::PerGrainFromEye)
//!         .unwrap();
//! // A camera at (0, -10, 2) looking at a grain at the origin, scaled by 2 and turned.
//! let eye = Vec3::new(0.0, -10.0, 2.0);
//! let ray = GrainRay::from_world(eye, Vec3::new(0.05, 1.0, -0.2), Vec3::ZERO, 2.0, Quat::from_rotation_z(0.3));
//! let sample = sampler.sample(&ray);
//! assert!((sample.weights.element_sum() - 1.0).abs() < 1e-6);
//! for k in 0..4 {
//!     let uv = sample.view_texture_coordinates(k); // read layer sample.indices[k] at uv
//!     assert!(uv.x.is_finite() && uv.y.is_finite());
//! }
//! assert!(sample.distance_ratio < 1.0 && sample.proxy_hit == 1);
//! ```
//!
//! # Misses and edge cases (decisions)
//!
//! - **`d > R`** (the ray passes outside the outer sphere): a miss in every mode. The grain
//!   lies inside its outer sphere, so no texel can hold it; the baked α there is 0 anyway
//!   when the bake extent is `R`, and returning a miss saves the texture reads.
//! - **The ray misses the proxy sphere** (`ρ < d ≤ R`, or the sphere lies behind the
//!   origin): spherical sampling returns a miss (this is what "cuts out parts of the
//!   object", §5); mixed sampling returns `P`, as `GrainViewer`'s
//!   `IntersectRayBillboard_MixedHit` does (it falls back to its plane hit when the
//!   sphere hit is invalid). Note that the paper's formula is then **discontinuous** at
//!   `d = ρ`: just inside, `M` still weighs `S` by `1 − ρ/R = (R − r)/(2R)`. `GrainViewer`
//!   avoids the jump with `smoothstep(0.2 ρ/R, ρ/R, d/R)` as the weight of `P`:
//!   [`SamplingMode::Mixed`] keeps the paper's formula and its jump,
//!   [`SamplingMode::MixedSmooth`] is the official code's variant, and the accuracy
//!   experiment of `grain-impostor` measures both.
//! - **Ray starting inside the proxy sphere**: its exit point (`GrainViewer`'s
//!   `intersectRaySphere` does the same).
//! - **Ray (nearly) parallel to a view plane**, `|direction·ω_i| < MIN_PLANE_COSINE`: `P`
//!   is a miss for that view (it would lie arbitrarily far away; `GrainViewer` divides by
//!   zero there). Mixed sampling then uses `S` alone.
//! - **Texture coordinates** are clamped to `[MISS_TEXTURE_COORDINATE,
//!   MAX_TEXTURE_COORDINATE] = [−1, 2]` so they stay finite; readers treat anything
//!   outside `[0, 1]²` as transparent (as `GrainViewer`'s `SampleBillboard`).
//! - **Unusable rays** (NaN, ±∞, huge origins, bad scale or rotation; see
//!   [`GrainRay::from_world`]): every view is a miss, `d/R = MAX_DISTANCE_RATIO`; the
//!   view indices still come from the (always defined) direction.

mod ray;
mod sample;

use glam::{UVec4, Vec2, Vec3, Vec4};

pub use ray::{
    GrainRay, MAX_GRAIN_SCALE, MAX_RAY_ORIGIN_COMPONENT, MAX_WORLD_COMPONENT, MIN_GRAIN_SCALE, intersect_proxy_sphere,
};
pub use sample::{ImpostorSample, ImpostorSamplingUniforms};

use crate::compact::compact_from_listing_index;
use crate::view_frame::ViewFrame;
use crate::views::{OctahedralViews, view_sample_from_direction};

/// The texture coordinate of a miss (both components); also the lower clamp bound.
pub const MISS_TEXTURE_COORDINATE: f32 = -1.0;

/// The upper clamp bound of texture coordinates.
pub const MAX_TEXTURE_COORDINATE: f32 = 2.0;

/// Below this `|cos|` between the ray and a view's direction, the ray is treated as
/// parallel to the view plane (planar sample = miss). `1e-3` is 89.94°.
pub const MIN_PLANE_COSINE: f32 = 1.0e-3;

/// The upper clamp bound of [`ImpostorSample::distance_ratio`].
pub const MAX_DISTANCE_RATIO: f32 = 2.0;

/// Which texel of a view a camera ray reads (§5).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum SamplingMode {
    /// `P`: the ray's intersection with the view plane.
    Planar = 0,
    /// `S`: the ray's intersection with the proxy sphere of radius `(r + R)/2`, projected
    /// along the view direction onto the plane.
    Spherical = 1,
    /// `M = (d/R)·P + (1 − d/R)·S`, the paper's mixed sampling.
    Mixed = 2,
    /// The continuous variant of the official code (`GrainViewer`): `M = w·P + (1 − w)·S`
    /// with `w = smoothstep(0.2 ρ/R, ρ/R, d/R)`, so that `M` reaches `P` exactly where the
    /// ray leaves the proxy sphere (`d = ρ`) instead of jumping there.
    MixedSmooth = 3,
}

impl SamplingMode {
    /// Every mode: the paper's three and the official code's continuous mixed variant.
    pub const ALL: [Self; 4] = [Self::Planar, Self::Spherical, Self::Mixed, Self::MixedSmooth];
}

/// `smoothstep(low, high, x) = t²(3 − 2t)` with `t = clamp((x − low)/(high − low), 0, 1)`,
/// written as WGSL defines it (the twin spells it out, so both round alike).
fn smoothstep(low: f32, high: f32, x: f32) -> f32 {
    let t = ((x - low) / (high - low)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Which view indices the samplers return.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum ViewLayout {
    /// Listing 1's indices, `0 .. 2n²` (equator views stored twice).
    Listing1 = 0,
    /// [`CompactViews`](crate::CompactViews) indices, `0 .. 2n² − 4(n − 1)`.
    Compact = 1,
}

/// How the direction that selects the four views is chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[repr(u32)]
pub enum ViewSelection {
    /// `−ray direction`, per fragment (`GrainViewer`).
    PerFragment = 0,
    /// The ray origin: the direction from the grain centre toward the eye when the ray
    /// starts at the eye of a perspective camera (the paper's per-grain choice, §4.2). For
    /// orthographic cameras use `PerFragment`: all rays are parallel, so it is per grain.
    PerGrainFromEye = 1,
}

/// A validated sampling configuration: layout, radii, mode.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImpostorSampler {
    uniforms: ImpostorSamplingUniforms,
}

impl ImpostorSampler {
    /// A sampler of impostors with the views `views`, outer radius `outer_radius` (`R`,
    /// also the half-size of each view's square) and inner radius `inner_radius` (`r`),
    /// or `None` unless `0 < r ≤ R ≤ MAX_RAY_ORIGIN_COMPONENT` (finite).
    pub fn new(
        views: OctahedralViews,
        outer_radius: f32,
        inner_radius: f32,
        mode: SamplingMode,
        layout: ViewLayout,
        selection: ViewSelection,
    ) -> Option<Self> {
        let valid = inner_radius > 0.0 && inner_radius <= outer_radius && outer_radius <= MAX_RAY_ORIGIN_COMPONENT;
        valid.then_some(Self {
            uniforms: ImpostorSamplingUniforms {
                subdivisions: views.subdivisions(),
                mode: mode as u32,
                view_layout: layout as u32,
                selection: selection as u32,
                outer_radius,
                inner_radius,
                padding: Vec2::ZERO,
            },
        })
    }

    /// The uniforms of the WGSL twin.
    pub fn uniforms(&self) -> ImpostorSamplingUniforms {
        self.uniforms
    }

    /// The proxy sphere's radius `(r + R) / 2` (§5).
    pub fn proxy_radius(&self) -> f32 {
        proxy_radius(&self.uniforms)
    }

    /// The views, weights and texture coordinates for `ray` (see the module docs).
    pub fn sample(&self, ray: &GrainRay) -> ImpostorSample {
        sample_impostor(ray, &self.uniforms)
    }
}

fn proxy_radius(uniforms: &ImpostorSamplingUniforms) -> f32 {
    0.5 * (uniforms.inner_radius + uniforms.outer_radius)
}

/// The texture coordinates of `point` (relative to the centre) in `frame`, clamped to
/// `[MISS_TEXTURE_COORDINATE, MAX_TEXTURE_COORDINATE]`.
fn clamped_texture_coordinates(frame: &ViewFrame, point: Vec3, outer_radius: f32) -> Vec2 {
    frame
        .texture_coordinates(point, outer_radius)
        .clamp(Vec2::splat(MISS_TEXTURE_COORDINATE), Vec2::splat(MAX_TEXTURE_COORDINATE))
}

/// Planar sampling `P` in `frame`: the ray's line meets the view plane, or `None` when it
/// is parallel to it within [`MIN_PLANE_COSINE`]. Computed from the closest point `c` of
/// the line to the centre (`P = c + t·direction`, `t = −c·ω / direction·ω`), which keeps
/// precision for far-away origins.
pub fn planar_point(ray: &GrainRay, frame: &ViewFrame) -> Option<Vec3> {
    let cosine = ray.direction.dot(frame.direction);
    if cosine.abs() < MIN_PLANE_COSINE {
        return None;
    }
    let closest = ray.closest_point_to_centre();
    Some(closest - ray.direction * (closest.dot(frame.direction) / cosine))
}

/// The Listing 1 view sample, weights and texture coordinates of `ray` under `uniforms`
/// (the free-function form of [`ImpostorSampler::sample`], mirrored by the WGSL
/// `impostor_sample`). `uniforms` should come from [`ImpostorSampler::uniforms`]; other
/// values are still defined (an unknown mode samples as mixed, an unknown layout as
/// Listing 1, an unknown selection per fragment, radii are used as given).
pub fn sample_impostor(ray: &GrainRay, uniforms: &ImpostorSamplingUniforms) -> ImpostorSample {
    let n = uniforms.subdivisions;
    let toward_camera =
        if uniforms.selection == ViewSelection::PerGrainFromEye as u32 { ray.origin } else { -ray.direction };
    let views = view_sample_from_direction(toward_camera, n);
    let weights = Vec4::from_array(views.weights());
    let outer = uniforms.outer_radius;
    let closest = ray.closest_point_to_centre();
    let distance = closest.length();
    // `distance` is finite for a usable origin; a NaN outer radius misses too.
    let misses_grain = ray.invalid_origin || distance.partial_cmp(&outer).is_none_or(|o| o.is_gt());
    let distance_ratio =
        if ray.invalid_origin { MAX_DISTANCE_RATIO } else { (distance / outer).clamp(0.0, MAX_DISTANCE_RATIO) };
    let proxy_hit = if misses_grain { None } else { intersect_proxy_sphere(ray, proxy_radius(uniforms)) };
    let layout = OctahedralViews::clamped(n);
    let miss = Vec2::splat(MISS_TEXTURE_COORDINATE);
    let mut coordinates = [miss; 4];
    for (k, index) in views.indices.to_array().into_iter().enumerate() {
        if misses_grain {
            break;
        }
        let direction = layout.view_direction(index).unwrap_or(crate::FALLBACK_DIRECTION);
        let frame = ViewFrame::from_unit_direction(direction);
        let planar = planar_point(ray, &frame);
        let point = match (uniforms.mode, planar, proxy_hit) {
            (0, p, _) => p,
            (1, _, s) => s,
            (3, Some(p), Some(s)) => {
                let proxy_ratio = proxy_radius(uniforms) / outer;
                let t = smoothstep(0.2 * proxy_ratio, proxy_ratio, distance_ratio);
                Some(p * t + s * (1.0 - t))
            }
            (_, Some(p), Some(s)) => {
                let t = distance_ratio;
                Some(p * t + s * (1.0 - t))
            }
            (_, p, s) => p.or(s),
        };
        coordinates[k] = point.map_or(miss, |q| clamped_texture_coordinates(&frame, q, outer));
    }
    let indices = if uniforms.view_layout == ViewLayout::Compact as u32 {
        UVec4::from_array(views.indices.to_array().map(|i| compact_from_listing_index(i, n)))
    } else {
        views.indices
    };
    ImpostorSample {
        indices,
        weights,
        texture_coordinates: [
            Vec4::new(coordinates[0].x, coordinates[0].y, coordinates[1].x, coordinates[1].y),
            Vec4::new(coordinates[2].x, coordinates[2].y, coordinates[3].x, coordinates[3].y),
        ],
        distance_ratio,
        proxy_hit: u32::from(proxy_hit.is_some()),
        padding: Vec2::ZERO,
    }
}

#[cfg(test)]
mod tests;
