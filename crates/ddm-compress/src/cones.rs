//! Direction cones: the `m × n` intervals of azimuth `θ` and elevation `φ` of §3.1.
//!
//! `θ ∈ [0, 2π)` is split into `m` equal intervals and `φ ∈ [φ_min, φ_max]` (a sub-range of
//! `[-π/2, π/2]`) into `n`. The paper's "DDM m×n" over viewing rays uses
//! `φ ∈ [-π/2, 0]`; shadow rays use `[0, π/2]`; [`DirectionCones::full`] covers both.

use core::f32::consts::{FRAC_PI_2, PI, TAU};
use core::fmt;

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

/// Which end of an elevation range a [`ConeError`] is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ElevationBound {
    /// The lowest elevation, `elevation_min`.
    Min,
    /// The highest elevation, `elevation_max`.
    Max,
}

impl fmt::Display for ElevationBound {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Min => "elevation_min",
            Self::Max => "elevation_max",
        })
    }
}

/// Why [`DirectionCones::new`] (or [`DirectionCones::full`], [`DirectionCones::downward`])
/// refused its arguments. The checks run in the order of the variants; the first that
/// fails is returned.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ConeError {
    /// Zero azimuth intervals (`m = 0`).
    ZeroAzimuths,
    /// Zero elevation intervals (`n = 0`).
    ZeroElevations,
    /// `m n` does not fit in a `u32` (cone indices are `u32`).
    TooManyCones {
        /// The requested azimuth intervals `m`.
        azimuths: u32,
        /// The requested elevation intervals `n`.
        elevations: u32,
    },
    /// An elevation bound is NaN or infinite.
    NonFiniteElevation {
        /// Which bound.
        bound: ElevationBound,
        /// Its value.
        value: f32,
    },
    /// An elevation bound lies outside `[-π/2, π/2]`.
    ElevationOutOfRange {
        /// Which bound.
        bound: ElevationBound,
        /// Its value, radians.
        value: f32,
    },
    /// The elevation range is empty: `elevation_min ≥ elevation_max`.
    EmptyElevationRange {
        /// The lowest elevation given, radians.
        min: f32,
        /// The highest elevation given, radians.
        max: f32,
    },
}

impl fmt::Display for ConeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::ZeroAzimuths => write!(f, "direction cones need at least one azimuth interval"),
            Self::ZeroElevations => write!(f, "direction cones need at least one elevation interval"),
            Self::TooManyCones { azimuths, elevations } => {
                write!(f, "{azimuths} × {elevations} direction cones do not fit in a u32 cone index")
            }
            Self::NonFiniteElevation { bound, value } => write!(f, "direction cones: {bound} {value} is not finite"),
            Self::ElevationOutOfRange { bound, value } => {
                write!(f, "direction cones: {bound} {value} lies outside [-π/2, π/2]")
            }
            Self::EmptyElevationRange { min, max } => {
                write!(f, "direction cones: the elevation range [{min}, {max}] is empty")
            }
        }
    }
}

impl core::error::Error for ConeError {}

impl DirectionCones {
    /// `azimuths × elevations` cones over elevations `[elevation_min, elevation_max]`, a
    /// non-empty sub-range of `[-π/2, π/2]`.
    ///
    /// # Errors
    ///
    /// A [`ConeError`] naming the first invalid argument: zero counts, more cones than a
    /// `u32` counts, a non-finite bound, a bound outside `[-π/2, π/2]`, or an empty range.
    pub fn new(azimuths: u32, elevations: u32, elevation_min: f32, elevation_max: f32) -> Result<Self, ConeError> {
        if azimuths == 0 {
            return Err(ConeError::ZeroAzimuths);
        }
        if elevations == 0 {
            return Err(ConeError::ZeroElevations);
        }
        if azimuths.checked_mul(elevations).is_none() {
            return Err(ConeError::TooManyCones { azimuths, elevations });
        }
        for (bound, value) in [(ElevationBound::Min, elevation_min), (ElevationBound::Max, elevation_max)] {
            if !value.is_finite() {
                return Err(ConeError::NonFiniteElevation { bound, value });
            }
        }
        for (bound, value) in [(ElevationBound::Min, elevation_min), (ElevationBound::Max, elevation_max)] {
            if !(-FRAC_PI_2..=FRAC_PI_2).contains(&value) {
                return Err(ConeError::ElevationOutOfRange { bound, value });
            }
        }
        if elevation_min >= elevation_max {
            return Err(ConeError::EmptyElevationRange { min: elevation_min, max: elevation_max });
        }
        Ok(Self { azimuths, elevations, elevation_min, elevation_max })
    }

