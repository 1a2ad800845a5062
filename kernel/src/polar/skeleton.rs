//! The skeleton inferred from a polar mesh (seed 004, §7.1) and skeleton-based coordinates
//! (§7.2): the base for animation (skinning, growth, gravity) and for L-systems.
//!
//! Nodes. Every pole is a node, at the pole. Every *loop complex* is a node, at the mean of its
//! vertices: a loop complex is a connected set of loop edges — a simple loop, or a nesting loop
//! together with the far sides of the gaps nested on it (the walks over, under and around a
//! gap all meet at its split vertices). This is the thesis's grouping: a nested feature hangs
//! from the node of the loop it is nested on (`skeletonInit(f, current)` in §7.1).
//!
//! Segments. Every region is a segment ("bone", §3.4.1): an annular region (a ring of quads)
//! joins the nodes of its two loops, a pole region (a fan) joins its pole to its loop. Faces
//! that share a backbone belong to one region. Parallel segments and self-loops are kept, so the
//! graph is a multigraph whose independent cycles match the handles of the surface: for a
//! connected polar mesh, `cycle_count() == genus` (the ladder's rungs − 1, the gear's 1).
//!
//! Binding. Every vertex is bound to one node: a pole to itself, any other vertex to its loop
//! complex ("simple skinning", §7.3).
//!
//! Rooted tree (§7.1.1). From a chosen root the graph is explored depth first (as the thesis's
//! recursive `skeletonInit`), visiting every segment once: the segments that reach a new node form
//! a spanning tree (`parent`, `children`); the others close cycles (`cycle_segments`). Parts of
//! the mesh not connected to the root get their own roots, by ascending node id.
//!
//! Coordinates (§7.2). A vertex's position is its node's position plus the vertex's offset from
//! the node; a node's position is its parent's plus the node's offset. Changing node offsets
//! moves the structure, changing vertex offsets the details: see
//! [`Skeleton::positions_from`].

use super::select_feature::Dsu;
use super::{PolarError, PolarMesh};
use crate::math::Vec3;

const NONE: u32 = u32::MAX;

/// The inferred skeleton of a polar mesh: nodes, segments, the vertex binding and a rooted
/// spanning tree. Built by [`PolarMesh::skeleton`]; it is a snapshot, not updated by later edits.
#[derive(Clone, Debug, PartialEq)]
pub struct Skeleton {
    positions: Vec<Vec3>,
    normals: Vec<Vec3>,
    pole_vertex: Vec<Option<u32>>,
    node_vertices: Vec<Vec<u32>>,
    segments: Vec<[u32; 2]>,
    segment_faces: Vec<Vec<u32>>,
    face_segment: Vec<u32>,
    vertex_node: Vec<u32>,
    vertex_offsets: Vec<Vec3>,
    adjacency: Vec<Vec<(u32, u32)>>,
    root: u32,
    roots: Vec<u32>,
    parent: Vec<Option<u32>>,
    parent_segment: Vec<Option<u32>>,
    children: Vec<Vec<u32>>,
    depth: Vec<u32>,
    order: Vec<u32>,
    in_tree: Vec<bool>,
}

impl PolarMesh {
    /// Infers the skeleton (seed 004, §7.1) with the node of vertex `root` as the root of the
    /// tree; `None` picks the node of the lowest-numbered pole, or node 0 on a mesh without
    /// poles. Linear time in the size of the mesh.
    ///
    /// # Errors
    /// [`PolarError::NoSuchElement`] for a bad root; [`PolarError::Internal`] if the mesh breaks a
    /// polar invariant (a region touching more than two nodes).
    pub fn skeleton(&self, root: Option<u32>) -> Result<Skeleton, PolarError> {
        if let Some(r) = root {
            self.vertex_id(i64::from(r))?;
        }
        Skeleton::infer(self, root)
    }
}

