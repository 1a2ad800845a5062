//! Limit positions and limit normals of every vertex, keeping vertex ids.
//!
//! Catmull–Clark masks need quads around the vertex; a mesh with other faces is refined once first
//! (vertex points keep their ids, see [`super::refiner`]), and the masks are applied there — the
//! limit of a vertex point is the limit of its parent vertex. Loop masks need triangles.
//!
//! Semi-sharp creases and corners: as OpenSubdiv, the mesh is first refined until every
//! sharpness is either 0 or infinite (⌈s⌉ levels for the largest semi-sharp s; the rules no longer
//! change after that), and the infinitely sharp masks are applied there. OpenSubdiv's
//! `PrimvarRefiner::Limit` at a level where sharpness remains treats it as infinite; refined far
//! enough, both give the exact limit.
//! The masks and the crease, corner and boundary conventions are described in
//! [`super::masks`]; boundary edges are sharp (OpenSubdiv's "edge only", Blender's default).

use std::borrow::Cow;

use crate::math::Vec3;
use crate::mesh::Mesh;

use super::masks::{limit_normal, position_mask, Mask, MaskScheme};
use super::refiner::{Refiner, Scheme};
use super::ring::{mesh_ring, MeshRing};
use super::stencil::{RowBuilder, StencilTable};
use super::BoundaryInterpolation;
use super::SubdivError;

/// The levels to refine before the limit masks apply: until no sharpness is semi-sharp (as
/// OpenSubdiv refines semi-sharp features before it takes limits: ⌈s⌉ levels for the largest
/// semi-sharp value s below 10, which also bounds Chaikin's decay), at least one for a
/// Catmull–Clark mesh with other faces than quads (the masks need quads) or when the boundary
/// mode sharpens corners (the refined mesh carries them as corner marks).
fn limit_levels(mesh: &Mesh, scheme: Scheme) -> u32 {
    let semi = |s: f64| if s > 0.0 && s < 10.0 { s.ceil() as u32 } else { 0 };
    let edges = mesh.edges().map(|h| semi(mesh.edge_sharpness(h))).max().unwrap_or(0);
    let corners = (0..mesh.vertex_count() as u32).map(|v| semi(mesh.corner_sharpness(v))).max().unwrap_or(0);
    let mut levels = edges.max(corners);
    let sharpened_corners = mesh.subdiv_options().boundary == BoundaryInterpolation::EdgeAndCorner;
    if (scheme == Scheme::CatmullClark && !mesh.is_quad_mesh()) || (sharpened_corners && !mesh.is_closed()) {
        levels = levels.max(1);
    }
    levels
}

/// A mesh whose vertices `0..V` have the same limits as the input's and to which the limit masks
/// apply (see [`limit_levels`]), and the stencils that made it (None when that is the input).
fn limit_level(mesh: &Mesh, scheme: Scheme) -> Result<(Cow<'_, Mesh>, Option<StencilTable>), SubdivError> {
    let levels = limit_levels(mesh, scheme);
    if levels == 0 {
        return Ok((Cow::Borrowed(mesh), None));
    }
    let r = Refiner::new(mesh, scheme, levels)?;
    let p = r.try_refine_positions(mesh.positions())?;
    Ok((Cow::Owned(r.to_mesh(p)?), Some(r.composed_stencils())))
}

fn quad_level(mesh: &Mesh) -> Result<(Cow<'_, Mesh>, Option<StencilTable>), SubdivError> {
    limit_level(mesh, Scheme::CatmullClark)
}

fn check_triangles(mesh: &Mesh) -> Result<(), SubdivError> {
    match (0..mesh.face_count() as u32).find(|&f| mesh.face_arity(f) != 3) {
        Some(f) => Err(SubdivError::NotTriangles { face: f as usize, arity: mesh.face_arity(f) }),
        None => Ok(()),
    }
}

/// The ring's points: centre, edge neighbours, face opposites (zero for empty slots).
fn ring_points(mesh: &Mesh, v: u32, ring: &MeshRing) -> (Vec3, Vec<Vec3>, Vec<Vec3>) {
    let p = mesh.positions();
    let e = ring.edges.iter().map(|&w| p[w as usize]).collect();
    let f = ring.opposite.iter().map(|&w| if w == crate::mesh::NONE { Vec3::ZERO } else { p[w as usize] }).collect();
    (p[v as usize], e, f)
}

