//! The GPU occluder map and splitter (`grain-splitter`) against its CPU reference, and the
//! culling against a mesh render.
//!
//! The reference evaluates the same `f32` operations. Only the centre's pixel and the
//! projected radius divide; WGSL allows a division 2.5 ulp of error, so a grain whose square
//! or centre lies within [`EDGE_TOLERANCE`] pixels of a pixel edge may land on the
//! neighbouring pixel on some adapter. A decision or texel may differ only for such a grain;
//! the tests print how many differ (0 on lavapipe, which divides exactly) and, when none
//! does, compare the counts, offsets and indirect arguments exactly. Tiers use no division
//! and must be equal for every grain.

use glam::{Quat, Vec3, Vec4};
use grain_impostor::mesh_gbuffer::{GpuMesh, MeshGbufferPass, ScreenGbuffer};
use grain_impostor::scene::{CameraUniforms, GrainInstance};
use grain_splitter::lists::state_model;
use grain_splitter::reference::{self, OccluderMap};
use grain_splitter::{
    CULLED_CONE, CULLED_HIZ, GrainSplitter, ListIndirect, ListOrder, OccluderMapKind, SplitCamera, SplitCounters,
    SplitSettings, SplitterOptions, TierThresholds,
};
use integration_tests::gpu;
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use wgpu::util::DeviceExt;

/// Pixels: far above the 2.5-ulp division error at these viewport sizes (≤ 256 px: an ulp
/// is ≤ 3·10⁻⁵ px).
const EDGE_TOLERANCE: f32 = 1e-3;

/// A jittered cubic stacking of `n³` grains of outer radius `outer` (scale in [0.9, 1.1]),
/// spacing `2.1·outer·1.1`, so that the outer balls never overlap.
fn stacking(n: u32, outer: f32, seed: u64) -> Vec<Vec4> {
    let mut rng = SmallRng::seed_from_u64(seed);
    let spacing = 2.1 * outer * 1.1;
    let jitter = 0.04 * outer;
    let mut grains = Vec::new();
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let site = Vec3::new(x as f32, y as f32, z as f32) * spacing;
                let offset = Vec3::new(rng.random(), rng.random(), rng.random()) * 2.0 - Vec3::ONE;
                grains.push((site + offset * jitter).extend(rng.random_range(0.9..1.1)));
            }
        }
    }
    grains
}

struct Frame {
    map: OccluderMap,
    /// Every level of the fusion pyramid (empty unless the Hi-Z test is on).
    pyramid: Vec<f32>,
    state: Vec<u32>,
    counters: SplitCounters,
    elements: Vec<u32>,
    indirect: [ListIndirect; 4],
}

fn read_u32(buffer: &wgpu::Buffer, words: usize) -> Vec<u32> {
    let bytes = gpu().read_buffer(buffer, words as u64 * 4).unwrap();
    bytemuck::cast_slice(&bytes).to_vec()
}

/// Runs `frames` frames (one camera each) and reads everything back after the last.
fn run_gpu(
    settings: SplitSettings,
    kind: OccluderMapKind,
    order: ListOrder,
    grains: &[Vec4],
    cameras: &[SplitCamera],
    mut after_frame: impl FnMut(usize, &Frame),
) {
    let gpu = gpu();
    let size = cameras[0].size();
    let options = SplitterOptions { capacity: grains.len() as u32, size, occluder_map: kind, order };
    let splitter = GrainSplitter::new(&gpu.device, settings, options).unwrap();
    let buffer = gpu.device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("grains"),
        contents: bytemuck::cast_slice(grains),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let bindings = splitter.bind(&gpu.device, &buffer).unwrap();
    for (i, camera) in cameras.iter().enumerate() {
        let mut encoder = gpu.device.create_command_encoder(&Default::default());
        splitter.encode(&gpu.queue, &mut encoder, &bindings, camera, grains.len() as u32, None).unwrap();
        gpu.queue.submit([encoder.finish()]);
        let (words, stride) = splitter.occluder_words();
        let pixels = (size.0 * size.1) as usize;
        let raw = read_u32(words, pixels * stride as usize);
        let ids =
            raw.iter().step_by(stride as usize).map(|&w| if w == 0 { reference::NO_OCCLUDER } else { !w }).collect();
        let counters: SplitCounters = bytemuck::pod_read_unaligned(&gpu.read_buffer(splitter.counters(), 64).unwrap());
        let indirect_words = read_u32(splitter.indirect(), 48);
        let indirect = std::array::from_fn(|l| {
            bytemuck::pod_read_unaligned(bytemuck::cast_slice(&indirect_words[l * 12..][..12]))
        });
        let listed: u32 = counters.count.iter().sum();
        let texels = if settings.hiz_culling { grain_splitter::hiz::pyramid_texels(size) as usize } else { 0 };
        let pyramid_bytes =
            if texels == 0 { Vec::new() } else { gpu.read_buffer(splitter.pyramid(), texels as u64 * 4).unwrap() };
        let frame = Frame {
            map: OccluderMap { width: size.0, height: size.1, ids },
            pyramid: bytemuck::pod_collect_to_vec(&pyramid_bytes),
            state: read_u32(splitter.state(), grains.len()),
            counters,
            elements: read_u32(splitter.elements(), listed as usize),
            indirect,
        };
        after_frame(i, &frame);
    }
}

