//! Building a half-edge mesh from indexed polygons, in time linear in the number of corners.
//!
//! Steps: validate faces; lay out face half-edges; bucket them by origin vertex (a counting sort);
//! find each twin in the target's outgoing bucket (scanned, or bisected when the valence is high); close every
//! unmatched half-edge with a boundary half-edge; link boundary loops; check that every vertex's
//! half-edges form one fan.

use super::{Mesh, MeshError, SubdivOptions, NONE};
use crate::math::{is_finite, Vec3};
use rayon::prelude::*;

/// [`MeshError::NonFinite`] naming the first vertex with a NaN or infinite coordinate.
///
/// Blocks of positions are tested without a branch per coordinate: `x · 0` is 0 for a finite
/// `x` and NaN for an infinite or NaN one, so a block's sum of them is finite exactly when every
/// coordinate is (two instructions a coordinate). Only a failing block is searched for the
/// culprit.
pub(super) fn check_finite(positions: &[Vec3]) -> Result<(), MeshError> {
    const BLOCK: usize = 256;
    let all_finite = positions.chunks(BLOCK).all(|b| is_finite(b.iter().fold(Vec3::ZERO, |acc, p| acc + *p * 0.0)));
    if all_finite {
        return Ok(());
    }
    match positions.iter().position(|p| !is_finite(*p)) {
        Some(i) => {
            let p = positions[i];
            Err(MeshError::NonFinite { vertex: i, x: p.x, y: p.y, z: p.z })
        }
        None => Ok(()),
    }
}

/// Buckets of outgoing half-edges up to this size are searched by a scan, larger ones by
/// bisection after sorting.
const SCAN_VALENCE: usize = 16;

/// Vertices per parallel run of [`Mesh::from_paired_triangles`]'s fan walks.
const FAN_WALK_RUN: usize = 4096;

/// Half-edges from which [`face_cycles`] fills its arrays in parallel.
const FACE_CYCLES_PAR: usize = 1 << 16;

/// The stoppable build charges its cancellation token once per this many faces or vertices (a
/// power of two).
const CHARGE_EVERY: usize = 1 << 16;

/// A vertex that appears more than once in a face's corner list.
fn repeated_vertex(corners: &[u32]) -> Option<u32> {
    if corners.len() <= 16 {
        (1..corners.len()).find(|&i| corners[..i].contains(&corners[i])).map(|i| corners[i])
    } else {
        let mut sorted = corners.to_vec();
        sorted.sort_unstable();
        sorted.windows(2).find(|w| w[0] == w[1]).map(|w| w[0])
    }
}

/// The twins of a mesh's face half-edges, and the half-edges bucketed by origin vertex.
struct FaceTwins {
    /// Each face half-edge's twin, [`NONE`] where no face runs the other way.
    twins: Vec<u32>,
    /// Vertex `v`'s outgoing half-edges are `out_list[out_start[v]..out_start[v + 1]]`, in
    /// increasing id.
    out_start: Vec<u32>,
    out_list: Vec<u32>,
}

impl FaceTwins {
    /// Buckets the face half-edges (origins `he_origin`, targets `he_target`, faces `he_face`)
    /// by origin (a counting sort) and finds each one's twin in its target's bucket (scanned, or
    /// bisected when the valence is high): linear in the number of half-edges.
    ///
    /// # Errors
    /// [`MeshError::NonManifoldEdge`] when two faces use the same directed edge; what `tick`
    /// returns, called once per vertex.
    fn find(
        nv: usize,
        he_origin: &[u32],
        he_target: &[u32],
        he_face: &[u32],
        tick: &mut dyn FnMut(usize) -> Result<(), crate::limits::LimitError>,
    ) -> Result<FaceTwins, MeshError> {
        // Bucket face half-edges by origin (CSR).
        let nfh = he_origin.len();
        let mut out_start = vec![0u32; nv + 1];
        for &v in he_origin {
            out_start[v as usize + 1] += 1;
        }
        for i in 0..nv {
            out_start[i + 1] += out_start[i];
        }
        let mut fill = out_start.clone();
        let mut out_list = vec![0u32; nfh];
        for (h, &v) in he_origin.iter().enumerate() {
            out_list[fill[v as usize] as usize] = h as u32;
            fill[v as usize] += 1;
        }
        // The same buckets for searching by target: those of high valence (a polygon's centre
        // after a subdivision step, a fan's hub) sorted by (target, id) and searched by bisection,
        // so that a vertex of valence n costs n log n rather than n².
        let mut by_target = out_list.clone();
        for v in 0..nv {
            let bucket = &mut by_target[out_start[v] as usize..out_start[v + 1] as usize];
            if bucket.len() > SCAN_VALENCE {
                bucket.sort_unstable_by_key(|&h| (he_target[h as usize], h));
            }
        }
        // The lowest-id half-edge of `v`'s bucket that ends at `t`.
        let first_to = |v: u32, t: u32| -> Option<u32> {
            let bucket = &by_target[out_start[v as usize] as usize..out_start[v as usize + 1] as usize];
            if bucket.len() > SCAN_VALENCE {
                let i = bucket.partition_point(|&o| he_target[o as usize] < t);
                bucket.get(i).copied().filter(|&o| he_target[o as usize] == t)
            } else {
                bucket.iter().copied().find(|&o| he_target[o as usize] == t)
            }
        };

        // Twins. A repeated directed edge is a non-manifold edge.
        let mut he_twin = vec![NONE; nfh];
        for v in 0..nv {
            tick(v)?;
            let bucket = &out_list[out_start[v] as usize..out_start[v + 1] as usize];
            for &h in bucket {
                let t = he_target[h as usize];
                if let Some(other) = first_to(v as u32, t).filter(|&o| o != h) {
                    return Err(MeshError::NonManifoldEdge {
                        a: v as u32,
                        b: t,
                        first: he_face[other as usize] as usize,
                        second: he_face[h as usize] as usize,
                    });
                }
                if let Some(tw) = first_to(t, v as u32) {
                    he_twin[h as usize] = tw;
                }
            }
        }

        Ok(FaceTwins { twins: he_twin, out_start, out_list })
    }
}

