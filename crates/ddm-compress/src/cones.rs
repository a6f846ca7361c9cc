//! Direction cones: the `m × n` intervals of azimuth `θ` and elevation `φ` of §3.1.
//!
//! `θ ∈ [0, 2π)` is split into `m` equal intervals and `φ ∈ [φ_min, φ_max]` (a sub-range of
//! `[-π/2, π/2]`) into `n`. The paper's "DDM m×n" over viewing rays uses
//! `φ ∈ [-π/2, 0]`; shadow rays use `[0, π/2]`; [`DirectionCones::full`] covers both.

use core::f32::consts::{FRAC_PI_2, PI, TAU};

use glam::Vec3;

/// An `m × n` partition of a band of directions into cones.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionCones {
    azimuths: u32,
    elevations: u32,
    elevation_min: f32,
    elevation_max: f32,
}

/// One cone: `[θ₁, θ₂] × [φ₁, φ₂]` in radians.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cone {
    /// Azimuth interval start `θ₁ ∈ [0, 2π)`.
    pub azimuth_min: f32,
    /// Azimuth interval end `θ₂ ≤ θ₁ + 2π`.
    pub azimuth_max: f32,
    /// Elevation interval start `φ₁`.
    pub elevation_min: f32,
    /// Elevation interval end `φ₂`.
    pub elevation_max: f32,
}

/// `(θ, φ)` of a direction, `θ ∈ [0, 2π)`, `φ ∈ [-π/2, π/2]`; `None` for zero or
/// non-finite vectors.
pub fn azimuth_elevation(direction: Vec3) -> Option<(f32, f32)> {
    let length = direction.length();
    if !direction.is_finite() || length == 0.0 || !length.is_finite() {
        return None;
    }
    let horizontal = libm::hypotf(direction.x, direction.y);
    let elevation = libm::atan2f(direction.z, horizontal);
    let mut azimuth = libm::atan2f(direction.y, direction.x);
    if azimuth < 0.0 {
        azimuth += TAU;
    }
    if azimuth >= TAU {
        azimuth = 0.0;
    }
    Some((azimuth, elevation))
}

impl DirectionCones {
    /// `azimuths × elevations` cones over elevations `[elevation_min, elevation_max]`, or
    /// `None` for zero counts or a range that is empty, not finite or outside `[-π/2, π/2]`.
    pub fn new(azimuths: u32, elevations: u32, elevation_min: f32, elevation_max: f32) -> Option<Self> {
        let valid = azimuths > 0
            && elevations > 0
            && elevation_min.is_finite()
            && elevation_max.is_finite()
            && -FRAC_PI_2 <= elevation_min
            && elevation_min < elevation_max
            && elevation_max <= FRAC_PI_2;
        valid.then_some(Self { azimuths, elevations, elevation_min, elevation_max })
    }

    /// Cones over every direction (`φ ∈ [-π/2, π/2]`).
    pub fn full(azimuths: u32, elevations: u32) -> Option<Self> {
        Self::new(azimuths, elevations, -FRAC_PI_2, FRAC_PI_2)
    }

    /// Cones over downward (viewing) directions, `φ ∈ [-π/2, 0]`, as the paper's DDM m×n.
    pub fn downward(azimuths: u32, elevations: u32) -> Option<Self> {
        Self::new(azimuths, elevations, -FRAC_PI_2, 0.0)
    }

    /// Number of cones `m n`.
    pub fn count(&self) -> u32 {
        self.azimuths * self.elevations
    }

    /// Cone `index` (`azimuth_index + m · elevation_index`), or `None` past the end.
    pub fn cone(&self, index: u32) -> Option<Cone> {
        if index >= self.count() {
            return None;
        }
        let (a, e) = (index % self.azimuths, index / self.azimuths);
        let step_a = TAU / self.azimuths as f32;
        let step_e = (self.elevation_max - self.elevation_min) / self.elevations as f32;
        Some(Cone {
            azimuth_min: a as f32 * step_a,
            azimuth_max: (a + 1) as f32 * step_a,
            elevation_min: self.elevation_min + e as f32 * step_e,
            elevation_max: if e + 1 == self.elevations {
                self.elevation_max
            } else {
                self.elevation_min + (e + 1) as f32 * step_e
            },
        })
    }

