//! Generation: a jittered FCC lattice filling the region bottom-up, with per-grain
//! orientation, scale and colour, in GPU-ready structure-of-arrays layout.

use glam::{Vec3, Vec4};

use crate::colour::sand_ramp;
use crate::error::{SceneError, invalid};
use crate::gap::min_gap;
use crate::lattice::Layout;
use crate::memory::{BYTES_PER_GRAIN, MemoryLimit};
use crate::rng::{GrainRng, Stream, in_unit_ball, unit_quaternion};
use crate::spec::{GrainRadii, StackingSpec};

/// An axis-aligned box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// The smallest corner.
    pub min: Vec3,
    /// The largest corner.
    pub max: Vec3,
}

/// A generated stacking: one grain per index, in filling order (lowest layers first).
///
/// # Rounding margin
///
/// Centres are stored in `f32`, so the inequality of [`StackingSpec`] must hold with room
/// for rounding: generation requires
/// `d·(1 − 2·jitter) − 2·r·s_max ≥ margin` with
/// `margin = (M + r·s_max) · 2⁻²⁰`, where `M` bounds every coordinate of every centre,
/// also when shaken (`M` = the largest site coordinate `+ d/2`). Each stored or posed
/// coordinate is at most two `f32` roundings (`2·M·2⁻²⁴`) from its exact value, so a
/// pair's distance moves by less than `2·√3·2·M·2⁻²⁴ < 7·M·2⁻²⁴`, and a scale by
/// `s_max·2⁻²⁴`: together less than `margin`. Hence [`Stacking::min_inner_gap`] `≥ 0` on
/// the stored values, not only on the exact ones.
#[derive(Clone, Debug, PartialEq)]
pub struct Stacking {
    centre_scale: Vec<Vec4>,
    rotation: Vec<Vec4>,
    colour: Vec<u32>,
    spec: StackingSpec,
    bounds: Aabb,
    margin: f64,
}

impl Stacking {
    /// Generates `spec` if its arrays fit in the memory available
    /// ([`MemoryLimit::Available`]).
    pub fn generate(spec: &StackingSpec) -> Result<Stacking, SceneError> {
        Stacking::generate_with_limit(spec, MemoryLimit::Available)
    }

    /// Generates `spec`, refusing with [`SceneError::TooLarge`] when its arrays
    /// (`count ×` [`BYTES_PER_GRAIN`]) exceed `limit`, before anything is allocated.
    pub fn generate_with_limit(spec: &StackingSpec, limit: MemoryLimit) -> Result<Stacking, SceneError> {
        spec.validate()?;
        let count = spec.count;
        let requested_bytes = (count as u64)
            .checked_mul(BYTES_PER_GRAIN)
            .filter(|&b| usize::try_from(b).is_ok())
            .ok_or_else(|| invalid("count", count as f64, "the arrays' size overflows usize"))?;
        limit.check(requested_bytes)?;

        let d = spec.lattice_distance();
        let s_max = spec.max_scale();
        let r = f64::from(spec.radii.inner());
        let big_r = f64::from(spec.radii.outer());
        let jitter = f64::from(spec.jitter) * d;
        // Layer 0 stands on y = 0: its outer balls lie above the ground.
        let layout = Layout::new(spec, big_r * s_max + jitter);
        let reach = layout.max_site_coordinate(count as u64) + 0.5 * d;
        if reach.is_nan() || reach >= 1e30 {
            return Err(invalid("spacing", spec.spacing.into(), "the stacking's extent overflows f32"));
        }
        let margin = (reach + r * s_max) * (2.0f64).powi(-20);
        if d * (1.0 - 2.0 * f64::from(spec.jitter)) - 2.0 * r * s_max < margin {
            return Err(invalid(
                "jitter",
                spec.jitter.into(),
                "spacing·(1 − 2·jitter) leaves no room for f32 rounding of the centres (see Stacking's rounding margin)",
            ));
        }

        let alloc_failed = |_| SceneError::AllocationFailed { requested_bytes };
        let mut centre_scale = Vec::new();
        centre_scale.try_reserve_exact(count).map_err(alloc_failed)?;
        let mut rotation = Vec::new();
        rotation.try_reserve_exact(count).map_err(alloc_failed)?;
        let mut colour = Vec::new();
        colour.try_reserve_exact(count).map_err(alloc_failed)?;

        let (seed, scale_jitter) = (spec.seed, f64::from(spec.scale_jitter));
        let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        layout.for_each_site(count as u64, |x, k, z| {
            let id = centre_scale.len() as u64;
            let site = layout.position(x, k, z);
            let p = in_unit_ball(&mut GrainRng::new(seed, id, Stream::Position));
            let s = 1.0 + scale_jitter * GrainRng::new(seed, id, Stream::Scale).signed();
            let q = unit_quaternion(&mut GrainRng::new(seed, id, Stream::Orientation));
            let t = GrainRng::new(seed, id, Stream::Colour).unit();
            let c = Vec4::new(
                (site[0] + jitter * p[0]) as f32,
                (site[1] + jitter * p[1]) as f32,
                (site[2] + jitter * p[2]) as f32,
                s as f32,
            );
            let extent = Vec3::splat(c.w * spec.radii.outer());
            lo = lo.min(c.truncate() - extent);
            hi = hi.max(c.truncate() + extent);
            centre_scale.push(c);
            rotation.push(Vec4::new(q[0] as f32, q[1] as f32, q[2] as f32, q[3] as f32));
            colour.push(sand_ramp(t));
        });
        debug_assert_eq!(centre_scale.len(), count);
        Ok(Stacking { centre_scale, rotation, colour, spec: *spec, bounds: Aabb { min: lo, max: hi }, margin })
    }

