//! The pixel rays of a perspective [`SplitCamera`] in `f64`, and a ray's entry into a ball:
//! the geometry occluder fusion ([`fusion`](mod@crate::fusion)) is proven with and its GPU
//! form ([`hiz`](mod@crate::hiz)) is parameterised by.

use glam::{DMat4, DVec3, DVec4, Vec4};

use crate::camera::SplitCamera;

/// How far (in pixels) each pixel's footprint is widened when bounding its depth, and a
/// grain's rectangle when choosing its texels: covers the `f32` camera's and rasteriser's
/// rounding (about `10⁻⁵` pixel) with room.
pub const FOOTPRINT_MARGIN_PX: f64 = 1e-3;

/// Relative margin added to every per-pixel bound `D(p)` (`f64` rounding is `~10⁻¹⁵`).
pub const DEPTH_MARGIN: f64 = 1e-9;

/// The camera in `f64`: view transform and the `x`, `y` rows of `clip_from_view`, whose
/// last row is `(0, 0, −1, 0)`, so that `ndc = (a·v, b·v) / (−v_z)`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Rays {
    view_from_world: DMat4,
    pub(crate) a: DVec3,
    pub(crate) b: DVec3,
    pub(crate) width: f64,
    pub(crate) height: f64,
}

impl Rays {
    /// `None` for orthographic cameras and any matrix this model does not cover.
    pub(crate) fn new(camera: &SplitCamera) -> Option<Self> {
        if !camera.is_perspective() {
            return None;
        }
        let columns =
            |c: &[Vec4; 4]| DMat4::from_cols(c[0].as_dvec4(), c[1].as_dvec4(), c[2].as_dvec4(), c[3].as_dvec4());
        let view = columns(&camera.view_from_world);
        let clip = columns(&camera.clip_from_world);
        let determinant = view.determinant();
        if !(view.is_finite() && clip.is_finite() && determinant.abs() > 1e-300) {
            return None;
        }
        // `clip_from_world` was rounded in f32: the recomputed projection is (0, 0, −1, 0) in
        // its last row and free of x/y translation only to within that rounding.
        let p = clip * view.inverse();
        let scale = 1.0 + view.to_cols_array().iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let tolerance = 1e-5 * scale * scale * (1.0 + p.x_axis.x.abs() + p.y_axis.y.abs());
        let last = p.row(3) - DVec4::new(0.0, 0.0, -1.0, 0.0);
        if last.abs().max_element() > tolerance || p.row(0).w.abs() > tolerance || p.row(1).w.abs() > tolerance {
            return None;
        }
        let (width, height) = camera.size();
        let rays = Self {
            view_from_world: view,
            a: p.row(0).truncate(),
            b: p.row(1).truncate(),
            width: f64::from(width),
            height: f64::from(height),
        };
        (rays.a.x * rays.b.y - rays.a.y * rays.b.x).is_normal().then_some(rays)
    }

    pub(crate) fn view(&self, world: DVec3) -> DVec3 {
        self.view_from_world.transform_point3(world)
    }

    /// The unit direction of the ray through the point `(px, py)` of the screen (pixels).
    pub(crate) fn direction(&self, px: f64, py: f64) -> DVec3 {
        let (nx, ny) = (2.0 * px / self.width - 1.0, 1.0 - 2.0 * py / self.height);
        // v = (vx, vy, −1): a·v = nx, b·v = ny.
        let (ex, ey) = (nx + self.a.z, ny + self.b.z);
        let det = self.a.x * self.b.y - self.a.y * self.b.x;
        let vx = (ex * self.b.y - self.a.y * ey) / det;
        let vy = (self.a.x * ey - ex * self.b.x) / det;
        DVec3::new(vx, vy, -1.0).normalize()
    }

    /// `(o, dx, dy)`: the (not normalised) direction of the ray through `(px, py)` is
    /// `o + px·dx + py·dy`, the affine form of [`Rays::direction`]'s solve.
    pub(crate) fn affine(&self) -> (DVec3, DVec3, DVec3) {
        let (a, b) = (self.a, self.b);
        let det = a.x * b.y - a.y * b.x;
        let origin = DVec3::new(
            ((a.z - 1.0) * b.y - a.y * (1.0 + b.z)) / det,
            (a.x * (1.0 + b.z) - (a.z - 1.0) * b.x) / det,
            -1.0,
        );
        let dx = DVec3::new(2.0 * b.y / (self.width * det), -2.0 * b.x / (self.width * det), 0.0);
        let dy = DVec3::new(2.0 * a.y / (self.height * det), -2.0 * a.x / (self.height * det), 0.0);
        (origin, dx, dy)
    }

