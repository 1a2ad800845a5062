//! `PolarMesh` and `Skeleton`: polar meshes, their seven operations, low-level modelling and the
//! inferred skeleton (Brazzolotto, seed 004; kernel `polar`).

use std::rc::Rc;

use blocksmith_kernel::math::fmt_num;
use blocksmith_kernel::polar::{
    FeatureOptions, Frame, LoopFrame, PolarMesh as KernelPolar, Skeleton as KernelSkeleton,
};
use blocksmith_kernel::Vec3;
use rhai::plugin::*;
use rhai::{exported_module, Array, Engine, Map, INT};

use super::mesh::SharedMesh;
use crate::convert::{
    count, factor3, fail, id_pairs, ids, kernel, number, type_name, vec3, Number, NumberOrVector, Options,
    ScriptResult, Vector,
};

/// A polar mesh as scripts hold it (script type `PolarMesh`): shared and copied on write, so
/// passing one around is cheap and no script sees another variable's mesh change. The seven
/// operations and the low-level moves change the mesh they are called on.
#[derive(Clone, Debug)]
pub struct PolarMesh(pub Rc<KernelPolar>);

impl PolarMesh {
    fn get_mut(&mut self) -> &mut KernelPolar {
        Rc::make_mut(&mut self.0)
    }
}

/// An inferred skeleton (script type `Skeleton`), read only.
#[derive(Clone, Debug)]
pub struct Skeleton(pub Rc<KernelSkeleton>);

/// Registers the `PolarMesh` and `Skeleton` types and every polar function on `engine`.
pub fn register(engine: &mut Engine) {
    engine.register_type_with_name::<PolarMesh>("PolarMesh");
    engine.register_type_with_name::<Skeleton>("Skeleton");
    engine.register_global_module(exported_module!(polar_api).into());
}

fn int(x: u32) -> Dynamic {
    Dynamic::from(INT::from(x))
}

fn id_array(xs: &[u32]) -> Array {
    xs.iter().map(|&x| int(x)).collect()
}

fn id_list(func: &str, arg: &str, v: &Dynamic) -> ScriptResult<Vec<u32>> {
    match v.clone().try_cast::<Array>() {
        Some(a) => ids(func, arg, &a),
        None => fail(func, format!("argument `{arg}` must be an array of vertex ids, got {}", type_name(v))),
    }
}

fn frame_map(f: &LoopFrame) -> Map {
    let mut m = Map::new();
    m.insert("center".into(), Dynamic::from(f.center));
    m.insert("normal".into(), Dynamic::from(f.normal));
    m.insert("tangent".into(), Dynamic::from(f.tangent));
    m.insert("bitangent".into(), Dynamic::from(f.bitangent));
    m
}

/// `center` (optional) and `frame` from an option map.
fn center_frame(opts: &Options) -> ScriptResult<(Option<Vec3>, Frame)> {
    let center = if opts.has("center") { Some(opts.vec3("center", Vec3::ZERO)?) } else { None };
    let frame = match opts.choice("frame", "global", &["global", "local"])?.as_str() {
        "local" => Frame::Local,
        _ => Frame::Global,
    };
    Ok((center, frame))
}

fn skeleton_node(func: &str, sk: &KernelSkeleton, i: INT) -> ScriptResult<u32> {
    if i < 0 || i as usize >= sk.node_count() {
        return fail(func, format!("node {i} does not exist (the skeleton has {})", sk.node_count()));
    }
    Ok(i as u32)
}

/// `move_vertices` (and its older name `move`, given as `func`).
fn move_selection(
    func: &'static str,
    pm: &mut PolarMesh,
    verts: &Array,
    offset: &Dynamic,
    options: Map,
) -> ScriptResult<()> {
    let opts = Options::new(func, options, &["frame"])?;
    let (_, frame) = center_frame(&opts)?;
    let v = ids(func, "verts", verts)?;
    let d = vec3(func, "offset", offset)?;
    kernel(func, pm.get_mut().move_vertices(&v, d, frame))
}

/// `scale_vertices` (and its older name `scale`, given as `func`).
fn scale_selection(
    func: &'static str,
    pm: &mut PolarMesh,
    verts: &Array,
    factor: &Dynamic,
    options: Map,
) -> ScriptResult<()> {
    let opts = Options::new(func, options, &["center", "frame"])?;
    let (center, frame) = center_frame(&opts)?;
    let v = ids(func, "verts", verts)?;
    let f = factor3(func, "factor", factor)?;
    if f == Vec3::ZERO && v.len() > 1 {
        return fail(
            func,
            "argument `factor` is 0, which would put all the vertices at one point (faces without area)",
        );
    }
    kernel(func, pm.get_mut().scale_vertices(&v, f, center, frame))
}

/// `rotate_vertices` (and its older name `rotate`, given as `func`).
fn rotate_selection(
    func: &'static str,
    pm: &mut PolarMesh,
    verts: &Array,
    axis: &Dynamic,
    degrees: &Dynamic,
    options: Map,
) -> ScriptResult<()> {
    let opts = Options::new(func, options, &["center", "frame"])?;
    let (center, frame) = center_frame(&opts)?;
    let v = ids(func, "verts", verts)?;
    let a = vec3(func, "axis", axis)?;
    let d = number(func, "degrees", degrees)?;
    kernel(func, pm.get_mut().rotate_vertices(&v, a, d, center, frame))
}

/// `moved` as a script value, unless a coordinate overflowed (`func`'s argument `arg` too large).
fn whole_finite(func: &str, arg: &str, moved: KernelPolar) -> ScriptResult<PolarMesh> {
    if moved.mesh().positions().iter().any(|p| !p.is_finite()) {
        return fail(func, format!("argument `{arg}` moves a vertex beyond the largest number"));
    }
    Ok(PolarMesh(Rc::new(moved)))
}

#[export_module]
pub mod polar_api {
    use super::*;

    // ---- Building ----------------------------------------------------------------------

    /// The regular octahedron of circumradius 1 as a polar mesh: poles at −z (vertex 0) and +z
    /// (vertex 5), the equator (vertices 1–4) its one loop. The thesis's starting point (§4.8).
    ///
    /// ```rhai
    /// let pm = polar_octahedron();
    /// assert_eq(pm.poles(), [0, 5]);
    /// assert_eq(pm.face_count, 8);
    /// ```
    pub fn polar_octahedron() -> PolarMesh {
        PolarMesh(Rc::new(KernelPolar::octahedron()))
    }