    /// Cones over every direction (`φ ∈ [-π/2, π/2]`).
    ///
    /// # Errors
    ///
    /// [`ConeError::ZeroAzimuths`], [`ConeError::ZeroElevations`] or
    /// [`ConeError::TooManyCones`], as [`DirectionCones::new`].
    pub fn full(azimuths: u32, elevations: u32) -> Result<Self, ConeError> {
        Self::new(azimuths, elevations, -FRAC_PI_2, FRAC_PI_2)
    }

    /// Cones over downward (viewing) directions, `φ ∈ [-π/2, 0]`, as the paper's DDM m×n.
    ///
    /// # Errors
    ///
    /// [`ConeError::ZeroAzimuths`], [`ConeError::ZeroElevations`] or
    /// [`ConeError::TooManyCones`], as [`DirectionCones::new`].
    pub fn downward(azimuths: u32, elevations: u32) -> Result<Self, ConeError> {
        Self::new(azimuths, elevations, -FRAC_PI_2, 0.0)
    }

    /// Azimuth intervals `m`.
    pub fn azimuths(&self) -> u32 {
        self.azimuths
    }

    /// Elevation intervals `n`.
    pub fn elevations(&self) -> u32 {
        self.elevations
    }

    /// Lowest elevation of the band, radians (the start of cone 0).
    pub fn elevation_min(&self) -> f32 {
        self.elevation_min
    }

    /// Highest elevation of the band, radians (the end of the last cone).
    pub fn elevation_max(&self) -> f32 {
        self.elevation_max
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
        self.angle_lower_bound_at(azimuth, elevation)
    }

    /// [`Cone::angle_lower_bound`] of the direction with azimuth `azimuth ∈ [0, 2π)` and
    /// elevation `elevation` (as [`azimuth_elevation`] gives them), so that one
    /// conversion serves several cones.
    pub fn angle_lower_bound_at(&self, azimuth: f32, elevation: f32) -> f32 {
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
            let from_start = wrap_angle(azimuth - self.azimuth_min);
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

    /// A lower bound of the angle between the direction `(azimuth, elevation)` and every
    /// direction *outside* the cone: 0 when the direction is outside or on the boundary.
    /// A set of directions within this angle of the direction lies wholly inside the cone.
    ///
    /// The cone's boundary is made of two arcs of latitude circles (great-circle distance
    /// `|φ − φ_b|` to the whole circle) and two meridian arcs (distance
    /// `asin(cos φ sin Δθ)` to the whole meridian half-circle when `Δθ ≤ π/2`, else the
    /// distance `π/2 − |φ|` to its nearer pole); each arc is farther than its whole circle.
    pub fn inside_margin_at(&self, azimuth: f32, elevation: f32) -> f32 {
        if elevation < self.elevation_min || elevation > self.elevation_max {
            return 0.0;
        }
        let mut margin = PI;
        if self.elevation_min > -FRAC_PI_2 {
            margin = margin.min(elevation - self.elevation_min);
        }
        if self.elevation_max < FRAC_PI_2 {
            margin = margin.min(self.elevation_max - elevation);
        }
        let width = self.azimuth_max - self.azimuth_min;
        if width < TAU {
            let from_start = wrap_angle(azimuth - self.azimuth_min);
            if from_start > width {
                return 0.0;
            }
            let cos_elevation = libm::cosf(elevation).max(0.0);
            for delta in [from_start, width - from_start] {
                let delta = delta.min(TAU - delta);
                let to_meridian = if delta <= FRAC_PI_2 {
                    libm::asinf((cos_elevation * libm::sinf(delta)).clamp(0.0, 1.0))
                } else {
                    FRAC_PI_2 - elevation.abs()
                };
                margin = margin.min(to_meridian);
            }
        }
        margin.max(0.0)
    }

    /// Whether the direction `(azimuth, elevation)` lies in the cone (boundaries included).
    pub fn contains_at(&self, azimuth: f32, elevation: f32) -> bool {
        if elevation < self.elevation_min || elevation > self.elevation_max {
            return false;
        }
        let width = self.azimuth_max - self.azimuth_min;
        width >= TAU || wrap_angle(azimuth - self.azimuth_min) <= width
    }
}

/// How a set of directions lies relative to a cone.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ConeRelation {
    /// No direction of the set is in the cone.
    Outside,
    /// Every direction of the set is in the cone.
    Inside,
    /// Possibly some in, some out.
    Partial,
}