impl Mesh {
    /// Builds a mesh from positions and faces given as vertex-id lists (counter-clockwise seen
    /// from outside).
    ///
    /// # Errors
    /// See [`Mesh::from_indexed`].
    pub fn from_polygons<F: AsRef<[u32]>>(positions: Vec<Vec3>, faces: &[F]) -> Result<Mesh, MeshError> {
        let mut indices = Vec::new();
        let mut arities = Vec::with_capacity(faces.len());
        for f in faces {
            let f = f.as_ref();
            indices.extend_from_slice(f);
            arities.push(f.len() as u32);
        }
        Mesh::from_indexed(positions, &indices, &arities)
    }

    /// Builds a mesh from positions, one flat index list and the arity of each face.
    ///
    /// Inputs: `positions` (#V), `indices` (Σ arities), `arities` (#F, each ≥ 3).
    ///
    /// # Errors
    /// - [`MeshError::IndexOutOfRange`] for an index ≥ #V;
    /// - [`MeshError::DegenerateFace`] for a face with fewer than 3 vertices or a repeated vertex;
    /// - [`MeshError::NonManifoldEdge`] when two faces use the same directed edge;
    /// - [`MeshError::NonManifoldVertex`] when a vertex's faces form more than one fan;
    /// - [`MeshError::NonFinite`] for a NaN or infinite coordinate.
    pub fn from_indexed(positions: Vec<Vec3>, indices: &[u32], arities: &[u32]) -> Result<Mesh, MeshError> {
        Mesh::build_indexed(positions, indices, arities, &mut |_| Ok(()))
    }

    /// [`Mesh::from_indexed`] charging its work to the current cancellation token
    /// ([`crate::limits::charge`]) every 65,536 faces or vertices, so that building a mesh of
    /// millions of faces stops soon after the token does.
    ///
    /// # Errors
    /// As [`Mesh::from_indexed`], and [`MeshError::Limit`] when the token stops the work.
    pub fn from_indexed_stoppable(positions: Vec<Vec3>, indices: &[u32], arities: &[u32]) -> Result<Mesh, MeshError> {
        Mesh::build_indexed(positions, indices, arities, &mut crate::limits::charge)
    }

