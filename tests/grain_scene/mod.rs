//! The scene both grain-renderer GPU test binaries draw (`grain_renderer_gpu`,
//! `grain_frame_gpu`): a jittered pile of grains with a baked atlas, and the renders they
//! compare (the impostor cloud, the splitter and tier in one submission).
// Each binary uses a part of this scaffolding.
#![allow(dead_code)]

use glam::{Quat, Vec3, Vec4};
use grain_impostor::atlas::ImpostorAtlas;
use grain_impostor::atlas_gpu::AtlasTextures;
use grain_impostor::bake::{BakeSettings, Baker, Progress};
use grain_impostor::cloud::{AtlasBinding, CloudFrame, CloudSettings, GBufferBinding, ImpostorCloudPass};
use grain_impostor::mesh_gbuffer::{GbufferImage, ScreenGbuffer};
use grain_impostor::scene::{CameraUniforms, GrainInstance};
use grain_renderer::ListInputs;
use grain_renderer::impostor_tier::TIER_STATS;
use grain_renderer::{ImpostorTier, TierFrame, TierSettings, VisibilityKind};
use grain_splitter::{
    GrainSplitter, ListOrder, OccluderMapKind, SplitCamera, SplitSettings, SplitterOptions, TierThresholds,
};
use integration_tests::gpu;
use octahedral_map::{ImpostorSampler, SamplingMode, ViewSelection};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use wgpu::util::DeviceExt;

pub const SIZE: (u32, u32) = (192, 144);

pub struct Scene {
    pub atlas: ImpostorAtlas,
    pub textures: AtlasTextures,
    pub mesh: grain_mesh::GrainMesh,
    pub grains: Vec<GrainInstance>,
    pub eye: Vec3,
    pub target: Vec3,
}

/// A jittered pile of `n³` grains of `mesh` with random orientations and scales, outer balls
/// overlapping (spacing 1.6 R), so that grains occlude each other.
pub fn scene(n: u32, mesh: grain_mesh::GrainMesh) -> Scene {
    scene_with_atlas(n, mesh, (4, 32))
}

/// [`scene`] with an atlas of `views × views` views of `texels` texels a side.
pub fn scene_with_atlas(n: u32, mesh: grain_mesh::GrainMesh, (views, texels): (u32, u32)) -> Scene {
    let gpu = gpu();
    let settings = BakeSettings { progress: Progress::Hidden, ..BakeSettings::new(views, texels) };
    let atlas = Baker::new(&gpu.device).unwrap().bake(&gpu.device, &gpu.queue, &mesh, &settings).unwrap();
    let textures = AtlasTextures::upload(&gpu.device, &gpu.queue, &atlas).unwrap();
    let outer = atlas.outer_radius;
    let mut rng = SmallRng::seed_from_u64(21);
    let mut grains = Vec::new();
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let site = Vec3::new(x as f32, y as f32, z as f32) * 1.6 * outer;
                let jitter = Vec3::new(rng.random(), rng.random(), rng.random()) * 0.4 * outer;
                let axis = Vec3::new(rng.random(), rng.random(), rng.random()) * 2.0 - Vec3::ONE;
                let rotation =
                    Quat::from_axis_angle(axis.normalize_or(Vec3::X), rng.random_range(0.0..std::f32::consts::TAU));
                grains.push(GrainInstance::new(site + jitter, rng.random_range(0.85..1.15), rotation));
            }
        }
    }
    let centre = Vec3::splat((n - 1) as f32 * 0.8 * outer);
    Scene {
        atlas,
        textures,
        mesh,
        grains,
        eye: centre + Vec3::new(0.4, 0.7, 1.0).normalize() * 3.2 * n as f32 * outer,
        target: centre,
    }
}

impl Scene {
    pub fn camera(&self) -> CameraUniforms {
        CameraUniforms::perspective(self.eye, self.target, Vec3::Y, 0.7, SIZE, (0.05, 500.0)).unwrap()
    }

    pub fn split_camera(&self) -> SplitCamera {
        SplitCamera::perspective(self.eye, self.target, Vec3::Y, 0.7, SIZE, (0.05, 500.0)).unwrap()
    }

    pub fn sampler(&self) -> ImpostorSampler {
        let a = &self.atlas;
        ImpostorSampler::new(
            a.views,
            a.outer_radius,
            a.inner_radius,
            SamplingMode::Mixed,
            a.layout,
            ViewSelection::PerGrainFromEye,
        )
        .unwrap()
    }

    pub fn binding(&self) -> AtlasBinding<'_> {
        AtlasBinding {
            normal_alpha: &self.textures.views[0],
            albedo_alpha: &self.textures.views[1],
            material_alpha: &self.textures.views[2],
            depth_alpha: &self.textures.views[3],
            sampler: &self.textures.sampler,
            texels: self.atlas.texels,
            layers: self.atlas.layer_count(),
        }
    }

    pub fn instances(&self) -> wgpu::Buffer {
        gpu().device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("grains"),
            contents: bytemuck::cast_slice(&self.grains),
            usage: wgpu::BufferUsages::STORAGE,
        })
    }
}

pub fn gbuffer_binding(target: &ScreenGbuffer) -> GBufferBinding<'_> {
    GBufferBinding {
        normal_coverage: &target.views[0],
        albedo: &target.views[1],
        material: &target.views[2],
        depth: &target.views[3],
    }
}

