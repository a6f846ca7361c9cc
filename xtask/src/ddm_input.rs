//! The user's own mesostructure for `ddm-trace`, `ddm-compression` and `ddm-render`:
//! `--obj PATH [--scale S | --fit-slab]` or `--height-map PNG --height H` replaces the five
//! procedural tiles (`mesostructure::Mesostructure::ALL`) with one tile read from a file,
//! named after the file's stem in the tables and image names.
//!
//! **Units.** The tile is the command's grid of `X × Y × Z` voxels (`--size`, or the
//! command's default grid), the slab `[0, X] × [0, Y] × [0, Z]`, repeated with period `X`
//! in x and `Y` in y (`--periodic`, the default), or alone (`--clamp`, for `ddm-trace`,
//! `ddm-render`, `ddm-compression` and `bench-gpu ddm`: nothing lies outside the slab, the maps count the
//! tile's own triangles only, the patches see no neighbour, and the tracers (CPU and
//! WGSL) treat a ray that leaves the slab through a side as a miss; relief mapping, whose
//! height map wraps, is not run on such a tile). With `--clamp` the vertices must lie in
//! the slab itself and the periodicity check is not made.
//!
//! - `--obj PATH`: a Wavefront OBJ file (read with `grain_mesh::parse_obj`, the workspace's
//!   one OBJ reader, `tobj` inside: polygons are triangulated, every object of the file is
//!   merged, materials ignored) whose
//!   coordinates are voxels of that grid. `--scale S` multiplies every coordinate by `S`
//!   (about the origin; `S` positive and finite). `--fit-slab` moves the mesh's bounding
//!   box's lower corner to the origin and scales it uniformly (keeping its aspect) by the
//!   largest factor that keeps the box inside the slab: a mesh of one period then fills
//!   `[0, X] × [0, Y]` only when its box has the slab's x : y aspect, and otherwise fails
//!   the periodicity check below.
//! - `--height-map PNG --height H`: a PNG height map (read with
//!   `mesostructure::HeightField::from_png`: 8- or 16-bit grey, colour converted to
//!   luminance) of `W × H` pixels is one period of the tile: pixel `(i, j)` (row `j = 0`
//!   the image's top row) is the corner `(i X / W, j Y / H)` at height `level · H` voxels
//!   (`level ∈ [0, 1]`, black 0); the corners at `x = X` and `y = Y` are column and row 0
//!   again (the last column and row wrap to the first), so the tile is periodic by
//!   construction. Two triangles per cell, `2 W H` triangles; a height field (relief
//!   mapping runs on it, as on the maze and bricks; it does not on an OBJ tile).
//!
//! **Checks**, each an error naming the flag and the file (and for OBJ text that does not
//! parse, a face index past the vertices or a face using a NaN vertex, the line: see
//! [`failing_line`]): an unreadable file, text that is not OBJ, no triangles, a NaN or
//! infinite coordinate, `--scale` not positive and finite, `--height` missing, not
//! positive and finite, or above `Z`, a PNG that does not decode or has fewer than 2 × 2
//! pixels, `--obj` with `--height-map` and `--scale` with `--fit-slab` (they exclude each
//! other), `--scale`/`--fit-slab` without `--obj`, `--height` without `--height-map`.
//! Then, for OBJ tiles:
//!
//! - *the slab*: every vertex (after `--scale`/`--fit-slab`) has `z ∈ [0, Z]` and `x`, `y`
//!   within half a tile of it, `[−X/2, 3X/2] × [−Y/2, 3Y/2]` (pieces may straddle the
//!   tile's border in x and y, as the chain mail's rings do: the maps and tracers add the
//!   copies shifted by one tile), all within [`TOLERANCE`]. Geometry outside is an error
//!   naming the first vertex out and the mesh's extent (nothing is clipped);
//! - *periodicity*: the tracers repeat the tile, so where the mesh is open its border must
//!   continue in the neighbouring tile's copy. An *open edge* is an edge of exactly one
//!   triangle, vertices welded by equal position; each open edge's two ends and midpoint
//!   must lie, shifted by `(±X, 0)`, `(0, ±Y)` or `(±X, ±Y)`, on another open edge (within
//!   [`TOLERANCE`]; an open edge whose midpoint lies unshifted on another is a crack
//!   narrower than that, closed). A closed mesh has no open edge and passes; a height field passes when
//!   its heights on `x = 0` equal those on `x = X` (and `y = 0`, `y = Y`). The error names
//!   the first point (in triangle order) that has no match, and its triangle.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use ddm_compress::Triangle;
use glam::{UVec3, Vec3};
use grain_mesh::{MeshError, ObjProblem};
use mesostructure::{HeightField, Mesostructure};

