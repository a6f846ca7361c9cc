//! Procedural mesostructure tiles as triangle meshes, in voxel units, for the directional
//! distance map experiments of Mehra & Kumar (Table 3): a height-field maze, rounded
//! bricks, beads sunk in a plane, a ball above a plane, and chain mail (interlocked tori,
//! not a height field); height maps from PNG files, adaptively triangulated; and a torus
//! base mesh with texture coordinates and tangent frames to map tiles on.
//!
//! Every mesh lies inside the tile `[0, size.x] × [0, size.y] × [0, size.z]`, except that
//! periodic structures whose pieces straddle the tile's x or y border (chain mail) reach
//! out of it in x and y; their copies shifted by the tile size complete them. Height
//! fields from code become two triangles per cell.
//!
//! ```
//! use glam::UVec3;
//! let tile = UVec3::new(16, 16, 8);
//! let bricks = mesostructure::bricks(tile);
//! assert_eq!(bricks.len(), 2 * 16 * 16);
//! ```

mod height_field;
mod height_map;
mod spheres;
mod torus;

pub use height_field::{HeightField, bricks, bricks_height_field, maze, maze_height_field};
pub use height_map::{AdaptiveMesh, HeightMapError};
pub use spheres::{SpheresOnFloor, ball, ball_sphere, bead_spheres, beads, plane, sphere};
pub use torus::{BaseMesh, Ring, chain_mail, chain_mail_rings, torus_base_mesh};

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
    /// [`chain_mail`].
    ChainMail,
}

impl Mesostructure {
    /// All five, the maze with seed 1.
    pub const ALL: [Mesostructure; 5] = [Self::Maze(1), Self::Bricks, Self::Beads, Self::Ball, Self::ChainMail];

    /// A short lowercase name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Maze(_) => "maze",
            Self::Bricks => "bricks",
            Self::Beads => "beads",
            Self::Ball => "ball",
            Self::ChainMail => "chainmail",
        }
    }

    /// The triangle mesh of a tile of `size` voxels.
    pub fn triangles(self, size: glam::UVec3) -> Vec<ddm_compress::Triangle> {
        match self {
            Self::Maze(seed) => maze(size, seed),
            Self::Bricks => bricks(size),
            Self::Beads => beads(size),
            Self::Ball => ball(size),
            Self::ChainMail => chain_mail(size),
        }
    }
}
