//! PLY, the Polygon File Format (Greg Turk, "The PLY Polygon File Format", 1994): read and
//! write, ASCII and binary (little- and big-endian), with polygon faces and vertex colours.
//!
//! A PLY file is a header naming its elements (`element vertex N`, `element face M`, …) and
//! their properties (scalars, or lists with a count before the items), then the data, element
//! after element. Writing gives `double` coordinates, so a binary or ASCII round trip keeps
//! every bit of every position; faces are `vertex_indices` lists (polygons kept); vertex colours
//! are `uchar` red, green, blue (and alpha when any colour is not opaque), as most tools expect,
//! and so are face colours (the face element's `red green blue [alpha]`, as MeshLab and Open3D
//! write them; faces without a colour in a mesh with some are written white). PLY has no part
//! names.
//!
//! Reading takes `x y z` of any numeric type, colours `red green blue [alpha]` (also
//! `diffuse_red …`; integers scaled by their type's maximum, floats as they are) on vertices
//! (vertex colours) and on faces (face colours), and the face lists `vertex_indices` or
//! `vertex_index`. Other properties (normals, texture
//! coordinates, …) and other elements (`edge`, `material`, …) are read past and ignored.
//! Before anything is allocated the element counts of the header are checked against the size
//! of the file: a header claiming 10¹² vertices in a small file is refused, naming the count.
//! Vertices are then welded by position ([`Weld`]), as exporters split them at normal and UV
//! seams; a file without near-duplicates keeps its vertices as they are.

use std::collections::HashMap;
use std::io::Write;
use std::path::Path;

use super::error::IoError;
use super::weld::Weld;
use crate::diagnose::Repairs;
use crate::math::Vec3;
use crate::mesh::{FacePart, Mesh};

/// How a PLY file stores its data.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum PlyEncoding {
    /// Text, one element entry per line.
    Ascii,
    /// Binary, little-endian (what most tools write).
    #[default]
    BinaryLittleEndian,
    /// Binary, big-endian.
    BinaryBigEndian,
}

impl PlyEncoding {
    /// The encoding named `"ascii"`, `"binary"` (little-endian), `"binary_little_endian"` or
    /// `"binary_big_endian"` (case-insensitive); `None` for any other name.
    #[must_use]
    pub fn from_name(name: &str) -> Option<PlyEncoding> {
        match name.to_ascii_lowercase().as_str() {
            "ascii" => Some(PlyEncoding::Ascii),
            "binary" | "binary_little_endian" => Some(PlyEncoding::BinaryLittleEndian),
            "binary_big_endian" => Some(PlyEncoding::BinaryBigEndian),
            _ => None,
        }
    }

    fn header_name(self) -> &'static str {
        match self {
            PlyEncoding::Ascii => "ascii",
            PlyEncoding::BinaryLittleEndian => "binary_little_endian",
            PlyEncoding::BinaryBigEndian => "binary_big_endian",
        }
    }
}

/// The scalar types of PLY, by both their old and their sized names.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn from_name(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    /// The value a colour channel of this type has at full intensity.
    fn full_scale(self) -> f64 {
        match self {
            Scalar::I8 => 127.0,
            Scalar::U8 => 255.0,
            Scalar::I16 => 32767.0,
            Scalar::U16 => 65535.0,
            Scalar::I32 => 2_147_483_647.0,
            Scalar::U32 => 4_294_967_295.0,
            Scalar::F32 | Scalar::F64 => 1.0,
        }
    }
}

/// What a property of the file is read for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Role {
    Coord(usize),
    Color(usize),
    Indices,
    Ignored,
}

#[derive(Debug)]
struct Property {
    /// `Some(count type)` for a list.
    list: Option<Scalar>,
    scalar: Scalar,
    role: Role,
}

#[derive(Debug)]
struct Element {
    name: String,
    count: u64,
    props: Vec<Property>,
}

fn ply_error(path: &Path, reason: String) -> IoError {
    IoError::Ply { path: path.into(), reason }
}

/// Reads a PLY file into a mesh, welding by [`Weld::DEFAULT`]; see [`read_ply_with`].
///
/// # Errors
/// As [`read_ply_with`].
pub fn read_ply(bytes: &[u8], path: &Path) -> Result<Mesh, IoError> {
    read_ply_with(bytes, path, Weld::DEFAULT)
}

/// Reads a PLY file (ASCII or binary) into a mesh: its vertices, its faces as polygons, its
/// vertex colours, welding vertices by `weld` (see the module documentation for what is read).
/// A file without faces gives a mesh of vertices only. `path` is only named in errors.
///
/// # Errors
/// - [`IoError::Ply`]: not PLY, an unknown format or type, a vertex element without `x y z`, a
///   face element without a vertex list, element counts the file is too small to hold
///   (checked before allocating), data ending early or a word that is not a number, an index
///   that is not a whole number, data left after the last element;
/// - [`IoError::IndexOutOfRange`] for a face naming a vertex that does not exist;
/// - [`IoError::NonFinite`] for a NaN or infinite coordinate;
/// - [`IoError::Mesh`] when the faces do not make a manifold mesh.
///
/// See also [`write_ply`], [`super::load_with`].
pub fn read_ply_with(bytes: &[u8], path: &Path, weld: Weld) -> Result<Mesh, IoError> {
    read_ply_report(bytes, path, weld, true).map(|r| r.0)
}

