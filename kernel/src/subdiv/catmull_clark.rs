//! Catmull–Clark subdivision of a polygon mesh: `Mesh::catmull_clark`.

use crate::mesh::Mesh;

use super::refiner::{Refiner, Scheme};
use super::SubdivError;
use super::SubdivOptions;

impl Mesh {
    /// The mesh after `levels` Catmull–Clark steps (0 returns a copy).
    ///
    /// Any polygons in; after one step every face is a quad (a face of arity n makes n quads).
    /// Crease-tagged edges and boundary edges are infinitely sharp; corner-marked vertices and
    /// vertices with three or more sharp edges stay put. Tags survive: each sharp edge becomes two,
    /// corner marks stay on the vertex, each child face keeps its parent's part (colour, origin).
    /// Vertex ids: the input's vertices keep theirs, then edge points, then face points; the
    /// layout is documented in [`super::refiner`].
    ///
    /// One step of the ±1 cube: 26 vertices, 24 quads; corners at (±5/9, ±5/9, ±5/9), edge
    /// midpoints at (±3/4, ±3/4, 0) and the like, face points at the face centres.
    ///
    /// # Errors
    /// [`SubdivError::TooLarge`] when the result would have more than
    /// [`super::MAX_FACES`] faces (the count is named). The input is never changed.
    ///
    /// See also [`Refiner`] (refine the topology once, positions many times),
    /// [`Mesh::catmull_clark_limit`], [`super::LimitEvaluator`]. Catmull & Clark 1978; sharp rules
    /// of Hoppe et al. 1994 and DeRose et al. 1998 as in OpenSubdiv; seed 000 §2.3.
    pub fn catmull_clark(&self, levels: u32) -> Result<Mesh, SubdivError> {
        self.catmull_clark_with(levels, &self.subdiv_options())
    }

