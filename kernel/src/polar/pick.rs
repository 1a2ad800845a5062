//! Picking for scripts: the vertex, half-edge and face nearest to a point (linear scans).

use super::{PolarError, PolarMesh};
use crate::math::{closest_on_triangle, is_finite, Vec3};

fn segment_distance(p: Vec3, a: Vec3, b: Vec3) -> f64 {
    let ab = b - a;
    let l = ab.length_squared();
    let t = if l > 0.0 { ((p - a).dot(ab) / l).clamp(0.0, 1.0) } else { 0.0 };
    p.distance(a + ab * t)
}

impl PolarMesh {
    fn finite_point(p: Vec3) -> Result<Vec3, PolarError> {
        if is_finite(p) {
            Ok(p)
        } else {
            Err(PolarError::NonFinite { what: format!("point {p}") })
        }
    }

    /// The vertex nearest to `p` (the lowest id on ties). Linear time.
    ///
    /// # Errors
    /// [`PolarError::NonFinite`] for a NaN or infinite point.
    pub fn nearest_vertex(&self, p: Vec3) -> Result<u32, PolarError> {
        let p = Self::finite_point(p)?;
        let ps = self.mesh.positions();
        let best = (0..ps.len()).min_by(|&i, &j| ps[i].distance_squared(p).total_cmp(&ps[j].distance_squared(p)));
        best.map(|i| i as u32).ok_or_else(|| PolarError::Internal("a polar mesh has vertices".into()))
    }

    /// The half-edge nearest to `p`: of the nearest edge, the half whose face's centre is nearer
    /// to `p` (the side `p` is on). Linear time.
    ///
    /// # Errors
    /// [`PolarError::NonFinite`] for a NaN or infinite point.
    pub fn nearest_halfedge(&self, p: Vec3) -> Result<u32, PolarError> {
        let p = Self::finite_point(p)?;
        let m = &self.mesh;
        let mut best = (u32::MAX, f64::INFINITY);
        for h in m.edges() {
            let d = segment_distance(p, m.position(m.origin(h)), m.position(m.target(h)));
            if d < best.1 {
                best = (h, d);
            }
        }
        let h = best.0;
        if h == u32::MAX {
            return Err(PolarError::Internal("a polar mesh has edges".into()));
        }
        let t = m.twin(h);
        let dh = m.face_centroid(m.face(h)).distance_squared(p);
        let dt = m.face_centroid(m.face(t)).distance_squared(p);
        Ok(if dt < dh { t } else { h })
    }

    /// The face nearest to `p` (distance to the face's fan triangulation from its first corner;
    /// the lowest id on ties). Linear time.
    ///
    /// # Errors
    /// [`PolarError::NonFinite`] for a NaN or infinite point.
    pub fn nearest_face(&self, p: Vec3) -> Result<u32, PolarError> {
        let p = Self::finite_point(p)?;
        let m = &self.mesh;
        let mut best = (u32::MAX, f64::INFINITY);
        for f in 0..m.face_count() as u32 {
            let c: Vec<Vec3> = m.face_vertices(f).map(|v| m.position(v)).collect();
            for i in 1..c.len() - 1 {
                let d = closest_on_triangle(p, c[0], c[i], c[i + 1]).distance_squared(p);
                if d < best.1 {
                    best = (f, d);
                }
            }
        }
        if best.0 == u32::MAX {
            return Err(PolarError::Internal("a polar mesh has faces".into()));
        }
        Ok(best.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn picks_on_the_octahedron() {
        let pm = PolarMesh::octahedron();
        assert_eq!(pm.nearest_vertex(Vec3::new(0.1, 0.0, 2.0)).unwrap(), 5);
        // Just outside the midpoint of edge 1–2, above the equator: the half-edge lies in an
        // upper face.
        let h = pm.nearest_halfedge(Vec3::new(0.6, 0.6, 0.1)).unwrap();
        let mut ends = pm.ends(h);
        ends.sort_unstable();
        assert_eq!(ends, [1, 2]);
        assert!(pm.mesh().face_vertices(pm.face_of(h)).any(|v| v == 5));
        // The face nearest to a point out along (1, 1, 1) is the one with corners 1, 2, 5.
        let f = pm.nearest_face(Vec3::splat(1.0)).unwrap();
        let mut c: Vec<u32> = pm.mesh().face_vertices(f).collect();
        c.sort_unstable();
        assert_eq!(c, vec![1, 2, 5]);
        assert!(matches!(pm.nearest_face(Vec3::NAN), Err(PolarError::NonFinite { .. })));
    }

    #[test]
    fn closest_point_regions() {
        let (a, b, c) = (Vec3::ZERO, Vec3::X, Vec3::Y);
        let d = closest_on_triangle(Vec3::new(0.2, 0.2, 1.0), a, b, c).distance(Vec3::new(0.2, 0.2, 0.0));
        assert!(d < 1e-15, "distance {d:e}");
        assert_eq!(closest_on_triangle(Vec3::new(-1.0, -1.0, 0.0), a, b, c), a);
        assert_eq!(closest_on_triangle(Vec3::new(0.5, -1.0, 0.0), a, b, c), Vec3::new(0.5, 0.0, 0.0));
    }
}