impl Skeleton {
    /// See [`PolarMesh::skeleton`]. Polls the current cancellation token every
    /// [`crate::limits::POLL_EVERY`] elements of each pass.
    ///
    /// # Errors
    /// As [`PolarMesh::skeleton`], and [`PolarError::Limit`] when the token stops the work.
    pub fn infer(pm: &PolarMesh, root: Option<u32>) -> Result<Skeleton, PolarError> {
        let m = pm.mesh();
        let (nv, nf) = (m.vertex_count(), m.face_count());
        // 1. Loop complexes.
        let mut loops = Dsu::new(nv);
        for (i, h) in m.edges().enumerate() {
            crate::limits::poll_at(i)?;
            if pm.is_loop(h) {
                loops.union(m.origin(h), m.target(h));
            }
        }
        // 2. Nodes, numbered by their lowest vertex.
        let mut node_of_root = vec![NONE; nv];
        let mut vertex_node = vec![NONE; nv];
        let mut pole_vertex: Vec<Option<u32>> = Vec::new();
        let mut node_vertices: Vec<Vec<u32>> = Vec::new();
        for v in 0..nv as u32 {
            crate::limits::poll_at(v as usize)?;
            let n = if pm.is_pole(v) {
                pole_vertex.push(Some(v));
                node_vertices.push(Vec::new());
                (pole_vertex.len() - 1) as u32
            } else {
                let r = loops.find(v) as usize;
                if node_of_root[r] == NONE {
                    node_of_root[r] = pole_vertex.len() as u32;
                    pole_vertex.push(None);
                    node_vertices.push(Vec::new());
                }
                node_of_root[r]
            };
            vertex_node[v as usize] = n;
            node_vertices[n as usize].push(v);
        }
        let nn = pole_vertex.len();
        let mut positions = Vec::with_capacity(nn);
        let mut normals = Vec::with_capacity(nn);
        for n in 0..nn {
            crate::limits::poll_at(n)?;
            let vs = &node_vertices[n];
            positions.push(crate::math::mean_point(vs.iter().map(|&v| m.position(v))));
            let normal = match pole_vertex[n] {
                Some(p) => m.vertex_faces(p).map(|f| m.face_vector_area(f)).sum::<Vec3>(),
                None => {
                    let h = m.outgoing(vs[0]).find(|&h| pm.is_loop(h));
                    let walk = h.map(|h| pm.walk_of(h)).unwrap_or_default();
                    let c = positions[n];
                    walk.iter().map(|&x| (m.position(m.origin(x)) - c).cross(m.position(m.target(x)) - c)).sum::<Vec3>()
                }
            };
            normals.push(normal.normalize_or_zero());
        }
        // 3. Regions (faces joined across backbones) are the segments, numbered by lowest face.
        let mut regions = Dsu::new(nf);
        for (i, h) in m.edges().enumerate() {
            crate::limits::poll_at(i)?;
            if !pm.is_loop(h) {
                regions.union(m.face(h), m.face(m.twin(h)));
            }
        }
        let mut region_of_root = vec![NONE; nf];
        let mut face_segment = vec![NONE; nf];
        let mut segments: Vec<[u32; 2]> = Vec::new();
        let mut segment_faces: Vec<Vec<u32>> = Vec::new();
        for f in 0..nf as u32 {
            crate::limits::poll_at(f as usize)?;
            let r = regions.find(f) as usize;
            if region_of_root[r] == NONE {
                region_of_root[r] = segments.len() as u32;
                segments.push([NONE, NONE]);
                segment_faces.push(Vec::new());
            }
            let s = region_of_root[r];
            face_segment[f as usize] = s;
            segment_faces[s as usize].push(f);
            for h in m.face_halfedges(f) {
                let v = m.origin(h);
                if pm.is_loop(h) || pm.is_pole(v) {
                    let n = vertex_node[v as usize];
                    let e = &mut segments[s as usize];
                    if e[0] == NONE || e[0] == n {
                        e[0] = n;
                    } else if e[1] == NONE || e[1] == n {
                        e[1] = n;
                    } else {
                        return Err(PolarError::Internal(format!(
                            "region of face {f} touches three skeleton nodes ({}, {}, {n})",
                            e[0], e[1]
                        )));
                    }
                }
            }
        }
        for (s, e) in segments.iter_mut().enumerate() {
            if e[0] == NONE {
                return Err(PolarError::Internal(format!("region {s} has no loop")));
            }
            if e[1] == NONE {
                e[1] = e[0];
            }
        }
        let mut adjacency: Vec<Vec<(u32, u32)>> = vec![Vec::new(); nn];
        for (s, &[a, b]) in segments.iter().enumerate() {
            adjacency[a as usize].push((s as u32, b));
            if a != b {
                adjacency[b as usize].push((s as u32, a));
            }
        }
        // 4. Depth-first spanning forest from the root.
        let root_node = match root {
            Some(v) => vertex_node[v as usize],
            None => pm.poles().first().map(|&p| vertex_node[p as usize]).unwrap_or(0),
        };
        let mut sk = Skeleton {
            vertex_offsets: (0..nv).map(|v| m.position(v as u32) - positions[vertex_node[v] as usize]).collect(),
            positions,
            normals,
            pole_vertex,
            node_vertices,
            in_tree: vec![false; segments.len()],
            segments,
            segment_faces,
            face_segment,
            vertex_node,
            adjacency,
            root: root_node,
            roots: Vec::new(),
            parent: vec![None; nn],
            parent_segment: vec![None; nn],
            children: vec![Vec::new(); nn],
            depth: vec![0; nn],
            order: Vec::with_capacity(nn),
        };
        let mut visited = vec![false; nn];
        let starts = std::iter::once(root_node).chain(0..nn as u32);
        for start in starts {
            if nn == 0 || visited[start as usize] {
                continue;
            }
            sk.roots.push(start);
            visited[start as usize] = true;
            sk.order.push(start);
            let mut stack: Vec<(u32, usize)> = vec![(start, 0)];
            while let Some(top) = stack.last_mut() {
                let (n, i) = (top.0, top.1);
                if i >= sk.adjacency[n as usize].len() {
                    stack.pop();
                    continue;
                }
                top.1 += 1;
                let (s, o) = sk.adjacency[n as usize][i];
                if !visited[o as usize] {
                    visited[o as usize] = true;
                    sk.parent[o as usize] = Some(n);
                    sk.parent_segment[o as usize] = Some(s);
                    sk.in_tree[s as usize] = true;
                    sk.depth[o as usize] = sk.depth[n as usize] + 1;
                    sk.children[n as usize].push(o);
                    sk.order.push(o);
                    stack.push((o, 0));
                }
            }
        }
        Ok(sk)
    }