fn lists_of(frame: &Frame) -> [Vec<u32>; 4] {
    std::array::from_fn(|l| {
        let start = frame.counters.offset[l] as usize;
        frame.elements[start..][..frame.counters.count[l] as usize].to_vec()
    })
}

/// Grains whose square in the occluder map has an edge (`floor(p ± h)`, `h` the half-side)
/// within the tolerance of a pixel edge.
fn ambiguous_splats(camera: &SplitCamera, settings: &SplitSettings, grains: &[Vec4]) -> Vec<bool> {
    grains
        .iter()
        .map(|&g| {
            let Some((pixel, h, _)) = reference::splat_half(camera, settings, g) else { return false };
            let near = |x: f32| (x - x.round()).abs() < EDGE_TOLERANCE;
            near(pixel.x - h) || near(pixel.x + h) || near(pixel.y - h) || near(pixel.y + h)
        })
        .collect()
}

fn camera(eye: Vec3, target: Vec3, fov: f32, size: (u32, u32)) -> SplitCamera {
    SplitCamera::perspective(eye, target, Vec3::Y, fov, size, (0.1, 500.0)).unwrap()
}

#[test]
fn gpu_lists_counts_and_indirect_arguments_equal_the_cpu_reference() {
    let grains = stacking(20, 1.0, 7);
    // Projected diameters span about 3.6 to 6.6 pixels here: every list gets grains.
    let thresholds = TierThresholds::new(4.5, 6.0, 1.0).unwrap();
    // The Hi-Z test rounds differently from its f64 reference: compared in its own test.
    let settings =
        SplitSettings { mesh_index_count: 960, hiz_culling: false, ..SplitSettings::new(0.9, 1.0, thresholds) };
    let size = (192, 144);
    let centre = Vec3::splat(20.0 * 2.31 / 2.0);
    let cam = camera(centre + Vec3::new(8.0, 12.0, 60.0), centre, 0.7, size);
    let has_64 = gpu().device.features().contains(wgpu::Features::SHADER_INT64_ATOMIC_MIN_MAX);
    let mut kinds = vec![OccluderMapKind::TwoPass32];
    if has_64 {
        kinds.push(OccluderMapKind::Atomic64);
    }
    println!("occluder maps compared: {kinds:?} (64-bit atomics: {has_64})");
    let cpu_map = reference::occluder_map(&cam, &settings, &grains);
    let ambiguous = ambiguous_splats(&cam, &settings, &grains);
    let ambiguous_count = ambiguous.iter().filter(|&&a| a).count();
    let mut maps = Vec::new();
    for &kind in &kinds {
        for order in [ListOrder::Atomic, ListOrder::Stable] {
            run_gpu(settings, kind, order, &grains, std::slice::from_ref(&cam), |_, frame| {
                // The map: equal wherever no ambiguous grain's square reaches.
                let differing: Vec<usize> =
                    (0..cpu_map.ids.len()).filter(|&t| frame.map.ids[t] != cpu_map.ids[t]).collect();
                let unexplained = differing
                    .iter()
                    .filter(|&&t| {
                        let (a, b) = (frame.map.ids[t], cpu_map.ids[t]);
                        ![a, b].iter().any(|&id| id != reference::NO_OCCLUDER && ambiguous[id as usize])
                    })
                    .count();
                println!(
                    "{kind:?} {order:?}: {} of {} texels filled, {} differ ({ambiguous_count} grains near a pixel edge), {unexplained} unexplained",
                    cpu_map.filled(),
                    cpu_map.ids.len(),
                    differing.len()
                );
                assert_eq!(unexplained, 0);
                // The decisions, given the GPU's own map: equal except for centres near a
                // pixel edge.
                let cpu = reference::split(&cam, &settings, &grains, &frame.map, &[]).unwrap();
                let near_edge: Vec<bool> =
                    grains.iter().map(|g| cam.project(g.truncate()).near_pixel_edge(size, 64.0)).collect();
                let mismatched: Vec<u32> =
                    (0..grains.len() as u32).filter(|&i| frame.state[i as usize] != cpu.state[i as usize]).collect();
                assert!(mismatched.iter().all(|&i| near_edge[i as usize]), "decisions differ: {mismatched:?}");
                println!(
                    "  {} of {} decisions equal; {} differ, all of centres near a pixel edge",
                    grains.len() - mismatched.len(),
                    grains.len(),
                    mismatched.len()
                );
                let gpu_lists = lists_of(frame);
                for (l, gpu_list) in gpu_lists.iter().enumerate() {
                    if order == ListOrder::Stable {
                        assert!(gpu_list.windows(2).all(|w| w[0] < w[1]), "list {l}: stable order is ascending");
                    }
                    let mut listed: Vec<u32> = gpu_list.iter().copied().filter(|i| !mismatched.contains(i)).collect();
                    listed.sort_unstable();
                    let expected: Vec<u32> = cpu.lists[l].iter().copied().filter(|i| !mismatched.contains(i)).collect();
                    assert_eq!(listed, expected, "list {l}");
                    assert!(frame.counters.count[l].abs_diff(cpu.counters.count[l]) as usize <= mismatched.len());
                }
                if mismatched.is_empty() {
                    assert_eq!(frame.counters.count, cpu.counters.count);
                    assert_eq!(frame.counters.offset, cpu.counters.offset);
                    assert_eq!(frame.counters.culled, cpu.counters.culled);
                    assert_eq!(frame.indirect, cpu.indirect);
                }
                // Cursors end at the counts (atomic order) or stay zero (stable order).
                let cursors = if order == ListOrder::Atomic { frame.counters.count } else { [0; 4] };
                assert_eq!(frame.counters.cursor, cursors);
                for l in 0..4 {
                    assert_eq!(frame.indirect[l], ListIndirect::new(frame.counters.count[l], 960, 6));
                }
                println!(
                    "  counts {:?}, culled (frustum, cone) {:?}",
                    frame.counters.count,
                    &frame.counters.culled[..2]
                );
                assert!(
                    frame.counters.culled[1] > 0 && frame.counters.count.iter().all(|&c| c > 0),
                    "the scene exercises every list"
                );
                maps.push(frame.map.clone());
            });
        }
    }
    // Both map kinds and both orders build the same map.
    assert!(maps.windows(2).all(|w| w[0] == w[1]));
}