/// [`read_ply_with`], repairing a file that is not manifold as written (or refusing it when
/// `repair` is false), with what was repaired (see [`super::assemble`]).
///
/// # Errors
/// As [`read_ply_with`]; [`IoError::NotManifold`] when `repair` is false and the file is not a
/// manifold surface as written.
pub(crate) fn read_ply_report(bytes: &[u8], path: &Path, weld: Weld, repair: bool) -> Result<(Mesh, Repairs), IoError> {
    let (encoding, elements, body) = parse_header(bytes, path)?;
    check_sizes(encoding, &elements, bytes.len() - body, path)?;
    let mut src = match encoding {
        PlyEncoding::Ascii => {
            let text = std::str::from_utf8(&bytes[body..])
                .map_err(|_| ply_error(path, "ASCII PLY data that is not valid text".into()))?;
            Source::Ascii { lines: text.lines(), words: "".split_ascii_whitespace() }
        }
        PlyEncoding::BinaryLittleEndian => Source::Binary { data: &bytes[body..], pos: 0, big: false },
        PlyEncoding::BinaryBigEndian => Source::Binary { data: &bytes[body..], pos: 0, big: true },
    };
    let mut positions: Vec<Vec3> = Vec::new();
    let mut colors: Option<Vec<[f32; 4]>> = None;
    let mut indices: Vec<u32> = Vec::new();
    let mut arities: Vec<u32> = Vec::new();
    let mut face_colors: Vec<[f32; 4]> = Vec::new();
    let mut seen_vertices = false;
    for el in &elements {
        let at = |i: u64| At { element: &el.name, i };
        match el.name.as_str() {
            "vertex" if !seen_vertices => {
                seen_vertices = true;
                // Checked against the file's size: at most one entry per byte.
                positions.reserve_exact(el.count as usize);
                let scales: Vec<f64> = el.props.iter().map(|p| p.scalar.full_scale()).collect();
                let has_color = el.props.iter().any(|p| matches!(p.role, Role::Color(_)));
                let mut cols = Vec::with_capacity(if has_color { el.count as usize } else { 0 });
                for i in 0..el.count {
                    let mut c = [0.0f64; 3];
                    let mut rgba = [0.0f32, 0.0, 0.0, 1.0];
                    for (p, &scale) in el.props.iter().zip(&scales) {
                        if p.list.is_some() {
                            src.skip_list(p, path, at(i))?;
                            continue;
                        }
                        let x = src.scalar(p.scalar, path, at(i))?;
                        match p.role {
                            Role::Coord(k) => c[k] = x,
                            Role::Color(k) => rgba[k] = (x / scale) as f32,
                            _ => {}
                        }
                    }
                    src.end_entry();
                    positions.push(Vec3::new(c[0], c[1], c[2]));
                    if has_color {
                        cols.push(rgba);
                    }
                }
                if has_color {
                    colors = Some(cols);
                }
            }
            "face" if arities.is_empty() => {
                arities.reserve_exact(el.count as usize);
                indices.reserve(3 * el.count as usize);
                let has_color = el.props.iter().any(|p| matches!(p.role, Role::Color(_)));
                if has_color {
                    face_colors.reserve_exact(el.count as usize);
                }
                for i in 0..el.count {
                    let mut rgba = [0.0f32, 0.0, 0.0, 1.0];
                    for p in &el.props {
                        match (p.list, p.role) {
                            (Some(count_type), Role::Indices) => {
                                let n = src.count(count_type, path, at(i))?;
                                for _ in 0..n {
                                    let v = src.scalar(p.scalar, path, at(i))?;
                                    indices.push(index(v, positions.len(), path, at(i))?);
                                }
                                arities.push(n as u32);
                            }
                            (Some(_), _) => src.skip_list(p, path, at(i))?,
                            (None, Role::Color(k)) => {
                                rgba[k] = (src.scalar(p.scalar, path, at(i))? / p.scalar.full_scale()) as f32;
                            }
                            (None, _) => {
                                src.scalar(p.scalar, path, at(i))?;
                            }
                        }
                    }
                    src.end_entry();
                    if has_color {
                        face_colors.push(rgba.map(|c| c.clamp(0.0, 1.0)));
                    }
                    if arities.len() as u64 != i + 1 {
                        return Err(ply_error(path, format!("{} has no vertex list", at(i))));
                    }
                    let a = arities[i as usize];
                    if a < 3 {
                        return Err(ply_error(path, format!("{} has {a} vertices (at least 3 needed)", at(i))));
                    }
                }
            }
            _ => {
                for i in 0..el.count {
                    for p in &el.props {
                        if p.list.is_some() {
                            src.skip_list(p, path, at(i))?;
                        } else {
                            src.scalar(p.scalar, path, at(i))?;
                        }
                    }
                    src.end_entry();
                }
            }
        }
    }
    if !src.is_done() {
        return Err(ply_error(path, "data is left after the last element the header declares".into()));
    }
    build(positions, colors, indices, arities, face_colors, weld, repair, path)
}

