//! Subdivision surfaces on `Mesh`: Catmull–Clark and Loop, limit positions and normals, the
//! Catmull–Clark limit surface at any (face, u, v) (kernel `subdiv`), and the subdivision tags
//! of a mesh: creases (`crease`, `crease_all`), corners and the scheme's options
//! (`subdiv_options`); `mesh(…, #{creases, corners})` sets them as a mesh is made.

use std::cell::RefCell;
use std::rc::Rc;
use std::sync::{Arc, Weak};

use blocksmith_kernel::subdiv::{LimitEvaluator, LimitSample, SHARPNESS_INFINITE};
use blocksmith_kernel::{Mesh, Vec3};
use rhai::plugin::*;
use rhai::{exported_module, Array, Engine, Map, INT};

use super::mesh::SharedMesh;
use crate::convert::{fail, id_pairs, ids, kernel, number, type_name, Integer, Number, Options, ScriptResult};

/// Registers every subdivision function on `engine`.
pub fn register(engine: &mut Engine) {
    engine.register_global_module(exported_module!(subdiv_api).into());
}

/// The largest level count accepted before the kernel's size guard (50M faces) is even asked.
const MAX_LEVELS: INT = 16;

fn levels(func: &str, n: INT) -> ScriptResult<u32> {
    if !(0..=MAX_LEVELS).contains(&n) {
        return fail(func, format!("argument `levels` must be between 0 and {MAX_LEVELS}, got {n}"));
    }
    Ok(n as u32)
}

thread_local! {
    /// The evaluator of the last mesh `limit_eval` saw: scripts that evaluate one mesh at many
    /// points build it once. A mesh changed in place gets a new allocation (copy on write drops
    /// the weak link), so a stale evaluator is never used.
    static EVALUATOR: RefCell<Option<(Weak<Mesh>, Rc<LimitEvaluator>)>> = const { RefCell::new(None) };
}

fn evaluator(m: &SharedMesh) -> ScriptResult<Rc<LimitEvaluator>> {
    let cached = EVALUATOR.with(|c| {
        c.borrow().as_ref().and_then(|(w, ev)| w.upgrade().filter(|mm| Arc::ptr_eq(mm, &m.0)).map(|_| ev.clone()))
    });
    if let Some(ev) = cached {
        return Ok(ev);
    }
    let ev = Rc::new(kernel("limit_eval", LimitEvaluator::new(&m.0))?);
    EVALUATOR.with(|c| *c.borrow_mut() = Some((Arc::downgrade(&m.0), ev.clone())));
    Ok(ev)
}

fn sample_map(s: LimitSample) -> Map {
    let mut map = Map::new();
    map.insert("position".into(), Dynamic::from(s.position));
    map.insert("du".into(), Dynamic::from(s.du));
    map.insert("dv".into(), Dynamic::from(s.dv));
    map.insert("normal".into(), Dynamic::from(s.normal));
    map
}

fn eval_one(ev: &LimitEvaluator, face: &Dynamic, u: &Dynamic, v: &Dynamic, at: &str) -> ScriptResult<Map> {
    let f = face
        .as_int()
        .or_else(|_| fail("limit_eval", format!("argument `{at}face` must be an integer, got {}", type_name(face))))?;
    if f < 0 || f >= ev.face_count() as INT {
        return fail(
            "limit_eval",
            format!("argument `{at}face`: face {f} does not exist (the mesh has {})", ev.face_count()),
        );
    }
    let (u, v) = (number("limit_eval", &format!("{at}u"), u)?, number("limit_eval", &format!("{at}v"), v)?);
    kernel("limit_eval", ev.eval(f as u32, u, v)).map(sample_map)
}

fn vectors(v: Vec<Vec3>) -> Array {
    v.into_iter().map(Dynamic::from).collect()
}

