//! The topology refiner: connectivity refined once, positions refined many times.
//!
//! [`Refiner::new`] builds the topology of every level from a mesh (no positions involved), then
//! [`Refiner::refine_positions`] applies the subdivision rules to any set of control positions, as
//! often as needed, and [`Refiner::stencils`] / [`Refiner::composed_stencils`] give the same maps as
//! explicit sparse weights. This is OpenSubdiv's split between `Far::TopologyRefiner`,
//! `Far::PrimvarRefiner` and `Far::StencilTableFactory`.
//!
//! # Id layout of a refined level
//! - **Catmull–Clark**: vertex points keep their parent's ids `0..V`, then one edge point per
//!   parent edge (`V + e`, edges in level order; level 0 uses [`Mesh::edges`] order), then one face
//!   point per parent face (`V + E + f`). Each parent face of arity n makes n quads, in corner order
//!   starting at the face's first vertex: child `k` of face `f` is
//!   `[vertex point of v_k, edge point of (v_k, v_k+1), face point of f, edge point of (v_k-1, v_k)]`,
//!   and the children of face `f` follow those of face `f - 1`.
//! - **Loop**: vertex points `0..V`, then edge points `V + e`. Triangle `(v0, v1, v2)` with edge
//!   points `m0 = (v0, v1)`, `m1 = (v1, v2)`, `m2 = (v2, v0)` makes `[v0, m0, m2]`, `[v1, m1, m0]`,
//!   `[v2, m2, m1]`, `[m0, m1, m2]`, in that order.
//!
//! (OpenSubdiv numbers face points first; keeping the parent ids first lets operations that only
//! move vertices and the limit functions keep vertex ids.) Crease tags survive: both halves of a
//! tagged edge are tagged; corner marks stay on the vertex point.
//!
//! # Rules
//! Catmull & Clark (1978) with the infinitely sharp rules of Hoppe et al. (1994) and DeRose et al.
//! (1998), as OpenSubdiv's `Sdc` implements them (see [`super::topology`] for the classification):
//! face point = centroid; smooth edge point = (v0 + v1 + f0 + f1) / 4; sharp edge point = midpoint;
//! smooth vertex point = ((n − 2) v + (Σ e_i + Σ f_i) / n) / n; crease vertex point =
//! (e_a + 6 v + e_b) / 8; corner = v. Loop (1987) with Loop's original weights, as seed 002 uses:
//! smooth edge point = 3/8 (v0 + v1) + 1/8 (opposite vertices); smooth vertex point =
//! (1 − nβ) v + β Σ e_i with β = (5/8 − (3/8 + ¼ cos 2π/n)²) / n; crease vertex point =
//! (e_a + 6 v + e_b) / 8; sharp edge point = midpoint.

use crate::math::Vec3;
use crate::mesh::Mesh;

use super::stencil::{RowBuilder, StencilTable};
use super::topology::{check_size, Blend, Level, Rule, NONE};
use super::SubdivError;
use super::SubdivOptions;

/// The most faces a refinement may produce (about 5 GB of output mesh).
pub const MAX_FACES: u64 = 50_000_000;

/// A subdivision scheme.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Scheme {
    /// Catmull–Clark: any polygons in, quads out.
    CatmullClark,
    /// Loop: triangles in, triangles out.
    Loop,
}

/// Refined topology of a mesh down to a fixed number of levels.
///
/// Holds the full topology of levels `0..levels` (each is needed to refine the next); the last
/// level's faces are produced on demand by [`Refiner::faces`].
#[derive(Clone, Debug)]
pub struct Refiner {
    scheme: Scheme,
    options: SubdivOptions,
    levels: Vec<Level>,
    depth: u32,
}

/// Loop's original β for a smooth vertex of valence n (Loop 1987, §3.1; seed 002 §2.2).
#[must_use]
pub fn loop_beta(n: usize) -> f64 {
    let nf = n as f64;
    let c = 0.375 + 0.25 * (std::f64::consts::TAU / nf).cos();
    (0.625 - c * c) / nf
}

