//! Local topological edits: replace a patch of faces by new polygons in time proportional to the
//! patch, keeping the mesh a 2-manifold.
//!
//! [`Mesh::replace_faces`] is the one primitive. It validates the whole edit before it changes
//! anything (so a refused edit leaves the mesh exactly as it was), then rewires only the patch.
//! The Euler-style operations are thin layers over it: [`Mesh::split_edge`], [`Mesh::split_face`],
//! [`Mesh::join_faces`], [`Mesh::dissolve_vertex`], [`Mesh::poke_face`], [`Mesh::unpoke_vertex`]
//! and [`Mesh::collapse_edge`]. Each keeps every invariant [`Mesh::is_manifold`] checks and never
//! creates two edges between the same pair of vertices, so the result always survives
//! [`Mesh::to_polygons`] → [`Mesh::from_polygons`].
//!
//! Ids. Deleted elements are removed by moving the last element of the array into the hole
//! ("swap-remove"), so every edit costs time proportional to the patch, never to the mesh; the
//! ids of moved elements change. New elements first take the slots of deleted ones. The
//! [`EditLog`] an edit returns records every move, so a caller keeping its own per-vertex,
//! per-half-edge or per-face arrays can follow (see [`EditLog::apply_vertex_moves`]).
//!
//! Scope: the patch must lie in the interior — no removed face and no vertex of one may touch
//! a boundary of the mesh — and the new polygons must close the patch exactly (every edge of
//! the result has a face on both sides). New edges get no crease tag; the edges the patch keeps
//! keep theirs. New vertices are not corners and, when the mesh has colours, are white.

use std::collections::HashMap;

use thiserror::Error;

use super::{Mesh, NONE};
use crate::math::{is_finite, IdMap, IdSet, Vec3};

/// Why a local edit was refused. The mesh is unchanged whenever one is returned.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum EditError {
    /// A vertex, half-edge or face id that does not exist.
    #[error("{what} {id} does not exist (the mesh has {count})")]
    NoSuchElement { what: &'static str, id: u64, count: usize },
    /// A face listed twice for removal.
    #[error("face {face} is listed twice for removal")]
    RepeatedFace { face: u32 },
    /// The patch touches a boundary of the mesh, which local edits do not handle.
    #[error("face or vertex {id} of the patch lies on a boundary of the mesh; local edits work on the interior only")]
    BoundaryPatch { id: u32 },
    /// A new polygon with fewer than three corners, a repeated corner or a corner out of range.
    #[error("new polygon {polygon} is degenerate: {reason}")]
    DegenerateFace { polygon: usize, reason: String },
    /// A new position that is NaN or infinite.
    #[error("new vertex {index} has a non-finite position")]
    NonFinite { index: usize },
    /// A new vertex that no new polygon uses.
    #[error("new vertex {index} is used by no new polygon")]
    UnusedNewVertex { index: usize },
    /// A directed edge that two faces of the result would share, or an edge that a face which
    /// stays already uses (the result would be non-manifold or have two edges between a and b).
    #[error(
        "edge ({a}, {b}) would be used twice: the result would be non-manifold or have two edges between {a} and {b}"
    )]
    EdgeInUse { a: u32, b: u32 },
    /// A new polygon's edge with no face on its other side: the result would have a boundary.
    #[error("edge ({a}, {b}) of the new polygons has no face on its other side: the result would have a hole")]
    OpenEdge { a: u32, b: u32 },
    /// An edge around the patch that no new polygon covers: the result would have a hole.
    #[error("edge ({a}, {b}) around the patch is covered by no new polygon: the result would have a hole")]
    HoleNotCovered { a: u32, b: u32 },
    /// A vertex whose faces would not form one fan (a pinch point).
    #[error("vertex {vertex} would be non-manifold: its faces would not form one fan")]
    NonManifoldVertex { vertex: u32 },
    /// An Euler operation asked for something its definition excludes.
    #[error("{0}")]
    Invalid(String),
    /// Too many elements for 32-bit ids.
    #[error("the mesh would be too large for 32-bit ids")]
    TooLarge,
}

/// What an edit changed: the final ids of what it added, and every move of an existing element.
///
/// Moves are `(from, to)` pairs in the order applied: the element at `from` (always the last
/// one of its array at that moment) now lives at `to`, the slot of a deleted element.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct EditLog {
    vertex_moves: Vec<(u32, u32)>,
    halfedge_moves: Vec<(u32, u32)>,
    face_moves: Vec<(u32, u32)>,
    /// Array lengths after the new elements were appended, before compaction: V, H, F.
    grown: [usize; 3],
    /// Array lengths after compaction: V, H, F.
    final_len: [usize; 3],
    new_faces: Vec<u32>,
    new_vertices: Vec<u32>,
    removed_vertices: Vec<u32>,
}

fn replay<T: Clone>(moves: &[(u32, u32)], grown: usize, final_len: usize, arr: &mut Vec<T>, fill: T) {
    arr.resize(grown, fill);
    for &(from, to) in moves {
        arr[to as usize] = arr[from as usize].clone();
    }
    arr.truncate(final_len);
}

fn follow(moves: &[(u32, u32)], mut id: u32) -> u32 {
    for &(from, to) in moves {
        if from == id {
            id = to;
        }
    }
    id
}

impl EditLog {
    /// The final ids of the added faces, in the order the polygons were given.
    #[must_use]
    pub fn new_faces(&self) -> &[u32] {
        &self.new_faces
    }

    /// The final ids of the new vertices, in the order their positions were given.
    #[must_use]
    pub fn new_vertices(&self) -> &[u32] {
        &self.new_vertices
    }

    /// The ids (before the edit) of the vertices the edit deleted because no face used them any
    /// more, ascending.
    #[must_use]
    pub fn removed_vertices(&self) -> &[u32] {
        &self.removed_vertices
    }

    /// The moves of vertices, `(from, to)`, in order.
    #[must_use]
    pub fn vertex_moves(&self) -> &[(u32, u32)] {
        &self.vertex_moves
    }

    /// The moves of half-edges, `(from, to)`, in order.
    #[must_use]
    pub fn halfedge_moves(&self) -> &[(u32, u32)] {
        &self.halfedge_moves
    }

    /// The moves of faces, `(from, to)`, in order.
    #[must_use]
    pub fn face_moves(&self) -> &[(u32, u32)] {
        &self.face_moves
    }

    /// Where a vertex that existed before the edit lives now, or `None` if the edit deleted it.
    /// Costs time proportional to the number of moves.
    #[must_use]
    pub fn map_vertex(&self, old: u32) -> Option<u32> {
        if self.removed_vertices.binary_search(&old).is_ok() {
            return None;
        }
        Some(follow(&self.vertex_moves, old))
    }

