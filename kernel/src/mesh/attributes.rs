//! Per-element attributes: crease sharpness on edges, corner sharpness and colours on vertices, sources
//! (provenance, [`FaceSource`]) on faces.

use super::{FaceSource, Mesh, MeshError, SubdivOptions};

/// Checks a crease or corner sharpness: any value from 0 to `f64::INFINITY`.
///
/// # Errors
/// [`MeshError::BadSharpness`] for NaN or a negative value.
pub fn check_sharpness(sharpness: f64) -> Result<(), MeshError> {
    if sharpness >= 0.0 {
        Ok(())
    } else {
        Err(MeshError::BadSharpness { sharpness })
    }
}

impl Mesh {
    /// Whether the edge of half-edge `h` is tagged as a crease (any sharpness above 0).
    #[must_use]
    pub fn is_crease(&self, h: u32) -> bool {
        self.he_sharpness[h as usize] > 0.0
    }

    /// The crease sharpness of the edge of half-edge `h`: 0 for a smooth edge, `f64::INFINITY` for
    /// an infinitely sharp one, anything between for a semi-sharp crease (DeRose, Kass & Truong
    /// 1998 §3: sharp rules for that many levels, then smooth). Subdivision treats 10 and above as
    /// infinite, as OpenSubdiv does.
    #[must_use]
    pub fn edge_sharpness(&self, h: u32) -> f64 {
        self.he_sharpness[h as usize]
    }

    /// Tags (or untags) the edge of half-edge `h` as an infinitely sharp crease, on both halves.
    pub fn set_crease_halfedge(&mut self, h: u32, sharp: bool) {
        self.set_edge_sharpness_halfedge(h, if sharp { f64::INFINITY } else { 0.0 });
    }

    /// Sets the crease sharpness of the edge of half-edge `h` on both halves. A value that is not
    /// a valid sharpness (NaN, below 0) is stored as 0; callers check with [`check_sharpness`].
    pub fn set_edge_sharpness_halfedge(&mut self, h: u32, sharpness: f64) {
        let s = if sharpness > 0.0 { sharpness } else { 0.0 };
        self.he_sharpness[h as usize] = s;
        let t = self.he_twin[h as usize] as usize;
        self.he_sharpness[t] = s;
    }

    /// Tags every edge `[a, b]` of `edges` as an infinitely sharp crease. All or nothing: on error
    /// no tag is set.
    ///
    /// # Errors
    /// [`MeshError::NotAnEdge`] for a pair not joined by an edge.
    pub fn crease_edges(&mut self, edges: &[[u32; 2]]) -> Result<(), MeshError> {
        self.crease_edges_sharpness(edges, f64::INFINITY)
    }

    /// Sets the crease sharpness of every edge `[a, b]` of `edges` (0 makes them smooth again,
    /// `f64::INFINITY` infinitely sharp). All or nothing: on error no tag is set.
    ///
    /// # Errors
    /// [`MeshError::BadSharpness`] for NaN or a negative value; [`MeshError::NotAnEdge`] for a
    /// pair not joined by an edge.
    pub fn crease_edges_sharpness(&mut self, edges: &[[u32; 2]], sharpness: f64) -> Result<(), MeshError> {
        check_sharpness(sharpness)?;
        let hs = edges
            .iter()
            .map(|&[a, b]| self.find_halfedge(a, b).ok_or(MeshError::NotAnEdge { a, b }))
            .collect::<Result<Vec<_>, _>>()?;
        for h in hs {
            self.set_edge_sharpness_halfedge(h, sharpness);
        }
        Ok(())
    }

    /// Tags every edge as an infinitely sharp crease.
    pub fn crease_all(&mut self) {
        self.he_sharpness.iter_mut().for_each(|c| *c = f64::INFINITY);
    }

    /// Removes every crease tag.
    pub fn clear_creases(&mut self) {
        self.he_sharpness.iter_mut().for_each(|c| *c = 0.0);
    }

    /// Number of edges tagged as creases (of any sharpness).
    #[must_use]
    pub fn crease_count(&self) -> usize {
        self.edges().filter(|&h| self.is_crease(h)).count()
    }

    /// The crease edges (of any sharpness) as `[a, b]` vertex pairs, each once.
    #[must_use]
    pub fn crease_pairs(&self) -> Vec<[u32; 2]> {
        self.edges().filter(|&h| self.is_crease(h)).map(|h| [self.origin(h), self.target(h)]).collect()
    }

    /// The crease edges with their sharpness, each once.
    #[must_use]
    pub fn crease_sharpnesses(&self) -> Vec<([u32; 2], f64)> {
        self.edges()
            .filter(|&h| self.is_crease(h))
            .map(|h| ([self.origin(h), self.target(h)], self.he_sharpness[h as usize]))
            .collect()
    }

    /// Whether any crease or corner is semi-sharp (finite and above 0).
    #[must_use]
    pub fn has_semi_sharp(&self) -> bool {
        let semi = |s: f64| s > 0.0 && s.is_finite();
        self.he_sharpness.iter().any(|&s| semi(s)) || self.vertex_sharpness.iter().any(|&s| semi(s))
    }

    /// Whether vertex `v` is marked as a corner (any corner sharpness above 0).
    #[must_use]
    pub fn is_corner(&self, v: u32) -> bool {
        self.vertex_sharpness[v as usize] > 0.0
    }

    /// The corner sharpness of vertex `v`: 0 for none, `f64::INFINITY` for a corner that stays put,
    /// between for a semi-sharp corner (the corner rule for that many levels).
    #[must_use]
    pub fn corner_sharpness(&self, v: u32) -> f64 {
        self.vertex_sharpness[v as usize]
    }

    /// Marks (or unmarks) vertex `v` as an infinitely sharp corner.
    pub fn set_corner(&mut self, v: u32, corner: bool) {
        self.set_corner_sharpness(v, if corner { f64::INFINITY } else { 0.0 });
    }

    /// Sets the corner sharpness of vertex `v` (NaN or a negative value is stored as 0; callers
    /// check with [`check_sharpness`]).
    pub fn set_corner_sharpness(&mut self, v: u32, sharpness: f64) {
        self.vertex_sharpness[v as usize] = if sharpness > 0.0 { sharpness } else { 0.0 };
    }

    /// The subdivision options the mesh is refined with by [`Mesh::catmull_clark`],
    /// [`Mesh::loop_subdivide`] and the limit functions (OpenSubdiv's `Sdc::Options`; a USD mesh
    /// holds the same three as attributes).
    #[must_use]
    pub fn subdiv_options(&self) -> SubdivOptions {
        self.subdiv_options
    }

    /// Sets the subdivision options.
    pub fn set_subdiv_options(&mut self, options: SubdivOptions) {
        self.subdiv_options = options;
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

    /// The source of every face, when the mesh has them (a boolean result does).
    #[must_use]
    pub fn face_sources(&self) -> Option<&[FaceSource]> {
        self.face_sources.as_deref()
    }

    /// Sets one source per face, or removes them with `None`. Moving vertices keeps them;
    /// topological edits drop them; triangulation, combining and reversing carry them.
    ///
    /// # Errors
    /// [`MeshError::NoSuchElement`] when the count differs from the face count.
    pub fn set_face_sources(&mut self, sources: Option<Vec<FaceSource>>) -> Result<(), MeshError> {
        if let Some(s) = &sources {
            if s.len() != self.face_count() {
                return Err(MeshError::NoSuchElement {
                    what: "face source",
                    id: s.len() as u64,
                    count: self.face_count(),
                });
            }
        }
        self.face_sources = sources;
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