    /// The number of grains.
    pub fn len(&self) -> usize {
        self.centre_scale.len()
    }

    /// Always `false`: a stacking has at least one grain.
    pub fn is_empty(&self) -> bool {
        self.centre_scale.is_empty()
    }

    /// Per grain: `xyz` the centre, `w` the scale. `bytemuck::cast_slice` gives the bytes
    /// of a `vec4<f32>` storage buffer.
    pub fn centre_scale(&self) -> &[Vec4] {
        &self.centre_scale
    }

    /// Per grain: the orientation, a unit quaternion `xyzw` (mesh space to world space).
    pub fn rotation(&self) -> &[Vec4] {
        &self.rotation
    }

    /// Per grain: the colour of Fig. 16's ramp ([`crate::SAND_RAMP`]), RGBA8 packed with
    /// red in the low byte (WGSL `unpack4x8unorm`).
    pub fn colour(&self) -> &[u32] {
        &self.colour
    }

    /// The spec it was generated from.
    pub fn spec(&self) -> &StackingSpec {
        &self.spec
    }

    /// The grain's radii at scale 1.
    pub fn radii(&self) -> GrainRadii {
        self.spec.radii
    }

    /// The axis-aligned box of the outer balls (radius `R·s` about each centre).
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// The lattice's nearest-neighbour distance `d`.
    pub fn lattice_distance(&self) -> f64 {
        self.spec.lattice_distance()
    }

    /// The rounding margin (see the type's documentation).
    pub fn rounding_margin(&self) -> f64 {
        self.margin
    }

    /// The largest shake amplitude (fraction of `d`) that keeps the inner balls disjoint:
    /// the largest `a` with `d·(1 − 2·(jitter + a)) − 2·r·s_max ≥ margin`.
    pub fn max_amplitude(&self) -> f64 {
        let d = self.lattice_distance();
        let slack = d * (1.0 - 2.0 * f64::from(self.spec.jitter))
            - 2.0 * f64::from(self.spec.radii.inner()) * self.spec.max_scale()
            - self.margin;
        (slack / (2.0 * d)).max(0.0)
    }

