//! Errors of polar meshes: bad arguments, broken chapter-3 invariants, refused operations.

use thiserror::Error;

use crate::mesh::edit::EditError;

/// Why a polar-mesh query or operation failed. Each refusal names the rule of the thesis (seed
/// 004) it enforces and the element that breaks it. Whenever an operation returns one of these,
/// the mesh is exactly as it was before the call.
///
/// Bad input is every variant but [`PolarError::Internal`], which is a bug in blocksmith.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum PolarError {
    // ---- Arguments -------------------------------------------------------------------------
    /// An id that names no element.
    #[error("{what} {id} does not exist (the mesh has {count})")]
    NoSuchElement { what: &'static str, id: i64, count: usize },
    /// A vertex that should be a pole but is not.
    #[error("vertex {vertex} is not a pole")]
    NotAPole { vertex: u32 },
    /// An empty vertex selection where at least one vertex is needed.
    #[error("the vertex selection is empty")]
    EmptySelection,
    /// A NaN or infinite number, or a result that would overflow.
    #[error("{what} is not finite")]
    NonFinite { what: String },
    /// Another bad argument (a zero rotation axis, an out-of-range parameter).
    #[error("{0}")]
    InvalidArgument(String),

    // ---- Chapter 3 invariants (check, from_mesh) -----------------------------------------------
    /// A boundary half-edge: polar meshes are closed.
    #[error("half-edge {halfedge} lies on a boundary: a polar mesh is closed (ch. 3: every loop edge is shared by exactly 2 regions)")]
    NotClosed { halfedge: u32 },
    /// The half-edge connectivity is not a 2-manifold.
    #[error("the half-edge connectivity is not a 2-manifold")]
    NotManifold,
    /// A vertex no face uses.
    #[error("vertex {vertex} is used by no face")]
    IsolatedVertex { vertex: u32 },
    /// A loop marker set on one half of an edge only.
    #[error("the loop marker of half-edge {halfedge} differs from its twin's (markers are per edge, §3.2.2)")]
    LoopMarkAsymmetric { halfedge: u32 },
    /// A face that is neither a quad nor a triangle.
    #[error(
        "face {face} has {arity} sides: every face is a backbone–loop–backbone–loop quad or a pole triangle (ch. 3)"
    )]
    FaceArity { face: u32, arity: usize },
    /// A quad with a pole corner.
    #[error("face {face} is a quad with the pole {pole} as a corner: a pole is the centre of a triangle fan (ch. 3)")]
    QuadWithPole { face: u32, pole: u32 },
    /// A quad whose edges do not alternate backbone, loop, backbone, loop.
    #[error("face {face} is a quad whose edges are not backbone–loop–backbone–loop (ch. 3, annular region)")]
    QuadNotAlternating { face: u32 },
    /// A triangle with no pole corner.
    #[error("face {face} is a triangle with no pole: triangles belong to pole fans (ch. 3, pole region)")]
    TriangleWithoutPole { face: u32 },
    /// A triangle with more than one pole corner.
    #[error("face {face} is a triangle with {count} poles: a pole triangle has exactly one (ch. 3)")]
    TriangleWithManyPoles { face: u32, count: usize },
    /// A pole triangle whose edge opposite the pole is not a loop, or whose spokes are loops.
    #[error("face {face} at pole {pole}: the edge opposite the pole must be a loop edge and the two edges at the pole backbones (ch. 3)")]
    PoleTriangleEdges { face: u32, pole: u32 },
    /// A break of §3.2.3: after a loop edge comes a backbone; after a backbone not ending at a pole
    /// comes a loop edge.
    #[error("half-edge {halfedge} breaks loop/backbone connectivity (§3.2.3): {rule}")]
    Connectivity { halfedge: u32, rule: &'static str },
    /// A pole with fewer than three edges.
    #[error("pole {pole} has valence {valence}; a pole needs at least 3 (a region of valency 2 doubles an edge)")]
    PoleValence { pole: u32, valence: usize },
    /// A non-pole vertex with fewer than four edges.
    #[error("vertex {vertex} has valence {valence}; a vertex that is not a pole alternates loop and backbone edges and needs at least 4")]
    VertexValence { vertex: u32, valence: usize },
    /// Two edges joining the same pair of vertices.
    #[error("vertices {a} and {b} are joined by more than one edge")]
    DuplicateEdge { a: u32, b: u32 },
    /// A face whose loop/backbone roles the markers do not determine.
    #[error("the edges of face {face} are neither marked nor implied by a marked edge or a pole: mark a loop edge in every region without poles (§3.2.2: loops cannot be inferred in general)")]
    UnmarkedFace { face: u32 },
    /// Markers that contradict each other within one face.
    #[error("the markers contradict each other at face {face}: {reason}")]
    InconsistentMarking { face: u32, reason: String },
    /// A loop marker given for two vertices that are not joined by an edge.
    #[error("loop marker ({a}, {b}) names no edge")]
    NotAnEdge { a: u32, b: u32 },

    // ---- remove_refinement (§4.2.4) ----------------------------------------------------------
    /// §4.2.4 (a): the loop is the last one separating two poles.
    #[error("the loop through half-edge {halfedge} is the last loop separating poles {} and {} (§4.2.4 a)", poles[0], poles[1])]
    LastLoopBetweenPoles { halfedge: u32, poles: [u32; 2] },
    /// §4.2.4 (b): the refinement passes a split vertex, so a feature is nested on it.
    #[error("the refinement through half-edge {halfedge} passes split vertex {vertex} (valence {valence}): it supports a nested feature; remove the nested features first (§4.2.4 b)")]
    RefinementSupportsFeature { halfedge: u32, vertex: u32, valence: usize },
    /// §4.2.4 (c): removing the backbone would leave a region with valency below 3.
    #[error("removing the backbone through half-edge {halfedge} would leave the region at vertex {vertex} with valency {valency}; a region needs at least 3 (§4.2.4 c)")]
    ValencyTooLow { halfedge: u32, vertex: u32, valency: usize },

    // ---- add_feature (§4.3) ----------------------------------------------------------------
    /// §4.3.1: fewer than three vertices (the pole needs 2(|VV|−1) ≥ 4 edges).
    #[error(
        "a feature needs at least 3 consecutive loop vertices (its pole gets 2(|VV|−1) edges, §4.3.1), got {count}"
    )]
    FeatureTooSmall { count: usize },
    /// §4.3.1: a pole among the vertices.
    #[error("vertex {vertex} is a pole; a feature's vertices must not be poles (§4.3.1)")]
    FeatureOnPole { vertex: u32 },
    /// The same vertex twice in a selection that must be a path.
    #[error("vertex {vertex} appears twice")]
    RepeatedVertex { vertex: u32 },
    /// Two listed vertices not joined by an edge.
    #[error("vertices {a} and {b} are not consecutive on one loop (§4.3.1)")]
    NotConsecutive { a: u32, b: u32 },
    /// §4.3.4 (a): the vertices follow a backbone.
    #[error("vertices {a} and {b} are joined by a backbone: features nest on loops, not along backbones (§4.3.4 a)")]
    FeatureOnBackbone { a: u32, b: u32 },
    /// §4.3.4 (d): the run turns at a split vertex into a nested feature's gap.
    #[error("at split vertex {vertex} the vertices leave the loop for the gap of a nested feature: a feature may not partially overlap another; follow the loop over the whole gap or keep clear of it (§4.3.4 d)")]
    FeaturePartialOverlap { vertex: u32 },

    // ---- remove_feature (§4.5) -------------------------------------------------------------
    /// The feature is a whole connected part of the mesh: nothing would bound the hole.
    #[error("the feature of face {face} is a whole connected part of the mesh (no nesting loop bounds it); there is nothing to close the hole with")]
    FeatureIsWholeComponent { face: u32 },
    /// A feature bounded otherwise than by a pole and a loop, or by two disjoint loops.
    #[error("the feature of face {face} is bounded by {loops} nesting loop(s) and {poles} pole(s); removal supports a pole and a loop, or two disjoint loops (§4.5.4)")]
    FeatureBoundary { face: u32, loops: usize, poles: usize },
    /// The feature lies on both sides of an edge of its own boundary loop (it wraps around a
    /// cycle of the skeleton, like a gear's disk around its teeth's loop).
    #[error("the feature of face {face} lies on both sides of the nesting loop at half-edge {halfedge}: it wraps around a cycle of the skeleton, so there is no gap to close (§4.5.4)")]
    FeatureWrapsAround { face: u32, halfedge: u32 },
    /// §4.5.1: the boundary loop has not exactly two split vertices.
    #[error("the boundary loop of the feature has {count} split vertices {vertices:?}; exactly 2 are needed (§4.5.1, §4.5.4)")]
    SplitVertexCount { count: usize, vertices: Vec<u32> },
    /// §4.5.1: the two paths between the split vertices differ in length.
    #[error("between split vertices {} and {} the boundary paths have {} and {} inner vertices; they must be equal (§4.5.1, Fig. 4.8)", split[0], split[1], inner[0], inner[1])]
    AsymmetricPaths { split: [u32; 2], inner: [usize; 2] },

    // ---- merge_features (§4.6) -------------------------------------------------------------
    /// Merging a pole with itself.
    #[error("pole {vertex} cannot be merged with itself")]
    SamePole { vertex: u32 },
    /// §4.6.4: valences differ.
    #[error("poles {} and {} have valences {} and {}; merging needs equal valences (§4.6.4)", poles[0], poles[1], valences[0], valences[1])]
    ValenceMismatch { poles: [u32; 2], valences: [usize; 2] },
    /// The two poles' loops share a vertex.
    #[error("the loops of the two poles share vertex {vertex}: bridging would glue a loop to itself")]
    SharedLoopVertex { vertex: u32 },

    // ---- split_feature (§4.7) --------------------------------------------------------------
    /// A backbone edge where a loop edge is needed.
    #[error("half-edge {halfedge} is a backbone edge; this needs a loop edge")]
    NotALoopEdge { halfedge: u32 },
    /// §4.7.3: a feature is nested on the split loop.
    #[error("the loop through half-edge {halfedge} passes split vertex {vertex}: no nested feature is allowed on the split loop (§4.7.3)")]
    SplitLoopNested { halfedge: u32, vertex: u32 },
    /// §4.7.3: the split loop needs a ring of quads and a supporting loop on both sides.
    #[error("face {face} next to the loop through half-edge {halfedge} is not a quad of a ring leading to another loop: splitting needs loop–split loop–loop side by side (§4.7.3)")]
    SplitNeedsSandwich { halfedge: u32, face: u32 },

    // ---- to_solid --------------------------------------------------------------------------
    /// The loops do not cut the mesh into tubes that unite into the same solid.
    #[error("the loops do not cut the mesh into tubes: {reason}")]
    NotTubes { reason: String },
    /// The boolean engine refused the tubes.
    #[error("{0}")]
    Solid(String),

    // ---- Any operation -------------------------------------------------------------------
    /// The edit would not leave a closed 2-manifold without doubled edges.
    #[error("the result would not be a closed manifold without doubled edges: {0}")]
    WouldBreakManifold(EditError),
    /// A broken internal invariant: a bug in blocksmith, please file an issue.
    #[error("internal error (please file an issue): {0}")]
    Internal(String),
    /// Refused over the memory budget, or stopped by the cancellation token.
    #[error(transparent)]
    Limit(#[from] crate::limits::LimitError),
}
