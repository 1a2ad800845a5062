//! Errors raised while reading or writing mesh files.

use std::path::PathBuf;

use thiserror::Error;

use crate::mesh::MeshError;

/// The file extensions [`load`](super::load) and [`save`](super::save) know, as listed in
/// error messages.
pub const KNOWN_EXTENSIONS: &str = ".obj, .glb, .gltf, .stl, .ply, .3mf";

/// Why a mesh file could not be read or written.
///
/// Every message starts with the path of the file and says the reason. Every variant is bad
/// input or a failing file system except [`IoError::Internal`], a bug in blocksmith.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum IoError {
    /// The file does not exist (a `.gltf` whose buffer file is missing is [`IoError::Gltf`]).
    #[error("{}: file not found", path.display())]
    NotFound { path: PathBuf },
    /// The file exists but could not be read (permissions, a directory, a device error).
    #[error("{}: cannot read the file: {source}", path.display())]
    Read { path: PathBuf, source: std::io::Error },
    /// The file could not be created or written.
    #[error("{}: cannot write the file: {source}", path.display())]
    Write { path: PathBuf, source: std::io::Error },
    /// The path has no extension, or one no reader or writer knows.
    #[error("{}: unknown file extension {ext:?} (known: {known})", path.display(), known = KNOWN_EXTENSIONS)]
    UnknownExtension { path: PathBuf, ext: String },
    /// A malformed OBJ file: an unknown keyword, a number that does not parse, a face with fewer
    /// than three corners, vertex colours on some vertices only. `line` is 1-based, 0 when the
    /// reason is not tied to one line.
    #[error("{}{}: malformed OBJ: {reason}", path.display(), line_suffix(*line))]
    Obj { path: PathBuf, line: usize, reason: String },
    /// A malformed STL file: truncated, or an ASCII file that does not follow the grammar.
    #[error("{}: malformed STL: {reason}", path.display())]
    Stl { path: PathBuf, reason: String },
    /// A malformed PLY file: no `ply` line, an unknown format or type, element counts the file
    /// cannot hold, data ending early, a word that is not a number.
    #[error("{}: malformed PLY: {reason}", path.display())]
    Ply { path: PathBuf, reason: String },
    /// A malformed 3MF package: not a zip archive, no model part, a part over the memory
    /// budget, invalid XML, a missing attribute, a build item naming no object.
    #[error("{}: malformed 3MF: {reason}", path.display())]
    ThreeMf { path: PathBuf, reason: String },
    /// A malformed glTF file: not glTF at all, truncated, invalid JSON, a failed schema check,
    /// an accessor of the wrong type or reaching past its buffer, a missing buffer.
    #[error("{}: malformed glTF: {reason}", path.display())]
    Gltf { path: PathBuf, reason: String },
    /// A malformed SVG document (for 2D profiles): invalid XML, malformed path data, number
    /// lists or transforms, non-finite coordinates, or nothing drawn with area.
    #[error("{}: malformed SVG: {reason}", path.display())]
    Svg { path: PathBuf, reason: String },
    /// A malformed DXF file (for 2D profiles): an odd number of lines, a group code that is not
    /// a number, a coordinate that does not parse, or no closed contour with area.
    #[error("{}{}: malformed DXF: {reason}", path.display(), line_suffix(*line))]
    Dxf { path: PathBuf, line: usize, reason: String },
    /// A well-formed file that uses a feature blocksmith does not read, such as a required glTF
    /// extension that compresses or quantizes geometry (`KHR_draco_mesh_compression`), or
    /// options that do not apply to the format (an up axis for glTF, which is Y-up by
    /// specification).
    #[error("{}: {reason}", path.display())]
    Unsupported { path: PathBuf, reason: String },
    /// A face names a vertex that does not exist. `at` says where (an OBJ line, a glTF
    /// primitive); `index` is as written in the file (1-based or negative for OBJ).
    #[error("{}: {at}: vertex index {index} is out of range (there are {vertex_count} vertices)", path.display())]
    IndexOutOfRange { path: PathBuf, at: String, index: i64, vertex_count: usize },
    /// A coordinate that is NaN or infinite. `vertex` is the mesh vertex id (0-based).
    #[error("{}: vertex {vertex} has a non-finite coordinate ({x}, {y}, {z})", path.display())]
    NonFinite { path: PathBuf, vertex: usize, x: f64, y: f64, z: f64 },
    /// The file parses but its faces do not make a valid mesh (non-manifold edge or vertex, a
    /// degenerate face, a face that cannot be triangulated for writing).
    #[error("{}: {source}", path.display())]
    Mesh { path: PathBuf, source: MeshError },
    /// The file's faces do not make a manifold surface as written (a vertex where sheets
    /// touch, an edge of more than two faces, neighbours of opposite orientations, a face
    /// repeating a vertex), and the load was asked not to repair it (`repair: false`).
    #[error(
        "{}: {source}; the file is not a manifold surface as written (load it without `repair: false` to have it split into one, no vertex moved)",
        path.display()
    )]
    NotManifold { path: PathBuf, source: MeshError },
    /// A broken internal invariant: a bug in blocksmith, please file an issue.
    #[error("{}: internal error (please file an issue): {reason}", path.display())]
    Internal { path: PathBuf, reason: String },
}

