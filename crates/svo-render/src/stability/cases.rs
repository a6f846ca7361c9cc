//! The scenes and views of each sweep: one [`Case`] per step of the relaxed parameter, each
//! an `svo-scenes` surface with the views that share its octree.
//!
//! Every length is given in finest voxels `S₀` of the octree (`domain.size / (4 ·
//! 2^(levels − 1))`, 4³ bricks over the cube `[−1, 1]³`), so that a step means the same
//! thing at every resolution. Cameras have the vertical field of view [`FOV_Y`]; a view "at
//! distance `D`" looks at the subject from `D` world units.

use std::sync::Arc;

use glam::Vec3;
use microsurface_truth::{HeightField, Spectrum, generate_cellular, generate_gaussian, generate_ridged};
use svo_brick::{ATTRIBUTE_CHANNELS, BrickSize, Domain, SurfaceSource};
use svo_scenes::{Attribute, AxisBox, HeightMapSurface, Plate, Sphere};
use svo_tracer::{Camera, Light, Material};

use super::{StabilitySettings, Sweep};
use crate::error::RenderError;

/// The vertical field of view of every view but the grazing ones (radians).
pub const FOV_Y: f32 = 0.5;

/// The vertical field of view of the grazing views (radians): wide, so that an eye inside
/// the domain still has pixels of about a finest voxel or more.
pub const GRAZING_FOV_Y: f32 = 1.0;

/// The cube every sweep's octree covers.
pub const DOMAIN: Domain = Domain { origin: Vec3::splat(-1.0), size: 2.0 };

/// The finest voxel of an octree of `levels` levels of 4³ bricks over [`DOMAIN`].
pub fn finest_voxel(levels: u32) -> f32 {
    let bricks = 1u64 << levels.saturating_sub(1).min(40);
    DOMAIN.size / (BrickSize::Four.side() as f32 * bricks as f32)
}

/// A surface shared by the views of one step.
pub type SharedSource = Arc<dyn SurfaceSource + Send + Sync>;

/// One view of a case: a label (`"face-on"`, `"sphere"`, `"cellular"`, …) and its camera
/// and light.
#[derive(Clone, Copy, Debug)]
pub struct View {
    /// What is seen, as written in the CSV's `variant` column.
    pub variant: &'static str,
    /// The camera.
    pub camera: Camera,
    /// The light (the same for every model of the view).
    pub light: Light,
    /// The point the camera looks at (where [`Self::pixel_voxels`] is measured).
    pub target: Vec3,
    /// The material (the same for every model of the view).
    pub material: Material,
}

impl View {
    /// A pixel's footprint at the target, in finest voxels `voxel`: `> 1` means the cone
    /// reads coarser levels there, `λ = log₂` of it (`svo_tracer`'s level of detail).
    pub fn pixel_voxels(&self, voxel: f32) -> f32 {
        (self.target - self.camera.position()).length() * self.camera.pixel_size() / voxel
    }
}

/// One step of a sweep: the relaxed parameter's value, the surface and its views.
pub struct Case {
    /// The sweep.
    pub sweep: Sweep,
    /// The parameter's value (its unit is [`Sweep::parameter`]).
    pub parameter: f32,
    /// The unfiltered surface: the octree is built from it and the truth traces it.
    pub source: SharedSource,
    /// The views.
    pub views: Vec<View>,
}

impl core::fmt::Debug for Case {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Case")
            .field("sweep", &self.sweep)
            .field("parameter", &self.parameter)
            .field("views", &self.views)
            .finish_non_exhaustive()
    }
}

/// `Err(Scene)` naming the sweep's scene.
fn scene<T>(name: &'static str, result: Result<T, svo_scenes::SceneError>) -> Result<T, RenderError> {
    result.map_err(|source| RenderError::Scene { scene: name, source })
}

/// A camera of `settings`' size at `eye` looking at `target` with the field of view [`FOV_Y`].
fn camera(settings: &StabilitySettings, eye: Vec3, target: Vec3, up: Vec3, view: u32) -> Result<Camera, RenderError> {
    wide_camera(settings, eye, target, up, view, FOV_Y)
}

