//! Fig. 11 and Fig. 12 of the paper against the supersampled truth of the unfiltered
//! surface: the colour shift of a far bumpy surface coloured by height at a grazing view
//! (the correlated attribute `ā(v, l)` of eq. 17 against naive separate filtering), and the
//! highlight-to-diffuse transition of a specular bumpy surface as the camera recedes (the
//! lobe `σn² + σnp²` of §5.5 against the lobe `σnp` alone).

use std::sync::OnceLock;

use abuffer_mask::MaskTable;
use glam::{DVec3, Vec3};
use svo_brick::{BrickSize, PackedTree, VoxelLayout};
use svo_render::truth::{TruthSettings, render_source_truth};
use svo_render::{Frame, cpu, scenes};
use svo_tracer::{Camera, Filtering, Light, Model, TraceSettings};

const BACKGROUND: Vec3 = Vec3::ZERO;
/// 128 finest voxels across the domain: the bumps' period is 8 finest voxels.
const LEVELS: u32 = 6;

fn table() -> &'static MaskTable<4> {
    static TABLE: OnceLock<MaskTable<4>> = OnceLock::new();
    TABLE.get_or_init(|| MaskTable::<4>::paper().unwrap())
}

/// The bumpy plane `y = A sin(f x) sin(f z)` coloured by height (red grooves, yellow crests):
/// `A = 0.012`, `f = 50`, a period of 8 finest voxels, slopes of deviation ~0.3 per axis.
fn plane() -> scenes::Scene {
    scenes::bumpy_plane(0.012, 50.0).unwrap()
}

fn plane_tree() -> &'static PackedTree {
    static TREE: OnceLock<PackedTree> = OnceLock::new();
    TREE.get_or_init(|| PackedTree::new(&plane().build(BrickSize::Four, LEVELS).unwrap(), VoxelLayout::Paper20))
}

/// The pixels whose centre ray meets the plane `y = 0` at a distance in `range` from the eye,
/// inside `|x|, |z| < 0.8` (away from the domain's faces).
fn patch(camera: &Camera, range: (f64, f64)) -> Vec<usize> {
    let (width, height) = camera.size();
    let mut pixels = Vec::new();
    for y in 0..height {
        for x in 0..width {
            let cone = camera.pixel_cone(x, y);
            let (o, d) = (cone.origin.as_dvec3(), cone.direction.as_dvec3());
            if d.y >= 0.0 {
                continue;
            }
            let t = -o.y / d.y;
            let hit: DVec3 = o + d * t;
            if t >= range.0 && t <= range.1 && hit.x.abs() < 0.8 && hit.z.abs() < 0.8 {
                pixels.push((y * width + x) as usize);
            }
        }
    }
    pixels
}

/// The mean radiance of `frame` over `pixels`.
fn mean_of(frame: &Frame, pixels: &[usize]) -> Vec3 {
    let sum: DVec3 = pixels.iter().map(|&i| frame.radiance[i].as_dvec3()).sum();
    (sum / pixels.len() as f64).as_vec3()
}

/// `|a − b| / |b|`.
fn relative(a: Vec3, b: Vec3) -> f64 {
    f64::from((a - b).length() / b.length())
}

/// A camera at `distance` from `centre` (on the plane) at `elevation` (radians) above it,
/// looking at it, with `width × height` pixels whose footprint at `centre` is `footprint`
/// wide (world units).
fn view(centre: Vec3, distance: f32, elevation: f32, footprint: f32, width: u32, height: u32) -> Camera {
    let eye = centre + Vec3::new(0.0, elevation.sin(), -elevation.cos()) * distance;
    let fov = footprint / distance * height as f32;
    Camera::look_at(eye, centre, Vec3::Y, fov, width, height).unwrap()
}

/// The truth with `k × k` rays per pixel, for `k` = 8 and 12: the second is the reference,
/// their difference estimates its sampling error.
fn truths(camera: &Camera, trace: &TraceSettings) -> [Frame; 2] {
    let scene = plane();
    let voxel = scene.voxel_size(BrickSize::Four, LEVELS);
    [8, 12].map(|k| {
        render_source_truth(scene.source.as_ref(), scene.domain, camera, trace, &TruthSettings::for_voxel(voxel, k))
            .unwrap()
    })
}

