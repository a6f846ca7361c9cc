//! Cameras, grain instances and the texture formats every pass of the crate agrees on.

use glam::{Mat4, Quat, UVec4, Vec3, Vec4};
use gpu_layout::{GpuConst, gpu_const, gpu_struct};
use wgsl_gen::{GenerateError, StructDecl, generate_declarations};

gpu_struct! {
    /// A camera as the shaders see it. Matrices are column-major arrays of columns, as glam
    /// stores them (`Mat4::to_cols_array_2d`).
    pub struct CameraUniforms {
        /// World → clip space (wgpu conventions: clip depth in `[0, 1]`).
        pub clip_from_world: [Vec4; 4],
        /// Clip → world space, the inverse of `clip_from_world`.
        pub world_from_clip: [Vec4; 4],
        /// Perspective cameras: the eye position, `w = 1`. Orthographic cameras: the unit
        /// viewing direction (where rays go), `w = 0`.
        pub eye: Vec4,
        /// `(width, height, 1 / width, 1 / height)` of the render target in pixels.
        pub viewport: Vec4,
    }
}

impl CameraUniforms {
    /// A perspective camera at `eye` looking at `target` (`up` the approximate up vector),
    /// with vertical field of view `fov_y_radians`, rendering `width × height` pixels; or
    /// `None` when the inputs do not define an invertible projection.
    pub fn perspective(
        eye: Vec3,
        target: Vec3,
        up: Vec3,
        fov_y_radians: f32,
        (width, height): (u32, u32),
        (near, far): (f32, f32),
    ) -> Option<Self> {
        let positive = |x: f32| x.is_finite() && x > 0.0;
        if width == 0 || height == 0 || !positive(near) || !(far.is_finite() && far > near) || !positive(fov_y_radians)
        {
            return None;
        }
        let forward = target - eye;
        if !forward.is_finite() || forward.length_squared() == 0.0 || forward.cross(up).length_squared() == 0.0 {
            return None;
        }
        let view = look_to_rh(eye, forward, up);
        let projection = perspective_rh(fov_y_radians, width as f32 / height as f32, near, far);
        Self::from_matrix(projection * view, eye.extend(1.0), (width, height))
    }

    /// An orthographic camera looking along `direction` at the square of half-size `extent`
    /// centred on `centre`, with depth range `centre ± depth_extent` along `direction`:
    /// the camera of an atlas view when `direction = -ω_i` (see
    /// [`octahedral_map::ViewFrame`]), in which case its image is exactly the view's
    /// texture (`up` = the frame's `up`).
    pub fn orthographic(
        centre: Vec3,
        direction: Vec3,
        up: Vec3,
        extent: f32,
        depth_extent: f32,
        (width, height): (u32, u32),
    ) -> Option<Self> {
        let positive = |x: f32| x.is_finite() && x > 0.0;
        if width == 0 || height == 0 || !positive(extent) || !positive(depth_extent) {
            return None;
        }
        let direction = direction.try_normalize()?;
        if direction.cross(up).length_squared() == 0.0 {
            return None;
        }
        let eye = centre - direction * (2.0 * depth_extent);
        let view = look_to_rh(eye, direction, up);
        let projection = orthographic_rh(extent, depth_extent, 3.0 * depth_extent);
        Self::from_matrix(projection * view, direction.extend(0.0), (width, height))
    }

    fn from_matrix(clip_from_world: Mat4, eye: Vec4, (width, height): (u32, u32)) -> Option<Self> {
        if !clip_from_world.is_finite() || clip_from_world.determinant().abs() < f32::MIN_POSITIVE {
            return None;
        }
        let world_from_clip = clip_from_world.inverse();
        let columns = |m: Mat4| m.to_cols_array_2d().map(Vec4::from_array);
        let (w, h) = (width as f32, height as f32);
        Some(Self {
            clip_from_world: columns(clip_from_world),
            world_from_clip: columns(world_from_clip),
            eye,
            viewport: Vec4::new(w, h, 1.0 / w, 1.0 / h),
        })
    }

    /// `clip_from_world` as a matrix.
    pub fn clip_from_world(&self) -> Mat4 {
        Mat4::from_cols_array_2d(&self.clip_from_world.map(|column| column.to_array()))
    }

