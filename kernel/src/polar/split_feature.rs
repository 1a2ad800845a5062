//! Split feature (§4.7): replace a loop and the two rings beside it by two pole fans.

use super::{PolarError, PolarMesh, Poly};
use crate::math::IdSet;

impl PolarMesh {
    /// Split feature (seed 004, §4.7): removes the loop through half-edge `h0` (the split loop)
    /// with the ring of quads on each side, and caps the two supporting loops beside it with a
    /// fan around a new pole each. Returns the two poles: the first caps the loop on the side of
    /// `face(h0)`. Each pole starts halfway from its loop's centre towards the split loop's centre.
    /// Splitting a ring of a handle lowers the genus by one; otherwise the part falls in two.
    ///
    /// Time proportional to the loop's length.
    ///
    /// # Errors
    /// Checked before anything changes (§4.7.3): [`PolarError::NotALoopEdge`];
    /// [`PolarError::SplitLoopNested`] when the split loop passes a split vertex (no nested
    /// feature on it); [`PolarError::SplitNeedsSandwich`] unless both sides are rings of quads
    /// leading to other loops (loop – split loop – loop side by side); [`PolarError::NoSuchElement`];
    /// [`PolarError::WouldBreakManifold`] when the supporting loops touch the split loop.
    pub fn split_feature(&mut self, h0: i64) -> Result<[u32; 2], PolarError> {
        let h0 = self.halfedge_id(h0)?;
        if !self.is_loop(h0) {
            return Err(PolarError::NotALoopEdge { halfedge: h0 });
        }
        let m = &self.mesh;
        let split = self.walk_of(h0);
        let mverts: IdSet<u32> = split.iter().map(|&x| m.origin(x)).collect();
        let mut sorted: Vec<u32> = mverts.iter().copied().collect();
        sorted.sort_unstable();
        if let Some(&v) = sorted.iter().find(|&&v| m.valence(v) != 4) {
            return Err(PolarError::SplitLoopNested { halfedge: h0, vertex: v });
        }
        let mut remove = Vec::with_capacity(2 * split.len());
        let (mut side_a, mut side_b) = (Vec::new(), Vec::new());
        for &x in &split {
            for (y, side) in [(x, &mut side_a), (m.twin(x), &mut side_b)] {
                let f = m.face(y);
                if m.face_arity(f) != 4 {
                    return Err(PolarError::SplitNeedsSandwich { halfedge: h0, face: f });
                }
                // The quad's far loop edge, kept by the face across it.
                let far = m.next(m.next(y));
                if mverts.contains(&m.origin(far)) || mverts.contains(&m.target(far)) {
                    return Err(PolarError::SplitNeedsSandwich { halfedge: h0, face: f });
                }
                side.push(far);
                remove.push(f);
            }
        }
        let nv = m.vertex_count() as u32;
        let centre = |hs: &[u32]| crate::math::mean_point(hs.iter().map(|&x| m.position(m.origin(x))));
        let cm = centre(&split);
        let (ca, cb) = (centre(&side_a), centre(&side_b));
        let positions = [ca.lerp(cm, 0.5), cb.lerp(cm, 0.5)];
        let mut polys = Vec::with_capacity(2 * split.len());
        for (side, pole) in [(&side_a, nv), (&side_b, nv + 1)] {
            for &far in side.iter() {
                polys.push(Poly { corners: vec![m.origin(far), m.target(far), pole], loops: vec![true, false, false] });
            }
        }
        let log = self.rebuild(&remove, &polys, &positions, &[true, true])?;
        Ok([log.new_vertices()[0], log.new_vertices()[1]])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splitting_a_sphere_gives_two_spheres() {
        // 8×6 sphere: split the middle loop (ring 3) → two parts of 2 rings + a new fan each.
        let mut pm = PolarMesh::uv_sphere(1.0, 8, 6);
        let h = pm.mesh().find_halfedge(17, 18).unwrap();
        let [p, q] = pm.split_feature(i64::from(h)).unwrap();
        pm.check().unwrap();
        assert!(pm.is_pole(p) && pm.is_pole(q));
        assert_eq!(pm.mesh().component_count(), 2);
        assert_eq!(pm.mesh().euler(), 4);
        assert_eq!((pm.valence(p), pm.valence(q)), (8, 8));
        // Merging the two new poles back gives one sphere again (2 rings between the caps'
        // loops once bridged).
        pm.merge_features(i64::from(p), i64::from(q)).unwrap();
        pm.check().unwrap();
        assert_eq!(pm.mesh().component_count(), 1);
        assert_eq!(pm.mesh().euler(), 2);
    }

    #[test]
    fn split_limitations_are_refused_unchanged() {
        let mut pm = PolarMesh::uv_sphere(1.0, 8, 4);
        let before = pm.clone();
        // A backbone.
        let b = pm.mesh().find_halfedge(1, 9).unwrap();
        assert!(matches!(pm.split_feature(i64::from(b)), Err(PolarError::NotALoopEdge { .. })));
        // The loop next to a pole has a fan on one side: no sandwich.
        let l = pm.mesh().find_halfedge(1, 2).unwrap();
        let e = pm.split_feature(i64::from(l)).unwrap_err();
        assert!(matches!(e, PolarError::SplitNeedsSandwich { .. }), "{e}");
        assert!(e.to_string().contains("§4.7.3"));
        assert_eq!(pm, before);
        // A feature nested on the equator.
        pm.add_feature(&[9, 10, 11]).unwrap();
        let before = pm.clone();
        let eq = pm.mesh().find_halfedge(13, 14).unwrap();
        let e = pm.split_feature(i64::from(eq)).unwrap_err();
        assert!(matches!(e, PolarError::SplitLoopNested { .. }), "{e}");
        assert_eq!(pm, before);
    }
}
