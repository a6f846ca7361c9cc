//! Seeded 3D value noise with its exact derivative, and fractional Brownian motion
//! ([`Fbm`]) with proven bounds of its magnitude and of its gradient's magnitude.

use glam::{IVec3, Vec3};

use crate::error::{SceneError, check, positive};

/// The proven bound `3.75 √3` of the value noise's gradient magnitude (see [`Fbm`]).
pub const NOISE_GRADIENT_BOUND: f32 = 3.75 * 1.732_050_8;

/// Most octaves an [`Fbm`] accepts.
pub const MAX_OCTAVES: u32 = 16;

/// `SplitMix64`'s finaliser.
fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The lattice value at `corner` for `seed`, in `[−1, 1)`.
fn lattice(seed: u64, corner: IVec3) -> f32 {
    let mut h = seed;
    for c in corner.to_array() {
        h = mix(h ^ u64::from(c as u32).wrapping_mul(0x9e37_79b9_7f4a_7c15));
    }
    (h >> 40) as f32 / (1u64 << 23) as f32 - 1.0
}

/// The quintic fade and its derivative.
fn fade(t: f32) -> (f32, f32) {
    (t * t * t * (t * (t * 6.0 - 15.0) + 10.0), 30.0 * t * t * (1.0 - t) * (1.0 - t))
}

/// Value noise at `q` for `seed`, and its gradient.
pub(crate) fn value_noise(seed: u64, q: Vec3) -> (f32, Vec3) {
    let cell = q.floor();
    let f = q - cell;
    let base = cell.as_ivec3();
    let (sx, dx) = fade(f.x);
    let (sy, dy) = fade(f.y);
    let (sz, dz) = fade(f.z);
    let v = |i: i32, j: i32, k: i32| lattice(seed, base + IVec3::new(i, j, k));
    let (v000, v100, v010, v110) = (v(0, 0, 0), v(1, 0, 0), v(0, 1, 0), v(1, 1, 0));
    let (v001, v101, v011, v111) = (v(0, 0, 1), v(1, 0, 1), v(0, 1, 1), v(1, 1, 1));
    let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
    // Along x first, then y, then z.
    let (x00, x10, x01, x11) = (lerp(v000, v100, sx), lerp(v010, v110, sx), lerp(v001, v101, sx), lerp(v011, v111, sx));
    let (y0, y1) = (lerp(x00, x10, sy), lerp(x01, x11, sy));
    let value = lerp(y0, y1, sz);
    let ddx = {
        let (e00, e10, e01, e11) = (v100 - v000, v110 - v010, v101 - v001, v111 - v011);
        dx * lerp(lerp(e00, e10, sy), lerp(e01, e11, sy), sz)
    };
    let ddy = dy * lerp(x10 - x00, x11 - x01, sz);
    let ddz = dz * (y1 - y0);
    (value, Vec3::new(ddx, ddy, ddz))
}

/// Fractional Brownian motion of 3D value noise, lacunarity 2.
///
/// # Value noise and its derivative bound
///
/// The noise `n(q)` interpolates values `v ∈ [−1, 1)` hashed from the integer lattice
/// corners of `q`'s unit cube, with the quintic fade `s(t) = 6t⁵ − 15t⁴ + 10t³` in each
/// axis (`s(0) = 0`, `s(1) = 1`, `s′ = s″ = 0` at both ends, so `n` is C²). Being a convex
/// combination of the corner values, `|n| ≤ 1`. Its x derivative is
///
/// `∂n/∂x = s′(u) · Σ_{y, z corners} w_y w_z (v_{1yz} − v_{0yz})`, with `Σ w_y w_z = 1`,
///
/// so `|∂n/∂x| ≤ max s′ · max |Δv| = (30/16) · 2 = 3.75` (`s′(t) = 30t²(1 − t)²` peaks at
/// `t = ½`), and likewise in y and z: `|∇n| ≤ 3.75 √3 =` [`NOISE_GRADIENT_BOUND`].
///
/// # fBm
///
/// `D(p) = A Σ_{k<K} gᵏ n_k(2ᵏ p / λ)` (lacunarity 2, amplitude `A`, gain `g`, base
/// wavelength `λ`, `K` octaves, each octave's lattice hashed with its own seed). Then
/// `|D| ≤ A Σ gᵏ` ([`Fbm::amplitude_bound`]) and, by the chain rule and the triangle
/// inequality, `|∇D| ≤ NOISE_GRADIENT_BOUND · A Σ gᵏ 2ᵏ / λ` ([`Fbm::gradient_bound`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fbm {
    seed: u64,
    octaves: u32,
    gain: f32,
    amplitude: f32,
    wavelength: f32,
}

impl Fbm {
    /// fBm of `octaves` octaves (1 to [`MAX_OCTAVES`]); `gain` (each octave's amplitude
    /// over the previous one's), `amplitude` (the first octave's, world units) and
    /// `wavelength` (the first octave's lattice step, world units) finite and positive.
    /// The same parameters give the same function on every platform up to `f32` rounding.
    pub fn new(seed: u64, octaves: u32, gain: f32, amplitude: f32, wavelength: f32) -> Result<Self, SceneError> {
        let octaves = check("Fbm", "octaves", octaves, (1..=MAX_OCTAVES).contains(&octaves), "1 to 16")?;
        Ok(Fbm {
            seed,
            octaves,
            gain: positive("Fbm", "gain", gain)?,
            amplitude: positive("Fbm", "amplitude", amplitude)?,
            wavelength: positive("Fbm", "wavelength", wavelength)?,
        })
    }

