//! Choosing the atlas `(n, p)` and sampling mode for a grain from its size on screen and an
//! error budget (§6 of the paper, then measured).
//!
//! # The paper's rule (eq. 4)
//!
//! §6: the grain's apparent diameter in pixels fixes `p` (one texel per pixel at mip 0), and
//! eq. 4 bounds the angle between the view and the nearest precomputed direction,
//! `θ ≤ arccos √(1/(1 + 1/p²))`, which fixes `n` through the octahedron's neighbour spacing
//! ([`octahedral_map::min_subdivisions_for_texels`]). [`paper_choice`] implements it. It is
//! very conservative (p = 64 asks for n = 137, 37 538 views): the paper itself uses fewer
//! views, relying on mixed sampling.
//!
//! # The measured rule
//!
//! [`choose_atlas`] picks, among measured configurations, the one with the **least memory**
//! whose SSIM against the mesh loses at most `max_ssim_loss` (`1 − SSIM ≤ budget`). The
//! measurements are rows of the accuracy sweep ([`crate::accuracy`]): SSIM of the
//! `image-compare` crate on luma, non-overlapping 8 × 8 windows, over a grid of 64 copies of
//! the grain seen from a spherical Fibonacci set of directions, under the same deferred
//! shading as the mesh (see [`crate::accuracy::metrics`]). A budget of 0.05 therefore means
//! "SSIM ≥ 0.95 on that scene". The rows of the grain measured at the smallest screen size
//! **at or above** the requested one are used (error grows with size on screen), so the
//! choice is conservative between measured sizes; beyond the largest measured size there is
//! no choice (`None`), because nothing was measured there.
//!
//! [`MEASURED_ACCURACY_CSV`] is the table measured by `cargo xtask impostor-accuracy` on the
//! four procedural grains (ball, bean, rock, nut) and committed with the crate.

use octahedral_map::{SamplingMode, ViewLayout};

use crate::accuracy::{SweepRow, rows_from_csv};

/// The accuracy table committed with the crate (`data/impostor_accuracy.csv`), measured with
/// `cargo xtask impostor-accuracy` (see the file's rows for the configurations).
pub const MEASURED_ACCURACY_CSV: &str = include_str!("../data/impostor_accuracy.csv");

/// The committed measurements, parsed.
pub fn measured_accuracy() -> Result<Vec<SweepRow>, String> {
    rows_from_csv(MEASURED_ACCURACY_CSV)
}

/// An atlas configuration chosen for a grain.
#[derive(Clone, Debug, PartialEq)]
pub struct AtlasChoice {
    /// `n`: views per edge.
    pub subdivisions: u32,
    /// `p`: texels per view side.
    pub texels: u32,
    /// The sampling mode to render it with.
    pub mode: SamplingMode,
    /// The atlas layout (the compact one whenever it was measured: same SSIM, less memory).
    pub layout: ViewLayout,
    /// GPU bytes of the atlas (in `layout`, full mips).
    pub atlas_bytes: u64,
    /// The SSIM measured for this configuration.
    pub measured_ssim: f64,
    /// The screen size (pixels) at which it was measured.
    pub measured_diameter: f32,
}

/// The smallest power of two `p ≥ apparent_diameter` (one texel per pixel at mip 0, §6), or
/// `None` for a non-finite, non-positive or huge (> 2³¹) diameter.
pub fn texels_for_diameter(apparent_diameter: f32) -> Option<u32> {
    if !(apparent_diameter.is_finite() && apparent_diameter > 0.0 && apparent_diameter <= 2_147_483_648.0) {
        return None;
    }
    (apparent_diameter.ceil() as u32).max(1).checked_next_power_of_two()
}

/// The paper's `(n, p)` for a grain `apparent_diameter` pixels wide: `p` from
/// [`texels_for_diameter`], `n` the smallest subdivision whose neighbouring views are within
/// eq. 4's validity cone, at most `max_subdivisions`; `None` when no `n` fits.
pub fn paper_choice(apparent_diameter: f32, max_subdivisions: u32) -> Option<(u32, u32)> {
    let texels = texels_for_diameter(apparent_diameter)?;
    let subdivisions = octahedral_map::min_subdivisions_for_texels(texels, max_subdivisions)?;
    Some((subdivisions, texels))
}

