//! `load` and `save`: mesh files by extension (`.obj`, `.glb`, `.gltf`, `.stl`, `.ply`, `.3mf`), and
//! 2D profile files (`.svg`, `.dxf`). Where the files are, and whether the run may read or write
//! them, is `api/paths.rs`.

use blocksmith_kernel::io::{LoadOptions, PlyEncoding, SaveOptions, UpAxis, Weld};
use blocksmith_kernel::{io, Mesh};
use rhai::plugin::*;
use rhai::Map;

use super::mesh::SharedMesh;
use super::paths::{companion_file, input_file, output_file, wrote};
use super::profile::Profile;
use crate::context::RunContext;
use crate::convert::{fail, kernel, type_name, Options, ScriptResult};

/// Reads the 2D file (`.svg`, `.dxf`) the script names by `path` (see [`input_file`]).
///
/// # Errors
/// The kernel's file error, naming `load` and the path.
fn read_profile_file(ctx: &NativeCallContext, path: &str) -> ScriptResult<Profile> {
    let p = input_file(ctx, "load", path)?;
    kernel("load", io::load_profile(&p)).map(|p| Profile(std::rc::Rc::new(p)))
}

/// Writes `mesh` to the script path `path` by extension: a relative path goes under the run's
/// output directory, and missing parent directories are created. Errors name `func`.
///
/// # Errors
/// A directory that cannot be created, or the kernel's file error.
pub fn write_mesh(ctx: &NativeCallContext, func: &str, mesh: &Mesh, path: &str) -> ScriptResult<()> {
    write_mesh_with(ctx, func, mesh, path, &SaveOptions::DEFAULT)
}

/// [`write_mesh`] with save options.
///
/// # Errors
/// As [`write_mesh`].
fn write_mesh_with(
    ctx: &NativeCallContext,
    func: &str,
    mesh: &Mesh,
    path: &str,
    options: &SaveOptions,
) -> ScriptResult<()> {
    let Some(p) = output_file(ctx, func, path)? else { return Ok(()) };
    // An OBJ with colours also writes its material library: the same checks apply to it.
    let library = match io::Format::from_path(&p) {
        Ok(io::Format::Obj) => io::obj::material_library_path(mesh, &p),
        _ => None,
    };
    if let Some(lib) = &library {
        if !companion_file(ctx, func, &p, lib, "the material library beside the .obj,")? {
            return Ok(());
        }
    }
    let result = io::save_with(mesh, &p, options);
    wrote(ctx, &p);
    if let Some(lib) = &library {
        wrote(ctx, lib);
    }
    match result {
        Ok(()) => Ok(()),
        Err(e) => fail(func, e),
    }
}

/// The `up` option: `"z"` or `"y"`, `None` when not given.
fn up_option(o: &Options, func: &str) -> ScriptResult<Option<UpAxis>> {
    if !o.has("up") {
        return Ok(None);
    }
    let name = o.string("up", "z")?;
    match UpAxis::from_name(&name) {
        Some(up) => Ok(Some(up)),
        None => fail(func, format!("option `up` must be \"z\" or \"y\", got \"{name}\"")),
    }
}

/// The `weld` option: `true` (the default tolerance), `false` (off), or a tolerance relative
/// to the bounding box's diagonal (≥ 0; 0 joins equal coordinates only).
fn weld_option(o: &Options) -> ScriptResult<Weld> {
    let Some(v) = o.raw("weld") else { return Ok(Weld::DEFAULT) };
    if let Ok(b) = v.as_bool() {
        return Ok(if b { Weld::DEFAULT } else { Weld::Off });
    }
    let t = o.number("weld", 0.0).map_err(|_| {
        crate::convert::error("load", format!("option `weld` must be true, false or a number, got {}", type_name(v)))
    })?;
    if !(t.is_finite() && t >= 0.0) {
        return fail("load", format!("option `weld` must be a tolerance ≥ 0 (relative to the model's size), got {t}"));
    }
    Ok(Weld::Relative(t))
}