/// A camera of `settings`' size at `eye` looking at `target` with the field of view `fov_y`.
fn wide_camera(
    settings: &StabilitySettings,
    eye: Vec3,
    target: Vec3,
    up: Vec3,
    view: u32,
    fov_y: f32,
) -> Result<Camera, RenderError> {
    Camera::look_at(eye, target, up, fov_y, settings.width, settings.height)
        .map_err(|source| RenderError::Camera { view, source })
}

/// A light far along `direction` from `target` (the tracer's light has no fall-off, so only
/// the direction matters), of the angular radius of a sphere of radius 1 at distance 20.
fn light(target: Vec3, direction: Vec3) -> Light {
    Light { position: target + direction.normalize_or_zero() * 20.0, radius: 1.0, radiance: 3.0 }
}

/// The distance at which an object of screen half-extent `half` fills `fill` of the
/// image's half-height.
fn framing_distance(half: f32, fill: f32) -> f32 {
    half / (fill * (0.5 * FOV_Y).tan())
}

/// The distance at which a pixel's footprint is `pixel_voxels` finest voxels `voxel`.
fn footprint_distance(settings: &StabilitySettings, pixel_voxels: f32, voxel: f32) -> f32 {
    pixel_voxels * voxel * settings.height as f32 / (2.0 * (0.5 * FOV_Y).tan())
}

/// The plates' radius (world units).
pub const PLATE_RADIUS: f32 = 0.8;

/// H7: a disk-shaped [`Plate`] of radius [`PLATE_RADIUS`], normal `z`, of thickness `t S₀`
/// for each `t` of [`StabilitySettings::plate_thickness`], its mid-plane at `z = offset S₀`
/// ([`StabilitySettings::plate_offset`]; 0.5 puts it halfway between two lattice planes,
/// where the finest level's vertices see `|z| − t/2 = (1 − t)/2 S₀ > 0` for `t < 1`: the
/// worst case). Three views: `"face-on"` along the normal and `"edge-on"` in the plate's
/// plane, at the distance where the disk fills 80 % of the image, and `"face-on-far"`
/// along the normal where a pixel is [`StabilitySettings::far_pixel_voxels`] finest voxels
/// (the cone reads a coarser level there).
pub fn thin_plates(settings: &StabilitySettings) -> Result<Vec<Case>, RenderError> {
    let voxel = finest_voxel(settings.levels);
    let centre = Vec3::new(0.0, 0.0, settings.plate_offset * voxel);
    let colour = scene("plate", Attribute::constant([0.8, 0.6, 0.3]))?;
    let distance = framing_distance(PLATE_RADIUS, 0.8);
    let lit = light(centre, Vec3::new(0.4, 0.5, -1.0));
    let face_on = camera(settings, centre - Vec3::Z * distance, centre, Vec3::Y, 0)?;
    let edge_on = camera(settings, centre + Vec3::X * distance, centre, Vec3::Z, 1)?;
    let far = footprint_distance(settings, settings.far_pixel_voxels, voxel);
    let face_far = camera(settings, centre - Vec3::Z * far, centre, Vec3::Y, 2)?;
    settings
        .plate_thickness
        .iter()
        .map(|&t| {
            let plate = scene("plate", Plate::disk(centre, Vec3::Z, 0.5 * t * voxel, PLATE_RADIUS, colour.clone()))?;
            Ok(Case {
                sweep: Sweep::ThinPlate,
                parameter: t,
                source: Arc::new(plate),
                views: vec![
                    View {
                        variant: "face-on",
                        camera: face_on,
                        light: lit,
                        target: centre,
                        material: Material::default(),
                    },
                    View {
                        variant: "edge-on",
                        camera: edge_on,
                        light: lit,
                        target: centre,
                        material: Material::default(),
                    },
                    View {
                        variant: "face-on-far",
                        camera: face_far,
                        light: lit,
                        target: centre,
                        material: Material::default(),
                    },
                ],
            })
        })
        .collect()
}