    /// The seed.
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// The number of octaves.
    pub fn octaves(&self) -> u32 {
        self.octaves
    }

    /// The gain.
    pub fn gain(&self) -> f32 {
        self.gain
    }

    /// The first octave's amplitude.
    pub fn amplitude(&self) -> f32 {
        self.amplitude
    }

    /// The first octave's wavelength.
    pub fn wavelength(&self) -> f32 {
        self.wavelength
    }

    /// `A Σ gᵏ`, a bound of `|D|`.
    pub fn amplitude_bound(&self) -> f32 {
        (0..self.octaves).map(|k| self.amplitude * self.gain.powi(k as i32)).sum()
    }

    /// `NOISE_GRADIENT_BOUND · A Σ gᵏ 2ᵏ / λ`, a bound of `|∇D|`.
    pub fn gradient_bound(&self) -> f32 {
        let sum: f32 = (0..self.octaves).map(|k| (2.0 * self.gain).powi(k as i32)).sum();
        NOISE_GRADIENT_BOUND * self.amplitude * sum / self.wavelength
    }

    /// `D(p)`.
    pub fn value(&self, p: Vec3) -> f32 {
        self.value_and_gradient(p).0
    }

    /// `D(p)` and its exact gradient `∇D(p)`.
    pub fn value_and_gradient(&self, p: Vec3) -> (f32, Vec3) {
        let (mut value, mut gradient) = (0.0, Vec3::ZERO);
        let (mut amplitude, mut frequency) = (self.amplitude, self.wavelength.recip());
        for k in 0..self.octaves {
            let (n, dn) = value_noise(mix(self.seed ^ u64::from(k).wrapping_mul(0xd1b5_4a32_d192_ed03)), p * frequency);
            value += amplitude * n;
            gradient += dn * (amplitude * frequency);
            amplitude *= self.gain;
            frequency *= 2.0;
        }
        (value, gradient)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing::Rng;

    #[test]
    fn noise_is_bounded_deterministic_and_interpolates_the_lattice() {
        let mut rng = Rng::new(11);
        let mut largest = (0.0f32, 0.0f32);
        for _ in 0..20_000 {
            let q = rng.vec3(Vec3::splat(-50.0), Vec3::splat(50.0));
            let (n, dn) = value_noise(3, q);
            assert!(n.abs() <= 1.0);
            assert_eq!((n, dn), value_noise(3, q));
            for c in dn.to_array() {
                assert!(c.abs() <= 3.75 + 1e-5);
            }
            largest = (largest.0.max(n.abs()), largest.1.max(dn.length()));
        }
        // The bounds are not loose by orders of magnitude.
        assert!(largest.0 > 0.8 && largest.1 > 0.4 * NOISE_GRADIENT_BOUND, "{largest:?}");
        assert_eq!(value_noise(3, Vec3::new(2.0, -1.0, 5.0)).0, lattice(3, IVec3::new(2, -1, 5)));
        assert_ne!(value_noise(3, Vec3::splat(0.5)).0, value_noise(4, Vec3::splat(0.5)).0);
    }

    #[test]
    fn fbm_gradient_equals_finite_differences() {
        let fbm = Fbm::new(9, 4, 0.5, 0.1, 0.5).unwrap();
        let mut rng = Rng::new(12);
        let h = 1e-3;
        for _ in 0..500 {
            let p = rng.vec3(Vec3::splat(-2.0), Vec3::splat(2.0));
            let d = |e: Vec3| (fbm.value(p + e * h) - fbm.value(p - e * h)) / (2.0 * h);
            let differences = Vec3::new(d(Vec3::X), d(Vec3::Y), d(Vec3::Z));
            let (_, gradient) = fbm.value_and_gradient(p);
            assert!((gradient - differences).length() < 2e-3 * (1.0 + gradient.length()), "{gradient} {differences}");
            assert!(gradient.length() <= fbm.gradient_bound());
            assert!(fbm.value(p).abs() <= fbm.amplitude_bound());
        }
        assert!((fbm.amplitude_bound() - 0.1875).abs() < 1e-6);
        assert!((fbm.gradient_bound() - NOISE_GRADIENT_BOUND * 0.1 * 4.0 / 0.5).abs() < 1e-5);
    }

    #[test]
    fn bad_parameters_are_errors() {
        assert!(Fbm::new(0, 0, 0.5, 0.1, 1.0).unwrap_err().to_string().contains("Fbm.octaves"));
        assert!(Fbm::new(0, 4, 0.5, -0.1, 1.0).unwrap_err().to_string().contains("Fbm.amplitude"));
        assert!(Fbm::new(0, 4, 0.5, 0.1, f32::NAN).unwrap_err().to_string().contains("Fbm.wavelength"));
    }
}