/// The meshes of a map joined into one, each named by its key (see `save(map, path)`).
///
/// # Errors
/// An empty map, or a value that is not a `Mesh`, naming its key.
pub fn named_parts(parts: &Map) -> ScriptResult<Mesh> {
    if parts.is_empty() {
        return fail("save", "the map of parts is empty: give each part a name and a mesh, as #{ body: …, lid: … }");
    }
    let mut meshes = Vec::with_capacity(parts.len());
    for (key, value) in parts {
        let Some(m) = value.clone().try_cast::<SharedMesh>() else {
            return fail(
                "save",
                format!(
                    "the part `{key}` is {}, not a Mesh: every value of a map of parts is a mesh",
                    type_name(value)
                ),
            );
        };
        let mut m = (*m.0).clone();
        let name: std::sync::Arc<str> = std::sync::Arc::from(key.as_str());
        m.map_parts(|p| p.name = Some(name.clone()));
        meshes.push(m);
    }
    let refs: Vec<&Mesh> = meshes.iter().collect();
    kernel("save", Mesh::combine(&refs))
}

#[export_module]
pub mod files_api {
    use super::*;

    /// Reads a mesh file by extension: `.obj` (polygons kept), `.gltf` (with its buffers) or
    /// `.glb`, `.stl` (binary or ASCII), `.ply` (ASCII or binary, polygons and vertex colours
    /// kept), `.3mf` (every build item with its transforms; colour groups and base materials as
    /// vertex colours). A relative path is tried from the working directory, then next to the script. A
    /// missing file, an unknown extension or a malformed file is an error naming the path and
    /// the reason.
    ///
    /// Axes: blocksmith is Z-up. glTF is Y-up by specification (glTF 2.0 §3.4) and is turned
    /// to Z-up exactly; 3MF is Z-up by specification; OBJ, STL and PLY are read as they are (see `load(path, #{up})`). Corners
    /// stored apart at one place (an STL's, a glTF's or PLY's split at seams, an OBJ converted
    /// from an STL) are welded by position (see `load(path, #{weld})`).
    ///
    /// A `.svg` or `.dxf` file is read as a 2D `Profile` (SVG paths, polygons and basic shapes
    /// with their transforms; DXF LWPOLYLINE, POLYLINE, LINE, ARC and CIRCLE).
    ///
    /// Topic: files
    ///
    /// ```rhai
    /// let c = cube(2);
    /// c.save("doc_example_cube.obj");
    /// let back = load("doc_example_cube.obj");
    /// assert_eq(back.face_count, 6);
    /// (rect([0, 0], [3, 2]) - circle(0.5, 16).translate([1, 1])).save("doc_example_plate.dxf");
    /// assert_near(load("doc_example_plate.dxf").area(), 6.0 - 8.0 * sin(2.0 * PI() / 16.0) * 0.25, 1e-9);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn load(ctx: NativeCallContext, path: &str) -> ScriptResult<Dynamic> {
        load_with_options(ctx, path, Map::new())
    }

    /// Reads a mesh file with options: `up` (`"z"` or `"y"`: the file's up axis, for OBJ, STL
    /// and PLY, which have no convention; default `"z"`, read as it is; glTF is always Y-up and
    /// takes no other), `weld` (corners closer than this fraction of the model's bounding-box
    /// diagonal in every coordinate become one vertex — default `true`, 1e-8 for STL, glTF and
    /// PLY, and equal coordinates only for OBJ and 3MF, which name their shared vertices; an OBJ
    /// with subdivision tags is never welded;
    /// `0` joins equal coordinates only; `false` keeps every vertex of the file, so a glTF
    /// split at normal or UV seams stays split; welding never joins sheets that touch into a
    /// non-manifold mesh: such vertices are kept apart), `repair` (default `true`: a file whose
    /// faces are not a manifold surface as written — two sheets touching at a vertex, an edge
    /// of three or more faces, neighbours facing opposite ways, a face repeating a vertex — is
    /// loaded as the nearest manifold mesh without moving a vertex: vertices split into one per
    /// fan, faces beyond two on an edge separated into their own sheets, components re-oriented
    /// where a consistent orientation exists, such faces dropped; each repair is a warning with
    /// counts and where; `false` refuses such a file).
    ///
    /// Topic: files
    ///
    /// ```rhai
    /// let c = box(vec3(0, 0, 0), vec3(1, 1, 3));
    /// c.save("doc_example_tall.stl", #{ up: "y" });
    /// let back = load("doc_example_tall.stl", #{ up: "y", weld: 1e-6 });
    /// assert_eq(back.bounds().max, vec3(1, 1, 3));
    /// assert_eq(load("doc_example_tall.stl", #{ weld: false }).vertex_count, 36);
    /// assert(load("doc_example_tall.stl", #{ repair: false }).is_closed(), "a valid file loads as it is");
    /// // Two cubes touching at a corner: one vertex of two fans in the file, split on load.
    /// combine([cube(1), cube(1).translate([1, 1, 1])]).save("doc_example_corner.stl");
    /// let two = load("doc_example_corner.stl");
    /// let w = take_warnings();
    /// assert(w[0].contains("split 1 non-manifold vertex into one per fan"), w[0]);
    /// assert_eq(two.components().len(), 2);
    /// assert_eq(two.defects().filter(|d| d.kind == "non_manifold_vertex")[0].position, vec3(0.5, 0.5, 0.5));
    /// ```
    #[rhai_fn(name = "load", return_raw)]
    pub fn load_with_options(ctx: NativeCallContext, path: &str, options: Map) -> ScriptResult<Dynamic> {
        if io::ProfileFormat::from_path(std::path::Path::new(path)).is_ok() {
            Options::new("load", options, &[])?;
            return read_profile_file(&ctx, path).map(Dynamic::from);
        }
        let o = Options::new("load", options, &["up", "weld", "repair"])?;
        let mut opts = LoadOptions::DEFAULT.with_weld(weld_option(&o)?).with_repair(o.bool("repair", true)?);
        if let Some(up) = up_option(&o, "load")? {
            opts = opts.with_up(up);
        }
        let p = input_file(&ctx, "load", path)?;
        if p.exists() {
            let run = RunContext::of(&ctx);
            // A .gltf's model is also in its buffer files.
            for buffer in crate::gltf_buffers::buffer_files(&p) {
                // Inside the glTF's folder by name, but a link there may point anywhere.
                run.access.check_read(&buffer).map_err(|e| crate::convert::error("load", e))?;
                if buffer.exists() {
                    run.record.input(&buffer);
                }
            }
        }
        match io::load_report(&p, &opts) {
            Ok((m, repairs)) => {
                let run = RunContext::of(&ctx);
                for line in repairs.summary() {
                    run.warnings.push(
                        &ctx,
                        format!(
                            "load: {}: {line} (no vertex moved; `repair: false` refuses the file instead)",
                            p.display()
                        ),
                    );
                }
                Ok(Dynamic::from(SharedMesh::new(m)))
            }
            Err(e) => fail("load", e),
        }
    }

    /// Writes a mesh by extension: `.obj` (polygons, exact positions), `.glb`, `.gltf`
    /// (+ `.bin`), `.stl` (binary, triangulated, f32), `.ply` (binary little-endian unless
    /// `#{ply}` says otherwise; polygons, exact positions, 8-bit vertex colours), `.3mf`
    /// (triangles, exact positions, vertex colours as a colour group or boolean sources as base
    /// materials). A relative path goes under the output directory (the working
    /// directory, or the test output directory under `blocksmith test`). Parent directories are
    /// created. Also callable as `mesh.save(path)`.
    ///
    /// Axes: blocksmith is Z-up; glTF is written Y-up as its specification says (glTF 2.0
    /// §3.4), converted exactly, so models stand upright in glTF viewers and read back to the
    /// same positions. OBJ, STL and PLY are written as they are (see `save(mesh, path, #{up})`).
    ///
    /// Topic: files
    ///
    /// ```rhai
    /// save(icosphere(1, 1), "doc_example_ico.glb");
    /// ```
    #[rhai_fn(return_raw)]
    pub fn save(ctx: NativeCallContext, mesh: &mut SharedMesh, path: &str) -> ScriptResult<()> {
        write_mesh(&ctx, "save", &mesh.0, path)
    }

    /// Writes a mesh by extension with options: `up` (`"z"` or `"y"`: the up axis to write
    /// OBJ, STL and PLY in, for tools that expect Y-up; default `"z"`, as it is; glTF is always
    /// written Y-up and takes no other), `ply` (`"binary"` — little-endian, the default —,
    /// `"binary_big_endian"` or `"ascii"`: how a `.ply` stores its data).
    ///
    /// Topic: files
    ///
    /// ```rhai
    /// let c = box(vec3(0, 0, 0), vec3(1, 1, 3));
    /// c.save("doc_example_tall_y.obj", #{ up: "y" });
    /// assert_eq(load("doc_example_tall_y.obj").bounds().max, vec3(1, 3, 0));
    /// c.save("doc_example_tall.ply", #{ ply: "ascii" });
    /// assert_eq(load("doc_example_tall.ply").bounds().max, vec3(1, 1, 3));
    /// ```
    #[rhai_fn(name = "save", return_raw)]
    pub fn save_with_options(
        ctx: NativeCallContext,
        mesh: &mut SharedMesh,
        path: &str,
        options: Map,
    ) -> ScriptResult<()> {
        let o = Options::new("save", options, &["up", "ply"])?;
        let mut opts = SaveOptions::DEFAULT;
        if let Some(up) = up_option(&o, "save")? {
            opts = opts.with_up(up);
        }
        if o.has("ply") {
            let name = o.string("ply", "binary")?;
            match PlyEncoding::from_name(&name) {
                Some(enc) => opts = opts.with_ply(enc),
                None => {
                    return fail(
                        "save",
                        format!("option `ply` must be \"binary\", \"binary_big_endian\" or \"ascii\", got \"{name}\""),
                    )
                }
            }
        }
        write_mesh_with(&ctx, "save", &mesh.0, path, &opts)
    }

    /// Writes a map of meshes as one file of named parts: each key names its mesh's faces —
    /// 3MF objects, glTF nodes, OBJ `o` groups (PLY and STL keep no names) — with each part's
    /// colours, so a slicer lists `body` and `lid` as parts with their colours. The parts are
    /// written in key order. A recipe whose last value is such a map is written the same way by
    /// `blocksmith run -o`. Every value must be a `Mesh`; the key replaces any part names the
    /// mesh had. An empty map is refused.
    ///
    /// Topic: files
    ///
    /// ```rhai
    /// let parts = #{ body: cube(2).color("#d04020"), lid: cube(1).translate([3, 0, 0]).color([0.2, 0.4, 0.9]) };
    /// save(parts, "doc_example_parts.3mf");
    /// let back = load("doc_example_parts.3mf");
    /// assert_eq(back.colors().len(), 2);
    /// assert_eq(back.face_count, 24);
    /// ```
    #[rhai_fn(name = "save", return_raw)]
    pub fn save_parts(ctx: NativeCallContext, parts: &mut Map, path: &str) -> ScriptResult<()> {
        let mesh = named_parts(parts)?;
        write_mesh(&ctx, "save", &mesh, path)
    }

    /// Writes a map of meshes as one file of named parts (see `save(map, path)`) with the
    /// options of `save(mesh, path, #{up, ply})`.
    ///
    /// Topic: files
    ///
    /// ```rhai
    /// let parts = #{ a: cube(1), b: cube(1).translate([2, 0, 0]).color("#00ff00") };
    /// save(parts, "doc_example_parts_y.obj", #{ up: "y" });
    /// assert_eq(load("doc_example_parts_y.obj", #{ up: "y" }).colors(), [[0.0, 1.0, 0.0, 1.0]]);
    /// ```
    #[rhai_fn(name = "save", return_raw)]
    pub fn save_parts_with_options(
        ctx: NativeCallContext,
        parts: &mut Map,
        path: &str,
        options: Map,
    ) -> ScriptResult<()> {
        let mesh = named_parts(parts)?;
        save_with_options(ctx, &mut SharedMesh::new(mesh), path, options)
    }

    /// Writes the profile by extension: `.svg` (one even-odd path, y up as drawn; millimetres
    /// per unit) or `.dxf` (closed polylines), for laser cutters, plotters and CAD. A relative
    /// path goes under the output directory; parent directories are created; the file is
    /// replaced only once the new one is complete. `load` reads both back.
    ///
    /// Topic: files
    ///
    /// ```rhai
    /// let p = rect([0, 0], [4, 2]) - circle(0.5, 24).translate([1, 1]);
    /// p.save("doc_example_part.svg");
    /// assert_near(load("doc_example_part.svg").area(), p.area(), 1e-6);
    /// ```
    #[rhai_fn(name = "save", return_raw)]
    pub fn save_profile(ctx: NativeCallContext, p: &mut Profile, path: &str) -> ScriptResult<()> {
        let Some(out) = output_file(&ctx, "save", path)? else { return Ok(()) };
        let result = blocksmith_kernel::io::save_profile(&p.0, &out);
        wrote(&ctx, &out);
        kernel("save", result)
    }
}