/// The chromaticity `rgb / (r + g + b)`.
fn chroma(c: Vec3) -> Vec3 {
    c / c.element_sum()
}

/// Fig. 11: deep red vanishes at a grazing view. The far patch of the bumpy plane coloured by
/// height, seen 5° above its plane with a footprint of 16 finest voxels (the cones read
/// levels 4–5, where the bumps — a period of 8 finest voxels — are in `σh`, `σn` and `a_s`),
/// lit from above. The truth sees mostly crests (yellow); separate filtering shades the mean colour
/// `ā`; eq. 17's `ā(v, l)` moves it towards the crests.
///
/// Measured and printed: the patch's mean colour error `|m − t|/|t|` and chromaticity error
/// (`rgb/(r+g+b)`, the hue shift of Fig. 11) of both models, and whether the goals
/// (correlated within 2 %, separate off by ≥ 20 %) are met. Asserted: the correlated model's
/// chromaticity is closer to the truth's than separate filtering's by more than twice the
/// truth's own sampling error (its change from 8² to 12² rays per pixel).
#[test]
fn fig11_a_far_grazing_patch_keeps_the_colour_of_its_crests() {
    let camera = view(Vec3::new(0.0, 0.0, 0.2), 3.0, 5f32.to_radians(), 0.25, 12, 6);
    let trace = TraceSettings {
        light: Light { position: Vec3::new(0.0, 8.0, -3.0), radius: 0.2, radiance: 3.0 },
        background: BACKGROUND,
        ..TraceSettings::default()
    };
    let pixels = patch(&camera, (0.0, f64::INFINITY));
    assert!(pixels.len() >= 6, "{} patch pixels", pixels.len());
    let truths = truths(&camera, &trace);
    let (coarse, truth) = (mean_of(&truths[0], &pixels), mean_of(&truths[1], &pixels));
    let noise = relative(coarse, truth);
    let chroma_noise = relative(chroma(coarse), chroma(truth));
    println!(
        "Fig. 11, {} far-patch pixels: truth {truth} (8² rays: {coarse}; noise {noise:.4}, chromaticity noise \
         {chroma_noise:.4})",
        pixels.len()
    );
    let mut errors = Vec::new();
    for model in [Model::Masks, Model::SeparateFiltering] {
        let frame = cpu::render(plane_tree(), table(), &camera, &TraceSettings { model, ..trace });
        let m = mean_of(&frame, &pixels);
        let (colour, hue) = (relative(m, truth), relative(chroma(m), chroma(truth)));
        println!("  {}: {m}, colour error {colour:.4}, chromaticity error {hue:.4}", model.name());
        errors.push((colour, hue));
    }
    println!(
        "  the issue's goals: correlated within 2 % ({}), separate ≥ 20 % ({})",
        if errors[0].0 <= 0.02 { "met" } else { "not met" },
        if errors[1].0 >= 0.2 { "met" } else { "not met" }
    );
    assert!(errors[0].1 + 2.0 * chroma_noise < errors[1].1, "chromaticity errors {errors:?}, noise {chroma_noise}");
}

/// The radiance of a flat element at the mirror configuration of `trace` seen at `elevation`:
/// the peak of the base lobe `σnp` that separate filtering keeps at every distance.
fn flat_peak(trace: &TraceSettings, elevation: f32) -> f32 {
    let view = Vec3::new(0.0, elevation.sin(), -elevation.cos());
    let light = Vec3::new(0.0, elevation.sin(), elevation.cos());
    let flat = svo_brick::Voxel { normal: Vec3::Y, attribute: [1.0; 3], ..svo_brick::Voxel::default() };
    svo_tracer::element_radiance(&flat, view, light, &trace.material, Filtering::Separate, trace.light.radiance, 1.0)
        .max_element()
}

