//! Errors raised by subdivision, limit positions and limit evaluation.

use thiserror::Error;

/// Why a subdivision operation could not be done.
///
/// Every variant but [`SubdivError::Internal`] is bad input; the mesh an operation was called on is
/// never changed.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum SubdivError {
    /// Loop subdivision (or a Loop limit) was asked of a mesh with a face that is not a triangle.
    #[error("Loop subdivision needs triangles, but face {face} has {arity} vertices (triangulate the mesh first)")]
    NotTriangles { face: usize, arity: usize },
    /// The limit evaluator was given a mesh with a face that is not a quad.
    #[error(
        "limit evaluation needs an all-quad mesh, but face {face} has {arity} vertices \
         (apply one Catmull-Clark step first)"
    )]
    NotQuads { face: usize, arity: usize },
    /// The limit evaluator was given a mesh with semi-sharp creases or corners.
    #[error(
        "limit evaluation needs creases and corners that are smooth or infinitely sharp; this mesh has \
         semi-sharp ones (apply {levels} Catmull-Clark steps first, after which they are smooth)"
    )]
    SemiSharp { levels: u32 },
    /// The requested number of levels would make a mesh too large to hold.
    #[error("{levels} subdivision levels would make {faces} faces, more than the limit of {limit}")]
    TooLarge { levels: u32, faces: u64, limit: u64 },
    /// A face id that does not exist.
    #[error("face {face} does not exist (the mesh has {count})")]
    NoSuchFace { face: u64, count: usize },
    /// A surface parameter outside [0, 1] or not finite.
    #[error("surface parameters must lie in [0, 1], got (u, v) = ({u}, {v})")]
    BadParameter { u: f64, v: f64 },
    /// The limit normal is undefined: the surface is degenerate there (zero-area faces, or all
    /// neighbours collinear).
    #[error("the limit normal at {at} is undefined: the surface is degenerate there (zero-area faces?)")]
    DegenerateNormal { at: String },
    /// A broken internal invariant: a bug in blocksmith, please file an issue.
    #[error("internal error in subdivision (please file an issue): {0}")]
    Internal(String),
    /// Refused over the memory budget, or stopped by the cancellation token.
    #[error(transparent)]
    Limit(#[from] crate::limits::LimitError),
}
