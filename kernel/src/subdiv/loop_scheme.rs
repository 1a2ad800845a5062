//! Loop subdivision of a triangle mesh: `Mesh::loop_subdivide`.

use crate::mesh::Mesh;

use super::refiner::{Refiner, Scheme};
use super::SubdivError;
use super::SubdivOptions;

impl Mesh {
    /// The mesh after `levels` Loop steps with Loop's original weights (0 returns a copy).
    ///
    /// Smooth vertex: (1 − nβ) v + β Σ e_i with β = (5/8 − (3/8 + ¼ cos 2π/n)²) / n; smooth edge
    /// point: 3/8 of each end plus 1/8 of each opposite vertex. Crease-tagged and boundary edges are
    /// sharp: edge points at midpoints, crease vertices (e_a + 6 v + e_b) / 8, corners stay. Tags
    /// survive as in [`Mesh::catmull_clark`]. Vertex ids: the input's, then one edge point per edge;
    /// see [`super::refiner`] for the face order.
    ///
    /// # Errors
    /// [`SubdivError::NotTriangles`] naming the first face that is not a triangle;
    /// [`SubdivError::TooLarge`] beyond [`super::MAX_FACES`] faces. The input is never changed.
    ///
    /// See also [`Mesh::loop_limit`], [`super::Refiner`]. Loop 1987 (§3); seed 002 §2.2 (which
    /// uses these original weights; libigl and open3d use Warren's 3/(8n) instead).
    pub fn loop_subdivide(&self, levels: u32) -> Result<Mesh, SubdivError> {
        self.loop_subdivide_with(levels, &self.subdiv_options())
    }

    /// [`Mesh::loop_subdivide`] with OpenSubdiv's options (boundary interpolation and creasing
    /// method; the triangle option is Catmull–Clark's only). Semi-sharp creases and corners as in
    /// [`Mesh::catmull_clark_with`].
    ///
    /// # Errors
    /// As [`Mesh::loop_subdivide`].
    pub fn loop_subdivide_with(&self, levels: u32, options: &SubdivOptions) -> Result<Mesh, SubdivError> {
        let r = Refiner::with_options(self, Scheme::Loop, levels, options)?;
        if levels == 0 {
            return Ok(self.clone());
        }
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
    use super::super::test_meshes::{assert_close, grid, tetrahedron};
    use super::super::{loop_beta, Refiner, Scheme, SubdivError};
    use crate::math::Vec3;
    use crate::mesh::Mesh;

    #[test]
    fn loop_beta_is_loops_original_weight() {
        // Valence 3: (5/8 - (3/8 - 1/8)^2)/3 = (9/16)/3 = 3/16; valence 6: (5/8 - 1/4)/6 = 1/16.
        // Both agree with Warren's 3/(8n) only at these two valences.
        assert!((loop_beta(3) - 3.0 / 16.0).abs() < 1e-16);
        assert!((loop_beta(6) - 1.0 / 16.0).abs() < 1e-16);
        let warren5 = 3.0 / 40.0;
        assert!((loop_beta(5) - warren5).abs() > 1e-3, "β5 {}", loop_beta(5));
    }

    #[test]
    fn tetrahedron_one_step_matches_the_rules_exactly() {
        let t = tetrahedron();
        let m = t.loop_subdivide(1).unwrap();
        assert_eq!((m.vertex_count(), m.face_count()), (10, 16));
        assert!(m.is_closed() && m.is_manifold() && m.is_triangle_mesh());
        // β3 = 3/16: v' = (1 - 9/16) v + 3/16 Σe = 7/16 (1,1,1) + 3/16 (-1,-1,-1) = (1/4)(1,1,1).
        assert_close(m.position(0), Vec3::splat(0.25), 1e-16);
        // Edge (1,1,1)-(1,-1,-1): 3/8 (2,0,0) + 1/8 ((-1,1,-1) + (-1,-1,1)) = (1/2, 0, 0).
        let e = t.edges().position(|h| {
            let (a, b) = (t.origin(h), t.target(h));
            (a.min(b), a.max(b)) == (0, 1)
        });
        assert_close(m.position(4 + e.unwrap() as u32), Vec3::new(0.5, 0.0, 0.0), 1e-16);
        // Face order: [v0, m0, m2], [v1, m1, m0], [v2, m2, m1], [m0, m1, m2].
        let f: Vec<u32> = m.face_vertices(0).collect();
        assert_eq!(f[0], t.face_vertices(0).next().unwrap());
        let centre: Vec<u32> = m.face_vertices(3).collect();
        assert!(centre.iter().all(|&v| v >= 4));
    }

    #[test]
    fn icosahedron_vertex_point_scales_radially_by_the_exact_factor() {
        // Valence 5 everywhere; the five neighbours of v sum to 5 cos α · v with cos α = 1/√5
        // (adjacent icosahedron vertices), so v' = (1 - 5β + √5 β) v with Loop's β5.
        let ico = Mesh::icosphere(1.0, 0);
        let m = ico.loop_subdivide(1).unwrap();
        let b = loop_beta(5);
        let k = 1.0 - 5.0 * b + 5f64.sqrt() * b;
        for v in 0..12 {
            assert_close(m.position(v), ico.position(v) * k, 1e-14);
        }
    }

    #[test]
    fn boundary_and_crease_follow_the_curve_rules() {
        // A triangulated 2×2 grid: boundary edge points at midpoints, boundary vertices
        // (e_a + 6 v + e_b)/8 along the boundary. Vertex 1 = (1,0): (0,0) + 6 (1,0) + (2,0) → (1,0).
        let g = grid(2).triangulate().unwrap();
        let m = g.loop_subdivide(1).unwrap();
        assert_close(m.position(1), Vec3::new(1.0, 0.0, 0.0), 1e-15);
        // The corner (0,0) with neighbours (1,0), (0,1) on the boundary: (1/8, 1/8, 0).
        assert_close(m.position(0), Vec3::new(0.125, 0.125, 0.0), 1e-15);
        assert!(m.positions().iter().all(|p| p.z == 0.0));
        let mut c = g.clone();
        c.crease_edges(&[[3, 4], [4, 5]]).unwrap();
        let m = c.loop_subdivide(2).unwrap();
        assert_eq!(m.crease_count(), 8);
    }

    #[test]
    fn non_triangles_are_refused_and_the_input_kept() {
        let cube = Mesh::cube(2.0);
        let before = cube.clone();
        let e = cube.loop_subdivide(1).unwrap_err();
        assert_eq!(e, SubdivError::NotTriangles { face: 0, arity: 4 });
        assert!(e.to_string().contains("face 0 has 4 vertices"));
        assert_eq!(cube, before);
        assert!(matches!(cube.loop_limit(), Err(SubdivError::NotTriangles { face: 0, arity: 4 })));
    }

    #[test]
    fn loop_stencils_reproduce_interpolation() {
        let mut s = Mesh::icosphere(1.0, 1);
        s.crease_edges(&[[0, 11]]).unwrap_or(());
        let r = Refiner::new(&s, Scheme::Loop, 3).unwrap();
        let direct = r.refine_positions(s.positions());
        for (a, b) in r.composed_stencils().apply(s.positions()).iter().zip(&direct) {
            assert_close(*a, *b, 1e-13);
        }
        let m = s.loop_subdivide(3).unwrap();
        assert_eq!(m.face_count(), 80 * 64);
        assert!(m.is_closed() && m.genus() == 0);
    }
}
