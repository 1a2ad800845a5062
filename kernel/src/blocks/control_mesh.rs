//! The control mesh of a block model (seed 000 §2.3): every exterior sub-face becomes a polygon
//! of one watertight mesh; connected (interior) sub-faces are dropped and their rims joined.
//!
//! # Steps
//! 1. **Per block**, the sub-face grids of its six faces share vertices: the 8 corners, points
//!    along each block edge (the union of the divisions of the two faces meeting there) and grid
//!    points inside faces. A sub-face whose side lies on a block edge divided more finely by the
//!    neighbouring face lists those T-vertices too, so it becomes an n-gon (§2.3, first step).
//! 2. **Connections**: both sub-faces are dropped, and their corners are joined pairwise by the
//!    least-cost rotation (Fig. 8) into one vertex at the average position of every vertex joined
//!    with it (Fig. 9: a vertex may join more than two blocks).
//! 3. **Rims**: the four sides of each dropped sub-face are glued to the sides of its partner.
//!    Sides with the same end vertices form one group; the T-vertices of all of them are merged
//!    by their parameter along the side and inserted into every remaining polygon that uses part
//!    of the side, and placed on the straight segment between the joined ends.
//! 4. An edge is sharp (a crease) when at least one block edge it lies on is sharp; its sharpness
//!    is the largest of theirs (semi-sharp block edges give semi-sharp creases).
//! 5. The polygons are built into a half-edge [`Mesh`] (which refuses non-manifold input), checked
//!    closed, and given one Catmull–Clark step (§2.3, second step): all quads. Where a block edge
//!    is semi-sharp, the quads are refined further until its sharpness is used up (DeRose, Kass &
//!    Truong 1998 §3: the crease rules apply for ⌈s⌉ levels, and only then are the quads patches
//!    of one limit surface that no longer changes from level to level, as the tessellator's
//!    [`crate::subdiv::LimitEvaluator`] needs); each child quad keeps its parent's sub-face and
//!    the quarter of its (u, v) it covers, and every half-edge keeps the sharpness of the block
//!    edge it lies on.

use std::collections::HashMap;

use crate::math::{lerp, Vec3};
use crate::mesh::{Mesh, MeshError, NONE};

use super::connect::pairing;
use super::{Block, BlockError, BlockModel, Connection, Edge, Face, SubFaceRef};

/// Two sub-face parameters closer than this are the same point.
const PARAM_EPS: f64 = 1e-9;

/// Where one quad of the control mesh comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PatchSource {
    /// The block sub-face whose polygon the quad is a Catmull–Clark child of.
    pub subface: SubFaceRef,
    /// The block-face (u, v) at the quad's four corners, in the quad's vertex order.
    pub uv: [[f64; 2]; 4],
}

/// The control mesh of a model: all quads, crease-tagged, with the origin of each quad.
#[derive(Clone, Debug)]
pub struct ControlMesh {
    /// The exterior sub-faces as polygons (n-gons where T-vertices were), before subdivision.
    pub polygons: Mesh,
    /// The sub-face of each polygon.
    pub polygon_sources: Vec<SubFaceRef>,
    /// `polygons` after one Catmull–Clark step, and as many more as semi-sharp block edges need
    /// to run out of sharpness: quads only, no semi-sharp crease left.
    pub mesh: Mesh,
    /// One entry per face of `mesh`.
    pub sources: Vec<PatchSource>,
    /// Per half-edge of `mesh`, the sharpness of the block edge it lies on as the blocks set it
    /// (0 off sharp block edges, `f64::INFINITY` on sharp ones, the value on semi-sharp ones,
    /// whose creases `mesh` itself has used up): the tessellation tags its edges with it.
    pub edge_sharpness: Vec<f64>,
}

impl BlockModel {
    /// The control mesh of the model: exterior sub-faces joined watertight, one Catmull–Clark
    /// step, quads only. See the [module documentation](self).
    ///
    /// # Errors
    /// [`BlockError::Empty`] for a model without blocks; [`BlockError::Topology`] when the
    /// connections make a surface that is not a closed 2-manifold (an edge collapsed, three
    /// faces on an edge).
    pub fn control_mesh(&self) -> Result<ControlMesh, BlockError> {
        let connections = self.connections()?;
        assemble(self, &connections)
    }
}

/// One exterior or interior sub-face polygon before joining.
struct Poly {
    verts: Vec<u32>,
    uv: Vec<[f64; 2]>,
    /// Positions in `verts` of the four sub-face corners, counter-clockwise from outside.
    corners: [usize; 4],
    src: SubFaceRef,
}

