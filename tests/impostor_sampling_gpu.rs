//! CPU = GPU differential tests of the impostor sampling part of
//! `shaders/octahedral_map.wgsl` (compact layout, view frames, grain rays, planar /
//! spherical / mixed sampling) against `octahedral_map::{compact, sampling, ViewFrame}`.
//!
//! Not bit-identical: the GPU may contract multiply-adds into FMAs and computes
//! `normalize`, `length`, `sqrt` and the division to within a few ulp (WGSL's accuracy
//! bounds), so float results differ by the rounding of a few operations. How much that
//! moves each result depends on its conditioning, which the test estimates per query:
//! it moves each of the query's 14 scalar inputs by [`PERTURBATION_ULPS`] ulp up and down
//! (28 CPU samples) and measures the spread of the CPU's own result. A result may differ
//! from the CPU's by at most 4 times that spread plus a rounding floor of the last
//! operations ([`FLOOR_ULPS`] ulp of the result's scale); the worst ratio to this
//! allowance is printed. A discrete decision (which Listing 1 cell, hit or miss at
//! `d = R`, `d = ρ`, `|cos| = MIN_PLANE_COSINE`) may differ only where the CPU's own
//! decision flips under those perturbations (the query lies within rounding of the
//! threshold); such queries are counted and printed, and all the others are compared
//! in full (at least 99 % of the random and special queries; rays along the view
//! directions lie exactly on Listing 1 grid vertices and may all flip).

use glam::{Quat, Vec2, Vec3, Vec4};
use integration_tests::{SPECIAL_F32, gpu, random_unit_directions};
use octahedral_map::sampling::MISS_TEXTURE_COORDINATE;
use octahedral_map::{
    CompactViews, GrainRay, ImpostorSample, ImpostorSampler, OctahedralViews, SamplingMode, ViewFrame, ViewLayout,
    ViewSelection,
};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};
use shader_registry::kernel_io::octahedral_map::ImpostorRayQuery;

const SUBDIVISIONS: [u32; 4] = [1, 2, 8, 12];
const OUTER_RADIUS: f32 = 1.3;
const INNER_RADIUS: f32 = 0.7;

/// How far (in ulp) the perturbed CPU samples move each input: the order of the
/// rounding of the few operations where CPU and GPU may round differently.
const PERTURBATION_ULPS: u32 = 4;

/// The rounding floor: CPU and GPU each round their last few operations (a division,
/// within 2.5 ulp in WGSL, and a multiply-add or two) by up to ~4 ulp of the result's
/// scale; a difference of 8 ulp needs no sensitivity to explain it.
const FLOOR_ULPS: f32 = 8.0;

/// The fraction of the random and special queries (not the view-aligned ones) that must
/// be compared in full: a random query lies within a few ulp of one of the ~10
/// thresholds with probability ~1e-5, so 1 % is ample.
const MIN_COMPARED: f64 = 0.99;

fn kernel_source() -> String {
    shader_registry::test_kernel_source("impostor_sampling_differential").unwrap_or_else(|e| panic!("{e}"))
}

fn query(origin: Vec3, direction: Vec3, centre: Vec3, scale: f32, rotation: Vec4) -> ImpostorRayQuery {
    ImpostorRayQuery {
        world_origin: origin.extend(0.0),
        world_direction: direction.extend(0.0),
        centre_scale: centre.extend(scale),
        rotation,
    }
}

fn cpu_ray(q: &ImpostorRayQuery) -> GrainRay {
    GrainRay::from_world(
        q.world_origin.truncate(),
        q.world_direction.truncate(),
        q.centre_scale.truncate(),
        q.centre_scale.w,
        Quat::from_vec4(q.rotation),
    )
}

/// Random grains (centre, scale, rotation) seen by random eyes 1.05 R to 20 R away,
/// aimed at random points within 1.4 R of the centre (so that `d` covers `[0, 1.4 R]`),
/// plus rays from inside the proxy sphere and rays along view directions.
fn random_queries(count: usize, seed: u64) -> Vec<ImpostorRayQuery> {
    let mut rng = SmallRng::seed_from_u64(seed);
    let directions = random_unit_directions(3 * count, seed + 1);
    (0..count)
        .map(|i| {
            let centre =
                Vec3::new(rng.random_range(-50.0..50.0), rng.random_range(-50.0..50.0), rng.random_range(-5.0..5.0));
            let scale = rng.random_range(0.2..3.0_f32);
            let rotation = Vec4::from(Quat::from_axis_angle(directions[3 * i], rng.random_range(0.0..6.3)));
            let distance = if i % 10 == 0 { rng.random_range(0.0..0.8) } else { rng.random_range(1.05..20.0) };
            let eye = centre + directions[3 * i + 1] * (distance * OUTER_RADIUS * scale);
            let target = centre + directions[3 * i + 2] * (rng.random_range(0.0..1.4) * OUTER_RADIUS * scale);
            let unnormalized = rng.random_range(0.01..100.0_f32);
            query(eye, (target - eye) * unnormalized, centre, scale, rotation * rng.random_range(0.5..2.0))
        })
        .collect()
}

