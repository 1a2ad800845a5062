//! Refinement topology: one level of a mesh as flat arrays, without positions.
//!
//! Notation: `nv`, `ne`, `nf` vertex, edge and face counts of a level. Faces are stored in CSR form
//! (`face_start`, `face_verts`), with `face_edges[i]` the edge from corner `i` to the next corner.
//! Each edge keeps its two end vertices and its one or two faces (the second is [`NONE`] on a
//! boundary). Vertex → edges and vertex → faces adjacency is derived once per level by counting
//! sorts, and so is each vertex's subdivision rule. Nothing here hashes or allocates per element:
//! building a level is a handful of linear passes over flat arrays (OpenSubdiv's `Vtr::Level`
//! plays the same part).
//!
//! Sharpness: an edge is *sharp* when it is tagged as a crease or lies on a boundary (OpenSubdiv's
//! boundary interpolation "edge only", Blender's default). A vertex's rule follows from its sharp
//! edges: a user-marked corner or 3+ sharp edges → [`Rule::Corner`]; exactly 2 → [`Rule::Crease`];
//! 0 or 1 (a dart) → [`Rule::Smooth`]. A boundary vertex has two boundary edges, so it is a crease
//! vertex (also with valence 2: the corner of an open grid moves, as in OpenSubdiv and Blender)
//! unless another sharp edge or a corner mark makes it a corner.

use crate::mesh::{Mesh, NONE as MESH_NONE};

use super::SubdivError;

/// The id that stands for "none" (the missing face of a boundary edge).
pub(crate) const NONE: u32 = u32::MAX;

/// How a vertex is refined and where its limit lies (infinitely sharp rules only).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Rule {
    /// No sharp edge, or one (a dart): the scheme's smooth vertex rule.
    Smooth,
    /// Exactly two sharp edges: the cubic B-spline curve rule along them.
    Crease,
    /// A marked corner, three or more sharp edges, or an isolated vertex: the vertex stays put.
    Corner,
}

/// One level of refinement topology.
#[derive(Clone, Debug, Default)]
pub(crate) struct Level {
    pub(crate) num_vertices: usize,
    pub(crate) face_start: Vec<u32>,
    pub(crate) face_verts: Vec<u32>,
    pub(crate) face_edges: Vec<u32>,
    pub(crate) edge_verts: Vec<[u32; 2]>,
    pub(crate) edge_faces: Vec<[u32; 2]>,
    /// User crease tags (boundary edges are sharp without being tagged).
    pub(crate) edge_crease: Vec<bool>,
    pub(crate) vertex_corner: Vec<bool>,
    pub(crate) vert_edge_start: Vec<u32>,
    pub(crate) vert_edges: Vec<u32>,
    pub(crate) vert_face_start: Vec<u32>,
    pub(crate) vert_faces: Vec<u32>,
    pub(crate) vertex_rule: Vec<Rule>,
    /// For a crease vertex, the far ends of its two sharp edges.
    pub(crate) crease_ends: Vec<[u32; 2]>,
}

impl Level {
    pub(crate) fn face_count(&self) -> usize {
        self.face_start.len() - 1
    }

    pub(crate) fn edge_count(&self) -> usize {
        self.edge_verts.len()
    }

    /// The corner range of face `f` in `face_verts` / `face_edges`.
    #[inline]
    pub(crate) fn face_range(&self, f: usize) -> std::ops::Range<usize> {
        self.face_start[f] as usize..self.face_start[f + 1] as usize
    }

    #[inline]
    pub(crate) fn is_sharp(&self, e: usize) -> bool {
        self.edge_crease[e] || self.edge_faces[e][1] == NONE
    }

    /// The edges at vertex `v` (unordered).
    #[inline]
    pub(crate) fn vertex_edges(&self, v: usize) -> &[u32] {
        &self.vert_edges[self.vert_edge_start[v] as usize..self.vert_edge_start[v + 1] as usize]
    }

