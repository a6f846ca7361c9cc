//! The conservativeness check: many random configurations, each decided by the `f32` test
//! ([`crate::is_occluded_by`]) and by the exact `f64` answer ([`crate::hidden_exact`]).
//! A visible grain that the test culls is a failure; the fraction of hidden grains the
//! test finds says how much the rounding margin costs.
//!
//! The configurations are deterministic from a seed (xorshift64*), and concentrate where
//! the test could fail: grains on and near the boundary of the occlusion cone, `R = r`
//! (the apex at the occluder's centre), `R < r` (per-grain scales), occluders from barely
//! outside the eye to a thousand radii away, and the special cases (`g₁` at the apex, at the
//! occluder's centre, at the eye).

use glam::{DVec3, Vec3};

use crate::cone::{Sphere, is_occluded_by};
use crate::exact::{Exact, hidden_exact};

/// What [`check_conservative`] counted.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CheckReport {
    /// Configurations decided.
    pub cases: u64,
    /// Configurations the exact answer says are hidden.
    pub hidden: u64,
    /// Configurations the exact answer says are visible.
    pub visible: u64,
    /// Configurations within `f64` rounding of the boundary (not counted either way).
    pub boundary: u64,
    /// Configurations where hiding is undefined (the eye inside the occluder).
    pub undefined: u64,
    /// Configurations the `f32` test culls.
    pub culled: u64,
    /// Visible configurations the `f32` test culls: must be 0.
    pub visible_culled: u64,
    /// Hidden configurations the `f32` test culls.
    pub hidden_culled: u64,
}

impl CheckReport {
    /// The fraction of hidden configurations the `f32` test culls.
    pub fn found_fraction(&self) -> f64 {
        if self.hidden == 0 { 0.0 } else { self.hidden_culled as f64 / self.hidden as f64 }
    }
}

/// The xorshift64* generator of the configurations.
struct Random(u64);

impl Random {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// Uniform in `[0, 1)`.
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    fn range(&mut self, low: f64, high: f64) -> f64 {
        low + (high - low) * self.unit()
    }

    /// `10^x`, `x` uniform in `[low, high)`.
    fn log(&mut self, low: f64, high: f64) -> f64 {
        libm::pow(10.0, self.range(low, high))
    }

    /// A unit vector at angle `angle` from `axis`, uniform around it.
    fn around(&mut self, axis: DVec3, angle: f64) -> DVec3 {
        let helper = if axis.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
        let e1 = axis.cross(helper).normalize();
        let e2 = axis.cross(e1);
        let phi = self.range(0.0, core::f64::consts::TAU);
        axis * libm::cos(angle) + (e1 * libm::cos(phi) + e2 * libm::sin(phi)) * libm::sin(angle)
    }
}

/// One random configuration `(occluder, grain)` in `f64`, rounded to the `f32` the test
/// reads (so both answers are about the same configuration).
fn configuration(random: &mut Random) -> (Sphere, Sphere) {
    let r = random.log(-2.0, 1.0);
    let big_r = match random.next() % 4 {
        0 => r,
        1 => r * random.range(0.3, 1.0),
        _ => r * random.range(1.0, 4.0),
    };
    // The occluder within 60° of the view axis −z, from barely outside the eye on.
    let tilt = random.range(0.0, 60_f64.to_radians());
    let u = random.around(DVec3::NEG_Z, tilt);
    let distance = r * (1.0 + random.log(-4.0, 3.0));
    let g0 = u * distance;
    let alpha = libm::asin(r / distance);
    let apex = g0 * (big_r.max(r) / r);
    let grain = match random.next() % 8 {
        // Near the cone's boundary, seen from the apex: the angle within a relative 10⁻²
        // … 10⁻⁷ of α, on either side.
        0..=3 => {
            let offset = random.log(-7.0, -2.0) * if random.next().is_multiple_of(2) { 1.0 } else { -1.0 };
            let beta = (alpha * (1.0 + offset)).max(0.0);
            apex + random.around(u, beta) * (big_r * random.log(-3.0, 3.0))
        }
        // Anywhere around the occluder, behind and in front.
        4 | 5 => {
            let angle = random.range(0.0, core::f64::consts::PI);
            g0 + random.around(u, angle) * (r * random.log(-2.0, 2.5))
        }
        // Deep inside the cone.
        6 => {
            let angle = alpha * random.unit();
            apex + random.around(u, angle) * (big_r * random.log(-1.0, 3.0))
        }
        // The special points.
        _ => match random.next() % 3 {
            0 => apex,
            1 => g0,
            _ => DVec3::ZERO,
        },
    };
    (
        Sphere { centre: g0.as_vec3(), radius: r as f32 },
        Sphere { centre: Vec3::new(grain.x as f32, grain.y as f32, grain.z as f32), radius: big_r as f32 },
    )
}

/// Decides `cases` configurations from `seed` (see the module documentation).
pub fn check_conservative(cases: u64, seed: u64) -> CheckReport {
    let mut random = Random(seed | 1);
    let mut report = CheckReport::default();
    for _ in 0..cases {
        let (occluder, grain) = configuration(&mut random);
        let culled = is_occluded_by(occluder, grain);
        let exact = hidden_exact(
            occluder.centre.as_dvec3(),
            f64::from(occluder.radius),
            grain.centre.as_dvec3(),
            f64::from(grain.radius),
        );
        report.cases += 1;
        report.culled += u64::from(culled);
        match exact {
            Exact::Hidden => {
                report.hidden += 1;
                report.hidden_culled += u64::from(culled);
            }
            Exact::Visible => {
                report.visible += 1;
                report.visible_culled += u64::from(culled);
            }
            Exact::Boundary => report.boundary += 1,
            Exact::Undefined => report.undefined += 1,
        }
    }
    report
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_visible_grain_is_culled_over_a_hundred_thousand_configurations() {
        let report = check_conservative(100_000, 0x0cc1_0de5);
        // The distribution reaches every branch often enough to mean something.
        assert!(report.hidden > 10_000 && report.visible > 10_000, "{report:?}");
        assert_eq!(report.visible_culled, 0, "{report:?}");
        assert!(report.hidden_culled > 0, "{report:?}");
        #[cfg(feature = "std")]
        {
            extern crate std;
            std::println!("{report:?}: {:.4} of the hidden grains culled", report.found_fraction());
        }
        assert_eq!(report.cases, report.hidden + report.visible + report.boundary + report.undefined);
    }
}
