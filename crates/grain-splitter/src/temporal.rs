//! Temporal two-phase culling, beyond the paper: the grains visible in the previous frame
//! are this frame's dense occluders.
//!
//! The occluder map holds one small square per grain (`k ≈ 0.2` of the projected inner
//! radius, §8), chosen for the single-occluder cone test: a larger square would hand a
//! pixel to a grain whose centre is near but whose surface there is far. Fusion's depth
//! bounds have no such trade-off — the smaller of two valid bounds is valid — so more
//! covered pixels only help, but splatting every grain's whole disc costs as much as
//! drawing it, and in a dense stacking most grains are hidden.
//!
//! Phase 1 therefore splats only the grains the previous frame kept (their state word's
//! model is a list), each over the square inscribed in its projected inner disc
//! ([`cover_square`]: half-side [`HIZ_COVER_FACTOR`] times the projected inner radius, at
//! most [`MAX_SPLAT_HALF`](crate::settings::MAX_SPLAT_HALF) pixels), keeping per pixel the
//! smallest bound `D(p)` ([`fusion`](mod@crate::fusion)) of the ball at its **current**
//! position. Phase 2 is the splitter's Hi-Z test against the max pyramid of
//! `min(map bound, cover bound)`.
//!
//! Conservative whatever the history: every bound written is a valid bound of a grain of
//! this frame, so which grains write them (last frame's visible set, or after
//! [`GrainSplitter::reset_history`](crate::GrainSplitter::reset_history) every grain, since a
//! cleared state word reads as the mesh list) changes how much is culled, never whether a
//! culled grain is hidden. A grain newly uncovered this frame is drawn (it passes the test)
//! and joins the occluders next frame.

use glam::Vec4;

use crate::camera::SplitCamera;
use crate::decision::{OccluderMap, Splat, splat};
use crate::fusion::{BaseBounds, DepthPyramid, map_bounds};
use crate::hiz::HIZ_COVER_FACTOR;
use crate::lists::{LIST_COUNT, state_model};
use crate::rays::Rays;
use crate::settings::SplitSettings;

/// Whether a grain's state word says the previous frame kept it (its model is a list).
pub fn was_visible(state: u32) -> bool {
    state_model(state) < LIST_COUNT
}

/// The square a grain covers in phase 1: the occluder-map square
/// ([`splat`]) with the splat factor [`HIZ_COVER_FACTOR`]. Twin of `hiz_cover`'s square.
pub fn cover_square(camera: &SplitCamera, settings: &SplitSettings, grain: Vec4) -> Option<Splat> {
    splat(camera, &SplitSettings { splat_factor: HIZ_COVER_FACTOR, ..*settings }, grain)
}

/// Offers to `base` (level 0, row-major) the bound `D(p)` of every grain visible in the
/// previous frame at each pixel of its [`cover_square`]. `previous_state`: one word per
/// grain, or empty (no history: every grain covers). Nothing where fusion does not apply.
pub(crate) fn cover_into(
    camera: &SplitCamera,
    settings: &SplitSettings,
    grains: &[Vec4],
    previous_state: &[u32],
    base: &mut BaseBounds,
) {
    let width = camera.size().0;
    let Some(rays) = Rays::new(camera).filter(|_| settings.occluder_radius > 0.0) else { return };
    for (index, &grain) in grains.iter().enumerate() {
        if !previous_state.get(index).is_none_or(|&s| was_visible(s)) {
            continue;
        }
        let Some(square) = cover_square(camera, settings, grain) else { continue };
        let g = rays.view(grain.truncate().as_dvec3());
        let radius = f64::from(settings.occluder_radius) * f64::from(grain.w);
        for y in square.min.1..=square.max.1 {
            for x in square.min.0..=square.max.0 {
                base.offer((y * width + x) as usize, rays.pixel_bound((x, y), g, radius), index as u32);
            }
        }
    }
}

impl DepthPyramid {
    /// The pyramid of two-phase culling (this module): per pixel the smaller of the
    /// map's bound and the bounds of the grains visible in the previous frame
    /// (`previous_state`, one word per grain; empty: every grain), each splatted over its
    /// inscribed square ([`cover_square`]).
    pub fn build_two_phase(
        camera: &SplitCamera,
        settings: &SplitSettings,
        grains: &[Vec4],
        map: &OccluderMap,
        previous_state: &[u32],
    ) -> Self {
        let (width, height) = camera.size();
        let mut base = map_bounds(camera, settings, grains, map);
        cover_into(camera, settings, grains, previous_state, &mut base);
        Self::from_base(width, height, base)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fusion::DepthPyramid;
    use crate::lists::{CULLED_CONE, STATE_MODEL_SHIFT};
    use crate::reference::occluder_map;
    use crate::tiers::TierThresholds;
    use glam::Vec3;

    #[test]
    fn covering_grains_bound_more_pixels_than_the_map_and_only_visible_ones_cover() {
        let camera = SplitCamera::perspective(Vec3::ZERO, Vec3::NEG_Z, Vec3::Y, 1.0, (64, 64), (0.1, 100.0)).unwrap();
        let settings = SplitSettings::new(0.9, 1.0, TierThresholds::new(2.0, 64.0, 1.0).unwrap());
        let grains = [Vec4::new(-1.2, 0.0, -10.0, 2.0), Vec4::new(1.2, 0.0, -10.0, 2.0)];
        let map = occluder_map(&camera, &settings, &grains);
        let plain = DepthPyramid::build(&camera, &settings, &grains, &map);
        let two_phase = DepthPyramid::build_two_phase(&camera, &settings, &grains, &map, &[]);
        println!("bounded pixels: map {}, two-phase {}", plain.finite_pixels(), two_phase.finite_pixels());
        assert!(two_phase.finite_pixels() > 2 * plain.finite_pixels());
        let (_, _, a) = plain.level(0).unwrap();
        let (_, _, b) = two_phase.level(0).unwrap();
        assert!(a.iter().zip(b).all(|(a, b)| b <= a), "the minimum never loosens a bound");
        // A grain culled last frame does not cover; a visible one does.
        let culled = CULLED_CONE << STATE_MODEL_SHIFT;
        let covered = |state: &[u32]| {
            let mut base = BaseBounds::empty(64 * 64);
            cover_into(&camera, &settings, &grains, state, &mut base);
            base.bound.iter().filter(|d| d.is_finite()).count()
        };
        let (none, one, all) = (covered(&[culled, culled]), covered(&[culled, 0]), covered(&[]));
        assert_eq!(none, 0);
        assert!(one > 0 && one < all);
    }
}