    fn build_indexed(
        positions: Vec<Vec3>,
        indices: &[u32],
        arities: &[u32],
        charge: &mut dyn FnMut(u64) -> Result<(), crate::limits::LimitError>,
    ) -> Result<Mesh, MeshError> {
        let mut tick = |i: usize| if i & (CHARGE_EVERY - 1) == 0 { charge(CHARGE_EVERY as u64) } else { Ok(()) };
        let nv = positions.len();
        if nv >= NONE as usize || indices.len() >= (NONE as usize) / 2 {
            return Err(MeshError::TooLarge { what: format!("{nv} vertices, {} corners", indices.len()) });
        }
        check_finite(&positions)?;
        let total: u64 = arities.iter().map(|&a| u64::from(a)).sum();
        if total != indices.len() as u64 {
            return Err(MeshError::DegenerateFace {
                face: arities.len(),
                reason: format!("face arities add up to {total} but {} indices were given", indices.len()),
            });
        }

        // 1. Validate faces and lay out their half-edges: face f owns ids start..start+arity.
        let nfh = indices.len();
        let mut he_origin = Vec::with_capacity(nfh * 2);
        let mut he_next = Vec::with_capacity(nfh * 2);
        let mut he_prev = Vec::with_capacity(nfh * 2);
        let mut he_face = Vec::with_capacity(nfh * 2);
        let mut face_he = Vec::with_capacity(arities.len());
        // Each face half-edge's target, so the twin search reads one array.
        let mut he_target = Vec::with_capacity(nfh);
        let mut start = 0usize;
        for (f, &arity) in arities.iter().enumerate() {
            tick(f)?;
            let arity = arity as usize;
            let corners = &indices[start..start + arity];
            if arity < 3 {
                return Err(MeshError::DegenerateFace {
                    face: f,
                    reason: format!("it has {arity} vertices (at least 3 needed)"),
                });
            }
            for &v in corners {
                if v as usize >= nv {
                    return Err(MeshError::IndexOutOfRange { face: f, index: u64::from(v), vertex_count: nv });
                }
            }
            if let Some(v) = repeated_vertex(corners) {
                return Err(MeshError::DegenerateFace { face: f, reason: format!("vertex {v} appears twice") });
            }
            face_he.push(start as u32);
            for (i, &corner) in corners.iter().enumerate() {
                he_origin.push(corner);
                he_next.push((start + (i + 1) % arity) as u32);
                he_prev.push((start + (i + arity - 1) % arity) as u32);
                he_face.push(f as u32);
                he_target.push(corners[(i + 1) % arity]);
            }
            start += arity;
        }

        // 2–3. Twins, from the half-edges bucketed by origin.
        let FaceTwins { twins: mut he_twin, out_start, out_list } =
            FaceTwins::find(nv, &he_origin, &he_target, &he_face, &mut tick)?;

        // 4. Boundary half-edges close every unmatched face half-edge.
        let boundary_out = close_boundary(nv, &mut he_origin, &mut he_next, &mut he_prev, &mut he_face, &mut he_twin)?;

        // 5. One outgoing half-edge per vertex (boundary first), and one fan per vertex.
        let mut vertex_out = vec![NONE; nv];
        for v in 0..nv {
            tick(v)?;
            let count = out_start[v + 1] - out_start[v];
            if count == 0 {
                continue;
            }
            // (No boundary list: a closed mesh.)
            let b = boundary_out.get(v).copied().unwrap_or(NONE);
            let first = if b != NONE { b } else { out_list[out_start[v] as usize] };
            vertex_out[v] = first;
            let expected = count + u32::from(b != NONE);
            let mut seen = 0u32;
            let mut h = first;
            loop {
                seen += 1;
                h = he_twin[he_prev[h as usize] as usize];
                if h == first || seen > expected {
                    break;
                }
            }
            if seen != expected {
                return Err(MeshError::NonManifoldVertex { vertex: v as u32, fans: 2 });
            }
        }

        let nh = he_origin.len();
        Ok(Mesh {
            positions,
            vertex_out,
            he_origin,
            he_next,
            he_prev,
            he_twin,
            he_face,
            face_he,
            he_sharpness: vec![0.0; nh],
            vertex_sharpness: vec![0.0; nv],
            subdiv_options: SubdivOptions::default(),
            vertex_colors: None,
            face_sources: None,
            face_parts: None,
            parts: Vec::new(),
        })
    }
}

