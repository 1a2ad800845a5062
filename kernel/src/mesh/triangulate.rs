//! Triangulation of polygon faces: a fan for convex faces, spade's constrained Delaunay
//! triangulation in the face's plane for the others.
//!
//! A whole mesh is triangulated face by face with one more rule, so that any valid manifold
//! polygon mesh gives a valid manifold triangle mesh: a face's new edges (its diagonals) must
//! not be an edge of the mesh or another face's diagonal, else the edge would have four
//! triangles. Two quads sharing two consecutive edges (a vertex of valence 2) would otherwise
//! both cut along the same diagonal. When a face's first choice repeats an edge, or fails (a
//! non-planar polygon whose projection crosses itself), the fans from each of its corners are
//! tried, the best-facing first (the one whose worst triangle faces the face's normal most).
//! When every fan repeats an edge too (a quad both of whose diagonals are already edges, as in
//! the five quads of K₅ on a torus), or a non-planar face has no usable fan, the face is cut
//! about a vertex added at the centroid of its corners, one triangle per side: its new edges
//! all end at the new vertex, so they repeat nothing. Only [`Mesh::triangulate`] and the
//! measures can add vertices; [`Mesh::triangulate_faces`], which keeps the vertex ids, refuses
//! such a face.

use spade::handles::FixedVertexHandle;
use spade::{ConstrainedDelaunayTriangulation, Point2, Triangulation};

use super::{Mesh, MeshError};
use crate::math::Vec3;

/// Corners of one polygon triangulated, as triples of positions in `corners`.
type Triangles = Vec<[usize; 3]>;

/// Triangulates the simple polygon `corners` (in order, counter-clockwise about `normal`).
///
/// Convex polygons take a fan from the first corner; others are triangulated by a constrained
/// Delaunay triangulation of the corners projected onto the plane of `normal`, keeping the
/// triangles inside (found by a flood fill that flips at every polygon edge).
///
/// # Errors
/// A reason string when the projected polygon has coincident corners or crosses itself.
pub fn triangulate_polygon(corners: &[Vec3], normal: Vec3) -> Result<Triangles, String> {
    let k = corners.len();
    if k < 3 {
        return Err(format!("it has {k} corners"));
    }
    if k == 3 {
        return Ok(vec![[0, 1, 2]]);
    }
    let n = crate::math::direction(normal).ok_or_else(|| "its corners are collinear (zero area)".to_string())?;
    let is_convex = (0..k).all(|i| {
        let (a, b, c) = (corners[i], corners[(i + 1) % k], corners[(i + 2) % k]);
        (b - a).cross(c - b).dot(n) > 0.0
    }) && (k < 5 || turns_once(corners, n));
    if is_convex {
        return Ok((1..k - 1).map(|i| [0, i, i + 1]).collect());
    }
    let (u, v) = n.any_orthonormal_pair();
    let mut cdt = ConstrainedDelaunayTriangulation::<Point2<f64>>::new();
    let mut handles: Vec<FixedVertexHandle> = Vec::with_capacity(k);
    for p in corners {
        let h = cdt
            .insert(Point2::new(p.dot(u), p.dot(v)))
            .map_err(|e| format!("a corner cannot be placed in the face's plane ({e:?})"))?;
        handles.push(h);
    }
    if cdt.num_vertices() != k {
        return Err("two corners coincide in the face's plane".to_string());
    }
    for i in 0..k {
        let (a, b) = (handles[i], handles[(i + 1) % k]);
        if !cdt.can_add_constraint(a, b) || cdt.try_add_constraint(a, b).len() != 1 {
            return Err(format!("the polygon crosses itself near its edge {i}–{}", (i + 1) % k));
        }
    }
    // Flood fill from the outer face: crossing a constraint edge flips inside/outside.
    let mut inside: Vec<Option<bool>> = vec![None; cdt.num_all_faces()];
    let mut stack = Vec::new();
    for e in cdt.convex_hull() {
        let f = e.rev().face();
        if let Some(inner) = f.as_inner() {
            let state = e.is_constraint_edge();
            if inside[inner.fix().index()].is_none() {
                inside[inner.fix().index()] = Some(state);
                stack.push(inner.fix());
            }
        }
    }
    while let Some(fh) = stack.pop() {
        let state = inside[fh.index()].unwrap_or(false);
        for e in cdt.face(fh).adjacent_edges() {
            if let Some(g) = e.rev().face().as_inner() {
                let s = state ^ e.is_constraint_edge();
                if inside[g.fix().index()].is_none() {
                    inside[g.fix().index()] = Some(s);
                    stack.push(g.fix());
                }
            }
        }
    }
    let triangles: Triangles = cdt
        .inner_faces()
        .filter(|f| inside[f.fix().index()] == Some(true))
        .map(|f| {
            let [a, b, c] = f.vertices();
            [a.fix().index(), b.fix().index(), c.fix().index()]
        })
        .collect();
    if triangles.len() != k - 2 {
        return Err(format!("the polygon is not simple ({} triangles inside, {} expected)", triangles.len(), k - 2));
    }
    Ok(triangles)
}

