//! Remove feature (§4.5): delete a feature and close the gap it leaves by zipping the two sides
//! of each boundary loop together.
//!
//! Step by step (§4.5.3): find the feature and its boundary loops; on each boundary loop find the
//! two split vertices and the two paths between them, which must have equal lengths; remove the
//! feature's faces; zip the paths, pairing vertices outwards from one split vertex, each pair
//! merging at its midpoint. The thesis removes features bounded by a pole and a loop only; a
//! feature bounded by two loops (a handle or a bridge, e.g. a ladder rung) is removed here the
//! same way, zipping both loops — sound because the zips are independent (the loops must not
//! touch) and each is the one of the pole case. Removing it lowers the genus by one, or splits
//! the part it bridged in two.

use super::{PolarError, PolarMesh};
use crate::math::{IdMap, IdSet};
use crate::mesh::edit::EditError;

impl PolarMesh {
    /// Remove feature (seed 004, §4.5): removes the feature of face `f` (see
    /// [`PolarMesh::select_feature`]) and closes the gap. Time proportional to the feature plus
    /// the faces around its boundary.
    ///
    /// # Errors
    /// Checked before anything changes:
    /// - [`PolarError::FeatureIsWholeComponent`] when no nesting loop bounds the feature;
    /// - [`PolarError::FeatureBoundary`] for a feature bounded otherwise than by one pole and one
    ///   loop or by two loops that do not touch;
    /// - [`PolarError::FeatureWrapsAround`] for a feature on both sides of its boundary loop;
    /// - [`PolarError::SplitVertexCount`]: a boundary loop without exactly 2 split vertices
    ///   (§4.5.1, §4.5.4, Fig. 4.7);
    /// - [`PolarError::AsymmetricPaths`]: paths of different lengths between them (§4.5.1,
    ///   Fig. 4.8);
    /// - [`PolarError::WouldBreakManifold`] when zipping would join two vertices twice;
    /// - [`PolarError::NoSuchElement`] for a bad id.
    pub fn remove_feature(&mut self, f: i64) -> Result<(), PolarError> {
        let f = self.face_id(f)?;
        let m = &self.mesh;
        let faces = self.feature_faces(f);
        let inside: IdSet<u32> = faces.iter().copied().collect();
        let mut boundary: Vec<u32> = Vec::new();
        let mut poles: Vec<u32> = Vec::new();
        for &g in &faces {
            for x in m.face_halfedges(g) {
                if !inside.contains(&m.face(m.twin(x))) {
                    boundary.push(x);
                }
                if self.is_pole(m.origin(x)) {
                    poles.push(m.origin(x));
                }
            }
        }
        poles.sort_unstable();
        poles.dedup();
        let on_boundary: IdSet<u32> = boundary.iter().copied().collect();
        let mut done: IdSet<u32> = IdSet::with_capacity_and_hasher(boundary.len(), Default::default());
        let mut walks: Vec<Vec<u32>> = Vec::new();
        for &x in &boundary {
            if done.contains(&x) {
                continue;
            }
            let w = self.walk_of(x);
            if let Some(&y) = w.iter().find(|&&y| !on_boundary.contains(&y)) {
                return Err(PolarError::FeatureWrapsAround { face: f, halfedge: y });
            }
            done.extend(w.iter().copied());
            walks.push(w);
        }
        match (walks.len(), poles.len()) {
            (0, _) => return Err(PolarError::FeatureIsWholeComponent { face: f }),
            (1, 1) | (2, 0) => {}
            (loops, poles) => return Err(PolarError::FeatureBoundary { face: f, loops, poles }),
        }
        // Zip plan: for every boundary loop, pairs (kept, merged) of vertices.
        let mut rename: IdMap<u32, u32> = IdMap::default();
        let mut pairs: Vec<(u32, u32)> = Vec::new();
        let mut all_walk_vertices: IdSet<u32> = IdSet::default();
        for w in &walks {
            let verts: Vec<u32> = w.iter().map(|&x| m.origin(x)).collect();
            for &v in &verts {
                if !all_walk_vertices.insert(v) {
                    return Err(PolarError::InvalidArgument(format!(
                        "the boundary loops of the feature of face {f} pass vertex {v} twice; removal needs loops that do not touch"
                    )));
                }
            }
            let splits: Vec<usize> = (0..verts.len()).filter(|&i| self.is_split(verts[i])).collect();
            if splits.len() != 2 {
                return Err(PolarError::SplitVertexCount {
                    count: splits.len(),
                    vertices: splits.iter().map(|&i| verts[i]).collect(),
                });
            }
            let (i1, i2) = (splits[0], splits[1]);
            let p1: Vec<u32> = verts[i1 + 1..i2].to_vec();
            let p2: Vec<u32> = verts[i2 + 1..].iter().chain(&verts[..i1]).copied().collect();
            if p1.len() != p2.len() {
                return Err(PolarError::AsymmetricPaths { split: [verts[i1], verts[i2]], inner: [p1.len(), p2.len()] });
            }
            let keep_first = p1.iter().min() <= p2.iter().min();
            for j in 0..p1.len() {
                let (a, b) = (p1[j], p2[p2.len() - 1 - j]);
                let (keep, merge) = if keep_first { (a, b) } else { (b, a) };
                rename.insert(merge, keep);
                pairs.push((keep, merge));
            }
        }
        // Faces outside the feature that touch a merged vertex are rebuilt with the new names.
        let mut outside: Vec<u32> = Vec::new();
        for &y in rename.keys() {
            outside.extend(m.vertex_faces(y).filter(|g| !inside.contains(g)));
        }
        outside.sort_unstable();
        outside.dedup();
        let mut polys = Vec::with_capacity(outside.len());
        for &g in &outside {
            let mut p = self.poly_from(m.face_halfedge(g));
            for c in &mut p.corners {
                if let Some(&k) = rename.get(c) {
                    *c = k;
                }
            }
            polys.push(p);
        }
        let midpoints: Vec<(u32, crate::math::Vec3)> =
            pairs.iter().map(|&(k, y)| (k, (m.position(k) + m.position(y)) * 0.5)).collect();
        let mut remove = faces;
        remove.extend_from_slice(&outside);
        let log = self.rebuild(&remove, &polys, &[], &[])?;
        let moved = log.vertex_map();
        for (k, p) in midpoints {
            if log.removed_vertices().binary_search(&k).is_ok() {
                return Err(PolarError::Internal(format!("zipped vertex {k} was deleted")));
            }
            let v = moved.get(&k).copied().unwrap_or(k);
            self.mesh.set_position(v, p).map_err(|e: EditError| PolarError::Internal(e.to_string()))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn removing_an_added_feature_restores_the_sphere() {
        let mut pm = PolarMesh::uv_sphere(1.0, 8, 4);
        let orig = pm.clone();
        let p = pm.add_feature(&[9, 10, 11]).unwrap();
        pm.check().unwrap();
        let face = pm.mesh().face(pm.fan_of(p)[0]);
        pm.remove_feature(i64::from(face)).unwrap();
        pm.check().unwrap();
        // Same counts as the sphere: V = 2 + 3·8, F = 8·4, E = V + F − 2.
        let m = pm.mesh();
        assert_eq!((m.vertex_count(), m.edge_count(), m.face_count()), (26, 56, 32));
        assert_eq!(pm.features().len(), 1);
        // Vertex 10 and the split point n1 (halfway up to vertex 18) zip at their midpoint.
        let want = (orig.position(10) + orig.position(10).lerp(orig.position(18), 0.5)) * 0.5;
        let best = (0..pm.vertex_count() as u32).map(|v| pm.position(v).distance(want)).fold(f64::INFINITY, f64::min);
        assert!(best < 1e-12, "no vertex at the zipped point {want}: nearest at distance {best}");
    }

    #[test]
    fn whole_component_and_asymmetric_and_crowded_boundaries_are_refused() {
        let mut pm = PolarMesh::uv_sphere(1.0, 8, 4);
        let before = pm.clone();
        assert!(matches!(pm.remove_feature(0), Err(PolarError::FeatureIsWholeComponent { face: 0 })));
        assert_eq!(pm, before);
        // A feature on 9..=11 opens above the equator. The part of the sphere above the
        // equator is bounded by the walk over the gap: 9 → n1 → 11 (1 inner vertex) and back
        // along the equator 11 → 12 … 16 → 9 (5 inner vertices): asymmetric (Fig. 4.8).
        let p1 = pm.add_feature(&[9, 10, 11]).unwrap();
        let north = (0..pm.vertex_count() as u32).find(|&v| pm.is_pole(v) && pm.position(v).z > 0.99).unwrap();
        let top = pm.mesh().face(pm.fan_of(north)[0]);
        let before = pm.clone();
        let e = pm.remove_feature(i64::from(top)).unwrap_err();
        assert!(matches!(e, PolarError::AsymmetricPaths { inner: [1, 5] | [5, 1], .. }), "{e}");
        assert!(e.to_string().contains("§4.5.1"));
        assert_eq!(pm, before);
        // A second feature on n1 → 11 → 12, from above, makes n1 a split vertex: the first
        // feature's boundary 9 → 10 → 11 → n1 now has three (Fig. 4.7 b).
        let m = pm.mesh();
        let n1 =
            m.vertex_neighbors(9).find(|&v| v != 10 && !pm.is_pole(v) && m.find_halfedge(v, 11).is_some()).unwrap();
        pm.add_feature(&[n1, 11, 12]).unwrap();
        pm.check().unwrap();
        let face = pm.mesh().face(pm.fan_of(p1)[0]);
        let before = pm.clone();
        let e = pm.remove_feature(i64::from(face)).unwrap_err();
        assert!(matches!(e, PolarError::SplitVertexCount { count: 3, .. }), "{e}");
        assert!(e.to_string().contains("§4.5.4"));
        assert_eq!(pm, before);
    }

    #[test]
    fn a_feature_nested_on_the_far_side_of_a_gap_survives_its_parent_removal() {
        // Feature 2 sits on feature 1's far side n1 between split vertices 9 and 11 (which
        // feature 2 shares): feature 1's boundary still has 2 split vertices and equal paths, so
        // it can go; feature 2 then sits on the equator.
        let mut pm = PolarMesh::uv_sphere(1.0, 8, 4);
        let p1 = pm.add_feature(&[9, 10, 11]).unwrap();
        let m = pm.mesh();
        let n1 =
            m.vertex_neighbors(9).find(|&v| v != 10 && !pm.is_pole(v) && m.find_halfedge(v, 11).is_some()).unwrap();
        pm.add_feature(&[9, n1, 11]).unwrap();
        let face = pm.mesh().face(pm.fan_of(p1)[0]);
        pm.remove_feature(i64::from(face)).unwrap();
        pm.check().unwrap();
        assert_eq!(pm.poles().len(), 3);
        assert_eq!(pm.features().len(), 3);
    }

    #[test]
    fn a_handle_bounded_by_two_loops_is_removed_and_the_genus_drops() {
        // Two branches on different loops merged into a handle: a feature bounded by two nesting
        // loops, which the thesis could not remove directly (§4.5.4). Removing it zips both
        // gaps: genus 1 → 0, χ 0 → 2, and the sphere's counts come back.
        let mut pm = PolarMesh::uv_sphere(1.0, 8, 6);
        let orig = pm.clone();
        let p = pm.add_feature(&[9, 10, 11]).unwrap();
        let q = pm.add_feature(&[28, 27, 26]).unwrap();
        pm.merge_features(i64::from(p), i64::from(q)).unwrap();
        pm.check().unwrap();
        assert_eq!(pm.mesh().genus(), 1);
        // A face of the bridge: next to the first gap's far side, away from the sphere body.
        let fid = (0..pm.face_count() as u32).find(|&f| pm.select_feature(i64::from(f)).unwrap().len() == 4).unwrap();
        pm.remove_feature(i64::from(fid)).unwrap();
        pm.check().unwrap();
        assert_eq!(pm.mesh().genus(), 0);
        let (a, b) = (pm.mesh(), orig.mesh());
        assert_eq!(
            (a.vertex_count(), a.edge_count(), a.face_count()),
            (b.vertex_count(), b.edge_count(), b.face_count())
        );
        assert_eq!(pm.features().len(), 1);
    }
}
