//! The per-vertex material a mesh may carry.

use glam::Vec3;

/// The simple per-vertex material of a procedural grain, for later impostor baking.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VertexMaterial {
    /// Linear RGB albedo, each channel in `[0, 1]`.
    pub albedo: Vec3,
    /// Perceptual (GGX-style) roughness in `[0, 1]`.
    pub roughness: f32,
}