    /// `world_from_clip` as a matrix.
    pub fn world_from_clip(&self) -> Mat4 {
        Mat4::from_cols_array_2d(&self.world_from_clip.map(|column| column.to_array()))
    }
}

/// Right-handed world → view transform of a camera at `eye` looking along `forward`
/// (the view looks down its `-z` axis). The glam build used here lacks the camera helpers.
/// Public so that other passes (the grain splitter) build bit-identical matrices.
pub fn look_to_rh(eye: Vec3, forward: Vec3, up: Vec3) -> Mat4 {
    let f = forward.normalize();
    let s = f.cross(up).normalize();
    let u = s.cross(f);
    Mat4::from_cols(
        Vec4::new(s.x, u.x, -f.x, 0.0),
        Vec4::new(s.y, u.y, -f.y, 0.0),
        Vec4::new(s.z, u.z, -f.z, 0.0),
        Vec4::new(-s.dot(eye), -u.dot(eye), f.dot(eye), 1.0),
    )
}

/// Right-handed perspective projection with clip depth in `[0, 1]` (wgpu), vertical field
/// of view `fov_y_radians`, `aspect` = width / height.
pub fn perspective_rh(fov_y_radians: f32, aspect: f32, near: f32, far: f32) -> Mat4 {
    let h = 1.0 / (0.5 * fov_y_radians).tan();
    let w = h / aspect;
    let r = far / (near - far);
    Mat4::from_cols(
        Vec4::new(w, 0.0, 0.0, 0.0),
        Vec4::new(0.0, h, 0.0, 0.0),
        Vec4::new(0.0, 0.0, r, -1.0),
        Vec4::new(0.0, 0.0, r * near, 0.0),
    )
}

/// Right-handed orthographic projection of the square `[-extent, extent]²` with clip depth in
/// `[0, 1]` between `near` and `far`.
pub fn orthographic_rh(extent: f32, near: f32, far: f32) -> Mat4 {
    let r = 1.0 / (near - far);
    Mat4::from_cols(
        Vec4::new(1.0 / extent, 0.0, 0.0, 0.0),
        Vec4::new(0.0, 1.0 / extent, 0.0, 0.0),
        Vec4::new(0.0, 0.0, r, 0.0),
        Vec4::new(0.0, 0.0, r * near, 1.0),
    )
}

gpu_struct! {
    /// One grain of a cloud: where it is, how large, how it is turned.
    pub struct GrainInstance {
        /// World position of the grain's centre (`xyz`) and its uniform scale (`w`, world
        /// units per unit of the grain's mesh).
        pub centre_scale: Vec4,
        /// Unit quaternion `(x, y, z, w)` rotating the grain's local frame into the world.
        pub rotation: Vec4,
    }
}

impl GrainInstance {
    /// A grain at `centre` with uniform `scale` and `rotation` (normalized here).
    pub fn new(centre: Vec3, scale: f32, rotation: Quat) -> Self {
        Self { centre_scale: centre.extend(scale), rotation: Vec4::from(rotation.normalize()) }
    }

    /// The grain's local → world transform.
    pub fn world_from_local(&self) -> Mat4 {
        let rotation = Quat::from_vec4(self.rotation);
        Mat4::from_scale_rotation_translation(Vec3::splat(self.centre_scale.w), rotation, self.centre_scale.truncate())
    }
}

/// One texture of a G-buffer or atlas: its name in shaders and its format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TextureLayer {
    /// The layer's name, used for bindings and file names.
    pub name: &'static str,
    /// What the channels hold.
    pub channels: &'static str,
    /// The wgpu format name (this crate does not depend on wgpu's types here).
    pub format: &'static str,
    /// Bytes per texel.
    pub bytes_per_texel: u32,
}

