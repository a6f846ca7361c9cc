//! Inputs shared by the benchmarks and the timing examples of this package.

use glam::{UVec3, Vec3};

/// The rays of the DDM tracer benchmarks: 4096 downward rays (origin, unit direction)
/// from random points one voxel above a `dims` tile, random azimuths, elevations −15° to
/// −85° (fixed xorshift seed).
pub fn tracer_rays(dims: UVec3) -> Vec<(Vec3, Vec3)> {
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    (0..4096)
        .map(|_| {
            let origin = Vec3::new(next() * dims.x as f32, next() * dims.y as f32, dims.z as f32 + 1.0);
            let (azimuth, elevation) = (next() * std::f32::consts::TAU, -(15.0 + 70.0 * next()).to_radians());
            (origin, Vec3::new(elevation.cos() * azimuth.cos(), elevation.cos() * azimuth.sin(), elevation.sin()))
        })
        .collect()
}

/// The displaced sphere of the `svo_brick` benchmark and the `svo_memory` example (paper
/// Fig. 11–12 in spirit): radius [`DISPLACED_RADIUS`](displaced::DISPLACED_RADIUS) at the origin, displaced along the
/// radius by [`DISPLACED_AMPLITUDE`](displaced::DISPLACED_AMPLITUDE) `× fbm(p)`, in the domain `[−1, 1)³`.
pub mod displaced {
    use glam::{Mat3, Vec3};
    use svo_brick::{Domain, SdfSurface, SurfaceSource};

    /// The undisplaced radius (world units).
    pub const DISPLACED_RADIUS: f32 = 0.6;
    /// The displacement's amplitude: `|displacement| ≤ DISPLACED_AMPLITUDE × fbm_max()`.
    pub const DISPLACED_AMPLITUDE: f32 = 0.04;
    /// The first octave's angular frequency (a wavelength of `2π / 8 ≈ 0.79`).
    pub const BASE_FREQUENCY: f32 = 8.0;
    /// Octaves of the fBm (frequency ×2, amplitude ×1/2 per octave).
    pub const OCTAVES: u32 = 4;

    /// Each octave's coordinates are the previous one's turned by this rotation (about
    /// `(1, 2, 3)`, 0.9 rad), so that the octaves' lattices do not align.
    fn octave_rotation() -> Mat3 {
        Mat3::from_axis_angle(Vec3::new(1.0, 2.0, 3.0).normalize(), 0.9)
    }

    /// Sine-product fBm: `Σₖ 2⁻ᵏ sin(x'ₖ) sin(y'ₖ) sin(z'ₖ)` with `p'ₖ = 2ᵏ f₀ Rᵏ p +
    /// φₖ`. Deterministic and cheap (three sines an octave); in `[−fbm_max, fbm_max]`, and
    /// `fbm_lipschitz`-Lipschitz (one octave's gradient has length ≤ its frequency, as
    /// `|∇ sin x sin y sin z| ≤ 1`).
    pub fn fbm(p: Vec3) -> f32 {
        let rotation = octave_rotation();
        let (mut q, mut sum, mut amplitude, mut frequency) = (p, 0.0, 1.0, BASE_FREQUENCY);
        for k in 0..OCTAVES {
            let phase = Vec3::new(0.3, 1.1, 2.3) * (k + 1) as f32;
            let x = q * frequency + phase;
            sum += amplitude * x.x.sin() * x.y.sin() * x.z.sin();
            q = rotation * q;
            amplitude *= 0.5;
            frequency *= 2.0;
        }
        sum
    }

    /// The bound of `|fbm|`: `Σₖ 2⁻ᵏ`.
    pub fn fbm_max() -> f32 {
        (0..OCTAVES).map(|k| 0.5_f32.powi(k as i32)).sum()
    }

    /// The Lipschitz bound of `fbm`: `Σₖ 2⁻ᵏ 2ᵏ f₀ = OCTAVES f₀`.
    pub fn fbm_lipschitz() -> f32 {
        OCTAVES as f32 * BASE_FREQUENCY
    }

    /// How the raw `|p| − R − A fbm(p)` is made 1-Lipschitz.
    #[derive(Clone, Copy, Debug, PartialEq, Eq)]
    pub enum Normalisation {
        /// Divided by `1 + L` (`L = A fbm_lipschitz`): a true bound, since the 3D noise's
        /// gradient may point along the radius (`|r̂ − A∇fbm| ≤ 1 + L`). The default.
        Sum,
        /// Divided by `√(1 + L²)`: exact for a displacement whose gradient is tangential
        /// (a height field over the sphere), not a bound for 3D noise.
        Hypot,
    }