impl Refiner {
    /// Refines the topology of `mesh` `levels` times with `scheme` and the mesh's own options
    /// ([`Mesh::subdiv_options`]).
    ///
    /// # Errors
    /// - [`SubdivError::NotTriangles`] for [`Scheme::Loop`] on a mesh with a non-triangle face;
    /// - [`SubdivError::TooLarge`] when the last level would have more than [`MAX_FACES`] faces.
    pub fn new(mesh: &Mesh, scheme: Scheme, levels: u32) -> Result<Refiner, SubdivError> {
        Refiner::with_options(mesh, scheme, levels, &mesh.subdiv_options())
    }

    /// [`Refiner::new`] with other options than the mesh's own.
    ///
    /// # Errors
    /// As [`Refiner::new`].
    pub fn with_options(
        mesh: &Mesh,
        scheme: Scheme,
        levels: u32,
        options: &SubdivOptions,
    ) -> Result<Refiner, SubdivError> {
        let mut opts = *options;
        if scheme == Scheme::Loop {
            opts.triangles = super::TriangleSubdivision::CatmullClark;
        }
        let base = Level::from_mesh(mesh, &opts);
        let mut r = Refiner::from_level(base, scheme, levels, MAX_FACES)?;
        r.options = *options;
        Ok(r)
    }

    pub(crate) fn from_level(base: Level, scheme: Scheme, depth: u32, limit: u64) -> Result<Refiner, SubdivError> {
        let is_loop = scheme == Scheme::Loop;
        if is_loop {
            if let Some((face, arity)) = base.first_face_not_of_arity(3) {
                return Err(SubdivError::NotTriangles { face, arity });
            }
        }
        check_size(&base, depth, is_loop, limit)?;
        let mut levels = vec![base];
        for _ in 1..depth {
            let last = levels.last().expect("at least the base level");
            crate::limits::charge(last.face_verts.len() as u64)?;
            let next = if is_loop { last.refine_loop()? } else { last.refine_catmull_clark()? };
            levels.push(next);
        }
        Ok(Refiner { scheme, options: SubdivOptions::default(), levels, depth })
    }

    /// The topology of levels `0..depth` (the last level's is never built).
    #[cfg(test)]
    pub(crate) fn levels(&self) -> &[Level] {
        &self.levels
    }

    /// The scheme this refiner applies.
    #[must_use]
    pub fn scheme(&self) -> Scheme {
        self.scheme
    }

    /// The number of levels below the base mesh.
    #[must_use]
    pub fn depth(&self) -> u32 {
        self.depth
    }

    /// Number of vertices at `level` (0 = the base mesh, up to [`Refiner::depth`]).
    #[must_use]
    pub fn vertex_count(&self, level: u32) -> usize {
        let l = level as usize;
        if l < self.levels.len() {
            self.levels[l].num_vertices
        } else {
            let p = &self.levels[l - 1];
            match self.scheme {
                Scheme::CatmullClark => p.num_vertices + p.edge_count() + p.face_count(),
                Scheme::Loop => p.num_vertices + p.edge_count(),
            }
        }
    }

    /// Number of faces at `level`.
    #[must_use]
    pub fn face_count(&self, level: u32) -> usize {
        let l = level as usize;
        if l < self.levels.len() {
            self.levels[l].face_count()
        } else {
            let p = &self.levels[l - 1];
            match self.scheme {
                Scheme::CatmullClark => p.face_verts.len(),
                Scheme::Loop => 4 * p.face_count(),
            }
        }
    }

    /// As [`Refiner::refine_positions`], checking the current cancellation token before each
    /// level ([`crate::limits::charge`], one unit per parent corner).
    ///
    /// # Panics
    /// When `positions.len()` differs from the base vertex count (a caller bug).
    ///
    /// # Errors
    /// [`SubdivError::Limit`] when the token stops the work.
    pub fn try_refine_positions(&self, positions: &[Vec3]) -> Result<Vec<Vec3>, SubdivError> {
        assert_eq!(positions.len(), self.levels[0].num_vertices, "one position per base vertex");
        let mut p = positions.to_vec();
        for l in 1..=self.depth {
            crate::limits::charge(self.levels[l as usize - 1].face_verts.len() as u64)?;
            p = self.refine_level(l, &p);
        }
        Ok(p)
    }

