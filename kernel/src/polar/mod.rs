//! Polar meshes (Brazzolotto, "A 3D Modeling System based on Polar Meshes", seed 004): closed
//! meshes made of annular regions (rings of backbone–loop–backbone–loop quads) and pole regions
//! (triangle fans), with explicit pole and loop markers, the seven structural operations of
//! chapter 4, low-level vertex modelling and the inferred skeleton of §7.1.
//!
//! Notation (ch. 3): a *loop* edge runs along a ring, a *backbone* edge across; a *pole* is the
//! centre of a triangle fan. Neither poles nor loops can be inferred from the topology in general
//! (§3.2.1, §3.2.2), so [`PolarMesh`] stores both. A *split vertex* is a vertex that is not a pole
//! and has valence above 4: a feature is nested there. A *nesting loop* passes a split vertex.
//!
//! Files, one concept each:
//! - [`check`](PolarMesh::check) — every chapter-3 invariant, naming the first one broken;
//! - `markers` — building from a mesh and markers ([`PolarMesh::from_mesh`]), primitives;
//! - `iterators` — the Loop, Parallel and Fan iterators of §3.3 and the list of loops;
//! - one file per operation of chapter 4: `add_refinement`, `remove_refinement`, `add_feature`,
//!   `select_feature` (features and nesting), `remove_feature`, `merge_features`, `split_feature`;
//! - `frames` — loop frames and the low-level move / scale / rotate of §2.4 in global or local frames;
//! - `pick` — nearest vertex, half-edge, face;
//! - `skeleton` — the inferred skeleton (§7.1) and skeleton-based coordinates (§7.2);
//! - `colors` — feature colour coding (appendix B.1.3);
//! - `to_solid` — the mesh as a valid solid: tubes capped inside their parents, united by the
//!   boolean engine (grown plants cross themselves at branch bases);
//! - `transform` — whole-mesh translate, rotate, scale and mirror, as a `Mesh` has them.
//!
//! Every operation validates first and edits only the faces it changes (through
//! [`Mesh::replace_faces`]), so it costs time proportional to the region it affects and leaves
//! the mesh exactly as it was when it refuses.
//!
//! For code that builds polar meshes step by step (L-systems, procedural recipes):
//! - ids of vertices that an operation does not delete are kept; new vertices get new ids
//!   (returned by the operation). Removals move the last elements into freed slots, so re-find
//!   elements by the ids an operation returns, by geometry or through walks after a removal;
//! - to *grow* a branch, nest a feature on a loop ([`PolarMesh::add_feature`]) and move its pole
//!   out; to *extend* any polar region by one segment, add a loop on a spoke of its pole
//!   (`add_refinement(fan(p)[0])`, the loop lands halfway to the pole) and move the pole on;
//! - to *join* two branches, [`PolarMesh::merge_features`] their poles (equal valences), to cut
//!   one, [`PolarMesh::split_feature`] a loop with loops on both sides;
//! - [`PolarMesh::skeleton`] gives nodes, segments, the vertex binding and a rooted tree for
//!   animation; [`Skeleton::positions_from`] rebuilds positions from skeleton coordinates.

mod add_feature;
mod add_refinement;
mod check;
mod colors;
mod error;
mod frames;
mod iterators;
mod markers;
mod merge_features;
mod pick;
mod remove_feature;
mod remove_refinement;
mod select_feature;
mod skeleton;
mod split_feature;
#[cfg(test)]
mod tests_property;
#[cfg(test)]
mod tests_recipes;
#[cfg(test)]
mod tests_to_solid;
mod to_solid;
mod transform;

pub use add_feature::FeatureOptions;
pub use add_refinement::Refinement;
pub use error::PolarError;
pub use frames::{Frame, LoopFrame};
pub use skeleton::Skeleton;

use crate::math::Vec3;
use crate::mesh::edit::EditLog;
use crate::mesh::Mesh;