    /// Where every vertex the edit moved lives now, as `old id → new id` (only moved vertices
    /// are listed). Time proportional to the number of moves; use it for many look-ups.
    #[must_use]
    pub fn vertex_map(&self) -> HashMap<u32, u32> {
        let mut original_at: HashMap<u32, u32> = HashMap::with_capacity(self.vertex_moves.len());
        for &(from, to) in &self.vertex_moves {
            let o = original_at.remove(&from).unwrap_or(from);
            original_at.insert(to, o);
        }
        original_at.into_iter().map(|(slot, o)| (o, slot)).collect()
    }

    /// Where a half-edge that survived the edit lives now (the id is followed through the moves;
    /// the answer is meaningless for a half-edge the edit deleted).
    #[must_use]
    pub fn map_halfedge(&self, old: u32) -> u32 {
        follow(&self.halfedge_moves, old)
    }

    /// Where a face that survived the edit lives now (meaningless for a removed face).
    #[must_use]
    pub fn map_face(&self, old: u32) -> u32 {
        follow(&self.face_moves, old)
    }

    /// Brings a caller's per-vertex array (one entry per vertex before the edit) to the new
    /// vertex ids: grows it with `fill`, replays the moves and truncates. Entries of new vertices
    /// hold `fill` or a stale value afterwards; set them from [`EditLog::new_vertices`].
    pub fn apply_vertex_moves<T: Clone>(&self, arr: &mut Vec<T>, fill: T) {
        replay(&self.vertex_moves, self.grown[0], self.final_len[0], arr, fill);
    }

    /// Brings a caller's per-half-edge array to the new half-edge ids (see
    /// [`EditLog::apply_vertex_moves`]). Entries of new half-edges must be set afterwards.
    pub fn apply_halfedge_moves<T: Clone>(&self, arr: &mut Vec<T>, fill: T) {
        replay(&self.halfedge_moves, self.grown[1], self.final_len[1], arr, fill);
    }

    /// Brings a caller's per-face array to the new face ids (see
    /// [`EditLog::apply_vertex_moves`]). Entries of new faces must be set afterwards.
    pub fn apply_face_moves<T: Clone>(&self, arr: &mut Vec<T>, fill: T) {
        replay(&self.face_moves, self.grown[2], self.final_len[2], arr, fill);
    }
}

/// How one corner edge of a new polygon gets its half-edge.
#[derive(Clone, Copy)]
enum Plan {
    /// The half-edge of a removed face on the patch border, kept with its twin.
    Reuse(u32),
    /// A new half-edge, paired with the new corner edge running the other way (its index in
    /// the corner edges).
    New(usize),
}

/// A corner of a vertex: the vertex before it and the vertex after it in one face.
type Corner = (u32, u32);

/// Whether the corners around one vertex form a single closed fan: starting anywhere and
/// stepping from corner `(u, w)` to the corner entered from `w`, every corner is met once.
fn is_single_fan(corners: &mut [Corner]) -> bool {
    let n = corners.len();
    if n <= 12 {
        // Small fans (nearly every vertex): a walk with linear look-ups, no sort.
        if (1..n).any(|i| corners[..i].iter().any(|c| c.0 == corners[i].0)) {
            return false;
        }
        let mut at = 0usize;
        for step in 1..=n {
            let out = corners[at].1;
            match corners.iter().position(|c| c.0 == out) {
                Some(i) => at = i,
                None => return false,
            }
            if at == 0 {
                return step == n;
            }
        }
        return false;
    }
    corners.sort_unstable();
    if corners.windows(2).any(|w| w[0].0 == w[1].0) {
        return false;
    }
    let mut at = 0usize;
    for step in 1..=n {
        let out = corners[at].1;
        match corners.binary_search_by_key(&out, |c| c.0) {
            Ok(i) => at = i,
            Err(_) => return false,
        }
        if at == 0 {
            return step == n;
        }
    }
    false
}

fn repeated(corners: &[u32]) -> Option<u32> {
    if corners.len() <= 16 {
        (1..corners.len()).find(|&i| corners[..i].contains(&corners[i])).map(|i| corners[i])
    } else {
        let mut s = corners.to_vec();
        s.sort_unstable();
        s.windows(2).find(|w| w[0] == w[1]).map(|w| w[0])
    }
}

impl Mesh {
    fn check_face_id(&self, f: u32) -> Result<(), EditError> {
        if f as usize >= self.face_count() {
            return Err(EditError::NoSuchElement { what: "face", id: u64::from(f), count: self.face_count() });
        }
        Ok(())
    }

    fn check_he_id(&self, h: u32) -> Result<(), EditError> {
        if h as usize >= self.halfedge_count() {
            return Err(EditError::NoSuchElement { what: "half-edge", id: u64::from(h), count: self.halfedge_count() });
        }
        Ok(())
    }

    fn check_vertex_id(&self, v: u32) -> Result<(), EditError> {
        if v as usize >= self.vertex_count() {
            return Err(EditError::NoSuchElement { what: "vertex", id: u64::from(v), count: self.vertex_count() });
        }
        Ok(())
    }

