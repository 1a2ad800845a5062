//! Remove refinement (§4.2): delete a loop or a backbone, merging the faces on its two sides.

use super::{PolarError, PolarMesh, Poly};
use crate::math::IdSet;

impl PolarMesh {
    /// Remove refinement (seed 004, §4.2): removes the loop or backbone through half-edge `h`
    /// (its [`PolarMesh::walk`]), merging the two faces on each of its edges and dissolving its
    /// vertices (poles at a backbone's ends stay). Removing a loop merges two regions into one;
    /// removing a backbone lowers the valency of every region it crosses by one.
    ///
    /// Time proportional to the length of the refinement times the valence of its vertices.
    ///
    /// # Errors
    /// Checked before anything changes, each naming the rule of §4.2.4:
    /// - [`PolarError::LastLoopBetweenPoles`] (a): the loop has pole fans on both sides;
    /// - [`PolarError::RefinementSupportsFeature`] (b): the refinement passes a split vertex;
    /// - [`PolarError::ValencyTooLow`] (c): a region would drop below valency 3 (the thesis says
    ///   0; here 3, because a region of valency 2 would join two vertices by two edges);
    /// - [`PolarError::WouldBreakManifold`] when the two sides would fold onto each other (the
    ///   loops beside the removed one touch) and [`PolarError::InvalidArgument`] when one face
    ///   lies on the refinement twice;
    /// - [`PolarError::NoSuchElement`] for a bad id.
    pub fn remove_refinement(&mut self, h: i64) -> Result<(), PolarError> {
        let h = self.halfedge_id(h)?;
        let m = &self.mesh;
        let line = self.walk_of(h);
        let is_loop_line = self.is_loop(h);
        let mut inner: IdSet<u32> = IdSet::with_capacity_and_hasher(line.len() * 2, Default::default());
        for &x in &line {
            for v in [m.origin(x), m.target(x)] {
                if !self.is_pole(v) {
                    inner.insert(v);
                }
            }
        }
        let mut sorted_inner: Vec<u32> = inner.iter().copied().collect();
        sorted_inner.sort_unstable();
        for &v in &sorted_inner {
            let valence = m.valence(v);
            if valence != 4 {
                return Err(PolarError::RefinementSupportsFeature { halfedge: h, vertex: v, valence });
            }
        }
        if is_loop_line {
            for &x in &line {
                let (f, g) = (m.face(x), m.face(m.twin(x)));
                if m.face_arity(f) == 3 && m.face_arity(g) == 3 {
                    let pole_of = |f: u32| m.face_vertices(f).find(|&v| self.is_pole(v)).unwrap_or(u32::MAX);
                    return Err(PolarError::LastLoopBetweenPoles { halfedge: h, poles: [pole_of(f), pole_of(g)] });
                }
            }
        } else {
            for &v in &sorted_inner {
                let l: Vec<u32> = m.outgoing(v).filter(|&x| self.is_loop(x)).map(|x| m.target(x)).collect();
                if l.len() == 2 && (l[0] == l[1] || m.find_halfedge(l[0], l[1]).is_some()) {
                    let lh = m.outgoing(v).find(|&x| self.is_loop(x)).unwrap_or(h);
                    let valency = self.walk_of(lh).len().saturating_sub(1);
                    return Err(PolarError::ValencyTooLow { halfedge: h, vertex: v, valency });
                }
            }
            let mut ends: Vec<u32> = Vec::new();
            for &x in &line {
                for v in [m.origin(x), m.target(x)] {
                    if self.is_pole(v) {
                        ends.push(v);
                    }
                }
            }
            ends.sort_unstable();
            for w in ends.chunk_by(|a, b| a == b) {
                let (p, removed) = (w[0], w.len());
                let valency = m.valence(p).saturating_sub(removed);
                if valency < 3 {
                    return Err(PolarError::ValencyTooLow { halfedge: h, vertex: p, valency });
                }
            }
        }
        let mut faces = Vec::with_capacity(2 * line.len());
        let mut seen: IdSet<u32> = IdSet::with_capacity_and_hasher(2 * line.len(), Default::default());
        for &x in &line {
            for f in [m.face(x), m.face(m.twin(x))] {
                if !seen.insert(f) {
                    return Err(PolarError::InvalidArgument(format!(
                        "face {f} lies on the refinement through half-edge {h} twice; removing it would fold the face onto itself"
                    )));
                }
                faces.push(f);
            }
        }
        let mut polys = Vec::with_capacity(line.len());
        for &x in &line {
            let t = m.twin(x);
            let mut p = Poly::default();
            // Face of x from target(x) round to origin(x), then the face of twin(x) from the
            // corner after origin(x) round to the corner before target(x).
            let mut y = m.next(x);
            loop {
                p.corners.push(m.origin(y));
                p.loops.push(self.is_loop(if y == x { m.next(t) } else { y }));
                if y == x {
                    break;
                }
                y = m.next(y);
            }
            let mut y = m.next(m.next(t));
            while y != t {
                p.corners.push(m.origin(y));
                p.loops.push(self.is_loop(y));
                y = m.next(y);
            }
            for k in (0..p.corners.len()).rev() {
                if inner.contains(&p.corners[k]) {
                    p.drop_corner(k);
                }
            }
            polys.push(p);
        }
        self.rebuild(&faces, &polys, &[], &[])?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn removing_an_added_loop_restores_the_octahedron_counts() {
        let mut pm = PolarMesh::octahedron();
        let s = pm.mesh().find_halfedge(0, 1).unwrap();
        let r = pm.add_refinement(i64::from(s)).unwrap();
        pm.remove_refinement(i64::from(r.halfedges[0])).unwrap();
        pm.check().unwrap();
        let m = pm.mesh();
        assert_eq!((m.vertex_count(), m.edge_count(), m.face_count()), (6, 12, 8));
    }

    #[test]
    fn removing_a_backbone_lowers_pole_valence() {
        let mut pm = PolarMesh::uv_sphere(1.0, 6, 4);
        let s = pm.fan_of(0)[0];
        pm.remove_refinement(i64::from(s)).unwrap();
        pm.check().unwrap();
        // 6 → 5 segments: V = 2 + 3·5, F = 5·4.
        assert_eq!((pm.vertex_count(), pm.face_count()), (17, 20));
        assert_eq!(pm.valence(0), 5);
    }

    #[test]
    fn last_loop_between_two_poles_is_refused() {
        // §4.2.4 a: the octahedron's equator separates its two poles.
        let mut pm = PolarMesh::octahedron();
        let before = pm.clone();
        let e = pm.remove_refinement(i64::from(pm.mesh().find_halfedge(1, 2).unwrap())).unwrap_err();
        assert!(matches!(e, PolarError::LastLoopBetweenPoles { poles: [_, _], .. }), "{e}");
        assert!(e.to_string().contains("§4.2.4 a"), "{e}");
        assert_eq!(pm, before);
    }

    #[test]
    fn valency_may_not_drop_below_three() {
        // §4.2.4 c: an octahedron has valency 4; one backbone can go, the next cannot.
        let mut pm = PolarMesh::octahedron();
        pm.remove_refinement(i64::from(pm.fan_of(0)[0])).unwrap();
        pm.check().unwrap();
        let before = pm.clone();
        let e = pm.remove_refinement(i64::from(pm.fan_of(0)[0])).unwrap_err();
        assert!(matches!(e, PolarError::ValencyTooLow { valency: 2, .. }), "{e}");
        assert!(e.to_string().contains("§4.2.4 c"), "{e}");
        assert_eq!(pm, before);
    }

    #[test]
    fn refinements_supporting_a_nested_feature_are_refused() {
        // §4.2.4 b: after a feature on the equator (vertices 9..=11), neither the equator nor
        // the meridian through split vertex 9 may go; a loop elsewhere still can.
        let mut pm = PolarMesh::uv_sphere(1.0, 8, 4);
        pm.add_feature(&[9, 10, 11]).unwrap();
        let before = pm.clone();
        let eq = pm.mesh().find_halfedge(13, 14).unwrap();
        let e = pm.remove_refinement(i64::from(eq)).unwrap_err();
        assert!(matches!(e, PolarError::RefinementSupportsFeature { vertex: 9 | 11, .. }), "{e}");
        assert!(e.to_string().contains("§4.2.4 b"), "{e}");
        let meridian = pm.mesh().find_halfedge(1, 9).unwrap();
        let e = pm.remove_refinement(i64::from(meridian)).unwrap_err();
        assert!(matches!(e, PolarError::RefinementSupportsFeature { vertex: 9, .. }), "{e}");
        assert_eq!(pm, before);
        let low = pm.mesh().find_halfedge(1, 2).unwrap();
        pm.remove_refinement(i64::from(low)).unwrap();
        pm.check().unwrap();
    }
}