/// The edges of the triangles `t` of a `k`-gon that are not edges of the polygon (corner
/// indices, each once).
fn new_edges(t: &[[usize; 3]], k: usize) -> impl Iterator<Item = (usize, usize)> + '_ {
    t.iter()
        .flat_map(|tri| [(tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])])
        .filter(move |&(a, b)| (a + 1) % k != b && (b + 1) % k != a && a < b)
}

/// Whether the polygon `corners`, turning left at every corner about `n`, turns once in all
/// (a convex polygon) rather than two or more times (a star, such as a pentagram): the turning
/// angles, measured in the plane of `n`, add up to 2π. A polygon of at most four corners that
/// turns left everywhere turns once.
fn turns_once(corners: &[Vec3], n: Vec3) -> bool {
    let k = corners.len();
    let (u, v) = n.any_orthonormal_pair();
    let d = |i: usize| {
        let e = corners[(i + 1) % k] - corners[i % k];
        (e.dot(u), e.dot(v))
    };
    let total: f64 = (0..k)
        .map(|i| {
            let ((ax, ay), (bx, by)) = (d(i), d(i + 1));
            (ax * by - ay * bx).atan2(ax * bx + ay * by)
        })
        .sum();
    total < 3.0 * std::f64::consts::PI
}

/// Whether the polygon `corners` lies in a plane of normal `normal`, up to 1e-9 of its size.
fn is_planar(corners: &[Vec3], normal: Vec3) -> bool {
    let Some(n) = normal.try_normalize() else { return true };
    let d: Vec<f64> = corners.iter().map(|p| (*p - corners[0]).dot(n)).collect();
    let spread = d.iter().copied().fold(f64::NEG_INFINITY, f64::max) - d.iter().copied().fold(f64::INFINITY, f64::min);
    let size = corners.iter().map(|p| (*p - corners[0]).length()).fold(0.0, f64::max);
    spread <= 1e-9 * size
}

/// Work allowed for trying fans on one face, in fan triangles: a polygon of `k` corners tries
/// the fans from all its corners while `k² ≤ FAN_WORK`, else from `FAN_WORK / k` corners spread
/// evenly (at least [`MIN_FANS`]), so that the fallback costs O(k) time and memory for any `k`
/// (all `k` fans of a 20,000-gon held 4·10⁸ triangles).
const FAN_WORK: usize = 1 << 20;

/// Corners from which a face polls the cancellation token by itself while it is triangulated.
const LONG_FACE: usize = 4096;

/// The fewest corners whose fans a long polygon tries: 0, 1, the last, and spread ones.
const MIN_FANS: usize = 16;

/// The fan of the `k`-gon from corner `i`: `k − 2` triangles `(i, i+j, i+j+1)`.
fn fan(i: usize, k: usize) -> impl Iterator<Item = [usize; 3]> {
    (1..k - 1).map(move |j| [i, (i + j) % k, (i + j + 1) % k])
}

