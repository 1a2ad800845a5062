//! The script runtime's own functions: assertions for tests and recipes.

use blocksmith_kernel::Vec3;
use rhai::plugin::*;
use rhai::{Array, Map};

use crate::context::RunContext;
use crate::convert::{fail, number, type_name, vec3, Number, NumberOrVector, ScriptResult};
use crate::params::Declared;

fn debug_text(ctx: &NativeCallContext, v: &Dynamic) -> String {
    ctx.call_native_fn::<String>("to_debug", (v.clone(),)).unwrap_or_else(|_| v.to_string())
}

#[export_module]
pub mod runtime_api {
    use super::*;

    /// The warnings the run has given so far, each a string (`mesh`'s blocks that touch
    /// without connecting: `"3:11: mesh: block 1 touches block 0 …"`), leaving none. `run` and
    /// the REPL print the warnings nobody took, and `blocksmith test` fails on them, so a test
    /// that means to make such a model takes them here and checks them.
    ///
    /// ```rhai
    /// let m = blocks();
    /// m.allow(0, 0);
    /// m.add(block([0, 0, 1], [2, 2, 1.2]));
    /// m.add(block([0, 0, 0], [0.2, 0.2, 1]));
    /// let s = m.mesh();
    /// let w = take_warnings();
    /// assert_eq(w.len(), 1);
    /// assert(w[0].contains("mesh: block 1 touches block 0 but does not connect to it"), w[0]);
    /// assert_eq(take_warnings(), []);
    /// ```
    pub fn take_warnings(ctx: NativeCallContext) -> Array {
        RunContext::of(&ctx)
            .warnings
            .take()
            .into_iter()
            .map(|w| {
                let at = match (w.position.line(), w.position.position()) {
                    (Some(l), Some(c)) => format!("{l}:{c}: "),
                    _ => String::new(),
                };
                Dynamic::from(format!("{at}{}", w.message))
            })
            .collect()
    }

    /// Fails the script with `message` unless `condition` is true.
    ///
    /// ```rhai
    /// assert(1 + 1 == 2, "arithmetic works");
    /// ```
    #[rhai_fn(return_raw)]
    pub fn assert(condition: bool, message: &str) -> ScriptResult<()> {
        if condition {
            Ok(())
        } else {
            fail("assert", format!("assertion failed: {message}"))
        }
    }

    /// Fails the script unless `condition` is true.
    #[rhai_fn(name = "assert", return_raw)]
    pub fn assert_plain(condition: bool) -> ScriptResult<()> {
        if condition {
            Ok(())
        } else {
            fail("assert", "assertion failed")
        }
    }

    /// Fails the script unless `a == b` (with the `==` of their types; integers equal floats of
    /// the same value). The message shows both values.
    ///
    /// ```rhai
    /// assert_eq(cube(1).face_count, 6);
    /// assert_eq(vec3(1, 2, 3), vec3(1.0, 2.0, 3.0));
    /// ```
    #[rhai_fn(return_raw)]
    pub fn assert_eq(ctx: NativeCallContext, a: Dynamic, b: Dynamic) -> ScriptResult<()> {
        let equal = ctx.call_native_fn::<bool>("==", (a.clone(), b.clone())).unwrap_or(false);
        if equal {
            Ok(())
        } else {
            fail(
                "assert_eq",
                format!("left != right\n  left:  {}\n  right: {}", debug_text(&ctx, &a), debug_text(&ctx, &b)),
            )
        }
    }

