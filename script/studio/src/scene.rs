//! What the studio shows: a run's value, or a mesh file, as named layers — each a `.glb` as
//! `save` writes it (so the page shows exactly what `blocksmith run -o x.glb` would write,
//! animation included), the model's own mesh (for downloads) and its facts, computed once.
//! A mesh or polar mesh is encoded in memory; an animation, whose modifiers may be script
//! functions, goes through `save` and a temporary file. `render` draws the `.glb` read back
//! ([`Layer::drawn`]), its colours as the page shows them.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use blocksmith_kernel::io::{self, gltf::write_glb};
use blocksmith_kernel::Mesh;
use rhai::{Dynamic, Engine, AST};

use blocksmith_script::api::{mesh::SharedMesh, polar::PolarMesh, profile::Profile};
use blocksmith_script::facts::Facts;
use blocksmith_script::run::{save_value, RunError};
use blocksmith_script::EngineOptions;

/// One value of a scene.
#[derive(Clone, Debug)]
pub struct Layer {
    /// `model` for a single value; the key or `[index]` of a map or array element.
    pub name: String,
    /// The value as a binary glTF file, as `save` writes it: the model's own colours.
    pub glb: Vec<u8>,
    /// For a boolean result (a mesh whose faces know their operands): the same mesh coloured by
    /// provenance, one colour per operand ([`io::gltf::write_glb_provenance`]), the debugging
    /// view the page offers as a toggle; `None` otherwise.
    pub provenance: Option<Vec<u8>>,
    /// The value's mesh (its rest pose for an animation): the model itself, not the file's
    /// vertices split at colour seams, so its facts say what the model is.
    pub mesh: Mesh,
    /// The mesh's facts.
    pub facts: Facts,
    /// The edges of the control mesh the value was made from, if any (see [`control_lines`]).
    pub control: Option<Vec<f32>>,
    /// For an animation: the pose `render` draws and its time — at the run's `--time`
    /// ([`blocksmith_script::RunContext::time`]), else the last frame `save` writes.
    pub pose: Option<(Mesh, f64)>,
}

/// A recipe's run: its layers and how long the run took (the script, not the conversion).
#[derive(Clone, Debug)]
pub struct Scene {
    pub layers: Vec<Layer>,
    pub run_time: Duration,
    /// The parameters the recipe declared (`ParamSpec::to_json`), for the page's controls.
    pub params: Vec<serde_json::Value>,
    /// The run's warnings, formatted as the terminal prints them (`file:line:col`, the line,
    /// a caret, the message).
    pub warnings: Vec<String>,
}

/// Runs the recipe at `path` with `options` (through the one runner,
/// [`blocksmith_script::run::run_recipe`]) and makes its value a scene.
///
/// # Errors
/// The run's error, formatted as the terminal prints it, or a value that cannot be saved.
pub fn from_recipe(path: &Path, options: EngineOptions) -> Result<Scene, RunError> {
    from_recipe_recorded(path, options).0
}

/// As [`from_recipe`], also returning the files the run read (the recipe, its imports, loaded
/// files), which a failed run names too: what a watcher watches.
///
/// When `options.context.shown` is set, the values the recipe passed to `show` follow the
/// model as layers `show 1`, `show 2`, ... (an array or map shown as `show 2 [0]`, `show 2 key`).
pub fn from_recipe_recorded(path: &Path, options: EngineOptions) -> (Result<Scene, RunError>, Vec<PathBuf>) {
    let shown = options.context.shown.clone();
    match blocksmith_script::run::run_recipe(path, options) {
        Ok(run) => {
            let params = run.record.params.iter().map(blocksmith_script::params::ParamSpec::to_json).collect();
            let scene = layers(&run.engine, &run.ast, run.value).and_then(|mut layers| {
                let values = shown.map(|s| s.take()).unwrap_or_default();
                for (i, v) in values.into_iter().enumerate() {
                    for mut l in self::layers(&run.engine, &run.ast, v)? {
                        l.name = if l.name == "model" {
                            format!("show {}", i + 1)
                        } else {
                            format!("show {} {}", i + 1, l.name)
                        };
                        layers.push(l);
                    }
                }
                Ok(Scene { layers, run_time: run.elapsed, params, warnings: run.warnings })
            });
            (scene, run.record.inputs)
        }
        Err(failure) => (Err(failure.error), failure.record.inputs),
    }
}

