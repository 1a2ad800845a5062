//! The voxel grid: an n³ array of 0–255 densities with a world mapping, and the bookkeeping that
//! keeps its Haar hierarchy and surface caches in step with every edit.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use super::haar3d::HaarHierarchy;
use super::lod_cache::SurfaceCache;
use super::tool_cache::ToolCache;
use super::{for_each_chunk, VoxelError};
use crate::limits::LimitError;
use crate::math::{is_finite, Vec3};

/// The largest grid side accepted: 512³ voxels are 128 MiB of densities and 256 MiB of Haar
/// coefficients; anything larger is refused with [`VoxelError::TooLarge`].
pub const MAX_SIZE: usize = 512;

static NEXT_REVISION: AtomicU64 = AtomicU64::new(1);

/// A fresh revision number, unique within the process.
pub(super) fn next_revision() -> u64 {
    NEXT_REVISION.fetch_add(1, Ordering::Relaxed)
}

/// An n³ grid of densities (0 empty, 255 full), n a power of two, with a world mapping
/// `world = origin + scale · grid`.
///
/// Voxel `(x, y, z)` is the unit cube `[x, x+1) × [y, y+1) × [z, z+1)` of grid coordinates and is
/// stored at `(z · n + y) · n + x`. Besides the densities a grid carries derived data, kept in step
/// with every edit: its [`HaarHierarchy`] (built on first use), one marching-cubes surface cache
/// per level of detail asked for, and the cache of the last rotated tool used on it.
///
/// Equality compares size, mapping and densities only.
///
/// See also [`Voxels::from_mesh`], [`Voxels::sculpt`], [`Voxels::to_mesh`]; Heurtebise & Thon §2.
#[derive(Clone, Debug)]
pub struct Voxels {
    pub(super) n: usize,
    pub(super) data: Vec<u8>,
    pub(super) origin: Vec3,
    pub(super) scale: f64,
    pub(super) parallel: bool,
    pub(super) revision: u64,
    pub(super) hierarchy: Option<HaarHierarchy>,
    pub(super) surfaces: Vec<Option<SurfaceCache>>,
    pub(super) tool_cache: Option<ToolCache>,
}

impl PartialEq for Voxels {
    fn eq(&self, other: &Voxels) -> bool {
        self.n == other.n && self.origin == other.origin && self.scale == other.scale && self.data == other.data
    }
}

impl Voxels {
    /// Checks a requested grid side: a power of two from 1 to [`MAX_SIZE`].
    ///
    /// # Errors
    /// [`VoxelError::NotPowerOfTwo`] for zero, negative or non-power-of-two sides,
    /// [`VoxelError::TooLarge`] above [`MAX_SIZE`].
    pub fn check_size(n: i64) -> Result<usize, VoxelError> {
        if n > MAX_SIZE as i64 && (n as u64).is_power_of_two() {
            let bytes = (MAX_SIZE as u128).pow(3) * 3;
            return Err(VoxelError::TooLarge { n, max: MAX_SIZE, mib: (bytes >> 20) as usize });
        }
        if n <= 0 || !(n as u64).is_power_of_two() {
            return Err(VoxelError::NotPowerOfTwo { n, max: MAX_SIZE });
        }
        Ok(n as usize)
    }

    /// An empty n³ grid with origin 0 and scale 1 (world coordinates are voxel units).
    ///
    /// # Errors
    /// See [`Voxels::check_size`].
    pub fn new(n: usize) -> Result<Voxels, VoxelError> {
        Voxels::with_map(n, Vec3::ZERO, 1.0)
    }

