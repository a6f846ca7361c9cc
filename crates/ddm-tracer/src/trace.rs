//! Directional sphere tracing (Algorithm 3.1) with ray–quadric intersection in
//! zero-distance voxels (Algorithm 3.2) and voxel-wall stepping (Algorithm 3.3), through
//! the DDM volume of a tile that repeats in x and y, or of a single tile. Mirrored by
//! `trace_ray` in `shaders/ddm_tracer.wgsl`.
//!
//! Coordinates are texture space in voxel units: the tile's slab is
//! `[0, L_x] × [0, L_y] × [0, L_z]`, repeated in x and y. A viewing ray (`r_z < 0`) enters
//! through the top `z = L_z` (or starts inside the slab) and leaves through `z = 0`.
//! A tile that does not repeat ([`DistanceSource::periodic_xy`] false, beyond the paper)
//! holds nothing outside its slab: the ray starts where it enters the slab through any
//! wall, steps are not capped (the maps bound all the geometry there is), and a ray whose
//! look-up point leaves the slab through a side wall misses.
//!
//! Each step reads the map of the ray's cone at the voxel containing the current point
//! (one *step* = one map read):
//!
//! - a positive value `d` is a safe distance (conservative DDM: no surface point of the
//!   cone is closer to any point of the voxel), so the ray advances by `d`
//!   ([`Stepping::Distance`], the paper's rule) or to the voxel's exit wall and `d`
//!   beyond ([`Stepping::VoxelExit`]; [`Stepping::BlockCells`] does so only across a
//!   compressed block without surface) (capped at
//!   `min(L_x, L_y)`, the distance beyond which the maps, built from the tile and its 8
//!   neighbours, no longer bound the mesostructure);
//! - a zero value means the voxel holds surface. [`Method::SphereTracing`] stops there, as
//!   Donnelly's distance-map sphere tracing does (its hit is the voxel entry point);
//!   [`Method::Quadric`] intersects the voxel's patches over the ray's segment inside the
//!   voxel (from where the ray enters it, whatever step led there) and returns the nearest
//!   hit, or moves to the voxel's exit wall (Algorithm 3.3) and continues.
//!
//! The voxel of a point on a voxel wall is decided by looking [`NUDGE`] ahead along the
//! ray (Algorithm 3.3's `ε`), without moving the point: every step is then taken from a
//! point inside or on the wall of the voxel whose value is used, which keeps it safe.

use glam::{IVec3, UVec3, Vec3};
use quadric_fit::normal;

use crate::maps::{ConeDistances, DistanceSource};
use crate::patch::{patch_hit, quadric_of};
use crate::patches::VoxelPatches;
use crate::voxel::{NUDGE, cell_exit, outside_tile, slab_entry, tile_entry, unit, voxel_entry, voxel_exit};

/// What happens in a zero-distance voxel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Stop at the voxel's entry point (sphere tracing with a distance map or DDM only).
    SphereTracing,
    /// Intersect the voxel's quadric patches, else step to its exit wall (Algorithm 3.1).
    Quadric,
}

/// How far a step through a voxel with a positive distance goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stepping {
    /// The stored distance `d` from the current point (Algorithm 3.1, line 9; Hart's
    /// sphere tracing).
    Distance,
    /// To the voxel's exit wall, then `d` further (beyond the paper). The stored value
    /// bounds the distance from *every* point of the closed voxel, so the whole segment
    /// inside the voxel holds no surface (a surface point there would be at distance 0
    /// from a point of the voxel) and the step from the exit point, still in the voxel, is
    /// safe: conservative like [`Stepping::Distance`], with fewer map reads.
    ///
    /// On compressed maps the same holds for a whole block without surface, whose stored
    /// minimum bounds the distance from every point of the block
    /// ([`ddm_compress::CompressedMap::access_cell`]): the step goes to the block's exit
    /// wall, then `d` further. Compression then saves steps instead of costing them.
    VoxelExit,
    /// The paper's rule ([`Stepping::Distance`]) in every voxel that has a value of its
    /// own, and [`Stepping::VoxelExit`]'s step across a compressed block without surface
    /// (beyond the paper): the block's one stored minimum bounds the distance from every
    /// point of the block, so the ray goes to the block's exit wall, then that minimum
    /// further. On raw maps (every cell a voxel) this is exactly [`Stepping::Distance`];
    /// on compressed maps it gives back the steps the paper's §4 concedes to the blocks'
    /// smaller values.
    BlockCells,
}

