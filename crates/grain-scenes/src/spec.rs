//! What to generate: the grain's radii, the lattice, the jitters, the region and the
//! number of grains, each validated with an error naming the field.

use std::fmt;
use std::str::FromStr;

use glam::Vec3;

use crate::error::{SceneError, invalid};

/// The inner radius `r` and outer radius `R` of the grain's mesh at scale 1 (§1: the
/// surface lies between the spheres of radii `r` and `R` about the grain's centre).
///
/// Take them from `grain_mesh::GrainBounds` (`inner_radius`, `outer_radius`; use
/// `occluder_radius()` as `r` for grains whose inner ball is not solid).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GrainRadii {
    inner: f32,
    outer: f32,
}

impl GrainRadii {
    /// Validated radii: finite, `0 ≤ inner ≤ outer`, `outer > 0`.
    pub fn new(inner: f32, outer: f32) -> Result<GrainRadii, SceneError> {
        if !outer.is_finite() || outer <= 0.0 {
            return Err(invalid("radii.outer", outer.into(), "must be finite and > 0"));
        }
        if !inner.is_finite() || inner < 0.0 || inner > outer {
            return Err(invalid("radii.inner", inner.into(), "must be finite with 0 <= inner <= outer"));
        }
        Ok(GrainRadii { inner, outer })
    }

    /// `r`, the inner radius at scale 1.
    pub fn inner(self) -> f32 {
        self.inner
    }

    /// `R`, the outer radius at scale 1.
    pub fn outer(self) -> f32 {
        self.outer
    }

    /// `r / R`, the ratio of Fig. 15.
    pub fn ratio(self) -> f32 {
        self.inner / self.outer
    }
}

/// The largest ratio between the components of a box's aspect.
pub const MAX_ASPECT_RATIO: f32 = 1000.0;
/// The range of a pile's slope (height over base radius).
pub const SLOPE_RANGE: (f32, f32) = (0.05, 20.0);

/// The shape the grains fill, bottom-up from the ground plane `y = 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Region {
    /// A box standing on `y = 0`, centred on the `y` axis. Its footprint has the
    /// proportions `aspect.x : aspect.z`; its height is what `count` needs, about
    /// `aspect.y` in the same proportion (exactly so when the top layer is full). Each
    /// component must be finite and `> 0`, and the largest at most
    /// [`MAX_ASPECT_RATIO`] times the smallest.
    Box {
        /// Relative extents along `x`, `y` and `z`.
        aspect: Vec3,
    },
    /// A conical heap on `y = 0` about the `y` axis, of height `slope` times its base
    /// radius (the tangent of the angle of repose: about 0.6–0.7 for dry sand). The slope
    /// must lie in [`SLOPE_RANGE`].
    Pile {
        /// Height over base radius.
        slope: f32,
    },
}

/// How many grains: the paper's stacking sizes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum StackingSize {
    /// 20 000 grains (Fig. 10: one cloud of grains).
    K20,
    /// 200 000 grains.
    K200,
    /// 1 600 000 grains (Fig. 9, 11: coffee beans).
    M1_6,
    /// 20 000 000 grains (Fig. 17: sand).
    M20,
}

impl StackingSize {
    /// Every size, smallest first.
    pub const ALL: [StackingSize; 4] = [StackingSize::K20, StackingSize::K200, StackingSize::M1_6, StackingSize::M20];

    /// The number of grains.
    pub fn count(self) -> usize {
        match self {
            StackingSize::K20 => 20_000,
            StackingSize::K200 => 200_000,
            StackingSize::M1_6 => 1_600_000,
            StackingSize::M20 => 20_000_000,
        }
    }

    /// The size's name, as parsed: `"20k"`, `"200k"`, `"1.6M"`, `"20M"`.
    pub fn name(self) -> &'static str {
        match self {
            StackingSize::K20 => "20k",
            StackingSize::K200 => "200k",
            StackingSize::M1_6 => "1.6M",
            StackingSize::M20 => "20M",
        }
    }
}

impl fmt::Display for StackingSize {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for StackingSize {
    type Err = SceneError;

