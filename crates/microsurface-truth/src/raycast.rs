//! Exact ray casting of a piecewise-linear periodic height field (2-D DDA over the cells of
//! its maximum pyramid, two triangles per cell, a block skipped when the ray stays above its
//! highest corner).

use glam::DVec3;

use crate::heightfield::HeightField;

/// Safety bound on the steps of one ray's walk (the ray has left the field's height range
/// long before in any sensible query).
const MAX_STEPS: usize = 10_000_000;

/// Intersection parameter of the ray `o + t d` (with `o` in cell-local coordinates
/// `(u, v)` measured from the cell's corner) with the plane `z = a + b u + c v`.
fn plane_hit(o: DVec3, d: DVec3, a: f64, b: f64, c: f64) -> Option<f64> {
    let denominator = d.z - b * d.x - c * d.y;
    (denominator != 0.0).then(|| (a + b * o.x + c * o.y - o.z) / denominator)
}

/// Smallest `t` in `[t0, t1]` where the ray meets cell `(i, j)`'s two triangles; `o` is in
/// cell-local coordinates.
fn cell_hit(field: &HeightField, i: i64, j: i64, o: DVec3, d: DVec3, t0: f64, t1: f64) -> Option<f64> {
    let (h00, h10, h01, h11) =
        (field.height(i, j), field.height(i + 1, j), field.height(i, j + 1), field.height(i + 1, j + 1));
    let mut best: Option<f64> = None;
    // Lower triangle (v ≤ u): z = h00 + (h10 - h00) u + (h11 - h10) v.
    // Upper triangle (v ≥ u): z = h00 + (h11 - h01) u + (h01 - h00) v.
    let triangles = [(h10 - h00, h11 - h10, true), (h11 - h01, h01 - h00, false)];
    for (b, c, lower) in triangles {
        let Some(t) = plane_hit(o, d, h00, b, c) else { continue };
        if t < t0 || t > t1 {
            continue;
        }
        let (u, v) = (o.x + t * d.x, o.y + t * d.y);
        let slack = 1e-9;
        let inside = if lower { v <= u + slack } else { v >= u - slack };
        if inside && best.is_none_or(|b| t < b) {
            best = Some(t);
        }
    }
    best
}

/// Walks the cells under the ray `origin + t direction` for `t ≥ t_start` and returns the
/// first intersection parameter, or `None` once the ray rises above the field (for
/// upward rays) or after [`MAX_STEPS`].
///
/// The walk descends the field's maximum pyramid: a block whose highest corner lies below
/// the ray over the block is left through its far face in one step, and each step out of
/// a block tries the next coarser level. Cells are tested in the order a cell-by-cell
/// walk tests them, each over the same stretch of the ray, so the first hit is the same.
fn march(field: &HeightField, origin: DVec3, direction: DVec3, t_start: f64) -> Option<f64> {
    let d = direction;
    let pyramid = field.pyramid();
    let start = origin + t_start * d;
    let (mut i, mut j) = (start.x.floor() as i64, start.y.floor() as i64);
    // Where the ray crosses the grid line `x = line` (or `y`); never along it.
    let inverse = |dir: f64| if dir != 0.0 { 1.0 / dir } else { 0.0 };
    let (inverse_x, inverse_y) = (inverse(d.x), inverse(d.y));
    let crossing = |line: i64, o: f64, dir: f64, inverse: f64| {
        if dir != 0.0 { (line as f64 - o) * inverse } else { f64::INFINITY }
    };
    let (mut level, mut t0) = (0, t_start);
    for _ in 0..MAX_STEPS {
        if d.z > 0.0 && origin.z + t0 * d.z > field.max_height() {
            return None;
        }
        let side = 1_i64 << level;
        let (bi, bj) = (i >> level, j >> level);
        // The block's far faces along the ray, and where the ray leaves it.
        let x_face = if d.x > 0.0 { (bi + 1) * side } else { bi * side };
        let y_face = if d.y > 0.0 { (bj + 1) * side } else { bj * side };
        let (tx, ty) = (crossing(x_face, origin.x, d.x, inverse_x), crossing(y_face, origin.y, d.y, inverse_y));
        let t1 = tx.min(ty);
        let z_low = (origin.z + t0 * d.z).min(origin.z + t1.min(1e300) * d.z);
        let skipped = z_low > pyramid.block_max(level, bi, bj);
        if !skipped {
            if level > 0 {
                level -= 1;
                continue;
            }
            let local = DVec3::new(origin.x - i as f64, origin.y - j as f64, origin.z);
            if let Some(t) = cell_hit(field, i, j, local, d, t0, t1) {
                return Some(t);
            }
        }
        if t1.is_infinite() {
            return None; // vertical ray that left its cell's height range
        }
        // Into the next block: across the face it leaves by, the other coordinate where
        // the ray crosses that face (kept inside the block's span against rounding).
        let inside =
            |p: f64, b: i64| if level == 0 { b } else { (p.floor() as i64).clamp(b * side, b * side + side - 1) };
        if tx < ty {
            (i, j) = (if d.x > 0.0 { x_face } else { x_face - 1 }, inside(origin.y + t1 * d.y, bj));
        } else {
            (i, j) = (inside(origin.x + t1 * d.x, bi), if d.y > 0.0 { y_face } else { y_face - 1 });
        }
        t0 = t1;
        // After a skip, a coarser block is worth a test once the ray has left the one it
        // was refined from (inside it, a downward ray's lowest point over the rest is the
        // same); after a cell the ray passed through, the ray is near the surface.
        if skipped && level < pyramid.top() && (i >> (level + 1), j >> (level + 1)) != (bi >> 1, bj >> 1) {
            level += 1;
        }
    }
    None
}

