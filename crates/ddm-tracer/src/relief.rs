//! Relief mapping (Policarpo et al., the paper's reference \[20\]): a linear search along
//! the ray for the first sample below a height map, refined by binary search. The
//! baseline of Table 2, for height-field mesostructures only.

use alloc::vec::Vec;
use core::fmt;

use glam::{DVec3, UVec3, Vec2, Vec3};

use crate::ground_truth::MeshRaycaster;
use crate::trace::{TraceHit, TraceOutcome};
use crate::voxel::{slab_entry, unit};

/// A periodic height map over the tile, sampled at texel centres, read bilinearly.
#[derive(Clone, Debug, PartialEq)]
pub struct HeightMap {
    /// Texels along x and y.
    pub texels: UVec3,
    /// Texels per voxel.
    pub texels_per_voxel: u32,
    /// Heights (voxel units), index `x + texels.x y`.
    pub heights: Vec<f32>,
}

/// Why [`HeightMap::from_mesh`] cannot sample a tile. The checks run in the order of the
/// variants; the first that fails is returned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HeightMapError {
    /// A side of the grid is zero.
    EmptyGrid {
        /// The grid size given.
        dims: UVec3,
    },
    /// Zero texels per voxel.
    ZeroTexelsPerVoxel,
    /// The texel count overflows a `u32` (WGSL indexes heights with `u32`).
    TooManyTexels {
        /// The grid size given.
        dims: UVec3,
        /// The texels per voxel given.
        texels_per_voxel: u32,
    },
}

impl fmt::Display for HeightMapError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::EmptyGrid { dims } => write!(f, "height map: the grid {dims} has no voxel"),
            Self::ZeroTexelsPerVoxel => write!(f, "height map: 0 texels per voxel"),
            Self::TooManyTexels { dims, texels_per_voxel } => write!(
                f,
                "height map: {texels_per_voxel} texels per voxel over {dims} voxels overflow u32 texel indices"
            ),
        }
    }
}

impl core::error::Error for HeightMapError {}

impl HeightMap {
    /// The height map of a tile of `dims` voxels at `texels_per_voxel` texels per voxel,
    /// from vertical rays against `mesh` (the first hit from above; 0 where a ray misses).
    ///
    /// # Errors
    ///
    /// A [`HeightMapError`]: an empty grid, zero texels per voxel, or more texels than
    /// `u32` indices reach.
    pub fn from_mesh(mesh: &MeshRaycaster, dims: UVec3, texels_per_voxel: u32) -> Result<Self, HeightMapError> {
        if dims.cmpeq(UVec3::ZERO).any() {
            return Err(HeightMapError::EmptyGrid { dims });
        }
        let s = texels_per_voxel;
        if s == 0 {
            return Err(HeightMapError::ZeroTexelsPerVoxel);
        }
        let texels = dims.x.checked_mul(s).zip(dims.y.checked_mul(s)).filter(|(x, y)| x.checked_mul(*y).is_some());
        let Some((x, y)) = texels else {
            return Err(HeightMapError::TooManyTexels { dims, texels_per_voxel });
        };
        let texels = UVec3::new(x, y, 1);
        let top = f64::from(dims.z) + 1.0;
        let mut heights = Vec::with_capacity(x as usize * y as usize);
        for y in 0..texels.y {
            for x in 0..texels.x {
                let p = DVec3::new((f64::from(x) + 0.5) / f64::from(s), (f64::from(y) + 0.5) / f64::from(s), top);
                let h = mesh.first_hit(p, DVec3::NEG_Z, top + 1.0).map_or(0.0, |hit| hit.point.z as f32);
                heights.push(h);
            }
        }
        Ok(Self { texels, texels_per_voxel: s, heights })
    }

    /// The height of texel `(x, y)` (periodic); 0 for a map whose fields disagree (no
    /// texels, or fewer heights than texels).
    fn texel(&self, x: i64, y: i64) -> f32 {
        let (w, h) = (i64::from(self.texels.x), i64::from(self.texels.y));
        if w == 0 || h == 0 {
            return 0.0;
        }
        self.heights.get((x.rem_euclid(w) + w * y.rem_euclid(h)) as usize).copied().unwrap_or(0.0)
    }

    /// The bilinear height at `p` (voxel units, periodic). WGSL twin: `relief_height`.
    pub fn height(&self, p: Vec2) -> f32 {
        let q = p * self.texels_per_voxel as f32 - 0.5;
        let (fx, fy) = (libm::floorf(q.x), libm::floorf(q.y));
        let (x, y) = (fx as i64, fy as i64);
        let (u, v) = (q.x - fx, q.y - fy);
        let a = self.texel(x, y) * (1.0 - u) + self.texel(x + 1, y) * u;
        let b = self.texel(x, y + 1) * (1.0 - u) + self.texel(x + 1, y + 1) * u;
        a * (1.0 - v) + b * v
    }

    /// The normal of the height map at `p` by central differences over one texel. WGSL
    /// twin: `relief_normal`.
    pub fn normal(&self, p: Vec2) -> Vec3 {
        let h = 1.0 / self.texels_per_voxel as f32;
        let dx = self.height(p + Vec2::new(h, 0.0)) - self.height(p - Vec2::new(h, 0.0));
        let dy = self.height(p + Vec2::new(0.0, h)) - self.height(p - Vec2::new(0.0, h));
        Vec3::new(-dx, -dy, 2.0 * h).normalize()
    }
}

