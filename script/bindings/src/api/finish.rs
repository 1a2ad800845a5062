//! Surface finishing on `Mesh` (kernel `finish`): sharp edges by angle (`smooth`), smooth
//! refinement (`refine`, `refine_to_length`), isotropic remeshing (`remesh`), quadric
//! decimation (`decimate`), relaxation (`relax`) and closures moving every vertex (`warp`).
//! Each keeps the mesh closed and manifold and every face's colour and part.

use blocksmith_kernel::finish::{
    self, DecimateOptions, DecimateReport, DecimateTarget, RelaxMethod, RelaxOptions, RemeshOptions, RemeshReport,
    DEFAULT_SHARP_ANGLE,
};
use blocksmith_kernel::{Mesh, Vec3};
use rhai::plugin::*;
use rhai::{exported_module, Engine, FnPtr, Map, INT};

use super::mesh::SharedMesh;
use crate::convert::{closure_error, fail, kernel, number, vec3, Number, Options, ScriptResult};

fn remesh_map(r: &RemeshReport) -> Map {
    let mut m = Map::new();
    m.insert("volume_before".into(), Dynamic::from(r.volume_before));
    m.insert("volume_after".into(), Dynamic::from(r.volume_after));
    m.insert("volume_change".into(), Dynamic::from((r.volume_after - r.volume_before) / r.volume_before));
    m.insert("distance_to_input".into(), Dynamic::from(r.distance_to_input));
    m.insert("min_angle".into(), Dynamic::from(r.min_angle));
    m.insert("mean_edge".into(), Dynamic::from(r.mean_edge));
    m.insert("edge_deviation".into(), Dynamic::from(r.edge_deviation));
    m
}

fn decimate_map(r: &DecimateReport) -> Map {
    let mut m = Map::new();
    m.insert("triangles_before".into(), Dynamic::from(r.triangles_before as INT));
    m.insert("triangles_after".into(), Dynamic::from(r.triangles_after as INT));
    m.insert("max_error".into(), Dynamic::from(r.max_error));
    m
}

fn remesh_options(o: &Options) -> ScriptResult<RemeshOptions> {
    if !o.has("edge_length") {
        return fail("remesh", "option `edge_length` is required (the target length of the new edges)");
    }
    let d = RemeshOptions::default();
    let iterations = o.int("iterations", INT::from(d.iterations))?;
    if !(1..=100).contains(&iterations) {
        return fail("remesh", format!("option `iterations` must be between 1 and 100, got {iterations}"));
    }
    Ok(RemeshOptions {
        edge_length: o.number("edge_length", d.edge_length)?,
        iterations: iterations as u32,
        sharp_angle: o.number("sharp_angle", d.sharp_angle)?,
    })
}

/// `decimate` with `options` checked, reported to the host's progress: the mesh and the report.
fn decimated(m: &SharedMesh, options: Map) -> ScriptResult<(Mesh, DecimateReport)> {
    let o = Options::new("decimate", options, &["ratio", "triangles", "error"])?;
    let opts = decimate_options(&o)?;
    let _bar = crate::progress::bar("decimate");
    kernel("decimate", finish::decimate(&m.0, opts))
}

fn decimate_options(o: &Options) -> ScriptResult<DecimateOptions> {
    let given: Vec<&str> = ["ratio", "triangles", "error"].into_iter().filter(|k| o.has(k)).collect();
    if given.len() != 1 {
        return fail(
            "decimate",
            format!("give exactly one of the options `ratio`, `triangles` or `error`, got {}", given.len()),
        );
    }
    let target = match given[0] {
        "ratio" => DecimateTarget::Ratio(o.number("ratio", 1.0)?),
        "triangles" => {
            let n = o.int("triangles", 4)?;
            if n < 4 {
                return fail("decimate", format!("option `triangles` must be at least 4, got {n}"));
            }
            DecimateTarget::Triangles(n as usize)
        }
        _ => DecimateTarget::Error(o.number("error", 0.0)?),
    };
    Ok(DecimateOptions { target })
}

