//! `Animation` and `Modifier`: skeleton-driven animation of polar meshes (Brazzolotto part II;
//! kernel `anim`) — skinning, the modifier stack (growth, gravity, script modifiers), poses,
//! frames and rigged glTF export.

use std::rc::Rc;

use blocksmith_kernel::anim::{
    write_animation_glb, Animation as KernelAnimation, Curve, Gravity, Growth, Modifier as KernelModifier, NodeState,
    Skinning,
};
use rhai::plugin::*;
use rhai::{exported_module, Array, Engine, FnPtr, Map, INT};

use super::mesh::SharedMesh;
use super::paths::output_file;
use super::polar::{PolarMesh, Skeleton};
use blocksmith_kernel::math::fmt_num;

use crate::convert::{fail, kernel, number, type_name, vec3, Number, Options, ScriptResult};

/// The most frames `frames` and `save` make.
const MAX_FRAMES: INT = 100_000;

/// The frames per second `save` writes by default.
const DEFAULT_FPS: f64 = 24.0;

/// How many frames `save` writes by default at `fps` for an animation of `duration`: frames
/// covering the growth, or 48 without one. A float, so that a long growth cannot overflow.
fn default_frame_count(duration: f64, fps: f64) -> f64 {
    if duration > 0.0 {
        (duration * fps).ceil() + 1.0
    } else {
        48.0
    }
}

/// An animation as scripts hold it (script type `Animation`): the kernel animation and the
/// script closures of its `modifier(...)` entries, by number.
#[derive(Clone)]
pub struct Animation {
    anim: Rc<KernelAnimation>,
    closures: Vec<FnPtr>,
}

impl Animation {
    /// The time of the last frame `save` writes by default (24 fps, frames covering the
    /// growth, or 48 frames): the pose `blocksmith render` draws and `--stats` measures when no
    /// `--time` is given.
    #[must_use]
    pub fn end_time(&self) -> f64 {
        let count = default_frame_count(self.anim.duration(), DEFAULT_FPS).min(MAX_FRAMES as f64);
        (count - 1.0) / DEFAULT_FPS
    }
}

/// The pose at time `t` (default [`Animation::end_time`]) of `value` when it is an `Animation`,
/// with the time: `None` for any other value. `functions` are the script's functions, which
/// its script modifiers call. For the host's `--time` (`run`, `render`).
///
/// # Errors
/// The pose's error (a script modifier's failure, a time that cannot be reached), as text.
pub fn pose_of_value(
    engine: &Engine,
    functions: &rhai::AST,
    value: &Dynamic,
    t: Option<f64>,
) -> Result<Option<(SharedMesh, f64)>, String> {
    let Some(anim) = value.read_lock::<Animation>().map(|a| a.clone()) else { return Ok(None) };
    let t = t.unwrap_or_else(|| anim.end_time());
    let mut scope = rhai::Scope::new();
    scope.push("__value", anim);
    scope.push("__t", t);
    let call = engine.compile("pose(__value, __t)").map_err(|e| e.to_string())?;
    let call = functions.clone_functions_only().merge(&call);
    let mesh = engine
        .eval_ast_with_scope::<SharedMesh>(&mut scope, &call)
        .map_err(|e| crate::diagnostics::explained_message(engine, &e))?;
    Ok(Some((mesh, t)))
}

/// One modifier before it is added to an animation (script type `Modifier`).
#[derive(Clone)]
pub enum Modifier {
    Kernel(KernelModifier),
    Script(FnPtr),
}

/// Registers `Animation`, `Modifier` and the animation functions on `engine`.
pub fn register(engine: &mut Engine) {
    engine.register_type_with_name::<Animation>("Animation");
    engine.register_type_with_name::<Modifier>("Modifier");
    engine.register_global_module(exported_module!(anim_api).into());
}

/// Calls the script modifiers of `closures` for the kernel: `(id, node, t, state)` → state.
fn script_modifiers<'a>(
    ctx: &'a NativeCallContext<'a>,
    closures: &'a [FnPtr],
) -> impl FnMut(usize, u32, f64, NodeState) -> Result<NodeState, String> + 'a {
    move |id, node, t, s| {
        let mut state = Map::new();
        state.insert("position".into(), Dynamic::from(s.position));
        state.insert("thickness".into(), Dynamic::from(s.thickness));
        let out: Dynamic = closures[id]
            .call_within_context(ctx, (INT::from(node), t, state))
            .map_err(|e| crate::convert::closure_error("the script modifier", &e))?;
        let Some(map) = out.clone().try_cast::<Map>() else {
            return Err(format!(
                "the script modifier must return a map #{{position, thickness}}, got {}",
                type_name(&out)
            ));
        };
        let position = match map.get("position") {
            Some(p) => vec3("modifier", "position", p).map_err(|e| e.to_string())?,
            None => s.position,
        };
        let thickness = match map.get("thickness") {
            Some(x) => number("modifier", "thickness", x).map_err(|e| e.to_string())?,
            None => s.thickness,
        };
        if let Some(bad) = map.keys().find(|k| !["position", "thickness"].contains(&k.as_str())) {
            return Err(format!("the script modifier returned an unknown key `{bad}` (valid: position, thickness)"));
        }
        Ok(NodeState { position, thickness })
    }
}

