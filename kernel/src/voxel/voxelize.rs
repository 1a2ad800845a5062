//! Voxelizing a closed mesh with partial coverage, so that block models, polar meshes or CSG
//! results can become tools or workpieces.
//!
//! Method: rays along +x through a 4 × 4 grid of (y, z) sub-samples per voxel row cross the
//! mesh's triangles (faces fanned from their first corner); a crossing counts +1 where the surface
//! faces −x (entering) and −1 where it faces +x, and the spans of non-zero winding are intersected
//! exactly with each voxel's x range. Coverage = the mean covered length over the row's 16 rays.
//!
//! Robustness: whether a ray passes a triangle is decided edge by edge in the (y, z) plane with
//! each edge evaluated in one canonical direction (lexicographically smaller end first) and a ray
//! exactly on an edge counted as lying to its left. Both triangles sharing an edge therefore agree
//! on which side a ray passes, so a ray through an edge or a vertex is counted exactly once
//! (the rule is the sign of a single infinitesimally shifted ray).

use super::fill::{density, overlap, voxel_range};
use super::{VoxelError, Voxels};
use crate::math::Vec3;
use crate::mesh::Mesh;

/// Ray sub-samples per voxel side in y and in z.
const RAYS: usize = 4;

/// Whether `q` lies to the left of the directed edge a → b in the (y, z) plane, ties broken by
/// the canonical direction of the edge (see the module documentation).
#[inline]
fn left_of(a: [f64; 2], b: [f64; 2], q: [f64; 2]) -> bool {
    let forward = (a[0], a[1]) < (b[0], b[1]);
    let (lo, hi) = if forward { (a, b) } else { (b, a) };
    let o = (hi[0] - lo[0]) * (q[1] - lo[1]) - (hi[1] - lo[1]) * (q[0] - lo[0]);
    (o >= 0.0) == forward
}