/// The cheapest measured configuration of `grain` whose SSIM loss at the grain's screen size
/// is within `max_ssim_loss` (see the module documentation); `None` when the grain or a large
/// enough screen size was not measured, the inputs are not finite, or nothing meets the
/// budget. Ties in memory go to the higher SSIM.
pub fn choose_atlas(rows: &[SweepRow], grain: &str, apparent_diameter: f32, max_ssim_loss: f64) -> Option<AtlasChoice> {
    if !(apparent_diameter.is_finite() && apparent_diameter > 0.0 && max_ssim_loss.is_finite()) {
        return None;
    }
    let measured_diameter = rows
        .iter()
        .filter(|r| r.grain == grain && r.apparent_diameter >= apparent_diameter)
        .map(|r| r.apparent_diameter)
        .min_by(f32::total_cmp)?;
    rows.iter()
        .filter(|r| r.grain == grain && r.apparent_diameter == measured_diameter)
        .filter(|r| 1.0 - r.error.ssim <= max_ssim_loss)
        .min_by(|a, b| a.atlas_bytes.cmp(&b.atlas_bytes).then(b.error.ssim.total_cmp(&a.error.ssim)))
        .map(|r| AtlasChoice {
            subdivisions: r.subdivisions,
            texels: r.texels,
            mode: r.mode,
            layout: r.layout,
            atlas_bytes: r.atlas_bytes,
            measured_ssim: r.error.ssim,
            measured_diameter,
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texels_follow_the_screen_size() {
        assert_eq!(texels_for_diameter(1.0), Some(1));
        assert_eq!(texels_for_diameter(32.0), Some(32));
        assert_eq!(texels_for_diameter(33.0), Some(64));
        assert_eq!(texels_for_diameter(100.0), Some(128));
        for bad in [0.0, -1.0, f32::NAN, f32::INFINITY, 1e12] {
            assert_eq!(texels_for_diameter(bad), None);
        }
    }

    #[test]
    fn paper_choice_follows_eq_4() {
        let (n, p) = paper_choice(60.0, 4096).unwrap();
        assert_eq!(p, 64);
        // Neighbouring views of n must be within the validity cone 2·atan(1/64) ≈ 1.79°, and
        // those of n − 1 must not.
        let cone = 2.0 * octahedral_map::validity_half_angle(64).unwrap();
        assert!(octahedral_map::max_neighbour_angle(n).unwrap() <= cone);
        assert!(octahedral_map::max_neighbour_angle(n - 1).unwrap() > cone);
        assert_eq!(paper_choice(60.0, 16), None);
    }

    #[test]
    fn the_committed_table_parses_and_covers_the_issue_grid() {
        let rows = measured_accuracy().unwrap();
        for grain in ["ball", "bean", "rock", "nut"] {
            for n in [4, 6, 8, 10, 12] {
                for p in [32, 64, 128] {
                    let count =
                        rows.iter().filter(|r| r.grain == grain && r.subdivisions == n && r.texels == p).count();
                    assert_eq!(count, 16, "{grain} n={n} p={p}: 4 modes × 2 layouts × 2 screen sizes");
                }
            }
        }
    }

    #[test]
    fn a_larger_budget_never_costs_more_and_choices_meet_the_budget() {
        let rows = measured_accuracy().unwrap();
        for grain in ["ball", "bean", "rock", "nut"] {
            for diameter in [20.0, 32.0, 48.0, 64.0] {
                let mut previous = u64::MAX;
                for budget in [0.01, 0.02, 0.05, 0.1, 0.2, 0.5] {
                    if let Some(choice) = choose_atlas(&rows, grain, diameter, budget) {
                        assert!(1.0 - choice.measured_ssim <= budget);
                        assert!(choice.measured_diameter >= diameter);
                        assert!(choice.atlas_bytes <= previous, "{grain} {diameter}px budget {budget}");
                        previous = choice.atlas_bytes;
                    } else {
                        assert_eq!(previous, u64::MAX, "{grain}: a smaller budget was met but {budget} is not");
                    }
                }
            }
            // Beyond the largest measured screen size there is no measured answer.
            assert_eq!(choose_atlas(&rows, grain, 1000.0, 0.5), None);
        }
        assert_eq!(choose_atlas(&rows, "teapot", 32.0, 0.5), None);
        // The compact layout renders the same images with less memory, so it is chosen.
        let bean = choose_atlas(&rows, "bean", 32.0, 0.06).unwrap();
        assert_eq!(bean.layout, ViewLayout::Compact);
        assert_eq!(bean.mode, SamplingMode::Mixed);
        assert_eq!(choose_atlas(&rows, "ball", f32::NAN, 0.5), None);
    }
}