/// A closed polar mesh: a half-edge [`Mesh`] with a pole marker per vertex and a loop marker per
/// half-edge (kept equal on both halves of an edge).
///
/// Build one with [`PolarMesh::octahedron`], [`PolarMesh::uv_sphere`] or [`PolarMesh::from_mesh`];
/// change it with the seven operations (`add_refinement`, `remove_refinement`, `add_feature`,
/// `select_feature`, `remove_feature`, `merge_features`, `split_feature`) and the low-level
/// `move_vertices`, `scale_vertices`, `rotate_vertices`. Ids are those of the underlying mesh and
/// are stable until the next structural operation.
#[derive(Clone, Debug, PartialEq)]
pub struct PolarMesh {
    mesh: Mesh,
    pole: Vec<bool>,
    is_loop: Vec<bool>,
}

/// A polygon an operation will create: its corners and, for each corner `k`, whether the edge
/// from corner `k` to corner `k + 1` is a loop edge.
#[derive(Clone, Debug, Default)]
pub(crate) struct Poly {
    pub corners: Vec<u32>,
    pub loops: Vec<bool>,
}

impl Poly {
    /// Drops consecutive repeated corners and the degenerate edge between them. When corner `k`
    /// equals corner `k + 1`, removing corner `k` with its edge flag keeps every other edge's
    /// flag: the edge from corner `k − 1` now reaches the same vertex as before.
    pub fn dedup(mut self) -> Poly {
        let mut k = 0;
        while self.corners.len() > 1 && k < self.corners.len() {
            let n = self.corners.len();
            if self.corners[k] == self.corners[(k + 1) % n] {
                self.corners.remove(k);
                self.loops.remove(k);
                k = 0;
            } else {
                k += 1;
            }
        }
        self
    }

    /// Removes corner `k`, joining its two edges; the joined edge keeps the flag of the edge
    /// that entered corner `k`.
    pub fn drop_corner(&mut self, k: usize) {
        self.corners.remove(k);
        // Edge k (leaving the corner) disappears; edge k − 1 now reaches corner k + 1.
        self.loops.remove(k);
    }
}

/// Polygons an operation will create, back to back: polygon `i` has the corners
/// `corners[ends[i − 1]..ends[i]]` and, for each, the loop marker of the edge to the next corner.
#[derive(Clone, Debug, Default)]
pub(crate) struct PolyList {
    corners: Vec<u32>,
    loops: Vec<bool>,
    ends: Vec<usize>,
}

impl PolyList {
    /// An empty list with room for `polys` polygons of `corners` corners in all.
    pub fn with_capacity(polys: usize, corners: usize) -> PolyList {
        PolyList {
            corners: Vec::with_capacity(corners),
            loops: Vec::with_capacity(corners),
            ends: Vec::with_capacity(polys),
        }
    }

    /// Appends a polygon (`corners` and `loops` of the same length).
    pub fn push(&mut self, corners: &[u32], loops: &[bool]) {
        debug_assert_eq!(corners.len(), loops.len());
        self.corners.extend_from_slice(corners);
        self.loops.extend_from_slice(loops);
        self.ends.push(self.corners.len());
    }

    /// Appends the polygon `corners[from..=to]` of a scratch polygon, closed by an edge marked
    /// `chord` (one side of a split along the chord between corners `from < to`).
    pub fn push_split_side(&mut self, corners: &[u32], loops: &[bool], from: usize, to: usize, chord: bool) {
        self.corners.extend_from_slice(&corners[from..=to]);
        self.loops.extend_from_slice(&loops[from..to]);
        self.loops.push(chord);
        self.ends.push(self.corners.len());
    }

    /// Appends the other side: `corners[to..]` then `corners[..=from]`, closed by `chord`.
    pub fn push_split_rest(&mut self, corners: &[u32], loops: &[bool], from: usize, to: usize, chord: bool) {
        self.corners.extend_from_slice(&corners[to..]);
        self.corners.extend_from_slice(&corners[..=from]);
        self.loops.extend_from_slice(&loops[to..]);
        self.loops.extend_from_slice(&loops[..from]);
        self.loops.push(chord);
        self.ends.push(self.corners.len());
    }

    /// Number of polygons.
    pub fn len(&self) -> usize {
        self.ends.len()
    }