/// Where a value is read, for errors: entry `i` of element `element` ("face 12"). Formatted only
/// when an error is made, so that reading costs no allocation per value.
#[derive(Clone, Copy)]
struct At<'a> {
    element: &'a str,
    i: u64,
}

impl std::fmt::Display for At<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} {}", self.element, self.i)
    }
}

/// A face index read as a number: a whole number below the vertex count.
fn index(v: f64, vertex_count: usize, path: &Path, at: At<'_>) -> Result<u32, IoError> {
    if v.fract() != 0.0 || v < 0.0 || v >= vertex_count as f64 {
        if v.fract() == 0.0 && v.is_finite() {
            return Err(IoError::IndexOutOfRange {
                path: path.into(),
                at: at.to_string(),
                index: v as i64,
                vertex_count,
            });
        }
        return Err(ply_error(path, format!("{at}: vertex index {v} is not a whole number")));
    }
    Ok(v as u32)
}

/// Welds by `rule` and builds the mesh (repaired if need be: see [`super::assemble`]), colours
/// carried to the kept vertices and faces (`face_colors`: one per face, or empty).
#[allow(clippy::too_many_arguments)]
fn build(
    positions: Vec<Vec3>,
    colors: Option<Vec<[f32; 4]>>,
    indices: Vec<u32>,
    arities: Vec<u32>,
    face_colors: Vec<[f32; 4]>,
    rule: Weld,
    repair: bool,
    path: &Path,
) -> Result<(Mesh, Repairs), IoError> {
    // Faces only name existing vertices (checked while reading), so a vertex used by no face
    // is kept as it is, like in OBJ.
    if let Some(v) = positions.iter().position(|p| !p.is_finite()) {
        let p = positions[v];
        return Err(IoError::NonFinite { path: path.into(), vertex: v, x: p.x, y: p.y, z: p.z });
    }
    let mut a = super::assemble::assemble(
        &positions,
        &indices,
        &arities,
        super::assemble::Topology::Indexed,
        rule,
        repair,
        path,
    )?;
    if !face_colors.is_empty() {
        // One part per distinct colour.
        let mut parts: Vec<FacePart> = Vec::new();
        let mut ids: HashMap<[u32; 4], u32> = HashMap::new();
        let face_parts: Vec<u32> = face_colors
            .iter()
            .map(|c| {
                *ids.entry(c.map(f32::to_bits)).or_insert_with(|| {
                    parts.push(FacePart::with_color(*c));
                    (parts.len() - 1) as u32
                })
            })
            .collect();
        a.set_input_parts(&face_parts, parts, path)?;
    }
    let mut mesh = a.mesh;
    if let Some(c) = colors {
        let colors = a.vertex_from.iter().map(|&v| c[v as usize]).collect();
        mesh.set_vertex_colors(Some(colors)).map_err(|e| IoError::from_mesh(path, e))?;
    }
    Ok((mesh, a.repairs))
}

