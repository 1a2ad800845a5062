//! Refinement topology: one level of a mesh as flat arrays, without positions.
//!
//! Notation: `nv`, `ne`, `nf` vertex, edge and face counts of a level. Faces are stored in CSR form
//! (`face_start`, `face_verts`), with `face_edges[i]` the edge from corner `i` to the next corner.
//! Each edge keeps its two end vertices and its one or two faces (the second is [`NONE`] on a
//! boundary). Vertex → edges and vertex → faces adjacency (each vertex's ids ascending) is
//! derived by counting sorts for the base level and written from the parent's for refined ones
//! (`super::child_adjacency`, which `super::child_level` calls when it builds the level one step
//! down); each vertex's subdivision rule follows from it and the sharpness.
//! Nothing here hashes or allocates per element:
//! building a level is a handful of linear passes over flat arrays (OpenSubdiv's `Vtr::Level`
//! plays the same part).
//!
//! Sharpness follows OpenSubdiv's `Sdc::Crease`, in its `f32` precision and with its value
//! [`INFINITE`] = 10 for infinitely sharp (10 and above count as infinite): boundary edges are
//! infinitely sharp in every boundary mode; a vertex's rule follows from its corner sharpness and
//! its sharp edges (semi-sharp ones included): corner sharpness above 0, 3+ sharp edges or no edge
//! → [`Rule::Corner`]; exactly 2 → [`Rule::Crease`]; 0 or 1 (a dart) → [`Rule::Smooth`]. A level with
//! semi-sharp values also holds its [`Transitions`]: the sharpness each edge's two halves get one
//! level down (uniform or Chaikin decay) and, where a vertex's rule changes from this level to
//! the next, the fractional weight that blends the two rules (`ComputeFractionalWeightAtVertex`).

use crate::mesh::{Mesh, NONE as MESH_NONE};

use super::SubdivError;
use super::{BoundaryInterpolation, CreaseMethod, SubdivOptions, TriangleSubdivision};

/// OpenSubdiv's infinite sharpness (`Sdc::Crease::SHARPNESS_INFINITE`).
pub(crate) const INFINITE: f32 = 10.0;

/// The id that stands for "none" (the missing face of a boundary edge).
pub(crate) const NONE: u32 = u32::MAX;

/// How a vertex is refined and where its limit lies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Rule {
    /// No sharp edge, or one (a dart): the scheme's smooth vertex rule.
    Smooth,
    /// Exactly two sharp edges: the cubic B-spline curve rule along them.
    Crease,
    /// A marked corner, three or more sharp edges, or an isolated vertex: the vertex stays put.
    Corner,
}

/// A level's vertex → edges and vertex → faces relations (CSR: starts, then ids).
pub(crate) struct Adjacency {
    pub(crate) vert_edge_start: Vec<u32>,
    pub(crate) vert_edges: Vec<u32>,
    pub(crate) vert_face_start: Vec<u32>,
    pub(crate) vert_faces: Vec<u32>,
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
    /// Edge sharpness (0 smooth, [`INFINITE`] for crease tags of 10 or more and boundary edges).
    pub(crate) edge_sharpness: Vec<f32>,
    /// Corner sharpness (with the corners the boundary mode sharpens).
    pub(crate) vertex_sharpness: Vec<f32>,
    pub(crate) creasing: CreaseMethod,
    /// Catmull–Clark's smooth-triangle edge weights apply (the option is on and a face is a triangle).
    pub(crate) tri_smooth: bool,
    /// Rule changes toward the next level; empty when no sharpness is semi-sharp.
    pub(crate) trans: Transitions,
    pub(crate) vert_edge_start: Vec<u32>,
    pub(crate) vert_edges: Vec<u32>,
    pub(crate) vert_face_start: Vec<u32>,
    pub(crate) vert_faces: Vec<u32>,
    pub(crate) vertex_rule: Vec<Rule>,
}

/// What changes between a level with semi-sharp values and the next.
#[derive(Clone, Debug, Default)]
pub(crate) struct Transitions {
    /// The sharpness of the two halves of each edge one level down (at `edge_verts[e][0]`, then
    /// `[1]`).
    pub(crate) child_edge: Vec<[f32; 2]>,
    /// Per edge, the weight of the midpoint rule in its edge point: 0 smooth, 1 crease, the
    /// edge's sharpness where it decays to smooth (`ComputeEdgeVertexMask`).
    pub(crate) edge_weight: Vec<f64>,
    /// Per vertex, the blend toward the child's rule where the rule changes.
    pub(crate) vertex: Vec<Option<Blend>>,
}

