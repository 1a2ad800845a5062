//! Wavefront OBJ: read (through tobj, keeping polygons) and write.
//!
//! What is read: `v x y z` positions (with an optional `w` that divides them, or `r g b` vertex
//! colours on every vertex), `f` faces of any arity by position index (texture and normal indices
//! are ignored; negative indices count back from the last vertex), and the subdivision tags of
//! OpenSubdiv's shape files: `t crease 2/1/0 a b s` tags the edge between the 0-based vertices
//! `a` and `b` as a crease of sharpness `s` (semi-sharp below 10), `t corner 1/1/0 v s` gives
//! vertex `v` a corner sharpness, and `t interpolateboundary`, `t creasemethod` and
//! `t smoothtriangles` set the mesh's subdivision options. Every face goes into one mesh whose
//! vertex `i` is the file's `i`-th `v` line (OBJ indices are global, so faces of different
//! objects that share a vertex stay joined). Face parts: `o NAME` names the faces after it (the
//! part name), `usemtl NAME` gives them the material's colour from the material libraries that
//! `mtllib` names (`Kd r g b` and `d` — or `Tr`, 1 − `d` — as alpha; a material without `Kd` is
//! no colour). A library is read only when the file was loaded from a folder
//! ([`read_obj_in`]) and the library is a regular file inside that folder (no absolute path,
//! no `..`, no link leading out, within the memory budget); one that is missing or refused is
//! skipped and its materials' faces read uncoloured, as OBJ files often travel without theirs.
//! Groups (`g`), smoothing groups, normals and texture coordinates are accepted and ignored. A line ending in `\` continues on the next (OBJ's line
//! continuation). A line whose keyword OBJ does not define is an error.
//!
//! What is written: the same subset, every coordinate with enough digits to read back the very
//! same `f64`, crease and corner tags as `t` lines with their sharpness (10, OpenSubdiv's
//! "infinitely sharp", for infinite), and the subdivision options that differ from the default.
//! A mesh with face parts is written in groups: an `o NAME` per part name (unnamed faces first,
//! before any `o`), and in each a `usemtl` per colour, the materials in a `.mtl` library beside
//! the file ([`write_mtl`]; `save` writes both): `Kd` the colour, `d` its alpha, named by its hex
//! colour. Faces without a colour come before any `usemtl` where they can (objects with no
//! colour at all first), else under `usemtl default`, a white material.
//!
//! How tobj is used: tobj numbers a model's vertices in the order faces first use them, drops
//! unused ones, and starts a new model (with its own vertex copies) at every `o`, `g` or
//! `usemtl`. To keep vertex ids, the reader hands tobj only the `v` and `f` lines, preceded by
//! one point element `f i` per vertex so that tobj's first-use order is the file order; the
//! point elements are skipped afterwards. Normals and texture coordinates are not handed over
//! either (they are ignored, and a bad texture index can overflow inside tobj).

use std::collections::HashMap;
use std::io::Write;
use std::path::{Component, Path, PathBuf};
use std::sync::Arc;

use super::error::IoError;
use super::weld::Weld;
use crate::diagnose::Repairs;
use crate::math::Vec3;
use crate::mesh::{BoundaryInterpolation, CreaseMethod, FacePart, Mesh, Rgba, SubdivOptions, TriangleSubdivision};

/// Keywords of the OBJ specification that the reader accepts and ignores (besides `v`, `f`
/// and `t`, which it reads, and comments).
const IGNORED_KEYWORDS: &[&str] = &[
    "vt",
    "vn",
    "vp",
    "l",
    "p",
    "o",
    "g",
    "s",
    "mg",
    "mtllib",
    "usemtl",
    "maplib",
    "usemap",
    "lod",
    "bevel",
    "c_interp",
    "d_interp",
    "shadow_obj",
    "trace_obj",
    "ctech",
    "stech",
    "cstype",
    "deg",
    "bmat",
    "step",
    "curv",
    "curv2",
    "surf",
    "parm",
    "trim",
    "hole",
    "scrv",
    "sp",
    "end",
    "con",
    "call",
    "csh",
];

/// OpenSubdiv's sharpness for an infinitely sharp crease or corner, written on `t` lines.
const INFINITE_SHARPNESS: &str = "10";

/// A subdivision tag read from a `t` line.
enum Tag {
    Crease { line: usize, a: u32, b: u32, sharpness: f64 },
    Corner { line: usize, v: u32, sharpness: f64 },
    Boundary(BoundaryInterpolation),
    Creasing(CreaseMethod),
    Triangles(TriangleSubdivision),
}

/// What the first pass over the text found.
struct Scan {
    vertex_count: usize,
    has_colors: bool,
    tags: Vec<Tag>,
    /// Each `f` line's (object name, material name) group, indexing `groups`.
    face_groups: Vec<u32>,
    groups: Vec<(Option<String>, Option<String>)>,
    /// The material libraries `mtllib` lines name, in order.
    libraries: Vec<String>,
    /// Faces of two corners (`f 1 2`: a line, not a face), dropped as a repair: the face's
    /// number among the file's `f` lines and its corners as 0-based vertex ids.
    short_faces: Vec<(u32, [usize; 2])>,
}

fn obj_error(path: &Path, line: usize, reason: impl Into<String>) -> IoError {
    IoError::Obj { path: path.into(), line, reason: reason.into() }
}

/// `text` with each line that ends in `\\` (OBJ's line continuation) joined to the next by a
/// space; an empty line is left after each joined line for each one it took, so every other
/// line keeps its number (and an error in a joined line names its first line).
fn join_continued_lines(text: &str) -> std::borrow::Cow<'_, str> {
    let continued = |l: &str| l.strip_suffix('\r').unwrap_or(l).ends_with('\\');
    if !text.split('\n').any(continued) {
        return std::borrow::Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 1);
    let mut taken = 0;
    let mut lines = text.split('\n').peekable();
    while let Some(line) = lines.next() {
        let body = line.strip_suffix('\r').unwrap_or(line);
        if let Some(head) = body.strip_suffix('\\').filter(|_| lines.peek().is_some()) {
            out.push_str(head);
            out.push(' ');
            taken += 1;
            continue;
        }
        out.push_str(body);
        for _ in 0..taken {
            out.push('\n');
        }
        taken = 0;
        if lines.peek().is_some() {
            out.push('\n');
        }
    }
    std::borrow::Cow::Owned(out)
}

/// The lines of `text` with their 1-based numbers, without line terminators.
fn numbered_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.split('\n').enumerate().map(|(i, l)| (i + 1, l.strip_suffix('\r').unwrap_or(l)))
}

