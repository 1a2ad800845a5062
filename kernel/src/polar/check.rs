//! Verification of every invariant of chapter 3, naming the first one broken.

use super::{PolarError, PolarMesh};
use crate::mesh::NONE;

impl PolarMesh {
    /// Verifies every invariant of a polar mesh (seed 004, ch. 3) and names the first one broken.
    ///
    /// In order: the markers cover every element; the mesh is closed and a 2-manifold with no
    /// unused vertex; loop markers agree on both halves of an edge; every face is a quad with no
    /// pole whose edges alternate backbone, loop, backbone, loop (annular region) or a triangle
    /// with exactly one pole, a loop edge opposite it and backbones at it (pole region); the
    /// loop/backbone connectivity of §3.2.3 holds; poles have valence ≥ 3 and other vertices
    /// ≥ 4; no two edges join the same two vertices. Time O(E log valence). Polls the current
    /// cancellation token every [`crate::limits::POLL_EVERY`] elements of each pass.
    ///
    /// # Errors
    /// The [`PolarError`] variant of the first broken invariant, naming the element;
    /// [`PolarError::Limit`] when the token stops.
    pub fn check(&self) -> Result<(), PolarError> {
        self.check_polling(true)
    }

    /// [`PolarMesh::check`], polling the cancellation token or not: the primitives, whose
    /// marking cannot fail, check without polling so that a stop never lands in them.
    pub(crate) fn check_polling(&self, poll: bool) -> Result<(), PolarError> {
        let tick = |i: usize| if poll { crate::limits::poll_at(i) } else { Ok(()) };
        let m = &self.mesh;
        if self.pole.len() != m.vertex_count() || self.is_loop.len() != m.halfedge_count() {
            return Err(PolarError::Internal(format!(
                "marker arrays have {} and {} entries for {} vertices and {} half-edges",
                self.pole.len(),
                self.is_loop.len(),
                m.vertex_count(),
                m.halfedge_count()
            )));
        }
        for h in 0..m.halfedge_count() as u32 {
            tick(h as usize)?;
            if m.is_boundary_halfedge(h) {
                return Err(PolarError::NotClosed { halfedge: h });
            }
        }
        if !m.is_manifold_polling(poll)? {
            return Err(PolarError::NotManifold);
        }
        for v in 0..m.vertex_count() as u32 {
            tick(v as usize)?;
            if m.vertex_halfedge(v) == NONE {
                return Err(PolarError::IsolatedVertex { vertex: v });
            }
        }
        for h in 0..m.halfedge_count() as u32 {
            tick(h as usize)?;
            if self.is_loop(h) != self.is_loop(m.twin(h)) {
                return Err(PolarError::LoopMarkAsymmetric { halfedge: h });
            }
        }
        for f in 0..m.face_count() as u32 {
            tick(f as usize)?;
            self.check_face(f)?;
        }
        for h in 0..m.halfedge_count() as u32 {
            tick(h as usize)?;
            let n = m.next(h);
            if self.is_loop(h) && self.is_loop(n) {
                return Err(PolarError::Connectivity {
                    halfedge: h,
                    rule: "a loop edge must be followed by a backbone",
                });
            }
            if !self.is_loop(h) && !self.is_pole(m.target(h)) && !self.is_loop(n) {
                return Err(PolarError::Connectivity {
                    halfedge: h,
                    rule: "a backbone not ending at a pole must be followed by a loop edge",
                });
            }
        }
        let mut neighbours = Vec::new();
        for v in 0..m.vertex_count() as u32 {
            tick(v as usize)?;
            let valence = m.valence(v);
            if self.is_pole(v) && valence < 3 {
                return Err(PolarError::PoleValence { pole: v, valence });
            }
            if !self.is_pole(v) && valence < 4 {
                return Err(PolarError::VertexValence { vertex: v, valence });
            }
            neighbours.clear();
            neighbours.extend(m.vertex_neighbors(v));
            neighbours.sort_unstable();
            if let Some(w) = neighbours.windows(2).find(|w| w[0] == w[1]) {
                return Err(PolarError::DuplicateEdge { a: v, b: w[0] });
            }
        }
        Ok(())
    }