    /// An empty n³ grid whose voxel `(i, j, k)` has its lowest corner at world position
    /// `origin + scale · (i, j, k)`.
    ///
    /// # Errors
    /// See [`Voxels::check_size`]; [`VoxelError::NonFinite`] for a non-finite origin or scale and
    /// [`VoxelError::InvalidArgument`] for a scale that is not positive.
    pub fn with_map(n: usize, origin: Vec3, scale: f64) -> Result<Voxels, VoxelError> {
        let n = Voxels::check_size(i64::try_from(n).unwrap_or(i64::MAX))?;
        if !is_finite(origin) {
            return Err(VoxelError::NonFinite { what: "grid origin", value: format!("{origin}") });
        }
        if !scale.is_finite() {
            return Err(VoxelError::NonFinite { what: "grid scale", value: format!("{scale}") });
        }
        if scale <= 0.0 {
            return Err(VoxelError::InvalidArgument { what: "grid scale", reason: format!("{scale} is not positive") });
        }
        // The densities, and the hierarchy and surface caches built on first use: about three
        // bytes a voxel (as `check_size` reports).
        crate::limits::check_memory(|| format!("a {n}³ voxel grid"), (n as f64).powi(3) * 3.0)?;
        Ok(Voxels {
            n,
            data: vec![0; n * n * n],
            origin,
            scale,
            parallel: true,
            revision: next_revision(),
            hierarchy: None,
            surfaces: Vec::new(),
            tool_cache: None,
        })
    }

    /// The side n of the grid.
    #[must_use]
    pub fn size(&self) -> usize {
        self.n
    }

    /// The number of levels of detail below the full resolution: log₂ n (level 0 is the grid
    /// itself, level log₂ n a single voxel).
    #[must_use]
    pub fn max_level(&self) -> u32 {
        self.n.trailing_zeros()
    }

    /// All densities, x fastest: voxel `(x, y, z)` at `(z · n + y) · n + x`.
    #[must_use]
    pub fn data(&self) -> &[u8] {
        &self.data
    }

    /// The world position of grid coordinate zero.
    #[must_use]
    pub fn origin(&self) -> Vec3 {
        self.origin
    }

    /// The world length of one voxel side.
    #[must_use]
    pub fn scale(&self) -> f64 {
        self.scale
    }

    /// Grid coordinates → world coordinates.
    #[must_use]
    pub fn to_world(&self, g: Vec3) -> Vec3 {
        self.origin + g * self.scale
    }

    /// World coordinates → grid coordinates.
    #[must_use]
    pub fn to_grid(&self, w: Vec3) -> Vec3 {
        (w - self.origin) / self.scale
    }

    /// Whether heavy operations run on rayon's pool (default `true`). Results do not depend on it.
    #[must_use]
    pub fn parallel(&self) -> bool {
        self.parallel
    }

    /// Turns the parallel paths on or off (results are identical either way).
    pub fn set_parallel(&mut self, parallel: bool) {
        self.parallel = parallel;
    }

    /// A number that changes on every edit of the densities (unique within the process), used to
    /// key caches of derived data.
    #[must_use]
    pub fn revision(&self) -> u64 {
        self.revision
    }

    /// The flat index of voxel `(x, y, z)` (no check).
    #[must_use]
    pub fn index(&self, x: usize, y: usize, z: usize) -> usize {
        (z * self.n + y) * self.n + x
    }

    fn checked(&self, x: i64, y: i64, z: i64) -> Result<usize, VoxelError> {
        let n = self.n as i64;
        if x < 0 || y < 0 || z < 0 || x >= n || y >= n || z >= n {
            return Err(VoxelError::OutOfRange { x, y, z, n: self.n });
        }
        Ok(self.index(x as usize, y as usize, z as usize))
    }

    /// The density of voxel `(x, y, z)`.
    ///
    /// # Errors
    /// [`VoxelError::OutOfRange`] outside the grid.
    pub fn get(&self, x: i64, y: i64, z: i64) -> Result<u8, VoxelError> {
        Ok(self.data[self.checked(x, y, z)?])
    }

    /// Sets the density of voxel `(x, y, z)`.
    ///
    /// # Errors
    /// [`VoxelError::OutOfRange`] outside the grid; [`VoxelError::Limit`] when the current
    /// cancellation token has stopped (nothing changes).
    pub fn set(&mut self, x: i64, y: i64, z: i64, value: u8) -> Result<(), VoxelError> {
        let i = self.checked(x, y, z)?;
        let (x, y, z) = (x as usize, y as usize, z as usize);
        let n = self.n;
        self.edit_slices([x, y, z], [x + 1, y + 1, z + 1], |_, slice| slice[i - z * n * n] = value)?;
        Ok(())
    }