/// Settings of [`trace`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TraceSettings {
    /// The method.
    pub method: Method,
    /// Map reads before the ray gives up (reported as [`TraceOutcome::exhausted`]).
    pub max_steps: u32,
    /// How far a step through free space goes.
    pub stepping: Stepping,
}

/// A hit of the tracer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TraceHit {
    /// Ray parameter from the given origin (the direction normalized).
    pub t: f32,
    /// The hit point, in the ray's unwrapped coordinates.
    pub point: Vec3,
    /// Unit normal facing the ray: the quadric's gradient, or for
    /// [`Method::SphereTracing`] the normal of the voxel wall the ray entered through.
    pub normal: Vec3,
    /// The voxel of the hit, in tile coordinates.
    pub voxel: UVec3,
}

/// The result of tracing one ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TraceOutcome {
    /// The hit, or `None` for a miss.
    pub hit: Option<TraceHit>,
    /// Map reads.
    pub steps: u32,
    /// Whether the ray ran out of steps (a miss that may hide a hit).
    pub exhausted: bool,
    /// The cone whose map the ray read (0 for the plain map).
    pub cone: u32,
}

impl TraceOutcome {
    fn miss(steps: u32, cone: u32) -> Self {
        Self { hit: None, steps, exhausted: false, cone }
    }
}

/// The `max_t` of [`trace_within`] that never stops a ray (`f32::MAX`, a value WGSL holds).
pub const NO_LIMIT: f32 = f32::MAX;

/// Traces the ray `origin + t direction` (Algorithm 3.1). Rays that do not point down
/// (`direction.z ≥ 0`), directions outside the maps' cones (or whose cone has no map in
/// `source`), and non-finite input miss with zero steps. `patches` is needed by
/// [`Method::Quadric`] (without it no voxel has a patch and every ray misses).
pub fn trace<S: DistanceSource>(
    source: &S,
    patches: Option<&VoxelPatches>,
    origin: Vec3,
    direction: Vec3,
    settings: TraceSettings,
) -> TraceOutcome {
    trace_within(source, patches, origin, direction, settings, NO_LIMIT)
}