    /// The face rules of chapter 3 for one face.
    pub(crate) fn check_face(&self, f: u32) -> Result<(), PolarError> {
        let m = &self.mesh;
        let hs: Vec<u32> = m.face_halfedges(f).collect();
        let poles: Vec<u32> = hs.iter().map(|&h| m.origin(h)).filter(|&v| self.is_pole(v)).collect();
        match hs.len() {
            4 => {
                if let Some(&p) = poles.first() {
                    return Err(PolarError::QuadWithPole { face: f, pole: p });
                }
                let l: Vec<bool> = hs.iter().map(|&h| self.is_loop(h)).collect();
                if !(l[0] != l[1] && l[0] == l[2] && l[1] == l[3]) {
                    return Err(PolarError::QuadNotAlternating { face: f });
                }
            }
            3 => {
                if poles.is_empty() {
                    return Err(PolarError::TriangleWithoutPole { face: f });
                }
                if poles.len() > 1 {
                    return Err(PolarError::TriangleWithManyPoles { face: f, count: poles.len() });
                }
                let p = poles[0];
                for &h in &hs {
                    // The edge opposite the pole is the one neither of whose ends is the pole.
                    let opposite = m.origin(h) != p && m.target(h) != p;
                    if self.is_loop(h) != opposite {
                        return Err(PolarError::PoleTriangleEdges { face: f, pole: p });
                    }
                }
            }
            n => return Err(PolarError::FaceArity { face: f, arity: n }),
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec3;
    use crate::mesh::Mesh;

    #[test]
    fn a_stop_lands_inside_the_check_of_a_large_mesh_but_not_in_the_primitives_check() {
        use crate::limits::{install, CancelToken, LimitError, StopReason};
        use std::sync::atomic::AtomicBool;
        use std::sync::Arc;
        // 90,000 faces: every pass polls more than once.
        let pm = PolarMesh::uv_sphere(1.0, 300, 300);
        let _g = install(CancelToken::with(Some(Arc::new(AtomicBool::new(true))), None, None));
        let e = pm.check().unwrap_err();
        assert!(matches!(e, PolarError::Limit(LimitError::Stopped(StopReason::Interrupted))), "{e}");
        pm.check_polling(false).unwrap();
        assert!(matches!(pm.mesh.is_manifold_polling(true), Err(LimitError::Stopped(_))));
        assert!(pm.mesh.is_manifold());
    }

    /// The error `check` gives for a copy of `pm` changed by `change`.
    fn broken(pm: &PolarMesh, change: impl FnOnce(&mut PolarMesh)) -> PolarError {
        let mut copy = pm.clone();
        change(&mut copy);
        copy.check().expect_err("the change must break an invariant")
    }

    /// A polar mesh of `mesh` with no marker set (to reach the structural checks).
    fn unmarked(mesh: Mesh) -> PolarMesh {
        let (nv, nh) = (mesh.vertex_count(), mesh.halfedge_count());
        PolarMesh { mesh, pole: vec![false; nv], is_loop: vec![false; nh] }
    }

    fn octahedron_faces() -> Vec<[u32; 3]> {
        let mut faces = Vec::new();
        for i in 0..4u32 {
            let (a, b) = (1 + i, 1 + (i + 1) % 4);
            faces.push([0, b, a]);
            faces.push([5, a, b]);
        }
        faces
    }

    #[test]
    fn markers_that_contradict_the_faces_are_named() {
        let oct = PolarMesh::octahedron();
        oct.check().unwrap();
        // Vertex 1 lies on the equator: promoted to a pole, its triangles have two poles each.
        let e = broken(&oct, |p| p.pole[1] = true);
        assert!(matches!(e, PolarError::TriangleWithManyPoles { count: 2, .. }), "{e}");
        // The -z pole demoted: its four triangles have no pole.
        let e = broken(&oct, |p| p.pole[0] = false);
        assert!(matches!(e, PolarError::TriangleWithoutPole { .. }), "{e}");
        // One half of an equator (loop) edge unmarked: the two halves disagree.
        let h = oct.mesh.find_halfedge(1, 2).unwrap();
        let t = oct.mesh.twin(h);
        let e = broken(&oct, |p| p.is_loop[h as usize] = false);
        assert!(matches!(e, PolarError::LoopMarkAsymmetric { halfedge } if halfedge == h.min(t)), "{e}");
        // Both halves unmarked: the triangles on that edge lose the loop opposite their pole.
        let e = broken(&oct, |p| {
            p.is_loop[h as usize] = false;
            p.is_loop[t as usize] = false;
        });
        assert!(matches!(e, PolarError::PoleTriangleEdges { .. }), "{e}");
        // On a UV sphere, a backbone between two quads marked as a loop: those quads no longer
        // alternate backbone, loop, backbone, loop.
        let sphere = PolarMesh::uv_sphere(1.0, 8, 6);
        sphere.check().unwrap();
        let m = &sphere.mesh;
        let backbone = (0..m.halfedge_count() as u32)
            .find(|&h| !sphere.is_loop(h) && [h, m.twin(h)].iter().all(|&x| m.face_halfedges(m.face(x)).count() == 4))
            .unwrap();
        let twin = m.twin(backbone);
        let e = broken(&sphere, |p| {
            p.is_loop[backbone as usize] = true;
            p.is_loop[twin as usize] = true;
        });
        assert!(matches!(e, PolarError::QuadNotAlternating { .. }), "{e}");
    }

    #[test]
    fn structural_faults_are_named() {
        let ring = |i: u32| {
            let a = f64::from(i) * std::f64::consts::TAU / 5.0;
            (a.cos(), a.sin())
        };
        let oct_positions = vec![Vec3::NEG_Z, Vec3::X, Vec3::Y, Vec3::NEG_X, Vec3::NEG_Y, Vec3::Z];
        // The octahedron less one face is open.
        let mut faces = octahedron_faces();
        faces.pop();
        let open = Mesh::from_polygons(oct_positions.clone(), &faces).unwrap();
        assert!(matches!(unmarked(open).check(), Err(PolarError::NotClosed { .. })));
        // A seventh vertex that no face uses.
        let mut positions = oct_positions.clone();
        positions.push(Vec3::new(3.0, 0.0, 0.0));
        let extra = Mesh::from_polygons(positions, &octahedron_faces()).unwrap();
        assert_eq!(unmarked(extra).check(), Err(PolarError::IsolatedVertex { vertex: 6 }));
        // A pentagonal prism: its first face is a pentagon, neither quad nor triangle.
        let mut positions = Vec::new();
        for z in [0.0, 1.0] {
            positions.extend((0..5).map(|i| Vec3::new(ring(i).0, ring(i).1, z)));
        }
        let mut faces: Vec<Vec<u32>> = vec![vec![4, 3, 2, 1, 0], vec![5, 6, 7, 8, 9]];
        faces.extend((0..5u32).map(|i| vec![i, (i + 1) % 5, 5 + (i + 1) % 5, 5 + i]));
        let prism = Mesh::from_polygons(positions, &faces).unwrap();
        assert_eq!(unmarked(prism).check(), Err(PolarError::FaceArity { face: 0, arity: 5 }));
    }
}
