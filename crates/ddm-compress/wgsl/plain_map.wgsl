// WGSL twin of crates/ddm-compress's plain distance map, per box–triangle pair (src/plain.rs,
// src/geometry.rs). Composed after generated/ddm_compress.wgsl, which declares
// PlainGpuNode, PlainGpuTriangle, PlainGpuUniforms and the DDM_PLAIN_* constants from the
// Rust source. Each function mirrors the Rust function named in its comment, operation for
// operation; the traversal over a scene's buffers belongs to the kernel that binds them
// (ddm-render's plain_map_build.wgsl). tests/ddm_plain_map_gpu.rs proves the maps equal
// within the tolerance, and each value at most the exact distance.

// Rust: ddm_compress::geometry::closest_point_on_segment.
fn ddm_closest_point_on_segment(p: vec3<f32>, a: vec3<f32>, b: vec3<f32>) -> vec3<f32> {
    let ab = b - a;
    let length_squared = dot(ab, ab);
    if length_squared <= 0.0 {
        return a;
    }
    return a + ab * clamp(dot(p - a, ab) / length_squared, 0.0, 1.0);
}

// Rust: ddm_compress::geometry::closest_point_on_triangle (Ericson §5.1.5; a degenerate
// triangle as the segment it is).
fn ddm_closest_point_on_triangle(p: vec3<f32>, a: vec3<f32>, b: vec3<f32>, c: vec3<f32>) -> vec3<f32> {
    let ab = b - a;
    let ac = c - a;
    let ap = p - a;
    let normal = cross(ab, ac);
    if dot(normal, normal) <= DDM_DEGENERATE_TRIANGLE_SINE_SQUARED * dot(ab, ab) * dot(ac, ac) {
        let on_ab = ddm_closest_point_on_segment(p, a, b);
        let on_bc = ddm_closest_point_on_segment(p, b, c);
        let on_ca = ddm_closest_point_on_segment(p, c, a);
        var nearest = on_ab;
        if dot(on_bc - p, on_bc - p) < dot(nearest - p, nearest - p) {
            nearest = on_bc;
        }
        if dot(on_ca - p, on_ca - p) < dot(nearest - p, nearest - p) {
            nearest = on_ca;
        }
        return nearest;
    }
    let d1 = dot(ab, ap);
    let d2 = dot(ac, ap);
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let d3 = dot(ab, bp);
    let d4 = dot(ac, bp);
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let d5 = dot(ab, cp);
    let d6 = dot(ac, cp);
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denominator = va + vb + vc;
    if !(abs(denominator) > 0.0) {
        // Degenerate triangle: the nearest of its vertices (the first of equals).
        var nearest = a;
        if dot(b - p, b - p) < dot(nearest - p, nearest - p) {
            nearest = b;
        }
        if dot(c - p, c - p) < dot(nearest - p, nearest - p) {
            nearest = c;
        }
        return nearest;
    }
    let v = vb / denominator;
    let w = vc / denominator;
    return a + ab * v + ac * w;
}

// Rust: ddm_compress::geometry::triangle_overlaps_box's separating-axis test along `axis`
// (corners relative to the box centre, `half` the box's half size).
fn ddm_separated(axis: vec3<f32>, a: vec3<f32>, b: vec3<f32>, c: vec3<f32>, half: vec3<f32>) -> bool {
    if dot(axis, axis) < DDM_DEGENERATE_AXIS_SQUARED {
        return false;
    }
    let pa = dot(a, axis);
    let pb = dot(b, axis);
    let pc = dot(c, axis);
    let r = half.x * abs(axis.x) + half.y * abs(axis.y) + half.z * abs(axis.z);
    return min(min(pa, pb), pc) > r || max(max(pa, pb), pc) < -r;
}

// The separating-axis tests along the cross products of `edge` with the three coordinate
// axes (unrolled: private arrays indexed at run time are slow on some GPUs and on lavapipe).
fn ddm_edge_separates(edge: vec3<f32>, a: vec3<f32>, b: vec3<f32>, c: vec3<f32>, half: vec3<f32>) -> bool {
    return ddm_separated(vec3<f32>(0.0, edge.z, -edge.y), a, b, c, half)
        || ddm_separated(vec3<f32>(-edge.z, 0.0, edge.x), a, b, c, half)
        || ddm_separated(vec3<f32>(edge.y, -edge.x, 0.0), a, b, c, half);
}

