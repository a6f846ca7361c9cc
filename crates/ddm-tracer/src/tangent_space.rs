//! Rendering a mesostructure mapped onto a base mesh (Mehra & Kumar §3, after Wang et
//! al.'s view-dependent displacement mapping): the per-pixel ray in the mesostructure's
//! tangent space, the shading normal back in world space, and the GPU layout of the
//! base-mesh G-buffer and of the shaded pixels. Mirrored by `wgsl/tangent_space.wgsl`.
//!
//! # The mapping
//!
//! The base mesh is the *top* of the mesostructure's slab: a surface point `P(u, v)` with
//! texture coordinates `(u, v)` (one unit = one tile) is the tracer's point
//! `(u L_x, v L_y, L_z)` in voxel units, and the slab extends a world thickness `h`
//! *below* the surface, along `−N`. Around the pixel's point the surface is replaced by
//! its tangent plane with the frame `(∂P/∂u, ∂P/∂v, N)` held constant along the whole
//! ray, the approximation of the paper (and of every per-pixel displacement method): a
//! world direction `d` becomes
//!
//! `d_ts = (L_x (d·∂P/∂u) / |∂P/∂u|², L_y (d·∂P/∂v) / |∂P/∂v|², (L_z / h) (d·N̂))`,
//!
//! which is the exact inverse of the Jacobian when the parametrisation is orthogonal
//! (plane, torus) and its projection otherwise. The world normal of a tangent-space
//! normal `n` is `Mᵀ n` for that linear map `M`:
//! `T̂ (L_x / |∂P/∂u|) n_x + B̂ (L_y / |∂P/∂v|) n_y + N̂ (L_z / h) n_z`, normalised.
//! Silhouettes are those of the base mesh (the paper's method has no silhouette
//! correction either); curvature makes rays that travel far below the surface land
//! slightly off, which `h` small relative to the curvature radius keeps small.

use glam::{Vec3, Vec4};
use gpu_layout::gpu_struct;

use crate::maps::DistanceSource;
use crate::patches::VoxelPatches;
use crate::trace::{TraceSettings, trace};

/// `BaseRenderPixel::color.w` of a pixel the base mesh does not cover.
pub const PIXEL_UNCOVERED: f32 = 0.0;
/// `BaseRenderPixel::color.w` of a covered pixel whose ray reaches the bottom of the slab
/// (or the step cap) without a hit: it shows the base surface under the mesostructure.
pub const PIXEL_MISS: f32 = 1.0;
/// `BaseRenderPixel::color.w` of a covered pixel whose ray hits the mesostructure.
pub const PIXEL_HIT: f32 = 2.0;
/// `BaseRenderPixel::color.w` of a covered pixel whose ray leaves the base mesh's solid
/// again before any hit and before the slab's bottom ([`pixel_class`]): nothing of this
/// object is seen there, the pixel shows what lies behind (the silhouettes of paper
/// Fig. 1 and 8).
pub const PIXEL_LEFT_SHELL: f32 = 3.0;
/// What [`shell_exit`] and [`slab_bottom`] return for a ray that never leaves the shell
/// or never reaches the bottom (`f32::MAX`, a finite value WGSL can hold).
pub const NO_EXIT: f32 = f32::MAX;

gpu_struct! {
    /// One texel of the base-mesh G-buffer (the output of the raster pass, the input of
    /// the per-pixel trace).
    pub struct BaseGBufferTexel {
        /// World position in `xyz`; `w` 1 where the base mesh covers the pixel, else 0.
        pub position_coverage: Vec4,
        /// Interpolated `∂P/∂u` (world units per texture unit) in `xyz`; `u` in `w`.
        pub tangent_u: Vec4,
        /// Interpolated `∂P/∂v` in `xyz`; `v` in `w`.
        pub bitangent_v: Vec4,
        /// Interpolated normal in `xyz` (not renormalised); view depth in `w`.
        pub normal_depth: Vec4,
    }
}

