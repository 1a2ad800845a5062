//! `Voxels`: voxel sculpting with Haar levels of detail and rotated discrete tools
//! (Heurtebise & Thon; kernel `voxel`).

use std::rc::Rc;

use blocksmith_kernel::math::fmt_num;
use blocksmith_kernel::math::Quat;
use blocksmith_kernel::voxel::{
    haar1d as k_haar1d, ihaar1d as k_ihaar1d, SculptMode, SculptOptions, Surface, Voxels as KernelVoxels, DEFAULT_ISO,
};
use rhai::plugin::*;
use rhai::{exported_module, Array, Engine, Map, INT};

use super::mesh::SharedMesh;
use crate::convert::{
    factor3, fail, kernel, number, type_name, vec3, Number, NumberOrVector, Options, ScriptResult, Vector,
};

/// A voxel grid as scripts hold it (script type `Voxels`): shared and copied on write, like
/// meshes, so passing a grid (e.g. as a tool) is cheap and no script ever sees another variable's
/// grid change. Operations that fill or sculpt change the grid they are called on.
#[derive(Clone, Debug)]
pub struct Voxels(pub Rc<KernelVoxels>);

impl Voxels {
    fn get_mut(&mut self) -> &mut KernelVoxels {
        Rc::make_mut(&mut self.0)
    }
}

/// Registers the `Voxels` type and every voxel function on `engine`.
pub fn register(engine: &mut Engine) {
    engine.register_type_with_name::<Voxels>("Voxels");
    engine.register_global_module(exported_module!(voxel_api).into());
}

fn size(func: &str, arg: &str, n: INT) -> ScriptResult<usize> {
    KernelVoxels::check_size(n).map_err(|e| crate::convert::error(func, format!("argument `{arg}`: {e}")))
}

fn level(func: &str, v: &Dynamic) -> ScriptResult<INT> {
    v.as_int().or_else(|_| fail(func, format!("option `level` must be an integer, got {}", type_name(v))))
}

/// One turn of a `rotate` list: `[axis, degrees]`, the axis a vector or `"x"`, `"y"`, `"z"`.
fn turn(i: usize, v: &Dynamic) -> ScriptResult<Quat> {
    let what = format!("option `rotate`[{i}]");
    let Some(pair) = v.read_lock::<Array>().filter(|a| a.len() == 2) else {
        return fail("sculpt", format!("{what} must be a pair [axis, degrees], got {}", type_name(v)));
    };
    let axis = match pair[0].clone().into_string() {
        Ok(name) => match name.as_str() {
            "x" => blocksmith_kernel::Vec3::X,
            "y" => blocksmith_kernel::Vec3::Y,
            "z" => blocksmith_kernel::Vec3::Z,
            other => return fail("sculpt", format!("{what}: axis \"{other}\" is not one of \"x\", \"y\", \"z\"")),
        },
        Err(_) => vec3("sculpt", &format!("option rotate[{i}][0]"), &pair[0])?,
    };
    let Some(axis) = axis.try_normalize() else {
        return fail("sculpt", format!("{what}: the axis {axis} has no direction"));
    };
    let deg = number("sculpt", &format!("option rotate[{i}][1]"), &pair[1])?;
    Ok(Quat::from_axis_angle(axis, deg.to_radians()))
}

