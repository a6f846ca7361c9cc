//! The paper's per-grain decisions and the occluder map, in the same `f32` operations as
//! the shaders (each function names its WGSL twin): the occluder map's squares, the frustum
//! test, the cone test against the occluder at the centre's pixel, the tier.

use glam::{Vec3, Vec4};
use occlusion_cone::{Sphere, is_occluded_by};

use crate::camera::{SplitCamera, transform};
use crate::lists::{
    CULLED_CONE, CULLED_FRUSTUM, LIST_IMPOSTOR_OCCLUDER, LIST_IMPOSTOR_REST, LIST_MESH, LIST_POINT, STATE_MODEL_SHIFT,
    state_tier,
};
use crate::settings::{FRUSTUM_MARGIN, MAX_SPLAT_HALF, SplitSettings};
use crate::tiers::Tier;

/// An empty occluder-map texel.
pub const NO_OCCLUDER: u32 = u32::MAX;

/// The grain whose centre is nearest the eye among those whose square covers each pixel
/// (ties: the lowest index), [`NO_OCCLUDER`] where none does.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OccluderMap {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major grain indices.
    pub ids: Vec<u32>,
}

impl OccluderMap {
    /// The occluder at pixel `(x, y)` (`None`: empty or outside).
    pub fn get(&self, (x, y): (u32, u32)) -> Option<u32> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let id = self.ids[(y * self.width + x) as usize];
        (id != NO_OCCLUDER).then_some(id)
    }

    /// How many pixels hold an occluder.
    pub fn filled(&self) -> usize {
        self.ids.iter().filter(|&&id| id != NO_OCCLUDER).count()
    }
}

/// The centre's pixel, the half-side of the grain's occluder-map square in pixels and the
/// centre's view depth, or `None` when the grain writes nothing (no solid core, not in front
/// of the eye). The first half of [`splat`].
pub fn splat_half(camera: &SplitCamera, settings: &SplitSettings, grain: Vec4) -> Option<(glam::Vec2, f32, f32)> {
    let radius = settings.occluder_radius * grain.w;
    if radius.is_nan() || radius <= 0.0 {
        return None;
    }
    let projected = camera.project(grain.truncate());
    let pixel = projected.pixel?;
    let depth = projected.view_depth;
    if depth.is_nan() || depth <= 0.0 {
        return None;
    }
    let focal = camera.projection.x;
    let radius_pixels = if camera.is_perspective() { radius * focal / depth } else { radius * focal };
    Some((pixel, (settings.splat_factor * radius_pixels).min(MAX_SPLAT_HALF), depth))
}

/// A grain's occluder-map square: inclusive pixel bounds and the depth key, or `None` when
/// the grain writes nothing (no solid core, not in front of the eye, off screen).
/// Twin of `split_splat` (WGSL).
pub fn splat(camera: &SplitCamera, settings: &SplitSettings, grain: Vec4) -> Option<Splat> {
    let (pixel, half, depth) = splat_half(camera, settings, grain)?;
    let (width, height) = (camera.viewport.x, camera.viewport.y);
    let lo = |x: f32, side: f32| (x - half).floor().clamp(-1.0, side);
    let hi = |x: f32, side: f32| (x + half).floor().clamp(-1.0, side);
    let (x0, x1, y0, y1) = (lo(pixel.x, width), hi(pixel.x, width), lo(pixel.y, height), hi(pixel.y, height));
    if x1 < 0.0 || y1 < 0.0 || x0 >= width || y0 >= height {
        return None;
    }
    let clamp = |x: f32, side: f32| x.clamp(0.0, side - 1.0) as u32;
    Some(Splat {
        min: (clamp(x0, width), clamp(y0, height)),
        max: (clamp(x1, width), clamp(y1, height)),
        depth_bits: depth.to_bits(),
    })
}

/// A grain's square in the occluder map.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Splat {
    /// First pixel (inclusive).
    pub min: (u32, u32),
    /// Last pixel (inclusive).
    pub max: (u32, u32),
    /// Bits of the centre's view depth (positive, so the bits order like the depths).
    pub depth_bits: u32,
}