    /// Replaces the faces `remove` by the polygons `add`, creating the vertices `new_positions`.
    ///
    /// Inputs:
    /// - `remove`: distinct face ids (the patch), none touching a boundary of the mesh;
    /// - `add`: polygons as corner lists, counter-clockwise seen from outside; a corner `< V`
    ///   names an existing vertex, a corner `V + i` the new vertex `new_positions[i]`;
    /// - `new_positions`: the positions of the new vertices (each must be used by a polygon).
    ///
    /// The result: the removed faces are gone with every edge and vertex only they used; the new
    /// polygons are faces, in the part (colour, origin) of the first removed face. Edges around
    /// the patch keep their half-edge ids (and crease tags);
    /// vertices and half-edges left without a face are deleted. Time and memory are
    /// proportional to the patch (the corners of removed and added faces, and the valences of
    /// their vertices), whatever the size of the mesh.
    ///
    /// # Errors
    /// Everything is checked before anything changes; on error the mesh is unchanged:
    /// - [`EditError::NoSuchElement`], [`EditError::RepeatedFace`] for bad face ids;
    /// - [`EditError::BoundaryPatch`] when the patch touches a boundary of the mesh;
    /// - [`EditError::DegenerateFace`], [`EditError::NonFinite`], [`EditError::UnusedNewVertex`]
    ///   for bad polygons or positions;
    /// - [`EditError::EdgeInUse`] when a directed edge would be used twice, or an edge a kept face
    ///   uses would be duplicated;
    /// - [`EditError::OpenEdge`], [`EditError::HoleNotCovered`] when the result would have a hole;
    /// - [`EditError::NonManifoldVertex`] when a vertex's faces would not form one fan;
    /// - [`EditError::TooLarge`] when ids would overflow 32 bits.
    ///
    /// See also the Euler operations of this module, built on this one.
    pub fn replace_faces<P: AsRef<[u32]>>(
        &mut self,
        remove: &[u32],
        add: &[P],
        new_positions: &[Vec3],
    ) -> Result<EditLog, EditError> {
        let nv0 = self.vertex_count();
        let nf0 = self.face_count();
        let nnew = new_positions.len();
        let total_corners: usize = add.iter().map(|p| p.as_ref().len()).sum();
        if nv0 + nnew >= NONE as usize
            || self.halfedge_count() + total_corners >= NONE as usize
            || nf0 + add.len() >= NONE as usize
        {
            return Err(EditError::TooLarge);
        }

        // 1. The patch: removed faces, the edges inside it and the border it leaves.
        let mut removed: IdSet<u32> = IdSet::with_capacity_and_hasher(remove.len() * 2, Default::default());
        for &f in remove {
            self.check_face_id(f)?;
            if !removed.insert(f) {
                return Err(EditError::RepeatedFace { face: f });
            }
        }
        let is_removed = |f: u32| f != NONE && removed.contains(&f);
        let mut border: IdMap<(u32, u32), u32> = IdMap::with_capacity_and_hasher(remove.len() * 4, Default::default());
        let mut dead_he: Vec<u32> = Vec::with_capacity(remove.len() * 4);
        let mut patch_vertices: Vec<u32> = Vec::with_capacity(remove.len() * 4);
        for &f in remove {
            for h in self.face_halfedges(f) {
                let g = self.face(self.twin(h));
                if g == NONE {
                    return Err(EditError::BoundaryPatch { id: f });
                }
                if is_removed(g) {
                    dead_he.push(h);
                } else {
                    border.insert((self.origin(h), self.target(h)), h);
                }
                patch_vertices.push(self.origin(h));
            }
        }

        // 2. The new polygons and positions.
        let limit = (nv0 + nnew) as u32;
        for (i, p) in new_positions.iter().enumerate() {
            if !is_finite(*p) {
                return Err(EditError::NonFinite { index: i });
            }
        }
        for (i, poly) in add.iter().enumerate() {
            let poly = poly.as_ref();
            if poly.len() < 3 {
                return Err(EditError::DegenerateFace {
                    polygon: i,
                    reason: format!("it has {} corners (at least 3 needed)", poly.len()),
                });
            }
            if let Some(&v) = poly.iter().find(|&&v| v >= limit) {
                return Err(EditError::DegenerateFace {
                    polygon: i,
                    reason: format!("corner {v} is neither a vertex nor a new vertex (limit {limit})"),
                });
            }
            if let Some(v) = repeated(poly) {
                return Err(EditError::DegenerateFace { polygon: i, reason: format!("vertex {v} appears twice") });
            }
        }

        // 3. Every directed edge of the new polygons: used once, paired, not clashing.
        let mut directed: IdMap<(u32, u32), usize> =
            IdMap::with_capacity_and_hasher(total_corners * 2, Default::default());
        let mut corner_edges: Vec<(u32, u32)> = Vec::with_capacity(total_corners);
        for poly in add {
            let poly = poly.as_ref();
            for (k, &a) in poly.iter().enumerate() {
                let b = poly[(k + 1) % poly.len()];
                if directed.insert((a, b), corner_edges.len()).is_some() {
                    return Err(EditError::EdgeInUse { a, b });
                }
                corner_edges.push((a, b));
            }
        }
        let mut plans: Vec<Plan> = Vec::with_capacity(total_corners);
        let mut covered = 0usize;
        for &(a, b) in &corner_edges {
            if let Some(&r) = border.get(&(a, b)) {
                plans.push(Plan::Reuse(r));
                covered += 1;
                continue;
            }
            if (a as usize) < nv0 && (b as usize) < nv0 {
                let existing = self.outgoing(a).find(|&h| self.target(h) == b);
                if let Some(h) = existing {
                    // Allowed only when both of its faces are removed (it is rebuilt).
                    if !(is_removed(self.face(h)) && is_removed(self.face(self.twin(h)))) {
                        return Err(EditError::EdgeInUse { a, b });
                    }
                }
            }
            match directed.get(&(b, a)) {
                Some(&t) => plans.push(Plan::New(t)),
                None => return Err(EditError::OpenEdge { a, b }),
            }
        }
        if covered != border.len() {
            let (&(a, b), _) =
                border.iter().find(|(k, _)| !directed.contains_key(k)).expect("an uncovered border edge exists");
            return Err(EditError::HoleNotCovered { a: b, b: a });
        }

        // 4. Every vertex the edit touches keeps (or gets) one closed fan of faces. The new
        // corners, sorted by vertex, are read alongside the sorted affected vertices.
        let mut new_corners: Vec<(u32, Corner)> = Vec::with_capacity(total_corners);
        for poly in add {
            let poly = poly.as_ref();
            let n = poly.len();
            for k in 0..n {
                new_corners.push((poly[k], (poly[(k + n - 1) % n], poly[(k + 1) % n])));
            }
        }
        new_corners.sort_unstable_by_key(|c| c.0);
        patch_vertices.sort_unstable();
        patch_vertices.dedup();
        // Both lists are sorted: merged, not sorted again.
        let mut affected: Vec<u32> = Vec::with_capacity(patch_vertices.len() + new_corners.len());
        {
            let (mut i, mut j) = (0, 0);
            while i < patch_vertices.len() || j < new_corners.len() {
                let v = if j == new_corners.len() || (i < patch_vertices.len() && patch_vertices[i] <= new_corners[j].0)
                {
                    i += 1;
                    patch_vertices[i - 1]
                } else {
                    j += 1;
                    new_corners[j - 1].0
                };
                if affected.last() != Some(&v) {
                    affected.push(v);
                }
            }
        }
        let mut dead_v: Vec<u32> = Vec::new();
        // Per affected vertex: a kept outgoing half-edge (NONE if none) and whether it has new
        // corners.
        let mut kept_out: Vec<u32> = vec![NONE; affected.len()];
        let mut has_new: Vec<bool> = vec![false; affected.len()];
        let mut corners: Vec<Corner> = Vec::with_capacity(16);
        let mut at = 0usize;
        for (i, &v) in affected.iter().enumerate() {
            corners.clear();
            if (v as usize) < nv0 {
                if self.is_boundary_vertex(v) {
                    return Err(EditError::BoundaryPatch { id: v });
                }
                for h in self.outgoing(v) {
                    if !is_removed(self.face(h)) {
                        corners.push((self.origin(self.prev(h)), self.target(h)));
                        if kept_out[i] == NONE {
                            kept_out[i] = h;
                        }
                    }
                }
            }
            while at < new_corners.len() && new_corners[at].0 == v {
                corners.push(new_corners[at].1);
                has_new[i] = true;
                at += 1;
            }
            if corners.is_empty() {
                if v as usize >= nv0 {
                    return Err(EditError::UnusedNewVertex { index: v as usize - nv0 });
                }
                dead_v.push(v);
                continue;
            }
            if !is_single_fan(&mut corners) {
                return Err(EditError::NonManifoldVertex { vertex: v });
            }
        }
        for i in 0..nnew {
            if new_corners.binary_search_by_key(&((nv0 + i) as u32), |c| c.0).is_err() {
                return Err(EditError::UnusedNewVertex { index: i });
            }
        }

        // ---- Everything is valid: mutate. ----
        // A topological edit does not know where its new faces came from; their part (colour,
        // origin) is the first removed face's.
        self.face_sources = None;
        let new_part = self.face_parts.as_ref().map(|ids| remove.first().map_or(0, |&f| ids[f as usize]));
        let mut log = EditLog { removed_vertices: dead_v.clone(), ..EditLog::default() };

        // 5. Slots: new elements take the slots of deleted ones first.
        let mut new_vid: Vec<u32> = Vec::with_capacity(nnew);
        for i in 0..nnew {
            let id = if i < dead_v.len() {
                dead_v[i]
            } else {
                self.positions.push(Vec3::ZERO);
                self.vertex_out.push(NONE);
                self.vertex_sharpness.push(0.0);
                if let Some(c) = &mut self.vertex_colors {
                    c.push([1.0; 4]);
                }
                (self.positions.len() - 1) as u32
            };
            self.positions[id as usize] = new_positions[i];
            self.vertex_out[id as usize] = NONE;
            self.vertex_sharpness[id as usize] = 0.0;
            if let Some(c) = &mut self.vertex_colors {
                c[id as usize] = [1.0; 4];
            }
            new_vid.push(id);
        }
        let resolve = |v: u32| if (v as usize) < nv0 { v } else { new_vid[v as usize - nv0] };
        let mut he_id: Vec<u32> = Vec::with_capacity(total_corners);
        // New elements take the lowest dead slots: the leftover (higher) ones are then filled
        // by moving elements from the end, which are never new ones, so new ids are final.
        dead_he.sort_unstable();
        let fresh = plans.iter().filter(|p| matches!(p, Plan::New(_))).count().saturating_sub(dead_he.len());
        self.he_origin.reserve(fresh);
        self.he_next.reserve(fresh);
        self.he_prev.reserve(fresh);
        self.he_twin.reserve(fresh);
        self.he_face.reserve(fresh);
        self.he_sharpness.reserve(fresh);
        let mut free_he = dead_he.iter().copied();
        for plan in &plans {
            he_id.push(match *plan {
                Plan::Reuse(r) => r,
                Plan::New(_) => match free_he.next() {
                    Some(h) => h,
                    None => {
                        self.he_origin.push(NONE);
                        self.he_next.push(NONE);
                        self.he_prev.push(NONE);
                        self.he_twin.push(NONE);
                        self.he_face.push(NONE);
                        self.he_sharpness.push(0.0);
                        (self.he_origin.len() - 1) as u32
                    }
                },
            });
        }
        let mut leftover_he: Vec<u32> = free_he.collect();
        let mut dead_f: Vec<u32> = remove.to_vec();
        dead_f.sort_unstable();
        let mut face_slot: Vec<u32> = Vec::with_capacity(add.len());
        for i in 0..add.len() {
            let slot = if i < dead_f.len() {
                dead_f[i]
            } else {
                self.face_he.push(NONE);
                if let Some(ids) = &mut self.face_parts {
                    ids.push(0);
                }
                (self.face_he.len() - 1) as u32
            };
            if let (Some(ids), Some(part)) = (&mut self.face_parts, new_part) {
                ids[slot as usize] = part;
            }
            face_slot.push(slot);
        }
        let mut leftover_f: Vec<u32> = dead_f.iter().skip(add.len()).copied().collect();
        let mut leftover_v: Vec<u32> = dead_v.iter().skip(nnew).copied().collect();
        log.grown = [self.positions.len(), self.he_origin.len(), self.face_he.len()];

        // 6. Wire the new faces.
        let mut c0 = 0usize;
        for (i, poly) in add.iter().enumerate() {
            let poly = poly.as_ref();
            let n = poly.len();
            let f = face_slot[i];
            for k in 0..n {
                let c = c0 + k;
                let h = he_id[c] as usize;
                self.he_origin[h] = resolve(poly[k]);
                self.he_face[h] = f;
                self.he_next[h] = he_id[c0 + (k + 1) % n];
                self.he_prev[h] = he_id[c0 + (k + n - 1) % n];
                if let Plan::New(t) = plans[c] {
                    self.he_sharpness[h] = 0.0;
                    self.he_twin[h] = he_id[t];
                }
            }
            self.face_he[f as usize] = he_id[c0];
            c0 += n;
        }
        for (c, &(a, _)) in corner_edges.iter().enumerate() {
            self.vertex_out[resolve(a) as usize] = he_id[c];
        }
        for (i, &v) in affected.iter().enumerate() {
            if (v as usize) < nv0 && !has_new[i] && kept_out[i] != NONE {
                self.vertex_out[v as usize] = kept_out[i];
            }
        }
        for &v in &leftover_v {
            self.vertex_out[v as usize] = NONE;
        }

        // 7. Compact: half-edges, then vertices, then faces, each by swap-remove, descending.
        leftover_he.sort_unstable_by(|a, b| b.cmp(a));
        for x in leftover_he {
            let last = (self.he_origin.len() - 1) as u32;
            if x != last {
                self.move_halfedge(last, x);
                log.halfedge_moves.push((last, x));
            }
            self.he_origin.pop();
            self.he_next.pop();
            self.he_prev.pop();
            self.he_twin.pop();
            self.he_face.pop();
            self.he_sharpness.pop();
        }
        leftover_v.sort_unstable_by(|a, b| b.cmp(a));
        for x in leftover_v {
            let last = (self.positions.len() - 1) as u32;
            if x != last {
                self.move_vertex(last, x);
                log.vertex_moves.push((last, x));
            }
            self.positions.pop();
            self.vertex_out.pop();
            self.vertex_sharpness.pop();
            if let Some(c) = &mut self.vertex_colors {
                c.pop();
            }
        }
        leftover_f.sort_unstable_by(|a, b| b.cmp(a));
        for x in leftover_f {
            let last = (self.face_he.len() - 1) as u32;
            if x != last {
                self.move_face(last, x);
                log.face_moves.push((last, x));
            }
            self.face_he.pop();
            if let Some(ids) = &mut self.face_parts {
                ids.pop();
            }
        }
        log.final_len = [self.positions.len(), self.he_origin.len(), self.face_he.len()];
        debug_assert!(log.face_moves.iter().all(|&(from, _)| !face_slot.contains(&from)));
        debug_assert!(log.vertex_moves.iter().all(|&(from, _)| !new_vid.contains(&from)));
        log.new_faces = face_slot;
        log.new_vertices = new_vid;
        Ok(log)
    }