/// An azimuth–elevation rectangle holding every direction of a set: the directions of the
/// points of a box that does not contain the origin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DirectionRange {
    /// Start of the azimuth arc, in `[0, 2π)`.
    pub azimuth_start: f32,
    /// Length of the azimuth arc (`2π`: every azimuth).
    pub azimuth_width: f32,
    /// Smallest elevation.
    pub elevation_min: f32,
    /// Largest elevation.
    pub elevation_max: f32,
}

/// Widening of [`DirectionRange`]s against rounding, in radians.
const RANGE_MARGIN: f32 = 2e-5;

impl DirectionRange {
    /// The directions of the points of the box `[min, max]`, or `None` when the box
    /// contains the origin or is not finite.
    ///
    /// Azimuths: the arc spanned by the four corners of the box's `xy` rectangle (every
    /// azimuth when that rectangle holds the origin). Elevations: `φ = atan2(z, h)` grows
    /// with `z` and, for `z ≥ 0`, falls with the horizontal distance `h`, so its extremes
    /// are at `z_max` with the smallest (`z_max ≥ 0`) or largest `h`, and at `z_min` with the
    /// largest (`z_min ≥ 0`) or smallest `h`.
    pub fn of_box(min: Vec3, max: Vec3) -> Option<Self> {
        if !(min.is_finite() && max.is_finite()) || (min.cmple(Vec3::ZERO).all() && max.cmpge(Vec3::ZERO).all()) {
            return None;
        }
        let nearest_xy = glam::Vec2::ZERO.clamp(min.truncate(), max.truncate());
        let h_min = nearest_xy.length();
        let h_max = libm::hypotf(min.x.abs().max(max.x.abs()), min.y.abs().max(max.y.abs()));
        let elevation_max = libm::atan2f(max.z, if max.z >= 0.0 { h_min } else { h_max }) + RANGE_MARGIN;
        let elevation_min = libm::atan2f(min.z, if min.z >= 0.0 { h_max } else { h_min }) - RANGE_MARGIN;
        let (azimuth_start, azimuth_width) = if h_min == 0.0 {
            (0.0, TAU)
        } else {
            let center = libm::atan2f(min.y + max.y, min.x + max.x);
            let (mut low, mut high) = (0.0_f32, 0.0_f32);
            for (x, y) in [(min.x, min.y), (max.x, min.y), (min.x, max.y), (max.x, max.y)] {
                let mut delta = libm::atan2f(y, x) - center;
                if delta > PI {
                    delta -= TAU;
                } else if delta < -PI {
                    delta += TAU;
                }
                low = low.min(delta);
                high = high.max(delta);
            }
            (wrap_angle(center + low - RANGE_MARGIN), (high - low + 2.0 * RANGE_MARGIN).min(TAU))
        };
        Some(Self {
            azimuth_start,
            azimuth_width,
            elevation_min: elevation_min.max(-FRAC_PI_2),
            elevation_max: elevation_max.min(FRAC_PI_2),
        })
    }
}