/// [`trace`] that gives up, as a miss (not exhausted), once its march passes the ray
/// parameter `max_t` (measured like [`TraceHit::t`]): no hit at `t ≤ max_t` is lost,
/// since the march reaches a hit's voxel before passing the hit. A renderer passes where
/// the ray leaves the base mesh's solid (`tangent_space::shell_exit`), so that silhouette
/// rays stop there instead of running along the slab. WGSL twin: `trace_ray_within`.
pub fn trace_within<S: DistanceSource>(
    source: &S,
    patches: Option<&VoxelPatches>,
    origin: Vec3,
    direction: Vec3,
    settings: TraceSettings,
    max_t: f32,
) -> TraceOutcome {
    let dims = source.dims();
    if !(origin.is_finite() && direction.is_finite()) || dims.cmpeq(UVec3::ZERO).any() {
        return TraceOutcome::miss(0, 0);
    }
    let d = unit(direction);
    // `d.z >= 0` or NaN: not a viewing ray.
    if d.z.partial_cmp(&0.0) != Some(core::cmp::Ordering::Less) {
        return TraceOutcome::miss(0, 0);
    }
    let Some(cone) = source.selector().select(d) else { return TraceOutcome::miss(0, 0) };
    let Some(map) = source.cone_map(cone) else { return TraceOutcome::miss(0, cone) };
    let size = dims.as_vec3();
    let periodic = source.periodic_xy();
    // Periodic maps bound only what lies within one tile of the voxel; a single tile's
    // maps bound all there is.
    let (t_enter, step_cap) = if periodic {
        (slab_entry(origin, d, size.z), size.x.min(size.y))
    } else {
        match tile_entry(origin, d, size) {
            Some(t) if t.is_finite() => (t, f32::MAX),
            _ => return TraceOutcome::miss(0, cone),
        }
    };
    let start = origin + d * t_enter;
    let mut t = 0.0_f32;
    let mut steps = 0;
    while steps < settings.max_steps {
        let p = start + d * t;
        let probe = p + d * NUDGE;
        if probe.z < 0.0 || t_enter + t > max_t || (!periodic && outside_tile(probe, size)) {
            return TraceOutcome::miss(steps, cone);
        }
        let v = IVec3::new(
            libm::floorf(probe.x) as i32,
            libm::floorf(probe.y) as i32,
            (libm::floorf(probe.z) as i32).min(dims.z as i32 - 1),
        );
        let wrapped =
            UVec3::new(v.x.rem_euclid(dims.x as i32) as u32, v.y.rem_euclid(dims.y as i32) as u32, v.z as u32);
        steps += 1;
        // Voxel-exit and block-cell stepping read the cell the value holds for (see
        // `Stepping::VoxelExit`).
        let cell = match settings.stepping {
            Stepping::Distance => None,
            Stepping::VoxelExit | Stepping::BlockCells => Some(map.cell_distance(wrapped)),
        };
        let value = cell.map_or_else(|| map.distance(wrapped), |cell| cell.distance);
        if value > 0.0 {
            let inside = match cell {
                None => 0.0,
                // A single voxel (the same value as the general case, computed cheaper).
                Some(cell) if cell.size == UVec3::ONE => match settings.stepping {
                    Stepping::VoxelExit => voxel_exit(p - v.as_vec3(), d),
                    _ => 0.0,
                },
                Some(cell) => {
                    // The cell's first corner where the ray is (x and y unwrapped).
                    let corner = v.as_vec3() - (wrapped - cell.origin).as_vec3();
                    cell_exit(p - corner, d, cell.size.as_vec3())
                }
            };
            t += (inside + value).min(step_cap);
            continue;
        }
        let corner = v.as_vec3();
        if settings.method == Method::SphereTracing {
            let normal = entry_wall_normal(p - corner, d);
            let hit = TraceHit { t: t_enter + t, point: p, normal, voxel: wrapped };
            return TraceOutcome { hit: Some(hit), steps, exhausted: false, cone };
        }
        // The patches are intersected from where the ray enters the voxel (not from `p`,
        // which depends on the steps that led here): a hit then depends only on the ray
        // and the voxel, and the same on raw and compressed maps.
        let start_local = start - corner;
        let t_in = voxel_entry(start_local, d);
        let entry = start_local + d * t_in;
        let t_exit = voxel_exit(entry, d);
        let list = patches.map_or(&[][..], |p| p.of_voxel(wrapped));
        if let Some((th, index)) = patch_hit(list, entry, d, t_exit) {
            let at = entry + d * th;
            let mut n = normal(&quadric_of(&list[index]), at);
            if n.dot(d) > 0.0 {
                n = -n;
            }
            let hit = TraceHit { t: t_enter + t_in + th, point: start + d * (t_in + th), normal: n, voxel: wrapped };
            return TraceOutcome { hit: Some(hit), steps, exhausted: false, cone };
        }
        t = t.max(t_in + t_exit);
    }
    TraceOutcome { hit: None, steps, exhausted: true, cone }
}