/// A vertex point blended between the parent's rule (weight `weight`) and the child's.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Blend {
    pub(crate) weight: f64,
    pub(crate) child_rule: Rule,
    /// The child's crease ends when `child_rule` is [`Rule::Crease`].
    pub(crate) child_ends: [u32; 2],
}

/// The sharpness one level down (`Sdc::Crease::decrementSharpness`): 0 and infinite stay, values
/// above 1 lose 1, the rest become 0.
#[inline]
pub(crate) fn decrement(s: f32) -> f32 {
    if s <= 0.0 {
        0.0
    } else if s >= INFINITE {
        INFINITE
    } else if s > 1.0 {
        s - 1.0
    } else {
        0.0
    }
}

#[inline]
pub(crate) fn is_semi_sharp(s: f32) -> bool {
    s > 0.0 && s < INFINITE
}

/// A mesh sharpness in OpenSubdiv's precision: `f32`, 10 and above infinite.
#[inline]
pub(crate) fn to_level_sharpness(s: f64) -> f32 {
    if s >= f64::from(INFINITE) {
        INFINITE
    } else if s > 0.0 {
        (s as f32).min(INFINITE)
    } else {
        0.0
    }
}

/// A level sharpness back to a mesh one ([`INFINITE`] is `f64::INFINITY`).
#[inline]
pub(crate) fn to_mesh_sharpness(s: f32) -> f64 {
    if s >= INFINITE {
        f64::INFINITY
    } else {
        f64::from(s)
    }
}