/// The colour of the curved subjects: a gradient along `z` over `[−half, half]`.
fn gradient_colour(centre: Vec3, half: f32) -> Attribute {
    Attribute::function(move |p: Vec3| {
        let t = ((p.z - centre.z) / half).clamp(-1.0, 1.0);
        [0.8, 0.55 + 0.25 * t, 0.3]
    })
}

/// H6: for each `r` of [`StabilitySettings::curvature_radius`], a [`Sphere`] of radius
/// `r S₀` (`"sphere"`, seen along `+z`) and a cube [`AxisBox`] of half-side `r S₀` seen
/// along its diagonal (`"box-corner"`, three faces and the corner between them) and along a
/// face diagonal (`"box-edge"`, two faces and their edge). Each camera's distance is
/// proportional to `r` (the subject fills 70 % of the image at every step), so the image
/// is the same but for the voxels: the curvature radius, or the half-side, relative to the
/// voxel is the only change. Centres are offset from the lattice by `(0.3, 0.2, 0.1) S₀`.
pub fn curvature(settings: &StabilitySettings) -> Result<Vec<Case>, RenderError> {
    let voxel = finest_voxel(settings.levels);
    let centre = Vec3::new(0.3, 0.2, 0.1) * voxel;
    let lit = |from: Vec3| light(centre, from);
    let mut cases = Vec::new();
    for &r in &settings.curvature_radius {
        let half = r * voxel;
        let sphere = scene("sphere", Sphere::new(centre, half, gradient_colour(centre, half)))?;
        let sphere_eye = centre - Vec3::Z * framing_distance(half, 0.7);
        let sphere_view = View {
            variant: "sphere",
            camera: camera(settings, sphere_eye, centre, Vec3::Y, 0)?,
            light: lit(Vec3::new(-0.5, 0.7, -1.0)),
            target: centre,
            material: Material::default(),
        };
        cases.push(Case { sweep: Sweep::Curvature, parameter: r, source: Arc::new(sphere), views: vec![sphere_view] });

        let colour = Attribute::function(move |p: Vec3| {
            ((Vec3::splat(0.5) + 0.4 * (p - centre) / half).clamp(Vec3::ZERO, Vec3::ONE)).to_array()
        });
        let cube = scene("box", AxisBox::new(centre, Vec3::splat(half), colour))?;
        // The projected half-extent along a diagonal is at most √2 half-sides.
        let distance = framing_distance(2f32.sqrt() * half, 0.7) + 3f32.sqrt() * half;
        let corner = Vec3::new(1.0, 1.0, -1.0).normalize();
        let edge = Vec3::new(1.0, 0.0, -1.0).normalize();
        let views = vec![
            View {
                variant: "box-corner",
                camera: camera(settings, centre + corner * distance, centre, Vec3::Y, 1)?,
                light: lit(Vec3::new(0.3, 1.0, -0.6)),
                target: centre,
                material: Material::default(),
            },
            View {
                variant: "box-edge",
                camera: camera(settings, centre + edge * distance, centre, Vec3::Y, 2)?,
                light: lit(Vec3::new(0.2, 0.6, -1.0)),
                target: centre,
                material: Material::default(),
            },
        ];
        cases.push(Case { sweep: Sweep::Curvature, parameter: r, source: Arc::new(cube), views });
    }
    Ok(cases)
}

/// The specular material of the H3 sweep's mirror views, Fig. 12's: a weak Lambert term
/// (`k_d` 0.2) under a microfacet lobe (`k_s` 1) of base slopes `σnp` 0.1, so that the
/// highlight's spread is the lobe `σn² + σnp²` of §5.5, whose `σn²` assumes Gaussian slopes.
pub const SPECULAR: Material = Material { diffuse: 0.2, specular: 1.0, brdf_slope: 0.1 };