/// The scene of the Hi-Z tests: grains of 8 to 14 pixels across, squares of 0.6 r.
fn hiz_scene() -> (Vec<Vec4>, SplitCamera, SplitSettings) {
    let grains = stacking(16, 1.0, 5);
    let settings = SplitSettings {
        splat_factor: 0.6,
        ..SplitSettings::new(0.9, 1.0, TierThresholds::new(2.0, 64.0, 1.0).unwrap())
    };
    let centre = Vec3::splat(16.0 * 2.31 / 2.0);
    (grains, camera(centre + Vec3::new(6.0, 9.0, 45.0), centre, 0.7, (192, 144)), settings)
}

/// Whether `rays` random rays from the eye through points of grain `index`'s outer ball all
/// meet another grain's inner ball before that point (`f64`, brute force over the grains).
/// Rays that leave the screen draw nothing and are not counted.
fn hidden_by_rays(cam: &SplitCamera, settings: &SplitSettings, grains: &[Vec4], index: usize, rays: u32) -> bool {
    use glam::DVec3;
    let view = glam::Mat4::from_cols_array_2d(&cam.view_from_world.map(|c| c.to_array())).as_dmat4();
    let eye = view.inverse().transform_point3(DVec3::ZERO);
    let mut rng = SmallRng::seed_from_u64(index as u64);
    let g = grains[index];
    let outer = f64::from(settings.outer_radius * g.w);
    (0..rays).all(|_| {
        let offset = loop {
            let v = DVec3::new(rng.random(), rng.random(), rng.random()) * 2.0 - DVec3::ONE;
            if v.length_squared() <= 1.0 {
                break v;
            }
        };
        let point = g.truncate().as_dvec3() + offset * outer;
        let (width, height) = (f64::from(cam.viewport.x), f64::from(cam.viewport.y));
        let on_screen = cam.project(point.as_vec3()).pixel.is_some_and(|p| {
            let p = p.as_dvec2();
            p.x > 0.01 && p.y > 0.01 && p.x < width - 0.01 && p.y < height - 0.01
        });
        if !on_screen {
            return true;
        }
        let (d, distance) = ((point - eye).normalize(), (point - eye).length());
        grains.iter().enumerate().any(|(j, o)| {
            let c = o.truncate().as_dvec3() - eye;
            let r = f64::from(settings.occluder_radius * o.w);
            let (along, across2) = (c.dot(d), c.cross(d).length_squared());
            j != index && across2 <= r * r && along > 0.0 && along - (r * r - across2).sqrt() < distance
        })
    })
}