// Rust: ddm_compress::geometry::triangle_overlaps_box (the 13 axes of Akenine-Möller's test,
// in the same order: the box's faces, the triangle's normal, the edge × axis products).
fn ddm_triangle_overlaps_box(box_min: vec3<f32>, box_max: vec3<f32>, ta: vec3<f32>, tb: vec3<f32>, tc: vec3<f32>) -> bool {
    let center = (box_min + box_max) * 0.5;
    let half = (box_max - box_min) * 0.5;
    let a = ta - center;
    let b = tb - center;
    let c = tc - center;
    if ddm_separated(vec3<f32>(1.0, 0.0, 0.0), a, b, c, half) || ddm_separated(vec3<f32>(0.0, 1.0, 0.0), a, b, c, half)
        || ddm_separated(vec3<f32>(0.0, 0.0, 1.0), a, b, c, half) {
        return false;
    }
    if ddm_separated(cross(b - a, c - b), a, b, c, half) {
        return false;
    }
    return !(ddm_edge_separates(b - a, a, b, c, half) || ddm_edge_separates(c - b, a, b, c, half)
        || ddm_edge_separates(a - c, a, b, c, half));
}

// Rust: ddm_compress::geometry::segment_distance_squared (Ericson §5.1.9).
fn ddm_segment_distance_squared(p1: vec3<f32>, q1: vec3<f32>, p2: vec3<f32>, q2: vec3<f32>) -> f32 {
    let d1 = q1 - p1;
    let d2 = q2 - p2;
    let r = p1 - p2;
    let a = dot(d1, d1);
    let e = dot(d2, d2);
    let f = dot(d2, r);
    var s = 0.0;
    var t = 0.0;
    if a <= DDM_DEGENERATE_SEGMENT_SQUARED && e <= DDM_DEGENERATE_SEGMENT_SQUARED {
        s = 0.0;
        t = 0.0;
    } else if a <= DDM_DEGENERATE_SEGMENT_SQUARED {
        t = clamp(f / e, 0.0, 1.0);
    } else {
        let c = dot(d1, r);
        if e <= DDM_DEGENERATE_SEGMENT_SQUARED {
            s = clamp(-c / a, 0.0, 1.0);
        } else {
            let b = dot(d1, d2);
            let denominator = a * e - b * b;
            if denominator > 0.0 {
                s = clamp((b * f - c * e) / denominator, 0.0, 1.0);
            }
            t = (b * s + f) / e;
            if t < 0.0 {
                s = clamp(-c / a, 0.0, 1.0);
                t = 0.0;
            } else if t > 1.0 {
                s = clamp((b - c) / a, 0.0, 1.0);
                t = 1.0;
            }
        }
    }
    let gap = (p1 + d1 * s) - (p2 + d2 * t);
    return dot(gap, gap);
}

// Corner `i` of the box of half size `half` centred at the origin (bit k of `i`: +half
// along axis k).
fn ddm_box_corner(i: u32, half: vec3<f32>) -> vec3<f32> {
    return select(-half, half, vec3<bool>((i & 1u) != 0u, (i & 2u) != 0u, (i & 4u) != 0u));
}

// The smallest squared distance from the segment `p q` to the twelve edges of the box of
// half size `half` centred at the origin (each edge once: from corner `i` along each axis
// whose bit `i` lacks, as in the Rust loop).
fn ddm_segment_box_edges_squared(p: vec3<f32>, q: vec3<f32>, half: vec3<f32>) -> f32 {
    var best = 3.4028235e38;
    for (var i = 0u; i < 8u; i++) {
        let corner = ddm_box_corner(i, half);
        if (i & 1u) == 0u {
            best = min(best, ddm_segment_distance_squared(p, q, corner, ddm_box_corner(i | 1u, half)));
        }
        if (i & 2u) == 0u {
            best = min(best, ddm_segment_distance_squared(p, q, corner, ddm_box_corner(i | 2u, half)));
        }
        if (i & 4u) == 0u {
            best = min(best, ddm_segment_distance_squared(p, q, corner, ddm_box_corner(i | 4u, half)));
        }
    }
    return best;
}

// The squared distance from `v` to the box of half size `half` centred at the origin.
fn ddm_point_box_squared(v: vec3<f32>, half: vec3<f32>) -> f32 {
    let gap = v - clamp(v, -half, half);
    return dot(gap, gap);
}