    /// Moves vertex `v` to `position`, keeping every id and attribute.
    ///
    /// # Errors
    /// [`EditError::NoSuchElement`], [`EditError::NonFinite`]; the mesh is unchanged on error.
    pub fn set_position(&mut self, v: u32, position: Vec3) -> Result<(), EditError> {
        self.check_vertex_id(v)?;
        if !is_finite(position) {
            return Err(EditError::NonFinite { index: v as usize });
        }
        self.positions[v as usize] = position;
        Ok(())
    }

    /// Moves half-edge `from` (a live one) into the dead slot `to`, fixing every reference.
    fn move_halfedge(&mut self, from: u32, to: u32) {
        let (f, t) = (from as usize, to as usize);
        let (twin, next, prev, face, origin) =
            (self.he_twin[f], self.he_next[f], self.he_prev[f], self.he_face[f], self.he_origin[f]);
        self.he_twin[twin as usize] = to;
        self.he_prev[next as usize] = to;
        self.he_next[prev as usize] = to;
        if face != NONE && self.face_he[face as usize] == from {
            self.face_he[face as usize] = to;
        }
        if self.vertex_out[origin as usize] == from {
            self.vertex_out[origin as usize] = to;
        }
        self.he_origin[t] = origin;
        self.he_next[t] = next;
        self.he_prev[t] = prev;
        self.he_twin[t] = twin;
        self.he_face[t] = face;
        self.he_sharpness[t] = self.he_sharpness[f];
    }

