//! Why a finishing operation refused or failed.

use thiserror::Error;

use crate::limits::LimitError;
use crate::mesh::MeshError;

/// Why a finishing operation ([`crate::finish`]) could not be done.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum FinishError {
    /// An option outside its range.
    #[error("option `{name}` must be {range}, got {value}")]
    BadOption { name: &'static str, value: String, range: String },
    /// The operation needs a closed mesh.
    #[error("the mesh has {boundary_edges} boundary edges: {what} needs a closed mesh")]
    NotClosed { what: &'static str, boundary_edges: usize },
    /// The result would be too large: the estimate is named.
    #[error("{what} would make an estimated {estimate:.3e} triangles, more than the limit of {limit:.0e}")]
    TooLarge { what: String, estimate: f64, limit: f64 },
    /// The boolean engine refused the mesh or its tangents.
    #[error("the smoothing engine failed: {0}")]
    Engine(String),
    /// The mesh could not be built or triangulated.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// Over the memory budget, or stopped.
    #[error(transparent)]
    Limit(#[from] LimitError),
}

impl FinishError {
    /// A [`FinishError::BadOption`] showing `value` as messages show numbers.
    #[must_use]
    pub fn bad(name: &'static str, value: f64, range: impl Into<String>) -> FinishError {
        FinishError::BadOption { name, value: crate::math::fmt_num(value), range: range.into() }
    }
}
