//! The iterators of §3.3 — Loop, Parallel, Fan — and the list of all loops.

use super::{PolarError, PolarMesh};

/// One face crossed by an edge ring: the half-edge of the ring edge by which the ring enters it
/// and, unless the ring ends here at a pole, the half-edge by which it leaves.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RingFace {
    pub face: u32,
    pub enter: u32,
    pub leave: Option<u32>,
}

/// An edge ring (the edges parallel to a given one, §3.3.2): its edges as half-edges all
/// pointing the same way, and the faces between consecutive edges.
#[derive(Clone, Debug, Default)]
pub(crate) struct Ring {
    pub edges: Vec<u32>,
    pub faces: Vec<RingFace>,
    pub closed: bool,
}

impl PolarMesh {
    /// The Loop iterator of §3.3.1: the loop or backbone through half-edge `h`, as half-edges in
    /// walking order, each the step `next(twin(next(·)))` of the one before. A loop is a closed
    /// walk starting at `h`; a backbone runs from pole to pole (ends included: the first
    /// half-edge leaves a pole, the last one reaches one) or is closed. At a split vertex the
    /// walk keeps to the side of `h`, so the two halves of a nesting loop's edge walk different
    /// paths (one over the nested gap, one under it).
    ///
    /// # Errors
    /// [`PolarError::NoSuchElement`] for a bad id.
    pub fn walk(&self, h: i64) -> Result<Vec<u32>, PolarError> {
        let h = self.halfedge_id(h)?;
        Ok(self.walk_of(h))
    }

    pub(crate) fn walk_of(&self, h: u32) -> Vec<u32> {
        let m = &self.mesh;
        let cap = m.halfedge_count();
        let mut fwd = vec![h];
        let mut x = h;
        let mut closed = false;
        while !self.is_pole(m.target(x)) && fwd.len() <= cap {
            x = m.next(m.twin(m.next(x)));
            if x == h {
                closed = true;
                break;
            }
            fwd.push(x);
        }
        if closed {
            return fwd;
        }
        let mut back = Vec::new();
        x = h;
        while !self.is_pole(m.origin(x)) && back.len() <= cap {
            x = m.prev(m.twin(m.prev(x)));
            back.push(x);
        }
        back.reverse();
        back.extend(fwd);
        back
    }

    /// The vertices of a walk in order (for a closed walk each once; for an open backbone both
    /// end poles included).
    pub(crate) fn walk_vertices(&self, walk: &[u32]) -> Vec<u32> {
        let m = &self.mesh;
        let mut vs: Vec<u32> = walk.iter().map(|&h| m.origin(h)).collect();
        if let Some(&last) = walk.last() {
            if m.target(last) != m.origin(walk[0]) {
                vs.push(m.target(last));
            }
        }
        vs
    }

    /// The Parallel iterator of §3.3.2: the edges parallel to the edge of `h` — the ring of edges
    /// that faces pass on from one to the opposite one (in a quad the opposite edge, in a pole
    /// triangle the other spoke). A ring of loop edges runs from pole to pole (or is closed); a
    /// ring of backbones is closed. The result starts with `h`; every half-edge points the same
    /// way as `h`, in ring order: a closed ring starts at `h`, an open one runs from one pole
    /// end to the other. These are the edges [`PolarMesh::add_refinement`] splits.
    ///
    /// # Errors
    /// [`PolarError::NoSuchElement`] for a bad id.
    pub fn parallel(&self, h: i64) -> Result<Vec<u32>, PolarError> {
        let h = self.halfedge_id(h)?;
        Ok(self.ring_of(h).edges)
    }

    /// The edge across face(x) from half-edge `x`: the opposite edge of a quad, the other spoke
    /// of a pole triangle; `None` when `x` is the loop edge of a pole triangle (the ring ends).
    fn across(&self, x: u32) -> Option<u32> {
        let m = &self.mesh;
        if m.next(m.next(m.next(x))) == x {
            if self.is_loop(x) {
                return None;
            }
            return Some(if self.is_loop(m.next(x)) { m.prev(x) } else { m.next(x) });
        }
        Some(m.next(m.next(x)))
    }