/// The 0-based vertex an OBJ corner (`7`, `7/1`, `7//2`, `-1`: relative to the `count`
/// vertices read so far) names, or an error naming the line.
fn corner_vertex(word: &str, count: usize, path: &Path, line: usize) -> Result<usize, IoError> {
    let head = word.split('/').next().unwrap_or("");
    let i: i64 = head.parse().map_err(|_| obj_error(path, line, format!("`{head:.40}` is not a vertex index")))?;
    let v = if i > 0 { i - 1 } else { count as i64 + i };
    if i == 0 || v < 0 || v >= count as i64 {
        return Err(IoError::IndexOutOfRange {
            path: path.into(),
            at: format!("line {line}"),
            index: i,
            vertex_count: count,
        });
    }
    Ok(v as usize)
}

/// First pass: check every keyword, count the vertices and their colours, and read the tags.
/// A face of two corners is refused unless `repair`: then it is listed to be dropped.
fn scan(text: &str, path: &Path, repair: bool) -> Result<Scan, IoError> {
    let mut n = 0usize;
    let mut colored = 0usize;
    let mut first_plain = None;
    let mut first_colored = None;
    let mut tags = Vec::new();
    let mut face_groups = Vec::new();
    let mut groups: Vec<(Option<String>, Option<String>)> = vec![(None, None)];
    let mut current = 0u32;
    let mut libraries = Vec::new();
    let mut short_faces = Vec::new();
    let rest_of = |line: &str, keyword: &str| line.trim_start()[keyword.len()..].trim().to_string();
    for (number, line) in numbered_lines(text) {
        let mut words = line.split_whitespace();
        let Some(keyword) = words.next() else { continue };
        match keyword {
            "o" | "usemtl" => {
                let name = Some(rest_of(line, keyword)).filter(|n| !n.is_empty());
                let mut g = groups[current as usize].clone();
                if keyword == "o" {
                    g.0 = name;
                } else {
                    g.1 = name;
                }
                current = match groups.iter().position(|x| *x == g) {
                    Some(i) => i as u32,
                    None => {
                        groups.push(g);
                        (groups.len() - 1) as u32
                    }
                };
            }
            "mtllib" => {
                let whole = rest_of(line, keyword);
                if !whole.is_empty() {
                    libraries.push(whole);
                }
            }
            "v" => {
                match words.count() {
                    3 | 4 => {
                        first_plain.get_or_insert(number);
                    }
                    6 => {
                        colored += 1;
                        first_colored.get_or_insert(number);
                    }
                    n => {
                        return Err(obj_error(
                            path,
                            number,
                            format!("a vertex needs x y z, optionally w or r g b; this one has {n} numbers"),
                        ))
                    }
                }
                n += 1;
            }
            "f" => {
                let corners: Vec<&str> = words.collect();
                match corners.len() {
                    // tobj reads two corners as a line element and drops it (`ignore_lines`).
                    2 if repair => {
                        let face = (face_groups.len() + short_faces.len()) as u32;
                        let ends =
                            [corner_vertex(corners[0], n, path, number)?, corner_vertex(corners[1], n, path, number)?];
                        short_faces.push((face, ends));
                    }
                    k if k < 3 => {
                        return Err(obj_error(
                            path,
                            number,
                            format!("a face needs at least 3 vertices, this one has {k}"),
                        ));
                    }
                    _ => face_groups.push(current),
                }
            }
            "t" => {
                tags.extend(parse_tag(words, number, path)?);
            }
            k if k.starts_with('#') => {}
            k if IGNORED_KEYWORDS.contains(&k) => {}
            k => {
                let shown: String = k.chars().take(40).collect();
                return Err(obj_error(path, number, format!("unknown keyword {shown:?} (not an OBJ statement)")));
            }
        }
    }
    if colored != 0 && colored != n {
        let line = first_plain.max(first_colored).unwrap_or(0);
        return Err(obj_error(path, line, "some vertices have colours (v x y z r g b) and others do not"));
    }
    // tobj reads one model; the point elements `f 1` … `f n` make its vertex order the file's.
    Ok(Scan { vertex_count: n, has_colors: colored > 0, tags, face_groups, groups, libraries, short_faces })
}

/// What tobj reads, made on the fly from the text (no copy of the file): one point element
/// `f i` per vertex (so that tobj's first-use order is the file's vertex order), then the `v`
/// and `f` lines of the text, in order.
struct TobjInput<'a> {
    next_point: usize,
    vertex_count: usize,
    rest: &'a str,
    chunk: Vec<u8>,
    pos: usize,
}

impl<'a> TobjInput<'a> {
    const CHUNK: usize = 1 << 16;

    fn new(text: &'a str, vertex_count: usize) -> Self {
        TobjInput { next_point: 1, vertex_count, rest: text, chunk: Vec::with_capacity(Self::CHUNK + 256), pos: 0 }
    }

    /// Refills the chunk with the next lines (empty at the end).
    fn refill(&mut self) {
        self.chunk.clear();
        self.pos = 0;
        let mut ibuf = itoa::Buffer::new();
        while self.next_point <= self.vertex_count && self.chunk.len() < Self::CHUNK {
            self.chunk.extend_from_slice(b"f ");
            self.chunk.extend_from_slice(ibuf.format(self.next_point).as_bytes());
            self.chunk.push(b'\n');
            self.next_point += 1;
        }
        while !self.rest.is_empty() && self.chunk.len() < Self::CHUNK {
            let (line, rest) = self.rest.split_once('\n').unwrap_or((self.rest, ""));
            self.rest = rest;
            if matches!(line.split_whitespace().next(), Some("v" | "f")) {
                self.chunk.extend_from_slice(line.as_bytes());
                self.chunk.push(b'\n');
            }
        }
    }
}

impl std::io::Read for TobjInput<'_> {
    fn read(&mut self, out: &mut [u8]) -> std::io::Result<usize> {
        let avail = std::io::BufRead::fill_buf(self)?;
        let n = avail.len().min(out.len());
        out[..n].copy_from_slice(&avail[..n]);
        std::io::BufRead::consume(self, n);
        Ok(n)
    }
}

impl std::io::BufRead for TobjInput<'_> {
    fn fill_buf(&mut self) -> std::io::Result<&[u8]> {
        if self.pos == self.chunk.len() {
            self.refill();
        }
        Ok(&self.chunk[self.pos..])
    }

    fn consume(&mut self, amount: usize) {
        self.pos = (self.pos + amount).min(self.chunk.len());
    }
}