    /// Parses a size's [`name`](StackingSize::name); the suffix's case is ignored
    /// (`"1.6m"` is `M1_6`), surrounding whitespace too.
    fn from_str(s: &str) -> Result<StackingSize, SceneError> {
        let t = s.trim();
        StackingSize::ALL
            .into_iter()
            .find(|size| size.name().eq_ignore_ascii_case(t))
            .ok_or_else(|| SceneError::InvalidSize { text: s.to_string() })
    }
}

/// What to generate. Every field is public; [`StackingSpec::validate`] (called by
/// [`crate::Stacking::generate`]) checks them all.
///
/// Lengths: the lattice's nearest-neighbour distance is
/// `d = spacing · 2·R·s_max` with `s_max = 1 + scale_jitter`, and every grain's centre lies
/// within `jitter · d` of its lattice site. Two grains' centres are therefore at least
/// `d − 2·jitter·d` apart, and
///
/// - the **inner balls** (radius `r·s`) never overlap when
///   `spacing · (1 − 2·jitter) ≥ r/R` (then `d − 2·jitter·d ≥ 2·r·s_max`). Specs violating
///   it are rejected; generation adds a rounding margin (see [`crate::Stacking`]).
/// - the **outer balls** (radius `R·s`) never overlap, so the meshes cannot interpenetrate,
///   when `spacing · (1 − 2·jitter) ≥ 1`: for example `spacing = 1` with no jitter, or
///   `spacing = 1.26` with `jitter = 0.1`. Smaller spacings give denser stackings in which
///   only the inner balls are guaranteed disjoint, as in the paper's dense piles (§8 needs
///   only `r`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StackingSpec {
    /// How many grains, `1 ≤ count ≤ u32::MAX` (grain ids are `u32` on the GPU).
    pub count: usize,
    /// The seed of every random value.
    pub seed: u64,
    /// The grain's radii at scale 1.
    pub radii: GrainRadii,
    /// Relative half-range of the per-grain scale: `s ∈ [1 − j, 1 + j)`, `0 ≤ j < 1`.
    pub scale_jitter: f32,
    /// The lattice's nearest-neighbour distance as a multiple of `2·R·(1 + scale_jitter)`,
    /// finite and `> 0` (see the type's documentation for what values mean).
    pub spacing: f32,
    /// Position jitter: each centre lies uniformly in the ball of radius `jitter · d` about
    /// its site, `0 ≤ jitter < 0.5`.
    pub jitter: f32,
    /// The region the grains fill.
    pub region: Region,
}

impl StackingSpec {
    /// A spec with `count` grains of `radii` in a cube, seed 0, no jitter and
    /// `spacing = 1.001`: the outer balls never overlap, with room for `f32` rounding
    /// (see [`crate::Stacking`]'s rounding margin) up to about 10⁹ grains.
    pub fn new(count: usize, radii: GrainRadii) -> StackingSpec {
        StackingSpec {
            count,
            seed: 0,
            radii,
            scale_jitter: 0.0,
            spacing: 1.001,
            jitter: 0.0,
            region: Region::Box { aspect: Vec3::ONE },
        }
    }

    /// The lattice's nearest-neighbour distance `d = spacing · 2·R·(1 + scale_jitter)`.
    pub fn lattice_distance(&self) -> f64 {
        f64::from(self.spacing) * 2.0 * f64::from(self.radii.outer) * self.max_scale()
    }

    /// `s_max = 1 + scale_jitter`.
    pub fn max_scale(&self) -> f64 {
        1.0 + f64::from(self.scale_jitter)
    }

    /// The smallest `spacing` at which the outer balls of a stacking with position jitter
    /// `jitter` are disjoint by construction, with the 0.1 % to spare of [`StackingSpec::new`]:
    /// `1.001 / (1 − 2·jitter)`. Tighter spacings let grains interpenetrate.
    ///
    /// ```
    /// use grain_scenes::{GrainRadii, StackingSpec};
    /// let mut spec = StackingSpec::new(8, GrainRadii::new(0.5, 1.0)?);
    /// spec.jitter = 0.1;
    /// spec.spacing = StackingSpec::disjoint_spacing(spec.jitter);
    /// assert!(spec.outer_balls_disjoint());
    /// # Ok::<(), grain_scenes::SceneError>(())
    /// ```
    pub fn disjoint_spacing(jitter: f32) -> f32 {
        1.001 / (1.0 - 2.0 * jitter)
    }