/// The corners whose fans are tried on the polygon `corners`, best first, each with its worst
/// facing: the smallest dot product of a fan triangle's vector area with `normal`; largest
/// first, ties by corner order. Every corner while `k² ≤ FAN_WORK`, else a spread subset
/// (see [`FAN_WORK`]); O(min(k², FAN_WORK) + k) time and O(candidates) memory. Build a fan's
/// triangles with [`fan`].
fn fans_best_first(corners: &[Vec3], normal: Vec3) -> Vec<(f64, usize)> {
    let k = corners.len();
    let tries = if k.saturating_mul(k) <= FAN_WORK { k } else { (FAN_WORK / k).clamp(MIN_FANS.min(k), k) };
    // Corners 0, 1 and k − 1 (next to the first corner, whose own diagonals a neighbour's
    // reverse face may already use), then spread evenly.
    let from: Vec<usize> = if tries == k {
        (0..k).collect()
    } else {
        let mut v: Vec<usize> = [0, 1, k - 1].into_iter().chain((1..tries - 3).map(|j| j * k / (tries - 3))).collect();
        v.sort_unstable();
        v.dedup();
        v
    };
    let mut fans: Vec<(f64, usize)> = from
        .into_iter()
        .map(|i| {
            let worst = fan(i, k)
                .map(|[a, b, c]| (corners[b] - corners[a]).cross(corners[c] - corners[a]).dot(normal))
                .fold(f64::INFINITY, f64::min);
            (worst, i)
        })
        .collect();
    fans.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    fans
}

/// A triangulation of every face, planned by [`Mesh::plan_triangles`].
pub(crate) struct FaceTriangles {
    /// Vertex-id triples, each face's triangles consecutively; ids from the mesh's vertex
    /// count on are the added centres, in order.
    pub tris: Vec<u32>,
    /// Each face's arity.
    pub arities: Vec<u32>,
    /// For each face cut about an added centre, the face and the centre's position.
    pub centres: Vec<(u32, Vec3)>,
}

impl FaceTriangles {
    /// Number of triangles of each face: arity − 2, or the arity for a face cut about a centre.
    pub fn counts(&self) -> Vec<u32> {
        let mut counts: Vec<u32> = self.arities.iter().map(|&a| a - 2).collect();
        for &(f, _) in &self.centres {
            counts[f as usize] += 2;
        }
        counts
    }
}

impl Mesh {
    /// The triangles of face `f`, as vertex-id triples oriented like the face.
    ///
    /// # Errors
    /// [`MeshError::Triangulation`] when the face, projected onto its best-fit plane (Newell
    /// normal), is not a simple polygon.
    pub fn triangulate_face(&self, f: u32) -> Result<Vec<[u32; 3]>, MeshError> {
        let ids: Vec<u32> = self.face_vertices(f).collect();
        let corners: Vec<Vec3> = ids.iter().map(|&v| self.position(v)).collect();
        let tris = triangulate_polygon(&corners, self.face_vector_area(f))
            .map_err(|reason| MeshError::Triangulation { face: f as usize, reason })?;
        Ok(tris.into_iter().map(|[a, b, c]| [ids[a], ids[b], ids[c]]).collect())
    }

    /// The triangles of every face, each face's consecutively, and each face's arity; no
    /// diagonal repeats an edge (see the module documentation), so the triangles make a
    /// manifold mesh whenever the faces do.
    ///
    /// The first triangle of face `f` starts at the face's first vertex `v0` and holds its first
    /// edge `v0 → v1`, so walking the boundary of a face's triangles from `v0` gives back the
    /// face in its own order (how the glTF reader re-joins polygons).
    ///
    /// Output: (3·T indices, F arities).
    ///
    /// # Errors
    /// [`MeshError::Triangulation`] naming the first face whose every fan repeats an edge (a
    /// face both of whose diagonals are already edges, such as a quad over a tetrahedron's
    /// edge); [`MeshError::TooLarge`] for more than 2³² − 1 triangles.
    pub fn triangulate_faces(&self) -> Result<(Vec<u32>, Vec<u32>), MeshError> {
        let plan = self.plan_triangles()?;
        if let Some(&(face, _)) = plan.centres.first() {
            return Err(MeshError::Triangulation {
                face: face as usize,
                reason: "every way to cut it between its corners repeats an edge of the mesh (triangulate() \
                         cuts it about a vertex added at its centre)"
                    .into(),
            });
        }
        Ok((plan.tris, plan.arities))
    }

    /// The triangles of every face as [`Mesh::triangulate_faces`] describes, except that a face
    /// no cut between its corners fits is cut about an added centre (see the module
    /// documentation) instead of refused.
    ///
    /// # Errors
    /// [`MeshError::Triangulation`] naming the first planar face that crosses itself (or whose
    /// centre is not finite); [`MeshError::TooLarge`] for more than 2³² − 1 triangles or
    /// vertices; [`MeshError::Limit`] when the current cancellation token stops (polled every
    /// [`crate::limits::POLL_EVERY`] faces).
    pub(crate) fn plan_triangles(&self) -> Result<FaceTriangles, MeshError> {
        self.plan_triangles_polling(true)
    }

