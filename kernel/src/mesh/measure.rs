//! Measures: counts, closedness, manifoldness, Euler characteristic, genus, volume, area, centroid,
//! bounds.

use super::{Mesh, NONE};
use crate::limits::LimitError;
use crate::math::{Aabb, Vec3};

/// Every measure at once, computed in one pass over the mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measures {
    pub vertices: usize,
    pub edges: usize,
    pub faces: usize,
    pub boundary_loops: usize,
    pub components: usize,
    pub euler: i64,
    pub genus: i64,
    pub volume: f64,
    pub area: f64,
    pub bounds: Aabb,
}

impl Mesh {
    /// Whether the mesh has no boundary edge.
    #[must_use]
    pub fn is_closed(&self) -> bool {
        self.he_face.iter().all(|&f| f != NONE)
    }

    /// Whether the connectivity is a valid 2-manifold: every half-edge's twin, next and prev are
    /// consistent, every edge has at most two faces, and every vertex's faces form one fan.
    ///
    /// Meshes built by [`Mesh::from_indexed`] always are; this re-verifies the invariants.
    #[must_use]
    pub fn is_manifold(&self) -> bool {
        self.is_manifold_polling(false).unwrap_or(false)
    }

    /// [`Mesh::is_manifold`], polling the current cancellation token every
    /// [`crate::limits::POLL_EVERY`] half-edges and vertices when `poll` (never stopped otherwise).
    ///
    /// # Errors
    /// [`LimitError::Stopped`] when polled and the token stops.
    pub(crate) fn is_manifold_polling(&self, poll: bool) -> Result<bool, LimitError> {
        let tick = |i: usize| if poll { crate::limits::poll_at(i) } else { Ok(()) };
        let nh = self.halfedge_count() as u32;
        for h in 0..nh {
            tick(h as usize)?;
            let (t, n, p) = (self.twin(h), self.next(h), self.prev(h));
            if t >= nh || n >= nh || p >= nh || self.twin(t) != h || self.prev(n) != h || self.next(p) != h {
                return Ok(false);
            }
            if t == h || self.origin(t) != self.origin(n) {
                return Ok(false);
            }
        }
        let mut out_count = vec![0usize; self.vertex_count()];
        for &o in &self.he_origin {
            out_count[o as usize] += 1;
        }
        for v in 0..self.vertex_count() as u32 {
            tick(v as usize)?;
            if self.vertex_out[v as usize] == NONE {
                if out_count[v as usize] != 0 {
                    return Ok(false);
                }
                continue;
            }
            let ring = self.outgoing(v).take(self.halfedge_count() + 1).count();
            if ring != out_count[v as usize] || self.outgoing(v).filter(|&h| self.is_boundary_halfedge(h)).count() > 1 {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// The Euler characteristic V − E + F (counting only vertices used by a face).
    #[must_use]
    pub fn euler(&self) -> i64 {
        let used = self.vertex_out.iter().filter(|&&h| h != NONE).count() as i64;
        used - self.edge_count() as i64 + self.face_count() as i64
    }

    /// Number of connected components (of faces).
    #[must_use]
    pub fn component_count(&self) -> usize {
        self.face_components().len()
    }

    /// The faces of each connected component (faces joined across edges): each list in
    /// ascending order, the components in order of their first face.
    #[must_use]
    pub fn face_components(&self) -> Vec<Vec<u32>> {
        let mut seen = vec![false; self.face_count()];
        let mut stack = Vec::new();
        let mut components = Vec::new();
        for f0 in 0..self.face_count() {
            if seen[f0] {
                continue;
            }
            let mut faces = Vec::new();
            seen[f0] = true;
            stack.push(f0 as u32);
            while let Some(f) = stack.pop() {
                faces.push(f);
                for h in self.face_halfedges(f) {
                    let g = self.face(self.twin(h));
                    if g != NONE && !seen[g as usize] {
                        seen[g as usize] = true;
                        stack.push(g);
                    }
                }
            }
            faces.sort_unstable();
            components.push(faces);
        }
        components
    }

    /// The genus: the number of handles, summed over components, from
    /// χ = 2c − 2g − b (c components, b boundary loops).
    #[must_use]
    pub fn genus(&self) -> i64 {
        let c = self.component_count() as i64;
        let b = self.boundary_loops().len() as i64;
        (2 * c - b - self.euler()) / 2
    }

    /// The vector area of face `f`: its normal scaled by its area (exact for planar faces;
    /// Newell's formula otherwise).
    #[must_use]
    pub fn face_vector_area(&self, f: u32) -> Vec3 {
        let mut hs = self.face_halfedges(f);
        let Some(h0) = hs.next() else { return Vec3::ZERO };
        let p0 = self.position(self.origin(h0));
        let mut sum = Vec3::ZERO;
        for h in hs {
            let a = self.position(self.origin(h)) - p0;
            let b = self.position(self.target(h)) - p0;
            sum += a.cross(b);
        }
        sum * 0.5
    }

    /// The unit normal of face `f` (zero for a degenerate face).
    #[must_use]
    pub fn face_normal(&self, f: u32) -> Vec3 {
        self.face_vector_area(f).normalize_or_zero()
    }

    /// The centroid of face `f`'s corners.
    #[must_use]
    pub fn face_centroid(&self, f: u32) -> Vec3 {
        crate::math::mean_point(self.face_vertices(f).map(|v| self.position(v)))
    }

    /// Area-weighted vertex normals (unit length; zero for isolated vertices).
    #[must_use]
    pub fn vertex_normals(&self) -> Vec<Vec3> {
        let mut normals = vec![Vec3::ZERO; self.vertex_count()];
        for f in 0..self.face_count() as u32 {
            let n = self.face_vector_area(f);
            for v in self.face_vertices(f) {
                normals[v as usize] += n;
            }
        }
        normals.iter().map(|n| n.normalize_or_zero()).collect()
    }

    /// Total surface area: the area of the triangles the mesh is written with
    /// ([`Mesh::triangulate_faces`], or a face's cut about its centre where
    /// [`Mesh::triangulate`] adds one; each face's fan when a face cannot be triangulated),
    /// which is each face's area for planar faces and what a tool reading the written file
    /// (trimesh) reports for non-planar ones. Each triangle's edges are differences of
    /// positions, so the sum does not depend on where the model lies.
    #[must_use]
    pub fn area(&self) -> f64 {
        let (tris, at) = self.measured_triangles();
        tris.chunks_exact(3)
            .map(|t| {
                let a = at(t[0]);
                (at(t[1]) - a).cross(at(t[2]) - a).length()
            })
            .sum::<f64>()
            * 0.5
    }

    /// The triangles area, volume and centroid are summed over: every face's, as written to
    /// files ([`Mesh::plan_triangles`], whose added centres have ids from the vertex count on),
    /// or each face's fan from its first corner when some face cannot be triangulated; with
    /// the position of each id.
    fn measured_triangles(&self) -> (Vec<u32>, impl Fn(u32) -> Vec3 + '_) {
        let (tris, centres) = if (0..self.face_count() as u32).all(|f| self.face_arity(f) == 3) {
            ((0..self.face_count() as u32).flat_map(|f| self.face_vertices(f)).collect(), Vec::new())
        } else if let Ok(plan) = self.plan_triangles_polling(false) {
            (plan.tris, plan.centres.into_iter().map(|(_, c)| c).collect())
        } else {
            let mut tris = Vec::new();
            for f in 0..self.face_count() as u32 {
                let ids: Vec<u32> = self.face_vertices(f).collect();
                for i in 1..ids.len() - 1 {
                    tris.extend_from_slice(&[ids[0], ids[i], ids[i + 1]]);
                }
            }
            (tris, Vec::new())
        };
        let p = &self.positions;
        let at = move |v: u32| p.get(v as usize).copied().unwrap_or_else(|| centres[v as usize - p.len()]);
        (tris, at)
    }

    /// The point every sum about a position is taken about: the centre of the bounds (the
    /// origin for a mesh without faces), so that a model far from the origin loses no digits to
    /// cancellation.
    fn reference_point(&self) -> Vec3 {
        let r = self.bounds();
        if r.is_empty() {
            Vec3::ZERO
        } else {
            r.center()
        }
    }

    /// Area of face `f`: the length of its vector area (its area for a planar face, convex or
    /// not; for a non-planar face the area of its projection on its best-fit plane — see
    /// [`Mesh::area`] for the area of its triangles).
    #[must_use]
    pub fn face_area(&self, f: u32) -> f64 {
        self.face_vector_area(f).length()
    }

    /// Signed enclosed volume by the divergence theorem, Σ over the triangles the mesh is
    /// written with (see [`Mesh::area`]) of det(a − r, b − r, c − r)/6: positive for a closed,
    /// outward-facing mesh. `r` is the centre of the bounds, so that a model far from the origin
    /// loses no digits to cancellation (summed about the origin, an icosphere of radius 1 at
    /// (1e6, 1e6, 1e6) came out at −1135 instead of 4.15).
    #[must_use]
    pub fn volume(&self) -> f64 {
        let r = self.reference_point();
        let (tris, at) = self.measured_triangles();
        let total: f64 = tris
            .chunks_exact(3)
            .map(|t| {
                let [a, b, c] = [t[0], t[1], t[2]].map(|v| at(v) - r);
                a.dot(b.cross(c))
            })
            .sum();
        total / 6.0
    }

    /// The centroid: the centre of mass of the solid the mesh bounds (uniform density; what
    /// trimesh calls `center_mass`), from the same triangles as [`Mesh::volume`], as the
    /// volume-weighted mean of the tetrahedra (r, a, b, c) with r the centre of the bounds, so
    /// that it keeps its digits far from the origin. A mesh enclosing no volume (open, flat or
    /// inside-out to zero) gives the area-weighted centroid of its surface instead; a mesh
    /// without faces the origin.
    #[must_use]
    pub fn centroid(&self) -> Vec3 {
        let r = self.reference_point();
        let (tris, at) = self.measured_triangles();
        let (mut moment, mut six_volume) = (Vec3::ZERO, 0.0);
        let (mut surface, mut twice_area) = (Vec3::ZERO, 0.0);
        // Σ |det|, so that a volume lost in rounding counts as none.
        let mut scale = 0.0;
        for t in tris.chunks_exact(3) {
            let [a, b, c] = [t[0], t[1], t[2]].map(|v| at(v) - r);
            let det = a.dot(b.cross(c));
            moment += (a + b + c) * det;
            six_volume += det;
            scale += det.abs();
            let area = (b - a).cross(c - a).length();
            surface += (a + b + c) * area;
            twice_area += area;
        }
        if six_volume.abs() > 1e-12 * scale && six_volume.is_finite() {
            r + moment / (4.0 * six_volume)
        } else if twice_area > 0.0 {
            r + surface / (3.0 * twice_area)
        } else {
            r
        }
    }

    /// The axis-aligned bounds of the vertices used by faces ([`Aabb::EMPTY`] for none).
    #[must_use]
    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(self.positions.iter().zip(&self.vertex_out).filter(|(_, &h)| h != NONE).map(|(p, _)| p))
    }

    /// Every measure at once.
    #[must_use]
    pub fn measures(&self) -> Measures {
        Measures {
            vertices: self.vertex_count(),
            edges: self.edge_count(),
            faces: self.face_count(),
            boundary_loops: self.boundary_loops().len(),
            components: self.component_count(),
            euler: self.euler(),
            genus: self.genus(),
            volume: self.volume(),
            area: self.area(),
            bounds: self.bounds(),
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::mesh::Mesh;
    use crate::Vec3;

    fn assert_rel(a: f64, b: f64, tol: f64) {
        let d = (a - b).abs() / b.abs().max(1e-300);
        assert!(d <= tol, "got {a}, expected {b}, relative difference {d:e}");
    }

    #[test]
    fn measures_far_from_the_origin_keep_their_digits() {
        // icosphere(1, 3) has volume 4.15 (issue 19: 2.40 at 1e5 and −1135 at 1e6 when summed
        // about the origin). Moving it rounds each coordinate to within half an ulp of the
        // offset (7.5e-9 at 1e8), which moves the volume by at most area × that ≈ 1e-7.
        let m = Mesh::icosphere(1.0, 3);
        let (v, a) = (m.volume(), m.area());
        for offset in [1e3, 1e5, 1e6, 1e7, 1e8] {
            let far = m.translate(Vec3::splat(offset));
            assert_rel(far.volume(), v, 1e-6);
            assert_rel(far.area(), a, 1e-6);
        }
    }

    #[test]
    fn centroid_is_the_centre_of_mass_and_keeps_its_digits_far_away() {
        // A box from (0, 0, 0) to (1, 2, 4) with a unit cube on top of its corner at (0, 0, 4):
        // volume 8 + 1, centre of mass (8·(0.5, 1, 2) + (0.5, 0.5, 4.5)) / 9.
        let a = Mesh::cuboid(Vec3::ZERO, Vec3::new(1.0, 2.0, 4.0));
        let b = Mesh::cuboid(Vec3::new(0.0, 0.0, 4.0), Vec3::new(1.0, 1.0, 5.0));
        let two = Mesh::combine(&[&a, &b]).unwrap();
        let want = (Vec3::new(0.5, 1.0, 2.0) * 8.0 + Vec3::new(0.5, 0.5, 4.5)) / 9.0;
        assert!((two.centroid() - want).length() < 1e-14, "{}", two.centroid());
        // An open surface (one square) has no volume: the centre of its area.
        let sq = Mesh::from_polygons(vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y], &[[0u32, 1, 2, 3]])
            .unwrap();
        assert!((sq.centroid() - Vec3::new(0.5, 0.5, 0.0)).length() < 1e-15);
        // Far away: an icosphere moved by d has its centroid moved by d, to within the rounding
        // of its coordinates (half an ulp of 1e8 is 7.5e-9); summed about the origin the
        // products of coordinates near 1e8 lose every digit.
        let m = Mesh::icosphere(1.0, 3);
        let c0 = m.centroid();
        assert!(c0.length() < 1e-15, "{c0}");
        for offset in [1e3, 1e5, 1e6, 1e7, 1e8] {
            let d = Vec3::new(offset, -offset, 0.5 * offset);
            let c = m.translate(d).centroid() - d;
            assert!(c.length() < 1e-7, "at {offset}: {c}");
        }
        assert_eq!(Mesh::default().centroid(), Vec3::ZERO);
    }

    #[test]
    fn area_of_a_non_planar_quad_is_that_of_its_two_triangles() {
        // A skew quad folded along its diagonal 0–2: triangles (0, 1, 2) of area 1/2 and
        // (0, 2, 3) of area √2/2, 1.207 in all; its vector area is only √3/2 = 0.866 long.
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Z];
        let m = Mesh::from_polygons(p, &[[0u32, 1, 2, 3]]).unwrap();
        let (tris, _) = m.triangulate_faces().unwrap();
        let want: f64 = tris
            .chunks(3)
            .map(|t| (m.position(t[1]) - m.position(t[0])).cross(m.position(t[2]) - m.position(t[0])).length() / 2.0)
            .sum();
        assert_rel(m.area(), want, 1e-15);
        assert_rel(want, 0.5 + 0.5 * 2f64.sqrt(), 1e-15);
        assert!(m.area() > m.face_area(0) + 0.1, "{} vs {}", m.area(), m.face_area(0));
    }

    #[test]
    fn cube_measures_are_exact() {
        // A cube of side 2 has volume 8, area 24, χ = 8 − 12 + 6 = 2, genus 0.
        let m = Mesh::cube(2.0);
        assert!(m.is_closed() && m.is_manifold());
        assert_eq!(m.euler(), 2);
        assert_eq!(m.genus(), 0);
        assert_rel(m.volume(), 8.0, 1e-15);
        assert_rel(m.area(), 24.0, 1e-15);
    }

    #[test]
    fn face_components_list_each_piece_in_order() {
        let a = Mesh::cube(1.0);
        let b = Mesh::cube(1.0).translate(Vec3::new(3.0, 0.0, 0.0));
        let both = Mesh::combine(&[&a, &b]).unwrap();
        let parts = both.face_components();
        assert_eq!(parts, vec![(0..6).collect::<Vec<u32>>(), (6..12).collect()]);
        assert_eq!(both.component_count(), 2);
    }

    #[test]
    fn inverted_cube_has_negative_volume() {
        let m = Mesh::cube(2.0).mirror(Vec3::X);
        assert_rel(m.volume(), 8.0, 1e-15);
        let faces: Vec<Vec<u32>> = m
            .to_polygons()
            .into_iter()
            .map(|mut f| {
                f.reverse();
                f
            })
            .collect();
        let inv = Mesh::from_polygons(m.positions().to_vec(), &faces).unwrap();
        assert_rel(inv.volume(), -8.0, 1e-15);
    }

    #[test]
    fn nonconvex_planar_face_area_is_exact() {
        // An L-shaped hexagon: 2×2 square minus a 1×1 corner = area 3.
        let p = [(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)]
            .iter()
            .map(|&(x, y)| Vec3::new(x, y, 0.0))
            .collect();
        let m = Mesh::from_polygons(p, &[[0, 1, 2, 3, 4, 5]]).unwrap();
        assert_rel(m.area(), 3.0, 1e-15);
        assert_eq!(m.genus(), 0);
        assert!(!m.is_closed());
    }
}
