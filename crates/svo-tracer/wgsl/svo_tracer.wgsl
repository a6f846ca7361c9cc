// WGSL twin of crates/svo-tracer: cone tracing of a pre-filtered sparse voxel octree
// (Heitz & Neyret 2012, §4, §5.3-5.5, Algorithm 1). Composed after svo_brick (the octree
// and its sampler, bindings 3-7), abuffer_mask (the (θ, v) table lookup and mask
// operations) and smith_micro (Λ, eq. 17, the eq. 13 lobe), and generated/svo_tracer.wgsl
// (GpuCamera, GpuTraceSettings and the constants, from the Rust source). Each function
// mirrors the Rust function named in its comment, operation for operation;
// tests/svo_tracer_gpu.rs compares whole cones with the CPU reference.
//
// The mask table's words (abuffer_mask::MaskTable::words) are bound at binding 8.

@group(0) @binding(8) var<storage, read> svo_masks: array<u32>;

// Rust: camera::Cone (the pixel cone) or the shadow cone of trace::light_visibility.
struct SvoCone {
    origin: vec3<f32>,
    direction: vec3<f32>,
    right: vec3<f32>,
    up: vec3<f32>,
    // Pixel cones: spread, aperture, focus, lens (0/1). Shadow cones: start width,
    // light diameter, light distance, 2.
    spread: f32,
    aperture: f32,
    focus: f32,
    kind: u32,
}

// Rust: trace::ConeResult.
struct SvoConeResult {
    radiance: vec3<f32>,
    coverage: f32,
    elements: u32,
}

// Rust: Camera::pixel_cone.
fn svo_pixel_cone(camera: GpuCamera, x: u32, y: u32) -> SvoCone {
    let pixel_size = camera.position_pixel_size.w;
    let u = (f32(x) + 0.5 - 0.5 * f32(camera.size.x)) * pixel_size;
    let v = (0.5 * f32(camera.size.y) - (f32(y) + 0.5)) * pixel_size;
    let ray = camera.forward.xyz + camera.right.xyz * u + camera.up.xyz * v;
    let length = length(ray);
    let direction = ray / length;
    let right = normalize(camera.right.xyz - direction * dot(camera.right.xyz, direction));
    var cone: SvoCone;
    cone.origin = camera.position_pixel_size.xyz;
    cone.direction = direction;
    cone.right = right;
    cone.up = cross(direction, right);
    cone.spread = pixel_size / length;
    cone.aperture = camera.lens.x;
    cone.focus = camera.lens.y;
    cone.kind = camera.size.z;
    return cone;
}

// Rust: Cone::width, and the shadow cone's widening.
fn svo_cone_width(cone: SvoCone, z: f32) -> f32 {
    if cone.kind == SVO_CONE_SHADOW {
        return cone.spread + (cone.aperture - cone.spread) * clamp(z / cone.focus, 0.0, 1.0);
    }
    let pinhole = z * cone.spread;
    if cone.kind == SVO_CONE_LENS {
        return pinhole + cone.aperture * abs(z - cone.focus) / cone.focus;
    }
    return pinhole;
}

// Rust: Cone::crossed.
fn svo_cone_crossed(cone: SvoCone, z: f32) -> bool {
    return cone.kind == SVO_CONE_LENS && cone.aperture > 0.0 && z > cone.focus;
}

// Rust: trace::box_interval; (enter, exit, hit).
fn svo_box_interval(origin: vec3<f32>, direction: vec3<f32>, lo: vec3<f32>, hi: vec3<f32>) -> vec3<f32> {
    let inverse = 1.0 / direction;
    let a = (lo - origin) * inverse;
    let b = (hi - origin) * inverse;
    let near = min(a, b);
    let far = max(a, b);
    let enter = max(max(max(near.x, near.y), near.z), 0.0);
    let exit = min(min(far.x, far.y), far.z);
    let finite = (bitcast<u32>(exit) & 0x7fffffffu) < 0x7f800000u;
    return vec3<f32>(enter, exit, select(0.0, 1.0, enter <= exit && finite));
}

