//! `Block` and `BlockModel`: modeling with blocks (Leblanc et al., seed 000; kernel `blocks`) —
//! blocks with sub-face grids and sharp edges, connections, the control mesh and its adaptive,
//! watertight tessellation with optional displacement.
//!
//! # Blocks are edited in place, and their edits return the block itself
//! A block is a description being set up, not a result: `subdivide`, `sharp`, `smooth`,
//! `sharp_all`, `smooth_all`, `b.group = g`, `translate` and `rotate` all change the block they
//! are called on (API.md lists them as statements, `b.translate(v)` beside `b.group = g`), where a
//! `Mesh`'s transforms return a new mesh. Each returns the block itself (a second handle on it,
//! [`Block::same`]), so a chain edits one block: `b.subdivide("+z", 2, 1).sharp_all();` on a
//! variable, `let b = block(lo, hi).subdivide("+y", 4, 1);` on a fresh one. Every other copy
//! is a block of its own (`let c = b;`, an argument, an array element): see
//! [`super::block_handle`]. A failed change leaves the block as it was. `m.add(b)` adds a copy:
//! later changes to `b` do not reach the model.
//!
//! # Nothing connects until `allow`
//! A new model allows no group pair (seed 000 Fig. 5a: blocks that touch stay separate
//! surfaces); `m.allow(g, g)` lets the blocks of group `g` connect with each other, `m.allow(g1,
//! g2)` across two groups. Manual `connect`ions ignore groups.

use blocksmith_kernel::blocks::tessellate::MAX_DEPTH;
use blocksmith_kernel::blocks::{
    Block as KernelBlock, BlockModel as KernelModel, BlockStats, Connection, Edge, Face, MeshOptions, Miss,
};
use blocksmith_kernel::math::fmt_num;
use blocksmith_kernel::Vec3;
use rhai::plugin::*;
use rhai::{exported_module, Array, Engine, Map, INT};

use super::block_handle::Block;
use super::mesh::SharedMesh;
use crate::convert::{error, fail, kernel, number, type_name, vec3, Number, Options, ScriptResult, Vector};

/// A block model as scripts hold it (script type `BlockModel`): the kernel model and the counts
/// of its last meshing (dropped when the model changes).
#[derive(Clone, Debug)]
pub struct BlockModel {
    model: KernelModel,
    stats: Option<BlockStats>,
}

impl BlockModel {
    /// The kernel model (for CSG operands).
    pub(crate) fn kernel_model(&self) -> &KernelModel {
        &self.model
    }

    fn changed(&mut self) -> &mut KernelModel {
        self.stats = None;
        &mut self.model
    }
}

/// Registers the `Block` and `BlockModel` types and every block function on `engine`.
pub fn register(engine: &mut Engine) {
    engine.register_type_with_name::<Block>("Block");
    engine.register_type_with_name::<BlockModel>("BlockModel");
    engine.register_global_module(exported_module!(blocks_api).into());
}

/// The bounds of `points`: (min, max).
fn bounds_of<'a>(points: impl Iterator<Item = &'a Vec3>) -> (Vec3, Vec3) {
    points.fold((Vec3::splat(f64::INFINITY), Vec3::splat(f64::NEG_INFINITY)), |(lo, hi), p| (lo.min(*p), hi.max(*p)))
}

fn face(func: &str, arg: &str, name: &str) -> ScriptResult<Face> {
    Face::parse(name).map_err(|e| error(func, format!("argument `{arg}`: {e}")))
}

fn edges(func: &str, list: &Array) -> ScriptResult<Vec<Edge>> {
    list.iter()
        .enumerate()
        .map(|(i, v)| {
            let s = v.clone().into_string().map_err(|_| {
                error(
                    func,
                    format!("argument `edges[{i}]` must be an edge name such as \"+x+y\", got {}", type_name(v)),
                )
            })?;
            Edge::parse(&s).map_err(|e| error(func, format!("argument `edges[{i}]`: {e}")))
        })
        .collect()
}

fn int(x: u32) -> Dynamic {
    Dynamic::from(INT::from(x))
}

fn connection_map(c: &Connection) -> Map {
    let mut m = Map::new();
    m.insert("a".into(), int(c.a.block));
    m.insert("face_a".into(), Dynamic::from(c.a.face.name().to_string()));
    m.insert("sub_a".into(), int(c.a.sub));
    m.insert("b".into(), int(c.b.block));
    m.insert("face_b".into(), Dynamic::from(c.b.face.name().to_string()));
    m.insert("sub_b".into(), int(c.b.sub));
    m.insert("distance".into(), Dynamic::from(c.distance));
    m.insert("manual".into(), Dynamic::from(c.manual));
    m
}