/// The rule of a vertex with corner sharpness `vs` and `sharp` sharp edges of `valence`
/// (`Sdc::Crease::DetermineVertexVertexRule`; an isolated vertex stays put).
#[inline]
fn rule_of(vs: f32, sharp: usize, valence: usize) -> Rule {
    if vs > 0.0 || sharp > 2 || valence == 0 {
        Rule::Corner
    } else if sharp == 2 {
        Rule::Crease
    } else {
        Rule::Smooth
    }
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

    /// The weight of the midpoint (crease) rule in the edge point of `e`: 0 for a smooth edge, 1
    /// for a sharp one, between for a semi-sharp edge decaying to smooth.
    #[inline]
    pub(crate) fn edge_weight(&self, e: usize) -> f64 {
        if self.trans.edge_weight.is_empty() {
            if self.edge_sharpness[e] > 0.0 {
                1.0
            } else {
                0.0
            }
        } else {
            self.trans.edge_weight[e]
        }
    }

    /// The sharpness of the two halves of edge `e` one level down.
    #[inline]
    pub(crate) fn child_sharpness(&self, e: usize) -> [f32; 2] {
        if self.trans.child_edge.is_empty() {
            [self.edge_sharpness[e]; 2]
        } else {
            self.trans.child_edge[e]
        }
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
    pub(crate) fn from_mesh(mesh: &Mesh, options: &SubdivOptions) -> Level {
        let nh = mesh.halfedge_count();
        let mut he_edge = vec![NONE; nh];
        let mut edge_verts = Vec::with_capacity(nh / 2);
        let mut edge_faces = Vec::with_capacity(nh / 2);
        let mut edge_sharpness = Vec::with_capacity(nh / 2);
        for h in mesh.edges() {
            let t = mesh.twin(h);
            let id = edge_verts.len() as u32;
            he_edge[h as usize] = id;
            he_edge[t as usize] = id;
            edge_verts.push([mesh.origin(h), mesh.target(h)]);
            let (fa, fb) = (mesh.face(h), mesh.face(t));
            let (fa, fb) = (if fa == MESH_NONE { NONE } else { fa }, if fb == MESH_NONE { NONE } else { fb });
            edge_faces.push(if fa == NONE { [fb, fa] } else { [fa, fb] });
            let boundary = fa == NONE || fb == NONE;
            edge_sharpness.push(if boundary { INFINITE } else { to_level_sharpness(mesh.edge_sharpness(h)) });
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
        let vertex_sharpness = (0..nv as u32).map(|v| to_level_sharpness(mesh.corner_sharpness(v))).collect();
        let mut level = Level {
            num_vertices: nv,
            face_start,
            face_verts,
            face_edges,
            edge_verts,
            edge_faces,
            edge_sharpness,
            vertex_sharpness,
            creasing: options.crease,
            ..Level::default()
        };
        level.adjacency();
        if options.boundary == BoundaryInterpolation::EdgeAndCorner {
            // `VTX_BOUNDARY_EDGE_AND_CORNER` sharpens topological corners: one face, two edges.
            for v in 0..nv {
                if level.vertex_faces(v).len() == 1 && level.vertex_edges(v).len() == 2 {
                    level.vertex_sharpness[v] = INFINITE;
                }
            }
        }
        level.tri_smooth =
            options.triangles == TriangleSubdivision::Smooth && level.first_face_not_of_arity(4).is_some();
        level.classify();
        level
    }

    /// Takes a refined level's vertex adjacency and classifies every vertex.
    pub(crate) fn derive(&mut self, adjacency: Adjacency) {
        self.vert_edge_start = adjacency.vert_edge_start;
        self.vert_edges = adjacency.vert_edges;
        self.vert_face_start = adjacency.vert_face_start;
        self.vert_faces = adjacency.vert_faces;
        self.classify();
    }

    /// Builds vertex → edges and vertex → faces adjacency (counting sorts; refined levels write
    /// theirs from their parent's, `super::child_adjacency`).
    pub(crate) fn adjacency(&mut self) {
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
    }

    /// Each vertex's rule, and the transitions when any sharpness is semi-sharp.
    ///
    /// The sharp edges at each vertex are counted from one pass over the edges that scatters
    /// only the sharp ones (counts saturate at 3: the rule tells 0–2 from more), so a level
    /// without creases costs a sequential read of its edge sharpness and of its vertices, not a
    /// visit of every vertex's edges.
    fn classify(&mut self) {
        let nv = self.num_vertices;
        let mut sharp = vec![0u8; nv];
        let mut semi = false;
        for (e, &s) in self.edge_sharpness.iter().enumerate() {
            if s > 0.0 {
                semi |= s < INFINITE;
                for v in self.edge_verts[e] {
                    let c = &mut sharp[v as usize];
                    *c = (*c + 1).min(3);
                }
            }
        }
        let start = &self.vert_edge_start;
        self.vertex_rule = (0..nv)
            .map(|v| rule_of(self.vertex_sharpness[v], usize::from(sharp[v]), (start[v + 1] - start[v]) as usize))
            .collect();
        semi |= self.vertex_sharpness.iter().any(|&s| is_semi_sharp(s));
        self.trans = if semi { self.transitions() } else { Transitions::default() };
    }

    /// For a crease vertex, the far ends of its first two sharp edges in edge order ([`NONE`]
    /// where there are fewer): found when needed, as only crease vertices need them.
    pub(crate) fn crease_ends(&self, v: usize) -> [u32; 2] {
        let mut ends = [NONE; 2];
        let mut k = 0;
        for &e in self.vertex_edges(v) {
            if self.edge_sharpness[e as usize] > 0.0 {
                ends[k] = self.other_end(e as usize, v as u32);
                k += 1;
                if k == 2 {
                    break;
                }
            }
        }
        ends
    }

    /// The child sharpness of edge `e` at its end vertex `v` (`SubdivideEdgeSharpnessAtVertex`).
    fn child_edge_sharpness_at(&self, e: usize, v: usize) -> f32 {
        let s = self.edge_sharpness[e];
        let edges = self.vertex_edges(v);
        if self.creasing == CreaseMethod::Uniform || edges.len() < 2 || !is_semi_sharp(s) {
            return decrement(s);
        }
        // Chaikin: ¾ of the edge's sharpness and ¼ of the mean of the other semi-sharp edges here.
        let (mut sum, mut count) = (0.0f32, 0usize);
        for &o in edges {
            let so = self.edge_sharpness[o as usize];
            if is_semi_sharp(so) {
                sum += so;
                count += 1;
            }
        }
        let mut c = s;
        if count > 1 {
            let avg = (sum - s) / (count - 1) as f32;
            c = 0.75 * s + 0.25 * avg;
        }
        c -= 1.0;
        if c > 0.0 {
            c
        } else {
            0.0
        }
    }

    /// The transitions toward the next level (OpenSubdiv `Sdc::Scheme::ComputeEdgeVertexMask`,
    /// `ComputeVertexVertexMask` and `Sdc::Crease::ComputeFractionalWeightAtVertex`).
    fn transitions(&self) -> Transitions {
        // Uniform creasing decrements each edge alike at both ends; only Chaikin's looks at the
        // other edges at each end.
        let child_edge: Vec<[f32; 2]> = if self.creasing == CreaseMethod::Uniform {
            self.edge_sharpness.iter().map(|&s| [decrement(s); 2]).collect()
        } else {
            self.edge_verts
                .iter()
                .enumerate()
                .map(|(e, &[a, b])| {
                    [self.child_edge_sharpness_at(e, a as usize), self.child_edge_sharpness_at(e, b as usize)]
                })
                .collect()
        };
        // An edge point follows the crease rule when both child halves stay sharp, and otherwise
        // blends the crease and smooth rules by the edge's sharpness.
        let edge_weight = self
            .edge_sharpness
            .iter()
            .zip(&child_edge)
            .map(|(&s, c)| {
                if s <= 0.0 {
                    0.0
                } else if c[0] > 0.0 && c[1] > 0.0 {
                    1.0
                } else {
                    f64::from(s)
                }
            })
            .collect();
        let uniform = self.creasing == CreaseMethod::Uniform;
        let vertex = (0..self.num_vertices)
            .map(|v| {
                let p_rule = self.vertex_rule[v];
                if p_rule == Rule::Smooth {
                    return None;
                }
                let edges = self.vertex_edges(v);
                let pvs = self.vertex_sharpness[v];
                let cvs = decrement(pvs);
                let child = |e: u32| {
                    let [a, _] = self.edge_verts[e as usize];
                    child_edge[e as usize][usize::from(a != v as u32)]
                };
                let sharp = edges.iter().filter(|&&e| child(e) > 0.0).count();
                let c_rule = rule_of(cvs, sharp, edges.len());
                if c_rule == p_rule {
                    return None;
                }
                let (mut count, mut sum) = (0usize, 0.0f32);
                if pvs > 0.0 && cvs <= 0.0 {
                    count = 1;
                    sum = pvs;
                }
                for &e in edges {
                    let ps = self.edge_sharpness[e as usize];
                    let transition = if uniform { ps > 0.0 && ps <= 1.0 } else { ps > 0.0 && child(e) <= 0.0 };
                    if transition {
                        sum += ps;
                        count += 1;
                    }
                }
                let weight = if count == 0 { 0.0 } else { (sum / count as f32).min(1.0) };
                let mut child_ends = [NONE; 2];
                let mut k = 0;
                for &e in edges {
                    if child(e) > 0.0 && k < 2 {
                        child_ends[k] = self.other_end(e as usize, v as u32);
                        k += 1;
                    }
                }
                Some(Blend { weight: f64::from(weight), child_rule: c_rule, child_ends })
            })
            .collect();
        Transitions { child_edge, edge_weight, vertex }
    }

    /// Index of the first face whose arity differs from `arity`, with that arity.
    pub(crate) fn first_face_not_of_arity(&self, arity: usize) -> Option<(usize, usize)> {
        (0..self.face_count()).map(|f| (f, self.face_range(f).len())).find(|&(_, n)| n != arity)
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

    /// The crease-tagged edges one step below this level with their sharpness (each edge splits
    /// in two at its edge point; boundary edges are not tags), and the corner sharpness of this
    /// level's vertices one step down.
    pub(crate) fn child_tags(&self) -> (Vec<([u32; 2], f64)>, Vec<f64>) {
        let nv = self.num_vertices as u32;
        let mut pairs = Vec::new();
        for (e, &[a, b]) in self.edge_verts.iter().enumerate() {
            if self.edge_sharpness[e] > 0.0 && self.edge_faces[e][1] != NONE {
                let m = nv + e as u32;
                let [sa, sb] = self.child_sharpness(e);
                if sa > 0.0 {
                    pairs.push(([a, m], to_mesh_sharpness(sa)));
                }
                if sb > 0.0 {
                    pairs.push(([m, b], to_mesh_sharpness(sb)));
                }
            }
        }
        let corners = self.vertex_sharpness.iter().map(|&s| to_mesh_sharpness(decrement(s))).collect();
        (pairs, corners)
    }

    /// This level's crease tags (boundary edges left out) and corner sharpness.
    pub(crate) fn tags(&self) -> (Vec<([u32; 2], f64)>, Vec<f64>) {
        let pairs = (0..self.edge_count())
            .filter(|&e| self.edge_sharpness[e] > 0.0 && self.edge_faces[e][1] != NONE)
            .map(|e| (self.edge_verts[e], to_mesh_sharpness(self.edge_sharpness[e])))
            .collect();
        (pairs, self.vertex_sharpness.iter().map(|&s| to_mesh_sharpness(s)).collect())
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
    // The last level as a mesh (quads, or triangles with half as many vertices as faces), and
    // the topology of the level above it, which the refiner keeps.
    let (vertices, corners) = if loop_scheme { (0.5, 3.0) } else { (1.0, 4.0) };
    let f = faces as f64 * 1.25;
    crate::mesh::check_mesh_size(
        || format!("the result of {levels} subdivision levels ({faces} faces)"),
        f * vertices,
        f * corners,
        f,
    )?;
    Ok(faces)
}