    /// [`Mesh::plan_triangles`], polling the cancellation token or not: measures, which cannot
    /// fail, plan without polling so that a stop never changes what they return.
    pub(crate) fn plan_triangles_polling(&self, poll: bool) -> Result<FaceTriangles, MeshError> {
        let mut centres: Vec<(u32, Vec3)> = Vec::new();
        let mut tris = Vec::with_capacity(3 * self.face_count() * 2);
        let mut arities = Vec::with_capacity(self.face_count());
        let mut diagonals: std::collections::HashSet<(u32, u32)> = std::collections::HashSet::new();
        let mut ids: Vec<u32> = Vec::with_capacity(8);
        let mut corners: Vec<Vec3> = Vec::with_capacity(8);
        for f in 0..self.face_count() as u32 {
            if poll {
                crate::limits::poll_at(f as usize)?;
            }
            ids.clear();
            ids.extend(self.face_vertices(f));
            let k = ids.len();
            arities.push(k as u32);
            if k == 3 {
                tris.extend_from_slice(&ids);
                continue;
            }
            corners.clear();
            corners.extend(ids.iter().map(|&v| self.position(v)));
            let normal = if k == 4 {
                (corners[2] - corners[0]).cross(corners[3] - corners[1]) / 2.0
            } else {
                self.face_vector_area(f)
            };
            let fresh = |t: &[[usize; 3]], diagonals: &std::collections::HashSet<(u32, u32)>| {
                new_edges(t, k).all(|(a, b)| {
                    let (a, b) = (ids[a], ids[b]);
                    self.find_halfedge(a, b).is_none() && !diagonals.contains(&(a.min(b), a.max(b)))
                })
            };
            // A long face is work enough to poll about on its own (its Delaunay triangulation,
            // each fan it tries).
            let long = poll && k >= LONG_FACE;
            if long {
                crate::limits::poll()?;
            }
            let first = triangulate_polygon(&corners, normal);
            let t = match first {
                Ok(t) if fresh(&t, &diagonals) => t,
                first => {
                    // A planar face takes only fans that keep every triangle facing its normal
                    // (else triangles would overlap); a non-planar one any fan. Areas beyond
                    // f64's range stay an error.
                    let planar = is_planar(&corners, normal);
                    // Each fan is built only when tried, so that memory stays O(k).
                    let mut scratch: Triangles = Vec::new();
                    let mut found = false;
                    for (worst, i) in fans_best_first(&corners, normal) {
                        if long {
                            crate::limits::poll()?;
                        }
                        if !worst.is_finite() || (planar && worst <= 0.0) {
                            continue;
                        }
                        scratch.clear();
                        scratch.extend(fan(i, k));
                        if fresh(&scratch, &diagonals) {
                            found = true;
                            break;
                        }
                    }
                    match (found, first) {
                        (true, _) => scratch,
                        (false, Err(reason)) if planar => {
                            return Err(MeshError::Triangulation { face: f as usize, reason })
                        }
                        (false, _) => {
                            // Cut about a new vertex at the centroid: one triangle per side,
                            // the side v0 → v1 first.
                            let c = crate::math::mean_point(corners.iter().copied());
                            if !c.is_finite() {
                                return Err(MeshError::Triangulation {
                                    face: f as usize,
                                    reason: "its centre is beyond the range of numbers".into(),
                                });
                            }
                            let id = u32::try_from(self.vertex_count() + centres.len())
                                .ok()
                                .filter(|&id| id != u32::MAX)
                                .ok_or_else(|| MeshError::TooLarge {
                                    what: "vertices with the added centres".into(),
                                })?;
                            centres.push((f, c));
                            for i in 0..k {
                                tris.extend_from_slice(&[ids[i], ids[(i + 1) % k], id]);
                            }
                            continue;
                        }
                    }
                }
            };
            diagonals.extend(new_edges(&t, k).map(|(a, b)| (ids[a].min(ids[b]), ids[a].max(ids[b]))));
            // The triangle holding the first edge goes first, starting at the first corner.
            let at = tris.len();
            for tri in &t {
                tris.extend(tri.iter().map(|&c| ids[c]));
            }
            let first = t
                .iter()
                .position(|tri| (0..3).any(|i| tri[i] == 0 && tri[(i + 1) % 3] == 1))
                .ok_or_else(|| MeshError::Internal(format!("face {f}'s triangles lack its first edge")))?;
            for i in 0..3 {
                tris.swap(at + i, at + 3 * first + i);
            }
            let r = (0..3).position(|i| tris[at + i] == ids[0]).unwrap_or(0);
            tris[at..at + 3].rotate_left(r);
        }
        if tris.len() / 3 > u32::MAX as usize {
            return Err(MeshError::TooLarge { what: format!("{} triangles", tris.len() / 3) });
        }
        Ok(FaceTriangles { tris, arities, centres })
    }