use crate::cli::{Args, Flag, switch, value};

/// `--obj PATH`: a mesostructure tile from an OBJ file.
pub const OBJ: Flag = value("obj", "PATH");
/// `--scale S`: the OBJ's coordinates times `S`.
pub const SCALE: Flag = value("scale", "S");
/// `--fit-slab`: the OBJ's bounding box fitted into the slab.
pub const FIT_SLAB: Flag = switch("fit-slab");
/// `--height-map PNG`: a mesostructure tile from a grey PNG height map.
pub const HEIGHT_MAP: Flag = value("height-map", "PNG");
/// `--height H`: the height map's white, in voxels.
pub const HEIGHT: Flag = value("height", "H");
/// `--periodic`: the user's tile repeats in x and y (the default).
pub const PERIODIC: Flag = switch("periodic");
/// `--clamp`: the user's tile stands alone; nothing lies outside it.
pub const CLAMP: Flag = switch("clamp");
/// The pairs of these flags that exclude each other.
pub const EXCLUSIVE: &[(&str, &str)] = &[("obj", "height-map"), ("scale", "fit-slab"), ("periodic", "clamp")];

/// Voxels of slack in the slab and periodicity checks.
pub const TOLERANCE: f32 = 1e-3;

/// How an OBJ's coordinates become voxels of the tile.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Placement {
    /// Every coordinate times this factor (1 without `--scale`).
    Scale(f32),
    /// The bounding box moved to the origin and scaled uniformly into the slab.
    FitSlab,
}

/// The user's mesostructure, as the flags name it.
#[derive(Clone, Debug, PartialEq)]
pub enum TileSource {
    /// `--obj PATH [--scale S | --fit-slab]`.
    Obj {
        /// The OBJ file.
        path: PathBuf,
        /// How its coordinates are placed in the tile.
        placement: Placement,
    },
    /// `--height-map PNG --height H`.
    HeightMap {
        /// The PNG file.
        path: PathBuf,
        /// The height of white, in voxels.
        height: f32,
    },
}

/// A tile to run a command on: a procedural one or the user's.
#[derive(Clone, Debug, PartialEq)]
pub struct Tile {
    /// Its name in the tables and image file names.
    pub name: &'static str,
    /// Its triangles, in voxels of the command's grid.
    pub triangles: Vec<Triangle>,
    /// Whether it is a height field (relief mapping applies).
    pub height_field: bool,
    /// The procedural tile it is, if it is one (its own surface is then known:
    /// `ddm_experiments::reference`).
    pub structure: Option<Mesostructure>,
    /// Whether it repeats in x and y (`--periodic`, the default) or stands alone
    /// (`--clamp`): the maps, patches, tracers and ground truth all follow it.
    pub periodic_xy: bool,
}

/// A positive, finite number.
fn positive_number(text: &str) -> Result<f32, String> {
    match text.parse::<f32>() {
        Ok(x) if x > 0.0 && x.is_finite() => Ok(x),
        _ => Err("expected a positive finite number".to_owned()),
    }
}

impl TileSource {
    /// The source the flags name, `None` without `--obj` and `--height-map` (the procedural
    /// tiles). Errors name the flag and show the usage.
    pub fn from_args(args: &Args<'_>) -> Result<Option<Self>, String> {
        let scale = args.parse_value("scale", positive_number)?;
        let height = args.parse_value("height", positive_number)?;
        if let Some(path) = args.value("obj") {
            let placement =
                if args.flag("fit-slab") { Placement::FitSlab } else { Placement::Scale(scale.unwrap_or(1.0)) };
            if args.flag("height") {
                return Err(args.error("--height is for --height-map, not --obj"));
            }
            return Ok(Some(Self::Obj { path: PathBuf::from(path), placement }));
        }
        for flag in ["scale", "fit-slab"] {
            if args.flag(flag) {
                return Err(args.error(format!("--{flag} needs --obj PATH")));
            }
        }
        match (args.value("height-map"), height) {
            (Some(path), Some(height)) => Ok(Some(Self::HeightMap { path: PathBuf::from(path), height })),
            (Some(path), None) => Err(args.error(format!("--height-map {path} needs --height H (voxels)"))),
            (None, Some(_)) => Err(args.error("--height needs --height-map PNG")),
            (None, None) => Ok(None),
        }
    }

