//! CSG (API.md §CSG; seed 000 §2.4.2; kernel `csg`): `union`, `subtract`, `intersect`, `a + b`,
//! `a - b` of block models and meshes — the result is a closed manifold `Mesh` whose faces know
//! their source (`m.sources()`, `m.face_source(f)`, `m.inputs()`) and which keeps the control
//! meshes of its mesh operands (subdivision inputs) for the studio to draw over it.
//!
//! Block-model operands are tessellated first with the call's `tolerance` option (default: the
//! model's default, 0.001 × its diagonal), so adaptive tessellation comes through. A `Mesh`
//! operand that is itself a boolean result keeps its sources; its inputs are renumbered after
//! those to its left.

use blocksmith_kernel::blocks::{MeshOptions, SubFaceRef};
use blocksmith_kernel::csg::Csg;
use blocksmith_kernel::mesh::FaceSource;
use rhai::plugin::*;
use rhai::{exported_module, Array, Engine, FuncRegistration, Map, INT};

use super::blocks::BlockModel;
use super::mesh::SharedMesh;
use crate::convert::{error, kernel, type_name, Options, ScriptResult, Solid};

/// Registers the boolean functions and operators and the provenance readers on `engine`.
pub fn register(engine: &mut Engine) {
    engine.register_global_module(exported_module!(csg_api).into());
    macro_rules! operators {
        ($($a:ty, $ta:literal, $b:ty, $tb:literal);*) => {$(
            FuncRegistration::new("+")
                .with_params_info([concat!("a: ", $ta), concat!("b: ", $tb), "SharedMesh"])
                .with_comments([UNION_DOC])
                .register_into_engine(engine, |a: $a, b: $b| -> ScriptResult<SharedMesh> {
                    boolean("+", Dynamic::from(a), Dynamic::from(b), Map::new())
                });
            FuncRegistration::new("-")
                .with_params_info([concat!("a: ", $ta), concat!("b: ", $tb), "SharedMesh"])
                .with_comments([SUBTRACT_DOC])
                .register_into_engine(engine, |a: $a, b: $b| -> ScriptResult<SharedMesh> {
                    boolean("-", Dynamic::from(a), Dynamic::from(b), Map::new())
                });
        )*};
    }
    operators!(
        SharedMesh, "SharedMesh", SharedMesh, "SharedMesh";
        SharedMesh, "SharedMesh", BlockModel, "BlockModel";
        BlockModel, "BlockModel", SharedMesh, "SharedMesh";
        BlockModel, "BlockModel", BlockModel, "BlockModel"
    );
}

/// The doc comment of the `+` operator on meshes and block models.
const UNION_DOC: &str = r#"/// `a + b`: the union of two solids, as `union(a, b)` (seed 000 §2.4.2): a closed manifold
/// `Mesh` whose faces remember which operand they came from (`m.sources()`). A `BlockModel`
/// operand is tessellated first at its default tolerance; call `union(a, b, #{ tolerance })`
/// for another.
///
/// ```rhai
/// let m = cube(2) + cube(2).translate([1, 1, 1]);
/// assert(m.is_closed(), "closed");
/// assert_near(m.volume(), 8.0 + 8.0 - 1.0, 1e-9);
/// ```"#;

/// The doc comment of the `-` operator on meshes and block models.
const SUBTRACT_DOC: &str = r#"/// `a - b`: `a` with `b` cut away, as `subtract(a, b)` (seed 000 §2.4.2): a closed manifold
/// `Mesh` whose faces remember which operand they came from (`m.sources()`). A `BlockModel`
/// operand is tessellated first at its default tolerance; call `subtract(a, b, #{ tolerance })`
/// for another.
///
/// ```rhai
/// let m = cube(2) - cube(2).translate([1, 1, 1]);
/// assert(m.is_closed(), "closed");
/// assert_near(m.volume(), 8.0 - 1.0, 1e-9);
/// ```"#;

/// One operand as a CSG leaf, or an error naming the function and the side.
fn operand(func: &str, side: &str, v: Dynamic, options: MeshOptions) -> ScriptResult<Csg> {
    if let Some(m) = v.clone().try_cast::<SharedMesh>() {
        // The leaf shares the mesh: no copy of a large operand before the boolean starts.
        return Ok(Csg::Mesh(std::sync::Arc::clone(&m.0)));
    }
    if let Some(b) = v.clone().try_cast::<BlockModel>() {
        return Ok(Csg::blocks(b.kernel_model().clone(), options));
    }
    let t = crate::catalogue::script_type(v.type_name());
    let hint = solid_hint(&t);
    Err(error(func, format!("the {side} operand must be a BlockModel or a Mesh, got {}{hint}", type_name(&v))))
}