/// What a [`Miss`] means and what to change, for the warning of `mesh`.
fn miss_message(x: &Miss) -> String {
    let (a, b) = (x.a, x.b);
    let mut msg = format!(
        "block {} touches block {} but does not connect to it, so it is a separate piece of the surface; \
         nearest miss: block {}'s {} sub-face {} and block {}'s {} sub-face {}, {} apart along the normal \
         with centres {} apart across it",
        x.block,
        x.other,
        x.block,
        a.face.name(),
        a.sub,
        x.other,
        b.face.name(),
        b.sub,
        fmt_num(x.gap),
        fmt_num(x.offset)
    );
    if x.gap.abs() >= x.reach {
        msg.push_str(&format!(
            " (sub-faces connect within {} here: raise `m.threshold` or move the blocks closer)",
            fmt_num(x.reach)
        ));
    } else if let Some(d) = x.advice {
        // Worked out from the geometry: the grid whose sub-face centres face every block
        // touching that face, this one included (checked by applying it in the tests).
        msg.push_str(&format!(
            " (sub-faces connect when the rays from their centres hit each other: subdivide block {}'s {} face \
             {} × {} — `b.subdivide(\"{}\", {}, {})` before adding it, or `m.set_block({}, b)` after — so that \
             a sub-face centre lies on block {}'s {} face and every block touching it connects)",
            d.block,
            d.face.name(),
            d.nu,
            d.nv,
            d.face.name(),
            d.nu,
            d.nv,
            d.block,
            x.block,
            a.face.name()
        ));
    } else {
        msg.push_str(&format!(
            " (sub-faces connect when the rays from their centres hit each other: subdivide block {}'s {} face \
             so that a sub-face centre lies over block {})",
            x.other,
            b.face.name(),
            x.block
        ));
    }
    msg.push_str(&format!(
        "; or join them: `m.connect({}, \"{}\", {}, {}, \"{}\", {})`",
        x.block,
        a.face.name(),
        a.sub,
        x.other,
        b.face.name(),
        b.sub
    ));
    msg
}

fn stats_map(s: &BlockStats) -> Map {
    let mut m = Map::new();
    m.insert("blocks".into(), Dynamic::from(s.blocks as INT));
    m.insert("patches".into(), Dynamic::from(s.patches as INT));
    m.insert("sub_patches".into(), Dynamic::from(s.sub_patches as INT));
    m.insert("triangles".into(), Dynamic::from(s.triangles as INT));
    m
}

/// The value a displacement closure returned, as a float.
fn displacement_value(v: &Dynamic) -> Result<f64, String> {
    if let Some(x) = v.clone().try_cast::<f64>() {
        Ok(x)
    } else if let Some(i) = v.clone().try_cast::<INT>() {
        Ok(i as f64)
    } else {
        Err(format!("the closure must return a number, got {}", type_name(v)))
    }
}

/// The error for a `displacement` option that is neither a closure nor a height map.
fn not_displacement(opts: &Options) -> Box<EvalAltResult> {
    let got = opts.raw("displacement").map_or_else(|| "nothing".to_string(), type_name);
    error(
        "mesh",
        format!("option `displacement` must be a closure |p, n, u, v| or a height map (an array of rows of numbers), got {got}"),
    )
}

/// A height map: rows (v from 0 to 1) of equally many numbers (u from 0 to 1), at least 2 × 2.
fn height_map(v: &Dynamic) -> ScriptResult<Vec<Vec<f64>>> {
    let bad = |why: String| error("mesh", format!("option `displacement`: a height map {why}"));
    let rows = v.clone().into_array().map_err(|_| bad("must be an array of rows".into()))?;
    let mut grid = Vec::with_capacity(rows.len());
    for (j, row) in rows.iter().enumerate() {
        let r = row.clone().into_array().map_err(|_| bad(format!("row {j} is {}, not an array", type_name(row))))?;
        let r = r
            .iter()
            .enumerate()
            .map(|(i, x)| number("mesh", &format!("displacement[{j}][{i}]"), x))
            .collect::<ScriptResult<Vec<f64>>>()?;
        grid.push(r);
    }
    let width = grid.first().map_or(0, Vec::len);
    if grid.len() < 2 || width < 2 || grid.iter().any(|r| r.len() != width) {
        return Err(bad(format!(
            "needs at least 2 rows of at least 2 numbers, all rows of one length; got {} rows of lengths {:?}",
            grid.len(),
            grid.iter().map(Vec::len).collect::<Vec<_>>()
        )));
    }
    Ok(grid)
}

/// The height map at (u, v) ∈ [0, 1]², bilinear between its samples (row `j` at v = j / (rows - 1)).
fn bilinear(grid: &[Vec<f64>], u: f64, v: f64) -> f64 {
    let (w, h) = (grid[0].len() - 1, grid.len() - 1);
    let (x, y) = (u.clamp(0.0, 1.0) * w as f64, v.clamp(0.0, 1.0) * h as f64);
    let (i, j) = ((x.floor() as usize).min(w - 1), (y.floor() as usize).min(h - 1));
    let (fx, fy) = (x - i as f64, y - j as f64);
    let row = |j: usize| grid[j][i] * (1.0 - fx) + grid[j][i + 1] * fx;
    row(j) * (1.0 - fy) + row(j + 1) * fy
}

/// Work units (two per patch) from which a meshing reports its progress to the host.
const PROGRESS_FROM: usize = 20_000;