    /// Moves vertex `from` into the dead slot `to`, fixing the origins of its half-edges.
    fn move_vertex(&mut self, from: u32, to: u32) {
        let outs: Vec<u32> = self.outgoing(from).collect();
        for h in outs {
            self.he_origin[h as usize] = to;
        }
        let (f, t) = (from as usize, to as usize);
        self.positions[t] = self.positions[f];
        self.vertex_out[t] = self.vertex_out[f];
        self.vertex_sharpness[t] = self.vertex_sharpness[f];
        if let Some(c) = &mut self.vertex_colors {
            c[t] = c[f];
        }
    }

    /// Moves face `from` into the dead slot `to`, fixing the faces of its half-edges.
    fn move_face(&mut self, from: u32, to: u32) {
        let hs: Vec<u32> = self.face_halfedges(from).collect();
        for h in hs {
            self.he_face[h as usize] = to;
        }
        self.face_he[to as usize] = self.face_he[from as usize];
        if let Some(ids) = &mut self.face_parts {
            ids[to as usize] = ids[from as usize];
        }
    }

    /// The two faces of an interior edge, or an error naming the edge.
    fn interior_faces(&self, h: u32) -> Result<(u32, u32), EditError> {
        self.check_he_id(h)?;
        let (f, g) = (self.face(h), self.face(self.twin(h)));
        if f == NONE || g == NONE {
            return Err(EditError::BoundaryPatch { id: self.origin(h) });
        }
        if f == g {
            return Err(EditError::Invalid(format!("both sides of half-edge {h} belong to face {f}")));
        }
        Ok((f, g))
    }

    /// The vertices of face `f` starting at the origin of its half-edge `h`.
    fn cycle_from(&self, h: u32) -> Vec<u32> {
        self.loop_halfedges(h).map(|x| self.origin(x)).collect()
    }

    /// Splits the edge of half-edge `h` with a new vertex at `origin + t·(target − origin)`; both
    /// faces of the edge gain a corner. Returns the new vertex and the log.
    ///
    /// # Errors
    /// [`EditError::NoSuchElement`]; [`EditError::BoundaryPatch`] for a boundary edge;
    /// [`EditError::NonFinite`] for a non-finite `t`.
    ///
    /// See also [`Mesh::dissolve_vertex`], its inverse. Thesis notation (seed 004, §3.1.4):
    /// `split_edge(h)`.
    pub fn split_edge(&mut self, h: u32, t: f64) -> Result<(u32, EditLog), EditError> {
        let (f, g) = self.interior_faces(h)?;
        let p = self.position(self.origin(h)).lerp(self.position(self.target(h)), t);
        let nv = self.vertex_count() as u32;
        // face f from target(h) around to origin(h), then the new vertex; likewise g.
        let mut pf = self.cycle_from(self.next(h));
        pf.push(nv);
        let tw = self.twin(h);
        let mut pg = self.cycle_from(self.next(tw));
        pg.push(nv);
        let log = self.replace_faces(&[f, g], &[pf, pg], &[p])?;
        Ok((log.new_vertices()[0], log))
    }

    /// Splits a face by a new edge between the origins of its half-edges `a` and `b`, which must
    /// not be neighbours. Returns the new half-edge from `origin(a)` to `origin(b)` and the log.
    ///
    /// # Errors
    /// [`EditError::Invalid`] when `a` and `b` are not in one face or are neighbours;
    /// [`EditError::EdgeInUse`] when the two vertices are already joined by an edge.
    ///
    /// See also [`Mesh::join_faces`], its inverse. Thesis: `split_face(f, v1, v2)` (§3.1.4).
    pub fn split_face(&mut self, a: u32, b: u32) -> Result<(u32, EditLog), EditError> {
        self.check_he_id(a)?;
        self.check_he_id(b)?;
        let f = self.face(a);
        if f == NONE || self.face(b) != f {
            return Err(EditError::Invalid(format!("half-edges {a} and {b} do not belong to one face")));
        }
        if a == b || self.next(a) == b || self.next(b) == a {
            return Err(EditError::Invalid(format!(
                "half-edges {a} and {b} start at the same or neighbouring corners: no diagonal joins them"
            )));
        }
        let (va, vb) = (self.origin(a), self.origin(b));
        let p1: Vec<u32> = self.loop_halfedges(a).take_while(|&x| x != b).map(|x| self.origin(x)).chain([vb]).collect();
        let p2: Vec<u32> = self.loop_halfedges(b).take_while(|&x| x != a).map(|x| self.origin(x)).chain([va]).collect();
        let log = self.replace_faces(&[f], &[p1, p2], &[])?;
        // The second polygon runs vb … va and closes with the diagonal va → vb.
        let nf = log.new_faces()[1];
        let h = self.face_halfedges(nf).find(|&x| self.origin(x) == va && self.target(x) == vb);
        let h = h.ok_or_else(|| EditError::Invalid("internal: the new diagonal was not found".into()))?;
        Ok((h, log))
    }