    /// The smallest gap between inner balls (radius `r·s`), `≥ 0` by construction
    /// ([`min_gap`]; `+∞` for one grain).
    pub fn min_inner_gap(&self) -> f32 {
        min_gap(&self.centre_scale, self.spec.radii.inner())
    }

    /// The smallest gap between outer balls (radius `R·s`); `≥ 0` when
    /// [`StackingSpec::outer_balls_disjoint`] holds with the rounding margin
    /// ([`Stacking::outer_balls_disjoint`]), negative in denser stackings.
    pub fn min_outer_gap(&self) -> f32 {
        min_gap(&self.centre_scale, self.spec.radii.outer())
    }

    /// Whether the outer balls are disjoint by construction, with the rounding margin:
    /// `d·(1 − 2·jitter) − 2·R·s_max ≥ margin`.
    pub fn outer_balls_disjoint(&self) -> bool {
        let d = self.lattice_distance();
        d * (1.0 - 2.0 * f64::from(self.spec.jitter)) - 2.0 * f64::from(self.spec.radii.outer()) * self.spec.max_scale()
            >= self.margin
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spec::Region;

    pub(crate) fn dense(count: usize, region: Region, seed: u64) -> StackingSpec {
        let mut spec = StackingSpec::new(count, GrainRadii::new(0.6, 1.0).unwrap());
        spec.seed = seed;
        spec.region = region;
        spec.scale_jitter = 0.2;
        spec.jitter = 0.1;
        // spacing·(1 − 2·0.1) = 0.76 ≥ r/R = 0.6: inner disjoint, outer overlapping.
        spec.spacing = 0.95;
        spec
    }

    fn bits(s: &Stacking) -> (Vec<u32>, Vec<u32>, Vec<u32>) {
        (
            bytemuck::cast_slice(s.centre_scale()).to_vec(),
            bytemuck::cast_slice(s.rotation()).to_vec(),
            s.colour().to_vec(),
        )
    }

    #[test]
    fn generation_is_deterministic() {
        let region = Region::Pile { slope: 0.6 };
        let a = Stacking::generate(&dense(5000, region, 1)).unwrap();
        let b = Stacking::generate(&dense(5000, region, 1)).unwrap();
        let c = Stacking::generate(&dense(5000, region, 2)).unwrap();
        assert_eq!(bits(&a), bits(&b));
        let (ca, cc) = (bits(&a), bits(&c));
        assert_ne!(ca.0, cc.0);
        assert_ne!(ca.1, cc.1);
        assert_ne!(ca.2, cc.2);
        // Grain i does not depend on the count: a prefix of a larger stacking's grains
        // has the same orientations, scales and colours.
        let big = Stacking::generate(&dense(6000, region, 1)).unwrap();
        assert_eq!(&big.rotation()[..5000], a.rotation());
        assert_eq!(&big.colour()[..5000], a.colour());
        // A regression pin of grain 0's centre x, rotation x and colour bits: changing the
        // generator (a breaking change, see the crate's Determinism section) must be
        // deliberate.
        let first = bits(&a);
        assert_eq!((first.0[0], first.1[0], first.2[0]), (0xc21a_8fde, 0x3eb7_5b70, 0xff95_c0da));
    }

    #[test]
    fn attributes_are_in_range() {
        for region in [Region::Box { aspect: Vec3::new(2.0, 1.0, 1.0) }, Region::Pile { slope: 0.7 }] {
            let spec = dense(20_000, region, 9);
            let s = Stacking::generate(&spec).unwrap();
            assert_eq!(s.len(), 20_000);
            assert_eq!(s.rotation().len(), 20_000);
            assert_eq!(s.colour().len(), 20_000);
            for (c, q) in s.centre_scale().iter().zip(s.rotation()) {
                assert!((q.length() - 1.0).abs() < 1e-6, "{q}");
                assert!((0.8..1.2).contains(&c.w), "scale {}", c.w);
                let outer = c.w * spec.radii.outer();
                assert!(c.y - outer >= 0.0, "below the ground: {c}");
                let b = s.bounds();
                assert!(c.truncate().cmpge(b.min + outer * 0.999).all());
                assert!(c.truncate().cmple(b.max - outer * 0.999).all());
            }
            let inner = s.min_inner_gap();
            let outer = s.min_outer_gap();
            println!("{region:?}: 20 000 grains, min inner gap {inner}, min outer gap {outer}");
            assert!(inner >= 0.0, "{inner}");
            assert!(outer < 0.0, "a dense stacking: outer balls overlap");
            assert!(!s.outer_balls_disjoint());
        }
    }

    #[test]
    fn outer_balls_are_disjoint_when_spacing_allows() {
        let mut spec = dense(20_000, Region::Box { aspect: Vec3::ONE }, 3);
        spec.spacing = 1.0 / 0.8 * 1.0001;
        let s = Stacking::generate(&spec).unwrap();
        assert!(s.outer_balls_disjoint());
        let outer = s.min_outer_gap();
        println!("spacing {}: min outer gap {outer}", spec.spacing);
        assert!(outer >= 0.0, "{outer}");
    }

    #[test]
    fn tight_specs_meet_the_rounding_margin() {
        // Exactly tight: spacing·(1 − 2·jitter) = r/R, rejected for want of margin.
        let mut spec = dense(1000, Region::Box { aspect: Vec3::ONE }, 0);
        spec.radii = GrainRadii::new(0.5, 1.0).unwrap();
        spec.jitter = 0.25;
        spec.spacing = 1.0;
        let e = Stacking::generate(&spec).unwrap_err();
        assert!(matches!(e, SceneError::InvalidField { field: "jitter", .. }), "{e}");
        spec.spacing = 1.0001;
        let s = Stacking::generate(&spec).unwrap();
        assert!(s.min_inner_gap() >= 0.0);
    }

    #[test]
    fn the_memory_guard_refuses_before_allocating() {
        let spec = dense(1000, Region::Pile { slope: 0.6 }, 0);
        let e = Stacking::generate_with_limit(&spec, MemoryLimit::Bytes(35_999)).unwrap_err();
        assert_eq!(e, SceneError::TooLarge { requested_bytes: 36_000, available_bytes: 35_999 });
        assert!(e.to_string().contains("exceeds this machine's available memory"));
        assert!(Stacking::generate_with_limit(&spec, MemoryLimit::Bytes(36_000)).is_ok());
        // 20 M grains need 720 MB: refused under a 100 MB budget, nothing allocated.
        let big = dense(20_000_000, Region::Pile { slope: 0.6 }, 0);
        let e = Stacking::generate_with_limit(&big, MemoryLimit::Bytes(100 << 20)).unwrap_err();
        assert!(matches!(e, SceneError::TooLarge { requested_bytes: 720_000_000, .. }), "{e}");
    }

    #[test]
    fn a_single_grain_and_extreme_boxes() {
        for region in [
            Region::Box { aspect: Vec3::ONE },
            Region::Box { aspect: Vec3::new(1.0, 1000.0, 1.0) },
            Region::Box { aspect: Vec3::new(1000.0, 1.0, 1000.0) },
            Region::Pile { slope: 20.0 },
            Region::Pile { slope: 0.05 },
        ] {
            for count in [1, 2, 3, 500] {
                let s = Stacking::generate(&dense(count, region, 5)).unwrap();
                assert_eq!(s.len(), count);
                assert!(s.min_inner_gap() >= 0.0, "{region:?} {count}");
            }
        }
    }

    /// 200 000 grains: a few seconds in debug builds.
    #[test]
    fn inner_balls_are_disjoint_at_200k() {
        for region in [Region::Box { aspect: Vec3::ONE }, Region::Pile { slope: 0.6 }] {
            let s = Stacking::generate(&dense(200_000, region, 11)).unwrap();
            let gap = s.min_inner_gap();
            println!("{region:?}: 200 000 grains, min inner gap {gap}, bounds {:?}", s.bounds());
            assert!(gap >= 0.0, "{gap}");
        }
    }
}