    /// The faces at vertex `v` (unordered).
    #[inline]
    pub(crate) fn vertex_faces(&self, v: usize) -> &[u32] {
        &self.vert_faces[self.vert_face_start[v] as usize..self.vert_face_start[v + 1] as usize]
    }

    /// The vertex at the other end of edge `e` from `v`.
    #[inline]
    pub(crate) fn other_end(&self, e: usize, v: u32) -> u32 {
        let [a, b] = self.edge_verts[e];
        if a == v {
            b
        } else {
            a
        }
    }

    /// The level-0 topology of a mesh: its faces in id order, its edges in [`Mesh::edges`] order.
    pub(crate) fn from_mesh(mesh: &Mesh) -> Level {
        let nh = mesh.halfedge_count();
        let mut he_edge = vec![NONE; nh];
        let mut edge_verts = Vec::with_capacity(nh / 2);
        let mut edge_faces = Vec::with_capacity(nh / 2);
        let mut edge_crease = Vec::with_capacity(nh / 2);
        for h in mesh.edges() {
            let t = mesh.twin(h);
            let id = edge_verts.len() as u32;
            he_edge[h as usize] = id;
            he_edge[t as usize] = id;
            edge_verts.push([mesh.origin(h), mesh.target(h)]);
            let (fa, fb) = (mesh.face(h), mesh.face(t));
            let (fa, fb) = (if fa == MESH_NONE { NONE } else { fa }, if fb == MESH_NONE { NONE } else { fb });
            edge_faces.push(if fa == NONE { [fb, fa] } else { [fa, fb] });
            edge_crease.push(mesh.is_crease(h));
        }
        let nf = mesh.face_count();
        let mut face_start = Vec::with_capacity(nf + 1);
        let mut face_verts = Vec::with_capacity(nh);
        let mut face_edges = Vec::with_capacity(nh);
        face_start.push(0);
        for f in 0..nf as u32 {
            for h in mesh.face_halfedges(f) {
                face_verts.push(mesh.origin(h));
                face_edges.push(he_edge[h as usize]);
            }
            face_start.push(face_verts.len() as u32);
        }
        let nv = mesh.vertex_count();
        let vertex_corner = (0..nv as u32).map(|v| mesh.is_corner(v)).collect();
        let mut level = Level {
            num_vertices: nv,
            face_start,
            face_verts,
            face_edges,
            edge_verts,
            edge_faces,
            edge_crease,
            vertex_corner,
            ..Level::default()
        };
        level.derive();
        level
    }