impl Mesh {
    /// A mesh whose faces all have `arity` corners, from face half-edges already paired: face `f`
    /// owns half-edges `arity·f .. arity·(f + 1)` in corner order, half-edge `h` leaves vertex
    /// `origins[h]`, its twin is `twins[h]` ([`NONE`] on a boundary) and its edge's crease
    /// sharpness `sharpness[h]`. Boundary half-edges are added and linked as
    /// [`Mesh::from_indexed`] adds them, so the result equals the mesh `from_indexed` builds from
    /// the same faces (with the same tags), without searching for twins: for callers that know
    /// them, as subdivision does (a child's twins follow from its parent's edges).
    ///
    /// # Errors
    /// [`MeshError::NonFinite`] for a NaN or infinite coordinate; [`MeshError::Internal`] when
    /// the arrays are inconsistent (twins not mutual or not reversed, lengths that differ, two
    /// boundary half-edges leaving one vertex) — a bug of the caller.
    pub(crate) fn from_paired_faces(
        positions: Vec<Vec3>,
        arity: usize,
        mut origins: Vec<u32>,
        mut twins: Vec<u32>,
        mut sharpness: Vec<f64>,
        vertex_sharpness: Vec<f64>,
    ) -> Result<Mesh, MeshError> {
        let nv = positions.len();
        let nfh = origins.len();
        let bad = |why: &str| Err(MeshError::Internal(format!("paired faces: {why}")));
        if arity < 3
            || !nfh.is_multiple_of(arity)
            || twins.len() != nfh
            || sharpness.len() != nfh
            || vertex_sharpness.len() != nv
        {
            return bad("array lengths differ");
        }
        if nv >= NONE as usize || nfh >= (NONE as usize) / 2 {
            return Err(MeshError::TooLarge { what: format!("{nv} vertices, {nfh} corners") });
        }
        check_finite(&positions)?;
        let nf = nfh / arity;
        let face_he: Vec<u32> = (0..nf as u32).map(|f| f * arity as u32).collect();
        // Face half-edges run in face order, `arity` to a face: face, next and prev are
        // arithmetic (written by exact-size extends, the arity a constant in the common cases).
        let cap = nfh + nfh / 8;
        let (mut he_face, mut he_next, mut he_prev) =
            (Vec::with_capacity(cap), Vec::with_capacity(cap), Vec::with_capacity(cap));
        match arity {
            3 => face_cycles::<3>(nfh, &mut he_face, &mut he_next, &mut he_prev),
            4 => face_cycles::<4>(nfh, &mut he_face, &mut he_next, &mut he_prev),
            a => {
                let a = a as u32;
                he_face.extend((0..nfh as u32).map(|h| h / a));
                he_next.extend((0..nfh as u32).map(|h| if (h + 1) % a == 0 { h + 1 - a } else { h + 1 }));
                he_prev.extend((0..nfh as u32).map(|h| if h % a == 0 { h + a - 1 } else { h - 1 }));
            }
        }
        // The smallest face half-edge leaving each vertex (from_indexed's first of its bucket),
        // and the twins checked in range (a branch-free pass). That they are mutual and run the
        // other way is the caller's construction (subdivision writes each pair at once, and its
        // tests compare the result with `from_indexed`'s); debug builds check it too, as that
        // check reads two arrays in random order and cost as much as the rest of the build.
        let mut vertex_out = vec![NONE; nv];
        for (h, &v) in origins.iter().enumerate() {
            if v as usize >= nv {
                return bad("a vertex id out of range");
            }
            if vertex_out[v as usize] == NONE {
                vertex_out[v as usize] = h as u32;
            }
        }
        // t < nfh or t = NONE, as one unsigned comparison (NONE + 1 wraps to 0).
        let in_range = twins.chunks(1024).all(|b| b.iter().fold(true, |ok, &t| ok & (t.wrapping_add(1) <= nfh as u32)));
        if !in_range {
            return bad("a twin out of range");
        }
        if cfg!(debug_assertions)
            && twins.iter().enumerate().any(|(h, &t)| {
                t != NONE && (twins[t as usize] != h as u32 || origins[t as usize] != origins[he_next[h] as usize])
            })
        {
            return bad("twins that do not pair");
        }
        // Boundary half-edges close every unmatched face half-edge, in half-edge order, each
        // as sharp as its twin.
        let boundary_out = close_boundary(nv, &mut origins, &mut he_next, &mut he_prev, &mut he_face, &mut twins)?;
        for b in nfh..origins.len() {
            sharpness.push(sharpness[twins[b] as usize]);
        }
        // (Empty for a closed mesh.)
        for (out, &b) in vertex_out.iter_mut().zip(&boundary_out) {
            if b != NONE {
                *out = b;
            }
        }
        Ok(Mesh {
            positions,
            vertex_out,
            he_origin: origins,
            he_next,
            he_prev,
            he_twin: twins,
            he_face,
            face_he,
            he_sharpness: sharpness,
            vertex_sharpness,
            subdiv_options: SubdivOptions::default(),
            vertex_colors: None,
            face_sources: None,
            face_parts: None,
            parts: Vec::new(),
        })
    }
}

impl Mesh {
    /// A closed triangle mesh from triangles whose half-edges are already paired, as a boolean
    /// engine holds them (Manifold's `halfedge` array, through
    /// [`crate::csg::engine::Solid::paired_triangles`]): triangle `t` has the corners
    /// `corners[3t..3t + 3]` counter-clockwise, half-edge `3t + i` runs from corner `i` to corner
    /// `i + 1`, and `pairs[3t + i]` is the half-edge running back along it. The result equals
    /// [`Mesh::from_indexed`]'s from the same triangles, built without searching for twins: one
    /// pass lays the half-edges out ([`Mesh::from_paired_faces`]) and one walk around every
    /// vertex checks the pairing and the fans.
    ///
    /// Where a vertex's triangles form more than one fan (a solid pinched to a point there: two
    /// cones tip to tip, a cut through a vertex), each fan after the vertex's first (the one of its
    /// smallest half-edge) gets a vertex of its own at the same position, numbered after the
    /// others in the order of the fans' smallest half-edges — as a boolean result keeps two
    /// vertices where two solids meet along an edge — rather than refusing the solid.
    ///
    /// Cost: O(n) for n triangles (the walk reads each half-edge's pair once).
    ///
    /// # Errors
    /// [`MeshError::NonFinite`] for a NaN or infinite coordinate; [`MeshError::DegenerateFace`] for
    /// a triangle that repeats a vertex; [`MeshError::Internal`] when the pairing is not one of a
    /// closed surface (a half-edge without a pair, pairs not mutual or not running back between
    /// the same vertices) — the engine's bug.
    pub(crate) fn from_paired_triangles(
        positions: Vec<Vec3>,
        corners: Vec<u32>,
        pairs: Vec<u32>,
    ) -> Result<Mesh, MeshError> {
        let (nv, nfh) = (positions.len(), corners.len());
        let bad = |why: &str| Err(MeshError::Internal(format!("paired triangles: {why}")));
        if pairs.len() != nfh {
            return bad("array lengths differ");
        }
        for (t, c) in corners.chunks_exact(3).enumerate() {
            if c[0] == c[1] || c[1] == c[2] || c[0] == c[2] {
                let v = if c[0] == c[1] || c[0] == c[2] { c[0] } else { c[1] };
                return Err(MeshError::DegenerateFace { face: t, reason: format!("vertex {v} appears twice") });
            }
        }
        // A half-edge without a pair (NONE) is out of range too: the surface must be closed.
        if !pairs.chunks(1024).all(|b| b.iter().fold(true, |ok, &t| ok & ((t as usize) < nfh))) {
            return bad("a half-edge without a pair");
        }
        let mut mesh = Mesh::from_paired_faces(positions, 3, corners, pairs, vec![0.0; nfh], vec![0.0; nv])?;
        // Each vertex's fan, walked from its first half-edge. A walk stays among its vertex's
        // half-edges and meets each once, so the walks cover them all (their lengths add up to
        // the half-edges) exactly when no vertex has a second fan. Runs of vertices in
        // parallel; the first error in vertex order, as one walk after another would give.
        let walks: Vec<Result<usize, MeshError>> = mesh
            .vertex_out
            .par_chunks(FAN_WALK_RUN)
            .map(|run| {
                run.iter()
                    .filter(|&&first| first != NONE)
                    .try_fold(0, |sum, &first| Ok(sum + mesh.walk_fan(first, |_| {})? as usize))
            })
            .collect();
        let mut walked = 0;
        for w in walks {
            walked += w?;
        }
        if walked != mesh.he_origin.len() {
            mesh.split_fans();
        }
        Ok(mesh)
    }

