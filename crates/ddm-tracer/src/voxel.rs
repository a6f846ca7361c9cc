//! Ray–voxel geometry shared by the tracer, the patches and relief mapping: where a ray
//! enters the tile's slab, enters and leaves a unit voxel or a cell of voxels, and how far
//! ahead a point's voxel is looked up ([`NUDGE`], Algorithm 3.3's `ε`).

use glam::Vec3;

/// How far ahead along the ray (voxels) the voxel of the current point is looked up.
pub const NUDGE: f32 = 1e-4;

/// `origin + t direction` enters the slab `z ≤ size.z`: the entry parameter (0 when the
/// origin is inside). WGSL twin: `trace_slab_entry`.
pub fn slab_entry(origin: Vec3, direction: Vec3, size_z: f32) -> f32 {
    if origin.z > size_z { (size_z - origin.z) / direction.z } else { 0.0 }
}

/// `origin + t direction` (with `direction.z < 0`) enters the slab of a tile that does not
/// repeat, `[0, size.x] × [0, size.y] × (−∞, size.z]`: the largest entry parameter of the
/// walls that the origin lies beyond (0 when it is inside), or `None` when it lies beyond
/// a side wall and moves away from it. The parameter may still be one where the ray is
/// outside the slab (it passed another side first): the tracer's first look-up then finds
/// the ray outside. WGSL twin: `trace_tile_entry` (negative for `None`).
pub fn tile_entry(origin: Vec3, direction: Vec3, size: Vec3) -> Option<f32> {
    let mut entry = slab_entry(origin, direction, size.z);
    for axis in 0..2 {
        let (o, r) = (origin[axis], direction[axis]);
        if o < 0.0 {
            if r <= 0.0 {
                return None;
            }
            entry = entry.max(-o / r);
        } else if o > size[axis] {
            if r >= 0.0 {
                return None;
            }
            entry = entry.max((size[axis] - o) / r);
        }
    }
    Some(entry)
}

/// Whether the look-up point `probe` lies outside the side walls of a tile of `size`
/// voxels that does not repeat (`[0, size.x) × [0, size.y)`). WGSL twin:
/// `trace_outside_tile`.
pub fn outside_tile(probe: Vec3, size: Vec3) -> bool {
    !(probe.x >= 0.0 && probe.y >= 0.0 && probe.x < size.x && probe.y < size.y)
}

/// `direction / |direction|` computed as both CPU and GPU do.
pub fn unit(direction: Vec3) -> Vec3 {
    direction * (1.0 / libm::sqrtf(direction.dot(direction)))
}

/// The ray parameter, from the point `local` relative to a unit voxel's lowest corner,
/// where the ray enters the voxel (the largest of the entry walls' parameters), never
/// negative: a ray starting inside the voxel enters it at its start. WGSL twin:
/// `trace_voxel_entry`.
pub fn voxel_entry(local: Vec3, direction: Vec3) -> f32 {
    let mut entry = 0.0_f32;
    for axis in 0..3 {
        let r = direction[axis];
        if r != 0.0 {
            let wall = if r > 0.0 { 0.0 } else { 1.0 };
            entry = entry.max((wall - local[axis]) / r);
        }
    }
    entry
}

/// The ray parameter, from the point `local` relative to a unit voxel's lowest corner,
/// where the ray leaves the voxel (Algorithm 3.3, lines 2–4), never negative.
pub fn voxel_exit(local: Vec3, direction: Vec3) -> f32 {
    cell_exit(local, direction, Vec3::ONE)
}

/// The `t ≥ 0` at which the ray `local + t direction` leaves the box `[0, size]` (a cell
/// of voxels, `local` relative to its first corner), for a point inside or on it.
///
/// WGSL twin: `trace_cell_exit`.
pub fn cell_exit(local: Vec3, direction: Vec3, size: Vec3) -> f32 {
    let mut exit = f32::MAX;
    for axis in 0..3 {
        let r = direction[axis];
        if r != 0.0 {
            let wall = if r > 0.0 { size[axis] } else { 0.0 };
            exit = exit.min((wall - local[axis]) / r);
        }
    }
    exit.max(0.0)
}
