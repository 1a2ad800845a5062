//! Triangulation of polygon faces: a fan for convex faces, spade's constrained Delaunay
//! triangulation in the face's plane for the others.

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
    let n = normal.try_normalize().ok_or_else(|| "its corners are collinear (zero area)".to_string())?;
    let is_convex = (0..k).all(|i| {
        let (a, b, c) = (corners[i], corners[(i + 1) % k], corners[(i + 2) % k]);
        (b - a).cross(c - b).dot(n) > 0.0
    });
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

    /// A triangle mesh of the same surface: same vertices (ids kept), each face split into
    /// triangles (see [`Mesh::triangulate_face`]); crease tags, corners, colours and face sources kept.
    /// Returns also, for each triangle, the face it came from.
    ///
    /// # Errors
    /// [`MeshError::Triangulation`] naming the first face that cannot be triangulated.
    pub fn triangulate_with_sources(&self) -> Result<(Mesh, Vec<u32>), MeshError> {
        let mut tris = Vec::with_capacity(self.face_count() * 2);
        let mut sources = Vec::with_capacity(self.face_count() * 2);
        for f in 0..self.face_count() as u32 {
            for t in self.triangulate_face(f)? {
                tris.push(t);
                sources.push(f);
            }
        }
        let flat: Vec<u32> = tris.iter().flatten().copied().collect();
        let mut m = Mesh::from_indexed(self.positions.clone(), &flat, &vec![3; tris.len()])?;
        m.copy_attributes_from(self);
        if let Some(fs) = &self.face_sources {
            m.face_sources = Some(sources.iter().map(|&f| fs[f as usize]).collect());
        }
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

    #[test]
    fn self_crossing_polygon_is_an_error() {
        // A bow-tie quadrilateral: edges 1–2 and 3–0 cross.
        let p: Vec<Vec3> =
            [(0., 0.), (2., 2.), (2., 0.), (0., 2.), (1., 3.)].iter().map(|&(x, y)| Vec3::new(x, y, 0.0)).collect();
        let m = Mesh::from_polygons(p, &[[0, 2, 1, 3, 4]]).unwrap();
        assert!(matches!(m.triangulate(), Err(MeshError::Triangulation { face: 0, .. })));
    }
}