    /// A closed mesh of the triangles `corners` (three vertex ids each, counter-clockwise seen
    /// from outside) over `positions`, pairing the half-edges itself ([`FaceTwins::find`]) and
    /// then as [`Mesh::from_paired_triangles`]: where the surface pinches to a point (a revolved
    /// profile touching the axis at one point) each fan after the first gets its own vertex.
    /// For callers whose triangles close a surface by construction (an extrusion, a
    /// revolution). Cost: O(n) for n triangles.
    ///
    /// # Errors
    /// [`MeshError::IndexOutOfRange`] for a corner ≥ #V; [`MeshError::NonManifoldEdge`] when two
    /// triangles use the same directed edge; [`MeshError::Internal`] when a half-edge has no twin
    /// (the triangles do not close) — the caller's bug; as [`Mesh::from_paired_triangles`].
    pub(crate) fn from_closed_triangles(positions: Vec<Vec3>, corners: Vec<u32>) -> Result<Mesh, MeshError> {
        let nv = positions.len();
        if nv >= NONE as usize || corners.len() >= (NONE as usize) / 2 || !corners.len().is_multiple_of(3) {
            return Err(MeshError::TooLarge { what: format!("{nv} vertices, {} corners", corners.len()) });
        }
        if let Some(i) = corners.iter().position(|&v| v as usize >= nv) {
            return Err(MeshError::IndexOutOfRange { face: i / 3, index: u64::from(corners[i]), vertex_count: nv });
        }
        let targets: Vec<u32> = corners.chunks_exact(3).flat_map(|c| [c[1], c[2], c[0]]).collect();
        let faces: Vec<u32> = (0..corners.len() as u32).map(|h| h / 3).collect();
        let twins = FaceTwins::find(nv, &corners, &targets, &faces, &mut |_| Ok(()))?.twins;
        if let Some(h) = twins.iter().position(|&t| t == NONE) {
            return Err(MeshError::Internal(format!(
                "closed triangles: the edge from vertex {} to vertex {} has no twin",
                corners[h], targets[h]
            )));
        }
        Mesh::from_paired_triangles(positions, corners, twins)
    }

    /// Walks the fan of half-edges leaving `first`'s origin (each the twin of the one before it
    /// in its triangle), calling `visit` on each, and returns how many it met; checks on the way
    /// that each pair is mutual and leaves the same vertex. Closed meshes only.
    fn walk_fan(&self, first: u32, mut visit: impl FnMut(u32)) -> Result<u32, MeshError> {
        let v = self.he_origin[first as usize];
        let limit = self.he_origin.len() as u32;
        let mut seen = 0u32;
        let mut h = first;
        loop {
            visit(h);
            seen += 1;
            let p = self.he_prev[h as usize];
            let t = self.he_twin[p as usize];
            if self.he_twin[t as usize] != p || self.he_origin[t as usize] != v {
                return Err(MeshError::Internal(format!(
                    "paired triangles: half-edges {p} and {t} are not a pair around vertex {v}"
                )));
            }
            h = t;
            if h == first || seen > limit {
                return Ok(seen);
            }
        }
    }