    /// Refines positions of the base vertices down to the last level (one position per vertex of
    /// [`Refiner::faces`]). Cheap enough to call for every frame of an animation.
    ///
    /// # Panics
    /// When `positions.len()` differs from the base vertex count (a caller bug).
    #[must_use]
    pub fn refine_positions(&self, positions: &[Vec3]) -> Vec<Vec3> {
        assert_eq!(positions.len(), self.levels[0].num_vertices, "one position per base vertex");
        let mut p = positions.to_vec();
        for l in 1..=self.depth {
            p = self.refine_level(l, &p);
        }
        p
    }

    /// Refines positions of level `level - 1` to level `level` (1 ≤ level ≤ depth).
    ///
    /// # Panics
    /// When `level` is out of range or `src` has the wrong length (caller bugs).
    #[must_use]
    pub fn refine_level(&self, level: u32, src: &[Vec3]) -> Vec<Vec3> {
        assert!(level >= 1 && level <= self.depth, "level {level} out of 1..={}", self.depth);
        let parent = &self.levels[level as usize - 1];
        assert_eq!(src.len(), parent.num_vertices, "one position per parent vertex");
        match self.scheme {
            Scheme::CatmullClark => interpolate_catmull_clark(parent, src),
            Scheme::Loop => interpolate_loop(parent, src),
        }
    }

    /// The stencils from level `level - 1` to level `level` (1 ≤ level ≤ depth).
    ///
    /// # Panics
    /// When `level` is out of range (a caller bug).
    #[must_use]
    pub fn stencils(&self, level: u32) -> StencilTable {
        assert!(level >= 1 && level <= self.depth, "level {level} out of 1..={}", self.depth);
        let parent = &self.levels[level as usize - 1];
        match self.scheme {
            Scheme::CatmullClark => stencils_catmull_clark(parent),
            Scheme::Loop => stencils_loop(parent),
        }
    }

    /// The stencils from the base vertices straight to the last level (levels composed).
    #[must_use]
    pub fn composed_stencils(&self) -> StencilTable {
        let mut t = StencilTable::identity(self.levels[0].num_vertices);
        for l in 1..=self.depth {
            t = t.then(&self.stencils(l));
        }
        t
    }

    /// The faces of the last level: one flat index list and one arity per face.
    #[must_use]
    pub fn faces(&self) -> (Vec<u32>, Vec<u32>) {
        if self.depth == 0 {
            let b = &self.levels[0];
            let ar = (0..b.face_count()).map(|f| b.face_range(f).len() as u32).collect();
            return (b.face_verts.clone(), ar);
        }
        self.levels.last().expect("base level").child_faces(self.scheme == Scheme::Loop)
    }

    /// For each face of the last level, the base-level (input mesh) face it lies in: Catmull–Clark
    /// makes one child quad per corner of a face, in corner order, and Loop four children per
    /// triangle (see [`super::refiner`]'s layout), so each level maps its children to their parents
    /// in one pass.
    #[must_use]
    pub fn base_faces(&self) -> Vec<u32> {
        let base = &self.levels[0];
        let mut ids: Vec<u32> = (0..base.face_count() as u32).collect();
        if self.depth == 0 {
            return ids;
        }
        for lv in &self.levels {
            ids = if self.scheme == Scheme::Loop {
                ids.iter().flat_map(|&f| [f; 4]).collect()
            } else {
                (0..lv.face_count()).flat_map(|f| std::iter::repeat_n(ids[f], lv.face_range(f).len())).collect()
            };
        }
        ids
    }

    /// The mesh of the last level with the given positions (from [`Refiner::refine_positions`]),
    /// carrying the crease and corner sharpness down (semi-sharp values less one per level, or as
    /// the Chaikin option decays them; a corner the boundary mode sharpens is marked as one).
    ///
    /// The half-edges are written straight from the last topology level (see `child_mesh`), not
    /// rebuilt from a face list.
    ///
    /// # Errors
    /// [`SubdivError::Internal`] if the refined faces do not form a valid mesh (a bug).
    pub fn to_mesh(&self, positions: Vec<Vec3>) -> Result<Mesh, SubdivError> {
        if self.depth == 0 {
            return self.to_mesh_from_faces(positions);
        }
        let last = self.levels.last().expect("base level");
        let mut mesh = super::child_mesh::child_mesh(last, self.scheme == Scheme::Loop, positions)?;
        mesh.set_subdiv_options(self.options);
        Ok(mesh)
    }