    /// Builds vertex adjacency (counting sorts) and classifies every vertex.
    pub(crate) fn derive(&mut self) {
        let nv = self.num_vertices;
        // Vertex → edges.
        let mut start = vec![0u32; nv + 1];
        for &[a, b] in &self.edge_verts {
            start[a as usize + 1] += 1;
            start[b as usize + 1] += 1;
        }
        for i in 0..nv {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut list = vec![0u32; 2 * self.edge_verts.len()];
        for (e, &[a, b]) in self.edge_verts.iter().enumerate() {
            list[fill[a as usize] as usize] = e as u32;
            fill[a as usize] += 1;
            list[fill[b as usize] as usize] = e as u32;
            fill[b as usize] += 1;
        }
        self.vert_edge_start = start;
        self.vert_edges = list;
        // Vertex → faces.
        let mut start = vec![0u32; nv + 1];
        for &v in &self.face_verts {
            start[v as usize + 1] += 1;
        }
        for i in 0..nv {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut list = vec![0u32; self.face_verts.len()];
        for f in 0..self.face_count() {
            for i in self.face_range(f) {
                let v = self.face_verts[i] as usize;
                list[fill[v] as usize] = f as u32;
                fill[v] += 1;
            }
        }
        self.vert_face_start = start;
        self.vert_faces = list;
        // Rules.
        let mut rules = Vec::with_capacity(nv);
        let mut ends = vec![[NONE; 2]; nv];
        for (v, end) in ends.iter_mut().enumerate() {
            let edges = self.vertex_edges(v);
            let mut sharp = 0usize;
            for &e in edges {
                if self.is_sharp(e as usize) {
                    if sharp < 2 {
                        end[sharp] = self.other_end(e as usize, v as u32);
                    }
                    sharp += 1;
                }
            }
            rules.push(if self.vertex_corner[v] || sharp >= 3 || edges.is_empty() {
                Rule::Corner
            } else if sharp == 2 {
                Rule::Crease
            } else {
                Rule::Smooth
            });
        }
        self.vertex_rule = rules;
        self.crease_ends = ends;
    }

    /// Index of the first face whose arity differs from `arity`, with that arity.
    pub(crate) fn first_face_not_of_arity(&self, arity: usize) -> Option<(usize, usize)> {
        (0..self.face_count()).map(|f| (f, self.face_range(f).len())).find(|&(_, n)| n != arity)
    }

    /// The topology of one Catmull–Clark step (see [`super::refiner`] for the id layout).
    pub(crate) fn refine_catmull_clark(&self) -> Level {
        let (nv, ne, nf) = (self.num_vertices, self.edge_count(), self.face_count());
        let ncorner = self.face_verts.len();
        let child_nv = nv + ne + nf;
        let child_ne = 2 * ne + ncorner;
        let mut edge_verts = vec![[0u32; 2]; child_ne];
        let mut edge_faces = vec![[NONE; 2]; child_ne];
        let mut edge_crease = vec![false; child_ne];
        for (e, &[a, b]) in self.edge_verts.iter().enumerate() {
            let m = (nv + e) as u32;
            edge_verts[2 * e] = [a, m];
            edge_verts[2 * e + 1] = [m, b];
            edge_crease[2 * e] = self.edge_crease[e];
            edge_crease[2 * e + 1] = self.edge_crease[e];
        }
        let mut face_start = Vec::with_capacity(ncorner + 1);
        let mut face_verts = Vec::with_capacity(4 * ncorner);
        let mut face_edges = Vec::with_capacity(4 * ncorner);
        for f in 0..nf {
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
                let other_half = half_k ^ 1;
                edge_faces[half_k][slot] = child;
                edge_faces[other_half][slot] = (s + kn) as u32;
                // Interior edge of corner k: edge point of ek to the face point, in children k, k+1.
                let ie = 2 * ne + s + k;
                edge_verts[ie] = [(nv + ek) as u32, fp];
                edge_faces[ie] = [child, (s + kn) as u32];
            }
        }
        face_start.push(face_verts.len() as u32);
        let mut vertex_corner = vec![false; child_nv];
        vertex_corner[..nv].copy_from_slice(&self.vertex_corner);
        let mut level = Level {
            num_vertices: child_nv,
            face_start,
            face_verts,
            face_edges,
            edge_verts,
            edge_faces,
            edge_crease,
            vertex_corner,
            ..Level::default()
        };
        level.derive();
        level
    }

    /// The topology of one Loop step of a triangle mesh (see [`super::refiner`] for the id layout).
    pub(crate) fn refine_loop(&self) -> Level {
        let (nv, ne, nf) = (self.num_vertices, self.edge_count(), self.face_count());
        let child_nv = nv + ne;
        let child_ne = 2 * ne + 3 * nf;
        let mut edge_verts = vec![[0u32; 2]; child_ne];
        let mut edge_faces = vec![[NONE; 2]; child_ne];
        let mut edge_crease = vec![false; child_ne];
        for (e, &[a, b]) in self.edge_verts.iter().enumerate() {
            let m = (nv + e) as u32;
            edge_verts[2 * e] = [a, m];
            edge_verts[2 * e + 1] = [m, b];
            edge_crease[2 * e] = self.edge_crease[e];
            edge_crease[2 * e + 1] = self.edge_crease[e];
        }
        let mut face_verts = Vec::with_capacity(12 * nf);
        let mut face_edges = Vec::with_capacity(12 * nf);
        for f in 0..nf {
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
                edge_faces[half_k][slot] = child;
                edge_faces[half_k ^ 1][slot] = (4 * f + (k + 1) % 3) as u32;
                // Interior edge k joins m[k] and m[k+1]: in the centre child and in child k+1.
                let ie = interior(k) as usize;
                edge_verts[ie] = [m[k], m[(k + 1) % 3]];
                edge_faces[ie] = [(4 * f + 3) as u32, (4 * f + (k + 1) % 3) as u32];
            }
            face_verts.extend_from_slice(&m);
            face_edges.extend_from_slice(&[interior(0), interior(1), interior(2)]);
        }
        let face_start = (0..=4 * nf as u32).map(|i| 3 * i).collect();
        let mut vertex_corner = vec![false; child_nv];
        vertex_corner[..nv].copy_from_slice(&self.vertex_corner);
        let mut level = Level {
            num_vertices: child_nv,
            face_start,
            face_verts,
            face_edges,
            edge_verts,
            edge_faces,
            edge_crease,
            vertex_corner,
            ..Level::default()
        };
        level.derive();
        level
    }