fn orient(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// The ray at `q` = (y, z) against triangle `t`: `Some((x, winding change))` if it crosses.
#[inline]
fn crossing(t: &[Vec3; 3], q: [f64; 2]) -> Option<(f64, i32)> {
    let p = [[t[0].y, t[0].z], [t[1].y, t[1].z], [t[2].y, t[2].z]];
    let s0 = left_of(p[0], p[1], q);
    if left_of(p[1], p[2], q) != s0 || left_of(p[2], p[0], q) != s0 {
        return None;
    }
    let total = orient(p[0], p[1], p[2]);
    let x = if total == 0.0 {
        (t[0].x + t[1].x + t[2].x) / 3.0
    } else {
        let la = orient(p[1], p[2], q) / total;
        let lb = orient(p[2], p[0], q) / total;
        let x = la * t[0].x + lb * t[1].x + (1.0 - la - lb) * t[2].x;
        x.clamp(t[0].x.min(t[1].x).min(t[2].x), t[0].x.max(t[1].x).max(t[2].x))
    };
    // Counter-clockwise in (y, z) means the normal has +x: the ray leaves the solid.
    Some((x, if s0 { -1 } else { 1 }))
}

impl Voxels {
    /// A new n³ grid holding `mesh` with partial coverage: the mesh's bounds plus one voxel of
    /// margin on every side map into the grid (centred, the longest side spanning n − 2 voxels), and
    /// the grid keeps that mapping so [`Voxels::to_mesh`] returns the mesh's own coordinates.
    ///
    /// # Errors
    /// [`VoxelError::NotPowerOfTwo`] / [`VoxelError::TooLarge`] for a bad n,
    /// [`VoxelError::InvalidArgument`] for n < 4 (no room inside the margin),
    /// [`VoxelError::BadMesh`] for a mesh that is empty, flat (zero extent) or not closed.
    ///
    /// See also [`Voxels::fill_mesh`].
    pub fn from_mesh(mesh: &Mesh, n: usize) -> Result<Voxels, VoxelError> {
        let n = Voxels::check_size(i64::try_from(n).unwrap_or(i64::MAX))?;
        if n < 4 {
            return Err(VoxelError::InvalidArgument {
                what: "voxelize grid size",
                reason: format!("{n} leaves no room inside the one-voxel margin (at least 4)"),
            });
        }
        check_mesh(mesh)?;
        let b = mesh.bounds();
        let extent = b.size().max_element();
        if extent <= 0.0 || !extent.is_finite() {
            return Err(VoxelError::BadMesh { reason: format!("its bounds have extent {extent}") });
        }
        let scale = extent / (n - 2) as f64;
        let origin = b.center() - Vec3::splat(scale * n as f64 / 2.0);
        let mut v = Voxels::with_map(n, origin, scale)?;
        v.fill_mesh(mesh)?;
        Ok(v)
    }

    /// Fills the solid bounded by the closed `mesh` (world coordinates) with partial coverage: each
    /// voxel's density becomes the larger of its density and 255 × the fraction of it inside
    /// (non-zero winding, so inverted or overlapping shells still fill). Parts outside the grid are
    /// ignored.
    ///
    /// # Errors
    /// [`VoxelError::BadMesh`] for a mesh with no faces or with boundary edges;
    /// [`VoxelError::Limit`] when the current cancellation token stops the fill or its undo copy
    /// passes the memory budget (see [`Voxels::edit_slices`]). The grid is unchanged on any error.
    pub fn fill_mesh(&mut self, mesh: &Mesh) -> Result<(), VoxelError> {
        check_mesh(mesh)?;
        let n = self.n;
        let mut tris: Vec<[Vec3; 3]> = Vec::with_capacity(mesh.face_count() * 2);
        for f in 0..mesh.face_count() as u32 {
            crate::limits::poll_at(f as usize)?;
            let vs: Vec<Vec3> = mesh.face_vertices(f).map(|v| self.to_grid(mesh.position(v))).collect();
            for i in 1..vs.len() - 1 {
                tris.push([vs[0], vs[i], vs[i + 1]]);
            }
        }
        let lo = tris.iter().flatten().fold(Vec3::INFINITY, |a, &p| a.min(p));
        let hi = tris.iter().flatten().fold(Vec3::NEG_INFINITY, |a, &p| a.max(p));
        let (x0, x1) = voxel_range(lo.x, hi.x, n);
        let (y0, y1) = voxel_range(lo.y, hi.y, n);
        let (z0, z1) = voxel_range(lo.z, hi.z, n);
        if x0 >= x1 || y0 >= y1 || z0 >= z1 {
            return Ok(());
        }
        // Bin triangles by the voxel rows (y, z) their (y, z) bounds touch (CSR).
        let (ny, nz) = (y1 - y0, z1 - z0);
        let rows_of = |t: &[Vec3; 3]| -> Option<((usize, usize), (usize, usize))> {
            let (a, b) = (t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2]));
            let (ya, yb) = voxel_range(a.y, b.y + 1e-9, n);
            let (za, zb) = voxel_range(a.z, b.z + 1e-9, n);
            let (ya, yb, za, zb) = (ya.max(y0), yb.min(y1), za.max(z0), zb.min(z1));
            (ya < yb && za < zb).then_some(((ya, yb), (za, zb)))
        };
        let mut start = vec![0u32; ny * nz + 1];
        for (ti, t) in tris.iter().enumerate() {
            crate::limits::poll_at(ti)?;
            if let Some(((ya, yb), (za, zb))) = rows_of(t) {
                for z in za..zb {
                    for y in ya..yb {
                        start[(z - z0) * ny + (y - y0) + 1] += 1;
                    }
                }
            }
        }
        for i in 0..ny * nz {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut list = vec![0u32; start[ny * nz] as usize];
        for (ti, t) in tris.iter().enumerate() {
            crate::limits::poll_at(ti)?;
            if let Some(((ya, yb), (za, zb))) = rows_of(t) {
                for z in za..zb {
                    for y in ya..yb {
                        let r = (z - z0) * ny + (y - y0);
                        list[fill[r] as usize] = ti as u32;
                        fill[r] += 1;
                    }
                }
            }
        }
        let tris = &tris;
        self.edit_slices([x0, y0, z0], [x1, y1, z1], |z, slice| {
            let mut cover = vec![0.0f64; n];
            let mut hits: Vec<(f64, i32)> = Vec::new();
            for y in y0..y1 {
                let r = (z - z0) * ny + (y - y0);
                let bin = &list[start[r] as usize..start[r + 1] as usize];
                if bin.is_empty() {
                    continue;
                }
                cover.iter_mut().for_each(|c| *c = 0.0);
                for b in 0..RAYS {
                    for a in 0..RAYS {
                        let q = [y as f64 + (a as f64 + 0.5) / RAYS as f64, z as f64 + (b as f64 + 0.5) / RAYS as f64];
                        hits.clear();
                        hits.extend(bin.iter().filter_map(|&ti| crossing(&tris[ti as usize], q)));
                        hits.sort_by(|p, q| p.0.total_cmp(&q.0).then(p.1.cmp(&q.1)));
                        let mut winding = 0;
                        let mut from = f64::NEG_INFINITY;
                        for &(x, dw) in &hits {
                            if winding != 0 {
                                let (xa, xb) = voxel_range(from, x, n);
                                for (i, c) in cover.iter_mut().enumerate().take(xb).skip(xa) {
                                    *c += overlap(from, x, i);
                                }
                            }
                            winding += dw;
                            from = x;
                        }
                    }
                }
                let row = &mut slice[y * n..y * n + n];
                for (v, &c) in row.iter_mut().zip(&cover) {
                    *v = (*v).max(density(c / (RAYS * RAYS) as f64));
                }
            }
        })?;
        Ok(())
    }
}