    /// Removes the edge of half-edge `h`, merging its two faces into one. Both ends must keep
    /// at least two edges. Returns the merged face and the log.
    ///
    /// # Errors
    /// [`EditError::Invalid`] when both sides are one face; [`EditError::DegenerateFace`] when
    /// the merged face would repeat a vertex (an end of valence 1 after removal, or faces that
    /// share more than this edge).
    ///
    /// See also [`Mesh::split_face`]. Thesis: `merge_faces(h, f1, f2)` (§3.1.4).
    pub fn join_faces(&mut self, h: u32) -> Result<(u32, EditLog), EditError> {
        let (f, g) = self.interior_faces(h)?;
        let mut poly = self.cycle_from(self.next(h));
        let tw = self.twin(h);
        poly.extend(self.loop_halfedges(self.next(self.next(tw))).take_while(|&x| x != tw).map(|x| self.origin(x)));
        let log = self.replace_faces(&[f, g], &[poly], &[])?;
        Ok((log.new_faces()[0], log))
    }

    /// Removes a vertex of valence 2, joining its two edges into one (its two faces each lose
    /// a corner). Returns the log.
    ///
    /// # Errors
    /// [`EditError::Invalid`] when the valence is not 2; [`EditError::DegenerateFace`] when a face
    /// would drop below three corners; [`EditError::EdgeInUse`] when the two neighbours are
    /// already joined.
    ///
    /// See also [`Mesh::split_edge`]. Thesis: `merge_edges(h1, h2)` (§3.1.4).
    pub fn dissolve_vertex(&mut self, v: u32) -> Result<EditLog, EditError> {
        self.check_vertex_id(v)?;
        let faces: Vec<u32> = self.vertex_faces(v).collect();
        if self.valence(v) != 2 || faces.len() != 2 {
            return Err(EditError::Invalid(format!("vertex {v} has valence {}, not 2", self.valence(v))));
        }
        let polys: Vec<Vec<u32>> =
            faces.iter().map(|&f| self.face_vertices(f).filter(|&x| x != v).collect::<Vec<u32>>()).collect();
        self.replace_faces(&faces, &polys, &[])
    }

    /// Splits face `f` into a fan of triangles around a new vertex at `position`. Returns the
    /// new vertex and the log.
    ///
    /// # Errors
    /// [`EditError::NoSuchElement`], [`EditError::NonFinite`].
    ///
    /// See also [`Mesh::unpoke_vertex`]. Thesis: `split_face_vertex(f)` (§4.3.2).
    pub fn poke_face(&mut self, f: u32, position: Vec3) -> Result<(u32, EditLog), EditError> {
        self.check_face_id(f)?;
        let c: Vec<u32> = self.face_vertices(f).collect();
        let nv = self.vertex_count() as u32;
        let polys: Vec<[u32; 3]> = (0..c.len()).map(|i| [c[i], c[(i + 1) % c.len()], nv]).collect();
        let log = self.replace_faces(&[f], &polys, &[position])?;
        Ok((log.new_vertices()[0], log))
    }

    /// Removes vertex `v` and all its edges, merging its faces into one polygon bounded by its
    /// link. Returns the merged face and the log.
    ///
    /// # Errors
    /// [`EditError::DegenerateFace`] when the link repeats a vertex; [`EditError::BoundaryPatch`]
    /// for a boundary vertex.
    ///
    /// See also [`Mesh::poke_face`].
    pub fn unpoke_vertex(&mut self, v: u32) -> Result<(u32, EditLog), EditError> {
        self.check_vertex_id(v)?;
        if self.is_boundary_vertex(v) {
            return Err(EditError::BoundaryPatch { id: v });
        }
        // Around v (clockwise via twin(prev)) each face v → t → … → u → v contributes t … (the
        // corner before u); the clockwise-next face starts at u, so the pieces chain into the link
        // in the faces' own (counter-clockwise) orientation.
        let outs: Vec<u32> = self.outgoing(v).collect();
        let faces: Vec<u32> = outs.iter().map(|&h| self.face(h)).collect();
        let mut link = Vec::new();
        for &h in &outs {
            let arity = self.loop_halfedges(h).count();
            link.extend(self.loop_halfedges(self.next(h)).take(arity - 2).map(|x| self.origin(x)));
        }
        let mut uniq = faces.clone();
        uniq.sort_unstable();
        uniq.dedup();
        if uniq.len() != faces.len() {
            return Err(EditError::Invalid(format!("a face meets vertex {v} twice")));
        }
        let link = dedup_cyclic(link);
        let log = self.replace_faces(&faces, &[link], &[])?;
        Ok((log.new_faces()[0], log))
    }

    /// Collapses the edge of half-edge `h`: its target merges into its origin, which moves to
    /// `position`; the faces on the edge lose a corner (triangles vanish). Returns the surviving
    /// vertex and the log.
    ///
    /// # Errors
    /// [`EditError::EdgeInUse`] or [`EditError::NonManifoldVertex`] when the collapse would break
    /// the manifold (the link condition fails); [`EditError::Invalid`] when no face would remain
    /// at the surviving vertex; [`EditError::NonFinite`].
    pub fn collapse_edge(&mut self, h: u32, position: Vec3) -> Result<(u32, EditLog), EditError> {
        self.interior_faces(h)?;
        if !is_finite(position) {
            return Err(EditError::NonFinite { index: 0 });
        }
        let (u, w) = (self.origin(h), self.target(h));
        let mut faces: Vec<u32> = self.vertex_faces(u).chain(self.vertex_faces(w)).collect();
        faces.sort_unstable();
        faces.dedup();
        let mut polys = Vec::with_capacity(faces.len());
        for &f in &faces {
            let p: Vec<u32> = self.face_vertices(f).map(|x| if x == w { u } else { x }).collect();
            let p = dedup_cyclic(p);
            if p.len() >= 3 {
                polys.push(p);
            }
        }
        if !polys.iter().any(|p| p.contains(&u)) {
            return Err(EditError::Invalid(format!(
                "collapsing half-edge {h} would leave no face at vertex {u}: every face around it would vanish"
            )));
        }
        let old = self.position(u);
        self.positions[u as usize] = position;
        match self.replace_faces(&faces, &polys, &[]) {
            Ok(log) => {
                let v = log.map_vertex(u).expect("the surviving vertex keeps faces");
                Ok((v, log))
            }
            Err(e) => {
                self.positions[u as usize] = old;
                Err(e)
            }
        }
    }
}

