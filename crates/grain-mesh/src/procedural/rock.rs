//! A sand grain or rock: an ellipsoid displaced along its radius by seeded noise.

use std::f64::consts::PI;

use glam::{DVec3, Vec3};

use super::{icosphere, mix_materials, require, require_positive};
use crate::error::MeshError;
use crate::material::VertexMaterial;
use crate::mesh::GrainMesh;

/// Waves per noise octave.
const WAVES_PER_OCTAVE: usize = 6;

/// A sand grain or rock: the unit-sphere point `u` maps to `S·u·(1 + displacement·n(u))`,
/// where `S` scales by [`SandGrain::semi_axes`] and `n(u) ∈ [−1, 1]` is a sum of plane
/// waves `cos(f·π·(u·d) + φ)` over random directions `d` and phases `φ`, frequencies `f`
/// doubling and amplitudes halving per octave, normalised by the sum of amplitudes. The
/// radial map is one-to-one for `displacement < 1`, so the grain is closed and free of
/// self-intersections.
///
/// Directions and phases come from `SplitMix64` seeded with [`SandGrain::seed`]: the same
/// seed gives the same grain on every platform and every version of this crate's
/// dependencies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SandGrain {
    /// Seed of the noise.
    pub seed: u64,
    /// Semi-axes of the underlying ellipsoid.
    pub semi_axes: Vec3,
    /// Largest relative radial displacement, in `[0, 1)`.
    pub displacement: f32,
    /// Noise octaves, 1 to 8; the first has frequency 1.5 (waves across the sphere).
    pub octaves: u32,
    /// Icosahedron subdivisions, at most [`super::MAX_SUBDIVISIONS`].
    pub subdivisions: u32,
    /// Material where the colour noise is lowest.
    pub light: VertexMaterial,
    /// Material where the colour noise is highest.
    pub dark: VertexMaterial,
}

impl Default for SandGrain {
    /// A rounded quartz sand grain of 5 120 triangles.
    fn default() -> Self {
        SandGrain {
            seed: 1,
            semi_axes: Vec3::new(1.0, 0.85, 0.75),
            displacement: 0.15,
            octaves: 3,
            subdivisions: 4,
            light: VertexMaterial { albedo: Vec3::new(0.76, 0.66, 0.48), roughness: 0.8 },
            dark: VertexMaterial { albedo: Vec3::new(0.50, 0.41, 0.30), roughness: 0.9 },
        }
    }
}

impl SandGrain {
    /// The grain's mesh.
    pub fn mesh(&self) -> Result<GrainMesh, MeshError> {
        require_positive("semi_axes.x", self.semi_axes.x)?;
        require_positive("semi_axes.y", self.semi_axes.y)?;
        require_positive("semi_axes.z", self.semi_axes.z)?;
        require("displacement", self.displacement, (0.0..1.0).contains(&self.displacement), "in [0, 1)")?;
        require("octaves", self.octaves as f32, (1..=8).contains(&self.octaves), "in 1..=8")?;
        let mut random = SplitMix64(self.seed);
        let shape = WaveNoise::new(&mut random, self.octaves);
        let colour = WaveNoise::new(&mut random, self.octaves);
        let (unit, triangles) = icosphere(self.subdivisions)?;
        let semi_axes = self.semi_axes.as_dvec3();
        let mut positions = Vec::with_capacity(unit.len());
        let mut materials = Vec::with_capacity(unit.len());
        for &u in &unit {
            let radius = 1.0 + f64::from(self.displacement) * shape.at(u);
            positions.push((semi_axes * u * radius).as_vec3());
            materials.push(mix_materials(self.light, self.dark, 0.5 + 0.5 * colour.at(u)));
        }
        GrainMesh::new(positions, triangles)?.with_materials(materials)
    }
}

/// `SplitMix64` (Steele, Lea & Flood 2014): a tiny portable generator.
struct SplitMix64(u64);

impl SplitMix64 {
    /// The next 64 random bits.
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[0, 1)`.
    fn next_unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1_u64 << 53) as f64)
    }

    /// Uniform on the unit sphere.
    fn next_direction(&mut self) -> DVec3 {
        let z = 2.0 * self.next_unit() - 1.0;
        let azimuth = 2.0 * PI * self.next_unit();
        let ring = (1.0 - z * z).max(0.0).sqrt();
        DVec3::new(ring * azimuth.cos(), ring * azimuth.sin(), z)
    }
}

/// One plane wave of [`WaveNoise`].
struct Wave {
    direction: DVec3,
    frequency: f64,
    phase: f64,
    amplitude: f64,
}

/// Sum of plane waves on the sphere, normalised into `[−1, 1]`.
struct WaveNoise {
    waves: Vec<Wave>,
    amplitude_sum: f64,
}

impl WaveNoise {
    /// `octaves × WAVES_PER_OCTAVE` waves drawn from `random`.
    fn new(random: &mut SplitMix64, octaves: u32) -> WaveNoise {
        let mut waves = Vec::new();
        for octave in 0..octaves {
            let scale = f64::from(1_u32 << octave);
            for _ in 0..WAVES_PER_OCTAVE {
                let direction = random.next_direction();
                let phase = 2.0 * PI * random.next_unit();
                waves.push(Wave { direction, frequency: 1.5 * scale, phase, amplitude: 1.0 / scale });
            }
        }
        let amplitude_sum = waves.iter().map(|w| w.amplitude).sum();
        WaveNoise { waves, amplitude_sum }
    }

    /// The noise at unit direction `u`, in `[−1, 1]`.
    fn at(&self, u: DVec3) -> f64 {
        let sum: f64 =
            self.waves.iter().map(|w| w.amplitude * (w.frequency * PI * u.dot(w.direction) + w.phase).cos()).sum();
        sum / self.amplitude_sum
    }
}
