//! The CPU reference of the occluder map and the splitter: the same decisions as the
//! shaders, evaluated with the same `f32` operations (each function names its WGSL twin),
//! and the lists in the stable order (ascending grain index).
//!
//! It serves the GPU tests (lists as sets, counts and indirect arguments compared), the
//! culling experiments (Fig. 15, which need no GPU) and users without a GPU.

use glam::{Vec3, Vec4};
use occlusion_cone::{Sphere, is_occluded_by};

use crate::camera::{SplitCamera, transform};
use crate::error::SplitError;
use crate::fusion::DepthPyramid;
use crate::lists::{
    CULLED_CONE, CULLED_FRUSTUM, CULLED_HIZ, LIST_COUNT, LIST_IMPOSTOR_OCCLUDER, LIST_IMPOSTOR_REST, LIST_MESH,
    LIST_POINT, ListIndirect, STATE_MODEL_SHIFT, SplitCounters, state_tier,
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

/// Everything one frame of the splitter produces.
#[derive(Clone, Debug, PartialEq)]
pub struct SplitOutput {
    /// The state word of every grain (input of the next frame).
    pub state: Vec<u32>,
    /// The elements of each list, ascending (the stable order).
    pub lists: [Vec<u32>; LIST_COUNT as usize],
    /// The counters (cursors as the stable order leaves them: zero).
    pub counters: SplitCounters,
    /// The indirect arguments of each list.
    pub indirect: [ListIndirect; LIST_COUNT as usize],
}

impl SplitOutput {
    /// The element buffer: the lists one after the other.
    pub fn elements(&self) -> Vec<u32> {
        self.lists.concat()
    }
}

/// One frame of the splitter over `grains`, given the previous frame's state words (empty:
/// no history). The Hi-Z test (when [`SplitSettings::hiz_applies`]) uses the `f64` pyramid
/// of [`DepthPyramid`] (two-phase with `previous_state` when
/// [`SplitSettings::temporal_occluders`]), of which the GPU's is a conservative rounding: the GPU culls a
/// subset of what this culls by Hi-Z. An error when `previous_state` is neither empty nor one word per grain.
pub fn split(
    camera: &SplitCamera,
    settings: &SplitSettings,
    grains: &[Vec4],
    map: &OccluderMap,
    previous_state: &[u32],
) -> Result<SplitOutput, SplitError> {
    settings.validate()?;
    if !previous_state.is_empty() && previous_state.len() != grains.len() {
        return Err(SplitError::InvalidBuffer(format!(
            "{} previous state words for {} grains",
            previous_state.len(),
            grains.len()
        )));
    }
    if grains.len() >= NO_OCCLUDER as usize {
        return Err(SplitError::TooLarge {
            what: "grain count",
            requested: grains.len() as u64,
            limit: u64::from(NO_OCCLUDER) - 1,
        });
    }
    let mut lists: [Vec<u32>; LIST_COUNT as usize] = Default::default();
    let mut counters = SplitCounters::default();
    let mut state = Vec::with_capacity(grains.len());
    let pyramid = settings.hiz_applies(camera).then(|| {
        if settings.temporal_occluders {
            DepthPyramid::build_two_phase(camera, settings, grains, map, previous_state)
        } else {
            DepthPyramid::build(camera, settings, grains, map)
        }
    });
    for index in 0..grains.len() as u32 {
        let previous = previous_state.get(index as usize).copied().unwrap_or(0);
        let mut decision = decide(camera, settings, grains, map, index, previous);
        if let Some(pyramid) = &pyramid
            && decision.model < LIST_COUNT
            && pyramid.hides_grain(camera, grains[index as usize], settings.outer_radius)
        {
            decision.model = CULLED_HIZ;
        }
        state.push(decision.state());
        match decision.model {
            CULLED_FRUSTUM => counters.culled[0] += 1,
            CULLED_CONE => counters.culled[1] += 1,
            CULLED_HIZ => counters.culled[2] += 1,
            list => lists[list as usize].push(index),
        }
    }
    let mut offset = 0;
    for (list, elements) in lists.iter().enumerate() {
        counters.count[list] = elements.len() as u32;
        counters.offset[list] = offset;
        offset += elements.len() as u32;
    }
    let indirect =
        counters.count.map(|count| ListIndirect::new(count, settings.mesh_index_count, settings.sprite_vertex_count));
    Ok(SplitOutput { state, lists, counters, indirect })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lists::state_model;
    use crate::tiers::TierThresholds;

    fn camera() -> SplitCamera {
        SplitCamera::perspective(Vec3::new(0.0, 0.0, 20.0), Vec3::ZERO, Vec3::Y, 0.6, (64, 48), (0.1, 100.0)).unwrap()
    }

    fn settings() -> SplitSettings {
        SplitSettings::new(0.8, 1.0, TierThresholds::new(2.0, 30.0, 1.0).unwrap())
    }

    #[test]
    fn a_grain_behind_another_on_the_axis_is_culled_and_the_front_one_owns_its_texel() {
        let grains = [Vec4::new(0.0, 0.0, 5.0, 1.0), Vec4::new(0.0, 0.0, -10.0, 1.0), Vec4::new(3.0, 0.0, 0.0, 1.0)];
        let (camera, settings) = (camera(), settings());
        let map = occluder_map(&camera, &settings, &grains);
        assert!(map.filled() > 0);
        let out = split(&camera, &settings, &grains, &map, &[]).unwrap();
        assert_eq!(out.counters.culled, [0, 1, 0, 0]);
        let listed: Vec<u32> = out.elements();
        assert!(listed.contains(&0) && listed.contains(&2) && !listed.contains(&1));
        let front = decide(&camera, &settings, &grains, &map, 0, 0);
        assert_eq!((front.tier, front.model), (Tier::Impostor, LIST_IMPOSTOR_OCCLUDER));
        // Without occlusion culling nothing is hidden.
        let off = SplitSettings { cone_culling: false, hiz_culling: false, ..settings };
        assert_eq!(split(&camera, &off, &grains, &map, &[]).unwrap().counters.culled, [0, 0, 0, 0]);
    }

    #[test]
    fn grains_outside_the_frustum_are_culled_and_those_touching_it_are_kept() {
        let camera = camera();
        // Half-width of the view at depth 20 is 20·tan(0.3)·64/48.
        let edge = 20.0 * (0.3f32).tan() * 64.0 / 48.0;
        let grains = [
            Vec4::new(edge + 1.5, 0.0, 0.0, 1.0),
            Vec4::new(edge + 0.9, 0.0, 0.0, 1.0),
            Vec4::new(0.0, 0.0, 25.0, 1.0),
        ];
        let settings = settings();
        let map = occluder_map(&camera, &settings, &grains);
        let out = split(&camera, &settings, &grains, &map, &[]).unwrap();
        let models: Vec<u32> = out.state.iter().map(|&s| state_model(s)).collect();
        assert_eq!(models[0], CULLED_FRUSTUM);
        assert_ne!(models[1], CULLED_FRUSTUM);
        assert_eq!(models[2], CULLED_FRUSTUM, "behind the eye");
    }

    #[test]
    fn counts_offsets_and_indirect_arguments_are_consistent() {
        let grains: Vec<Vec4> = (0..500)
            .map(|i| {
                let t = i as f32;
                Vec4::new((t * 0.37).sin() * 6.0, (t * 0.11).cos() * 4.0, -(t * 0.05), 0.5 + (t * 0.7).sin().abs())
            })
            .collect();
        let (camera, settings) = (camera(), settings());
        let map = occluder_map(&camera, &settings, &grains);
        let out = split(&camera, &settings, &grains, &map, &[]).unwrap();
        let listed: u32 = out.counters.count.iter().sum();
        assert_eq!(listed + out.counters.culled.iter().sum::<u32>(), 500);
        for l in 0..4 {
            assert_eq!(out.indirect[l].draw[1], out.counters.count[l]);
            assert!(out.lists[l].windows(2).all(|w| w[0] < w[1]));
        }
        assert_eq!(out.counters.offset[3], out.counters.count[..3].iter().sum::<u32>());
        let bad = split(&camera, &settings, &grains, &map, &[0; 3]).unwrap_err();
        assert!(bad.to_string().contains("3 previous state words"));
    }

    #[test]
    fn the_map_keeps_the_nearest_centre() {
        let camera = camera();
        let settings = SplitSettings { splat_factor: 4.0, ..settings() };
        let grains = [Vec4::new(0.0, 0.0, 0.0, 1.0), Vec4::new(0.05, 0.0, 2.0, 1.0)];
        let map = occluder_map(&camera, &settings, &grains);
        assert_eq!(map.get((32, 24)), Some(1));
        let none = SplitSettings { occluder_radius: 0.0, ..settings };
        assert_eq!(occluder_map(&camera, &none, &grains).filled(), 0);
    }
}
