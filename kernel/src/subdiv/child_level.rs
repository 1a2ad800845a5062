//! The topology one step down: the child [`Level`] of a Catmull–Clark or Loop step, built from its
//! parent in a few linear passes (OpenSubdiv's `Vtr::QuadRefinement` / `TriRefinement`). Child
//! ids follow the layout of `super::refiner`: vertex points, edge points, then face points; each
//! parent edge `e` splits into child edges `2 e` and `2 e + 1`, and the interior edges follow.
//! The child's vertex → edges and vertex → faces relations come from `super::child_adjacency`.

use super::topology::{decrement, Level, NONE};

impl Level {
    /// The first `2 ne` child edges of one step, both schemes: each parent edge `e` splits at its
    /// edge point `m` into `2 e` = (a, m) and `2 e + 1` = (m, b), with their sharpness one level
    /// down and their faces not yet known (`NONE`, which stays in the second slot of a boundary
    /// edge's halves). Edge verts and faces come back with room for `child_ne` edges, for the
    /// interior edges the face pass pushes in order; the sharpness list is complete (interior
    /// edges are smooth). Written in one pass with pushes, so no list is filled first.
    fn split_edges(&self, child_ne: usize) -> (Vec<[u32; 2]>, Vec<[u32; 2]>, Vec<f32>) {
        let nv = self.num_vertices;
        let mut edge_verts = Vec::with_capacity(child_ne);
        let mut edge_faces = Vec::with_capacity(child_ne);
        let mut edge_sharpness = Vec::with_capacity(child_ne);
        for (e, &[a, b]) in self.edge_verts.iter().enumerate() {
            let m = (nv + e) as u32;
            edge_verts.extend_from_slice(&[[a, m], [m, b]]);
            edge_faces.extend_from_slice(&[[NONE; 2]; 2]);
            edge_sharpness.extend_from_slice(&self.child_sharpness(e));
        }
        edge_sharpness.resize(child_ne, 0.0);
        (edge_verts, edge_faces, edge_sharpness)
    }

    /// The corner sharpness of the `child_nv` vertices one step down: each vertex point keeps
    /// its vertex's, decremented; edge and face points have none.
    fn child_vertex_sharpness(&self, child_nv: usize) -> Vec<f32> {
        let mut out = Vec::with_capacity(child_nv);
        out.extend(self.vertex_sharpness.iter().map(|&s| decrement(s)));
        out.resize(child_nv, 0.0);
        out
    }

    /// The topology of one Catmull–Clark step (see [`super::refiner`] for the id layout).
    pub(crate) fn refine_catmull_clark(&self) -> Result<Level, crate::limits::LimitError> {
        let (nv, ne, nf) = (self.num_vertices, self.edge_count(), self.face_count());
        let ncorner = self.face_verts.len();
        let child_nv = nv + ne + nf;
        let child_ne = 2 * ne + ncorner;
        let (mut edge_verts, mut edge_faces, edge_sharpness) = self.split_edges(child_ne);
        // Each edge's corner in each of its faces, for the child adjacency.
        let mut corners = vec![[0u32; 2]; ne];
        let mut face_start = Vec::with_capacity(ncorner + 1);
        let mut face_verts = Vec::with_capacity(4 * ncorner);
        let mut face_edges = Vec::with_capacity(4 * ncorner);
        for f in 0..nf {
            crate::limits::poll_at(f)?;
            let r = self.face_range(f);
            let (s, n) = (r.start, r.len());
            let fp = (nv + ne + f) as u32;
            for k in 0..n {
                let kp = if k == 0 { n - 1 } else { k - 1 };
                let kn = if k + 1 == n { 0 } else { k + 1 };
                let v = self.face_verts[s + k];
                let (ek, ep) = (self.face_edges[s + k] as usize, self.face_edges[s + kp] as usize);
                let child = face_start.len() as u32; // child face id = s + k
                face_start.push(face_verts.len() as u32);
                face_verts.extend_from_slice(&[v, (nv + ek) as u32, fp, (nv + ep) as u32]);
                let half_k = if self.edge_verts[ek][0] == v { 2 * ek } else { 2 * ek + 1 };
                let half_p = if self.edge_verts[ep][0] == v { 2 * ep } else { 2 * ep + 1 };
                face_edges.extend_from_slice(&[
                    half_k as u32,
                    (2 * ne + s + k) as u32,
                    (2 * ne + s + kp) as u32,
                    half_p as u32,
                ]);
                // The two halves of edge ek: the one at v lies in child k, the other in child k+1.
                let slot = usize::from(self.edge_faces[ek][0] != f as u32);
                corners[ek][slot] = (s + k) as u32;
                let other_half = half_k ^ 1;
                edge_faces[half_k][slot] = child;
                edge_faces[other_half][slot] = (s + kn) as u32;
                // Interior edge of corner k (edge 2 ne + s + k, pushed in corner order): edge
                // point of ek to the face point, in children k, k+1.
                edge_verts.push([(nv + ek) as u32, fp]);
                edge_faces.push([child, (s + kn) as u32]);
            }
        }
        face_start.push(face_verts.len() as u32);
        let vertex_sharpness = self.child_vertex_sharpness(child_nv);
        let mut level = Level {
            num_vertices: child_nv,
            face_start,
            face_verts,
            face_edges,
            edge_verts,
            edge_faces,
            edge_sharpness,
            vertex_sharpness,
            creasing: self.creasing,
            ..Level::default()
        };
        level.derive(self.child_adjacency_catmull_clark(&corners));
        Ok(level)
    }