gpu_struct! {
    /// What the per-pixel pass needs besides the G-buffer and the tracer's scene.
    pub struct BaseRenderParams {
        /// Camera position in `xyz`; `w` zero.
        pub eye: Vec4,
        /// Unit direction toward the (directional) light in `xyz`; ambient term in `w`.
        pub light: Vec4,
        /// `(L_x, L_y, L_z / h, shadow_tolerance)`: voxels per texture unit along `u` and
        /// `v`, voxels per world unit along `−N`, and how far short of the hit (voxels) a
        /// shadow ray's hit must be to shadow it; a negative tolerance disables shadows.
        pub slab: Vec4,
        /// Colour of the base mesh where the ray misses the mesostructure (`rgb`); `w` 1
        /// where the base mesh is drawn, 0 where such a pixel shows what lies behind.
        pub miss_color: Vec4,
        /// The mesostructure's albedo in `rgb`; in `w` how much of it is replaced by the
        /// normal's colour `0.5 n + 0.5`, so that the relief reads in the images.
        pub albedo: Vec4,
    }
}

gpu_struct! {
    /// One shaded pixel (the output of the per-pixel pass).
    pub struct BaseRenderPixel {
        /// Linear colour in `rgb`; `w` one of [`PIXEL_UNCOVERED`], [`PIXEL_MISS`],
        /// [`PIXEL_HIT`].
        pub color: Vec4,
        /// The tangent-space ray origin (voxels) in `xyz`; the tracer's steps in `w`.
        pub ray_origin: Vec4,
        /// The tangent-space ray direction (voxels, not normalised) in `xyz`; `w` 1 when
        /// the hit is in shadow.
        pub ray_direction: Vec4,
        /// The tangent-space hit point in `xyz`, its ray parameter in `w`.
        pub hit: Vec4,
    }
}

/// The linear map from world directions to tangent-space (voxel) directions at one
/// G-buffer texel: the scaled frame of the module documentation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TangentFrame {
    /// `L_x ∂P/∂u / |∂P/∂u|²`: world direction → tangent-space `x`.
    pub to_x: Vec3,
    /// `L_y ∂P/∂v / |∂P/∂v|²`.
    pub to_y: Vec3,
    /// `(L_z / h) N̂`.
    pub to_z: Vec3,
}

impl TangentFrame {
    /// The frame of `texel` for `slab = (L_x, L_y, L_z / h)`. `None` where a frame vector
    /// is zero or not finite. WGSL twin: `render_tangent_frame`.
    pub fn new(texel: &BaseGBufferTexel, slab: Vec3) -> Option<Self> {
        let (tu, tv, n) = (texel.tangent_u.truncate(), texel.bitangent_v.truncate(), texel.normal_depth.truncate());
        let (tu2, tv2, n2) = (tu.dot(tu), tv.dot(tv), n.dot(n));
        if !(tu2 > 0.0 && tv2 > 0.0 && n2 > 0.0 && tu2.is_finite() && tv2.is_finite() && n2.is_finite()) {
            return None;
        }
        Some(Self { to_x: tu * (slab.x / tu2), to_y: tv * (slab.y / tv2), to_z: n * (slab.z / libm::sqrtf(n2)) })
    }

    /// A world direction in tangent space (voxels). WGSL twin: `render_to_tangent`.
    pub fn to_tangent(&self, world: Vec3) -> Vec3 {
        Vec3::new(self.to_x.dot(world), self.to_y.dot(world), self.to_z.dot(world))
    }

    /// A tangent-space normal in world space (`Mᵀ n`, normalised). WGSL twin:
    /// `render_normal_to_world`.
    pub fn normal_to_world(&self, normal: Vec3) -> Vec3 {
        (self.to_x * normal.x + self.to_y * normal.y + self.to_z * normal.z).normalize_or_zero()
    }
}

/// The tangent-space ray `(origin, direction)` of a covered G-buffer texel seen from
/// `eye`: the origin is the texel's point on top of the slab, `(u L_x, v L_y, L_z)`, and
/// the direction is the world view direction mapped by [`TangentFrame`]. `None` for an
/// uncovered texel or a degenerate frame. WGSL twin: `render_tangent_ray`.
pub fn tangent_space_ray(texel: &BaseGBufferTexel, eye: Vec3, slab: Vec3, size_z: f32) -> Option<(Vec3, Vec3)> {
    if texel.position_coverage.w <= 0.0 {
        return None;
    }
    let frame = TangentFrame::new(texel, slab)?;
    let origin = Vec3::new(texel.tangent_u.w * slab.x, texel.bitangent_v.w * slab.y, size_z);
    let direction = frame.to_tangent(texel.position_coverage.truncate() - eye);
    Some((origin, direction))
}