    fn range(&self, i: usize) -> std::ops::Range<usize> {
        (if i == 0 { 0 } else { self.ends[i - 1] })..self.ends[i]
    }

    /// Polygon `i`'s corners.
    pub fn corners(&self, i: usize) -> &[u32] {
        &self.corners[self.range(i)]
    }

    /// Polygon `i`'s edge markers.
    pub fn loops(&self, i: usize) -> &[bool] {
        &self.loops[self.range(i)]
    }
}

impl PolarMesh {
    /// The underlying half-edge mesh.
    #[must_use]
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// A copy of the underlying mesh (same vertex ids and positions).
    #[must_use]
    pub fn to_mesh(&self) -> Mesh {
        self.mesh.clone()
    }

    /// Colours every face `color` (see [`Mesh::set_color`]); faces the operations and growth
    /// make later take the colour of the faces they replace.
    ///
    /// # Errors
    /// [`PolarError::InvalidArgument`] for a component outside `0..=1`; the polar mesh is
    /// unchanged.
    pub fn set_color(&mut self, color: crate::mesh::Rgba) -> Result<(), PolarError> {
        self.mesh.set_color(color).map_err(|e| PolarError::InvalidArgument(e.to_string()))
    }

    /// Colours the faces `faces` (a feature's faces, say) `color` (see [`Mesh::color_faces`]).
    ///
    /// # Errors
    /// [`PolarError::InvalidArgument`] for a bad colour or face id; the polar mesh is unchanged.
    pub fn color_faces(&mut self, faces: &[u32], color: crate::mesh::Rgba) -> Result<(), PolarError> {
        self.mesh.color_faces(faces, color).map_err(|e| PolarError::InvalidArgument(e.to_string()))
    }

    /// The underlying mesh, consuming the polar mesh.
    #[must_use]
    pub fn into_mesh(self) -> Mesh {
        self.mesh
    }

    /// Number of vertices.
    #[must_use]
    pub fn vertex_count(&self) -> usize {
        self.mesh.vertex_count()
    }

    /// Number of faces.
    #[must_use]
    pub fn face_count(&self) -> usize {
        self.mesh.face_count()
    }

    /// Number of half-edges.
    #[must_use]
    pub fn halfedge_count(&self) -> usize {
        self.mesh.halfedge_count()
    }

    /// Whether vertex `v` is marked as a pole. `v` must exist.
    #[must_use]
    pub fn is_pole(&self, v: u32) -> bool {
        self.pole[v as usize]
    }

    /// Whether the edge of half-edge `h` is marked as a loop edge (otherwise it is a backbone).
    #[must_use]
    pub fn is_loop(&self, h: u32) -> bool {
        self.is_loop[h as usize]
    }

    /// The poles, ascending.
    #[must_use]
    pub fn poles(&self) -> Vec<u32> {
        (0..self.vertex_count() as u32).filter(|&v| self.pole[v as usize]).collect()
    }

    /// The number of edges at vertex `v`.
    #[must_use]
    pub fn valence(&self, v: u32) -> usize {
        self.mesh.valence(v)
    }

    /// Whether `v` is a split vertex: not a pole, valence above 4 (a feature is nested there).
    #[must_use]
    pub fn is_split(&self, v: u32) -> bool {
        !self.pole[v as usize] && self.mesh.valence(v) > 4
    }

    /// The position of vertex `v`.
    #[must_use]
    pub fn position(&self, v: u32) -> Vec3 {
        self.mesh.position(v)
    }

    /// `[origin, target]` of half-edge `h`.
    #[must_use]
    pub fn ends(&self, h: u32) -> [u32; 2] {
        [self.mesh.origin(h), self.mesh.target(h)]
    }

    /// The face of half-edge `h`.
    #[must_use]
    pub fn face_of(&self, h: u32) -> u32 {
        self.mesh.face(h)
    }

    /// Checks a vertex id from a script or a caller.
    ///
    /// # Errors
    /// [`PolarError::NoSuchElement`].
    pub fn vertex_id(&self, v: i64) -> Result<u32, PolarError> {
        if v < 0 || v as usize >= self.vertex_count() {
            return Err(PolarError::NoSuchElement { what: "vertex", id: v, count: self.vertex_count() });
        }
        Ok(v as u32)
    }