    /// Gives every fan of half-edges around a vertex after its first (see
    /// [`Mesh::from_paired_triangles`]) a vertex of its own at the same position.
    fn split_fans(&mut self) {
        let nfh = self.he_origin.len();
        let mut visited = vec![false; nfh];
        for v in 0..self.positions.len() {
            let first = self.vertex_out[v];
            if first != NONE {
                // Checked by the caller's walk: no error here.
                let _ = self.walk_fan(first, |h| visited[h as usize] = true);
            }
        }
        for h0 in 0..nfh as u32 {
            if visited[h0 as usize] {
                continue;
            }
            let w = self.positions.len() as u32;
            let v = self.he_origin[h0 as usize] as usize;
            self.positions.push(self.positions[v]);
            self.vertex_sharpness.push(self.vertex_sharpness[v]);
            self.vertex_out.push(h0);
            let mut fan = Vec::new();
            let _ = self.walk_fan(h0, |h| fan.push(h));
            for h in fan {
                visited[h as usize] = true;
                self.he_origin[h as usize] = w;
            }
        }
    }
}

/// The face, next and previous half-edge of `nfh` face half-edges laid out `A` to a face, in
/// face order (the arity a constant, so the divisions are multiplications; for a power of two
/// such as quads, next and previous are branch-free masks, which vectorise).
fn face_cycles<const A: u32>(nfh: usize, face: &mut Vec<u32>, next: &mut Vec<u32>, prev: &mut Vec<u32>) {
    let n = nfh as u32;
    // The face's first half-edge plus the corner after (before) h's, modulo A.
    let m = A - 1;
    let face_of = |h: u32| h / A;
    let next_of = |h: u32| {
        if A.is_power_of_two() {
            (h & !m) | ((h + 1) & m)
        } else if (h + 1).is_multiple_of(A) {
            h + 1 - A
        } else {
            h + 1
        }
    };
    let prev_of = |h: u32| {
        if A.is_power_of_two() {
            (h & !m) | (h.wrapping_add(m) & m)
        } else if h.is_multiple_of(A) {
            h + A - 1
        } else {
            h - 1
        }
    };
    if nfh >= FACE_CYCLES_PAR {
        face.par_extend((0..n).into_par_iter().map(face_of));
        next.par_extend((0..n).into_par_iter().map(next_of));
        prev.par_extend((0..n).into_par_iter().map(prev_of));
    } else {
        face.extend((0..n).map(face_of));
        next.extend((0..n).map(next_of));
        prev.extend((0..n).map(prev_of));
    }
}