/// A kernel sharpness as scripts see it: infinity becomes [`SHARPNESS_INFINITE`] (10), which
/// subdivision reads back as infinite, since Rhai's comparisons of infinity are all false.
pub(crate) fn script_sharpness(s: f64) -> f64 {
    s.min(SHARPNESS_INFINITE)
}

#[export_module]
pub mod subdiv_api {
    use super::*;

    /// The mesh after `levels` Catmull–Clark steps: any polygons in, quads out (an n-gon makes n
    /// quads). Crease-tagged and boundary edges stay sharp, tags survive (each sharp edge becomes
    /// two), corners stay put. The input's vertex ids are kept, then edge points, then face points.
    ///
    /// ```rhai
    /// let m = cube(2).catmull_clark(1);
    /// assert_eq(m.vertex_count, 26);
    /// assert_eq(m.face_count, 24);
    /// assert_near(m.positions()[7], vec3(5, 5, 5) / 9.0, 1e-15);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn catmull_clark(m: &mut SharedMesh, levels: INT) -> ScriptResult<SharedMesh> {
        let l = super::levels("catmull_clark", levels)?;
        kernel("catmull_clark", m.0.catmull_clark(l)).map(|r| SharedMesh::with_control(r, m.control_for_derived()))
    }

    /// The mesh after `levels` Loop steps with Loop's original weights (triangles only). Crease
    /// and boundary rules as `catmull_clark`; vertex ids kept, then one edge point per edge.
    ///
    /// ```rhai
    /// let m = icosphere(1, 0).loop_subdivide(2);
    /// assert_eq(m.face_count, 320);
    /// assert_eq(m.vertex_count, 162);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn loop_subdivide(m: &mut SharedMesh, levels: INT) -> ScriptResult<SharedMesh> {
        let l = super::levels("loop_subdivide", levels)?;
        kernel("loop_subdivide", m.0.loop_subdivide(l)).map(|r| SharedMesh::with_control(r, m.control_for_derived()))
    }

    /// A copy with every vertex moved to its Catmull–Clark limit position (vertex ids, creases
    /// and corners kept).
    ///
    /// ```rhai
    /// let l = cube(2).catmull_clark_limit();
    /// assert_near(l.positions()[7], [0.5, 0.5, 0.5], 1e-15);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn catmull_clark_limit(m: &mut SharedMesh) -> ScriptResult<SharedMesh> {
        kernel("catmull_clark_limit", m.0.catmull_clark_limit())
            .map(|r| SharedMesh::with_control(r, m.control_for_derived()))
    }

    /// A copy with every vertex moved to its Loop limit position (triangles only; vertex ids,
    /// creases and corners kept).
    ///
    /// ```rhai
    /// let l = icosphere(1, 1).loop_limit();
    /// assert_eq(l.vertex_count, 42);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn loop_limit(m: &mut SharedMesh) -> ScriptResult<SharedMesh> {
        kernel("loop_limit", m.0.loop_limit()).map(|r| SharedMesh::with_control(r, m.control_for_derived()))
    }

    /// The unit Catmull–Clark limit normal of every vertex (indexed by vertex id). At creases
    /// and corners, the normalised sum of the normals of the sectors between sharp edges.
    ///
    /// ```rhai
    /// let n = cube(2).catmull_clark_limit_normals();
    /// assert_near(n[7], vec3(1, 1, 1) / sqrt(3.0), 1e-14);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn catmull_clark_limit_normals(m: &mut SharedMesh) -> ScriptResult<Array> {
        kernel("catmull_clark_limit_normals", m.0.catmull_clark_limit_normals()).map(vectors)
    }

    /// The unit Loop limit normal of every vertex (triangles only).
    ///
    /// ```rhai
    /// let n = icosphere(1, 1).loop_limit_normals();
    /// assert_near(n[0], icosphere(1, 1).positions()[0], 1e-12);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn loop_limit_normals(m: &mut SharedMesh) -> ScriptResult<Array> {
        kernel("loop_limit_normals", m.0.loop_limit_normals()).map(vectors)
    }

    /// The Catmull–Clark limit surface of an all-quad mesh at (u, v) in [0, 1]² of face `face`:
    /// `#{position, du, dv, normal}`. (0, 0) is the face's first vertex, u runs toward its second
    /// vertex, v toward its last. Exact everywhere (bicubic patches, adaptive refinement near
    /// extraordinary vertices and creases); the evaluator is built once per mesh and reused.
    ///
    /// ```rhai
    /// let s = cube(2).limit_eval(5, 0.5, 0.5);
    /// assert_near(s.position, [0, 0, 68.0 / 81.0], 1e-14);
    /// assert_near(s.normal, [0, 0, 1], 1e-14);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn limit_eval(m: &mut SharedMesh, face: Integer, u: Number, v: Number) -> ScriptResult<Map> {
        let ev = evaluator(m)?;
        eval_one(&ev, &face, &u, &v, "")
    }

    /// `limit_eval` at many points at once: `samples` is an array of `[face, u, v]`; returns
    /// one `#{position, du, dv, normal}` per sample.
    ///
    /// ```rhai
    /// let s = cube(2).limit_eval([[0, 0, 0], [5, 0.5, 0.5]]);
    /// assert_eq(s.len(), 2);
    /// assert_near(s[0].position, [-0.5, -0.5, -0.5], 1e-14);
    /// ```
    #[rhai_fn(pure, return_raw, name = "limit_eval")]
    pub fn limit_eval_many(m: &mut SharedMesh, samples: Array) -> ScriptResult<Array> {
        let ev = evaluator(m)?;
        samples
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let a = s.clone().try_cast::<Array>().filter(|a| a.len() == 3).ok_or_else(|| {
                    crate::convert::error(
                        "limit_eval",
                        format!("argument `samples[{i}]` must be [face, u, v], got {}", type_name(s)),
                    )
                })?;
                eval_one(&ev, &a[0], &a[1], &a[2], &format!("samples[{i}].")).map(Dynamic::from_map)
            })
            .collect()
    }

    /// Tags edges as infinitely sharp creases for subdivision; `edges` is an array of `[a, b]`
    /// vertex-id pairs. All or nothing: a pair that is not an edge is an error and no tag is set.
    ///
    /// ```rhai
    /// let m = cube(2);
    /// m.crease([[0, 1], [1, 3]]);
    /// assert_eq(m.crease_count(), 2);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn crease(m: &mut SharedMesh, edges: Array) -> ScriptResult<()> {
        let pairs = id_pairs("crease", "edges", &edges)?;
        if let Some((i, [a, b])) = pairs.iter().enumerate().find(|(_, &[a, b])| m.0.find_halfedge(a, b).is_none()) {
            return fail("crease", format!("argument `edges[{i}]`: vertices {a} and {b} are not joined by an edge"));
        }
        let mut copy = (*m.0).clone();
        kernel("crease", copy.crease_edges(&pairs))?;
        m.0 = Arc::new(copy);
        Ok(())
    }
    /// Sets the crease sharpness of edges for subdivision (semi-sharp creases, DeRose, Kass &
    /// Truong 1998 §3, OpenSubdiv's rules): `edges` is an array of `[a, b]` vertex-id pairs,
    /// `sharpness` a number from 0 (smooth again) up; an edge of sharpness s follows the sharp rules
    /// for ⌊s⌋ levels, a blend by the fraction in the next, the smooth rules after; 10 and more is
    /// infinitely sharp, as `m.crease(edges)`. All or nothing.
    ///
    /// ```rhai
    /// let m = cube(2);
    /// m.crease([[0, 1]], 1.5);
    /// assert_eq(m.crease_sharpness(0, 1), 1.5);
    /// assert_eq(m.catmull_clark(1).crease_count(), 2);
    /// ```
    #[rhai_fn(name = "crease", return_raw)]
    pub fn crease_with_sharpness(m: &mut SharedMesh, edges: Array, sharpness: Number) -> ScriptResult<()> {
        let s = number("crease", "sharpness", &sharpness)?;
        if s < 0.0 {
            return fail("crease", format!("argument `sharpness` must be 0 or more, got {s}"));
        }
        let pairs = id_pairs("crease", "edges", &edges)?;
        if let Some((i, [a, b])) = pairs.iter().enumerate().find(|(_, &[a, b])| m.0.find_halfedge(a, b).is_none()) {
            return fail("crease", format!("argument `edges[{i}]`: vertices {a} and {b} are not joined by an edge"));
        }
        let mut copy = (*m.0).clone();
        kernel("crease", copy.crease_edges_sharpness(&pairs, s))?;
        m.0 = Arc::new(copy);
        Ok(())
    }
    /// The crease sharpness of the edge joining vertices `a` and `b`: 0 for a smooth edge, the
    /// semi-sharp value as set, and 10 for an infinitely sharp one (OpenSubdiv's
    /// `SHARPNESS_INFINITE`: subdivision treats every sharpness from 10 up as infinite, so
    /// `s >= 10` tests for it; Rhai cannot compare infinity, `inf > 10.0` is false).
    ///
    /// ```rhai
    /// let m = cube(2);
    /// assert_eq(m.crease_sharpness(0, 1), 0.0);
    /// m.crease([[0, 1]], 3);
    /// assert_eq(m.crease_sharpness(0, 1), 3.0);
    /// m.crease([[0, 1]]);
    /// assert(m.crease_sharpness(0, 1) >= 10);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn crease_sharpness(m: &mut SharedMesh, a: INT, b: INT) -> ScriptResult<f64> {
        let (ua, ub) = (u32::try_from(a).ok(), u32::try_from(b).ok());
        match ua.zip(ub).and_then(|(a, b)| m.0.find_halfedge(a, b)) {
            Some(h) => Ok(script_sharpness(m.0.edge_sharpness(h))),
            None => fail("crease_sharpness", format!("vertices {a} and {b} are not joined by an edge")),
        }
    }
    /// The corner sharpness of vertex `v`: 0 for none, the semi-sharp value as set, and 10 for
    /// an infinitely sharp corner (as `crease_sharpness`: every value from 10 up is infinite).
    ///
    /// ```rhai
    /// let m = cube(2);
    /// assert_eq(m.corner_sharpness(0), 0.0);
    /// m.corner([0], 2.5);
    /// assert_eq(m.corner_sharpness(0), 2.5);
    /// m.corner([0], 1e9);
    /// assert_eq(m.corner_sharpness(0), 10.0);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn corner_sharpness(m: &mut SharedMesh, v: INT) -> ScriptResult<f64> {
        let n = m.0.vertex_count();
        match u32::try_from(v).ok().filter(|&v| (v as usize) < n) {
            Some(v) => Ok(script_sharpness(m.0.corner_sharpness(v))),
            None => fail("corner_sharpness", format!("argument `v`: vertex {v} does not exist (the mesh has {n})")),
        }
    }
    /// Gives vertices a corner sharpness for subdivision: `verts` an array of vertex ids,
    /// `sharpness` from 0 (none) up; a corner of sharpness s stays put for ⌊s⌋ levels and then
    /// smooths out; 10 and more stays put at every level.
    ///
    /// ```rhai
    /// let m = cube(2);
    /// m.corner([0, 6], 2.5);
    /// let s = m.catmull_clark(1);
    /// assert_eq(s.positions()[0], m.positions()[0]);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn corner(m: &mut SharedMesh, verts: Array, sharpness: Number) -> ScriptResult<()> {
        let s = number("corner", "sharpness", &sharpness)?;
        if s < 0.0 {
            return fail("corner", format!("argument `sharpness` must be 0 or more, got {s}"));
        }
        let vs = ids("corner", "verts", &verts)?;
        let n = m.0.vertex_count();
        if let Some((i, v)) = vs.iter().enumerate().find(|(_, &v)| v as usize >= n) {
            return fail("corner", format!("argument `verts[{i}]`: vertex {v} does not exist (the mesh has {n})"));
        }
        let copy = Arc::make_mut(&mut m.0);
        for v in vs {
            copy.set_corner_sharpness(v, s);
        }
        Ok(())
    }
    /// Sets the subdivision options OpenSubdiv names (`Sdc::Options`), used by `catmull_clark`,
    /// `loop_subdivide` and the limits: `boundary` "edge_only" (default; boundary corners move
    /// along the boundary curve), "edge_and_corner" (corners with one face stay put) or "none";
    /// `crease` "uniform" (default) or "chaikin" (sharpness decays smoothly along a crease);
    /// `triangles` "catmull_clark" (default) or "smooth" (OpenSubdiv's smooth-triangle weights).
    ///
    /// ```rhai
    /// let g = mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2, 3]]);
    /// g.subdiv_options(#{ boundary: "edge_and_corner" });
    /// assert_eq(g.catmull_clark(2).bounds().max, vec3(1, 1, 0));
    /// ```
    #[rhai_fn(return_raw)]
    pub fn subdiv_options(m: &mut SharedMesh, options: Map) -> ScriptResult<()> {
        use blocksmith_kernel::subdiv::{BoundaryInterpolation as B, CreaseMethod as C, TriangleSubdivision as T};
        let f = "subdiv_options";
        let opts = Options::new(f, options, &["boundary", "crease", "triangles"])?;
        let mut o = m.0.subdiv_options();
        o.boundary = match opts.string("boundary", "edge_only")?.as_str() {
            "edge_only" => B::EdgeOnly,
            "edge_and_corner" => B::EdgeAndCorner,
            "none" => B::None,
            x => {
                return fail(
                    f,
                    format!("option `boundary` must be \"edge_only\", \"edge_and_corner\" or \"none\", got {x:?}"),
                )
            }
        };
        o.crease = match opts.string("crease", "uniform")?.as_str() {
            "uniform" => C::Uniform,
            "chaikin" => C::Chaikin,
            x => return fail(f, format!("option `crease` must be \"uniform\" or \"chaikin\", got {x:?}")),
        };
        o.triangles = match opts.string("triangles", "catmull_clark")?.as_str() {
            "catmull_clark" => T::CatmullClark,
            "smooth" => T::Smooth,
            x => return fail(f, format!("option `triangles` must be \"catmull_clark\" or \"smooth\", got {x:?}")),
        };
        Arc::make_mut(&mut m.0).set_subdiv_options(o);
        Ok(())
    }
    /// Tags every edge as a crease.
    ///
    /// ```rhai
    /// let m = cube(2);
    /// m.crease_all();
    /// assert_eq(m.crease_count(), 12);
    /// ```
    pub fn crease_all(m: &mut SharedMesh) {
        Arc::make_mut(&mut m.0).crease_all();
    }
    /// Number of edges tagged as creases.
    ///
    /// ```rhai
    /// let m = cube(1);
    /// m.crease([[0, 1]]);
    /// assert_eq(m.crease_count(), 1);
    /// ```
    #[rhai_fn(pure)]
    pub fn crease_count(m: &mut SharedMesh) -> INT {
        m.0.crease_count() as INT
    }
    /// The crease edges as `[a, b]` vertex-id pairs.
    ///
    /// ```rhai
    /// let m = cube(1);
    /// m.crease_all();
    /// assert_eq(m.creases().len(), 12);
    /// assert_eq(m.creases()[0].len(), 2);
    /// ```
    #[rhai_fn(pure)]
    pub fn creases(m: &mut SharedMesh) -> Array {
        m.0.crease_pairs()
            .into_iter()
            .map(|[a, b]| Dynamic::from_array(vec![Dynamic::from(INT::from(a)), Dynamic::from(INT::from(b))]))
            .collect()
    }
}
