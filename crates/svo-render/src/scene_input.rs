//! The scenes a user names: one of [`NAMED_SCENES`], a closed OBJ mesh, or a grayscale PNG
//! height map, each as a [`Scene`] with a domain and a point to dolly towards
//! (`cargo xtask svo --scene NAME | --obj PATH | --height-map PNG`).

use std::path::{Path, PathBuf};

use glam::Vec3;
use svo_brick::{Domain, SurfaceSource};
use svo_scenes::{Attribute, Displaced, Fbm, HeightColours, HeightMapSurface, MeshSurface, Sphere, Torus};

use crate::error::RenderError;
use crate::scenes::{self, CREST, DOMAIN, GROOVE, Scene};

/// The names [`SceneInput::Named`] accepts, with what each is.
pub const NAMED_SCENES: [(&str, &str); 6] = [
    ("sphere", "a smooth sphere of radius 0.6"),
    ("bumpy-sphere", "a sphere of radius 0.6 with sine bumps of amplitude 0.03, coloured by height (Fig. 11)"),
    ("fbm-sphere", "a sphere of radius 0.6 displaced by 5 octaves of fBm, coloured by height (Fig. 8, 11)"),
    ("bumpy-plane", "a plane with sine bumps of amplitude 0.05, coloured by height"),
    ("box", "a box of half-sides 0.5 × 0.4 × 0.3 (edges and corners: H6)"),
    ("torus", "a torus of radii 0.55 and 0.2 (curvature of both signs)"),
];

/// The relief of a height map, as a fraction of the tile's width: white is this high.
pub const HEIGHT_MAP_RELIEF: f32 = 0.05;

/// A scene as a user gives it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum SceneInput {
    /// One of [`NAMED_SCENES`].
    Named(String),
    /// A closed, consistently oriented OBJ mesh (any size: the domain is fitted to it).
    Obj(PathBuf),
    /// A square 8- or 16-bit grayscale PNG: one tile of width 2, periodic, black at height 0
    /// and white at [`HEIGHT_MAP_RELIEF`] × 2, coloured from groove to crest.
    HeightMap(PathBuf),
}

impl SceneInput {
    /// The scene (errors name the scene, the file or the parameter).
    pub fn load(&self) -> Result<Scene, RenderError> {
        match self {
            SceneInput::Named(name) => named(name),
            SceneInput::Obj(path) => obj(path),
            SceneInput::HeightMap(path) => height_map(path),
        }
    }
}

fn scene_error(scene: &'static str) -> impl FnOnce(svo_scenes::SceneError) -> RenderError {
    move |source| RenderError::Scene { scene, source }
}

fn file_error(path: &Path) -> impl FnOnce(svo_scenes::SceneError) -> RenderError + '_ {
    move |source| RenderError::SceneFile { path: path.to_path_buf(), source }
}

/// One of [`NAMED_SCENES`] by name.
pub fn named(name: &str) -> Result<Scene, RenderError> {
    match name {
        "sphere" => scenes::sphere(0.6),
        "bumpy-sphere" => scenes::bumpy_sphere(0.6, 0.03, 20.0),
        "bumpy-plane" => scenes::bumpy_plane(0.05, 9.0),
        "box" => scenes::cuboid(Vec3::new(0.5, 0.4, 0.3)),
        "fbm-sphere" => {
            let sphere = Sphere::new(Vec3::ZERO, 0.6, Attribute::grey()).map_err(scene_error("fbm-sphere"))?;
            let fbm = Fbm::new(7, 5, 0.5, 0.03, 0.25).map_err(scene_error("fbm-sphere"))?;
            let source = Displaced::new(sphere, fbm, HeightColours::default()).map_err(scene_error("fbm-sphere"))?;
            let target = Vec3::NEG_Z * (0.6 + fbm.value(Vec3::NEG_Z * 0.6));
            Ok(Scene { name: "fbm-sphere", source: Box::new(source), domain: DOMAIN, target, outward: Vec3::NEG_Z })
        }
        "torus" => {
            let colour = Attribute::constant([0.35, 0.55, 0.8]).map_err(scene_error("torus"))?;
            let source = Torus::new(Vec3::ZERO, 0.55, 0.2, colour).map_err(scene_error("torus"))?;
            let target = Vec3::new(0.0, -0.75, 0.0);
            Ok(Scene { name: "torus", source: Box::new(source), domain: DOMAIN, target, outward: Vec3::NEG_Y })
        }
        _ => Err(RenderError::UnknownScene {
            name: name.to_owned(),
            known: NAMED_SCENES.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", "),
        }),
    }
}