// Rust: shading::tangent_frame (Duff et al. 2017). Returns (t1, t2) as columns.
fn svo_tangent_frame(n: vec3<f32>) -> mat2x3<f32> {
    let sign = select(-1.0, 1.0, n.z >= 0.0);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    return mat2x3<f32>(
        vec3<f32>(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        vec3<f32>(b, sign + n.y * n.y * a, -n.y),
    );
}

// Rust: shading::lambda (None and the horizon give +∞).
fn svo_lambda(direction: vec3<f32>, slopes: vec3<f32>) -> SmithValue {
    if direction.z <= 0.0 {
        return smith_positive_infinity();
    }
    let lambda = smith_lambda_direction(direction, slopes);
    if lambda.kind == SMITH_NONE {
        return smith_positive_infinity();
    }
    return lambda;
}

// Rust: lambert::rectified; (mean, cdf, density, ratio) of lambert::Rectified.
fn svo_rectified(mu: f32, tau: f32) -> vec4<f32> {
    let one_sided = vec4<f32>(max(mu, 0.0), select(0.0, 1.0, mu > 0.0), 0.0, 0.0);
    if !(tau > 0.0) {
        return one_sided;
    }
    let x = mu / tau * SVO_FRAC_1_SQRT_2;
    if !(abs(x) < SVO_RECTIFIED_CUTOFF) {
        return one_sided;
    }
    let erfc = smith_erfc(-x);
    let cdf = 0.5 * select(0.0, erfc.value, erfc.kind == SMITH_FINITE);
    let density = exp(-(x * x)) * SVO_FRAC_1_SQRT_2PI;
    let mean = max(mu * cdf + tau * density, 0.0);
    return vec4<f32>(mean, cdf, density, mu / tau);
}

// Rust: lambert::expected_clamped_cosine.
fn svo_expected_clamped_cosine(view: vec3<f32>, light: vec3<f32>, sigma: f32) -> f32 {
    if !(sigma > 0.0) {
        return max(light.z, 0.0);
    }
    let normalisation = sqrt(1.0 + 2.0 * (sigma * sigma));
    let view_across = sqrt(view.x * view.x + view.y * view.y);
    let light_across = sqrt(light.x * light.x + light.y * light.y);
    let tau_v = sigma * view_across;
    let tau_l = sigma * light_across;
    let lit = svo_rectified(light.z, tau_l);
    let seen = svo_rectified(view.z, tau_v);
    if !(tau_v > 0.0 && tau_l > 0.0 && seen.x > 0.0) {
        return lit.x / normalisation;
    }
    let rho = clamp((view.x * light.x + view.y * light.y) / (view_across * light_across), -1.0, 1.0);
    let a = seen.w;
    let b = lit.w;
    let a2 = a * a;
    let b2 = b * b;
    let hermite = 0.5
        + rho
            * (a * b * (1.0 / 6.0)
                + rho * ((a2 - 1.0) * (b2 - 1.0) * (1.0 / 24.0) + rho * (a * (a2 - 3.0)) * (b * (b2 - 3.0)) * (1.0 / 120.0)));
    let series = rho * (seen.y * lit.y) + (seen.z * lit.z) * (rho * rho) * hermite;
    let product = max(seen.x * lit.x + (tau_v * tau_l) * series, 0.0);
    return product / (seen.x * normalisation);
}

// Rust: shading::element_radiance. `separate`: Filtering::Separate.
fn svo_element_radiance(voxel: SvoRawVoxel, view: vec3<f32>, light: vec3<f32>, settings: GpuTraceSettings, separate: bool, visibility: f32) -> vec3<f32> {
    let n = voxel.normal;
    if dot(n, n) < 0.5 {
        return vec3<f32>(0.0);
    }
    let frame = svo_tangent_frame(n);
    let v = vec3<f32>(dot(view, frame[0]), dot(view, frame[1]), dot(view, n));
    let l = vec3<f32>(dot(light, frame[0]), dot(light, frame[1]), dot(light, n));
    let sigma = select(min(sqrt(max(voxel.slope_variance, 0.0)), SMITH_MAX_SLOPE_DEVIATION), 0.0, separate);
    let slopes = smith_slope_deviation(sigma, sigma);
    let lambda_view = svo_lambda(v, slopes);
    let lambda_light = svo_lambda(l, slopes);
    let lit = svo_expected_clamped_cosine(v, l, sigma);
    var out = vec3<f32>(0.0);
    for (var c = 0u; c < 3u; c++) {
        let correlation = select(voxel.correlation[c], 0.0, separate);
        let correlated = vec2<f32>(voxel.mean_attribute[c], correlation);
        var visible = voxel.mean_attribute[c];
        if smith_attribute_is_valid(correlated) {
            let seen = smith_visible_mean_attribute(correlated, lambda_view, lambda_light);
            if seen.kind == SMITH_FINITE {
                visible = seen.value;
            }
        }
        out[c] = settings.shading.y * SVO_FRAC_1_PI * visible * lit;
    }
    var specular = 0.0;
    if settings.shading.z > 0.0 {
        let brdf = smith_slope_deviation(settings.shading.w, settings.shading.w);
        if brdf.z != 0.0 {
            let lobe = smith_shade(v, l, slopes, brdf, vec2<f32>(1.0, 0.0), 1.0);
            specular = settings.shading.z * select(0.0, lobe.value, lobe.kind == SMITH_FINITE);
        }
    }
    return (out + specular) * (settings.shading.x * visibility);
}

// Rust: abuffer_mask::exact_coverage, in f32 (the Rust computes in f64).
fn svo_exact_coverage(theta: f32, v: f32) -> f32 {
    let normal = vec2<f32>(cos(theta), sin(theta));
    var square = array<vec2<f32>, 4>(vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0), vec2<f32>(-1.0, 1.0));
    var clipped: array<vec2<f32>, 5>;
    var count = 0u;
    for (var i = 0u; i < 4u; i++) {
        let a = square[i];
        let b = square[(i + 1u) % 4u];
        let fa = dot(a, normal) - v;
        let fb = dot(b, normal) - v;
        if fa <= 0.0 {
            clipped[count] = a;
            count += 1u;
        }
        if (fa < 0.0 && fb > 0.0) || (fa > 0.0 && fb < 0.0) {
            clipped[count] = a + (b - a) * (fa / (fa - fb));
            count += 1u;
        }
    }
    var twice_area = 0.0;
    for (var i = 0u; i < count; i++) {
        let p = clipped[i];
        let q = clipped[(i + 1u) % count];
        twice_area += p.x * q.y - p.y * q.x;
    }
    return clamp(abs(twice_area) / 8.0, 0.0, 1.0);
}