/// Registers the surface-finishing functions on `engine`.
pub fn register(engine: &mut Engine) {
    engine.register_global_module(exported_module!(finish_api).into());
}

#[export_module]
pub mod finish_api {
    use super::*;

    /// This mesh with its edges tagged for smoothing: an edge whose faces' normals differ by more
    /// than `sharp_angle` degrees (default 60; 0–180) becomes a sharp crease, every other edge
    /// smooth (earlier crease tags are replaced). Nothing moves: `refine` and
    /// `refine_to_length` then make the smooth surface through the mesh, keeping the sharp
    /// edges sharp (Manifold's `SmoothOut` then `Refine`).
    ///
    /// ```rhai
    /// let c = cube(2).smooth(#{sharp_angle: 60});
    /// assert_eq(c.crease_count(), 12);
    /// let r = c.refine(4);                 // still the cube: its 12 edges stay sharp
    /// assert_near(r.volume(), 8.0, 1e-9);
    /// assert_eq(r.face_count, 12 * 16);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn smooth(m: &mut SharedMesh, options: Map) -> ScriptResult<SharedMesh> {
        let o = Options::new("smooth", options, &["sharp_angle"])?;
        let angle = o.number("sharp_angle", DEFAULT_SHARP_ANGLE)?;
        kernel("smooth", finish::sharp_edges(&m.0, angle)).map(SharedMesh::new)
    }

    /// `smooth(#{sharp_angle: 60})`.
    ///
    /// ```rhai
    /// assert_eq(cylinder(1, 2, 24).smooth().crease_count(), 48);   // the two rims
    /// ```
    #[rhai_fn(pure, return_raw, name = "smooth")]
    pub fn smooth_default(m: &mut SharedMesh) -> ScriptResult<SharedMesh> {
        smooth(m, Map::new())
    }

    /// The smooth surface through this closed mesh, every edge split into `n` pieces and every
    /// triangle into n² (1–1000). New vertices lie on curved patches whose tangents follow the
    /// vertex normals (Manifold's `Refine`); the input vertices stay where they are. Crease
    /// edges (from `smooth(#{sharp_angle})` or `crease`) stay sharp; an untagged mesh is smooth
    /// everywhere, as with `catmull_clark`. Colours and parts follow their faces; creases
    /// are kept. Refused before allocating when n² × triangles is over 50 million.
    ///
    /// ```rhai
    /// let ball = icosphere(1, 1).refine(4);
    /// assert_eq(ball.face_count, 80 * 16);
    /// assert(ball.is_closed() && ball.genus() == 0);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn refine(m: &mut SharedMesh, n: INT) -> ScriptResult<SharedMesh> {
        if !(1..=INT::from(finish::MAX_REFINE)).contains(&n) {
            return fail("refine", format!("argument `n` must be between 1 and {}, got {n}", finish::MAX_REFINE));
        }
        let _task = crate::progress::start("refine", None);
        kernel("refine", finish::refine(&m.0, n as u32)).map(SharedMesh::new)
    }

    /// `refine` with each edge split into ⌊its length / `length`⌋ + 1 pieces, so straight
    /// pieces are at most `length` long (curved ones a little longer).
    ///
    /// ```rhai
    /// let t = torus(2, 0.6, 16, 8).color("#ff0000").refine_to_length(0.25);
    /// assert_eq(t.genus(), 1);
    /// assert_eq(t.colors(), [[1.0, 0.0, 0.0, 1.0]]);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn refine_to_length(m: &mut SharedMesh, length: Number) -> ScriptResult<SharedMesh> {
        let l = number("refine_to_length", "length", &length)?;
        let _task = crate::progress::start("refine_to_length", None);
        kernel("refine_to_length", finish::refine_to_length(&m.0, l)).map(SharedMesh::new)
    }

    /// This closed mesh remeshed to near-equilateral triangles of edge `edge_length` (required)
    /// by isotropic remeshing (Botsch & Kobbelt 2004: split long edges, collapse short ones,
    /// flip towards valence 6, relax tangentially, project back onto the input). Options:
    /// `iterations` (1–100, default 10), `sharp_angle` (default 60: edges sharper than it are
    /// kept, as are crease-tagged edges and the borders between colours). Colours and parts
    /// follow their faces. Refused before allocating when the surface area over the target
    /// triangle's area is beyond 50 million triangles. `remesh_report` gives the numbers.
    ///
    /// ```rhai
    /// let plate = box([-10, -5, -1], [10, 5, 1]) - cylinder(2, 4, 32).translate([-5, 0, 0]);
    /// let m = plate.remesh(#{edge_length: 1.0, iterations: 3});
    /// assert(m.is_closed() && m.genus() == 1);
    /// assert(abs(m.volume() - plate.volume()) < 0.005 * plate.volume());
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn remesh(m: &mut SharedMesh, options: Map) -> ScriptResult<SharedMesh> {
        remesh_report(m, options).and_then(|r| {
            r.get("mesh")
                .and_then(|v| v.clone().try_cast::<SharedMesh>())
                .ok_or_else(|| crate::convert::error("remesh", "no mesh"))
        })
    }

    /// `remesh` with what it did: `#{mesh, volume_before, volume_after, volume_change`
    /// (relative)`, distance_to_input` (largest distance of a new vertex from the input
    /// surface)`, min_angle` (degrees)`, mean_edge, edge_deviation}`.
    ///
    /// ```rhai
    /// let r = icosphere(1, 2).remesh_report(#{edge_length: 0.2, iterations: 4});
    /// assert(abs(r.volume_change) < 0.02);
    /// assert(r.min_angle > 20.0);
    /// assert(abs(r.mean_edge - 0.2) < 0.04);
    /// assert(r.mesh.is_closed());
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn remesh_report(m: &mut SharedMesh, options: Map) -> ScriptResult<Map> {
        let o = Options::new("remesh", options, &["edge_length", "iterations", "sharp_angle"])?;
        let opts = remesh_options(&o)?;
        let _bar = crate::progress::bar("remesh");
        let (mesh, report) = kernel("remesh", finish::remesh(&m.0, opts))?;
        let mut map = remesh_map(&report);
        map.insert("mesh".into(), Dynamic::from(SharedMesh::new(mesh)));
        Ok(map)
    }

    /// This closed mesh with fewer triangles, by quadric error (Garland & Heckbert 1997): the
    /// edges whose collapse changes the surface least go first. Exactly one option: `ratio`
    /// (share of the triangles kept, above 0 and at most 1), `triangles` (how many to keep, at
    /// least 4) or `error` (stop before a collapse whose error — about its distance from the
    /// input's planes — is larger). Crease edges and colour borders are kept; colours and
    /// parts follow their faces. `decimate_report` gives the numbers.
    ///
    /// ```rhai
    /// let fine = icosphere(1, 4);                       // 5120 triangles
    /// let coarse = fine.decimate(#{triangles: 500});
    /// assert(coarse.face_count <= 500 && coarse.is_closed());
    /// assert_eq(cube(2).smooth().refine(8).decimate(#{error: 1e-9}).face_count, 12);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn decimate(m: &mut SharedMesh, options: Map) -> ScriptResult<SharedMesh> {
        decimated(m, options).map(|(mesh, _)| SharedMesh::new(mesh))
    }

    /// `decimate` with what it did: `#{mesh, triangles_before, triangles_after, max_error}`.
    ///
    /// ```rhai
    /// let r = torus(3, 1, 48, 24).decimate_report(#{ratio: 0.25});
    /// assert_eq(r.triangles_before, 2304);
    /// assert(r.triangles_after <= 576 && r.mesh.genus() == 1);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn decimate_report(m: &mut SharedMesh, options: Map) -> ScriptResult<Map> {
        let (mesh, report) = decimated(m, options)?;
        let mut map = decimate_map(&report);
        map.insert("mesh".into(), Dynamic::from(SharedMesh::new(mesh)));
        Ok(map)
    }

    /// This mesh with its vertices moved towards the mean of their neighbours: `method`
    /// `"taubin"` (default: Taubin's λ|μ steps, smooths without shrinking) or `"laplacian"`
    /// (smoother, but shrinks), `iterations` (1–10000, default 10). Vertices on crease edges
    /// and on the boundary stay. Every id, colour and part is kept.
    ///
    /// ```rhai
    /// let r = rng(1);
    /// let ball = icosphere(1, 3);
    /// let rough = ball.warp(|p| p * (1.0 + 0.03 * r.range(-1, 1)));
    /// let smooth = rough.relax(#{iterations: 10});
    /// assert(abs(smooth.volume() - ball.volume()) < 0.02 * ball.volume());
    /// assert(rough.relax(#{method: "laplacian"}).volume() < 0.95 * ball.volume());
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn relax(m: &mut SharedMesh, options: Map) -> ScriptResult<SharedMesh> {
        let o = Options::new("relax", options, &["iterations", "method"])?;
        let iterations = o.int("iterations", 10)?;
        if !(1..=10_000).contains(&iterations) {
            return fail("relax", format!("option `iterations` must be between 1 and 10000, got {iterations}"));
        }
        let method = match o.choice("method", "taubin", &["taubin", "laplacian"])?.as_str() {
            "laplacian" => RelaxMethod::Laplacian,
            _ => RelaxMethod::Taubin,
        };
        let _bar = crate::progress::bar("relax");
        kernel("relax", finish::relax(&m.0, RelaxOptions { iterations: iterations as u32, method }))
            .map(SharedMesh::new)
    }

    /// This mesh with every vertex moved by the closure `f(p)` → new position (a `Vec3` or
    /// `[x, y, z]`); ids, colours, parts and creases kept. Refused when the result crosses
    /// itself and the input did not (an exact test over all faces, O(n log n)), or when a
    /// closed mesh is turned inside out.
    ///
    /// ```rhai
    /// let wavy = box([0, 0, 0], [10, 10, 1]).remesh(#{edge_length: 0.5, iterations: 2})
    ///     .warp(|p| p + vec3(0, 0, 0.3 * noise(p, #{frequency: 0.3, seed: 2})));
    /// assert(wavy.is_closed());
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn warp(ctx: NativeCallContext, m: &mut SharedMesh, f: FnPtr) -> ScriptResult<SharedMesh> {
        let mut moved: Vec<Vec3> = Vec::with_capacity(m.0.vertex_count());
        for (i, &p) in m.0.positions().iter().enumerate() {
            let out: Dynamic = f
                .call_within_context(&ctx, (p,))
                .map_err(|e| crate::convert::error("warp", closure_error("the closure", &e)))?;
            moved.push(vec3("warp", &format!("the closure's result for vertex {i}"), &out)?);
        }
        let mut mesh = (*m.0).clone();
        kernel("warp", mesh.set_positions(moved))?;
        if m.0.is_closed() && m.0.volume() > 0.0 && mesh.volume() <= 0.0 {
            return fail(
                "warp",
                format!("the moved mesh is turned inside out (volume {}): move the vertices less", mesh.volume()),
            );
        }
        let crossed = kernel("warp", blocksmith_kernel::diagnose::self_intersections(&mesh))?;
        if let Some(pair) = crossed.first() {
            let before = kernel("warp", blocksmith_kernel::diagnose::self_intersections(&m.0))?;
            if before.is_empty() {
                return fail(
                    "warp",
                    format!(
                        "the moved mesh crosses itself ({} pairs of faces, the first faces {} and {}): move the vertices less",
                        crossed.len(),
                        pair[0],
                        pair[1]
                    ),
                );
            }
        }
        Ok(SharedMesh::new(mesh))
    }
}
