//! Add feature (§4.3): open a gap on a loop and nest a new polar region (a branch) in it.

use super::{PolarError, PolarMesh, Poly, PolyList};
use crate::math::Vec3;

/// Where [`PolarMesh::add_feature_with`] puts the new vertices.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct FeatureOptions {
    /// How far up the backbones the gap's far side lies, as a fraction of each backbone from
    /// the loop to the next loop (or pole). Default value: 0.5.
    pub depth: f64,
    /// How far the new pole stands out of the gap, along the gap's normal, in units of the gap's
    /// mean edge length. Default value: 0.25.
    pub height: f64,
}

impl FeatureOptions {
    /// The defaults: depth 0.5, height 0.25.
    pub const DEFAULT: FeatureOptions = FeatureOptions { depth: 0.5, height: 0.25 };

    /// With `depth` (0 < depth < 1).
    #[must_use]
    pub fn with_depth(mut self, depth: f64) -> FeatureOptions {
        self.depth = depth;
        self
    }

    /// With `height` (any finite number; 0 leaves the pole in the gap's plane).
    #[must_use]
    pub fn with_height(mut self, height: f64) -> FeatureOptions {
        self.height = height;
        self
    }
}

impl Default for FeatureOptions {
    fn default() -> FeatureOptions {
        FeatureOptions::DEFAULT
    }
}

impl PolarMesh {
    /// Add feature (seed 004, §4.3) with [`FeatureOptions::DEFAULT`]; returns the new pole.
    ///
    /// # Errors
    /// See [`PolarMesh::add_feature_with`].
    pub fn add_feature(&mut self, verts: &[u32]) -> Result<u32, PolarError> {
        self.add_feature_with(verts, &FeatureOptions::DEFAULT)
    }