/// The screen G-buffer written by the mesh pass and the impostor cloud pass, and read by the
/// deferred shading pass. Background pixels have coverage 0 and depth `+∞`.
pub const GBUFFER_LAYERS: [TextureLayer; 4] = [
    TextureLayer {
        name: "normal_coverage",
        channels: "world-space unit normal (xyz), coverage in [0, 1] (a)",
        format: "Rgba16Float",
        bytes_per_texel: 8,
    },
    TextureLayer {
        name: "albedo",
        channels: "linear albedo (rgb), unused (a)",
        format: "Rgba8Unorm",
        bytes_per_texel: 4,
    },
    TextureLayer {
        name: "material",
        channels: "roughness (r), metallic (g), unused (ba)",
        format: "Rgba8Unorm",
        bytes_per_texel: 4,
    },
    TextureLayer {
        name: "depth",
        channels: "view-space distance along the camera's forward axis (r)",
        format: "R32Float",
        bytes_per_texel: 4,
    },
];

/// The layers of an impostor atlas: `p × p` texels, `N = 2n²` array layers (one per view),
/// full mip chains. Every channel is **premultiplied by the coverage α** (§4.2), so that
/// filtering and mip reduction never mix in background values.
pub const ATLAS_LAYERS: [TextureLayer; 4] = [
    TextureLayer {
        name: "normal_alpha",
        channels: "(0.5·n + 0.5)·α (rgb; n the unit normal in the grain's local frame), α (a)",
        format: "Rgba8Unorm",
        bytes_per_texel: 4,
    },
    TextureLayer {
        name: "albedo_alpha",
        channels: "linear albedo·α (rgb), α (a)",
        format: "Rgba8UnormSrgb",
        bytes_per_texel: 4,
    },
    TextureLayer {
        name: "material_alpha",
        channels: "roughness·α (r), metallic·α (g), unused (b), α (a)",
        format: "Rgba8Unorm",
        bytes_per_texel: 4,
    },
    TextureLayer {
        name: "depth_alpha",
        channels: "depth·α (r; depth = dot(q, ω)/R ∈ [-1, 1], see ViewFrame::depth), α (g)",
        format: "Rg16Float",
        bytes_per_texel: 4,
    },
];

gpu_struct! {
    /// Parameters of the supersampling reduction (`shaders/gbuffer_reduce.wgsl`): `s × s`
    /// blocks of the high-resolution G-buffer become one output texel.
    pub struct ReduceParams {
        /// `(s, output width, output height, array layers)`.
        pub size: UVec4,
        /// `(R, 0, 0, 0)`: the atlas extent, for the atlas output's depth
        /// `1 - (distance from the near plane) / R` (= `dot(q, ω) / R`, see `mesh_gbuffer`).
        pub extent: Vec4,
    }
}

gpu_struct! {
    /// The light, ambient term and background of the deferred shading pass
    /// (`shaders/shading.wgsl`). Colours are linear RGB.
    pub struct ShadingUniforms {
        /// Unit direction from the surface toward the directional light (`xyz`), `w = 0`.
        pub light_direction: Vec4,
        /// Irradiance of the light on a surface facing it (`rgb`), `a` unused.
        pub light_colour: Vec4,
        /// Uniform ambient radiance (`rgb`), multiplied by the albedo; `a` unused.
        pub ambient: Vec4,
        /// Background colour where coverage is 0 (`rgb`), `a` unused.
        pub background: Vec4,
    }
}

/// The structs of this module, for WGSL generation.
pub fn struct_declarations() -> Vec<StructDecl> {
    vec![
        StructDecl::of::<CameraUniforms>(),
        StructDecl::of::<GrainInstance>(),
        StructDecl::of::<ReduceParams>(),
        StructDecl::of::<ShadingUniforms>(),
    ]
}

/// Pixels per side of the square workgroup of every per-pixel compute pass (the impostor
/// cloud's passes, the G-buffer reduction, the shading): the shaders declare
/// `@workgroup_size(PIXEL_TILE, PIXEL_TILE)` and the dispatches divide the image by it.
pub const PIXEL_TILE: u32 = 8;

/// The constants of this crate's shaders, generated with its structs.
pub const WGSL_CONSTANTS: &[GpuConst] = &[
    gpu_const!(PIXEL_TILE: u32),
    gpu_const!("PI": f32 = core::f32::consts::PI),
    gpu_const!("POSITIVE_INFINITY_BITS": u32 = gpu_layout::f32_bits::INFINITY_BITS),
];

