//! Procedural mesostructure tiles as triangle meshes, in voxel units, for the directional
//! distance map experiments of Mehra & Kumar (Table 3): a height-field maze, rounded
//! bricks, beads sunk in a plane, and a ball above a plane.
//!
//! Every mesh lies inside the tile `[0, size.x] × [0, size.y] × [0, size.z]`. Height fields
//! become two triangles per cell; an adaptive triangulation (e.g. with `spade`) that
//! merges flat regions is a later step.
//!
//! ```
//! use glam::UVec3;
//! let tile = UVec3::new(16, 16, 8);
//! let bricks = mesostructure::bricks(tile);
//! assert_eq!(bricks.len(), 2 * 16 * 16);
//! ```

mod height_field;
mod spheres;

pub use height_field::{HeightField, bricks, maze};
pub use spheres::{ball, beads, plane, sphere};

/// The mesostructures of the experiments, by name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mesostructure {
    /// [`maze`] with the given seed.
    Maze(u64),
    /// [`bricks`].
    Bricks,
    /// [`beads`].
    Beads,
    /// [`ball`].
    Ball,
}

impl Mesostructure {
    /// All four, the maze with seed 1.
    pub const ALL: [Mesostructure; 4] = [Self::Maze(1), Self::Bricks, Self::Beads, Self::Ball];

    /// A short lowercase name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Maze(_) => "maze",
            Self::Bricks => "bricks",
            Self::Beads => "beads",
            Self::Ball => "ball",
        }
    }

    /// The triangle mesh of a tile of `size` voxels.
    pub fn triangles(self, size: glam::UVec3) -> Vec<ddm_compress::Triangle> {
        match self {
            Self::Maze(seed) => maze(size, seed),
            Self::Bricks => bricks(size),
            Self::Beads => beads(size),
            Self::Ball => ball(size),
        }
    }
}