/// Parses the words after `t` (OpenSubdiv's shape-file tags, `t name ints/floats/strings ...`):
/// crease tags (a crease tag with `k` vertices sets the `k - 1` edges of the chain they form, to
/// one sharpness or one each), corner tags, `interpolateboundary` (0 none, 1 edge and corner,
/// 2 edge only), `creasemethod` (`normal` or `chaikin`) and `smoothtriangles` (`catmark` or
/// `smooth`); other tags (holes, face-varying options) are ignored, and so are zero or negative
/// sharpness values (smooth, as OpenSubdiv clamps them to 0).
fn parse_tag<'a>(mut words: impl Iterator<Item = &'a str>, line: usize, path: &Path) -> Result<Vec<Tag>, IoError> {
    let name = words.next().unwrap_or("");
    let (min_ints, floats_needed, strings_needed, form) = match name {
        "crease" => (2, 1, 0, "2/1/0 a b sharpness"),
        "corner" => (1, 1, 0, "1/1/0 v sharpness"),
        "interpolateboundary" => (1, 0, 0, "1/0/0 mode"),
        "creasemethod" => (0, 0, 1, "0/0/1 normal|chaikin"),
        "smoothtriangles" => (0, 0, 1, "0/0/1 catmark|smooth"),
        _ => return Ok(Vec::new()),
    };
    let bad = || obj_error(path, line, format!("malformed `t {name}` tag (expected `t {name} {form}`)"));
    let counts: Vec<usize> =
        words.next().unwrap_or("").split('/').map(str::parse).collect::<Result<_, _>>().map_err(|_| bad())?;
    let (ni, nf, ns) = match counts.as_slice() {
        [ni, nf, ns] => (*ni, *nf, *ns),
        [ni, nf] => (*ni, *nf, 0),
        _ => return Err(bad()),
    };
    if ni < min_ints || nf < floats_needed || ns < strings_needed {
        return Err(bad());
    }
    let ints: Vec<u32> =
        (0..ni).map(|_| words.next().and_then(|w| w.parse().ok())).collect::<Option<_>>().ok_or_else(bad)?;
    let floats: Vec<f64> =
        (0..nf).map(|_| words.next().and_then(|w| w.parse().ok())).collect::<Option<_>>().ok_or_else(bad)?;
    let strings: Vec<&str> = (0..ns).map(|_| words.next()).collect::<Option<_>>().ok_or_else(bad)?;
    if words.next().is_some() || floats.iter().any(|s| s.is_nan()) {
        return Err(bad());
    }
    Ok(match name {
        "crease" => {
            let edges = ni - 1;
            if nf != 1 && nf != edges {
                return Err(obj_error(
                    path,
                    line,
                    format!("`t crease` with {edges} edges needs 1 sharpness or {edges}, it has {nf}"),
                ));
            }
            ints.windows(2)
                .enumerate()
                .map(|(i, w)| (w, floats[if nf == 1 { 0 } else { i }]))
                .filter(|&(_, s)| s > 0.0)
                .map(|(w, sharpness)| Tag::Crease { line, a: w[0], b: w[1], sharpness })
                .collect()
        }
        "corner" => {
            if nf != 1 && nf != ni {
                return Err(obj_error(
                    path,
                    line,
                    format!("`t corner` with {ni} vertices needs 1 sharpness or {ni}, it has {nf}"),
                ));
            }
            ints.iter()
                .enumerate()
                .map(|(i, &v)| (v, floats[if nf == 1 { 0 } else { i }]))
                .filter(|&(_, s)| s > 0.0)
                .map(|(v, sharpness)| Tag::Corner { line, v, sharpness })
                .collect()
        }
        "interpolateboundary" => vec![Tag::Boundary(match ints[0] {
            0 => BoundaryInterpolation::None,
            1 => BoundaryInterpolation::EdgeAndCorner,
            2 => BoundaryInterpolation::EdgeOnly,
            m => return Err(obj_error(path, line, format!("`t interpolateboundary` mode {m} is not 0, 1 or 2"))),
        })],
        "creasemethod" => vec![Tag::Creasing(match strings[0] {
            "normal" | "uniform" => CreaseMethod::Uniform,
            "chaikin" => CreaseMethod::Chaikin,
            m => return Err(obj_error(path, line, format!("`t creasemethod` {m:?} is not normal or chaikin"))),
        })],
        _ => vec![Tag::Triangles(match strings[0] {
            "catmark" => TriangleSubdivision::CatmullClark,
            "smooth" => TriangleSubdivision::Smooth,
            m => return Err(obj_error(path, line, format!("`t smoothtriangles` {m:?} is not catmark or smooth"))),
        })],
    })
}

/// Finds the line responsible for an error tobj reported without one.
fn diagnose(text: &str, path: &Path, vertex_count: usize, tobj_error: &tobj::LoadError) -> IoError {
    let mut seen = 0usize;
    for (number, line) in numbered_lines(text) {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                seen += 1;
                let values: Vec<&str> = words.collect();
                if let Some(bad) = values.iter().find(|w| w.parse::<f64>().is_err()) {
                    let shown: String = bad.chars().take(40).collect();
                    return obj_error(path, number, format!("{shown:?} is not a number"));
                }
                if values.len() == 4 && values[3].parse::<f64>() == Ok(0.0) {
                    return obj_error(path, number, "the vertex weight w is 0");
                }
            }
            Some("f") => {
                for word in words {
                    let mut parts = word.split('/');
                    let first = parts.next().unwrap_or("");
                    let Ok(index) = first.parse::<i64>() else {
                        let shown: String = word.chars().take(40).collect();
                        return obj_error(path, number, format!("{shown:?} is not a vertex index"));
                    };
                    if parts.any(|p| !p.is_empty() && p.parse::<i64>().is_err()) || word.split('/').count() > 3 {
                        let shown: String = word.chars().take(40).collect();
                        return obj_error(path, number, format!("{shown:?} is not a vertex index"));
                    }
                    let resolved = if index < 0 { seen as i64 + index } else { index - 1 };
                    if index == 0 || resolved < 0 || resolved >= vertex_count as i64 {
                        return IoError::IndexOutOfRange {
                            path: path.into(),
                            at: format!("line {number}"),
                            index,
                            vertex_count,
                        };
                    }
                }
            }
            _ => {}
        }
    }
    obj_error(path, 0, format!("tobj: {tobj_error}"))
}

/// tobj's options: polygons kept, one index per position, point elements kept (they carry the
/// vertex order), lines dropped.
// Field by field: other tobj features (merging, reordering) add fields that must stay off.
#[allow(clippy::field_reassign_with_default)]
fn tobj_options() -> tobj::LoadOptions {
    let mut options = tobj::LoadOptions::default();
    options.triangulate = false;
    options.single_index = false;
    options.ignore_points = false;
    options.ignore_lines = true;
    options
}

