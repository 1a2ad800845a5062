//! STL: binary write; binary and ASCII read.
//!
//! STL stores a soup of triangles, each with its own copy of its corners in `f32`. Writing
//! triangulates every face (see [`super::face_triangles`]); reading welds corners within a
//! tolerance relative to the model's size (see [`super::Weld`]) back into shared vertices, so
//! a closed mesh written by [`write_stl`] — or a CAD part whose corners differ by arithmetic
//! noise — reads back closed. Vertex ids, polygons, creases and colours are not kept.

use std::io::Write;
use std::path::Path;

use super::error::IoError;
use super::weld::Weld;
use crate::diagnose::Repairs;
use crate::math::Vec3;
use crate::mesh::{Mesh, MeshError};

/// The 80-byte header of the files [`write_stl`] writes (it must not begin with `solid`, which
/// some readers take for ASCII STL).
const HEADER: &[u8] = b"binary STL written by blocksmith";

/// Writes `mesh` as binary STL: the header, the triangle count, then per triangle its unit
/// normal (zero for a degenerate triangle) and its three corners, all `f32`, and a zero
/// attribute word. Triangles are oriented like the faces they come from.
///
/// # Errors
/// [`IoError::Mesh`] when a face cannot be triangulated or there are more than 2³² − 1
/// triangles; [`IoError::Write`] for errors of `out`. `path` is only named in errors.
///
/// See also [`read_stl`], [`super::save`].
pub fn write_stl<W: Write>(mesh: &Mesh, out: &mut W, path: &Path) -> Result<(), IoError> {
    let (mesh, tris, _) = super::face_triangles(mesh).map_err(|e| IoError::from_mesh(path, e))?;
    let mesh = &*mesh;
    let count = u32::try_from(tris.len() / 3).map_err(|_| {
        IoError::from_mesh(path, MeshError::TooLarge { what: "more than 2³² − 1 STL triangles".into() })
    })?;
    let write_err = |e| IoError::Write { path: path.into(), source: e };
    let mut header = [b' '; 80];
    header[..HEADER.len()].copy_from_slice(HEADER);
    out.write_all(&header).map_err(write_err)?;
    out.write_all(&count.to_le_bytes()).map_err(write_err)?;
    let mut buf = Vec::with_capacity(50 * 1024);
    for t in tris.chunks_exact(3) {
        let [a, b, c] = [t[0], t[1], t[2]].map(|v| mesh.position(v));
        let n = (b - a).cross(c - a).normalize_or_zero();
        for p in [n, a, b, c] {
            for x in [p.x, p.y, p.z] {
                buf.extend_from_slice(&(x as f32).to_le_bytes());
            }
        }
        buf.extend_from_slice(&[0, 0]);
        if buf.len() >= 50 * 1024 {
            out.write_all(&buf).map_err(write_err)?;
            buf.clear();
        }
    }
    out.write_all(&buf).map_err(write_err)
}

/// Reads a binary or ASCII STL file into a mesh, welding corners by [`Weld::DEFAULT`].
///
/// See [`read_stl_with`].
///
/// # Errors
/// As [`read_stl_with`].
pub fn read_stl(bytes: &[u8], path: &Path) -> Result<Mesh, IoError> {
    read_stl_with(bytes, path, Weld::DEFAULT)
}

/// Reads a binary or ASCII STL file into a mesh, welding corners by `weld`.
///
/// A file is binary when its length is exactly 84 + 50 × (the count in bytes 80..84); otherwise
/// it must be ASCII: one or more `solid … endsolid` blocks, all read into the one mesh.
/// Triangles that weld to fewer than three distinct vertices (slivers thinner than the
/// tolerance) are dropped. Normals and attribute words are ignored.
///
/// # Errors
/// - [`IoError::Stl`]: a file too short for a binary header, a length that does not match the
///   triangle count, ASCII that does not follow the grammar (naming the line);
/// - [`IoError::NonFinite`] for a NaN or infinite coordinate;
/// - [`IoError::Mesh`] when the welded triangles are not a manifold mesh.
///
/// See also [`write_stl`], [`super::load_with`].
pub fn read_stl_with(bytes: &[u8], path: &Path, weld: Weld) -> Result<Mesh, IoError> {
    read_stl_report(bytes, path, weld, true).map(|r| r.0)
}