    /// [`Mesh::catmull_clark`] with other options than the mesh's own ([`Mesh::subdiv_options`]):
    /// boundary interpolation, the creasing method and the smooth-triangle weights. The result
    /// carries the options it was made with.
    ///
    /// Semi-sharp creases (an edge sharpness s between 0 and 10) follow DeRose, Kass & Truong
    /// 1998 §3 as OpenSubdiv's `Sdc` implements them: the sharp rules for ⌊s⌋ levels, the sharp
    /// and smooth rules blended by the fractional part in the level where the sharpness runs out,
    /// the smooth rules after; corner sharpness likewise. Sharpness is held as OpenSubdiv holds it
    /// (`f32`, 10 and above infinitely sharp), so results agree with it bit for bit in the weights.
    ///
    /// # Errors
    /// As [`Mesh::catmull_clark`].
    pub fn catmull_clark_with(&self, levels: u32, options: &SubdivOptions) -> Result<Mesh, SubdivError> {
        if levels == 0 {
            return Ok(self.clone());
        }
        let r = Refiner::with_options(self, Scheme::CatmullClark, levels, options)?;
        let p = r.try_refine_positions(self.positions())?;
        let mut m = r.to_mesh(p)?;
        if self.face_part_ids().is_some() {
            m.inherit_parts(self, &r.base_faces()).map_err(|e| SubdivError::Internal(e.to_string()))?;
        }
        Ok(m)
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_meshes::{assert_close, cube_crease_loop, grid, mixed_torus, tetrahedron};
    use super::super::{Refiner, Scheme, SubdivError};
    use crate::math::Vec3;
    use crate::mesh::Mesh;

    /// The edge id (in `Mesh::edges` order) of the edge joining `a` and `b`.
    fn edge_id(m: &Mesh, a: u32, b: u32) -> usize {
        let h = m.find_halfedge(a, b).unwrap();
        m.edges().position(|e| e == m.edge_key(h)).unwrap()
    }

    #[test]
    fn a_set_interrupt_stops_subdivision_with_the_reason() {
        // The current token is checked before every level: a stopped token stops the work and
        // says why, and the same call without it succeeds.
        use crate::limits::{install, CancelToken, LimitError, StopReason};
        use std::sync::atomic::AtomicBool;
        use std::sync::Arc;
        let cube = Mesh::cube(2.0);
        {
            let _g = install(CancelToken::with(Some(Arc::new(AtomicBool::new(true))), None, None));
            let e = cube.catmull_clark(3).unwrap_err();
            assert_eq!(e, SubdivError::Limit(LimitError::Stopped(StopReason::Interrupted)));
            assert_eq!(e.to_string(), "interrupted");
        }
        assert_eq!(cube.catmull_clark(3).unwrap().face_count(), 6 * 64);
    }

    #[test]
    fn cube_one_step_matches_the_rules_exactly() {
        let cube = Mesh::cube(2.0);
        let m = cube.catmull_clark(1).unwrap();
        // V + E + F = 8 + 12 + 6 vertices; each quad makes 4 quads.
        assert_eq!((m.vertex_count(), m.face_count(), m.edge_count()), (26, 24, 48));
        assert!(m.is_closed() && m.is_manifold() && m.is_quad_mesh());
        assert_eq!(m.genus(), 0);
        // Vertex points: n = 3, ((n-2) v + (Σe + Σf)/n)/n with Σe = Σf = v for v = (1,1,1)·s,
        // so v' = (1 + 2/3)/3 v = 5/9 v. Ids 0..8 are kept.
        for v in 0..8 {
            assert_close(m.position(v), cube.position(v) * (5.0 / 9.0), 1e-15);
        }
        // Edge points: (v0 + v1 + f0 + f1)/4; for the edge (1,1,-1)-(1,1,1) that is (3/4, 3/4, 0).
        let (a, b) = (3u32, 7u32); // (1,1,-1) and (1,1,1)
        let e = edge_id(&cube, a, b);
        assert_close(m.position(8 + e as u32), Vec3::new(0.75, 0.75, 0.0), 1e-15);
        for e in 0..12u32 {
            let p = m.position(8 + e);
            // Every edge point has two coordinates ±3/4 and one 0.
            let mut c = [p.x.abs(), p.y.abs(), p.z.abs()];
            c.sort_by(f64::total_cmp);
            assert_eq!(c, [0.0, 0.75, 0.75], "edge point {e}: {p}");
        }
        // Face points at the face centres, in face order.
        for f in 0..6u32 {
            assert_close(m.position(20 + f), cube.face_centroid(f), 1e-15);
        }
        // Child k of face f is [v_k, edge point (v_k, v_k+1), face point, edge point (v_k-1, v_k)].
        let fv: Vec<u32> = cube.face_vertices(0).collect();
        let child: Vec<u32> = m.face_vertices(0).collect();
        assert_eq!(
            child,
            vec![fv[0], 8 + edge_id(&cube, fv[0], fv[1]) as u32, 20, 8 + edge_id(&cube, fv[3], fv[0]) as u32]
        );
    }

    #[test]
    fn all_crease_cube_stays_the_cube_at_every_level() {
        let mut cube = Mesh::cube(2.0);
        cube.crease_all();
        for levels in 1..=3 {
            let m = cube.catmull_clark(levels).unwrap();
            // Every vertex has 3 sharp edges at the corners (fixed), 2 along cube edges (crease rule on
            // a straight line) and none inside faces, where every rule is an affine combination of
            // coplanar points: all vertices stay on the surface and the volume stays 8.
            assert!(m.positions().iter().all(|p| (p.abs().max_element() - 1.0).abs() < 1e-14));
            assert!((m.volume() - 8.0).abs() < 1e-12, "volume {}", m.volume());
            for v in 0..8 {
                assert_eq!(m.position(v), cube.position(v));
            }
            // Each sharp edge becomes two per level: 12 · 2^levels tags.
            assert_eq!(m.crease_count(), 12 << levels);
        }
    }

    #[test]
    fn tetrahedron_triangles_become_quads_with_exact_vertex_points() {
        let t = tetrahedron();
        let m = t.catmull_clark(1).unwrap();
        assert_eq!((m.vertex_count(), m.face_count()), (4 + 6 + 4, 12));
        assert!(m.is_quad_mesh() && m.is_closed());
        // v = (1,1,1): Σe = (-1,-1,-1); Σ of the three face centroids = (3v + 2Σe)/3 = (1,1,1)/3;
        // v' = (v + (Σe + Σf)/3)/3 = (1 - 2/9)/3 = 7/27 per coordinate.
        assert_close(m.position(0), Vec3::splat(7.0 / 27.0), 1e-15);
    }

    #[test]
    fn open_grid_corner_follows_the_crease_rule_unless_marked() {
        // One unit quad: every edge is a boundary, every vertex has 2 sharp edges (Blender and
        // OpenSubdiv "edge only"): corner (0,0) → ((1,0) + 6 (0,0) + (0,1))/8 = (1/8, 1/8).
        let g = grid(1);
        let m = g.catmull_clark(1).unwrap();
        assert_close(m.position(0), Vec3::new(0.125, 0.125, 0.0), 1e-15);
        assert_close(m.position(8), Vec3::new(0.5, 0.5, 0.0), 1e-15); // the face point
        assert_eq!(m.crease_count(), 0); // boundary edges are sharp without tags
        let mut pinned = g.clone();
        pinned.set_corner(0, true);
        let m = pinned.catmull_clark(2).unwrap();
        assert_eq!(m.position(0), Vec3::ZERO);
        assert!(m.is_corner(0) && !m.is_corner(1));
    }

    #[test]
    fn crease_loop_tags_double_per_level_and_topology_is_kept() {
        let c = cube_crease_loop();
        for levels in 1..=3 {
            let m = c.catmull_clark(levels).unwrap();
            assert_eq!(m.crease_count(), 4 << levels);
            assert!(m.is_closed() && m.is_manifold() && m.genus() == 0);
        }
        let t = mixed_torus();
        let m = t.catmull_clark(2).unwrap();
        assert!(m.is_closed() && m.is_manifold() && m.is_quad_mesh());
        assert_eq!(m.genus(), 1);
        // F1 = Σ arities, then ×4: the mixed torus has 45 quads, a hexagon and 2 triangles.
        let corners: usize = (0..t.face_count() as u32).map(|f| t.face_arity(f)).sum();
        assert_eq!(m.face_count(), 4 * corners);
    }

    #[test]
    fn stencils_reproduce_interpolation_and_sum_to_one() {
        let mut t = mixed_torus();
        t.crease_edges(&[[0, 6], [6, 12]]).unwrap();
        t.set_corner(30, true);
        let r = Refiner::new(&t, Scheme::CatmullClark, 3).unwrap();
        let direct = r.refine_positions(t.positions());
        let st = r.composed_stencils();
        assert_eq!(st.rows(), direct.len());
        for (a, b) in st.apply(t.positions()).iter().zip(&direct) {
            assert_close(*a, *b, 1e-13);
        }
        assert!(st.row_sums().iter().all(|s| (s - 1.0).abs() < 1e-13));
        // Positions refined again after moving the control points: same topology, new result.
        let moved: Vec<Vec3> = t.positions().iter().map(|p| *p * 2.0).collect();
        let again = r.refine_positions(&moved);
        for (a, b) in again.iter().zip(&direct) {
            assert_close(*a, *b * 2.0, 1e-13);
        }
    }

    #[test]
    fn huge_level_counts_are_refused_naming_the_size() {
        let cube = Mesh::cube(2.0);
        // 24 quads after one step, ×4 per further step: 24 · 4^11 = 100,663,296 at level 12.
        let e = cube.catmull_clark(12).unwrap_err();
        assert_eq!(e, SubdivError::TooLarge { levels: 12, faces: 24 * 4u64.pow(11), limit: 50_000_000 });
        assert!(e.to_string().contains("100663296"));
        // Absurd counts saturate instead of overflowing.
        assert!(matches!(cube.catmull_clark(u32::MAX), Err(SubdivError::TooLarge { .. })));
        assert_eq!(cube.catmull_clark(0).unwrap(), cube);
    }
}
