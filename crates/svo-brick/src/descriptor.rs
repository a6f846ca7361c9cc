//! The voxel descriptor of §5.2 (Fig. 6): the macroscopic signed distance and normal, and
//! the Gaussian micro-descriptors of the surface and its attributes.

use glam::Vec3;

/// Attribute channels per voxel (RGB colour).
pub const ATTRIBUTE_CHANNELS: usize = 3;

/// One voxel of a pre-filtered octree (§5.2, Fig. 6), in the octree's units (lengths in
/// finest voxels; see [`BrickTree`](crate::BrickTree)).
///
/// - `distance`, `distance_variance`: the macroscopic signed distance `h̄` (negative
///   inside) and the variance `σh²` of the micro-heights about the macroscopic plane.
/// - `normal`, `slope_variance`: the macroscopic normal `n̄` (the gradient of the filtered
///   `h̄`, of length ≤ 1) and the isotropic slope variance `σn²` of the micro-normals in
///   `n̄`'s frame (the paper's isotropic case; the anisotropic `σnx², σny²` need a tangent
///   frame that the text does not name, and are not stored).
/// - `attribute`, `correlation`: per channel, the mean `ā` and the correlation `a_s` of
///   the attribute with the height through `s(h) = 2 g(h) − 1` (H5bis, eq. 5):
///   `a(h) = ā + a_s s(h)`.
///
/// At the finest level every variance and `a_s` is zero (§5.2, "initialized at the deepest
/// level … σp² = 0").
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Voxel {
    /// `h̄`: the macroscopic signed distance, negative inside.
    pub distance: f32,
    /// `σh²`: the variance of the micro-heights about the plane `(h̄, n̄)`.
    pub distance_variance: f32,
    /// `n̄`: the macroscopic normal (the gradient of `h̄`; not normalised).
    pub normal: Vec3,
    /// `σn²`: the isotropic variance of the micro-slopes in `n̄`'s frame.
    pub slope_variance: f32,
    /// `ā` per channel.
    pub attribute: [f32; ATTRIBUTE_CHANNELS],
    /// `a_s` per channel: the projection of `a − ā` on `s(h)` (§5.2).
    pub correlation: [f32; ATTRIBUTE_CHANNELS],
}

impl Voxel {
    /// The voxel with every field scaled as lengths scale by `scale` (distances by
    /// `scale`, variances of heights by `scale²`; normals, slopes and attributes are
    /// dimensionless).
    #[must_use]
    pub fn scaled(self, scale: f32) -> Self {
        Self { distance: self.distance * scale, distance_variance: self.distance_variance * (scale * scale), ..self }
    }
}