/// Two-phase culling on the GPU: the previous frame's visible grains cover their discs.
/// Checked over two frames (no history, then the GPU's own state): every finite level-0
/// bound is at least the `f64` two-phase reference's, or another covering grain witnesses
/// it; the culled set contains the single-phase one (a minimum of bounds is never looser);
/// every grain culled by Hi-Z is hidden when rays are cast through it.
#[test]
fn gpu_two_phase_culling_covers_more_and_stays_conservative() {
    use grain_splitter::hiz::HIZ_NONE;
    use grain_splitter::temporal::cover_square;
    let (grains, cam, settings) = hiz_scene();
    let culled_set = |frame: &Frame| -> Vec<bool> { frame.state.iter().map(|&s| state_model(s) >= 4).collect() };
    let mut single = Vec::new();
    let single_settings = SplitSettings { temporal_occluders: false, ..settings };
    run_gpu(single_settings, OccluderMapKind::Auto, ListOrder::Stable, &grains, std::slice::from_ref(&cam), |_, f| {
        single = culled_set(f);
    });
    let mut previous: Vec<u32> = Vec::new();
    let cameras = [cam, cam];
    run_gpu(settings, OccluderMapKind::Auto, ListOrder::Stable, &grains, &cameras, |i, frame| {
        let cpu = grain_splitter::DepthPyramid::build_two_phase(&cam, &settings, &grains, &frame.map, &previous);
        let (w, h, base) = cpu.level(0).unwrap();
        let (mut finite, mut witnessed) = (0, 0);
        for y in 0..h {
            for x in 0..w {
                let b = frame.pyramid[(y * w + x) as usize];
                if b >= HIZ_NONE {
                    continue;
                }
                finite += 1;
                if f64::from(b) >= base[(y * w + x) as usize] {
                    continue;
                }
                // A square edge rounded the other way: some grain whose square, widened by
                // a pixel, holds (x, y) must bound it.
                let witness = grains.iter().any(|&g| {
                    cover_square(&cam, &settings, g).is_some_and(|sq| {
                        let inside = |p: u32, lo: u32, hi: u32| p + 1 >= lo && p <= hi + 1;
                        inside(x, sq.min.0, sq.max.0)
                            && inside(y, sq.min.1, sq.max.1)
                            && grain_splitter::occluder_bound(&cam, (x, y), g.truncate(), f64::from(0.9 * g.w))
                                <= f64::from(b)
                    })
                });
                assert!(witness, "frame {i}, ({x}, {y}): bound {b} below every grain's");
                witnessed += 1;
            }
        }
        let culled = culled_set(frame);
        assert!(single.iter().zip(&culled).all(|(&s, &t)| !s || t), "frame {i}: a grain single-phase culls is kept");
        let hiz: Vec<usize> = (0..grains.len()).filter(|&g| state_model(frame.state[g]) == CULLED_HIZ).collect();
        for &g in &hiz {
            assert!(hidden_by_rays(&cam, &settings, &grains, g, 48), "frame {i}: grain {g} is visible");
        }
        let reference = reference::split(&cam, &settings, &grains, &frame.map, &previous).unwrap();
        println!(
            "frame {i}: {finite} bounded pixels ({} in the f64 reference, {witnessed} below it with a witness); culled single-phase {}, two-phase {} (Hi-Z {} GPU, {} f64 reference), every Hi-Z one hidden from 48 rays",
            cpu.finite_pixels(),
            single.iter().filter(|&&c| c).count(),
            culled.iter().filter(|&&c| c).count(),
            hiz.len(),
            reference.counters.culled[2]
        );
        assert!(culled.iter().filter(|&&c| c).count() > single.iter().filter(|&&c| c).count(), "two-phase culls more");
        previous = frame.state.clone();
    });
}

