//! Errors of 2D profiles and of the solids made from them.

use thiserror::Error;

use crate::limits::LimitError;
use crate::math::fmt_num;

/// Why a profile, or a solid made from profiles, could not be built. Every variant but
/// [`ProfileError::Engine`] is bad input and names what is wrong with it.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum ProfileError {
    /// A coordinate that is NaN or infinite.
    #[error("{what} has a non-finite coordinate at point {index}")]
    NonFinite { what: String, index: usize },
    /// A contour (or path) with too few points.
    #[error("{what} has {count} points; it needs at least {needed}")]
    TooFewPoints { what: String, count: usize, needed: usize },
    /// Input that encloses no area (collinear points, a zero-size rectangle, a cancelled-out
    /// polygon).
    #[error("{what} encloses no area")]
    ZeroArea { what: String },
    /// A coordinate beyond [`MAX_REACH`](super::MAX_REACH) from the origin, where the 2D engine's
    /// integer grid would overflow.
    #[error(
        "{what} has a coordinate {} at point {index}, beyond the 2D range of ±1e9 (the engine \
         keeps 2D coordinates on a grid of 1e-8)",
        fmt_num(*value)
    )]
    OutOfRange { what: String, index: usize, value: f64 },
    /// Font data that is not a TrueType or OpenType font.
    #[error("the font cannot be read: {reason}")]
    Font { reason: String },
    /// A number out of its range.
    #[error("{name} must be {expected}, not {}", fmt_num(*value))]
    BadValue { name: &'static str, value: f64, expected: &'static str },
    /// An operation that needs a region got an empty profile.
    #[error("{what} is empty: it has no contours")]
    Empty { what: String },
    /// A revolved profile reaching to x < 0 (the far side of the axis).
    #[error(
        "the profile crosses the revolve axis: contour {contour} reaches x = {} at point {index}; \
         a revolved profile must lie in x >= 0 (x is the radius)",
        fmt_num(*x)
    )]
    CrossesAxis { contour: usize, index: usize, x: f64 },
    /// A sweep path with two consecutive points at one place.
    #[error("the path repeats point {index} at point {} (consecutive points must differ)", index + 1)]
    RepeatedPoint { index: usize },
    /// A sweep path turning so sharply at a point that the profile would fold over itself there.
    #[error(
        "the path turns by {} degrees at point {index}: too sharp for the profile, whose side \
         would fold back over itself there (shorten the profile or round the turn)",
        fmt_num(*degrees)
    )]
    SharpTurn { index: usize, degrees: f64 },
    /// A swept or lofted solid that passes through itself (closed and manifold, but no solid).
    #[error(
        "{what} passes through itself near {near}, at ({}, {}, {}): the solid would count that \
         space twice (move the path or profiles apart there, or build the parts separately and \
         unite them)",
        fmt_num(at.x), fmt_num(at.y), fmt_num(at.z)
    )]
    SelfCrossing { what: &'static str, near: String, at: crate::math::Vec3 },
    /// Lofted profiles whose contours do not correspond.
    #[error("profile {index} cannot be lofted from profile 0: {reason}")]
    LoftMismatch { index: usize, reason: String },
    /// An input mesh with a boundary or no faces: it bounds no solid.
    #[error("{what} is not a closed solid: {reason}")]
    NotSolid { what: String, reason: String },
    /// The engine built no valid result (please file an issue).
    #[error("the geometry engine failed: {reason} (please file an issue)")]
    Engine { reason: String },
    /// Refused over the memory budget, or stopped by the cancellation token.
    #[error(transparent)]
    Limit(#[from] LimitError),
}
