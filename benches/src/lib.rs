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