    pub(crate) fn ring_of(&self, h: u32) -> Ring {
        let m = &self.mesh;
        let cap = m.halfedge_count();
        let mut ring = Ring { edges: vec![h], ..Ring::default() };
        // Forward through face(h).
        let (mut x, mut d) = (h, h);
        loop {
            match self.across(x) {
                None => break,
                Some(y) => {
                    ring.faces.push(RingFace { face: m.face(x), enter: x, leave: Some(y) });
                    let t = m.twin(y);
                    if t == h {
                        ring.closed = true;
                        return ring;
                    }
                    d = if x == d { t } else { y };
                    ring.edges.push(d);
                    x = t;
                }
            }
            if ring.faces.len() > cap {
                break;
            }
        }
        ring.faces.push(RingFace { face: m.face(x), enter: x, leave: None });
        // Backward through face(twin h).
        let mut back_edges = Vec::new();
        let mut back_faces = Vec::new();
        let (mut x, mut d) = (m.twin(h), h);
        loop {
            match self.across(x) {
                None => {
                    back_faces.push(RingFace { face: m.face(x), enter: x, leave: None });
                    break;
                }
                Some(y) => {
                    back_faces.push(RingFace { face: m.face(x), enter: x, leave: Some(y) });
                    d = if x == d { m.twin(y) } else { y };
                    back_edges.push(d);
                    x = m.twin(y);
                }
            }
            if back_faces.len() > cap {
                break;
            }
        }
        back_edges.reverse();
        back_faces.reverse();
        back_edges.extend(ring.edges);
        back_faces.extend(ring.faces);
        ring.edges = back_edges;
        ring.faces = back_faces;
        ring
    }

    /// The Fan iterator of §3.3.3: the half-edges leaving pole `p`, in the order of its loop
    /// (the face of `fan[i]` holds the loop edge from `target(fan[i])` to `target(fan[i + 1])`).
    ///
    /// # Errors
    /// [`PolarError::NoSuchElement`], [`PolarError::NotAPole`].
    pub fn fan(&self, p: i64) -> Result<Vec<u32>, PolarError> {
        let p = self.pole_id(p)?;
        Ok(self.fan_of(p))
    }

    pub(crate) fn fan_of(&self, p: u32) -> Vec<u32> {
        self.mesh.outgoing(p).collect()
    }

    /// Every loop of the mesh once, each as a closed walk ([`PolarMesh::walk`]). A loop without
    /// split vertices is listed once (in one direction); around a nested feature the walks
    /// over, under and around the gap are each listed (they are different loops).
    #[must_use]
    pub fn loops(&self) -> Vec<Vec<u32>> {
        let m = &self.mesh;
        let mut seen = vec![false; m.halfedge_count()];
        let mut out = Vec::new();
        for h in 0..m.halfedge_count() as u32 {
            if !self.is_loop(h) || seen[h as usize] {
                continue;
            }
            let w = self.walk_of(h);
            for &x in &w {
                seen[x as usize] = true;
            }
            // The same loop walked from its other side: skip it when it has the same edges.
            let t = m.twin(h);
            if !seen[t as usize] {
                let wt = self.walk_of(t);
                let same = wt.len() == w.len() && wt.iter().all(|&x| seen[m.twin(x) as usize]);
                if same {
                    for &x in &wt {
                        seen[x as usize] = true;
                    }
                }
            }
            out.push(w);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn octahedron_walks_fans_and_rings() {
        let pm = PolarMesh::octahedron();
        let eq = pm.mesh().find_halfedge(1, 2).unwrap();
        // The equator is one closed loop of 4 edges.
        let w = pm.walk(i64::from(eq)).unwrap();
        assert_eq!(w.len(), 4);
        assert!(w.iter().all(|&h| pm.is_loop(h)));
        // A spoke's backbone runs pole → equator → pole: 2 edges.
        let s = pm.mesh().find_halfedge(0, 1).unwrap();
        let b = pm.walk(i64::from(s)).unwrap();
        assert_eq!(b.len(), 2);
        assert_eq!(pm.mesh().origin(b[0]), 0);
        assert_eq!(pm.mesh().target(b[1]), 5);
        // The fan of a pole has 4 spokes, and its loop order matches the faces.
        let fan = pm.fan(0).unwrap();
        assert_eq!(fan.len(), 4);
        for i in 0..4 {
            let h = fan[i];
            let a = pm.mesh().target(h);
            let b = pm.mesh().target(fan[(i + 1) % 4]);
            let l = pm.mesh().next(h);
            assert_eq!((pm.mesh().origin(l), pm.mesh().target(l)), (a, b));
        }
        // Parallel of a spoke: the 4 spokes of its pole (a closed ring); of an equator edge: one
        // edge, the ring ending at both poles.
        assert_eq!(pm.parallel(i64::from(s)).unwrap().len(), 4);
        assert_eq!(pm.parallel(i64::from(eq)).unwrap(), vec![eq]);
        assert_eq!(pm.loops().len(), 1);
        assert!(matches!(pm.fan(1), Err(PolarError::NotAPole { vertex: 1 })));
    }

    #[test]
    fn uv_sphere_loop_ring_runs_pole_to_pole() {
        let pm = PolarMesh::uv_sphere(1.0, 6, 4);
        // A latitude edge's parallels: one per loop (3 loops), ring from pole to pole.
        let h = pm.mesh().find_halfedge(1, 2).unwrap();
        let p = pm.parallel(i64::from(h)).unwrap();
        assert_eq!(p.len(), 3);
        assert_eq!(p[0], h);
        let ring = pm.ring_of(h);
        assert!(!ring.closed);
        assert_eq!(ring.faces.len(), 4);
        assert_eq!(pm.loops().len(), 3);
    }
}
