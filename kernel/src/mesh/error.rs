//! Errors raised while building or changing a [`Mesh`](super::Mesh).

use thiserror::Error;

/// Why a mesh could not be built or an operation on it could not be done.
///
/// Every variant is bad input; a broken internal invariant is reported as
/// [`MeshError::Internal`] ("please file an issue").
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum MeshError {
    /// A face names a vertex id that does not exist.
    #[error("face {face} names vertex {index}, but there are only {vertex_count} vertices")]
    IndexOutOfRange { face: usize, index: u64, vertex_count: usize },
    /// A face with fewer than three vertices or with a vertex repeated.
    #[error("face {face} is degenerate: {reason}")]
    DegenerateFace { face: usize, reason: String },
    /// A directed edge used by two faces: either more than two faces share the edge, or two
    /// neighbouring faces are oriented inconsistently.
    #[error(
        "edge ({a}, {b}) is non-manifold: faces {first} and {second} both use it in the same direction \
         (more than two faces share it, or their orientations disagree)"
    )]
    NonManifoldEdge { a: u32, b: u32, first: usize, second: usize },
    /// A vertex whose faces do not form one fan (two cones touching at a point, a bow-tie).
    #[error("vertex {vertex} is non-manifold: its faces form {fans} separate fans")]
    NonManifoldVertex { vertex: u32, fans: usize },
    /// A coordinate that is NaN or infinite.
    #[error("vertex {vertex} has a non-finite coordinate ({x}, {y}, {z})")]
    NonFinite { vertex: usize, x: f64, y: f64, z: f64 },
    /// A vertex, face or edge id that does not exist in this mesh.
    #[error("{what} {id} does not exist (the mesh has {count})")]
    NoSuchElement { what: &'static str, id: u64, count: usize },
    /// Two vertex ids that are not joined by an edge.
    #[error("vertices {a} and {b} are not joined by an edge")]
    NotAnEdge { a: u32, b: u32 },
    /// A crease or corner sharpness that is NaN or negative.
    #[error("sharpness {sharpness} is not valid: it must be 0 (smooth) or more, up to infinity")]
    BadSharpness { sharpness: f64 },
    /// A colour component outside `0..=1` (or NaN).
    #[error("colour component {component} must be between 0 and 1, got {value}")]
    BadColor { component: usize, value: f64 },
    /// A face that cannot be triangulated in its plane.
    #[error("face {face} cannot be triangulated: {reason}")]
    Triangulation { face: usize, reason: String },
    /// A length or coordinate outside the range the operation takes (`value` and `range` as
    /// messages show numbers).
    #[error("argument `{name}` must be between {range}, got {value}")]
    OutOfRange { name: String, value: String, range: String },
    /// Too many elements for 32-bit ids.
    #[error("the mesh is too large: {what}")]
    TooLarge { what: String },
    /// A broken internal invariant: a bug in blocksmith, please file an issue.
    #[error("internal error (please file an issue): {0}")]
    Internal(String),
    /// Refused over the memory budget, or stopped by the cancellation token.
    #[error(transparent)]
    Limit(#[from] crate::limits::LimitError),
}