/// A valid query with each of its 14 scalar inputs replaced in turn by every special
/// value, and pairs of special values in the origin and direction.
fn special_queries() -> Vec<ImpostorRayQuery> {
    let base = [3.0, 0.5, 4.0, -1.0, -0.1, -1.2, 0.2, 0.1, 0.3, 1.5, 0.1, 0.2, 0.3, 0.9];
    let mut values = SPECIAL_F32.to_vec();
    values.extend([1e20, -1e37, 1e-20, 1.0]);
    let from = |s: [f32; 14]| {
        query(
            Vec3::new(s[0], s[1], s[2]),
            Vec3::new(s[3], s[4], s[5]),
            Vec3::new(s[6], s[7], s[8]),
            s[9],
            Vec4::new(s[10], s[11], s[12], s[13]),
        )
    };
    let mut queries = vec![from(base)];
    for slot in 0..14 {
        for &v in &values {
            let mut s = base;
            s[slot] = v;
            queries.push(from(s));
        }
    }
    for &a in &values {
        for &b in &values {
            queries.push(query(Vec3::new(a, 0.3, 2.0), Vec3::new(-0.2, b, -1.0), Vec3::ZERO, 1.0, Vec4::W));
            queries.push(query(Vec3::new(0.1, 0.2, 3.0), Vec3::new(a, b, -1.0), Vec3::ZERO, 1.0, Vec4::W));
        }
    }
    // Origins on the proxy sphere, at the centre, zero and axis directions.
    for d in [Vec3::X, Vec3::NEG_Y, Vec3::Z, Vec3::ZERO] {
        queries.push(query(d, -d, Vec3::ZERO, 1.0, Vec4::W));
        queries.push(query(Vec3::ZERO, d, Vec3::ZERO, 1.0, Vec4::W));
    }
    queries
}

/// Rays exactly along every view direction of `views`, from 3 R away, slightly offset.
fn view_aligned_queries(views: OctahedralViews) -> Vec<ImpostorRayQuery> {
    (0..views.view_count())
        .map(|i| {
            let omega = views.view_direction(i).unwrap();
            let frame = ViewFrame::from_direction(omega).unwrap();
            let origin = omega * 3.0 * OUTER_RADIUS + frame.right * 0.3 - frame.up * 0.2;
            query(origin, -omega, Vec3::ZERO, 1.0, Vec4::W)
        })
        .collect()
}

/// The Listing 1 index of view `k` of `sample`, whose indices are in `layout`.
fn listing_index(views: OctahedralViews, layout: ViewLayout, sample: &ImpostorSample, k: usize) -> u32 {
    let index = sample.indices[k];
    match layout {
        ViewLayout::Listing1 => index,
        ViewLayout::Compact => CompactViews::new(views).listing_index(index).unwrap_or(index),
    }
}

/// `x` moved by `ulps` ulp up (`up`) or down.
fn nudged(x: f32, ulps: u32, up: bool) -> f32 {
    (0..ulps).fold(x, |x, _| if up { x.next_up() } else { x.next_down() })
}

/// The query with each of its 14 scalar inputs moved by [`PERTURBATION_ULPS`] ulp up and
/// down, one at a time (28 queries).
fn perturbations(q: &ImpostorRayQuery) -> Vec<ImpostorRayQuery> {
    let scalars = [
        q.world_origin.truncate().to_array().to_vec(),
        q.world_direction.truncate().to_array().to_vec(),
        q.centre_scale.to_array().to_vec(),
        q.rotation.to_array().to_vec(),
    ]
    .concat();
    let from = |s: &[f32]| {
        query(
            Vec3::new(s[0], s[1], s[2]),
            Vec3::new(s[3], s[4], s[5]),
            Vec3::new(s[6], s[7], s[8]),
            s[9],
            Vec4::new(s[10], s[11], s[12], s[13]),
        )
    };
    let mut out = Vec::with_capacity(28);
    for slot in 0..scalars.len() {
        for up in [false, true] {
            let mut s = scalars.clone();
            s[slot] = nudged(s[slot], PERTURBATION_ULPS, up);
            out.push(from(&s));
        }
    }
    out
}

