//! Per-element attributes: crease tags on edges, corner marks and colours on vertices.

use super::{Mesh, MeshError};

impl Mesh {
    /// Whether the edge of half-edge `h` is tagged as an infinitely sharp crease.
    #[must_use]
    pub fn is_crease(&self, h: u32) -> bool {
        self.he_crease[h as usize]
    }

    /// Tags (or untags) the edge of half-edge `h` as a crease, on both of its halves.
    pub fn set_crease_halfedge(&mut self, h: u32, sharp: bool) {
        self.he_crease[h as usize] = sharp;
        let t = self.he_twin[h as usize] as usize;
        self.he_crease[t] = sharp;
    }

    /// Tags every edge `[a, b]` of `edges` as a crease. All or nothing: on error no tag is set.
    ///
    /// # Errors
    /// [`MeshError::NotAnEdge`] for a pair not joined by an edge.
    pub fn crease_edges(&mut self, edges: &[[u32; 2]]) -> Result<(), MeshError> {
        let hs = edges
            .iter()
            .map(|&[a, b]| self.find_halfedge(a, b).ok_or(MeshError::NotAnEdge { a, b }))
            .collect::<Result<Vec<_>, _>>()?;
        for h in hs {
            self.set_crease_halfedge(h, true);
        }
        Ok(())
    }

    /// Tags every edge as a crease.
    pub fn crease_all(&mut self) {
        self.he_crease.iter_mut().for_each(|c| *c = true);
    }

    /// Removes every crease tag.
    pub fn clear_creases(&mut self) {
        self.he_crease.iter_mut().for_each(|c| *c = false);
    }

    /// Number of edges tagged as creases.
    #[must_use]
    pub fn crease_count(&self) -> usize {
        self.edges().filter(|&h| self.he_crease[h as usize]).count()
    }

    /// The crease edges as `[a, b]` vertex pairs, each once.
    #[must_use]
    pub fn crease_pairs(&self) -> Vec<[u32; 2]> {
        self.edges().filter(|&h| self.he_crease[h as usize]).map(|h| [self.origin(h), self.target(h)]).collect()
    }

    /// Whether vertex `v` is marked as a corner (kept sharp by subdivision).
    #[must_use]
    pub fn is_corner(&self, v: u32) -> bool {
        self.vertex_corner[v as usize]
    }

    /// Marks (or unmarks) vertex `v` as a corner.
    pub fn set_corner(&mut self, v: u32, corner: bool) {
        self.vertex_corner[v as usize] = corner;
    }

    /// The vertex colours (RGBA in 0..=1), when the mesh has them.
    #[must_use]
    pub fn vertex_colors(&self) -> Option<&[[f32; 4]]> {
        self.vertex_colors.as_deref()
    }

    /// Sets one RGBA colour per vertex, or removes the colours with `None`.
    ///
    /// # Errors
    /// [`MeshError::NoSuchElement`] when the count differs from the vertex count.
    pub fn set_vertex_colors(&mut self, colors: Option<Vec<[f32; 4]>>) -> Result<(), MeshError> {
        if let Some(c) = &colors {
            if c.len() != self.vertex_count() {
                return Err(MeshError::NoSuchElement {
                    what: "vertex colour",
                    id: c.len() as u64,
                    count: self.vertex_count(),
                });
            }
        }
        self.vertex_colors = colors;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use crate::mesh::{Mesh, MeshError};

    #[test]
    fn crease_tags_are_symmetric_and_all_or_nothing() {
        let mut m = Mesh::cube(2.0);
        let h = m.face_halfedge(0);
        let (a, b) = (m.origin(h), m.target(h));
        m.crease_edges(&[[b, a]]).unwrap();
        assert!(m.is_crease(h) && m.is_crease(m.twin(h)));
        assert_eq!(m.crease_count(), 1);
        let before = m.clone();
        // The second pair is a diagonal, not an edge: nothing may change.
        let diag = m.face_halfedges(0).nth(2).map(|x| m.origin(x)).unwrap();
        let e = m.crease_edges(&[[m.target(m.next(h)), m.origin(m.next(h))], [a, diag]]).unwrap_err();
        assert_eq!(e, MeshError::NotAnEdge { a, b: diag });
        assert_eq!(m, before);
        m.crease_all();
        assert_eq!(m.crease_count(), 12);
    }
}
