//! Adjacency circulators: around a face, around a vertex.

use super::{Mesh, NONE};

/// The half-edges of one face (or boundary loop), following `next`.
pub struct FaceHalfedges<'a> {
    mesh: &'a Mesh,
    first: u32,
    current: u32,
}

impl Iterator for FaceHalfedges<'_> {
    type Item = u32;
    fn next(&mut self) -> Option<u32> {
        if self.current == NONE {
            return None;
        }
        let h = self.current;
        let n = self.mesh.next(h);
        self.current = if n == self.first { NONE } else { n };
        Some(h)
    }
}

/// The outgoing half-edges of one vertex, clockwise seen from outside (`twin(prev(h))`),
/// starting from the boundary one when the vertex is on a boundary.
pub struct Outgoing<'a> {
    mesh: &'a Mesh,
    first: u32,
    current: u32,
}

impl Iterator for Outgoing<'_> {
    type Item = u32;
    fn next(&mut self) -> Option<u32> {
        if self.current == NONE {
            return None;
        }
        let h = self.current;
        let n = self.mesh.twin(self.mesh.prev(h));
        self.current = if n == self.first { NONE } else { n };
        Some(h)
    }
}

impl Mesh {
    /// The half-edges of face `f`, starting at [`Mesh::face_halfedge`].
    #[must_use]
    pub fn face_halfedges(&self, f: u32) -> FaceHalfedges<'_> {
        let first = self.face_he[f as usize];
        FaceHalfedges { mesh: self, first, current: first }
    }

    /// The half-edges of the loop (face or boundary) that `h` belongs to, starting at `h`.
    #[must_use]
    pub fn loop_halfedges(&self, h: u32) -> FaceHalfedges<'_> {
        FaceHalfedges { mesh: self, first: h, current: h }
    }

    /// The vertex ids of face `f`, in order.
    pub fn face_vertices(&self, f: u32) -> impl Iterator<Item = u32> + '_ {
        self.face_halfedges(f).map(move |h| self.he_origin[h as usize])
    }

    /// The outgoing half-edges of vertex `v` (none for an isolated vertex).
    #[must_use]
    pub fn outgoing(&self, v: u32) -> Outgoing<'_> {
        let first = self.vertex_out[v as usize];
        Outgoing { mesh: self, first, current: first }
    }

    /// The neighbouring vertices of `v` (its one-ring), in circulation order.
    pub fn vertex_neighbors(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        self.outgoing(v).map(move |h| self.target(h))
    }

    /// The faces around vertex `v`, in circulation order.
    pub fn vertex_faces(&self, v: u32) -> impl Iterator<Item = u32> + '_ {
        self.outgoing(v).map(move |h| self.face(h)).filter(|&f| f != NONE)
    }

    /// The number of edges at vertex `v`.
    #[must_use]
    pub fn valence(&self, v: u32) -> usize {
        self.outgoing(v).count()
    }

    /// Each boundary loop once, as its list of boundary half-edges.
    #[must_use]
    pub fn boundary_loops(&self) -> Vec<Vec<u32>> {
        let mut seen = vec![false; self.halfedge_count()];
        let mut loops = Vec::new();
        for h in 0..self.halfedge_count() as u32 {
            if self.is_boundary_halfedge(h) && !seen[h as usize] {
                let l: Vec<u32> = self.loop_halfedges(h).collect();
                for &x in &l {
                    seen[x as usize] = true;
                }
                loops.push(l);
            }
        }
        loops
    }
}

#[cfg(test)]
mod tests {
    use crate::mesh::Mesh;

    #[test]
    fn cube_vertex_has_three_neighbours_and_faces() {
        let m = Mesh::cube(2.0);
        for v in 0..8 {
            let mut n: Vec<u32> = m.vertex_neighbors(v).collect();
            n.sort_unstable();
            n.dedup();
            assert_eq!(n.len(), 3);
            assert_eq!(m.vertex_faces(v).count(), 3);
        }
        for f in 0..6 {
            assert_eq!(m.face_vertices(f).count(), 4);
        }
    }

    #[test]
    fn open_fan_circulates_from_boundary() {
        let p = vec![crate::Vec3::ZERO, crate::Vec3::X, crate::Vec3::Y, -crate::Vec3::X];
        let m = Mesh::from_polygons(p, &[[0, 1, 2], [0, 2, 3]]).unwrap();
        assert!(m.is_boundary_vertex(0));
        assert_eq!(m.valence(0), 3);
        assert_eq!(m.vertex_faces(0).count(), 2);
        assert_eq!(m.boundary_loops().len(), 1);
    }
}