/// The rotation a sculpt's options give: `rotate` (turns applied in order), `quaternion`
/// (`[x, y, z, w]`), or `axis`/`angle` (None: the kernel takes those); at most one way.
fn sculpt_rotation(opts: &Options) -> ScriptResult<Option<Quat>> {
    let given: Vec<&str> = ["rotate", "quaternion", "axis", "angle"].into_iter().filter(|k| opts.has(k)).collect();
    let ways = usize::from(opts.has("rotate"))
        + usize::from(opts.has("quaternion"))
        + usize::from(opts.has("axis") || opts.has("angle"));
    if ways > 1 {
        return fail(
            "sculpt",
            format!(
                "options {} each give a rotation: use one of `rotate`, `quaternion` or `axis`/`angle`",
                given.join(", ")
            ),
        );
    }
    if let Some(list) = opts.raw("rotate") {
        let Some(list) = list.read_lock::<Array>() else {
            return fail(
                "sculpt",
                format!("option `rotate` must be a list of [axis, degrees] turns, got {}", type_name(list)),
            );
        };
        // The first turn is applied first: q = qₙ ⋯ q₂ q₁.
        return list.iter().enumerate().try_fold(Quat::IDENTITY, |q, (i, t)| Ok(turn(i, t)? * q)).map(Some);
    }
    if let Some(q) = opts.raw("quaternion") {
        let Some(a) = q.read_lock::<Array>().filter(|a| a.len() == 4) else {
            return fail("sculpt", format!("option `quaternion` must be [x, y, z, w], got {}", type_name(q)));
        };
        let c: Vec<f64> = a
            .iter()
            .enumerate()
            .map(|(i, v)| number("sculpt", &format!("option quaternion[{i}]"), v))
            .collect::<ScriptResult<_>>()?;
        return Ok(Some(Quat::from_xyzw(c[0], c[1], c[2], c[3])));
    }
    Ok(None)
}

fn floats(func: &str, values: &Array) -> ScriptResult<Vec<f64>> {
    values.iter().enumerate().map(|(i, v)| number(func, &format!("values[{i}]"), v)).collect()
}

#[export_module]
pub mod voxel_api {
    use super::*;