/// Whether two samples take the same discrete decisions: the four views, hit or miss of
/// the proxy, and which view coordinates are misses.
fn same_decisions(a: &ImpostorSample, b: &ImpostorSample) -> bool {
    let miss = Vec2::splat(MISS_TEXTURE_COORDINATE);
    a.indices == b.indices
        && a.proxy_hit == b.proxy_hit
        && (0..4).all(|k| (a.view_texture_coordinates(k) == miss) == (b.view_texture_coordinates(k) == miss))
}

/// The differences of `b` from `a` that the tolerances bound, each in its own scale:
/// `[uv, weight, ratio]`. Texture coordinates relative to the origin's distance in units
/// of R (rounding grows with it; the closest point cancels it) and, for planar points,
/// times `|cos|` (`P = c − direction·(c·ω)/cos` amplifies the rounding of `c` by
/// `1/|cos|`); `d/R` relative to the origin's distance; weights per unit of `n − 1`
/// (Listing 1 scales the local direction by `n − 1` into `(u, v)`).
fn differences(
    views: OctahedralViews,
    layout: ViewLayout,
    mode: SamplingMode,
    ray: &GrainRay,
    a: &ImpostorSample,
    b: &ImpostorSample,
) -> [f32; 3] {
    let mut uv = 0.0_f32;
    for k in 0..4 {
        let omega = views.view_direction(listing_index(views, layout, a, k)).unwrap_or(Vec3::Z);
        let amplification = if mode == SamplingMode::Spherical { 1.0 } else { ray.direction.dot(omega).abs().min(1.0) };
        uv = uv.max(a.view_texture_coordinates(k).distance(b.view_texture_coordinates(k)) * amplification);
    }
    let magnitude = (ray.origin.length() / OUTER_RADIUS).max(1.0);
    let edges = (views.subdivisions().max(2) - 1) as f32;
    [
        uv / magnitude,
        (a.weights - b.weights).abs().max_element() / edges,
        (a.distance_ratio - b.distance_ratio).abs() / magnitude,
    ]
}