/// How to get a solid (a `Mesh` or a `BlockModel`) from a value of script type `t`, for CSG's
/// messages: `: get a Mesh with `.to_mesh()``; empty when there is no way. Read from the
/// declarations of the script API ([`super::registry`]), so no engine is needed to phrase it.
#[must_use]
pub fn solid_hint(t: &str) -> String {
    use super::registry::REGISTRY;
    use crate::catalogue::script_type;
    let of_type = |rust: &str| script_type(rust) == t;
    // Its methods returning a Mesh, fewest arguments then shortest names first.
    let mut ways: Vec<_> =
        REGISTRY.iter().filter(|d| d.receiver.is_some_and(of_type) && script_type(d.returns) == "Mesh").collect();
    ways.sort_by_key(|d| (d.arity, d.name.len()));
    if let Some(d) = ways.first() {
        return format!(": get a Mesh with `.{}({})`", d.name, if d.arity > 1 { "…" } else { "" });
    }
    // A value that goes into a model (a Block) becomes a solid there.
    let mut into: Vec<&str> = REGISTRY
        .iter()
        .filter(|d| d.receiver == Some("BlockModel") && d.params.get(1).is_some_and(|p| of_type(p)))
        .map(|d| d.name)
        .collect();
    into.sort_unstable();
    match into.first() {
        Some(name) => format!(": put it in a model, `let model = blocks(); model.{name}(…);`, and use the model"),
        None => String::new(),
    }
}

fn boolean(func: &'static str, a: Dynamic, b: Dynamic, options: Map) -> ScriptResult<SharedMesh> {
    let opts = Options::new(func, options, &["tolerance"])?;
    let mut mesh_options = MeshOptions::DEFAULT;
    if opts.has("tolerance") {
        let t = opts.number("tolerance", 0.0)?;
        if !(t.is_finite() && t > 0.0) {
            return Err(error(func, format!("option `tolerance` must be a positive number, got {t}")));
        }
        mesh_options = mesh_options.with_tolerance(t);
    }
    // The mesh operands' control meshes stay with the result, for the studio's overlay.
    let meshes: Vec<SharedMesh> =
        [&a, &b].into_iter().filter_map(|v| v.read_lock::<SharedMesh>().map(|m| SharedMesh::clone(&m))).collect();
    let control = SharedMesh::controls(&meshes);
    let (a, b) = (operand(func, "left", a, mesh_options)?, operand(func, "right", b, mesh_options)?);
    let tree = match func {
        "union" | "+" => a.union(b),
        "subtract" | "-" => a.difference(b),
        _ => a.intersection(b),
    };
    // A boolean's length is not known ahead: a spinner, where the host shows progress.
    let task = crate::progress::start(&format!("{func}: evaluating the boolean"), None);
    let result = tree.evaluate();
    drop(task);
    kernel(func, result).map(|r| SharedMesh(std::sync::Arc::new(r), control))
}

fn source_map(s: &FaceSource) -> Map {
    let mut m = Map::new();
    match *s {
        FaceSource::Block { leaf, sub_face } => {
            m.insert("input".into(), Dynamic::from(INT::from(leaf)));
            m.insert("kind".into(), Dynamic::from("block".to_string()));
            m.insert("block".into(), Dynamic::from(INT::from(sub_face.block)));
            // The face by its name (`+z`); a face index no block has (never made by the kernel)
            // by its number.
            let face =
                SubFaceRef::try_from(sub_face).map_or_else(|_| sub_face.face.to_string(), |r| r.face.name().into());
            m.insert("face".into(), Dynamic::from(face));
            m.insert("sub".into(), Dynamic::from(INT::from(sub_face.sub)));
        }
        FaceSource::Mesh { leaf, face } => {
            m.insert("input".into(), Dynamic::from(INT::from(leaf)));
            m.insert("kind".into(), Dynamic::from("mesh".to_string()));
            m.insert("face".into(), Dynamic::from(INT::from(face)));
        }
        FaceSource::Unknown => {
            m.insert("input".into(), Dynamic::from(-1 as INT));
            m.insert("kind".into(), Dynamic::from("unknown".to_string()));
        }
    }
    m
}

