//! The culling experiments of the paper's Fig. 15 on the CPU reference: the proportion of
//! grains still rendered after occlusion culling as the inner radius assumed for culling
//! goes from `R` to 0, and as the occluder map's splat factor varies (§8 measured 0.15–0.2).
//!
//! Fig. 15 relaxes the *hypothesis* `r/R` on fixed stackings; on grains whose true inner
//! radius is smaller than the `r` assumed, the higher ratios would cull visible grains — the
//! curve measures how much culling each hypothesis buys, not a safe setting. Run it on balls
//! (`r = R`) for every point to be conservative.

use glam::{Vec3, Vec4};

use crate::camera::SplitCamera;
use crate::error::SplitError;
use crate::fusion::{DepthPyramid, check_fusion, fused_split_counts};
use crate::reference::{occluder_map, split};
use crate::settings::SplitSettings;

/// The culling of one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CullingPoint {
    /// The occluder radius over the outer radius assumed for culling.
    pub ratio: f32,
    /// The occluder map's splat factor.
    pub splat_factor: f32,
    /// Grains in the scene.
    pub grains: u32,
    /// Grains inside the frustum (not frustum-culled).
    pub in_frustum: u32,
    /// Grains culled by the occlusion cone.
    pub cone_culled: u32,
    /// Grains that occluder fusion ([`crate::fusion`]) culls besides those.
    pub fusion_extra: u32,
    /// Rays cast by the fusion check ([`crate::fusion::check_fusion`], 4 per fused grain).
    pub fusion_rays: u64,
    /// Of those, rays that reach a culled grain before its pixel's occluder: must be 0.
    pub fusion_violations: u64,
    /// Grains that two-phase culling ([`crate::temporal`]: the Hi-Z test with the grains
    /// visible in the previous frame as occluders) culls besides the cone, in the second of
    /// two frames from the same camera (the first has no history: every grain covers).
    pub two_phase_extra: u32,
    /// Rays cast by the check of the second frame's pyramid.
    pub two_phase_rays: u64,
    /// Of those, rays that reach a culled grain first: must be 0.
    pub two_phase_violations: u64,
    /// Pixels of the occluder map holding an occluder.
    pub map_filled: u32,
    /// Pixels of the occluder map.
    pub map_pixels: u32,
}

impl CullingPoint {
    /// Fig. 15's measure: the grains still rendered over the grains in the frustum.
    pub fn rendered_fraction(&self) -> f64 {
        if self.in_frustum == 0 {
            return 1.0;
        }
        f64::from(self.in_frustum - self.cone_culled) / f64::from(self.in_frustum)
    }

    /// The same with occluder fusion as well as the cone.
    pub fn rendered_fraction_with_fusion(&self) -> f64 {
        self.rendered_with(self.fusion_extra)
    }

    /// The same with two-phase culling as well as the cone.
    pub fn rendered_fraction_two_phase(&self) -> f64 {
        self.rendered_with(self.two_phase_extra)
    }

    fn rendered_with(&self, extra: u32) -> f64 {
        if self.in_frustum == 0 {
            return 1.0;
        }
        f64::from(self.in_frustum - self.cone_culled - extra) / f64::from(self.in_frustum)
    }
}

/// One frame of the CPU reference with `settings`, counted, with occluder fusion and
/// two-phase culling (two frames), each with its ray check.
pub fn culling_point(
    camera: &SplitCamera,
    settings: &SplitSettings,
    grains: &[Vec4],
) -> Result<CullingPoint, SplitError> {
    settings.validate()?;
    let map = occluder_map(camera, settings, grains);
    let fused = fused_split_counts(camera, settings, grains, &map);
    let check = check_fusion(camera, settings, grains, &DepthPyramid::build(camera, settings, grains, &map), 4, 0x5eed);
    let two_phase = SplitSettings { hiz_culling: true, temporal_occluders: true, ..*settings };
    let first = split(camera, &two_phase, grains, &map, &[])?;
    let second = split(camera, &two_phase, grains, &map, &first.state)?;
    let pyramid = DepthPyramid::build_two_phase(camera, &two_phase, grains, &map, &first.state);
    let two_phase_check = check_fusion(camera, &two_phase, grains, &pyramid, 4, 0x5eed);
    Ok(CullingPoint {
        ratio: settings.occluder_radius / settings.outer_radius,
        splat_factor: settings.splat_factor,
        grains: grains.len() as u32,
        in_frustum: grains.len() as u32 - fused.frustum,
        cone_culled: fused.cone,
        fusion_extra: fused.fusion_only,
        fusion_rays: check.rays,
        fusion_violations: check.violations,
        two_phase_extra: second.counters.culled[2],
        two_phase_rays: two_phase_check.rays,
        two_phase_violations: two_phase_check.violations,
        map_filled: map.filled() as u32,
        map_pixels: map.ids.len() as u32,
    })
}