    /// [`Refiner::to_mesh`] through the generic build from the face list (the base level, and
    /// the reference the direct build is tested against).
    pub(crate) fn to_mesh_from_faces(&self, positions: Vec<Vec3>) -> Result<Mesh, SubdivError> {
        let (idx, ar) = self.faces();
        let last = self.levels.last().expect("base level");
        let (creases, corners) = if self.depth == 0 { last.tags() } else { last.child_tags() };
        let mut mesh = Mesh::from_indexed(positions, &idx, &ar)
            .map_err(|e| SubdivError::Internal(format!("refined faces do not form a mesh: {e}")))?;
        for ([a, b], s) in creases {
            let h =
                mesh.find_halfedge(a, b).ok_or_else(|| SubdivError::Internal(format!("crease tag ({a}, {b}) lost")))?;
            mesh.set_edge_sharpness_halfedge(h, s);
        }
        for (v, &c) in corners.iter().enumerate() {
            if c > 0.0 {
                mesh.set_corner_sharpness(v as u32, c);
            }
        }
        mesh.set_subdiv_options(self.options);
        Ok(mesh)
    }
}

/// The crease vertex point (e_a + 6 v + e_b) / 8 of both schemes, relative to v.
#[inline]
fn crease_point(p: &[Vec3], v: usize, [a, b]: [u32; 2]) -> Vec3 {
    p[v] + ((p[a as usize] - p[v]) + (p[b as usize] - p[v])) * 0.125
}

/// One Catmull–Clark step of positions: face points, then edge points, then vertex points.
///
/// Every point is an affine combination written relative to one of its own inputs,
/// `base + Σ wᵢ (pᵢ − base)`: where all inputs share a coordinate (a flat sharp face, a straight
/// crease), the output has it exactly — summing `Σ wᵢ pᵢ` would round 0.3 to 0.29999999999999993
/// and make faces that should touch miss by that.
fn interpolate_catmull_clark(lv: &Level, p: &[Vec3]) -> Vec<Vec3> {
    let (nv, ne, nf) = (lv.num_vertices, lv.edge_count(), lv.face_count());
    let mut out = vec![Vec3::ZERO; nv + ne + nf];
    let (vout, rest) = out.split_at_mut(nv);
    let (eout, fout) = rest.split_at_mut(ne);
    for (f, fp) in fout.iter_mut().enumerate() {
        let r = lv.face_range(f);
        let n = r.len() as f64;
        let base = p[lv.face_verts[r.start] as usize];
        let mut s = Vec3::ZERO;
        for &v in &lv.face_verts[r] {
            s += p[v as usize] - base;
        }
        *fp = base + s / n;
    }
    for (e, ep) in eout.iter_mut().enumerate() {
        let [a, b] = lv.edge_verts[e];
        let [f0, f1] = lv.edge_faces[e];
        let (pa, pb) = (p[a as usize], p[b as usize]);
        let w = lv.edge_weight(e);
        *ep = if w == 1.0 {
            pa + (pb - pa) * 0.5
        } else if w == 0.0 && !lv.tri_smooth {
            pa + ((pb - pa) + (fout[f0 as usize] - pa) + (fout[f1 as usize] - pa)) * 0.25
        } else {
            let mut sink = PointSink { p, faces: fout, base: pa, acc: Vec3::ZERO };
            cc_edge_mask(lv, e, &mut sink);
            sink.point()
        };
    }
    let (fout, blends) = (&*fout, &lv.trans.vertex);
    for (v, vp) in vout.iter_mut().enumerate() {
        if let Some(Some(blend)) = blends.get(v) {
            let mut sink = PointSink { p, faces: fout, base: p[v], acc: Vec3::ZERO };
            blended_vertex_mask(lv, v, blend, &mut sink, cc_rule_mask);
            *vp = sink.point();
            continue;
        }
        *vp = match lv.vertex_rule[v] {
            Rule::Corner => p[v],
            Rule::Crease => crease_point(p, v, lv.crease_ends(v)),
            Rule::Smooth => {
                // ((n − 2) v + (Σ e + Σ f) / n) / n, relative to v.
                let edges = lv.vertex_edges(v);
                let n = edges.len() as f64;
                let mut s = Vec3::ZERO;
                for &e in edges {
                    s += p[lv.other_end(e as usize, v as u32) as usize] - p[v];
                }
                for &f in lv.vertex_faces(v) {
                    s += fout[f as usize] - p[v];
                }
                p[v] + s / (n * n)
            }
        };
    }
    out
}