#[test]
fn impostor_samples_match_the_cpu_reference() {
    let source = kernel_source();
    let mut total = 0;
    for n in SUBDIVISIONS {
        let views = OctahedralViews::new(n).unwrap();
        let mut queries = random_queries(6_000, u64::from(n));
        queries.extend(special_queries());
        // View-aligned rays lie exactly on Listing 1 grid vertices: the GPU's rounding of
        // the direction may pick either neighbouring cell there, so they are counted apart.
        let aligned_from = queries.len();
        queries.extend(view_aligned_queries(views));
        for mode in SamplingMode::ALL {
            for layout in [ViewLayout::Listing1, ViewLayout::Compact] {
                for selection in [ViewSelection::PerFragment, ViewSelection::PerGrainFromEye] {
                    let sampler =
                        ImpostorSampler::new(views, OUTER_RADIUS, INNER_RADIUS, mode, layout, selection).unwrap();
                    let uniforms = bytemuck::bytes_of(&sampler.uniforms()).to_vec();
                    let gpu_samples: Vec<ImpostorSample> =
                        gpu().compute_map(&source, "impostor_samples", &uniforms, &queries).unwrap();
                    let (mut worst, mut worst_ratio, mut exact, mut near_threshold, mut near_aligned) =
                        ([0.0_f32; 3], 0.0_f32, 0, 0, 0);
                    for (i, (q, g)) in queries.iter().zip(&gpu_samples).enumerate() {
                        let ray = cpu_ray(q);
                        let c = sampler.sample(&ray);
                        let context = || {
                            format!(
                                "n={n} {mode:?} {layout:?} {selection:?}: {q:?}\nlocal ray {ray:?}\nCPU {c:?}\nGPU {g:?}"
                            )
                        };
                        if c == *g {
                            exact += 1;
                            continue;
                        }
                        let perturbed: Vec<ImpostorSample> =
                            perturbations(q).iter().map(|p| sampler.sample(&cpu_ray(p))).collect();
                        if !same_decisions(&c, g) {
                            let flips = perturbed.iter().any(|p| !same_decisions(&c, p));
                            assert!(flips, "a decision differs where the CPU's is stable: {}", context());
                            if i >= aligned_from {
                                near_aligned += 1;
                            } else {
                                near_threshold += 1;
                            }
                            continue;
                        }
                        let error = differences(views, layout, mode, &ray, &c, g);
                        let mut spread = [0.0_f32; 3];
                        for p in perturbed.iter().filter(|p| same_decisions(&c, p)) {
                            let d = differences(views, layout, mode, &ray, &c, p);
                            spread = std::array::from_fn(|k| spread[k].max(d[k]));
                        }
                        // The floor in each difference's own scale (see `differences`).
                        let floor = FLOOR_ULPS * f32::EPSILON;
                        for k in 0..3 {
                            let allowed = 4.0 * spread[k] + floor;
                            assert!(
                                error[k] <= allowed,
                                "{} differs by {:e} (allowed {allowed:e}, CPU spread {:e}): {}",
                                ["uv", "weight", "d/R"][k],
                                error[k],
                                spread[k],
                                context()
                            );
                            worst[k] = worst[k].max(error[k]);
                            worst_ratio = worst_ratio.max(error[k] / allowed);
                        }
                    }
                    let aligned = queries.len() - aligned_from;
                    let compared = aligned_from - near_threshold;
                    println!(
                        "n={n} {mode:?} {layout:?} {selection:?}: {} rays, {exact} bit-identical; max uv diff {:e}, \
                         weight diff per edge {:e}, d/R diff {:e} ({worst_ratio:.3} of the allowed); {near_threshold} \
                         (+ {near_aligned} of {aligned} view-aligned) differ within rounding of a decision",
                        queries.len(),
                        worst[0],
                        worst[1],
                        worst[2]
                    );
                    assert!(
                        compared as f64 >= MIN_COMPARED * aligned_from as f64,
                        "n={n} {mode:?}: only {compared} of {aligned_from} queries compared in full"
                    );
                    total += queries.len();
                }
            }
        }
    }
    assert!(total > 100_000);
}

#[test]
fn grain_rays_match_the_cpu_reference() {
    let source = kernel_source();
    let mut queries = random_queries(20_000, 99);
    queries.extend(special_queries());
    let uniforms = ImpostorSampler::new(
        OctahedralViews::new(8).unwrap(),
        OUTER_RADIUS,
        INNER_RADIUS,
        SamplingMode::Mixed,
        ViewLayout::Listing1,
        ViewSelection::PerFragment,
    )
    .unwrap()
    .uniforms();
    let gpu_rays: Vec<[Vec4; 2]> =
        gpu().compute_map(&source, "grain_rays", bytemuck::bytes_of(&uniforms), &queries).unwrap();
    // Differences relative to the origin's scale (the direction is unit); allowed: 4
    // times the spread of the CPU's own ray under perturbations of the query by rounding,
    // plus the rounding floor (see the module documentation).
    let relative = |a: &GrainRay, b: &GrainRay| {
        let scale = a.origin.abs().max_element().max(1.0);
        ((a.origin - b.origin).abs().max_element() / scale).max((a.direction - b.direction).abs().max_element())
    };
    let (mut worst, mut worst_ratio, mut exact, mut near_decision) = (0.0_f32, 0.0_f32, 0, 0);
    for (q, g) in queries.iter().zip(&gpu_rays) {
        let c = cpu_ray(q);
        let gpu_ray = GrainRay { origin: g[0].truncate(), direction: g[1].truncate(), invalid_origin: g[0].w == 1.0 };
        if c == gpu_ray {
            exact += 1;
            continue;
        }
        let perturbed: Vec<GrainRay> = perturbations(q).iter().map(cpu_ray).collect();
        if c.invalid_origin != gpu_ray.invalid_origin {
            assert!(
                perturbed.iter().any(|p| p.invalid_origin != c.invalid_origin),
                "{q:?}: validity differs where the CPU's is stable: CPU {c:?} GPU {g:?}"
            );
            near_decision += 1;
            continue;
        }
        let spread = perturbed
            .iter()
            .filter(|p| p.invalid_origin == c.invalid_origin)
            .map(|p| relative(&c, p))
            .fold(0.0, f32::max);
        let error = relative(&c, &gpu_ray);
        let allowed = 4.0 * spread + FLOOR_ULPS * f32::EPSILON;
        assert!(error <= allowed, "{q:?}: differs by {error:e} (allowed {allowed:e}): CPU {c:?} GPU {g:?}");
        worst = worst.max(error);
        worst_ratio = worst_ratio.max(error / allowed);
    }
    println!(
        "{} grain rays, {exact} bit-identical, max relative difference {worst:e} ({worst_ratio:.3} of the allowed), \
         {near_decision} differ in validity within rounding",
        queries.len()
    );
    assert!(
        (queries.len() - near_decision) as f64 >= MIN_COMPARED * queries.len() as f64,
        "only {} of {} grain rays compared",
        queries.len() - near_decision,
        queries.len()
    );
}