    /// Add feature (seed 004, §4.3): nests a new feature on the run of consecutive loop
    /// vertices `verts = [v0, …, vk]` (k ≥ 2) and returns its pole.
    ///
    /// The gap opens on the side of the faces to the left of `v0 → v1 → …` (counter-clockwise
    /// faces: the side the run turns around when walked in the given order; list the vertices in
    /// the other order for the other side). Each inner vertex's backbone on that side is split at
    /// `depth` (new vertices n1 … n(k−1)); the far side `v0, n1, …, n(k−1), vk` becomes a loop
    /// and the gap `v0 … vk, n(k−1) … n1` a fan around the new pole, which has valence
    /// 2(|VV| − 1) (§4.3.1). When the faces on that side are a pole's triangles, the gap opens
    /// into that polar region. Only the k faces on the run change.
    ///
    /// # Errors
    /// Checked before anything changes:
    /// - [`PolarError::NoSuchElement`], [`PolarError::RepeatedVertex`];
    /// - [`PolarError::FeatureTooSmall`] for fewer than 3 vertices (§4.3.1);
    /// - [`PolarError::FeatureOnPole`] for a pole among them (§4.3.1);
    /// - [`PolarError::NotConsecutive`] for two listed neighbours not joined by an edge;
    /// - [`PolarError::FeatureOnBackbone`] when they are joined by a backbone (§4.3.4 a);
    /// - [`PolarError::FeaturePartialOverlap`] when the run turns, at a split vertex, into the gap
    ///   of a nested feature (§4.3.4 d); running over a whole gap, or along a gap's edges from
    ///   outside, is allowed (§4.3.4 b, c);
    /// - [`PolarError::InvalidArgument`] for a depth outside (0, 1) or a non-finite height;
    /// - [`PolarError::WouldBreakManifold`] when the run would close on itself.
    pub fn add_feature_with(&mut self, verts: &[u32], opts: &FeatureOptions) -> Result<u32, PolarError> {
        if !(opts.depth > 0.0 && opts.depth < 1.0 && opts.height.is_finite()) {
            return Err(PolarError::InvalidArgument(format!(
                "feature depth must lie strictly between 0 and 1 and height be finite, got {} and {}",
                opts.depth, opts.height
            )));
        }
        for &v in verts {
            self.vertex_id(i64::from(v))?;
        }
        if verts.len() < 3 {
            return Err(PolarError::FeatureTooSmall { count: verts.len() });
        }
        if let Some(&v) = verts.iter().find(|&&v| self.is_pole(v)) {
            return Err(PolarError::FeatureOnPole { vertex: v });
        }
        for (i, &v) in verts.iter().enumerate() {
            if verts[..i].contains(&v) {
                return Err(PolarError::RepeatedVertex { vertex: v });
            }
        }
        let m = &self.mesh;
        let k = verts.len() - 1;
        let mut hs = Vec::with_capacity(k);
        for i in 0..k {
            let (a, b) = (verts[i], verts[i + 1]);
            let h = m.find_halfedge(a, b).ok_or(PolarError::NotConsecutive { a, b })?;
            if !self.is_loop(h) {
                return Err(PolarError::FeatureOnBackbone { a, b });
            }
            if i > 0 && m.next(m.twin(m.next(hs[i - 1]))) != h {
                return Err(PolarError::FeaturePartialOverlap { vertex: a });
            }
            hs.push(h);
        }
        // t[i]: the vertex across the top face from v_i (t[i] == pole for a fan).
        let mut t = Vec::with_capacity(k + 1);
        for (i, &h) in hs.iter().enumerate() {
            if m.face_arity(m.face(h)) == 4 {
                t.push(m.origin(m.prev(h)));
            } else {
                t.push(m.target(m.next(h)));
            }
            if i == k - 1 {
                t.push(m.target(m.next(h)));
            }
        }
        let nv = m.vertex_count() as u32;
        let n = |i: usize| nv + i as u32 - 1; // n_i for 1 ≤ i ≤ k−1
        let pole = nv + k as u32 - 1;
        let mut positions: Vec<Vec3> =
            (1..k).map(|i| m.position(verts[i]).lerp(m.position(t[i]), opts.depth)).collect();
        let mut polys = PolyList::with_capacity(3 * k, 10 * k);
        for i in 0..k {
            let a = if i == 0 { verts[0] } else { n(i) };
            let b = if i == k - 1 { verts[k] } else { n(i + 1) };
            let far = self.edge_is_loop(t[i + 1], t[i]).unwrap_or(true);
            let p = Poly { corners: vec![a, b, t[i + 1], t[i]], loops: vec![true, false, far, false] }.dedup();
            polys.push(&p.corners, &p.loops);
        }
        let mut gap: Vec<u32> = verts.to_vec();
        gap.extend((1..k).rev().map(n));
        let gap_pos = |c: u32| if c < nv { m.position(c) } else { positions[(c - nv) as usize] };
        let pts: Vec<Vec3> = gap.iter().map(|&c| gap_pos(c)).collect();
        // Centre and (Newell) normal about the gap's own centre, so a mesh far from the origin
        // keeps its digits.
        let centre = crate::math::mean_point(pts.iter().copied());
        let mut normal = Vec3::ZERO;
        let mut perimeter = 0.0;
        for j in 0..pts.len() {
            let (p, q) = (pts[j], pts[(j + 1) % pts.len()]);
            normal += (p - centre).cross(q - centre);
            perimeter += p.distance(q);
        }
        let normal = normal.normalize_or_zero();
        positions.push(centre + normal * (opts.height * perimeter / pts.len() as f64));
        for j in 0..gap.len() {
            polys.push(&[gap[j], gap[(j + 1) % gap.len()], pole], &[true, false, false]);
        }
        let remove: Vec<u32> = hs.iter().map(|&h| m.face(h)).collect();
        let mut poles = vec![false; k];
        poles[k - 1] = true;
        let log = self.rebuild_list(&remove, &polys, &positions, &poles)?;
        Ok(log.new_vertices()[k - 1])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A UV sphere with 8 segments and 4 bands; its loop at ring 2 (the equator) has vertices
    /// 9..=16.
    fn sphere() -> PolarMesh {
        PolarMesh::uv_sphere(1.0, 8, 4)
    }

    #[test]
    fn feature_on_three_vertices_makes_a_pole_of_valence_four() {
        let mut pm = sphere();
        let (v0, e0, f0) = (pm.vertex_count(), pm.mesh().edge_count(), pm.face_count());
        let p = pm.add_feature(&[9, 10, 11]).unwrap();
        pm.check().unwrap();
        assert!(pm.is_pole(p));
        assert_eq!(pm.valence(p), 4);
        // One new inner vertex n1 and the pole: V+2; faces: 2 top faces stay 2, + 4 fan
        // triangles: F+4; χ unchanged so E+6.
        assert_eq!((pm.vertex_count(), pm.mesh().edge_count(), pm.face_count()), (v0 + 2, e0 + 6, f0 + 4));
        assert!(pm.is_split(9) && pm.is_split(11));
        assert_eq!(pm.valence(10), 4);
    }

    #[test]
    fn limitations_of_add_feature_are_refused_unchanged() {
        let mut pm = sphere();
        let before = pm.clone();
        // §4.3.1: at least three vertices; no poles.
        assert!(matches!(pm.add_feature(&[9, 10]), Err(PolarError::FeatureTooSmall { count: 2 })));
        assert!(matches!(pm.add_feature(&[0, 1, 2]), Err(PolarError::FeatureOnPole { vertex: 0 })));
        // §4.3.4 a: 1 → 9 → 17 follows a meridian backbone.
        let e = pm.add_feature(&[1, 9, 17]).unwrap_err();
        assert!(matches!(e, PolarError::FeatureOnBackbone { a: 1, b: 9 }), "{e}");
        assert!(e.to_string().contains("§4.3.4 a"));
        assert!(matches!(pm.add_feature(&[9, 11, 12]), Err(PolarError::NotConsecutive { a: 9, b: 11 })));
        assert!(matches!(pm.add_feature(&[9, 10, 9]), Err(PolarError::RepeatedVertex { vertex: 9 })));
        assert!(matches!(pm.add_feature(&[9, 10, 99_999]), Err(PolarError::NoSuchElement { .. })));
        assert_eq!(pm, before);
    }

    #[test]
    fn partial_overlap_with_a_nested_gap_is_refused() {
        // §4.3.4 d: after a feature on 9..=11 (gap above the equator), the run 16, 9, 10 walked
        // on the same side turns at split vertex 9 into the gap.
        let mut pm = sphere();
        pm.add_feature(&[9, 10, 11]).unwrap();
        let before = pm.clone();
        let e = pm.add_feature(&[16, 9, 10]).unwrap_err();
        assert!(matches!(e, PolarError::FeaturePartialOverlap { vertex: 9 }), "{e}");
        assert!(e.to_string().contains("§4.3.4 d"));
        assert_eq!(pm, before);
        // §4.3.4 b: another feature on the same loop is fine; §4.3.4 c: one under the gap's
        // edges from the other side too.
        pm.add_feature(&[13, 14, 15]).unwrap();
        pm.add_feature(&[11, 10, 9]).unwrap();
        pm.check().unwrap();
    }
}