/// The vertex opposite edge `e` in triangle `f`.
#[inline]
fn opposite_in_triangle(lv: &Level, f: u32, e: usize) -> u32 {
    let s = 3 * f as usize;
    let k = (0..3).find(|&k| lv.face_edges[s + k] as usize == e).unwrap_or(0);
    lv.face_verts[s + (k + 2) % 3]
}

/// One Loop step of positions.
fn interpolate_loop(lv: &Level, p: &[Vec3]) -> Vec<Vec3> {
    let (nv, ne) = (lv.num_vertices, lv.edge_count());
    let mut out = vec![Vec3::ZERO; nv + ne];
    let (vout, eout) = out.split_at_mut(nv);
    for (e, ep) in eout.iter_mut().enumerate() {
        let [a, b] = lv.edge_verts[e];
        let [f0, f1] = lv.edge_faces[e];
        let (pa, pb) = (p[a as usize], p[b as usize]);
        let w = lv.edge_weight(e);
        *ep = if w == 1.0 {
            pa + (pb - pa) * 0.5
        } else if w == 0.0 {
            let c = p[opposite_in_triangle(lv, f0, e) as usize];
            let d = p[opposite_in_triangle(lv, f1, e) as usize];
            pa + (pb - pa) * 0.375 + ((c - pa) + (d - pa)) * 0.125
        } else {
            let mut sink = PointSink { p, faces: &[], base: pa, acc: Vec3::ZERO };
            loop_edge_mask(lv, e, &mut sink);
            sink.point()
        };
    }
    let mut beta_cache: Vec<f64> = Vec::new();
    for (v, vp) in vout.iter_mut().enumerate() {
        if let Some(Some(blend)) = lv.trans.vertex.get(v) {
            let mut sink = PointSink { p, faces: &[], base: p[v], acc: Vec3::ZERO };
            blended_vertex_mask(lv, v, blend, &mut sink, loop_rule_mask);
            *vp = sink.point();
            continue;
        }
        *vp = match lv.vertex_rule[v] {
            Rule::Corner => p[v],
            Rule::Crease => crease_point(p, v, lv.crease_ends(v)),
            Rule::Smooth => {
                let edges = lv.vertex_edges(v);
                let n = edges.len();
                if beta_cache.len() <= n {
                    beta_cache.extend((beta_cache.len()..=n).map(|k| if k == 0 { 0.0 } else { loop_beta(k) }));
                }
                let beta = beta_cache[n];
                let mut s = Vec3::ZERO;
                for &e in edges {
                    s += p[lv.other_end(e as usize, v as u32) as usize] - p[v];
                }
                // (1 − nβ) v + β Σ e, relative to v.
                p[v] + s * beta
            }
        };
    }
    out
}

/// Where the weights of one child point go: control vertices of the parent level, and (for
/// Catmull–Clark) the face points of the same step.
trait Sink {
    fn vert(&mut self, v: u32, w: f64);
    fn face(&mut self, f: u32, w: f64);
}

/// Sums weighted points relative to `base` (one of the inputs), as the fast paths do.
struct PointSink<'a> {
    p: &'a [Vec3],
    faces: &'a [Vec3],
    base: Vec3,
    acc: Vec3,
}

impl PointSink<'_> {
    fn point(&self) -> Vec3 {
        self.base + self.acc
    }
}

impl Sink for PointSink<'_> {
    #[inline]
    fn vert(&mut self, v: u32, w: f64) {
        self.acc += (self.p[v as usize] - self.base) * w;
    }
    #[inline]
    fn face(&mut self, f: u32, w: f64) {
        self.acc += (self.faces[f as usize] - self.base) * w;
    }
}