    /// Checks a half-edge id.
    ///
    /// # Errors
    /// [`PolarError::NoSuchElement`].
    pub fn halfedge_id(&self, h: i64) -> Result<u32, PolarError> {
        if h < 0 || h as usize >= self.halfedge_count() {
            return Err(PolarError::NoSuchElement { what: "half-edge", id: h, count: self.halfedge_count() });
        }
        Ok(h as u32)
    }

    /// Checks a face id.
    ///
    /// # Errors
    /// [`PolarError::NoSuchElement`].
    pub fn face_id(&self, f: i64) -> Result<u32, PolarError> {
        if f < 0 || f as usize >= self.face_count() {
            return Err(PolarError::NoSuchElement { what: "face", id: f, count: self.face_count() });
        }
        Ok(f as u32)
    }

    /// Checks a pole id.
    ///
    /// # Errors
    /// [`PolarError::NoSuchElement`], [`PolarError::NotAPole`].
    pub fn pole_id(&self, v: i64) -> Result<u32, PolarError> {
        let v = self.vertex_id(v)?;
        if !self.is_pole(v) {
            return Err(PolarError::NotAPole { vertex: v });
        }
        Ok(v)
    }

    /// The loop marker of the edge joining `a` and `b`, if they are joined.
    pub(crate) fn edge_is_loop(&self, a: u32, b: u32) -> Option<bool> {
        self.mesh.outgoing(a).find(|&h| self.mesh.target(h) == b).map(|h| self.is_loop[h as usize])
    }

    /// The corners of face `f` starting at the origin of its half-edge `h`, with loop markers.
    pub(crate) fn poly_from(&self, h: u32) -> Poly {
        let mut p = Poly::default();
        for x in self.mesh.loop_halfedges(h) {
            p.corners.push(self.mesh.origin(x));
            p.loops.push(self.is_loop[x as usize]);
        }
        p
    }

    /// Replaces faces `remove` by `polys` (new vertex `V + i` at `new_positions[i]`, a pole when
    /// `new_poles[i]`), then brings the markers along. Validated before anything changes.
    pub(crate) fn rebuild(
        &mut self,
        remove: &[u32],
        polys: &[Poly],
        new_positions: &[Vec3],
        new_poles: &[bool],
    ) -> Result<EditLog, PolarError> {
        let mut flat = PolyList::with_capacity(polys.len(), polys.iter().map(|p| p.corners.len()).sum());
        for p in polys {
            flat.push(&p.corners, &p.loops);
        }
        self.rebuild_list(remove, &flat, new_positions, new_poles)
    }

    /// [`PolarMesh::rebuild`] with the polygons back to back in one list (no allocation per
    /// polygon: the operations that rebuild whole rings use it).
    pub(crate) fn rebuild_list(
        &mut self,
        remove: &[u32],
        polys: &PolyList,
        new_positions: &[Vec3],
        new_poles: &[bool],
    ) -> Result<EditLog, PolarError> {
        let corners: Vec<&[u32]> = (0..polys.len()).map(|i| polys.corners(i)).collect();
        let log = self.mesh.replace_faces(remove, &corners, new_positions).map_err(PolarError::WouldBreakManifold)?;
        log.apply_vertex_moves(&mut self.pole, false);
        for (i, &v) in log.new_vertices().iter().enumerate() {
            self.pole[v as usize] = new_poles.get(i).copied().unwrap_or(false);
        }
        log.apply_halfedge_moves(&mut self.is_loop, false);
        for (i, &f) in log.new_faces().iter().enumerate() {
            let h0 = self.mesh.face_halfedge(f);
            let flags = polys.loops(i);
            for (k, h) in self.mesh.loop_halfedges(h0).enumerate() {
                self.is_loop[h as usize] = flags[k];
                self.is_loop[self.mesh.twin(h) as usize] = flags[k];
            }
        }
        Ok(log)
    }
}