/// The layers of a value: each element of an array (`[0]`, `[1]`, …) or map (by key), else
/// the value itself as `model`. Nothing (unit) is an error, as for `run -o`.
///
/// # Errors
/// An element that cannot be saved, named.
pub fn layers(engine: &Engine, functions: &AST, value: Dynamic) -> Result<Vec<Layer>, RunError> {
    let named: Vec<(String, Dynamic)> = if value.is_array() {
        value.into_array().unwrap_or_default().into_iter().enumerate().map(|(i, v)| (format!("[{i}]"), v)).collect()
    } else if value.is_map() {
        value.cast::<rhai::Map>().into_iter().map(|(k, v)| (k.to_string(), v)).collect()
    } else {
        vec![("model".to_string(), value)]
    };
    if named.is_empty() {
        return Err(RunError("error: nothing to show: the script's last value is an empty array or map".into()));
    }
    named.into_iter().map(|(name, v)| layer(engine, functions, name, v)).collect()
}

/// The layer `name` showing `value`.
///
/// # Errors
/// A value that cannot be saved, named unless it is the `model`.
pub fn layer(engine: &Engine, functions: &AST, name: String, value: Dynamic) -> Result<Layer, RunError> {
    let named = |e: RunError| if name == "model" { e } else { RunError(format!("layer {name}: {}", e.0)) };
    // A block model is shown as its surface, `.mesh()`, which keeps its control mesh.
    let value = if engine.map_type_name(value.type_name()) == "BlockModel" {
        let mut scope = rhai::Scope::new();
        scope.push("model", value);
        engine
            .eval_with_scope::<Dynamic>(&mut scope, "model.mesh()")
            .map_err(|e| named(RunError(format!("error: cannot mesh the block model: {e}"))))?
    } else {
        value
    };
    let control = control_lines(&value);
    // An animation is drawn posed: at `--time`, else at its last frame.
    let time = blocksmith_script::RunContext::of_engine(engine).time;
    let pose = blocksmith_script::api::anim::pose_of_value(engine, functions, &value, time)
        .map_err(|e| named(RunError(format!("error: cannot pose the animation: {e}"))))?
        .map(|(m, t)| (Arc::try_unwrap(m.0).unwrap_or_else(|shared| (*shared).clone()), t));
    if pose.is_none() {
        if let Some(t) = time {
            return Err(named(RunError(format!(
                "error: --time {t}: the value is {}, not an Animation: only an animation has poses",
                blocksmith_script::catalogue::a(engine.map_type_name(value.type_name()))
            ))));
        }
    }
    let file = PathBuf::from(format!("{name}.glb"));
    let mut provenance = None;
    let (glb, mesh) = match own_mesh(value) {
        Ok(mesh) => {
            let mut glb = Vec::new();
            write_glb(&mesh, &mut glb, &file).map_err(|e| named(RunError(format!("error: {e}"))))?;
            if mesh.face_sources().is_some() {
                let mut p = Vec::new();
                io::gltf::write_glb_provenance(&mesh, &mut p, &file)
                    .map_err(|e| named(RunError(format!("error: {e}"))))?;
                provenance = Some(p);
            }
            (glb, mesh)
        }
        Err(value) => {
            let glb = glb_of(engine, functions, value).map_err(named)?;
            // Unwelded: the file's own vertices, as the animation moves them.
            let mesh = io::gltf::read_gltf_with(&glb, None, &file, io::Weld::Off)
                .map_err(|e| RunError(format!("error: layer {name}: {e}")))?;
            (glb, mesh)
        }
    };
    let facts = Facts::of(&mesh);
    Ok(Layer { name, glb, provenance, mesh, facts, control, pose })
}

