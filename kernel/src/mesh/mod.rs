//! The half-edge polygon mesh.
//!
//! Notation: `v` vertex, `h` half-edge, `f` face, all `u32` ids indexing dense arrays. A face is a
//! cycle of half-edges linked by `next`; every half-edge has a `twin` running the other way.
//! A half-edge with no face ([`NONE`]) lies on a boundary; boundary half-edges are linked into
//! boundary loops by `next` too, so circulation never meets a missing twin.
//!
//! Ids are stable until the next topological operation. Operations that only move vertices keep
//! every id.

mod attributes;
mod build;
mod circulate;
mod combine;
pub mod edit;
mod error;
mod estimate;
mod face_part;
mod face_source;
mod measure;
mod primitive_checks;
mod primitives;
mod subdiv_options;
mod transform;
mod triangulate;

pub use attributes::check_sharpness;
pub use error::MeshError;
pub use estimate::{check_mesh_size, mesh_bytes};
pub use face_part::{check_color, parse_hex_color, to_hex_color, FacePart, Origin, Rgba, Span};
pub use face_source::{BlockSubFace, FaceSource};
pub use measure::Measures;
pub use primitive_checks::{check_length, check_point, MAX_LENGTH, MIN_LENGTH};
pub use subdiv_options::{BoundaryInterpolation, CreaseMethod, SubdivOptions, TriangleSubdivision, SHARPNESS_INFINITE};

use crate::math::Vec3;

/// The id that stands for "none" (the face of a boundary half-edge, the outgoing half-edge of an
/// isolated vertex).
pub const NONE: u32 = u32::MAX;

/// A closed or bounded 2-manifold polygon mesh with faces of any arity.
///
/// Built by [`Mesh::from_polygons`] or [`Mesh::from_indexed`], which reject non-manifold input.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    positions: Vec<Vec3>,
    /// One outgoing half-edge per vertex; the boundary one when the vertex is on a boundary.
    vertex_out: Vec<u32>,
    he_origin: Vec<u32>,
    he_next: Vec<u32>,
    he_prev: Vec<u32>,
    he_twin: Vec<u32>,
    he_face: Vec<u32>,
    face_he: Vec<u32>,
    /// Crease sharpness per half-edge (0 smooth, `f64::INFINITY` infinitely sharp), kept equal on
    /// both halves of an edge.
    he_sharpness: Vec<f64>,
    /// Corner sharpness per vertex (0 none, `f64::INFINITY` a corner that stays put).
    vertex_sharpness: Vec<f64>,
    /// The subdivision options this mesh is refined with (boundary mode, creasing, triangles).
    subdiv_options: SubdivOptions,
    /// Optional RGBA colour per vertex, components in 0..=1.
    vertex_colors: Option<Vec<[f32; 4]>>,
    /// Optional provenance per face: the input each face of a boolean result came from.
    face_sources: Option<Vec<FaceSource>>,
    /// Optional part id per face (colour, name, recipe origin), indexing `parts`; see [`FacePart`].
    face_parts: Option<Vec<u32>>,
    /// The part table the ids of `face_parts` index (empty when `face_parts` is `None`).
    parts: Vec<FacePart>,
}

impl Mesh {
    /// Number of vertices (including any not used by a face).
    #[must_use]
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of faces.
    #[must_use]
    pub fn face_count(&self) -> usize {
        self.face_he.len()
    }

    /// Number of half-edges (twice the number of edges).
    #[must_use]
    pub fn halfedge_count(&self) -> usize {
        self.he_origin.len()
    }

    /// Number of edges.
    #[must_use]
    pub fn edge_count(&self) -> usize {
        self.he_origin.len() / 2
    }

    /// Position of vertex `v`.
    #[must_use]
    pub fn position(&self, v: u32) -> Vec3 {
        self.positions[v as usize]
    }

    /// All positions, indexed by vertex id.
    #[must_use]
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// Replaces every position (same count), keeping all ids and attributes.
    ///
    /// # Errors
    /// [`MeshError::NoSuchElement`] when the count differs, [`MeshError::NonFinite`] for NaN or
    /// infinite coordinates. The mesh is unchanged on error.
    pub fn set_positions(&mut self, positions: Vec<Vec3>) -> Result<(), MeshError> {
        if positions.len() != self.positions.len() {
            return Err(MeshError::NoSuchElement {
                what: "vertex",
                id: positions.len() as u64,
                count: self.positions.len(),
            });
        }
        build::check_finite(&positions)?;
        self.positions = positions;
        Ok(())
    }

    /// A copy with the positions mapped by `f`, keeping every id and attribute.
    #[must_use]
    pub fn map_positions(&self, f: impl Fn(Vec3) -> Vec3) -> Mesh {
        let mut m = self.clone();
        for p in &mut m.positions {
            *p = f(*p);
        }
        m
    }

    /// The vertex a half-edge starts from.
    #[must_use]
    pub fn origin(&self, h: u32) -> u32 {
        self.he_origin[h as usize]
    }

    /// The vertex a half-edge points to.
    #[must_use]
    pub fn target(&self, h: u32) -> u32 {
        self.he_origin[self.he_twin[h as usize] as usize]
    }