// Rust: ddm_compress::box_triangle_distance (the exact distance less its rounding margin:
// the triangle's corners to the box, the box's corners to the triangle, and the triangle's
// edges to the box's edges).
fn ddm_box_triangle_distance(box_min: vec3<f32>, box_max: vec3<f32>, ta: vec3<f32>, tb: vec3<f32>, tc: vec3<f32>) -> f32 {
    if ddm_triangle_overlaps_box(box_min, box_max, ta, tb, tc) {
        return 0.0;
    }
    let center = (box_min + box_max) * 0.5;
    let half = (box_max - box_min) * 0.5;
    let a = ta - center;
    let b = tb - center;
    let c = tc - center;
    var best = min(min(ddm_point_box_squared(a, half), ddm_point_box_squared(b, half)), ddm_point_box_squared(c, half));
    for (var i = 0u; i < 8u; i++) {
        let p = ddm_box_corner(i, half);
        let gap = p - ddm_closest_point_on_triangle(p, a, b, c);
        best = min(best, dot(gap, gap));
    }
    best = min(best, ddm_segment_box_edges_squared(a, b, half));
    best = min(best, ddm_segment_box_edges_squared(b, c, half));
    best = min(best, ddm_segment_box_edges_squared(c, a, half));
    let extent = max(max(abs(a), abs(b)), abs(c));
    let scale = 1.0 + max(max(abs(center.x), abs(center.y)), abs(center.z)) + max(max(extent.x, extent.y), extent.z)
        + max(max(half.x, half.y), half.z);
    return max(sqrt(best) - DDM_BOX_TRIANGLE_MARGIN * scale, 0.0);
}

// Rust: ddm_compress::plain::rounding_margin.
fn ddm_plain_rounding_margin(box_min: vec3<f32>, box_max: vec3<f32>, magnitude: f32) -> f32 {
    let c = abs((box_min + box_max) * 0.5);
    return DDM_PLAIN_MARGIN * (1.0 + 2.0 * max(max(c.x, c.y), c.z) + magnitude);
}

// Rust: ddm_compress::plain::pair_lower_bound (its value; the CPU's second result, whether
// the exact distance was taken, is not returned): a certified lower bound of the distance
// between the box and the triangle within `tolerance` of it, or at least `best`.
fn ddm_plain_pair_lower_bound(
    box_min: vec3<f32>,
    box_max: vec3<f32>,
    ta: vec3<f32>,
    tb: vec3<f32>,
    tc: vec3<f32>,
    tolerance: f32,
    best: f32,
    magnitude: f32,
) -> f32 {
    let center = (box_min + box_max) * 0.5;
    let half = (box_max - box_min) * 0.5;
    let a = ta - center;
    let b = tb - center;
    let c = tc - center;
    let margin = ddm_plain_rounding_margin(box_min, box_max, magnitude);
    var q = ddm_closest_point_on_triangle(vec3<f32>(0.0), a, b, c);
    var lower = -3.4028235e38;
    let to_center = -q;
    let length = sqrt(dot(to_center, to_center));
    if length > 0.0 {
        let n = to_center / length;
        lower = length - dot(half, abs(n)) - margin;
    }
    for (var k = 0u; k < DDM_PLAIN_MAX_PROJECTIONS; k++) {
        if lower >= best {
            return max(lower, 0.0);
        }
        let p = clamp(q, -half, half);
        let upper = distance(p, q);
        if upper - max(lower, 0.0) <= tolerance {
            return max(lower, 0.0);
        }
        q = ddm_closest_point_on_triangle(p, a, b, c);
        let gap = p - q;
        let gap_length = sqrt(dot(gap, gap));
        if gap_length > 0.0 {
            let n = gap / gap_length;
            lower = max(lower, -dot(q, n) - dot(half, abs(n)) - margin);
        } else {
            // The box touches the triangle.
            return 0.0;
        }
    }
    if lower >= best {
        return max(lower, 0.0);
    }
    return ddm_box_triangle_distance(box_min, box_max, ta, tb, tc);
}

// Rust: ddm_compress::plain's gap_squared: the squared gap between two boxes (0 where they
// overlap).
fn ddm_box_gap_squared(a_min: vec3<f32>, a_max: vec3<f32>, b_min: vec3<f32>, b_max: vec3<f32>) -> f32 {
    let gap = max(max(a_min - b_max, b_min - a_max), vec3<f32>(0.0));
    return dot(gap, gap);
}
