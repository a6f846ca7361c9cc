//! `cargo xtask stackings [OUT_DIR] [--grains COUNT] [--frames K] [--obj PATH | --grain NAME]
//! [--mix NAME] [--mesh-above PX] [--point-below PX] [--shake | --accuracy] [--samples S] [--quick]`: the multiscale renderer (`grain-renderer`) on a pile
//! from `grain-scenes` — a backward dolly from a close view to the whole pile (paper Fig. 9),
//! with `--shake` every grain moving and turning each frame (`grain_scenes::Shake`, uploaded
//! per frame) — written as PNG frames, with the per-stage breakdown printed and written to
//! `stackings.csv` (GPU timestamps on a GPU, wall clock on a software adapter).
//!
//! The mesh threshold is the measured impostor table's (`TierThresholds::from_impostor_table`,
//! SSIM loss ≤ 0.05) for the procedural grains; an OBJ grain has no measured table, so
//! `--mesh-above` must say it (pixels of projected diameter). The point threshold is the
//! committed tier table's for a procedural grain (`grain_renderer::tier_selection`: the
//! largest diameter up to which points measure ꟻLIP ≤ 0.1 against the meshes; `cargo xtask
//! select-tables --only tiers` measures it), measured on the pile itself before the dolly for an OBJ grain, unless `--point-below`
//! gives it.
//!
//! With `--accuracy` the dolly runs again with a fresh renderer, each frame against every
//! grain as a mesh 4×4 supersampled (`grain_renderer::frame_accuracy`): standard SSIM, ꟻLIP,
//! mean error and popping per frame in `accuracy.csv`, the reference and the ꟻLIP map as
//! `reference_KK.png` and `flip_KK.png`. `--samples S` gives the impostor and point tiers
//! `S × S` visibility samples per pixel (fractional silhouettes; 1 by default). `--mix NAME`
//! makes every other grain a second procedural type (`grain_renderer::GrainType`: its own
//! atlas, measured mesh threshold and point threshold, scaled to the pile's outer radius; the
//! pile's inner radius is the larger `r/R`, so every type's inner balls stay disjoint). `COUNT` may be a paper size (`1.6M`, `20M`); a count
//! whose buffers exceed the adapter's limits is an error naming the limit.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use glam::{Quat, Vec3};
use grain_impostor::atlas::ImpostorAtlas;
use grain_impostor::bake::{BakeSettings, Baker, Progress};
use grain_impostor::scene::{GrainInstance, ShadingUniforms};
use grain_renderer::bench::time_frame;
use grain_renderer::point_threshold::MeasureView;
use grain_renderer::renderer::NO_POINT_TIER;
use grain_renderer::tier_selection;
use grain_renderer::{
    GrainType, RendererOptions, StackingCamera, StackingRenderer, Stage, TierSettings, VisibilityKind,
};
use grain_scenes::{GrainRadii, Region, Stacking, StackingSpec};
use grain_splitter::sweep::Shot;
use grain_splitter::{OccluderMapKind, TierThresholds};
use model_select::{Budget, Metric};

use crate::cli::{Args, positive};
use crate::impostor_cloud::{GRAINS, load_grain};

/// The command's settings.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    out: PathBuf,
    obj: Option<PathBuf>,
    grain: &'static str,
    mix: Option<&'static str>,
    count: usize,
    frames: u32,
    mesh_above: Option<f32>,
    point_below: Option<f32>,
    shake: bool,
    accuracy: bool,
    samples: u32,
    size: (u32, u32),
}

impl Options {
    fn from_args(args: &Args<'_>) -> Result<Self, String> {
        let quick = args.flag("quick");
        let grain = |name: &str| {
            GRAINS.into_iter().find(|g| *g == name).ok_or_else(|| format!("expected one of {}", GRAINS.join(", ")))
        };
        Ok(Self {
            out: args.out_dir(),
            obj: args.value("obj").map(PathBuf::from),
            grain: args.parse_value("grain", grain)?.unwrap_or("bean"),
            mix: args.parse_value("mix", grain)?,
            count: args.parse_value("grains", crate::bench_gpu::grain_count)?.unwrap_or(if quick {
                5_000
            } else {
                20_000
            }),
            frames: args.parse_value("frames", positive::<u32>)?.unwrap_or(if quick { 3 } else { 6 }),
            mesh_above: args.parse_value("mesh-above", pixels)?,
            point_below: args.parse_value("point-below", pixels)?,
            shake: args.flag("shake"),
            accuracy: args.flag("accuracy"),
            samples: args.parse_value("samples", samples_per_side)?.unwrap_or(1),
            size: if quick { (480, 270) } else { (960, 540) },
        })
    }
}