fn line_suffix(line: usize) -> String {
    if line == 0 {
        String::new()
    } else {
        format!(":{line}")
    }
}

impl IoError {
    /// The path the error is about.
    #[must_use]
    pub fn path(&self) -> &std::path::Path {
        match self {
            IoError::NotFound { path }
            | IoError::Read { path, .. }
            | IoError::Write { path, .. }
            | IoError::UnknownExtension { path, .. }
            | IoError::Obj { path, .. }
            | IoError::Stl { path, .. }
            | IoError::Ply { path, .. }
            | IoError::ThreeMf { path, .. }
            | IoError::Gltf { path, .. }
            | IoError::Svg { path, .. }
            | IoError::Dxf { path, .. }
            | IoError::Unsupported { path, .. }
            | IoError::IndexOutOfRange { path, .. }
            | IoError::NonFinite { path, .. }
            | IoError::Mesh { path, .. }
            | IoError::NotManifold { path, .. }
            | IoError::Internal { path, .. } => path,
        }
    }

    /// Wraps a [`MeshError`] raised while building a mesh from the file at `path`; a non-finite
    /// coordinate becomes [`IoError::NonFinite`].
    #[must_use]
    pub fn from_mesh(path: &std::path::Path, source: MeshError) -> IoError {
        match source {
            MeshError::NonFinite { vertex, x, y, z } => IoError::NonFinite { path: path.into(), vertex, x, y, z },
            source => IoError::Mesh { path: path.into(), source },
        }
    }

    /// An error opening or reading `path`: [`IoError::NotFound`] for a missing file,
    /// [`IoError::Read`] otherwise.
    #[must_use]
    pub fn from_read(path: &std::path::Path, source: std::io::Error) -> IoError {
        if source.kind() == std::io::ErrorKind::NotFound {
            IoError::NotFound { path: path.into() }
        } else {
            IoError::Read { path: path.into(), source }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_message_starts_with_the_path() {
        let p = PathBuf::from("dir/some file.obj");
        let errors = [
            IoError::NotFound { path: p.clone() },
            IoError::UnknownExtension { path: p.clone(), ext: "ply".into() },
            IoError::Obj { path: p.clone(), line: 3, reason: "junk".into() },
            IoError::Obj { path: p.clone(), line: 0, reason: "junk".into() },
            IoError::from_mesh(&p, MeshError::NotAnEdge { a: 1, b: 2 }),
            IoError::from_mesh(&p, MeshError::NonFinite { vertex: 0, x: f64::NAN, y: 0.0, z: 0.0 }),
        ];
        for e in &errors {
            let msg = e.to_string();
            assert!(msg.starts_with("dir/some file.obj"), "{msg}");
            assert_eq!(e.path(), p.as_path());
        }
        assert!(errors[1].to_string().contains(".obj, .glb, .gltf, .stl, .ply"));
        assert!(errors[2].to_string().starts_with("dir/some file.obj:3: malformed OBJ"));
        assert!(matches!(errors[5], IoError::NonFinite { vertex: 0, .. }));
    }
}
