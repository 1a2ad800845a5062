//! Merge features (§4.6): replace two pole fans by a ring of quads bridging their loops.

use super::{PolarError, PolarMesh, Poly};

impl PolarMesh {
    /// Merge features (seed 004, §4.6): removes the fans of poles `p1` and `p2` and bridges their
    /// loops with a ring of quads, making one annular region. Loop vertices are paired with the
    /// cyclic shift (the only pairings that keep the orientation) of least total distance, which
    /// avoids twisting the bridge (§4.6.3). The poles are deleted. Merging two parts of one
    /// connected mesh adds a handle (genus + 1); merging two separate parts joins them.
    ///
    /// Time proportional to the square of the valence (the pairing search) plus the fans.
    ///
    /// # Errors
    /// Checked before anything changes: [`PolarError::NoSuchElement`], [`PolarError::NotAPole`],
    /// [`PolarError::SamePole`], [`PolarError::ValenceMismatch`] (§4.6.4: valences must match),
    /// [`PolarError::SharedLoopVertex`] when the two loops share a vertex, and
    /// [`PolarError::WouldBreakManifold`] when a paired vertex is already joined to its partner
    /// (the two loops are one ring apart: add a refinement between them first).
    pub fn merge_features(&mut self, p1: i64, p2: i64) -> Result<(), PolarError> {
        let p1 = self.pole_id(p1)?;
        let p2 = self.pole_id(p2)?;
        if p1 == p2 {
            return Err(PolarError::SamePole { vertex: p1 });
        }
        let m = &self.mesh;
        let (f1, f2) = (self.fan_of(p1), self.fan_of(p2));
        let n = f1.len();
        if f2.len() != n {
            return Err(PolarError::ValenceMismatch { poles: [p1, p2], valences: [n, f2.len()] });
        }
        let a: Vec<u32> = f1.iter().map(|&h| m.target(h)).collect();
        let b: Vec<u32> = f2.iter().map(|&h| m.target(h)).collect();
        if let Some(&v) = a.iter().find(|v| b.contains(v)) {
            return Err(PolarError::SharedLoopVertex { vertex: v });
        }
        // a_i pairs with b_(c − i): the quad (a_i, a_(i+1), b_(c−i−1), b_(c−i)) then runs along
        // both loops in their fans' directions.
        let sigma = |c: usize, i: usize| (c + n - i % n) % n;
        let cost = |c: usize| (0..n).map(|i| m.position(a[i]).distance(m.position(b[sigma(c, i)]))).sum::<f64>();
        let mut best = (0, f64::INFINITY);
        for c in 0..n {
            let d = cost(c);
            if d < best.1 {
                best = (c, d);
            }
        }
        let c = best.0;
        let mut polys = Vec::with_capacity(n);
        for i in 0..n {
            let j = (i + 1) % n;
            polys.push(Poly {
                corners: vec![a[i], a[j], b[sigma(c, j)], b[sigma(c, i)]],
                loops: vec![true, false, true, false],
            });
        }
        let remove: Vec<u32> = f1.iter().chain(&f2).map(|&h| m.face(h)).collect();
        self.rebuild(&remove, &polys, &[], &[])?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn merging_two_poles_of_a_sphere_makes_a_torus() {
        // A UV sphere's poles are 4 rings apart: bridging them gives genus 1, no poles, and
        // removes 2 vertices and 2·8 − 8 faces.
        let mut pm = PolarMesh::uv_sphere(1.0, 8, 5);
        let (v0, f0) = (pm.vertex_count(), pm.face_count());
        let north = pm.vertex_count() as i64 - 1;
        pm.merge_features(0, north).unwrap();
        pm.check().unwrap();
        assert_eq!((pm.vertex_count(), pm.face_count()), (v0 - 2, f0 - 8));
        assert_eq!(pm.mesh().genus(), 1);
        assert!(pm.poles().is_empty());
    }

    #[test]
    fn pairing_follows_least_distance() {
        // Each south loop vertex has a north loop vertex straight above it; the least-distance
        // pairing bridges exactly those pairs.
        let mut pm = PolarMesh::uv_sphere(1.0, 6, 6);
        let north = pm.vertex_count() as i64 - 1;
        let south_loop: Vec<u32> = pm.fan_of(0).iter().map(|&h| pm.mesh().target(h)).collect();
        pm.merge_features(0, north).unwrap();
        for &v in &south_loop {
            let p = pm.position(v);
            let straight = pm.mesh().vertex_neighbors(v).any(|w| {
                let q = pm.position(w);
                (q - p).truncate().length() < 1e-9 && q.z > p.z + 1.0
            });
            assert!(straight, "vertex {v} at {p} is not bridged straight up");
        }
    }

    #[test]
    fn merge_limitations_are_refused_unchanged() {
        let mut pm = PolarMesh::octahedron();
        let before = pm.clone();
        assert!(matches!(pm.merge_features(0, 0), Err(PolarError::SamePole { vertex: 0 })));
        assert!(matches!(pm.merge_features(0, 1), Err(PolarError::NotAPole { vertex: 1 })));
        // The octahedron's poles share the equator.
        assert!(matches!(pm.merge_features(0, 5), Err(PolarError::SharedLoopVertex { .. })));
        assert_eq!(pm, before);
        // §4.6.4: a feature's pole of valence 4 cannot merge with a pole of valence 8.
        let mut pm = PolarMesh::uv_sphere(1.0, 8, 4);
        let p = pm.add_feature(&[9, 10, 11]).unwrap();
        let before = pm.clone();
        let e = pm.merge_features(i64::from(p), 0).unwrap_err();
        assert!(matches!(e, PolarError::ValenceMismatch { valences: [4, 8], .. }), "{e}");
        assert!(e.to_string().contains("§4.6.4"));
        assert_eq!(pm, before);
        // Loops one ring apart: every bridge edge already exists.
        let mut pm = PolarMesh::uv_sphere(1.0, 8, 3);
        let before = pm.clone();
        let north = pm.vertex_count() as i64 - 1;
        assert!(matches!(pm.merge_features(0, north), Err(PolarError::WouldBreakManifold(_))));
        assert_eq!(pm, before);
    }
}