    /// The next half-edge around the same face (or boundary loop).
    #[must_use]
    pub fn next(&self, h: u32) -> u32 {
        self.he_next[h as usize]
    }

    /// The previous half-edge around the same face (or boundary loop).
    #[must_use]
    pub fn prev(&self, h: u32) -> u32 {
        self.he_prev[h as usize]
    }

    /// The half-edge running the other way along the same edge.
    #[must_use]
    pub fn twin(&self, h: u32) -> u32 {
        self.he_twin[h as usize]
    }

    /// The face of a half-edge, or [`NONE`] on a boundary.
    #[must_use]
    pub fn face(&self, h: u32) -> u32 {
        self.he_face[h as usize]
    }

    /// Whether `h` lies on a boundary (has no face).
    #[must_use]
    pub fn is_boundary_halfedge(&self, h: u32) -> bool {
        self.he_face[h as usize] == NONE
    }

    /// One half-edge of face `f`.
    #[must_use]
    pub fn face_halfedge(&self, f: u32) -> u32 {
        self.face_he[f as usize]
    }

    /// One outgoing half-edge of `v` (the boundary one for a boundary vertex), or [`NONE`] for an
    /// isolated vertex.
    #[must_use]
    pub fn vertex_halfedge(&self, v: u32) -> u32 {
        self.vertex_out[v as usize]
    }

    /// Whether vertex `v` lies on a boundary.
    #[must_use]
    pub fn is_boundary_vertex(&self, v: u32) -> bool {
        let h = self.vertex_out[v as usize];
        h != NONE && self.is_boundary_halfedge(h)
    }

    /// The edge id of a half-edge: the smaller of the two half-edge ids divided by two is not
    /// dense, so edges are named by their lower half-edge; see [`Mesh::edges`].
    #[must_use]
    pub fn edge_key(&self, h: u32) -> u32 {
        h.min(self.he_twin[h as usize])
    }

    /// Each edge once, as its lower half-edge id.
    pub fn edges(&self) -> impl Iterator<Item = u32> + '_ {
        (0..self.he_origin.len() as u32).filter(move |&h| h < self.he_twin[h as usize])
    }

    /// The half-edge from `a` to `b`, if they are joined by an edge.
    #[must_use]
    pub fn find_halfedge(&self, a: u32, b: u32) -> Option<u32> {
        if a as usize >= self.positions.len() || b as usize >= self.positions.len() {
            return None;
        }
        self.outgoing(a).find(|&h| self.target(h) == b)
    }

    /// The faces as vertex-id lists, in face-id order.
    #[must_use]
    pub fn to_polygons(&self) -> Vec<Vec<u32>> {
        (0..self.face_count() as u32).map(|f| self.face_vertices(f).collect()).collect()
    }

    /// The faces as one flat index list and one arity per face (the compact form of
    /// [`Mesh::to_polygons`]).
    #[must_use]
    pub fn to_indexed(&self) -> (Vec<u32>, Vec<u32>) {
        let mut indices = Vec::with_capacity(self.halfedge_count() / 2 * 2);
        let mut arities = Vec::with_capacity(self.face_count());
        for f in 0..self.face_count() as u32 {
            let before = indices.len();
            indices.extend(self.face_vertices(f));
            arities.push((indices.len() - before) as u32);
        }
        (indices, arities)
    }

    /// Number of vertices of face `f`.
    #[must_use]
    pub fn face_arity(&self, f: u32) -> usize {
        self.face_halfedges(f).count()
    }

    /// Whether every face is a triangle.
    #[must_use]
    pub fn is_triangle_mesh(&self) -> bool {
        (0..self.face_count() as u32).all(|f| self.face_arity(f) == 3)
    }

    /// Whether every face is a quad.
    #[must_use]
    pub fn is_quad_mesh(&self) -> bool {
        (0..self.face_count() as u32).all(|f| self.face_arity(f) == 4)
    }

    /// Checks that `v` names a vertex of this mesh.
    ///
    /// # Errors
    /// [`MeshError::NoSuchElement`] otherwise.
    pub fn check_vertex(&self, v: i64) -> Result<u32, MeshError> {
        if v < 0 || v as usize >= self.vertex_count() {
            return Err(MeshError::NoSuchElement { what: "vertex", id: v as u64, count: self.vertex_count() });
        }
        Ok(v as u32)
    }

    /// Checks that `f` names a face of this mesh.
    ///
    /// # Errors
    /// [`MeshError::NoSuchElement`] otherwise.
    pub fn check_face(&self, f: i64) -> Result<u32, MeshError> {
        if f < 0 || f as usize >= self.face_count() {
            return Err(MeshError::NoSuchElement { what: "face", id: f as u64, count: self.face_count() });
        }
        Ok(f as u32)
    }

    /// Checks that `h` names a half-edge of this mesh.
    ///
    /// # Errors
    /// [`MeshError::NoSuchElement`] otherwise.
    pub fn check_halfedge(&self, h: i64) -> Result<u32, MeshError> {
        if h < 0 || h as usize >= self.halfedge_count() {
            return Err(MeshError::NoSuchElement { what: "half-edge", id: h as u64, count: self.halfedge_count() });
        }
        Ok(h as u32)
    }
}