#[export_module]
pub mod csg_api {
    /// The union `a ∪ b` of two solids, each a `BlockModel` (tessellated first) or a closed
    /// `Mesh` (an earlier result too): a closed manifold triangle `Mesh` whose faces know their
    /// source (see `sources`). Same as `a + b`. The result's edges keep the crease tags of the
    /// input edges they lie on (a block's sharp edges among them). Errors name the side: an
    /// operand that is open, empty, touches itself or is not a solid type.
    ///
    /// Topic: booleans
    ///
    /// ```rhai
    /// let u = union(box([0, 0, 0], [1, 1, 1]), box([0.5, 0, 0], [1.5, 1, 1]));
    /// assert_near(u.volume(), 1.5, 1e-12);
    /// assert(u.is_closed() && u.is_manifold(), "a closed manifold mesh");
    /// assert_eq((box([0, 0, 0], [1, 1, 1]) + box([1, 0, 0], [2, 1, 1])).volume(), 2.0);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn union(a: Solid, b: Solid) -> ScriptResult<SharedMesh> {
        boolean("union", a, b, Map::new())
    }

    /// `union(a, b)` with options: `tolerance`, the chord tolerance for tessellating
    /// `BlockModel` operands (default 0.001 × each model's diagonal).
    ///
    /// Topic: booleans
    ///
    /// ```rhai
    /// let m = blocks();
    /// m.add(block([-1, -1, -1], [1, 1, 1]).subdivide("+z", 2, 2));
    /// let fine = union(m, box([0, 0, 0.5], [0.2, 0.2, 2]), #{ tolerance: 0.0005 });
    /// let coarse = union(m, box([0, 0, 0.5], [0.2, 0.2, 2]), #{ tolerance: 0.01 });
    /// assert(fine.face_count > coarse.face_count, "finer tessellation");
    /// ```
    #[rhai_fn(name = "union", return_raw)]
    pub fn union_with(a: Solid, b: Solid, options: Map) -> ScriptResult<SharedMesh> {
        boolean("union", a, b, options)
    }

    /// The difference `a − b`: `a` with the solid `b` carved out (same as `a - b`); operands and
    /// result as for `union`.
    ///
    /// Topic: booleans
    ///
    /// ```rhai
    /// let cube = box([0, 0, 0], [1, 1, 1]);
    /// let hole = subtract(cube, box([0.25, 0.25, -1], [0.75, 0.75, 2]));
    /// assert_eq(hole.genus(), 1);
    /// assert_near(hole.volume(), 0.75, 1e-12);
    /// assert_near((cube - box([0.5, 0.5, 0.5], [2, 2, 2])).volume(), 0.875, 1e-12);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn subtract(a: Solid, b: Solid) -> ScriptResult<SharedMesh> {
        boolean("subtract", a, b, Map::new())
    }

    /// `subtract(a, b)` with options (`tolerance`, as for `union`).
    ///
    /// Topic: booleans
    ///
    /// ```rhai
    /// let m = blocks();
    /// m.add(block([-1, -1, -1], [1, 1, 1]));
    /// let dent = subtract(m, icosphere(0.3, 2).translate(vec3(0, 0, 1)), #{ tolerance: 0.005 });
    /// assert(dent.volume() < m.mesh(#{ tolerance: 0.005 }).volume(), "a dent");
    /// ```
    #[rhai_fn(name = "subtract", return_raw)]
    pub fn subtract_with(a: Solid, b: Solid, options: Map) -> ScriptResult<SharedMesh> {
        boolean("subtract", a, b, options)
    }

    /// The intersection `a ∩ b`; operands and result as for `union`. Solids that do not overlap
    /// (or only touch, over a whole face or part of one) give a mesh without faces: booleans
    /// are regularised, no zero-thickness sheet is left where solids meet.
    ///
    /// Topic: booleans
    ///
    /// ```rhai
    /// let i = intersect(box([0, 0, 0], [1, 1, 1]), box([0.5, 0.5, 0.5], [2, 2, 2]));
    /// assert_near(i.volume(), 0.125, 1e-12);
    /// assert_eq(intersect(box([0, 0, 0], [1, 1, 1]), box([1, 0, 0], [2, 1, 1])).face_count, 0);
    /// assert_eq(intersect(box([0, 0, 0], [1, 1, 1]), box([0.25, 1, 0.25], [0.75, 2, 0.75])).face_count, 0);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn intersect(a: Solid, b: Solid) -> ScriptResult<SharedMesh> {
        boolean("intersect", a, b, Map::new())
    }

    /// `intersect(a, b)` with options (`tolerance`, as for `union`).
    ///
    /// Topic: booleans
    ///
    /// ```rhai
    /// let m = blocks();
    /// m.add(block([-1, -1, -1], [1, 1, 1]));
    /// let half = intersect(m, box([0, -2, -2], [2, 2, 2]), #{ tolerance: 0.002 });
    /// assert_near(half.volume(), m.mesh(#{ tolerance: 0.002 }).volume() / 2, 1e-3);
    /// ```
    #[rhai_fn(name = "intersect", return_raw)]
    pub fn intersect_with(a: Solid, b: Solid, options: Map) -> ScriptResult<SharedMesh> {
        boolean("intersect", a, b, options)
    }

    /// The distinct sources of the faces of a boolean result, in order, each a map with the
    /// count of its faces: `#{input, kind: "block", block, face, sub, faces}` for a block
    /// sub-face or `#{input, kind: "mesh", face, faces}` for a face of an input mesh. `input`
    /// numbers the operands left to right from 0 (`-1`, kind `"unknown"`, where `combine`
    /// joined a mesh without sources). Empty for a mesh that is no boolean result.
    ///
    /// ```rhai
    /// let d = box([0, 0, 0], [1, 1, 1]) - box([0.5, 0.5, 0.5], [2, 2, 2]);
    /// let s = d.sources();
    /// assert_eq(s.len(), 9);   // three faces of the cutter show, and six of the box
    /// assert_eq(s.filter(|x| x.input == 1).len(), 3);
    /// assert_eq(box([0, 0, 0], [1, 1, 1]).sources(), []);
    /// ```
    #[rhai_fn(pure)]
    pub fn sources(m: &mut SharedMesh) -> Array {
        let Some(fs) = m.0.face_sources() else { return Array::new() };
        let mut counts = std::collections::BTreeMap::new();
        for s in fs {
            *counts.entry(*s).or_insert(0 as INT) += 1;
        }
        counts
            .into_iter()
            .map(|(s, n)| {
                let mut map = source_map(&s);
                map.insert("faces".into(), Dynamic::from(n));
                Dynamic::from(map)
            })
            .collect()
    }

    /// The source of face `f` (a map as in `sources`, without `faces`), or an error when the
    /// face does not exist or the mesh is no boolean result.
    ///
    /// ```rhai
    /// let d = box([0, 0, 0], [1, 1, 1]) - box([0.5, 0.5, 0.5], [2, 2, 2]);
    /// let s = d.face_source(0);
    /// assert(s.input == 0 || s.input == 1, "one of the two operands");
    /// assert_eq(s.kind, "mesh");
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn face_source(m: &mut SharedMesh, f: INT) -> ScriptResult<Map> {
        let f = kernel("face_source", m.0.check_face(f))?;
        let fs = m
            .0
            .face_sources()
            .ok_or_else(|| error("face_source", "this mesh has no face sources (only boolean results have them)"))?;
        Ok(source_map(&fs[f as usize]))
    }

    /// The distinct operand numbers (`input`) the faces of a boolean result come from, sorted —
    /// e.g. to count the pits a subtraction left.
    ///
    /// ```rhai
    /// let cube = box([-1, -1, -1], [1, 1, 1]);
    /// let pits = union(icosphere(0.2, 2).translate(vec3(0, 0, 1)), icosphere(0.2, 2).translate(vec3(1, 0, 0)));
    /// assert_eq((cube - pits).inputs(), [0, 1, 2]);
    /// ```
    #[rhai_fn(pure)]
    pub fn inputs(m: &mut SharedMesh) -> Array {
        let Some(fs) = m.0.face_sources() else { return Array::new() };
        let set: std::collections::BTreeSet<u32> = fs.iter().filter_map(FaceSource::leaf).collect();
        set.into_iter().map(|l| Dynamic::from(INT::from(l))).collect()
    }
}