/// The micro-surfaces of the H3 sweep: a Gaussian random field (the hypothesis) and two
/// non-Gaussian ones of `microsurface-truth` (sharp-crested ridges, skewed; cellular
/// cobblestones, bimodal slopes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MicroSurface {
    /// `generate_gaussian` with a Gaussian spectrum of correlation length `ℓ`.
    Gaussian,
    /// `generate_cellular`: `F2 − F1` Worley noise with one feature point per `ℓ²` cells.
    Cellular,
    /// `generate_ridged`: `−|g|` of a Gaussian field of correlation length `2ℓ` (the ridges,
    /// zero crossings of `g`, are about `ℓ` apart).
    Ridged,
}

impl MicroSurface {
    /// Every surface, the Gaussian first.
    pub const ALL: [MicroSurface; 3] = [MicroSurface::Gaussian, MicroSurface::Cellular, MicroSurface::Ridged];

    /// Its name in the CSV's `variant` column.
    pub const fn name(self) -> &'static str {
        match self {
            MicroSurface::Gaussian => "gaussian",
            MicroSurface::Cellular => "cellular",
            MicroSurface::Ridged => "ridged",
        }
    }

    /// The name of its mirror view (the [`SPECULAR`] material, the light at the view's
    /// mirror direction) in the CSV's `variant` column.
    pub const fn specular_name(self) -> &'static str {
        match self {
            MicroSurface::Gaussian => "gaussian-specular",
            MicroSurface::Cellular => "cellular-specular",
            MicroSurface::Ridged => "ridged-specular",
        }
    }

    /// The periodic height field of `size × size` cells with feature size `feature` cells,
    /// its heights shifted to mean 0 and scaled to RMS 1 (so that every surface has the
    /// same RMS height `σh` once scaled; their slopes then differ).
    pub fn unit_heights(self, size: usize, feature: f64, seed: u64) -> Result<HeightField, RenderError> {
        let field = match self {
            MicroSurface::Gaussian => generate_gaussian(size, Spectrum::Gaussian { wavelength: feature }, 1.0, seed),
            MicroSurface::Cellular => {
                let cells = ((size * size) as f64 / (feature * feature)).round().max(2.0) as usize;
                generate_cellular(size, cells, 1.0, seed)
            }
            MicroSurface::Ridged => generate_ridged(size, 2.0 * feature, 1.0, seed),
        };
        let field = field.map_err(|source| RenderError::HeightField { surface: self.name(), source })?;
        let heights = field.heights();
        let count = heights.len().max(1) as f64;
        let mean = heights.iter().sum::<f64>() / count;
        let rms = (heights.iter().map(|h| (h - mean).powi(2)).sum::<f64>() / count).sqrt();
        let scale = if rms > 0.0 { rms.recip() } else { 0.0 };
        HeightField::new(field.size(), heights.iter().map(|h| (h - mean) * scale).collect())
            .map_err(|source| RenderError::HeightField { surface: self.name(), source })
    }
}

/// The colour of a height `h` for RMS height `sigma`: deep red to high yellow through a
/// logistic of `2h/σ` (the height-correlated colour of Fig. 11, H5).
fn height_colour(h: f32, sigma: f32) -> [f32; ATTRIBUTE_CHANNELS] {
    let t = 1.0 / (1.0 + (-2.0 * h / sigma.max(f32::MIN_POSITIVE)).exp());
    let (deep, high) = ([0.8, 0.1, 0.05], [0.95, 0.85, 0.1]);
    std::array::from_fn(|c| deep[c] + (high[c] - deep[c]) * t)
}

/// The [`HeightMapSurface`] `z = σ H(x, y)` of `surface` over the whole domain: a periodic
/// grid of two vertices per finest voxel (its period is the domain's side), feature size
/// [`StabilitySettings::feature_voxels`] finest voxels, RMS height `sigma` world units,
/// coloured by height.
pub fn height_map(
    surface: MicroSurface,
    settings: &StabilitySettings,
    sigma: f32,
) -> Result<HeightMapSurface, RenderError> {
    let voxel = finest_voxel(settings.levels);
    let texel = 0.5 * voxel;
    let size = (DOMAIN.size / texel).round() as usize;
    let unit = surface.unit_heights(size, 2.0 * f64::from(settings.feature_voxels), settings.seed)?;
    let heights = unit.heights().iter().map(|&h| h as f32).collect();
    let colour = Attribute::function(move |h: f32| height_colour(h, sigma));
    scene("height-map", HeightMapSurface::new(size, heights, texel, sigma, colour))
}

