//! Frames and the low-level modelling of §2.4: move, scale and rotate any set of vertices, in
//! global axes or in a local frame (the loop's own centre and normal) — the frames whose lack
//! §5.2 names as the prototype's weakness.

use super::{PolarError, PolarMesh};
use crate::math::{is_finite, Quat, Vec3};

/// The axes a low-level operation works in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Frame {
    /// World axes x, y, z. Default value.
    #[default]
    Global,
    /// The selection's own frame ([`PolarMesh::selection_frame`]): x along the tangent, y along
    /// the bitangent, z along the normal.
    Local,
}

/// A local frame: an origin and three orthonormal axes (tangent × bitangent = normal).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LoopFrame {
    /// The centre: the mean of the vertices.
    pub center: Vec3,
    /// The unit normal of the best plane; for a loop it follows the right-hand rule along the
    /// walk (towards the side of the faces the walk turns around).
    pub normal: Vec3,
    /// A unit axis in the plane, pointing from the centre towards the first vertex.
    pub tangent: Vec3,
    /// `normal × tangent`.
    pub bitangent: Vec3,
}

impl LoopFrame {
    /// The global direction of the local vector `v` = (x along tangent, y along bitangent,
    /// z along normal).
    #[must_use]
    pub fn to_global(&self, v: Vec3) -> Vec3 {
        self.tangent * v.x + self.bitangent * v.y + self.normal * v.z
    }

    fn from_normal(center: Vec3, normal: Vec3, first: Vec3) -> LoopFrame {
        let normal = normal.try_normalize().unwrap_or(Vec3::Z);
        let d = first - center;
        let tangent = (d - normal * d.dot(normal)).try_normalize().unwrap_or_else(|| normal.any_orthonormal_vector());
        LoopFrame { center, normal, tangent, bitangent: normal.cross(tangent) }
    }
}