    /// The topology of one Loop step of a triangle mesh (see [`super::refiner`] for the id layout).
    pub(crate) fn refine_loop(&self) -> Result<Level, crate::limits::LimitError> {
        let (nv, ne, nf) = (self.num_vertices, self.edge_count(), self.face_count());
        let child_nv = nv + ne;
        let child_ne = 2 * ne + 3 * nf;
        let (mut edge_verts, mut edge_faces, edge_sharpness) = self.split_edges(child_ne);
        let mut corners = vec![[0u32; 2]; ne];
        let mut face_verts = Vec::with_capacity(12 * nf);
        let mut face_edges = Vec::with_capacity(12 * nf);
        for f in 0..nf {
            crate::limits::poll_at(f)?;
            let s = 3 * f;
            let v = [self.face_verts[s], self.face_verts[s + 1], self.face_verts[s + 2]];
            let e = [self.face_edges[s] as usize, self.face_edges[s + 1] as usize, self.face_edges[s + 2] as usize];
            let m = [(nv + e[0]) as u32, (nv + e[1]) as u32, (nv + e[2]) as u32];
            let interior = |k: usize| (2 * ne + 3 * f + k) as u32;
            for k in 0..3 {
                let kp = (k + 2) % 3;
                let child = (4 * f + k) as u32;
                face_verts.extend_from_slice(&[v[k], m[k], m[kp]]);
                let half_k = if self.edge_verts[e[k]][0] == v[k] { 2 * e[k] } else { 2 * e[k] + 1 };
                let half_p = if self.edge_verts[e[kp]][0] == v[k] { 2 * e[kp] } else { 2 * e[kp] + 1 };
                face_edges.extend_from_slice(&[half_k as u32, interior(kp), half_p as u32]);
                let slot = usize::from(self.edge_faces[e[k]][0] != f as u32);
                corners[e[k]][slot] = (s + k) as u32;
                edge_faces[half_k][slot] = child;
                edge_faces[half_k ^ 1][slot] = (4 * f + (k + 1) % 3) as u32;
                // Interior edge k (edge 2 ne + 3 f + k, pushed in that order) joins m[k] and
                // m[k+1]: in the centre child and in child k+1.
                edge_verts.push([m[k], m[(k + 1) % 3]]);
                edge_faces.push([(4 * f + 3) as u32, (4 * f + (k + 1) % 3) as u32]);
            }
            face_verts.extend_from_slice(&m);
            face_edges.extend_from_slice(&[interior(0), interior(1), interior(2)]);
        }
        let face_start = (0..=4 * nf as u32).map(|i| 3 * i).collect();
        let vertex_sharpness = self.child_vertex_sharpness(child_nv);
        let mut level = Level {
            num_vertices: child_nv,
            face_start,
            face_verts,
            face_edges,
            edge_verts,
            edge_faces,
            edge_sharpness,
            vertex_sharpness,
            creasing: self.creasing,
            ..Level::default()
        };
        level.derive(self.child_adjacency_loop(&corners));
        Ok(level)
    }
}