/// A closed OBJ mesh in a cube domain 1.25 times its largest side, centred on its bounds,
/// dollied towards the point of the mesh nearest to the front (`−z`) of its bounds.
pub fn obj(path: &Path) -> Result<Scene, RenderError> {
    let colour = Attribute::constant([0.8, 0.7, 0.55]).map_err(file_error(path))?;
    let mesh = MeshSurface::from_obj(path, colour).map_err(file_error(path))?;
    let (lo, hi) = mesh.bounds();
    let extent = (hi - lo).max_element();
    if !(extent > 0.0 && extent.is_finite()) {
        return Err(RenderError::Setting {
            field: "the OBJ's bounds",
            value: f64::from(extent),
            expected: "a mesh with volume",
        });
    }
    let centre = 0.5 * (lo + hi);
    let size = 1.25 * extent;
    let domain = Domain { origin: centre - Vec3::splat(0.5 * size), size };
    let target = mesh.closest_point(Vec3::new(centre.x, centre.y, lo.z - extent));
    let outside = target + (target - centre).normalize_or(Vec3::NEG_Z) * (0.01 * extent);
    let outward = mesh.gradient(outside).normalize_or(Vec3::NEG_Z);
    Ok(Scene { name: "obj", source: Box::new(mesh), domain, target, outward })
}

/// A PNG height map as one periodic tile of width 2 over `[0, 2]²` (see
/// [`SceneInput::HeightMap`]), dollied towards its centre from above (`+z`).
pub fn height_map(path: &Path) -> Result<Scene, RenderError> {
    const WIDTH: f32 = 2.0;
    let relief = HEIGHT_MAP_RELIEF * WIDTH;
    let probe = image::image_dimensions(path)
        .map_err(|e| RenderError::SceneFile {
            path: path.to_path_buf(),
            source: svo_scenes::SceneError::Image { path: path.to_path_buf(), message: e.to_string() },
        })?
        .0
        .max(2);
    let texel = WIDTH / probe as f32;
    let colour = Attribute::function(move |h: f32| {
        let t = (h / relief).clamp(0.0, 1.0);
        std::array::from_fn(|c| GROOVE[c] + (CREST[c] - GROOVE[c]) * t)
    });
    let surface = HeightMapSurface::from_png(path, texel, relief, colour).map_err(file_error(path))?;
    let middle = 0.5 * WIDTH;
    let target = Vec3::new(middle, middle, surface.interpolate(middle, middle).0);
    let domain = Domain { origin: Vec3::new(0.0, 0.0, 0.5 * relief - 0.5 * WIDTH), size: WIDTH };
    Ok(Scene { name: "height-map", source: Box::new(surface), domain, target, outward: Vec3::Z })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_named_scene_loads_and_its_target_is_on_its_surface() {
        for (name, _) in NAMED_SCENES {
            let scene = SceneInput::Named(name.to_owned()).load().unwrap();
            let d = scene.source.distance(scene.target);
            assert!(d.abs() < 1e-4, "{name}: {d}");
            let g = scene.source.gradient(scene.target + scene.outward * 0.01).normalize();
            assert!(g.dot(scene.outward) > 0.7, "{name}: {g}");
        }
        let error = named("teapot").unwrap_err().to_string();
        assert!(error.contains("teapot") && error.contains("bumpy-sphere"), "{error}");
    }

    #[test]
    fn an_obj_and_a_height_map_load_and_bad_files_are_named() {
        let dir = std::env::temp_dir().join(format!("svo-render-inputs-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        // A tetrahedron, outward-facing.
        let obj_path = dir.join("tetra.obj");
        std::fs::write(&obj_path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n").unwrap();
        let scene = obj(&obj_path).unwrap();
        assert!(scene.source.distance(scene.target).abs() < 1e-4);
        assert!((scene.domain.size - 1.25).abs() < 1e-6);
        let png = dir.join("ramp.png");
        image::GrayImage::from_fn(16, 16, |x, y| image::Luma([((x + y) * 8) as u8])).save(&png).unwrap();
        let scene = height_map(&png).unwrap();
        assert!(scene.source.distance(scene.target).abs() < 1e-5);
        let missing = dir.join("missing.png");
        let error = SceneInput::HeightMap(missing).load().unwrap_err().to_string();
        assert!(error.contains("missing.png"), "{error}");
        let error = SceneInput::Obj(dir.join("nothing.obj")).load().unwrap_err().to_string();
        assert!(error.contains("nothing.obj"), "{error}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