/// Relief mapping of the ray through the slab of height `size_z`: `linear_steps` equal
/// steps from the slab top to `z = 0`, then `binary_steps` bisections of the first
/// interval that ends below the height map. Steps count height-map reads. WGSL twin:
/// `relief_trace_ray` (the hit's `voxel` is the tile voxel of the hit point, z clamped
/// to the slab).
pub fn relief_trace(
    map: &HeightMap,
    size_z: f32,
    origin: Vec3,
    direction: Vec3,
    linear_steps: u32,
    binary_steps: u32,
) -> TraceOutcome {
    let miss = |steps| TraceOutcome { hit: None, steps, exhausted: false, cone: 0 };
    if !(origin.is_finite() && direction.is_finite()) {
        return miss(0);
    }
    let d = unit(direction);
    // `d.z >= 0` or NaN: not a viewing ray.
    if d.z.partial_cmp(&0.0) != Some(core::cmp::Ordering::Less) {
        return miss(0);
    }
    let t_enter = slab_entry(origin, d, size_z);
    let start = origin + d * t_enter;
    let t_bottom = -start.z / d.z;
    let dt = t_bottom / linear_steps.max(1) as f32;
    let below = |t: f32| {
        let p = start + d * t;
        p.z <= map.height(p.truncate())
    };
    let mut steps = 0;
    let (mut lo, mut hi) = (0.0, f32::NAN);
    for i in 1..=linear_steps.max(1) {
        let t = dt * i as f32;
        steps += 1;
        if below(t) {
            hi = t;
            break;
        }
        lo = t;
    }
    if hi.is_nan() {
        return miss(steps);
    }
    for _ in 0..binary_steps {
        let mid = 0.5 * (lo + hi);
        steps += 1;
        if below(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let t = 0.5 * (lo + hi);
    let p = start + d * t;
    // The tile's voxels along x and y (at least 1, so that a map whose fields disagree
    // gives a wrong voxel rather than a division by zero).
    let tile = |texels: u32| i64::from((texels / map.texels_per_voxel.max(1)).max(1));
    let voxel = UVec3::new(
        (libm::floorf(p.x) as i64).rem_euclid(tile(map.texels.x)) as u32,
        (libm::floorf(p.y) as i64).rem_euclid(tile(map.texels.y)) as u32,
        libm::floorf(p.z).clamp(0.0, (size_z - 1.0).max(0.0)) as u32,
    );
    let hit = TraceHit { t: t_enter + t, point: p, normal: map.normal(p.truncate()), voxel };
    TraceOutcome { hit: Some(hit), steps, exhausted: false, cone: 0 }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn relief_mapping_finds_a_flat_floor() {
        let dims = UVec3::new(8, 8, 4);
        let mesh = MeshRaycaster::new(&mesostructure::plane(dims, 1.4), Vec2::new(8.0, 8.0));
        let map = HeightMap::from_mesh(&mesh, dims, 2).unwrap();
        assert!(map.heights.iter().all(|&h| (h - 1.4).abs() < 1e-6));
        let out = relief_trace(&map, 4.0, Vec3::new(1.0, 2.0, 6.0), Vec3::new(0.5, 0.2, -1.0), 16, 8);
        let hit = out.hit.unwrap();
        assert!((hit.point.z - 1.4).abs() < 4.0 / 16.0 / 256.0 * 2.0, "{hit:?}");
        assert_eq!(out.steps, 11 + 8);
    }

    #[test]
    fn each_unusable_tile_has_its_error() {
        let dims = UVec3::new(8, 8, 4);
        let mesh = MeshRaycaster::new(&mesostructure::plane(dims, 1.4), Vec2::new(8.0, 8.0));
        let flat = UVec3::new(8, 0, 4);
        assert_eq!(HeightMap::from_mesh(&mesh, flat, 2), Err(HeightMapError::EmptyGrid { dims: flat }));
        assert_eq!(HeightMap::from_mesh(&mesh, dims, 0), Err(HeightMapError::ZeroTexelsPerVoxel));
        let wide = UVec3::new(1 << 16, 1 << 16, 1);
        assert_eq!(
            HeightMap::from_mesh(&mesh, wide, 1),
            Err(HeightMapError::TooManyTexels { dims: wide, texels_per_voxel: 1 })
        );
        assert_eq!(
            HeightMap::from_mesh(&mesh, dims, 1 << 30),
            Err(HeightMapError::TooManyTexels { dims, texels_per_voxel: 1 << 30 })
        );
    }

    #[test]
    fn a_map_whose_fields_disagree_reads_without_panicking() {
        let ray = (Vec3::new(1.0, 2.0, 6.0), Vec3::new(0.5, 0.2, -1.0));
        for map in [
            HeightMap { texels: UVec3::ZERO, texels_per_voxel: 0, heights: Vec::new() },
            HeightMap { texels: UVec3::new(4, 4, 1), texels_per_voxel: 8, heights: alloc::vec![1.0; 3] },
        ] {
            assert!(map.height(Vec2::new(0.3, 0.7)).is_finite());
            let out = relief_trace(&map, 4.0, ray.0, ray.1, 16, 8);
            assert!(out.hit.is_some_and(|h| h.point.is_finite()), "{out:?}");
        }
    }
}