    /// Fails the script unless `|a − b| ≤ eps`, for numbers or vectors (distance). The
    /// message shows both values and the difference.
    ///
    /// ```rhai
    /// assert_near(0.1 + 0.2, 0.3, 1e-12);
    /// assert_near(vec3(1, 0, 0), [1, 0, 1e-9], 1e-6);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn assert_near(a: NumberOrVector, b: NumberOrVector, eps: Number) -> ScriptResult<()> {
        let eps = number("assert_near", "eps", &eps)?;
        let is_num = |v: &Dynamic| v.is_int() || v.is_float();
        let (diff, sa, sb) = if is_num(&a) && is_num(&b) {
            let (x, y) = (number("assert_near", "a", &a)?, number("assert_near", "b", &b)?);
            ((x - y).abs(), x.to_string(), y.to_string())
        } else if a.is::<Vec3>() || a.is_array() {
            let (x, y) = (vec3("assert_near", "a", &a)?, vec3("assert_near", "b", &b)?);
            (x.distance(y), format!("{x}"), format!("{y}"))
        } else {
            return fail(
                "assert_near",
                format!("arguments must be numbers or vectors, got {} and {}", type_name(&a), type_name(&b)),
            );
        };
        if diff <= eps {
            Ok(())
        } else {
            fail("assert_near", format!("values differ by {diff:e} > {eps:e}\n  left:  {sa}\n  right: {sb}"))
        }
    }

    /// Shows `value` (a mesh, an animation, an array or map of them...) in the studio and
    /// returns it: under `blocksmith watch` it is drawn beside the recipe's model as a layer of
    /// its own (`show 1`, `show 2`, ... in call order), in the REPL it opens or updates the
    /// studio page as `:show` does. Elsewhere (`run`, `test`, `render`) it does nothing and says
    /// so once on standard error. For looking at a step of a recipe while writing it.
    ///
    /// ```rhai
    /// let base = show(cube(2));
    /// assert_eq(base.face_count, 6);
    /// ```
    pub fn show(ctx: NativeCallContext, value: Dynamic) -> Dynamic {
        static SAID: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);
        match &RunContext::of(&ctx).shown {
            Some(shown) => shown.push(value.clone()),
            None => {
                if !SAID.swap(true, std::sync::atomic::Ordering::Relaxed) {
                    eprintln!("note: show(...) draws values in `blocksmith watch` and the REPL; here it does nothing");
                }
            }
        }
        value
    }

    /// States a relation between parameters that no single range can: fails the run with
    /// `message` and the parameters' values so far (those given by `--set` marked) unless
    /// `condition` is true. Put it right after the `param` calls, so `--set`, `blocksmith
    /// params` and the studio report a bad combination at that line before any modeling runs.
    ///
    /// Topic: runtime
    ///
    /// ```rhai
    /// let teeth = param("teeth", 12, #{ min: 6, max: 60 });
    /// let module_ = param("module", 1.0, #{ min: 0.2, max: 10 });
    /// let bore = param("bore", 3.0, #{ min: 0, max: 50 });
    /// let root = module_ * (teeth - 2.5);   // the root circle's diameter
    /// param_check(bore < root, `the bore (${bore}) must be smaller than the root circle (${root})`);
    /// ```
    #[rhai_fn(return_raw)]
    pub fn param_check(ctx: NativeCallContext, condition: bool, message: &str) -> ScriptResult<()> {
        let record = &RunContext::of(&ctx).record;
        let line = ctx.call_position().line().unwrap_or(0);
        record.check(crate::record::ParamCheck { message: message.to_string(), passed: condition, line });
        if condition {
            return Ok(());
        }
        let params = record.snapshot().params;
        let values: Vec<String> =
            params.iter().map(|p| format!("{} = {}{}", p.name, p.value, if p.set { " (--set)" } else { "" })).collect();
        let with = if values.is_empty() { String::new() } else { format!(" (with {})", values.join(", ")) };
        fail("param_check", format!("{message}{with}"))
    }

    /// The value given on the command line with `--set name=value`, parsed by the type of
    /// `default` (integer, float — an integer is taken —, bool, text, `Vec3` as `x,y,z`, array
    /// as comma-separated elements), or `default`. Recipes declare their knobs this way; the run
    /// records each (`blocksmith params` lists them). A value that does not parse is an error
    /// naming the parameter, what it must be and its default.
    ///
    /// ```rhai
    /// let teeth = param("teeth", 12);
    /// assert(teeth > 0, "teeth must be positive");
    /// ```
    #[rhai_fn(return_raw)]
    pub fn param(ctx: NativeCallContext, name: &str, default: Dynamic) -> ScriptResult<Dynamic> {
        declare(&ctx, name, default, Map::new())
    }

    /// `param(name, default, #{min, max, step, choices, doc})`: a parameter with a range
    /// (`min`, `max`: inclusive, of a number or of each coordinate or element), the increment a
    /// control uses (`step`: a value must be `min`, else 0, plus a whole number of steps, within
    /// a millionth of a step), the allowed values (`choices`, of the default's type) and a
    /// one-line description (`doc`), after OpenSCAD's customizer. The default must pass the
    /// checks; a `--set` value outside them is an error naming the parameter, what it must be
    /// and its default, before the recipe runs further.
    ///
    /// ```rhai
    /// let teeth = param("teeth", 12, #{ min: 6, max: 40, step: 1, doc: "number of teeth" });
    /// let wood = param("wood", "oak", #{ choices: ["oak", "pine", "walnut"] });
    /// assert_eq(teeth, 12);
    /// assert_eq(wood, "oak");
    /// ```
    #[rhai_fn(name = "param", return_raw)]
    pub fn param_with(ctx: NativeCallContext, name: &str, default: Dynamic, options: Map) -> ScriptResult<Dynamic> {
        declare(&ctx, name, default, options)
    }
}

/// Declares the parameter `name`, records it in the run's record and returns its value.
fn declare(ctx: &NativeCallContext, name: &str, default: Dynamic, options: Map) -> ScriptResult<Dynamic> {
    let run = RunContext::of(ctx);
    let declared = Declared::new(name, default, options)?;
    let (value, spec) = declared.resolve(run.params.get(name).map(String::as_str))?;
    run.record.param(spec);
    Ok(value)
}
