//! Vertex → edges and vertex → faces of a refined level, written straight from its parent level.
//!
//! The base level derives these relations with counting sorts (`Level::adjacency`): a pass that
//! counts, a prefix sum, and a pass that scatters every edge end and every corner to its vertex in
//! random order. A refined level's relations follow from its parent's instead, as OpenSubdiv's
//! `Vtr::QuadRefinement` / `TriRefinement` populate them (`populateVertexEdgesFromParent*`,
//! `populateVertexFacesFromParent*`): a vertex point has the halves of its vertex's edges and the
//! children at its vertex's corners; an edge point has its edge's two halves and the interior edges
//! and children beside it in each face of the edge; a face point has its face's interior edges and
//! children. The child vertices are numbered vertex points, edge points, face points, so both lists
//! are written front to back with pushes (no counting pass, no fill, no scatter), except the
//! vertex points' children, which are scattered from the parent's corners into the parent's own
//! vertex → face layout.
//!
//! The lists come out exactly as the counting sort orders them (each vertex's ids ascending), which
//! the refinement rules rely on: their sums run in list order, so the refined positions stay bit for
//! bit the same (tested against `Level::adjacency` below).

use super::topology::{Adjacency, Level, NONE};

/// Sorts a short list in place (at most six ids).
#[inline]
fn sorted<const N: usize>(mut a: [u32; N], len: usize) -> [u32; N] {
    a[..len].sort_unstable();
    a
}

impl Level {
    /// The child half of edge `e` at its end `v`: `2 e` at `edge_verts[e][0]`, `2 e + 1` at the
    /// other end (the split both schemes use, `Level::split_edges`).
    #[inline]
    fn half_at(&self, e: u32, v: u32) -> u32 {
        if self.edge_verts[e as usize][0] == v {
            2 * e
        } else {
            2 * e + 1
        }
    }

    /// The vertex points' part of both relations, common to both schemes: each vertex's edge halves
    /// (in its edges' order), and the children at its corners, `child(c)` for corner `c`, ascending
    /// (corners scattered into the parent's vertex → face layout, which orders them by face).
    /// `total_faces` is the room to leave in the returned list for the other child vertices.
    fn vertex_points_adjacency(
        &self,
        child: impl Fn(u32) -> u32,
        total_faces: usize,
        edges: &mut Vec<u32>,
        edge_start: &mut Vec<u32>,
    ) -> Vec<u32> {
        let nv = self.num_vertices;
        for v in 0..nv {
            edges.extend(self.vertex_edges(v).iter().map(|&e| self.half_at(e, v as u32)));
            edge_start.push(edges.len() as u32);
        }
        let mut faces = Vec::with_capacity(total_faces);
        faces.resize(self.face_verts.len(), 0);
        let mut fill = self.vert_face_start[..nv].to_vec();
        for (c, &v) in self.face_verts.iter().enumerate() {
            let slot = &mut fill[v as usize];
            faces[*slot as usize] = child(c as u32);
            *slot += 1;
        }
        faces
    }

    /// The relations of the level one Catmull–Clark step below (ids as `super::refiner` lays them
    /// out), given each parent edge's corner in each of its faces (`corners[e][slot]` for the face
    /// `edge_faces[e][slot]`).
    pub(crate) fn child_adjacency_catmull_clark(&self, corners: &[[u32; 2]]) -> Adjacency {
        let (nv, ne, nf) = (self.num_vertices, self.edge_count(), self.face_count());
        let nc = self.face_verts.len();
        let child_nv = nv + ne + nf;
        let ie = |c: u32| (2 * ne) as u32 + c; // the interior edge of corner c
        let next = |f: u32, c: u32| {
            let f = f as usize;
            if c + 1 == self.face_start[f + 1] {
                self.face_start[f]
            } else {
                c + 1
            }
        };
        let mut edge_start = Vec::with_capacity(child_nv + 1);
        let mut edges = Vec::with_capacity(2 * (2 * ne + nc));
        edge_start.push(0);
        let mut faces = self.vertex_points_adjacency(|c| c, 4 * nc, &mut edges, &mut edge_start);
        let mut face_start = Vec::with_capacity(child_nv + 1);
        face_start.extend_from_slice(&self.vert_face_start);
        // Edge points: the two halves, the interior edge in each face, the children on each side
        // (the one at the corner that starts the edge in that face, and the next).
        for (e, &[c0, c1]) in corners.iter().enumerate() {
            let e32 = e as u32;
            let [f0, f1] = self.edge_faces[e];
            if f1 == NONE {
                edges.extend_from_slice(&[2 * e32, 2 * e32 + 1, ie(c0)]);
                faces.extend_from_slice(&sorted([c0, next(f0, c0)], 2));
            } else {
                let (lo, hi) = if c0 < c1 { (c0, c1) } else { (c1, c0) };
                edges.extend_from_slice(&[2 * e32, 2 * e32 + 1, ie(lo), ie(hi)]);
                faces.extend_from_slice(&sorted([c0, next(f0, c0), c1, next(f1, c1)], 4));
            }
            edge_start.push(edges.len() as u32);
            face_start.push(faces.len() as u32);
        }
        // Face points: the face's interior edges and its children, in corner order.
        for f in 0..nf {
            let r = self.face_range(f);
            edges.extend(r.clone().map(|c| ie(c as u32)));
            faces.extend(r.map(|c| c as u32));
            edge_start.push(edges.len() as u32);
            face_start.push(faces.len() as u32);
        }
        Adjacency { vert_edge_start: edge_start, vert_edges: edges, vert_face_start: face_start, vert_faces: faces }
    }

