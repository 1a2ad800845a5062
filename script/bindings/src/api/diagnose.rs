//! What is wrong with a mesh and where (kernel `diagnose`): its connected pieces, its open
//! boundaries, the faces that cross, and one list of every defect with its elements and a
//! position to show it at.

use blocksmith_kernel::diagnose::{self, Defect, DefectKind};
use rhai::plugin::*;
use rhai::{exported_module, Array, Engine, Map, INT};

use super::mesh::SharedMesh;
use crate::convert::{kernel, ScriptResult};

/// Registers the diagnosis functions on `engine`.
pub fn register(engine: &mut Engine) {
    engine.register_global_module(exported_module!(diagnose_api).into());
}

fn int_array(ids: &[u32]) -> Array {
    ids.iter().map(|&i| Dynamic::from(INT::from(i))).collect()
}

/// The edges of a closed loop of vertices, `[a, b]` each, in the loop's order.
fn loop_edges(vertices: &[u32]) -> Array {
    (0..vertices.len()).map(|i| Dynamic::from(int_array(&[vertices[i], vertices[(i + 1) % vertices.len()]]))).collect()
}

/// A defect as a script map: `kind`, `elements`, `position`, `component`, and the key that
/// names its elements by what they are (`vertices`, `faces` or `edges`), `genus` for a
/// component, the loop's `edges` for a boundary and a handle.
fn defect_map(d: Defect) -> Map {
    let mut m = Map::new();
    m.insert("kind".into(), Dynamic::from(d.kind.name().to_string()));
    m.insert("position".into(), Dynamic::from(d.position));
    m.insert("component".into(), Dynamic::from(d.component as INT));
    let elements = int_array(&d.elements);
    match d.kind {
        DefectKind::Boundary | DefectKind::Handle => {
            m.insert("vertices".into(), Dynamic::from(elements.clone()));
            m.insert("edges".into(), Dynamic::from(loop_edges(&d.elements)));
        }
        DefectKind::NonManifoldVertex => {
            m.insert("vertices".into(), Dynamic::from(elements.clone()));
        }
        DefectKind::NonManifoldEdge => {
            let pairs: Array = d.elements.chunks(2).map(|p| Dynamic::from(int_array(p))).collect();
            m.insert("edges".into(), Dynamic::from(pairs));
        }
        DefectKind::SelfIntersection | DefectKind::DegenerateFace | DefectKind::Component => {
            m.insert("faces".into(), Dynamic::from(elements.clone()));
        }
    }
    if let Some(g) = d.genus {
        m.insert("genus".into(), Dynamic::from(g as INT));
    }
    m.insert("elements".into(), Dynamic::from(elements));
    m
}

#[export_module]
pub mod diagnose_api {
    use super::*;

