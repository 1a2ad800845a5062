//! Handle loops: for each handle of a surface, a short closed loop of edges around it, such
//! that cutting the surface along all of them leaves genus 0.
//!
//! Dey, Li, Sun and Cohen-Steiner ("Computing geometry-aware handle and tunnel loops in 3D
//! models", SIGGRAPH 2008) find each handle's loop from the persistence of the inside and
//! outside volumes. This is the equivalent that needs no volume, after Erickson and Whittlesey
//! ("Greedy optimal homotopy and homology generators", SODA 2005, §3–4):
//! 1. a shortest-path tree T from a root vertex (Dijkstra, edge lengths);
//! 2. a maximum spanning tree C of the dual graph (faces, and one node per boundary loop so the
//!    surface is closed) over the edges not in T, each weighted by the length of its loop
//!    σ(e) = path(root, u) + e + path(v, root): the 2g edges in neither tree give the greedy
//!    shortest system of loops through the root, a basis of the surface's homology;
//! 3. each loop without the tail its two tree paths share (a cycle through their last common
//!    vertex, shorter and homologous);
//! 4. the loops in order of length, each kept when cutting the surface along it and the loops
//!    kept before lowers the genus by one (checked by building the cut surface), until g are
//!    kept: so every handle gets the shortest basis loop that goes around it, and the kept loops
//!    cut the surface's genus to 0;
//! 5. steps 1–4 again with the candidates of roots on each loop found as well: a handle far
//!    from the first root gets its loop from a root beside it.
//!
//! Cost per component of genus g with n elements: O(min(g, 16)·n log n) for the trees,
//! O(g²·n) for the cut checks (at most 2g candidates per root). Loops are computed for at most [`MAX_HANDLES`] handles in
//! all.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use crate::mesh::{Mesh, MeshError, NONE};

/// Handles whose loops are computed, at most, over the whole mesh (a noisy voxel surface can
/// have thousands; the count is still reported by the components' genus).
pub const MAX_HANDLES: usize = 64;

/// Loops of the first pass from whose vertices the search is run again, at most, per
/// component.
const REROOTS: usize = 16;

/// A closed loop of edges around one handle.
#[derive(Clone, Debug, PartialEq)]
pub struct HandleLoop {
    /// The loop's vertices in order (the edge from the last back to the first closes it).
    pub vertices: Vec<u32>,
    /// The loop's half-edges in order (`origin(halfedges[i]) == vertices[i]`).
    pub halfedges: Vec<u32>,
    /// The loop's length.
    pub length: f64,
    /// The component it lies on (index into [`Mesh::face_components`]).
    pub component: usize,
}

/// One loop per handle of `mesh` (up to [`MAX_HANDLES`] in all), components in order, each
/// component's loops shortest first. See the module documentation.
///
/// # Errors
/// [`MeshError::Limit`] when the current cancellation token stops.
pub fn handle_loops(mesh: &Mesh) -> Result<Vec<HandleLoop>, MeshError> {
    let comps = mesh.face_components();
    let mut face_comp = vec![0u32; mesh.face_count()];
    for (c, faces) in comps.iter().enumerate() {
        for &f in faces {
            face_comp[f as usize] = c as u32;
        }
    }
    let genus = component_genus(mesh, &comps, &face_comp);
    let mut out = Vec::new();
    for (c, faces) in comps.iter().enumerate() {
        let g = genus[c];
        if g <= 0 || out.len() >= MAX_HANDLES {
            continue;
        }
        crate::limits::poll()?;
        let budget = MAX_HANDLES - out.len();
        let root = faces.iter().flat_map(|&f| mesh.face_vertices(f)).min().unwrap_or(0);
        let mut candidates = basis_loops(mesh, faces, root)?;
        let first = greedy(mesh, faces, g, budget, &candidates)?;
        // Step 5: again from a root on each loop found (a loop far from the first root has
        // a long tail or goes the long way round; from a vertex on it, the short loop around
        // the same handle is among the shortest), all candidates together.
        for (_, hs) in first.iter().take(REROOTS) {
            let mid = mesh.origin(hs[hs.len() / 2]);
            candidates.extend(basis_loops(mesh, faces, mid)?);
        }
        candidates.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        candidates.dedup();
        let second = greedy(mesh, faces, g, budget, &candidates)?;
        let kept = if second.len() >= first.len() { second } else { first };
        out.extend(kept.into_iter().map(|(length, hs)| HandleLoop {
            vertices: hs.iter().map(|&h| mesh.origin(h)).collect(),
            halfedges: hs,
            length,
            component: c,
        }));
    }
    Ok(out)
}