/// Where the ray of a covered texel leaves the base mesh's solid again, as the tracer's
/// parameter (voxels along the unit tangent-space direction, from the texel's point).
///
/// The G-buffer holds, per pixel, the distance from the eye to the nearest base-mesh
/// surface (`front_distance`, the texel's) and to the next surface behind it along the
/// same eye ray (`exit_distance`, `ddm-render`'s second raster pass; 0 where there is
/// none, as for an open mesh seen from its side). The world stretch between them,
/// `exit − front`, maps to tangent space with the texel's constant frame (the paper's
/// approximation, [module documentation](self)): the world vector `P − eye` of length
/// `front` maps to `direction`, so a world length `s` along the ray is
/// `s · |direction| / front` voxels. [`NO_EXIT`] when `exit_distance ≤ front_distance`
/// (no second surface) or the result is not finite. WGSL twin: `render_shell_exit`.
pub fn shell_exit(front_distance: f32, exit_distance: f32, direction: Vec3) -> f32 {
    if !(exit_distance > front_distance && front_distance > 0.0) {
        return NO_EXIT;
    }
    let t = (exit_distance / front_distance - 1.0) * direction.length();
    if t.is_finite() { t } else { NO_EXIT }
}

/// The world distance from the eye of the point at the tracer's parameter `t` on the ray
/// of a covered texel whose base surface lies `front_distance` from the eye and whose
/// tangent-space direction is `direction`: `front + t · front / |direction|`, the inverse
/// of the mapping in [`shell_exit`] (one frame along the whole ray, the paper's
/// approximation). What `ddm-render` depth-tests objects with. WGSL twin:
/// `render_eye_distance`.
pub fn eye_distance(front_distance: f32, direction: Vec3, t: f32) -> f32 {
    front_distance + t * front_distance / direction.length()
}

/// The tracer's parameter at which the ray from the top of a slab `size_z` voxels deep,
/// along `direction`, reaches the bottom `z = 0` (voxels along the unit direction);
/// [`NO_EXIT`] for a direction that does not descend. WGSL twin: `render_slab_bottom`.
pub fn slab_bottom(direction: Vec3, size_z: f32) -> f32 {
    let length = direction.length();
    if !(direction.z < 0.0 && length.is_finite()) {
        return NO_EXIT;
    }
    size_z * length / -direction.z
}

/// A covered pixel's class from its ray's hit parameter (`None` for a miss), its
/// [`shell_exit`] and its [`slab_bottom`]: [`PIXEL_HIT`] for a hit within the shell;
/// otherwise [`PIXEL_LEFT_SHELL`] when the ray leaves the shell before the slab's bottom,
/// else [`PIXEL_MISS`]. WGSL twin: `render_pixel_class`.
pub fn pixel_class(hit_t: Option<f32>, shell_exit: f32, slab_bottom: f32) -> f32 {
    match hit_t {
        Some(t) if t <= shell_exit => PIXEL_HIT,
        _ if shell_exit < slab_bottom => PIXEL_LEFT_SHELL,
        _ => PIXEL_MISS,
    }
}