    /// Number of nodes.
    #[must_use]
    pub fn node_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of segments (regions).
    #[must_use]
    pub fn segment_count(&self) -> usize {
        self.segments.len()
    }

    /// The segments as `[node, node]` pairs (equal for a region whose two loops are one
    /// complex), indexed by segment id.
    #[must_use]
    pub fn segments(&self) -> &[[u32; 2]] {
        &self.segments
    }

    /// The faces of segment `s` (its region), ascending.
    #[must_use]
    pub fn segment_faces(&self, s: u32) -> &[u32] {
        &self.segment_faces[s as usize]
    }

    /// The segment (region) face `f` belongs to.
    #[must_use]
    pub fn segment_of_face(&self, f: u32) -> u32 {
        self.face_segment[f as usize]
    }

    /// The position of node `i` when inferred: a pole's position, or the mean of a loop
    /// complex's vertices (§3.4.1).
    #[must_use]
    pub fn position(&self, i: u32) -> Vec3 {
        self.positions[i as usize]
    }

    /// All node positions, indexed by node.
    #[must_use]
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// A unit normal of node `i`: the plane normal of its loop (right-hand rule along one walk)
    /// or, for a pole, the surface normal there; zero when degenerate.
    #[must_use]
    pub fn normal(&self, i: u32) -> Vec3 {
        self.normals[i as usize]
    }

    /// Whether node `i` is a pole.
    #[must_use]
    pub fn is_pole(&self, i: u32) -> bool {
        self.pole_vertex[i as usize].is_some()
    }

    /// The pole vertex of node `i`, if it is a pole node.
    #[must_use]
    pub fn pole_vertex(&self, i: u32) -> Option<u32> {
        self.pole_vertex[i as usize]
    }

    /// The vertices bound to node `i`, ascending.
    #[must_use]
    pub fn vertices(&self, i: u32) -> &[u32] {
        &self.node_vertices[i as usize]
    }

    /// The node vertex `v` is bound to.
    #[must_use]
    pub fn node_of(&self, v: u32) -> u32 {
        self.vertex_node[v as usize]
    }

    /// The node of every vertex, indexed by vertex.
    #[must_use]
    pub fn vertex_nodes(&self) -> &[u32] {
        &self.vertex_node
    }

    /// The segments at node `i` as `(segment, other node)` pairs, by ascending segment.
    #[must_use]
    pub fn neighbors(&self, i: u32) -> &[(u32, u32)] {
        &self.adjacency[i as usize]
    }

