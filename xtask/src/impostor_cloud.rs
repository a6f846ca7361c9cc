//! `cargo xtask impostor-cloud [OUT_DIR] [--obj PATH | --grain ball|bean|rock|nut] [--n N]
//! [--p P] [--mode planar|spherical|mixed|mixed-smooth] [--grains COUNT]`: bakes any grain (an OBJ file or
//! a procedural one) into an octahedral impostor atlas and renders a pile of randomly turned
//! copies as an impostor cloud, next to the mesh rendered with the same shading; writes the
//! atlas file, both renders side by side, and prints SSIM, RMSE and times.

use std::path::PathBuf;
use std::time::Instant;

use glam::{Quat, Vec3};
use grain_impostor::accuracy::{
    AccuracySweep, ComparisonScene, compare_images, sampling_mode_from_name, sampling_mode_name,
};
use grain_impostor::atlas_file::save_atlas;
use grain_impostor::atlas_gpu::AtlasTextures;
use grain_impostor::bake::{BakeSettings, Baker};
use grain_impostor::scene::{CameraUniforms, GrainInstance};
use grain_mesh::{Ball, CoffeeBean, GrainMesh, HexNut, SandGrain, load_obj};
use octahedral_map::SamplingMode;
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

use crate::cli::{Args, positive};

/// A pile of `count` grains of outer radius `radius`: layers of a jittered square grid, each
/// grain turned at random and scaled by 0.8–1.0, seen from above at an angle.
fn pile_scene(count: u32, radius: f32, size: (u32, u32)) -> Option<ComparisonScene> {
    let side = ((count as f32 / 2.0).sqrt().ceil() as u32).max(1);
    let spacing = 2.1 * radius;
    let mut rng = SmallRng::seed_from_u64(0x5eed);
    let mut random = || rng.random::<f32>();
    let mut instances = Vec::new();
    let mut directions = Vec::new();
    let extent = side as f32 * spacing;
    let eye = Vec3::new(0.0, -1.1 * extent, 0.9 * extent);
    'grid: for layer in 0..2 {
        for row in 0..side {
            for column in 0..side {
                if instances.len() as u32 == count {
                    break 'grid;
                }
                let jitter = Vec3::new(random() - 0.5, random() - 0.5, 0.0) * 0.1 * radius;
                let offset = if layer == 1 { 0.5 * spacing } else { 0.0 };
                let centre = Vec3::new(
                    (column as f32 - 0.5 * (side - 1) as f32) * spacing + offset,
                    (row as f32 - 0.5 * (side - 1) as f32) * spacing + offset,
                    layer as f32 * 1.5 * radius,
                ) + jitter;
                let axis = Vec3::new(random() - 0.5, random() - 0.5, random() - 0.5);
                let rotation =
                    Quat::from_axis_angle(axis.try_normalize().unwrap_or(Vec3::Z), std::f32::consts::TAU * random());
                let scale = 0.8 + 0.2 * random();
                instances.push(GrainInstance::new(centre, scale, rotation));
                directions.push(rotation.inverse() * (eye - centre).normalize());
            }
        }
    }
    let camera = CameraUniforms::perspective(eye, Vec3::ZERO, Vec3::Z, 0.6, size, (0.1 * extent, 4.0 * extent))?;
    let apparent_diameter = 2.0 * radius / (eye.length() * (0.3_f32).tan()) * size.1 as f32 * 0.5;
    Some(ComparisonScene { camera, instances, local_directions_to_eye: directions, size, apparent_diameter })
}

/// The procedural grains `--grain` names.
pub const GRAINS: [&str; 4] = ["ball", "bean", "rock", "nut"];

/// The command's settings.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// Where the files go.
    pub out: PathBuf,
    /// A grain from an OBJ file, else the procedural `grain`.
    pub obj: Option<PathBuf>,
    /// One of [`GRAINS`] (`bean` by default).
    pub grain: &'static str,
    /// Views per hemisphere edge (`--n`, 8 by default).
    pub n: u32,
    /// Texels per view (`--p`, 64 by default).
    pub p: u32,
    /// The sampling mode (`--mode`, mixed by default).
    pub mode: SamplingMode,
    /// Grains in the pile (`--grains`, 400 by default).
    pub count: u32,
}