/// Writes weights into a stencil row; a face point becomes its face's vertices.
struct RowSink<'a> {
    lv: &'a Level,
    b: RowBuilder,
}

impl Sink for RowSink<'_> {
    #[inline]
    fn vert(&mut self, v: u32, w: f64) {
        self.b.add(v, w);
    }
    fn face(&mut self, f: u32, w: f64) {
        let r = self.lv.face_range(f as usize);
        let wf = w / r.len() as f64;
        for &v in &self.lv.face_verts[r] {
            self.b.add(v, wf);
        }
    }
}

/// The smooth Catmull–Clark edge-point weights (vertex, face): ¼ and ¼, or with OpenSubdiv's
/// smooth-triangle option 0.47 for a triangle's face point (`Scheme<CATMARK>::assignSmoothMaskForEdge`).
fn cc_smooth_edge_weights(lv: &Level, [f0, f1]: [u32; 2]) -> (f64, f64) {
    if lv.tri_smooth {
        let tri = |f: u32| lv.face_range(f as usize).len() == 3;
        let (t0, t1) = (tri(f0), tri(f1));
        if t0 || t1 {
            const TRI: f64 = 0.470;
            let fw = 0.5 * (if t0 { TRI } else { 0.25 } + if t1 { TRI } else { 0.25 });
            return (0.5 * (1.0 - 2.0 * fw), fw);
        }
    }
    (0.25, 0.25)
}

/// A Catmull–Clark edge point: the midpoint for a sharp edge, the smooth rule for a smooth one,
/// and for a semi-sharp edge decaying to smooth the two blended by its sharpness w:
/// w · midpoint + (1 − w) · smooth (`Sdc::Scheme::ComputeEdgeVertexMask`).
fn cc_edge_mask(lv: &Level, e: usize, sink: &mut impl Sink) {
    let [a, b] = lv.edge_verts[e];
    let w = lv.edge_weight(e);
    if w == 1.0 {
        sink.vert(a, 0.5);
        sink.vert(b, 0.5);
        return;
    }
    let faces = lv.edge_faces[e];
    let (vw, fw) = cc_smooth_edge_weights(lv, faces);
    let c = 1.0 - w;
    sink.vert(a, w * 0.5 + c * vw);
    sink.vert(b, w * 0.5 + c * vw);
    sink.face(faces[0], c * fw);
    sink.face(faces[1], c * fw);
}

/// A Loop edge point, blended as [`cc_edge_mask`] (the opposite vertices are Loop's face weights).
fn loop_edge_mask(lv: &Level, e: usize, sink: &mut impl Sink) {
    let [a, b] = lv.edge_verts[e];
    let w = lv.edge_weight(e);
    if w == 1.0 {
        sink.vert(a, 0.5);
        sink.vert(b, 0.5);
        return;
    }
    let [f0, f1] = lv.edge_faces[e];
    let c = 1.0 - w;
    sink.vert(a, w * 0.5 + c * 0.375);
    sink.vert(b, w * 0.5 + c * 0.375);
    sink.vert(opposite_in_triangle(lv, f0, e), c * 0.125);
    sink.vert(opposite_in_triangle(lv, f1, e), c * 0.125);
}

/// The corner and crease vertex-point weights, scaled by `s`: the same for Catmull–Clark and
/// Loop (the crease rule is the cubic B-spline's along the crease, `Sdc::Crease`).
fn sharp_rule_mask(v: usize, rule: Rule, ends: [u32; 2], s: f64, sink: &mut dyn FnMut(bool, u32, f64)) {
    if rule == Rule::Corner {
        sink(false, v as u32, s);
    } else {
        sink(false, v as u32, 0.75 * s);
        sink(false, ends[0], 0.125 * s);
        sink(false, ends[1], 0.125 * s);
    }
}

/// The Catmull–Clark vertex-point weights of `rule`, scaled by `s`.
fn cc_rule_mask(lv: &Level, v: usize, rule: Rule, ends: [u32; 2], s: f64, sink: &mut dyn FnMut(bool, u32, f64)) {
    match rule {
        Rule::Corner | Rule::Crease => sharp_rule_mask(v, rule, ends, s, sink),
        Rule::Smooth => {
            let edges = lv.vertex_edges(v);
            let n = edges.len() as f64;
            let w = s / (n * n);
            sink(false, v as u32, s * (n - 2.0) / n);
            for &e in edges {
                sink(false, lv.other_end(e as usize, v as u32), w);
            }
            for &f in lv.vertex_faces(v) {
                sink(true, f, w);
            }
        }
    }
}