// Rust: trace::coarsest_read_level (`top` the tree's top level; `svo_clamped_lod` is
// svo-brick's, as the sampler clamps).
fn svo_coarsest_read_level(tree: OctreeUniforms, lod: f32) -> u32 {
    let top = tree.shape.x - 1u;
    let clamped = svo_clamped_lod(tree, lod);
    let level = floor(clamped);
    let blended = floor((clamped - level) * SVO_FRACTION_STEPS) > 0.0;
    return min(u32(level) + select(0u, 1u, blended), top);
}

// Rust: trace::sampled_level.
fn svo_sampled_level(tree: OctreeUniforms, lod: f32, model: u32) -> u32 {
    if model == SVO_MODEL_NEAREST {
        return min(u32(floor(svo_clamped_lod(tree, lod) + 0.5)), tree.shape.x - 1u);
    }
    return svo_coarsest_read_level(tree, lod);
}

// Rust: trace::error_bound.
fn svo_error_bound(tree: OctreeUniforms, lod: f32, voxel: f32) -> f32 {
    return SVO_ERROR_BOUND_FACTOR * f32(1u << svo_coarsest_read_level(tree, lod)) * voxel;
}

fn svo_table_mask(table: MaskTableUniforms, theta: f32, v: f32) -> vec4<u32> {
    let first = abuffer_mask_word_offset(abuffer_cell_index(theta, v, table), table);
    var mask = vec4<u32>(0u);
    for (var w = 0u; w < min(table.words_per_mask, 4u); w++) {
        mask[w] = svo_masks[first + w];
    }
    return mask;
}