/// The outward normal of the wall of the unit voxel through which a ray in `direction`
/// entered at the voxel-local point `local`: the entry wall nearest to it.
pub fn entry_wall_normal(local: Vec3, direction: Vec3) -> Vec3 {
    let mut best = f32::MAX;
    let mut normal = Vec3::Z;
    for axis in 0..3 {
        let r = direction[axis];
        if r == 0.0 {
            continue;
        }
        let wall = if r < 0.0 { 1.0 } else { 0.0 };
        let distance = (local[axis] - wall).abs();
        if distance < best {
            best = distance;
            normal = Vec3::ZERO;
            normal[axis] = if r < 0.0 { 1.0 } else { -1.0 };
        }
    }
    normal
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::patches::PatchSettings;
    use ddm_compress::{DirectionCones, DistanceMapSettings, MapKind, compute_distance_maps};

    #[test]
    fn a_flat_floor_is_hit_exactly_by_the_quadric_method() {
        // 2.0 lies on voxel walls: both voxels around it are surface voxels and only one
        // of them gets the patch (it was lost before the patch segment started at -NUDGE).
        for floor in [1.37, 2.0] {
            let dims = UVec3::new(6, 6, 4);
            let tris = mesostructure::plane(dims, floor);
            let settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: true };
            // The plain map: the patches, not the cones, are under test here (and the DDM of a
            // floor on voxel walls is slow to bound).
            let maps = compute_distance_maps(dims, &tris, MapKind::Plain, settings).unwrap();
            let patches = VoxelPatches::build(dims, &tris, &maps.surface, PatchSettings::default()).unwrap();
            let quadric = TraceSettings { method: Method::Quadric, max_steps: 64, stepping: Stepping::Distance };
            let sphere = TraceSettings { method: Method::SphereTracing, max_steps: 64, stepping: Stepping::Distance };
            for k in 0..80 {
                let a = k as f32 * 0.7;
                let origin = Vec3::new(3.3 + k as f32 * 0.37, 2.1 + k as f32 * 0.13, 6.0);
                let direction = Vec3::new(libm::cosf(a) * 0.8, libm::sinf(a) * 0.8, -1.0 - (k % 7) as f32 * 0.3);
                let out = trace(&maps, Some(&patches), origin, direction, quadric);
                let hit = out.hit.unwrap_or_else(|| panic!("floor {floor}, ray {k}: {out:?}"));
                assert!((hit.point.z - floor).abs() < 1e-5, "{hit:?}");
                assert!((hit.normal - Vec3::Z).length() < 1e-4);
                let coarse = trace(&maps, None, origin, direction, sphere).hit.unwrap();
                // Sphere tracing stops at the entry of the floor's voxel, above the floor.
                assert!(coarse.point.z >= floor - 1e-5 && coarse.point.z <= libm::floorf(floor) + 1.0 + 1e-4);
            }
        }
        let dims = UVec3::new(6, 6, 4);
        let tris = mesostructure::plane(dims, 1.37);
        let settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: true };
        let kind = MapKind::Directional(DirectionCones::downward(4, 1).unwrap());
        let maps = compute_distance_maps(dims, &tris, kind, settings).unwrap();
        let patches = VoxelPatches::build(dims, &tris, &maps.surface, PatchSettings::default()).unwrap();
        let quadric = TraceSettings { method: Method::Quadric, max_steps: 64, stepping: Stepping::Distance };
        // Upward rays and rays outside the downward cones miss without a step.
        let up = trace(&maps, Some(&patches), Vec3::new(1.0, 1.0, 2.0), Vec3::Z, quadric);
        assert_eq!((up.hit, up.steps), (None, 0));
    }

    #[test]
    fn a_limited_trace_keeps_every_hit_before_its_limit_and_stops_after_it() {
        let dims = UVec3::new(6, 6, 4);
        let tris = mesostructure::plane(dims, 1.37);
        let settings = DistanceMapSettings { tolerance: 0.25, periodic_xy: true };
        let maps = compute_distance_maps(dims, &tris, MapKind::Plain, settings).unwrap();
        let patches = VoxelPatches::build(dims, &tris, &maps.surface, PatchSettings::default()).unwrap();
        let quadric = TraceSettings { method: Method::Quadric, max_steps: 64, stepping: Stepping::Distance };
        for k in 0..40 {
            let a = k as f32 * 0.9;
            let origin = Vec3::new(1.3 + k as f32 * 0.21, 4.1, 4.0);
            let direction = Vec3::new(libm::cosf(a) * 2.5, libm::sinf(a) * 2.5, -1.0);
            let full = trace(&maps, Some(&patches), origin, direction, quadric);
            let hit = full.hit.unwrap();
            // At or beyond the hit the limit changes nothing; before it the ray stops as a
            // miss that is not exhausted, with no more steps than the full trace took.
            assert_eq!(trace_within(&maps, Some(&patches), origin, direction, quadric, hit.t), full);
            let short = trace_within(&maps, Some(&patches), origin, direction, quadric, 0.5 * hit.t);
            assert!(short.hit.is_none() && !short.exhausted && short.steps <= full.steps, "ray {k}: {short:?}");
        }
    }
}
