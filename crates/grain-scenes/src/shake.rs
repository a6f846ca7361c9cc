//! Animation: every grain oscillates about its place and spins about its own axis, so
//! positions *and* orientations change every frame (`GrainViewer` reuses 20 orientations,
//! `id % 20`, and only moves the positions).

use glam::Vec4;

use crate::error::{SceneError, invalid};
use crate::rng::{GrainRng, Stream, unit_vector};
use crate::spec::check_motion;
use crate::stacking::Stacking;

/// A shaking motion, the same law for every grain with hashed per-grain parameters:
///
/// - position: `c(t) = c + amplitude·d·sin(2π·frequency·t + φᵢ)·eᵢ`, with `c` the
///   generated centre, `d` the lattice distance, `eᵢ` a uniform unit vector and `φᵢ`
///   uniform in `[0, 2π)`, both hashed from `(seed, i)`. The displacement is at most
///   `amplitude·d`.
/// - orientation: `q(t) = rot(aᵢ, spin·t + ψᵢ)·q`, a rotation about the hashed unit axis
///   `aᵢ` at angular speed `spin` (radians per second) with hashed phase `ψᵢ`, applied to
///   the generated orientation `q`.
///
/// **The inner balls never overlap, at any `t`**: every centre stays within
/// `(jitter + amplitude)·d` of its lattice site, so [`Shake::pose_at`] requires
/// `spacing·(1 − 2·(jitter + amplitude)) ≥ r/R` with the stacking's rounding margin
/// (that is, `amplitude ≤` [`Stacking::max_amplitude`]), the inequality of generation with
/// `jitter + amplitude` in place of `jitter`.
///
/// Poses use `sin` and `cos` of the standard library, which may differ by an ulp between
/// platforms; generation itself is bit-identical everywhere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shake {
    amplitude: f32,
    frequency: f32,
    spin: f32,
}

impl Shake {
    /// A validated shake: `0 ≤ amplitude < 0.5` (fraction of the lattice distance), and
    /// `frequency` (Hz) and `spin` (rad/s) finite.
    pub fn new(amplitude: f32, frequency: f32, spin: f32) -> Result<Shake, SceneError> {
        if !amplitude.is_finite() || !(0.0..0.5).contains(&amplitude) {
            return Err(invalid("amplitude", amplitude.into(), "must lie in [0, 0.5)"));
        }
        if !frequency.is_finite() {
            return Err(invalid("frequency", frequency.into(), "must be finite"));
        }
        if !spin.is_finite() {
            return Err(invalid("spin", spin.into(), "must be finite"));
        }
        Ok(Shake { amplitude, frequency, spin })
    }

    /// The amplitude, a fraction of the lattice distance.
    pub fn amplitude(&self) -> f32 {
        self.amplitude
    }

    /// The oscillation frequency in hertz.
    pub fn frequency(&self) -> f32 {
        self.frequency
    }

    /// The angular speed in radians per second.
    pub fn spin(&self) -> f32 {
        self.spin
    }

    /// Whether this shake keeps `stacking`'s inner balls disjoint (see the type).
    pub fn check(&self, stacking: &Stacking) -> Result<(), SceneError> {
        let spec = stacking.spec();
        check_motion(spec.spacing, spec.jitter + self.amplitude, spec.radii, "amplitude")?;
        if f64::from(self.amplitude) > stacking.max_amplitude() {
            return Err(invalid(
                "amplitude",
                self.amplitude.into(),
                "jitter + amplitude leave no room for f32 rounding (see Stacking::max_amplitude)",
            ));
        }
        Ok(())
    }

    /// Writes the pose at time `t` (seconds) of every grain into the caller's slices, one
    /// element per grain: `centre_scale` (centre, scale) and `rotation` (unit quaternion
    /// `xyzw`), without allocating. Errors: a slice of the wrong length, a non-finite `t`,
    /// or an amplitude too large for the stacking ([`Shake::check`]).
    pub fn pose_at(
        &self,
        stacking: &Stacking,
        t: f32,
        centre_scale: &mut [Vec4],
        rotation: &mut [Vec4],
    ) -> Result<(), SceneError> {
        let n = stacking.len();
        for (slice, len) in [("centre_scale", centre_scale.len()), ("rotation", rotation.len())] {
            if len != n {
                return Err(SceneError::LengthMismatch { slice, expected: n, actual: len });
            }
        }
        if !t.is_finite() {
            return Err(invalid("t", t.into(), "must be finite"));
        }
        self.check(stacking)?;
        let seed = stacking.spec().seed;
        let reach = f64::from(self.amplitude) * stacking.lattice_distance();
        let tau = std::f64::consts::TAU;
        let (omega_t, spin_t) = (tau * f64::from(self.frequency) * f64::from(t), f64::from(self.spin) * f64::from(t));
        let grains = stacking.centre_scale().iter().zip(stacking.rotation());
        for (i, ((c0, q0), (c, q))) in grains.zip(centre_scale.iter_mut().zip(rotation.iter_mut())).enumerate() {
            let mut rng = GrainRng::new(seed, i as u64, Stream::ShakeOffset);
            let e = unit_vector(&mut rng);
            let phase = tau * rng.unit();
            let a = reach * (omega_t + phase).sin().clamp(-1.0, 1.0);
            *c = Vec4::new(
                (f64::from(c0.x) + a * e[0]) as f32,
                (f64::from(c0.y) + a * e[1]) as f32,
                (f64::from(c0.z) + a * e[2]) as f32,
                c0.w,
            );
            let mut rng = GrainRng::new(seed, i as u64, Stream::ShakeSpin);
            let axis = unit_vector(&mut rng);
            let half = 0.5 * (spin_t + tau * rng.unit());
            let (s, w) = half.sin_cos();
            *q = quat_mul([axis[0] * s, axis[1] * s, axis[2] * s, w], q0.to_array().map(f64::from));
        }
        Ok(())
    }
}