    /// The root chosen at inference.
    #[must_use]
    pub fn root(&self) -> u32 {
        self.root
    }

    /// The roots of the spanning forest: the chosen root first, then one per other connected part.
    #[must_use]
    pub fn roots(&self) -> &[u32] {
        &self.roots
    }

    /// The parent of node `i` in the rooted tree (`None` for a root).
    #[must_use]
    pub fn parent(&self, i: u32) -> Option<u32> {
        self.parent[i as usize]
    }

    /// The tree segment joining node `i` to its parent.
    #[must_use]
    pub fn parent_segment(&self, i: u32) -> Option<u32> {
        self.parent_segment[i as usize]
    }

    /// The children of node `i` in the rooted tree, in visiting order.
    #[must_use]
    pub fn children(&self, i: u32) -> &[u32] {
        &self.children[i as usize]
    }

    /// The number of tree segments between node `i` and its root.
    #[must_use]
    pub fn depth(&self, i: u32) -> u32 {
        self.depth[i as usize]
    }

    /// Every node once, depth first from the root (parents before children), then the other
    /// parts of a disconnected mesh.
    #[must_use]
    pub fn depth_first_order(&self) -> &[u32] {
        &self.order
    }

    /// Whether segment `s` belongs to the spanning tree (otherwise it closes a cycle).
    #[must_use]
    pub fn is_tree_segment(&self, s: u32) -> bool {
        self.in_tree[s as usize]
    }

    /// The segments outside the spanning tree, each closing one independent cycle.
    #[must_use]
    pub fn cycle_segments(&self) -> Vec<u32> {
        (0..self.segments.len() as u32).filter(|&s| !self.in_tree[s as usize]).collect()
    }

    /// The number of independent cycles: segments − nodes + connected parts. Equals the genus
    /// of a connected polar mesh (the ladder has rungs − 1, the gear 1).
    #[must_use]
    pub fn cycle_count(&self) -> usize {
        self.segments.len() + self.roots.len() - self.positions.len()
    }

    /// The number of connected parts.
    #[must_use]
    pub fn component_count(&self) -> usize {
        self.roots.len()
    }

    /// Skeleton-based coordinates of node `i` (§7.2): its position relative to its parent (its
    /// position for a root).
    #[must_use]
    pub fn node_offset(&self, i: u32) -> Vec3 {
        match self.parent[i as usize] {
            Some(p) => self.positions[i as usize] - self.positions[p as usize],
            None => self.positions[i as usize],
        }
    }

    /// All node offsets ([`Skeleton::node_offset`]), indexed by node.
    #[must_use]
    pub fn node_offsets(&self) -> Vec<Vec3> {
        (0..self.node_count() as u32).map(|i| self.node_offset(i)).collect()
    }

    /// Skeleton-based coordinates of vertex `v` (§7.2): its position relative to its node.
    #[must_use]
    pub fn vertex_offset(&self, v: u32) -> Vec3 {
        self.vertex_offsets[v as usize]
    }

    /// All vertex offsets, indexed by vertex.
    #[must_use]
    pub fn vertex_offsets(&self) -> &[Vec3] {
        &self.vertex_offsets
    }

    /// Node positions from node offsets (#nodes, each relative to its parent): accumulated from
    /// the roots down the tree.
    ///
    /// # Errors
    /// [`PolarError::InvalidArgument`] for a wrong count.
    pub fn node_positions_from(&self, node_offsets: &[Vec3]) -> Result<Vec<Vec3>, PolarError> {
        if node_offsets.len() != self.node_count() {
            return Err(PolarError::InvalidArgument(format!(
                "{} node offsets given for {} nodes",
                node_offsets.len(),
                self.node_count()
            )));
        }
        let mut out = vec![Vec3::ZERO; self.node_count()];
        for &i in &self.order {
            let base = self.parent[i as usize].map_or(Vec3::ZERO, |p| out[p as usize]);
            out[i as usize] = base + node_offsets[i as usize];
        }
        Ok(out)
    }