/// Removes consecutive repeats from a cyclic vertex list.
fn dedup_cyclic(mut p: Vec<u32>) -> Vec<u32> {
    p.dedup();
    while p.len() > 1 && p.first() == p.last() {
        p.pop();
    }
    p
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::SplitMix64;

    fn assert_sound(m: &Mesh) {
        assert!(m.is_manifold(), "not manifold");
        assert!(m.is_closed(), "not closed");
        // Round trip through polygons: no doubled edges, no degenerate faces.
        let back = Mesh::from_polygons(m.positions().to_vec(), &m.to_polygons());
        assert!(back.is_ok(), "polygon round trip failed: {back:?}");
    }

    #[test]
    fn split_edge_adds_one_vertex_two_half_edges_and_keeps_faces() {
        // Splitting an edge: V+1, E+1, F unchanged, so χ stays 2 on the cube.
        let mut m = Mesh::cube(2.0);
        let h = m.face_halfedge(0);
        let (a, b) = (m.position(m.origin(h)), m.position(m.target(h)));
        let (v, _) = m.split_edge(h, 0.5).unwrap();
        assert_eq!((m.vertex_count(), m.edge_count(), m.face_count()), (9, 13, 6));
        assert_eq!(m.valence(v), 2);
        assert!((m.position(v) - (a + b) / 2.0).length() < 1e-15);
        assert_eq!(m.euler(), 2);
        assert_sound(&m);
        m.dissolve_vertex(v).unwrap();
        assert_eq!((m.vertex_count(), m.edge_count(), m.face_count()), (8, 12, 6));
        assert_sound(&m);
    }

    #[test]
    fn split_face_then_join_restores_counts() {
        let mut m = Mesh::cube(2.0);
        let a = m.face_halfedge(2);
        let b = m.next(m.next(a));
        let (d, _) = m.split_face(a, b).unwrap();
        assert_eq!((m.edge_count(), m.face_count()), (13, 7));
        assert_eq!(m.origin(d), m.origin(a));
        assert_sound(&m);
        m.join_faces(d).unwrap();
        assert_eq!((m.vertex_count(), m.edge_count(), m.face_count()), (8, 12, 6));
        assert!(m.is_quad_mesh());
        assert_sound(&m);
    }

    #[test]
    fn split_face_refuses_neighbouring_corners_and_leaves_mesh() {
        let mut m = Mesh::cube(2.0);
        let before = m.clone();
        let a = m.face_halfedge(0);
        assert!(matches!(m.split_face(a, m.next(a)), Err(EditError::Invalid(_))));
        assert!(matches!(m.split_face(a, m.face_halfedge(1)), Err(EditError::Invalid(_))));
        assert_eq!(m, before);
    }

    #[test]
    fn poke_and_unpoke_round_trip() {
        let mut m = Mesh::cube(2.0);
        let (v, _) = m.poke_face(3, Vec3::new(0.0, 1.5, 0.0)).unwrap();
        assert_eq!((m.vertex_count(), m.face_count()), (9, 9));
        assert_eq!(m.valence(v), 4);
        assert_sound(&m);
        let (f, _) = m.unpoke_vertex(v).unwrap();
        assert_eq!((m.vertex_count(), m.edge_count(), m.face_count()), (8, 12, 6));
        assert_eq!(m.face_arity(f), 4);
        assert_sound(&m);
        assert!((m.volume() - 8.0).abs() < 1e-12, "volume {} vs 8", m.volume());
    }

    #[test]
    fn deleting_low_ids_moves_last_elements_and_log_follows() {
        // Unpoking vertex 0's... use an icosphere: collapse an edge at vertex 0 so the last
        // vertex is moved into the freed slot; a per-vertex tag array must follow the move.
        let mut m = Mesh::icosphere(1.0, 1);
        let nv = m.vertex_count();
        let mut tag: Vec<u32> = (0..nv as u32).collect();
        let h = m.vertex_halfedge(0);
        let w = m.target(h);
        let (v, log) = m.collapse_edge(h, Vec3::new(0.0, 1.0, 0.0)).unwrap();
        log.apply_vertex_moves(&mut tag, u32::MAX);
        assert_eq!(m.vertex_count(), nv - 1);
        assert_eq!(log.removed_vertices(), &[w]);
        assert_eq!(tag[v as usize], 0);
        // Every surviving tag names the old vertex now at that slot: positions agree.
        let orig = Mesh::icosphere(1.0, 1);
        for (i, &t) in tag.iter().enumerate() {
            if t != 0 {
                assert_eq!(m.position(i as u32), orig.position(t));
            }
        }
        assert_eq!(m.euler(), 2);
        assert_sound(&m);
    }

    #[test]
    fn collapse_violating_link_condition_is_refused_unchanged() {
        // Triangular bipyramid: equator vertices a, b share the neighbour c without a face
        // (a, b, c), so collapsing a–b would glue edges a–c and b–c: two faces would both use
        // the directed edge c→a.
        let s = 3f64.sqrt() / 2.0;
        let p = vec![Vec3::X, Vec3::new(-0.5, s, 0.0), Vec3::new(-0.5, -s, 0.0), Vec3::Z, -Vec3::Z];
        let (a, b, c, t, bo) = (0, 1, 2, 3, 4);
        let faces = [[a, b, t], [b, c, t], [c, a, t], [b, a, bo], [c, b, bo], [a, c, bo]];
        let mut m = Mesh::from_polygons(p, &faces).unwrap();
        let before = m.clone();
        let h = m.find_halfedge(a, b).unwrap();
        let e = m.collapse_edge(h, Vec3::ZERO).unwrap_err();
        assert!(matches!(e, EditError::EdgeInUse { .. } | EditError::NonManifoldVertex { .. }), "{e}");
        assert_eq!(m, before);
    }

    #[test]
    fn replace_faces_refuses_holes_duplicates_and_pinches_unchanged() {
        let mut m = Mesh::cube(2.0);
        let before = m.clone();
        // Removing a face without covering it leaves a hole.
        assert!(matches!(m.replace_faces::<Vec<u32>>(&[0], &[], &[]), Err(EditError::HoleNotCovered { .. })));
        // Re-adding a face reversed clashes with its neighbours' edges.
        let mut rev: Vec<u32> = m.face_vertices(0).collect();
        rev.reverse();
        assert!(matches!(m.replace_faces(&[0], &[rev], &[]), Err(EditError::EdgeInUse { .. })));
        // A diagonal of face 0 that already... a polygon reusing kept edge direction.
        let f1: Vec<u32> = m.face_vertices(1).collect();
        assert!(matches!(
            m.replace_faces(&[0], &[f1], &[]),
            Err(EditError::EdgeInUse { .. } | EditError::OpenEdge { .. })
        ));
        // Repeated face, bad ids, degenerate polygons, NaN positions, unused new vertices.
        assert!(matches!(m.replace_faces::<Vec<u32>>(&[0, 0], &[], &[]), Err(EditError::RepeatedFace { face: 0 })));
        assert!(matches!(m.replace_faces::<Vec<u32>>(&[99], &[], &[]), Err(EditError::NoSuchElement { .. })));
        assert!(matches!(m.replace_faces(&[0], &[vec![0, 4]], &[]), Err(EditError::DegenerateFace { .. })));
        let f0: Vec<u32> = m.face_vertices(0).collect();
        assert!(matches!(
            m.replace_faces(&[0], std::slice::from_ref(&f0), &[Vec3::new(f64::NAN, 0.0, 0.0)]),
            Err(EditError::NonFinite { index: 0 })
        ));
        assert!(matches!(m.replace_faces(&[0], &[f0], &[Vec3::ZERO]), Err(EditError::UnusedNewVertex { index: 0 })));
        assert_eq!(m, before);
    }

    #[test]
    fn patch_touching_a_boundary_is_refused() {
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::new(1.0, 1.0, 0.0)];
        let mut m = Mesh::from_polygons(p, &[[0, 1, 3], [0, 3, 2]]).unwrap();
        let before = m.clone();
        assert!(matches!(m.split_edge(m.face_halfedge(0), 0.5), Err(EditError::BoundaryPatch { .. })));
        assert_eq!(m, before);
    }

    #[test]
    fn single_fan_detects_pinches() {
        // Two separate triangles' corners at one vertex: (1,2) and (3,4) do not chain.
        assert!(!is_single_fan(&mut [(1, 2), (3, 4)]));
        assert!(is_single_fan(&mut [(1, 2), (2, 3), (3, 1)]));
        assert!(!is_single_fan(&mut [(1, 2), (2, 1), (3, 4), (4, 3)]));
    }

    /// The fan check by sorting and binary search alone (the path fans over 12 corners take).
    fn single_fan_by_sorting(corners: &[Corner]) -> bool {
        let mut c = corners.to_vec();
        c.sort_unstable();
        if c.windows(2).any(|w| w[0].0 == w[1].0) {
            return false;
        }
        let mut at = 0usize;
        for step in 1..=c.len() {
            match c.binary_search_by_key(&c[at].1, |x| x.0) {
                Ok(i) => at = i,
                Err(_) => return false,
            }
            if at == 0 {
                return step == c.len();
            }
        }
        false
    }

    /// Small fans are checked by linear look-ups without sorting (faster on the few corners
    /// nearly every vertex has): the answer is the sorted check's on closed fans, fans split in
    /// two, open fans and repeated corners, in every order.
    #[test]
    fn small_fans_are_judged_as_the_sorted_check_judges_them() {
        let mut rng = SplitMix64::new(11);
        let (mut yes, mut no) = (0, 0);
        for case in 0..4000 {
            let n = 1 + rng.below(20);
            // A closed fan over neighbours 0..n, then one of: kept, split in two cycles, one
            // corner dropped (open), one neighbour repeated; shuffled.
            let mut c: Vec<Corner> = (0..n as u32).map(|k| (k, (k + 1) % n as u32)).collect();
            match case % 4 {
                1 if n >= 4 => {
                    let k = 1 + rng.below(n - 2) as u32;
                    c[k as usize - 1].1 = 0;
                    c[n - 1].1 = k;
                }
                2 if n >= 2 => {
                    c.remove(rng.below(n));
                }
                3 if n >= 2 => {
                    let k = rng.below(n);
                    c[k].0 = c[(k + 1) % n].0;
                }
                _ => {}
            }
            for k in (1..c.len()).rev() {
                c.swap(k, rng.below(k + 1));
            }
            let want = single_fan_by_sorting(&c);
            assert_eq!(is_single_fan(&mut c.clone()), want, "case {case}: {c:?}");
            if want {
                yes += 1;
            } else {
                no += 1;
            }
        }
        assert!(yes > 500 && no > 500, "both answers exercised: {yes} / {no}");
    }

    #[test]
    fn random_euler_operations_keep_the_mesh_sound_or_leave_it_unchanged() {
        // 40 seeded runs of 60 random Euler operations on random elements: a success keeps a
        // closed manifold that survives the polygon round trip and the Euler characteristic the
        // operation implies (every one here keeps χ, except a collapse that deletes a face pair
        // — still χ-preserving on a closed surface); a refusal changes nothing.
        let mut successes = [0usize; 7];
        for seed in 0..40u64 {
            let mut rng = SplitMix64::new(seed * 7919 + 1);
            let mut m = if seed % 2 == 0 { Mesh::icosphere(1.0, 1) } else { Mesh::cube(2.0) };
            for _ in 0..60 {
                let before = m.clone();
                let chi = m.euler();
                let (nh, nf, nv) = (m.halfedge_count(), m.face_count(), m.vertex_count());
                let op = rng.below(7);
                let h = rng.below(nh) as u32;
                let r: Result<(), EditError> = match op {
                    0 => m.split_edge(h, 0.3).map(|_| ()),
                    1 => {
                        let f = m.face(h);
                        let k = rng.below(m.face_arity(f));
                        let b = m.face_halfedges(f).nth(k).unwrap();
                        m.split_face(h, b).map(|_| ())
                    }
                    2 => m.join_faces(h).map(|_| ()),
                    3 => m.dissolve_vertex(rng.below(nv) as u32).map(|_| ()),
                    4 => m.poke_face(rng.below(nf) as u32, Vec3::ZERO).map(|_| ()),
                    5 => m.unpoke_vertex(rng.below(nv) as u32).map(|_| ()),
                    _ => {
                        let (a, b) = (m.position(m.origin(h)), m.position(m.target(h)));
                        m.collapse_edge(h, (a + b) * 0.5).map(|_| ())
                    }
                };
                match r {
                    Ok(()) => {
                        successes[op] += 1;
                        assert_sound(&m);
                        assert_eq!(m.euler(), chi, "operation {op} changed χ");
                        assert!(m.vertex_halfedge(0) != NONE || m.vertex_count() == 0);
                    }
                    Err(e) => assert_eq!(m, before, "operation {op} refused ({e}) but changed the mesh"),
                }
            }
        }
        assert!(successes.iter().all(|&n| n > 0), "every operation must succeed sometimes: {successes:?}");
    }
}