impl Layer {
    /// The mesh as the page draws it: the `.glb` read back unwelded, so colour seams split
    /// vertices and each vertex carries the colour it is drawn with; for an animation, its
    /// pose ([`Layer::pose`]), not the rest mesh the file skins.
    ///
    /// # Errors
    /// The `.glb` cannot be read (never for one this module wrote).
    pub fn drawn(&self) -> Result<Mesh, RunError> {
        if let Some((pose, _)) = &self.pose {
            return Ok(pose.clone());
        }
        io::gltf::read_gltf_with(&self.glb, None, Path::new(&format!("{}.glb", self.name)), io::Weld::Off)
            .map_err(|e| RunError(format!("error: layer {}: {e}", self.name)))
    }
}

/// The mesh that `save` writes for `value` when it is a `Mesh` (taken, not copied, when no
/// one else holds it) or a `PolarMesh` (with its feature colours); the value back otherwise.
fn own_mesh(value: Dynamic) -> Result<Mesh, Dynamic> {
    match value.try_cast_result::<SharedMesh>() {
        Ok(m) => Ok(Arc::try_unwrap(m.0).unwrap_or_else(|shared| (*shared).clone())),
        Err(value) => match value.try_cast_result::<PolarMesh>() {
            Ok(p) => Ok(p.0.to_colored_mesh()),
            Err(value) => match value.try_cast_result::<Profile>() {
                Ok(p) => flat(&p).ok_or_else(|| Dynamic::from(p)),
                Err(value) => Err(value),
            },
        },
    }
}

/// A profile shown flat on the grid: its region as a sheet a thousandth of its size thick
/// (`None` for an empty profile, which has nothing to show).
fn flat(p: &Profile) -> Option<Mesh> {
    let (min, max) = p.0.bounds()?;
    let thickness = 1e-3 * (max - min).max_element().max(1e-9);
    let options = blocksmith_kernel::profile::ExtrudeOptions::DEFAULT;
    blocksmith_kernel::profile::extrude(&p.0, thickness, &options).ok()
}

/// The edges of the control mesh `value` was made from, as segment end points (x, y, z of
/// each end, in the kernel's Z-up frame): a subdivision surface's input mesh or a block model's
/// control mesh (a `Mesh` that holds one), a polar mesh's polygons (`PolarMesh`); `None` for
/// any other value.
#[must_use]
pub fn control_lines(value: &Dynamic) -> Option<Vec<f32>> {
    let control: Arc<Mesh> = if let Some(m) = value.read_lock::<SharedMesh>() {
        m.1.clone()?
    } else if let Some(p) = value.read_lock::<PolarMesh>() {
        Arc::new(p.0.to_mesh())
    } else if let Some(p) = value.read_lock::<Profile>() {
        // A profile's contours, drawn on the grid (z = 0) over its sheet.
        let ends = p.0.contours().iter().flat_map(|c| {
            (0..c.len()).flat_map(move |i| [c[i], c[(i + 1) % c.len()]]).flat_map(|q| [q.x as f32, q.y as f32, 0.0])
        });
        return Some(ends.collect());
    } else {
        return None;
    };
    let ends = control.edges().flat_map(|h| [control.position(control.origin(h)), control.position(control.target(h))]);
    Some(ends.flat_map(|p| [p.x as f32, p.y as f32, p.z as f32]).collect())
}

/// The `.glb` that `save` writes for `value`, through a temporary file (for values whose
/// writing needs the engine: an animation's script modifiers).
fn glb_of(engine: &Engine, functions: &AST, value: Dynamic) -> Result<Vec<u8>, RunError> {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let path: PathBuf = std::env::temp_dir().join(format!("blocksmith-studio-{}-{n}.glb", std::process::id()));
    // The temporary file is no business of the person looking: errors name the page instead.
    let hide = |e: RunError| {
        RunError(
            e.0.replace(&format!(" to {}", path.display()), "")
                .replace(&path.display().to_string(), "the page")
                .replace("error: cannot write ", "error: cannot show "),
        )
    };
    let result = save_value(engine, functions, value, &path)
        .and_then(|()| std::fs::read(&path).map_err(|e| RunError(format!("error: cannot read back the model: {e}"))))
        .map_err(hide);
    // Best effort: the file may not exist when saving failed.
    let _ = std::fs::remove_file(&path);
    result
}