/// Path of the committed generated WGSL, relative to the workspace root.
pub const GENERATED_WGSL_PATH: &str = "crates/grain-impostor/shaders/generated.wgsl";

/// The committed generated declarations (embedded at build time).
pub const GENERATED_WGSL: &str = include_str!("../shaders/generated.wgsl");

/// The WGSL declarations of this crate's GPU structs, as the Rust source says they should be
/// now (`cargo xtask codegen` writes them to [`GENERATED_WGSL_PATH`]).
pub fn generated_wgsl() -> Result<String, GenerateError> {
    generate_declarations("grain_impostor", &struct_declarations(), WGSL_CONSTANTS)
}

#[cfg(test)]
mod tests {
    use super::*;
    use wgsl_gen::{ComposedShader, check_layout};

    #[test]
    fn committed_generated_wgsl_is_fresh_valid_and_laid_out_like_rust() {
        let expected = generated_wgsl().unwrap();
        assert!(GENERATED_WGSL == expected, "stale {GENERATED_WGSL_PATH}; run `cargo xtask codegen`");
        let module = ComposedShader::new("grain_impostor").with_part(GENERATED_WGSL_PATH, GENERATED_WGSL).validate();
        let module = module.unwrap_or_else(|e| panic!("{e}"));
        check_layout(&module.module, &struct_declarations()).unwrap();
    }

    #[test]
    fn perspective_camera_projects_its_target_to_the_screen_centre() {
        let camera =
            CameraUniforms::perspective(Vec3::new(0.0, -5.0, 2.0), Vec3::ZERO, Vec3::Z, 0.8, (64, 48), (0.1, 100.0))
                .unwrap();
        let clip = camera.clip_from_world() * Vec4::new(0.0, 0.0, 0.0, 1.0);
        assert!((clip.x / clip.w).abs() < 1e-6 && (clip.y / clip.w).abs() < 1e-6);
        let back = camera.world_from_clip() * clip;
        assert!((back.truncate() / back.w).length() < 1e-5);
        assert!(CameraUniforms::perspective(Vec3::ZERO, Vec3::ZERO, Vec3::Z, 0.8, (64, 48), (0.1, 1.0)).is_none());
        assert!(CameraUniforms::perspective(Vec3::ONE, Vec3::ZERO, Vec3::Z, 0.8, (0, 48), (0.1, 1.0)).is_none());
    }

    #[test]
    fn orthographic_camera_of_a_view_maps_points_to_the_view_texture_coordinates() {
        let views = octahedral_map::OctahedralViews::new(4).unwrap();
        let extent = 1.5;
        for index in 0..views.view_count() {
            let frame = octahedral_map::ViewFrame::from_direction(views.view_direction(index).unwrap()).unwrap();
            let camera =
                CameraUniforms::orthographic(Vec3::ZERO, -frame.direction, frame.up, extent, extent, (32, 32)).unwrap();
            for point in [Vec3::new(0.3, -0.2, 0.5), Vec3::new(-1.0, 0.4, 0.1), Vec3::ZERO] {
                let clip = camera.clip_from_world() * point.extend(1.0);
                // Clip x, y in [-1, 1] (y up) → texture coordinates (v down).
                let uv = glam::Vec2::new(0.5 + 0.5 * clip.x / clip.w, 0.5 - 0.5 * clip.y / clip.w);
                let expected = frame.texture_coordinates(point, extent);
                assert!(uv.distance(expected) < 1e-5, "view {index}: {uv} vs {expected}");
                // Clip depth grows away from the camera: nearer points (larger view depth) are smaller.
                let z = clip.z / clip.w;
                assert!((z - (0.5 - 0.5 * frame.depth(point, extent))).abs() < 1e-5, "view {index}: z {z}");
            }
        }
    }

    #[test]
    fn grain_instance_transform_scales_rotates_and_moves() {
        let grain =
            GrainInstance::new(Vec3::new(1.0, 2.0, 3.0), 2.0, Quat::from_rotation_z(core::f32::consts::FRAC_PI_2));
        let p = grain.world_from_local().transform_point3(Vec3::X);
        assert!(p.distance(Vec3::new(1.0, 4.0, 3.0)) < 1e-5);
    }
}