    /// Whether the outer balls are disjoint by construction (`spacing·(1 − 2·jitter) ≥ 1`,
    /// before the rounding margin).
    pub fn outer_balls_disjoint(&self) -> bool {
        f64::from(self.spacing) * (1.0 - 2.0 * f64::from(self.jitter)) >= 1.0
    }

    /// Checks every field (not the rounding margin, which depends on the stacking's
    /// extent and is checked by [`crate::Stacking::generate`]).
    pub fn validate(&self) -> Result<(), SceneError> {
        if self.count == 0 || u32::try_from(self.count).is_err() {
            return Err(invalid("count", self.count as f64, "must satisfy 1 <= count <= u32::MAX"));
        }
        // Re-validate the radii: the fields are private, but keep the spec self-checking.
        GrainRadii::new(self.radii.inner, self.radii.outer)?;
        let j = self.scale_jitter;
        if !j.is_finite() || !(0.0..1.0).contains(&j) {
            return Err(invalid("scale_jitter", j.into(), "must lie in [0, 1)"));
        }
        let sp = self.spacing;
        if !sp.is_finite() || sp <= 0.0 {
            return Err(invalid("spacing", sp.into(), "must be finite and > 0"));
        }
        let jit = self.jitter;
        if !jit.is_finite() || !(0.0..0.5).contains(&jit) {
            return Err(invalid("jitter", jit.into(), "must lie in [0, 0.5)"));
        }
        check_motion(self.spacing, self.jitter, self.radii, "jitter")?;
        validate_region(self.region)
    }
}

/// `spacing·(1 − 2·total) ≥ r/R`: the inner balls stay disjoint when every centre moves at
/// most `total · d` from its site.
pub(crate) fn check_motion(spacing: f32, total: f32, radii: GrainRadii, field: &'static str) -> Result<(), SceneError> {
    let lhs = f64::from(spacing) * (1.0 - 2.0 * f64::from(total));
    if lhs < f64::from(radii.inner) / f64::from(radii.outer) {
        return Err(invalid(
            field,
            total.into(),
            "spacing·(1 − 2·(jitter + amplitude)) must be >= r/R, or the inner balls could overlap",
        ));
    }
    Ok(())
}