/// Reads an OBJ file's text into a mesh, keeping its polygons and its vertex order.
///
/// Inputs: the bytes of the file (UTF-8) and the path to name in errors. See the module
/// documentation for what is read and what is ignored.
///
/// # Errors
/// - [`IoError::Obj`] with the line number: an unknown keyword, a number that does not parse,
///   a face with fewer than 3 vertices, colours on some vertices only, a malformed or
///   out-of-range `t` tag, text that is not UTF-8;
/// - [`IoError::IndexOutOfRange`] naming the line of a face index past the vertices (or 0);
/// - [`IoError::NonFinite`] for a NaN or infinite coordinate;
/// - [`IoError::Mesh`] when the faces are not a manifold mesh (the face number counts `f`
///   lines from 0).
///
/// See also [`write_obj`], [`super::load`].
pub fn read_obj(bytes: &[u8], path: &Path) -> Result<Mesh, IoError> {
    read_obj_report(bytes, None, path, Weld::DEFAULT, true).map(|r| r.0)
}

/// [`read_obj`] of a file in the folder `base`, whose material libraries (`mtllib`) are read
/// from that folder for the faces' colours (see the module documentation).
///
/// # Errors
/// As [`read_obj`]; [`IoError::Obj`] naming the library and its line for a malformed number
/// in a material library.
pub fn read_obj_in(bytes: &[u8], base: &Path, path: &Path) -> Result<Mesh, IoError> {
    read_obj_report(bytes, Some(base), path, Weld::DEFAULT, true).map(|r| r.0)
}

/// [`read_obj`], welding corners by `weld` ([`Weld::for_named_vertices`]: by default only
/// corners at equal coordinates, as an OBJ converted from an STL repeats each corner per
/// triangle, or one split at UV seams repeats a vertex), repairing a file that is not manifold
/// as written (or refusing it when `repair` is false), with what was repaired (see
/// [`super::assemble`]). A file with subdivision tags (`t`) is never welded: its tags name the
/// file's vertex ids, and repairs keep every one of them (vertices split per fan get new ids
/// after them).
///
/// # Errors
/// As [`read_obj`]; [`IoError::NotManifold`] when `repair` is false and the file is not a
/// manifold surface as written.
pub(crate) fn read_obj_report(
    bytes: &[u8],
    base: Option<&Path>,
    path: &Path,
    weld: Weld,
    repair: bool,
) -> Result<(Mesh, Repairs), IoError> {
    let text = std::str::from_utf8(bytes).map_err(|e| {
        let line = bytes[..e.valid_up_to()].iter().filter(|&&b| b == b'\n').count() + 1;
        obj_error(path, line, "the text is not valid UTF-8")
    })?;
    let joined = join_continued_lines(text);
    let text: &str = &joined;
    let scan = scan(text, path, repair)?;
    let options = tobj_options();
    let mut reader = TobjInput::new(text, scan.vertex_count);
    let (models, _) = tobj::load_obj_buf(&mut reader, &options, |_| Err(tobj::LoadError::GenericFailure))
        .map_err(|e| diagnose(text, path, scan.vertex_count, &e))?;
    let internal = |reason: &str| IoError::Internal { path: path.into(), reason: reason.into() };
    let [model] = <[tobj::Model; 1]>::try_from(models).map_err(|_| internal("tobj returned other than one model"))?;
    let m = model.mesh;
    let n = scan.vertex_count;
    if m.positions.len() != 3 * n || m.indices.len() < n || m.face_arities.len() < n {
        return Err(internal("tobj's vertex count differs from the file's"));
    }
    if m.indices[..n].iter().enumerate().any(|(i, &v)| v as usize != i) || m.face_arities[..n].iter().any(|&a| a != 1) {
        return Err(internal("tobj did not keep the file's vertex order"));
    }
    if scan.has_colors && m.vertex_color.len() != 3 * n {
        let e = tobj::LoadError::ColorParseError;
        return Err(diagnose(text, path, n, &e));
    }
    let positions: Vec<Vec3> = m.positions.chunks_exact(3).map(|p| Vec3::new(p[0], p[1], p[2])).collect();
    let arities = &m.face_arities[n..];
    let mut a = super::assemble::assemble(
        &positions,
        &m.indices[n..],
        arities,
        super::assemble::Topology::Indexed,
        if scan.tags.is_empty() { weld.for_named_vertices() } else { Weld::Off },
        repair,
        path,
    )?;
    if scan.groups.len() > 1 {
        let materials = match base {
            Some(base) => read_libraries(&scan.libraries, base)?,
            None => HashMap::new(),
        };
        let parts: Vec<FacePart> = scan
            .groups
            .iter()
            .map(|(object, material)| FacePart {
                color: material.as_ref().and_then(|m| materials.get(m).copied().flatten()),
                name: object.as_deref().map(Arc::from),
                origin: None,
            })
            .collect();
        if parts.iter().any(|p| p.color.is_some() || p.name.is_some()) {
            a.set_input_parts(&scan.face_groups, parts, path)?;
        }
    }
    let (mut mesh, mut repairs) = (a.mesh, a.repairs);
    // Two-corner faces, dropped before tobj: reported with the others dropped, every face
    // numbered among the file's `f` lines (the faces tobj read skip the two-corner ones).
    if !scan.short_faces.is_empty() {
        for d in &mut repairs.dropped_faces {
            let mut file_face = d.0;
            for &(short, _) in &scan.short_faces {
                if short <= file_face {
                    file_face += 1;
                }
            }
            d.0 = file_face;
        }
        for &(face, [u, v]) in &scan.short_faces {
            repairs.dropped_faces.push((face, (positions[u] + positions[v]) * 0.5));
        }
        repairs.dropped_faces.sort_by_key(|d| d.0);
    }
    if scan.has_colors {
        let colors: Vec<[f32; 4]> =
            m.vertex_color.chunks_exact(3).map(|c| [c[0] as f32, c[1] as f32, c[2] as f32, 1.0]).collect();
        let colors = a.vertex_from.iter().map(|&v| colors[v as usize]).collect();
        mesh.set_vertex_colors(Some(colors)).map_err(|e| IoError::from_mesh(path, e))?;
    }
    let mut options = SubdivOptions::default();
    for tag in &scan.tags {
        match *tag {
            Tag::Boundary(b) => options.boundary = b,
            Tag::Creasing(c) => options.crease = c,
            Tag::Triangles(t) => options.triangles = t,
            Tag::Crease { line, a, b, sharpness } => {
                mesh.crease_edges_sharpness(&[[a, b]], sharpness).map_err(|_| {
                    obj_error(
                        path,
                        line,
                        format!("`t crease` names vertices {a} and {b}, which are not joined by an edge"),
                    )
                })?;
            }
            Tag::Corner { line, v, sharpness } => {
                if v as usize >= mesh.vertex_count() {
                    return Err(obj_error(
                        path,
                        line,
                        format!(
                            "`t corner` names vertex {v}, but there are {} vertices (tags count from 0)",
                            mesh.vertex_count()
                        ),
                    ));
                }
                mesh.set_corner_sharpness(v, sharpness);
            }
        }
    }
    mesh.set_subdiv_options(options);
    Ok((mesh, repairs))
}