/// The GPU pyramid against the `f64` reference built from the GPU's own occluder map: every
/// finite GPU bound is at least the reference's (conservative rounding, `hiz` module docs);
/// a bound the reference has and the GPU lacks is allowed only where the occluder ball shrunk
/// by twice its slack misses a corner of the pixel; every level above the first is the max
/// of its children, exactly; every grain the GPU's Hi-Z test culls, the reference culls.
#[test]
fn gpu_hiz_is_a_conservative_rounding_of_the_f64_reference() {
    use grain_splitter::hiz::{HIZ_NONE, HIZ_SLACK};
    let (grains, cam, settings) = hiz_scene();
    let settings = SplitSettings { temporal_occluders: false, ..settings };
    let size = cam.size();
    let mut checked = false;
    run_gpu(settings, OccluderMapKind::Auto, ListOrder::Stable, &grains, std::slice::from_ref(&cam), |_, frame| {
        let cpu = grain_splitter::DepthPyramid::build(&cam, &settings, &grains, &frame.map);
        let levels = grain_splitter::hiz::pyramid_levels(size);
        let (w, h, base) = cpu.level(0).unwrap();
        let (mut finite, mut dropped, mut excess) = (0, 0, Vec::new());
        for y in 0..h {
            for x in 0..w {
                let i = (y * w + x) as usize;
                let (gpu_bound, cpu_bound) = (frame.pyramid[i], base[i]);
                if gpu_bound < HIZ_NONE {
                    finite += 1;
                    assert!(
                        cpu_bound.is_finite() && f64::from(gpu_bound) >= cpu_bound,
                        "({x}, {y}): {gpu_bound} < {cpu_bound}"
                    );
                    excess.push(f64::from(gpu_bound) / cpu_bound - 1.0);
                } else if cpu_bound.is_finite() {
                    dropped += 1;
                    let id = frame.map.get((x, y)).unwrap() as usize;
                    let g = grains[id];
                    let view = cam.project(g.truncate()).view;
                    let slack = f64::from(HIZ_SLACK) * f64::from(view.length() + g.truncate().length());
                    let shrunk = f64::from(settings.occluder_radius * g.w) - 2.0 * slack;
                    let bound = grain_splitter::occluder_bound(&cam, (x, y), g.truncate(), shrunk);
                    assert!(bound.is_infinite(), "({x}, {y}): the GPU dropped a bound the shrunk ball has");
                }
            }
        }
        excess.sort_by(f64::total_cmp);
        println!(
            "pyramid level 0: {finite} GPU bounds, all >= the f64 ones (relative excess median {:.2e}, max {:.2e}); {dropped} dropped near a silhouette",
            excess[excess.len() / 2],
            excess[excess.len() - 1]
        );
        assert!(finite * 4 > cpu.finite_pixels() * 3, "most bounds survive the rounding");
        for k in 1..levels.len() {
            let (level, finer) = (levels[k], levels[k - 1]);
            for y in 0..level.height {
                for x in 0..level.width {
                    let mut max = 0.0f32;
                    for (cx, cy) in [(2 * x, 2 * y), (2 * x + 1, 2 * y), (2 * x, 2 * y + 1), (2 * x + 1, 2 * y + 1)] {
                        if cx < finer.width && cy < finer.height {
                            max = max.max(frame.pyramid[(finer.offset + cy * finer.width + cx) as usize]);
                        }
                    }
                    assert_eq!(frame.pyramid[(level.offset + y * level.width + x) as usize], max, "level {k}");
                }
            }
        }
        let gpu_hiz: Vec<usize> = (0..grains.len()).filter(|&i| state_model(frame.state[i]) == CULLED_HIZ).collect();
        let reference = reference::split(&cam, &settings, &grains, &frame.map, &[]).unwrap();
        let cpu_hiz = (0..grains.len()).filter(|&i| state_model(reference.state[i]) == CULLED_HIZ).count();
        for &i in &gpu_hiz {
            assert!(cpu.hides_grain(&cam, grains[i], settings.outer_radius), "grain {i}: culled by the GPU only");
        }
        assert_eq!(frame.counters.culled[2] as usize, gpu_hiz.len());
        println!(
            "Hi-Z culls {} grains on the GPU, {cpu_hiz} in the f64 reference (cone: {}, frustum: {}); every GPU one is hidden in the reference",
            gpu_hiz.len(),
            frame.counters.culled[1],
            frame.counters.culled[0]
        );
        assert!(!gpu_hiz.is_empty(), "the scene exercises the Hi-Z test");
        checked = true;
    });
    assert!(checked);
}