    /// The flag and file, for messages: `--obj tile.obj`.
    fn named(&self) -> String {
        match self {
            Self::Obj { path, .. } => format!("--obj {}", path.display()),
            Self::HeightMap { path, .. } => format!("--height-map {}", path.display()),
        }
    }

    /// Reads and checks the tile on a grid of `dims` voxels, repeating in x and y or
    /// alone (`periodic`; see the module's documentation).
    pub fn load(&self, dims: UVec3, periodic: bool) -> Result<Tile, String> {
        let (path, triangles, height_field) = match self {
            Self::Obj { path, placement } => (path, obj_triangles(path, *placement, dims, periodic)?, false),
            Self::HeightMap { path, height } => (path, height_map_triangles(path, *height, dims)?, true),
        };
        if periodic && let Err(problem) = check_periodic(&triangles, dims) {
            return Err(format!("{}: {problem} (or give --clamp for a tile that stands alone)", self.named()));
        }
        let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
        if stem.is_empty() {
            return Err(format!("{}: the file name has no stem to name the tile by", self.named()));
        }
        // One name per run, shared by every row and image of the tile.
        Ok(Tile {
            name: Box::leak(stem.into_boxed_str()),
            triangles,
            height_field,
            structure: None,
            periodic_xy: periodic,
        })
    }
}

/// Whether the user's tile repeats: `--clamp` (only with `--obj` or `--height-map`: the
/// procedural tiles repeat) makes it stand alone, `--periodic` is the default said aloud.
pub fn periodic_from_args(args: &Args<'_>, source: Option<&TileSource>) -> Result<bool, String> {
    if args.flag("clamp") && source.is_none() {
        return Err(args.error("--clamp needs --obj PATH or --height-map PNG (the procedural tiles repeat)"));
    }
    Ok(!args.flag("clamp"))
}

/// The tiles a command runs on: the user's (`source`, repeating or alone as `periodic`
/// says), else the five procedural ones.
pub fn tiles(source: Option<&TileSource>, dims: UVec3, periodic: bool) -> Result<Vec<Tile>, String> {
    match source {
        Some(source) => Ok(vec![source.load(dims, periodic)?]),
        None => Ok(Mesostructure::ALL
            .into_iter()
            .map(|structure| Tile {
                name: structure.name(),
                triangles: structure.triangles(dims),
                height_field: matches!(structure, Mesostructure::Maze(_) | Mesostructure::Bricks),
                structure: Some(structure),
                periodic_xy: true,
            })
            .collect()),
    }
}

/// A one-line description of the tile source for a command's header.
pub fn describe(source: Option<&TileSource>) -> String {
    match source {
        None => "the five procedural tiles".to_owned(),
        Some(TileSource::Obj { path, placement: Placement::Scale(s) }) => {
            format!("{} (coordinates in voxels × {s})", path.display())
        }
        Some(TileSource::Obj { path, placement: Placement::FitSlab }) => {
            format!("{} (bounding box fitted into the slab)", path.display())
        }
        Some(TileSource::HeightMap { path, height }) => format!("{} (heights 0..{height} voxels)", path.display()),
    }
}