/// The first point where a downward ray along `direction` (`direction.z < 0`), entering
/// above the field at horizontal position `(x, y)`, meets the surface.
pub fn first_hit(field: &HeightField, x: f64, y: f64, direction: DVec3) -> Option<DVec3> {
    if !direction.is_finite() || direction.z >= 0.0 {
        return None;
    }
    let origin = DVec3::new(x, y, field.max_height() + 1.0);
    march(field, origin, direction, 0.0).map(|t| origin + t * direction)
}

/// Whether `point` on the surface sees the light in direction `light` (`light.z > 0`):
/// the shadow ray escapes above the field without meeting it.
pub fn is_lit(field: &HeightField, point: DVec3, light: DVec3) -> bool {
    if light.z.is_nan() || light.z <= 0.0 {
        return false;
    }
    // Skip the surface the point lies on; 1e-7 cells is far below any feature size.
    march(field, point, light, 1e-7).is_none()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cell-by-cell walk the pyramid's replaced: every cell under the ray in turn.
    fn march_cell_by_cell(field: &HeightField, origin: DVec3, d: DVec3, t_start: f64) -> Option<f64> {
        let step = |x: f64| if x > 0.0 { 1_i64 } else { -1 };
        let start = origin + t_start * d;
        let (mut i, mut j) = (start.x.floor() as i64, start.y.floor() as i64);
        let next_boundary = |p: f64, cell: i64, dir: f64| {
            if dir > 0.0 {
                (cell as f64 + 1.0 - p) / dir
            } else if dir < 0.0 {
                (cell as f64 - p) / dir
            } else {
                f64::INFINITY
            }
        };
        let mut t_next_x = t_start + next_boundary(start.x, i, d.x);
        let mut t_next_y = t_start + next_boundary(start.y, j, d.y);
        let (t_delta_x, t_delta_y) = (1.0 / d.x.abs(), 1.0 / d.y.abs());
        let mut t0 = t_start;
        for _ in 0..MAX_STEPS {
            let t1 = t_next_x.min(t_next_y);
            if d.z > 0.0 && origin.z + t0 * d.z > field.max_height() {
                return None;
            }
            let local = DVec3::new(origin.x - i as f64, origin.y - j as f64, origin.z);
            if let Some(t) = cell_hit(field, i, j, local, d, t0, t1) {
                return Some(t);
            }
            if t1.is_infinite() {
                return None;
            }
            if t_next_x < t_next_y {
                i += step(d.x);
                t_next_x += t_delta_x;
            } else {
                j += step(d.y);
                t_next_y += t_delta_y;
            }
            t0 = t1;
        }
        None
    }

    #[test]
    fn the_pyramid_walk_finds_the_cell_by_cell_walks_hit() {
        // Sizes with a full pyramid (64), a partial one (48: levels 0 … 4) and none (33);
        // view rays from straight down to 89°, shadow rays from their hits.
        let mut compared = (0, 0);
        for size in [64_usize, 48, 33] {
            let heights: Vec<f64> =
                (0..size * size).map(|k| ((k * 7919 % 263) as f64 * 0.013).powi(2) + (k % 5) as f64 * 0.1).collect();
            let field = HeightField::new(size, heights).unwrap();
            for k in 0..400 {
                let (angle, azimuth) = ((f64::from(k % 90) + 0.5).to_radians(), f64::from(k) * 2.399);
                let d = -DVec3::new(angle.sin() * azimuth.cos(), angle.sin() * azimuth.sin(), angle.cos());
                let origin = DVec3::new(f64::from(k) * 0.731, f64::from(k) * 1.917, field.max_height() + 1.0);
                let (fast, slow) = (march(&field, origin, d, 0.0), march_cell_by_cell(&field, origin, d, 0.0));
                assert_eq!(fast.is_some(), slow.is_some(), "size {size}, ray {k}");
                let (Some(fast), Some(slow)) = (fast, slow) else { continue };
                assert!((fast - slow).abs() <= 1e-9 * slow.abs().max(1.0), "size {size}, ray {k}: {fast} vs {slow}");
                compared.0 += 1;
                let hit = origin + slow * d;
                let light = DVec3::new(azimuth.sin() * 0.9, azimuth.cos() * 0.9, 0.05 + f64::from(k % 7) * 0.1);
                let light = light.normalize();
                let (fast, slow) = (march(&field, hit, light, 1e-7), march_cell_by_cell(&field, hit, light, 1e-7));
                assert_eq!(fast.is_some(), slow.is_some(), "size {size}, shadow ray {k}");
                if let (Some(fast), Some(slow)) = (fast, slow) {
                    assert!((fast - slow).abs() <= 1e-9 * slow.abs().max(1.0), "size {size}, shadow ray {k}");
                    compared.1 += 1;
                }
            }
        }
        // Every view ray hits; a share of the shadow rays does.
        assert_eq!(compared.0, 1200);
        assert!(compared.1 > 100, "{} shadow rays hit", compared.1);
    }

    #[test]
    fn a_flat_field_is_hit_at_its_height() {
        let field = HeightField::new(4, vec![0.5; 16]).unwrap();
        let d = DVec3::new(0.6, 0.3, -0.2).normalize();
        let hit = first_hit(&field, 1.3, 2.7, d).unwrap();
        assert!((hit.z - 0.5).abs() < 1e-12);
        assert!(is_lit(&field, hit, DVec3::new(0.1, 0.0, 1.0).normalize()));
    }

    #[test]
    fn hits_lie_on_the_interpolated_surface() {
        let heights: Vec<f64> = (0..64).map(|k| f64::from((k * 7919) % 13) * 0.3).collect();
        let field = HeightField::new(8, heights).unwrap();
        for k in 0..200 {
            let a = f64::from(k) * 0.37;
            let d = DVec3::new(a.cos(), a.sin(), -0.3 - f64::from(k % 5) * 0.2).normalize();
            let hit = first_hit(&field, f64::from(k) * 0.11, f64::from(k) * 0.23, d).unwrap();
            assert!((hit.z - field.interpolate(hit.x, hit.y)).abs() < 1e-9, "ray {k}");
        }
    }

    #[test]
    fn a_wall_casts_a_shadow() {
        // A ridge of height 4 along x = 4; points just east of it are shadowed from the west.
        let size = 8;
        let heights = (0..size * size).map(|k| if k % size == 4 { 4.0 } else { 0.0 }).collect();
        let field = HeightField::new(size, heights).unwrap();
        let west_low = DVec3::new(-1.0, 0.0, 0.3).normalize();
        assert!(!is_lit(&field, DVec3::new(5.5, 2.0, 0.0), west_low));
        assert!(is_lit(&field, DVec3::new(5.5, 2.0, 0.0), DVec3::new(1.0, 0.0, 1.0).normalize()));
    }
}