impl Options {
    /// `[OUT_DIR] [--obj PATH | --grain NAME] [--n N] [--p P] [--mode MODE] [--grains COUNT]`.
    pub fn from_args(args: &Args<'_>) -> Result<Self, String> {
        let grain = |name: &str| {
            GRAINS.into_iter().find(|g| *g == name).ok_or_else(|| format!("expected one of {}", GRAINS.join(", ")))
        };
        let mode = |name: &str| {
            sampling_mode_from_name(name).ok_or_else(|| {
                let names: Vec<_> = SamplingMode::ALL.into_iter().map(sampling_mode_name).collect();
                format!("expected one of {}", names.join(", "))
            })
        };
        Ok(Self {
            out: args.out_dir(),
            obj: args.value("obj").map(PathBuf::from),
            grain: args.parse_value("grain", grain)?.unwrap_or("bean"),
            n: args.parse_value("n", positive)?.unwrap_or(8),
            p: args.parse_value("p", positive)?.unwrap_or(64),
            mode: args.parse_value("mode", mode)?.unwrap_or(SamplingMode::Mixed),
            count: args.parse_value("grains", positive)?.unwrap_or(400),
        })
    }
}

/// The grain of `--obj PATH` (named by the file stem) or of the procedural `grain`.
pub fn load_grain(obj: Option<&std::path::Path>, grain: &str) -> Result<(String, GrainMesh), String> {
    match obj {
        Some(path) => Ok((
            path.file_stem().map_or_else(|| "grain".into(), |s| s.to_string_lossy().into_owned()),
            load_obj(path).map_err(|e| e.to_string())?,
        )),
        None => {
            let mesh = match grain {
                "ball" => Ball::default().mesh(),
                "bean" => CoffeeBean::default().mesh(),
                "rock" => SandGrain::default().mesh(),
                "nut" => HexNut::default().mesh(),
                other => return Err(format!("unknown grain {other}: use ball, bean, rock, nut or --obj PATH")),
            };
            Ok((grain.to_owned(), mesh.map_err(|e| e.to_string())?))
        }
    }
}

/// Runs the command.
pub fn run(args: &Args<'_>) -> Result<(), String> {
    let Options { out, obj, grain, n, p, mode, count } = Options::from_args(args)?;
    let (name, mesh) = load_grain(obj.as_deref(), grain)?;
    std::fs::create_dir_all(&out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let gpu = gpu_harness::Gpu::new().map_err(|e| e.to_string())?;
    println!("impostor cloud of `{name}` on {}", gpu.describe());
    let bounds = mesh.bounds();
    println!("{} triangles, r = {:.4}, R = {:.4}", mesh.triangles().len(), bounds.inner_radius, bounds.outer_radius);
    let (device, queue) = (&gpu.device, &gpu.queue);
    let start = Instant::now();
    let baker = Baker::new(device).map_err(|e| e.to_string())?;
    let atlas = baker.bake(device, queue, &mesh, &BakeSettings::new(n, p)).map_err(|e| e.to_string())?;
    let memory = atlas.memory();
    println!(
        "baked n = {n} ({} views), p = {p} in {:.2} s (wall clock): {:.2} MiB on the GPU",
        atlas.layer_count(),
        start.elapsed().as_secs_f64(),
        memory.gpu_bytes as f64 / 1048576.0
    );
    let atlas_path = out.join(format!("{name}_n{n}_p{p}.atlas"));
    save_atlas(&atlas, &atlas_path).map_err(|e| e.to_string())?;
    println!("wrote {}", atlas_path.display());
    let scene = pile_scene(count, bounds.outer_radius, (960, 640)).ok_or("cannot build the pile's camera")?;
    let sweep = AccuracySweep::new(device).map_err(|e| e.to_string())?;
    let textures = AtlasTextures::upload(device, queue, &atlas).map_err(|e| e.to_string())?;
    let start = Instant::now();
    let impostor = sweep.impostor(device, queue, &atlas, &textures, &scene, mode).map_err(|e| e.to_string())?;
    let impostor_seconds = start.elapsed().as_secs_f64();
    let start = Instant::now();
    let reference = sweep.reference(device, queue, &mesh, &scene).map_err(|e| e.to_string())?;
    let reference_seconds = start.elapsed().as_secs_f64();
    let error = compare_images(&reference, &impostor).map_err(|e| e.to_string())?;
    println!(
        "{} grains ≈ {:.0} px wide: impostor cloud {:.3} s, mesh (4×4 supersampled) {:.3} s, wall clock with readback",
        scene.instances.len(),
        scene.apparent_diameter,
        impostor_seconds,
        reference_seconds
    );
    println!("SSIM {:.4}, RMSE {:.4} (impostor against mesh)", error.ssim, error.rmse);
    let mut pair = image::RgbaImage::new(2 * scene.size.0, scene.size.1);
    image::imageops::replace(&mut pair, &reference, 0, 0);
    image::imageops::replace(&mut pair, &impostor, i64::from(scene.size.0), 0);
    let path = out.join(format!("{name}_cloud_mesh_vs_impostor.png"));
    pair.save(&path).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    println!("wrote {} (left: mesh, right: impostor)", path.display());
    Ok(())
}