/// H3: for each surface of [`MicroSurface::ALL`] and each RMS height `σ S₀` of
/// [`StabilitySettings::rms_height`], the [`height_map`] seen from 50° off its normal where
/// a pixel is [`StabilitySettings::height_pixel_voxels`] finest voxels at the centre (more
/// towards the top of the image: the cone reads the coarse levels whose Gaussian
/// descriptors H3 is about), twice: diffuse, lit from the side 45° off the normal (the
/// visible colour of eq. 17, whose masking assumes Gaussian heights), and [`SPECULAR`],
/// lit from the mirror direction (Fig. 12's highlight, whose lobe `σn² + σnp²` assumes
/// Gaussian slopes).
pub fn non_gaussian(settings: &StabilitySettings) -> Result<Vec<Case>, RenderError> {
    let voxel = finest_voxel(settings.levels);
    let (target, theta) = (Vec3::ZERO, 50f32.to_radians());
    let distance = footprint_distance(settings, settings.height_pixel_voxels, voxel);
    let eye = target + Vec3::new(-theta.sin(), 0.0, theta.cos()) * distance;
    let side = light(target, Vec3::new(0.0, 45f32.to_radians().sin(), 45f32.to_radians().cos()));
    let mirror = light(target, Vec3::new(theta.sin(), 0.0, theta.cos()));
    let mut cases = Vec::new();
    for surface in MicroSurface::ALL {
        for &sigma in &settings.rms_height {
            let map = height_map(surface, settings, sigma * voxel)?;
            let camera = camera(settings, eye, target, Vec3::Z, 0)?;
            let views = vec![
                View { variant: surface.name(), camera, light: side, target, material: Material::default() },
                View { variant: surface.specular_name(), camera, light: mirror, target, material: SPECULAR },
            ];
            cases.push(Case { sweep: Sweep::NonGaussian, parameter: sigma, source: Arc::new(map), views });
        }
    }
    Ok(cases)
}

/// Grazing views: the Gaussian [`height_map`] of RMS height
/// [`StabilitySettings::bump_amplitude`] `S₀` (feature size
/// [`StabilitySettings::feature_voxels`], coloured by height), one case per angle `θ` of
/// [`StabilitySettings::view_angle_deg`]: the eye at distance 0.9 from the origin, `θ` off
/// the normal (inside the domain, so that no ray enters through a side face below the
/// surface), with the wide field of view [`GRAZING_FOV_Y`], the light 40° off the normal
/// on the other side. (A height map rather than `svo_scenes::Displaced`: its exact vertex
/// samples build the octree some 40 times faster than the thin-shell samples of a
/// displaced surface.)
pub fn grazing(settings: &StabilitySettings) -> Result<Vec<Case>, RenderError> {
    let voxel = finest_voxel(settings.levels);
    let bumps: SharedSource = Arc::new(height_map(MicroSurface::Gaussian, settings, settings.bump_amplitude * voxel)?);
    let target = Vec3::ZERO;
    let lit = light(target, Vec3::new(40f32.to_radians().sin(), 0.0, 40f32.to_radians().cos()));
    settings
        .view_angle_deg
        .iter()
        .enumerate()
        .map(|(i, &angle)| {
            let theta = angle.to_radians();
            let direction = Vec3::new(-theta.sin(), 0.0, theta.cos());
            // Up: the plane's normal, or y when looking straight down.
            let up = if angle.abs() < 1.0 { Vec3::Y } else { Vec3::Z };
            let eye = target + direction * 0.9;
            let camera = wide_camera(settings, eye, target, up, i as u32, GRAZING_FOV_Y)?;
            let view = View { variant: "bumpy-plane", camera, light: lit, target, material: Material::default() };
            Ok(Case { sweep: Sweep::Grazing, parameter: angle, source: Arc::clone(&bumps), views: vec![view] })
        })
        .collect()
}
