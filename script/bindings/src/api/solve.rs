//! `Solver`: Shape-Up constraints on a mesh's vertices (Tsoi & Hui §4, after Bouaziz et al.;
//! kernel `solve`), `fit_circle` and `fit_cylinder` (§5).

use blocksmith_kernel::solve::{
    fit_circle as kernel_fit_circle, fit_cylinder as kernel_fit_cylinder, retain_circular_features as kernel_retain,
    CircleSize, RadiusRule, RetainOptions, ShapeUp, SolveError,
};
use blocksmith_kernel::Vec3;
use rhai::plugin::*;
use rhai::{exported_module, Array, Engine, Map, INT};

use super::mesh::SharedMesh;
use crate::convert::{fail, ids, kernel, number, vec3, Number, Options, ScriptResult};

/// A constraint system (script type `Solver`) on the vertices of the mesh it was made from, and
/// the energies of its last solve.
#[derive(Clone)]
pub struct Solver {
    mesh: std::sync::Arc<blocksmith_kernel::Mesh>,
    system: ShapeUp,
    energies: Vec<f64>,
}

/// The positions of `verts` (argument `verts` of `func`), each an existing vertex of `mesh`.
fn ring_points(func: &str, mesh: &SharedMesh, verts: &Array) -> ScriptResult<Vec<Vec3>> {
    let v = ids(func, "verts", verts)?;
    let n = mesh.0.vertex_count();
    if let Some(&bad) = v.iter().find(|&&x| x as usize >= n) {
        return fail(func, format!("argument `verts`: vertex {bad} does not exist (the mesh has {n})"));
    }
    Ok(v.iter().map(|&i| mesh.0.position(i)).collect())
}

/// A kernel error of a fit over the vertices `verts`, as an error about that argument.
fn verts_error<T>(func: &str, r: Result<T, SolveError>) -> ScriptResult<T> {
    r.map_err(|e| crate::convert::error(func, format!("argument `verts`: {e}")))
}

/// Registers `Solver`, `shape_up`, `fit_circle` and `fit_cylinder` on `engine`.
pub fn register(engine: &mut Engine) {
    engine.register_type_with_name::<Solver>("Solver");
    engine.register_global_module(exported_module!(solve_api).into());
}

#[export_module]
pub mod solve_api {
    use super::*;

    /// A Shape-Up constraint system on `mesh`'s vertices, starting from its positions. Add
    /// constraints and energies, then `solve(iterations)`.
    ///
    /// Topic: shape_up
    ///
    /// ```rhai
    /// let m = icosphere(1, 1);
    /// let s = shape_up(m);
    /// let all = [];
    /// for v in 0..m.vertex_count { all.push(v); }
    /// s.anchor([0], [[0, 0, 2]], 100);
    /// s.rigid(all, 10);
    /// let moved = s.solve(500);
    /// assert_near(moved.volume(), m.volume(), 1e-3);   // rigid: it only moved
    /// ```
    #[rhai_fn(return_raw)]
    pub fn shape_up(mesh: SharedMesh) -> ScriptResult<Solver> {
        let system = kernel("shape_up", ShapeUp::new(&mesh.0))?;
        Ok(Solver { mesh: mesh.0.clone(), system, energies: Vec::new() })
    }

    /// Keeps `verts` in their current shape up to a rotation and translation (SVD fit, never a
    /// reflection; Eqs. 5–9), with weight `w`.
    ///
    /// ```rhai
    /// let m = cube(2);
    /// let s = shape_up(m);
    /// s.rigid([0, 1, 2, 3, 4, 5, 6, 7], 10);
    /// s.anchor([0], [[0, 0, 5]], 100);
    /// assert_near(s.solve(100).volume(), 8.0, 1e-3);   // moved whole, not squashed
    /// ```
    #[rhai_fn(return_raw)]
    pub fn rigid(s: &mut Solver, verts: Array, w: Number) -> ScriptResult<()> {
        let v = ids("rigid", "verts", &verts)?;
        let w = number("rigid", "w", &w)?;
        kernel("rigid", s.system.rigid(&v, None, w))
    }

