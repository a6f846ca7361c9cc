//! PNG height maps: read back exactly, bad files rejected with their name; adaptive
//! triangulations within their tolerance with fewer triangles than two per cell.

use std::path::PathBuf;

use glam::UVec3;
use mesostructure::{HeightField, HeightMapError, bricks_height_field, maze_height_field};

fn temp_dir() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("mesostructure-height-maps-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Projected area of the triangles (each counted with its orientation).
fn signed_area(triangles: &[ddm_compress::Triangle]) -> f32 {
    triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.0;
            0.5 * ((b - a).x * (c - a).y - (c - a).x * (b - a).y)
        })
        .sum()
}

#[test]
fn png_height_maps_are_read_back_and_bad_files_named() {
    let dir = temp_dir();
    let path = dir.join("ramp.png");
    let image = image::ImageBuffer::from_fn(5, 4, |x, y| image::Luma([(x * 10_000 + y * 1_000) as u16]));
    image.save(&path).unwrap();
    let field = HeightField::from_png(&path, 8.0).unwrap();
    assert_eq!((field.width, field.height), (4, 3));
    let expected = (3 * 10_000 + 2 * 1_000) as f32 / 65535.0 * 8.0;
    assert!((field.corner(3, 2) - expected).abs() < 1e-5);

    let missing = dir.join("missing.png");
    let error = HeightField::from_png(&missing, 1.0).unwrap_err();
    assert!(matches!(error, HeightMapError::Read { .. }) && error.to_string().contains("missing.png"), "{error}");
    let garbage = dir.join("garbage.png");
    std::fs::write(&garbage, b"not a png at all").unwrap();
    let error = HeightField::from_png(&garbage, 1.0).unwrap_err();
    assert!(matches!(error, HeightMapError::Decode { .. }) && error.to_string().contains("garbage.png"), "{error}");
    let tiny = dir.join("tiny.png");
    image::ImageBuffer::from_fn(1, 7, |_, _| image::Luma([0_u8])).save(&tiny).unwrap();
    let error = HeightField::from_png(&tiny, 1.0).unwrap_err();
    assert!(
        matches!(error, HeightMapError::TooSmall { width: 1, height: 7, .. }) && error.to_string().contains("tiny.png")
    );
    assert!(matches!(HeightField::from_png(&path, -1.0), Err(HeightMapError::BadScale(_))));
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn adaptive_meshes_stay_within_tolerance_with_fewer_triangles() {
    let size = UVec3::new(64, 64, 16);
    let wavy = HeightField::from_fn(64, 64, |x, y| 5.0 + 3.0 * ((x * 0.3).sin() + (y * 0.25).cos()));
    let cases =
        [("maze", maze_height_field(size, 1), 0.05), ("bricks", bricks_height_field(size), 0.05), ("wavy", wavy, 0.1)];
    for (name, field, tolerance) in cases {
        let regular = field.triangles().len();
        let adaptive = field.adaptive_triangles(tolerance).unwrap();
        println!(
            "{name}: {} triangles ({} vertices) instead of {regular}, max height error {:.4} (tolerance {tolerance})",
            adaptive.triangles.len(),
            adaptive.vertices,
            adaptive.max_error
        );
        assert!(adaptive.max_error <= tolerance + 1e-6, "{name}");
        assert!(adaptive.triangles.len() < regular, "{name}");
        // The triangles cover the tile once, counter-clockwise from above.
        let area = signed_area(&adaptive.triangles);
        assert!((area - (field.width * field.height) as f32).abs() < 1e-2, "{name}: area {area}");
        assert!(adaptive.triangles.iter().all(|t| {
            let [a, b, c] = t.0;
            (b - a).x * (c - a).y - (c - a).x * (b - a).y > 0.0
        }));
    }
    let flat = HeightField::from_fn(8, 8, |_, _| 1.0).adaptive_triangles(0.01).unwrap();
    assert_eq!(flat.max_error, 0.0);
    assert_eq!(flat.vertices, 32, "only the border samples");
    assert!(HeightField::from_fn(8, 8, |_, _| 1.0).adaptive_triangles(0.0).is_none());
}
