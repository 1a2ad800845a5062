//! Select feature (§4.4) and the partition of the mesh into features (§3.4).
//!
//! A feature is a chain of regions between boundaries that are poles or nesting loops (§3.4.1).
//! Two faces that share a backbone belong to one region; two faces that share a loop edge belong
//! to one feature unless that loop is a nesting loop. A loop is nesting exactly when its walk
//! passes a split vertex: at a vertex of valence 4 the walks from both sides of an edge go
//! straight on together, at a split vertex they always part, so either both walks of an edge
//! pass a split vertex or neither does.

use super::{PolarError, PolarMesh};
use crate::math::{IdMap, IdSet};

/// A union–find over dense ids.
pub(crate) struct Dsu(Vec<u32>);

impl Dsu {
    pub fn new(n: usize) -> Dsu {
        Dsu((0..n as u32).collect())
    }
    pub fn find(&mut self, mut x: u32) -> u32 {
        while self.0[x as usize] != x {
            let up = self.0[self.0[x as usize] as usize];
            self.0[x as usize] = up;
            x = up;
        }
        x
    }
    pub fn union(&mut self, a: u32, b: u32) {
        let (a, b) = (self.find(a), self.find(b));
        if a != b {
            let (lo, hi) = if a < b { (a, b) } else { (b, a) };
            self.0[hi as usize] = lo;
        }
    }
}

impl PolarMesh {
    /// Whether the loop through loop half-edge `h` is a nesting loop (its walk passes a split
    /// vertex, so a feature branches there; §3.4.1). Costs one walk of the loop.
    ///
    /// # Errors
    /// [`PolarError::NoSuchElement`], [`PolarError::NotALoopEdge`].
    pub fn is_nesting(&self, h: i64) -> Result<bool, PolarError> {
        let h = self.halfedge_id(h)?;
        if !self.is_loop(h) {
            return Err(PolarError::NotALoopEdge { halfedge: h });
        }
        Ok(self.walk_of(h).iter().any(|&x| self.is_split(self.mesh.origin(x))))
    }

    /// Select feature (seed 004, §4.4): the faces of the feature that face `f` belongs to,
    /// ascending. The walk spreads from `f` across backbones and across loops that are not
    /// nesting, so it stops at poles and nesting loops as §4.4.3 describes, and it costs time
    /// proportional to the feature and its boundary loops, whatever the size of the mesh.
    ///
    /// # Errors
    /// [`PolarError::NoSuchElement`] for a bad id.
    pub fn select_feature(&self, f: i64) -> Result<Vec<u32>, PolarError> {
        let f = self.face_id(f)?;
        let mut faces = self.feature_faces(f);
        faces.sort_unstable();
        Ok(faces)
    }

    /// The faces of the feature of `f`, in the order found.
    pub(crate) fn feature_faces(&self, f: u32) -> Vec<u32> {
        let m = &self.mesh;
        let mut nesting: IdMap<u32, bool> = IdMap::default();
        let mut seen: IdSet<u32> = IdSet::default();
        seen.insert(f);
        let mut out = vec![f];
        let mut i = 0;
        while i < out.len() {
            let g = out[i];
            i += 1;
            for x in m.face_halfedges(g) {
                let other = m.face(m.twin(x));
                if seen.contains(&other) {
                    continue;
                }
                let cross = if self.is_loop(x) {
                    let key = m.edge_key(x);
                    let nest = match nesting.get(&key) {
                        Some(&b) => b,
                        None => {
                            let w = self.walk_of(x);
                            let b = w.iter().any(|&y| self.is_split(m.origin(y)));
                            for &y in &w {
                                nesting.insert(m.edge_key(y), b);
                            }
                            b
                        }
                    };
                    !nest
                } else {
                    true
                };
                if cross {
                    seen.insert(other);
                    out.push(other);
                }
            }
        }
        out
    }

    /// The feature of every face: `(ids, count)` with `ids[f]` in `0..count`, numbered in order
    /// of their first face. Linear time (a union–find over loop edges, then over faces).
    ///
    /// See also [`PolarMesh::features`], [`PolarMesh::select_feature`].
    #[must_use]
    pub fn feature_ids(&self) -> (Vec<u32>, usize) {
        let m = &self.mesh;
        let nv = m.vertex_count();
        let mut loops = Dsu::new(nv);
        for h in m.edges() {
            if self.is_loop(h) {
                loops.union(m.origin(h), m.target(h));
            }
        }
        let mut nest = vec![false; nv];
        for v in 0..nv as u32 {
            if self.is_split(v) {
                let r = loops.find(v);
                nest[r as usize] = true;
            }
        }
        let mut faces = Dsu::new(m.face_count());
        for h in m.edges() {
            let cross = !self.is_loop(h) || !nest[loops.find(m.origin(h)) as usize];
            if cross {
                faces.union(m.face(h), m.face(m.twin(h)));
            }
        }
        let mut label = vec![u32::MAX; m.face_count()];
        let mut ids = Vec::with_capacity(m.face_count());
        let mut count = 0u32;
        for f in 0..m.face_count() as u32 {
            let r = faces.find(f) as usize;
            if label[r] == u32::MAX {
                label[r] = count;
                count += 1;
            }
            ids.push(label[r]);
        }
        (ids, count as usize)
    }

    /// Every feature as its faces (ascending), in order of their first face.
    #[must_use]
    pub fn features(&self) -> Vec<Vec<u32>> {
        let (ids, count) = self.feature_ids();
        let mut out = vec![Vec::new(); count];
        for (f, &i) in ids.iter().enumerate() {
            out[i as usize].push(f as u32);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sphere_is_one_feature_until_a_branch_splits_it_in_three() {
        let mut pm = PolarMesh::uv_sphere(1.0, 8, 4);
        assert_eq!(pm.features().len(), 1);
        assert_eq!(pm.select_feature(0).unwrap().len(), pm.face_count());
        let p = pm.add_feature(&[9, 10, 11]).unwrap();
        // The equator now nests the branch: below it, above it and the branch (§3.4.1).
        let feats = pm.features();
        assert_eq!(feats.len(), 3);
        let fan_face = pm.mesh().face(pm.fan_of(p)[0]);
        let branch = pm.select_feature(i64::from(fan_face)).unwrap();
        assert_eq!(branch.len(), 4);
        assert!(feats.contains(&branch));
        // Local and global agree for every face.
        let (ids, _) = pm.feature_ids();
        for f in 0..pm.face_count() as u32 {
            let sel = pm.select_feature(i64::from(f)).unwrap();
            assert!(sel.iter().all(|&g| ids[g as usize] == ids[f as usize]));
            assert_eq!(sel.len(), feats[ids[f as usize] as usize].len());
        }
        let eq = pm.mesh().find_halfedge(13, 14).unwrap();
        assert!(pm.is_nesting(i64::from(eq)).unwrap());
    }
}