// The state of trace::march between two elements that add coverage.
struct SvoMarch {
    z: f32,
    exit: f32,
    steps: u32,
    elements: u32,
    mask: vec4<u32>,
    alpha: f32,
    proof_z: f32,
    proof_lower: f32,
    has_proof: bool,
    region: SvoEmptyRegion,
    done: bool,
}

// An element that adds coverage: its sample, position, level of detail and added coverage.
struct SvoElement {
    voxel: SvoRawVoxel,
    z: f32,
    lod: f32,
    half_length: f32,
    added: f32,
    found: bool,
}

// Rust: trace::march, up to the entry of the loop.
fn svo_march_begin(tree: OctreeUniforms, cone: SvoCone, settings: GpuTraceSettings) -> SvoMarch {
    var state: SvoMarch;
    let lo = tree.origin_inverse_size.xyz;
    let hi = lo + tree.voxel_size.x * f32(tree.counts.z);
    let interval = svo_box_interval(cone.origin, cone.direction, lo, hi);
    state.done = interval.z == 0.0;
    let start = max(interval.x, 0.0);
    state.z = start + svo_half_length(tree, cone, settings, start);
    state.exit = interval.y;
    return state;
}

fn svo_half_length(tree: OctreeUniforms, cone: SvoCone, settings: GpuTraceSettings, z: f32) -> f32 {
    return max(0.5 * svo_cone_width(cone, z), settings.background_floor.w * tree.voxel_size.x);
}