/// `a·b` (first `b`, then `a`), normalised, as an `f32` quaternion `xyzw`.
fn quat_mul(a: [f64; 4], b: [f64; 4]) -> Vec4 {
    let [ax, ay, az, aw] = a;
    let [bx, by, bz, bw] = b;
    let q = [
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    ];
    let q = crate::rng::normalize4(q);
    Vec4::new(q[0] as f32, q[1] as f32, q[2] as f32, q[3] as f32)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gap::min_gap;
    use crate::spec::{GrainRadii, Region, StackingSpec};
    use glam::{Quat, Vec3};

    fn stacking() -> Stacking {
        let mut spec = StackingSpec::new(20_000, GrainRadii::new(0.6, 1.0).unwrap());
        spec.seed = 4;
        spec.region = Region::Pile { slope: 0.6 };
        spec.scale_jitter = 0.2;
        spec.jitter = 0.05;
        spec.spacing = 0.95;
        Stacking::generate(&spec).unwrap()
    }

    #[test]
    fn quaternion_product_matches_glam() {
        let a = Quat::from_axis_angle(Vec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
        let b = Quat::from_axis_angle(Vec3::new(-1.0, 0.5, 0.0).normalize(), 2.1);
        let q = quat_mul(a.to_array().map(f64::from), b.to_array().map(f64::from));
        assert!((q - Vec4::from(a * b)).length() < 1e-6);
    }

    #[test]
    fn shaking_keeps_the_inner_balls_disjoint_and_moves_every_grain() {
        let s = stacking();
        // spacing·(1 − 2·(0.05 + a)) ≥ 0.6 ⇔ a ≤ 0.134…, less the margin.
        let max = s.max_amplitude();
        assert!((0.13..0.135).contains(&max), "{max}");
        let shake = Shake::new(max as f32 * 0.999, 2.0, 3.0).unwrap();
        let n = s.len();
        let (mut c, mut q) = (vec![Vec4::ZERO; n], vec![Vec4::ZERO; n]);
        let (mut c2, mut q2) = (vec![Vec4::ZERO; n], vec![Vec4::ZERO; n]);
        let d = s.lattice_distance() as f32;
        for t in [0.0, 0.013, 0.1, 0.25, 1.0 / 3.0, 7.7] {
            shake.pose_at(&s, t, &mut c, &mut q).unwrap();
            let gap = min_gap(&c, s.radii().inner());
            println!("t = {t}: min inner gap {gap}");
            assert!(gap >= 0.0, "t = {t}: {gap}");
            for (i, (p, r)) in c.iter().zip(&q).enumerate() {
                assert!((r.length() - 1.0).abs() < 1e-6);
                assert!(p.truncate().distance(s.centre_scale()[i].truncate()) <= shake.amplitude() * d * 1.0001);
                assert_eq!(p.w, s.centre_scale()[i].w);
            }
        }
        // Two consecutive frames at 60 Hz.
        shake.pose_at(&s, 0.5, &mut c, &mut q).unwrap();
        shake.pose_at(&s, 0.5 + 1.0 / 60.0, &mut c2, &mut q2).unwrap();
        let moved = c.iter().zip(&c2).filter(|(a, b)| a.truncate() != b.truncate()).count();
        let turned = q.iter().zip(&q2).filter(|(a, b)| a != b).count();
        println!("between two frames: {moved} of {n} grains moved, {turned} turned");
        assert!(moved >= n - n / 1000, "{moved} of {n}");
        assert_eq!(turned, n);
    }

    #[test]
    fn bad_shakes_are_refused() {
        let s = stacking();
        let n = s.len();
        let (mut c, mut q) = (vec![Vec4::ZERO; n], vec![Vec4::ZERO; n]);
        let field = |e: SceneError| match e {
            SceneError::InvalidField { field, .. } => field,
            other => panic!("{other}"),
        };
        assert_eq!(field(Shake::new(0.5, 1.0, 1.0).unwrap_err()), "amplitude");
        assert_eq!(field(Shake::new(-0.1, 1.0, 1.0).unwrap_err()), "amplitude");
        assert_eq!(field(Shake::new(0.1, f32::NAN, 1.0).unwrap_err()), "frequency");
        assert_eq!(field(Shake::new(0.1, 1.0, f32::INFINITY).unwrap_err()), "spin");
        let too_much = Shake::new(0.2, 1.0, 1.0).unwrap();
        assert_eq!(field(too_much.pose_at(&s, 0.0, &mut c, &mut q).unwrap_err()), "amplitude");
        let just_over = Shake::new(s.max_amplitude() as f32 * 1.0001 + 1e-7, 1.0, 1.0).unwrap();
        assert_eq!(field(just_over.pose_at(&s, 0.0, &mut c, &mut q).unwrap_err()), "amplitude");
        let ok = Shake::new(0.05, 1.0, 1.0).unwrap();
        assert_eq!(field(ok.pose_at(&s, f32::NAN, &mut c, &mut q).unwrap_err()), "t");
        let e = ok.pose_at(&s, 0.0, &mut c[1..], &mut q).unwrap_err();
        assert_eq!(e, SceneError::LengthMismatch { slice: "centre_scale", expected: n, actual: n - 1 });
        let e = ok.pose_at(&s, 0.0, &mut c, &mut q[..3]).unwrap_err();
        assert_eq!(e, SceneError::LengthMismatch { slice: "rotation", expected: n, actual: 3 });
    }
}
