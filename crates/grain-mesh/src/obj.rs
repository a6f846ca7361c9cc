//! Wavefront OBJ input (with `tobj`) and a minimal OBJ writer for debugging and export.
//!
//! Loading triangulates polygons, merges every object of the file into one grain, and
//! gives each distinct `position/texcoord/normal` combination its own vertex. Normals come
//! from the file when every vertex has one, else they are area-weighted
//! ([`crate::area_weighted_normals`]). Materials (`mtllib`) are ignored.
//!
//! Vertex numbers in errors (and in the loaded mesh) count from 0 in order of first use by
//! a face, not in the file's `v` order; errors about a vertex also print its position.

use std::fmt;
use std::io::{self, BufRead, Write};
use std::path::{Path, PathBuf};

use glam::Vec3;

use crate::error::MeshError;
use crate::mesh::GrainMesh;

/// Why an OBJ file could not be read or written, naming the file.
#[derive(Debug)]
pub struct ObjError {
    /// The file.
    pub path: PathBuf,
    /// What went wrong with it.
    pub problem: ObjProblem,
}

/// What went wrong with an OBJ file.
#[derive(Debug)]
pub enum ObjProblem {
    /// The file could not be opened, read or written.
    Io(io::Error),
    /// The file is not valid OBJ (as `tobj` reports it).
    Parse(tobj::LoadError),
    /// The file parses, but its mesh is not a usable grain.
    Mesh(MeshError),
}

impl fmt::Display for ObjError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let path = self.path.display();
        match &self.problem {
            ObjProblem::Io(error) => write!(f, "grain OBJ file {path}: {error}"),
            ObjProblem::Parse(error) => write!(f, "grain OBJ file {path}: not valid OBJ: {error}"),
            ObjProblem::Mesh(error) => write!(f, "grain OBJ file {path}: {error}"),
        }
    }
}

impl std::error::Error for ObjError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match &self.problem {
            ObjProblem::Io(error) => Some(error),
            ObjProblem::Parse(error) => Some(error),
            ObjProblem::Mesh(error) => Some(error),
        }
    }
}

/// Loads a grain from the OBJ file at `path`.
pub fn load_obj(path: impl AsRef<Path>) -> Result<GrainMesh, ObjError> {
    let path = path.as_ref();
    let error = |problem| ObjError { path: path.to_path_buf(), problem };
    let bytes = std::fs::read(path).map_err(|e| error(ObjProblem::Io(e)))?;
    parse_obj(&mut bytes.as_slice()).map_err(error)
}

/// Parses a grain from OBJ text.
pub fn parse_obj(reader: &mut impl BufRead) -> Result<GrainMesh, ObjProblem> {
    let options = tobj::LoadOptions { single_index: true, triangulate: true, ..tobj::LoadOptions::default() };
    let (models, _materials) =
        tobj::load_obj_buf(reader, &options, |_| Err(tobj::LoadError::GenericFailure)).map_err(ObjProblem::Parse)?;
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut triangles = Vec::new();
    let mut every_vertex_has_a_normal = true;
    for model in &models {
        let mesh = &model.mesh;
        let base = positions.len() as u32;
        let vertex_count = mesh.positions.len() / 3;
        positions.extend(mesh.positions.chunks_exact(3).map(Vec3::from_slice));
        if mesh.normals.len() == mesh.positions.len() {
            normals.extend(mesh.normals.chunks_exact(3).map(Vec3::from_slice));
        } else {
            every_vertex_has_a_normal = false;
        }
        for corners in mesh.indices.chunks_exact(3) {
            // An index past this model's vertices must not alias the next model's.
            let corner = |i: u32| if (i as usize) < vertex_count { base + i } else { u32::MAX };
            triangles.push([corner(corners[0]), corner(corners[1]), corner(corners[2])]);
        }
    }
    let mesh = if every_vertex_has_a_normal && !normals.is_empty() {
        GrainMesh::with_normals(positions, normals, triangles)
    } else {
        GrainMesh::new(positions, triangles)
    };
    mesh.map_err(ObjProblem::Mesh)
}

/// Writes `mesh` as OBJ to `path`: one `v` and one `vn` per vertex and one `f v//vn` per
/// triangle. Floats are written in the shortest form that reads back to the same `f32`,
/// so [`load_obj`] gives back the same triangles. Materials are not written.
pub fn write_obj(mesh: &GrainMesh, path: impl AsRef<Path>) -> Result<(), ObjError> {
    let path = path.as_ref();
    let error = |e| ObjError { path: path.to_path_buf(), problem: ObjProblem::Io(e) };
    let file = std::fs::File::create(path).map_err(error)?;
    let mut writer = io::BufWriter::new(file);
    write_obj_to(mesh, &mut writer).and_then(|()| writer.flush()).map_err(error)
}

/// Writes `mesh` as OBJ text to `writer` (see [`write_obj`]).
pub fn write_obj_to(mesh: &GrainMesh, writer: &mut impl Write) -> io::Result<()> {
    writeln!(writer, "# grain-mesh: {} vertices, {} triangles", mesh.positions().len(), mesh.triangles().len())?;
    for p in mesh.positions() {
        writeln!(writer, "v {} {} {}", p.x, p.y, p.z)?;
    }
    for n in mesh.normals() {
        writeln!(writer, "vn {} {} {}", n.x, n.y, n.z)?;
    }
    for triangle in mesh.triangles() {
        let [a, b, c] = triangle.map(|i| u64::from(i) + 1);
        writeln!(writer, "f {a}//{a} {b}//{b} {c}//{c}")?;
    }
    Ok(())
}