/// The occluder map of `grains` (`(centre, scale)` each).
pub fn occluder_map(camera: &SplitCamera, settings: &SplitSettings, grains: &[Vec4]) -> OccluderMap {
    let (width, height) = camera.size();
    let mut keys = vec![u64::MAX; width as usize * height as usize];
    for (id, &grain) in grains.iter().enumerate() {
        let Some(splat) = splat(camera, settings, grain) else { continue };
        let key = (u64::from(splat.depth_bits) << 32) | id as u64;
        for y in splat.min.1..=splat.max.1 {
            let row = &mut keys[(y * width) as usize..][..width as usize];
            for slot in &mut row[splat.min.0 as usize..=splat.max.0 as usize] {
                *slot = (*slot).min(key);
            }
        }
    }
    let ids = keys.into_iter().map(|key| if key == u64::MAX { NO_OCCLUDER } else { key as u32 }).collect();
    OccluderMap { width, height, ids }
}

/// Why a grain was culled, or the list it went to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Decision {
    /// Its tier this frame (computed for every grain, culled ones included).
    pub tier: Tier,
    /// Its model code: a list index or a `CULLED_*` code.
    pub model: u32,
}

impl Decision {
    /// The state word the shaders keep for the grain.
    pub fn state(self) -> u32 {
        self.tier.code() | (self.model << STATE_MODEL_SHIFT)
    }
}

/// Whether the outer ball `(centre, radius)` is certainly outside one of the frustum's
/// planes, with the rounding margin of [`FRUSTUM_MARGIN`]. Twin of `split_outside_frustum`.
pub fn outside_frustum(camera: &SplitCamera, centre: Vec3, radius: f32) -> bool {
    camera.frustum.iter().any(|plane| {
        let (x, y, z) = (plane.x * centre.x, plane.y * centre.y, plane.z * centre.z);
        let distance = x + y + z + plane.w;
        let slack = FRUSTUM_MARGIN * (x.abs() + y.abs() + z.abs() + plane.w.abs() + radius);
        distance < -(radius + slack)
    })
}

/// The decision for grain `index`, given the occluder map and the grain's previous state
/// word (0: none). Twin of `split_decide`.
pub fn decide(
    camera: &SplitCamera,
    settings: &SplitSettings,
    grains: &[Vec4],
    map: &OccluderMap,
    index: u32,
    previous_state: u32,
) -> Decision {
    let grain = grains[index as usize];
    let centre = grain.truncate();
    let radius = settings.outer_radius * grain.w;
    let projected = camera.project(centre);
    let perspective = camera.is_perspective();
    let twice_radius_focal = 2.0 * radius * camera.projection.x;
    let depth = if perspective { projected.view_depth } else { 1.0 };
    let hysteresis = settings.thresholds.band() > 1.0;
    let previous = if hysteresis { Tier::from_code(state_tier(previous_state)) } else { None };
    let tier = settings.thresholds.tier(twice_radius_focal, depth, previous);
    if settings.frustum_culling && outside_frustum(camera, centre, radius) {
        return Decision { tier, model: CULLED_FRUSTUM };
    }
    let occluder = projected.centre_texel(camera.size()).and_then(|texel| map.get(texel));
    let owner = occluder == Some(index);
    if settings.cone_culling
        && settings.occluder_radius > 0.0
        && perspective
        && let Some(other) = occluder.filter(|&o| o != index && (o as usize) < grains.len())
    {
        let o = grains[other as usize];
        let occluder = Sphere {
            centre: transform(&camera.view_from_world, o.truncate()).truncate(),
            radius: settings.occluder_radius * o.w,
        };
        if is_occluded_by(occluder, Sphere { centre: projected.view, radius }) {
            return Decision { tier, model: CULLED_CONE };
        }
    }
    let model = match tier {
        Tier::Mesh => LIST_MESH,
        Tier::Impostor if owner => LIST_IMPOSTOR_OCCLUDER,
        Tier::Impostor => LIST_IMPOSTOR_REST,
        Tier::Point => LIST_POINT,
    };
    Decision { tier, model }
}