    /// An empty n³ voxel grid (n a power of two up to 512), densities 0–255. Voxel `(i, j, k)`
    /// spans `[i, i+1) × [j, j+1) × [k, k+1)`; world coordinates are voxel units.
    ///
    /// ```rhai
    /// let vx = voxels(16);
    /// assert_eq(vx.size, 16);
    /// assert_eq(vx.filled(), 0);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn voxels(n: INT) -> ScriptResult<Voxels> {
        let n = size("voxels", "n", n)?;
        kernel("voxels", KernelVoxels::new(n)).map(|v| Voxels(Rc::new(v)))
    }

    /// A closed mesh voxelized into an n³ grid with partial coverage as density. The mesh's
    /// bounds plus one voxel of margin map into the grid, and the grid keeps that mapping: its
    /// `to_mesh` results, shapes filled into it and sculpt positions are in the mesh's coordinates.
    ///
    /// Topic: voxels
    ///
    /// ```rhai
    /// let vx = voxelize(cube(2), 32);
    /// assert_near(vx.world_volume(), 8.0, 1e-9);
    /// assert(vx.to_mesh().is_closed(), "closed");
    /// ```
    #[rhai_fn(return_raw)]
    pub fn voxelize(mesh: SharedMesh, n: INT) -> ScriptResult<Voxels> {
        let n = size("voxelize", "n", n)?;
        kernel("voxelize", KernelVoxels::from_mesh(&mesh.0, n)).map(|v| Voxels(Rc::new(v)))
    }

    /// The grid side n.
    ///
    /// ```rhai
    /// assert_eq(voxels(16).size, 16);
    /// ```
    #[rhai_fn(get = "size", pure)]
    pub fn get_size(vx: &mut Voxels) -> INT {
        vx.0.size() as INT
    }
    /// The world length of one voxel side (1 for `voxels(n)`).
    #[rhai_fn(get = "scale", pure)]
    pub fn get_scale(vx: &mut Voxels) -> f64 {
        vx.0.scale()
    }
    /// The world position of the grid's corner (0, 0, 0).
    ///
    /// ```rhai
    /// assert_eq(voxels(8).origin, vec3(0, 0, 0));
    /// ```
    #[rhai_fn(get = "origin", pure)]
    pub fn get_origin(vx: &mut Voxels) -> blocksmith_kernel::Vec3 {
        vx.0.origin()
    }
    /// The coarsest level of detail, log₂ n.
    ///
    /// ```rhai
    /// assert_eq(voxels(64).max_level, 6);
    /// ```
    #[rhai_fn(get = "max_level", pure)]
    pub fn get_max_level(vx: &mut Voxels) -> INT {
        INT::from(vx.0.max_level())
    }

    /// Fills the ball of `radius` around `center` (world coordinates) with partial coverage:
    /// each voxel's density becomes the larger of its density and 255 × the part of it inside.
    ///
    /// ```rhai
    /// let vx = voxels(32);
    /// vx.fill_sphere([16, 16, 16], 10);
    /// assert_near(vx.volume(), 4.0 / 3.0 * PI() * 1000.0, 5.0);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn fill_sphere(vx: &mut Voxels, center: Vector, radius: Number) -> ScriptResult<()> {
        let c = vec3("fill_sphere", "center", &center)?;
        let r = number("fill_sphere", "radius", &radius)?;
        if r <= 0.0 {
            return fail("fill_sphere", format!("argument `radius` must be positive, got {}", fmt_num(r)));
        }
        kernel("fill_sphere", vx.get_mut().fill_sphere(c, r))
    }

    /// Fills the box from `min` to `max` (world coordinates) with partial coverage; with integer
    /// bounds exactly the voxels in `[min, max)` become 255.
    ///
    /// ```rhai
    /// let vx = voxels(8);
    /// vx.fill_box([2, 2, 2], [5, 4, 8]);
    /// assert_eq(vx.filled(), 3 * 2 * 6);
    /// assert_eq(vx.get(2, 3, 7), 255);
    /// assert_eq(vx.get(5, 3, 7), 0);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn fill_box(vx: &mut Voxels, min: Vector, max: Vector) -> ScriptResult<()> {
        let (a, b) = (vec3("fill_box", "min", &min)?, vec3("fill_box", "max", &max)?);
        kernel("fill_box", vx.get_mut().fill_box(a, b))
    }

    /// Fills the solid bounded by a closed mesh (world coordinates) with partial coverage, so a
    /// block model, a polar mesh or a CSG result can become a tool or a workpiece.
    ///
    /// ```rhai
    /// let ring = voxels(32);
    /// ring.fill_mesh(torus(10, 3, 48, 24).translate([16, 16, 16]));
    /// assert(ring.to_mesh().genus() == 1, "a ring has one handle");
    /// ```
    #[rhai_fn(return_raw)]
    pub fn fill_mesh(vx: &mut Voxels, mesh: SharedMesh) -> ScriptResult<()> {
        kernel("fill_mesh", vx.get_mut().fill_mesh(&mesh.0))
    }

    /// The density (0–255) of voxel `(x, y, z)`.
    ///
    /// ```rhai
    /// let vx = voxels(4);
    /// assert_eq(vx.get(0, 0, 0), 0);
    /// vx.fill_box([0, 0, 0], [1, 1, 1]);
    /// assert_eq(vx.get(0, 0, 0), 255);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn get(vx: &mut Voxels, x: INT, y: INT, z: INT) -> ScriptResult<INT> {
        kernel("get", vx.0.get(x, y, z)).map(INT::from)
    }

    /// Sets the density of voxel `(x, y, z)` to `value` (0–255).
    ///
    /// ```rhai
    /// let vx = voxels(4);
    /// vx.set(1, 2, 3, 128);
    /// assert_eq(vx.get(1, 2, 3), 128);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn set(vx: &mut Voxels, x: INT, y: INT, z: INT, value: INT) -> ScriptResult<()> {
        let Ok(v) = u8::try_from(value) else {
            return fail("set", format!("argument `value` must be a density between 0 and 255, got {value}"));
        };
        kernel("set", vx.0.get(x, y, z))?;
        kernel("set", vx.get_mut().set(x, y, z, v))
    }

    /// The number of non-empty voxels.
    ///
    /// ```rhai
    /// let vx = voxels(8);
    /// vx.fill_box([0, 0, 0], [2, 2, 2]);
    /// assert_eq(vx.filled(), 8);
    /// ```
    #[rhai_fn(pure)]
    pub fn filled(vx: &mut Voxels) -> INT {
        vx.0.filled() as INT
    }

    /// A one-line summary: size, filled voxels and volume (what the REPL shows).
    ///
    /// ```rhai
    /// let vx = voxels(8);
    /// vx.fill_box([0, 0, 0], [2, 2, 2]);
    /// assert_eq(vx.to_string(), "Voxels(8³, 8 filled, volume 8)");
    /// ```
    #[rhai_fn(name = "to_string", name = "to_debug", pure)]
    pub fn to_string(vx: &mut Voxels) -> String {
        format!("Voxels({}³, {} filled, volume {})", vx.0.size(), vx.0.filled(), vx.0.volume())
    }

    /// The sum of densities / 255: the filled volume in voxel units.
    #[rhai_fn(pure)]
    pub fn volume(vx: &mut Voxels) -> f64 {
        vx.0.volume()
    }

    /// The filled volume in world units (`volume()` × scale³).
    ///
    /// ```rhai
    /// let vx = voxelize(cube(2), 16);
    /// assert_near(vx.world_volume(), 8.0, 1e-9);
    /// ```
    #[rhai_fn(pure)]
    pub fn world_volume(vx: &mut Voxels) -> f64 {
        vx.0.world_volume()
    }

    /// Bytes held by the grid with its derived data (Haar hierarchy, surface caches, rotated-tool
    /// cache).
    ///
    /// ```rhai
    /// assert(voxels(16).memory() >= 16 * 16 * 16, "at least a byte a voxel");
    /// ```
    #[rhai_fn(pure)]
    pub fn memory(vx: &mut Voxels) -> INT {
        vx.0.memory_bytes() as INT
    }

    /// Sculpts this grid with `tool` (another `Voxels`, e.g. an object sculpted earlier, or
    /// `voxel_sphere(r)` / `voxel_box(size)`): the tool grid's centre goes to `at` (world
    /// coordinates, required), turned about that centre by one of: `angle` degrees (default 0)
    /// about `axis` (default `[0, 0, 1]`); `rotate`, a list of turns `[axis, degrees]` applied in
    /// order (the axis a vector or `"x"`, `"y"`, `"z"`); or `quaternion`, `[x, y, z, w]` of any
    /// non-zero length (normalised). Each voxel in contact
    /// gains (`mode: "add"`, the default) or loses (`"subtract"`) the tool's density there,
    /// clamped to 0–255. `antialias` (default true) resamples the rotated tool trilinearly.
    /// Returns `#{contact, rotated, reused, changed}` voxel counts: rotated tool voxels are
    /// cached, so a stroke moved by whole voxels rotates only the newly touched ones.
    ///
    /// ```rhai
    /// let block = voxels(32);
    /// block.fill_box([4, 4, 4], [28, 28, 28]);
    /// let ball = voxels(16);
    /// ball.fill_sphere([8, 8, 8], 6);
    /// let before = block.volume();
    /// let r = block.sculpt(ball, #{ at: [16, 16, 28], mode: "subtract" });
    /// assert(r.changed > 0, "the ball bit into the block");
    /// assert(block.volume() < before, "material was removed");
    /// block.sculpt(ball, #{ at: [16, 16, 4], axis: [1, 1, 0], angle: 30, mode: "subtract", antialias: false });
    /// // A box tool turned 30° about z, then 20° about x; the same turn as a quaternion.
    /// let key = voxel_box([8, 4, 4]);
    /// block.sculpt(key, #{ at: [10, 16, 16], rotate: [["z", 30], ["x", 20]], mode: "subtract" });
    /// let s = sin(PI() / 12.0);
    /// block.sculpt(key, #{ at: [22, 16, 16], quaternion: [0, 0, s, cos(PI() / 12.0)], mode: "subtract" });
    /// ```
    #[rhai_fn(return_raw)]
    pub fn sculpt(vx: &mut Voxels, tool: Voxels, options: Map) -> ScriptResult<Map> {
        let opts =
            Options::new("sculpt", options, &["at", "axis", "angle", "rotate", "quaternion", "mode", "antialias"])?;
        let Some(at) = opts.raw("at") else {
            return fail("sculpt", "option `at` (where the tool's centre goes) is required");
        };
        let at = vec3("sculpt", "option `at`", at)?;
        let axis = opts.vec3("axis", blocksmith_kernel::Vec3::Z)?;
        if axis.length_squared() == 0.0 {
            return fail("sculpt", "option `axis` is the zero vector, which has no direction");
        }
        let angle = opts.number("angle", 0.0)?;
        let mode = match opts.choice("mode", "add", &["add", "subtract"])?.as_str() {
            "subtract" => SculptMode::Subtract,
            _ => SculptMode::Add,
        };
        let mut o = SculptOptions::at(at)
            .with_rotation(axis, angle)
            .with_mode(mode)
            .with_antialias(opts.bool("antialias", true)?);
        if let Some(q) = sculpt_rotation(&opts)? {
            o = o.with_quat(q);
        }
        let r = kernel("sculpt", vx.get_mut().sculpt(&tool.0, &o))?;
        let mut m = Map::new();
        m.insert("contact".into(), Dynamic::from(r.contact as INT));
        m.insert("rotated".into(), Dynamic::from(r.rotated as INT));
        m.insert("reused".into(), Dynamic::from(r.reused as INT));
        m.insert("changed".into(), Dynamic::from(r.changed as INT));
        Ok(m)
    }

    /// Level `level` of detail (0…max_level) as a grid of side n / 2^level, each voxel the
    /// average of its block, extracted from the grid's Haar hierarchy; it covers the same world
    /// box (scale × 2^level).
    ///
    /// ```rhai
    /// let vx = voxels(16);
    /// vx.fill_box([0, 0, 0], [8, 8, 8]);
    /// let l1 = vx.lod(1);
    /// assert_eq(l1.size, 8);
    /// assert_eq(l1.get(3, 3, 3), 255);
    /// assert_eq(vx.lod(4).get(0, 0, 0), 32);   // 512 full voxels of 4096, rounded: 255 / 8
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn lod(vx: &mut Voxels, level: INT) -> ScriptResult<Voxels> {
        kernel("lod", vx.get_mut().lod(level)).map(|v| Voxels(Rc::new(v)))
    }

    /// The surface of level 0 at iso level 127.5 (half coverage) by marching cubes, in world
    /// coordinates: a closed, manifold triangle mesh (the grid border caps the object). The
    /// densities are first smoothed by a small filter (7 taps, zero second moment), so curved
    /// surfaces show no terraces and rotated flat faces stay flat; sharp edges round over about
    /// three voxels, and curved surfaces sit slightly inside (about 0.45 / r voxel on a ball of
    /// radius r voxels). `to_mesh(#{ surface: "raw" })` meshes the densities themselves.
    ///
    /// ```rhai
    /// let vx = voxels(32);
    /// vx.fill_sphere([16, 16, 16], 10);
    /// let m = vx.to_mesh();
    /// assert(m.is_closed() && m.is_manifold(), "watertight");
    /// // Every vertex lies within a tenth of a voxel of the sphere.
    /// for p in m.positions() { assert_near((p - vec3(16, 16, 16)).length(), 10.0, 0.1); }
    /// // On a curved surface the smoothed one sits inside by about 0.45 / r voxel on average, so a
    /// // ball of radius r voxels loses about 1.76 / r² of its volume (raw: 0.82 / r²).
    /// let ball = 4.0 / 3.0 * PI() * 1000.0;
    /// assert_near(m.volume(), ball * (1.0 - 1.76 / 100.0), 0.003 * ball);
    /// assert_near(vx.to_mesh(#{ surface: "raw" }).volume(), ball * (1.0 - 0.82 / 100.0), 0.003 * ball);
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn to_mesh(vx: &mut Voxels) -> ScriptResult<SharedMesh> {
        let _bar = crate::progress::bar("to_mesh: marching cubes");
        kernel("to_mesh", vx.get_mut().to_mesh(0, DEFAULT_ISO)).map(SharedMesh::new)
    }

    /// The surface with options `level` (level of detail, default 0), `iso` (density above
    /// which a voxel is inside, in [0, 255), default 127.5) and `surface`: `"smooth"` (default,
    /// the densities smoothed first: no terraces, edges rounded over about three voxels) or
    /// `"raw"` (the densities themselves, stepped where they jump from 0 to 255, exact for small
    /// features). Each level's surface is cached and only the parts a sculpt touched are
    /// re-meshed.
    ///
    /// ```rhai
    /// let vx = voxels(32);
    /// vx.fill_sphere([16, 16, 16], 10);
    /// let fine = vx.to_mesh(#{ level: 0 });
    /// let coarse = vx.to_mesh(#{ level: 2, iso: 100 });
    /// assert(coarse.face_count < fine.face_count, "coarser level, fewer faces");
    /// assert(coarse.is_closed(), "closed at every level");
    /// let raw = vx.to_mesh(#{ surface: "raw" });
    /// assert(raw.is_closed() && raw.genus() == 0, "the raw surface is kept");
    /// ```
    #[rhai_fn(name = "to_mesh", pure, return_raw)]
    pub fn to_mesh_with(vx: &mut Voxels, options: Map) -> ScriptResult<SharedMesh> {
        let opts = Options::new("to_mesh", options, &["level", "iso", "surface"])?;
        let lvl = match opts.raw("level") {
            Some(v) => level("to_mesh", v)?,
            None => 0,
        };
        let iso = opts.number("iso", DEFAULT_ISO)?;
        let surface = match opts.choice("surface", "smooth", &["smooth", "raw"])?.as_str() {
            "raw" => Surface::Raw,
            _ => Surface::Smooth,
        };
        let _bar = crate::progress::bar("to_mesh: marching cubes");
        kernel("to_mesh", vx.get_mut().to_mesh_with(lvl, iso, surface)).map(SharedMesh::new)
    }

    /// A tool grid holding a ball of radius `r` (voxel units) at its centre, with one empty voxel
    /// of margin (the smallest power-of-two side above 2r + 2), mapped so its centre is world
    /// position 0: `sculpt` places it by that centre, and its `to_mesh` is centred on the origin.
    ///
    /// ```rhai
    /// let ball = voxel_sphere(5);
    /// assert_eq(ball.size, 16);
    /// assert_near(ball.volume(), 4.0 / 3.0 * PI() * 125.0, 1.0);
    /// let block = voxels(32);
    /// block.fill_box([0, 0, 0], [32, 32, 16]);
    /// block.sculpt(ball, #{ at: [16, 16, 16], mode: "subtract" });   // a hemispherical dent
    /// assert_near(block.volume(), 32.0 * 32.0 * 16.0 - 2.0 / 3.0 * PI() * 125.0, 2.0);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn voxel_sphere(r: Number) -> ScriptResult<Voxels> {
        let r = number("voxel_sphere", "r", &r)?;
        kernel("voxel_sphere", KernelVoxels::centred_sphere(r)).map(|v| Voxels(Rc::new(v)))
    }

    /// A tool grid holding an axis-aligned box of `size` (a number for a cube, or `[x, y, z]`, in
    /// voxel units) at its centre, with one empty voxel of margin, mapped so its centre is world
    /// position 0 (see `voxel_sphere`).
    ///
    /// ```rhai
    /// let key = voxel_box([6, 4, 2]);
    /// assert_eq(key.size, 8);
    /// assert_near(key.volume(), 48.0, 1e-9);
    /// assert_near(voxel_box(3).volume(), 27.0, 0.1);   // faces half-covered, densities rounded
    /// ```
    #[rhai_fn(return_raw)]
    pub fn voxel_box(size: NumberOrVector) -> ScriptResult<Voxels> {
        let s = factor3("voxel_box", "size", &size)?;
        kernel("voxel_box", KernelVoxels::centred_box(s)).map(|v| Voxels(Rc::new(v)))
    }

    /// The 1D Haar decomposition of `values` (length a power of two): the coarsest average, then
    /// the details from coarsest to finest (Heurtebise & Thon §2.1).
    ///
    /// ```rhai
    /// assert_eq(haar1d([9, 7, 3, 5]), [6.0, 2.0, 1.0, -1.0]);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn haar1d(values: Array) -> ScriptResult<Array> {
        let v = floats("haar1d", &values)?;
        kernel("haar1d", k_haar1d(&v)).map(|out| out.into_iter().map(Dynamic::from).collect())
    }

    /// The inverse of `haar1d`.
    ///
    /// ```rhai
    /// assert_eq(ihaar1d([6, 2, 1, -1]), [9.0, 7.0, 3.0, 5.0]);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn ihaar1d(values: Array) -> ScriptResult<Array> {
        let v = floats("ihaar1d", &values)?;
        kernel("ihaar1d", k_ihaar1d(&v)).map(|out| out.into_iter().map(Dynamic::from).collect())
    }
}
