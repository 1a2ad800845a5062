//! Subdivision surfaces on `Mesh`: Catmull–Clark and Loop, limit positions and normals, and the
//! Catmull–Clark limit surface at any (face, u, v) (kernel `subdiv`). Creases are tagged with
//! `crease` / `crease_all` and corners with `mesh(…, #{corners})` (see `api/mesh.rs`).

use std::cell::RefCell;
use std::rc::Rc;
use std::sync::{Arc, Weak};

use blocksmith_kernel::subdiv::{LimitEvaluator, LimitSample};
use blocksmith_kernel::{Mesh, Vec3};
use rhai::plugin::*;
use rhai::{exported_module, Array, Engine, Map, INT};

use super::mesh::SharedMesh;
use crate::convert::{fail, kernel, number, type_name, Integer, Number, ScriptResult};

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
}