    /// A triangle mesh of the same surface: same vertices (ids kept), each face split into
    /// triangles (see [`Mesh::triangulate_faces`]), and a vertex added at the centre of each
    /// face that no cut between its corners fits (ids from the vertex count on; see the module
    /// documentation), so that any manifold polygon mesh gives a manifold triangle mesh. Crease
    /// tags, corners, colours (an added vertex takes the mean of its face's), face sources and
    /// face parts kept. Returns also, for each triangle, the face it came from.
    ///
    /// # Errors
    /// [`MeshError::Triangulation`] naming the first face that cannot be triangulated (a planar
    /// face that crosses itself).
    pub fn triangulate_with_sources(&self) -> Result<(Mesh, Vec<u32>), MeshError> {
        let plan = self.plan_triangles()?;
        let sources: Vec<u32> =
            plan.counts().iter().enumerate().flat_map(|(f, &n)| std::iter::repeat_n(f as u32, n as usize)).collect();
        let mut positions = self.positions.clone();
        positions.extend(plan.centres.iter().map(|&(_, c)| c));
        let mut m = Mesh::from_indexed(positions, &plan.tris, &vec![3; sources.len()])?;
        m.copy_attributes_from(self);
        m.vertex_sharpness.resize(m.vertex_count(), 0.0);
        if let Some(colors) = &mut m.vertex_colors {
            for &(f, _) in &plan.centres {
                let (sum, n) = self.face_vertices(f).fold(([0.0f32; 4], 0.0f32), |(mut s, n), v| {
                    for (a, b) in s.iter_mut().zip(colors[v as usize]) {
                        *a += b;
                    }
                    (s, n + 1.0)
                });
                colors.push(sum.map(|c| c / n));
            }
        }
        if let Some(fs) = &self.face_sources {
            m.face_sources = Some(sources.iter().map(|&f| fs[f as usize]).collect());
        }
        m.inherit_parts(self, &sources)?;
        Ok((m, sources))
    }

    /// A triangle mesh of the same surface; see [`Mesh::triangulate_with_sources`].
    ///
    /// # Errors
    /// [`MeshError::Triangulation`] naming the first face that cannot be triangulated.
    pub fn triangulate(&self) -> Result<Mesh, MeshError> {
        self.triangulate_with_sources().map(|(m, _)| m)
    }

    /// Number of triangles this mesh triangulates into (Σ (arity − 2)).
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        (0..self.face_count() as u32).map(|f| self.face_arity(f) - 2).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn l_shape_triangulates_inside_only() {
        // The L-shaped hexagon of area 3: its four triangles must cover exactly that area.
        let p: Vec<Vec3> = [(0., 0.), (2., 0.), (2., 1.), (1., 1.), (1., 2.), (0., 2.)]
            .iter()
            .map(|&(x, y)| Vec3::new(x, y, 0.0))
            .collect();
        let m = Mesh::from_polygons(p, &[[0, 1, 2, 3, 4, 5]]).unwrap();
        let t = m.triangulate().unwrap();
        assert_eq!(t.face_count(), 4);
        assert!((t.area() - 3.0).abs() < 1e-14);
        for f in 0..4 {
            assert!(t.face_normal(f).z > 0.99, "triangle {f} flipped");
        }
    }