/// The colours of the materials in the libraries `names` (each an `mtllib` line's text: the
/// whole text names one file when there is one of that name, else each word names one) inside
/// the folder `base`; libraries missing or refused (see the module documentation) are skipped.
///
/// # Errors
/// [`IoError::Obj`] naming a library and its line: a `Kd`, `d` or `Tr` whose numbers do not
/// parse or lie outside 0–1.
fn read_libraries(names: &[String], base: &Path) -> Result<HashMap<String, Option<Rgba>>, IoError> {
    let mut out = HashMap::new();
    for line in names {
        let files: Vec<&str> =
            if library_file(base, line).is_some() { vec![line.as_str()] } else { line.split_whitespace().collect() };
        for name in files {
            let Some(file) = library_file(base, name) else { continue };
            let Ok(bytes) = super::uri::read_regular(&file) else { continue };
            parse_mtl(&String::from_utf8_lossy(&bytes), &file, &mut out)?;
        }
    }
    Ok(out)
}

/// The regular file named `name` inside `base` (a relative name without `..`, not leaving the
/// folder through a link), `None` otherwise.
fn library_file(base: &Path, name: &str) -> Option<PathBuf> {
    let relative = Path::new(name);
    if name.contains('\0') || !relative.components().all(|c| matches!(c, Component::Normal(_) | Component::CurDir)) {
        return None;
    }
    let base = if base.as_os_str().is_empty() { Path::new(".") } else { base };
    let real = base.join(relative).canonicalize().ok()?;
    (real.starts_with(base.canonicalize().ok()?) && real.is_file()).then_some(real)
}

/// Reads the materials of one `.mtl` text into `out`: `newmtl NAME`, `Kd r g b`, `d a` and
/// `Tr t` (alpha 1 − t); other statements are ignored. A material without `Kd` is no colour.
fn parse_mtl(text: &str, path: &Path, out: &mut HashMap<String, Option<Rgba>>) -> Result<(), IoError> {
    // Each material's diffuse colour and alpha, in the order defined.
    let mut defined: Vec<(String, Option<[f32; 3]>, f32)> = Vec::new();
    for (number, line) in numbered_lines(text) {
        let mut words = line.split_whitespace();
        let Some(keyword) = words.next() else { continue };
        if keyword == "newmtl" {
            defined.push((line.trim_start()["newmtl".len()..].trim().to_string(), None, 1.0));
            continue;
        }
        if !matches!(keyword, "Kd" | "d" | "Tr") {
            continue;
        }
        let Some(current) = defined.last_mut() else { continue };
        let k = if keyword == "Kd" { 3 } else { 1 };
        let bad = || obj_error(path, number, format!("`{keyword}` needs {k} number(s) from 0 to 1"));
        let v: Vec<f32> = words.map(str::parse::<f32>).collect::<Result<_, _>>().map_err(|_| bad())?;
        if v.len() != k || v.iter().any(|x| !(0.0..=1.0).contains(x)) {
            return Err(bad());
        }
        match keyword {
            "Kd" => current.1 = Some([v[0], v[1], v[2]]),
            "d" => current.2 = v[0],
            _ => current.2 = 1.0 - v[0],
        }
    }
    for (name, kd, alpha) in defined {
        out.insert(name, kd.map(|[r, g, b]| [r, g, b, alpha]));
    }
    Ok(())
}

/// The material library `save` writes beside an OBJ file at `path` for `mesh`: `STEM.mtl`,
/// `None` when the mesh has no face colours (then no library is written or named).
#[must_use]
pub fn material_library_path(mesh: &Mesh, path: &Path) -> Option<PathBuf> {
    mesh.has_face_colors().then(|| path.with_extension("mtl"))
}

/// Writes the material library of `mesh`'s face colours as `.mtl` text: one `newmtl` per
/// colour, named by its hex colour as [`write_obj_with_library`] names it in `usemtl`, with
/// `Kd` its colour and `d` its alpha (`default`, white, for faces without a colour). Numbers
/// are the shortest decimals that read back to the same `f32`.
///
/// # Errors
/// Only those of `out`.
pub fn write_mtl<W: Write>(mesh: &Mesh, out: &mut W) -> std::io::Result<()> {
    let groups = super::face_groups::FaceGroups::of(mesh);
    // `default` only when some uncoloured face comes after a `usemtl`.
    let default_used =
        grouped_faces(mesh).iter().any(|(h, _)| h.as_deref().is_some_and(|h| h.contains("usemtl default\n")));
    let used: Vec<usize> = (0..groups.colors.len()).filter(|&k| groups.colors[k].is_some() || default_used).collect();
    let mut text = format!("# blocksmith {}: {} materials\n", env!("CARGO_PKG_VERSION"), used.len());
    let mut fbuf = zmij::Buffer::new();
    let mut num = |x: f32| fbuf.format(x).trim_end_matches(".0").to_string();
    for k in used {
        let c = groups.colors[k].unwrap_or([1.0; 4]);
        let (r, g, b, a) = (num(c[0]), num(c[1]), num(c[2]), num(c[3]));
        text += &format!("newmtl {}\nKd {r} {g} {b}\nd {a}\nillum 1\n", groups.material_name(k));
    }
    out.write_all(text.as_bytes())
}

