//! Levels of detail and their surface cache (Heurtebise & Thon §2.3): one marching-cubes cache per
//! level, holding that level's image (levels ≥ 1, extracted from the Haar hierarchy) and the
//! triangles of every block; an edit marks the blocks it touches, and the next
//! [`Voxels::to_mesh`] re-extracts and re-meshes only those.

use super::grid::next_revision;
use super::haar3d::sums_to_densities;
use super::marching_cubes::{assemble, block_count, check_iso, mesh_block, Image, BLOCK, CELLS_PER_BLOCK};
use super::{map_range_checked, VoxelError, Voxels};
use crate::mesh::Mesh;

/// The default iso level: 127.5, where a voxel is half covered, so the surface of a shape filled
/// with partial coverage lies close to the shape's own surface.
pub const DEFAULT_ISO: f64 = 127.5;

/// The marching-cubes surface of one level of detail, block by block.
#[derive(Clone, Debug)]
pub(super) struct SurfaceCache {
    iso: f64,
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
    fn new(level: u32, iso: f64, n: usize) -> SurfaceCache {
        let m = n >> level;
        let nb = block_count(m);
        SurfaceCache {
            iso,
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
}

impl Voxels {
    fn check_level(&self, level: i64) -> Result<u32, VoxelError> {
        if level < 0 || level > i64::from(self.max_level()) {
            return Err(VoxelError::LevelOutOfRange { level, max: self.max_level(), n: self.n });
        }
        Ok(level as u32)
    }

    /// Level `level` of detail as a grid of side n / 2ˡᵉᵛᵉˡ: each voxel the average of its
    /// 2ˡᵉᵛᵉˡ-cube block (rounded half up), extracted from the Haar hierarchy (built if needed),
    /// with the same origin and a scale 2ˡᵉᵛᵉˡ times larger so it covers the same world box.
    /// Level 0 is a copy of the grid.
    ///
    /// # Errors
    /// [`VoxelError::LevelOutOfRange`] outside 0…log₂ n.
    ///
    /// See also [`HaarHierarchy::extract`](super::HaarHierarchy::extract); Heurtebise & Thon §2.2.
    pub fn lod(&mut self, level: i64) -> Result<Voxels, VoxelError> {
        let level = self.check_level(level)?;
        let mut out = Voxels::with_map(self.n >> level, self.origin, self.scale * f64::from(1u32 << level))?;
        out.parallel = self.parallel;
        if level == 0 {
            out.data.clone_from(&self.data);
        } else {
            let parallel = self.parallel;
            out.data = self.hierarchy().extract(level, parallel)?;
        }
        out.revision = next_revision();
        Ok(out)
    }

    /// The marching-cubes surface of level `level` at iso level `iso` (use [`DEFAULT_ISO`]), in
    /// world coordinates: closed and manifold (the grid is capped at its border), faces outward.
    ///
    /// The surface of each level is cached block by block; after an edit only the blocks it
    /// touched are extracted again from the hierarchy and re-meshed. A different iso level
    /// rebuilds that level's cache.
    ///
    /// # Errors
    /// [`VoxelError::LevelOutOfRange`] outside 0…log₂ n; [`VoxelError::NonFinite`] or
    /// [`VoxelError::InvalidArgument`] for an iso level outside [0, 255).
    ///
    /// See also [`marching_cubes`](super::marching_cubes); Heurtebise & Thon §2.3.
    pub fn to_mesh(&mut self, level: i64, iso: f64) -> Result<Mesh, VoxelError> {
        let level = self.check_level(level)?;
        check_iso(iso)?;
        self.refresh_surface(level, iso)?;
        let cache = self.surfaces[level as usize].as_ref().expect("refreshed just above");
        let img = if level == 0 {
            Image { values: &self.data, m: self.n }
        } else {
            Image { values: &cache.image, m: cache.m }
        };
        let (origin, scale) = (self.origin, self.scale * f64::from(1u32 << level));
        assemble(img, iso, &cache.blocks, |p| origin + p * scale, self.parallel)
    }

    /// The number of blocks the last [`Voxels::to_mesh`] of `level` re-meshed (0 when nothing
    /// changed), or `None` when that level has no cache.
    #[must_use]
    pub fn last_remeshed_blocks(&self, level: u32) -> Option<usize> {
        self.surfaces.get(level as usize)?.as_ref().map(|c| c.last_remeshed)
    }

    /// Brings the cache of `level` up to date: pulls the changed box into the level's image and
    /// re-meshes the dirty blocks.
    fn refresh_surface(&mut self, level: u32, iso: f64) -> Result<(), VoxelError> {
        if level > 0 && self.hierarchy.is_none() {
            let _ = self.hierarchy();
        }
        if self.surfaces.len() <= level as usize {
            self.surfaces.resize(level as usize + 1, None);
        }
        let n = self.n;
        let parallel = self.parallel;
        let slot = &mut self.surfaces[level as usize];
        if slot.as_ref().is_none_or(|c| c.iso.to_bits() != iso.to_bits()) {
            *slot = Some(SurfaceCache::new(level, iso, n));
        }
        let cache = slot.as_mut().expect("set just above");
        let m = cache.m;
        let nb = block_count(m);
        if let Some((lo, hi)) = cache.pending.take() {
            // The level's voxels covering the changed box.
            let klo = [lo[0] >> level, lo[1] >> level, lo[2] >> level];
            let khi = [((hi[0] - 1) >> level) + 1, ((hi[1] - 1) >> level) + 1, ((hi[2] - 1) >> level) + 1];
            if level > 0 {
                let h = self.hierarchy.as_ref().expect("built above for levels ≥ 1");
                let dens = sums_to_densities(&h.sums(level, klo, khi, parallel)?, level);
                if cache.image.len() != m * m * m {
                    cache.image = vec![0; m * m * m];
                }
                let w = khi[0] - klo[0];
                let mut src = dens.chunks_exact(w);
                for z in klo[2]..khi[2] {
                    for y in klo[1]..khi[1] {
                        let r = (z * m + y) * m + klo[0];
                        cache.image[r..r + w].copy_from_slice(src.next().expect("one row per (y, z)"));
                    }
                }
            }
            // Voxel v is padded sample v + 1, which cells v and v + 1 use.
            let (blo, bhi) = (klo.map(|v| v / BLOCK), khi.map(|v| (v / BLOCK).min(nb - 1)));
            for bz in blo[2]..=bhi[2] {
                for by in blo[1]..=bhi[1] {
                    for bx in blo[0]..=bhi[0] {
                        cache.dirty[(bz * nb + by) * nb + bx] = true;
                    }
                }
            }
        }
        let dirty: Vec<usize> = (0..cache.dirty.len()).filter(|&b| cache.dirty[b]).collect();
        let img = if level == 0 { Image { values: &self.data, m } } else { Image { values: &cache.image, m } };
        let fresh = map_range_checked(parallel, dirty.len(), CELLS_PER_BLOCK, |i| {
            let bi = dirty[i];
            mesh_block(img, iso, [bi % nb, (bi / nb) % nb, bi / (nb * nb)])
        })?;
        cache.last_remeshed = dirty.len();
        for (bi, tris) in dirty.into_iter().zip(fresh) {
            cache.blocks[bi] = tris;
            cache.dirty[bi] = false;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;
    use std::f64::consts::PI;

    #[test]
    fn a_stop_lands_in_the_assembly_of_a_cached_surface() {
        use crate::limits::{install, CancelToken, LimitError, StopReason};
        use std::sync::atomic::AtomicBool;
        use std::sync::Arc;
        let mut v = Voxels::new(64).unwrap();
        v.fill_sphere(Vec3::splat(32.0), 20.0).unwrap();
        let first = v.to_mesh(0, DEFAULT_ISO).unwrap();
        {
            // Nothing changed: no block is re-meshed, so only the assembly can see the stop.
            let _g = install(CancelToken::with(Some(Arc::new(AtomicBool::new(true))), None, None));
            let e = v.to_mesh(0, DEFAULT_ISO).unwrap_err();
            assert_eq!(e, VoxelError::Limit(LimitError::Stopped(StopReason::Interrupted)));
        }
        assert_eq!(v.to_mesh(0, DEFAULT_ISO).unwrap().positions(), first.positions());
    }

    #[test]
    fn sphere_surface_is_closed_manifold_genus_zero_with_the_right_volume() {
        // Partial coverage puts the 127.5 iso-surface within a fraction of a voxel of the sphere,
        // so the enclosed volume is 4/3 π r³ to within about 1%.
        let mut v = Voxels::new(32).unwrap();
        let r = 10.0;
        v.fill_sphere(Vec3::splat(16.0), r).unwrap();
        let m = v.to_mesh(0, DEFAULT_ISO).unwrap();
        assert!(m.is_closed() && m.is_manifold());
        assert_eq!((m.genus(), m.component_count()), (0, 1));
        let exact = 4.0 / 3.0 * PI * r * r * r;
        let rel = (m.volume() - exact).abs() / exact;
        assert!(rel < 0.01, "volume {} vs {exact}: relative {rel:e}", m.volume());
    }

    #[test]
    fn torus_voxelized_and_meshed_has_genus_one() {
        let mut v = Voxels::from_mesh(&Mesh::torus(2.0, 0.7, 48, 24), 32).unwrap();
        let m = v.to_mesh(0, DEFAULT_ISO).unwrap();
        assert!(m.is_closed() && m.is_manifold());
        assert_eq!((m.genus(), m.component_count()), (1, 1));
        // In the torus's own coordinates: volume 2π² R r².
        let exact = 2.0 * PI * PI * 2.0 * 0.49;
        let rel = (m.volume() - exact).abs() / exact;
        assert!(rel < 0.03, "volume {} vs {exact}: relative {rel:e}", m.volume());
    }

    #[test]
    fn lower_levels_are_coarser_closed_surfaces_in_the_same_place() {
        let mut v = Voxels::new(32).unwrap();
        v.fill_sphere(Vec3::new(16.0, 15.0, 17.0), 11.0).unwrap();
        let fine = v.to_mesh(0, DEFAULT_ISO).unwrap();
        for level in 1..=2 {
            let m = v.to_mesh(level, DEFAULT_ISO).unwrap();
            assert!(m.is_closed() && m.is_manifold() && m.genus() == 0, "level {level}");
            assert!(m.face_count() < fine.face_count());
            let c = m.bounds().center();
            assert!((c - Vec3::new(16.0, 15.0, 17.0)).length() < 0.6, "level {level}: centre {c}");
            // Marching cubes cuts corners off a convex shape, more so the fewer voxels span it: the
            // radius is 5.5 voxels at level 1 and 2.75 at level 2.
            let rel = (m.volume() - fine.volume()).abs() / fine.volume();
            let tol = [0.0, 0.05, 0.15][level as usize];
            assert!(rel < tol, "level {level}: volume {} vs {}, relative {rel:e}", m.volume(), fine.volume());
        }
        // The level grid itself covers the same world box at twice the voxel size.
        let l1 = v.lod(1).unwrap();
        assert_eq!((l1.size(), l1.scale(), l1.origin()), (16, 2.0, Vec3::ZERO));
        assert!((l1.volume() * 8.0 - v.volume()).abs() < 16.0 * 16.0 * 16.0 * 0.5 / 255.0 * 8.0 + 1e-9);
        assert!(matches!(v.lod(6), Err(VoxelError::LevelOutOfRange { .. })));
        assert!(matches!(v.to_mesh(-1, DEFAULT_ISO), Err(VoxelError::LevelOutOfRange { .. })));
        assert!(matches!(v.to_mesh(0, f64::NAN), Err(VoxelError::NonFinite { .. })));
    }

    #[test]
    fn a_256_grid_with_hierarchy_and_surface_cache_fits_in_64_mib() {
        // Densities 16 MiB, levels 1–2 in i16 32 MiB, deeper levels 2 MiB, leaving ~14 MiB for the
        // surface cache at 6 bytes per triangle.
        let mut v = Voxels::new(256).unwrap();
        v.fill_sphere(Vec3::splat(128.0), 100.0).unwrap();
        let _ = v.hierarchy();
        let mesh = v.to_mesh(0, DEFAULT_ISO).unwrap();
        assert!(mesh.is_closed() && mesh.is_manifold() && mesh.genus() == 0);
        let mib = v.memory_bytes() as f64 / 1048576.0;
        assert!(mib < 64.0, "{mib:.1} MiB for {} triangles", mesh.face_count());
    }

    #[test]
    fn serial_and_parallel_surfaces_are_identical() {
        // Blocks are meshed and welded independently and vertices numbered by owner block, so the
        // schedule cannot change the output.
        let mut v =
            Voxels::from_mesh(&Mesh::torus(2.0, 0.8, 32, 16).rotate(Vec3::new(1.0, 0.5, 0.2), 40.0), 64).unwrap();
        let mut s = v.clone();
        s.set_parallel(false);
        s.clear_caches();
        for level in [0, 1, 2] {
            assert_eq!(v.to_mesh(level, DEFAULT_ISO).unwrap(), s.to_mesh(level, DEFAULT_ISO).unwrap(), "level {level}");
        }
    }

    #[test]
    fn edits_re_mesh_only_touched_blocks_and_match_a_fresh_mesh() {
        // After a small edit the cached surface must equal one computed from scratch, while only
        // the blocks around the edit were re-meshed.
        let mut v = Voxels::new(64).unwrap();
        v.fill_sphere(Vec3::splat(32.0), 20.0).unwrap();
        for level in [0, 1] {
            v.to_mesh(level, DEFAULT_ISO).unwrap();
        }
        let total = block_count(64).pow(3);
        assert_eq!(v.last_remeshed_blocks(0), Some(total));
        v.fill_box(Vec3::new(50.0, 30.0, 30.0), Vec3::new(56.0, 34.0, 34.0)).unwrap();
        for level in [0i64, 1] {
            let cached = v.to_mesh(level, DEFAULT_ISO).unwrap();
            let remeshed = v.last_remeshed_blocks(level as u32).unwrap();
            assert!(remeshed > 0 && remeshed <= 8, "level {level}: {remeshed} blocks re-meshed");
            let mut fresh = v.clone();
            fresh.clear_caches();
            assert_eq!(cached, fresh.to_mesh(level, DEFAULT_ISO).unwrap(), "level {level}");
        }
        // Nothing changed since: nothing is re-meshed.
        v.to_mesh(0, DEFAULT_ISO).unwrap();
        assert_eq!(v.last_remeshed_blocks(0), Some(0));
    }
}