    /// Vertex positions from skeleton-based coordinates (§7.2): each vertex at its node's
    /// position (accumulated from `node_offsets`, #nodes) plus its offset (`vertex_offsets`,
    /// #vertices). With the skeleton's own offsets this gives back the mesh positions.
    ///
    /// # Errors
    /// [`PolarError::InvalidArgument`] for wrong counts.
    pub fn positions_from(&self, node_offsets: &[Vec3], vertex_offsets: &[Vec3]) -> Result<Vec<Vec3>, PolarError> {
        if vertex_offsets.len() != self.vertex_node.len() {
            return Err(PolarError::InvalidArgument(format!(
                "{} vertex offsets given for {} vertices",
                vertex_offsets.len(),
                self.vertex_node.len()
            )));
        }
        let nodes = self.node_positions_from(node_offsets)?;
        Ok(self.vertex_node.iter().zip(vertex_offsets).map(|(&n, &o)| nodes[n as usize] + o).collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stop_lands_inside_inferring_a_large_skeleton() {
        use crate::limits::{install, CancelToken, LimitError, StopReason};
        use std::sync::atomic::AtomicBool;
        use std::sync::Arc;
        let pm = PolarMesh::uv_sphere(1.0, 300, 300);
        assert!(pm.mesh().vertex_count() > crate::limits::POLL_EVERY);
        {
            let _g = install(CancelToken::with(Some(Arc::new(AtomicBool::new(true))), None, None));
            let e = pm.skeleton(None).unwrap_err();
            assert!(matches!(e, PolarError::Limit(LimitError::Stopped(StopReason::Interrupted))), "{e}");
        }
        assert_eq!(pm.skeleton(None).unwrap().node_count(), 301);
    }

    #[test]
    fn sphere_skeleton_is_a_chain_pole_loops_pole() {
        // 8×5 UV sphere: 2 poles + 4 loops = 6 nodes, 5 regions (2 fans, 3 rings), a chain.
        let pm = PolarMesh::uv_sphere(1.0, 8, 5);
        let sk = pm.skeleton(None).unwrap();
        assert_eq!((sk.node_count(), sk.segment_count(), sk.cycle_count()), (6, 5, 0));
        assert_eq!(sk.root(), sk.node_of(0));
        assert!(sk.is_pole(sk.root()));
        // A chain: every node has at most one child.
        assert!((0..6).all(|i| sk.children(i).len() <= 1));
        assert_eq!(sk.depth_first_order().len(), 6);
        // Loop centres lie on the z axis.
        for i in 0..6 {
            let p = sk.position(i);
            assert!(p.truncate().length() < 1e-12, "node {i} at {p}");
        }
        // Skeleton coordinates reproduce the mesh.
        let back = sk.positions_from(&sk.node_offsets(), sk.vertex_offsets()).unwrap();
        for (v, p) in back.iter().enumerate() {
            assert!(p.distance(pm.position(v as u32)) < 1e-12);
        }
    }

    #[test]
    fn a_branch_hangs_from_its_nesting_loop_and_a_handle_adds_a_cycle() {
        let mut pm = PolarMesh::uv_sphere(1.0, 8, 4);
        let p = pm.add_feature(&[9, 10, 11]).unwrap();
        let sk = pm.skeleton(None).unwrap();
        // 2 poles + 3 loops + the branch's pole; 4 + 1 segments; the branch's pole node hangs
        // from the equator's node.
        assert_eq!((sk.node_count(), sk.segment_count(), sk.cycle_count()), (6, 5, 0));
        let pn = sk.node_of(p);
        assert_eq!(sk.parent(pn), Some(sk.node_of(9)));
        // A second branch on the equator merged with the first makes a handle: one cycle.
        let q = pm.add_feature(&[13, 14, 15]).unwrap();
        pm.merge_features(i64::from(p), i64::from(q)).unwrap();
        pm.check().unwrap();
        let sk = pm.skeleton(Some(0)).unwrap();
        assert_eq!(pm.mesh().genus(), 1);
        assert_eq!(sk.cycle_count(), 1);
        assert_eq!(sk.cycle_segments().len(), 1);
    }

    #[test]
    fn torus_without_poles_is_one_cycle() {
        let t = crate::mesh::Mesh::torus(2.0, 0.5, 8, 6);
        let pm = PolarMesh::from_mesh(t, &[], &[[0, 1]]).unwrap();
        let sk = pm.skeleton(None).unwrap();
        // 8 tube circles (loops) and 8 rings between them: a cycle of 8.
        assert_eq!((sk.node_count(), sk.segment_count(), sk.cycle_count()), (8, 8, 1));
        assert!(matches!(pm.skeleton(Some(999)), Err(PolarError::NoSuchElement { .. })));
    }
}