    /// The number of voxels with a non-zero density.
    #[must_use]
    pub fn filled(&self) -> usize {
        self.data.iter().filter(|&&v| v != 0).count()
    }

    /// The sum of densities / 255: the filled volume in voxel units (a full voxel counts 1).
    ///
    /// See also [`Voxels::world_volume`].
    #[must_use]
    pub fn volume(&self) -> f64 {
        let sum: u64 = self.data.iter().map(|&v| u64::from(v)).sum();
        sum as f64 / 255.0
    }

    /// [`Voxels::volume`] in world units (times scale³).
    #[must_use]
    pub fn world_volume(&self) -> f64 {
        self.volume() * self.scale.powi(3)
    }

    /// Heap bytes held by the grid and its derived data (densities, hierarchy, surface caches and
    /// the rotated-tool cache).
    #[must_use]
    pub fn memory_bytes(&self) -> usize {
        let mut total = self.data.capacity();
        if let Some(h) = &self.hierarchy {
            total += h.memory_bytes();
        }
        total += self.surfaces.iter().flatten().map(SurfaceCache::memory_bytes).sum::<usize>();
        if let Some(t) = &self.tool_cache {
            total += t.memory_bytes();
        }
        total
    }

    /// Whether the Haar hierarchy has been built (it is built on first use and then kept in step
    /// with every edit).
    #[must_use]
    pub fn has_hierarchy(&self) -> bool {
        self.hierarchy.is_some()
    }

    /// The Haar hierarchy of the grid with every level (log₂ n), built now if needed.
    ///
    /// See also [`HaarHierarchy::build`].
    pub fn hierarchy(&mut self) -> &HaarHierarchy {
        if self.hierarchy.is_none() {
            self.hierarchy = Some(HaarHierarchy::build_with(&self.data, self.n, self.max_level(), self.parallel));
        }
        self.hierarchy.as_ref().expect("built just above")
    }

    /// Drops the derived data (hierarchy, surface caches, tool cache) to free memory; it is
    /// rebuilt on demand.
    pub fn clear_caches(&mut self) {
        self.hierarchy = None;
        self.surfaces.clear();
        self.tool_cache = None;
    }

    /// Runs `edit(z, slice)` for every z-slice `z` of the box `[lo, hi)` (`slice` the slice's
    /// n² densities, x fastest; `edit` must change densities only inside the box), on rayon's
    /// pool when the grid is parallel; then brings the hierarchy and the surface caches up to
    /// date for that box.
    ///
    /// An edit is a transaction. The calling thread's cancellation token is read before each
    /// slice (a slice of a 512³ grid is milliseconds of work); once it stops, the remaining
    /// slices are skipped and the box is restored from the copy taken before the edit, so a
    /// stopped edit leaves the grid and its caches as they were. The copy (one byte per voxel of
    /// the box) is taken when the token can stop or a hierarchy needs the edit's delta.
    ///
    /// # Errors
    /// [`LimitError::Stopped`] when the token stops; [`LimitError::OverBudget`] when the copy
    /// would pass the memory budget. Either way the grid is unchanged.
    pub(super) fn edit_slices(
        &mut self,
        lo: [usize; 3],
        hi: [usize; 3],
        edit: impl Fn(usize, &mut [u8]) + Sync + Send,
    ) -> Result<(), LimitError> {
        let n = self.n;
        let (lo, hi) = ([lo[0].min(n), lo[1].min(n), lo[2].min(n)], [hi[0].min(n), hi[1].min(n), hi[2].min(n)]);
        if (0..3).any(|a| lo[a] >= hi[a]) {
            return Ok(());
        }
        let dims = [hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]];
        let token = crate::limits::current();
        let old = if token.is_active() || self.hierarchy.is_some() {
            let bytes = dims[0] * dims[1] * dims[2];
            crate::limits::check_growth(
                || format!("the copy of the {} × {} × {} voxels an edit may change", dims[0], dims[1], dims[2]),
                bytes as f64,
            )?;
            Some(copy_box(&self.data, n, lo, dims))
        } else {
            None
        };
        let stopped = AtomicBool::new(false);
        let slab = &mut self.data[lo[2] * n * n..hi[2] * n * n];
        for_each_chunk(self.parallel, slab, n * n, |dz, slice| {
            if stopped.load(Ordering::Relaxed) {
                return;
            }
            if token.stopped().is_some() {
                stopped.store(true, Ordering::Relaxed);
                return;
            }
            edit(lo[2] + dz, slice);
        });
        if let Some(reason) = token.stopped() {
            if let Some(old) = &old {
                paste_box(&mut self.data, n, lo, dims, old);
            }
            return Err(LimitError::Stopped(reason));
        }
        let mut changed = true;
        if let (Some(h), Some(old)) = (self.hierarchy.as_mut(), old) {
            let now = copy_box(&self.data, n, lo, dims);
            let delta: Vec<i16> = now.iter().zip(&old).map(|(&a, &b)| i16::from(a) - i16::from(b)).collect();
            changed = delta.iter().any(|&d| d != 0);
            if changed {
                h.add_delta(lo, dims, &delta, self.parallel);
            }
        }
        if changed {
            for s in self.surfaces.iter_mut().flatten() {
                s.mark_changed(lo, hi);
            }
            self.revision = next_revision();
        }
        Ok(())
    }
}