/// Adds a boundary half-edge opposite every face half-edge without a twin (in half-edge order)
/// and links each boundary loop; returns each vertex's outgoing boundary half-edge (`NONE` for
/// an inner vertex), or no list at all when every face half-edge has a twin (a closed mesh,
/// found by one branch-free pass). Two boundary half-edges leaving one vertex make it
/// non-manifold.
fn close_boundary(
    nv: usize,
    origin: &mut Vec<u32>,
    next: &mut Vec<u32>,
    prev: &mut Vec<u32>,
    face: &mut Vec<u32>,
    twin: &mut Vec<u32>,
) -> Result<Vec<u32>, MeshError> {
    let nfh = origin.len();
    const BLOCK: usize = 1024;
    let Some(first_block) = twin.chunks(BLOCK).position(|b| b.iter().fold(false, |open, &t| open | (t == NONE))) else {
        return Ok(Vec::new());
    };
    let mut boundary_out = vec![NONE; nv];
    for h in first_block * BLOCK..nfh {
        if twin[h] == NONE {
            let b = origin.len() as u32;
            let from = origin[next[h] as usize];
            if boundary_out[from as usize] != NONE {
                return Err(MeshError::NonManifoldVertex { vertex: from, fans: 2 });
            }
            boundary_out[from as usize] = b;
            origin.push(from);
            next.push(NONE);
            prev.push(NONE);
            face.push(NONE);
            twin.push(h as u32);
            twin[h] = b;
        }
    }
    for b in nfh..origin.len() {
        // b runs from target(h) to origin(h); the boundary continues from origin(h).
        let n = boundary_out[origin[twin[b] as usize] as usize];
        next[b] = n;
        prev[n as usize] = b as u32;
    }
    Ok(boundary_out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad_positions() -> Vec<Vec3> {
        vec![Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)]
    }

    #[test]
    fn single_quad_has_boundary_loop() {
        let m = Mesh::from_polygons(quad_positions(), &[[0, 1, 2, 3]]).unwrap();
        assert_eq!((m.vertex_count(), m.edge_count(), m.face_count()), (4, 4, 1));
        assert!(!m.is_closed());
        // Every boundary half-edge's next is a boundary half-edge: one loop of four.
        let b = m.twin(m.face_halfedge(0));
        let mut h = b;
        for _ in 0..4 {
            assert!(m.is_boundary_halfedge(h));
            h = m.next(h);
        }
        assert_eq!(h, b);
    }

    #[test]
    fn out_of_range_index_names_face_and_index() {
        let e = Mesh::from_polygons(quad_positions(), &[[0, 1, 7]]).unwrap_err();
        assert_eq!(e, MeshError::IndexOutOfRange { face: 0, index: 7, vertex_count: 4 });
    }

    #[test]
    fn three_faces_on_one_edge_are_rejected_naming_the_edge() {
        let mut p = quad_positions();
        p.push(Vec3::new(0.5, 0.5, 1.0));
        p.push(Vec3::new(0.5, 0.5, -1.0));
        // Faces 0, 1 and 2 all contain edge 0-1; faces 1 and 2 both use it as 0→1.
        let e = Mesh::from_polygons(p, &[vec![1, 0, 2], vec![0, 1, 4], vec![0, 1, 5]]).unwrap_err();
        assert_eq!(e, MeshError::NonManifoldEdge { a: 0, b: 1, first: 1, second: 2 });
        assert!(e.to_string().contains("edge (0, 1)"));
    }

    #[test]
    fn bowtie_vertex_is_rejected() {
        let p = vec![
            Vec3::ZERO,
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-1.0, 0.0, 0.0),
            Vec3::new(-1.0, -1.0, 0.0),
        ];
        let e = Mesh::from_polygons(p, &[[0, 1, 2], [0, 3, 4]]).unwrap_err();
        assert!(matches!(e, MeshError::NonManifoldVertex { vertex: 0, .. }), "{e}");
    }

    #[test]
    fn a_hub_of_high_valence_finds_its_twins_and_its_repeated_edges() {
        // A closed fan of 50,000 triangles around a hub, over a 50,000-gon: the hub's bucket is
        // searched by bisection; every half-edge has its twin and the mesh is closed.
        let n = 50_000u32;
        let mut positions = vec![Vec3::new(0.0, 0.0, 1.0)];
        positions.extend((0..n).map(|i| Vec3::new(f64::from(i).cos(), f64::from(i).sin(), 0.0)));
        let mut faces: Vec<Vec<u32>> = (0..n).map(|i| vec![0, 1 + i, 1 + (i + 1) % n]).collect();
        faces.push((1..=n).rev().collect());
        let m = Mesh::from_polygons(positions.clone(), &faces).unwrap();
        assert!(m.is_closed() && m.is_manifold());
        assert_eq!(
            (m.vertex_count(), m.face_count(), m.edge_count()),
            (n as usize + 1, n as usize + 1, 2 * n as usize)
        );
        // The same directed hub edge twice is found in the sorted bucket, naming both faces.
        faces[7] = vec![0, 4, 10];
        let e = Mesh::from_polygons(positions, &faces).unwrap_err();
        assert_eq!(e, MeshError::NonManifoldEdge { a: 0, b: 4, first: 3, second: 7 });
    }

    #[test]
    fn nan_coordinate_is_rejected() {
        let mut p = quad_positions();
        p[2].y = f64::NAN;
        let e = Mesh::from_polygons(p, &[[0, 1, 2, 3]]).unwrap_err();
        assert!(matches!(e, MeshError::NonFinite { vertex: 2, .. }));
    }

    #[test]
    fn repeated_vertex_and_short_faces_are_degenerate() {
        assert!(matches!(
            Mesh::from_polygons(quad_positions(), &[vec![0, 1, 1]]),
            Err(MeshError::DegenerateFace { face: 0, .. })
        ));
        assert!(matches!(
            Mesh::from_polygons(quad_positions(), &[vec![0, 1]]),
            Err(MeshError::DegenerateFace { face: 0, .. })
        ));
    }

    /// The corners and the twin of every face half-edge of a closed triangle mesh (face `f`'s
    /// half-edges are `3f..3f + 3`, as `from_indexed` lays them out).
    fn corners_and_pairs(m: &Mesh) -> (Vec<u32>, Vec<u32>) {
        let nfh = 3 * m.face_count() as u32;
        ((0..nfh).map(|h| m.origin(h)).collect(), (0..nfh).map(|h| m.twin(h)).collect())
    }

    #[test]
    fn paired_triangles_build_the_mesh_from_indexed_builds() {
        let m = Mesh::icosphere(1.0, 3);
        let (corners, pairs) = corners_and_pairs(&m);
        let arities = vec![3; m.face_count()];
        let indexed = Mesh::from_indexed(m.positions().to_vec(), &corners, &arities).unwrap();
        let paired = Mesh::from_paired_triangles(m.positions().to_vec(), corners, pairs).unwrap();
        assert_eq!(paired, indexed);
        assert!(paired.is_closed() && paired.is_manifold());
    }

    #[test]
    fn paired_triangles_give_each_further_fan_of_a_pinched_vertex_its_own_vertex() {
        // Two tetrahedra tip to tip at vertex 0: two fans there, which from_indexed refuses.
        let tetra = |p: [Vec3; 4]| Mesh::from_polygons(p.to_vec(), &[[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]]);
        let o = Vec3::ZERO;
        let a = tetra([o, Vec3::new(1.0, 0.0, 1.0), Vec3::new(0.0, 1.0, 1.0), Vec3::new(1.0, 1.0, 2.0)]).unwrap();
        let b = tetra([o, Vec3::new(1.0, 0.0, -1.0), Vec3::new(1.0, 1.0, -2.0), Vec3::new(0.0, 1.0, -1.0)]).unwrap();
        let (mut corners, mut pairs) = corners_and_pairs(&a);
        let (cb, pb) = corners_and_pairs(&b);
        // b's vertices after a's, its vertex 0 being a's; its half-edges after a's.
        corners.extend(cb.iter().map(|&v| if v == 0 { 0 } else { v + 3 }));
        pairs.extend(pb.iter().map(|&h| h + 12));
        let mut positions = a.positions().to_vec();
        positions.extend_from_slice(&b.positions()[1..]);
        let arities = vec![3; 8];
        let refused = Mesh::from_indexed(positions.clone(), &corners, &arities).unwrap_err();
        assert!(matches!(refused, MeshError::NonManifoldVertex { vertex: 0, .. }), "{refused}");
        let m = Mesh::from_paired_triangles(positions, corners, pairs).unwrap();
        assert!(m.is_closed() && m.is_manifold());
        assert_eq!((m.vertex_count(), m.face_count(), m.component_count()), (8, 8, 2));
        assert_eq!(m.position(7), o);
        // The first fan (of half-edge 0, a's) keeps vertex 0; b's triangles use the new one.
        assert_eq!((0..4).filter(|&f| m.face_vertices(f).any(|v| v == 0)).count(), 3);
        assert_eq!((4..8).filter(|&f| m.face_vertices(f).any(|v| v == 7)).count(), 3);
        assert!((4..8).all(|f| m.face_vertices(f).all(|v| v != 0)));
        assert!((m.volume() - (a.volume() + b.volume())).abs() < 1e-12);
    }

    /// Over many runs of the parallel fan walks and face cycles: a fine sphere builds as
    /// `from_indexed` builds it, and two fine spheres sharing one vertex get it split.
    #[test]
    fn paired_triangles_over_many_runs_build_the_same_and_split_a_shared_vertex() {
        let m = Mesh::icosphere(1.0, 6);
        let (corners, pairs) = corners_and_pairs(&m);
        let (nv, nfh) = (m.vertex_count(), corners.len());
        assert!(nv > 4 * FAN_WALK_RUN && nfh > FACE_CYCLES_PAR);
        let arities = vec![3; m.face_count()];
        let indexed = Mesh::from_indexed(m.positions().to_vec(), &corners, &arities).unwrap();
        let paired = Mesh::from_paired_triangles(m.positions().to_vec(), corners.clone(), pairs.clone()).unwrap();
        assert!(paired == indexed);
        // A second sphere whose vertex `shared` is the first sphere's vertex 7 (moved there).
        let shared = nv as u32 - 5;
        let renumber = |v: u32| match v {
            v if v == shared => 7,
            v if v > shared => v + nv as u32 - 1,
            v => v + nv as u32,
        };
        let mut positions = m.positions().to_vec();
        let offset = m.position(7) - m.position(shared);
        positions.extend((0..nv as u32).filter(|&v| v != shared).map(|v| m.position(v) + offset));
        let mut both_corners = corners.clone();
        both_corners.extend(corners.iter().map(|&v| renumber(v)));
        let mut both_pairs = pairs.clone();
        both_pairs.extend(pairs.iter().map(|&h| h + nfh as u32));
        let two = Mesh::from_paired_triangles(positions, both_corners, both_pairs).unwrap();
        assert!(two.is_closed() && two.is_manifold());
        assert_eq!((two.vertex_count(), two.component_count()), (2 * nv, 2));
        assert_eq!(two.position(2 * nv as u32 - 1), m.position(7));
    }

    #[test]
    fn paired_triangles_refuse_a_bad_pairing_and_a_repeated_corner() {
        let m = Mesh::icosphere(1.0, 1);
        let (corners, pairs) = corners_and_pairs(&m);
        let p = m.positions().to_vec();
        let mut unpaired = pairs.clone();
        unpaired[5] = NONE;
        let e = Mesh::from_paired_triangles(p.clone(), corners.clone(), unpaired).unwrap_err();
        assert!(matches!(e, MeshError::Internal(_)), "{e}");
        // Two half-edges swapped: pairs no longer mutual.
        let mut swapped = pairs.clone();
        swapped.swap(0, 1);
        assert!(matches!(
            Mesh::from_paired_triangles(p.clone(), corners.clone(), swapped),
            Err(MeshError::Internal(_))
        ));
        let mut repeated = corners;
        repeated[4] = repeated[3];
        let e = Mesh::from_paired_triangles(p, repeated, pairs).unwrap_err();
        assert!(matches!(e, MeshError::DegenerateFace { face: 1, .. }), "{e}");
    }
}