/// The Loop vertex-point weights of `rule`, scaled by `s`.
fn loop_rule_mask(lv: &Level, v: usize, rule: Rule, ends: [u32; 2], s: f64, sink: &mut dyn FnMut(bool, u32, f64)) {
    match rule {
        Rule::Corner | Rule::Crease => sharp_rule_mask(v, rule, ends, s, sink),
        Rule::Smooth => {
            let edges = lv.vertex_edges(v);
            let beta = loop_beta(edges.len());
            sink(false, v as u32, s * (1.0 - edges.len() as f64 * beta));
            for &e in edges {
                sink(false, lv.other_end(e as usize, v as u32), s * beta);
            }
        }
    }
}

/// The crease ends a rule mask reads: a crease vertex's own, nothing for the other rules.
fn rule_ends(lv: &Level, v: usize, rule: Rule) -> [u32; 2] {
    if rule == Rule::Crease {
        lv.crease_ends(v)
    } else {
        [NONE; 2]
    }
}

type RuleMask = fn(&Level, usize, Rule, [u32; 2], f64, &mut dyn FnMut(bool, u32, f64));

/// A vertex point whose rule changes toward the next level: w · (parent rule) + (1 − w) · (child
/// rule), w the fractional weight (`Sdc::Scheme::ComputeVertexVertexMask`).
fn blended_vertex_mask(lv: &Level, v: usize, blend: &Blend, sink: &mut impl Sink, mask: RuleMask) {
    let mut put = |face: bool, id: u32, w: f64| {
        if face {
            sink.face(id, w);
        } else {
            sink.vert(id, w);
        }
    };
    let rule = lv.vertex_rule[v];
    mask(lv, v, rule, rule_ends(lv, v, rule), blend.weight, &mut put);
    mask(lv, v, blend.child_rule, blend.child_ends, 1.0 - blend.weight, &mut put);
}

/// A vertex point with its level's rules (blended where the rule changes).
fn vertex_mask(lv: &Level, v: usize, sink: &mut impl Sink, mask: RuleMask) {
    if let Some(Some(blend)) = lv.trans.vertex.get(v) {
        blended_vertex_mask(lv, v, blend, sink, mask);
        return;
    }
    let mut put = |face: bool, id: u32, w: f64| {
        if face {
            sink.face(id, w);
        } else {
            sink.vert(id, w);
        }
    };
    let rule = lv.vertex_rule[v];
    mask(lv, v, rule, rule_ends(lv, v, rule), 1.0, &mut put);
}

/// Catmull–Clark stencils of one step, rows in child-vertex order.
fn stencils_catmull_clark(lv: &Level) -> StencilTable {
    let (nv, ne, nf) = (lv.num_vertices, lv.edge_count(), lv.face_count());
    let b = RowBuilder::new(nv, nv + ne + nf, 9 * nv + 6 * ne + lv.face_verts.len());
    let mut sink = RowSink { lv, b };
    for v in 0..nv {
        vertex_mask(lv, v, &mut sink, cc_rule_mask);
        sink.b.end_row();
    }
    for e in 0..ne {
        cc_edge_mask(lv, e, &mut sink);
        sink.b.end_row();
    }
    for f in 0..nf {
        sink.face(f as u32, 1.0);
        sink.b.end_row();
    }
    sink.b.finish()
}

/// Loop stencils of one step, rows in child-vertex order.
fn stencils_loop(lv: &Level) -> StencilTable {
    let (nv, ne) = (lv.num_vertices, lv.edge_count());
    let b = RowBuilder::new(nv, nv + ne, 7 * nv + 4 * ne);
    let mut sink = RowSink { lv, b };
    for v in 0..nv {
        vertex_mask(lv, v, &mut sink, loop_rule_mask);
        sink.b.end_row();
    }
    for e in 0..ne {
        loop_edge_mask(lv, e, &mut sink);
        sink.b.end_row();
    }
    sink.b.finish()
}