/// Meshes `m` with the options of `options` (checked key by key).
fn mesh_model(ctx: &NativeCallContext, m: &mut BlockModel, options: Map) -> ScriptResult<SharedMesh> {
    let opts = Options::new("mesh", options, &["tolerance", "max_depth", "displacement"])?;
    let mut o = MeshOptions::DEFAULT;
    if opts.has("tolerance") {
        o = o.with_tolerance(opts.number("tolerance", 0.0)?);
    }
    let depth = opts.int("max_depth", INT::from(MeshOptions::DEFAULT.max_depth))?;
    if !(0..=INT::from(MAX_DEPTH)).contains(&depth) {
        return fail("mesh", format!("option `max_depth` must be between 0 and {MAX_DEPTH}, got {depth}"));
    }
    o = o.with_max_depth(depth as u32);
    let map = match opts.raw("displacement") {
        Some(v) if v.is_array() => Some(height_map(v)?),
        _ => None,
    };
    let f = if map.is_some() { None } else { opts.fn_ptr("displacement").map_err(|_| not_displacement(&opts))? };
    // The closure may read the model: mesh a copy, so nothing is borrowed while it runs.
    let model = m.model.clone();
    let mut bar = crate::progress::Meter::at_least("mesh", PROGRESS_FROM as u64);
    let result = {
        let mut progress = |done: usize, total: usize| bar.update(done as u64, total as u64);
        match &f {
            None if map.is_some() => {
                let grid = map.unwrap_or_default();
                let sample = |_p: Vec3, _n: Vec3, u: f64, v: f64| -> Result<f64, String> { Ok(bilinear(&grid, u, v)) };
                model.tessellate_with_progress(&o, Some(&sample), &mut progress)
            }
            None => model.tessellate_with_progress(&o, None, &mut progress),
            Some(f) => {
                let call = |p: Vec3, n: Vec3, u: f64, v: f64| -> Result<f64, String> {
                    let r: Dynamic = f
                        .call_within_context(ctx, (p, n, u, v))
                        .map_err(|e| crate::convert::closure_error("the closure `displacement`", &e))?;
                    displacement_value(&r)
                };
                model.tessellate_with_progress(&o, Some(&call), &mut progress)
            }
        }
    };
    drop(bar);
    let t = kernel("mesh", result)?;
    m.stats = Some(t.stats);
    // Blocks that touch without connecting come out as separate pieces: say so, with the fix.
    // They go with the lint's warnings: `run` and the REPL print them, `blocksmith test` fails.
    let run = crate::context::RunContext::of(ctx);
    for miss in kernel("mesh", model.unconnected())? {
        run.warnings.push(ctx, format!("mesh: {}", miss_message(&miss)));
    }
    // The control mesh goes with the surface, for the studio to draw over it.
    Ok(SharedMesh::with_control(t.mesh, std::sync::Arc::new(t.control)))
}

#[export_module]
pub mod blocks_api {
    use super::*;

    // ---- Blocks -------------------------------------------------------------------------