/// [`read_stl_with`], repairing a file that is not manifold as written (or refusing it when
/// `repair` is false), with what was repaired (see [`super::assemble`]).
///
/// # Errors
/// As [`read_stl_with`]; [`IoError::NotManifold`] when `repair` is false and the file is not a
/// manifold surface as written.
pub(crate) fn read_stl_report(bytes: &[u8], path: &Path, weld: Weld, repair: bool) -> Result<(Mesh, Repairs), IoError> {
    let binary_count = bytes.get(80..84).map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]) as u64);
    let corners = match binary_count {
        Some(n) if 84 + 50 * n == bytes.len() as u64 => read_binary(&bytes[84..], n as usize),
        _ if bytes.trim_ascii_start().starts_with(b"solid") => read_ascii(bytes, path)?,
        None => {
            return Err(stl_error(path, format!("{} bytes is too short for a binary STL (at least 84)", bytes.len())))
        }
        Some(n) => {
            return Err(stl_error(
                path,
                format!(
                    "the header counts {n} triangles, which take {} bytes, but the file has {} (truncated or not STL)",
                    84 + 50 * n,
                    bytes.len()
                ),
            ))
        }
    };
    build(&corners, weld, repair, path)
}

fn stl_error(path: &Path, reason: String) -> IoError {
    IoError::Stl { path: path.into(), reason }
}

/// The corners of `n` binary records, three per triangle.
fn read_binary(records: &[u8], n: usize) -> Vec<Vec3> {
    let f = |b: &[u8], i: usize| f64::from(f32::from_le_bytes([b[4 * i], b[4 * i + 1], b[4 * i + 2], b[4 * i + 3]]));
    let mut corners = Vec::with_capacity(3 * n);
    for r in records.chunks_exact(50) {
        for k in 1..4 {
            corners.push(Vec3::new(f(r, 3 * k), f(r, 3 * k + 1), f(r, 3 * k + 2)));
        }
    }
    corners
}

/// The corners of an ASCII STL file, three per triangle (a facet with more corners is a fan).
fn read_ascii(bytes: &[u8], path: &Path) -> Result<Vec<Vec3>, IoError> {
    let text = std::str::from_utf8(bytes).map_err(|_| stl_error(path, "ASCII STL that is not valid text".into()))?;
    let mut words =
        text.lines().enumerate().flat_map(|(i, line)| line.split_whitespace().map(move |w| (i + 1, w))).peekable();
    let mut corners = Vec::new();
    // One or more solids, each `solid [name]`, facets, `endsolid [name]`.
    let mut solids = 0;
    while let Some((solid_line, w)) = words.next() {
        if w != "solid" {
            let what = if solids == 0 { "ASCII STL must begin with `solid`" } else { "expected `solid` or the end" };
            return Err(stl_error(path, format!("line {solid_line}: {what}, found `{w:.40}`")));
        }
        solids += 1;
        // The solid's name is the rest of its line.
        while words.peek().is_some_and(|&(l, w)| l == solid_line && w != "facet" && w != "endsolid") {
            words.next();
        }
        read_facets(&mut words, &mut corners, path)?;
    }
    Ok(corners)
}

/// Reads facets up to and including `endsolid` (and the name after it on the same line),
/// appending their corners, three per triangle (a facet with more corners is a fan).
fn read_facets<'a>(
    words: &mut std::iter::Peekable<impl Iterator<Item = (usize, &'a str)>>,
    corners: &mut Vec<Vec3>,
    path: &Path,
) -> Result<(), IoError> {
    let expect = |want: &str, words: &mut dyn Iterator<Item = (usize, &str)>| match words.next() {
        Some((_, w)) if w == want => Ok(()),
        Some((line, w)) => Err(stl_error(path, format!("line {line}: expected `{want}`, found `{w:.40}`"))),
        None => Err(stl_error(path, format!("the file ends where `{want}` is expected"))),
    };
    let number = |words: &mut dyn Iterator<Item = (usize, &str)>| match words.next() {
        Some((line, w)) => {
            w.parse::<f64>().map_err(|_| stl_error(path, format!("line {line}: `{w:.40}` is not a number")))
        }
        None => Err(stl_error(path, "the file ends inside a facet".into())),
    };
    loop {
        match words.next() {
            Some((_, "facet")) => {}
            Some((end_line, "endsolid")) => {
                while words.peek().is_some_and(|&(l, _)| l == end_line) {
                    words.next();
                }
                return Ok(());
            }
            Some((line, w)) => {
                return Err(stl_error(path, format!("line {line}: expected `facet` or `endsolid`, found `{w:.40}`")))
            }
            None => return Err(stl_error(path, "the file ends without `endsolid`".into())),
        }
        expect("normal", words)?;
        for _ in 0..3 {
            number(words)?;
        }
        expect("outer", words)?;
        expect("loop", words)?;
        let mut facet = Vec::with_capacity(3);
        while words.peek().is_some_and(|&(_, w)| w == "vertex") {
            words.next();
            let (x, y, z) = (number(words)?, number(words)?, number(words)?);
            facet.push(Vec3::new(x, y, z));
        }
        if facet.len() < 3 {
            let line = words.peek().map_or(0, |&(l, _)| l);
            return Err(stl_error(
                path,
                format!("line {line}: a facet with {} vertices (at least 3 needed)", facet.len()),
            ));
        }
        for i in 1..facet.len() - 1 {
            corners.extend_from_slice(&[facet[0], facet[i], facet[i + 1]]);
        }
        expect("endloop", words)?;
        expect("endfacet", words)?;
    }
}

