//! Errors raised by voxel grids, the Haar hierarchy, marching cubes and sculpting.

use thiserror::Error;

/// Why a voxel operation could not be done.
///
/// Every variant but [`VoxelError::Internal`] is bad input; the grid an operation was called on
/// is left exactly as it was when one is returned.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum VoxelError {
    /// A grid size that is not a power of two.
    #[error("grid size {n} is not a power of two (1, 2, 4, …, {max})")]
    NotPowerOfTwo { n: i64, max: usize },
    /// A grid size whose memory would exceed the limit.
    #[error("grid size {n} is too large: at most {max}³ voxels are allowed (about {mib} MiB with its hierarchy)")]
    TooLarge { n: i64, max: usize, mib: usize },
    /// A NaN or infinite number where a finite one is needed.
    #[error("{what} is not finite ({value})")]
    NonFinite { what: &'static str, value: String },
    /// An argument outside what the operation accepts.
    #[error("{what}: {reason}")]
    InvalidArgument { what: &'static str, reason: String },
    /// A voxel index outside the grid.
    #[error("voxel ({x}, {y}, {z}) is outside the {n}³ grid")]
    OutOfRange { x: i64, y: i64, z: i64, n: usize },
    /// A level of detail that the grid does not have.
    #[error("level {level} does not exist: a {n}³ grid has levels 0 to {max}")]
    LevelOutOfRange { level: i64, max: u32, n: usize },
    /// A mesh that cannot be voxelized because it is not closed or has no faces.
    #[error("cannot voxelize the mesh: {reason}")]
    BadMesh { reason: String },
    /// A broken internal invariant: a bug in blocksmith, please file an issue.
    #[error("internal error (please file an issue): {0}")]
    Internal(String),
    /// Refused over the memory budget, or stopped by the cancellation token.
    #[error(transparent)]
    Limit(#[from] crate::limits::LimitError),
}
