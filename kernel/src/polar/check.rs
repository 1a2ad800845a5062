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
    /// ≥ 4; no two edges join the same two vertices. Time O(E log valence).
    ///
    /// # Errors
    /// The [`PolarError`] variant of the first broken invariant, naming the element.
    pub fn check(&self) -> Result<(), PolarError> {
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
        if let Some(h) = (0..m.halfedge_count() as u32).find(|&h| m.is_boundary_halfedge(h)) {
            return Err(PolarError::NotClosed { halfedge: h });
        }
        if !m.is_manifold() {
            return Err(PolarError::NotManifold);
        }
        if let Some(v) = (0..m.vertex_count() as u32).find(|&v| m.vertex_halfedge(v) == NONE) {
            return Err(PolarError::IsolatedVertex { vertex: v });
        }
        if let Some(h) = (0..m.halfedge_count() as u32).find(|&h| self.is_loop(h) != self.is_loop(m.twin(h))) {
            return Err(PolarError::LoopMarkAsymmetric { halfedge: h });
        }
        for f in 0..m.face_count() as u32 {
            self.check_face(f)?;
        }
        for h in 0..m.halfedge_count() as u32 {
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
