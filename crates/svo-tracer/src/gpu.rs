//! The GPU forms of a camera and of the trace settings, for the WGSL twin.

use glam::{UVec4, Vec4};
use gpu_layout::gpu_struct;

use crate::camera::Camera;
use crate::trace::{Model, TraceSettings};

gpu_struct! {
    /// A [`Camera`] for `svo_pixel_cone`.
    pub struct GpuCamera {
        /// `(eye, pixel size at unit distance)`.
        pub position_pixel_size: Vec4,
        /// `(right, 0)`.
        pub right: Vec4,
        /// `(up, 0)`.
        pub up: Vec4,
        /// `(forward, 0)`.
        pub forward: Vec4,
        /// `(width, height, has a lens (0 or 1), 0)`.
        pub size: UVec4,
        /// `(aperture, focus, 0, 0)`; unused without a lens.
        pub lens: Vec4,
    }
}

gpu_struct! {
    /// [`TraceSettings`] for `svo_trace_cone`.
    pub struct GpuTraceSettings {
        /// `(model index, max elements, empty-space skip (0 or 1), shadow cones)`.
        pub model_limits: UVec4,
        /// `(light position, light radius)`.
        pub light: Vec4,
        /// `(light radiance, diffuse, specular, BRDF slope σnp)`.
        pub shading: Vec4,
        /// `(background, κ the half-length floor in finest voxels)`.
        pub background_floor: Vec4,
    }
}

impl Model {
    /// The model's index on the GPU (`SVO_MODEL_*`).
    pub const fn index(self) -> u32 {
        match self {
            Model::Masks => 0,
            Model::AlphaBlend => 1,
            Model::Nearest => 2,
            Model::SeparateFiltering => 3,
        }
    }
}

impl Camera {
    /// The camera's GPU form.
    pub fn to_gpu(&self) -> GpuCamera {
        let (width, height) = self.size();
        let lens = self.lens();
        GpuCamera {
            position_pixel_size: self.position().extend(self.pixel_size()),
            right: self.right().extend(0.0),
            up: self.up().extend(0.0),
            forward: self.forward().extend(0.0),
            size: UVec4::new(width, height, u32::from(lens.is_some()), 0),
            lens: lens.map_or(Vec4::ZERO, |l| Vec4::new(l.aperture, l.focus, 0.0, 0.0)),
        }
    }
}

impl TraceSettings {
    /// The settings' GPU form.
    pub fn to_gpu(&self) -> GpuTraceSettings {
        GpuTraceSettings {
            model_limits: UVec4::new(
                self.model.index(),
                self.max_elements,
                u32::from(self.empty_space_skip),
                self.shadow_cones,
            ),
            light: self.light.position.extend(self.light.radius),
            shading: Vec4::new(
                self.light.radiance,
                self.material.diffuse,
                self.material.specular,
                self.material.brdf_slope,
            ),
            background_floor: self.background.extend(self.min_half_length),
        }
    }
}