// Rust: the loop of trace::march, to the next element that adds coverage (found = false:
// the cone ended).
fn svo_march_next(tree: OctreeUniforms, table: MaskTableUniforms, cone: SvoCone, settings: GpuTraceSettings, state: ptr<function, SvoMarch>) -> SvoElement {
    var element: SvoElement;
    let voxel = tree.voxel_size.x;
    let model = settings.model_limits.x;
    let skip = settings.model_limits.z != 0u;
    loop {
        if (*state).done || !((*state).z - svo_half_length(tree, cone, settings, (*state).z) < (*state).exit) || (*state).steps >= settings.model_limits.y {
            (*state).done = true;
            return element;
        }
        (*state).steps += 1u;
        let z = (*state).z;
        let width = svo_cone_width(cone, z);
        let r = 0.5 * width;
        let l = svo_half_length(tree, cone, settings, z);
        let lod = log2(max(width / voxel, 1.17549435e-38));
        let p = cone.origin + cone.direction * z;
        let finest = svo_sampled_level(tree, lod, model);
        if skip {
            let g = (*state).region;
            let in_region = g.found && g.level >= finest && all(p >= g.min) && all(p < g.max);
            let far = (*state).has_proof && (*state).proof_lower - (z - (*state).proof_z) - svo_error_bound(tree, lod, voxel) > l + 2.0 * r;
            if in_region || far {
                (*state).z = z + 2.0 * l;
                continue;
            }
        }
        var sample: SvoSample;
        if model == SVO_MODEL_NEAREST {
            sample = svo_sample_nearest(tree, p, lod);
        } else {
            sample = svo_sample(tree, p, lod);
        }
        (*state).elements += 1u;
        if !sample.inside {
            (*state).done = true;
            return element;
        }
        let s = sample.voxel;
        if skip {
            var region: SvoEmptyRegion;
            if all(s.normal == vec3<f32>(0.0)) && s.distance > 0.0 {
                region = svo_empty_region(tree, p, finest);
                if region.inside {
                    region.found = false;
                }
            }
            (*state).region = region;
            (*state).proof_z = z;
            (*state).proof_lower = select(s.distance - svo_error_bound(tree, lod, voxel), s.distance, region.found);
            (*state).has_proof = true;
        }
        (*state).z = z + 2.0 * l;
        if model == SVO_MODEL_ALPHA_BLEND {
            let n = s.normal;
            let local = vec3<f32>(dot(n, cone.right), dot(n, cone.up), dot(n, cone.direction));
            let plane = abuffer_half_plane(s.distance, local, r, l);
            let opacity = svo_exact_coverage(plane.x, plane.y);
            if opacity > 0.0 {
                let added = (1.0 - (*state).alpha) * opacity;
                (*state).alpha += added;
                if (*state).alpha >= 1.0 - 1.0 / 1024.0 {
                    (*state).done = true;
                }
                return SvoElement(s, z, lod, l, added, true);
            }
        } else {
            var mask = vec4<u32>(0u);
            if model == SVO_MODEL_NEAREST {
                mask = select(vec4<u32>(0u), vec4<u32>(0xffffffffu), s.distance <= 0.0);
            } else {
                let n = s.normal;
                let sign = select(1.0, -1.0, svo_cone_crossed(cone, z));
                let local = vec3<f32>(sign * dot(n, cone.right), sign * dot(n, cone.up), dot(n, cone.direction));
                let plane = abuffer_half_plane(s.distance, local, r, l);
                mask = svo_table_mask(table, plane.x, plane.y);
            }
            let added = abuffer_mask_popcount(abuffer_mask_difference(mask, (*state).mask));
            if added > 0u {
                (*state).mask = abuffer_mask_union((*state).mask, mask);
                if abuffer_mask_popcount((*state).mask) >= table.sample_count {
                    (*state).done = true;
                }
                return SvoElement(s, z, lod, l, f32(added) * (1.0 / f32(table.sample_count)), true);
            }
        }
    }
    return element;
}

// Rust: the coverage at the end of trace::march.
fn svo_march_coverage(table: MaskTableUniforms, settings: GpuTraceSettings, state: SvoMarch) -> f32 {
    if settings.model_limits.x == SVO_MODEL_ALPHA_BLEND {
        return state.alpha;
    }
    return f32(abuffer_mask_popcount(state.mask)) * (1.0 / f32(table.sample_count));
}

// Rust: trace::light_visibility.
fn svo_light_visibility(tree: OctreeUniforms, table: MaskTableUniforms, surface: vec3<f32>, normal: vec3<f32>, width: f32, settings: GpuTraceSettings) -> f32 {
    let to_light = settings.light.xyz - surface;
    let distance = length(to_light);
    if !(distance > 0.0) {
        return 1.0;
    }
    let direction = to_light / distance;
    var cone: SvoCone;
    cone.direction = direction;
    let frame = svo_tangent_frame(direction);
    cone.right = frame[0];
    cone.up = frame[1];
    cone.spread = width;
    cone.aperture = 2.0 * settings.light.w;
    cone.focus = distance;
    cone.kind = SVO_CONE_SHADOW;
    let floor = settings.background_floor.w * tree.voxel_size.x;
    let first = max(0.5 * svo_cone_width(cone, 0.0), floor);
    let r1 = 0.5 * svo_cone_width(cone, first);
    let l1 = max(0.5 * svo_cone_width(cone, first), floor);
    let reach = sqrt(l1 * l1 + 2.0 * (r1 * r1));
    let lift = reach - first * dot(normal, direction) + SVO_SHADOW_LIFT_VOXELS * tree.voxel_size.x;
    cone.origin = surface + normal * lift;
    var state = svo_march_begin(tree, cone, settings);
    loop {
        let element = svo_march_next(tree, table, cone, settings, &state);
        if !element.found {
            break;
        }
    }
    return 1.0 - svo_march_coverage(table, settings, state);
}

