//! What the tables measure: the tile, the view, the maps' settings and the timing rounds.

use ddm_compress::DistanceMapSettings;
use ddm_tracer::{Method, Stepping, TraceSettings};
use glam::UVec3;

use super::BUDGETS;
use crate::ExperimentError;
use crate::steps::StepsSettings;
use crate::timing::RATIO_ROUNDS;

/// Settings of the tables.
#[derive(Clone, Debug, PartialEq)]
pub struct TraceTablesSettings {
    /// Voxels of the tile.
    pub dims: UVec3,
    /// Pixels per row of the view.
    pub width: u32,
    /// Rows of the view.
    pub height: u32,
    /// How the maps are computed.
    pub map_settings: DistanceMapSettings,
    /// Map reads before a ray gives up.
    pub max_steps: u32,
    /// Block side of Table 3's compressed maps.
    pub compression_block: u32,
    /// Error budget (voxels) of the `adaptive` patches: the accuracy goal.
    pub adaptive_budget: f32,
    /// Cells per voxel and axis of the `watertight` patches
    /// ([`ddm_tracer::PatchSettings::watertight_subdivision`]; 1: the voxels).
    pub watertight_subdivision: u32,
    /// Error budgets (voxels) of [`super::TraceScene::budget_rows`].
    pub budgets: Vec<f32>,
    /// Timed CPU passes per method; its time is the fastest.
    pub timed_passes: usize,
    /// Rounds of the interleaved raw / compressed time ratio (its median).
    pub ratio_rounds: usize,
    /// The steps-against-angle sweep.
    pub steps: StepsSettings,
}

impl TraceTablesSettings {
    /// The tables as `cargo xtask ddm-trace` measures them: 24 × 24 × 8 voxel tiles,
    /// 192 × 144 rays, tolerance 0.25 voxel, 512 steps, blocks of 4, budget 1e-3 voxel,
    /// fastest of 5 passes, median of [`RATIO_ROUNDS`] rounds.
    pub fn full() -> Self {
        Self {
            dims: UVec3::new(24, 24, 8),
            width: 192,
            height: 144,
            map_settings: DistanceMapSettings { tolerance: 0.25, periodic_xy: true },
            max_steps: 512,
            compression_block: 4,
            adaptive_budget: 1e-3,
            watertight_subdivision: 1,
            budgets: BUDGETS.to_vec(),
            timed_passes: 5,
            ratio_rounds: RATIO_ROUNDS,
            steps: StepsSettings::default(),
        }
    }

    /// [`TraceTablesSettings::full`] on 12 × 12 × 6 voxel tiles and 96 × 72 rays.
    pub fn quick() -> Self {
        Self { dims: UVec3::new(12, 12, 6), width: 96, height: 72, ..Self::full() }
    }

    /// Checks the fields that no later step meets as a scene error.
    pub fn validate(&self) -> Result<(), ExperimentError> {
        let positive = |x: f32| x.is_finite() && x > 0.0;
        if self.dims.cmpeq(UVec3::ZERO).any() {
            return Err(ExperimentError::settings("dims", format!("every size must be positive, not {}", self.dims)));
        }
        if self.width == 0 || self.height == 0 {
            return Err(ExperimentError::settings(
                "width/height",
                format!("empty view {}x{}", self.width, self.height),
            ));
        }
        if self.max_steps == 0 {
            return Err(ExperimentError::settings("max_steps", "must be positive"));
        }
        if !(1..=64).contains(&self.compression_block) {
            return Err(ExperimentError::settings(
                "compression_block",
                format!("must be 1 to 64, not {}", self.compression_block),
            ));
        }
        if !positive(self.adaptive_budget) {
            return Err(ExperimentError::settings(
                "adaptive_budget",
                format!("{} is not positive", self.adaptive_budget),
            ));
        }
        if !(1..=ddm_tracer::MAX_WATERTIGHT_SUBDIVISION).contains(&self.watertight_subdivision) {
            return Err(ExperimentError::settings(
                "watertight_subdivision",
                format!("must be 1 to {}, not {}", ddm_tracer::MAX_WATERTIGHT_SUBDIVISION, self.watertight_subdivision),
            ));
        }
        if let Some(budget) = self.budgets.iter().find(|&&b| !positive(b)) {
            return Err(ExperimentError::settings("budgets", format!("{budget} is not positive")));
        }
        if self.timed_passes == 0 || self.ratio_rounds == 0 {
            return Err(ExperimentError::settings("timed_passes/ratio_rounds", "must be positive"));
        }
        self.steps.validate()
    }

    pub(super) fn sphere(&self) -> TraceSettings {
        TraceSettings { method: Method::SphereTracing, max_steps: self.max_steps, stepping: Stepping::Distance }
    }

    pub(super) fn quadric(&self) -> TraceSettings {
        TraceSettings { method: Method::Quadric, max_steps: self.max_steps, stepping: Stepping::Distance }
    }
}