/// The faces of `mesh` in the order a grouped OBJ writes them, each run of one object and one
/// material headed by its `o` / `usemtl` lines: unnamed faces first, then objects without any
/// colour, then the rest; in each object faces without a colour first. (No groups for a mesh
/// without parts: every face in order.)
fn grouped_faces(mesh: &Mesh) -> Vec<(Option<String>, u32)> {
    let n = mesh.face_count() as u32;
    if !super::face_groups::has_parts(mesh) {
        return (0..n).map(|f| (None, f)).collect();
    }
    let groups = super::face_groups::FaceGroups::of(mesh);
    let colourless =
        |faces: &[u32]| faces.iter().all(|&f| groups.colors[groups.material_of_face(f) as usize].is_none());
    let mut order: Vec<usize> = (0..groups.objects.len()).collect();
    order.sort_by_key(|&k| (groups.objects[k].is_some(), !colourless(&groups.object_faces[k])));
    let mut out = Vec::with_capacity(n as usize);
    let mut material: Option<u32> = None;
    for k in order {
        let mut faces = groups.object_faces[k].clone();
        faces.sort_by_key(|&f| groups.colors[groups.material_of_face(f) as usize].is_some());
        let mut head = groups.objects[k].as_deref().map(|name| format!("o {name}\n"));
        for f in faces {
            let m = groups.material_of_face(f);
            // Faces without a colour need no `usemtl` until some material is in use.
            let uncoloured_before_any = groups.colors[m as usize].is_none() && material.is_none();
            if material != Some(m) && !uncoloured_before_any {
                material = Some(m);
                head.get_or_insert_with(String::new)
                    .push_str(&format!("usemtl {}\n", groups.material_name(m as usize)));
            }
            out.push((head.take(), f));
        }
    }
    out
}

/// [`write_obj`] naming the material library `library` (a file name beside the OBJ, see
/// [`material_library_path`]) in an `mtllib` line when given.
///
/// # Errors
/// Only those of `out`.
pub fn write_obj_with_library<W: Write>(mesh: &Mesh, out: &mut W, library: Option<&str>) -> std::io::Result<()> {
    write_obj_text(mesh, out, library)
}

/// Writes `mesh` as OBJ text: a header comment, one `v` line per vertex (with `r g b` when the
/// mesh has vertex colours; alpha is not written), one `f` line per face (1-based), and `t`
/// lines for crease edges and corners (0-based, as OpenSubdiv writes them).
///
/// Coordinates are written with the shortest decimal form that reads back as the same `f64`,
/// so [`read_obj`] returns the same positions, polygons, creases and corners.
///
/// # Errors
/// Only those of `out`.
///
/// See also [`read_obj`], [`super::save`].
pub fn write_obj<W: Write>(mesh: &Mesh, out: &mut W) -> std::io::Result<()> {
    write_obj_text(mesh, out, None)
}