/// A pile of `count` grains whose inner balls are disjoint (spacing over the outer diameter
/// at least `r/R` over the jitter's margin).
pub(crate) fn pile(count: usize, inner: f32, outer: f32) -> Result<Stacking, String> {
    pile_spaced(count, inner, outer, pile_spacing(inner, outer))
}

/// The pile's lattice spacing: 0.85, or tighter only as far as the inner balls allow.
fn pile_spacing(inner: f32, outer: f32) -> f32 {
    (1.02 * inner / outer / (1.0 - 2.0 * PILE_JITTER)).max(0.85)
}

/// The pile's position jitter (`grain_scenes::StackingSpec::jitter`).
pub(crate) const PILE_JITTER: f32 = 0.05;

/// [`pile`] with its lattice spacing given (`grain_scenes::StackingSpec::spacing`).
pub(crate) fn pile_spaced(count: usize, inner: f32, outer: f32, spacing: f32) -> Result<Stacking, String> {
    let mut spec = StackingSpec::new(count, GrainRadii::new(inner, outer).map_err(|e| e.to_string())?);
    spec.seed = 9;
    spec.region = Region::Pile { slope: 0.6 };
    spec.scale_jitter = 0.1;
    spec.jitter = PILE_JITTER;
    spec.spacing = spacing;
    Stacking::generate(&spec).map_err(|e| e.to_string())
}

/// The diameters (pixels) at which the point threshold is measured.
const POINT_DIAMETERS: [f32; 5] = [1.0, 1.5, 2.0, 3.0, 4.0];
/// The point tier's budget: mean ꟻLIP of the pile against its meshes 4 × 4 supersampled
/// (the tier table's; both tiers measure 0.055 to 0.14 there between 1 and 4 px).
const POINT_BUDGET: f64 = 0.1;

/// How much nearer than the foreground shot the dolly starts (its first frame shows grains
/// above the mesh threshold).
const CLOSE_UP: f32 = 0.45;

/// Frame `k` of `frames`: from a close-up (the foreground shot's direction at [`CLOSE_UP`]
/// of its distance) back to the wide shot, the distance to the target growing geometrically.
pub(crate) fn dolly(shots: &[Shot; 3], k: u32, frames: u32, size: (u32, u32)) -> Result<StackingCamera, String> {
    let [wide, _, close] = shots;
    let t = if frames > 1 { k as f32 / (frames - 1) as f32 } else { 1.0 };
    let target = close.target.lerp(wide.target, t);
    let (d0, d1) = (CLOSE_UP * (close.eye - close.target).length(), (wide.eye - wide.target).length());
    let direction = (close.eye - close.target).normalize().lerp((wide.eye - wide.target).normalize(), t).normalize();
    let distance = d0 * (d1 / d0).powf(t);
    let fov = close.fov_y + (wide.fov_y - close.fov_y) * t;
    let far = 4.0 * (distance + (wide.eye - wide.target).length());
    StackingCamera::perspective(target + direction * distance, target, fov, size, (1e-3 * distance, far))
        .map_err(|e| e.to_string())
}

/// A pile of `count` grains of `mesh` ([`pile`]) and its instances.
pub(crate) fn pile_instances(
    count: usize,
    mesh: &grain_mesh::GrainMesh,
) -> Result<(Stacking, Vec<GrainInstance>), String> {
    let bounds = mesh.bounds();
    let inner = bounds.occluder_radius().max(1e-6 * bounds.outer_radius);
    pile_instances_spaced(count, mesh, pile_spacing(inner, bounds.outer_radius))
}

/// [`pile_instances`] with the lattice spacing given.
pub(crate) fn pile_instances_spaced(
    count: usize,
    mesh: &grain_mesh::GrainMesh,
    spacing: f32,
) -> Result<(Stacking, Vec<GrainInstance>), String> {
    let bounds = mesh.bounds();
    let (inner, outer) = (bounds.occluder_radius(), bounds.outer_radius);
    let stacking = pile_spaced(count, inner.max(1e-6 * outer), outer, spacing)?;
    let grains = instances(&stacking, 0..stacking.len(), 1.0);
    Ok((stacking, grains))
}