#[export_module]
pub mod anim_api {
    use super::*;

    /// An animation of a polar mesh (Brazzolotto §8.1) with the skeleton rooted at the first
    /// pole's node and smooth skinning; see `animation(pm, options)`.
    ///
    /// Topic: animation
    ///
    /// ```rhai
    /// let anim = animation(polar_sphere(0.2, 8, 6));
    /// assert_eq(anim.node_count, 7);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn animation(pm: PolarMesh) -> ScriptResult<Animation> {
        animation_with(pm, Map::new())
    }
    /// An animation of a polar mesh with options: `root` — a vertex id whose skeleton node
    /// becomes the root (default: the first pole); `root_face` — a face id instead (its first
    /// vertex's node); `skinning` — `"smooth"` (default: each joint turned halfway between its
    /// arriving and leaving segments, Fig. 7.5) or `"simple"` (each vertex follows one joint,
    /// §7.3); `subdivide` — Catmull–Clark levels (0 to 4, default 0) for a smooth plant: the
    /// rest mesh is refined with the branch tips kept pointed, and each refined vertex is
    /// skinned to up to four joints with the weights the refinement carries, so every pose and
    /// the saved glTF (skin weights in `WEIGHTS_0`) show the smooth plant moving.
    ///
    /// Topic: animation
    ///
    /// ```rhai
    /// let pm = polar_sphere(0.2, 8, 6);
    /// let anim = animation(pm, #{ root: pm.vertex_count - 1, skinning: "simple" });
    /// assert_eq(anim.skeleton().root, anim.skeleton().node_of(pm.vertex_count - 1));
    /// let plant = lsystem(#{ axiom: "F[+F][-F]F" }).grow(0);
    /// let smooth = animation(plant, #{ subdivide: 2 });
    /// smooth.add(growth());
    /// let end = smooth.pose(smooth.duration());
    /// assert(end.face_count > 10 * plant.face_count && end.is_closed(), "a smooth, closed plant");
    /// ```
    #[rhai_fn(name = "animation", return_raw)]
    pub fn animation_with(pm: PolarMesh, options: Map) -> ScriptResult<Animation> {
        let opts = Options::new("animation", options, &["root", "root_face", "skinning", "subdivide"])?;
        let levels = opts.int("subdivide", 0)?;
        let max = blocksmith_kernel::anim::MAX_LEVELS;
        if !(0..=INT::from(max)).contains(&levels) {
            return fail("animation", format!("option `subdivide` must be between 0 and {max} (levels), got {levels}"));
        }
        let skinning = match opts.choice("skinning", "smooth", &["smooth", "simple"])?.as_str() {
            "simple" => Skinning::Simple,
            _ => Skinning::Smooth,
        };
        if opts.has("root") && opts.has("root_face") {
            return fail("animation", "give `root` or `root_face`, not both");
        }
        let root = if opts.has("root") {
            Some(kernel("animation", pm.0.vertex_id(opts.int("root", 0)?))?)
        } else if opts.has("root_face") {
            let f = kernel("animation", pm.0.face_id(opts.int("root_face", 0)?))?;
            pm.0.mesh().face_vertices(f).next()
        } else {
            None
        };
        let mut anim = kernel("animation", KernelAnimation::new(&pm.0, root, skinning))?;
        if levels > 0 {
            let _bar = crate::progress::bar("subdivide");
            anim = kernel("animation", anim.subdivided(levels as u32))?;
        }
        Ok(Animation { anim: Rc::new(anim), closures: Vec::new() })
    }

    /// The growth modifier (§9.1) with its defaults; see `growth(options)`.
    ///
    /// ```rhai
    /// let anim = animation(polar_sphere(0.2, 8, 6));
    /// anim.add(growth());
    /// assert_eq(anim.duration(), 7.0);   // the far pole is 6 segments deep: 6 × delay 1 + 1 / speed 1
    /// ```
    #[rhai_fn(return_raw)]
    pub fn growth() -> ScriptResult<Modifier> {
        growth_with(Map::new())
    }
    /// The growth modifier (§9.1): the plant grows from collapsed on its root to its modelled
    /// shape. Options: `delay` (1: time between a node's onset and its children's, so later
    /// nodes mature later), `speed` (1: full length 1/speed after onset), `thickness_delay` and
    /// `thickness_speed` (1, 1: the same for the thickness), `curve` — `"sigmoid"` (default: the
    /// thesis's 1/(1+e^(5−10x)), rescaled to run exactly from 0 to 1) or `"linear"`.
    ///
    /// ```rhai
    /// let pm = polar_sphere(0.2, 8, 6);
    /// let anim = animation(pm);
    /// anim.add(growth(#{ delay: 0.5, speed: 2, curve: "linear" }));
    /// let end = anim.pose(anim.duration());
    /// assert_eq(end.positions(), pm.to_mesh().positions());
    /// ```
    #[rhai_fn(name = "growth", return_raw)]
    pub fn growth_with(options: Map) -> ScriptResult<Modifier> {
        let opts = Options::new("growth", options, &["delay", "speed", "thickness_delay", "thickness_speed", "curve"])?;
        let d = Growth::default();
        let g = Growth {
            delay: opts.number("delay", d.delay)?,
            speed: opts.number("speed", d.speed)?,
            thickness_delay: opts.number("thickness_delay", d.thickness_delay)?,
            thickness_speed: opts.number("thickness_speed", d.thickness_speed)?,
            curve: match opts.choice("curve", "sigmoid", &["sigmoid", "linear"])?.as_str() {
                "linear" => Curve::Linear,
                _ => Curve::Sigmoid,
            },
        };
        kernel("growth", g.validate())?;
        Ok(Modifier::Kernel(KernelModifier::Growth(g)))
    }

    /// The gravity modifier (§9.2) with its defaults; see `gravity(options)`.
    ///
    /// ```rhai
    /// let anim = animation(polar_sphere(0.2, 8, 6));
    /// anim.add(gravity());
    /// assert_eq(anim.frames(3, 0.1).len(), 3);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn gravity() -> ScriptResult<Modifier> {
        gravity_with(Map::new())
    }
    /// The gravity modifier (§9.2): per node a Verlet step under gravity, a Hooke force back to
    /// the nominal offset from the parent and the inherited velocity kept by `drag`, then
    /// Jakobsen's relaxation restoring the segment lengths; the root is fixed. Simulated from
    /// rest: `frames(count, dt)` steps once a frame, `pose(t)` 24 times per time unit. Options: `g` (9.81), `down` (`[0, 0, -1]`), `k` (20), `drag` (0.5, in
    /// (0, 1]), `iterations` (10 relaxation sweeps), `dt` (the simulation step; default one
    /// step per frame).
    ///
    /// ```rhai
    /// let anim = animation(polar_sphere(0.2, 8, 6));
    /// anim.add(gravity(#{ drag: 0.1, k: 5 }));
    /// let frames = anim.frames(10, 1.0 / 24);
    /// assert_eq(frames.len(), 10);
    /// ```
    #[rhai_fn(name = "gravity", return_raw)]
    pub fn gravity_with(options: Map) -> ScriptResult<Modifier> {
        let opts = Options::new("gravity", options, &["g", "down", "k", "drag", "iterations", "dt"])?;
        let d = Gravity::default();
        let iterations = opts.int("iterations", INT::from(d.iterations))?;
        if !(0..=1000).contains(&iterations) {
            return fail("gravity", format!("option `iterations` must be between 0 and 1000, got {iterations}"));
        }
        let g = Gravity {
            g: opts.number("g", d.g)?,
            down: opts.vec3("down", d.down)?,
            k: opts.number("k", d.k)?,
            drag: opts.number("drag", d.drag)?,
            iterations: iterations as u32,
            dt: if opts.has("dt") { Some(opts.number("dt", 0.0)?) } else { None },
        };
        kernel("gravity", g.validate())?;
        Ok(Modifier::Kernel(KernelModifier::Gravity(g)))
    }

    /// A modifier written in the script: `f(node, t, state)` is called for every skeleton node
    /// (parents first) with the state the previous modifiers produced, a map `#{position,
    /// thickness}`, and returns the new map (a missing key keeps its value).
    ///
    /// ```rhai
    /// let anim = animation(polar_sphere(0.2, 8, 6));
    /// anim.add(modifier(|node, t, s| #{ position: s.position + vec3(0, 0, t) }));
    /// let up = anim.pose(2.0);
    /// assert_near(up.bounds().min.z, -0.2 + 2.0, 1e-12);
    /// ```
    pub fn modifier(f: FnPtr) -> Modifier {
        Modifier::Script(f)
    }

    /// Appends a modifier to the stack: each is applied to every node in the order added,
    /// receiving the states the previous one produced.
    ///
    /// ```rhai
    /// let anim = animation(polar_sphere(0.2, 8, 6));
    /// anim.add(growth());
    /// anim.add(modifier(|node, t, s| s));
    /// assert_eq(anim.modifier_count(), 2);
    /// ```
    pub fn add(anim: &mut Animation, m: Modifier) {
        let entry = match m {
            Modifier::Kernel(k) => k,
            Modifier::Script(f) => {
                anim.closures.push(f);
                KernelModifier::Custom(anim.closures.len() - 1)
            }
        };
        Rc::make_mut(&mut anim.anim).add(entry).expect("modifiers are validated when they are made");
    }

    /// The number of modifiers on the stack.
    ///
    /// ```rhai
    /// let anim = animation(polar_sphere(0.2, 8, 6));
    /// assert_eq(anim.modifier_count(), 0);
    /// anim.add(growth());
    /// assert_eq(anim.modifier_count(), 1);
    /// ```
    #[rhai_fn(pure)]
    pub fn modifier_count(anim: &mut Animation) -> INT {
        anim.anim.modifiers().len() as INT
    }

    /// The number of skeleton nodes.
    ///
    /// ```rhai
    /// assert_eq(animation(polar_sphere(0.2, 8, 6)).node_count, 7);   // 2 poles + 5 loops
    /// ```
    #[rhai_fn(get = "node_count", pure)]
    pub fn node_count(anim: &mut Animation) -> INT {
        anim.anim.skeleton().node_count() as INT
    }

    /// The time at which every growth on the stack has finished (0 without one).
    ///
    /// ```rhai
    /// let anim = animation(polar_sphere(0.2, 8, 6));
    /// assert_eq(anim.duration(), 0.0);
    /// anim.add(growth(#{ delay: 0.5, thickness_delay: 0.5 }));
    /// assert_eq(anim.duration(), 4.0);   // the far pole 6 segments deep: 6 × 0.5 + 1 / speed 1
    /// ```
    #[rhai_fn(pure)]
    pub fn duration(anim: &mut Animation) -> f64 {
        anim.anim.duration()
    }

    /// The skeleton the animation is rooted on.
    ///
    /// ```rhai
    /// let anim = animation(polar_sphere(0.2, 8, 6));
    /// assert_eq(anim.skeleton().node_count, 7);
    /// ```
    #[rhai_fn(pure)]
    pub fn skeleton(anim: &mut Animation) -> Skeleton {
        Skeleton(Rc::new(anim.anim.skeleton().clone()))
    }

    /// The mesh posed at time `t` (vertex ids kept, the polar mesh's feature colours). Growth
    /// and script modifiers are evaluated at `t`; a stack with gravity is simulated from rest
    /// at time 0 to `t` in steps of at most 1/24 (so a pose at a frame's time is the frame
    /// `save` writes at 24 fps). Every pose is a valid mesh that triangulates, saves and
    /// renders: no part is smaller than a thousandth of its modelled size — a node's thickness
    /// is at least 0.001, a segment at least 0.001 of its modelled length (a shorter one is
    /// lengthened along its direction, its branch moving with it) — so at the start of a
    /// growth the plant is its model scaled by 0.001 about the root, a seed rather than a
    /// point.
    ///
    /// ```rhai
    /// let pm = polar_sphere(0.2, 8, 6);
    /// let anim = animation(pm);
    /// anim.add(growth());
    /// let seed = anim.pose(0);
    /// let height = seed.bounds().max.z - seed.bounds().min.z;
    /// assert_near(height, 0.001 * 0.4, 1e-12);   // the model, a thousandth of its size
    /// for t in [0.0, 1.5, 3.0, 4.5, 6.0] {
    ///     let m = anim.pose(t).triangulate();      // every pose is a valid mesh
    ///     assert(m.is_closed() && m.is_manifold());
    /// }
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn pose(ctx: NativeCallContext, anim: &mut Animation, t: Number) -> ScriptResult<SharedMesh> {
        let t = number("pose", "t", &t)?;
        let mut custom = script_modifiers(&ctx, &anim.closures);
        kernel("pose", anim.anim.pose(t, &mut custom)).map(SharedMesh::new)
    }

    /// `count` posed meshes at times 0, dt, 2·dt, …: simulated modifiers (gravity) step once a
    /// frame from rest.
    ///
    /// ```rhai
    /// let anim = animation(polar_sphere(0.2, 8, 6));
    /// anim.add(growth(#{ curve: "linear" }));
    /// let frames = anim.frames(5, 2.0);   // t = 0, 2, 4, 6, 8: grown by t = 7
    /// assert_eq(frames[4].positions(), polar_sphere(0.2, 8, 6).to_mesh().positions());
    /// ```
    #[rhai_fn(pure, return_raw)]
    pub fn frames(ctx: NativeCallContext, anim: &mut Animation, count: INT, dt: Number) -> ScriptResult<Array> {
        if !(1..=MAX_FRAMES).contains(&count) {
            return fail("frames", format!("argument `count` must be between 1 and {MAX_FRAMES}, got {count}"));
        }
        let dt = number("frames", "dt", &dt)?;
        let mut custom = script_modifiers(&ctx, &anim.closures);
        let meshes = kernel("frames", anim.anim.frames(count as usize, dt, &mut custom))?;
        Ok(meshes.into_iter().map(|m| Dynamic::from(SharedMesh::new(m))).collect())
    }

    /// Writes the animation as a `.glb`: the rest mesh skinned to the skeleton (one joint per
    /// node), and `frames` keys at `fps` (defaults: 24 fps, frames to cover the growth, or 48).
    /// Blender and three.js play it.
    ///
    /// ```rhai
    /// let anim = animation(polar_sphere(0.2, 8, 6));
    /// anim.add(growth());
    /// anim.save("doc_example_growth.glb", #{ fps: 12, frames: 24 });
    /// ```
    #[rhai_fn(return_raw)]
    pub fn save(ctx: NativeCallContext, anim: &mut Animation, path: &str, options: Map) -> ScriptResult<()> {
        let opts = Options::new("save", options, &["fps", "frames"])?;
        let fps = opts.number("fps", DEFAULT_FPS)?;
        if fps <= 0.0 {
            return fail("save", format!("option `fps` must be > 0, got {fps}"));
        }
        let duration = anim.anim.duration();
        let count = if opts.has("frames") {
            let count = opts.int("frames", 0)?;
            if !(1..=MAX_FRAMES).contains(&count) {
                return fail("save", format!("option `frames` must be between 1 and {MAX_FRAMES}, got {count}"));
            }
            count
        } else if duration > 0.0 {
            // Frames covering the growth, computed in floats: a long growth must not overflow.
            let n = default_frame_count(duration, fps);
            if n.is_nan() || n > MAX_FRAMES as f64 {
                return fail(
                    "save",
                    format!(
                        "the growth lasts {} time units: at {} fps that is {} frames, over {MAX_FRAMES}; \
                         pass option `frames`, a lower `fps`, or grow faster",
                        fmt_num(duration),
                        fmt_num(fps),
                        fmt_num(n)
                    ),
                );
            }
            n as INT
        } else {
            48
        };
        if !path.to_ascii_lowercase().ends_with(".glb") {
            return fail("save", format!("an Animation is written as .glb, got `{path}`"));
        }
        let mut custom = script_modifiers(&ctx, &anim.closures);
        let frames = kernel("save", anim.anim.frame_states(count as usize, 1.0 / fps, &mut custom))?;
        let Some(p) = output_file(&ctx, "save", path)? else { return Ok(()) };
        // Atomic: a failing write leaves the old file.
        let result = blocksmith_kernel::io::write_atomic(&p, |w| write_animation_glb(&anim.anim, &frames, fps, w, &p));
        crate::api::paths::wrote(&ctx, &p);
        kernel("save", result)
    }
    /// `save(path, #{})`: 24 fps, frames covering the growth (or 48).
    #[rhai_fn(name = "save", return_raw)]
    pub fn save_default(ctx: NativeCallContext, anim: &mut Animation, path: &str) -> ScriptResult<()> {
        save(ctx, anim, path, Map::new())
    }

    /// A one-line summary.
    #[rhai_fn(name = "to_string", name = "to_debug", pure)]
    pub fn to_string(anim: &mut Animation) -> String {
        format!(
            "Animation({} nodes, {} modifiers, {:?} skinning)",
            anim.anim.skeleton().node_count(),
            anim.anim.modifiers().len(),
            anim.anim.skinning()
        )
    }
}