/// Eigen-decomposition of a symmetric 3×3 matrix by cyclic Jacobi rotations: the eigenvector of
/// the smallest eigenvalue.
fn smallest_eigenvector(mut a: [[f64; 3]; 3]) -> Vec3 {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..50 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        if off < 1e-300 {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q].abs() < 1e-300 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            for row in &mut a {
                let (akp, akq) = (row[p], row[q]);
                row[p] = c * akp - s * akq;
                row[q] = s * akp + c * akq;
            }
            let (rp, rq) = (a[p], a[q]);
            a[p] = std::array::from_fn(|k| c * rp[k] - s * rq[k]);
            a[q] = std::array::from_fn(|k| s * rp[k] + c * rq[k]);
            for row in &mut v {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    let i = (0..3).min_by(|&i, &j| a[i][i].total_cmp(&a[j][j])).unwrap_or(2);
    Vec3::new(v[0][i], v[1][i], v[2][i])
}

impl PolarMesh {
    /// The frame of the loop (or backbone) through half-edge `h`: the centre of its walk's
    /// vertices, and for a closed walk the normal of its polygon (Newell), oriented by the
    /// right-hand rule along the walk; for an open walk the principal-axes normal.
    ///
    /// # Errors
    /// [`PolarError::NoSuchElement`].
    pub fn loop_frame(&self, h: i64) -> Result<LoopFrame, PolarError> {
        let h = self.halfedge_id(h)?;
        let walk = self.walk_of(h);
        let verts = self.walk_vertices(&walk);
        let closed = self.mesh.target(walk[walk.len() - 1]) == self.mesh.origin(walk[0]);
        if !closed {
            return Ok(self.principal_frame(&verts));
        }
        Ok(self.polygon_frame(&verts))
    }

    fn polygon_frame(&self, verts: &[u32]) -> LoopFrame {
        let pts: Vec<Vec3> = verts.iter().map(|&v| self.position(v)).collect();
        let center = crate::math::mean_point(pts.iter().copied());
        let mut n = Vec3::ZERO;
        for i in 0..pts.len() {
            n += (pts[i] - center).cross(pts[(i + 1) % pts.len()] - center);
        }
        LoopFrame::from_normal(center, n, pts[0])
    }

    fn principal_frame(&self, verts: &[u32]) -> LoopFrame {
        let m = &self.mesh;
        let pts: Vec<Vec3> = verts.iter().map(|&v| m.position(v)).collect();
        let center = crate::math::mean_point(pts.iter().copied());
        let mut c = [[0.0; 3]; 3];
        for p in &pts {
            let d = (*p - center).to_array();
            for i in 0..3 {
                for j in 0..3 {
                    c[i][j] += d[i] * d[j];
                }
            }
        }
        let mut normal = smallest_eigenvector(c);
        let mut sum = Vec3::ZERO;
        for &v in verts {
            for f in m.vertex_faces(v) {
                sum += m.face_vector_area(f);
            }
        }
        if normal.dot(sum) < 0.0 || (normal.dot(sum) == 0.0 && normal.z < 0.0) {
            normal = -normal;
        }
        LoopFrame::from_normal(center, normal, pts[0])
    }

    /// The local frame of a vertex selection: when the selection is exactly the vertices of a
    /// loop, that loop's centre and plane normal (see [`PolarMesh::loop_frame`]), turned so that
    /// its largest component is positive (a horizontal loop's normal is +z); otherwise the centre
    /// of the vertices and the normal of their best-fitting plane (principal axes), turned to the
    /// side the surface at them faces. The tangent points towards the first vertex.
    ///
    /// # Errors
    /// [`PolarError::EmptySelection`], [`PolarError::NoSuchElement`].
    pub fn selection_frame(&self, verts: &[u32]) -> Result<LoopFrame, PolarError> {
        let verts = self.selection(verts)?;
        let m = &self.mesh;
        let mut sorted = verts.clone();
        sorted.sort_unstable();
        for h in m.outgoing(verts[0]).filter(|&h| self.is_loop(h)) {
            let walk = self.walk_of(h);
            if walk.len() != verts.len() {
                continue;
            }
            let mut wv = self.walk_vertices(&walk);
            let ordered = wv.clone();
            wv.sort_unstable();
            if wv == sorted {
                let mut f = self.polygon_frame(&ordered);
                // A loop has no preferred direction here: turn the normal so that its largest
                // component is positive (a horizontal loop's normal points up, +z).
                let n = f.normal;
                let big = if n.x.abs() >= n.y.abs() && n.x.abs() >= n.z.abs() {
                    n.x
                } else if n.y.abs() >= n.z.abs() {
                    n.y
                } else {
                    n.z
                };
                if big < 0.0 {
                    f = LoopFrame::from_normal(f.center, -n, self.position(ordered[0]));
                }
                return Ok(f);
            }
        }
        Ok(self.principal_frame(&verts))
    }

    /// Checks ids and removes repeats, keeping the first occurrence order.
    fn selection(&self, verts: &[u32]) -> Result<Vec<u32>, PolarError> {
        if verts.is_empty() {
            return Err(PolarError::EmptySelection);
        }
        let mut seen: crate::math::IdSet<u32> = crate::math::IdSet::default();
        let mut out = Vec::with_capacity(verts.len());
        for &v in verts {
            self.vertex_id(i64::from(v))?;
            if seen.insert(v) {
                out.push(v);
            }
        }
        Ok(out)
    }

    /// Applies `f` to the positions of `verts`: all new positions are computed and checked
    /// before any is written.
    fn map_selection(&mut self, verts: &[u32], f: impl Fn(Vec3) -> Vec3) -> Result<(), PolarError> {
        let new: Vec<(u32, Vec3)> = verts.iter().map(|&v| (v, f(self.position(v)))).collect();
        if let Some(&(v, p)) = new.iter().find(|(_, p)| !is_finite(*p)) {
            return Err(PolarError::NonFinite { what: format!("the new position {p} of vertex {v}") });
        }
        for (v, p) in new {
            self.mesh.set_position(v, p).map_err(|e| PolarError::Internal(e.to_string()))?;
        }
        Ok(())
    }

    /// Moves vertex `v` to `position` (low-level modelling; the topology never changes).
    ///
    /// # Errors
    /// [`PolarError::NoSuchElement`], [`PolarError::NonFinite`]; nothing moves on error.
    pub fn set_position(&mut self, v: u32, position: Vec3) -> Result<(), PolarError> {
        self.vertex_id(i64::from(v))?;
        let p = Self::checked("position", position)?;
        self.mesh.set_position(v, p).map_err(|e| PolarError::Internal(e.to_string()))
    }

    /// The vertices within distance `radius` of `center`, ascending (a linear scan): a
    /// selection for the low-level operations.
    ///
    /// # Errors
    /// [`PolarError::NonFinite`] for a non-finite centre or radius.
    pub fn vertices_near(&self, center: Vec3, radius: f64) -> Result<Vec<u32>, PolarError> {
        let c = Self::checked("centre", center)?;
        if !radius.is_finite() {
            return Err(PolarError::NonFinite { what: format!("radius {radius}") });
        }
        let r2 = radius * radius;
        Ok((0..self.vertex_count() as u32).filter(|&v| self.position(v).distance_squared(c) <= r2).collect())
    }

    fn checked(what: &str, v: Vec3) -> Result<Vec3, PolarError> {
        if is_finite(v) {
            Ok(v)
        } else {
            Err(PolarError::NonFinite { what: format!("{what} {v}") })
        }
    }

    /// Moves the vertices `verts` by `offset`, given in world axes ([`Frame::Global`]) or in the
    /// selection's local frame ([`Frame::Local`], see [`PolarMesh::selection_frame`]). The
    /// topology never changes (§2.4 low-level modelling). Repeated ids move once.
    ///
    /// # Errors
    /// [`PolarError::EmptySelection`], [`PolarError::NoSuchElement`], [`PolarError::NonFinite`]
    /// (nothing moves on error).
    pub fn move_vertices(&mut self, verts: &[u32], offset: Vec3, frame: Frame) -> Result<(), PolarError> {
        let verts = self.selection(verts)?;
        let offset = Self::checked("offset", offset)?;
        let d = match frame {
            Frame::Global => offset,
            Frame::Local => self.selection_frame(&verts)?.to_global(offset),
        };
        self.map_selection(&verts, |p| p + d)
    }

    /// Scales the vertices `verts` by `factors` (per axis of the frame) about `center` (default:
    /// the selection's centre). In [`Frame::Local`] the axes are the selection frame's tangent,
    /// bitangent and normal: `(s, s, 1)` widens a loop in its own plane.
    ///
    /// # Errors
    /// [`PolarError::EmptySelection`], [`PolarError::NoSuchElement`], [`PolarError::NonFinite`].
    pub fn scale_vertices(
        &mut self,
        verts: &[u32],
        factors: Vec3,
        center: Option<Vec3>,
        frame: Frame,
    ) -> Result<(), PolarError> {
        let verts = self.selection(verts)?;
        let factors = Self::checked("scale factor", factors)?;
        let fr = self.selection_frame(&verts)?;
        let c = Self::checked("centre", center.unwrap_or(fr.center))?;
        match frame {
            Frame::Global => self.map_selection(&verts, |p| c + (p - c) * factors),
            Frame::Local => self.map_selection(&verts, |p| {
                let d = p - c;
                let l = Vec3::new(d.dot(fr.tangent), d.dot(fr.bitangent), d.dot(fr.normal)) * factors;
                c + fr.to_global(l)
            }),
        }
    }

    /// Turns the vertices `verts` by `degrees` about `axis` (in the frame's axes: in
    /// [`Frame::Local`], `(0, 0, 1)` is the selection's normal) through `center` (default: the
    /// selection's centre); right-handed.
    ///
    /// # Errors
    /// [`PolarError::EmptySelection`], [`PolarError::NoSuchElement`], [`PolarError::NonFinite`],
    /// [`PolarError::InvalidArgument`] for a zero axis.
    pub fn rotate_vertices(
        &mut self,
        verts: &[u32],
        axis: Vec3,
        degrees: f64,
        center: Option<Vec3>,
        frame: Frame,
    ) -> Result<(), PolarError> {
        let verts = self.selection(verts)?;
        let axis = Self::checked("axis", axis)?;
        if !degrees.is_finite() {
            return Err(PolarError::NonFinite { what: format!("angle {degrees}") });
        }
        let fr = self.selection_frame(&verts)?;
        let c = Self::checked("centre", center.unwrap_or(fr.center))?;
        let axis = match frame {
            Frame::Global => axis,
            Frame::Local => fr.to_global(axis),
        };
        let axis =
            axis.try_normalize().ok_or_else(|| PolarError::InvalidArgument("the rotation axis is zero".into()))?;
        let q = Quat::from_axis_angle(axis, degrees.to_radians());
        self.map_selection(&verts, |p| c + q * (p - c))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn assert_close(a: Vec3, b: Vec3) {
        let d = a.distance(b);
        assert!(d < 1e-12, "got {a}, expected {b}, distance {d:e}");
    }

    #[test]
    fn equator_frame_is_centred_with_vertical_normal() {
        let pm = PolarMesh::uv_sphere(2.0, 8, 4);
        let h = pm.mesh().find_halfedge(9, 10).unwrap();
        let f = pm.loop_frame(i64::from(h)).unwrap();
        assert_close(f.center, Vec3::ZERO);
        // 9 → 10 runs counter-clockwise seen from +z: the normal is +z.
        assert_close(f.normal, Vec3::Z);
        assert!((f.tangent.dot(f.normal)).abs() < 1e-12);
        // The selection of the same vertices in any order finds the same frame.
        let s = pm.selection_frame(&[12, 9, 10, 11, 13, 14, 15, 16]).unwrap();
        assert_close(s.normal, Vec3::Z);
    }

    #[test]
    fn local_scale_widens_a_tilted_loop_in_its_own_plane() {
        let mut pm = PolarMesh::uv_sphere(1.0, 8, 4);
        let all: Vec<u32> = (0..pm.vertex_count() as u32).collect();
        pm.rotate_vertices(&all, Vec3::X, 90.0, Some(Vec3::ZERO), Frame::Global).unwrap();
        let eq: Vec<u32> = (9..=16).collect();
        pm.scale_vertices(&eq, Vec3::new(2.0, 2.0, 1.0), None, Frame::Local).unwrap();
        // The equator, now in the plane y = 0 (the x–z plane), has radius 2 there.
        for &v in &eq {
            let p = pm.position(v);
            assert!(p.y.abs() < 1e-12 && (p.length() - 2.0).abs() < 1e-12, "{p}");
        }
        pm.check().unwrap();
    }

    #[test]
    fn local_move_follows_the_loop_normal() {
        let mut pm = PolarMesh::uv_sphere(1.0, 8, 4);
        let eq: Vec<u32> = (9..=16).collect();
        let before: Vec<Vec3> = eq.iter().map(|&v| pm.position(v)).collect();
        pm.move_vertices(&eq, Vec3::new(0.0, 0.0, 0.5), Frame::Local).unwrap();
        for (i, &v) in eq.iter().enumerate() {
            assert_close(pm.position(v), before[i] + Vec3::Z * 0.5);
        }
    }

    #[test]
    fn bad_low_level_input_is_refused_unchanged() {
        let mut pm = PolarMesh::octahedron();
        let before = pm.clone();
        assert!(matches!(pm.move_vertices(&[], Vec3::X, Frame::Global), Err(PolarError::EmptySelection)));
        assert!(matches!(pm.move_vertices(&[99], Vec3::X, Frame::Global), Err(PolarError::NoSuchElement { .. })));
        assert!(matches!(pm.move_vertices(&[1], Vec3::NAN, Frame::Global), Err(PolarError::NonFinite { .. })));
        assert!(matches!(
            pm.rotate_vertices(&[1, 2], Vec3::ZERO, 10.0, None, Frame::Global),
            Err(PolarError::InvalidArgument(_))
        ));
        // A huge factor overflows to infinity: refused before anything moves.
        assert!(matches!(
            pm.scale_vertices(&[1, 2, 3], Vec3::splat(1e308), Some(Vec3::new(-1e10, 0.0, 0.0)), Frame::Global),
            Err(PolarError::NonFinite { .. })
        ));
        assert_eq!(pm, before);
    }

    #[test]
    fn jacobi_finds_the_flat_direction() {
        let n = smallest_eigenvector([[4.0, 1.0, 0.0], [1.0, 3.0, 0.0], [0.0, 0.0, 0.01]]);
        assert!((n.z.abs() - 1.0).abs() < 1e-12, "{n}");
    }
}
