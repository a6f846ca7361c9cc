//! [`RendererOptions`]: what a [`StackingRenderer`](crate::StackingRenderer) is built for.

use grain_splitter::OccluderMapKind;

use crate::impostor_tier::VisibilityKind;

/// A point threshold no grain on screen is below: no grain goes to the point list.
pub const NO_POINT_TIER: f32 = 1e-6;

/// What a renderer is built for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RendererOptions {
    /// Viewport in pixels.
    pub size: (u32, u32),
    /// The most grains a scene may hold (of each grain type).
    pub capacity: u32,
    /// Projected diameter (pixels) above which a grain is a mesh: the measured impostor
    /// table's (`TierThresholds::from_impostor_table`), never a distance. A scene of several
    /// grain types takes each type's own ([`GrainType`](crate::GrainType)).
    pub mesh_above: f32,
    /// Projected diameter (pixels) below which a grain is a point ([`NO_POINT_TIER`]: none
    /// are): measured by [`crate::point_threshold::measure`], never a distance (per type
    /// likewise).
    pub point_below: f32,
    /// Hysteresis band (≥ 1) around both thresholds.
    pub band: f32,
    /// The occluder map's atomics.
    pub occluder_map: OccluderMapKind,
    /// The visibility buffer's atomics.
    pub visibility: VisibilityKind,
    /// Frustum, cone, Hi-Z and two-phase culling (all conservative: off only to compare).
    pub culling: bool,
    /// Visibility samples per pixel side of the impostor and point tiers (1: a pixel is
    /// covered or not at its centre; 2: fractional silhouettes, 4× the atlas evaluations;
    /// `crate::impostor_tier`, "Silhouettes").
    pub samples: u32,
}