fn mask_row(b: &mut RowBuilder, v: u32, ring: &MeshRing, m: &Mask) {
    b.add(v, m.c);
    for (i, &w) in m.e.iter().enumerate() {
        if w != 0.0 {
            b.add(ring.edges[i], w);
        }
    }
    for (i, &w) in m.f.iter().enumerate() {
        if w != 0.0 {
            b.add(ring.opposite[i], w);
        }
    }
    b.end_row();
}

/// Limit stencils of the first `count` vertices of `mesh` (rows over its vertices).
fn limit_rows(mesh: &Mesh, count: usize, scheme: MaskScheme) -> StencilTable {
    let mut b = RowBuilder::new(mesh.vertex_count(), count, count * 9);
    for v in 0..count as u32 {
        let ring = mesh_ring(mesh, v);
        mask_row(&mut b, v, &ring, &position_mask(scheme, &ring.topo));
    }
    b.finish()
}

/// The Catmull–Clark limit stencils: row `v` gives the limit position of vertex `v` as weights of
/// the mesh's control vertices (#V rows over #V sources).
///
/// # Errors
/// [`SubdivError::TooLarge`] only for meshes too large to refine once.
///
/// See also [`Mesh::catmull_clark_limit`].
pub fn catmull_clark_limit_stencils(mesh: &Mesh) -> Result<StencilTable, SubdivError> {
    let (q, st) = quad_level(mesh)?;
    let rows = limit_rows(&q, mesh.vertex_count(), MaskScheme::CatmullClark);
    Ok(match st {
        Some(st) => st.then(&rows),
        None => rows,
    })
}

/// The Loop limit stencils: row `v` gives the limit position of vertex `v` as weights of the
/// control vertices. Seed 002 (§5) constrains the limit surface with these.
///
/// # Errors
/// [`SubdivError::NotTriangles`] for a face that is not a triangle.
///
/// See also [`Mesh::loop_limit`].
pub fn loop_limit_stencils(mesh: &Mesh) -> Result<StencilTable, SubdivError> {
    check_triangles(mesh)?;
    let (q, st) = limit_level(mesh, Scheme::Loop)?;
    let rows = limit_rows(&q, mesh.vertex_count(), MaskScheme::Loop);
    Ok(match st {
        Some(st) => st.then(&rows),
        None => rows,
    })
}

/// The limit position of each of the first `count` vertices, polling the current cancellation
/// token every [`crate::limits::POLL_EVERY`] vertices.
fn limit_positions(mesh: &Mesh, count: usize, scheme: MaskScheme) -> Result<Vec<Vec3>, SubdivError> {
    (0..count as u32)
        .map(|v| {
            crate::limits::poll_at(v as usize)?;
            let ring = mesh_ring(mesh, v);
            let (c, e, f) = ring_points(mesh, v, &ring);
            Ok(position_mask(scheme, &ring.topo).apply(c, &e, &f))
        })
        .collect()
}

fn limit_normals(mesh: &Mesh, count: usize, scheme: MaskScheme) -> Result<Vec<Vec3>, SubdivError> {
    (0..count as u32)
        .map(|v| {
            crate::limits::poll_at(v as usize)?;
            let ring = mesh_ring(mesh, v);
            if ring.edges.is_empty() {
                return Ok(Vec3::ZERO);
            }
            let (c, e, f) = ring_points(mesh, v, &ring);
            limit_normal(scheme, &ring.topo, c, &e, &f)
                .ok_or_else(|| SubdivError::DegenerateNormal { at: format!("vertex {v}") })
        })
        .collect()
}

impl Mesh {
    /// A copy with every vertex moved to its Catmull–Clark limit position, keeping all ids, crease
    /// tags and corner marks.
    ///
    /// Smooth vertices: (n² v + 4 Σ e_i + Σ f_i) / (n (n + 5)) over the quads around them (after one
    /// refinement step when the mesh has other faces); crease and boundary vertices:
    /// (e_a + 4 v + e_b) / 6; corners stay. The ±1 cube's corners go to (±½, ±½, ±½).
    ///
    /// # Errors
    /// [`SubdivError::TooLarge`] only for meshes too large to refine once.
    ///
    /// See also [`Mesh::catmull_clark_limit_normals`], [`catmull_clark_limit_stencils`],
    /// [`super::LimitEvaluator`] (the limit anywhere on the surface). Halstead, Kass & DeRose 1993
    /// §4 (the eigenanalysis behind the mask); OpenSubdiv `Sdc::Scheme<CATMARK>` limit masks.
    pub fn catmull_clark_limit(&self) -> Result<Mesh, SubdivError> {
        let (q, _) = quad_level(self)?;
        let p = limit_positions(&q, self.vertex_count(), MaskScheme::CatmullClark)?;
        let mut out = self.clone();
        out.set_positions(p).map_err(|e| SubdivError::Internal(e.to_string()))?;
        Ok(out)
    }