    /// The screen point (pixels) of a view-space point in front of the eye.
    pub(crate) fn pixel(&self, v: DVec3) -> Option<(f64, f64)> {
        let w = -v.z;
        (w > 0.0).then(|| {
            let (nx, ny) = (self.a.dot(v) / w, self.b.dot(v) / w);
            ((nx + 1.0) * 0.5 * self.width, (1.0 - ny) * 0.5 * self.height)
        })
    }

    /// `D(p)` for pixel `(x, y)` and occluder ball `B(g0, r0)` (module docs).
    pub(crate) fn pixel_bound(&self, (x, y): (u32, u32), g0: DVec3, r0: f64) -> f64 {
        let g2 = g0.length_squared();
        if !(r0 > 0.0 && g0.is_finite() && r0.is_finite() && g2 > r0 * r0) {
            return f64::INFINITY;
        }
        let m = FOOTPRINT_MARGIN_PX;
        let (x0, x1, y0, y1) = (f64::from(x) - m, f64::from(x) + 1.0 + m, f64::from(y) - m, f64::from(y) + 1.0 + m);
        let mut bound = 0.0f64;
        for (px, py) in [(x0, y0), (x1, y0), (x0, y1), (x1, y1)] {
            match entry(self.direction(px, py), g0, r0) {
                Some(t) => bound = bound.max(t),
                None => return f64::INFINITY,
            }
        }
        bound * (1.0 + DEPTH_MARGIN)
    }

    /// `[x_min, x_max, y_min, y_max]` in pixels of the ball's projection (module docs).
    pub(crate) fn bounds(&self, g: DVec3, radius: f64) -> Option<[f64; 4]> {
        let depth = -g.z;
        if !(g.is_finite() && radius.is_finite() && radius >= 0.0 && depth - radius > 0.0 && g.length() > radius) {
            return None;
        }
        let n = DVec3::NEG_Z;
        let r2 = radius * radius;
        let range = |a: DVec3| {
            let (big_a, big_n) = (a.dot(g), depth);
            let q2 = big_n * big_n - r2;
            let q1 = big_a * big_n - r2 * a.dot(n);
            // q1² − q2·q0 (q0 = A² − R²|a|²) without cancellation: R²(|N a − A n|² − R²|a × n|²).
            let u = big_n * a - big_a * n;
            let root = radius * (u.length_squared() - r2 * a.cross(n).length_squared()).max(0.0).sqrt();
            ((q1 - root) / q2, (q1 + root) / q2)
        };
        let ((sx0, sx1), (sy0, sy1)) = (range(self.a), range(self.b));
        let bounds = [
            (sx0 + 1.0) * 0.5 * self.width,
            (sx1 + 1.0) * 0.5 * self.width,
            (1.0 - sy1) * 0.5 * self.height,
            (1.0 - sy0) * 0.5 * self.height,
        ];
        bounds.iter().all(|b| b.is_finite()).then_some(bounds)
    }

    /// The rectangle's inclusive pixel range, clamped to the screen; `None` when empty.
    pub(crate) fn rect(&self, g: DVec3, radius: f64) -> Option<[u32; 4]> {
        let [x0, x1, y0, y1] = self.bounds(g, radius)?;
        let m = FOOTPRINT_MARGIN_PX;
        let (lx, hx) = ((x0 - m).floor().max(0.0), (x1 + m).floor().min(self.width - 1.0));
        let (ly, hy) = ((y0 - m).floor().max(0.0), (y1 + m).floor().min(self.height - 1.0));
        (lx <= hx && ly <= hy).then_some([lx as u32, hx as u32, ly as u32, hy as u32])
    }
}

/// Where the unit ray `d` from the eye enters the ball `B(g, r)` (eye outside it), if it meets it.
pub(crate) fn entry(d: DVec3, g: DVec3, r: f64) -> Option<f64> {
    let c = d.dot(g);
    let discriminant = r * r - d.cross(g).length_squared();
    (c > 0.0 && discriminant >= 0.0).then(|| (g.length_squared() - r * r) / (c + discriminant.sqrt()))
}