    /// The cone containing `direction`, or `None` outside the elevation band or for zero
    /// and non-finite vectors. Directions on a boundary go to the cone above it, the last
    /// boundary to the last cone.
    pub fn cone_of(&self, direction: Vec3) -> Option<u32> {
        let (azimuth, elevation) = azimuth_elevation(direction)?;
        if elevation < self.elevation_min || elevation > self.elevation_max {
            return None;
        }
        let a = ((azimuth / TAU * self.azimuths as f32) as u32).min(self.azimuths - 1);
        let t = (elevation - self.elevation_min) / (self.elevation_max - self.elevation_min);
        let e = ((t * self.elevations as f32) as u32).min(self.elevations - 1);
        Some(a + self.azimuths * e)
    }
}

impl Cone {
    /// A lower bound of the angle between `direction` and every direction of the cone
    /// (0 when it is inside). It never exceeds the true angle, so a pair of objects whose
    /// directions all lie farther than this from the cone can be safely ignored.
    ///
    /// From the haversine formula, `sin²(d/2) = sin²(Δφ/2) + cos φ cos φ' sin²(Δθ/2)`,
    /// each term bounded below separately over the cone.
    pub fn angle_lower_bound(&self, direction: Vec3) -> f32 {
        let Some((azimuth, elevation)) = azimuth_elevation(direction) else { return 0.0 };
        let delta_elevation = if elevation < self.elevation_min {
            self.elevation_min - elevation
        } else if elevation > self.elevation_max {
            elevation - self.elevation_max
        } else {
            0.0
        };
        let delta_azimuth = if self.azimuth_max - self.azimuth_min >= TAU {
            0.0
        } else {
            let wrap = |x: f32| x - TAU * libm::floorf(x / TAU);
            let from_start = wrap(azimuth - self.azimuth_min);
            let width = self.azimuth_max - self.azimuth_min;
            if from_start <= width { 0.0 } else { (from_start - width).min(TAU - from_start).min(PI) }
        };
        // min over the cone of cos φ' is at the elevation farthest from the equator.
        let cos_min = libm::cosf(self.elevation_min.abs().max(self.elevation_max.abs()));
        let s_e = libm::sinf(delta_elevation / 2.0);
        let s_a = libm::sinf(delta_azimuth / 2.0);
        let h = (s_e * s_e + libm::cosf(elevation) * cos_min * s_a * s_a).clamp(0.0, 1.0);
        2.0 * libm::asinf(libm::sqrtf(h))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_direction_of_the_band_has_one_cone() {
        let cones = DirectionCones::downward(4, 2).unwrap();
        assert_eq!(cones.count(), 8);
        // Shallow downward directions are in the upper elevation band (index + 4).
        assert_eq!(cones.cone_of(Vec3::new(1.0, 0.1, -0.2)), Some(4));
        assert_eq!(cones.cone_of(Vec3::new(-1.0, -0.1, -0.2)), Some(6));
        assert_eq!(cones.cone_of(Vec3::new(-1.0, -0.1, -5.0)), Some(2));
        assert_eq!(cones.cone_of(Vec3::new(1.0, 0.1, 0.2)), None);
        assert_eq!(cones.cone_of(Vec3::NEG_Z), Some(0));
        assert_eq!(cones.cone_of(Vec3::ZERO), None);
        assert!(DirectionCones::new(0, 1, 0.0, 1.0).is_none());
        assert!(DirectionCones::new(1, 1, 0.5, 0.5).is_none());
    }

    #[test]
    fn the_angle_bound_is_zero_inside_and_below_the_true_angle_outside() {
        let cones = DirectionCones::full(8, 4).unwrap();
        for index in 0..cones.count() {
            let cone = cones.cone(index).unwrap();
            for k in 0..400 {
                let (s, c) = libm::sincosf(k as f32 * 0.731);
                let d = Vec3::new(c * libm::cosf(k as f32 * 0.13), s, libm::sinf(k as f32 * 0.377)).normalize();
                let bound = cone.angle_lower_bound(d);
                if cones.cone_of(d) == Some(index) {
                    assert!(bound <= 1e-5, "cone {index} {d}: {bound}");
                }
                // True angle to the cone, by sampling the cone densely.
                let mut best = f32::INFINITY;
                for i in 0..=24 {
                    for j in 0..=24 {
                        let t = cone.azimuth_min + (cone.azimuth_max - cone.azimuth_min) * i as f32 / 24.0;
                        let p = cone.elevation_min + (cone.elevation_max - cone.elevation_min) * j as f32 / 24.0;
                        let q = Vec3::new(libm::cosf(p) * libm::cosf(t), libm::cosf(p) * libm::sinf(t), libm::sinf(p));
                        best = best.min(libm::acosf(q.dot(d).clamp(-1.0, 1.0)));
                    }
                }
                assert!(bound <= best + 1e-4, "cone {index} {d}: bound {bound} > sampled {best}");
            }
        }
    }
}