fn check_mesh(mesh: &Mesh) -> Result<(), VoxelError> {
    if mesh.face_count() == 0 {
        return Err(VoxelError::BadMesh { reason: "it has no faces".into() });
    }
    if !mesh.is_closed() {
        return Err(VoxelError::BadMesh {
            reason: format!("it is not closed ({} boundary loops)", mesh.boundary_loops().len()),
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn an_integer_aligned_box_voxelizes_exactly() {
        // Box faces on voxel boundaries: every voxel is wholly in or out, and rays that run exactly
        // along the box's faces and edges are counted once by the tie rule.
        let mut v = Voxels::new(16).unwrap();
        v.fill_mesh(&Mesh::cuboid(Vec3::new(2.0, 3.0, 4.0), Vec3::new(9.0, 8.0, 12.0))).unwrap();
        let mut w = Voxels::new(16).unwrap();
        w.fill_box(Vec3::new(2.0, 3.0, 4.0), Vec3::new(9.0, 8.0, 12.0)).unwrap();
        assert_eq!(v, w);
        assert_eq!(v.volume(), 7.0 * 5.0 * 8.0);
    }

    #[test]
    fn from_mesh_maps_bounds_with_a_one_voxel_margin() {
        // A cube of side 3 in a 32³ grid: 30 voxels span 3 units, centred, so the outer layer of
        // voxels is empty and the volume in world units is 27.
        let v = Voxels::from_mesh(&Mesh::cube(3.0), 32).unwrap();
        assert_eq!(v.scale(), 0.1);
        assert!((v.origin() - Vec3::splat(-1.6)).length() < 1e-12);
        for i in 0..32 {
            assert_eq!(v.get(0, i, i).unwrap(), 0);
            assert_eq!(v.get(31, i, 5).unwrap(), 0);
        }
        assert!((v.world_volume() - 27.0).abs() < 1e-9, "{}", v.world_volume());
    }

    #[test]
    fn icosphere_coverage_matches_its_volume_and_the_analytic_fill() {
        // The voxel volume equals the polyhedron's volume up to coverage quantisation, and is
        // close to the analytic sphere filled directly.
        let mesh = Mesh::icosphere(10.0, 4).translate(Vec3::splat(16.0));
        let mut v = Voxels::new(32).unwrap();
        v.fill_mesh(&mesh).unwrap();
        let rel = (v.volume() - mesh.volume()).abs() / mesh.volume();
        assert!(rel < 2e-3, "voxel volume {} vs mesh {} (relative {rel:e})", v.volume(), mesh.volume());
        let mut s = Voxels::new(32).unwrap();
        s.fill_sphere(Vec3::splat(16.0), 10.0).unwrap();
        let exact = 4.0 / 3.0 * PI * 1000.0;
        assert!((s.volume() - exact).abs() / exact < 2e-3);
    }

    #[test]
    fn parallel_and_serial_voxelization_agree() {
        let mesh = Mesh::torus(1.0, 0.4, 40, 20).rotate(Vec3::new(1.0, 2.0, 0.5), 33.0);
        let a = Voxels::from_mesh(&mesh, 32).unwrap();
        let mut b = Voxels::with_map(32, a.origin(), a.scale()).unwrap();
        b.set_parallel(false);
        b.fill_mesh(&mesh).unwrap();
        assert_eq!(a, b);
    }

    #[test]
    fn open_empty_or_flat_meshes_are_refused() {
        let open = Mesh::from_polygons(vec![Vec3::ZERO, Vec3::X, Vec3::Y], &[[0u32, 1, 2]]).unwrap();
        let mut v = Voxels::new(8).unwrap();
        assert!(matches!(v.fill_mesh(&open), Err(VoxelError::BadMesh { .. })));
        assert!(matches!(v.fill_mesh(&Mesh::default()), Err(VoxelError::BadMesh { .. })));
        assert!(matches!(Voxels::from_mesh(&Mesh::cube(1.0), 2), Err(VoxelError::InvalidArgument { .. })));
        assert!(matches!(Voxels::from_mesh(&Mesh::cube(1.0), 100), Err(VoxelError::NotPowerOfTwo { .. })));
        assert!(matches!(Voxels::from_mesh(&Mesh::cube(1.0), 4096), Err(VoxelError::TooLarge { .. })));
        assert!(matches!(Voxels::from_mesh(&Mesh::cube(0.0), 8), Err(VoxelError::BadMesh { .. })));
        assert_eq!(v.volume(), 0.0);
    }
}