/// Whether the tangent-space point `point` is in shadow for the tangent-space direction
/// toward the light `light`: a light at or below the tangent plane (`light.z ≤ 0`)
/// shadows; otherwise the ray from where the shadow ray leaves the top of the slab is
/// traced back toward `point` (the tracer follows descending rays only), and a hit more
/// than `tolerance` voxels before `point` shadows it. WGSL twin: `render_in_shadow` (which
/// also runs relief mapping when the scene is a relief scene).
pub fn in_shadow<S: DistanceSource>(
    source: &S,
    patches: Option<&VoxelPatches>,
    point: Vec3,
    light: Vec3,
    tolerance: f32,
    settings: TraceSettings,
) -> bool {
    if light.z.partial_cmp(&0.0) != Some(core::cmp::Ordering::Greater) {
        return true;
    }
    let size_z = source.dims().z as f32;
    let top = point + light * ((size_z - point.z) / light.z);
    let distance = (top - point).length();
    trace(source, patches, top, -light, settings).hit.is_some_and(|hit| hit.t < distance - tolerance)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn texel(position: Vec3, tu: Vec3, tv: Vec3, n: Vec3, uv: (f32, f32)) -> BaseGBufferTexel {
        BaseGBufferTexel {
            position_coverage: position.extend(1.0),
            tangent_u: tu.extend(uv.0),
            bitangent_v: tv.extend(uv.1),
            normal_depth: n.extend(1.0),
        }
    }

    #[test]
    fn plane_in_voxel_units_is_the_identity() {
        // A plane at z = 4 with world = voxel units: ∂P/∂u = (L_x, 0, 0), h = L_z.
        let t = texel(
            Vec3::new(3.0, 5.0, 4.0),
            Vec3::new(8.0, 0.0, 0.0),
            Vec3::new(0.0, 8.0, 0.0),
            Vec3::Z,
            (0.375, 0.625),
        );
        let eye = Vec3::new(-2.0, 1.0, 12.0);
        let (origin, direction) = tangent_space_ray(&t, eye, Vec3::new(8.0, 8.0, 1.0), 4.0).unwrap();
        assert_eq!(origin, Vec3::new(3.0, 5.0, 4.0));
        assert_eq!(direction, Vec3::new(3.0, 5.0, 4.0) - eye);
    }

    #[test]
    fn normals_transform_with_the_inverse_transpose() {
        // Stretched frame: a tangent-space plane through the ray's points keeps its
        // normal perpendicular to every mapped tangent direction.
        let t = texel(
            Vec3::ZERO,
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::new(-3.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 5.0),
            (0.0, 0.0),
        );
        let frame = TangentFrame::new(&t, Vec3::new(16.0, 16.0, 20.0)).unwrap();
        let n_ts = Vec3::new(0.3, -0.2, 0.9).normalize();
        let n_world = frame.normal_to_world(n_ts);
        for world in [Vec3::X, Vec3::Y, Vec3::Z, Vec3::new(0.2, -0.7, 0.4)] {
            // A world direction lies in the surface iff its tangent image is ⟂ n_ts.
            let ts = frame.to_tangent(world);
            let in_plane_world = world - n_world * n_world.dot(world);
            let image = frame.to_tangent(in_plane_world);
            assert!(image.dot(n_ts).abs() < 1e-4 * image.length().max(1.0), "{ts}");
        }
    }

    #[test]
    fn a_ray_leaving_the_shell_before_the_bottom_shows_what_is_behind() {
        // A world stretch of half the front distance is half the tangent direction's length.
        let direction = Vec3::new(3.0, 0.0, -4.0);
        assert_eq!(shell_exit(10.0, 15.0, direction), 2.5);
        assert_eq!(shell_exit(10.0, 0.0, direction), NO_EXIT);
        assert_eq!(shell_exit(10.0, 10.0, direction), NO_EXIT);
        assert_eq!(shell_exit(0.0, 1.0, direction), NO_EXIT);
        // 8 voxels deep along a direction descending at 4/5: 10 voxels to the bottom.
        assert_eq!(slab_bottom(direction, 8.0), 10.0);
        assert_eq!(slab_bottom(Vec3::X, 8.0), NO_EXIT);
        assert_eq!(pixel_class(Some(2.0), 2.5, 10.0), PIXEL_HIT);
        assert_eq!(pixel_class(Some(3.0), 2.5, 10.0), PIXEL_LEFT_SHELL);
        assert_eq!(pixel_class(None, 2.5, 10.0), PIXEL_LEFT_SHELL);
        assert_eq!(pixel_class(None, 12.0, 10.0), PIXEL_MISS);
        assert_eq!(pixel_class(None, NO_EXIT, 10.0), PIXEL_MISS);
        assert_eq!(pixel_class(Some(9.0), NO_EXIT, 10.0), PIXEL_HIT);
        // Back from the tracer's parameter to the eye distance.
        assert_eq!(eye_distance(10.0, direction, 2.5), 15.0);
        assert_eq!(eye_distance(10.0, direction, 0.0), 10.0);
    }

    #[test]
    fn degenerate_texels_are_rejected() {
        let mut t = texel(Vec3::ZERO, Vec3::ZERO, Vec3::Y, Vec3::Z, (0.0, 0.0));
        assert!(tangent_space_ray(&t, Vec3::Z, Vec3::ONE, 1.0).is_none());
        t.tangent_u = Vec4::new(1.0, 0.0, 0.0, 0.0);
        t.position_coverage.w = 0.0;
        assert!(tangent_space_ray(&t, Vec3::Z, Vec3::ONE, 1.0).is_none());
        t.position_coverage.w = 1.0;
        assert!(tangent_space_ray(&t, Vec3::Z, Vec3::ONE, 1.0).is_some());
        t.normal_depth = Vec4::new(f32::NAN, 0.0, 1.0, 0.0);
        assert!(tangent_space_ray(&t, Vec3::Z, Vec3::ONE, 1.0).is_none());
    }
}