    #[test]
    fn triangulated_solids_keep_volume_and_area() {
        for m in [Mesh::cube(2.0), Mesh::cylinder(1.0, 2.0, 9), Mesh::torus(2.0, 0.5, 8, 6)] {
            let t = m.triangulate().unwrap();
            assert!(t.is_closed() && t.is_triangle_mesh());
            assert_eq!(t.face_count(), m.triangle_count());
            assert!((t.volume() - m.volume()).abs() < 1e-12);
            assert_eq!(t.genus(), m.genus());
        }
    }

    /// Checks that `t` is a closed manifold triangle mesh with Euler characteristic 2.
    fn assert_closed_sphere(t: &Mesh) {
        assert!(t.is_triangle_mesh() && t.is_closed() && t.is_manifold());
        let chi = t.vertex_count() as i64 - t.edge_count() as i64 + t.face_count() as i64;
        assert_eq!(chi, 2);
    }

    #[test]
    fn quads_sharing_two_consecutive_edges_get_different_diagonals() {
        // Two skew quads glued along all four edges (every vertex of valence 2, as in
        // OpenSubdiv's catmark_val2 shapes). The second quad starts at b, so its fan from its
        // first corner would cut along b–a, the diagonal the first quad took: an edge of four
        // triangles. It must take v–c instead: a tetrahedron.
        let p = vec![Vec3::ZERO, Vec3::new(1.0, 0.0, 0.5), Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 0.5)];
        let (a, v, b, c) = (0, 1, 2, 3);
        let m = Mesh::from_polygons(p, &[[a, v, b, c], [b, v, a, c]]).unwrap();
        let t = m.triangulate().unwrap();
        assert_closed_sphere(&t);
        assert!(t.find_halfedge(a, b).is_some() && t.find_halfedge(v, c).is_some());
        // The tetrahedron's volume: det(v − a, b − a, c − a) / 6 = 1/6 (these faces wind inward).
        assert!((t.volume().abs() - 1.0 / 6.0).abs() < 1e-12, "{}", t.volume());
        // The io path writes the same triangles.
        let (tris, _) = m.triangulate_faces().unwrap();
        assert_eq!(tris.len(), 12);
    }

    #[test]
    fn non_planar_polygon_whose_projection_crosses_itself_triangulates() {
        // A pentagram (a pentagon that winds twice around the z axis), climbing so that it does
        // not meet itself in 3D: its projection crosses itself, so the Delaunay triangulation
        // refuses it; a fan does not. Glued to its reverse, it is a closed sphere of two faces,
        // and the second face must avoid the first one's diagonals.
        let p: Vec<Vec3> = (0..5)
            .map(|i| {
                let a = f64::from(i) * 4.0 * std::f64::consts::PI / 5.0;
                Vec3::new(a.cos(), a.sin(), f64::from(i) * 0.3)
            })
            .collect();
        let m = Mesh::from_polygons(p, &[vec![0, 1, 2, 3, 4], vec![4, 3, 2, 1, 0]]).unwrap();
        assert!(m.triangulate_face(0).is_err(), "the projection crosses itself");
        let t = m.triangulate().unwrap();
        assert_closed_sphere(&t);
        assert_eq!(t.face_count(), 6);
    }

    /// K₅ on a torus as five quads (every pair of the five vertices is an edge, so both
    /// diagonals of every quad are edges already), on a skew pentagon.
    fn k5_torus() -> Mesh {
        let p: Vec<Vec3> = (0..5)
            .map(|i| {
                let a = f64::from(i) * std::f64::consts::TAU / 5.0;
                Vec3::new(a.cos(), a.sin(), 0.3 * f64::from(i % 2) + 0.1 * f64::from(i))
            })
            .collect();
        Mesh::from_polygons(p, &[[0u32, 1, 2, 3], [0, 2, 4, 1], [0, 4, 3, 2], [0, 3, 1, 4], [1, 3, 4, 2]]).unwrap()
    }

    #[test]
    fn quads_whose_diagonals_are_both_edges_are_cut_about_their_centres() {
        let m = k5_torus();
        assert!(m.is_closed() && m.is_manifold());
        assert_eq!((m.edge_count(), m.euler()), (10, 0));
        // Keeping the vertex ids, no quad can be cut.
        assert!(matches!(m.triangulate_faces(), Err(MeshError::Triangulation { face: 0, .. })));
        let (t, from) = m.triangulate_with_sources().unwrap();
        // Each quad: four triangles about a new vertex at the mean of its corners.
        assert!(t.is_triangle_mesh() && t.is_closed() && t.is_manifold());
        assert_eq!((t.vertex_count(), t.face_count(), t.euler(), t.genus()), (10, 20, 0, 1));
        assert_eq!(from, (0..5).flat_map(|f| [f; 4]).collect::<Vec<u32>>());
        for f in 0..5u32 {
            assert!((t.position(5 + f) - m.face_centroid(f)).length() < 1e-15);
            // The first triangle holds the face's first edge.
            let first: Vec<u32> = t.face_vertices(4 * f).collect();
            let face: Vec<u32> = m.face_vertices(f).collect();
            assert_eq!(first, vec![face[0], face[1], 5 + f]);
        }
        // The measures use the same triangles.
        assert!((t.area() - m.area()).abs() < 1e-14 && (t.volume() - m.volume()).abs() < 1e-14);
        assert!(m.area() > (0..5).map(|f| m.face_area(f)).sum::<f64>() * 0.5);
    }

    #[test]
    fn a_cut_about_a_centre_colours_the_centre_by_its_face() {
        let mut m = k5_torus();
        let colors: Vec<[f32; 4]> = (0..5).map(|i| [i as f32 / 4.0, 0.5, 1.0, 1.0]).collect();
        m.set_vertex_colors(Some(colors)).unwrap();
        m.set_corner_sharpness(2, 3.0);
        let t = m.triangulate().unwrap();
        let c = t.vertex_colors().unwrap();
        assert_eq!(c.len(), 10);
        // Face 0 has corners 0–3: red (0 + 0.25 + 0.5 + 0.75) / 4.
        assert_eq!(c[5], [0.375, 0.5, 1.0, 1.0]);
        assert_eq!(t.corner_sharpness(2), 3.0);
        assert_eq!(t.corner_sharpness(7), 0.0);
    }

    #[test]
    fn self_crossing_polygon_is_an_error() {
        // A bow-tie quadrilateral: edges 1–2 and 3–0 cross.
        let p: Vec<Vec3> =
            [(0., 0.), (2., 2.), (2., 0.), (0., 2.), (1., 3.)].iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect();
        let m = Mesh::from_polygons(p, &[[0, 2, 1, 3, 4]]).unwrap();
        assert!(matches!(m.triangulate(), Err(MeshError::Triangulation { face: 0, .. })));
    }

    /// A closed "pillow" of two `k`-gons glued along all their edges: the polygon
    /// `r(i) (cos θᵢ, sin θᵢ)` and its reverse, starting at the same corner, so that the second
    /// face's first choice repeats the first face's diagonals and the fallback runs.
    fn pillow(k: usize, r: impl Fn(usize) -> f64) -> Mesh {
        let p: Vec<Vec3> = (0..k)
            .map(|i| {
                let a = i as f64 * std::f64::consts::TAU / k as f64;
                Vec3::new(r(i) * a.cos(), r(i) * a.sin(), 0.0)
            })
            .collect();
        let front: Vec<u32> = (0..k as u32).collect();
        let back: Vec<u32> = std::iter::once(0).chain((1..k as u32).rev()).collect();
        Mesh::from_polygons(p, &[front, back]).unwrap()
    }

    #[test]
    fn long_polygons_whose_first_cut_repeats_triangulate_in_linear_memory() {
        // 20,000 corners, the OBJ of issue 33: trying every fan held k² = 4·10⁸ triangles (an
        // abort at 1.8 GB). A convex disk's back face takes the fan from its second corner; a
        // star's (no fan faces its normal everywhere) is cut about its centre. Both stay closed
        // spheres, and quickly: each takes a bounded number of O(k) fans.
        let k = 20_000;
        for (m, centres) in [(pillow(k, |_| 1.0), 0), (pillow(k, |i| if i % 2 == 0 { 1.0 } else { 0.5 }), 1)] {
            let t0 = std::time::Instant::now();
            let t = m.triangulate().unwrap();
            assert!(t0.elapsed().as_secs_f64() < 5.0, "{:?}", t0.elapsed());
            assert_closed_sphere(&t);
            assert_eq!(t.vertex_count(), k + centres);
            assert!((t.area() - 2.0 * m.face_area(0)).abs() < 1e-9 * m.face_area(0), "{} {}", t.area(), m.face_area(0));
        }
    }
}