/// The densities of the box at `lo` with `dims`, x fastest.
pub(super) fn copy_box(data: &[u8], n: usize, lo: [usize; 3], dims: [usize; 3]) -> Vec<u8> {
    let mut out = Vec::with_capacity(dims[0] * dims[1] * dims[2]);
    for z in lo[2]..lo[2] + dims[2] {
        for y in lo[1]..lo[1] + dims[1] {
            let s = (z * n + y) * n + lo[0];
            out.extend_from_slice(&data[s..s + dims[0]]);
        }
    }
    out
}

/// Writes `values` (as [`copy_box`] gives them) back into the box at `lo` with `dims`.
fn paste_box(data: &mut [u8], n: usize, lo: [usize; 3], dims: [usize; 3], values: &[u8]) {
    for (i, row) in values.chunks_exact(dims[0]).enumerate() {
        let (y, z) = (lo[1] + i % dims[1], lo[2] + i / dims[1]);
        let s = (z * n + y) * n + lo[0];
        data[s..s + dims[0]].copy_from_slice(row);
    }
}

// The hierarchy's constructor from a grid lives with the grid (haar3d.rs knows densities only).
impl HaarHierarchy {
    /// Builds the hierarchy of an n³ grid down to `levels` levels (the paper's Table 1 builds 5
    /// for 128³; `levels` = log₂ n goes down to one voxel).
    ///
    /// Input: densities `data` (n³, x fastest), n a power of two.
    ///
    /// # Errors
    /// [`VoxelError::LevelOutOfRange`] when `levels` exceeds log₂ n.
    ///
    /// See also [`Voxels::hierarchy`], which builds every level and
    /// keeps it in step with edits.
    pub fn build(voxels: &Voxels, levels: u32) -> Result<HaarHierarchy, VoxelError> {
        if levels > voxels.max_level() {
            return Err(VoxelError::LevelOutOfRange { level: i64::from(levels), max: voxels.max_level(), n: voxels.n });
        }
        Ok(HaarHierarchy::build_with(&voxels.data, voxels.n, levels, voxels.parallel))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_edit_stopped_half_way_restores_its_box_and_keeps_the_caches() {
        use crate::limits::{install, CancelToken, StopReason};
        use std::sync::Arc;
        for parallel in [false, true] {
            let mut v = Voxels::new(32).unwrap();
            v.set_parallel(parallel);
            v.fill_box(Vec3::splat(2.0), Vec3::splat(20.0)).unwrap();
            v.hierarchy();
            let (before, revision) = (v.clone(), v.revision());
            let flag = Arc::new(AtomicBool::new(false));
            {
                let _g = install(CancelToken::with(Some(flag.clone()), None, None));
                // The edit raises the interrupt itself after writing slice 10: the slices
                // before it are written, the rest skipped, and all of them restored.
                let e = v
                    .edit_slices([0, 0, 4], [32, 32, 28], |z, slice| {
                        slice.fill(200);
                        if z == 10 {
                            flag.store(true, Ordering::Relaxed);
                        }
                    })
                    .unwrap_err();
                assert_eq!(e, LimitError::Stopped(StopReason::Interrupted));
            }
            assert_eq!(v, before);
            assert_eq!(v.revision(), revision);
            // The hierarchy was not given the stopped edit's delta: it still sums the grid.
            let h = HaarHierarchy::build_with(v.data(), 32, v.max_level(), false);
            assert_eq!(v.hierarchy().extract(2, false).unwrap(), h.extract(2, false).unwrap());
            // Without a stop the same edit goes through.
            v.edit_slices([0, 0, 4], [32, 32, 28], |_, slice| slice.fill(200)).unwrap();
            assert_eq!(v.get(0, 0, 27).unwrap(), 200);
        }
    }

    #[test]
    fn every_fill_and_a_set_are_refused_whole_once_stopped() {
        use crate::limits::{install, CancelToken, StopReason};
        use std::sync::Arc;
        let mut v = Voxels::new(16).unwrap();
        v.fill_sphere(Vec3::splat(8.0), 4.0).unwrap();
        let before = v.clone();
        let stopped = VoxelError::Limit(LimitError::Stopped(StopReason::Interrupted));
        let _g = install(CancelToken::with(Some(Arc::new(AtomicBool::new(true))), None, None));
        assert_eq!(v.fill_box(Vec3::ZERO, Vec3::splat(16.0)), Err(stopped.clone()));
        assert_eq!(v.fill_sphere(Vec3::splat(3.0), 5.0), Err(stopped.clone()));
        assert_eq!(v.fill_mesh(&crate::mesh::Mesh::cube(6.0).translate(Vec3::splat(8.0))), Err(stopped.clone()));
        assert_eq!(v.set(0, 0, 0, 9), Err(stopped));
        assert_eq!(v, before);
    }

    #[test]
    fn sizes_must_be_powers_of_two_within_the_limit() {
        // 1, 2, …, 512 are accepted; 0, negatives, 3, 96 and anything above 512 are not.
        for n in [1, 2, 8, 64, 512] {
            assert_eq!(Voxels::check_size(n), Ok(n as usize));
        }
        for n in [0, -4, 3, 96, 1000] {
            assert!(matches!(Voxels::check_size(n), Err(VoxelError::NotPowerOfTwo { .. })), "{n}");
        }
        for n in [1024, 1 << 40] {
            assert!(matches!(Voxels::check_size(n), Err(VoxelError::TooLarge { .. })), "{n}");
        }
        assert!(Voxels::new(48).is_err());
        assert!(Voxels::with_map(8, Vec3::new(f64::NAN, 0.0, 0.0), 1.0).is_err());
        assert!(Voxels::with_map(8, Vec3::ZERO, 0.0).is_err());
    }

    #[test]
    fn get_and_set_check_bounds_and_leave_the_grid_unchanged_on_error() {
        let mut v = Voxels::new(4).unwrap();
        v.set(1, 2, 3, 200).unwrap();
        assert_eq!(v.get(1, 2, 3), Ok(200));
        assert_eq!(v.data()[v.index(1, 2, 3)], 200);
        let before = v.clone();
        assert!(matches!(v.set(4, 0, 0, 1), Err(VoxelError::OutOfRange { .. })));
        assert!(matches!(v.get(0, -1, 0), Err(VoxelError::OutOfRange { .. })));
        assert_eq!(v, before);
        // One voxel at 200/255 is 200/255 of a voxel of volume.
        assert_eq!(v.filled(), 1);
        assert!((v.volume() - 200.0 / 255.0).abs() < 1e-15);
    }
}