/// Welds the corners by `rule` and builds the mesh of the triangles that keep three corners
/// (see [`super::assemble`]: a weld that would break the surface is split back, and a file
/// that is not manifold as written is repaired when `repair` says so).
fn build(corners: &[Vec3], rule: Weld, repair: bool, path: &Path) -> Result<(Mesh, Repairs), IoError> {
    let indices: Vec<u32> = (0..corners.len() as u32).collect();
    let arities = vec![3; corners.len() / 3];
    let a =
        super::assemble::assemble(corners, &indices, &arities, super::assemble::Topology::Soup, rule, repair, path)?;
    Ok((a.mesh, a.repairs))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn written(mesh: &Mesh) -> Vec<u8> {
        let mut bytes = Vec::new();
        write_stl(mesh, &mut bytes, Path::new("mem.stl")).unwrap();
        bytes
    }

    #[test]
    fn binary_layout_counts_triangles() {
        // A cube's 6 quads make 12 triangles: 84 + 12 × 50 bytes.
        let bytes = written(&Mesh::cube(2.0));
        assert_eq!(bytes.len(), 84 + 12 * 50);
        assert_eq!(u32::from_le_bytes(bytes[80..84].try_into().unwrap()), 12);
        assert!(!bytes.starts_with(b"solid"));
    }

    #[test]
    fn closed_mesh_reloads_watertight_with_its_volume() {
        // Positions of the torus are not f32 numbers: the reloaded volume agrees to f32 precision.
        for m in [Mesh::cube(2.0), Mesh::torus(2.0, 0.5, 24, 12), Mesh::cylinder(1.5, 3.0, 16)] {
            let back = read_stl(&written(&m), Path::new("mem.stl")).unwrap();
            assert!(back.is_closed() && back.is_manifold());
            assert_eq!(back.genus(), m.genus());
            assert_eq!(back.vertex_count(), m.vertex_count());
            assert_eq!(back.face_count(), m.triangle_count());
            let (a, b) = (back.volume(), m.volume());
            assert!((a - b).abs() <= 1e-6 * b, "volume {a} vs {b}, difference {}", a - b);
        }
    }

    #[test]
    fn ascii_stl_is_read_and_welded() {
        // A tetrahedron, outward-facing, with the solid named on its first line.
        let text = "solid tet named here\n\
            facet normal 0 0 -1\n outer loop\n vertex 0 0 0\n vertex 0 1 0\n vertex 1 0 0\n endloop\nendfacet\n\
            facet normal 0 -1 0\n outer loop\n vertex 0 0 0\n vertex 1 0 0\n vertex 0 0 1\n endloop\nendfacet\n\
            facet normal -1 0 0\n outer loop\n vertex 0 0 0\n vertex 0 0 1\n vertex 0 1 0\n endloop\nendfacet\n\
            facet normal 1 1 1\n outer loop\n vertex 1 0 0\n vertex 0 1 0\n vertex 0 0 1\n endloop\nendfacet\n\
            endsolid tet\n";
        let m = read_stl(text.as_bytes(), Path::new("tet.stl")).unwrap();
        assert_eq!((m.vertex_count(), m.face_count()), (4, 4));
        assert!(m.is_closed());
        // The unit right tetrahedron has volume 1/6.
        assert!((m.volume() - 1.0 / 6.0).abs() < 1e-15, "{}", m.volume());
    }

    /// The outward tetrahedron's facets, with `noise` added to coordinates that are 0 in a
    /// different facet each time (as a CAD exporter's arithmetic leaves them).
    fn tet_facets(offset: f64, noise: f64) -> String {
        let facets = [
            [[0., 0., 0.], [0., 1., 0.], [1., 0., 0.]],
            [[0., 0., 0.], [1., 0., 0.], [0., 0., 1.]],
            [[0., 0., 0.], [0., 0., 1.], [0., 1., 0.]],
            [[1., 0., 0.], [0., 1., 0.], [0., 0., 1.]],
        ];
        let mut out = String::new();
        for (i, f) in facets.iter().enumerate() {
            out += "facet normal 0 0 0\n outer loop\n";
            for p in f {
                let q = p.map(|c| if c == 0.0 { c + noise * (i as f64 - 1.5) } else { c } + offset);
                out += &format!("  vertex {:e} {:e} {:e}\n", q[0], q[1], q[2]);
            }
            out += " endloop\nendfacet\n";
        }
        out
    }

    #[test]
    fn every_solid_of_an_ascii_file_is_read() {
        // Two tetrahedra in two solids (the second named on its endsolid line too).
        let text =
            format!("solid a\n{}endsolid a\nsolid b\n{}endsolid b\n", tet_facets(0.0, 0.0), tet_facets(3.0, 0.0));
        let m = read_stl(text.as_bytes(), Path::new("two.stl")).unwrap();
        assert_eq!((m.vertex_count(), m.face_count(), m.component_count()), (8, 8, 2));
        assert!((m.volume() - 2.0 / 6.0).abs() < 1e-12, "{}", m.volume());
        // Anything after the last solid but another solid is an error, not ignored.
        let e = read_stl(format!("{text}junk\n").as_bytes(), Path::new("junk.stl")).unwrap_err();
        assert!(e.to_string().contains("expected `solid` or the end, found `junk`"), "{e}");
    }

    #[test]
    fn cad_noise_is_welded_relative_to_the_size() {
        // Corners equal up to 1e-17 (issue 19's CAD parts), or 1e-13 at an offset of 1e3 (a few
        // ulps there), weld shut: the tolerance is 1e-8 of the diagonal. Welding only equal
        // coordinates leaves the facets apart (a soup that is not closed).
        for (offset, noise) in [(0.0, 1e-17), (1e3, 1e-13)] {
            let text = format!("solid n\n{}endsolid n\n", tet_facets(offset, noise));
            let m = read_stl(text.as_bytes(), Path::new("noise.stl")).unwrap();
            assert_eq!((m.vertex_count(), m.face_count()), (4, 4), "offset {offset}");
            assert!(m.is_closed());
        }
        let text = format!("solid n\n{}endsolid n\n", tet_facets(0.0, 1e-17));
        let m = read_stl_with(text.as_bytes(), Path::new("noise.stl"), Weld::Relative(0.0));
        assert!(m.is_err() || !m.unwrap().is_closed());
        let m = read_stl_with(text.as_bytes(), Path::new("noise.stl"), Weld::Off).unwrap();
        assert_eq!((m.vertex_count(), m.component_count()), (12, 4));
    }

    #[test]
    fn truncated_and_garbage_files_are_stl_errors_naming_the_path() {
        let bytes = written(&Mesh::cube(2.0));
        for bad in [
            &bytes[..bytes.len() - 7],
            &bytes[..50],
            b"solid x\nfacet normal 0 0 1\n outer loop\n vertex 0 0".as_slice(),
        ] {
            let e = read_stl(bad, Path::new("bad.stl")).unwrap_err();
            assert!(matches!(e, IoError::Stl { .. }), "{e}");
            assert!(e.to_string().starts_with("bad.stl: malformed STL"), "{e}");
        }
    }

    #[test]
    fn nan_corner_is_non_finite() {
        let mut bytes = written(&Mesh::cube(2.0));
        bytes[84 + 12..84 + 16].copy_from_slice(&f32::NAN.to_le_bytes());
        assert!(matches!(read_stl(&bytes, Path::new("nan.stl")), Err(IoError::NonFinite { .. })));
    }
}