impl Cone {
    /// How the directions of `range` lie relative to the cone (exact for the rectangle, so
    /// a conservative answer for the set it holds).
    pub fn relation(&self, range: &DirectionRange) -> ConeRelation {
        if range.elevation_max < self.elevation_min || range.elevation_min > self.elevation_max {
            return ConeRelation::Outside;
        }
        let elevation_inside = self.elevation_min <= range.elevation_min && range.elevation_max <= self.elevation_max;
        let width = self.azimuth_max - self.azimuth_min;
        let azimuth_inside = if width >= TAU {
            true
        } else if range.azimuth_width >= TAU {
            false
        } else {
            let range_from_cone = wrap_angle(range.azimuth_start - self.azimuth_min);
            let cone_from_range = wrap_angle(self.azimuth_min - range.azimuth_start);
            if range_from_cone > width && cone_from_range > range.azimuth_width {
                // Neither arc starts inside the other: disjoint, unless the range reaches a
                // pole, where every azimuth meets.
                let at_pole =
                    range.elevation_min <= -FRAC_PI_2 + RANGE_MARGIN || range.elevation_max >= FRAC_PI_2 - RANGE_MARGIN;
                if !at_pole {
                    return ConeRelation::Outside;
                }
                false
            } else {
                range_from_cone + range.azimuth_width <= width
            }
        };
        if elevation_inside && azimuth_inside { ConeRelation::Inside } else { ConeRelation::Partial }
    }
}

/// `x` reduced to `[0, 2π)`.
fn wrap_angle(x: f32) -> f32 {
    x - TAU * libm::floorf(x / TAU)
}