impl Poly {
    /// Side `k`: the vertices from corner `k` to corner `k + 1`, both included.
    fn side(&self, k: usize) -> Vec<u32> {
        let (a, b) = (self.corners[k], self.corners[(k + 1) % 4]);
        let n = self.verts.len();
        let len = (b + n - a) % n;
        (0..=len).map(|i| self.verts[(a + i) % n]).collect()
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Local {
    Corner(u8),
    Edge(u8, u64),
    Face(u8, u32, u32),
}

struct Assembly {
    positions: Vec<Vec3>,
    polys: Vec<Poly>,
    /// Sharp edges as ordered vertex pairs (smaller id first), with their sharpness.
    sharp: HashMap<(u32, u32), f64>,
    index: HashMap<SubFaceRef, usize>,
}

fn key(a: u32, b: u32) -> (u32, u32) {
    (a.min(b), a.max(b))
}

/// The polygons of one block (step 1).
fn add_block(asm: &mut Assembly, bi: u32, block: &Block) {
    let corners = block.corners();
    let along = |face: Face, axis: usize| {
        let (p, _) = face.uv_axes();
        let (nu, nv) = block.divisions(face);
        if p == axis {
            nu
        } else {
            nv
        }
    };
    let edge_params: Vec<Vec<f64>> = Edge::all()
        .map(|e| {
            let (f, g) = e.faces();
            let mut ts = Vec::new();
            for face in [f, g] {
                let n = along(face, e.axis());
                ts.extend((1..n).map(|i| f64::from(i) / f64::from(n)));
            }
            ts.sort_by(f64::total_cmp);
            ts.dedup();
            ts
        })
        .collect();
    let edge_point = |e: Edge, t: f64| {
        let (lo, hi) = e.corners();
        lerp(corners[lo], corners[hi], t)
    };
    let mut ids: HashMap<Local, u32> = HashMap::new();
    let mut vertex = |positions: &mut Vec<Vec3>, k: Local, p: Vec3| -> u32 {
        *ids.entry(k).or_insert_with(|| {
            positions.push(p);
            (positions.len() - 1) as u32
        })
    };
    for face in Face::ALL {
        let (p, q) = face.uv_axes();
        let (nu, nv) = block.divisions(face);
        let grid = |i: u32, j: u32| -> (Local, Vec3) {
            let (ub, vb) = (i == 0 || i == nu, j == 0 || j == nv);
            let (s, t) = (usize::from(i == nu), usize::from(j == nv));
            let (u, v) = (f64::from(i) / f64::from(nu), f64::from(j) / f64::from(nv));
            if ub && vb {
                let c = face.corner(s, t);
                (Local::Corner(c as u8), corners[c])
            } else if ub {
                let e = Edge::along(q, face.corner(s, 0));
                (Local::Edge(e.index() as u8, v.to_bits()), edge_point(e, v))
            } else if vb {
                let e = Edge::along(p, face.corner(0, t));
                (Local::Edge(e.index() as u8, u.to_bits()), edge_point(e, u))
            } else {
                (Local::Face(face.index() as u8, i, j), block.face_point(face, u, v))
            }
        };
        for j in 0..nv {
            for i in 0..nu {
                let (u0, u1) = (f64::from(i) / f64::from(nu), f64::from(i + 1) / f64::from(nu));
                let (v0, v1) = (f64::from(j) / f64::from(nv), f64::from(j + 1) / f64::from(nv));
                let mut verts = Vec::new();
                let mut uv = Vec::new();
                let mut idx = [0usize; 4];
                // Sides in (u, v) counter-clockwise order: bottom, right, top, left; each with the
                // block edge it lies on, if any, and its T-vertex parameters in walking order.
                let sides: [(Option<Edge>, f64, f64); 4] = [
                    ((j == 0).then(|| Edge::along(p, face.corner(0, 0))), u0, u1),
                    ((i + 1 == nu).then(|| Edge::along(q, face.corner(1, 0))), v0, v1),
                    ((j + 1 == nv).then(|| Edge::along(p, face.corner(0, 1))), u1, u0),
                    ((i == 0).then(|| Edge::along(q, face.corner(0, 0))), v1, v0),
                ];
                let grid_corners = [(i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)];
                let corner_uv = [[u0, v0], [u1, v0], [u1, v1], [u0, v1]];
                for k in 0..4 {
                    let (gi, gj) = grid_corners[k];
                    let (lk, pos) = grid(gi, gj);
                    idx[k] = verts.len();
                    verts.push(vertex(&mut asm.positions, lk, pos));
                    uv.push(corner_uv[k]);
                    let (edge, from, to) = sides[k];
                    if let Some(e) = edge {
                        let ts = &edge_params[e.index()];
                        let inside: Vec<f64> = if from < to {
                            ts.iter().copied().filter(|&t| t > from && t < to).collect()
                        } else {
                            ts.iter().rev().copied().filter(|&t| t < from && t > to).collect()
                        };
                        for t in inside {
                            verts.push(vertex(
                                &mut asm.positions,
                                Local::Edge(e.index() as u8, t.to_bits()),
                                edge_point(e, t),
                            ));
                            uv.push(if k % 2 == 0 { [t, corner_uv[k][1]] } else { [corner_uv[k][0], t] });
                        }
                    }
                }
                // Sharp sides: every piece of a side on a sharp block edge.
                let n = verts.len();
                for k in 0..4 {
                    if let (Some(e), _, _) = sides[k] {
                        if block.is_sharp(e) {
                            let end = if k == 3 { n } else { idx[k + 1] };
                            for m in idx[k]..end {
                                sharpen(&mut asm.sharp, key(verts[m], verts[(m + 1) % n]), block.sharpness(e));
                            }
                        }
                    }
                }
                let corners_at = if face.uv_is_outward() {
                    idx
                } else {
                    // Reverse the winding, keeping the first vertex first.
                    verts[1..].reverse();
                    uv[1..].reverse();
                    [0, n - idx[3], n - idx[2], n - idx[1]]
                };
                let src = SubFaceRef { block: bi, face, sub: i + nu * j };
                asm.index.insert(src, asm.polys.len());
                asm.polys.push(Poly { verts, uv, corners: corners_at, src });
            }
        }
    }
}

struct UnionFind(Vec<u32>);

impl UnionFind {
    fn find(&mut self, mut v: u32) -> u32 {
        while self.0[v as usize] != v {
            let p = self.0[v as usize];
            self.0[v as usize] = self.0[p as usize];
            v = p;
        }
        v
    }

    fn union(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            // The smaller id is the root: results do not depend on the order of unions.
            let (lo, hi) = (ra.min(rb), ra.max(rb));
            self.0[hi as usize] = lo;
        }
    }
}

/// A side of a dropped sub-face, its vertices with their parameter along it.
type Chain = Vec<(f64, u32)>;

/// Groups the glued sides by their (joined) end vertices, each side oriented from the smaller
/// end to the larger.
fn group_chains(
    chains: &[Vec<u32>],
    positions: &[Vec3],
    uf: &mut UnionFind,
) -> Result<HashMap<(u32, u32), Vec<Chain>>, BlockError> {
    let mut groups: HashMap<(u32, u32), Vec<Chain>> = HashMap::new();
    for ch in chains {
        let (first, last) = (ch[0], ch[ch.len() - 1]);
        let (x, y) = (uf.find(first), uf.find(last));
        if x == y {
            return Err(BlockError::Topology {
                reason: "joining the corners of connected sub-faces collapses a sub-face side to a point".into(),
            });
        }
        let mut ch = ch.clone();
        if x > y {
            ch.reverse();
        }
        let (a, b) = (positions[ch[0] as usize], positions[ch[ch.len() - 1] as usize]);
        let d = b - a;
        let dd = d.length_squared();
        let n = ch.len();
        let pts: Chain = ch
            .iter()
            .enumerate()
            .map(|(i, &v)| {
                let t = if i == 0 {
                    0.0
                } else if i + 1 == n {
                    1.0
                } else if dd > 0.0 {
                    ((positions[v as usize] - a).dot(d) / dd).clamp(0.0, 1.0)
                } else {
                    0.5
                };
                (t, v)
            })
            .collect();
        groups.entry(key(x, y)).or_default().push(pts);
    }
    Ok(groups)
}

/// Tags edge `k` with sharpness `s`, keeping the larger of two tags.
fn sharpen(sharp: &mut HashMap<(u32, u32), f64>, k: (u32, u32), s: f64) {
    let e = sharp.entry(k).or_insert(0.0);
    *e = e.max(s);
}

/// A sub-face, for messages.
fn describe(r: SubFaceRef) -> String {
    format!("sub-face {} of face {} of block {}", r.sub, r.face.name(), r.block)
}

/// Steps 2–5 on the polygons of every block.
fn assemble(model: &BlockModel, connections: &[Connection]) -> Result<ControlMesh, BlockError> {
    if model.blocks().is_empty() {
        return Err(BlockError::Empty);
    }
    let mut asm = Assembly { positions: Vec::new(), polys: Vec::new(), sharp: HashMap::new(), index: HashMap::new() };
    for (bi, block) in model.blocks().iter().enumerate() {
        add_block(&mut asm, bi as u32, block);
    }
    let nv = asm.positions.len();
    let mut uf = UnionFind((0..nv as u32).collect());
    let mut removed = vec![false; asm.polys.len()];
    let mut chains: Vec<Vec<u32>> = Vec::new();

    // Step 2: drop connected sub-faces, join their corners.
    for c in connections {
        let (pa, pb) = match (asm.index.get(&c.a), asm.index.get(&c.b)) {
            (Some(&a), Some(&b)) => (a, b),
            _ => return Err(BlockError::Internal(format!("connection {c:?} names a missing sub-face"))),
        };
        if removed[pa] || removed[pb] {
            return Err(BlockError::Topology { reason: format!("a sub-face of connection {c:?} is connected twice") });
        }
        removed[pa] = true;
        removed[pb] = true;
        let ca: [u32; 4] = asm.polys[pa].corners.map(|k| asm.polys[pa].verts[k]);
        let cb: [u32; 4] = asm.polys[pb].corners.map(|k| asm.polys[pb].verts[k]);
        let r = pairing(&ca.map(|v| asm.positions[v as usize]), &cb.map(|v| asm.positions[v as usize]));
        for (i, &a) in ca.iter().enumerate() {
            uf.union(a, cb[(r + 4 - i) % 4]);
        }
        for p in [pa, pb] {
            for k in 0..4 {
                chains.push(asm.polys[p].side(k));
            }
        }
    }

    // Step 3a: merge T-vertices that meet at the same parameter of a glued side.
    let groups = group_chains(&chains, &asm.positions, &mut uf)?;
    let mut keys: Vec<(u32, u32)> = groups.keys().copied().collect();
    keys.sort_unstable();
    for k in &keys {
        let mut pts: Vec<(f64, u32)> = groups[k].iter().flat_map(|ch| ch[1..ch.len() - 1].iter().copied()).collect();
        pts.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        for w in pts.windows(2) {
            if w[1].0 - w[0].0 < PARAM_EPS {
                uf.union(w[0].1, w[1].1);
            }
        }
    }
    let groups = group_chains(&chains, &asm.positions, &mut uf)?;
    let root: Vec<u32> = (0..nv as u32).map(|v| uf.find(v)).collect();

    // Joined positions: the average of every vertex joined.
    let mut pos = vec![Vec3::ZERO; nv];
    let mut count = vec![0u32; nv];
    for v in 0..nv {
        pos[root[v] as usize] += asm.positions[v];
        count[root[v] as usize] += 1;
    }
    for v in 0..nv {
        if count[v] > 0 {
            pos[v] /= f64::from(count[v]);
        }
    }
    let mut sharp: HashMap<(u32, u32), f64> = HashMap::new();
    for (&(a, b), &s) in &asm.sharp {
        sharpen(&mut sharp, key(root[a as usize], root[b as usize]), s);
    }

    // Step 3b: every glued side lists all T-vertices of its group; remaining polygons that use a
    // piece of it get the ones inside that piece. Rules map a directed edge to the vertices to
    // insert, with their fraction along it.
    let mut rules: HashMap<(u32, u32), Vec<(u32, f64)>> = HashMap::new();
    let mut keys: Vec<(u32, u32)> = groups.keys().copied().collect();
    keys.sort_unstable();
    for k in &keys {
        let mut list: Vec<(f64, u32)> = Vec::new();
        let mut pts: Vec<(f64, u32)> =
            groups[k].iter().flat_map(|ch| ch[1..ch.len() - 1].iter().map(|&(t, v)| (t, root[v as usize]))).collect();
        pts.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        for (t, c) in pts {
            if !list.iter().any(|&(_, d)| d == c) {
                list.push((t, c));
            }
        }
        // Straight rims: T-vertices on the segment between the joined ends.
        let (x, y) = *k;
        for &(t, c) in &list {
            pos[c as usize] = lerp(pos[x as usize], pos[y as usize], t);
        }
        for ch in &groups[k] {
            for w in ch.windows(2) {
                let ((t0, v0), (t1, v1)) = (w[0], w[1]);
                let (c0, c1) = (root[v0 as usize], root[v1 as usize]);
                let inside: Vec<(u32, f64)> = list
                    .iter()
                    .filter(|&&(t, c)| t > t0 + PARAM_EPS && t < t1 - PARAM_EPS && c != c0 && c != c1)
                    .map(|&(t, c)| (c, (t - t0) / (t1 - t0)))
                    .collect();
                if inside.is_empty() {
                    continue;
                }
                if let Some(&s) = sharp.get(&key(c0, c1)) {
                    let mut prev = c0;
                    for &(c, _) in &inside {
                        sharpen(&mut sharp, key(prev, c), s);
                        prev = c;
                    }
                    sharpen(&mut sharp, key(prev, c1), s);
                }
                let back: Vec<(u32, f64)> = inside.iter().rev().map(|&(c, f)| (c, 1.0 - f)).collect();
                rules.insert((c0, c1), inside);
                rules.insert((c1, c0), back);
            }
        }
    }

    // Step 5: the remaining polygons, with joined vertices and inserted T-vertices.
    let mut final_id = vec![NONE; nv];
    let mut out_pos: Vec<Vec3> = Vec::new();
    let mut indices: Vec<u32> = Vec::new();
    let mut arities: Vec<u32> = Vec::new();
    let mut uvs: Vec<Vec<[f64; 2]>> = Vec::new();
    let mut polygon_sources = Vec::new();
    for (pi, poly) in asm.polys.iter().enumerate() {
        if removed[pi] {
            continue;
        }
        let m = poly.verts.len();
        let mut cls = Vec::with_capacity(m);
        let mut puv = Vec::with_capacity(m);
        for k in 0..m {
            let (c, d) = (root[poly.verts[k] as usize], root[poly.verts[(k + 1) % m] as usize]);
            cls.push(c);
            puv.push(poly.uv[k]);
            if let Some(ins) = rules.get(&(c, d)) {
                let (a, b) = (poly.uv[k], poly.uv[(k + 1) % m]);
                for &(e, f) in ins {
                    cls.push(e);
                    puv.push([a[0] + (b[0] - a[0]) * f, a[1] + (b[1] - a[1]) * f]);
                }
            }
        }
        if let Some(i) = (1..cls.len()).find(|&i| cls[..i].contains(&cls[i])) {
            let p = pos[cls[i] as usize];
            return Err(BlockError::Topology {
                reason: format!(
                    "the connections join two corners of {} to one point ({}, {}, {}): connected sub-faces do \
                     not line up with their neighbours (check the sub-face grids and groups)",
                    describe(poly.src),
                    p.x,
                    p.y,
                    p.z
                ),
            });
        }
        for &c in &cls {
            if final_id[c as usize] == NONE {
                final_id[c as usize] = out_pos.len() as u32;
                out_pos.push(pos[c as usize]);
            }
            indices.push(final_id[c as usize]);
        }
        arities.push(cls.len() as u32);
        uvs.push(puv);
        polygon_sources.push(poly.src);
    }
    let out_pos_copy = out_pos.clone();
    let mut polygons = Mesh::from_indexed(out_pos, &indices, &arities).map_err(|e| {
        let reason = match e {
            MeshError::NonManifoldEdge { first, second, .. } => format!(
                "{} and {} share an edge in the same direction (more than two sub-faces meet at an edge)",
                describe(polygon_sources[first]),
                describe(polygon_sources[second])
            ),
            MeshError::NonManifoldVertex { vertex, fans } => {
                let p = out_pos_copy[vertex as usize];
                format!(
                    "the sub-faces around ({}, {}, {}) form {fans} separate fans (blocks touching at a point)",
                    p.x, p.y, p.z
                )
            }
            other => other.to_string(),
        };
        BlockError::Topology { reason }
    })?;
    if !polygons.is_closed() {
        let open = (0..polygons.halfedge_count() as u32).filter(|&h| polygons.is_boundary_halfedge(h)).count();
        return Err(BlockError::Topology {
            reason: format!("the surface has {open} boundary edges (sub-faces joined to sides that do not match)"),
        });
    }
    let mut sharp_pairs: Vec<((u32, u32), f64)> = sharp.into_iter().collect();
    sharp_pairs.sort_unstable_by_key(|a| a.0);
    for ((a, b), s) in sharp_pairs {
        let (fa, fb) = (final_id[a as usize], final_id[b as usize]);
        if fa == NONE || fb == NONE {
            continue;
        }
        if let Some(h) = polygons.find_halfedge(fa, fb) {
            polygons.set_edge_sharpness_halfedge(h, s);
        }
    }
    let mesh = polygons.catmull_clark(1).map_err(|e| BlockError::internal("", e))?;
    // Child k of polygon f is [v_k, edge point (v_k, v_k+1), face point, edge point (v_k-1, v_k)].
    let mut sources = Vec::with_capacity(mesh.face_count());
    for (f, puv) in uvs.iter().enumerate() {
        let n = puv.len();
        let mut centre = [0.0, 0.0];
        for p in puv {
            centre[0] += p[0] / n as f64;
            centre[1] += p[1] / n as f64;
        }
        let mid = |a: [f64; 2], b: [f64; 2]| [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
        for k in 0..n {
            let uv = [puv[k], mid(puv[k], puv[(k + 1) % n]), centre, mid(puv[(k + n - 1) % n], puv[k])];
            sources.push(PatchSource { subface: polygon_sources[f], uv });
        }
    }
    if sources.len() != mesh.face_count() {
        return Err(BlockError::Internal(format!("{} sources for {} quads", sources.len(), mesh.face_count())));
    }
    let mut tags: HashMap<(u32, u32), f64> =
        polygons.crease_sharpnesses().into_iter().map(|([a, b], s)| (key(a, b), s)).collect();
    tags = child_tags(&polygons, &tags);
    let (mesh, sources, tags) = use_up_sharpness(mesh, sources, tags)?;
    let mut edge_sharpness = vec![0.0; mesh.halfedge_count()];
    for (&(a, b), &s) in &tags {
        let h = mesh.find_halfedge(a, b).ok_or_else(|| BlockError::Internal(format!("crease ({a}, {b}) lost")))?;
        edge_sharpness[h as usize] = s;
        edge_sharpness[mesh.twin(h) as usize] = s;
    }
    Ok(ControlMesh { polygons, polygon_sources, mesh, sources, edge_sharpness })
}

/// The tags of `parent`'s edges on the edges of its Catmull–Clark child: the edge point of the
/// parent's `e`-th edge (in [`Mesh::edges`] order) is child vertex `V + e`, and both halves of a
/// tagged edge keep its tag (the layout of [`crate::subdiv::refiner`]).
fn child_tags(parent: &Mesh, tags: &HashMap<(u32, u32), f64>) -> HashMap<(u32, u32), f64> {
    let nv = parent.vertex_count() as u32;
    let mut out = HashMap::with_capacity(2 * tags.len());
    for (e, h) in parent.edges().enumerate() {
        let (a, b) = (parent.origin(h), parent.target(h));
        if let Some(&s) = tags.get(&key(a, b)) {
            let m = nv + e as u32;
            out.insert(key(a, m), s);
            out.insert(key(m, b), s);
        }
    }
    out
}

/// Refines `mesh` until no semi-sharp crease is left, each child quad with the quarter of its
/// parent's source it covers and the block-edge tags carried down.
#[allow(clippy::type_complexity)]
fn use_up_sharpness(
    mut mesh: Mesh,
    mut sources: Vec<PatchSource>,
    mut tags: HashMap<(u32, u32), f64>,
) -> Result<(Mesh, Vec<PatchSource>, HashMap<(u32, u32), f64>), BlockError> {
    while mesh.has_semi_sharp() {
        let child = mesh.catmull_clark(1).map_err(|e| match e {
            crate::subdiv::SubdivError::Limit(l) => BlockError::Limit(l),
            e => BlockError::Topology { reason: format!("refining semi-sharp block edges: {e}") },
        })?;
        // Quad f's child k covers the quarter at its corner k (see the sources above).
        let mid = |a: [f64; 2], b: [f64; 2]| [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
        let mut next = Vec::with_capacity(4 * sources.len());
        for s in &sources {
            let q = s.uv;
            let centre = mid(mid(q[0], q[1]), mid(q[2], q[3]));
            for k in 0..4 {
                let uv = [q[k], mid(q[k], q[(k + 1) % 4]), centre, mid(q[(k + 3) % 4], q[k])];
                next.push(PatchSource { subface: s.subface, uv });
            }
        }
        tags = child_tags(&mesh, &tags);
        mesh = child;
        sources = next;
    }
    Ok((mesh, sources, tags))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::blocks::test_models::{boxed, hand};

    fn check_closed(c: &ControlMesh) {
        for m in [&c.polygons, &c.mesh] {
            assert!(m.is_closed(), "not closed");
            assert!(m.is_manifold(), "not manifold");
            assert_eq!(m.genus(), 0);
            assert!(m.volume() > 0.0, "faces point inward: {}", m.volume());
        }
        assert!(c.mesh.is_quad_mesh());
        assert_eq!(c.sources.len(), c.mesh.face_count());
    }

    #[test]
    fn a_single_block_is_its_cube() {
        let mut m = BlockModel::new();
        m.add(boxed([0.0; 3], [1.0, 2.0, 3.0]));
        let c = m.control_mesh().unwrap();
        check_closed(&c);
        // 6 quads on 8 corners; one Catmull–Clark step: 8 + 12 + 6 vertices, 24 quads.
        assert_eq!((c.polygons.vertex_count(), c.polygons.face_count()), (8, 6));
        assert_eq!((c.mesh.vertex_count(), c.mesh.face_count()), (26, 24));
        assert!((c.polygons.volume() - 6.0).abs() < 1e-12);
        assert_eq!(c.mesh.crease_count(), 0);
    }

    #[test]
    fn finer_neighbouring_faces_make_n_gons() {
        let mut b = boxed([0.0; 3], [1.0; 3]);
        b.subdivide(Face::PosZ, 2, 2).unwrap();
        let mut m = BlockModel::new();
        m.add(b);
        let c = m.control_mesh().unwrap();
        check_closed(&c);
        // +z makes 4 quads; each side face gets a T-vertex on its top edge: 4 pentagons.
        let arities: Vec<usize> = (0..c.polygons.face_count() as u32).map(|f| c.polygons.face_arity(f)).collect();
        assert_eq!(arities.iter().filter(|&&a| a == 5).count(), 4);
        assert_eq!(c.polygons.face_count(), 9);
        // 8 corners + 4 edge midpoints + the centre of +z.
        assert_eq!(c.polygons.vertex_count(), 13);
        // A quad per polygon corner: 4·4 + 4·5 + 4.
        assert_eq!(c.mesh.face_count(), 40);
    }

    #[test]
    fn sharp_block_edges_become_creases() {
        let mut b = boxed([0.0; 3], [1.0; 3]);
        b.subdivide(Face::PosZ, 2, 2).unwrap();
        b.set_sharp(Edge::parse("+x+z").unwrap(), true);
        let mut m = BlockModel::new();
        m.add(b.clone());
        let c = m.control_mesh().unwrap();
        // The edge is cut in two by the +z grid; each half is cut again by Catmull–Clark.
        assert_eq!(c.polygons.crease_count(), 2);
        assert_eq!(c.mesh.crease_count(), 4);
        b.sharp_all();
        let mut m = BlockModel::new();
        m.add(b);
        // 12 block edges, 4 of them halved by the +z grid: 16 polygon edges, 32 after a step.
        assert_eq!(m.control_mesh().unwrap().polygons.crease_count(), 16);
    }

    #[test]
    fn two_connected_blocks_share_their_rim() {
        let mut m = BlockModel::new();
        m.allow(0, 0);
        m.add(boxed([0.0; 3], [1.0; 3]));
        m.add(boxed([1.0, 0.0, 0.0], [2.0, 1.0, 1.0]));
        let c = m.control_mesh().unwrap();
        check_closed(&c);
        // Two cubes less the two joined faces; 8 + 8 − 4 vertices.
        assert_eq!((c.polygons.vertex_count(), c.polygons.face_count()), (12, 10));
        assert!((c.polygons.volume() - 2.0).abs() < 1e-12);
    }

    #[test]
    fn joined_vertices_sit_at_the_average() {
        // A gap of 0.2 between the blocks: the joined rim lies halfway.
        let mut m = BlockModel::new();
        m.allow(0, 0);
        m.add(boxed([0.0; 3], [1.0; 3]));
        m.add(boxed([1.2, 0.0, 0.0], [2.2, 1.0, 1.0]));
        let c = m.control_mesh().unwrap();
        check_closed(&c);
        let at_rim = c.polygons.positions().iter().filter(|p| (p.x - 1.1).abs() < 1e-12).count();
        assert_eq!(at_rim, 4);
    }

    #[test]
    fn an_l_of_three_blocks_is_one_solid() {
        let mut m = BlockModel::new();
        m.allow(0, 0);
        m.add(boxed([0.0; 3], [1.0; 3]));
        m.add(boxed([1.0, 0.0, 0.0], [2.0, 1.0, 1.0]));
        m.add(boxed([0.0, 1.0, 0.0], [1.0, 2.0, 1.0]));
        assert_eq!(m.connections().unwrap().len(), 2);
        let c = m.control_mesh().unwrap();
        check_closed(&c);
        assert_eq!((c.polygons.vertex_count(), c.polygons.face_count()), (16, 14));
        assert!((c.polygons.volume() - 3.0).abs() < 1e-12);
    }

    #[test]
    fn four_blocks_around_an_edge_join_at_one_vertex() {
        // Fig. 9: a 2 × 2 × 1 arrangement; the central vertical edge loses every face, and the
        // top and bottom vertices on it join four blocks (valence 4).
        let mut m = BlockModel::new();
        m.allow(0, 0);
        for (x, y) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
            m.add(boxed([x, y, 0.0], [x + 1.0, y + 1.0, 1.0]));
        }
        assert_eq!(m.connections().unwrap().len(), 4);
        let c = m.control_mesh().unwrap();
        check_closed(&c);
        assert_eq!((c.polygons.vertex_count(), c.polygons.face_count()), (18, 16));
        let centre = (0..c.polygons.vertex_count() as u32)
            .find(|&v| c.polygons.position(v).distance(Vec3::new(1.0, 1.0, 1.0)) < 1e-12)
            .unwrap();
        assert_eq!(c.polygons.valence(centre), 4);
        // Eight blocks in a 2 × 2 × 2 cube: the centre vertex is interior and dropped.
        let mut m = BlockModel::new();
        m.allow(0, 0);
        for k in 0..8 {
            let o = [f64::from(k & 1), f64::from((k >> 1) & 1), f64::from((k >> 2) & 1)];
            m.add(boxed(o, [o[0] + 1.0, o[1] + 1.0, o[2] + 1.0]));
        }
        assert_eq!(m.connections().unwrap().len(), 12);
        let c = m.control_mesh().unwrap();
        check_closed(&c);
        assert_eq!((c.polygons.vertex_count(), c.polygons.face_count()), (26, 24));
        assert!((c.polygons.volume() - 8.0).abs() < 1e-12);
    }

    #[test]
    fn the_hand_joins_fingers_to_sub_faces_of_the_palm() {
        let m = hand();
        let conns = m.connections().unwrap();
        assert_eq!(conns.len(), 5);
        // The thumb joins the middle of the three side sub-faces.
        let thumb = conns.iter().find(|c| c.b.block == 5).unwrap();
        assert_eq!((thumb.a.face, thumb.a.sub), (Face::NegX, 1));
        let c = m.control_mesh().unwrap();
        check_closed(&c);
        // Palm: 2 of 3 side sub-faces and 4 whole faces remain; 5 faces per finger and thumb.
        assert_eq!(c.polygons.face_count(), 6 + 5 * 5);
    }

    #[test]
    fn unequal_rims_get_the_t_vertices_of_both_sides() {
        // Block 0's +x face is whole, but its neighbour faces divide the shared edges in 2; block
        // 1's -x face is whole with its neighbours divided in 3. The glued rim carries both.
        let mut a = boxed([0.0; 3], [1.0; 3]);
        a.subdivide(Face::PosY, 1, 2).unwrap();
        let mut b = boxed([1.0, 0.0, 0.0], [2.0, 1.0, 1.0]);
        b.subdivide(Face::PosY, 1, 3).unwrap();
        b.subdivide(Face::PosZ, 1, 3).unwrap();
        let mut m = BlockModel::new();
        m.allow(0, 0);
        m.add(a);
        m.add(b);
        let c = m.control_mesh().unwrap();
        check_closed(&c);
        // Block 0's +y face (1 × 2) and block 1's +y face (1 × 3) meet at the rim x = 1, y = 1,
        // which carries z = 1/3, 1/2, 2/3 from both sides, plus its two ends.
        let on_rim =
            c.polygons.positions().iter().filter(|p| (p.x - 1.0).abs() < 1e-12 && (p.y - 1.0).abs() < 1e-12).count();
        assert_eq!(on_rim, 5);
        assert!((c.polygons.volume() - 2.0).abs() < 1e-12);
    }
}
