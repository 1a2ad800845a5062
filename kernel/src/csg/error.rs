//! Errors of CSG evaluation.

use thiserror::Error;

use crate::blocks::BlockError;
use crate::math::fmt_num;
use crate::mesh::MeshError;

/// Which operand of a boolean is at fault.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// The first operand (`a` in `a - b`).
    Left,
    /// The second operand (`b` in `a - b`).
    Right,
}

impl std::fmt::Display for Side {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Side::Left => "left",
            Side::Right => "right",
        })
    }
}

/// Why a CSG tree could not be evaluated. Every variant but [`CsgError::Engine`] is bad input and
/// names the operand (`side`) of the innermost boolean that holds it and the input's `leaf`
/// number (inputs numbered left to right from 0).
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum CsgError {
    /// An input mesh with a boundary: it bounds no solid.
    #[error("the {side} operand (input {leaf}) is not closed: it has {boundary_edges} boundary edges, so it bounds no solid")]
    OpenMesh { side: Side, leaf: u32, boundary_edges: usize },
    /// An input with no faces (a block model without blocks, an empty mesh).
    #[error("the {side} operand (input {leaf}) is empty: it has no faces")]
    EmptyOperand { side: Side, leaf: u32 },
    /// An input whose surface touches itself (two of its vertices at one point) or that the
    /// engine refuses as not manifold.
    #[error("the {side} operand (input {leaf}) is not manifold: {reason}")]
    NonManifold { side: Side, leaf: u32, reason: String },
    /// A non-finite coordinate in an input.
    #[error("the {side} operand (input {leaf}) has a non-finite coordinate at vertex {vertex}")]
    NonFinite { side: Side, leaf: u32, vertex: usize },
    /// A block model that could not be tessellated.
    #[error("the {side} operand (input {leaf}) could not be meshed: {source}")]
    Blocks {
        side: Side,
        leaf: u32,
        #[source]
        source: BlockError,
    },
    /// An input mesh whose faces cannot be triangulated.
    #[error("the {side} operand (input {leaf}) could not be triangulated: {source}")]
    Triangulation {
        side: Side,
        leaf: u32,
        #[source]
        source: MeshError,
    },
    /// An operand too small, in some direction, for the engine's precision where it lies.
    #[error(
        "the {side} operand spans {} at coordinates up to {}: booleans resolve 1e-12 of the largest coordinate, \
         and every operand must span at least 1e-10 of it in each direction (the precision limit); \
         move the operands nearer the origin",
        fmt_num(*span),
        format!("{magnitude:.2e}")
    )]
    Precision { side: Side, span: f64, magnitude: f64 },
    /// The inputs are too large for 32-bit triangle ids.
    #[error("the inputs have {triangles} triangles in all; at most 2^31 fit")]
    TooLarge { triangles: usize },
    /// The engine's result is not a valid mesh (please file an issue).
    #[error("the boolean engine failed: {reason} (please file an issue)")]
    Engine { reason: String },
    /// Refused over the memory budget, or stopped by the cancellation token.
    #[error(transparent)]
    Limit(#[from] crate::limits::LimitError),
}