/// The OBJ's triangles placed in the slab, or an error naming `--obj`, the file and (for
/// text that is not OBJ) the line.
fn obj_triangles(path: &Path, placement: Placement, dims: UVec3, periodic: bool) -> Result<Vec<Triangle>, String> {
    let named = format!("--obj {}", path.display());
    let bytes = std::fs::read(path).map_err(|e| format!("{named}: {e}"))?;
    let mesh = grain_mesh::parse_obj(&mut bytes.as_slice()).map_err(|problem| {
        let line = if is_of_a_line(&problem) { failing_line(&bytes) } else { None };
        let message = match problem {
            ObjProblem::Io(e) => e.to_string(),
            ObjProblem::Parse(e) => format!("not valid OBJ: {e}"),
            ObjProblem::Mesh(e) => e.to_string(),
        };
        match line {
            Some(line) => format!("{named}, line {line}: {message}"),
            None => format!("{named}: {message}"),
        }
    })?;
    let positions = mesh.positions();
    let (lo, hi) = positions.iter().fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), &p| (lo.min(p), hi.max(p)));
    let slab = dims.as_vec3();
    let (offset, factor, how) = match placement {
        Placement::Scale(s) => (Vec3::ZERO, s, if s == 1.0 { String::new() } else { format!(" (after --scale {s})") }),
        Placement::FitSlab => {
            let extent = hi - lo;
            let factor = [0, 1, 2]
                .into_iter()
                .filter(|&axis| extent[axis] > 0.0)
                .map(|axis| slab[axis] / extent[axis])
                .fold(f32::INFINITY, f32::min);
            if !(factor.is_finite() && factor > 0.0) {
                return Err(format!("{named}: --fit-slab: the mesh's extent {extent} cannot be scaled into the slab"));
            }
            (lo, factor, format!(" (after --fit-slab: × {factor})"))
        }
    };
    let place = |p: Vec3| (p - offset) * factor;
    let (lo, hi) = (place(lo), place(hi));
    if !(lo.is_finite() && hi.is_finite()) {
        return Err(format!("{named}: the coordinates overflow{how}"));
    }
    // A repeating tile's pieces may straddle its border by half a tile; a lone tile's not.
    let (min, max, within) = if periodic {
        (
            Vec3::new(-0.5 * slab.x, -0.5 * slab.y, 0.0),
            Vec3::new(1.5 * slab.x, 1.5 * slab.y, slab.z),
            "within half a tile of",
        )
    } else {
        (Vec3::ZERO, slab, "in (--clamp: the tile stands alone)")
    };
    if let Some(&p) = positions.iter().find(|&&p| {
        let q = place(p);
        q.cmplt(min - TOLERANCE).any() || q.cmpgt(max + TOLERANCE).any()
    }) {
        return Err(format!(
            "{named}: the vertex {} lies outside the slab{how}: z must be in [0, {}] and x, y {within} \
             [0, {}] × [0, {}], i.e. in [{}, {}] × [{}, {}] (voxels of the {}x{}x{} grid); the mesh's extent is \
             [{}, {}] × [{}, {}] × [{}, {}] (scale it with --scale S or --fit-slab)",
            place(p),
            slab.z,
            slab.x,
            slab.y,
            min.x,
            max.x,
            min.y,
            max.y,
            dims.x,
            dims.y,
            dims.z,
            lo.x,
            hi.x,
            lo.y,
            hi.y,
            lo.z,
            hi.z
        ));
    }
    Ok(mesh.triangles().iter().map(|t| Triangle(t.map(|i| place(positions[i as usize])))).collect())
}

/// Whether one line of the file causes `problem`, so that every longer prefix of the file
/// fails too: text that is not OBJ, a face index past the vertices, a face using a
/// non-finite vertex.
fn is_of_a_line(problem: &ObjProblem) -> bool {
    matches!(
        problem,
        ObjProblem::Parse(_) | ObjProblem::Mesh(MeshError::IndexOutOfRange { .. } | MeshError::NonFiniteVertex { .. })
    )
}

/// The first line `n` (from 1) such that the first `n` lines of `bytes` fail to parse with
/// a problem of a line ([`is_of_a_line`]), or `None` if the whole text does not: such a
/// failure persists in every longer prefix, so the lines are bisected, each prefix parsed
/// again by `grain_mesh::parse_obj` (the reader reports no line itself). For a non-finite
/// vertex this is the first face that uses it (a vertex no face uses is no error).
fn failing_line(bytes: &[u8]) -> Option<usize> {
    // `ends[k]`: the length of the first `k + 1` lines, newline included.
    let mut ends: Vec<usize> = bytes.iter().enumerate().filter(|&(_, &b)| b == b'\n').map(|(i, _)| i + 1).collect();
    if ends.last() != Some(&bytes.len()) && !bytes.is_empty() {
        ends.push(bytes.len());
    }
    let fails = |lines: usize| {
        let prefix = &bytes[..ends[lines - 1]];
        grain_mesh::parse_obj(&mut &prefix[..]).err().is_some_and(|p| is_of_a_line(&p))
    };
    if ends.is_empty() || !fails(ends.len()) {
        return None;
    }
    // The first `lo` lines parse (or fail otherwise), the first `hi` fail.
    let (mut lo, mut hi) = (0, ends.len());
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if fails(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Some(hi)
}

/// The height map's triangles: `W × H` pixels as `W × H` cells over the slab's `X × Y`,
/// the last column and row wrapped to the first.
fn height_map_triangles(path: &Path, height: f32, dims: UVec3) -> Result<Vec<Triangle>, String> {
    if !(height > 0.0 && height.is_finite()) {
        return Err(format!("--height {height}: expected a positive finite number"));
    }
    if height > dims.z as f32 {
        return Err(format!(
            "--height {height}: the height map {} would rise above the slab, whose depth is {} voxels (the {}x{}x{} \
             grid; --size sets it)",
            path.display(),
            dims.z,
            dims.x,
            dims.y,
            dims.z
        ));
    }
    let field = HeightField::from_png(path, height).map_err(|e| format!("--height-map: {e}"))?;
    // `from_png` gives the pixels as corners; here they are the cells' lower corners.
    let (w, h) = (field.width + 1, field.height + 1);
    let wrapped = HeightField {
        width: w,
        height: h,
        heights: (0..=h)
            .flat_map(|y| (0..=w).map(move |x| (x % w, y % h)))
            .map(|(x, y)| field.heights[(x + w * y) as usize])
            .collect(),
    };
    let cell = Vec3::new(dims.x as f32 / w as f32, dims.y as f32 / h as f32, 1.0);
    Ok(wrapped.triangles().into_iter().map(|t| Triangle(t.0.map(|p| p * cell))).collect())
}

/// A welded vertex: its position's bits.
type WeldKey = [u32; 3];

/// How many triangles have an edge, and the first one's index and the edge's ends.
type EdgeUse = (usize, usize, Vec3, Vec3);

/// Position bits with `-0.0` as `0.0`: equal positions weld.
fn weld_key(p: Vec3) -> WeldKey {
    p.to_array().map(|c| if c == 0.0 { 0 } else { c.to_bits() })
}

/// The distance from `p` to the segment `a`–`b`.
fn segment_distance(p: Vec3, a: Vec3, b: Vec3) -> f32 {
    let ab = b - a;
    let t = if ab.length_squared() > 0.0 { ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0) } else { 0.0 };
    p.distance(a + t * ab)
}