// Rust: trace::axis_step: (the point, the axis parameter in w).
fn svo_axis_step(p: vec3<f32>, direction: vec3<f32>, t: f32, anchor: vec3<f32>, n: vec3<f32>, height: f32, half_length: f32) -> vec4<f32> {
    let slope = dot(n, direction);
    var next = t;
    if slope != 0.0 {
        next = clamp(t - (height + dot(n, p + direction * t - anchor)) / slope, -half_length, half_length);
    }
    let a = p + direction * next;
    return vec4<f32>(a - n * (height + dot(n, a - anchor)), next);
}

// Rust: trace::shading_points: (where the element is sampled, that point on the last plane).
fn svo_shading_points(tree: OctreeUniforms, p: vec3<f32>, direction: vec3<f32>, voxel: SvoRawVoxel, lod: f32, half_length: f32, refine: bool) -> mat2x3<f32> {
    var anchor = p;
    var n = voxel.normal;
    var height = voxel.distance;
    var step = svo_axis_step(p, direction, 0.0, anchor, n, height, half_length);
    if refine && lod < 1.0 {
        for (var k = 0u; k < SVO_SHADING_POINT_REFINEMENTS; k++) {
            let there = svo_sample(tree, step.xyz, lod);
            if !there.inside || all(there.voxel.normal == vec3<f32>(0.0)) {
                break;
            }
            anchor = step.xyz;
            n = there.voxel.normal;
            height = there.voxel.distance;
            step = svo_axis_step(p, direction, step.w, anchor, n, height, half_length);
        }
    }
    let sampled = p + (step.xyz - p) * clamp(1.0 - lod, 0.0, 1.0);
    return mat2x3<f32>(sampled, sampled - n * (height + dot(n, sampled - anchor)));
}

// Rust: trace::surface_voxel.
fn svo_surface_voxel(tree: OctreeUniforms, voxel: SvoRawVoxel, point: vec3<f32>, lod: f32, model: u32) -> SvoRawVoxel {
    if model == SVO_MODEL_NEAREST {
        return voxel;
    }
    let there = svo_sample(tree, point, lod);
    if there.inside && any(there.voxel.normal != vec3<f32>(0.0)) {
        return there.voxel;
    }
    return voxel;
}

// Rust: trace::trace_cone.
fn svo_trace_cone(tree: OctreeUniforms, table: MaskTableUniforms, cone: SvoCone, settings: GpuTraceSettings) -> SvoConeResult {
    let view = -cone.direction;
    let separate = settings.model_limits.x == SVO_MODEL_SEPARATE;
    var radiance = vec3<f32>(0.0);
    var shadows = 0u;
    var visibility = 1.0;
    var state = svo_march_begin(tree, cone, settings);
    loop {
        let element = svo_march_next(tree, table, cone, settings, &state);
        if !element.found {
            break;
        }
        let p = cone.origin + cone.direction * element.z;
        let refine = settings.model_limits.x != SVO_MODEL_NEAREST;
        let points = svo_shading_points(tree, p, cone.direction, element.voxel, element.lod, element.half_length, refine);
        let surface = points[1];
        let shading = svo_surface_voxel(tree, element.voxel, points[0], element.lod, settings.model_limits.x);
        let to_light = settings.light.xyz - surface;
        let light = select(vec3<f32>(0.0), normalize(to_light), dot(to_light, to_light) > 0.0);
        if shadows < settings.model_limits.w {
            let r = 0.5 * svo_cone_width(cone, element.z);
            visibility = svo_light_visibility(tree, table, surface, element.voxel.normal, 2.0 * r, settings);
            shadows += 1u;
        }
        radiance += svo_element_radiance(shading, view, light, settings, separate, visibility) * element.added;
    }
    let coverage = svo_march_coverage(table, settings, state);
    return SvoConeResult(radiance + settings.background_floor.xyz * (1.0 - coverage), coverage, state.elements);
}