#[test]
fn tiers_with_hysteresis_follow_the_cpu_reference_over_a_dolly() {
    let grains = stacking(12, 1.0, 11);
    let thresholds = TierThresholds::new(4.0, 20.0, 1.25).unwrap();
    let settings = SplitSettings { hiz_culling: false, ..SplitSettings::new(0.9, 1.0, thresholds) };
    let size = (160, 120);
    let centre = Vec3::splat(12.0 * 2.31 / 2.0);
    // A dolly out and back in: grains cross both thresholds in both directions.
    let cameras: Vec<SplitCamera> = [30.0, 38.0, 47.0, 58.0, 70.0, 58.0, 47.0, 38.0, 30.0]
        .iter()
        .map(|&d| camera(centre + Vec3::new(0.3, 0.4, 1.0).normalize() * d, centre, 0.8, size))
        .collect();
    let mut previous = Vec::new();
    let mut switches_held = 0;
    run_gpu(settings, OccluderMapKind::Auto, ListOrder::Stable, &grains, &cameras, |i, frame| {
        let cpu = reference::split(&cameras[i], &settings, &grains, &frame.map, &previous).unwrap();
        let mismatched: Vec<usize> = (0..grains.len()).filter(|&g| frame.state[g] != cpu.state[g]).collect();
        assert!(
            mismatched.iter().all(|&g| cameras[i].project(grains[g].truncate()).near_pixel_edge(size, 64.0)),
            "frame {i}: states differ: {mismatched:?}"
        );
        let compared = grains.len() - mismatched.len();
        for (g, (&a, &b)) in frame.state.iter().zip(&cpu.state).enumerate() {
            assert_eq!(a & 0xff, b & 0xff, "frame {i}, grain {g}: the tier");
        }
        // The band held back some grains that plain thresholds would have switched.
        if !previous.is_empty() {
            let plain = SplitSettings { thresholds: TierThresholds::new(4.0, 20.0, 1.0).unwrap(), ..settings };
            let without = reference::split(&cameras[i], &plain, &grains, &frame.map, &previous).unwrap();
            switches_held += cpu.state.iter().zip(&without.state).filter(|(a, b)| (**a & 0xff) != (**b & 0xff)).count();
        }
        println!(
            "frame {i}: {compared} of {} states equal (the others near a pixel edge), counts {:?}",
            grains.len(),
            frame.counters.count
        );
        previous = frame.state.clone();
    });
    println!("grain-frames the hysteresis kept in their tier: {switches_held}");
    assert!(switches_held > 0);
}

#[test]
fn the_splitter_owns_no_mappable_buffer() {
    let settings = SplitSettings::new(0.5, 1.0, TierThresholds::new(2.0, 30.0, 1.1).unwrap());
    for kind in [OccluderMapKind::Auto, OccluderMapKind::TwoPass32] {
        let options = SplitterOptions { capacity: 1000, size: (64, 64), occluder_map: kind, order: ListOrder::Atomic };
        let splitter = GrainSplitter::new(&gpu().device, settings, options).unwrap();
        let buffers = splitter.buffers();
        assert!(buffers.len() >= 8);
        for (name, buffer) in buffers {
            let usage = buffer.usage();
            assert!(
                !usage.intersects(wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::MAP_WRITE),
                "{name}: {usage:?}"
            );
        }
        assert!(splitter.indirect().usage().contains(wgpu::BufferUsages::INDIRECT));
    }
    // Errors name what is wrong.
    let too_big =
        SplitterOptions { capacity: 10, size: (64, 64), occluder_map: OccluderMapKind::Auto, order: ListOrder::Atomic };
    let splitter = GrainSplitter::new(&gpu().device, settings, too_big).unwrap();
    let buffer = gpu().device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size: 160,
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    });
    let bindings = splitter.bind(&gpu().device, &buffer).unwrap();
    let mut encoder = gpu().device.create_command_encoder(&Default::default());
    let cam = camera(Vec3::Z * 10.0, Vec3::ZERO, 0.8, (64, 64));
    let e = splitter.encode(&gpu().queue, &mut encoder, &bindings, &cam, 11, None).unwrap_err();
    assert!(e.to_string().contains("grain count"), "{e}");
    let other = camera(Vec3::Z * 10.0, Vec3::ZERO, 0.8, (32, 64));
    let e = splitter.encode(&gpu().queue, &mut encoder, &bindings, &other, 10, None).unwrap_err();
    assert!(e.to_string().contains("size"), "{e}");
}