/// The grain's atlas (n = 8, p = 64).
pub(crate) fn bake_atlas(gpu: &gpu_harness::Gpu, mesh: &grain_mesh::GrainMesh) -> Result<ImpostorAtlas, String> {
    let settings = BakeSettings { progress: Progress::Hidden, ..BakeSettings::new(8, 64) };
    let baker = Baker::new(&gpu.device).map_err(|e| e.to_string())?;
    baker.bake(&gpu.device, &gpu.queue, mesh, &settings).map_err(|e| e.to_string())
}

/// The mesh threshold (pixels of projected diameter): `given` (`--mesh-above`), else the
/// measured impostor table's for a procedural grain (SSIM loss ≤ 0.05); an OBJ grain has no
/// measured table, so it must be given.
pub(crate) fn mesh_threshold(given: Option<f32>, obj: Option<&Path>, name: &str) -> Result<f32, String> {
    match (given, obj) {
        (Some(pixels), _) => Ok(pixels),
        (None, Some(path)) => Err(format!(
            "{}: no measured impostor table for an OBJ grain; give its mesh threshold with --mesh-above PX",
            path.display()
        )),
        (None, None) => {
            let rows = grain_impostor::choice::measured_accuracy()?;
            Ok(TierThresholds::from_impostor_table(&rows, name, 0.05, NO_POINT_TIER, 1.1)
                .map_err(|e| e.to_string())?
                .mesh_above())
        }
    }
}

/// Visibility samples per pixel side (`--samples`): 1 to `TIER_MAX_SAMPLES`.
pub(crate) fn samples_per_side(text: &str) -> Result<u32, String> {
    let max = grain_renderer::tier_layout::TIER_MAX_SAMPLES;
    text.parse::<u32>()
        .ok()
        .filter(|s| (1..=max).contains(s))
        .ok_or_else(|| format!("`{text}` is not a number of samples per pixel side from 1 to {max}"))
}

/// A positive number of pixels (`--mesh-above`).
pub(crate) fn pixels(text: &str) -> Result<f32, String> {
    text.parse::<f32>()
        .ok()
        .filter(|v| v.is_finite() && *v > 0.0)
        .ok_or_else(|| format!("`{text}` is not a positive number of pixels"))
}

