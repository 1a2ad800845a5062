//! Errors of the animation module.

use thiserror::Error;

/// What went wrong building or running an animation.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum AnimError {
    /// A root vertex or face that is not on the mesh.
    #[error("{what} {id} does not exist (the mesh has {count})")]
    NoSuchElement { what: &'static str, id: i64, count: usize },
    /// A parameter outside its range; `name` is the option, `reason` says why.
    #[error("`{name}` {reason}")]
    InvalidParameter { name: &'static str, reason: String },
    /// A modifier produced a NaN, an infinite value or a negative thickness.
    #[error("modifier {index} ({kind}) gave node {node} {what}")]
    BadState { index: usize, kind: &'static str, node: u32, what: String },
    /// A modifier supplied by the caller failed.
    #[error("modifier {index} failed at node {node}: {message}")]
    Custom { index: usize, node: u32, message: String },
    /// The skeleton could not be inferred.
    #[error("the skeleton cannot be inferred: {0}")]
    Skeleton(String),
    /// Refused over the memory budget, or stopped by the cancellation token.
    #[error(transparent)]
    Limit(#[from] crate::limits::LimitError),
}