    /// The unit limit normal of every vertex of the Catmull–Clark surface (#V; zero for isolated
    /// vertices). At crease and corner vertices, the normalised sum of the sector normals (see
    /// [`super::masks`]).
    ///
    /// # Errors
    /// [`SubdivError::DegenerateNormal`] naming the first vertex whose limit tangents are parallel
    /// or zero (zero-area faces around it).
    pub fn catmull_clark_limit_normals(&self) -> Result<Vec<Vec3>, SubdivError> {
        let (q, _) = quad_level(self)?;
        limit_normals(&q, self.vertex_count(), MaskScheme::CatmullClark)
    }

    /// A copy with every vertex moved to its Loop limit position (Loop's original weights),
    /// keeping all ids, crease tags and corner marks.
    ///
    /// Smooth vertices: (1 − n w) v + w Σ e_i with w = 1 / (n + 3 / (8β)); crease and boundary
    /// vertices: (e_a + 4 v + e_b) / 6; corners stay.
    ///
    /// # Errors
    /// [`SubdivError::NotTriangles`] for a face that is not a triangle.
    ///
    /// See also [`Mesh::loop_limit_normals`], [`loop_limit_stencils`]. Loop 1987 §3.3; seed 002 §5.
    pub fn loop_limit(&self) -> Result<Mesh, SubdivError> {
        check_triangles(self)?;
        let (q, _) = limit_level(self, Scheme::Loop)?;
        let p = limit_positions(&q, self.vertex_count(), MaskScheme::Loop)?;
        let mut out = self.clone();
        out.set_positions(p).map_err(|e| SubdivError::Internal(e.to_string()))?;
        Ok(out)
    }