    /// The relations of the level one Loop step below (ids as `super::refiner` lays them out),
    /// given each parent edge's corner in each of its triangles as for
    /// [`Level::child_adjacency_catmull_clark`].
    pub(crate) fn child_adjacency_loop(&self, corners: &[[u32; 2]]) -> Adjacency {
        let (nv, ne, nf) = (self.num_vertices, self.edge_count(), self.face_count());
        let child_nv = nv + ne;
        // Corner c = 3 f + j: its child 4 f + j; the interior edges at its edge point m_j are
        // 2 ne + 3 f + j (m_j to m_j+1) and 2 ne + 3 f + (j + 2) % 3 (m_j-1 to m_j); the children
        // holding m_j are 4 f + j, 4 f + (j + 1) % 3 and the centre 4 f + 3.
        let split = |c: u32| (c / 3, c % 3);
        let inner = |c: u32| {
            let (f, j) = split(c);
            [(2 * ne) as u32 + 3 * f + j, (2 * ne) as u32 + 3 * f + (j + 2) % 3]
        };
        let kids = |c: u32| {
            let (f, j) = split(c);
            [4 * f + j, 4 * f + (j + 1) % 3, 4 * f + 3]
        };
        let mut edge_start = Vec::with_capacity(child_nv + 1);
        let mut edges = Vec::with_capacity(2 * (2 * ne + 3 * nf));
        edge_start.push(0);
        let mut faces = self.vertex_points_adjacency(|c| c + c / 3, 12 * nf, &mut edges, &mut edge_start);
        let mut face_start = Vec::with_capacity(child_nv + 1);
        face_start.extend_from_slice(&self.vert_face_start);
        for (e, &[c0, c1]) in corners.iter().enumerate() {
            let e32 = e as u32;
            let [a0, b0] = inner(c0);
            let [p0, q0, r0] = kids(c0);
            if self.edge_faces[e][1] == NONE {
                let [a, b] = sorted([a0, b0], 2);
                edges.extend_from_slice(&[2 * e32, 2 * e32 + 1, a, b]);
                faces.extend_from_slice(&sorted([p0, q0, r0], 3));
            } else {
                let [a1, b1] = inner(c1);
                let [p1, q1, r1] = kids(c1);
                let i = sorted([a0, b0, a1, b1], 4);
                edges.extend_from_slice(&[2 * e32, 2 * e32 + 1]);
                edges.extend_from_slice(&i);
                faces.extend_from_slice(&sorted([p0, q0, r0, p1, q1, r1], 6));
            }
            edge_start.push(edges.len() as u32);
            face_start.push(faces.len() as u32);
        }
        Adjacency { vert_edge_start: edge_start, vert_edges: edges, vert_face_start: face_start, vert_faces: faces }
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_meshes::{cube_crease_loop, grid, mixed_torus, tetrahedron};
    use super::super::{Refiner, Scheme};
    use crate::mesh::Mesh;

    #[test]
    fn refined_relations_equal_the_counting_sorts() {
        // Closed and open meshes, n-gons, triangles, an isolated vertex; both schemes, three
        // levels: every refined level's relations, id for id, as the base level's counting sorts
        // would build them.
        let mut lone = grid(2).to_polygons();
        lone.iter_mut().for_each(|f| f.iter_mut().for_each(|v| *v += 1));
        let mut p = vec![crate::math::Vec3::new(9.0, 9.0, 9.0)];
        p.extend_from_slice(grid(2).positions());
        let isolated = Mesh::from_polygons(p, &lone).unwrap();
        let meshes = [
            Mesh::cube(2.0),
            cube_crease_loop(),
            mixed_torus(),
            grid(3),
            isolated,
            tetrahedron(),
            grid(3).triangulate().unwrap(),
            Mesh::icosphere(1.0, 1),
            Mesh::cylinder(1.0, 1.0, 40),
        ];
        for m in &meshes {
            let schemes: &[Scheme] =
                if m.is_triangle_mesh() { &[Scheme::CatmullClark, Scheme::Loop] } else { &[Scheme::CatmullClark] };
            for &scheme in schemes {
                let r = Refiner::new(m, scheme, 4).unwrap();
                for lv in r.levels().iter().skip(1) {
                    let mut sorted = lv.clone();
                    sorted.adjacency();
                    assert_eq!(lv.vert_edge_start, sorted.vert_edge_start, "{scheme:?}");
                    assert_eq!(lv.vert_edges, sorted.vert_edges, "{scheme:?}");
                    assert_eq!(lv.vert_face_start, sorted.vert_face_start, "{scheme:?}");
                    assert_eq!(lv.vert_faces, sorted.vert_faces, "{scheme:?}");
                }
            }
        }
    }
}