/// Every grain through the impostor cloud.
pub fn cloud_render(scene: &Scene) -> GbufferImage {
    let gpu = gpu();
    let pass = ImpostorCloudPass::new(&gpu.device).unwrap();
    let target = ScreenGbuffer::new(&gpu.device, SIZE).unwrap();
    let instances = scene.instances();
    let camera = scene.camera();
    let frame = CloudFrame {
        camera: &camera,
        sampling: scene.sampler().uniforms(),
        instances: &instances,
        grain_count: scene.grains.len() as u32,
        settings: CloudSettings::default(),
    };
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    pass.encode(&gpu.device, &mut encoder, &frame, &scene.binding(), &gbuffer_binding(&target), None).unwrap();
    gpu.queue.submit([encoder.finish()]);
    target.read(&gpu.device, &gpu.queue).unwrap()
}

/// The splitter (every grain an impostor; culling as `culling`), then the tier, in one
/// submission; the G-buffer `target` (read back) and the tier's counters.
pub fn tier_render(
    scene: &Scene,
    kind: VisibilityKind,
    settings: TierSettings,
    culling: bool,
    target: &ScreenGbuffer,
) -> (GbufferImage, [u32; TIER_STATS as usize], [u32; 4]) {
    let (image, stats, culled, _) =
        tier_render_with(scene, kind, settings, culling, TierThresholds::new(1e-3, 1e6, 1.0).unwrap(), target);
    (image, stats, culled)
}

/// [`tier_render`] with `thresholds`, also returning the point tier's sums.
pub fn tier_render_with(
    scene: &Scene,
    kind: VisibilityKind,
    settings: TierSettings,
    culling: bool,
    thresholds: TierThresholds,
    target: &ScreenGbuffer,
) -> (GbufferImage, [u32; TIER_STATS as usize], [u32; 4], Vec<u32>) {
    tier_render_sampled(scene, kind, settings, culling, thresholds, 1, target)
}

/// [`tier_render_with`] with `samples × samples` visibility samples per pixel.
pub fn tier_render_sampled(
    scene: &Scene,
    kind: VisibilityKind,
    settings: TierSettings,
    culling: bool,
    thresholds: TierThresholds,
    samples: u32,
    target: &ScreenGbuffer,
) -> (GbufferImage, [u32; TIER_STATS as usize], [u32; 4], Vec<u32>) {
    let gpu = gpu();
    let n = scene.grains.len() as u32;
    let bounds = scene.mesh.bounds();
    let split_settings = SplitSettings {
        frustum_culling: culling,
        cone_culling: culling,
        hiz_culling: culling,
        ..SplitSettings::new(bounds.occluder_radius(), scene.atlas.outer_radius, thresholds)
    };
    let options =
        SplitterOptions { capacity: n, size: SIZE, occluder_map: OccluderMapKind::Auto, order: ListOrder::Atomic };
    let splitter = GrainSplitter::new(&gpu.device, split_settings, options).unwrap();
    let centres: Vec<Vec4> = scene.grains.iter().map(|g| g.centre_scale).collect();
    let centre_buffer = GrainSplitter::upload_grains(&gpu.device, &centres).unwrap();
    let split_bindings = splitter.bind(&gpu.device, &centre_buffer).unwrap();
    let tier = ImpostorTier::with_samples(&gpu.device, SIZE, kind, samples).unwrap();
    let instances = scene.instances();
    let inputs = ListInputs {
        instances: &instances,
        elements: splitter.elements(),
        counters: splitter.counters(),
        indirect: splitter.indirect(),
    };
    let atlas = scene.binding();
    let bindings = tier.bind(&gpu.device, &inputs, &atlas, &gbuffer_binding(target)).unwrap();
    let camera = scene.camera();
    let frame = TierFrame { camera: &camera, sampling: scene.sampler().uniforms(), instance_count: n, settings };
    let mut encoder = gpu.device.create_command_encoder(&Default::default());
    splitter.encode(&gpu.queue, &mut encoder, &split_bindings, &scene.split_camera(), n, None).unwrap();
    tier.encode(&gpu.queue, &mut encoder, &bindings, &frame, &atlas).unwrap();
    gpu.queue.submit([encoder.finish()]);
    let stats: [u32; TIER_STATS as usize] =
        bytemuck::pod_read_unaligned(&gpu.read_buffer(tier.stats(), u64::from(TIER_STATS) * 4).unwrap());
    let counters: grain_splitter::SplitCounters =
        bytemuck::pod_read_unaligned(&gpu.read_buffer(splitter.counters(), 64).unwrap());
    let sums_bytes = u64::from(SIZE.0 * SIZE.1 * grain_renderer::impostor_tier::TIER_POINT_SUMS) * 4;
    let sums = bytemuck::pod_collect_to_vec(&gpu.read_buffer(tier.point_sums(), sums_bytes).unwrap());
    (target.read(&gpu.device, &gpu.queue).unwrap(), stats, counters.culled, sums)
}

pub fn kinds() -> Vec<VisibilityKind> {
    let mut kinds = vec![VisibilityKind::TwoPass32];
    if ImpostorTier::supports_atomic64(&gpu().device) {
        kinds.push(VisibilityKind::Atomic64);
    }
    kinds
}

pub fn covered(image: &GbufferImage) -> usize {
    image.normal_coverage.iter().filter(|n| n.w > 0.0).count()
}

impl Scene {
    /// Every `step`-th grain placed by its centre as the atlas is: the mesh's bounds centre
    /// moved onto the grain centre (the instances the mesh pass draws).
    pub fn mesh_placed(&self, step: usize) -> Vec<GrainInstance> {
        let centre = self.mesh.bounds().centre;
        self.grains
            .iter()
            .step_by(step)
            .map(|g| {
                let rotation = Quat::from_vec4(g.rotation);
                GrainInstance::new(
                    g.centre_scale.truncate() - rotation * (g.centre_scale.w * centre),
                    g.centre_scale.w,
                    rotation,
                )
            })
            .collect()
    }
}