#[test]
fn compact_indices_and_view_frames_match_the_cpu_reference() {
    let source = kernel_source();
    for n in SUBDIVISIONS.into_iter().chain([3, 33]) {
        let views = OctahedralViews::new(n).unwrap();
        let compact = CompactViews::new(views);
        let uniforms = ImpostorSampler::new(
            views,
            1.5,
            1.0,
            SamplingMode::Planar,
            ViewLayout::Compact,
            ViewSelection::PerFragment,
        )
        .unwrap()
        .uniforms();
        let uniforms = bytemuck::bytes_of(&uniforms);
        let indices: Vec<u32> = (0..views.view_count()).collect();
        let gpu_compact: Vec<[u32; 4]> = gpu().compute_map(&source, "compact_indices", uniforms, &indices).unwrap();
        for (&i, g) in indices.iter().zip(&gpu_compact) {
            assert_eq!(g[0], compact.compact_index(i).unwrap(), "n={n} listing {i}");
            assert_eq!(g[2], compact.view_count());
            if i < compact.view_count() {
                assert_eq!(g[1], compact.listing_index(i).unwrap(), "n={n} compact {i}");
            }
        }
        let points = random_unit_directions(20_000, u64::from(n) + 5);
        let inputs: Vec<Vec4> = points
            .iter()
            .enumerate()
            .map(|(k, p)| (*p * (k % 7) as f32 * 0.3).extend(f32::from_bits(k as u32 % views.view_count())))
            .collect();
        let gpu_frames: Vec<[Vec4; 2]> = gpu().compute_map(&source, "view_frames", uniforms, &inputs).unwrap();
        let (mut worst, mut worst_ratio) = (0.0_f32, 0.0_f32);
        for (input, g) in inputs.iter().zip(&gpu_frames) {
            let frame = ViewFrame::from_direction(views.view_direction(input.w.to_bits()).unwrap()).unwrap();
            // (uv, depth, point back from them) of a point.
            let project = |point: Vec3| {
                let uv = frame.texture_coordinates(point, 1.5);
                let depth = frame.depth(point, 1.5);
                (uv, depth, frame.point_at(uv, depth, 1.5))
            };
            let differences =
                |a: (Vec2, f32, Vec3), b: (Vec2, f32, Vec3)| [a.0.distance(b.0), (a.1 - b.1).abs(), a.2.distance(b.2)];
            let point = input.truncate();
            let cpu = project(point);
            let gpu = (g[0].truncate().truncate(), g[0].z, g[1].truncate());
            // Allowed: 4 times the spread of the CPU's own values under perturbations of
            // the point by rounding, plus the floor in units of the point's scale (the
            // frame's own rounding, computed from the view direction, scales with it).
            let mut spread = [0.0_f32; 3];
            for axis in 0..3 {
                for up in [false, true] {
                    let mut p = point;
                    p[axis] = nudged(p[axis], PERTURBATION_ULPS, up);
                    let d = differences(cpu, project(p));
                    spread = std::array::from_fn(|k| spread[k].max(d[k]));
                }
            }
            let floor = FLOOR_ULPS * f32::EPSILON * (point.length() / 1.5).max(1.0);
            let error = differences(cpu, gpu);
            for k in 0..3 {
                let allowed = 4.0 * spread[k] + floor;
                assert!(
                    error[k] <= allowed,
                    "n={n} {input}: {} differs by {:e} (allowed {allowed:e}): CPU {cpu:?} GPU {g:?}",
                    ["uv", "depth", "point"][k],
                    error[k]
                );
                worst = worst.max(error[k]);
                worst_ratio = worst_ratio.max(error[k] / allowed);
            }
        }
        println!(
            "n={n}: {} view-frame points, max difference {worst:e} ({worst_ratio:.3} of the allowed)",
            inputs.len()
        );
    }
}