    /// The faces one step below this level as one flat index list and an arity per face, without
    /// building that level's topology (the last level of a refinement needs only its faces).
    pub(crate) fn child_faces(&self, loop_scheme: bool) -> (Vec<u32>, Vec<u32>) {
        let (nv, ne) = (self.num_vertices, self.edge_count());
        if loop_scheme {
            let mut idx = Vec::with_capacity(12 * self.face_count());
            for f in 0..self.face_count() {
                let s = 3 * f;
                let v = &self.face_verts[s..s + 3];
                let m: [u32; 3] = std::array::from_fn(|k| (nv as u32) + self.face_edges[s + k]);
                for k in 0..3 {
                    idx.extend_from_slice(&[v[k], m[k], m[(k + 2) % 3]]);
                }
                idx.extend_from_slice(&m);
            }
            let n = idx.len() / 3;
            (idx, vec![3; n])
        } else {
            let mut idx = Vec::with_capacity(4 * self.face_verts.len());
            for f in 0..self.face_count() {
                let r = self.face_range(f);
                let (s, n) = (r.start, r.len());
                let fp = (nv + ne + f) as u32;
                for k in 0..n {
                    let kp = if k == 0 { n - 1 } else { k - 1 };
                    idx.extend_from_slice(&[
                        self.face_verts[s + k],
                        (nv as u32) + self.face_edges[s + k],
                        fp,
                        (nv as u32) + self.face_edges[s + kp],
                    ]);
                }
            }
            let n = idx.len() / 4;
            (idx, vec![4; n])
        }
    }

    /// The crease-tagged edges one step below this level, as vertex pairs (each tagged edge splits
    /// in two at its edge point).
    pub(crate) fn child_crease_pairs(&self) -> Vec<[u32; 2]> {
        let nv = self.num_vertices as u32;
        let mut pairs = Vec::new();
        for (e, &[a, b]) in self.edge_verts.iter().enumerate() {
            if self.edge_crease[e] {
                let m = nv + e as u32;
                pairs.push([a, m]);
                pairs.push([m, b]);
            }
        }
        pairs
    }
}

/// Face count after `levels` steps from `level`, or an error when it passes `limit`.
pub(crate) fn check_size(level: &Level, levels: u32, loop_scheme: bool, limit: u64) -> Result<u64, SubdivError> {
    let mut faces = level.face_count() as u64;
    for l in 0..levels {
        faces = if l == 0 && !loop_scheme { level.face_verts.len() as u64 } else { faces.saturating_mul(4) };
        if faces > limit {
            // Report the count the full request would make (saturating), not the partial one.
            let full = faces.saturating_mul(4u64.saturating_pow(levels - l - 1));
            return Err(SubdivError::TooLarge { levels, faces: full, limit });
        }
    }
    Ok(faces)
}
