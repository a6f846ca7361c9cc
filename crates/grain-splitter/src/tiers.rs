//! Which model draws a grain: mesh, impostor or point, from its **projected diameter** in
//! pixels (§6–7 of the paper, which discriminates by distance), with a hysteresis band.
//!
//! # Thresholds
//!
//! - Mesh above `mesh_above` pixels: the largest diameter at which the measured impostor
//!   table still has an atlas within the error budget
//!   ([`TierThresholds::from_impostor_table`], from `grain_impostor::choice`); beyond it
//!   nothing was measured to be good enough, so the mesh draws the grain.
//! - Point below `point_below` pixels, impostor in between.
//!
//! `GrainViewer` discriminates by hand-tuned view distances (`instanceLimit`, `impostorLimit`);
//! a diameter in pixels is what the impostor's error depends on (§6), and it follows the
//! field of view, the resolution and each grain's scale.
//!
//! # Hysteresis
//!
//! A grain at a threshold would flicker between two models as it jitters. With a band
//! `b ≥ 1`, a grain moves to a finer model only when its diameter exceeds the threshold
//! times `b`, and back only when it falls below the threshold divided by `b`; a grain with
//! no history (the first frame) uses the threshold itself. [`TierThresholds::new`] requires
//! `point_below · b < mesh_above / b`, so the two bands never overlap and a grain never
//! skips the impostor tier by hysteresis alone.
//!
//! # No division
//!
//! The diameter of a grain of outer radius `R·s` at view depth `z` is `d = 2 R s f / z`
//! (`f` the focal length in pixels, see [`crate::SplitCamera`]). The test `d > T` is
//! evaluated as `2 R s f > T z`: two correctly rounded products, the same on every adapter,
//! so the CPU reference and the GPU agree exactly (WGSL's division may be off by 2.5 ulp).

use crate::error::SplitError;

/// A model a grain can be drawn with, from coarsest to finest.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Tier {
    /// A point (or small splat).
    Point = 0,
    /// An octahedral impostor.
    Impostor = 1,
    /// The grain's mesh.
    Mesh = 2,
}

impl Tier {
    /// All tiers, coarsest first.
    pub const ALL: [Tier; 3] = [Tier::Point, Tier::Impostor, Tier::Mesh];

    /// The tier of a state code (`1 + tier`, 0 = none), as stored per grain.
    pub fn from_code(code: u32) -> Option<Tier> {
        match code {
            1 => Some(Tier::Point),
            2 => Some(Tier::Impostor),
            3 => Some(Tier::Mesh),
            _ => None,
        }
    }

    /// `1 + tier`, the state code of this tier (0 means no history).
    pub fn code(self) -> u32 {
        self as u32 + 1
    }
}

/// The tier thresholds and the hysteresis band, validated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TierThresholds {
    point_below: f32,
    mesh_above: f32,
    band: f32,
}