#[cfg(test)]
mod tests {
    use alloc::string::ToString;

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
    }

    #[test]
    fn each_invalid_argument_has_its_error() {
        use ConeError::*;
        use ElevationBound::{Max, Min};
        assert_eq!(DirectionCones::new(0, 1, 0.0, 1.0), Err(ZeroAzimuths));
        assert_eq!(DirectionCones::downward(0, 0), Err(ZeroAzimuths));
        assert_eq!(DirectionCones::full(4, 0), Err(ZeroElevations));
        assert_eq!(
            DirectionCones::downward(1 << 16, 1 << 16),
            Err(TooManyCones { azimuths: 1 << 16, elevations: 1 << 16 })
        );
        assert_eq!(DirectionCones::downward(u32::MAX, 1).map(|c| c.count()), Ok(u32::MAX));
        assert!(matches!(
            DirectionCones::new(4, 1, f32::NAN, 0.0),
            Err(NonFiniteElevation { bound: Min, value }) if value.is_nan()
        ));
        assert_eq!(
            DirectionCones::new(4, 1, 0.0, f32::INFINITY),
            Err(NonFiniteElevation { bound: Max, value: f32::INFINITY })
        );
        assert_eq!(DirectionCones::new(4, 1, -2.0, 0.0), Err(ElevationOutOfRange { bound: Min, value: -2.0 }));
        assert_eq!(DirectionCones::new(4, 1, 0.0, 1.6), Err(ElevationOutOfRange { bound: Max, value: 1.6 }));
        assert_eq!(DirectionCones::new(1, 1, 0.5, 0.5), Err(EmptyElevationRange { min: 0.5, max: 0.5 }));
        assert_eq!(DirectionCones::new(1, 1, 0.5, -0.5), Err(EmptyElevationRange { min: 0.5, max: -0.5 }));
        // The bounds ±π/2 themselves are valid, and the accessors return the arguments.
        let cones = DirectionCones::new(3, 2, -FRAC_PI_2, FRAC_PI_2).unwrap();
        assert_eq!(
            (cones.azimuths(), cones.elevations(), cones.elevation_min(), cones.elevation_max()),
            (3, 2, -FRAC_PI_2, FRAC_PI_2)
        );
        // Every message names what is wrong.
        let message = DirectionCones::new(4, 1, 0.0, 1.6).unwrap_err().to_string();
        assert!(message.contains("elevation_max") && message.contains("1.6"), "{message}");
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

    #[test]
    fn directions_within_the_inside_margin_stay_in_the_cone() {
        for cones in [DirectionCones::full(8, 4).unwrap(), DirectionCones::downward(4, 2).unwrap()] {
            for index in 0..cones.count() {
                let cone = cones.cone(index).unwrap();
                let mut inside_seen = 0;
                for k in 0..600 {
                    let (s, c) = libm::sincosf(k as f32 * 0.731);
                    let d = Vec3::new(c * libm::cosf(k as f32 * 0.13), s, libm::sinf(k as f32 * 0.377)).normalize();
                    let (azimuth, elevation) = azimuth_elevation(d).unwrap();
                    let margin = cone.inside_margin_at(azimuth, elevation);
                    assert!(margin == 0.0 || cone.contains_at(azimuth, elevation));
                    if margin <= 1e-4 {
                        continue;
                    }
                    inside_seen += 1;
                    // Directions on a circle of radius 0.999 margin around d are inside.
                    let helper = if d.z.abs() < 0.9 { Vec3::Z } else { Vec3::X };
                    let (u, v) = (d.cross(helper).normalize(), d.cross(d.cross(helper)).normalize());
                    for j in 0..64 {
                        let (sj, cj) = libm::sincosf(j as f32 * TAU / 64.0);
                        let angle = 0.999 * margin;
                        let e = d * libm::cosf(angle) + (u * cj + v * sj) * libm::sinf(angle);
                        let (a, el) = azimuth_elevation(e).unwrap();
                        assert!(cone.contains_at(a, el), "cone {index}: {d} margin {margin}, {e} outside");
                    }
                }
                assert!(inside_seen > 0, "cone {index}");
            }
        }
    }

    #[test]
    fn direction_ranges_hold_their_boxes_and_relations_are_right() {
        let mut next = crate::test_random::uniform(0x853c_49e6_748f_ea9b_u64);
        let cone_sets = [
            DirectionCones::full(4, 2).unwrap(),
            DirectionCones::downward(8, 1).unwrap(),
            DirectionCones::full(3, 3).unwrap(),
        ];
        let (mut outside, mut inside) = (0, 0);
        for _ in 0..3000 {
            let a = Vec3::new(next(), next(), next()) * 8.0 - 4.0;
            let size = Vec3::new(next(), next(), next()) * 3.0;
            let (min, max) = (a, a + size);
            let Some(range) = DirectionRange::of_box(min, max) else {
                assert!(min.cmple(Vec3::ZERO).all() && max.cmpge(Vec3::ZERO).all());
                continue;
            };
            for cones in cone_sets {
                for index in 0..cones.count() {
                    let cone = cones.cone(index).unwrap();
                    let relation = cone.relation(&range);
                    outside += usize::from(relation == ConeRelation::Outside);
                    inside += usize::from(relation == ConeRelation::Inside);
                    for i in 0..125 {
                        let t = Vec3::new((i % 5) as f32, ((i / 5) % 5) as f32, (i / 25) as f32) / 4.0;
                        let p = min + size * t;
                        let Some((azimuth, elevation)) = azimuth_elevation(p) else { continue };
                        assert!(
                            elevation >= range.elevation_min && elevation <= range.elevation_max,
                            "{min} {max} {p} {range:?}"
                        );
                        assert!(
                            wrap_angle(azimuth - range.azimuth_start) <= range.azimuth_width + 1e-6
                                || wrap_angle(azimuth - range.azimuth_start) >= TAU - 1e-6,
                            "{min} {max} {p} {range:?}"
                        );
                        let contained = cone.contains_at(azimuth, elevation);
                        match relation {
                            ConeRelation::Outside => assert!(!contained, "{min} {max} {p} cone {index} {range:?}"),
                            ConeRelation::Inside => assert!(contained, "{min} {max} {p} cone {index} {range:?}"),
                            ConeRelation::Partial => {}
                        }
                    }
                }
            }
        }
        assert!(outside > 1000 && inside > 100, "{outside} {inside}");
    }
}