/// Parses the header: the encoding, the elements, and where the data starts.
fn parse_header(bytes: &[u8], path: &Path) -> Result<(PlyEncoding, Vec<Element>, usize), IoError> {
    let magic_len = if bytes.starts_with(b"ply\n") {
        4
    } else if bytes.starts_with(b"ply\r\n") {
        5
    } else {
        return Err(ply_error(path, "a PLY file must begin with the line `ply`".into()));
    };
    let mut pos = magic_len;
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    let mut line_no = 1;
    loop {
        let Some(len) = bytes[pos..].iter().position(|&b| b == b'\n') else {
            return Err(ply_error(path, "the header has no `end_header` line".into()));
        };
        line_no += 1;
        let raw = &bytes[pos..pos + len];
        pos += len + 1;
        let line = std::str::from_utf8(raw)
            .map_err(|_| ply_error(path, format!("header line {line_no} is not valid text")))?
            .trim_end_matches('\r');
        let words: Vec<&str> = line.split_ascii_whitespace().collect();
        let fail = |what: String| ply_error(path, format!("header line {line_no}: {what}"));
        match words.as_slice() {
            [] | ["comment" | "obj_info", ..] => {}
            ["format", name, version] => {
                if encoding.is_some() {
                    return Err(fail("a second `format` line".into()));
                }
                if *version != "1.0" {
                    return Err(fail(format!("PLY version {version:.20} (only 1.0 is known)")));
                }
                encoding = Some(match *name {
                    "ascii" => PlyEncoding::Ascii,
                    "binary_little_endian" => PlyEncoding::BinaryLittleEndian,
                    "binary_big_endian" => PlyEncoding::BinaryBigEndian,
                    other => return Err(fail(format!("unknown format `{other:.40}`"))),
                });
            }
            ["element", name, count] => {
                let count: u64 = count
                    .parse()
                    .map_err(|_| fail(format!("the count of element `{name:.40}` `{count:.40}` is not a number")))?;
                elements.push(Element { name: (*name).into(), count, props: Vec::new() });
            }
            ["property", rest @ ..] => {
                let el = elements.last_mut().ok_or_else(|| fail("a property before any element".into()))?;
                let ty = |t: &str| Scalar::from_name(t).ok_or_else(|| fail(format!("unknown type `{t:.40}`")));
                let (list, scalar, name) = match rest {
                    ["list", count, item, name] => (Some(ty(count)?), ty(item)?, *name),
                    [t, name] => (None, ty(t)?, *name),
                    _ => return Err(fail(format!("`{line:.80}` is not a property"))),
                };
                if matches!(list, Some(Scalar::F32 | Scalar::F64)) {
                    return Err(fail(format!("the list `{name:.40}` has a floating-point count type")));
                }
                let role = match (el.name.as_str(), name, list) {
                    ("vertex", "x", None) => Role::Coord(0),
                    ("vertex", "y", None) => Role::Coord(1),
                    ("vertex", "z", None) => Role::Coord(2),
                    ("vertex", "red" | "diffuse_red", None) => Role::Color(0),
                    ("vertex", "green" | "diffuse_green", None) => Role::Color(1),
                    ("vertex", "blue" | "diffuse_blue", None) => Role::Color(2),
                    ("vertex", "alpha" | "diffuse_alpha", None) => Role::Color(3),
                    ("face", "red" | "diffuse_red", None) => Role::Color(0),
                    ("face", "green" | "diffuse_green", None) => Role::Color(1),
                    ("face", "blue" | "diffuse_blue", None) => Role::Color(2),
                    ("face", "alpha" | "diffuse_alpha", None) => Role::Color(3),
                    ("face", "vertex_indices" | "vertex_index", Some(_)) => Role::Indices,
                    _ => Role::Ignored,
                };
                if role != Role::Ignored && el.props.iter().any(|p| p.role == role) {
                    return Err(fail(format!("element `{}` has a second `{name:.40}`", el.name)));
                }
                el.props.push(Property { list, scalar, role });
            }
            ["end_header"] => break,
            _ => return Err(fail(format!("`{line:.80}` is not a header line"))),
        }
    }
    let encoding = encoding.ok_or_else(|| ply_error(path, "the header has no `format` line".into()))?;
    let vertex = elements.iter().find(|e| e.name == "vertex");
    if let Some(v) = vertex {
        for (k, axis) in ["x", "y", "z"].iter().enumerate() {
            if !v.props.iter().any(|p| p.role == Role::Coord(k)) {
                return Err(ply_error(path, format!("the vertex element has no `{axis}` property")));
            }
        }
        if v.count > u64::from(u32::MAX) {
            return Err(ply_error(path, format!("{} vertices are more than 2³² − 1", v.count)));
        }
    }
    if let Some(f) = elements.iter().find(|e| e.name == "face") {
        if !f.props.iter().any(|p| p.role == Role::Indices) && f.count > 0 {
            return Err(ply_error(path, "the face element has no `vertex_indices` list".into()));
        }
        if vertex.is_none() && f.count > 0 {
            return Err(ply_error(path, "faces but no vertex element".into()));
        }
        if f.count > u64::from(u32::MAX) {
            return Err(ply_error(path, format!("{} faces are more than 2³² − 1", f.count)));
        }
    }
    Ok((encoding, elements, pos))
}

/// Refuses element counts that the data cannot hold, before anything is allocated: each
/// binary entry takes at least its scalars' and its lists' counts' sizes; each ASCII value at
/// least one character and a separator.
fn check_sizes(encoding: PlyEncoding, elements: &[Element], data_len: usize, path: &Path) -> Result<(), IoError> {
    let mut need: u128 = 0;
    for el in elements {
        let per_entry: u128 = el
            .props
            .iter()
            .map(|p| match encoding {
                PlyEncoding::Ascii => 2,
                _ => p.list.unwrap_or(p.scalar).size() as u128,
            })
            .sum();
        let this = u128::from(el.count) * per_entry;
        need += this;
        if need > data_len as u128 + 1 {
            return Err(ply_error(
                path,
                format!(
                    "the header declares {} `{}` entries, which take at least {this} bytes, but the data after the header has {data_len}",
                    el.count, el.name
                ),
            ));
        }
    }
    Ok(())
}