fn write_obj_text<W: Write>(mesh: &Mesh, out: &mut W, library: Option<&str>) -> std::io::Result<()> {
    let mut buf: Vec<u8> = Vec::with_capacity(1 << 16);
    let mut fbuf = zmij::Buffer::new();
    let mut ibuf = itoa::Buffer::new();
    writeln!(
        buf,
        "# blocksmith {}: {} vertices, {} faces",
        env!("CARGO_PKG_VERSION"),
        mesh.vertex_count(),
        mesh.face_count()
    )?;
    let colors = mesh.vertex_colors();
    for (i, p) in mesh.positions().iter().enumerate() {
        buf.extend_from_slice(b"v");
        for c in [p.x, p.y, p.z] {
            buf.push(b' ');
            buf.extend_from_slice(fbuf.format(c).as_bytes());
        }
        if let Some(colors) = colors {
            for &c in &colors[i][..3] {
                buf.push(b' ');
                // The f64 form of the f32 value reads back exactly.
                buf.extend_from_slice(fbuf.format(f64::from(c)).as_bytes());
            }
        }
        buf.push(b'\n');
        if buf.len() > (1 << 16) {
            out.write_all(&buf)?;
            buf.clear();
        }
    }
    if let Some(name) = library {
        writeln!(buf, "mtllib {name}")?;
    }
    for (head, f) in grouped_faces(mesh) {
        if let Some(head) = head {
            buf.extend_from_slice(head.as_bytes());
        }
        buf.push(b'f');
        for v in mesh.face_vertices(f) {
            buf.push(b' ');
            buf.extend_from_slice(ibuf.format(v + 1).as_bytes());
        }
        buf.push(b'\n');
        if buf.len() > (1 << 16) {
            out.write_all(&buf)?;
            buf.clear();
        }
    }
    let mut sharpness =
        |s: f64| if s.is_finite() { fbuf.format(s).to_string() } else { INFINITE_SHARPNESS.to_string() };
    for ([a, b], s) in mesh.crease_sharpnesses() {
        writeln!(buf, "t crease 2/1/0 {a} {b} {}", sharpness(s))?;
    }
    for v in (0..mesh.vertex_count() as u32).filter(|&v| mesh.is_corner(v)) {
        writeln!(buf, "t corner 1/1/0 {v} {}", sharpness(mesh.corner_sharpness(v)))?;
    }
    let o = mesh.subdiv_options();
    match o.boundary {
        BoundaryInterpolation::EdgeOnly => {}
        BoundaryInterpolation::None => writeln!(buf, "t interpolateboundary 1/0/0 0")?,
        BoundaryInterpolation::EdgeAndCorner => writeln!(buf, "t interpolateboundary 1/0/0 1")?,
    }
    if o.crease == CreaseMethod::Chaikin {
        writeln!(buf, "t creasemethod 0/0/1 chaikin")?;
    }
    if o.triangles == TriangleSubdivision::Smooth {
        writeln!(buf, "t smoothtriangles 0/0/1 smooth")?;
    }
    out.write_all(&buf)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<Mesh, IoError> {
        read_obj(text.as_bytes(), Path::new("t/test.obj"))
    }

    fn round_trip(mesh: &Mesh) -> Mesh {
        let mut bytes = Vec::new();
        write_obj(mesh, &mut bytes).unwrap();
        read_obj(&bytes, Path::new("mem.obj")).unwrap()
    }

    #[test]
    fn round_trip_keeps_ids_positions_polygons_creases_and_corners() {
        // A torus of quads moved off the origin so every coordinate has many digits.
        let mut m = Mesh::torus(2.0, 0.5, 12, 8).translate(Vec3::new(0.1, -1.0 / 3.0, 1e-7));
        m.crease_edges(&[[0, 1], [8, 0]]).unwrap();
        m.set_corner(5, true);
        let back = round_trip(&m);
        assert_eq!(back.positions(), m.positions(), "positions must be bit-exact");
        assert_eq!(back.to_polygons(), m.to_polygons());
        assert_eq!(back.crease_pairs().len(), 2);
        assert!(back.find_halfedge(0, 1).is_some_and(|h| back.is_crease(h)));
        assert!(back.find_halfedge(8, 0).is_some_and(|h| back.is_crease(h)));
        assert!(back.is_corner(5) && (0..back.vertex_count() as u32).filter(|&v| back.is_corner(v)).count() == 1);
        assert!(back.vertex_colors().is_none());
    }

    #[test]
    fn round_trip_keeps_colours_and_unused_vertices() {
        let mut m =
            Mesh::from_polygons(vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(5.0, 5.0, 5.0)], &[[0u32, 1, 2]]).unwrap();
        let colors = vec![[0.1f32, 0.2, 0.3, 1.0], [1.0, 0.0, 0.5, 1.0], [0.7, 0.7, 0.7, 1.0], [0.0, 0.0, 0.0, 1.0]];
        m.set_vertex_colors(Some(colors.clone())).unwrap();
        let back = round_trip(&m);
        // Vertex 3 is used by no face; it keeps its id and position all the same.
        assert_eq!(back.positions(), m.positions());
        assert_eq!(back.vertex_colors(), Some(colors.as_slice()));
    }

    #[test]
    fn quads_load_as_quads_and_negative_indices_count_back() {
        let text = "# a unit square and a triangle on top, relative indices\n\
                    v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvn 0 0 1\nvt 0 0\n\
                    o square\nf 1/1/1 2//1 3 4\nv 0.5 2 0\no roof\nf -2 -3 -1\n";
        let m = read(text).unwrap();
        assert_eq!(m.to_polygons(), vec![vec![0, 1, 2, 3], vec![3, 2, 4]]);
    }

    #[test]
    fn objects_sharing_vertices_stay_joined() {
        // Two objects using the same two vertices: one mesh of 4 vertices, one interior edge.
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 -1 0\ng a\nf 1 2 3\ng b\nusemtl red\nf 2 1 4\n";
        let m = read(text).unwrap();
        assert_eq!((m.vertex_count(), m.edge_count(), m.face_count()), (4, 5, 2));
    }

    #[test]
    fn continued_lines_are_joined_and_later_lines_keep_their_numbers() {
        // A quad whose `f` line continues twice (with CRLF), then a junk line on line 9.
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 \\\r\n2 3 \\\n 4\n# end\n";
        let m = read(text).unwrap();
        assert_eq!(m.to_polygons(), vec![vec![0, 1, 2, 3]]);
        let e = read(&format!("{text}junk 1\n")).unwrap_err();
        assert!(matches!(e, IoError::Obj { line: 9, .. }), "{e}");
    }

    #[test]
    fn junk_line_names_its_line() {
        let e = read("v 0 0 0\nv 1 0 0\nv 0 1 0\nhello world\nf 1 2 3\n").unwrap_err();
        assert!(matches!(e, IoError::Obj { line: 4, .. }), "{e}");
        assert!(e.to_string().starts_with("t/test.obj:4: malformed OBJ: unknown keyword \"hello\""), "{e}");
    }

    #[test]
    fn bad_index_names_line_and_index() {
        let e = read("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n").unwrap_err();
        match &e {
            IoError::IndexOutOfRange { at, index: 9, vertex_count: 3, .. } => assert_eq!(at, "line 5"),
            _ => panic!("{e}"),
        }
        assert!(e.to_string().contains("t/test.obj"));
        // Index 0 does not exist in OBJ (indices start at 1).
        assert!(matches!(read("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"), Err(IoError::IndexOutOfRange { index: 0, .. })));
        assert!(matches!(
            read("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n"),
            Err(IoError::IndexOutOfRange { index: -4, .. })
        ));
    }

    #[test]
    fn malformed_numbers_and_short_faces_name_their_line() {
        assert!(matches!(read("v 0 0 0\nv 1 zero 0\n"), Err(IoError::Obj { line: 2, .. })));
        assert!(matches!(read("v 0 0\n"), Err(IoError::Obj { line: 1, .. })));
        let refused = |text: &str| {
            read_obj_report(text.as_bytes(), None, Path::new("t/test.obj"), Weld::DEFAULT, false).unwrap_err()
        };
        assert!(matches!(refused("v 0 0 0\nv 1 0 0\nf 1 2\n"), IoError::Obj { line: 3, .. }));
        assert!(matches!(read("v 0 0 0\nv 1 0 0\nf 1\n"), Err(IoError::Obj { line: 3, .. })));
        assert!(matches!(read("v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 x\n"), Err(IoError::Obj { line: 4, .. })));
        assert!(matches!(read("v 0 0 0 1 0 0\nv 1 0 0\n"), Err(IoError::Obj { line: 2, .. })));
        assert!(matches!(read("v 0 0 0\nt crease 2/1/0 0\n"), Err(IoError::Obj { line: 2, .. })));
        assert!(matches!(read_obj(b"v 0 0 0\n\xff\n", Path::new("x.obj")), Err(IoError::Obj { line: 2, .. })));
    }

    #[test]
    fn a_face_of_two_corners_is_dropped_and_reported_as_trimesh_drops_it() {
        // trimesh's notenoughindices.obj: a two-corner `f` (a line) before a triangle. Dropped as
        // a repair, numbered among the file's faces; the corner indices are still checked.
        let text = "v -500 0 500\nv 500 0 500\nv 500 500 500\nv 0 0 0\n\
                    f 1// 2//\nf 1// 2// 3//\nf 1 2 4\nf -1 -4\nf 1 1 2\n";
        let (m, repairs) =
            read_obj_report(text.as_bytes(), None, Path::new("t/test.obj"), Weld::DEFAULT, true).unwrap();
        assert_eq!((m.vertex_count(), m.face_count()), (4, 2));
        let dropped: Vec<(u32, Vec3)> = repairs.dropped_faces.clone();
        assert_eq!(
            dropped,
            [
                (0, Vec3::new(0.0, 0.0, 500.0)),
                (3, Vec3::new(-250.0, 0.0, 250.0)),
                (4, Vec3::new(-500.0 / 3.0, 0.0, 500.0))
            ]
        );
        let e = read_obj_report(b"v 0 0 0\nv 1 0 0\nf 1 3\n", None, Path::new("t/test.obj"), Weld::DEFAULT, true)
            .unwrap_err();
        assert!(matches!(e, IoError::IndexOutOfRange { index: 3, vertex_count: 2, .. }), "{e}");
    }

    #[test]
    fn nan_coordinate_is_an_error_naming_the_vertex() {
        let e = read("v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n").unwrap_err();
        assert!(matches!(e, IoError::NonFinite { vertex: 1, .. }), "{e}");
    }

    #[test]
    fn non_manifold_faces_are_repaired_or_refused_naming_the_edge() {
        // Three triangles on the edge 1–2: by default the third becomes a sheet of its own
        // (no vertex moves); with repair off, the load is refused naming the edge.
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 0 0 -1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n";
        let (m, repairs) =
            read_obj_report(text.as_bytes(), None, Path::new("t/test.obj"), Weld::DEFAULT, true).unwrap();
        assert!(m.is_manifold() && m.face_count() == 3 && m.component_count() == 2);
        assert_eq!((repairs.separated_edges.len(), repairs.separated_edges[0].separated), (1, 1));
        let e = read_obj_report(text.as_bytes(), None, Path::new("t/test.obj"), Weld::DEFAULT, false).unwrap_err();
        assert!(matches!(e, IoError::NotManifold { .. }), "{e}");
        assert!(e.to_string().contains("edge (0, 1)") && e.to_string().starts_with("t/test.obj"), "{e}");
    }

    #[test]
    fn crease_tag_on_a_non_edge_is_an_error() {
        let text = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nt crease 2/1/0 0 2 10\n";
        assert!(matches!(read(text), Err(IoError::Obj { line: 6, .. })));
        // Zero sharpness means "not a crease" and is accepted.
        let ok = read("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\nt crease 2/1/0 0 1 0\n").unwrap();
        assert_eq!(ok.crease_count(), 0);
    }

    #[test]
    fn unicode_spaces_and_crlf_are_read_like_tobj_reads_them() {
        // An ideographic space separates words as ASCII spaces do; CRLF line ends are fine.
        let m = read("v\u{3000}0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2\u{3000}3\r\n").unwrap();
        assert_eq!(m.to_polygons(), vec![vec![0, 1, 2]]);
    }

    #[test]
    fn many_vertices_cross_the_reader_chunks() {
        // More point elements and lines than one 64 KiB chunk of tobj's input holds.
        let m = Mesh::torus(2.0, 0.5, 100, 60);
        let back = round_trip(&m);
        assert_eq!(back.positions(), m.positions());
        assert_eq!(back.to_polygons(), m.to_polygons());
    }

    #[test]
    fn mtllib_is_never_read_from_bytes_nor_outside_the_folder() {
        // From bytes no library is read; from a folder, a library out of the folder or a
        // device is skipped (reading /dev/zero would never end), and its faces read uncoloured.
        let text = "mtllib /dev/zero ../../etc/passwd\nusemtl x\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
        let m = read(text).unwrap();
        assert_eq!(m.face_count(), 1);
        let dir = tempfile::tempdir().unwrap();
        let inner = dir.path().join("in");
        std::fs::create_dir(&inner).unwrap();
        std::fs::write(dir.path().join("out.mtl"), "newmtl x\nKd 1 0 0\n").unwrap();
        #[cfg(unix)]
        std::os::unix::fs::symlink(dir.path().join("out.mtl"), inner.join("link.mtl")).unwrap();
        for lib in ["/dev/zero", "../out.mtl", "link.mtl", "missing.mtl"] {
            let text = format!("mtllib {lib}\nusemtl x\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
            let m = read_obj_in(text.as_bytes(), &inner, Path::new("in/t.obj")).unwrap();
            assert_eq!((m.face_count(), m.face_color(0)), (1, None), "{lib}");
        }
    }

    #[test]
    fn materials_and_objects_are_face_colours_and_part_names() {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(
            dir.path().join("my lib.mtl"),
            "# two\nnewmtl red\nKd 1 0 0\nnewmtl glass\nd 0.25\nKd 0 0 1\nnewmtl plain\nNs 10\n",
        )
        .unwrap();
        // A tetrahedron: a face before any group, two red in `a`, one blue in `b`; `plain`
        // has no Kd, so no colour; `g` is ignored.
        let text =
            "mtllib my lib.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\no a\nusemtl red\nf 1 2 4\ng x\nf 2 3 4\n\
                    o b\nusemtl glass\nf 1 4 3\n";
        let m = read_obj_in(text.as_bytes(), dir.path(), Path::new("t.obj")).unwrap();
        let parts: Vec<(Option<Rgba>, Option<&str>)> =
            (0..4).map(|f| m.face_part(f).map_or((None, None), |p| (p.color, p.name.as_deref()))).collect();
        let (red, blue) = (Some([1.0, 0.0, 0.0, 1.0]), Some([0.0, 0.0, 1.0, 0.25]));
        assert_eq!(parts, [(None, None), (red, Some("a")), (red, Some("a")), (blue, Some("b"))]);
        assert!(m.is_closed());
        // A bad number in the library names it and its line.
        std::fs::write(dir.path().join("my lib.mtl"), "newmtl red\nKd 1 0 2\n").unwrap();
        let e = read_obj_in(text.as_bytes(), dir.path(), Path::new("t.obj")).unwrap_err();
        assert!(e.to_string().contains("my lib.mtl:2:") && e.to_string().contains("`Kd` needs 3"), "{e}");
    }

    #[test]
    fn grouped_writing_puts_uncoloured_faces_before_any_material() {
        // An uncoloured unnamed cube, a named cube with one uncoloured face among red ones.
        let plain = Mesh::cube(1.0);
        let mut named = Mesh::cube(1.0).translate(Vec3::new(3.0, 0.0, 0.0));
        named.set_color([1.0, 0.0, 0.0, 1.0]).unwrap();
        named.map_parts(|p| p.name = Some("lid".into()));
        let mut m = Mesh::combine(&[&plain, &named]).unwrap();
        let mut ids = m.face_part_ids().unwrap().to_vec();
        let mut parts = m.parts().to_vec();
        parts.push(FacePart { color: None, name: Some("lid".into()), origin: None });
        ids[6] = (parts.len() - 1) as u32;
        m.set_face_parts(ids, parts).unwrap();
        let mut text = Vec::new();
        write_obj_with_library(&m, &mut text, Some("m.mtl")).unwrap();
        let text = String::from_utf8(text).unwrap();
        let heads: Vec<&str> = text.lines().filter(|l| !l.starts_with("v ") && !l.starts_with("f ")).collect();
        assert_eq!(heads[1..], ["mtllib m.mtl", "o lid", "usemtl #ff0000"], "{text}");
        // The uncoloured face of `lid` comes first in its object, before any usemtl.
        let mut mtl = Vec::new();
        write_mtl(&m, &mut mtl).unwrap();
        let mtl = String::from_utf8(mtl).unwrap();
        assert!(mtl.contains("newmtl #ff0000\nKd 1 0 0\nd 1\n") && !mtl.contains("default"), "{mtl}");
    }

    #[test]
    fn empty_text_is_an_empty_mesh() {
        let m = read("# nothing\n\n").unwrap();
        assert_eq!((m.vertex_count(), m.face_count()), (0, 0));
    }
}