    /// Each connected piece of the mesh (faces joined across edges) as a mesh of its own, in
    /// the order of their first faces. Positions are copied exactly; vertex colours, creases,
    /// corners and face parts go with them; vertices are renumbered in order of first use.
    ///
    /// Topic: repair
    ///
    /// ```rhai
    /// let m = combine([cube(1), torus(3, 1, 16, 8).translate([10, 0, 0])]);
    /// let parts = m.components();
    /// assert_eq(parts.len(), 2);
    /// assert_eq(parts[0].face_count, 6);
    /// assert_eq(parts[1].genus(), 1);
    /// assert_near(parts[0].volume(), 1.0, 1e-12);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn components(m: &mut SharedMesh) -> ScriptResult<Array> {
        let parts = kernel("components", diagnose::components(&m.0))?;
        Ok(parts.into_iter().map(|p| Dynamic::from(SharedMesh::new(p))).collect())
    }

    /// Each open boundary of the mesh as the ids of its vertices in order (walking the
    /// boundary against the faces beside it). A closed mesh has none.
    ///
    /// Topic: repair
    ///
    /// ```rhai
    /// assert_eq(cube(1).boundary_loops(), []);
    /// let square = mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]]);
    /// let loops = square.boundary_loops();
    /// assert_eq(loops.len(), 1);
    /// assert_eq(loops[0].len(), 4);
    /// ```
    #[rhai_fn(pure)]
    pub fn boundary_loops(m: &mut SharedMesh) -> Array {
        diagnose::boundary_loops(&m.0).iter().map(|l| Dynamic::from(int_array(l))).collect()
    }

    /// The pairs of faces `[f, g]` (f < g, sorted) that cross or touch each other away from
    /// the corners and edges they share — decided exactly (orientation predicates in exact
    /// arithmetic, Shewchuk's), over a bounding-volume hierarchy of the faces' triangles:
    /// O(n log n + k) for n triangles and k pairs. Faces of zero area are left out (`defects`
    /// lists them). A valid solid has none.
    ///
    /// Topic: repair
    ///
    /// ```rhai
    /// assert_eq(icosphere(1, 2).self_intersections(), []);
    /// let crossed = combine([cube(2), cube(2).translate([1, 1, 1])]);
    /// let pairs = crossed.self_intersections();
    /// assert(pairs.len() > 0, "two overlapping cubes cross");
    /// assert(pairs.all(|p| p[0] < 6 && p[1] >= 6), "each pair is a face of each cube");
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn self_intersections(m: &mut SharedMesh) -> ScriptResult<Array> {
        let _task = crate::progress::start("self_intersections", None);
        let pairs = kernel("self_intersections", diagnose::self_intersections(&m.0))?;
        Ok(pairs.iter().map(|p| Dynamic::from(int_array(p))).collect())
    }

    /// Everything wrong with the mesh, one map per defect: `kind`, the ids it names
    /// (`elements`, and by what they are: `vertices`, `faces` or `edges` as `[a, b]` pairs),
    /// a `position` to show it at and its `component` (an index into `components()`).
    /// Kinds, in this order:
    /// - `"component"` (each piece, when there is more than one or one is open or has
    ///   handles): its `faces` and `genus`;
    /// - `"boundary"`: an open boundary loop, its `vertices` and `edges` in order;
    /// - `"non_manifold_vertex"`: vertices at one position that are not one vertex (where
    ///   sheets touched in the file and loading split them);
    /// - `"non_manifold_edge"`: edges at one position (faces beyond two met there), `edges`;
    /// - `"degenerate_face"`: a face of zero area or with two corners at one place;
    /// - `"self_intersection"`: two faces that cross or touch, at a point of their crossing;
    /// - `"handle"`: a short loop of edges around a handle (`vertices`, `edges`); cutting along
    ///   every handle loop leaves genus 0 (a greedy system of loops, Erickson and Whittlesey
    ///   2005, from a shortest-path tree and a maximum spanning cotree).
    ///
    /// A valid solid of genus 0 has none. Cost: linear, plus `self_intersections`' search and
    /// O(g·n) for g handles (at most 64 loops).
    ///
    /// Topic: repair
    ///
    /// ```rhai
    /// assert_eq(cube(1).defects(), []);
    /// let d = torus(3, 1, 24, 12).defects();
    /// let handles = d.filter(|x| x.kind == "handle");
    /// assert_eq(handles.len(), 1);
    /// assert_eq(d.filter(|x| x.kind == "component")[0].genus, 1);
    /// let e = handles[0].edges;
    /// assert_eq(e.len(), handles[0].vertices.len());
    /// assert_eq(e[0][1], e[1][0]);
    /// let open = mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]]).defects();
    /// assert_eq(open.map(|x| x.kind), ["component", "boundary"]);
    /// assert_eq(open[1].vertices.len(), 3);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn defects(m: &mut SharedMesh) -> ScriptResult<Array> {
        let _task = crate::progress::start("defects", None);
        let found = kernel("defects", diagnose::defects(&m.0))?;
        Ok(found.into_iter().map(|d| Dynamic::from(defect_map(d))).collect())
    }
}