    /// A latitude–longitude sphere as a polar mesh: poles at −z (vertex 0) and +z (the last
    /// vertex), `rings − 1` latitude loops of `segments` edges.
    ///
    /// ```rhai
    /// let pm = polar_sphere(1, 8, 4);
    /// assert_eq(pm.loops().len(), 3);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn polar_sphere(radius: Number, segments: INT, rings: INT) -> ScriptResult<PolarMesh> {
        let r = number("polar_sphere", "radius", &radius)?;
        if r <= 0.0 {
            return fail("polar_sphere", format!("argument `radius` must be positive, got {}", fmt_num(r)));
        }
        if segments < 3 || rings < 2 {
            return fail("polar_sphere", format!("needs `segments` ≥ 3 and `rings` ≥ 2, got {segments} and {rings}"));
        }
        let s = count("polar_sphere", "segments", segments, 100_000)?;
        let n = count("polar_sphere", "rings", rings, 100_000)?;
        // Built as the kernel's UV sphere is, stopping with the run's token while it is.
        let mesh = kernel("polar_sphere", blocksmith_kernel::Mesh::try_uv_sphere(r, s, n))?;
        let north = mesh.vertex_count() as u32 - 1;
        kernel("polar_sphere", KernelPolar::from_mesh(mesh, &[0, north], &[])).map(|pm| PolarMesh(Rc::new(pm)))
    }

    /// Marks a closed mesh as a polar mesh: option `poles` (vertex ids) and `loops` (loop edges
    /// as `[a, b]` vertex pairs). Markers are completed by propagation (spokes of poles are
    /// backbones, their opposite edges loops; quads alternate), so give the poles plus one loop
    /// edge in every part no pole reaches. An invalid marking is an error naming the first broken
    /// rule.
    ///
    /// Topic: polar
    ///
    /// ```rhai
    /// let s = uv_sphere(1, 8, 4);
    /// let pm = polar_from(s, #{ poles: [0, s.vertex_count - 1] });
    /// pm.check();
    /// let t = polar_from(torus(2, 0.5, 8, 6), #{ loops: [[0, 1]] });
    /// assert_eq(t.loops().len(), 8);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn polar_from(mesh: SharedMesh, options: Map) -> ScriptResult<PolarMesh> {
        let opts = Options::new("polar_from", options, &["poles", "loops"])?;
        let poles = match opts.raw("poles") {
            Some(v) => id_list("polar_from", "poles", v)?,
            None => Vec::new(),
        };
        let loops = match opts.raw("loops") {
            Some(v) => match v.clone().try_cast::<Array>() {
                Some(a) => id_pairs("polar_from", "loops", &a)?,
                None => {
                    return fail(
                        "polar_from",
                        format!("option `loops` must be an array of [a, b] pairs, got {}", type_name(v)),
                    )
                }
            },
            None => Vec::new(),
        };
        kernel("polar_from", KernelPolar::from_mesh((*mesh.0).clone(), &poles, &loops)).map(|p| PolarMesh(Rc::new(p)))
    }

    // ---- Queries ------------------------------------------------------------------------

    /// Number of vertices.
    #[rhai_fn(get = "vertex_count", pure)]
    pub fn vertex_count(pm: &mut PolarMesh) -> INT {
        pm.0.vertex_count() as INT
    }
    /// Number of faces.
    #[rhai_fn(get = "face_count", pure)]
    pub fn face_count(pm: &mut PolarMesh) -> INT {
        pm.0.face_count() as INT
    }
    /// Number of edges.
    #[rhai_fn(get = "edge_count", pure)]
    pub fn edge_count(pm: &mut PolarMesh) -> INT {
        pm.0.mesh().edge_count() as INT
    }
    /// Number of half-edges (ids run from 0 to this − 1).
    ///
    /// ```rhai
    /// assert_eq(polar_octahedron().halfedge_count, 24);
    /// ```
    #[rhai_fn(get = "halfedge_count", pure)]
    pub fn halfedge_count(pm: &mut PolarMesh) -> INT {
        pm.0.halfedge_count() as INT
    }

    /// The number of connected parts.
    ///
    /// ```rhai
    /// let pm = polar_sphere(1, 8, 6);
    /// pm.split_feature(pm.halfedge(17, 18));
    /// assert_eq(pm.component_count(), 2);
    /// ```
    #[rhai_fn(pure)]
    pub fn component_count(pm: &mut PolarMesh) -> INT {
        pm.0.mesh().component_count() as INT
    }

    /// The poles, ascending.
    ///
    /// ```rhai
    /// assert_eq(polar_octahedron().poles().len(), 2);
    /// ```
    #[rhai_fn(pure)]
    pub fn poles(pm: &mut PolarMesh) -> Array {
        id_array(&pm.0.poles())
    }
    /// Whether vertex `v` is a pole.
    ///
    /// ```rhai
    /// assert(polar_octahedron().is_pole(0));
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn is_pole(pm: &mut PolarMesh, v: INT) -> ScriptResult<bool> {
        Ok(pm.0.is_pole(kernel("is_pole", pm.0.vertex_id(v))?))
    }
    /// Whether half-edge `h` lies on a loop (otherwise on a backbone).
    ///
    /// ```rhai
    /// let pm = polar_octahedron();
    /// assert(pm.is_loop(pm.halfedge(1, 2)), "the equator is a loop");
    /// assert(!pm.is_loop(pm.halfedge(0, 1)), "pole to equator is a backbone");
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn is_loop(pm: &mut PolarMesh, h: INT) -> ScriptResult<bool> {
        Ok(pm.0.is_loop(kernel("is_loop", pm.0.halfedge_id(h))?))
    }
    /// The Loop iterator (§3.3.1): the loop or backbone through half-edge `h`, as half-edges in
    /// walking order (a loop is closed; a backbone runs pole to pole).
    ///
    /// ```rhai
    /// let pm = polar_octahedron();
    /// let h = pm.fan(0)[0];
    /// assert_eq(pm.walk(h).len(), 2); // pole → equator → pole
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn walk(pm: &mut PolarMesh, h: INT) -> ScriptResult<Array> {
        kernel("walk", pm.0.walk(h)).map(|w| id_array(&w))
    }
    /// The Parallel iterator (§3.3.2): the edges parallel to `h` (the ones `add_refinement(h)`
    /// splits), as half-edges pointing the same way.
    ///
    /// ```rhai
    /// let pm = polar_octahedron();
    /// assert_eq(pm.parallel(pm.fan(0)[0]).len(), 4);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn parallel(pm: &mut PolarMesh, h: INT) -> ScriptResult<Array> {
        kernel("parallel", pm.0.parallel(h)).map(|w| id_array(&w))
    }
    /// The Fan iterator (§3.3.3): the half-edges leaving pole `pole`, in the order of its loop.
    ///
    /// ```rhai
    /// assert_eq(polar_octahedron().fan(5).len(), 4);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn fan(pm: &mut PolarMesh, pole: INT) -> ScriptResult<Array> {
        kernel("fan", pm.0.fan(pole)).map(|w| id_array(&w))
    }
    /// Every loop once, each an array of half-edges (a closed walk).
    ///
    /// ```rhai
    /// assert_eq(polar_octahedron().loops().len(), 1);
    /// ```
    #[rhai_fn(pure)]
    pub fn loops(pm: &mut PolarMesh) -> Array {
        pm.0.loops().iter().map(|l| Dynamic::from_array(id_array(l))).collect()
    }
    /// Every feature (§3.4) once, each an array of faces.
    ///
    /// ```rhai
    /// let pm = polar_sphere(1, 8, 4);
    /// assert_eq(pm.features().len(), 1);
    /// pm.add_feature([9, 10, 11]);
    /// assert_eq(pm.features().len(), 3);
    /// ```
    #[rhai_fn(pure)]
    pub fn features(pm: &mut PolarMesh) -> Array {
        pm.0.features().iter().map(|f| Dynamic::from_array(id_array(f))).collect()
    }
    /// The number of edges at vertex `v`.
    ///
    /// ```rhai
    /// assert_eq(polar_octahedron().valence(0), 4);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn valence(pm: &mut PolarMesh, v: INT) -> ScriptResult<INT> {
        Ok(pm.0.valence(kernel("valence", pm.0.vertex_id(v))?) as INT)
    }
    /// The position of vertex `v`.
    ///
    /// ```rhai
    /// assert_eq(polar_octahedron().position(5), vec3(0, 0, 1));
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn position(pm: &mut PolarMesh, v: INT) -> ScriptResult<Vec3> {
        Ok(pm.0.position(kernel("position", pm.0.vertex_id(v))?))
    }
    /// All vertex positions, indexed by vertex id.
    ///
    /// ```rhai
    /// assert_eq(polar_octahedron().positions().len(), 6);
    /// ```
    #[rhai_fn(pure)]
    pub fn positions(pm: &mut PolarMesh) -> Array {
        pm.0.mesh().positions().iter().map(|p| Dynamic::from(*p)).collect()
    }
    /// `[from, to]`: the vertices of half-edge `h`.
    ///
    /// ```rhai
    /// let pm = polar_octahedron();
    /// assert_eq(pm.ends(pm.fan(0)[0])[0], 0);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn ends(pm: &mut PolarMesh, h: INT) -> ScriptResult<Array> {
        let h = kernel("ends", pm.0.halfedge_id(h))?;
        Ok(id_array(&pm.0.ends(h)))
    }
    /// The face of half-edge `h`.
    ///
    /// ```rhai
    /// let pm = polar_octahedron();
    /// let f = pm.face_of(pm.halfedge(1, 2));
    /// assert(pm.face_vertices(f).contains(1), "the face of a half-edge has its vertices");
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn face_of(pm: &mut PolarMesh, h: INT) -> ScriptResult<INT> {
        let h = kernel("face_of", pm.0.halfedge_id(h))?;
        Ok(INT::from(pm.0.face_of(h)))
    }
    /// The vertices of face `f`, in order.
    ///
    /// ```rhai
    /// assert_eq(polar_octahedron().face_vertices(0).len(), 3);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn face_vertices(pm: &mut PolarMesh, f: INT) -> ScriptResult<Array> {
        let f = kernel("face_vertices", pm.0.face_id(f))?;
        Ok(pm.0.mesh().face_vertices(f).map(int).collect())
    }
    /// The half-edges leaving vertex `v`.
    ///
    /// ```rhai
    /// let pm = polar_octahedron();
    /// assert_eq(pm.outgoing(0).len(), 4);
    /// for h in pm.outgoing(0) { assert_eq(pm.ends(h)[0], 0); }
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn outgoing(pm: &mut PolarMesh, v: INT) -> ScriptResult<Array> {
        let v = kernel("outgoing", pm.0.vertex_id(v))?;
        Ok(pm.0.mesh().outgoing(v).map(int).collect())
    }
    /// The half-edge from vertex `a` to vertex `b`, or an error if they are not neighbours.
    ///
    /// ```rhai
    /// let pm = polar_octahedron();
    /// assert_eq(pm.ends(pm.halfedge(1, 2)), [1, 2]);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn halfedge(pm: &mut PolarMesh, a: INT, b: INT) -> ScriptResult<INT> {
        let (a, b) = (kernel("halfedge", pm.0.vertex_id(a))?, kernel("halfedge", pm.0.vertex_id(b))?);
        match pm.0.mesh().find_halfedge(a, b) {
            Some(h) => Ok(INT::from(h)),
            None => fail("halfedge", format!("vertices {a} and {b} are not joined by an edge")),
        }
    }
    /// The vertex nearest to point `p`.
    ///
    /// ```rhai
    /// assert_eq(polar_octahedron().nearest_vertex([0, 0, 2]), 5);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn nearest_vertex(pm: &mut PolarMesh, p: Vector) -> ScriptResult<INT> {
        let p = vec3("nearest_vertex", "p", &p)?;
        kernel("nearest_vertex", pm.0.nearest_vertex(p)).map(INT::from)
    }
    /// The half-edge nearest to point `p` (of the nearest edge, the half on `p`'s side).
    ///
    /// ```rhai
    /// let pm = polar_octahedron();
    /// let e = pm.ends(pm.nearest_halfedge(lerp(pm.position(1), pm.position(2), 0.5)));
    /// e.sort();
    /// assert_eq(e, [1, 2]);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn nearest_halfedge(pm: &mut PolarMesh, p: Vector) -> ScriptResult<INT> {
        let p = vec3("nearest_halfedge", "p", &p)?;
        kernel("nearest_halfedge", pm.0.nearest_halfedge(p)).map(INT::from)
    }
    /// The face nearest to point `p`.
    ///
    /// ```rhai
    /// let pm = polar_octahedron();
    /// let f = pm.nearest_face((pm.position(0) + pm.position(1) + pm.position(2)) / 3);
    /// let v = pm.face_vertices(f);
    /// v.sort();
    /// assert_eq(v, [0, 1, 2]);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn nearest_face(pm: &mut PolarMesh, p: Vector) -> ScriptResult<INT> {
        let p = vec3("nearest_face", "p", &p)?;
        kernel("nearest_face", pm.0.nearest_face(p)).map(INT::from)
    }
    /// The vertices within `radius` of point `p`, ascending: a selection for the low-level moves.
    ///
    /// ```rhai
    /// assert_eq(polar_octahedron().vertices_near([0, 0, 1], 0.1), [5]);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn vertices_near(pm: &mut PolarMesh, p: Vector, radius: Number) -> ScriptResult<Array> {
        let p = vec3("vertices_near", "p", &p)?;
        let r = number("vertices_near", "radius", &radius)?;
        kernel("vertices_near", pm.0.vertices_near(p, r)).map(|v| id_array(&v))
    }
    /// Verifies every polar invariant of chapter 3; an error names the first one broken.
    ///
    /// ```rhai
    /// polar_octahedron().check();
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn check(pm: &mut PolarMesh) -> ScriptResult<()> {
        kernel("check", pm.0.check())
    }
    /// The underlying mesh (same vertex ids and positions).
    ///
    /// ```rhai
    /// assert_eq(polar_octahedron().to_mesh().genus(), 0);
    /// ```
    #[rhai_fn(pure)]
    pub fn to_mesh(pm: &mut PolarMesh) -> SharedMesh {
        SharedMesh::new(pm.0.to_mesh())
    }
    /// This polar mesh as a smooth surface: `levels` Catmull–Clark steps (0 to 4) with the
    /// branch tips kept pointed (the poles at the ends of the skeleton, rooted at the first
    /// pole; the root is smoothed like the rest). Face colours ride on their faces. For a smooth
    /// plant that moves, use `animation(pm, #{ subdivide: levels })`.
    ///
    /// ```rhai
    /// let plant = lsystem(#{ axiom: "F[+F][-F]F" }).grow(0);
    /// let smooth = plant.catmull_clark(2);
    /// assert(smooth.is_closed() && smooth.is_manifold() && smooth.genus() == 0, "a closed surface");
    /// assert(smooth.volume() < plant.to_mesh().volume(), "smoothing rounds the facets in");
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn catmull_clark(pm: &mut PolarMesh, levels: INT) -> ScriptResult<SharedMesh> {
        let max = blocksmith_kernel::anim::MAX_LEVELS;
        if !(0..=INT::from(max)).contains(&levels) {
            return crate::convert::fail(
                "catmull_clark",
                format!("argument `levels` must be between 0 and {max}, got {levels}"),
            );
        }
        let _bar = crate::progress::bar("catmull_clark");
        kernel("catmull_clark", blocksmith_kernel::anim::subdivide_polar_mesh(&pm.0, None, levels as u32))
            .map(SharedMesh::new)
    }
    /// The mesh with each feature in its own hue as vertex colours (appendix B.1.3),
    /// neighbouring features in different hues.
    ///
    /// ```rhai
    /// let m = polar_octahedron().to_colored_mesh();
    /// assert_eq(m.face_count, 8);
    /// ```
    #[rhai_fn(pure)]
    pub fn to_colored_mesh(pm: &mut PolarMesh) -> SharedMesh {
        SharedMesh::new(pm.0.to_colored_mesh())
    }
    /// The same shape as a valid solid: a closed, manifold triangle mesh whose faces cross
    /// nowhere, for booleans, volumes, slicers and 3D printing. A grown plant's polar mesh is
    /// closed but crosses itself where a branch's first quads pass through its parent's wall;
    /// here the surface is cut along its loops into tubes (branching to branching), each capped
    /// by cones that reach into the parent, and the tubes are united by the boolean engine, so
    /// the crossings are cut away. The result holds all of the union of the tubes and exceeds
    /// it only where a region's faces cross (a branch's loops folded over themselves), which
    /// stands in as its convex hull: by 2-4 % of a plant's volume, at most 5 % (6 % grown with
    /// `wide_gaps`) over 256 seeded plants. The polar mesh is not changed, so it can be edited
    /// further. Errors when the loops do not cut the mesh
    /// into tubes (a loop round a hole) or two vertices lie at one point (a zero-length
    /// segment).
    ///
    /// ```rhai
    /// import "check" as check;
    /// let pm = lsystem(#{ axiom: "F[+F][-F]F" }).grow(0);
    /// let solid = pm.to_solid();
    /// check::solid(solid, 0);
    /// assert(solid.volume() > 0.9 * pm.to_mesh().volume(), "the same plant");
    /// pm.check();                                  // the polar mesh is unchanged
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn to_solid(pm: &mut PolarMesh) -> ScriptResult<SharedMesh> {
        let _bar = crate::progress::bar("to_solid");
        kernel("to_solid", pm.0.to_solid()).map(SharedMesh::new)
    }
    /// Writes the mesh with its feature colours (see `to_colored_mesh`) by extension, like a
    /// mesh's `save`. Also callable as `pm.save(path)`.
    ///
    /// ```rhai
    /// polar_octahedron().save("doc_example_polar.glb");
    /// ```
    #[rhai_fn(return_raw)]
    pub fn save(ctx: NativeCallContext, pm: &mut PolarMesh, path: &str) -> ScriptResult<()> {
        crate::api::files::write_mesh(&ctx, "save", &pm.0.to_colored_mesh(), path)
    }
    /// Writes the polar mesh with options: `solid` (default `false`: the polar mesh with its
    /// feature colours; `true`: `to_solid()`, the valid solid without crossings, for printing
    /// and slicers), and a mesh's save options `up` and `ply`.
    ///
    /// ```rhai
    /// let plant = lsystem(#{ axiom: "F[+F][-F]F" }).grow(0);
    /// plant.save("doc_example_plant_solid.obj", #{ solid: true });
    /// let back = load("doc_example_plant_solid.obj");
    /// assert(back.is_closed() && back.is_manifold());
    /// ```
    #[rhai_fn(name = "save", return_raw)]
    pub fn save_with(ctx: NativeCallContext, pm: &mut PolarMesh, path: &str, options: Map) -> ScriptResult<()> {
        let opts = Options::new("save", options.clone(), &["solid", "up", "ply"])?;
        let mesh = if opts.bool("solid", false)? { kernel("save", pm.0.to_solid())? } else { pm.0.to_colored_mesh() };
        let mut rest = options;
        rest.remove("solid");
        crate::api::files::files_api::save_with_options(ctx, &mut SharedMesh::new(mesh), path, rest)
    }
    /// A one-line summary.
    #[rhai_fn(name = "to_string", name = "to_debug", pure)]
    pub fn to_string(pm: &mut PolarMesh) -> String {
        format!(
            "PolarMesh({} vertices, {} faces, {} poles, {} loops)",
            pm.0.vertex_count(),
            pm.0.face_count(),
            pm.0.poles().len(),
            pm.0.loops().len()
        )
    }

    // ---- The seven operations (ch. 4) ------------------------------------------------------

    /// Add refinement (§4.1): splits every edge parallel to `h` at its midpoint and joins the new
    /// vertices: on a backbone a new loop, on a loop edge a new backbone. Returns the new loop or
    /// backbone as half-edges.
    ///
    /// ```rhai
    /// let pm = polar_octahedron();
    /// let l = pm.add_refinement(pm.fan(0)[0]);
    /// assert_eq(l.len(), 4);
    /// assert_eq(pm.loops().len(), 2);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn add_refinement(pm: &mut PolarMesh, h: INT) -> ScriptResult<Array> {
        add_refinement_with(pm, h, Map::new())
    }
    /// Add refinement with option `at`: where along `h` (0 < at < 1, default 0.5) the edges are
    /// split, measured in `h`'s direction.
    ///
    /// ```rhai
    /// let pm = polar_octahedron();
    /// pm.add_refinement(pm.halfedge(0, 1), #{ at: 0.25 });
    /// assert_near(pm.position(pm.vertex_count - 1).z, -0.75, 1e-12);
    /// ```
    #[rhai_fn(name = "add_refinement", return_raw)]
    pub fn add_refinement_with(pm: &mut PolarMesh, h: INT, options: Map) -> ScriptResult<Array> {
        let opts = Options::new("add_refinement", options, &["at"])?;
        let t = opts.number("at", 0.5)?;
        let r = kernel("add_refinement", pm.get_mut().add_refinement_at(h, t))?;
        Ok(id_array(&r.halfedges))
    }
    /// Remove refinement (§4.2): removes the loop or backbone through `h`. Refused (§4.2.4) for
    /// the last loop between two poles, a refinement carrying a nested feature, or a backbone
    /// whose removal leaves a region below valency 3.
    ///
    /// ```rhai
    /// let pm = polar_octahedron();
    /// let l = pm.add_refinement(pm.fan(0)[0]);
    /// pm.remove_refinement(l[0]);
    /// assert_eq(pm.face_count, 8);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn remove_refinement(pm: &mut PolarMesh, h: INT) -> ScriptResult<()> {
        kernel("remove_refinement", pm.get_mut().remove_refinement(h))
    }
    /// Add feature (§4.3): nests a new feature on consecutive loop vertices `verts` (at least 3)
    /// and returns its pole (valence 2(|verts| − 1)). The gap opens on the side of the faces to
    /// the left of the run walked in the given order.
    ///
    /// ```rhai
    /// let pm = polar_sphere(1, 8, 4);
    /// let p = pm.add_feature([9, 10, 11]);
    /// assert_eq(pm.valence(p), 4);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn add_feature(pm: &mut PolarMesh, verts: Array) -> ScriptResult<INT> {
        add_feature_with(pm, verts, Map::new())
    }
    /// Add feature with options `depth` (how far up the backbones the gap reaches, 0–1, default
    /// 0.5) and `height` (how far the pole stands out, in gap edge lengths, default 0.25).
    ///
    /// ```rhai
    /// let pm = polar_sphere(1, 8, 4);
    /// pm.add_feature([9, 10, 11, 12], #{ depth: 0.3, height: 0 });
    /// pm.check();
    /// ```
    #[rhai_fn(name = "add_feature", return_raw)]
    pub fn add_feature_with(pm: &mut PolarMesh, verts: Array, options: Map) -> ScriptResult<INT> {
        let opts = Options::new("add_feature", options, &["depth", "height"])?;
        let o = FeatureOptions::DEFAULT
            .with_depth(opts.number("depth", FeatureOptions::DEFAULT.depth)?)
            .with_height(opts.number("height", FeatureOptions::DEFAULT.height)?);
        let v = ids("add_feature", "verts", &verts)?;
        kernel("add_feature", pm.get_mut().add_feature_with(&v, &o)).map(INT::from)
    }
    /// Select feature (§4.4): the faces of the feature face `f` belongs to, ascending.
    ///
    /// ```rhai
    /// let pm = polar_sphere(1, 8, 4);
    /// assert_eq(pm.select_feature(0).len(), pm.face_count);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn select_feature(pm: &mut PolarMesh, f: INT) -> ScriptResult<Array> {
        kernel("select_feature", pm.0.select_feature(f)).map(|v| id_array(&v))
    }
    /// Remove feature (§4.5): removes the feature of face `f` and closes the gap by zipping its
    /// boundary loop. Needs exactly two split vertices on the boundary and equal paths between
    /// them (§4.5.4); a feature between two loops (a handle) is removed too.
    ///
    /// ```rhai
    /// let pm = polar_sphere(1, 8, 4);
    /// let p = pm.add_feature([9, 10, 11]);
    /// pm.remove_feature(pm.face_of(pm.fan(p)[0]));
    /// assert_eq(pm.features().len(), 1);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn remove_feature(pm: &mut PolarMesh, f: INT) -> ScriptResult<()> {
        kernel("remove_feature", pm.get_mut().remove_feature(f))
    }
    /// Merge features (§4.6): bridges the loops of poles `p1` and `p2` (equal valences) with a
    /// ring of quads, pairing vertices by least total distance; both poles disappear.
    ///
    /// ```rhai
    /// let pm = polar_sphere(1, 8, 5);
    /// pm.merge_features(0, pm.vertex_count - 1);
    /// assert_eq(pm.to_mesh().genus(), 1);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn merge_features(pm: &mut PolarMesh, p1: INT, p2: INT) -> ScriptResult<()> {
        kernel("merge_features", pm.get_mut().merge_features(p1, p2))
    }
    /// Split feature (§4.7): replaces the loop through `h` and the rings beside it by two pole
    /// fans; returns the two new poles.
    ///
    /// ```rhai
    /// let pm = polar_sphere(1, 8, 6);
    /// let p = pm.split_feature(pm.halfedge(17, 18));
    /// assert_eq(p.len(), 2);
    /// assert_eq(pm.to_mesh().euler(), 4); // two spheres
    /// ```
    #[rhai_fn(return_raw)]
    pub fn split_feature(pm: &mut PolarMesh, h: INT) -> ScriptResult<Array> {
        kernel("split_feature", pm.get_mut().split_feature(h)).map(|p| id_array(&p))
    }

    // ---- Low-level modelling (§2.4) --------------------------------------------------------

    /// Moves the vertices `verts` by `offset` (world axes). Like every PolarMesh edit, it
    /// changes this mesh and returns nothing.
    ///
    /// ```rhai
    /// let pm = polar_octahedron();
    /// pm.move_vertices([5], [0, 0, 1]);
    /// assert_eq(pm.position(5), vec3(0, 0, 2));
    /// ```
    #[rhai_fn(name = "move_vertices", return_raw)]
    pub fn move_vertices(pm: &mut PolarMesh, verts: Array, offset: Vector) -> ScriptResult<()> {
        move_vertices_with(pm, verts, offset, Map::new())
    }
    /// Moves the vertices `verts` by `offset`, with option `frame`: `"global"` (world axes,
    /// default) or `"local"` (x, y in the selection's plane, z along its normal; for a loop, the
    /// loop's own centre and normal).
    ///
    /// ```rhai
    /// let pm = polar_sphere(1, 8, 4);
    /// pm.move_vertices([9, 10, 11, 12, 13, 14, 15, 16], [0, 0, 0.5], #{ frame: "local" });
    /// assert_near(pm.position(9).z, 0.5, 1e-12);
    /// ```
    #[rhai_fn(name = "move_vertices", return_raw)]
    pub fn move_vertices_with(pm: &mut PolarMesh, verts: Array, offset: Vector, options: Map) -> ScriptResult<()> {
        move_selection("move_vertices", pm, &verts, &offset, options)
    }
    /// `move_vertices` under its older name: moves the vertices `verts` by `offset`, with the
    /// same options.
    ///
    /// ```rhai
    /// let pm = polar_octahedron();
    /// pm.move([5], [0, 0, 1]);
    /// assert_eq(pm.position(5), vec3(0, 0, 2));
    /// ```
    #[rhai_fn(name = "move", return_raw)]
    pub fn move_(pm: &mut PolarMesh, verts: Array, offset: Vector) -> ScriptResult<()> {
        move_selection("move", pm, &verts, &offset, Map::new())
    }
    /// `move_vertices` under its older name: moves the vertices `verts` by `offset`, with the
    /// same options.
    #[rhai_fn(name = "move", return_raw)]
    pub fn move_with(pm: &mut PolarMesh, verts: Array, offset: Vector, options: Map) -> ScriptResult<()> {
        move_selection("move", pm, &verts, &offset, options)
    }
    /// Scales the vertices `verts` by `factor` (a number, or a vector per axis) about their
    /// centre, changing this mesh (a Mesh's `m.scale(f)` returns a new, whole scaled mesh).
    ///
    /// ```rhai
    /// let pm = polar_sphere(1, 8, 4);
    /// pm.scale_vertices([9, 10, 11, 12, 13, 14, 15, 16], 2);
    /// assert_near(pm.position(9).x, 2.0, 1e-12);
    /// ```
    #[rhai_fn(name = "scale_vertices", return_raw)]
    pub fn scale_vertices(pm: &mut PolarMesh, verts: Array, factor: NumberOrVector) -> ScriptResult<()> {
        scale_vertices_with(pm, verts, factor, Map::new())
    }
    /// Scales with options `center` (default: the selection's centre) and `frame` (`"global"` or
    /// `"local"`: a vector factor then acts along the selection's tangent, bitangent, normal).
    ///
    /// ```rhai
    /// let pm = polar_sphere(1, 8, 4);
    /// pm.scale_vertices([9, 10, 11, 12, 13, 14, 15, 16], [1.5, 1.5, 1], #{ frame: "local", center: [0, 0, 0] });
    /// assert_near(pm.position(9).x, 1.5, 1e-12);
    /// ```
    #[rhai_fn(name = "scale_vertices", return_raw)]
    pub fn scale_vertices_with(
        pm: &mut PolarMesh,
        verts: Array,
        factor: NumberOrVector,
        options: Map,
    ) -> ScriptResult<()> {
        scale_selection("scale_vertices", pm, &verts, &factor, options)
    }
    /// `scale_vertices` under its older name (API.md): scales the vertices `verts` by `factor`
    /// about their centre. Unlike `m.scale(factor)` on a Mesh, the first argument is the
    /// vertices; prefer `scale_vertices`, which says so.
    ///
    /// ```rhai
    /// let pm = polar_sphere(1, 8, 4);
    /// pm.scale([9, 10, 11, 12, 13, 14, 15, 16], 2);
    /// assert_near(pm.position(9).x, 2.0, 1e-12);
    /// ```
    #[rhai_fn(name = "scale", return_raw)]
    pub fn scale(pm: &mut PolarMesh, verts: Array, factor: NumberOrVector) -> ScriptResult<()> {
        scale_selection("scale", pm, &verts, &factor, Map::new())
    }
    /// `scale_vertices` under its older name, with the same options `center` and `frame`.
    #[rhai_fn(name = "scale", return_raw)]
    pub fn scale_with(pm: &mut PolarMesh, verts: Array, factor: NumberOrVector, options: Map) -> ScriptResult<()> {
        scale_selection("scale", pm, &verts, &factor, options)
    }
    /// Turns the vertices `verts` by `degrees` about `axis` through their centre (right-handed),
    /// changing this mesh (a Mesh's `m.rotate(axis, deg)` returns a new, whole turned mesh).
    ///
    /// ```rhai
    /// let pm = polar_octahedron();
    /// pm.rotate_vertices([1, 2, 3, 4], [0, 0, 1], 90);
    /// assert_near(pm.position(1), vec3(0, 1, 0), 1e-12);
    /// ```
    #[rhai_fn(name = "rotate_vertices", return_raw)]
    pub fn rotate_vertices(pm: &mut PolarMesh, verts: Array, axis: Vector, degrees: Number) -> ScriptResult<()> {
        rotate_vertices_with(pm, verts, axis, degrees, Map::new())
    }
    /// Turns with options `center` (default: the selection's centre) and `frame` (`"local"`:
    /// the axis is given in the selection's frame, `[0, 0, 1]` its normal).
    ///
    /// ```rhai
    /// let pm = polar_octahedron();
    /// pm.rotate_vertices([5], [1, 0, 0], 90, #{ center: [0, 0, 0] });
    /// assert_near(pm.position(5), vec3(0, -1, 0), 1e-12);
    /// ```
    #[rhai_fn(name = "rotate_vertices", return_raw)]
    pub fn rotate_vertices_with(
        pm: &mut PolarMesh,
        verts: Array,
        axis: Vector,
        degrees: Number,
        options: Map,
    ) -> ScriptResult<()> {
        rotate_selection("rotate_vertices", pm, &verts, &axis, &degrees, options)
    }
    /// `rotate_vertices` under its older name (API.md): turns the vertices `verts` by `degrees`
    /// about `axis` through their centre. Unlike `m.rotate(axis, deg)` on a Mesh, the first
    /// argument is the vertices; prefer `rotate_vertices`, which says so.
    ///
    /// ```rhai
    /// let pm = polar_octahedron();
    /// pm.rotate([1, 2, 3, 4], [0, 0, 1], 90);
    /// assert_near(pm.position(1), vec3(0, 1, 0), 1e-12);
    /// ```
    #[rhai_fn(name = "rotate", return_raw)]
    pub fn rotate(pm: &mut PolarMesh, verts: Array, axis: Vector, degrees: Number) -> ScriptResult<()> {
        rotate_selection("rotate", pm, &verts, &axis, &degrees, Map::new())
    }
    /// `rotate_vertices` under its older name, with the same options `center` and `frame`.
    #[rhai_fn(name = "rotate", return_raw)]
    pub fn rotate_with(
        pm: &mut PolarMesh,
        verts: Array,
        axis: Vector,
        degrees: Number,
        options: Map,
    ) -> ScriptResult<()> {
        rotate_selection("rotate", pm, &verts, &axis, &degrees, options)
    }
    /// This polar mesh with every face coloured `c`: `[r, g, b]` or `[r, g, b, a]` (0 to 1) or
    /// `"#rrggbb"`. The operations and growth give the faces they make the colour of the faces
    /// they replace; `to_mesh`, `to_solid` and `save` keep the colours (a coloured polar mesh is
    /// saved in its own colours, not the feature hues). A new polar mesh; this one is left as it
    /// was.
    ///
    /// ```rhai
    /// let pm = polar_sphere(1, 8, 4).color("#3a7d2c");
    /// assert_eq(pm.to_mesh().colors().len(), 1);
    /// ```
    #[rhai_fn(name = "color", pure, return_raw)]
    pub fn color_all(pm: &mut PolarMesh, c: crate::convert::Color) -> ScriptResult<PolarMesh> {
        let rgba = crate::api::color::color_value("color", "c", &c)?;
        let mut out = pm.clone();
        kernel("color", out.get_mut().set_color(rgba))?;
        Ok(out)
    }
    /// This polar mesh with the faces `faces` coloured `c` (a feature: `pm.select_feature(f)`),
    /// the others as they were. A new polar mesh; this one is left as it was.
    ///
    /// ```rhai
    /// let pm = lsystem(#{ axiom: "F[+F][-F]F" }).grow(0).color([0, 0.5, 0]);
    /// let trunk = pm.color([0.5, 0.25, 0], pm.select_feature(0));
    /// assert_eq(trunk.to_mesh().colors().len(), 2);
    /// assert_eq(trunk.to_solid().colors().len(), 2);   // the solid keeps them
    /// ```
    #[rhai_fn(name = "color", pure, return_raw)]
    pub fn color_some(pm: &mut PolarMesh, c: crate::convert::Color, faces: Array) -> ScriptResult<PolarMesh> {
        let rgba = crate::api::color::color_value("color", "c", &c)?;
        let f = ids("color", "faces", &faces)?;
        let mut out = pm.clone();
        kernel("color", out.get_mut().color_faces(&f, rgba))?;
        Ok(out)
    }
    /// This polar mesh moved by `offset`, like a Mesh's `translate`: a new polar mesh with the
    /// same vertex ids, poles and loops; this one is left as it was (keep the result).
    ///
    /// ```rhai
    /// let pm = polar_octahedron();
    /// let up = pm.translate([0, 0, 2]);
    /// assert_eq(up.position(5), vec3(0, 0, 3));
    /// assert_eq(pm.position(5), vec3(0, 0, 1));   // unchanged
    /// up.check();
    /// ```
    #[rhai_fn(name = "translate", pure, return_raw)]
    pub fn translate_whole(pm: &mut PolarMesh, offset: Vector) -> ScriptResult<PolarMesh> {
        let v = vec3("translate", "offset", &offset)?;
        let moved = pm.0.translate(v);
        whole_finite("translate", "offset", moved)
    }
    /// This polar mesh turned by `degrees` about `axis` through the origin (right-handed), like
    /// a Mesh's `rotate`: a new polar mesh, poles and loops kept. (`pm.rotate(verts, axis,
    /// degrees)` turns some vertices in place.)
    ///
    /// ```rhai
    /// let pm = polar_octahedron().rotate([1, 0, 0], 90);
    /// assert_near(pm.position(5), vec3(0, -1, 0), 1e-12);
    /// pm.check();
    /// ```
    #[rhai_fn(name = "rotate", pure, return_raw)]
    pub fn rotate_whole(pm: &mut PolarMesh, axis: Vector, degrees: Number) -> ScriptResult<PolarMesh> {
        let a = vec3("rotate", "axis", &axis)?;
        if a == Vec3::ZERO {
            return fail("rotate", "argument `axis` is the zero vector, which has no direction");
        }
        let d = number("rotate", "degrees", &degrees)?;
        Ok(PolarMesh(Rc::new(pm.0.rotate(a, d))))
    }
    /// This polar mesh scaled about the origin by a number or per axis by a vector, like a
    /// Mesh's `scale`: a new polar mesh, poles and loops kept; a mirroring scale (a negative
    /// product) keeps the faces outward. A zero factor is an error. (`pm.scale(verts, factor)`
    /// scales some vertices in place.)
    ///
    /// ```rhai
    /// let pm = polar_sphere(1, 8, 4);
    /// let big = pm.scale(2);
    /// assert_near(big.to_mesh().volume(), 8 * pm.to_mesh().volume(), 1e-9);
    /// let flipped = pm.scale([-1, 1, 1]);
    /// assert_near(flipped.to_mesh().volume(), pm.to_mesh().volume(), 1e-9);   // still outward
    /// flipped.check();
    /// ```
    #[rhai_fn(name = "scale", pure, return_raw)]
    pub fn scale_whole(pm: &mut PolarMesh, factor: NumberOrVector) -> ScriptResult<PolarMesh> {
        let f = factor3("scale", "factor", &factor)?;
        if f.x * f.y * f.z == 0.0 {
            return fail(
                "scale",
                format!("argument `factor` has a zero component ({f}), which would flatten the mesh"),
            );
        }
        let scaled = kernel("scale", pm.0.scale(f))?;
        whole_finite("scale", "factor", scaled)
    }
    /// This polar mesh reflected through the plane through the origin with normal `normal`,
    /// like a Mesh's `mirror`: faces reversed to keep facing outward, poles and loops kept.
    ///
    /// ```rhai
    /// let pm = polar_octahedron().translate([1, 0, 0]).mirror([1, 0, 0]);
    /// assert_eq(pm.position(5), vec3(-1, 0, 1));
    /// assert(pm.to_mesh().volume() > 0);
    /// ```
    #[rhai_fn(name = "mirror", pure, return_raw)]
    pub fn mirror_whole(pm: &mut PolarMesh, normal: Vector) -> ScriptResult<PolarMesh> {
        let n = vec3("mirror", "normal", &normal)?;
        if n == Vec3::ZERO {
            return fail("mirror", "argument `normal` is the zero vector, which has no direction");
        }
        kernel("mirror", pm.0.mirror(n)).map(|m| PolarMesh(Rc::new(m)))
    }
    /// Moves vertex `v` to point `p`.
    ///
    /// ```rhai
    /// let pm = polar_octahedron();
    /// pm.set_position(5, [0, 0, 3]);
    /// assert_eq(pm.position(5).z, 3.0);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn set_position(pm: &mut PolarMesh, v: INT, p: Vector) -> ScriptResult<()> {
        let v = kernel("set_position", pm.0.vertex_id(v))?;
        let p = vec3("set_position", "p", &p)?;
        kernel("set_position", pm.get_mut().set_position(v, p))
    }
    /// The frame of the loop (or backbone) through `h`: `#{center, normal, tangent, bitangent}`;
    /// the normal follows the right-hand rule along the walk.
    ///
    /// ```rhai
    /// let pm = polar_octahedron();
    /// let f = pm.loop_frame(pm.halfedge(1, 2));
    /// assert_near(f.normal, vec3(0, 0, 1), 1e-12);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn loop_frame(pm: &mut PolarMesh, h: INT) -> ScriptResult<Map> {
        kernel("loop_frame", pm.0.loop_frame(h)).map(|f| frame_map(&f))
    }
    /// The local frame of a vertex selection (the one `"local"` moves use):
    /// `#{center, normal, tangent, bitangent}`.
    ///
    /// ```rhai
    /// let f = polar_octahedron().selection_frame([1, 2, 3, 4]);
    /// assert_near(f.center, vec3(0, 0, 0), 1e-12);
    /// assert_near(length(cross(f.normal, vec3(0, 0, 1))), 0.0, 1e-12);   // the equator's plane
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn selection_frame(pm: &mut PolarMesh, verts: Array) -> ScriptResult<Map> {
        let v = ids("selection_frame", "verts", &verts)?;
        kernel("selection_frame", pm.0.selection_frame(&v)).map(|f| frame_map(&f))
    }

    // ---- Skeleton (§7.1–7.2) -------------------------------------------------------------

    /// The inferred skeleton (§7.1), rooted at the node of the first pole (or node 0).
    ///
    /// ```rhai
    /// let sk = polar_sphere(1, 8, 5).skeleton();
    /// assert_eq(sk.node_count, 6);   // 2 poles + 4 loops
    /// assert_eq(sk.cycle_count(), 0);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn skeleton(pm: &mut PolarMesh) -> ScriptResult<Skeleton> {
        skeleton_with(pm, Map::new())
    }
    /// The inferred skeleton with option `root`: a vertex whose node becomes the root.
    ///
    /// ```rhai
    /// let pm = polar_sphere(1, 8, 5);
    /// let sk = pm.skeleton(#{ root: pm.vertex_count - 1 });
    /// assert(sk.is_pole(sk.root));
    /// assert_eq(sk.parent(sk.root), ());
    /// ```
    #[rhai_fn(name = "skeleton", pure, return_raw)]
    pub fn skeleton_with(pm: &mut PolarMesh, options: Map) -> ScriptResult<Skeleton> {
        let opts = Options::new("skeleton", options, &["root"])?;
        let root = if opts.has("root") {
            let r = opts.int("root", 0)?;
            Some(kernel("skeleton", pm.0.vertex_id(r))?)
        } else {
            None
        };
        kernel("skeleton", pm.0.skeleton(root)).map(|s| Skeleton(Rc::new(s)))
    }
    /// Number of skeleton nodes (poles and loop complexes).
    #[rhai_fn(get = "node_count", pure)]
    pub fn node_count(sk: &mut Skeleton) -> INT {
        sk.0.node_count() as INT
    }
    /// Number of segments (one per region).
    ///
    /// ```rhai
    /// assert_eq(polar_sphere(1, 8, 5).skeleton().segment_count, 5);   // a chain of 6 nodes
    /// ```
    #[rhai_fn(get = "segment_count", pure)]
    pub fn segment_count(sk: &mut Skeleton) -> INT {
        sk.0.segment_count() as INT
    }
    /// The root node.
    ///
    /// ```rhai
    /// let sk = polar_sphere(1, 8, 5).skeleton();
    /// assert(sk.is_pole(sk.root), "rooted at a pole");
    /// ```
    #[rhai_fn(get = "root", pure)]
    pub fn root(sk: &mut Skeleton) -> INT {
        INT::from(sk.0.root())
    }
    /// The segments as `[node, node]` pairs.
    ///
    /// ```rhai
    /// let s = polar_sphere(1, 8, 5).skeleton().segments();
    /// assert_eq(s.len(), 5);
    /// assert_eq(s[0].len(), 2);
    /// ```
    #[rhai_fn(pure)]
    pub fn segments(sk: &mut Skeleton) -> Array {
        sk.0.segments().iter().map(|s| Dynamic::from_array(id_array(s))).collect()
    }
    /// The position of node `i` (a pole, or the centre of a loop).
    ///
    /// ```rhai
    /// let sk = polar_sphere(1, 8, 5).skeleton();
    /// assert_near(length(sk.position(sk.root)), 1.0, 1e-12);   // a pole of the unit sphere
    /// ```
    #[rhai_fn(name = "position", pure, return_raw)]
    pub fn node_position(sk: &mut Skeleton, i: INT) -> ScriptResult<Vec3> {
        Ok(sk.0.position(skeleton_node("position", &sk.0, i)?))
    }
    /// The parent of node `i` in the rooted tree, or `()` for a root.
    ///
    /// ```rhai
    /// let sk = polar_sphere(1, 8, 5).skeleton();
    /// let child = sk.children(sk.root)[0];
    /// assert_eq(sk.parent(child), sk.root);
    /// assert_eq(sk.parent(sk.root), ());
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn parent(sk: &mut Skeleton, i: INT) -> ScriptResult<Dynamic> {
        let i = skeleton_node("parent", &sk.0, i)?;
        Ok(sk.0.parent(i).map_or(Dynamic::UNIT, int))
    }
    /// The children of node `i` in the rooted tree.
    ///
    /// ```rhai
    /// let sk = polar_sphere(1, 8, 5).skeleton();
    /// assert_eq(sk.children(sk.root).len(), 1);   // a chain
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn children(sk: &mut Skeleton, i: INT) -> ScriptResult<Array> {
        let i = skeleton_node("children", &sk.0, i)?;
        Ok(id_array(sk.0.children(i)))
    }
    /// The depth of node `i` below its root.
    ///
    /// ```rhai
    /// let sk = polar_sphere(1, 8, 5).skeleton();
    /// let order = sk.order();
    /// assert_eq(sk.depth(sk.root), 0);
    /// assert_eq(sk.depth(order[order.len() - 1]), 5);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn depth(sk: &mut Skeleton, i: INT) -> ScriptResult<INT> {
        let i = skeleton_node("depth", &sk.0, i)?;
        Ok(INT::from(sk.0.depth(i)))
    }
    /// Whether node `i` is a pole.
    #[rhai_fn(name = "is_pole", pure, return_raw)]
    pub fn node_is_pole(sk: &mut Skeleton, i: INT) -> ScriptResult<bool> {
        Ok(sk.0.is_pole(skeleton_node("is_pole", &sk.0, i)?))
    }
    /// The vertices bound to node `i`.
    ///
    /// ```rhai
    /// let sk = polar_sphere(1, 8, 5).skeleton();
    /// assert_eq(sk.vertices(sk.root).len(), 1);   // a pole
    /// assert_eq(sk.vertices(sk.children(sk.root)[0]).len(), 8);   // a loop
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn vertices(sk: &mut Skeleton, i: INT) -> ScriptResult<Array> {
        let i = skeleton_node("vertices", &sk.0, i)?;
        Ok(id_array(sk.0.vertices(i)))
    }
    /// The number of independent cycles (the genus of a connected polar mesh).
    ///
    /// ```rhai
    /// let t = polar_from(torus(2, 0.5, 8, 6), #{ loops: [[0, 1]] });
    /// assert_eq(t.skeleton().cycle_count(), 1);
    /// ```
    #[rhai_fn(pure)]
    pub fn cycle_count(sk: &mut Skeleton) -> INT {
        sk.0.cycle_count() as INT
    }
    /// The node vertex `v` is bound to.
    ///
    /// ```rhai
    /// let sk = polar_sphere(1, 8, 5).skeleton();
    /// assert_eq(sk.node_of(sk.vertices(sk.root)[0]), sk.root);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn node_of(sk: &mut Skeleton, v: INT) -> ScriptResult<INT> {
        let n = sk.0.vertex_nodes().len();
        if v < 0 || v as usize >= n {
            return fail("node_of", format!("vertex {v} does not exist (the skeleton binds {n})"));
        }
        Ok(INT::from(sk.0.node_of(v as u32)))
    }
    /// Every node, depth first from the root (parents before children).
    ///
    /// ```rhai
    /// let sk = polar_sphere(1, 8, 5).skeleton();
    /// assert_eq(sk.order().len(), 6);
    /// assert_eq(sk.order()[0], sk.root);
    /// ```
    #[rhai_fn(pure)]
    pub fn order(sk: &mut Skeleton) -> Array {
        id_array(sk.0.depth_first_order())
    }
    /// A one-line summary.
    #[rhai_fn(name = "to_string", name = "to_debug", pure)]
    pub fn skeleton_to_string(sk: &mut Skeleton) -> String {
        format!(
            "Skeleton({} nodes, {} segments, {} cycles)",
            sk.0.node_count(),
            sk.0.segment_count(),
            sk.0.cycle_count()
        )
    }
}