fn write(path: &Path, text: &str) -> Result<(), String> {
    std::fs::write(path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// One grain type of the pile: every `types`-th grain from `first`, scaled so that its outer
/// radius is the pile's.
struct PileType {
    name: String,
    mesh: grain_mesh::GrainMesh,
    atlas: ImpostorAtlas,
    mesh_above: f32,
    point_below: f32,
    /// The pile's outer radius over this mesh's.
    scale: f32,
    grains: Vec<GrainInstance>,
}

/// The grains of `stacking` at `indices`, scaled by `scale`.
fn instances(stacking: &Stacking, indices: impl Iterator<Item = usize>, scale: f32) -> Vec<GrainInstance> {
    let (centres, rotations) = (stacking.centre_scale(), stacking.rotation());
    indices
        .map(|i| GrainInstance::new(centres[i].truncate(), centres[i].w * scale, Quat::from_vec4(rotations[i])))
        .collect()
}

/// The point threshold of grain type `name` (pixels of projected diameter;
/// `grain_renderer::tier_selection::point_threshold`: ꟻLIP ≤ [`POINT_BUDGET`]), its rows
/// printed: a procedural grain's from the committed tier table
/// (an error when it is stale), an OBJ grain's measured on `stacking` made all of it
/// (`mesh`, `atlas`, scaled by `scale`) from the wide shot.
#[allow(clippy::too_many_arguments)]
fn point_threshold(
    gpu: &gpu_harness::Gpu,
    options: &Options,
    stacking: &Stacking,
    shots: &[Shot; 3],
    (name, mesh, atlas): (&str, &grain_mesh::GrainMesh, &ImpostorAtlas),
    scale: f32,
) -> Result<f32, String> {
    let (rows, source) = if options.obj.is_none() {
        let selector = crate::select::selector("tiers").ok_or("the tier table has no selector")?;
        let table = crate::select::fresh_table(selector)?;
        let rows: Vec<_> = table.rows().iter().filter(|r| r.object == name).cloned().collect();
        (rows, format!("{} (commit {})", selector.table_file, table.stamp().commit))
    } else {
        let whole = instances(stacking, 0..stacking.len(), scale);
        let view = MeasureView {
            target: shots[0].target,
            direction: shots[0].eye - shots[0].target,
            size: options.size,
            frames: 1,
        };
        let measured = grain_renderer::point_threshold::measure(gpu, mesh, atlas, &whole, view, &POINT_DIAMETERS)
            .map_err(|e| e.to_string())?;
        (tier_selection::measurements(name, &measured), "measured on the pile".to_owned())
    };
    for pair in rows.chunks(2) {
        let line: Vec<String> = pair
            .iter()
            .map(|r| format!("{} ꟻLIP {:.4}, SSIM loss {:.4}, {:.2} ms", r.representation, r.flip, r.ssim_loss, r.cost))
            .collect();
        println!("  against the mesh (4×4 supersampled), worst up to {:.1} px: {}", pair[0].condition, line.join("; "));
    }
    let budget = Budget::new(Metric::Flip, POINT_BUDGET).map_err(|e| e.to_string())?;
    let threshold = tier_selection::point_threshold(&rows, name, budget).map_err(|e| e.to_string())?;
    println!("  point threshold: {threshold:?} px (points' ꟻLIP ≤ {POINT_BUDGET}; {source})");
    Ok(threshold.unwrap_or(NO_POINT_TIER))
}

/// Runs the command.
pub fn run(args: &Args<'_>) -> Result<(), String> {
    let options = Options::from_args(args)?;
    if options.accuracy && options.mix.is_some() {
        return Err("stackings: --accuracy compares one grain type with its meshes, not a --mix scene".into());
    }
    let mut loaded = vec![load_grain(options.obj.as_deref(), options.grain)?];
    if let Some(mix) = options.mix {
        loaded.push(load_grain(None, mix)?);
    }
    std::fs::create_dir_all(&options.out).map_err(|e| format!("cannot create {}: {e}", options.out.display()))?;
    let gpu = gpu_harness::Gpu::new().map_err(|e| e.to_string())?;
    let outer = loaded[0].1.bounds().outer_radius;
    // Inner balls stay disjoint for every type: the pile's inner radius is the largest r/R.
    let ratio = loaded.iter().map(|(_, m)| m.bounds().occluder_radius() / m.bounds().outer_radius).fold(0.0, f32::max);
    let started = Instant::now();
    let stacking = pile(options.count, (ratio * outer).max(1e-6 * outer), outer)?;
    let region = stacking.bounds();
    let shots = Shot::fig15(region.min, region.max);
    let mut types = Vec::new();
    for (k, (name, mesh)) in loaded.into_iter().enumerate() {
        let mesh_above = mesh_threshold(
            if k == 0 { options.mesh_above } else { None },
            options.obj.as_deref().filter(|_| k == 0),
            &name,
        )?;
        let scale = outer / mesh.bounds().outer_radius;
        let atlas = bake_atlas(&gpu, &mesh)?;
        println!(
            "stackings: `{name}` (r/R = {:.2}), meshes above {mesh_above:.1} px",
            mesh.bounds().occluder_radius() / mesh.bounds().outer_radius
        );
        let point_below = match options.point_below {
            Some(given) => {
                println!("  point threshold: {given} px (given)");
                given
            }
            None => point_threshold(&gpu, &options, &stacking, &shots, (&name, &mesh, &atlas), scale)?,
        };
        types.push(PileType { name, mesh, atlas, mesh_above, point_below, scale, grains: Vec::new() });
    }
    let count = types.len();
    for (k, t) in types.iter_mut().enumerate() {
        t.grains = instances(&stacking, (k..stacking.len()).step_by(count), t.scale);
    }
    println!(
        "stackings: {} grains ({}), {}×{}, {} frames, on {}; scene, atlases and point thresholds in {:.1} s",
        stacking.len(),
        types.iter().map(|t| format!("{} {}", t.grains.len(), t.name)).collect::<Vec<_>>().join(", "),
        options.size.0,
        options.size.1,
        options.frames,
        gpu.describe(),
        started.elapsed().as_secs_f64()
    );
    let renderer_options = RendererOptions {
        size: options.size,
        capacity: types.iter().map(|t| t.grains.len() as u32).max().unwrap_or(1),
        mesh_above: types[0].mesh_above,
        point_below: types[0].point_below,
        band: 1.1,
        occluder_map: OccluderMapKind::Auto,
        visibility: VisibilityKind::Auto,
        culling: true,
        samples: options.samples,
    };
    let grain_types: Vec<GrainType<'_>> = types
        .iter()
        .map(|t| GrainType { mesh: &t.mesh, atlas: &t.atlas, mesh_above: t.mesh_above, point_below: t.point_below })
        .collect();
    let renderer = StackingRenderer::with_types(&gpu.device, &gpu.queue, &grain_types, renderer_options)
        .map_err(|e| e.to_string())?;
    let per_type: Vec<&[GrainInstance]> = types.iter().map(|t| t.grains.as_slice()).collect();
    let scene = renderer.upload_types(&gpu.device, &per_type).map_err(|e| e.to_string())?;
    // Within the amplitude that keeps the inner balls apart (`Stacking::max_amplitude`).
    let shake = options
        .shake
        .then(|| grain_scenes::Shake::new((0.9 * stacking.max_amplitude()).min(0.05) as f32, 2.0, 3.0))
        .transpose()
        .map_err(|e| e.to_string())?;
    let (mut centre_scale, mut rotation) = (stacking.centre_scale().to_vec(), stacking.rotation().to_vec());
    let lighting = ShadingUniforms::new(
        Vec3::new(0.4, 1.0, 0.6),
        Vec3::splat(2.6),
        Vec3::splat(0.25),
        Vec3::new(0.08, 0.09, 0.12),
    )
    .ok_or("the light direction is zero")?;
    let mut csv = String::from("adapter,timing,frame,distance,");
    for stage in Stage::ALL {
        let _ = write!(csv, "{}_ms,", stage.name());
    }
    csv += "total_ms,mesh,impostor_occluder,impostor_rest,point,culled_frustum,culled_cone,culled_hiz\n";
    let adapter = gpu.adapter_info().name.replace('"', "\"\"");
    for k in 0..options.frames {
        let camera = dolly(&shots, k, options.frames, options.size)?;
        if let Some(shake) = &shake {
            let started = Instant::now();
            shake.pose_at(&stacking, k as f32 / 24.0, &mut centre_scale, &mut rotation).map_err(|e| e.to_string())?;
            for (t, grain_type) in types.iter().enumerate() {
                let moved: Vec<GrainInstance> = (t..centre_scale.len())
                    .step_by(count)
                    .map(|i| {
                        let c = centre_scale[i];
                        GrainInstance::new(c.truncate(), c.w * grain_type.scale, Quat::from_vec4(rotation[i]))
                    })
                    .collect();
                renderer.update_range(&gpu.queue, &scene, t, 0, &moved).map_err(|e| e.to_string())?;
            }
            println!(
                "  frame {k}: {} grains posed and uploaded in {:.1} ms",
                centre_scale.len(),
                started.elapsed().as_secs_f64() * 1e3
            );
        }
        let times = time_frame(&gpu, &renderer, &scene, &camera, &lighting, TierSettings::default())
            .map_err(|e| e.to_string())?;
        let counters = renderer.read_counters(&gpu).map_err(|e| e.to_string())?;
        let image = grain_impostor::shading::read_image(&gpu.device, &gpu.queue, renderer.image())
            .map_err(|e| e.to_string())?;
        let path = options.out.join(format!("stackings_{k:02}.png"));
        image.save(&path).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        let distance = (camera.uniforms.eye.truncate() - shots[0].target).length();
        let breakdown: Vec<String> =
            Stage::ALL.iter().zip(times.ms).map(|(s, ms)| format!("{} {ms:.1}", s.name())).collect();
        println!(
            "  frame {k}: {} ms ({:?}: {}); lists {:?}, culled (frustum, cone, Hi-Z) {:?}",
            format_args!("{:.1}", times.total()),
            times.source,
            breakdown.join(", "),
            counters.count,
            &counters.culled[..3]
        );
        let _ = write!(csv, "\"{adapter}\",{:?},{k},{distance:.3},", times.source);
        for ms in times.ms {
            let _ = write!(csv, "{ms:.4},");
        }
        let c = counters;
        let _ = writeln!(
            csv,
            "{:.4},{},{},{},{},{},{},{}",
            times.total(),
            c.count[0],
            c.count[1],
            c.count[2],
            c.count[3],
            c.culled[0],
            c.culled[1],
            c.culled[2]
        );
    }
    write(&options.out.join("stackings.csv"), &csv)?;
    println!(
        "wrote {} frames and stackings.csv into {} in {:.1} s",
        options.frames,
        options.out.display(),
        started.elapsed().as_secs_f64()
    );
    if options.accuracy {
        let cameras = (0..options.frames)
            .map(|k| {
                let camera = dolly(&shots, k, options.frames, options.size)?;
                let distance = (camera.uniforms.eye.truncate() - shots[0].target).length();
                Ok((camera, grain_diameter(&camera, outer, distance)))
            })
            .collect::<Result<Vec<_>, String>>()?;
        let t = &types[0];
        accuracy(&gpu, &options, &t.mesh, &t.atlas, &t.grains, renderer_options, &cameras, &lighting)?;
    }
    Ok(())
}

/// The projected diameter (pixels) of a grain of scale 1 and outer radius `outer` at
/// `distance` from the eye of `camera` (its focal length in pixels times `2·outer/distance`).
fn grain_diameter(camera: &StackingCamera, outer: f32, distance: f32) -> f32 {
    camera.split.projection.x * 2.0 * outer / distance
}

/// `--accuracy`: the dolly again with a fresh renderer, each frame against every grain as a
/// mesh 4×4 supersampled (`grain_renderer::frame_accuracy`): `reference_KK.png`,
/// `flip_KK.png` and `accuracy.csv`.
#[allow(clippy::too_many_arguments)]
fn accuracy(
    gpu: &gpu_harness::Gpu,
    options: &Options,
    mesh: &grain_mesh::GrainMesh,
    atlas: &ImpostorAtlas,
    grains: &[GrainInstance],
    renderer_options: RendererOptions,
    cameras: &[(StackingCamera, f32)],
    lighting: &ShadingUniforms,
) -> Result<(), String> {
    use grain_renderer::frame_accuracy::{measure_frames, spikes};
    let started = Instant::now();
    let renderer =
        StackingRenderer::new(&gpu.device, &gpu.queue, mesh, atlas, renderer_options).map_err(|e| e.to_string())?;
    let scene = renderer.upload(&gpu.device, grains).map_err(|e| e.to_string())?;
    let truth = grain_renderer::mesh_reference::MeshReference::new(&gpu.device, mesh, grains, options.size)
        .map_err(|e| e.to_string())?;
    println!("  accuracy: each frame against every grain as a mesh, 4×4 supersampled");
    let save = |name: String, image: &dyn Fn(&Path) -> image::ImageResult<()>| {
        let path = options.out.join(name);
        image(&path)
            .map_err(|e| grain_renderer::RenderError::InvalidInput(format!("cannot write {}: {e}", path.display())))
    };
    let frames =
        measure_frames(gpu, &renderer, &scene, &truth, cameras, lighting, TierSettings::default(), |k, f, images| {
            println!(
                "  frame {k} ({:.1} px grains): SSIM {:.4}, FLIP {:.4}, mean error {:.4}, popping {}; lists {:?}",
                f.label,
                f.ssim,
                f.flip,
                f.error,
                f.popping().map_or_else(|| "-".to_owned(), |p| format!("{p:+.4}")),
                f.lists
            );
            save(format!("reference_{k:02}.png"), &|p| images.reference.save(p))?;
            save(format!("flip_{k:02}.png"), &|p| images.flip_map.save(p))
        })
        .map_err(|e| e.to_string())?;
    let spiking = spikes(&frames);
    let mut csv = String::from(
        "frame,grain_diameter_px,mesh,impostor_occluder,impostor_rest,point,ssim,flip,mean_error,change,reference_change,popping,spike\n",
    );
    for (k, f) in frames.iter().enumerate() {
        let opt = |v: Option<f64>| v.map_or_else(String::new, |v| format!("{v:.6}"));
        let _ = writeln!(
            csv,
            "{k},{:.3},{},{},{},{},{:.6},{:.6},{:.6},{},{},{},{}",
            f.label,
            f.lists[0],
            f.lists[1],
            f.lists[2],
            f.lists[3],
            f.ssim,
            f.flip,
            f.error,
            opt(f.change),
            opt(f.reference_change),
            opt(f.popping()),
            spiking.contains(&k)
        );
    }
    write(&options.out.join("accuracy.csv"), &csv)?;
    println!(
        "  accuracy.csv, reference and FLIP images in {:.1} s; frames spiking (popping > half a full pop): {spiking:?}",
        started.elapsed().as_secs_f64()
    );
    Ok(())
}
