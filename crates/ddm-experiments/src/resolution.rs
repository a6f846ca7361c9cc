//! Error against resolution: each patch construction's accuracy against the tile's own
//! surface ([`crate::reference`](mod@crate::reference)) as the same tile is sampled by finer grids.
//!
//! A tile of `n × n × max(4, n / 3)` voxels (its shapes scale with it, so a feature spans
//! more voxels as `n` grows) is traced from the tables' camera ([`View::perspective`])
//! through the DDM 4×1 with each [`PatchKind`], and measured against its reference:
//! |SDF(hit)| in voxels of that grid and in tile widths, and leaks. A construction that
//! converges shows its error in tile widths falling with `n`; one limited by the mesh's
//! facets (the exact triangles against an analytic sphere) does not.

use ddm_compress::DistanceMapSettings;
use ddm_tracer::{Method, PatchSettings, Stepping, TraceSettings, VoxelPatches, trace};
use glam::UVec3;
use mesostructure::Mesostructure;

use crate::ExperimentError;
use crate::maps::{TableMap, compute_named};
use crate::reference::{ReferenceAccuracy, ReferenceSurface, reference_accuracy};
use crate::trace_tables::PatchKind;
use crate::view::View;

/// Settings of [`resolution_sweep`].
#[derive(Clone, Debug, PartialEq)]
pub struct ResolutionSettings {
    /// Voxels across the tile (x and y), one grid each.
    pub voxels_across: Vec<u32>,
    /// Pixels per row of the view.
    pub width: u32,
    /// Rows of the view.
    pub height: u32,
    /// How the maps are computed.
    pub map_settings: DistanceMapSettings,
    /// The adaptive patches' error budget (voxels).
    pub adaptive_budget: f32,
    /// Map reads before a ray gives up.
    pub max_steps: u32,
}

impl ResolutionSettings {
    /// 12, 24, 48 and 96 voxels across (the range), 96 × 72 rays.
    pub fn full() -> Self {
        Self {
            voxels_across: vec![12, 24, 48, 96],
            width: 96,
            height: 72,
            map_settings: DistanceMapSettings { tolerance: 0.25, periodic_xy: true },
            adaptive_budget: 1e-3,
            max_steps: 2048,
        }
    }

    /// 12 and 24 voxels across, 48 × 36 rays.
    pub fn quick() -> Self {
        Self { voxels_across: vec![12, 24], width: 48, height: 36, ..Self::full() }
    }

    /// The grid of `n` voxels across: `n × n × max(4, n / 3)`.
    pub fn dims(n: u32) -> UVec3 {
        UVec3::new(n, n, (n / 3).max(4))
    }
}

/// One construction at one resolution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ResolutionRow {
    /// The tile.
    pub mesostructure: &'static str,
    /// Voxels across the tile.
    pub voxels_across: u32,
    /// The patch construction.
    pub patches: PatchKind,
    /// Its accuracy, in voxels of this grid.
    pub accuracy: ReferenceAccuracy,
}

impl ResolutionRow {
    /// The p99 of |SDF(hit)| in tile widths (comparable across resolutions).
    pub fn p99_tile_widths(&self) -> f64 {
        self.accuracy.p99 / f64::from(self.voxels_across)
    }
}

/// The rows of `which` at every resolution of `settings`, in [`PatchKind::ALL`] order per
/// resolution.
///
/// # Errors
///
/// [`ExperimentError::InvalidSettings`] for no resolution, a resolution below 4 or an
/// empty view; [`ExperimentError::Scene`] when a map or a patch construction fails.
pub fn resolution_sweep(
    which: Mesostructure,
    settings: &ResolutionSettings,
) -> Result<Vec<ResolutionRow>, ExperimentError> {
    if settings.voxels_across.is_empty() {
        return Err(ExperimentError::settings("voxels_across", "no resolution given"));
    }
    if let Some(n) = settings.voxels_across.iter().find(|&&n| n < 4) {
        return Err(ExperimentError::settings("voxels_across", format!("{n} is below 4")));
    }
    let name = which.name();
    let trace_settings =
        TraceSettings { method: Method::Quadric, max_steps: settings.max_steps, stepping: Stepping::Distance };
    let mut rows = Vec::new();
    for &n in &settings.voxels_across {
        let dims = ResolutionSettings::dims(n);
        let triangles = which.triangles(dims);
        let view = View::perspective(dims, settings.width, settings.height)?;
        let maps = compute_named(name, dims, &triangles, TableMap::ddm("DDM 4x1", 4, 1), settings.map_settings)?;
        let reference = ReferenceSurface::of(which, dims);
        for kind in PatchKind::ALL {
            let patch_settings =
                PatchSettings { surface: kind.surface(settings.adaptive_budget), ..PatchSettings::default() };
            let patches = VoxelPatches::build(dims, &triangles, &maps.maps.surface, patch_settings).map_err(|e| {
                ExperimentError::scene(name, format!("the {} patches at {n} voxels across failed: {e}", kind.name()))
            })?;
            let outcomes: Vec<_> =
                view.rays.iter().map(|&(o, d)| trace(&maps.maps, Some(&patches), o, d, trace_settings)).collect();
            let accuracy = reference_accuracy(&reference, &view.rays, &outcomes, dims.z as f32);
            rows.push(ResolutionRow { mesostructure: name, voxels_across: n, patches: kind, accuracy });
        }
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_exact_triangles_of_a_height_field_stay_exact_and_bad_settings_are_named() {
        let settings =
            ResolutionSettings { voxels_across: vec![8, 12], width: 12, height: 9, ..ResolutionSettings::quick() };
        let rows = resolution_sweep(Mesostructure::Bricks, &settings).unwrap();
        assert_eq!(rows.len(), 2 * PatchKind::ALL.len());
        for row in rows.iter().filter(|r| r.patches == PatchKind::Triangles) {
            // The height field's triangles are its reference: only f32 rounding of the hit.
            assert!(row.accuracy.max < 1e-3 && row.accuracy.leaks == 0, "{row:?}");
            assert!(row.accuracy.hits > 0);
        }
        let none = ResolutionSettings { voxels_across: vec![], ..settings.clone() };
        assert!(resolution_sweep(Mesostructure::Ball, &none).unwrap_err().to_string().contains("voxels_across"));
        let tiny = ResolutionSettings { voxels_across: vec![2], ..settings };
        assert!(resolution_sweep(Mesostructure::Ball, &tiny).unwrap_err().to_string().contains("2 is below 4"));
    }
}
