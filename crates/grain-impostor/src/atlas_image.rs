//! One level of an atlas in `f32`, un-premultiplied: what the baker reads back, what the
//! mip builder ([`crate::mips`]) filters and what [`crate::atlas`] quantizes.

use glam::Vec3;

/// One texel of an atlas, **un-premultiplied** (attributes of the covered part, and α).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AtlasTexel {
    /// Normal in the grain's local frame (unit at level 0 where covered; mip averages may
    /// be shorter).
    pub normal: Vec3,
    /// Linear albedo.
    pub albedo: Vec3,
    /// Perceptual roughness.
    pub roughness: f32,
    /// Metallic.
    pub metallic: f32,
    /// Signed depth `dot(q, ω) / R` of [`octahedral_map::ViewFrame::depth`].
    pub depth: f32,
    /// Coverage α in `[0, 1]`.
    pub alpha: f32,
}

impl AtlasTexel {
    /// The attributes as one vector `(n, ρ, roughness, metallic, depth)`, for averaging.
    pub fn attributes(&self) -> [f32; 9] {
        let (n, a) = (self.normal, self.albedo);
        [n.x, n.y, n.z, a.x, a.y, a.z, self.roughness, self.metallic, self.depth]
    }

    /// A texel from [`attributes`](Self::attributes) and α.
    pub fn from_attributes(attributes: [f32; 9], alpha: f32) -> Self {
        let [nx, ny, nz, ax, ay, az, roughness, metallic, depth] = attributes;
        Self { normal: Vec3::new(nx, ny, nz), albedo: Vec3::new(ax, ay, az), roughness, metallic, depth, alpha }
    }
}

/// One level of an atlas in `f32`: `views` views of `side × side` texels, view-major, rows
/// top to bottom.
#[derive(Clone, Debug, PartialEq)]
pub struct AtlasImage {
    /// Texels per side.
    pub side: u32,
    /// Number of views.
    pub views: u32,
    /// `views · side²` texels.
    pub texels: Vec<AtlasTexel>,
}

impl AtlasImage {
    /// The index of texel `(x, y)` of `view`, or `None` outside.
    pub fn index(&self, view: u32, x: u32, y: u32) -> Option<usize> {
        (view < self.views && x < self.side && y < self.side).then(|| {
            ((u64::from(view) * u64::from(self.side) + u64::from(y)) * u64::from(self.side) + u64::from(x)) as usize
        })
    }

    /// The texels of one view, or `None` when `view` is out of range.
    pub fn view(&self, view: u32) -> Option<&[AtlasTexel]> {
        let per_view = (self.side * self.side) as usize;
        self.texels.get(view as usize * per_view..(view as usize + 1) * per_view)
    }
}
