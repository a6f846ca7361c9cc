//! OBJ round trips of the procedural grains, and every kind of bad input giving an error
//! that names the file and the problem.

use std::path::{Path, PathBuf};

use glam::Vec3;
use grain_mesh::{
    Ball, CoffeeBean, GrainMesh, HexNut, MeshError, ObjError, ObjProblem, SandGrain, load_obj, write_obj,
};

/// A directory under the system's temporary directory, removed when dropped.
struct TempDir(PathBuf);

impl TempDir {
    fn new(name: &str) -> TempDir {
        let path = std::env::temp_dir().join(format!("grain-mesh-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&path).unwrap();
        TempDir(path)
    }

    /// Writes `contents` to `file` in the directory and returns its path.
    fn file(&self, file: &str, contents: &[u8]) -> PathBuf {
        let path = self.0.join(file);
        std::fs::write(&path, contents).unwrap();
        path
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Loads `path`, expecting an error whose message names the file and contains `problem`.
fn load_error(path: &Path, problem: &str) -> ObjError {
    let error = match load_obj(path) {
        Ok(mesh) => panic!("{} loaded: {:?}", path.display(), mesh.bounds()),
        Err(error) => error,
    };
    let message = error.to_string();
    assert!(message.contains(&path.display().to_string()), "{message}");
    assert!(message.contains(problem), "expected {problem:?} in {message:?}");
    assert_eq!(error.path, path);
    error
}

#[test]
fn procedural_grains_round_trip_through_obj() {
    let dir = TempDir::new("round-trip");
    let grains = [
        ("ball", Ball::default().mesh().unwrap()),
        ("bean", CoffeeBean::default().mesh().unwrap()),
        ("sand", SandGrain::default().mesh().unwrap()),
        ("nut", HexNut::default().mesh().unwrap()),
    ];
    for (name, mesh) in grains {
        let path = dir.0.join(format!("{name}.obj"));
        write_obj(&mesh, &path).unwrap();
        let loaded = load_obj(&path).unwrap();
        assert_eq!(loaded.triangles().len(), mesh.triangles().len(), "{name}");
        assert_eq!(loaded.positions().len(), mesh.positions().len(), "{name}");
        for t in 0..mesh.triangles().len() {
            // Same triangles, corner by corner, bit for bit.
            assert_eq!(loaded.triangle_corners(t), mesh.triangle_corners(t), "{name}: triangle {t}");
            for k in 0..3 {
                let original = mesh.normals()[mesh.triangles()[t][k] as usize];
                let read = loaded.normals()[loaded.triangles()[t][k] as usize];
                assert!(read.abs_diff_eq(original, 1e-6), "{name}: triangle {t} corner {k}: {read} vs {original}");
            }
        }
        assert_eq!(loaded.bounds(), mesh.bounds(), "{name}");
        assert!(loaded.materials().is_none(), "OBJ carries no per-vertex material");
    }
}

#[test]
fn polygons_are_triangulated_and_missing_normals_are_computed() {
    let dir = TempDir::new("cube");
    // A unit cube of quads, wound outward, without normals.
    let cube = b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
        f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
    let mesh = load_obj(dir.file("cube.obj", cube)).unwrap();
    assert_eq!(mesh.triangles().len(), 12);
    assert!(mesh.edge_report().is_closed_and_oriented());
    let bounds = mesh.bounds();
    assert!(bounds.centre.abs_diff_eq(Vec3::splat(0.5), 1e-6), "{}", bounds.centre);
    assert!((bounds.inner_radius - 0.5).abs() < 1e-6);
    assert!((bounds.outer_radius - 3.0_f32.sqrt() / 2.0).abs() < 1e-6);
    assert!((bounds.volume.unwrap() - 1.0).abs() < 1e-6);
    // Area-weighted normals at a corner point away from the cube, along its diagonal.
    let corner = mesh.normals()[mesh.positions().iter().position(|&p| p == Vec3::ONE).unwrap()];
    assert!(corner.dot(Vec3::ONE.normalize()) > 0.9, "{corner}");
}

#[test]
fn unreadable_file_is_an_io_error() {
    let dir = TempDir::new("missing");
    let error = load_error(&dir.0.join("no-such-grain.obj"), "No such file");
    assert!(matches!(error.problem, ObjProblem::Io(_)));
    // A directory is not a file either.
    let error = load_error(&dir.0, "grain OBJ file");
    assert!(matches!(error.problem, ObjProblem::Io(_)));
}

#[test]
fn file_without_triangles_is_an_error() {
    let dir = TempDir::new("empty");
    for (file, contents) in [("empty.obj", &b""[..]), ("points.obj", b"# only vertices\nv 0 0 0\nv 1 0 0\nv 0 1 0\n")] {
        let error = load_error(&dir.file(file, contents), "no triangles");
        assert!(matches!(error.problem, ObjProblem::Mesh(MeshError::NoTriangles)));
    }
}

#[test]
fn nan_vertex_is_an_error() {
    let dir = TempDir::new("nan");
    let path = dir.file("nan.obj", b"v 0 0 0\nv 1 0 0\nv 0 NaN 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
    // Vertices are numbered in order of first use by a face (file vertex 3 is used second).
    let error = load_error(&path, "vertex 1 has a non-finite position [0, NaN, 0]");
    assert!(matches!(error.problem, ObjProblem::Mesh(MeshError::NonFiniteVertex { vertex: 1, .. })));
    let path = dir.file("inf.obj", b"v 0 0 0\nv inf 0 0\nv 0 1 0\nf 1 2 3\n");
    load_error(&path, "non-finite position");
}

#[test]
fn mesh_collapsed_to_a_point_is_an_error() {
    let dir = TempDir::new("point");
    let path = dir.file("point.obj", b"v 2 3 4\nv 2 3 4\nv 2 3 4\nf 1 2 3\nf 3 2 1\n");
    let error = load_error(&path, "r = R = 0");
    assert!(matches!(error.problem, ObjProblem::Mesh(MeshError::ZeroExtent { .. })));
    // Distinct but collinear vertices: no area to centre or shade.
    let path = dir.file("line.obj", b"v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
    load_error(&path, "every triangle has zero area");
}

#[test]
fn malformed_obj_is_a_parse_error() {
    let dir = TempDir::new("malformed");
    for (file, contents) in [
        ("text.obj", &b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n"[..]),
        ("index.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n"),
        ("coordinates.obj", b"v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
        ("binary.obj", &[0xff, 0xfe, 0x00, 0x13, 0x37, b'\n', 0xc3, 0x28]),
    ] {
        let error = load_error(&dir.file(file, contents), "grain OBJ file");
        assert!(matches!(error.problem, ObjProblem::Parse(_)), "{file}: {error}");
    }
}

#[test]
fn zero_normal_in_the_file_is_an_error() {
    let dir = TempDir::new("normal");
    let path = dir.file("normal.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nvn 0 0 0\nf 1//1 2//2 3//1\n");
    let error = load_error(&path, "has a normal");
    assert!(matches!(error.problem, ObjProblem::Mesh(MeshError::InvalidNormal { .. })));
}

#[test]
fn open_mesh_is_centred_on_its_surface() {
    let dir = TempDir::new("open");
    // The unit cube without its top: no enclosed volume, so the surface centroid is used.
    let open = b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
        f 1 4 3 2\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
    let mesh: GrainMesh = load_obj(dir.file("open.obj", open)).unwrap();
    let bounds = mesh.bounds();
    assert_eq!(bounds.centre_kind, grain_mesh::CentreKind::SurfaceCentroid);
    assert_eq!(bounds.volume, None);
    // Area-weighted: the bottom at z = 0 (area 1) and four walls centred at z = 0.5 (area 4).
    assert!(bounds.centre.abs_diff_eq(Vec3::new(0.5, 0.5, 0.4), 1e-6), "{}", bounds.centre);
    assert!(mesh.edge_report().boundary_edges == 4);
}