/// The mesh render with every grain equals the render of the grains the splitter kept: no
/// visible grain is culled. Balls, whose inner radius is nearly their outer one, so that the
/// cone culls many grains; the Hi-Z test adds some.
#[test]
fn culling_never_hides_a_visible_grain() {
    let gpu = gpu();
    let ball = grain_mesh::Ball { subdivisions: 3, ..Default::default() }.mesh().unwrap();
    let bounds = ball.bounds();
    assert!(bounds.centre.length() < 1e-4 * bounds.outer_radius, "the ball is centred");
    let (r, outer) = (bounds.occluder_radius(), bounds.outer_radius);
    println!("ball: r = {r}, R = {outer}, r/R = {}", r / outer);
    let grains = stacking(14, outer, 3);
    let size = (160, 120);
    let centre = Vec3::splat(14.0 * 2.31 * outer / 2.0);
    let eye = centre + Vec3::new(10.0, 14.0, 50.0) * outer;
    let (fov, near, far) = (0.7, 0.1, 500.0);
    let cam = SplitCamera::perspective(eye, centre, Vec3::Y, fov, size, (near, far)).unwrap();
    let uniforms = CameraUniforms::perspective(eye, centre, Vec3::Y, fov, size, (near, far)).unwrap();
    let instances = |ids: &mut dyn Iterator<Item = usize>| -> Vec<GrainInstance> {
        ids.map(|i| GrainInstance::new(grains[i].truncate(), grains[i].w, Quat::IDENTITY)).collect()
    };
    let mesh = GpuMesh::upload(&gpu.device, &ball).unwrap();
    let pass = MeshGbufferPass::new(&gpu.device).unwrap();
    let render = |instances: &[GrainInstance]| {
        let target = ScreenGbuffer::new(&gpu.device, size).unwrap();
        pass.render(&gpu.device, &gpu.queue, &mesh, &uniforms, instances, 1, &target).unwrap();
        target.read(&gpu.device, &gpu.queue).unwrap()
    };
    let all = render(&instances(&mut (0..grains.len())));
    let covered = all.normal_coverage.iter().filter(|n| n.w > 0.0).count();
    println!("{covered} of {} pixels covered", all.depth.len());
    assert!(covered * 2 > all.depth.len());
    // The paper's splat factor, and a larger one whose squares cover more pixels (more Hi-Z).
    let mut hiz_culled = 0;
    for splat_factor in [grain_splitter::DEFAULT_SPLAT_FACTOR, 0.6] {
        let settings = SplitSettings {
            splat_factor,
            ..SplitSettings::new(r, outer, TierThresholds::new(2.0, 30.0, 1.0).unwrap())
        };
        let mut kept = Vec::new();
        let mut culled = [0; 4];
        run_gpu(settings, OccluderMapKind::Auto, ListOrder::Stable, &grains, std::slice::from_ref(&cam), |_, frame| {
            kept = frame.elements.clone();
            culled = frame.counters.culled;
            for (model, count) in [(CULLED_CONE, culled[1]), (CULLED_HIZ, culled[2])] {
                assert_eq!(frame.state.iter().filter(|&&s| state_model(s) == model).count() as u32, count);
            }
        });
        kept.sort_unstable();
        println!(
            "splat factor {splat_factor}: {} grains, {} kept, culled (frustum, cone, Hi-Z) {:?}",
            grains.len(),
            kept.len(),
            &culled[..3]
        );
        // Enough culled grains for the comparison to mean something.
        assert!(culled[1] >= 100, "the cone culls {} grains", culled[1]);
        hiz_culled += culled[2];
        let subset = render(&instances(&mut kept.iter().map(|&i| i as usize)));
        assert!(all == subset, "culling changed the image (splat factor {splat_factor})");
    }
    assert!(hiz_culled > 0, "the Hi-Z test culls grains here");
}