/// A mesh file (`.glb`, `.gltf`, `.obj`, `.stl`) as a one-layer scene; a `.glb` is shown as it
/// is (with its animation), the others as the `.glb` of their mesh.
///
/// # Errors
/// The file's read error.
pub fn load_file(path: &Path) -> Result<Scene, RunError> {
    let start = Instant::now();
    let mesh = io::load(path).map_err(|e| RunError(format!("error: {e}")))?;
    let glb = if io::Format::from_path(path).ok() == Some(io::Format::Glb) {
        std::fs::read(path).map_err(|e| RunError(format!("error: cannot read {}: {e}", path.display())))?
    } else {
        let mut bytes = Vec::new();
        write_glb(&mesh, &mut bytes, path).map_err(|e| RunError(format!("error: {e}")))?;
        bytes
    };
    let facts = Facts::of(&mesh);
    Ok(Scene {
        layers: vec![Layer { name: "model".into(), glb, provenance: None, mesh, facts, control: None, pose: None }],
        run_time: start.elapsed(),
        params: Vec::new(),
        warnings: Vec::new(),
    })
}

/// A recipe (`.rhai`) is run, any other file is read as a mesh.
///
/// # Errors
/// As [`from_recipe`] or [`load_file`].
pub fn open(path: &Path, options: EngineOptions) -> Result<Scene, RunError> {
    if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("rhai")) {
        from_recipe(path, options)
    } else {
        load_file(path)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn recipe(dir: &Path, text: &str) -> PathBuf {
        let p = dir.join("r.rhai");
        std::fs::write(&p, text).unwrap();
        p
    }

    #[test]
    fn a_single_value_is_one_layer_with_its_facts() {
        let dir = tempfile::tempdir().unwrap();
        let scene = from_recipe(&recipe(dir.path(), "cube(2)"), EngineOptions::default()).unwrap();
        assert_eq!(scene.layers.len(), 1);
        assert_eq!(scene.layers[0].name, "model");
        assert_eq!(&scene.layers[0].glb[..4], b"glTF");
        let f = &scene.layers[0].facts;
        assert_eq!((f.vertices, f.triangles, f.closed, f.manifold, f.genus), (8, 12, true, true, 0));
        assert!((f.volume - 8.0).abs() < 1e-6, "{}", f.volume);
    }

    #[test]
    fn a_profile_is_shown_flat_on_the_grid_with_its_contours_drawn() {
        // A 4 × 2 plate with a hole: a sheet a thousandth of its size thick (so its volume is
        // the area × 0.004), lying on z = 0, its two contours (4 + 16 edges) drawn as lines.
        let dir = tempfile::tempdir().unwrap();
        let text = "rect([0, 0], [4, 2]) - circle(0.5, 16).translate([1, 1])";
        let scene = from_recipe(&recipe(dir.path(), text), EngineOptions::default()).unwrap();
        let l = &scene.layers[0];
        let b = l.mesh.bounds();
        assert_eq!((b.min.z, b.max.x, b.max.y), (0.0, 4.0, 2.0));
        assert!((b.max.z - 0.004).abs() < 1e-12, "{}", b.max.z);
        let area = 8.0 - 8.0 * (2.0 * std::f64::consts::PI / 16.0).sin() * 0.25;
        assert!((l.facts.volume - area * 0.004).abs() < 1e-9, "{} vs {}", l.facts.volume, area * 0.004);
        assert_eq!(l.control.as_ref().map(|c| c.len()), Some((4 + 16) * 2 * 3));
        // An empty profile has nothing to show: a clear error, not an empty page.
        let e =
            from_recipe(&recipe(dir.path(), "rect([0, 0], [1, 1]) - rect([0, 0], [1, 1])"), EngineOptions::default());
        assert!(e.is_err());
    }

    #[test]
    fn a_boolean_result_has_the_facts_of_the_model_not_of_its_colour_split_file() {
        let dir = tempfile::tempdir().unwrap();
        let text = "union(cube(1), cube(1).translate([0.5, 0.5, 0.5]))";
        let scene = from_recipe(&recipe(dir.path(), text), EngineOptions::default()).unwrap();
        let l = &scene.layers[0];
        let f = &l.facts;
        assert_eq!((f.closed, f.manifold, f.components, f.boundary_loops), (true, true, 1, 0));
        assert!((f.volume - 1.875).abs() < 1e-9, "{}", f.volume);
        // The model is drawn uncoloured (provenance is not its colour); the provenance view
        // splits vertices where the sources' colours meet.
        let drawn = l.drawn().unwrap();
        assert!(drawn.vertex_colors().is_none() && !drawn.has_face_colors());
        assert_eq!(drawn.triangle_count(), f.triangles);
        let file = Path::new("p.glb");
        let view = io::gltf::read_gltf_with(l.provenance.as_ref().unwrap(), None, file, io::Weld::Off).unwrap();
        assert!(view.vertex_count() > l.mesh.vertex_count() && view.vertex_colors().is_some());
        assert_eq!(view.triangle_count(), f.triangles);
    }

    #[test]
    fn an_animation_is_drawn_posed_at_its_time_or_its_last_frame() {
        // A growing sphere of height 0.4: its last frame is grown; at --time 0 a seed a
        // thousandth of its size; a value that is no animation has no pose to pick.
        let dir = tempfile::tempdir().unwrap();
        let text = "let a = animation(polar_sphere(0.2, 8, 6)); a.add(growth()); a";
        let height = |m: &Mesh| m.bounds().max.z - m.bounds().min.z;
        let scene = from_recipe(&recipe(dir.path(), text), EngineOptions::default()).unwrap();
        let l = &scene.layers[0];
        let (end, t) = l.pose.as_ref().expect("an animation has a pose");
        assert!((t - 7.0).abs() < 1e-12, "the last frame of 24 fps frames covering 7: {t}");
        assert!((height(end) - 0.4).abs() < 1e-12);
        assert_eq!(l.drawn().unwrap().positions(), end.positions(), "render draws the pose");
        assert!(l.drawn().unwrap().vertex_colors().is_some(), "in the polar mesh's feature colours");
        let mut options = EngineOptions::default();
        options.context.time = Some(0.0);
        let scene = from_recipe(&recipe(dir.path(), text), options).unwrap();
        let (seed, t) = scene.layers[0].pose.as_ref().unwrap();
        assert_eq!(*t, 0.0);
        assert!((height(seed) - 0.4e-3).abs() < 1e-12, "{}", height(seed));
        let mut options = EngineOptions::default();
        options.context.time = Some(1.0);
        let e = from_recipe(&recipe(dir.path(), "cube(1)"), options).unwrap_err();
        assert!(e.0.contains("--time 1: the value is a Mesh, not an Animation"), "{e}");
    }

    #[test]
    fn an_array_or_map_is_named_layers_and_a_bad_element_is_named() {
        let dir = tempfile::tempdir().unwrap();
        let s = from_recipe(&recipe(dir.path(), "[cube(1), icosphere(1, 1)]"), EngineOptions::default()).unwrap();
        let names: Vec<&str> = s.layers.iter().map(|l| l.name.as_str()).collect();
        assert_eq!(names, ["[0]", "[1]"]);
        assert_eq!(s.layers[1].mesh.triangle_count(), 80);
        let s = from_recipe(&recipe(dir.path(), "#{ lid: cube(1), box: cube(2) }"), EngineOptions::default()).unwrap();
        let names: Vec<&str> = s.layers.iter().map(|l| l.name.as_str()).collect();
        assert_eq!(names, ["box", "lid"]);
        let e = from_recipe(&recipe(dir.path(), "#{ a: cube(1), b: 5 }"), EngineOptions::default()).unwrap_err();
        assert!(e.0.contains("layer b") && e.0.contains("cannot be saved"), "{e}");
        let e = from_recipe(&recipe(dir.path(), "[]"), EngineOptions::default()).unwrap_err();
        assert!(e.0.contains("nothing to show"), "{e}");
    }

    #[test]
    fn subdivision_surfaces_and_block_models_carry_their_control_mesh_and_plain_meshes_none() {
        let dir = tempfile::tempdir().unwrap();
        let text = "#{ plain: cube(2), smooth: cube(2).catmull_clark(2), twice: cube(2).catmull_clark(1).catmull_clark(1), \
                    blocks: { let m = blocks(); m.add(block([0, 0, 0], [1, 1, 1])); m.mesh() }, polar: polar_octahedron() }";
        let s = from_recipe(&recipe(dir.path(), text), EngineOptions::default()).unwrap();
        let edges =
            |name: &str| s.layers.iter().find(|l| l.name == name).unwrap().control.as_ref().map(|c| c.len() / 6);
        assert_eq!(edges("plain"), None);
        assert_eq!(edges("smooth"), Some(12), "the cube's 12 edges");
        assert_eq!(edges("twice"), Some(12), "the first input, not the intermediate surface");
        assert_eq!(edges("blocks"), Some(48), "the block's control mesh: 24 quads");
        assert_eq!(edges("polar"), Some(12), "the octahedron's edges");
        let smooth = s.layers.iter().find(|l| l.name == "smooth").unwrap().control.clone().unwrap();
        assert!(smooth.iter().all(|c| c.abs() == 1.0), "the cube's corners: {smooth:?}");
    }

    #[test]
    fn moves_turns_and_booleans_keep_the_control_mesh_with_the_surface() {
        let dir = tempfile::tempdir().unwrap();
        let text = "let s = cube(2).catmull_clark(2);\n\
                    #{ moved: s.translate([5, 0, 0]), turned: s.rotate([0, 0, 1], 45).triangulate(), \
                    joined: union(s, cube(1).translate([1, 1, 1])), both: s - s.scale(0.5).translate([1, 0, 0]), \
                    side: combine([s, cube(1).translate([4, 0, 0])]), plain: union(cube(1), cube(1).translate([0.5, 0, 0])) }";
        let s = from_recipe(&recipe(dir.path(), text), EngineOptions::default()).unwrap();
        let control = |name: &str| s.layers.iter().find(|l| l.name == name).unwrap().control.clone();
        let xs = |c: &[f32]| c.chunks(3).map(|p| p[0]).fold((f32::MAX, f32::MIN), |(lo, hi), x| (lo.min(x), hi.max(x)));
        let moved = control("moved").unwrap();
        assert_eq!((moved.len() / 6, xs(&moved)), (12, (4.0, 6.0)), "the cube's edges, moved with the surface");
        let turned = control("turned").unwrap();
        let r = 2f32.sqrt();
        assert!((xs(&turned).1 - r).abs() < 1e-5, "turned 45°: a corner at x = √2, {:?}", xs(&turned));
        assert_eq!(control("joined").map(|c| c.len() / 6), Some(12), "the subdivided operand's cage");
        assert_eq!(control("both").map(|c| c.len() / 6), Some(24), "both operands' cages");
        assert_eq!(control("side").map(|c| c.len() / 6), Some(12));
        assert_eq!(control("plain"), None, "no operand has a control mesh");
    }

    #[test]
    fn a_mesh_file_is_one_layer() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("c.obj");
        io::save(&Mesh::cuboid(blocksmith_kernel::Vec3::ZERO, blocksmith_kernel::Vec3::ONE), &p).unwrap();
        let s = open(&p, EngineOptions::default()).unwrap();
        assert_eq!(s.layers[0].mesh.face_count(), 6);
        assert_eq!(&s.layers[0].glb[..4], b"glTF");
    }
}
