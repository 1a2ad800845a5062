//! Levels of detail of a grid and their surfaces (Heurtebise & Thon §2.2–2.3): [`Voxels::lod`]
//! extracts a coarser grid from the Haar hierarchy, and [`Voxels::to_mesh`] meshes any level
//! through that level's surface cache (`lod_cache`), re-meshing only the blocks an edit touched.

use super::grid::next_revision;
use super::lod_cache::SurfaceCache;
use super::marching_cubes::{check_iso, Surface};
use super::{VoxelError, Voxels};
use crate::mesh::Mesh;

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

    /// The smooth marching-cubes surface of level `level` at iso level `iso` (use
    /// [`DEFAULT_ISO`](super::DEFAULT_ISO)): [`Voxels::to_mesh_with`] with [`Surface::Smooth`].
    ///
    /// # Errors
    /// As [`Voxels::to_mesh_with`].
    pub fn to_mesh(&mut self, level: i64, iso: f64) -> Result<Mesh, VoxelError> {
        self.to_mesh_with(level, iso, Surface::Smooth)
    }

    /// The marching-cubes surface of level `level` at iso level `iso` (use
    /// [`DEFAULT_ISO`](super::DEFAULT_ISO)) in world coordinates, of the smoothed densities
    /// ([`Surface::Smooth`]) or the densities themselves ([`Surface::Raw`]): closed and manifold
    /// (the grid is capped at its border), faces outward.
    ///
    /// The surface of each level is cached block by block; after an edit only the blocks it
    /// touched (and, for the smooth surface, those within the filter's reach of it) are extracted
    /// again from the hierarchy and re-meshed. A different iso level or surface rebuilds that
    /// level's cache. Tells a listener ([`crate::limits::listen`]) the blocks re-meshed.
    ///
    /// # Errors
    /// [`VoxelError::LevelOutOfRange`] outside 0…log₂ n; [`VoxelError::NonFinite`] or
    /// [`VoxelError::InvalidArgument`] for an iso level outside [0, 255).
    ///
    /// See also [`marching_cubes`](super::marching_cubes); Heurtebise & Thon §2.3.
    pub fn to_mesh_with(&mut self, level: i64, iso: f64, surface: Surface) -> Result<Mesh, VoxelError> {
        let level = self.check_level(level)?;
        check_iso(iso)?;
        self.refresh_surface(level, iso, surface)?;
        let cache = self.surfaces[level as usize].as_ref().expect("refreshed just above");
        let (origin, scale) = (self.origin, self.scale * f64::from(1u32 << level));
        cache.to_mesh(level, &self.data, |p| origin + p * scale, self.parallel)
    }

    /// The number of blocks the last [`Voxels::to_mesh`] of `level` re-meshed (0 when nothing
    /// changed), or `None` when that level has no cache.
    #[must_use]
    pub fn last_remeshed_blocks(&self, level: u32) -> Option<usize> {
        self.surfaces.get(level as usize)?.as_ref().map(SurfaceCache::last_remeshed)
    }

    /// Brings the cache of `level` up to date: pulls the changed box into the level's image and
    /// re-meshes the dirty blocks.
    fn refresh_surface(&mut self, level: u32, iso: f64, surface: Surface) -> Result<(), VoxelError> {
        if level > 0 && self.hierarchy.is_none() {
            let _ = self.hierarchy();
        }
        if self.surfaces.len() <= level as usize {
            self.surfaces.resize(level as usize + 1, None);
        }
        let n = self.n;
        let parallel = self.parallel;
        let slot = &mut self.surfaces[level as usize];
        if slot.as_ref().is_none_or(|c| !c.is_for(iso, surface)) {
            *slot = Some(SurfaceCache::new(level, iso, surface, n));
        }
        let cache = slot.as_mut().expect("set just above");
        cache.refresh(level, &self.data, self.hierarchy.as_ref(), parallel)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;
    use crate::voxel::marching_cubes::block_count;
    use crate::voxel::DEFAULT_ISO;
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
        // Partial coverage puts the raw 127.5 iso-surface within a fraction of a voxel of the
        // sphere, so the enclosed volume is 4/3 π r³ to within about 1%. The smooth surface of a
        // ball of radius r voxels loses about 1.8/r² of the volume (smooth_field's doc: the
        // separable filter moves oblique surfaces inward: on average 0.45/r voxel), 1.8 % here.
        let mut v = Voxels::new(32).unwrap();
        let r = 10.0;
        v.fill_sphere(Vec3::splat(16.0), r).unwrap();
        let exact = 4.0 / 3.0 * PI * r * r * r;
        for (surface, expected, tol) in
            [(Surface::Raw, exact, 0.01), (Surface::Smooth, exact * (1.0 - 1.76 / (r * r)), 0.003)]
        {
            let m = v.to_mesh_with(0, DEFAULT_ISO, surface).unwrap();
            assert!(m.is_closed() && m.is_manifold());
            assert_eq!((m.genus(), m.component_count()), (0, 1));
            let rel = (m.volume() - expected).abs() / exact;
            assert!(rel < tol, "{surface:?}: volume {} vs {expected}: relative {rel:e}", m.volume());
        }
    }

    #[test]
    fn torus_voxelized_and_meshed_has_genus_one() {
        let mut v = Voxels::from_mesh(&Mesh::torus(2.0, 0.7, 48, 24), 32).unwrap();
        // The tube is 3.9 voxels thick: the smooth surface rounds it inward by about 0.1 voxel.
        for (surface, tol) in [(Surface::Raw, 0.03), (Surface::Smooth, 0.06)] {
            let m = v.to_mesh_with(0, DEFAULT_ISO, surface).unwrap();
            assert!(m.is_closed() && m.is_manifold());
            assert_eq!((m.genus(), m.component_count()), (1, 1));
            // In the torus's own coordinates: volume 2π² R r².
            let exact = 2.0 * PI * PI * 2.0 * 0.49;
            let rel = (m.volume() - exact).abs() / exact;
            assert!(rel < tol, "{surface:?}: volume {} vs {exact}: relative {rel:e}", m.volume());
        }
    }

    #[test]
    fn lower_levels_are_coarser_closed_surfaces_in_the_same_place() {
        let mut v = Voxels::new(32).unwrap();
        v.fill_sphere(Vec3::new(16.0, 15.0, 17.0), 11.0).unwrap();
        // The raw surface: the smooth one rounds a ball of 2.75 voxels (level 2) much further.
        let fine = v.to_mesh_with(0, DEFAULT_ISO, Surface::Raw).unwrap();
        for level in 1..=2 {
            let m = v.to_mesh_with(level, DEFAULT_ISO, Surface::Raw).unwrap();
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
