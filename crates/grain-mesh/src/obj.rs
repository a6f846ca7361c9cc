//! Wavefront OBJ input (with `tobj`) and a minimal OBJ writer for debugging and export.
//!
//! Loading triangulates polygons, merges every object of the file into one grain, and
//! gives each distinct `position/texcoord/normal` combination its own vertex. Normals come
//! from the file when every vertex has one, else they are area-weighted
//! ([`crate::area_weighted_normals`]). Materials (`mtllib`) are ignored.
//!
//! Vertex numbers in errors (and in the loaded mesh) count from 0 in order of first use by
//! a face, not in the file's `v` order; errors about a vertex also print its position.
//! Errors that a line of the file causes — text that is not OBJ, a face with an index past
//! the vertices, a face using a NaN or infinite vertex (the face's line, not the `v`
//! line's: a vertex no face uses is not an error) — also name that line
//! ([`ObjError::line`]): the first line `n` such that the file's first `n` lines already
//! fail to load (found by bisection, re-reading prefixes of the file with `tobj`).

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
    /// The line (counting from 1) that causes the problem, where one does (see the
    /// module's documentation); `None` for problems of the whole file or mesh.
    pub line: Option<usize>,
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
        write!(f, "grain OBJ file {}", self.path.display())?;
        if let Some(line) = self.line {
            write!(f, ", line {line}")?;
        }
        write!(f, ": {}", self.problem)
    }
}

impl fmt::Display for ObjProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ObjProblem::Io(error) => write!(f, "{error}"),
            ObjProblem::Parse(error) => write!(f, "not valid OBJ: {error}"),
            ObjProblem::Mesh(error) => write!(f, "{error}"),
        }
    }
}

impl ObjProblem {
    /// Whether one line of the file causes the problem, so that every longer prefix of
    /// the file fails too: text that is not OBJ, a face index past the vertices, a face
    /// using a non-finite vertex.
    fn is_of_a_line(&self) -> bool {
        matches!(
            self,
            ObjProblem::Parse(_)
                | ObjProblem::Mesh(MeshError::IndexOutOfRange { .. } | MeshError::NonFiniteVertex { .. })
        )
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
    let error = |line, problem| ObjError { path: path.to_path_buf(), line, problem };
    let bytes = std::fs::read(path).map_err(|e| error(None, ObjProblem::Io(e)))?;
    parse_obj(&mut bytes.as_slice()).map_err(|problem| {
        let line = if problem.is_of_a_line() { failing_line(&bytes) } else { None };
        error(line, problem)
    })
}

/// The first line `n` (from 1) such that the first `n` lines of `bytes` fail to load with
/// a problem of a line ([`ObjProblem::is_of_a_line`]), or `None` if the whole text does
/// not. Such a failure persists in every longer prefix, so the lines are bisected.
fn failing_line(bytes: &[u8]) -> Option<usize> {
    // `ends[k]`: the length of the first `k + 1` lines, newline included.
    let ends: Vec<usize> = bytes
        .iter()
        .enumerate()
        .filter(|&(_, &b)| b == b'\n')
        .map(|(i, _)| i + 1)
        .chain((bytes.last() != Some(&b'\n') && !bytes.is_empty()).then_some(bytes.len()))
        .collect();
    let fails = |lines: usize| {
        let prefix = &bytes[..ends[lines - 1]];
        parse_obj(&mut &prefix[..]).err().is_some_and(|p| p.is_of_a_line())
    };
    if ends.is_empty() || !fails(ends.len()) {
        return None;
    }
    // Invariant: the first `lo` lines load (or fail otherwise), the first `hi` fail.
    let (mut lo, mut hi) = (0, ends.len());
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if fails(mid) { hi = mid } else { lo = mid }
    }
    Some(hi)
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
    let error = |e| ObjError { path: path.to_path_buf(), line: None, problem: ObjProblem::Io(e) };
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
