//! Errors raised while defining, connecting or meshing blocks.

use thiserror::Error;

/// Why a block operation could not be done.
///
/// Every variant but [`BlockError::Internal`] is bad input; the block or model an operation was
/// called on is left exactly as it was.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum BlockError {
    /// A corner with a NaN or infinite coordinate.
    #[error("corner {corner} has a non-finite coordinate ({x}, {y}, {z})")]
    NonFinite { corner: usize, x: f64, y: f64, z: f64 },
    /// A corner farther from the origin than [`MAX_COORDINATE`](super::block::MAX_COORDINATE) on
    /// some axis: products of such coordinates overflow.
    #[error(
        "corner {corner} has a coordinate of magnitude {value:e}, beyond the limit 1e100 (its products would overflow)"
    )]
    TooFar { corner: usize, value: f64 },
    /// Two corners at the same place (the block would be degenerate).
    #[error("corners {a} and {b} coincide")]
    CoincidentCorners { a: usize, b: usize },
    /// A face whose corners cross: the bilinear face folds over itself.
    #[error("face {face} is folded (its corners cross over each other)")]
    FoldedFace { face: &'static str },
    /// A negative (or zero) volume at a corner: the block is inside out or folded there.
    #[error(
        "the block is inverted at corner {corner} (negative volume: corners out of order, or min > max on an axis)"
    )]
    Inverted { corner: usize },
    /// A face name other than `-x +x -y +y -z +z`.
    #[error("unknown face \"{name}\"; faces are \"-x\", \"+x\", \"-y\", \"+y\", \"-z\", \"+z\"")]
    UnknownFace { name: String },
    /// An edge name that is not two faces of different axes, e.g. `"+x+y"`.
    #[error("unknown edge \"{name}\"; an edge is named by two faces of different axes, e.g. \"+x+y\" or \"-z+x\"")]
    UnknownEdge { name: String },
    /// An edge sharpness that is NaN or negative.
    #[error("edge {edge} needs a sharpness of 0 or more, got {sharpness}")]
    BadSharpness { edge: String, sharpness: f64 },
    /// A colour component outside `0..=1` (NaN included).
    #[error("colour component {component} must be between 0 and 1, got {value}")]
    BadColor { component: usize, value: f64 },
    /// A sub-face index outside `0..nu*nv` of its face.
    #[error("sub-face {sub} of face {face} does not exist (the face has {count})")]
    SubFaceOutOfRange { face: &'static str, sub: i64, count: u32 },
    /// A face divided into zero parts along u or v.
    #[error("face {face} needs at least one division along u and v, got {nu} x {nv}")]
    ZeroSubdivisions { face: &'static str, nu: i64, nv: i64 },
    /// A face divided into more parts than the limit.
    #[error("face {face} may be divided into at most {max} parts along u and v, got {nu} x {nv}")]
    TooManySubdivisions { face: &'static str, nu: i64, nv: i64, max: u32 },
    /// A block id that is not in the model.
    #[error("block {id} does not exist (the model has {count})")]
    NoSuchBlock { id: i64, count: usize },
    /// A manual connection of a block to itself.
    #[error("a connection joins two different blocks, but both sides are block {block}")]
    SameBlock { block: u32 },
    /// A sub-face used by two manual connections.
    #[error("sub-face {sub} of face {face} of block {block} is already connected")]
    AlreadyConnected { block: u32, face: &'static str, sub: u32 },
    /// A threshold that is negative or not finite.
    #[error("the connection threshold must be a finite number >= 0, got {value}")]
    BadThreshold { value: f64 },
    /// A meshing option out of range.
    #[error("option `{name}` {reason}, got {value}")]
    BadOption { name: &'static str, value: f64, reason: &'static str },
    /// A model without blocks has no surface.
    #[error("the model has no blocks")]
    Empty,
    /// The connections make a surface that is not a closed 2-manifold (sub-faces joined so that
    /// an edge collapses or three faces meet at an edge).
    #[error("the connections do not form a closed manifold surface: {reason}")]
    Topology { reason: String },
    /// The displacement function failed or returned a value that is not finite.
    #[error("the displacement function {reason}")]
    Displacement { reason: String },
    /// The limit surface is degenerate (zero-area faces, blocks squashed flat).
    #[error("the limit surface is degenerate: {reason}")]
    Degenerate { reason: String },
    /// A broken internal invariant: a bug in blocksmith, please file an issue.
    #[error("internal error in blocks (please file an issue): {0}")]
    Internal(String),
    /// Refused over the memory budget, or stopped by the cancellation token.
    #[error(transparent)]
    Limit(#[from] crate::limits::LimitError),
}

impl BlockError {
    /// The error of a step that cannot fail on valid input (`what` names it): a limit (the
    /// memory budget, a stop) stays a limit, anything else is an internal error.
    pub(crate) fn internal(what: &str, e: impl Into<InnerFailure>) -> BlockError {
        match e.into() {
            InnerFailure::Limit(l) => BlockError::Limit(l),
            InnerFailure::Other(reason) if what.is_empty() => BlockError::Internal(reason),
            InnerFailure::Other(reason) => BlockError::Internal(format!("{what}: {reason}")),
        }
    }
}

/// A mesh or subdivision error seen by the block mesher: a limit, or anything else as text.
pub(crate) enum InnerFailure {
    Limit(crate::limits::LimitError),
    Other(String),
}

impl From<crate::mesh::MeshError> for InnerFailure {
    fn from(e: crate::mesh::MeshError) -> InnerFailure {
        match e {
            crate::mesh::MeshError::Limit(l) => InnerFailure::Limit(l),
            e => InnerFailure::Other(e.to_string()),
        }
    }
}

impl From<crate::subdiv::SubdivError> for InnerFailure {
    fn from(e: crate::subdiv::SubdivError) -> InnerFailure {
        match e {
            crate::subdiv::SubdivError::Limit(l) => InnerFailure::Limit(l),
            e => InnerFailure::Other(e.to_string()),
        }
    }
}
