//! The cache of rotated tool voxels a grid keeps between sculpt strokes (Heurtebise & Thon §3.3):
//! what [`Voxels::sculpt`](super::Voxels::sculpt) computed for the last tool placement, and the
//! key that says when it can be reused.

use crate::math::Vec3;

/// Marks a rotated voxel not yet computed.
pub(super) const UNSET: u16 = u16::MAX;

/// What the cached voxels depend on, bit for bit: the tool (its revision and side), the rotation,
/// the ratio of voxel sizes, the sub-voxel offset and antialiasing.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) struct CacheKey {
    pub(super) tool: u64,
    pub(super) tool_n: usize,
    pub(super) rotation: [u64; 9],
    pub(super) ratio: u64,
    pub(super) frac: [u64; 3],
    pub(super) antialias: bool,
}

/// The rotated voxels of the last tool placement, over its whole reach, relative to its anchor:
/// valid for any placement that differs by whole voxels only.
#[derive(Clone, Debug)]
pub(super) struct ToolCache {
    pub(super) key: CacheKey,
    /// Where the tool's samples can be non-zero (tool coordinates); `None` for an empty tool.
    pub(super) bounds: Option<(Vec3, Vec3)>,
    pub(super) rel: [i64; 3],
    pub(super) dims: [usize; 3],
    pub(super) values: Vec<u16>,
}

impl ToolCache {
    pub(super) fn memory_bytes(&self) -> usize {
        self.values.capacity() * 2
    }
}