/// Loops taken from the candidates in order, each kept when cutting along it and the loops
/// kept before lowers the genus by one (step 4), until `g` (or `budget`) are kept.
fn greedy(
    mesh: &Mesh,
    faces: &[u32],
    g: i64,
    budget: usize,
    candidates: &[(f64, Vec<u32>)],
) -> Result<Vec<(f64, Vec<u32>)>, MeshError> {
    let mut kept: Vec<(f64, Vec<u32>)> = Vec::new();
    let mut cut = vec![false; mesh.halfedge_count()];
    let mut current = g;
    let mark = |cut: &mut [bool], hs: &[u32], on: bool| {
        for &h in hs {
            cut[h as usize] = on;
            cut[mesh.twin(h) as usize] = on;
        }
    };
    for (length, hs) in candidates {
        if kept.len() as i64 >= g || kept.len() >= budget {
            break;
        }
        crate::limits::poll()?;
        mark(&mut cut, hs, true);
        let after = cut_genus(mesh, faces, &cut)?;
        if after == current - 1 {
            current = after;
            kept.push((*length, hs.clone()));
        } else {
            mark(&mut cut, hs, false);
            for (_, k) in &kept {
                mark(&mut cut, k, true);
            }
        }
    }
    Ok(kept)
}

/// The genus of each component, from χ = 2 − 2g − b per component.
pub(crate) fn component_genus(mesh: &Mesh, comps: &[Vec<u32>], face_comp: &[u32]) -> Vec<i64> {
    let n = comps.len();
    let mut chi = vec![0i64; n];
    let mut loops = vec![0i64; n];
    for (c, faces) in comps.iter().enumerate() {
        chi[c] += faces.len() as i64;
    }
    let comp_of_h = |h: u32| {
        let f = mesh.face(h);
        let f = if f == NONE { mesh.face(mesh.twin(h)) } else { f };
        face_comp[f as usize] as usize
    };
    for h in mesh.edges() {
        chi[comp_of_h(h)] -= 1;
    }
    for v in 0..mesh.vertex_count() as u32 {
        let h = mesh.vertex_halfedge(v);
        if h != NONE {
            chi[comp_of_h(h)] += 1;
        }
    }
    for l in mesh.boundary_loops() {
        loops[comp_of_h(l[0])] += 1;
    }
    (0..n).map(|c| (2 - chi[c] - loops[c]) / 2).collect()
}

/// A distance in Dijkstra's heap: the smallest first.
#[derive(PartialEq)]
struct Near(f64, u32);

impl Eq for Near {}