    /// An axis-aligned block from `min` to `max` (each a `Vec3` or `[x, y, z]`): every face one
    /// sub-face, every edge smooth, group 0. Corner `k` is
    /// `(k&1 ? max.x : min.x, k&2 ? max.y : min.y, k&4 ? max.z : min.z)`.
    ///
    /// Blocks are edited in place: `subdivide`, `sharp`, `smooth`, `sharp_all`, `smooth_all`,
    /// `b.group = g`, `translate` and `rotate` change the block (a `Mesh`'s transforms return a
    /// new mesh instead). Each returns the block itself, so a chain edits one block:
    /// `b.subdivide("+y", 4, 1).sharp_all();` on a variable, `let b = block(lo, hi).sharp_all();`
    /// on a fresh one. `let c = b;` is a copy that changes on its own, while
    /// `let c = b.translate(v);` is b itself. `m.add(b)` adds a copy. Nothing connects until
    /// `m.allow(g1, g2)`.
    ///
    /// Topic: blocks
    ///
    /// ```rhai
    /// let b = block([0, 0, 0], [1, 2, 3]);
    /// assert_eq(b.corners()[6], vec3(0, 2, 3));
    /// assert_near(b.volume(), 6.0, 1e-12);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn block(min: Vector, max: Vector) -> ScriptResult<Block> {
        let (lo, hi) = (vec3("block", "min", &min)?, vec3("block", "max", &max)?);
        kernel("block", KernelBlock::from_bounds(lo, hi)).map(Block::new)
    }

    /// A block from 8 free corners: bit `i` of the index says whether the corner is on the high
    /// side of axis `i`, i.e. corner `k` stands where `(k&1 ? max.x : min.x, k&2 ? max.y :
    /// min.y, k&4 ? max.z : min.z)` would for a box. Faces are bilinear (they need not be
    /// planar). Coincident corners, folded faces and inside-out blocks are errors.
    ///
    /// Topic: blocks
    ///
    /// ```rhai
    /// // A box whose top is skewed by 0.5 in x.
    /// let c = [];
    /// for k in 0..8 {
    ///     let x = if k % 2 == 1 { 1.0 } else { 0.0 };
    ///     let y = if (k / 2) % 2 == 1 { 1.0 } else { 0.0 };
    ///     let z = if k >= 4 { 1.0 } else { 0.0 };
    ///     c.push([x + 0.5 * z, y, z]);
    /// }
    /// let b = block(c);
    /// assert_near(b.volume(), 1.0, 1e-12);
    /// ```
    #[rhai_fn(name = "block", return_raw)]
    pub fn block_from_corners(corners: Array) -> ScriptResult<Block> {
        if corners.len() != 8 {
            return fail("block", format!("argument `corners` must hold 8 corners, got {}", corners.len()));
        }
        let mut c = [Vec3::ZERO; 8];
        for (i, p) in corners.iter().enumerate() {
            c[i] = vec3("block", &format!("corners[{i}]"), p)?;
        }
        kernel("block", KernelBlock::from_corners(c)).map(Block::new)
    }

    /// The 8 corners.
    ///
    /// ```rhai
    /// assert_eq(block([0, 0, 0], [1, 1, 1]).corners()[7], vec3(1, 1, 1));
    /// ```
    #[rhai_fn(pure)]
    pub fn corners(b: &mut Block) -> Array {
        b.read().corners().iter().map(|p| Dynamic::from(*p)).collect()
    }

    /// The block's volume (faces split about their centres; exact for planar faces).
    ///
    /// ```rhai
    /// assert_near(block([0, 0, 0], [2, 2, 2]).volume(), 8.0, 1e-12);
    /// ```
    #[rhai_fn(pure, name = "volume")]
    pub fn block_volume(b: &mut Block) -> f64 {
        b.read().volume()
    }

    /// A one-line summary: group and bounds (what the REPL shows).
    ///
    /// ```rhai
    /// assert_eq(block([0, 0, 0], [1, 2, 3]).to_string(), "Block(group 0, bounds [0, 0, 0]..[1, 2, 3])");
    /// ```
    #[rhai_fn(name = "to_string", name = "to_debug", pure)]
    pub fn block_to_string(b: &mut Block) -> String {
        let b = b.read();
        let (lo, hi) = bounds_of(b.corners().iter());
        format!("Block(group {}, bounds {lo}..{hi})", b.group())
    }

    /// Divides `face` (`"-x" "+x" "-y" "+y" "-z" "+z"`) into `nu × nv` sub-faces, numbered
    /// `i + nu * j`. On a face of axis a, u runs along the first of the other two axes in x, y, z
    /// order and v along the second (on `"+y"`, u along x and v along z). Changes the block in
    /// place and returns it, for a chain (see `blocksmith doc Block`).
    ///
    /// ```rhai
    /// let b = block([0, 0, 0], [1, 1, 1]);
    /// b.subdivide("+y", 4, 1);
    /// assert_eq(b.subface_count("+y"), 4);
    /// assert_eq(b.divisions("+y"), [4, 1]);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn subdivide(b: &mut Block, face_name: &str, nu: INT, nv: INT) -> ScriptResult<Block> {
        let f = face("subdivide", "face", face_name)?;
        kernel("subdivide", b.write().subdivide(f, nu, nv))?;
        Ok(b.same())
    }

    /// The sub-face grid of `face`: `[nu, nv]`.
    ///
    /// ```rhai
    /// assert_eq(block([0, 0, 0], [1, 1, 1]).divisions("-z"), [1, 1]);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn divisions(b: &mut Block, face_name: &str) -> ScriptResult<Array> {
        let (nu, nv) = b.read().divisions(face("divisions", "face", face_name)?);
        Ok(vec![int(nu), int(nv)])
    }

    /// Number of sub-faces of `face`.
    ///
    /// ```rhai
    /// assert_eq(block([0, 0, 0], [1, 1, 1]).subdivide("+x", 2, 3).subface_count("+x"), 6);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn subface_count(b: &mut Block, face_name: &str) -> ScriptResult<INT> {
        Ok(INT::from(b.read().subface_count(face("subface_count", "face", face_name)?)))
    }

    /// Tags `edges` (an array of names of two faces, e.g. `["+x+y", "-z+x"]`; either order)
    /// sharp: the surface keeps a crease there. All or nothing. Changes the block in place and
    /// returns it, for a chain (see `blocksmith doc Block`).
    ///
    /// ```rhai
    /// let b = block([0, 0, 0], [1, 1, 1]);
    /// b.sharp(["+x+y", "+z-x"]);
    /// assert(b.is_sharp("+y+x"), "tagged");
    /// assert(!b.is_sharp("-x-y"), "others stay smooth");
    /// ```
    #[rhai_fn(return_raw)]
    pub fn sharp(b: &mut Block, edge_names: Array) -> ScriptResult<Block> {
        for e in edges("sharp", &edge_names)? {
            b.write().set_sharp(e, true);
        }
        Ok(b.same())
    }

    /// Gives `edges` (names of two faces, as `sharp` takes them) a crease `sharpness`: 0 is
    /// smooth, 10 and more sharp, and a value between makes a semi-sharp edge (DeRose, Kass &
    /// Truong 1998 §3, OpenSubdiv's rules) — a bevel on a smooth block, rounder as the value
    /// falls. It reaches the control mesh, the surface (refined until the sharpness is used up)
    /// and booleans, whose output edges keep it. All or nothing. Changes the block in place and
    /// returns it, for a chain (see `blocksmith doc Block`).
    ///
    /// ```rhai
    /// let b = block([0, 0, 0], [1, 1, 1]);
    /// b.sharp(["+x+y", "+z-x"], 1.5);
    /// assert_eq(b.sharpness("+y+x"), 1.5);
    /// assert(b.is_sharp("+x+y"), "semi-sharp counts as sharp");
    /// assert_eq(b.sharpness("-x-y"), 0.0);
    /// ```
    #[rhai_fn(name = "sharp", return_raw)]
    pub fn sharp_with_sharpness(b: &mut Block, edge_names: Array, sharpness: Number) -> ScriptResult<Block> {
        let s = number("sharp", "sharpness", &sharpness)?;
        if s.is_nan() || s < 0.0 {
            return fail("sharp", format!("argument `sharpness` must be 0 or more, got {s}"));
        }
        let list = edges("sharp", &edge_names)?;
        let mut copy = b.kernel_copy();
        for e in list {
            kernel("sharp", copy.set_sharpness(e, s))?;
        }
        *b.write() = copy;
        Ok(b.same())
    }

    /// The sharpness of `edge`: 0 smooth, 10 sharp (OpenSubdiv's infinite; every value from
    /// 10 up is sharp), between for a semi-sharp edge.
    ///
    /// ```rhai
    /// let b = block([0, 0, 0], [1, 1, 1]).sharp_all();
    /// assert_eq(b.sharpness("+x+z"), 10.0);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn sharpness(b: &mut Block, edge: &str) -> ScriptResult<f64> {
        let e = Edge::parse(edge).map_err(|e| error("sharpness", format!("argument `edge`: {e}")))?;
        Ok(crate::api::subdiv::script_sharpness(b.read().sharpness(e)))
    }

    /// Tags `edges` smooth (the reverse of `sharp`). Changes the block in place and returns it,
    /// for a chain (see `blocksmith doc Block`).
    ///
    /// ```rhai
    /// let b = block([0, 0, 0], [1, 1, 1]).sharp_all();
    /// b.smooth(["+x+y"]);
    /// assert(!b.is_sharp("+x+y") && b.is_sharp("-x+y"), "one edge smooth");
    /// ```
    #[rhai_fn(return_raw)]
    pub fn smooth(b: &mut Block, edge_names: Array) -> ScriptResult<Block> {
        for e in edges("smooth", &edge_names)? {
            b.write().set_sharp(e, false);
        }
        Ok(b.same())
    }

    /// Whether `edge` is sharp.
    ///
    /// ```rhai
    /// assert(!block([0, 0, 0], [1, 1, 1]).is_sharp("+x+z"), "smooth by default");
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn is_sharp(b: &mut Block, edge: &str) -> ScriptResult<bool> {
        let e = Edge::parse(edge).map_err(|e| error("is_sharp", format!("argument `edge`: {e}")))?;
        Ok(b.read().is_sharp(e))
    }

    /// Tags all 12 edges sharp (Fig. 2, red edges). Changes the block in place and returns it,
    /// for a chain (see `blocksmith doc Block`).
    ///
    /// ```rhai
    /// assert(block([0, 0, 0], [1, 1, 1]).sharp_all().is_sharp("-y-z"), "sharp");
    /// // A chain on a variable edits it: both changes reach `b`.
    /// let b = block([0, 0, 0], [1, 1, 1]);
    /// b.subdivide("+z", 2, 2).sharp_all();
    /// assert(b.is_sharp("-y-z") && b.subface_count("+z") == 4, "subdivided and sharp");
    /// ```
    pub fn sharp_all(b: &mut Block) -> Block {
        b.write().sharp_all();
        b.same()
    }

    /// Gives all 12 edges the crease `sharpness`: 0 is smooth (as `smooth_all()`), 10 and more
    /// sharp (as `sharp_all()`), a value between a semi-sharp bevel on every edge. Changes the
    /// block in place and returns it, for a chain (see `blocksmith doc Block`).
    ///
    /// ```rhai
    /// let b = block([0, 0, 0], [1, 1, 1]).sharp_all(2.5);
    /// assert_eq(b.sharpness("+x+y"), 2.5);
    /// assert_eq(b.sharpness("-y-z"), 2.5);
    /// assert(!block([0, 0, 0], [1, 1, 1]).sharp_all(0).is_sharp("+x+y"), "0 is smooth");
    /// ```
    #[rhai_fn(name = "sharp_all", return_raw)]
    pub fn sharp_all_with_sharpness(b: &mut Block, sharpness: Number) -> ScriptResult<Block> {
        let s = number("sharp_all", "sharpness", &sharpness)?;
        if s.is_nan() || s < 0.0 {
            return fail("sharp_all", format!("argument `sharpness` must be 0 or more, got {s}"));
        }
        kernel("sharp_all", b.write().set_sharpness_all(s))?;
        Ok(b.same())
    }

    /// Tags all 12 edges smooth (the default). Changes the block in place and returns it, for a
    /// chain (see `blocksmith doc Block`).
    ///
    /// ```rhai
    /// assert(!block([0, 0, 0], [1, 1, 1]).sharp_all().smooth_all().is_sharp("-y-z"), "smooth");
    /// ```
    pub fn smooth_all(b: &mut Block) -> Block {
        b.write().smooth_all();
        b.same()
    }

    /// Colours the block: `[r, g, b]` or `[r, g, b, a]` (components 0 to 1) or `"#rrggbb"`.
    /// The model's mesh gives the faces made from this block's sub-faces that colour (blocks
    /// without one stay uncoloured), and they keep it through booleans and `save` as a mesh's
    /// colours do. Changes the block in place and returns it, for a chain (see `blocksmith doc
    /// Block`); a bad colour is an error and the block keeps its colour.
    ///
    /// ```rhai
    /// let m = blocks();
    /// m.add(block([0, 0, 0], [2, 1, 1]).sharp_all().color("#8b5a2b"));
    /// m.add(block([3, 0, 0], [4, 1, 1]).sharp_all().color([0, 0.5, 1]));
    /// m.add(block([5, 0, 0], [6, 1, 1]).sharp_all());
    /// let mesh = m.mesh();
    /// assert_eq(mesh.colors().len(), 2);
    /// assert_eq(mesh.colors()[1], [0.0, 0.5, 1.0, 1.0]);   // the third block has none
    /// ```
    #[rhai_fn(name = "color", return_raw)]
    pub fn block_color(b: &mut Block, c: crate::convert::Color) -> ScriptResult<Block> {
        let rgba = crate::api::color::color_value("color", "c", &c)?;
        kernel("color", b.write().set_color(Some(rgba)))?;
        Ok(b.same())
    }

    /// The group id (0 by default); blocks connect only across allowed group pairs.
    ///
    /// ```rhai
    /// let b = block([0, 0, 0], [1, 1, 1]);
    /// b.group = 3;
    /// assert_eq(b.group, 3);
    /// ```
    #[rhai_fn(get = "group", pure)]
    pub fn get_group(b: &mut Block) -> INT {
        b.read().group()
    }

    /// Sets the group id.
    #[rhai_fn(set = "group")]
    pub fn set_group(b: &mut Block, g: INT) {
        b.write().set_group(g);
    }

    /// Moves the block by `v`, in place (see `blocksmith doc block`: blocks are edited, meshes are
    /// transformed into new ones), and returns it, for a chain. An offset that takes a
    /// coordinate to NaN, infinity or beyond ±1e100 is an error and the block stays where it was.
    ///
    /// ```rhai
    /// let b = block([0, 0, 0], [1, 1, 1]);
    /// b.translate([2, 0, 0]);
    /// assert_eq(b.corners()[0], vec3(2, 0, 0));
    /// ```
    #[rhai_fn(name = "translate", return_raw)]
    pub fn block_translate(b: &mut Block, v: Vector) -> ScriptResult<Block> {
        let v = vec3("translate", "v", &v)?;
        kernel("translate", b.write().translate(v))?;
        Ok(b.same())
    }

    /// Turns the block by `deg` degrees about `axis` through the origin (right-handed), in place,
    /// and returns it, for a chain; a zero axis leaves it as it is (as `Mesh.rotate`
    /// does). A non-finite angle is an error and the block stays as it was.
    ///
    /// ```rhai
    /// let b = block([0, 0, 0], [1, 1, 1]).rotate([0, 0, 1], 90);
    /// assert_near(b.corners()[1], [0, 1, 0], 1e-12);
    /// ```
    #[rhai_fn(name = "rotate", return_raw)]
    pub fn block_rotate(b: &mut Block, axis: Vector, deg: Number) -> ScriptResult<Block> {
        let (a, d) = (vec3("rotate", "axis", &axis)?, number("rotate", "deg", &deg)?);
        kernel("rotate", b.write().rotate(a, d))?;
        Ok(b.same())
    }

    // ---- Models -------------------------------------------------------------------------

    /// An empty block model (threshold 0.05, no allowed group pair: nothing connects until
    /// `allow` is called, as in Fig. 5a).
    ///
    /// ```rhai
    /// let m = blocks();
    /// assert_eq(m.block_count, 0);
    /// assert_near(m.threshold, 0.05, 0.0);
    /// ```
    pub fn blocks() -> BlockModel {
        BlockModel { model: KernelModel::new(), stats: None }
    }

    /// Adds a copy of block `b`; returns its id (0, 1, …).
    ///
    /// ```rhai
    /// let m = blocks();
    /// assert_eq(m.add(block([0, 0, 0], [1, 1, 1])), 0);
    /// assert_eq(m.add(block([1, 0, 0], [2, 1, 1])), 1);
    /// ```
    pub fn add(m: &mut BlockModel, b: Block) -> INT {
        INT::from(m.changed().add(b.kernel_copy()))
    }

    /// A one-line summary: block count, bounds and threshold (what the REPL shows).
    ///
    /// ```rhai
    /// let m = blocks();
    /// m.add(block([0, 0, 0], [1, 1, 1]));
    /// m.add(block([1, 0, 0], [2, 1, 1]));
    /// assert_eq(m.to_string(), "BlockModel(2 blocks, bounds [0, 0, 0]..[2, 1, 1], threshold 0.05)");
    /// ```
    #[rhai_fn(name = "to_string", name = "to_debug", pure)]
    pub fn model_to_string(m: &mut BlockModel) -> String {
        let blocks = m.model.blocks();
        if blocks.is_empty() {
            return format!("BlockModel(0 blocks, threshold {})", m.model.threshold());
        }
        let (lo, hi) = bounds_of(blocks.iter().flat_map(|b| b.corners().to_vec()).collect::<Vec<_>>().iter());
        format!("BlockModel({} blocks, bounds {lo}..{hi}, threshold {})", blocks.len(), m.model.threshold())
    }

    /// Number of blocks.
    ///
    /// ```rhai
    /// let m = blocks();
    /// m.add(block([0, 0, 0], [1, 1, 1]));
    /// m.add(block([1, 0, 0], [2, 1, 1]));
    /// assert_eq(m.block_count, 2);
    /// ```
    #[rhai_fn(get = "block_count", pure)]
    pub fn block_count(m: &mut BlockModel) -> INT {
        m.model.blocks().len() as INT
    }

    /// A copy of block `id` (editing it leaves the model as it is: write it back with
    /// `m.set_block(id, b)`).
    ///
    /// ```rhai
    /// let m = blocks();
    /// m.add(block([0, 0, 0], [1, 1, 1]));
    /// assert_eq(m.block(0).corners()[7], vec3(1, 1, 1));
    /// ```
    #[rhai_fn(name = "block", pure, return_raw)]
    pub fn model_block(m: &mut BlockModel, id: INT) -> ScriptResult<Block> {
        kernel("block", m.model.block(id)).map(|b| Block::new(b.clone()))
    }

    /// Replaces block `id` with a copy of `b`: how a block is edited after it was added
    /// (`let top = m.block(0); top.subdivide("-z", 6, 6); m.set_block(0, top);`). Manual
    /// connections to the block stay; one naming a sub-face `b` does not have is an error, and
    /// the model is left as it was.
    ///
    /// ```rhai
    /// let m = blocks();
    /// m.allow(0, 0);
    /// let id = m.add(block([0, 0, 1], [2, 2, 1.2]));        // a table top
    /// m.add(block([0, 0, 0], [0.2, 0.2, 1]));               // a leg under its corner
    /// assert_eq(m.connections().len(), 0);                  // the top's one centre misses the leg
    /// let top = m.block(id);
    /// top.subdivide("-z", 6, 6);
    /// m.set_block(id, top);
    /// assert_eq(m.connections().len(), 1);
    /// assert_eq(m.block(id).subface_count("-z"), 36);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn set_block(m: &mut BlockModel, id: INT, b: Block) -> ScriptResult<()> {
        // The kernel leaves the model as it was on error; the last mesh's stats go only on success.
        kernel("set_block", m.model.set_block(id, b.kernel_copy()))?;
        m.changed();
        Ok(())
    }

    /// Lets blocks of groups `g1` and `g2` connect (either order; `allow(g, g)` within a group).
    ///
    /// ```rhai
    /// let m = blocks();
    /// m.add(block([0, 0, 0], [1, 1, 1]));
    /// m.add(block([1, 0, 0], [2, 1, 1]));
    /// assert_eq(m.connections().len(), 0);
    /// m.allow(0, 0);
    /// assert_eq(m.connections().len(), 1);
    /// ```
    pub fn allow(m: &mut BlockModel, g1: INT, g2: INT) {
        m.changed().allow(g1, g2);
    }

    /// The connection threshold: sub-faces A and B connect only when their distance is below
    /// `threshold × (perimeter(A) + perimeter(B))` (scale invariant).
    ///
    /// ```rhai
    /// let m = blocks();
    /// m.allow(0, 0);
    /// m.add(block([0, 0, 0], [1, 1, 1]));
    /// m.add(block([1.5, 0, 0], [2.5, 1, 1]));
    /// assert_eq(m.connections().len(), 0);
    /// m.threshold = 0.1;
    /// assert_near(m.connections()[0].distance, 0.5, 1e-12);
    /// ```
    #[rhai_fn(get = "threshold", pure)]
    pub fn get_threshold(m: &mut BlockModel) -> f64 {
        m.model.threshold()
    }

    /// Sets the connection threshold (a number ≥ 0).
    #[rhai_fn(set = "threshold", return_raw)]
    pub fn set_threshold(m: &mut BlockModel, t: Number) -> ScriptResult<()> {
        let t = number("threshold", "threshold", &t)?;
        kernel("threshold", m.model.set_threshold(t))?;
        m.stats = None;
        Ok(())
    }

    /// A manual connection: sub-face `sub_a` of face `face_a` of block `a` joins sub-face `sub_b`
    /// of `face_b` of block `b`, whatever their distance and groups. Neither sub-face nor the
    /// block pair gets another connection.
    ///
    /// ```rhai
    /// let m = blocks();
    /// m.add(block([0, 0, 0], [1, 1, 1]));
    /// m.add(block([3, 0, 0], [4, 1, 1]));
    /// m.connect(0, "+x", 0, 1, "-x", 0);
    /// let c = m.connections();
    /// assert_eq(c.len(), 1);
    /// assert(c[0].manual, "manual");
    /// assert_eq(m.control_mesh().face_count, 40);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn connect(
        m: &mut BlockModel,
        a: INT,
        face_a: &str,
        sub_a: INT,
        b: INT,
        face_b: &str,
        sub_b: INT,
    ) -> ScriptResult<()> {
        let fa = face("connect", "face_a", face_a)?;
        let fb = face("connect", "face_b", face_b)?;
        kernel("connect", m.model.connect(a, fa, sub_a, b, fb, sub_b))?;
        m.stats = None;
        Ok(())
    }

    /// Every connection: `#{a, face_a, sub_a, b, face_b, sub_b, distance, manual}`. Found ones
    /// come from a ray cast from each sub-face centre along its normal: different blocks, allowed
    /// groups, within the threshold, mutual nearest, one (the shortest) per block pair.
    ///
    /// ```rhai
    /// let m = blocks();
    /// m.allow(0, 0);
    /// m.add(block([0, 0, 0], [1, 1, 1]));
    /// m.add(block([0, 0, 1], [1, 1, 2]));
    /// let c = m.connections()[0];
    /// assert_eq([c.a, c.face_a, c.b, c.face_b], [0, "+z", 1, "-z"]);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn connections(m: &mut BlockModel) -> ScriptResult<Array> {
        let c = kernel("connections", m.model.connections())?;
        Ok(c.iter().map(|c| Dynamic::from_map(connection_map(c))).collect())
    }

    /// The control mesh: exterior sub-faces joined watertight (T-vertices make n-gons), creases
    /// where block edges are sharp, after one Catmull–Clark step: quads only.
    ///
    /// ```rhai
    /// let m = blocks();
    /// m.add(block([0, 0, 0], [1, 1, 1]).sharp_all());
    /// let c = m.control_mesh();
    /// assert_eq(c.face_count, 24);
    /// assert_eq(c.crease_count(), 24);
    /// assert(c.is_closed(), "closed");
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn control_mesh(m: &mut BlockModel) -> ScriptResult<SharedMesh> {
        kernel("control_mesh", m.model.control_mesh()).map(|c| SharedMesh::new(c.mesh))
    }

    /// The model's surface as a closed, manifold triangle mesh, with default options.
    /// `model.to_mesh()` is the same, named as `pm.to_mesh()` and `vx.to_mesh()` are.
    ///
    /// ```rhai
    /// let m = blocks();
    /// m.add(block([0, 0, 0], [1, 1, 1]).sharp_all());
    /// assert_near(m.mesh().volume(), 1.0, 1e-9);
    /// ```
    #[rhai_fn(name = "mesh", name = "to_mesh", return_raw)]
    pub fn model_mesh(ctx: NativeCallContext, m: &mut BlockModel) -> ScriptResult<SharedMesh> {
        mesh_model(&ctx, m, Map::new())
    }

    /// The model's surface as a closed, manifold triangle mesh: each control-mesh quad is a patch
    /// of the limit surface, split adaptively in u, v or both until every row and column of
    /// samples is within `tolerance` of its chord (default 0.001 × the model's diagonal), at most
    /// `max_depth` times per direction (default 8, at most 14); neighbouring patches share their
    /// edge points, so there are no cracks. `displacement` is a closure `|p, n, u, v|` returning
    /// the offset along the unit normal `n` at `p`, where `(u, v)` is the block-face parameter,
    /// or a height map: an array of rows (v from 0 to 1) of offsets (u from 0 to 1), sampled
    /// bilinearly on every face.
    ///
    /// ```rhai
    /// let m = blocks();
    /// m.add(block([-1, -1, -1], [1, 1, 1]).sharp_all());
    /// let bumpy = m.mesh(#{ tolerance: 0.01, displacement: |p, n, u, v| 0.1 * sin(PI() * u) * sin(PI() * v) });
    /// assert(bumpy.is_closed() && bumpy.is_manifold(), "watertight");
    /// assert(bumpy.volume() > 8.0, "bumps outward");
    /// assert(m.stats().sub_patches > m.stats().patches, "adaptive");
    /// // A 3 × 3 height map raising the middle of every face.
    /// let raised = m.mesh(#{ displacement: [[0, 0, 0], [0, 0.2, 0], [0, 0, 0]] });
    /// assert_near(raised.bounds().max.z, 1.2, 1e-9);
    /// ```
    #[rhai_fn(name = "mesh", name = "to_mesh", return_raw)]
    pub fn model_mesh_with(ctx: NativeCallContext, m: &mut BlockModel, options: Map) -> ScriptResult<SharedMesh> {
        mesh_model(&ctx, m, options)
    }

    /// The ids of the blocks that touch a block they may connect with (bounds touching or
    /// overlapping, groups allowed) but end up in another piece of the surface than the
    /// largest piece of what they touch — a table leg under the corner of a one-sub-face top
    /// (connections join sub-faces whose centres face each other). `mesh` warns of each with
    /// its nearest miss and the fix.
    ///
    /// ```rhai
    /// let m = blocks();
    /// m.allow(0, 0);
    /// m.add(block([0, 0, 1], [2, 2, 1.2]));
    /// m.add(block([0, 0, 0], [0.2, 0.2, 1]));
    /// assert_eq(m.unconnected(), [1]);
    /// // Under the centre of one of 10 × 10 sub-faces of the top's underside, the leg connects.
    /// let fixed = blocks();
    /// fixed.allow(0, 0);
    /// fixed.add(block([0, 0, 1], [2, 2, 1.2]).subdivide("-z", 10, 10));
    /// fixed.add(block([0, 0, 0], [0.2, 0.2, 1]));
    /// assert_eq(fixed.unconnected(), []);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn unconnected(m: &mut BlockModel) -> ScriptResult<Array> {
        let misses = kernel("unconnected", m.model.unconnected())?;
        Ok(misses.iter().map(|x| int(x.block)).collect())
    }

    /// Counts of the last `mesh` (meshing with default options first if the model changed since):
    /// `#{blocks, patches, sub_patches, triangles}`.
    ///
    /// ```rhai
    /// let m = blocks();
    /// m.add(block([0, 0, 0], [1, 1, 1]));
    /// let s = m.stats();
    /// assert_eq([s.blocks, s.patches], [1, 24]);
    /// assert(s.triangles >= 2 * s.sub_patches, "two or more triangles per sub-patch");
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn stats(ctx: NativeCallContext, m: &mut BlockModel) -> ScriptResult<Map> {
        if m.stats.is_none() {
            mesh_model(&ctx, m, Map::new())?;
        }
        let s = m.stats.ok_or_else(|| error("stats", "no counts after meshing (please file an issue)"))?;
        Ok(stats_map(&s))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use blocksmith_kernel::blocks::MAX_SUBDIVISIONS;

    #[test]
    fn subdivision_limits_are_reported() {
        let mut b = Block::new(KernelBlock::from_bounds(Vec3::ZERO, Vec3::ONE).unwrap());
        let e = blocks_api::subdivide(&mut b, "+q", 1, 1).unwrap_err().to_string();
        assert!(e.contains("subdivide: argument `face`: unknown face \"+q\""), "{e}");
        let e = blocks_api::subdivide(&mut b, "+x", 0, 1).unwrap_err().to_string();
        assert!(e.contains("at least one division"), "{e}");
        let n = INT::from(MAX_SUBDIVISIONS) + 1;
        assert!(blocks_api::subdivide(&mut b, "+x", n, 1).is_err());
    }
}
