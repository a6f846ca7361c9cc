//! The CPU reference of the occluder map and the splitter: the same decisions as the
//! shaders, evaluated with the same `f32` operations (each function names its WGSL twin),
//! and the lists in the stable order (ascending grain index).
//!
//! It serves the GPU tests (lists as sets, counts and indirect arguments compared), the
//! culling experiments (Fig. 15, which need no GPU) and users without a GPU.

use glam::Vec4;

use crate::camera::SplitCamera;
pub use crate::decision::{
    Decision, NO_OCCLUDER, OccluderMap, Splat, decide, occluder_map, outside_frustum, splat, splat_half,
};
use crate::error::SplitError;
use crate::fusion::DepthPyramid;
use crate::lists::{CULLED_CONE, CULLED_FRUSTUM, CULLED_HIZ, LIST_COUNT, ListIndirect, SplitCounters};
use crate::settings::SplitSettings;

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
    use crate::lists::{LIST_IMPOSTOR_OCCLUDER, state_model};
    use crate::tiers::{Tier, TierThresholds};
    use glam::Vec3;

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
