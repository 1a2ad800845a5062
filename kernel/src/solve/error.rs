//! Errors of the constraint solver.

use thiserror::Error;

/// What went wrong setting up or solving a constraint system.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SolveError {
    /// A vertex id past the mesh's vertices.
    #[error("vertex {vertex} does not exist (the mesh has {count})")]
    NoSuchVertex { vertex: u32, count: usize },
    /// A constraint over no vertex, or with fewer than it needs.
    #[error("{what} needs at least {needed} vertices, got {got}")]
    TooFewVertices { what: &'static str, needed: usize, got: usize },
    /// A vertex listed twice in one constraint.
    #[error("vertex {vertex} appears twice in one {what} constraint")]
    RepeatedVertex { what: &'static str, vertex: u32 },
    /// Anchors whose position count differs from their vertex count.
    #[error("{count} anchor positions for {verts} vertices")]
    AnchorCount { verts: usize, count: usize },
    /// A weight that is not finite and > 0.
    #[error("weight {weight} is not a finite number > 0")]
    BadWeight { weight: f64 },
    /// A circle radius that is not finite and > 0.
    #[error("radius {radius} is not a finite number > 0")]
    BadRadius { radius: f64 },
    /// Points no circle fits: all on one line, or all at one place.
    #[error("{what} lies on one line or at one place, so no circle fits it")]
    NoCircle { what: &'static str },
    /// A NaN or infinite coordinate in the input.
    #[error("{what} has a non-finite coordinate")]
    NonFinite { what: &'static str },
    /// No anchors and no closeness: translations (at least) leave the energy unchanged.
    #[error(
        "the system has no anchoring term: add anchors or a closeness energy, otherwise moving every vertex \
         together leaves the energy unchanged and the solution is not unique"
    )]
    Unanchored,
    /// The normal matrix is not positive definite.
    #[error("the normal matrix is singular: the constraints leave some vertices free ({0})")]
    Singular(String),
    /// Refused over the memory budget, or stopped by the cancellation token.
    #[error(transparent)]
    Limit(#[from] crate::limits::LimitError),
}