fn validate_region(region: Region) -> Result<(), SceneError> {
    match region {
        Region::Box { aspect } => {
            let fields = ["region.aspect.x", "region.aspect.y", "region.aspect.z"];
            for (field, a) in fields.into_iter().zip(aspect.to_array()) {
                if !a.is_finite() || a <= 0.0 {
                    return Err(invalid(field, a.into(), "must be finite and > 0"));
                }
            }
            if aspect.max_element() > MAX_ASPECT_RATIO * aspect.min_element() {
                let ratio = aspect.max_element() / aspect.min_element();
                return Err(invalid("region.aspect", ratio.into(), "largest over smallest component must be <= 1000"));
            }
            Ok(())
        }
        Region::Pile { slope } => {
            if !slope.is_finite() || slope < SLOPE_RANGE.0 || slope > SLOPE_RANGE.1 {
                return Err(invalid("region.slope", slope.into(), "must lie in [0.05, 20]"));
            }
            Ok(())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn field_of(e: SceneError) -> &'static str {
        match e {
            SceneError::InvalidField { field, .. } => field,
            other => panic!("not a field error: {other}"),
        }
    }

    fn spec() -> StackingSpec {
        let mut s = StackingSpec::new(1000, GrainRadii::new(0.5, 1.0).unwrap());
        s.jitter = 0.1;
        s.scale_jitter = 0.2;
        s
    }

    #[test]
    fn radii_are_validated() {
        assert_eq!(field_of(GrainRadii::new(0.5, 0.0).unwrap_err()), "radii.outer");
        assert_eq!(field_of(GrainRadii::new(0.5, f32::NAN).unwrap_err()), "radii.outer");
        assert_eq!(field_of(GrainRadii::new(1.5, 1.0).unwrap_err()), "radii.inner");
        assert_eq!(field_of(GrainRadii::new(-0.1, 1.0).unwrap_err()), "radii.inner");
        assert_eq!(field_of(GrainRadii::new(f32::INFINITY, 1.0).unwrap_err()), "radii.inner");
        assert_eq!(GrainRadii::new(0.0, 1.0).unwrap().ratio(), 0.0);
        assert_eq!(GrainRadii::new(1.0, 1.0).unwrap().ratio(), 1.0);
    }

    #[test]
    fn every_bad_field_is_named() {
        assert!(spec().validate().is_ok());
        type Breaker = fn(&mut StackingSpec);
        let cases: [(&str, Breaker); 16] = [
            ("count", |s| s.count = 0),
            ("count", |s| s.count = usize::MAX),
            ("scale_jitter", |s| s.scale_jitter = 1.0),
            ("scale_jitter", |s| s.scale_jitter = -0.1),
            ("scale_jitter", |s| s.scale_jitter = f32::NAN),
            ("spacing", |s| s.spacing = 0.0),
            ("spacing", |s| s.spacing = f32::INFINITY),
            ("jitter", |s| s.jitter = -0.01),
            ("jitter", |s| s.jitter = 0.5),
            ("jitter", |s| s.jitter = f32::NAN),
            // spacing·(1 − 2·0.3) = 0.4 < r/R = 0.5: the inner balls could overlap.
            ("jitter", |s| s.jitter = 0.3),
            ("jitter", |s| s.spacing = 0.55),
            ("region.aspect.y", |s| s.region = Region::Box { aspect: Vec3::new(1.0, 0.0, 1.0) }),
            ("region.aspect", |s| s.region = Region::Box { aspect: Vec3::new(1.0, 1.0, 2000.0) }),
            ("region.slope", |s| s.region = Region::Pile { slope: 0.0 }),
            ("region.slope", |s| s.region = Region::Pile { slope: f32::NAN }),
        ];
        for (field, break_it) in cases {
            let mut s = spec();
            break_it(&mut s);
            let e = s.validate().unwrap_err();
            assert!(e.to_string().contains(field), "{e}");
            assert_eq!(field_of(e), field);
        }
    }

    #[test]
    fn the_inner_inequality_is_tight() {
        // r/R = 0.5, jitter 0.25: spacing·0.5 >= 0.5 iff spacing >= 1.
        let mut s = spec();
        s.jitter = 0.25;
        s.spacing = 1.0;
        assert!(s.validate().is_ok());
        s.spacing = 0.999;
        assert!(s.validate().is_err());
        // A grain with r = 0 accepts any spacing.
        s.radii = GrainRadii::new(0.0, 1.0).unwrap();
        s.spacing = 1e-3;
        assert!(s.validate().is_ok());
    }

    #[test]
    fn outer_disjointness_is_reported() {
        let mut s = spec();
        s.jitter = 0.1;
        // 1.25·(1 − 2·0.1) = 1 in exact arithmetic, 0.99999997 with jitter = 0.1f32.
        s.spacing = 1.2501;
        assert!(s.outer_balls_disjoint());
        s.spacing = 1.2;
        assert!(!s.outer_balls_disjoint());
    }

    #[test]
    fn presets_parse() {
        for size in StackingSize::ALL {
            assert_eq!(size.name().parse::<StackingSize>(), Ok(size));
            assert_eq!(size.to_string(), size.name());
        }
        assert_eq!(" 1.6m ".parse::<StackingSize>(), Ok(StackingSize::M1_6));
        assert_eq!("20K".parse::<StackingSize>(), Ok(StackingSize::K20));
        assert_eq!(StackingSize::M20.count(), 20_000_000);
        assert_eq!(StackingSize::M1_6.count(), 1_600_000);
        let e = "2M".parse::<StackingSize>().unwrap_err();
        assert_eq!(e, SceneError::InvalidSize { text: "2M".into() });
        assert!(e.to_string().contains("\"2M\""));
    }
}