/// Whether the open edges of `triangles` continue across the tile's borders under shifts
/// by the tile size (see the module's documentation); the error says where not.
pub fn check_periodic(triangles: &[Triangle], dims: UVec3) -> Result<(), String> {
    // Open edges: edges (of welded vertices) that one triangle alone has.
    let mut edges: HashMap<(WeldKey, WeldKey), EdgeUse> = HashMap::new();
    for (index, triangle) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (triangle.0[k], triangle.0[(k + 1) % 3]);
            let (ka, kb) = (weld_key(a), weld_key(b));
            if ka == kb {
                continue;
            }
            let key = if ka < kb { (ka, kb) } else { (kb, ka) };
            edges.entry(key).and_modify(|e| e.0 += 1).or_insert((1, index, a, b));
        }
    }
    let mut open: Vec<(usize, Vec3, Vec3)> =
        edges.into_values().filter(|e| e.0 == 1).map(|(_, index, a, b)| (index, a, b)).collect();
    if open.is_empty() {
        return Ok(());
    }
    open.sort_by(|x, y| {
        x.0.cmp(&y.0).then(x.1.to_array().partial_cmp(&y.1.to_array()).unwrap_or(std::cmp::Ordering::Equal))
    });
    // A grid over x and y of cells about a 32nd of the tile: each open edge in every cell
    // its box (grown by the tolerance) touches.
    let slab = dims.as_vec3();
    let cell = (slab.x.max(slab.y) / 32.0).max(1.0);
    let cell_of = |x: f32, y: f32| ((x / cell).floor() as i64, (y / cell).floor() as i64);
    let mut grid: HashMap<(i64, i64), Vec<usize>> = HashMap::new();
    for (i, &(_, a, b)) in open.iter().enumerate() {
        let (x0, y0) = cell_of(a.x.min(b.x) - TOLERANCE, a.y.min(b.y) - TOLERANCE);
        let (x1, y1) = cell_of(a.x.max(b.x) + TOLERANCE, a.y.max(b.y) + TOLERANCE);
        for cx in x0..=x1 {
            for cy in y0..=y1 {
                grid.entry((cx, cy)).or_default().push(i);
            }
        }
    }
    let on_open_edge = |p: Vec3, except: usize| {
        grid.get(&cell_of(p.x, p.y)).is_some_and(|list| {
            list.iter().any(|&j| j != except && segment_distance(p, open[j].1, open[j].2) <= TOLERANCE)
        })
    };
    let shifts: Vec<Vec3> =
        [(-1.0, 0.0), (1.0, 0.0), (0.0, -1.0), (0.0, 1.0), (-1.0, -1.0), (-1.0, 1.0), (1.0, -1.0), (1.0, 1.0)]
            .into_iter()
            .map(|(sx, sy)| Vec3::new(sx * slab.x, sy * slab.y, 0.0))
            .collect();
    for (i, &(triangle, a, b)) in open.iter().enumerate() {
        // An open edge whose midpoint lies on another one is a crack within the tolerance
        // (a seam whose two sides were computed apart): closed.
        if on_open_edge(0.5 * (a + b), i) {
            continue;
        }
        for p in [a, 0.5 * (a + b), b] {
            if !shifts.iter().any(|&s| on_open_edge(p + s, i)) {
                return Err(format!(
                    "the tile is not periodic: the open border point {p} (on an edge of triangle {triangle}, counting \
                     from 0, that no other triangle shares) has no match shifted by the tile size (±{}, 0), (0, ±{}) \
                     or both within {TOLERANCE} voxel: the tracers repeat the tile in x and y, so the mesh's border on \
                     x = 0 must match the one on x = {} (and y = 0 the one on y = {}), and it may have no other open \
                     edge",
                    slab.x, slab.y, slab.x, slab.y
                ));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A directory under the system's temporary directory, removed when dropped.
    struct TempDir(PathBuf);

    impl TempDir {
        fn new(name: &str) -> TempDir {
            let path = std::env::temp_dir().join(format!("xtask-ddm-input-{}-{name}", std::process::id()));
            std::fs::create_dir_all(&path).unwrap();
            TempDir(path)
        }

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

    /// Writes `triangles` as an OBJ file with `grain_mesh::write_obj` (three vertices per
    /// triangle, as the procedural tiles give them).
    fn write_tile(dir: &TempDir, file: &str, triangles: &[Triangle]) -> PathBuf {
        let positions: Vec<Vec3> = triangles.iter().flat_map(|t| t.0).collect();
        let indices = (0..triangles.len() as u32).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
        let mesh = grain_mesh::GrainMesh::new(positions, indices).unwrap();
        let path = dir.0.join(file);
        grain_mesh::write_obj(&mesh, &path).unwrap();
        path
    }

    const DIMS: UVec3 = UVec3::new(12, 12, 6);

    fn obj(path: &Path) -> TileSource {
        TileSource::Obj { path: path.to_owned(), placement: Placement::Scale(1.0) }
    }

    /// Loads `source`, expecting an error containing each of `parts`.
    fn load_error(source: &TileSource, dims: UVec3, parts: &[&str]) -> String {
        let error = source.load(dims, true).err().unwrap_or_else(|| panic!("{source:?} loaded"));
        for part in parts {
            assert!(error.contains(part), "expected {part:?} in {error:?}");
        }
        error
    }

    #[test]
    fn every_procedural_tile_passes_the_checks_and_reads_back_from_obj() {
        let dir = TempDir::new("procedural");
        for structure in Mesostructure::ALL {
            let triangles = structure.triangles(DIMS);
            check_periodic(&triangles, DIMS).unwrap_or_else(|e| panic!("{}: {e}", structure.name()));
            let path = write_tile(&dir, &format!("{}.obj", structure.name()), &triangles);
            let tile = obj(&path).load(DIMS, true).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(tile.name, structure.name());
            assert_eq!(tile.triangles, triangles, "{}", structure.name());
            assert!(!tile.height_field);
        }
    }

    #[test]
    fn an_obj_of_the_bricks_gives_the_bricks_compression_rows() {
        use ddm_experiments::compression::{CompressionSettings, map_compression};
        let dir = TempDir::new("rows");
        let settings = CompressionSettings::quick();
        let bricks = Mesostructure::Bricks.triangles(settings.dims);
        let tile = obj(&write_tile(&dir, "bricks.obj", &bricks)).load(settings.dims, true).unwrap();
        let rows = |triangles: &[Triangle]| {
            map_compression("bricks", triangles, &settings)
                .unwrap()
                .into_iter()
                .map(|r| (r.map, r.triangles, r.cones, r.efficiencies))
                .collect::<Vec<_>>()
        };
        assert_eq!(rows(&tile.triangles), rows(&bricks));
    }

    #[test]
    fn scale_and_fit_slab_place_the_mesh() {
        let dir = TempDir::new("placement");
        let bricks = Mesostructure::Bricks.triangles(DIMS);
        let half: Vec<Triangle> = bricks.iter().map(|t| Triangle(t.0.map(|p| 0.5 * p))).collect();
        let path = write_tile(&dir, "half.obj", &half);
        let scaled = TileSource::Obj { path: path.clone(), placement: Placement::Scale(2.0) }.load(DIMS, true).unwrap();
        assert_eq!(scaled.triangles, bricks);
        // Shifted up and shrunk: the box goes back to the origin and fills the slab in x
        // and y (bricks span z 0.2 Z .. 0.7 Z, so z does not limit the factor).
        let moved: Vec<Triangle> =
            bricks.iter().map(|t| Triangle(t.0.map(|p| 0.25 * p + Vec3::new(-3.0, 5.0, 7.0)))).collect();
        let path = write_tile(&dir, "moved.obj", &moved);
        let fitted = TileSource::Obj { path, placement: Placement::FitSlab }.load(DIMS, true).unwrap();
        let (lo, hi) = fitted
            .triangles
            .iter()
            .flat_map(|t| t.0)
            .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| (lo.min(p), hi.max(p)));
        assert!(
            lo.abs_diff_eq(Vec3::ZERO, 1e-4) && (hi.x - 12.0).abs() < 1e-4 && (hi.y - 12.0).abs() < 1e-4,
            "{lo} {hi}"
        );
        assert!((hi.z - 0.5 * 6.0).abs() < 1e-3, "{hi}");
    }

    #[test]
    fn a_height_map_becomes_a_periodic_height_field_tile() {
        let dir = TempDir::new("height-map");
        let path = dir.0.join("ramp.png");
        // 4 × 3 pixels: a ramp in x, so the wrapped last column (back to 0) makes a cliff.
        let image = image::GrayImage::from_fn(4, 3, |x, _| image::Luma([(x * 85) as u8]));
        image.save(&path).unwrap();
        let tile = TileSource::HeightMap { path, height: 3.0 }.load(DIMS, true).unwrap();
        assert_eq!((tile.name, tile.height_field, tile.triangles.len()), ("ramp", true, 2 * 4 * 3));
        let corners: Vec<Vec3> = tile.triangles.iter().flat_map(|t| t.0).collect();
        for p in &corners {
            assert!(p.x >= 0.0 && p.x <= 12.0 && p.y >= 0.0 && p.y <= 12.0 && p.z >= 0.0 && p.z <= 3.0, "{p}");
        }
        // Pixel (3, ·) = 255 is the corner x = 3 · 12/4 = 9 at the full height; x = 12 wraps to 0.
        assert!(corners.iter().any(|p| p.x == 9.0 && p.z == 3.0));
        assert!(corners.iter().filter(|p| p.x == 12.0).all(|p| p.z == 0.0));
        check_periodic(&tile.triangles, DIMS).unwrap();
    }

    #[test]
    fn bad_obj_files_are_errors_naming_the_flag_the_file_and_the_line() {
        let dir = TempDir::new("bad-obj");
        let missing = dir.0.join("missing.obj");
        load_error(&obj(&missing), DIMS, &["--obj ", "missing.obj: "]);
        for (file, contents, line) in [
            ("text.obj", &b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n"[..], 4),
            ("index.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 7", 5),
            ("coordinates.obj", b"v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", 1),
            ("binary.obj", &[0xff, 0xfe, 0x00, 0x13, 0x37, b'\n', 0xc3, 0x28], 1),
            ("late.obj", b"# fine\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nv 1 1 zero\nf 1 2 3\n", 6),
        ] {
            let path = dir.file(file, contents);
            load_error(&obj(&path), DIMS, &["--obj ", &format!("{file}, line {line}: not valid OBJ")]);
        }
        let path = dir.file("empty.obj", b"v 0 0 0\nv 1 0 0\n");
        load_error(&obj(&path), DIMS, &["empty.obj: the mesh has no triangles"]);
        let path = dir.file("nan.obj", b"v 0 0 0\nv 1 0 0\nv 0 nan 0\nf 1 2 3\n");
        load_error(&obj(&path), DIMS, &["nan.obj, line 4: ", "non-finite position"]);
        let path = dir.file("inf.obj", b"v 0 0 0\nv inf 0 0\nv 0 1 0\nf 1 2 3\n");
        load_error(&obj(&path), DIMS, &["inf.obj, line 4: ", "non-finite position"]);
    }

    #[test]
    fn geometry_outside_the_slab_is_an_error_naming_the_extent() {
        let dir = TempDir::new("slab");
        let bricks = Mesostructure::Bricks.triangles(DIMS);
        let path = write_tile(&dir, "bricks.obj", &bricks);
        let source = TileSource::Obj { path, placement: Placement::Scale(3.0) };
        load_error(
            &source,
            DIMS,
            &[
                "bricks.obj: the vertex",
                "lies outside the slab (after --scale 3)",
                "z must be in [0, 6]",
                "the mesh's extent is [0, 36] × [0, 36] × [",
            ],
        );
        // Far outside in x (more than half a tile).
        let path = dir.file("far.obj", b"v 20 0 1\nv 21 0 1\nv 20 1 1\nf 1 2 3\n");
        load_error(&obj(&path), DIMS, &["far.obj: the vertex [20, 0, 1] lies outside the slab"]);
        // Below z = 0.
        let path = dir.file("below.obj", b"v 0 0 -1\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        load_error(&obj(&path), DIMS, &["below.obj: the vertex [0, 0, -1] lies outside the slab"]);
    }

    #[test]
    fn a_tile_whose_borders_differ_is_not_periodic() {
        let dir = TempDir::new("periodic");
        // The bricks with the corner (12, 12) raised: its heights on x = 12 no longer equal
        // those on x = 0.
        let mut bricks = Mesostructure::Bricks.triangles(DIMS);
        for t in &mut bricks {
            for p in &mut t.0 {
                if p.x == 12.0 && p.y == 12.0 {
                    p.z = 5.0;
                }
            }
        }
        let path = write_tile(&dir, "raised.obj", &bricks);
        load_error(
            &obj(&path),
            DIMS,
            &[
                "--obj ",
                "raised.obj: the tile is not periodic: the open border point",
                "has no match shifted by the tile size (±12, 0), (0, ±12)",
            ],
        );
        // One square (two triangles) that does not fill the tile: its whole border is open.
        let path = dir.file("square.obj", b"v 1 1 1\nv 3 1 1\nv 3 3 1\nv 1 3 1\nf 1 2 3 4\n");
        load_error(&obj(&path), DIMS, &["square.obj: the tile is not periodic: the open border point [1, 1, 1]"]);
        // The same square fills a 2 × 2 tile after --fit-slab, and repeats.
        let source = TileSource::Obj { path, placement: Placement::FitSlab };
        let tile = source.load(UVec3::new(2, 2, 1), true).unwrap();
        assert_eq!(tile.triangles.len(), 2);
    }

    #[test]
    fn a_tile_that_stands_alone_needs_no_match_but_must_lie_in_the_slab() {
        let dir = TempDir::new("clamp");
        // The square that is not periodic loads as a lone tile (--clamp) and says so.
        let path = dir.file("square.obj", b"v 1 1 1\nv 3 1 1\nv 3 3 1\nv 1 3 1\nf 1 2 3 4\n");
        let error = load_error(&obj(&path), DIMS, &["square.obj: the tile is not periodic"]);
        assert!(error.ends_with("(or give --clamp for a tile that stands alone)"), "{error}");
        let tile = obj(&path).load(DIMS, false).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!((tile.triangles.len(), tile.periodic_xy), (2, false));
        // A repeating tile's pieces may straddle its border by half a tile; a lone tile's
        // may not leave it.
        let path = dir.file("straddle.obj", b"v -1 1 1\nv 3 1 1\nv 3 3 1\nf 1 2 3\n");
        let error = obj(&path).load(DIMS, false).unwrap_err();
        assert!(
            error.contains("straddle.obj: the vertex [-1, 1, 1] lies outside the slab: z must be in [0, 6] and x, y in (--clamp: the tile stands alone) [0, 12] × [0, 12], i.e. in [0, 12] × [0, 12]"),
            "{error}"
        );
        assert!(obj(&path).load(DIMS, true).unwrap_err().contains("the tile is not periodic"));
    }

    #[test]
    fn bad_height_maps_are_errors_naming_the_flag_and_file() {
        let dir = TempDir::new("bad-png");
        let garbage = dir.file("garbage.png", b"not a png");
        let source = |path: &Path, height| TileSource::HeightMap { path: path.to_owned(), height };
        load_error(&source(&garbage, 2.0), DIMS, &["--height-map: ", "garbage.png is not a valid PNG"]);
        load_error(&source(&dir.0.join("none.png"), 2.0), DIMS, &["--height-map: cannot read height map", "none.png"]);
        let tiny = dir.0.join("tiny.png");
        image::GrayImage::new(1, 4).save(&tiny).unwrap();
        load_error(&source(&tiny, 2.0), DIMS, &["tiny.png has 1 × 4 pixels"]);
        load_error(&source(&tiny, 7.0), DIMS, &["--height 7: the height map", "tiny.png would rise above the slab"]);
        load_error(&source(&tiny, 0.0), DIMS, &["--height 0: expected a positive finite number"]);
    }
}
