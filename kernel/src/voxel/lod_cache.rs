//! The surface cache of a level of detail (Heurtebise & Thon §2.3): one marching-cubes cache per
//! level, holding that level's image (levels ≥ 1, extracted from the Haar hierarchy) and the
//! triangles of every block; an edit marks the blocks it touches, and the next
//! [`Voxels::to_mesh`](super::Voxels::to_mesh) re-extracts and re-meshes only those (see `lod`).

use super::haar3d::{sums_to_densities, HaarHierarchy};
use super::marching_cubes::{assemble, block_count, mesh_block, Image, Surface, BLOCK, CELLS_PER_BLOCK};
use super::{map_range_checked, VoxelError};
use crate::math::Vec3;
use crate::mesh::Mesh;

/// The default iso level: 127.5, where a voxel is half covered, so the surface of a shape filled
/// with partial coverage lies close to the shape's own surface.
pub const DEFAULT_ISO: f64 = 127.5;

/// The fewest blocks meshed between two reports of progress: enough to keep the workers busy.
const BATCH_LEAST: usize = 64;

/// The marching-cubes surface of one level of detail, block by block.
#[derive(Clone, Debug)]
pub(super) struct SurfaceCache {
    iso: f64,
    surface: Surface,
    /// Side of the level's image.
    m: usize,
    /// The level's densities (empty for level 0, which reads the grid itself).
    image: Vec<u8>,
    /// Triangles per block as block-local edge keys.
    blocks: Vec<Vec<u16>>,
    dirty: Vec<bool>,
    /// The box of level-0 voxels changed since the image was last brought up to date.
    pending: Option<([usize; 3], [usize; 3])>,
    /// Blocks re-meshed by the last refresh (for tests and reports).
    last_remeshed: usize,
}

impl SurfaceCache {
    pub(super) fn new(level: u32, iso: f64, surface: Surface, n: usize) -> SurfaceCache {
        let m = n >> level;
        let nb = block_count(m);
        SurfaceCache {
            iso,
            surface,
            m,
            image: Vec::new(),
            blocks: vec![Vec::new(); nb * nb * nb],
            dirty: vec![true; nb * nb * nb],
            pending: Some(([0; 3], [n; 3])),
            last_remeshed: 0,
        }
    }

    pub(super) fn memory_bytes(&self) -> usize {
        self.image.capacity()
            + self.blocks.capacity() * std::mem::size_of::<Vec<u16>>()
            + self.blocks.iter().map(|b| b.capacity() * 2).sum::<usize>()
            + self.dirty.capacity()
    }

    /// Records that the level-0 voxels in `[lo, hi)` changed.
    pub(super) fn mark_changed(&mut self, lo: [usize; 3], hi: [usize; 3]) {
        self.pending = Some(match self.pending {
            None => (lo, hi),
            Some((a, b)) => (
                [a[0].min(lo[0]), a[1].min(lo[1]), a[2].min(lo[2])],
                [b[0].max(hi[0]), b[1].max(hi[1]), b[2].max(hi[2])],
            ),
        });
    }

    /// Whether the cache was built for iso level `iso` (bit for bit) and field `surface`.
    pub(super) fn is_for(&self, iso: f64, surface: Surface) -> bool {
        self.iso.to_bits() == iso.to_bits() && self.surface == surface
    }

    /// Blocks re-meshed by the last [`SurfaceCache::refresh`].
    pub(super) fn last_remeshed(&self) -> usize {
        self.last_remeshed
    }

    /// The cached surface as one mesh, each point mapped by `to_world`; `data` is the grid's own
    /// densities, which level 0 reads.
    pub(super) fn to_mesh(
        &self,
        level: u32,
        data: &[u8],
        to_world: impl Fn(Vec3) -> Vec3 + Sync,
        parallel: bool,
    ) -> Result<Mesh, VoxelError> {
        let img = if level == 0 { Image { values: data, m: self.m } } else { Image { values: &self.image, m: self.m } };
        assemble(img, self.iso, self.surface, &self.blocks, to_world, parallel)
    }

    /// Brings the cache of `level` up to date: pulls the changed box into the level's image (from
    /// `hierarchy`, which levels ≥ 1 need) and re-meshes the dirty blocks; `data` is the grid's own
    /// densities, which level 0 reads.
    pub(super) fn refresh(
        &mut self,
        level: u32,
        data: &[u8],
        hierarchy: Option<&HaarHierarchy>,
        parallel: bool,
    ) -> Result<(), VoxelError> {
        let (m, iso, surface) = (self.m, self.iso, self.surface);
        let nb = block_count(m);
        if let Some((lo, hi)) = self.pending.take() {
            // The level's voxels covering the changed box.
            let klo = [lo[0] >> level, lo[1] >> level, lo[2] >> level];
            let khi = [((hi[0] - 1) >> level) + 1, ((hi[1] - 1) >> level) + 1, ((hi[2] - 1) >> level) + 1];
            if level > 0 {
                let h = hierarchy.expect("built by the caller for levels ≥ 1");
                let dens = sums_to_densities(&h.sums(level, klo, khi, parallel)?, level);
                if self.image.len() != m * m * m {
                    self.image = vec![0; m * m * m];
                }
                let w = khi[0] - klo[0];
                let mut src = dens.chunks_exact(w);
                for z in klo[2]..khi[2] {
                    for y in klo[1]..khi[1] {
                        let r = (z * m + y) * m + klo[0];
                        self.image[r..r + w].copy_from_slice(src.next().expect("one row per (y, z)"));
                    }
                }
            }
            // Voxel v is padded sample v + 1, which cells v and v + 1 use; the smoothed field at
            // the samples within the filter's reach r of it changes too, which cells v − r to
            // v + 1 + r use.
            let r = surface.reach();
            let (blo, bhi) = (klo.map(|v| v.saturating_sub(r) / BLOCK), khi.map(|v| ((v + r) / BLOCK).min(nb - 1)));
            for bz in blo[2]..=bhi[2] {
                for by in blo[1]..=bhi[1] {
                    for bx in blo[0]..=bhi[0] {
                        self.dirty[(bz * nb + by) * nb + bx] = true;
                    }
                }
            }
        }
        let dirty: Vec<usize> = (0..self.dirty.len()).filter(|&b| self.dirty[b]).collect();
        let img = if level == 0 { Image { values: data, m } } else { Image { values: &self.image, m } };
        // In batches, so that the blocks meshed so far are reported (a hundred reports at most)
        // from this thread while the workers mesh each batch.
        let work = crate::limits::Work::start(dirty.len() as u64);
        let batch = (dirty.len() / 100).max(BATCH_LEAST);
        let mut fresh = Vec::with_capacity(dirty.len());
        for (k, part) in dirty.chunks(batch).enumerate() {
            fresh.extend(map_range_checked(parallel, part.len(), CELLS_PER_BLOCK, |i| {
                let bi = part[i];
                mesh_block(img, iso, [bi % nb, (bi / nb) % nb, bi / (nb * nb)], surface)
            })?);
            work.set((k * batch + part.len()) as u64);
        }
        self.last_remeshed = dirty.len();
        for (bi, tris) in dirty.into_iter().zip(fresh) {
            self.blocks[bi] = tris;
            self.dirty[bi] = false;
        }
        Ok(())
    }
}