/// Fig. 15: [`culling_point`] at each ratio `r/R` (occluder radius `ratio · outer_radius`).
pub fn ratio_sweep(
    camera: &SplitCamera,
    base: &SplitSettings,
    grains: &[Vec4],
    ratios: &[f32],
) -> Result<Vec<CullingPoint>, SplitError> {
    ratios
        .iter()
        .map(|&ratio| {
            let settings = SplitSettings { occluder_radius: ratio * base.outer_radius, ..*base };
            culling_point(camera, &settings, grains)
        })
        .collect()
}

/// §8's splat size: [`culling_point`] at each splat factor.
pub fn splat_sweep(
    camera: &SplitCamera,
    base: &SplitSettings,
    grains: &[Vec4],
    factors: &[f32],
) -> Result<Vec<CullingPoint>, SplitError> {
    factors
        .iter()
        .map(|&splat_factor| culling_point(camera, &SplitSettings { splat_factor, ..*base }, grains))
        .collect()
}

/// A camera shot of a stacking, sized from its bounding box (Fig. 15's three curves).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shot {
    /// What the shot is.
    pub name: &'static str,
    /// The eye.
    pub eye: Vec3,
    /// The point looked at.
    pub target: Vec3,
    /// The vertical field of view in radians.
    pub fov_y: f32,
}

impl Shot {
    /// The three shots of Fig. 15 for a stacking inside the box `min..max`, all looking at
    /// its centre from the same direction (front, above): **wide** (60° field of view, the
    /// bounding sphere framed), **narrow** (17°, from farther: more parallel rays, less
    /// culling) and **foreground** (80°, the eye just outside the bounding sphere: near
    /// grains hide much of the rest).
    pub fn fig15(min: Vec3, max: Vec3) -> [Shot; 3] {
        let target = 0.5 * (min + max);
        let radius = 0.5 * (max - min).length();
        let direction = Vec3::new(0.0, 0.35, 1.0).normalize();
        let at = |name, fov_y: f32, distance: f32| Shot { name, eye: target + direction * distance, target, fov_y };
        [
            at("wide", 60f32.to_radians(), radius / (30f32.to_radians()).sin()),
            at("narrow", 17f32.to_radians(), radius / (8.5f32.to_radians()).sin()),
            at("foreground", 80f32.to_radians(), 1.05 * radius),
        ]
    }

    /// The shot's camera at `size` pixels (near plane `10⁻³` of the eye's distance, far
    /// plane beyond the stacking).
    pub fn camera(&self, size: (u32, u32)) -> Result<SplitCamera, SplitError> {
        let distance = self.eye.distance(self.target);
        SplitCamera::perspective(self.eye, self.target, Vec3::Y, self.fov_y, size, (1e-3 * distance, 4.0 * distance))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tiers::TierThresholds;

    fn lattice(n: i32) -> Vec<Vec4> {
        let mut grains = Vec::new();
        for z in 0..n {
            for y in 0..n {
                for x in 0..n {
                    grains.push(Vec4::new(x as f32 * 2.05, y as f32 * 2.05, z as f32 * 2.05, 1.0));
                }
            }
        }
        grains
    }

    #[test]
    fn no_inner_radius_culls_nothing_and_errors_pass_through() {
        let grains = lattice(10);
        let camera =
            SplitCamera::perspective(Vec3::new(9.0, 9.0, 60.0), Vec3::splat(9.0), Vec3::Y, 0.8, (96, 96), (0.1, 200.0))
                .unwrap();
        let base = SplitSettings::new(1.0, 1.0, TierThresholds::new(1.0, 100.0, 1.0).unwrap());
        let points = ratio_sweep(&camera, &base, &grains, &[1.0, 0.5, 0.0]).unwrap();
        assert_eq!(points[2].cone_culled, 0);
        assert_eq!(points[2].map_filled, 0);
        assert_eq!(points[2].rendered_fraction(), 1.0);
        assert!(points[0].cone_culled > 0, "balls in a dense lattice hide each other");
        assert!(points.iter().all(|p| p.fusion_violations == 0));
        assert_eq!(points[2].fusion_extra, 0, "no inner radius, no fusion");
        assert!(points.iter().all(|p| p.in_frustum == points[0].in_frustum));
        let bad = SplitSettings { splat_factor: -1.0, ..base };
        assert!(culling_point(&camera, &bad, &grains).unwrap_err().to_string().contains("splat_factor"));
        let splats = splat_sweep(&camera, &base, &grains, &[0.1, 1.0]).unwrap();
        assert!(splats[1].map_filled >= splats[0].map_filled, "larger squares fill more pixels");
    }

    #[test]
    fn the_shots_see_the_whole_box_except_the_foreground_one() {
        let (min, max) = (Vec3::ZERO, Vec3::new(40.0, 20.0, 40.0));
        let corners =
            (0..8).map(|i| Vec3::new([min.x, max.x][i & 1], [min.y, max.y][i >> 1 & 1], [min.z, max.z][i >> 2]));
        for shot in Shot::fig15(min, max) {
            let camera = shot.camera((160, 90)).unwrap();
            let outside = corners.clone().filter(|&c| crate::reference::outside_frustum(&camera, c, 0.0)).count();
            assert_eq!(outside == 0, shot.name != "foreground", "{}: {outside} corners outside", shot.name);
        }
    }
}