/// The data after the header, read value by value. ASCII data is read by lines, one entry of
/// an element per line as the format has it: an entry starts on a new line, may run on to the
/// next lines, and whatever its line holds past its declared properties is not read (VCG's
/// writer, behind MeshLab, puts more values on each face line than its header declares; trimesh
/// reads those files the same way).
enum Source<'a> {
    Ascii { lines: std::str::Lines<'a>, words: std::str::SplitAsciiWhitespace<'a> },
    Binary { data: &'a [u8], pos: usize, big: bool },
}

impl Source<'_> {
    /// Ends an entry: ASCII data goes on at the next line.
    fn end_entry(&mut self) {
        if let Source::Ascii { words, .. } = self {
            *words = "".split_ascii_whitespace();
        }
    }

    fn scalar(&mut self, s: Scalar, path: &Path, at: At<'_>) -> Result<f64, IoError> {
        match self {
            Source::Ascii { lines, words } => {
                let w = loop {
                    if let Some(w) = words.next() {
                        break w;
                    }
                    let line = lines.next().ok_or_else(|| ply_error(path, format!("{at}: the data ends early")))?;
                    *words = line.split_ascii_whitespace();
                };
                let v: f64 = w.parse().map_err(|_| ply_error(path, format!("{at}: `{w:.40}` is not a number")))?;
                if !matches!(s, Scalar::F32 | Scalar::F64) && v.fract() != 0.0 {
                    return Err(ply_error(path, format!("{at}: `{w:.40}` is not a whole number")));
                }
                Ok(v)
            }
            Source::Binary { data, pos, big } => {
                let n = s.size();
                let b =
                    data.get(*pos..*pos + n).ok_or_else(|| ply_error(path, format!("{at}: the data ends early")))?;
                *pos += n;
                let mut a = [0u8; 8];
                a[..n].copy_from_slice(b);
                if *big {
                    a[..n].reverse();
                }
                Ok(match s {
                    Scalar::I8 => f64::from(a[0] as i8),
                    Scalar::U8 => f64::from(a[0]),
                    Scalar::I16 => f64::from(i16::from_le_bytes([a[0], a[1]])),
                    Scalar::U16 => f64::from(u16::from_le_bytes([a[0], a[1]])),
                    Scalar::I32 => f64::from(i32::from_le_bytes([a[0], a[1], a[2], a[3]])),
                    Scalar::U32 => f64::from(u32::from_le_bytes([a[0], a[1], a[2], a[3]])),
                    Scalar::F32 => f64::from(f32::from_le_bytes([a[0], a[1], a[2], a[3]])),
                    Scalar::F64 => f64::from_le_bytes(a),
                })
            }
        }
    }

    /// A list's count: a whole number ≥ 0.
    fn count(&mut self, s: Scalar, path: &Path, at: At<'_>) -> Result<u64, IoError> {
        let n = self.scalar(s, path, at)?;
        if n < 0.0 {
            return Err(ply_error(path, format!("{at}: a list of {n} items")));
        }
        Ok(n as u64)
    }

    fn skip_list(&mut self, p: &Property, path: &Path, at: At<'_>) -> Result<(), IoError> {
        let n = self.count(p.list.unwrap_or(Scalar::U8), path, at)?;
        for _ in 0..n {
            self.scalar(p.scalar, path, at)?;
        }
        Ok(())
    }

    fn is_done(&mut self) -> bool {
        match self {
            Source::Ascii { lines, words } => words.next().is_none() && lines.all(|l| l.trim().is_empty()),
            Source::Binary { data, pos, .. } => *pos == data.len(),
        }
    }
}