impl PartialOrd for Near {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Near {
    fn cmp(&self, other: &Self) -> Ordering {
        other.0.total_cmp(&self.0).then(other.1.cmp(&self.1))
    }
}

/// The greedy system of loops through `root` of the component of `faces` (steps 1–3 of the module
/// documentation): each as (length, half-edges of the cycle), shortest first.
fn basis_loops(mesh: &Mesh, faces: &[u32], root: u32) -> Result<Vec<(f64, Vec<u32>)>, MeshError> {
    let len = |h: u32| (mesh.position(mesh.target(h)) - mesh.position(mesh.origin(h))).length();
    // 1. Shortest-path tree: parent half-edge (pointing at the vertex) and depth.
    let nv = mesh.vertex_count();
    let mut dist = vec![f64::INFINITY; nv];
    let mut parent = vec![NONE; nv];
    let mut depth = vec![0u32; nv];
    let mut heap = BinaryHeap::new();
    dist[root as usize] = 0.0;
    heap.push(Near(0.0, root));
    let mut steps = 0usize;
    while let Some(Near(d, v)) = heap.pop() {
        if d > dist[v as usize] {
            continue;
        }
        steps += 1;
        crate::limits::poll_at(steps)?;
        for h in mesh.outgoing(v) {
            let w = mesh.target(h);
            let nd = d + len(h);
            if nd < dist[w as usize] {
                dist[w as usize] = nd;
                parent[w as usize] = h;
                depth[w as usize] = depth[v as usize] + 1;
                heap.push(Near(nd, w));
            }
        }
    }
    let in_tree = |h: u32| {
        let (a, b) = (mesh.origin(h), mesh.target(h));
        parent[b as usize] == h || parent[a as usize] == mesh.twin(h)
    };
    // 2. Maximum spanning cotree over the dual graph: nodes are faces, then boundary loops.
    let nf = mesh.face_count();
    let mut loop_of = vec![NONE; mesh.halfedge_count()];
    let mut nloops = 0u32;
    for l in mesh.boundary_loops() {
        if faces.binary_search(&mesh.face(mesh.twin(l[0]))).is_ok() {
            for h in l {
                loop_of[h as usize] = nloops;
            }
            nloops += 1;
        }
    }
    let node = |h: u32| {
        let f = mesh.face(h);
        if f == NONE {
            nf as u32 + loop_of[h as usize]
        } else {
            f
        }
    };
    let mut dual: Vec<(f64, u32)> = Vec::new();
    for &f in faces {
        for h in mesh.face_halfedges(f) {
            let t = mesh.twin(h);
            // Each edge once: from the face side with the smaller half-edge, or its only face.
            if (mesh.face(t) != NONE && t < h) || in_tree(h) {
                continue;
            }
            let sigma = dist[mesh.origin(h) as usize] + len(h) + dist[mesh.target(h) as usize];
            dual.push((sigma, h));
        }
    }
    dual.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    let mut uf: Vec<u32> = (0..nf as u32 + nloops).collect();
    fn find(uf: &mut [u32], mut x: u32) -> u32 {
        while uf[x as usize] != x {
            uf[x as usize] = uf[uf[x as usize] as usize];
            x = uf[x as usize];
        }
        x
    }
    let mut leftover = Vec::new();
    for &(_, h) in &dual {
        let (a, b) = (find(&mut uf, node(h)), find(&mut uf, node(mesh.twin(h))));
        if a == b {
            leftover.push(h);
        } else {
            uf[a as usize] = b;
        }
    }
    // 3. Each leftover edge's cycle through the last common vertex of its two tree paths.
    let mut loops: Vec<(f64, Vec<u32>)> = leftover
        .into_iter()
        .map(|h| {
            let (mut a, mut b) = (mesh.origin(h), mesh.target(h));
            // Half-edges from the common vertex down to a, and from b up to it.
            let (mut down, mut up) = (Vec::new(), Vec::new());
            while a != b {
                if depth[a as usize] >= depth[b as usize] {
                    let p = parent[a as usize];
                    down.push(p);
                    a = mesh.origin(p);
                } else {
                    let p = parent[b as usize];
                    up.push(mesh.twin(p));
                    b = mesh.origin(p);
                }
            }
            down.reverse();
            let mut cycle = down;
            cycle.push(h);
            cycle.extend(up);
            (cycle.iter().map(|&x| len(x)).sum(), cycle)
        })
        .collect();
    loops.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    Ok(loops)
}

/// The genus of the surface of `faces` cut along the edges marked in `cut` (by half-edge, both
/// halves marked): corners are joined across uncut edges into vertices, and the cut surface
/// built and measured.
pub(crate) fn cut_genus(mesh: &Mesh, faces: &[u32], cut: &[bool]) -> Result<i64, MeshError> {
    let nh = mesh.halfedge_count();
    let mut uf: Vec<u32> = (0..nh as u32).collect();
    fn find(uf: &mut [u32], mut x: u32) -> u32 {
        while uf[x as usize] != x {
            uf[x as usize] = uf[uf[x as usize] as usize];
            x = uf[x as usize];
        }
        x
    }
    // A face half-edge stands for the corner at its origin.
    for &f in faces {
        for h in mesh.face_halfedges(f) {
            let t = mesh.twin(h);
            if cut[h as usize] || mesh.face(t) == NONE {
                continue;
            }
            // The corner at origin(h) in f and the corner at origin(h) in t's face (next(t)).
            let (a, b) = (find(&mut uf, h), find(&mut uf, mesh.next(t)));
            uf[a as usize] = b;
        }
    }
    let mut id = vec![NONE; nh];
    let mut count = 0u32;
    let mut indices = Vec::new();
    let mut arities = Vec::with_capacity(faces.len());
    for &f in faces {
        let mut a = 0;
        for h in mesh.face_halfedges(f) {
            let r = find(&mut uf, h) as usize;
            if id[r] == NONE {
                id[r] = count;
                count += 1;
            }
            indices.push(id[r]);
            a += 1;
        }
        arities.push(a);
    }
    let positions = vec![crate::math::Vec3::ZERO; count as usize];
    let cut_mesh = Mesh::from_indexed(positions, &indices, &arities)?;
    Ok(cut_mesh.genus())
}