impl TierThresholds {
    /// Points below `point_below` pixels of projected diameter, meshes above `mesh_above`,
    /// hysteresis band `band ≥ 1` (1 = none). Errors name the field: both thresholds finite
    /// and positive, `band` finite and ≥ 1, and `point_below · band < mesh_above / band`.
    pub fn new(point_below: f32, mesh_above: f32, band: f32) -> Result<Self, SplitError> {
        let bad = |field: &'static str, value: f32, reason: &str| SplitError::InvalidSetting {
            field,
            reason: format!("{value}: {reason}"),
        };
        if !(point_below.is_finite() && point_below > 0.0) {
            return Err(bad("point_below", point_below, "must be finite and positive (pixels)"));
        }
        if !(mesh_above.is_finite() && mesh_above > 0.0) {
            return Err(bad("mesh_above", mesh_above, "must be finite and positive (pixels)"));
        }
        if !(band.is_finite() && band >= 1.0) {
            return Err(bad("band", band, "must be finite and at least 1"));
        }
        if point_below * band >= mesh_above / band {
            return Err(bad("band", band, &format!("point_below·band must stay below mesh_above/band ({mesh_above})")));
        }
        Ok(Self { point_below, mesh_above, band })
    }

    /// `mesh_above` from the measured impostor table: the largest apparent diameter at which
    /// [`grain_impostor::choice::choose_atlas`] finds an atlas of `grain` within
    /// `max_ssim_loss`; an error naming the grain when no measured size meets the budget.
    pub fn from_impostor_table(
        rows: &[grain_impostor::accuracy::SweepRow],
        grain: &str,
        max_ssim_loss: f64,
        point_below: f32,
        band: f32,
    ) -> Result<Self, SplitError> {
        let covered = rows
            .iter()
            .filter(|row| row.grain == grain)
            .map(|row| row.apparent_diameter)
            .filter(|&d| grain_impostor::choice::choose_atlas(rows, grain, d, max_ssim_loss).is_some())
            .max_by(f32::total_cmp);
        let mesh_above = covered.ok_or_else(|| SplitError::InvalidSetting {
            field: "grain",
            reason: format!("no measured impostor of `{grain}` is within an SSIM loss of {max_ssim_loss}"),
        })?;
        Self::new(point_below, mesh_above, band)
    }

    /// Points below this projected diameter (pixels).
    pub fn point_below(&self) -> f32 {
        self.point_below
    }

    /// Meshes above this projected diameter (pixels).
    pub fn mesh_above(&self) -> f32 {
        self.mesh_above
    }

    /// The hysteresis band (1 = none).
    pub fn band(&self) -> f32 {
        self.band
    }

    /// `(up, down, plain)` thresholds of the point | impostor boundary, as the shader gets
    /// them.
    pub fn point_boundary(&self) -> [f32; 3] {
        [self.point_below * self.band, self.point_below / self.band, self.point_below]
    }

    /// `(up, down, plain)` thresholds of the impostor | mesh boundary.
    pub fn mesh_boundary(&self) -> [f32; 3] {
        [self.mesh_above * self.band, self.mesh_above / self.band, self.mesh_above]
    }

    /// The tier of a grain whose projected diameter is `twice_radius_focal / depth`
    /// (`2 R s f` and the view depth `z`, see the module documentation; `depth ≤ 0` means the
    /// grain reaches the eye plane: a mesh), coming from `previous` (`None`: no history).
    /// Twin of `split_tier` (WGSL).
    pub fn tier(&self, twice_radius_focal: f32, depth: f32, previous: Option<Tier>) -> Tier {
        if depth.is_nan() || depth <= 0.0 {
            return Tier::Mesh;
        }
        let above = |[up, down, plain]: [f32; 3], boundary: Tier| {
            let threshold = match previous {
                None => plain,
                Some(p) if p >= boundary => down,
                Some(_) => up,
            };
            twice_radius_focal > threshold * depth
        };
        match (above(self.point_boundary(), Tier::Impostor), above(self.mesh_boundary(), Tier::Mesh)) {
            (_, true) => Tier::Mesh,
            (true, false) => Tier::Impostor,
            (false, false) => Tier::Point,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thresholds_split_by_diameter() {
        let t = TierThresholds::new(3.0, 40.0, 1.0).unwrap();
        assert_eq!(t.tier(2.0, 1.0, None), Tier::Point);
        assert_eq!(t.tier(3.5, 1.0, None), Tier::Impostor);
        assert_eq!(t.tier(40.5, 1.0, None), Tier::Mesh);
        // d = 2Rsf / z: the same grain twice as far is half as wide.
        assert_eq!(t.tier(50.0, 2.0, None), Tier::Impostor);
        assert_eq!(t.tier(1.0, 0.0, None), Tier::Mesh, "reaches the eye plane");
        assert_eq!(t.tier(1.0, f32::NAN, None), Tier::Mesh);
    }

    #[test]
    fn hysteresis_keeps_the_previous_tier_inside_the_band() {
        let t = TierThresholds::new(3.0, 40.0, 1.25).unwrap();
        // Just above the mesh threshold: a mesh stays a mesh, an impostor stays an impostor.
        assert_eq!(t.tier(41.0, 1.0, Some(Tier::Mesh)), Tier::Mesh);
        assert_eq!(t.tier(41.0, 1.0, Some(Tier::Impostor)), Tier::Impostor);
        assert_eq!(t.tier(39.0, 1.0, Some(Tier::Mesh)), Tier::Mesh);
        assert_eq!(t.tier(31.0, 1.0, Some(Tier::Mesh)), Tier::Impostor);
        assert_eq!(t.tier(51.0, 1.0, Some(Tier::Impostor)), Tier::Mesh);
        // Point boundary.
        assert_eq!(t.tier(3.5, 1.0, Some(Tier::Point)), Tier::Point);
        assert_eq!(t.tier(2.5, 1.0, Some(Tier::Impostor)), Tier::Impostor);
        assert_eq!(t.tier(2.0, 1.0, Some(Tier::Impostor)), Tier::Point);
        // A point far above every threshold becomes a mesh in one step.
        assert_eq!(t.tier(100.0, 1.0, Some(Tier::Point)), Tier::Mesh);
    }

    #[test]
    fn a_grain_oscillating_inside_the_band_never_switches() {
        let t = TierThresholds::new(3.0, 40.0, 1.1).unwrap();
        for start in [Tier::Impostor, Tier::Mesh] {
            let mut tier = start;
            for i in 0..100 {
                let d = 40.0 * (1.0 + 0.08 * (i as f32 * 0.7).sin());
                tier = t.tier(d, 1.0, Some(tier));
                assert_eq!(tier, start, "frame {i}, d = {d}");
            }
        }
        // Without a band the same oscillation switches.
        let plain = TierThresholds::new(3.0, 40.0, 1.0).unwrap();
        let switches = (0..100)
            .map(|i| plain.tier(40.0 * (1.0 + 0.08 * (i as f32 * 0.7).sin()), 1.0, Some(Tier::Mesh)))
            .filter(|&tier| tier != Tier::Mesh)
            .count();
        assert!(switches > 10);
    }

    #[test]
    fn bad_thresholds_name_the_field() {
        let e = |r: Result<TierThresholds, SplitError>| r.unwrap_err().to_string();
        assert!(e(TierThresholds::new(0.0, 40.0, 1.0)).contains("point_below"));
        assert!(e(TierThresholds::new(3.0, f32::NAN, 1.0)).contains("mesh_above"));
        assert!(e(TierThresholds::new(3.0, 40.0, 0.9)).contains("band"));
        assert!(e(TierThresholds::new(3.0, 40.0, 4.0)).contains("band"));
        assert!(e(TierThresholds::new(50.0, 40.0, 1.0)).contains("band"));
    }

    #[test]
    fn the_mesh_threshold_comes_from_the_measured_table() {
        let rows = grain_impostor::choice::measured_accuracy().unwrap();
        let t = TierThresholds::from_impostor_table(&rows, "bean", 0.1, 2.0, 1.1).unwrap();
        let largest = rows.iter().filter(|r| r.grain == "bean").map(|r| r.apparent_diameter).fold(0.0, f32::max);
        assert!(t.mesh_above() > 2.0 && t.mesh_above() <= largest);
        assert!(grain_impostor::choice::choose_atlas(&rows, "bean", t.mesh_above(), 0.1).is_some());
        let e = TierThresholds::from_impostor_table(&rows, "teapot", 0.1, 2.0, 1.1).unwrap_err();
        assert!(e.to_string().contains("teapot"));
        assert!(TierThresholds::from_impostor_table(&rows, "bean", -1.0, 2.0, 1.1).is_err());
    }

    #[test]
    fn codes_round_trip() {
        for tier in Tier::ALL {
            assert_eq!(Tier::from_code(tier.code()), Some(tier));
        }
        assert_eq!(Tier::from_code(0), None);
    }
}