    impl Normalisation {
        /// The divisor.
        pub fn divisor(self) -> f32 {
            let l = DISPLACED_AMPLITUDE * fbm_lipschitz();
            match self {
                Normalisation::Sum => 1.0 + l,
                Normalisation::Hypot => (1.0 + l * l).sqrt(),
            }
        }
    }

    /// The raw displaced distance `|p| − R − A fbm(p)` (not normalised).
    pub fn raw_distance(p: Vec3) -> f32 {
        p.length() - DISPLACED_RADIUS - DISPLACED_AMPLITUDE * fbm(p)
    }

    /// The colour at a surface point, correlated with the displacement: dark brown in the
    /// valleys to pale sand on the crests.
    pub fn colour(x: Vec3) -> [f32; 3] {
        let u = 0.5 + 0.5 * fbm(x) / fbm_max();
        [0.25 + 0.7 * u, 0.18 + 0.65 * u, 0.12 + 0.55 * u]
    }

    /// The displaced sphere as a surface source: the distance normalised by
    /// `normalisation`, the gradient by central differences of step `1e-4` (a fortieth of
    /// the finest voxel at 512³), [`colour`] as the attribute.
    pub fn displaced_sphere(normalisation: Normalisation) -> impl SurfaceSource {
        let inverse = 1.0 / normalisation.divisor();
        SdfSurface::new(move |p: Vec3| raw_distance(p) * inverse, colour, 1e-4).expect("a valid gradient step")
    }

    /// The domain `[−1, 1)³`.
    pub fn domain() -> Domain {
        Domain { origin: Vec3::splat(-1.0), size: 2.0 }
    }
}

/// The closed mesh of the plain distance map's build benchmark (issue 13, part 6): a
/// torus of 96 × 47 quads (9 024 triangles) tilted in a 64³ grid, and the baseline it is
/// measured against.
pub mod plain_map {
    use ddm_compress::Triangle;
    use glam::{UVec3, Vec3};
    use mesostructure::Ring;

    /// The grid of the benchmark.
    pub const DIMS: UVec3 = UVec3::splat(64);

    /// A torus of `segments × sides` quads (two triangles each) centred in a `dims` grid,
    /// its axis tilted off z, centre radius `0.3 dims.x` and tube radius `0.12 dims.x`.
    pub fn tilted_torus(dims: UVec3, segments: u32, sides: u32) -> Vec<Triangle> {
        let size = dims.as_vec3();
        Ring {
            center: size * 0.5,
            axis: Vec3::new(0.3, 0.2, 1.0).normalize(),
            major_radius: 0.3 * size.x,
            minor_radius: 0.12 * size.x,
        }
        .triangles(segments, sides)
    }

    /// The benchmark's mesh: [`tilted_torus`] of 96 × 47 quads in [`DIMS`].
    pub fn torus_9024() -> Vec<Triangle> {
        tilted_torus(DIMS, 96, 47)
    }

    /// The conservative bound a grid signed distance field gives: `|sdf|` at each voxel
    /// centre (the `mesh_to_sdf` crate's `generate_grid_sdf`, which propagates nearest
    /// triangles from the cells around each triangle) less half the voxel diagonal,
    /// clamped at 0; voxel order `x + dims.x (y + dims.y z)`, as the distance maps.
    pub fn centre_sdf_bound(dims: UVec3, triangles: &[Triangle]) -> Vec<f32> {
        let vertices: Vec<[f32; 3]> = triangles.iter().flat_map(|t| t.0.map(|v| v.to_array())).collect();
        let size = dims.as_vec3().to_array();
        let cells = [dims.x as usize, dims.y as usize, dims.z as usize];
        let grid = mesh_to_sdf::Grid::from_bounding_box(&[0.0, 0.0, 0.0], &size, cells);
        let sdf = mesh_to_sdf::generate_grid_sdf(
            &vertices,
            mesh_to_sdf::Topology::TriangleList(None::<&[u32]>),
            &grid,
            mesh_to_sdf::SignMethod::Normal,
        );
        // `mesh_to_sdf` orders cells z fastest (`x · ny · nz + y · nz + z`).
        let (ny, nz) = (dims.y as usize, dims.z as usize);
        let half_diagonal = 0.75_f32.sqrt();
        let mut bound = vec![0.0; sdf.len()];
        for x in 0..dims.x as usize {
            for y in 0..ny {
                for z in 0..nz {
                    let value = sdf[x * ny * nz + y * nz + z];
                    bound[x + dims.x as usize * (y + ny * z)] = (value.abs() - half_diagonal).max(0.0);
                }
            }
        }
        bound
    }
}