/// Writes `mesh` as PLY in `encoding`: `double` positions (exact), polygon faces as
/// `vertex_indices` lists, and vertex colours and face colours as `uchar` red, green, blue
/// (alpha too when any colour is not opaque; faces without a colour white when others have one).
///
/// # Errors
/// [`IoError::Write`] for errors of `out`. `path` is only named in errors.
///
/// See also [`read_ply`], [`super::save_with`].
pub fn write_ply<W: Write>(mesh: &Mesh, out: &mut W, encoding: PlyEncoding, path: &Path) -> Result<(), IoError> {
    let write_err = |e| IoError::Write { path: path.into(), source: e };
    let (indices, arities) = mesh.to_indexed();
    let colors = mesh.vertex_colors();
    let alpha = colors.is_some_and(|c| c.iter().any(|c| c[3] != 1.0));
    let count_type = if arities.iter().any(|&a| a > 255) { "uint" } else { "uchar" };
    let index_type = if mesh.vertex_count() > i32::MAX as usize { "uint" } else { "int" };
    let mut head = format!(
        "ply\nformat {} 1.0\ncomment written by blocksmith {}\nelement vertex {}\n\
         property double x\nproperty double y\nproperty double z\n",
        encoding.header_name(),
        env!("CARGO_PKG_VERSION"),
        mesh.vertex_count()
    );
    if colors.is_some() {
        head += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
        if alpha {
            head += "property uchar alpha\n";
        }
    }
    head += &format!("element face {}\nproperty list {count_type} {index_type} vertex_indices\n", arities.len());
    // Face colours, 8 bits a channel, after each face's list.
    let face_rgba: Option<Vec<[u8; 4]>> = mesh.has_face_colors().then(|| {
        (0..mesh.face_count() as u32)
            .map(|f| mesh.face_color(f).unwrap_or([1.0; 4]).map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8))
            .collect()
    });
    let face_channels = if face_rgba.as_ref().is_some_and(|c| c.iter().any(|c| c[3] != 255)) { 4 } else { 3 };
    if face_rgba.is_some() {
        head += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
        if face_channels == 4 {
            head += "property uchar alpha\n";
        }
    }
    head += "end_header\n";
    let mut buf: Vec<u8> = Vec::with_capacity(1 << 16);
    buf.extend_from_slice(head.as_bytes());
    let channels = if alpha { 4 } else { 3 };
    let byte = |c: f32| (c.clamp(0.0, 1.0) * 255.0).round() as u8;
    let mut fbuf = zmij::Buffer::new();
    let mut ibuf = itoa::Buffer::new();
    let big = encoding == PlyEncoding::BinaryBigEndian;
    for (i, p) in mesh.positions().iter().enumerate() {
        let rgba = colors.map(|c| c[i].map(byte));
        match encoding {
            PlyEncoding::Ascii => {
                for (k, c) in [p.x, p.y, p.z].into_iter().enumerate() {
                    if k > 0 {
                        buf.push(b' ');
                    }
                    buf.extend_from_slice(fbuf.format(c).as_bytes());
                }
                for &c in rgba.iter().flat_map(|c| &c[..channels]) {
                    buf.push(b' ');
                    buf.extend_from_slice(ibuf.format(c).as_bytes());
                }
                buf.push(b'\n');
            }
            _ => {
                for c in [p.x, p.y, p.z] {
                    buf.extend_from_slice(&if big { c.to_be_bytes() } else { c.to_le_bytes() });
                }
                if let Some(c) = rgba {
                    buf.extend_from_slice(&c[..channels]);
                }
            }
        }
        if buf.len() > (1 << 16) {
            out.write_all(&buf).map_err(write_err)?;
            buf.clear();
        }
    }
    let mut start = 0;
    for (f, &a) in arities.iter().enumerate() {
        let face = &indices[start..start + a as usize];
        start += a as usize;
        let rgba = face_rgba.as_ref().map(|c| &c[f][..face_channels]);
        match encoding {
            PlyEncoding::Ascii => {
                buf.extend_from_slice(ibuf.format(a).as_bytes());
                for &v in face {
                    buf.push(b' ');
                    buf.extend_from_slice(ibuf.format(v).as_bytes());
                }
                for &c in rgba.into_iter().flatten() {
                    buf.push(b' ');
                    buf.extend_from_slice(ibuf.format(c).as_bytes());
                }
                buf.push(b'\n');
            }
            _ => {
                if count_type == "uchar" {
                    buf.push(a as u8);
                } else {
                    buf.extend_from_slice(&if big { a.to_be_bytes() } else { a.to_le_bytes() });
                }
                for &v in face {
                    buf.extend_from_slice(&if big { v.to_be_bytes() } else { v.to_le_bytes() });
                }
                if let Some(c) = rgba {
                    buf.extend_from_slice(c);
                }
            }
        }
        if buf.len() > (1 << 16) {
            out.write_all(&buf).map_err(write_err)?;
            buf.clear();
        }
    }
    out.write_all(&buf).map_err(write_err)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn written(mesh: &Mesh, encoding: PlyEncoding) -> Vec<u8> {
        let mut bytes = Vec::new();
        write_ply(mesh, &mut bytes, encoding, Path::new("mem.ply")).unwrap();
        bytes
    }

    const ALL: [PlyEncoding; 3] = [PlyEncoding::Ascii, PlyEncoding::BinaryLittleEndian, PlyEncoding::BinaryBigEndian];

    #[test]
    fn every_encoding_round_trips_positions_polygons_and_colours_bit_exactly() {
        // Positions that are not f32 numbers, polygons (the torus's quads), colours of u8 steps.
        let mut m = Mesh::torus(2.0, 0.5, 12, 8).map_positions(|p| p * 0.1 + Vec3::new(1e5, -3.0, 1.0 / 3.0));
        let colors: Vec<[f32; 4]> =
            (0..m.vertex_count()).map(|i| [(i % 256) as f32 / 255.0, 0.5f32.min(1.0), 1.0, 1.0]).collect();
        m.set_vertex_colors(Some(colors)).unwrap();
        for enc in ALL {
            let back = read_ply(&written(&m, enc), Path::new("mem.ply")).unwrap();
            assert_eq!(back.positions(), m.positions(), "{enc:?}");
            assert_eq!(back.to_polygons(), m.to_polygons(), "{enc:?}");
            let (a, b) = (back.vertex_colors().unwrap(), m.vertex_colors().unwrap());
            for (x, y) in a.iter().zip(b) {
                for k in 0..4 {
                    assert!((x[k] - y[k]).abs() <= 0.5 / 255.0 + 1e-6, "{enc:?}: {x:?} vs {y:?}");
                }
            }
            // Writing what was read gives the same bytes.
            assert_eq!(written(&back, enc), written(&m, enc), "{enc:?}");
        }
    }

    #[test]
    fn a_hand_written_ascii_file_with_other_elements_and_properties() {
        // Normals and an edge element are read past; colours in floats; a quad and a
        // triangle fan closing a square pyramid.
        let text = "ply\r\nformat ascii 1.0\r\ncomment made by hand\r\nelement vertex 5\r\n\
            property float x\nproperty float y\nproperty float z\nproperty float nx\n\
            property float red\nproperty float green\nproperty float blue\n\
            element face 5\nproperty list uchar int vertex_index\nproperty uchar flags\n\
            element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n\
            0 0 0 9 1 0 0\n1 0 0 9 0 1 0\n1 1 0 9 0 0 1\n0 1 0 9 1 1 1\n0.5 0.5 1 9 0 0 0\n\
            4 0 3 2 1 7\n3 0 1 4 0\n3 1 2 4 0\n3 2 3 4 0\n3 3 0 4 0\n0 1\n";
        let m = read_ply(text.as_bytes(), Path::new("pyr.ply")).unwrap();
        assert_eq!((m.vertex_count(), m.face_count()), (5, 5));
        assert!(m.is_closed() && m.is_manifold());
        assert!((m.volume() - 1.0 / 3.0).abs() < 1e-15, "{}", m.volume());
        assert_eq!(m.vertex_colors().unwrap()[1], [0.0, 1.0, 0.0, 1.0]);
    }

    #[test]
    fn ascii_entries_are_lines_and_what_a_line_holds_past_its_properties_is_not_read() {
        // As VCG (MeshLab) writes some files (trimesh's fuze_ascii.ply): each face line holds a
        // texture-coordinate list, then ten values where the header declares four colour bytes.
        // Read by lines, the tetrahedron is whole; read as one stream of values, the extra six
        // would start the next face ("face 1 has 1 vertices"). A list may still run on to the
        // next line.
        let text = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
            property float z\nelement face 4\nproperty list uchar int vertex_indices\n\
            property list uchar float texcoord\nproperty uchar red\nproperty uchar green\n\
            property uchar blue\nproperty uchar alpha\nend_header\n\
            0 0 0 \n1 0 0 extra\n0 1 0\n0 0 1\n\
            3 0 2 1 6 0 0 1 0 0 1 9 1 1 1 1 1 1 1 1 1\n\
            3 0 1 3 6 0 0 1 0 0 1 9 1 1 1 1 1 1 1 1 1\n\
            3 0 3 2 6 0 0 1 0 0 1 9 1 1 1 1 1 1 1 1 1\n\
            3 1 2\n3 6 0 0 1 0 0 1 9 1 1 1\n\n";
        let m = read_ply(text.as_bytes(), Path::new("vcg.ply")).unwrap();
        assert_eq!((m.vertex_count(), m.face_count()), (4, 4));
        assert!(m.is_closed() && m.is_manifold());
        assert!((m.volume() - 1.0 / 6.0).abs() < 1e-15, "{}", m.volume());
        // A line that ends before its entry does still runs on; data past the last entry's
        // line is still an error.
        let cut = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n\
            property float z\nend_header\n0 0 0\n1 0          \n";
        let e = read_ply(cut.as_bytes(), Path::new("cut.ply")).unwrap_err().to_string();
        assert!(e.contains("vertex 1: the data ends early"), "{e}");
    }

    #[test]
    fn split_vertices_are_welded_unless_asked_not_to() {
        // A cube whose six quads each have their own four corners (24 vertices).
        let c = Mesh::cube(1.0);
        let mut p = Vec::new();
        let mut faces = Vec::new();
        for f in c.to_polygons() {
            faces.push((p.len() as u32..p.len() as u32 + f.len() as u32).collect::<Vec<u32>>());
            p.extend(f.iter().map(|&v| c.position(v)));
        }
        let split = Mesh::from_polygons(p, &faces).unwrap();
        let bytes = written(&split, PlyEncoding::BinaryLittleEndian);
        let m = read_ply(&bytes, Path::new("split.ply")).unwrap();
        assert_eq!((m.vertex_count(), m.face_count()), (8, 6));
        assert!(m.is_closed());
        let m = read_ply_with(&bytes, Path::new("split.ply"), Weld::Off).unwrap();
        assert_eq!((m.vertex_count(), m.component_count()), (24, 6));
    }

    #[test]
    fn huge_counts_are_refused_before_allocating_naming_the_count() {
        // 10¹² vertices are more than the indices of a mesh reach; 10⁹ fit but not in the file.
        for (fmt, count, want) in [
            ("ascii", "1000000000000", "1000000000000 vertices are more than 2³² − 1"),
            ("binary_little_endian", "1000000000", "the header declares 1000000000 `vertex` entries"),
            ("ascii", "1000000000", "the header declares 1000000000 `vertex` entries"),
        ] {
            let text = format!(
                "ply\nformat {fmt} 1.0\nelement vertex {count}\nproperty float x\nproperty float y\n\
                 property float z\nend_header\n0 0 0\n"
            );
            let e = read_ply(text.as_bytes(), Path::new("huge.ply")).unwrap_err();
            assert!(matches!(e, IoError::Ply { .. }), "{e}");
            assert!(e.to_string().contains(want), "{e}");
        }
        // An element the reader skips is held to the size of the file too.
        let text =
            "ply\nformat binary_big_endian 1.0\nelement junk 999999999999\nproperty list uint uchar v\nend_header\n";
        let e = read_ply(text.as_bytes(), Path::new("huge.ply")).unwrap_err();
        assert!(e.to_string().contains("999999999999 `junk` entries, which take at least 3999999999996 bytes"), "{e}");
    }

    #[test]
    fn malformed_files_are_ply_errors_naming_the_path() {
        // Corners at 0 and 1: vertex lines start with `0.0 ` or `1.0 `, face lines with `4 `.
        let cube = Mesh::cube(1.0).map_positions(|p| p + Vec3::splat(0.5));
        let good = String::from_utf8(written(&cube, PlyEncoding::Ascii)).unwrap();
        let cases = [
            ("not ply\n".to_string(), "must begin with the line `ply`"),
            (good.replace("format ascii", "format packed"), "unknown format `packed`"),
            (good.replace("end_header\n", ""), "is not a header line"),
            (good.replace("property double y\n", ""), "no `y` property"),
            (good.replace("double z", "quad z"), "unknown type `quad`"),
            (format!("{good}7\n"), "data is left after the last element"),
            (good.replacen("\n4 ", "\n4 0.5 ", 1), "not a whole number"),
            (good[..good.len() - 4].to_string(), "the data ends early"),
            (good.replacen("end_header\n", "end_header\nx ", 1), "`x` is not a number"),
        ];
        for (text, want) in cases {
            let e = read_ply(text.as_bytes(), Path::new("bad.ply")).map(|_| 0).expect_err(want);
            assert!(e.to_string().starts_with("bad.ply: malformed PLY"), "{e}");
            assert!(e.to_string().contains(want), "{e} (wanted {want})");
        }
        let e = read_ply(good.replacen("\n4 ", "\n4 80 ", 1).as_bytes(), Path::new("bad.ply")).unwrap_err();
        assert!(matches!(e, IoError::IndexOutOfRange { index: 80, vertex_count: 8, .. }), "{e}");
        let bytes = written(&Mesh::cube(1.0), PlyEncoding::BinaryBigEndian);
        for cut in [1, 9, 40] {
            let e = read_ply(&bytes[..bytes.len() - cut], Path::new("bad.ply")).unwrap_err();
            assert!(matches!(e, IoError::Ply { .. }), "{e}");
        }
    }

    #[test]
    fn welding_never_joins_two_touching_solids_into_one_vertex() {
        // Two tetrahedra whose tips meet at (0, 0, 1), each with its own vertex there.
        let p = [(0., 0., 0.), (1., 0., 0.), (0., 1., 0.), (0., 0., 1.), (0., 0., 2.), (1., 0., 2.), (0., 1., 2.)];
        let mut p: Vec<Vec3> = p.iter().map(|&(x, y, z)| Vec3::new(x, y, z)).collect();
        p.push(Vec3::new(0.0, 0.0, 1.0));
        let faces = [[0u32, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3], [4, 5, 6], [4, 7, 5], [4, 6, 7], [5, 7, 6]];
        let two = Mesh::from_polygons(p, &faces).unwrap();
        let bytes = written(&two, PlyEncoding::BinaryLittleEndian);
        // The weld would join the tips into a bowtie vertex: it keeps them apart, and the
        // file (manifold as written) needs no repair.
        let (m, repairs) = read_ply_report(&bytes, Path::new("touch.ply"), Weld::DEFAULT, false).unwrap();
        assert!(repairs.is_empty());
        assert!(m.is_closed() && m.is_manifold());
        assert_eq!((m.vertex_count(), m.component_count()), (8, 2));
        assert_eq!(m, read_ply_with(&bytes, Path::new("touch.ply"), Weld::Off).unwrap());
    }

    #[test]
    fn a_point_cloud_reads_as_vertices_only() {
        let text = "ply\nformat ascii 1.0\nelement vertex 2\nproperty double x\nproperty double y\n\
            property double z\nend_header\n1 2 3\n4 5 6\n";
        let m = read_ply(text.as_bytes(), Path::new("pts.ply")).unwrap();
        assert_eq!((m.vertex_count(), m.face_count()), (2, 0));
    }
}
