//! Voxel sculpting with Haar-wavelet levels of detail and rotated discrete tools.
//!
//! Follows Heurtebise & Thon, "Discrete tools for virtual sculpture" (seed 001):
//! - [`Voxels`] ([`grid`](self::Voxels)): an n³ grid of 0–255 densities (n a power of two) with a
//!   world mapping, filled from shapes ([`Voxels::fill_box`], [`Voxels::fill_sphere`]) or by
//!   voxelizing any closed [`Mesh`](crate::Mesh) ([`Voxels::from_mesh`], [`Voxels::fill_mesh`]),
//!   always with partial coverage as density.
//! - [`haar1d`] / [`ihaar1d`] (§2.1) and the 3D hierarchy [`HaarHierarchy`] (§2.2): the 1D Haar
//!   transform along x, y and z at each level, in Pinnamaneni's in-place layout, stored in
//!   integers scaled by 8ˡ so that reconstruction is exact.
//! - Marching cubes per level of detail (§2.3, [`Voxels::to_mesh`]): closed, manifold output,
//!   cached per level in blocks so a sculpt re-meshes only the blocks it touched; by default over
//!   the densities smoothed by a small filter ([`Surface::Smooth`], no terraces), or over the
//!   densities themselves ([`Surface::Raw`]).
//! - Tools (§3): [`rotate_tool`] (inverse mapping §3.1.3, the incremental stepping of Algorithm 1,
//!   trilinear antialiasing §3.2) and [`Voxels::sculpt`] (§3.3: add or subtract the filling
//!   percentage, clamped to 0–255, computing only the tool voxels in contact and reusing a cache
//!   of rotated voxels).
//!
//! Coordinates: voxel `(i, j, k)` is the unit cube `[i, i+1) × [j, j+1) × [k, k+1)` of grid
//! coordinates, its density sampled at its centre. A grid maps grid coordinates `g` to its own
//! ("world") coordinates `origin + scale · g`; a grid made by [`Voxels::new`] has origin 0 and
//! scale 1, one made by [`Voxels::from_mesh`] maps the mesh's bounds (plus one voxel of margin)
//! into the grid. Shapes, sculpt positions and output meshes are all in world coordinates.
//!
//! Heavy loops run on rayon's pool when [`Voxels::set_parallel`] is on (the default), slice by
//! slice, with results identical to the serial path.

mod centred_tools;
mod error;
mod fill;
mod grid;
mod haar1d;
mod haar3d;
mod lod;
mod lod_cache;
mod marching_cubes;
mod mc_table;
mod rotate;
mod sculpt;
mod smooth_field;
mod tool_cache;
mod voxelize;

pub use error::VoxelError;
pub use grid::{Voxels, MAX_SIZE};
pub use haar1d::{haar1d, ihaar1d};
pub use haar3d::HaarHierarchy;
pub use lod_cache::DEFAULT_ISO;
pub use marching_cubes::{marching_cubes, Surface};
pub use rotate::{rotate_tool, sample_tool, Placement, RotatedVoxels, RotationMethod};
pub use sculpt::{SculptMode, SculptOptions, SculptReport};

use rayon::prelude::*;

/// Runs `f(index, chunk)` over consecutive `chunk`-sized pieces of `data`, on rayon's pool when
/// `parallel`, else in order. Each piece is written by one call only, so both paths give the
/// same result.
pub(crate) fn for_each_chunk<T: Send>(
    parallel: bool,
    data: &mut [T],
    chunk: usize,
    f: impl Fn(usize, &mut [T]) + Sync + Send,
) {
    if chunk == 0 || data.is_empty() {
        return;
    }
    if parallel {
        data.par_chunks_mut(chunk).enumerate().for_each(|(i, c)| f(i, c));
    } else {
        data.chunks_mut(chunk).enumerate().for_each(|(i, c)| f(i, c));
    }
}

/// As [`map_range`], charging `units` of work per item to the calling thread's cancellation
/// token (checked on the workers too): once it stops, the remaining items are skipped and the
/// reason is returned instead of a partial result.
pub(crate) fn map_range_checked<R: Send + Default>(
    parallel: bool,
    count: usize,
    units: u64,
    f: impl Fn(usize) -> R + Sync + Send,
) -> Result<Vec<R>, crate::limits::LimitError> {
    let token = crate::limits::current();
    let out = map_range(parallel, count, |i| if token.charge(units).is_ok() { f(i) } else { R::default() });
    match token.stopped() {
        Some(reason) => Err(crate::limits::LimitError::Stopped(reason)),
        None => Ok(out),
    }
}

/// As [`map_range`], reading the calling thread's cancellation token before each item (on the
/// workers too) without charging work: for passes whose work was charged already. Once it
/// stops, the remaining items are skipped and the reason is returned instead of a partial result.
pub(crate) fn map_range_polled<R: Send + Default>(
    parallel: bool,
    count: usize,
    f: impl Fn(usize) -> R + Sync + Send,
) -> Result<Vec<R>, crate::limits::LimitError> {
    let token = crate::limits::current();
    let out = map_range(parallel, count, |i| if token.stopped().is_none() { f(i) } else { R::default() });
    match token.stopped() {
        Some(reason) => Err(crate::limits::LimitError::Stopped(reason)),
        None => Ok(out),
    }
}

/// `f(i)` for `i` in `0..count`, collected in order, on rayon's pool when `parallel`.
pub(crate) fn map_range<R: Send>(parallel: bool, count: usize, f: impl Fn(usize) -> R + Sync + Send) -> Vec<R> {
    if parallel {
        (0..count).into_par_iter().map(f).collect()
    } else {
        (0..count).map(f).collect()
    }
}

#[cfg(test)]
mod tests_smooth;