/// Fig. 12: bumps turn into a diffuse lobe. The specular bumpy plane (`σnp = 0.1`) seen at
/// 45° with the light at the mirror direction, from 1, 2 and 4 units with footprints of 1,
/// 4 and 16 finest voxels (the patch `|x|, |z| < 0.8` in 32², 8², 4² pixels).
///
/// Measured and printed per distance: the patch's mean radiance against the truth (ratio),
/// and its brightest pixel. Asserted, from properties rather than this run's values:
/// - far, separate filtering keeps the base lobe's sharp peak: its brightest pixel is at
///   least half the peak `P` of a flat element at the mirror configuration (the patch's
///   centre is within half a pixel diagonal of it, which turns the half-vector by ~0.03, a
///   quarter of `σnp`, where the lobe is within 5 % of its peak);
/// - far, the paper's lobe `σn² + σnp²` spreads it: where the sampled `σn² ≥ σnp²` (checked)
///   the Gaussian lobe's peak is at most `σnp²/(σn² + σnp²) ≤ ½` of `P`, so no pixel exceeds
///   `P/2`;
/// - across the distances, the paper's model keeps its ratio to the truth while separate
///   filtering's grows: separate's ratio grows from the nearest to the farthest view by more
///   than ours does, by more than the truth's sampling error.
#[test]
fn fig12_a_receding_specular_patch_turns_diffuse() {
    let material = svo_render::stability::cases::SPECULAR;
    let elevation = 45f32.to_radians();
    let light = Vec3::new(0.0, elevation.sin(), elevation.cos());
    let trace = TraceSettings {
        light: Light { position: light * 30.0, radius: 0.2, radiance: 3.0 },
        material,
        background: BACKGROUND,
        ..TraceSettings::default()
    };
    let peak = flat_peak(&trace, elevation);
    let voxel = plane().voxel_size(BrickSize::Four, LEVELS);
    let mut ratios = Vec::new();
    let mut worst_noise = 0.0_f64;
    for (distance, footprint, size) in [(1.0_f32, voxel, 32_u32), (2.0, 4.0 * voxel, 8), (4.0, 16.0 * voxel, 4)] {
        let camera = view(Vec3::ZERO, distance, elevation, footprint, size, size);
        let pixels = patch(&camera, (0.0, f64::INFINITY));
        let truths = truths(&camera, &trace);
        let (coarse, truth) = (mean_of(&truths[0], &pixels), mean_of(&truths[1], &pixels));
        let noise = relative(coarse, truth);
        worst_noise = worst_noise.max(noise);
        let brightest = |f: &Frame| pixels.iter().map(|&i| f.radiance[i].max_element()).fold(0.0, f32::max);
        println!(
            "Fig. 12, distance {distance} ({} px, footprint {:.1} voxels): truth {truth} (noise {noise:.4}), \
             brightest {:.3}; flat peak P = {peak:.3}",
            pixels.len(),
            footprint / voxel,
            brightest(&truths[1])
        );
        let mut row = Vec::new();
        for model in [Model::Masks, Model::SeparateFiltering] {
            let frame = cpu::render(plane_tree(), table(), &camera, &TraceSettings { model, ..trace });
            let m = mean_of(&frame, &pixels);
            let ratio = f64::from(m.element_sum() / truth.element_sum());
            println!("  {}: mean {m}, ratio to the truth {ratio:.3}, brightest {:.3}", model.name(), brightest(&frame));
            row.push((ratio, brightest(&frame)));
        }
        if distance == 4.0 {
            let lod = (footprint / voxel).log2();
            let sample = plane_tree().sample(Vec3::ZERO, lod).unwrap();
            println!("  far: sampled σn² {:.4} at λ = {lod:.2} (σnp² = {})", sample.slope_variance, 0.01);
            assert!(sample.slope_variance >= material.brdf_slope.powi(2), "σn² {}", sample.slope_variance);
            assert!(row[1].1 >= 0.5 * peak, "separate's brightest {} vs P {peak}", row[1].1);
            assert!(row[0].1 <= 0.5 * peak, "ours' brightest {} vs P {peak}", row[0].1);
        }
        ratios.push((row[0].0, row[1].0));
    }
    let (ours, separate) = (ratios[2].0 / ratios[0].0, ratios[2].1 / ratios[0].1);
    println!("ratio far/near: ours {ours:.3}, separate {separate:.3} (truth noise up to {worst_noise:.4})");
    assert!(separate > ours * (1.0 + 2.0 * worst_noise), "far/near ratios: ours {ours}, separate {separate}");
}