    /// Keeps `verts` on a circle (any centre, radius and plane), with weight `w`.
    ///
    /// ```rhai
    /// let m = uv_sphere(1, 16, 8).scale([1, 0.6, 1]);
    /// let s = shape_up(m);
    /// let ring = [];
    /// for v in 49..65 { ring.push(v); }
    /// s.circle(ring, 50);
    /// s.closeness(0.01);
    /// let round = s.solve(100);
    /// let c = fit_cylinder(round, ring);
    /// assert(c.radius > 0.5);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn circle(s: &mut Solver, verts: Array, w: Number) -> ScriptResult<()> {
        circle_with(s, verts, w, Map::new())
    }

    /// `circle` that also keeps the circle's size (Tsoi & Hui §5, Eq. 18: each point's radial
    /// part scaled to the radius, its place along the axis kept): option `radius` (a number
    /// > 0) keeps that radius, `keep_size: true` the radius of the circle fitted to the
    /// vertices' starting positions (`fit_circle`). Give one or neither. The circle's centre
    /// and plane stay free. A bad option leaves the solver unchanged.
    ///
    /// Topic: shape_up
    ///
    /// ```rhai
    /// // A plate with a Ø10 hole squashed to an ellipse of semi-axes 5.3 and 4.8.
    /// let pos = [];
    /// let faces = [];
    /// for k in 0..3 {
    ///     for i in 0..24 {
    ///         let a = i * PI() / 12.0;
    ///         pos.push([(5.3 + 3.0 * k) * cos(a), (4.8 + 3.5 * k) * sin(a), 0]);
    ///     }
    /// }
    /// for k in 0..2 {
    ///     for i in 0..24 {
    ///         let a = 24 * k + i;
    ///         let b = 24 * k + (i + 1) % 24;
    ///         faces.push([a, b, b + 24]);
    ///         faces.push([a, b + 24, a + 24]);
    ///     }
    /// }
    /// let plate = mesh(pos, faces);
    /// let hole = [];
    /// for i in 0..24 { hole.push(i); }
    /// let s = shape_up(plate);
    /// s.circle(hole, 1e6, #{ radius: 5 });
    /// s.closeness(1);
    /// let c = fit_circle(s.solve(60), hole);
    /// assert_near(c.radius, 5.0, 1e-6);       // round again, at its drawn size
    /// assert(c.deviation < 1e-5, `deviation ${c.deviation}`);
    /// ```
    #[rhai_fn(name = "circle", return_raw)]
    pub fn circle_with(s: &mut Solver, verts: Array, w: Number, options: Map) -> ScriptResult<()> {
        const FUNC: &str = "circle";
        let opts = Options::new(FUNC, options, &["radius", "keep_size"])?;
        let v = ids(FUNC, "verts", &verts)?;
        let w = number(FUNC, "w", &w)?;
        let keep = opts.bool("keep_size", false)?;
        let size = match (opts.has("radius"), keep) {
            (true, true) => {
                return fail(FUNC, "options `radius` and `keep_size: true` ask for two sizes: give one");
            }
            (true, false) => {
                let r = opts.number("radius", 0.0)?;
                if r <= 0.0 {
                    return fail(FUNC, format!("option `radius` must be a number > 0, got {r}"));
                }
                CircleSize::Radius(r)
            }
            (false, true) => CircleSize::KeepSize,
            (false, false) => CircleSize::Free,
        };
        match s.system.circle_sized(&v, w, size) {
            Err(e @ SolveError::NoCircle { .. }) => fail(FUNC, format!("option `keep_size`: {e}")),
            r => kernel(FUNC, r),
        }
    }

    /// Keeps `verts` on a plane, with weight `w`.
    ///
    /// ```rhai
    /// let m = uv_sphere(1, 16, 8);
    /// let s = shape_up(m);
    /// let cap = [];
    /// for v in 0..m.vertex_count { if m.positions()[v].z > 0.5 { cap.push(v); } }
    /// s.plane(cap, 100);
    /// s.closeness(0.01);
    /// let flat = s.solve(50);
    /// let z = flat.positions()[cap[0]].z;
    /// for v in cap { assert_near(flat.positions()[v].z, z, 1e-2); }
    /// ```
    #[rhai_fn(return_raw)]
    pub fn plane(s: &mut Solver, verts: Array, w: Number) -> ScriptResult<()> {
        let v = ids("plane", "verts", &verts)?;
        let w = number("plane", "w", &w)?;
        kernel("plane", s.system.plane(&v, w))
    }

    /// Pins `verts` to `positions` (one each), with weight `w`.
    ///
    /// ```rhai
    /// let s = shape_up(cube(2));
    /// s.anchor([0], [[0, 0, 5]], 100);
    /// s.closeness(1);
    /// assert_near(s.solve(10).positions()[0], vec3(0, 0, 5), 0.1);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn anchor(s: &mut Solver, verts: Array, positions: Array, w: Number) -> ScriptResult<()> {
        let v = ids("anchor", "verts", &verts)?;
        let p: Vec<Vec3> = positions
            .iter()
            .enumerate()
            .map(|(i, x)| vec3("anchor", &format!("positions[{i}]"), x))
            .collect::<ScriptResult<_>>()?;
        let w = number("anchor", "w", &w)?;
        kernel("anchor", s.system.anchor(&v, &p, w))
    }

    /// Weights the closeness of every vertex to the starting surface (Eq. 10); 0 turns it off.
    ///
    /// ```rhai
    /// let s = shape_up(cube(2));
    /// s.closeness(1);   // nothing else asked: nothing moves
    /// assert_near(s.solve(5).volume(), 8.0, 1e-9);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn closeness(s: &mut Solver, w: Number) -> ScriptResult<()> {
        let w = number("closeness", "w", &w)?;
        kernel("closeness", s.system.closeness(w))
    }

    /// Weights the cotangent Laplacian of the displacement (Eq. 11); 0 turns it off.
    ///
    /// ```rhai
    /// let s = shape_up(cube(2));
    /// s.laplacian(0.5);
    /// s.closeness(1);
    /// assert_near(s.solve(5).volume(), 8.0, 1e-9);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn laplacian(s: &mut Solver, w: Number) -> ScriptResult<()> {
        let w = number("laplacian", "w", &w)?;
        kernel("laplacian", s.system.laplacian(w))
    }

    /// Runs `iterations` local/global steps (the normal matrix factored once) and returns the
    /// mesh with the solved positions (vertex ids kept). A system with no anchor and no
    /// closeness is refused: its solution would not be unique.
    ///
    /// ```rhai
    /// let s = shape_up(cube(2));
    /// s.plane([0, 1, 2, 3], 1);
    /// let e = "";
    /// try { s.solve(10); } catch (err) { e = `${err}`; }
    /// assert(e.contains("no anchoring term"), e);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn solve(s: &mut Solver, iterations: INT) -> ScriptResult<SharedMesh> {
        if !(0..=100_000).contains(&iterations) {
            return fail("solve", format!("argument `iterations` must be between 0 and 100000, got {iterations}"));
        }
        let factored = kernel("solve", s.system.factor())?;
        let solution = kernel("solve", factored.solve(s.mesh.positions(), iterations as usize))?;
        let mut m = (*s.mesh).clone();
        kernel("solve", m.set_positions(solution.positions))?;
        s.energies = solution.energies;
        Ok(SharedMesh::new(m))
    }

    /// The energy before the first iteration and after each iteration of the last `solve`.
    ///
    /// ```rhai
    /// let m = icosphere(1, 1);
    /// let s = shape_up(m);
    /// s.anchor([0], [[0, 0, 1.5]], 10);
    /// s.laplacian(1);
    /// s.closeness(1);
    /// s.solve(5);
    /// let e = s.energies();
    /// assert_eq(e.len(), 6);
    /// assert(e[5] <= e[0]);
    /// ```
    #[rhai_fn(pure)]
    pub fn energies(s: &mut Solver) -> Array {
        s.energies.iter().map(|&e| Dynamic::from(e)).collect()
    }

    /// The least-squares circle through the vertices `verts` (at least 3) of `mesh`: their plane
    /// by principal components, then the circle in it minimising the squared distances (started
    /// from Kåsa's algebraic fit), so unevenly spaced vertices give the circle, not their
    /// centroid. Returns `#{center, normal, radius, deviation}`: `normal` is the unit normal of
    /// the plane, oriented so that `verts` run counter-clockwise about it, and `deviation` the
    /// largest distance of a vertex from the circle (in and out of its plane).
    ///
    /// Topic: shape_up
    ///
    /// ```rhai
    /// let c = fit_circle(cylinder(0.5, 2, 24), [0, 1, 2, 3, 4, 5]);   // a quarter of the rim
    /// assert_near(c.radius, 0.5, 1e-9);
    /// assert_near(c.center, vec3(0, 0, -1), 1e-9);      // the bottom rim
    /// assert_near(c.normal.z.abs(), 1.0, 1e-9);
    /// assert(c.deviation < 1e-9);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn fit_circle(mesh: SharedMesh, verts: Array) -> ScriptResult<Map> {
        const FUNC: &str = "fit_circle";
        let points = ring_points(FUNC, &mesh, &verts)?;
        let c = verts_error(FUNC, kernel_fit_circle(&points))?;
        let mut m = Map::new();
        m.insert("center".into(), Dynamic::from(c.center));
        m.insert("normal".into(), Dynamic::from(c.normal));
        m.insert("radius".into(), Dynamic::from(c.radius));
        m.insert("deviation".into(), Dynamic::from(c.deviation));
        Ok(m)
    }

    /// Fits the cylinder of a circular feature (§5, Eqs. 13–14) through the vertices `verts` (at
    /// least 3) of `mesh`. Returns `#{center, axis, radius}`: `center` on the axis (the middle of
    /// the feature along it), `radius` the vertices' minimum distance to the axis (Eq. 14). A
    /// feature within a tenth of its radius of one plane (a hole's ring) is fitted as a circle,
    /// its axis the plane's normal (`fit_circle`); a taller one by least squares on the
    /// distances from the cylinder, so unevenly spaced vertices and partial arcs give the
    /// cylinder, not their centroid and principal directions as the paper's PCA would.
    ///
    /// Topic: shape_up
    ///
    /// ```rhai
    /// let bottom = [];
    /// for v in 0..24 { bottom.push(v); }
    /// let c = fit_cylinder(cylinder(0.5, 2, 24), bottom);
    /// assert_near(c.radius, 0.5, 1e-9);
    /// assert_near(c.axis.z.abs(), 1.0, 1e-9);
    /// // A third of the side: both rims' vertices 0-8 and 24-32, off the centroid.
    /// let side = [];
    /// for v in 0..9 { side.push(v); side.push(v + 24); }
    /// let t = fit_cylinder(cylinder(0.5, 2, 24), side);
    /// assert_near(t.radius, 0.5, 1e-9);
    /// assert_near(t.center, vec3(0, 0, 0), 1e-9);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn fit_cylinder(mesh: SharedMesh, verts: Array) -> ScriptResult<Map> {
        fit_cylinder_with(mesh, verts, Map::new())
    }
    /// `fit_cylinder` with option `radius`: `"min"` (default, Eq. 14) or `"mean"`.
    ///
    /// Topic: shape_up
    #[rhai_fn(name = "fit_cylinder", return_raw)]
    pub fn fit_cylinder_with(mesh: SharedMesh, verts: Array, options: Map) -> ScriptResult<Map> {
        let opts = Options::new("fit_cylinder", options, &["radius"])?;
        let rule = match opts.choice("radius", "min", &["min", "mean"])?.as_str() {
            "mean" => RadiusRule::Mean,
            _ => RadiusRule::Minimum,
        };
        let points = ring_points("fit_cylinder", &mesh, &verts)?;
        let c = verts_error("fit_cylinder", kernel_fit_cylinder(&points, rule))?;
        let mut m = Map::new();
        m.insert("center".into(), Dynamic::from(c.center));
        m.insert("axis".into(), Dynamic::from(c.axis));
        m.insert("radius".into(), Dynamic::from(c.radius));
        Ok(m)
    }

    /// Retains circular features on a deformed Loop surface (Tsoi & Hui, Fig. 1): `features` is
    /// an array of vertex-id arrays (one per circular feature of `original`); the result is the
    /// adjusted control mesh (the ids of `deformed`) whose Loop limit surface keeps each
    /// feature's radius. Options: `weights` (`[10, 5, 1]`: shape, closeness, smoothness of the
    /// retention), `size_weights` (`[2, 1]`: size, boundary of the adjustment), `iterations`
    /// (200 per solve), `passes` (20 compensation passes at most; the paper stops at one),
    /// `tolerance` (1e-5, relative radius error), `levels` (0: match the radii on the Loop limit
    /// surface; L > 0: on the feature vertices after L Loop levels). Creases of `deformed` stay
    /// creases of the result and are not enlarged with the shrinkage compensation, so a creased
    /// plate keeps its sharp, flat-edged outline while its holes keep their radii.
    ///
    /// Topic: shape_up
    ///
    /// ```rhai
    /// let t = torus(2, 0.5, 24, 12).triangulate();
    /// let ring = [];
    /// for j in 0..12 { ring.push(j); }
    /// let adjusted = retain_circular_features(t, t, [ring]);
    /// let r = fit_cylinder(adjusted.loop_limit(), ring).radius;
    /// assert(abs(r - 0.5) < 0.5 * 5e-4, `limit radius ${r}`);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn retain_circular_features(
        original: SharedMesh,
        deformed: SharedMesh,
        features: Array,
    ) -> ScriptResult<SharedMesh> {
        retain_circular_features_with(original, deformed, features, Map::new())
    }
    /// `retain_circular_features` with options.
    ///
    /// Topic: shape_up
    #[rhai_fn(name = "retain_circular_features", return_raw)]
    pub fn retain_circular_features_with(
        original: SharedMesh,
        deformed: SharedMesh,
        features: Array,
        options: Map,
    ) -> ScriptResult<SharedMesh> {
        const FUNC: &str = "retain_circular_features";
        let opts =
            Options::new(FUNC, options, &["weights", "size_weights", "iterations", "passes", "tolerance", "levels"])?;
        let d = RetainOptions::default();
        let list = |key: &str, default: &[f64]| -> ScriptResult<Vec<f64>> {
            match opts.raw(key) {
                None => Ok(default.to_vec()),
                Some(v) => match v.clone().try_cast::<Array>() {
                    Some(a) if a.len() == default.len() => {
                        a.iter().enumerate().map(|(i, x)| number(FUNC, &format!("option `{key}`[{i}]"), x)).collect()
                    }
                    _ => fail(FUNC, format!("option `{key}` must be an array of {} numbers", default.len())),
                },
            }
        };
        let w = list("weights", &d.weights)?;
        let sw = list("size_weights", &d.size_weights)?;
        let iterations = opts.int("iterations", d.iterations as INT)?;
        let passes = opts.int("passes", d.passes as INT)?;
        if !(1..=100_000).contains(&iterations) || !(0..=1000).contains(&passes) {
            return fail(FUNC, "options `iterations` (1 to 100000) and `passes` (0 to 1000) are out of range");
        }
        let o = RetainOptions {
            weights: [w[0], w[1], w[2]],
            size_weights: [sw[0], sw[1]],
            iterations: iterations as usize,
            passes: passes as usize,
            tolerance: opts.number("tolerance", d.tolerance)?,
            levels: u32::try_from(opts.int("levels", 0)?)
                .ok()
                .filter(|&l| l <= 6)
                .ok_or_else(|| crate::convert::error(FUNC, "option `levels` must be between 0 and 6"))?,
        };
        let mut feats = Vec::with_capacity(features.len());
        for (i, f) in features.iter().enumerate() {
            match f.clone().try_cast::<Array>() {
                Some(a) => feats.push(ids(FUNC, &format!("features[{i}]"), &a)?),
                None => return fail(FUNC, format!("argument `features[{i}]` must be an array of vertex ids")),
            }
        }
        let (mesh, _) = kernel(FUNC, kernel_retain(&original.0, &deformed.0, &feats, &o))?;
        Ok(SharedMesh::new(mesh))
    }

    /// A one-line summary.
    #[rhai_fn(name = "to_string", name = "to_debug", pure)]
    pub fn to_string(s: &mut Solver) -> String {
        format!("Solver({} vertices)", s.system.vertex_count())
    }
}
