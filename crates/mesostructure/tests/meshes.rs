//! Every generator gives a non-empty, finite mesh inside its tile; height fields have two
//! triangles per cell.

use glam::{UVec3, Vec3};
use mesostructure::{HeightField, Mesostructure, bricks, maze};

const TILES: [UVec3; 3] = [UVec3::new(32, 32, 16), UVec3::new(16, 12, 8), UVec3::new(8, 8, 4)];

#[test]
fn meshes_are_finite_non_empty_and_inside_the_tile() {
    for size in TILES {
        for structure in Mesostructure::ALL {
            let triangles = structure.triangles(size);
            assert!(!triangles.is_empty(), "{} {size}", structure.name());
            // Periodic structures may straddle the x and y borders by less than a tile.
            let straddles = structure == Mesostructure::ChainMail;
            let margin = if straddles { Vec3::new(size.x as f32, size.y as f32, 0.0) } else { Vec3::ZERO };
            let limit = size.as_vec3() + margin + 1e-4;
            for triangle in &triangles {
                assert!(triangle.is_finite(), "{} {size}", structure.name());
                for v in triangle.0 {
                    let v = v + margin;
                    assert!(
                        v.cmpge(Vec3::splat(-1e-4)).all() && v.cmple(limit).all(),
                        "{} {size}: {v}",
                        structure.name()
                    );
                }
            }
        }
    }
}

#[test]
fn height_fields_have_two_triangles_per_cell() {
    for size in TILES {
        let cells = (size.x * size.y) as usize;
        assert_eq!(maze(size, 7).len(), 2 * cells);
        assert_eq!(bricks(size).len(), 2 * cells);
    }
    assert_eq!(HeightField::from_fn(3, 5, |x, y| x + y).triangles().len(), 30);
}

#[test]
fn maze_has_walls_and_floor_and_depends_on_the_seed() {
    let size = UVec3::new(32, 32, 16);
    let heights = |seed| {
        let mut z: Vec<f32> = maze(size, seed).iter().flat_map(|t| t.0.map(|v| v.z)).collect();
        z.dedup();
        z
    };
    let one = heights(1);
    assert!(one.contains(&12.0) && one.contains(&2.0));
    assert_ne!(one, heights(2));
}

#[test]
fn bricks_reach_their_top_and_their_mortar() {
    let size = UVec3::new(32, 32, 10);
    let z: Vec<f32> = bricks(size).iter().flat_map(|t| t.0.map(|v| v.z)).collect();
    let (low, high) = z.iter().fold((f32::MAX, f32::MIN), |(a, b), &h| (a.min(h), b.max(h)));
    assert_eq!((low, high), (2.0, 7.0));
}