    /// The unit limit normal of every vertex of the Loop surface (#V; zero for isolated vertices).
    ///
    /// # Errors
    /// [`SubdivError::NotTriangles`]; [`SubdivError::DegenerateNormal`] naming the first vertex
    /// whose limit tangents are parallel or zero.
    pub fn loop_limit_normals(&self) -> Result<Vec<Vec3>, SubdivError> {
        check_triangles(self)?;
        let (q, _) = limit_level(self, Scheme::Loop)?;
        limit_normals(&q, self.vertex_count(), MaskScheme::Loop)
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_meshes::{assert_close, cube_crease_loop, grid, mixed_torus, tetrahedron};
    use super::super::SubdivError;
    use super::*;

    #[test]
    fn a_stop_lands_inside_the_limit_of_a_large_mesh() {
        // 98,306 vertices, all of quads: no refinement and no per-level check before the masks,
        // so only the poll inside the loop over vertices can stop it.
        use crate::limits::{install, CancelToken, LimitError, StopReason};
        use std::sync::atomic::AtomicBool;
        use std::sync::Arc;
        let m = Mesh::cube(2.0).catmull_clark(7).unwrap();
        assert!(m.vertex_count() > crate::limits::POLL_EVERY);
        {
            let _g = install(CancelToken::with(Some(Arc::new(AtomicBool::new(true))), None, None));
            let stopped = SubdivError::Limit(LimitError::Stopped(StopReason::Interrupted));
            assert_eq!(m.catmull_clark_limit().unwrap_err(), stopped);
            assert_eq!(m.catmull_clark_limit_normals().unwrap_err(), stopped);
            assert_eq!(m.triangulate().unwrap_err().to_string(), "interrupted");
        }
        assert_eq!(m.catmull_clark_limit().unwrap().vertex_count(), m.vertex_count());
    }

    #[test]
    fn cube_limits_match_the_closed_forms() {
        let cube = Mesh::cube(2.0);
        // Corner, n = 3: (9 v + 4 Σe + Σf)/24 with Σe = v, Σf = -v (opposite corners): 12/24 v.
        let l = cube.catmull_clark_limit().unwrap();
        for v in 0..8 {
            assert_close(l.position(v), cube.position(v) * 0.5, 1e-15);
        }
        // One step, then the limit of the edge point of (1,1,-1)-(1,1,1) and of the +z face point:
        // (16 c + 4 Σe + Σf)/36 on level 1 gives 395/648 and 68/81 (OpenSubdiv via bpy agrees).
        let m = cube.catmull_clark(1).unwrap();
        let l = m.catmull_clark_limit().unwrap();
        let em = (8..20).find(|&v| (m.position(v) - Vec3::new(0.75, 0.75, 0.0)).length() < 1e-12).unwrap();
        assert_close(l.position(em), Vec3::new(395.0 / 648.0, 395.0 / 648.0, 0.0), 1e-15);
        assert_close(l.position(20 + 5), Vec3::new(0.0, 0.0, 68.0 / 81.0), 1e-15);
        // Limit normals: symmetry makes the corner normal (1,1,1)/√3 and the face centre +z.
        let n = m.catmull_clark_limit_normals().unwrap();
        assert_close(n[7], Vec3::splat(1.0 / 3f64.sqrt()), 1e-14);
        assert_close(n[25], Vec3::Z, 1e-14);
    }

    #[test]
    fn limit_is_the_same_from_every_level() {
        // The limit mask is the left eigenvector of the refinement rules: a vertex and its vertex
        // points at every level share one limit. Checked on smooth (valence 3, 4, 5, 6 after one
        // step of the hexagon), crease, dart, corner and boundary vertices.
        let mut t = mixed_torus();
        t.crease_edges(&[[0, 6], [6, 12], [12, 18]]).unwrap(); // a crease with a dart at each end
        t.crease_edges(&[[20, 26], [20, 21], [20, 14]]).unwrap(); // a 3-crease corner at 20
        t.set_corner(40, true);
        let mut g = grid(3);
        g.crease_edges(&[[5, 6]]).unwrap();
        for mesh in [t, g, cube_crease_loop(), tetrahedron()] {
            let l0 = mesh.catmull_clark_limit().unwrap();
            let l3 = mesh.catmull_clark(3).unwrap().catmull_clark_limit().unwrap();
            for v in 0..mesh.vertex_count() as u32 {
                assert_close(l3.position(v), l0.position(v), 1e-12);
            }
        }
        let mut s = Mesh::icosphere(1.0, 1).translate(Vec3::X);
        s.crease_edges(&[[0, 11], [11, 5]]).unwrap_or(());
        let mut gt = grid(3).triangulate().unwrap();
        gt.set_corner(0, true);
        for mesh in [s, gt, tetrahedron()] {
            let l0 = mesh.loop_limit().unwrap();
            let l3 = mesh.loop_subdivide(3).unwrap().loop_limit().unwrap();
            for v in 0..mesh.vertex_count() as u32 {
                assert_close(l3.position(v), l0.position(v), 1e-12);
            }
        }
    }

    #[test]
    fn limit_stencils_give_the_limit_positions() {
        let t = mixed_torus();
        let st = catmull_clark_limit_stencils(&t).unwrap();
        let l = t.catmull_clark_limit().unwrap();
        for (a, b) in st.apply(t.positions()).iter().zip(l.positions()) {
            assert_close(*a, *b, 1e-13);
        }
        let s = Mesh::icosphere(2.0, 2);
        let st = loop_limit_stencils(&s).unwrap();
        for (a, b) in st.apply(s.positions()).iter().zip(s.loop_limit().unwrap().positions()) {
            assert_close(*a, *b, 1e-14);
        }
    }

    #[test]
    fn normals_of_symmetric_and_flat_shapes() {
        // Icosphere vertices: by symmetry the Loop limit normal is radial.
        let s = Mesh::icosphere(1.0, 1);
        for (v, n) in s.loop_limit_normals().unwrap().iter().enumerate() {
            assert_close(*n, s.position(v as u32).normalize(), 1e-12);
        }
        // A flat open grid: +z everywhere, boundary (one sector) and corner vertices included.
        for n in grid(3).catmull_clark_limit_normals().unwrap() {
            assert_close(n, Vec3::Z, 1e-14);
        }
        for n in grid(3).triangulate().unwrap().loop_limit_normals().unwrap() {
            assert_close(n, Vec3::Z, 1e-14);
        }
        // The all-crease cube: at a corner the three one-face sectors have normals ±x, ±y, ±z.
        let mut c = Mesh::cube(2.0);
        c.crease_all();
        let n = c.catmull_clark_limit_normals().unwrap();
        assert_close(n[7], Vec3::splat(1.0 / 3f64.sqrt()), 1e-14);
    }

    #[test]
    fn zero_area_faces_make_the_normal_undefined() {
        // A quad squashed onto a line: every tangent is parallel to x.
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::new(2.0, 0.0, 0.0), Vec3::new(3.0, 0.0, 0.0)];
        let m = Mesh::from_polygons(p, &[[0, 1, 2, 3]]).unwrap();
        let e = m.catmull_clark_limit_normals().unwrap_err();
        assert!(matches!(e, SubdivError::DegenerateNormal { .. }), "{e}");
        // Positions are still defined.
        assert!(m.catmull_clark_limit().is_ok());
    }
}
